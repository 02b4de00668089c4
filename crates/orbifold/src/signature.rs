//! Kaleidoscopic signatures `*k₁…k_N`: the polygons whose walls are mirrors.

use std::fmt;
use std::str::FromStr;

use num_bigint::BigInt;
use num_rational::{BigRational, Ratio};
use num_traits::{CheckedAdd, CheckedDiv, One, Zero};

use crate::euler::{EulerCharacteristic, Geometry};
use crate::necklace;
use crate::notation::{ParseError, ParseErrorKind, parse_symbol};
use crate::order::{Order, rational_to_u128};

/// Whether a signature names an orbifold, a bad orbifold, or a room that is not an orbifold.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Kind {
    /// A good orbifold: its mirror images tile the sphere, the plane or the hyperbolic plane.
    Orbifold,
    /// A bad orbifold (`*k`, or `*k₁k₂` with k₁ ≠ k₂): it has no polygon and is never built.
    Bad,
    /// Some corner order is not an integer: a room of mirrors whose images overlap.
    NonOrbifold,
}

impl Kind {
    /// The lower-case name used in JSON output: `orbifold`, `bad`, `non-orbifold`.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Orbifold => "orbifold",
            Kind::Bad => "bad",
            Kind::NonOrbifold => "non-orbifold",
        }
    }
}

impl fmt::Display for Kind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A corner order that a signature cannot hold.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct InvalidOrder {
    /// The 0-based index of the corner.
    pub index: usize,
    /// The offending order.
    pub order: Order,
}

impl fmt::Display for InvalidOrder {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "corner {} has order {}, but corner orders must be at least 1",
            self.index + 1,
            self.order
        )
    }
}

impl std::error::Error for InvalidOrder {}

/// A kaleidoscopic signature `*k₁…k_N`: a polygon with N corners of angles π/kᵢ, all walls mirrors.
///
/// Corners of order 1 (angle π) are no corners and are dropped, so `*11` is `*`, the one-mirror
/// hemisphere. Two signatures are the same orbifold when one is a rotation or reversal of the
/// other; [`Signature::canonical`] picks the smallest reading, and equality compares readings as
/// written (use `a.canonical() == b.canonical()` for "same orbifold").
///
/// ```
/// use orbifold::{Geometry, Kind, Signature};
/// let sig: Signature = "*632".parse().unwrap();
/// assert_eq!(sig.canonical().to_string(), "*236");
/// assert_eq!(sig.euler_characteristic().to_string(), "0");
/// assert_eq!(sig.geometry(), Geometry::Euclidean);
/// assert_eq!(sig.kind(), Kind::Orbifold);
///
/// let bad: Signature = "*23".parse().unwrap();
/// assert_eq!(bad.kind(), Kind::Bad);
/// ```
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Signature {
    corners: Vec<Order>,
}

impl Signature {
    /// A signature from its corner orders, read around the polygon. Orders of 1 are dropped;
    /// orders below 1 are an error.
    ///
    /// ```
    /// use orbifold::{Order, Signature};
    /// let sig = Signature::new([2, 3, 3, 3].map(Order::integer)).unwrap();
    /// assert_eq!(sig.to_string(), "*2333");
    /// ```
    pub fn new(corners: impl IntoIterator<Item = Order>) -> Result<Self, InvalidOrder> {
        let mut kept = Vec::new();
        for (index, order) in corners.into_iter().enumerate() {
            let below_one = match order {
                Order::Finite(r) => *r.numer() < *r.denom() || r.numer() == &0,
                Order::Infinite => false,
            };
            if below_one {
                return Err(InvalidOrder { index, order });
            }
            if !order.is_one() {
                kept.push(order);
            }
        }
        Ok(Signature { corners: kept })
    }

    /// The signature with integer corner orders (each ≥ 1; orders of 1 are dropped).
    pub fn from_integers(orders: impl IntoIterator<Item = u64>) -> Result<Self, InvalidOrder> {
        Signature::new(orders.into_iter().map(Order::integer))
    }

    /// Signatures whose corners are already known to be valid (orders > 1).
    pub(crate) fn from_valid_corners(corners: Vec<Order>) -> Self {
        Signature { corners }
    }

    /// The corner orders, in reading order.
    pub fn corners(&self) -> &[Order] {
        &self.corners
    }

    /// The number of corners N (0 for `*`).
    pub fn corner_count(&self) -> usize {
        self.corners.len()
    }

    /// The number of walls: N, except that `*` has one wall and no corner.
    pub fn wall_count(&self) -> usize {
        self.corners.len().max(1)
    }

    /// The canonical reading: the smallest of the 2N rotations and reversals, ∞ after every number.
    pub fn canonical(&self) -> Signature {
        Signature {
            corners: necklace::smallest_reading(&self.corners),
        }
    }

    /// Whether this reading is already canonical.
    pub fn is_canonical(&self) -> bool {
        necklace::is_smallest_reading(&self.corners)
    }

