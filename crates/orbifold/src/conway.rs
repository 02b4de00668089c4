//! Conway's orbifold notation for every two-dimensional orbifold: `632`, `4*2`, `22×`, `**`, `o`, ….

use std::fmt;
use std::str::FromStr;

use num_rational::BigRational;

use crate::euler::{EulerCharacteristic, Geometry};
use crate::necklace;
use crate::notation::{ParseError, parse_symbol};
use crate::order::{Order, rational_to_u128};
use crate::signature::{Kind, Signature};

/// Any two-dimensional orbifold in Conway's notation: `o` handles, cone points (gyrations),
/// mirror boundaries `*` with their corners (kaleidoscopes), and cross-caps `×` (miracles).
///
/// Kaleidoscopic signatures are the symbols with a single `*` and nothing else; only those are
/// polygons of mirrors and can be built into rooms ([`OrbifoldSymbol::as_kaleidoscopic`]).
///
/// ```
/// use orbifold::{Geometry, OrbifoldSymbol};
/// let p4g: OrbifoldSymbol = "4*2".parse().unwrap();
/// assert_eq!(p4g.euler_characteristic().to_string(), "0");
/// assert_eq!(p4g.geometry(), Geometry::Euclidean);
/// assert_eq!(p4g.symmetry_group().unwrap().name, "p4g");
/// assert!(p4g.as_kaleidoscopic().is_none());
/// ```
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct OrbifoldSymbol {
    handles: u32,
    cones: Vec<Order>,
    boundaries: Vec<Vec<Order>>,
    crosscaps: u32,
}

impl OrbifoldSymbol {
    /// Builds a symbol from its parts (orders of 1 are dropped). Orders must be integers ≥ 1 or ∞
    /// except in a kaleidoscopic symbol (no handles, cones or cross-caps, one boundary).
    pub fn new(
        handles: u32,
        cones: Vec<Order>,
        boundaries: Vec<Vec<Order>>,
        crosscaps: u32,
    ) -> Self {
        let drop_ones = |v: Vec<Order>| v.into_iter().filter(|k| !k.is_one()).collect::<Vec<_>>();
        OrbifoldSymbol {
            handles,
            cones: drop_ones(cones),
            boundaries: boundaries.into_iter().map(drop_ones).collect(),
            crosscaps,
        }
    }

    /// The number of handles `o`.
    pub fn handles(&self) -> u32 {
        self.handles
    }

    /// The orders of the cone points (gyration points), as written.
    pub fn cones(&self) -> &[Order] {
        &self.cones
    }

    /// The mirror boundaries, each with its corner orders in reading order.
    pub fn boundaries(&self) -> &[Vec<Order>] {
        &self.boundaries
    }

    /// The number of cross-caps `×`.
    pub fn crosscaps(&self) -> u32 {
        self.crosscaps
    }

    /// The kaleidoscopic signature, when the symbol is one (`*k₁…k_N` and nothing else).
    pub fn as_kaleidoscopic(&self) -> Option<Signature> {
        match self.boundaries.as_slice() {
            [corners] if self.handles == 0 && self.crosscaps == 0 && self.cones.is_empty() => {
                Some(Signature::from_valid_corners(corners.clone()))
            }
            _ => None,
        }
    }

    /// Whether the underlying surface is orientable and there are no mirrors: then the group
    /// preserves orientation.
    pub fn preserves_orientation(&self) -> bool {
        self.boundaries.is_empty() && self.crosscaps == 0
    }

