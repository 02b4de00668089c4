//! Cyclic sequences up to rotation and reversal (necklaces and bracelets).
//!
//! The corners of a polygon are read around it from any corner, in either direction: 2N readings
//! of one orbifold. The canonical reading is the lexicographically smallest; enumeration produces
//! each class once by generating canonical readings directly.

use std::cmp::Ordering;

/// Compares two readings of `seq` without building them: `(start, reversed)` reads
/// `seq[start], seq[start ± 1], …` cyclically.
fn compare_readings<T: Ord>(seq: &[T], a: (usize, bool), b: (usize, bool)) -> Ordering {
    let n = seq.len();
    let at = |(start, reversed): (usize, bool), i: usize| {
        if reversed {
            &seq[(start + n - i % n) % n]
        } else {
            &seq[(start + i) % n]
        }
    };
    (0..n)
        .map(|i| at(a, i).cmp(at(b, i)))
        .find(|o| o.is_ne())
        .unwrap_or(Ordering::Equal)
}

fn read<T: Clone>(seq: &[T], (start, reversed): (usize, bool)) -> Vec<T> {
    let n = seq.len();
    (0..n)
        .map(|i| {
            if reversed {
                seq[(start + n - i) % n].clone()
            } else {
                seq[(start + i) % n].clone()
            }
        })
        .collect()
}

fn smallest<T: Ord + Clone>(seq: &[T], directions: &[bool]) -> Vec<T> {
    if seq.is_empty() {
        return Vec::new();
    }
    let readings = directions
        .iter()
        .flat_map(|&rev| (0..seq.len()).map(move |s| (s, rev)));
    let best = readings
        .min_by(|&a, &b| compare_readings(seq, a, b))
        .expect("non-empty");
    read(seq, best)
}

/// The lexicographically smallest of the N rotations of a cyclic sequence.
///
/// ```
/// assert_eq!(orbifold::necklace::smallest_rotation(&[3, 1, 2]), vec![1, 2, 3]);
/// assert_eq!(orbifold::necklace::smallest_rotation(&[2, 1, 3]), vec![1, 3, 2]);
/// ```
pub fn smallest_rotation<T: Ord + Clone>(seq: &[T]) -> Vec<T> {
    smallest(seq, &[false])
}

/// The lexicographically smallest of the 2N readings (rotations and reversals) of a cyclic sequence.
///
/// ```
/// assert_eq!(orbifold::necklace::smallest_reading(&[2, 1, 3]), vec![1, 2, 3]);
/// assert_eq!(orbifold::necklace::smallest_reading(&[6, 3, 2]), vec![2, 3, 6]);
/// ```
pub fn smallest_reading<T: Ord + Clone>(seq: &[T]) -> Vec<T> {
    smallest(seq, &[false, true])
}

/// The reversal of a cyclic sequence that keeps its first element first.
pub fn reversed<T: Clone>(seq: &[T]) -> Vec<T> {
    read(seq, (0, true))
}

/// Whether `seq` is the smallest of its 2N readings.
pub fn is_smallest_reading<T: Ord>(seq: &[T]) -> bool {
    let n = seq.len();
    (0..n).all(|s| {
        compare_readings(seq, (0, false), (s, false)).is_le()
            && compare_readings(seq, (0, false), (s, true)).is_le()
    })
}

/// Every bracelet (cyclic sequence up to rotation and reversal) of length `n` over the alphabet
/// `0..alphabet`, each given once by its smallest reading, in lexicographic order.
///
/// Necklaces come from the Fredricksen–Kessler–Maiorana algorithm in constant amortised time;
/// a necklace is kept when no reading of its reversal is smaller.
///
/// ```
/// use orbifold::necklace::Bracelets;
/// // The 6 bracelets of length 4 over two symbols: 0000 0001 0011 0101 0111 1111.
/// assert_eq!(Bracelets::new(4, 2).count(), 6);
/// ```
#[derive(Clone, Debug)]
pub struct Bracelets {
    n: usize,
    alphabet: usize,
    word: Vec<usize>,
    done: bool,
}

impl Bracelets {
    /// Bracelets of length `n` over `alphabet` symbols.
    pub fn new(n: usize, alphabet: usize) -> Self {
        // The FKM state is a pre-necklace a[1..=n] (a[0] is a sentinel); start at 0…0.
        Bracelets {
            n,
            alphabet,
            word: vec![0; n + 1],
            done: alphabet == 0 && n > 0,
        }
    }

    /// Advances the FKM state to the next pre-necklace; returns the length of its Lyndon prefix,
    /// or `None` when the enumeration is over.
    fn advance(&mut self) -> Option<usize> {
        let a = &mut self.word;
        let mut i = self.n;
        while i > 0 && a[i] == self.alphabet - 1 {
            i -= 1;
        }
        if i == 0 {
            return None;
        }
        a[i] += 1;
        for j in i + 1..=self.n {
            a[j] = a[j - i];
        }
        Some(i)
    }
}

impl Iterator for Bracelets {
    type Item = Vec<usize>;

    fn next(&mut self) -> Option<Vec<usize>> {
        if self.done {
            return None;
        }
        if self.n == 0 {
            self.done = true;
            return Some(Vec::new());
        }
        // The current state is 0…0 on the first call, which is a necklace and a bracelet.
        loop {
            let current = self.word[1..].to_vec();
            let keep = is_necklace_state(&self.word, self.n) && !reversal_is_smaller(&current);
            match self.advance() {
                Some(_) => {}
                None => self.done = true,
            }
            if keep {
                return Some(current);
            }
            if self.done {
                return None;
            }
        }
    }
}

/// A pre-necklace a[1..=n] is a necklace iff n is divisible by the length of its longest Lyndon prefix.
fn is_necklace_state(a: &[usize], n: usize) -> bool {
    let mut p = 1;
    for i in 2..=n {
        match a[i].cmp(&a[i - p]) {
            Ordering::Greater => p = i,
            Ordering::Equal => {}
            Ordering::Less => return false,
        }
    }
    n.is_multiple_of(p)
}

/// For a necklace `w` (smallest rotation): whether some rotation of its reversal is smaller.
fn reversal_is_smaller(w: &[usize]) -> bool {
    let n = w.len();
    (0..n).any(|s| compare_readings(w, (s, true), (0, false)).is_lt())
}
