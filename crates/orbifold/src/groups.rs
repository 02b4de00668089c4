//! Classical names of orbifold groups: the 17 wallpaper groups, the 7 frieze groups and the
//! spherical point groups (Schoenflies notation), identified from canonical Conway symbols.

use crate::conway::OrbifoldSymbol;
use crate::order::Order;

/// Which classical list a named group belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum GroupFamily {
    /// One of the 17 plane crystallographic groups (compact Euclidean orbifolds).
    Wallpaper,
    /// One of the 7 frieze groups (Euclidean orbifolds with a cusp ∞: symmetries of a strip).
    Frieze,
    /// A finite group of isometries of the sphere (spherical orbifolds).
    Spherical,
}

impl GroupFamily {
    /// `wallpaper`, `frieze` or `spherical`.
    pub fn name(self) -> &'static str {
        match self {
            GroupFamily::Wallpaper => "wallpaper",
            GroupFamily::Frieze => "frieze",
            GroupFamily::Spherical => "spherical",
        }
    }
}

/// The classical name of an orbifold's symmetry group.
///
/// ```
/// use orbifold::OrbifoldSymbol;
/// let group = "*532".parse::<OrbifoldSymbol>().unwrap().symmetry_group().unwrap();
/// assert_eq!(group.name, "Ih");
/// assert_eq!(group.conway, "*532");
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SymmetryGroup {
    /// The short name: IUCr for wallpaper groups (`p6m`), IUC for frieze groups (`p2mg`),
    /// Schoenflies for spherical groups (`D5h`, `Ih`).
    pub name: String,
    /// The symbol as Conway writes it, largest orders first (`*632`, `4*2`, `22∞`).
    pub conway: String,
    /// Wallpaper, frieze or spherical.
    pub family: GroupFamily,
    /// A short description (`full icosahedral`, `prismatic`, `spinning sidle`).
    pub description: String,
    /// For Euclidean groups, the number of shape parameters of the lattice up to similarity.
    pub shape_parameters: usize,
}

/// The 17 wallpaper groups by their short IUCr names, with their Conway symbols: what a symbol
/// may also be written as (`orbifold tiling p6`). Frieze groups are not read by name: `p1` and
/// `p2` name frieze groups too, and here they are the wallpaper groups `o` and `2222`.
const WALLPAPER_NAMES: [(&str, &str); 17] = [
    ("p1", "o"),
    ("p2", "2222"),
    ("pm", "**"),
    ("pg", "××"),
    ("cm", "*×"),
    ("pmm", "*2222"),
    ("pmg", "22*"),
    ("pgg", "22×"),
    ("cmm", "2*22"),
    ("p4", "442"),
    ("p4m", "*442"),
    ("p4g", "4*2"),
    ("p3", "333"),
    ("p3m1", "*333"),
    ("p31m", "3*3"),
    ("p6", "632"),
    ("p6m", "*632"),
];

/// The Conway symbol of the wallpaper group with this short IUCr name (`p4g` → `4*2`).
///
/// ```
/// use orbifold::groups::wallpaper_symbol;
/// assert_eq!(wallpaper_symbol("p4g"), Some("4*2"));
/// assert_eq!(wallpaper_symbol("pgg"), Some("22×"));
/// assert_eq!(wallpaper_symbol("*632"), None);
/// ```
pub fn wallpaper_symbol(name: &str) -> Option<&'static str> {
    WALLPAPER_NAMES
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, conway)| *conway)
}

/// A Conway symbol written in the order given (the family's pattern, such as `*22n` or `2*n`).
fn conway(cones: &[Order], boundaries: &[&[Order]], crosscaps: u32) -> String {
    OrbifoldSymbol::new(
        0,
        cones.to_vec(),
        boundaries.iter().map(|b| b.to_vec()).collect(),
        crosscaps,
    )
    .to_string()
}

/// Names the group of a canonical symbol, if it is a classical one.
pub(crate) fn identify(canonical: &OrbifoldSymbol) -> Option<SymmetryGroup> {
    wallpaper(canonical)
        .or_else(|| frieze(canonical))
        .or_else(|| spherical(canonical))
}

