//! Every free shape parameter of a hyperbolic star: the star's polygon deformed, keeping its
//! side pairings, until chosen closed geodesics have the lengths asked for (docs/orbifolds.md,
//! "Shape parameters of the star").
//!
//! **What is deformed.** The star (or the balanced star) of a hyperbolic symbol is one point of
//! a manifold of polygons with the same combinatorics whose pairings are isometries and whose
//! vertex cycles have their angle sums. Its unknowns are the corners (a finite corner: its
//! hyperboloid coordinates x, y; an ideal corner: its bearing on the circle at infinity); its
//! equations are Poincaré's conditions (Maskit, "On Poincaré's theorem for fundamental
//! polygons", Adv. Math. 7, 1971; Beardon, *The Geometry of Discrete Groups*, 1983, §9.8):
//! every paired finite edge has its partner's length, every finite vertex cycle its angle sum
//! (2π/k at a cone, π/k on a mirror, 2π at an ordinary point) and every cusp its parabolic
//! pairing (the two finite ends of its edges on one horocycle: ⟨a, c⟩ = ⟨b, c⟩ for the null
//! vector c). Near the star these equations are independent (the code checks the rank), so the
//! polygons form a manifold of dimension T + E + 3: T = [`OrbifoldSymbol::free_parameters`] (Thurston's −3χ(X) + 2·cones +
//! corners, the dimension of the Teichmüller space of the orbifold), E the ways to move the
//! cut system (the base point v, the cuts' feet on a boundary), which change the polygon but not
//! the group, and 3 for the isometries of H².
//!
//! **The parameters.** A closed geodesic's length ℓ(w) = acosh((tr W − det W)/2), W the 3×3
//! matrix of an element w of the group (translation length; for an orientation-reversing w, a
//! glide, that of its one-sided geodesic), depends only on the group up to conjugacy: it is
//! constant along the E + 3 directions. Lengths of enough closed geodesics are local coordinates
//! on Teichmüller space (as Fenchel–Nielsen lengths and twists are; Fenchel and Nielsen,
//! *Discontinuous Groups of Isometries in the Hyperbolic Plane*, 2003; trace coordinates in
//! Goldman, "Trace coordinates on Fricke spaces", 2009). The words are chosen once, at the star,
//! among the side pairings, their products by twos and, if needed, by threes (the shortest
//! first): greedily, each time the word whose gradient on the manifold's tangent space has the
//! largest part outside the span of those already chosen, until T are chosen. Parameter k is the
//! chosen word's length as a factor of its length in the star: 1 is the star itself, which
//! therefore stays the default exactly.
//!
//! **Solving.** From the star, Newton's method on [equations; ℓ(wₖ) − φₖ·ℓ₀(wₖ)] with the
//! minimum-norm step (the pseudo-inverse of the Jacobian, by a QR factorisation of its
//! transpose): the step is orthogonal to the directions that change neither equation nor length,
//! which are the E + 3 that do not matter, so the polygon moves no more than the lengths ask. The
//! factors are reached along a homotopy from 1 with an adaptive step. The result is checked (angle
//! sums and paired lengths to 1e-9, the lengths asked for to 1e-9 relative, both times the size of
//! the corners' coordinates, whose rounding they carry; every corner convex) before it is
//! returned; otherwise the answer is a [`LayoutError::Unrealisable`], never a wrong polygon. The
//! Jacobians are central differences; the linear algebra is modified Gram–Schmidt (twice), as the
//! systems have at most a few dozen unknowns.
//!
//! **Exceptions.** A corner of angle π in a cycle of several (the balanced star's two copies of v
//! when it has two sectors) is kept at π, or convexity would be lost at once. A balanced star
//! whose paired edges have length 0 (the cone and both copies of v at one point, as a cone of
//! order 2 and one boundary with corners would give) is not deformed: it keeps no parameters, and
//! `missing_parameters` says so; no symbol reaches it, as that family (`2*2222`, `2*3∞`) has its
//! folded polygon of mirrors instead (`textbook`). Why the words are not longer than three letters
//! nor longer than 30: the trace of a long product comes out of cancellations between entries of
//! size e^ℓ; the sign of det W is taken from the letters for the same reason.

use std::collections::HashMap;
use std::f64::consts::PI;
use std::sync::{Mutex, OnceLock};

use glam::{DMat3, DVec3};

use super::geometry::{corner_angle, wall_through};
use super::{Draft, EdgeKind, Glue, finish, pair_letters};
use crate::conway::OrbifoldSymbol;
use crate::cover::reflection;
use crate::layout::LayoutError;
use crate::space::Space;

