//! Enumeration of good kaleidoscopic orbifolds (the seed's chapter 4), each dihedral class once.

use std::fmt;

use crate::euler::Geometry;
use crate::necklace::Bracelets;
use crate::order::Order;
use crate::signature::Signature;

/// What to enumerate.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EnumerationOptions {
    /// The number of corners N (0 gives `*`; 1 gives nothing, since every `*k` is bad).
    pub corners: usize,
    /// The largest finite corner order K: orders run over 2..=K.
    pub max_order: u64,
    /// Also use ideal corners (order ∞).
    pub ideal: bool,
    /// Keep only orbifolds of this geometry.
    pub geometry: Option<Geometry>,
}

/// Options that cannot be enumerated.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum EnumerationError {
    /// No corner order is available: K < 2 and no ideal corners.
    NoOrders {
        /// The requested largest order.
        max_order: u64,
    },
}

impl fmt::Display for EnumerationError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EnumerationError::NoOrders { max_order } => write!(
                f,
                "the largest corner order is {max_order}, but orbifold corners have order at least 2; \
                 ask for a maximum order of 2 or more, or for ideal corners"
            ),
        }
    }
}

impl std::error::Error for EnumerationError {}

/// An iterator over every good kaleidoscopic orbifold with the given number of corners and corner
/// orders, each dihedral class exactly once, in canonical form and lexicographic order.
///
/// ```
/// use orbifold::{Enumeration, EnumerationOptions, Geometry};
/// let options = EnumerationOptions { corners: 3, max_order: 6, ideal: false, geometry: Some(Geometry::Euclidean) };
/// let names: Vec<String> = Enumeration::new(options).unwrap().map(|s| s.to_string()).collect();
/// assert_eq!(names, ["*236", "*244", "*333"]);
/// ```
#[derive(Clone, Debug)]
pub struct Enumeration {
    alphabet: Vec<Order>,
    bracelets: Bracelets,
    corners: usize,
    geometry: Option<Geometry>,
}

impl Enumeration {
    /// Prepares the enumeration; nothing is computed until it is iterated.
    pub fn new(options: EnumerationOptions) -> Result<Self, EnumerationError> {
        let mut alphabet: Vec<Order> = (2..=options.max_order).map(Order::integer).collect();
        if options.ideal {
            alphabet.push(Order::Infinite);
        }
        if alphabet.is_empty() {
            return Err(EnumerationError::NoOrders {
                max_order: options.max_order,
            });
        }
        Ok(Enumeration {
            bracelets: Bracelets::new(options.corners, alphabet.len()),
            alphabet,
            corners: options.corners,
            geometry: options.geometry,
        })
    }

    /// Good orbifolds only: one corner is always bad, two corners must be equal.
    fn is_good(&self, word: &[usize]) -> bool {
        match self.corners {
            1 => false,
            2 => word[0] == word[1],
            _ => true,
        }
    }
}

impl Iterator for Enumeration {
    type Item = Signature;

    fn next(&mut self) -> Option<Signature> {
        loop {
            let word = self.bracelets.next()?;
            if !self.is_good(&word) {
                continue;
            }
            let sig =
                Signature::from_valid_corners(word.iter().map(|&i| self.alphabet[i]).collect());
            if self.geometry.is_none_or(|g| g == sig.geometry()) {
                return Some(sig);
            }
        }
    }
}