    /// The canonical form: cones in increasing order; each mirror boundary at its smallest
    /// rotation; boundaries in increasing order. Reversing a boundary's corners needs an
    /// orientation-reversing homeomorphism, which reverses every boundary at once, unless the
    /// surface has a cross-cap; handles next to cross-caps become cross-caps (o× = ×××).
    ///
    /// ```
    /// # use orbifold::OrbifoldSymbol;
    /// let canon = |s: &str| s.parse::<OrbifoldSymbol>().unwrap().canonical().to_string();
    /// assert_eq!(canon("632"), "236");
    /// assert_eq!(canon("*632"), "*236");
    /// assert_eq!(canon("o×"), "×××");
    /// ```
    pub fn canonical(&self) -> OrbifoldSymbol {
        let mut cones = self.cones.clone();
        cones.sort();
        let (handles, crosscaps) = if self.crosscaps > 0 {
            (0, self.crosscaps + 2 * self.handles)
        } else {
            (self.handles, 0)
        };
        let boundaries = if crosscaps > 0 {
            sorted(
                self.boundaries
                    .iter()
                    .map(|b| necklace::smallest_reading(b))
                    .collect(),
            )
        } else {
            let forward = sorted(
                self.boundaries
                    .iter()
                    .map(|b| necklace::smallest_rotation(b))
                    .collect(),
            );
            let backward = sorted(
                self.boundaries
                    .iter()
                    .map(|b| necklace::smallest_rotation(&necklace::reversed(b)))
                    .collect(),
            );
            forward.min(backward)
        };
        OrbifoldSymbol {
            handles,
            cones,
            boundaries,
            crosscaps,
        }
    }

    /// χ = 2 − 2·handles − cross-caps − boundaries − Σ(k−1)/k over cones − Σ(k−1)/(2k) over
    /// corners, exactly (an order ∞ costs 1 as a cone and 1/2 as a corner).
    pub fn euler_characteristic(&self) -> EulerCharacteristic {
        let mut chi = BigRational::from_integer(self.underlying_euler_characteristic().into());
        for k in &self.cones {
            chi -= k.cone_cost();
        }
        let half = BigRational::new(1.into(), 2.into());
        for k in self.boundaries.iter().flatten() {
            chi -= k.cone_cost() * &half;
        }
        EulerCharacteristic::new(chi)
    }

    /// The Euler characteristic of the underlying surface: 2 − 2·handles − cross-caps − boundaries.
    pub fn underlying_euler_characteristic(&self) -> i64 {
        2 - 2 * i64::from(self.handles) - i64::from(self.crosscaps) - self.boundaries.len() as i64
    }

    /// The geometry selected by the sign of χ.
    pub fn geometry(&self) -> Geometry {
        self.euler_characteristic().geometry()
    }

    /// Why this is not a good orbifold, in words: a bad orbifold (the teardrop `n`, the spindle
    /// `mn` with m ≠ n, and their halves `*n` and `*mn`, the only bad 2-orbifolds by Thurston's
    /// theorem) or a non-orbifold kaleidoscopic room. `None` for good orbifolds.
    pub fn reason(&self) -> Option<String> {
        if let Some(sig) = self.as_kaleidoscopic() {
            return sig.reason();
        }
        if self.handles > 0 || self.crosscaps > 0 || !self.boundaries.is_empty() {
            return None;
        }
        match self.cones.as_slice() {
            [k] => Some(format!(
                "a sphere with a single cone point of order {k} (a teardrop) is a bad orbifold: \
                 no surface covers it, because a rotation about one point alone cannot close up"
            )),
            [a, b] if a != b => Some(format!(
                "a sphere with two cone points of different orders {a} and {b} (a spindle) is a bad \
                 orbifold: the rotations about the two poles would have to be the same"
            )),
            _ => None,
        }
    }

    /// Whether this is a bad orbifold (see [`OrbifoldSymbol::reason`]).
    pub fn is_bad(&self) -> bool {
        match self.as_kaleidoscopic() {
            Some(sig) => sig.kind() == Kind::Bad,
            None => self.reason().is_some(),
        }
    }

    /// The order of the symmetry group, 2/χ, for good spherical orbifolds.
    pub fn group_order(&self) -> Option<u128> {
        if let Some(sig) = self.as_kaleidoscopic() {
            return sig.group_order();
        }
        let chi = self.euler_characteristic();
        if self.is_bad() || chi.geometry() != Geometry::Spherical {
            return None;
        }
        rational_to_u128(&(BigRational::from_integer(2.into()) / chi.value()))
    }