/// The documented range of every length factor (exclusive). Lengths of crossing geodesics are
/// not independent far from the star, so the box is small: a random corner of it was valid for
/// each of 6000 random symbols of up to 18 parameters (the ignored test `deform::tests::sweep`;
/// at (0.97, 1.03) 1 of 8000 failed, at (0.95, 1.05) 9 of 2000), and the property test
/// `deformed_stars_meet_poincare` samples it. Not proved: a box of lengths is not a product in
/// Teichmüller space.
pub const FACTOR_RANGE: (f64, f64) = (0.98, 1.02);

/// Equations and lengths to this accuracy, times the corners' reach (below), or the polygon is
/// refused.
const TOLERANCE: f64 = 1e-9;

/// The largest time coordinate (cosh of the distance from the origin) of a finite corner, at
/// least 1: lengths and angles at far corners come from coordinates of that size, so their
/// rounding grows with it (the tests of Poincaré's conditions allow the same).
fn reach(points: &[DVec3], ideal: &[bool]) -> f64 {
    points
        .iter()
        .zip(ideal)
        .filter(|(_, i)| !**i)
        .fold(1.0f64, |m, (p, _)| m.max(p.z))
}

/// A letter of a word: a generator (the neighbour of a pair's lower edge, or a mirror's
/// reflection), or its inverse.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Letter {
    edge: usize,
    inverse: bool,
}

/// The polygon's combinatorics and Poincaré's conditions on its corners.
struct Problem {
    space: Space,
    ideal: Vec<bool>,
    glue: Vec<Glue>,
    /// Paired edges (i < j) with finite ends, of equal lengths.
    lengths: Vec<(usize, usize)>,
    /// Cusps: (ideal corner c, finite corners a, b) with a and b on one horocycle about c.
    cusps: Vec<(usize, usize, usize)>,
    /// Finite vertex cycles and their angle sums.
    angles: Vec<(Vec<usize>, f64)>,
}

/// The star's draft with parameters: the draft itself at the default (every factor 1, or none
/// given), or the polygon with the lengths asked for.
pub(crate) fn deformed(
    symbol: &OrbifoldSymbol,
    space: Space,
    star: Draft,
    given: Option<&[f64]>,
) -> Result<Draft, LayoutError> {
    let problem = Problem::new(symbol, space, &star)?;
    let x0 = problem.pack(&star.points);
    let words = words_of(symbol, &problem, &x0, &star.points);
    let defaults = vec![1.0; words.len()];
    let ranges = vec![FACTOR_RANGE; words.len()];
    let factors = super::textbook::take_parameters(given, &defaults, &ranges)?;
    let lengths0 = problem.lengths_of(&problem.unpack(&x0), &words);
    let meanings = meanings(&problem, &words, &lengths0);
    let mut draft = Draft {
        parameters: factors.clone(),
        ranges,
        meanings,
        ..star
    };
    if factors.iter().all(|&f| f == 1.0) {
        return Ok(draft);
    }
    let targets: Vec<f64> = lengths0.iter().zip(&factors).map(|(l, f)| l * f).collect();
    let x = solve(&problem, &words, x0, &lengths0, &targets)?;
    let points = problem.unpack(&x);
    draft.centre = space.normalize_point(points.iter().copied().sum());
    draft.points = points;
    draft.walls = None;
    draft.neighbours = None;
    Ok(draft)
}

/// At most this many symbols' words are remembered by [`words_of`].
const REMEMBERED: usize = 256;

/// The words whose lengths are `symbol`'s parameters ([`choose_words`]; none for a degenerate
/// star). They depend on the symbol alone, through its default star, and choosing them is most
/// of the cost of a default polygon, which a studio builds several times a frame: they are
/// chosen once per symbol and remembered.
fn words_of(
    symbol: &OrbifoldSymbol,
    problem: &Problem,
    x0: &[f64],
    star: &[DVec3],
) -> Vec<Vec<Letter>> {
    type Remembered = Mutex<HashMap<String, Vec<Vec<Letter>>>>;
    static WORDS: OnceLock<Remembered> = OnceLock::new();
    let key = symbol.to_string();
    let remembered = WORDS.get_or_init(Default::default);
    if let Some(words) = remembered.lock().ok().and_then(|m| m.get(&key).cloned()) {
        return words;
    }
    let words = if problem.degenerate(star) {
        Vec::new()
    } else {
        choose_words(problem, x0, symbol.free_parameters())
    };
    if let Ok(mut m) = remembered.lock() {
        if m.len() >= REMEMBERED {
            m.clear();
        }
        m.insert(key, words.clone());
    }
    words
}