fn ints(orders: &[Order]) -> Option<Vec<u64>> {
    orders.iter().map(Order::as_integer).collect()
}

/// The parts of a canonical symbol with finite orders, as plain integers.
struct Parts {
    handles: u32,
    cones: Vec<u64>,
    boundaries: Vec<Vec<u64>>,
    crosscaps: u32,
}

fn parts(s: &OrbifoldSymbol) -> Option<Parts> {
    Some(Parts {
        handles: s.handles(),
        cones: ints(s.cones())?,
        boundaries: s
            .boundaries()
            .iter()
            .map(|b| ints(b))
            .collect::<Option<_>>()?,
        crosscaps: s.crosscaps(),
    })
}

fn wallpaper(s: &OrbifoldSymbol) -> Option<SymmetryGroup> {
    let p = parts(s)?;
    let b: Vec<&[u64]> = p.boundaries.iter().map(Vec::as_slice).collect();
    let (name, conway_symbol, description, shape) =
        match (p.handles, p.cones.as_slice(), b.as_slice(), p.crosscaps) {
            (1, [], [], 0) => ("p1", "o", "translations only", 2),
            (0, [2, 2, 2, 2], [], 0) => ("p2", "2222", "half-turns", 2),
            (0, [], [[], []], 0) => ("pm", "**", "parallel mirrors", 1),
            (0, [], [[]], 1) => ("cm", "*×", "mirrors and glides between them", 1),
            (0, [], [], 2) => ("pg", "××", "parallel glides", 1),
            (0, [2, 2], [[]], 0) => ("pmg", "22*", "mirrors one way, glides the other", 1),
            (0, [2, 2], [], 1) => ("pgg", "22×", "perpendicular glides", 1),
            (0, [], [[2, 2, 2, 2]], 0) => ("pmm", "*2222", "rectangular kaleidoscope", 1),
            (0, [2], [[2, 2]], 0) => (
                "cmm",
                "2*22",
                "rhombic: perpendicular mirrors and half-turns off them",
                1,
            ),
            (0, [2, 4, 4], [], 0) => ("p4", "442", "quarter-turns", 0),
            (0, [], [[2, 4, 4]], 0) => ("p4m", "*442", "square kaleidoscope", 0),
            (0, [4], [[2]], 0) => ("p4g", "4*2", "quarter-turns off the mirrors", 0),
            (0, [3, 3, 3], [], 0) => ("p3", "333", "third-turns", 0),
            (0, [], [[3, 3, 3]], 0) => ("p3m1", "*333", "equilateral kaleidoscope", 0),
            (0, [3], [[3]], 0) => ("p31m", "3*3", "third-turns off the mirrors", 0),
            (0, [2, 3, 6], [], 0) => ("p6", "632", "sixth-turns", 0),
            (0, [], [[2, 3, 6]], 0) => ("p6m", "*632", "hexagonal kaleidoscope", 0),
            _ => return None,
        };
    Some(SymmetryGroup {
        name: name.to_string(),
        conway: conway_symbol.to_string(),
        family: GroupFamily::Wallpaper,
        description: format!("wallpaper group {name}: {description}"),
        shape_parameters: shape,
    })
}

fn frieze(s: &OrbifoldSymbol) -> Option<SymmetryGroup> {
    use Order::Infinite as I;
    let two = Order::integer(2);
    let b: Vec<&[Order]> = s.boundaries().iter().map(Vec::as_slice).collect();
    if s.handles() != 0 {
        return None;
    }
    let (name, conway_symbol, nickname) = match (s.cones(), b.as_slice(), s.crosscaps()) {
        ([I, I], [], 0) => ("p1", "∞∞", "hop"),
        ([I], [], 1) => ("p11g", "∞×", "step"),
        ([], [[I, I]], 0) => ("p1m1", "*∞∞", "sidle"),
        ([a, b, I], [], 0) if *a == two && *b == two => ("p2", "22∞", "spinning hop"),
        ([a], [[I]], 0) if *a == two => ("p2mg", "2*∞", "spinning sidle"),
        ([I], [[]], 0) => ("p11m", "∞*", "jump"),
        ([], [[a, b, I]], 0) if *a == two && *b == two => ("p2mm", "*22∞", "spinning jump"),
        _ => return None,
    };
    Some(SymmetryGroup {
        name: name.to_string(),
        conway: conway_symbol.to_string(),
        family: GroupFamily::Frieze,
        description: format!("frieze group {name} (\"{nickname}\")"),
        shape_parameters: 0,
    })
}

