//! The families of the seed's Table 4.1: every good kaleidoscopic orbifold by number of walls and
//! geometry, extended with ideal corners (order ∞).

use crate::euler::Geometry;
use crate::order::Order;
use crate::signature::{Kind, Signature};

/// Which rows of the table a family occupies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Walls {
    /// Exactly this many walls.
    Exactly(usize),
    /// This many walls or more.
    AtLeast(usize),
}

impl Walls {
    /// Whether a polygon with `n` walls falls in this row.
    pub fn contains(self, n: usize) -> bool {
        match self {
            Walls::Exactly(m) => n == m,
            Walls::AtLeast(m) => n >= m,
        }
    }
}

/// One cell entry of Table 4.1: a family of good kaleidoscopic orbifolds.
///
/// ```
/// use orbifold::{Geometry, Signature};
/// let family = "*2 2 7".parse::<Signature>().unwrap().family().unwrap();
/// assert_eq!(family.pattern, "*22k (k ≥ 2)");
/// assert_eq!(family.geometry, Geometry::Spherical);
/// ```
#[derive(Debug)]
pub struct Family {
    /// The number of walls (the seed's N; `*` has one wall and no corner).
    pub walls: Walls,
    /// The geometry of every member.
    pub geometry: Geometry,
    /// The pattern, such as `*22k (k ≥ 2)`; k may be ∞ unless the pattern says otherwise.
    pub pattern: &'static str,
    /// A few members, in canonical form.
    pub examples: &'static [&'static str],
    /// Whether the seed's table lists this family; the others are the ideal-corner (∞) additions.
    pub in_seed: bool,
    matches: fn(&[Order]) -> bool,
}

impl Family {
    /// Whether a canonical good signature belongs to this family.
    pub fn contains(&self, canonical: &Signature) -> bool {
        self.walls.contains(canonical.wall_count()) && (self.matches)(canonical.corners())
    }
}

fn int(k: &Order) -> Option<u64> {
    k.as_integer()
}

/// `k ≥ m`, where ∞ is at least everything.
fn at_least(k: &Order, m: u64) -> bool {
    k.is_infinite() || int(k).is_some_and(|k| k >= m)
}

fn is(k: &Order, m: u64) -> bool {
    int(k) == Some(m)
}