impl Problem {
    /// The conditions of the star's polygon, read from its finished default (its cycles).
    fn new(symbol: &OrbifoldSymbol, space: Space, star: &Draft) -> Result<Problem, LayoutError> {
        let polygon = finish(symbol, space, star.clone(), DMat3::IDENTITY)?;
        let n = star.points.len();
        let mut problem = Problem {
            space,
            ideal: star.ideal.clone(),
            glue: star.glue.clone(),
            lengths: Vec::new(),
            cusps: Vec::new(),
            angles: Vec::new(),
        };
        let finite_edge = |i: usize| !star.ideal[i] && !star.ideal[(i + 1) % n];
        for (i, e) in polygon.edges.iter().enumerate() {
            if let EdgeKind::Paired { partner } = e.kind
                && i < partner
                && finite_edge(i)
                && finite_edge(partner)
            {
                problem.lengths.push((i, partner));
            }
        }
        for c in &polygon.cycles {
            let v = c.vertices[0];
            if !star.ideal[v] {
                problem
                    .angles
                    .push((c.vertices.clone(), c.expected_angle_sum()));
                // A corner of angle π in a cycle of several (the two copies of v of a balanced
                // star with two sectors) lies in the middle of a side: it stays there, or the
                // polygon would lose convexity as soon as the cycle's angles move apart.
                let straight = c
                    .vertices
                    .iter()
                    .filter(|&&m| (polygon.vertices[m].angle - PI).abs() < 1e-9);
                if c.vertices.len() > 1 {
                    problem.angles.extend(straight.map(|&m| (vec![m], PI)));
                }
                continue;
            }
            let (before, after) = ((v + n - 1) % n, (v + 1) % n);
            let own_pair = star.glue[before]
                == (Glue::Paired {
                    partner: v,
                    reverses: false,
                });
            match (c.closed, c.vertices.len(), own_pair) {
                // An ideal corner of a mirror boundary: its two mirrors are asymptotic.
                (false, 1, _) => {}
                // A cusp: its two edges paired by the isometry that fixes it.
                (true, 1, true) => problem.cusps.push((v, before, after)),
                _ => {
                    return Err(LayoutError::Unsupported(
                        "an ideal vertex cycle of several corners cannot be deformed".into(),
                    ));
                }
            }
        }
        Ok(problem)
    }

    /// Whether a paired edge has length 0: the balanced star of a cone of order 2 between the
    /// two copies of v would put all three at one point of a side, where the lengths are not
    /// differentiable; such a star is kept rigid. (The one family that would, `2*k₁…kₙ`, is built
    /// as a folded polygon of mirrors instead.)
    fn degenerate(&self, points: &[DVec3]) -> bool {
        let n = points.len();
        self.lengths
            .iter()
            .any(|&(i, _)| self.space.ambient_distance(points[i], points[(i + 1) % n]) < 1e-6)
    }

    /// The unknowns: x, y of each finite corner on the hyperboloid, the bearing of each ideal one.
    fn pack(&self, points: &[DVec3]) -> Vec<f64> {
        let mut x = Vec::new();
        for (p, &ideal) in points.iter().zip(&self.ideal) {
            if ideal {
                x.push(p.y.atan2(p.x));
            } else {
                x.extend([p.x, p.y]);
            }
        }
        x
    }

    fn unpack(&self, x: &[f64]) -> Vec<DVec3> {
        let mut at = 0;
        self.ideal
            .iter()
            .map(|&ideal| {
                if ideal {
                    at += 1;
                    let (s, c) = x[at - 1].sin_cos();
                    DVec3::new(c, s, 1.0)
                } else {
                    at += 2;
                    let (a, b) = (x[at - 2], x[at - 1]);
                    DVec3::new(a, b, (1.0 + a * a + b * b).sqrt())
                }
            })
            .collect()
    }

    /// Poincaré's conditions as residuals: paired lengths, cusps' horocycles, angle sums.
    fn conditions(&self, points: &[DVec3]) -> Vec<f64> {
        let space = self.space;
        let n = points.len();
        let length = |i: usize| space.ambient_distance(points[i], points[(i + 1) % n]);
        let horocycle = |c: usize, a: usize| (-space.point_dot(points[a], points[c])).ln();
        let mut out: Vec<f64> = self
            .lengths
            .iter()
            .map(|&(i, j)| length(i) - length(j))
            .collect();
        out.extend(
            self.cusps
                .iter()
                .map(|&(c, a, b)| horocycle(c, a) - horocycle(c, b)),
        );
        out.extend(self.angles.iter().map(|(members, sum)| {
            members.iter().map(|&v| self.angle(points, v)).sum::<f64>() - sum
        }));
        out
    }

