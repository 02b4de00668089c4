//! The order of a corner or cone point: an integer, ∞, or (for non-orbifold rooms) a rational.

use std::cmp::Ordering;
use std::fmt;

use num_bigint::BigInt;
use num_rational::{BigRational, Ratio};
use num_traits::{One, ToPrimitive, Zero};

/// The order `k` of a corner (angle π/k) or of a cone point (rotation by 2π/k).
///
/// Orbifold corners have integer orders ≥ 2; an ideal corner, whose two walls meet tangentially
/// on the circle at infinity, has order ∞ (angle 0). Non-orbifold rooms may have any rational
/// order greater than 1, such as 3/2 (a corner of 2π/3). Orders compare as numbers, with ∞ after
/// every finite order.
///
/// ```
/// use orbifold::Order;
/// let three_halves = Order::ratio(3, 2).unwrap();
/// assert!(Order::integer(2) > three_halves);
/// assert!(Order::Infinite > Order::integer(1_000_000));
/// assert_eq!(Order::integer(12).to_string(), "12");
/// assert_eq!(three_halves.to_string(), "3/2");
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Order {
    /// A finite order `p/q` in lowest terms (an integer when `q = 1`).
    Finite(Ratio<u64>),
    /// An ideal corner or a cusp: angle 0.
    Infinite,
}

impl Order {
    /// The integer order `k`.
    pub fn integer(k: u64) -> Self {
        Order::Finite(Ratio::from_integer(k))
    }

    /// The rational order `p/q`, reduced; `None` when `q` is 0.
    pub fn ratio(p: u64, q: u64) -> Option<Self> {
        (q != 0).then(|| Order::Finite(Ratio::new(p, q)))
    }

    /// The integer value, if this order is a finite integer.
    pub fn as_integer(&self) -> Option<u64> {
        match self {
            Order::Finite(r) if r.is_integer() => Some(r.to_integer()),
            _ => None,
        }
    }

    /// Whether this order is allowed in an orbifold: an integer or ∞.
    pub fn is_orbifold_order(&self) -> bool {
        matches!(self, Order::Infinite) || self.as_integer().is_some()
    }

    /// Whether the order is ∞.
    pub fn is_infinite(&self) -> bool {
        matches!(self, Order::Infinite)
    }

    /// Whether the order is exactly 1 (a corner of angle π, which is no corner at all).
    pub fn is_one(&self) -> bool {
        self.as_integer() == Some(1)
    }

    /// 1/k as an exact rational (0 for ∞).
    pub fn reciprocal(&self) -> BigRational {
        match self {
            Order::Finite(r) => {
                BigRational::new(BigInt::from(*r.denom()), BigInt::from(*r.numer()))
            }
            Order::Infinite => BigRational::zero(),
        }
    }

    /// The order as a floating-point number (`f64::INFINITY` for ∞).
    pub fn to_f64(&self) -> f64 {
        match self {
            Order::Finite(r) => *r.numer() as f64 / *r.denom() as f64,
            Order::Infinite => f64::INFINITY,
        }
    }

    /// The corner angle π/k in radians (0 for an ideal corner).
    ///
    /// ```
    /// # use orbifold::Order;
    /// assert!((Order::integer(2).corner_angle() - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
    /// assert_eq!(Order::Infinite.corner_angle(), 0.0);
    /// ```
    pub fn corner_angle(&self) -> f64 {
        match self {
            Order::Finite(r) => std::f64::consts::PI * (*r.denom() as f64) / (*r.numer() as f64),
            Order::Infinite => 0.0,
        }
    }

    /// (k − 1)/k as an exact rational (1 for ∞): what a cone point of order k costs in χ.
    pub fn cone_cost(&self) -> BigRational {
        BigRational::one() - self.reciprocal()
    }

    /// Writes the order as it appears inside a signature: single digits bare, `∞` bare,
    /// everything else in parentheses (`(12)`, `(3/2)`).
    pub fn write_in_signature(&self, out: &mut impl fmt::Write) -> fmt::Result {
        match self.as_integer() {
            Some(k) if k < 10 => write!(out, "{k}"),
            _ if self.is_infinite() => out.write_char('∞'),
            _ => write!(out, "({self})"),
        }
    }
}

impl fmt::Display for Order {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Order::Finite(r) if r.is_integer() => write!(f, "{}", r.numer()),
            Order::Finite(r) => write!(f, "{}/{}", r.numer(), r.denom()),
            Order::Infinite => f.write_str("∞"),
        }
    }
}

impl Ord for Order {
    fn cmp(&self, other: &Self) -> Ordering {
        match (self, other) {
            (Order::Finite(a), Order::Finite(b)) => a.cmp(b),
            (Order::Finite(_), Order::Infinite) => Ordering::Less,
            (Order::Infinite, Order::Finite(_)) => Ordering::Greater,
            (Order::Infinite, Order::Infinite) => Ordering::Equal,
        }
    }
}

impl PartialOrd for Order {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl From<u64> for Order {
    fn from(k: u64) -> Self {
        Order::integer(k)
    }
}

/// Converts an exact rational that is known to be an integer into `u128`, if it fits.
pub(crate) fn rational_to_u128(r: &BigRational) -> Option<u128> {
    r.is_integer().then(|| r.to_integer().to_u128()).flatten()
}
