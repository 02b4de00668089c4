//! The Euler characteristic, exact, and the geometry its sign selects.

use std::cmp::Ordering;
use std::fmt;

use num_rational::BigRational;
use num_traits::{Signed, ToPrimitive, Zero};

/// The geometry of an orbifold's universal cover, selected by the sign of χ.
///
/// ```
/// use orbifold::{Geometry, Signature};
/// let sig: Signature = "*236".parse().unwrap();
/// assert_eq!(sig.geometry(), Geometry::Euclidean);
/// assert_eq!(Geometry::Hyperbolic.curvature(), -1);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Geometry {
    /// Positive curvature: the sphere S² (χ > 0).
    Spherical,
    /// Zero curvature: the Euclidean plane E² (χ = 0).
    Euclidean,
    /// Negative curvature: the hyperbolic plane H² (χ < 0).
    Hyperbolic,
}

impl Geometry {
    /// All three geometries, spherical first.
    pub const ALL: [Geometry; 3] = [
        Geometry::Spherical,
        Geometry::Euclidean,
        Geometry::Hyperbolic,
    ];

    /// The constant curvature κ ∈ {+1, 0, −1} used throughout the geometry code.
    pub fn curvature(self) -> i8 {
        match self {
            Geometry::Spherical => 1,
            Geometry::Euclidean => 0,
            Geometry::Hyperbolic => -1,
        }
    }

    /// The geometry whose χ has the given sign.
    pub fn from_sign(sign: Ordering) -> Self {
        match sign {
            Ordering::Greater => Geometry::Spherical,
            Ordering::Equal => Geometry::Euclidean,
            Ordering::Less => Geometry::Hyperbolic,
        }
    }

    /// The lower-case name, as used in JSON output and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Geometry::Spherical => "spherical",
            Geometry::Euclidean => "euclidean",
            Geometry::Hyperbolic => "hyperbolic",
        }
    }
}

impl fmt::Display for Geometry {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Geometry {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "spherical" | "sphere" | "s" => Ok(Geometry::Spherical),
            "euclidean" | "flat" | "e" => Ok(Geometry::Euclidean),
            "hyperbolic" | "h" => Ok(Geometry::Hyperbolic),
            other => Err(format!(
                "unknown geometry {other:?}; expected spherical, euclidean or hyperbolic"
            )),
        }
    }
}

/// An exact Euler characteristic χ.
///
/// ```
/// use orbifold::Signature;
/// let chi = "*22222".parse::<Signature>().unwrap().euler_characteristic();
/// assert_eq!(chi.to_string(), "-1/4");
/// assert!((chi.to_f64() + 0.25).abs() < 1e-15);
/// ```
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct EulerCharacteristic(BigRational);

impl EulerCharacteristic {
    /// Wraps an exact rational.
    pub fn new(value: BigRational) -> Self {
        EulerCharacteristic(value)
    }

    /// The exact value.
    pub fn value(&self) -> &BigRational {
        &self.0
    }

    /// The sign of χ.
    pub fn sign(&self) -> Ordering {
        self.0.cmp(&BigRational::zero())
    }

    /// The geometry that the sign of χ selects.
    pub fn geometry(&self) -> Geometry {
        Geometry::from_sign(self.sign())
    }

    /// χ as a float (for display and areas).
    pub fn to_f64(&self) -> f64 {
        self.0.to_f64().unwrap_or(f64::NAN)
    }

    /// The intrinsic area 2π|χ| of a fundamental domain in curvature ±1 (Gauss–Bonnet).
    pub fn area(&self) -> f64 {
        2.0 * std::f64::consts::PI * self.0.abs().to_f64().unwrap_or(f64::NAN)
    }

    /// The area 2π|χ| written exactly as a multiple of π: `2π`, `π/2`, `3π/2`, `π/30`, `0`.
    ///
    /// ```
    /// # use orbifold::Signature;
    /// let area = |s: &str| s.parse::<Signature>().unwrap().euler_characteristic().area_in_pi();
    /// assert_eq!(area("*"), "2π");
    /// assert_eq!(area("*235"), "π/30");
    /// assert_eq!(area("*22222"), "π/2");
    /// assert_eq!(area("*2∞∞"), "π/2");
    /// ```
    pub fn area_in_pi(&self) -> String {
        let twice = self.0.abs() * BigRational::from_integer(2.into());
        let (numer, denom) = (twice.numer().to_string(), twice.denom().to_string());
        let numer = match numer.as_str() {
            "0" => return "0".to_string(),
            "1" => "π".to_string(),
            n => format!("{n}π"),
        };
        if denom == "1" {
            numer
        } else {
            format!("{numer}/{denom}")
        }
    }
}

impl fmt::Display for EulerCharacteristic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0.is_integer() {
            write!(f, "{}", self.0.numer())
        } else {
            write!(f, "{}/{}", self.0.numer(), self.0.denom())
        }
    }
}