    fn angle(&self, points: &[DVec3], v: usize) -> f64 {
        let n = points.len();
        corner_angle(
            self.space,
            points[v],
            points[(v + 1) % n],
            points[(v + n - 1) % n],
        )
    }

    /// Every finite corner convex (a cone of order 2 has the angle π, in the middle of a side).
    fn convex(&self, points: &[DVec3]) -> bool {
        (0..points.len()).filter(|&v| !self.ideal[v]).all(|v| {
            let a = self.angle(points, v);
            a > 0.0 && a < PI + 1e-9
        })
    }

    /// The generators: `neighbour(i)` of every edge, from the corners.
    fn generators(&self, points: &[DVec3]) -> Vec<DMat3> {
        let space = self.space;
        let n = points.len();
        let inside = space.normalize_point(points.iter().copied().sum());
        let walls: Vec<DVec3> = (0..n)
            .map(|i| wall_through(space, points[i], points[(i + 1) % n], inside))
            .collect();
        (0..n)
            .map(|i| match self.glue[i] {
                Glue::Mirror => reflection(space, walls[i]),
                Glue::Paired { .. } => {
                    super::neighbour(space, points, &self.ideal, &walls, &self.glue, i)
                }
            })
            .collect()
    }

    /// The translation lengths of `words`.
    fn lengths_of(&self, points: &[DVec3], words: &[Vec<Letter>]) -> Vec<f64> {
        let generators = self.generators(points);
        words
            .iter()
            .map(|w| translation_length(word_matrix(&generators, w), reverses(&self.glue, w)))
            .collect()
    }

    /// Residuals [conditions; ℓ(w) − target] at `x`.
    fn residual(&self, x: &[f64], words: &[Vec<Letter>], targets: &[f64]) -> Vec<f64> {
        let points = self.unpack(x);
        let mut out = self.conditions(&points);
        let lengths = self.lengths_of(&points, words);
        out.extend(lengths.iter().zip(targets).map(|(l, t)| l - t));
        out
    }
}

fn word_matrix(generators: &[DMat3], word: &[Letter]) -> DMat3 {
    word.iter().fold(DMat3::IDENTITY, |m, l| {
        let g = generators[l.edge];
        m * if l.inverse { g.inverse() } else { g }
    })
}

/// acosh((tr W − det W)/2): the translation length of a hyperbolic element or a glide (0 for
/// elliptic and parabolic elements and reflections). det W = ±1 is given (`reverses`: −1), not
/// computed: for a long word the determinant of the product comes out of cancellations between
/// entries of size e^ℓ and is not even close to ±1.
fn translation_length(w: DMat3, reverses: bool) -> f64 {
    let det = if reverses { -1.0 } else { 1.0 };
    let c = 0.5 * (w.x_axis.x + w.y_axis.y + w.z_axis.z - det);
    c.max(1.0).acosh()
}

/// Whether a word reverses orientation: an odd number of mirrors and glides.
fn reverses(glue: &[Glue], word: &[Letter]) -> bool {
    word.iter()
        .filter(|l| {
            matches!(
                glue[l.edge],
                Glue::Mirror | Glue::Paired { reverses: true, .. }
            )
        })
        .count()
        % 2
        == 1
}