    /// χ = Σ 1/(2kᵢ) − N/2 + 1, exactly (1/∞ = 0).
    pub fn euler_characteristic(&self) -> EulerCharacteristic {
        match self.small_euler_characteristic() {
            Some(chi) => EulerCharacteristic::new(BigRational::new_raw(
                BigInt::from(*chi.numer()),
                BigInt::from(*chi.denom()),
            )),
            None => self.big_euler_characteristic(),
        }
    }

    /// χ in 128-bit arithmetic, the common case; `None` if an intermediate value overflows
    /// (many large coprime orders), in which case [`Self::big_euler_characteristic`] is exact.
    fn small_euler_characteristic(&self) -> Option<Ratio<i128>> {
        let mut reciprocals = Ratio::<i128>::zero();
        for k in &self.corners {
            if let Order::Finite(r) = k {
                let reciprocal = Ratio::new_raw(i128::from(*r.denom()), i128::from(*r.numer()));
                reciprocals = reciprocals.checked_add(&reciprocal)?;
            }
        }
        let n = i128::try_from(self.corners.len()).ok()?;
        let two_minus_n = Ratio::from_integer(2 - n);
        two_minus_n
            .checked_add(&reciprocals)?
            .checked_div(&Ratio::from_integer(2))
    }

    fn big_euler_characteristic(&self) -> EulerCharacteristic {
        let two = BigRational::from_integer(2.into());
        let reciprocals = self
            .corners
            .iter()
            .fold(BigRational::zero(), |sum, k| sum + k.reciprocal());
        let n = BigRational::from_integer(self.corners.len().into());
        EulerCharacteristic::new(BigRational::one() + (reciprocals - n) / two)
    }

    /// The geometry of the universal cover, by the sign of χ. This agrees with the angle-sum test
    /// Σπ/kᵢ against (N − 2)π, since 2πχ = Σπ/kᵢ − (N − 2)π.
    pub fn geometry(&self) -> Geometry {
        match self.small_euler_characteristic() {
            Some(chi) => Geometry::from_sign(chi.numer().cmp(&0)),
            None => self.big_euler_characteristic().geometry(),
        }
    }

    /// The sum of the corner angles Σπ/kᵢ in radians.
    pub fn angle_sum(&self) -> f64 {
        self.corners.iter().map(Order::corner_angle).sum()
    }

    /// Whether every corner order is an integer or ∞.
    pub fn has_orbifold_orders(&self) -> bool {
        self.corners.iter().all(Order::is_orbifold_order)
    }

    /// Whether the polygon cannot exist: one wall meeting itself at a corner, or two walls meeting
    /// twice at different angles.
    fn is_unrealisable(&self) -> bool {
        match self.corners.as_slice() {
            [_] => true,
            [a, b] => a != b,
            _ => false,
        }
    }

    /// Orbifold, bad orbifold, or non-orbifold room.
    pub fn kind(&self) -> Kind {
        if !self.has_orbifold_orders() {
            Kind::NonOrbifold
        } else if self.is_unrealisable() {
            Kind::Bad
        } else {
            Kind::Orbifold
        }
    }

    /// Whether a polygon with these corner angles exists, so that a room can be built on it.
    /// Bad orbifolds and their non-orbifold analogues (`*(3/2)`, `*2(5/2)`) cannot be built.
    pub fn is_buildable(&self) -> bool {
        !self.is_unrealisable()
    }

    /// Why this signature is not a good orbifold, in words; `None` for good orbifolds.
    pub fn reason(&self) -> Option<String> {
        let unrealisable = self.unrealisable_reason();
        let non_integer = self.corners.iter().enumerate().find(|(_, k)| !k.is_orbifold_order()).map(|(i, k)| {
            format!(
                "corner {} has order {k}, which is not an integer: its angle π/k = {} is not π divided by a \
                 whole number, so its mirror images overlap instead of tiling; it is a non-orbifold room",
                i + 1,
                angle_in_pi(k)
            )
        });
        match (non_integer, unrealisable) {
            (None, None) => None,
            (Some(n), None) => Some(format!("{n}, which can still be built and rendered")),
            (None, Some(u)) => Some(format!("{self} is a bad orbifold: {u}; it is never built")),
            (Some(n), Some(u)) => Some(format!("{n}, and it cannot be built: {u}")),
        }
    }

    fn unrealisable_reason(&self) -> Option<String> {
        match self.corners.as_slice() {
            [k] => Some(format!(
                "a single mirror cannot meet itself at a corner of angle π/{k}; the only one-mirror room \
                 is *, the hemisphere bounded by one great circle"
            )),
            [a, b] if a != b => Some(format!(
                "two mirrors that meet twice must meet at the same angle both times, not at π/{a} and π/{b}"
            )),
            _ => None,
        }
    }