/// Every family, in table order: by walls, then spherical, Euclidean, hyperbolic.
pub static FAMILIES: &[Family] = &[
    Family {
        walls: Walls::Exactly(1),
        geometry: Geometry::Spherical,
        pattern: "*",
        examples: &["*"],
        in_seed: true,
        matches: |c| c.is_empty(),
    },
    Family {
        walls: Walls::Exactly(2),
        geometry: Geometry::Spherical,
        pattern: "*kk (k ≥ 2)",
        examples: &["*22", "*33", "*44"],
        in_seed: true,
        matches: |c| c[0] == c[1] && !c[0].is_infinite(),
    },
    Family {
        walls: Walls::Exactly(2),
        geometry: Geometry::Euclidean,
        pattern: "*∞∞ (a strip)",
        examples: &["*∞∞"],
        in_seed: false,
        matches: |c| c[0].is_infinite() && c[1].is_infinite(),
    },
    Family {
        walls: Walls::Exactly(3),
        geometry: Geometry::Spherical,
        pattern: "*22k (k ≥ 2)",
        examples: &["*222", "*223", "*224"],
        in_seed: true,
        matches: |c| is(&c[0], 2) && is(&c[1], 2) && !c[2].is_infinite(),
    },
    Family {
        walls: Walls::Exactly(3),
        geometry: Geometry::Spherical,
        pattern: "*23k (k = 3, 4, 5)",
        examples: &["*233", "*234", "*235"],
        in_seed: true,
        matches: |c| {
            is(&c[0], 2) && is(&c[1], 3) && int(&c[2]).is_some_and(|k| (3..=5).contains(&k))
        },
    },
    Family {
        walls: Walls::Exactly(3),
        geometry: Geometry::Euclidean,
        pattern: "*236",
        examples: &["*236"],
        in_seed: true,
        matches: |c| is(&c[0], 2) && is(&c[1], 3) && is(&c[2], 6),
    },
    Family {
        walls: Walls::Exactly(3),
        geometry: Geometry::Euclidean,
        pattern: "*244",
        examples: &["*244"],
        in_seed: true,
        matches: |c| is(&c[0], 2) && is(&c[1], 4) && is(&c[2], 4),
    },
    Family {
        walls: Walls::Exactly(3),
        geometry: Geometry::Euclidean,
        pattern: "*333",
        examples: &["*333"],
        in_seed: true,
        matches: |c| c.iter().all(|k| is(k, 3)),
    },
    Family {
        walls: Walls::Exactly(3),
        geometry: Geometry::Euclidean,
        pattern: "*22∞ (a half-strip)",
        examples: &["*22∞"],
        in_seed: false,
        matches: |c| is(&c[0], 2) && is(&c[1], 2) && c[2].is_infinite(),
    },
    Family {
        walls: Walls::Exactly(3),
        geometry: Geometry::Hyperbolic,
        pattern: "*23k (k ≥ 7)",
        examples: &["*237", "*238", "*23∞"],
        in_seed: true,
        matches: |c| is(&c[0], 2) && is(&c[1], 3) && at_least(&c[2], 7),
    },
    Family {
        walls: Walls::Exactly(3),
        geometry: Geometry::Hyperbolic,
        pattern: "*24k (k ≥ 5)",
        examples: &["*245", "*246", "*24∞"],
        in_seed: true,
        matches: |c| is(&c[0], 2) && is(&c[1], 4) && at_least(&c[2], 5),
    },
    Family {
        walls: Walls::Exactly(3),
        geometry: Geometry::Hyperbolic,
        pattern: "*2k₂k₃ (k₃ ≥ k₂ ≥ 5)",
        examples: &["*255", "*256", "*2∞∞"],
        in_seed: true,
        matches: |c| is(&c[0], 2) && at_least(&c[1], 5),
    },
    Family {
        walls: Walls::Exactly(3),
        geometry: Geometry::Hyperbolic,
        pattern: "*33k (k ≥ 4)",
        examples: &["*334", "*335", "*33∞"],
        in_seed: true,
        matches: |c| is(&c[0], 3) && is(&c[1], 3) && at_least(&c[2], 4),
    },
    Family {
        walls: Walls::Exactly(3),
        geometry: Geometry::Hyperbolic,
        pattern: "*3k₂k₃ (k₃ ≥ k₂ ≥ 4)",
        examples: &["*344", "*345", "*3∞∞"],
        in_seed: true,
        matches: |c| is(&c[0], 3) && at_least(&c[1], 4),
    },
    Family {
        walls: Walls::Exactly(3),
        geometry: Geometry::Hyperbolic,
        pattern: "*k₁k₂k₃ (k₃ ≥ k₂ ≥ k₁ ≥ 4)",
        examples: &["*444", "*445", "*∞∞∞"],
        in_seed: true,
        matches: |c| at_least(&c[0], 4),
    },
    Family {
        walls: Walls::Exactly(4),
        geometry: Geometry::Euclidean,
        pattern: "*2222",
        examples: &["*2222"],
        in_seed: true,
        matches: |c| c.iter().all(|k| is(k, 2)),
    },
    Family {
        walls: Walls::Exactly(4),
        geometry: Geometry::Hyperbolic,
        pattern: "*k₁k₂k₃k₄ (some kᵢ > 2)",
        examples: &["*2223", "*2323", "*∞∞∞∞"],
        in_seed: true,
        matches: |c| c.iter().any(|k| !is(k, 2)),
    },
    Family {
        walls: Walls::AtLeast(5),
        geometry: Geometry::Hyperbolic,
        pattern: "*k₁…k_N (every N ≥ 5)",
        examples: &["*22222", "*23456789(10)(11)", "*∞∞∞∞∞"],
        in_seed: true,
        matches: |_| true,
    },
];

/// The family of a canonical good signature.
pub(crate) fn family_of(canonical: &Signature) -> Option<&'static Family> {
    FAMILIES.iter().find(|family| family.contains(canonical))
}

/// The pattern of a family as it reads in row `walls`, expanding `*k₁…k_N` for rows N ≥ 5.
pub fn pattern_in_row(family: &Family, walls: usize) -> String {
    match family.walls {
        Walls::AtLeast(_) => {
            let subscripts = ["₀", "₁", "₂", "₃", "₄", "₅", "₆", "₇", "₈", "₉"];
            let sub = |i: usize| {
                i.to_string()
                    .chars()
                    .map(|d| subscripts[d as usize - '0' as usize])
                    .collect::<String>()
            };
            format!(
                "*{}",
                (1..=walls)
                    .map(|i| format!("k{}", sub(i)))
                    .collect::<String>()
            )
        }
        Walls::Exactly(_) => family.pattern.to_string(),
    }
}

impl Signature {
    /// The family of the seed's Table 4.1 that this good orbifold belongs to (canonical form taken
    /// internally); `None` for bad orbifolds and non-orbifold rooms.
    pub fn family(&self) -> Option<&'static Family> {
        if self.kind() != Kind::Orbifold {
            return None;
        }
        family_of(&self.canonical())
    }
}