/// Central differences of `f` at `x`: row r of the result is ∂f_r/∂x.
fn jacobian(x: &[f64], f: impl Fn(&[f64]) -> Vec<f64>) -> Vec<Vec<f64>> {
    let mut columns = Vec::with_capacity(x.len());
    let mut y = x.to_vec();
    for i in 0..x.len() {
        let h = 1e-6 * (1.0 + x[i].abs());
        y[i] = x[i] + h;
        let plus = f(&y);
        y[i] = x[i] - h;
        let minus = f(&y);
        y[i] = x[i];
        columns.push(
            plus.iter()
                .zip(&minus)
                .map(|(a, b)| (a - b) / (2.0 * h))
                .collect::<Vec<f64>>(),
        );
    }
    let rows = columns.first().map_or(0, Vec::len);
    (0..rows)
        .map(|r| columns.iter().map(|c| c[r]).collect())
        .collect()
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// An orthonormal basis of a span of rows, built row by row (modified Gram–Schmidt, twice, for
/// orthogonality to rounding), with the triangular factor: rows = Rᵀ·Q.
#[derive(Default)]
struct RowBasis {
    /// The orthonormal rows (a zero row where a row was dependent).
    q: Vec<Vec<f64>>,
    /// r[k][l] = ⟨row k, q_l⟩ for l ≤ k.
    r: Vec<Vec<f64>>,
}

impl RowBasis {
    /// The part of `row` orthogonal to the basis, and its coefficients along it.
    fn reduce(&self, row: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let mut rest = row.to_vec();
        let mut coefficients = vec![0.0; self.q.len()];
        for _ in 0..2 {
            for (c, q) in coefficients.iter_mut().zip(&self.q) {
                let t = dot(&rest, q);
                *c += t;
                rest.iter_mut().zip(q).for_each(|(x, y)| *x -= t * y);
            }
        }
        (rest, coefficients)
    }

    /// Adds a row; returns the norm of its part outside the previous span.
    fn push(&mut self, row: &[f64]) -> f64 {
        let scale = dot(row, row).sqrt();
        let (rest, mut coefficients) = self.reduce(row);
        let norm = dot(&rest, &rest).sqrt();
        let independent = norm > 1e-10 * scale.max(1e-300);
        coefficients.push(if independent { norm } else { 0.0 });
        self.q.push(if independent {
            rest.iter().map(|x| x / norm).collect()
        } else {
            vec![0.0; row.len()]
        });
        self.r.push(coefficients);
        norm
    }

    /// The minimum-norm x with rows·x = b (least squares over dependent rows): Rᵀ y = b by
    /// forward substitution, x = Qᵀ y.
    fn solve(&self, b: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; b.len()];
        for k in 0..b.len() {
            let diagonal = self.r[k][k];
            if diagonal == 0.0 {
                continue;
            }
            let known: f64 = (0..k).map(|l| self.r[k][l] * y[l]).sum();
            y[k] = (b[k] - known) / diagonal;
        }
        let width = self.q.first().map_or(0, Vec::len);
        let mut x = vec![0.0; width];
        for (q, yk) in self.q.iter().zip(&y) {
            x.iter_mut().zip(q).for_each(|(a, b)| *a += yk * b);
        }
        x
    }
}

/// Candidate words: single generators, then products of two, then of three, with inverses (of
/// pairings: a reflection is its own inverse). With `sorted`, the letters' generators are distinct
/// and in the edges' order (a·b and b·a are conjugate, so of two letters that loses nothing);
/// without, in every order and repeated, as a·c·b and a·b·c are not conjugate.
fn candidate_words(problem: &Problem, letters: usize, sorted: bool) -> Vec<Vec<Letter>> {
    let generators: Vec<usize> = (0..problem.glue.len())
        .filter(|&i| match problem.glue[i] {
            Glue::Mirror => true,
            Glue::Paired { partner, .. } => i < partner,
        })
        .collect();
    let signs = |e: usize| match problem.glue[e] {
        Glue::Paired { .. } => vec![false, true],
        Glue::Mirror => vec![false],
    };
    let mut words: Vec<Vec<Letter>> = vec![Vec::new()];
    for _ in 0..letters {
        let mut longer = Vec::new();
        for w in &words {
            let last = match w.last() {
                Some(l) if sorted => l.edge + 1,
                _ => 0,
            };
            for &g in generators.iter().filter(|&&g| g >= last) {
                for inverse in signs(g) {
                    // The first letter is never inverted: w and w⁻¹ have the same length.
                    if w.is_empty() && inverse {
                        continue;
                    }
                    let mut v = w.clone();
                    v.push(Letter { edge: g, inverse });
                    longer.push(v);
                }
            }
        }
        words = longer;
    }
    words
}

/// The longest closed geodesic chosen: longer words are products of matrices with entries of
/// size e^ℓ whose trace comes out of cancellations, and their lengths lose digits.
const MAX_LENGTH: f64 = 30.0;

/// A word's weight in the choice: shorter words are preferred when they do nearly as well.
fn preference(word: &[Letter]) -> f64 {
    [1.0, 0.8, 0.6][word.len().min(3) - 1]
}

/// The smallest part of a chosen word's gradient (of log ℓ, per unit of the corners'
/// coordinates) outside the span of the conditions and the words before it, relative to the
/// smaller of the first word's and the word's own part outside the conditions' span (the sine
/// of its angle to the span): below it the lengths would be poor coordinates (nearly
/// dependent), and Newton's steps long. The word's own part counts because a first word much
/// steeper than the others would otherwise turn away independent ones: in `o233*2∞∞*3` the
/// sixteenth word keeps a quarter of its gradient, but only 0.0049 of the first word's.
const INDEPENDENCE: f64 = 0.005;