    /// The area 2π|χ| of a fundamental domain (curvature ±1); `None` for Euclidean and bad ones.
    pub fn area(&self) -> Option<f64> {
        if let Some(sig) = self.as_kaleidoscopic() {
            return sig.area();
        }
        let chi = self.euler_characteristic();
        (!self.is_bad() && chi.geometry() != Geometry::Euclidean).then(|| chi.area())
    }

    /// The dimension of the space of shapes: for kaleidoscopic polygons their free parameters;
    /// for hyperbolic orbifolds Thurston's −3χ(X) + 2·cones + corners; for Euclidean ones the
    /// shapes of the lattice up to similarity; 0 for spherical and bad ones.
    pub fn free_parameters(&self) -> usize {
        if let Some(sig) = self.as_kaleidoscopic() {
            return sig.free_parameters();
        }
        if self.is_bad() {
            return 0;
        }
        match self.geometry() {
            Geometry::Spherical => 0,
            Geometry::Euclidean => self.symmetry_group().map_or(0, |g| g.shape_parameters),
            Geometry::Hyperbolic => {
                let corners: usize = self.boundaries.iter().map(Vec::len).sum();
                let dim = -3 * self.underlying_euler_characteristic()
                    + 2 * self.cones.len() as i64
                    + corners as i64;
                usize::try_from(dim).unwrap_or(0)
            }
        }
    }

    /// One line per feature, in Conway's terms, for explanations.
    pub fn features(&self) -> Vec<String> {
        let mut lines = Vec::new();
        if self.handles > 0 {
            lines.push(format!(
                "{} handle(s) o (a \"wonder\": the surface is a torus or more)",
                self.handles
            ));
        }
        for k in &self.cones {
            lines.push(match k {
                Order::Infinite => {
                    "a cusp ∞: a rotation centre of infinite order, at infinity".to_string()
                }
                _ => format!(
                    "a {k}-fold gyration point: a rotation centre by 360°/{k}, on no mirror"
                ),
            });
        }
        for corners in &self.boundaries {
            lines.push(match corners.len() {
                0 => "a mirror boundary * with no corner".to_string(),
                _ => format!(
                    "a mirror boundary * with kaleidoscopic corners of order {}",
                    corners
                        .iter()
                        .map(ToString::to_string)
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            });
        }
        if self.crosscaps > 0 {
            lines.push(format!(
                "{} cross-cap(s) × (a \"miracle\": a glide reflection that no mirror explains)",
                self.crosscaps
            ));
        }
        if lines.is_empty() {
            lines.push("nothing at all: the sphere itself, the trivial group".to_string());
        }
        lines
    }
}

fn sorted(mut v: Vec<Vec<Order>>) -> Vec<Vec<Order>> {
    v.sort();
    v
}

impl fmt::Display for OrbifoldSymbol {
    /// Conway notation; the trivial orbifold (the sphere) is written `1`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.handles == 0
            && self.cones.is_empty()
            && self.boundaries.is_empty()
            && self.crosscaps == 0
        {
            return f.write_str("1");
        }
        for _ in 0..self.handles {
            f.write_str("o")?;
        }
        self.cones
            .iter()
            .try_for_each(|k| k.write_in_signature(f))?;
        for corners in &self.boundaries {
            f.write_str("*")?;
            corners.iter().try_for_each(|k| k.write_in_signature(f))?;
        }
        for _ in 0..self.crosscaps {
            f.write_str("×")?;
        }
        Ok(())
    }
}

impl FromStr for OrbifoldSymbol {
    type Err = ParseError;

    fn from_str(s: &str) -> Result<Self, ParseError> {
        let raw = parse_symbol(s)?;
        Ok(OrbifoldSymbol {
            handles: raw.handles,
            cones: raw.cones,
            boundaries: raw.boundaries,
            crosscaps: raw.crosscaps,
        })
    }
}

impl From<Signature> for OrbifoldSymbol {
    fn from(sig: Signature) -> Self {
        OrbifoldSymbol {
            handles: 0,
            cones: Vec::new(),
            boundaries: vec![sig.corners().to_vec()],
            crosscaps: 0,
        }
    }
}