    /// The intrinsic area of the polygon, 2π|χ| (Gauss–Bonnet, curvature ±1). `None` for
    /// Euclidean signatures, whose scale is free, and for polygons that cannot be built.
    pub fn area(&self) -> Option<f64> {
        let chi = self.euler_characteristic();
        (self.is_buildable() && chi.geometry() != Geometry::Euclidean).then(|| chi.area())
    }

    /// The order of the reflection group, 2/χ, for spherical orbifolds; `None` otherwise
    /// (infinite groups, bad orbifolds and non-orbifold rooms).
    ///
    /// ```
    /// # use orbifold::Signature;
    /// let order = |s: &str| s.parse::<Signature>().unwrap().group_order();
    /// assert_eq!(order("*235"), Some(120));
    /// assert_eq!(order("*22"), Some(4));
    /// assert_eq!(order("*333"), None);
    /// ```
    pub fn group_order(&self) -> Option<u128> {
        let chi = self.euler_characteristic();
        if self.kind() != Kind::Orbifold || chi.geometry() != Geometry::Spherical {
            return None;
        }
        rational_to_u128(&(BigRational::from_integer(2.into()) / chi.value()))
    }

    /// The number of free shape parameters of the polygon: N − 3 for N ≥ 3 (1 for `*2222`, its
    /// aspect ratio; N − 3 cut lengths for hyperbolic N-gons), 0 for triangles, lunes, `*` and
    /// polygons that cannot be built.
    pub fn free_parameters(&self) -> usize {
        if self.is_buildable() {
            self.corners.len().saturating_sub(3)
        } else {
            0
        }
    }
}

/// "π/2", "2π/3", "0" for a corner angle π/k written as a multiple of π.
fn angle_in_pi(k: &Order) -> String {
    match k {
        Order::Infinite => "0".to_string(),
        Order::Finite(r) => match (*r.denom(), *r.numer()) {
            (1, q) => format!("π/{q}"),
            (p, 1) => format!("{p}π"),
            (p, q) => format!("{p}π/{q}"),
        },
    }
}

impl fmt::Display for Signature {
    /// Kaleidoscopic notation: `*`, `*2333`, `*23456789(10)(11)`, `*∞∞∞`, `*(3/2)33`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("*")?;
        self.corners
            .iter()
            .try_for_each(|k| k.write_in_signature(f))
    }
}

impl FromStr for Signature {
    type Err = ParseError;

    /// Reads kaleidoscopic notation. Conway symbols that are not kaleidoscopic (`632`, `2*22`)
    /// are an error that says so; use [`crate::OrbifoldSymbol`] to read those.
    fn from_str(s: &str) -> Result<Self, ParseError> {
        let raw = parse_symbol(s)?;
        if raw.is_kaleidoscopic() {
            let corners = raw.boundaries.into_iter().next().expect("one boundary");
            return Ok(Signature::from_valid_corners(corners));
        }
        let why = if raw.boundaries.is_empty() {
            "it has no mirror `*`; a kaleidoscopic signature starts with `*`".to_string()
        } else {
            "it has rotation centres, cross-caps, handles or several mirror boundaries as well as `*`; \
             only a single `*` followed by corner orders describes a polygon of mirrors"
                .to_string()
        };
        let first = s.chars().take_while(|c| c.is_whitespace()).count() + 1;
        Err(ParseError::new(
            s,
            first,
            s.trim().chars().count(),
            ParseErrorKind::NotKaleidoscopic(why),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn order() -> impl Strategy<Value = Order> {
        prop_oneof![
            (2u64..=12).prop_map(Order::integer),
            (1u64..=u64::MAX / 2).prop_map(|k| Order::integer(k + 1)),
            Just(Order::Infinite),
            (1u64..=1_000_000, 1u64..=1_000_000)
                .prop_map(|(q, extra)| Order::ratio(q + extra, q).unwrap()),
        ]
    }

    proptest! {
        /// The 128-bit fast path, when it answers, equals the arbitrary-precision computation.
        #[test]
        fn fast_and_exact_euler_characteristics_agree(corners in prop::collection::vec(order(), 0..=12)) {
            let sig = Signature::new(corners).unwrap();
            let exact = sig.big_euler_characteristic();
            prop_assert_eq!(sig.euler_characteristic(), exact.clone());
            prop_assert_eq!(sig.geometry(), exact.geometry());
        }
    }

    #[test]
    fn overflow_falls_back_to_exact_arithmetic() {
        let primes = [
            1_000_003u64,
            1_000_033,
            1_000_037,
            1_000_039,
            1_000_081,
            1_000_099,
            1_000_117,
            1_000_121,
        ];
        let sig = Signature::from_integers(primes).unwrap();
        assert!(sig.small_euler_characteristic().is_none());
        assert_eq!(sig.euler_characteristic(), sig.big_euler_characteristic());
        assert_eq!(sig.geometry(), Geometry::Hyperbolic);
    }
}