/// T words whose lengths are independent on the manifold of polygons at `x0` (fewer when no
/// product of up to three generators gives more). Greedy, as column pivoting in QR: each time the
/// word whose gradient has the largest weighted part outside the span so far.
fn choose_words(problem: &Problem, x0: &[f64], count: usize) -> Vec<Vec<Letter>> {
    let conditions = jacobian(x0, |x| problem.conditions(&problem.unpack(x)));
    let mut chosen: Vec<Vec<Letter>> = Vec::new();
    // Words of three letters only where those of up to two do not give T, and those in every
    // order of their letters only where three in the edges' order do not.
    for (longest, sorted) in [(2, true), (3, true), (3, false)] {
        if chosen.len() >= count {
            break;
        }
        chosen.clear();
        let mut basis = RowBasis::default();
        for row in &conditions {
            basis.push(row);
        }
        let candidates: Vec<Vec<Letter>> = (1..=longest)
            .flat_map(|letters| candidate_words(problem, letters, sorted))
            .filter(|w| {
                let l = problem.lengths_of(&problem.unpack(x0), std::slice::from_ref(w))[0];
                l > 0.05 && l < MAX_LENGTH
            })
            .collect();
        if candidates.is_empty() {
            continue;
        }
        let lengths0 = problem.lengths_of(&problem.unpack(x0), &candidates);
        // Gradients of log ℓ: the relative change, comparable between words.
        let gradients: Vec<Vec<f64>> = jacobian(x0, |x| {
            let l = problem.lengths_of(&problem.unpack(x), &candidates);
            l.iter().zip(&lengths0).map(|(a, b)| (a / b).ln()).collect()
        });
        let mut rests: Vec<Vec<f64>> = gradients.iter().map(|g| basis.reduce(g).0).collect();
        // Each word's gradient on the manifold (outside the conditions' span): how much of it
        // is left outside the chosen words' span is the sine of its angle to that span.
        let tangents: Vec<f64> = rests.iter().map(|r| dot(r, r).sqrt()).collect();
        let mut firsts = None;
        while chosen.len() < count {
            let score = |k: usize| dot(&rests[k], &rests[k]).sqrt() * preference(&candidates[k]);
            let best = (0..candidates.len())
                .max_by(|&a, &b| score(a).total_cmp(&score(b)))
                .expect("candidates");
            let norm = dot(&rests[best], &rests[best]).sqrt();
            let first = *firsts.get_or_insert(norm);
            if norm < INDEPENDENCE * first && norm < INDEPENDENCE * tangents[best] {
                break;
            }
            let q: Vec<f64> = rests[best].iter().map(|x| x / norm).collect();
            basis.push(&gradients[best]);
            chosen.push(candidates[best].clone());
            for r in &mut rests {
                let t = dot(r, &q);
                r.iter_mut().zip(&q).for_each(|(a, b)| *a -= t * b);
            }
        }
    }
    chosen
}

/// Newton's method with minimum-norm steps along a homotopy from the star's lengths to the
/// targets; the result checked.
fn solve(
    problem: &Problem,
    words: &[Vec<Letter>],
    x0: Vec<f64>,
    start: &[f64],
    targets: &[f64],
) -> Result<Vec<f64>, LayoutError> {
    let towards = |s: f64| -> Vec<f64> {
        start
            .iter()
            .zip(targets)
            .map(|(a, b)| a + s * (b - a))
            .collect()
    };
    let (mut x, mut s, mut step) = (x0, 0.0f64, 1.0f64);
    while s < 1.0 {
        let next = (s + step).min(1.0);
        match newton(problem, words, &x, &towards(next)) {
            Some(y) if problem.convex(&problem.unpack(&y)) => {
                (x, s) = (y, next);
                step = (2.0 * step).min(1.0);
            }
            _ if step > 1.0 / 256.0 => step /= 2.0,
            _ => {
                return Err(LayoutError::Unrealisable(
                    "no convex polygon of the star's combinatorics has these lengths".into(),
                ));
            }
        }
    }
    check(problem, words, &x, targets)?;
    Ok(x)
}

fn newton(
    problem: &Problem,
    words: &[Vec<Letter>],
    x0: &[f64],
    targets: &[f64],
) -> Option<Vec<f64>> {
    let residual = |x: &[f64]| problem.residual(x, words, targets);
    let tolerance = |x: &[f64]| TOLERANCE * reach(&problem.unpack(x), &problem.ideal);
    let size = |r: &[f64]| r.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut x = x0.to_vec();
    let mut r = residual(&x);
    for _ in 0..40 {
        if size(&r) < 1e-12 {
            return Some(x);
        }
        let mut basis = RowBasis::default();
        for row in jacobian(&x, residual) {
            basis.push(&row);
        }
        let minus: Vec<f64> = r.iter().map(|v| -v).collect();
        let dx = basis.solve(&minus);
        // Damped: halve the step until the residual falls.
        let mut t = 1.0;
        loop {
            let y: Vec<f64> = x.iter().zip(&dx).map(|(a, b)| a + t * b).collect();
            let ry = residual(&y);
            if ry.iter().all(|v| v.is_finite()) && size(&ry) < size(&r) {
                (x, r) = (y, ry);
                break;
            }
            t /= 2.0;
            if t < 1e-3 {
                return (size(&r) < 0.5 * tolerance(&x)).then_some(x);
            }
        }
    }
    (size(&r) < 0.5 * tolerance(&x)).then_some(x)
}