fn spherical(s: &OrbifoldSymbol) -> Option<SymmetryGroup> {
    let p = parts(s)?;
    if p.handles != 0 {
        return None;
    }
    let b: Vec<&[u64]> = p.boundaries.iter().map(Vec::as_slice).collect();
    let o = |k: u64| Order::integer(k);
    let group =
        |name: String, conway_symbol: String, description: String, order: u64| SymmetryGroup {
            description: format!("spherical point group {name}: {description}, of order {order}"),
            name,
            conway: conway_symbol,
            family: GroupFamily::Spherical,
            shape_parameters: 0,
        };
    Some(match (p.cones.as_slice(), b.as_slice(), p.crosscaps) {
        ([], [], 0) => group("C1".into(), "1".into(), "the trivial group".into(), 1),
        (&[m, n], [], 0) if m == n => group(
            format!("C{n}"),
            conway(&[o(n), o(n)], &[], 0),
            "cyclic (pyramidal rotations)".into(),
            n,
        ),
        (&[2, 2, n], [], 0) => group(
            format!("D{n}"),
            conway(&[o(2), o(2), o(n)], &[], 0),
            "dihedral (prismatic rotations)".into(),
            2 * n,
        ),
        ([2, 3, 3], [], 0) => group("T".into(), "332".into(), "chiral tetrahedral".into(), 12),
        ([2, 3, 4], [], 0) => group("O".into(), "432".into(), "chiral octahedral".into(), 24),
        ([2, 3, 5], [], 0) => group("I".into(), "532".into(), "chiral icosahedral".into(), 60),
        ([], [], 1) => group("Ci".into(), "×".into(), "central inversion".into(), 2),
        (&[n], [], 1) => group(
            format!("S{}", 2 * n),
            conway(&[o(n)], &[], 1),
            "rotoreflection (antiprismatic rotations with inversion)".into(),
            2 * n,
        ),
        ([], [[]], 0) => group("Cs".into(), "*".into(), "a single mirror".into(), 2),
        ([], &[&[m, n]], 0) if m == n => group(
            format!("C{n}v"),
            conway(&[], &[&[o(n), o(n)]], 0),
            "pyramidal (mirrors through the axis)".into(),
            2 * n,
        ),
        (&[n], [[]], 0) => group(
            format!("C{n}h"),
            conway(&[o(n)], &[&[]], 0),
            "rotations and the equatorial mirror".into(),
            2 * n,
        ),
        ([], &[&[2, 2, n]], 0) => group(
            format!("D{n}h"),
            conway(&[], &[&[o(2), o(2), o(n)]], 0),
            "prismatic".into(),
            4 * n,
        ),
        (&[2], &[&[n]], 0) => group(
            format!("D{n}d"),
            conway(&[o(2)], &[&[o(n)]], 0),
            "antiprismatic".into(),
            4 * n,
        ),
        ([3], [[2]], 0) => group("Th".into(), "3*2".into(), "pyritohedral".into(), 24),
        ([], [[2, 3, 3]], 0) => group("Td".into(), "*332".into(), "full tetrahedral".into(), 24),
        ([], [[2, 3, 4]], 0) => group("Oh".into(), "*432".into(), "full octahedral".into(), 48),
        ([], [[2, 3, 5]], 0) => group("Ih".into(), "*532".into(), "full icosahedral".into(), 120),
        _ => return None,
    })
}

impl OrbifoldSymbol {
    /// The classical name of the symmetry group: one of the 17 wallpaper groups, the 7 frieze
    /// groups, or a spherical point group (Schoenflies notation), when the orbifold is one.
    pub fn symmetry_group(&self) -> Option<SymmetryGroup> {
        identify(&self.canonical())
    }
}