/// The polygon meets Poincaré's conditions and has the lengths asked for, to [`TOLERANCE`]
/// times its [`reach`].
fn check(
    problem: &Problem,
    words: &[Vec<Letter>],
    x: &[f64],
    targets: &[f64],
) -> Result<(), LayoutError> {
    let points = problem.unpack(x);
    let worst = problem
        .conditions(&points)
        .iter()
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let lengths = problem.lengths_of(&points, words);
    let off = lengths
        .iter()
        .zip(targets)
        .fold(0.0f64, |m, (l, t)| m.max((l - t).abs() / t));
    let tolerance = TOLERANCE * reach(&points, &problem.ideal);
    if worst < tolerance && off < tolerance && problem.convex(&points) {
        Ok(())
    } else {
        Err(LayoutError::Unrealisable(format!(
            "the deformed star misses Poincaré's conditions by {worst:.1e} and the lengths by {off:.1e}"
        )))
    }
}

/// One sentence per parameter: the word, its default length, the range.
fn meanings(problem: &Problem, words: &[Vec<Letter>], lengths0: &[f64]) -> Vec<String> {
    let partners: Vec<Option<usize>> = problem
        .glue
        .iter()
        .map(|g| match g {
            Glue::Mirror => None,
            Glue::Paired { partner, .. } => Some(*partner),
        })
        .collect();
    let letters = pair_letters(&partners);
    words
        .iter()
        .zip(lengths0)
        .map(|(w, l)| {
            let name = word_name(w, &letters);
            // Name the mirrors a word goes through: their edges carry no letter in the drawing.
            let mirrors: Vec<String> = w
                .iter()
                .filter(|l| letters[l.edge].is_none())
                .map(|l| format!("r{0} the reflection in mirror edge {0}", l.edge))
                .collect();
            let legend = if mirrors.is_empty() {
                String::new()
            } else {
                format!(", {}", mirrors.join(", "))
            };
            format!(
                "the length of the closed geodesic of the word {name} (pairings lettered as \
                 drawn{legend}), as a factor of its default {l:.6}; in ({}, {}), default 1",
                FACTOR_RANGE.0, FACTOR_RANGE.1
            )
        })
        .collect()
}

fn word_name(word: &[Letter], letters: &[Option<char>]) -> String {
    word.iter()
        .map(|l| {
            let base = letters[l.edge].map_or(format!("r{}", l.edge), |c| c.to_string());
            if l.inverse {
                format!("{base}⁻¹")
            } else {
                base
            }
        })
        .collect::<Vec<_>>()
        .join("·")
}

/// The words whose lengths are `symbol`'s parameters, as (edge, inverse) letters, and their
/// lengths in the star (for tests).
#[cfg(test)]
pub(crate) fn words_for(symbol: &OrbifoldSymbol) -> (Vec<Vec<(usize, bool)>>, Vec<f64>) {
    let space = Space::new(symbol.geometry());
    let star = super::star::draft(symbol, space, None).expect("a star");
    let problem = Problem::new(symbol, space, &star).expect("conditions");
    let x0 = problem.pack(&star.points);
    let words = if problem.degenerate(&star.points) {
        Vec::new()
    } else {
        choose_words(&problem, &x0, symbol.free_parameters())
    };
    let lengths = problem.lengths_of(&star.points, &words);
    let plain = words
        .iter()
        .map(|w| w.iter().map(|l| (l.edge, l.inverse)).collect())
        .collect();
    (plain, lengths)
}

/// The translation lengths of words in a finished polygon's generators (for tests): an
/// independent reading of the parameters from the pairings alone.
#[cfg(test)]
pub(crate) fn lengths_in(
    polygon: &super::FundamentalPolygon,
    words: &[Vec<(usize, bool)>],
) -> Vec<f64> {
    let generators: Vec<DMat3> = polygon.edges.iter().map(|e| e.neighbour).collect();
    words
        .iter()
        .map(|w| {
            let letters: Vec<Letter> = w
                .iter()
                .map(|&(edge, inverse)| Letter { edge, inverse })
                .collect();
            let odd = letters
                .iter()
                .filter(|l| polygon.edges[l.edge].reverses_orientation())
                .count()
                % 2
                == 1;
            translation_length(word_matrix(&generators, &letters), odd)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::{LayoutOptions, Shape};
    use crate::pairing::FundamentalPolygon;

    fn with(s: &OrbifoldSymbol, v: Vec<f64>) -> Result<FundamentalPolygon, LayoutError> {
        FundamentalPolygon::new(
            s,
            &LayoutOptions {
                shape: Shape::Parameters(v),
                ..Default::default()
            },
        )
    }

    /// The sweep behind the documented range (docs/orbifolds.md): random hyperbolic symbols of
    /// the star, each at a random corner of the cube of factors. `SEED=7 COUNT=2000 cargo test
    /// --release -p orbifold --lib deform::tests::sweep -- --ignored --nocapture`.
    #[test]
    #[ignore]
    fn sweep() {
        use crate::euler::Geometry;
        use crate::order::Order;
        let mut seed: u64 = std::env::var("SEED").map_or(99, |s| s.parse().unwrap());
        let mut random = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut tried, mut failed, mut short) = (0, 0, 0);
        let mut worst = std::time::Duration::ZERO;
        while tried < std::env::var("COUNT").map_or(600, |s| s.parse().unwrap()) {
            let order = |r: &mut dyn FnMut() -> f64| {
                if r() < 0.12 {
                    Order::Infinite
                } else {
                    Order::integer(2 + (r() * 7.0) as u64)
                }
            };
            let h = (random() * 3.0) as u32;
            let cones: Vec<Order> = (0..(random() * 5.0) as usize)
                .map(|_| order(&mut random))
                .collect();
            let boundaries: Vec<Vec<Order>> = (0..(random() * 3.0) as usize)
                .map(|_| {
                    (0..(random() * 4.0) as usize)
                        .map(|_| order(&mut random))
                        .collect()
                })
                .collect();
            let x = (random() * 3.0) as u32;
            let s = OrbifoldSymbol::new(h, cones, boundaries, x);
            if s.geometry() != Geometry::Hyperbolic
                || s.as_kaleidoscopic().is_some()
                || s.is_bad()
                || 4 * s.handles() as usize
                    + s.cones().len()
                    + s.boundaries().len()
                    + 2 * s.crosscaps() as usize
                    > 9
            {
                continue;
            }
            let p = FundamentalPolygon::new(&s, &Default::default()).unwrap();
            if p.construction != crate::pairing::Construction::Star {
                continue;
            }
            tried += 1;
            if p.missing_parameters > 0 {
                short += 1;
                eprintln!("{s}: missing {}", p.missing_parameters);
            }
            let (lo, hi) = FACTOR_RANGE;
            let v: Vec<f64> = (0..p.parameters.len())
                .map(|_| if random() < 0.5 { lo + 1e-6 } else { hi - 1e-6 })
                .collect();
            let t = std::time::Instant::now();
            if let Err(e) = with(&s, v) {
                failed += 1;
                eprintln!("{s} (T={}): {e}", p.parameters.len());
            }
            worst = worst.max(t.elapsed());
        }
        eprintln!("tried {tried} failed {failed} short {short} worst {worst:?}");
    }

    /// One symbol (`SYMBOL`) at `COUNT` random corners of the box, with the failures' reasons.
    #[test]
    #[ignore]
    fn corners_of_one() {
        let s: OrbifoldSymbol = std::env::var("SYMBOL").unwrap().parse().unwrap();
        let count: usize = std::env::var("COUNT").map_or(50, |c| c.parse().unwrap());
        let p = FundamentalPolygon::new(&s, &Default::default()).unwrap();
        let mut seed = 5u64;
        let mut failed = 0;
        if let Ok(values) = std::env::var("VALUES") {
            let v: Vec<f64> = values.split(',').map(|x| x.parse().unwrap()).collect();
            eprintln!("{:?}", with(&s, v).map(|_| ()));
        }
        for _ in 0..count {
            let v: Vec<f64> = (0..p.parameters.len())
                .map(|_| {
                    seed = seed
                        .wrapping_mul(6364136223846793005)
                        .wrapping_add(1442695040888963407);
                    let (lo, hi) = FACTOR_RANGE;
                    if seed >> 63 == 0 {
                        lo + 1e-6
                    } else {
                        hi - 1e-6
                    }
                })
                .collect();
            if let Err(e) = with(&s, v) {
                failed += 1;
                eprintln!("{e}");
            }
        }
        eprintln!("{s}: T={} failed {failed} of {count}", p.parameters.len());
    }
}
