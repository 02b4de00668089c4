//! Vertex cycles: the corners of the polygon that the side pairings glue into one point of the
//! orbifold (Maskit 1971, §2; Beardon, *The Geometry of Discrete Groups*, §9.3).
//!
//! Walk around an image point: leave a corner through one of its two edges; across a paired edge
//! the pairing's preimage of the corner is the next corner of the cycle, entered through the
//! partner edge, and the walk leaves it through its other edge. A walk that returns to its start
//! is a closed cycle (a cone point or an ordinary point); a walk that meets a mirror edge is half
//! of a corner cycle, which is then walked from one mirror to the other.

use super::{Cycle, CycleKind, Edge, EdgeKind, Vertex};
use crate::order::Order;

/// The two edges at vertex `v` of an `n`-gon: (incoming, outgoing).
fn edges_at(v: usize, n: usize) -> (usize, usize) {
    ((v + n - 1) % n, v)
}

/// One step: leaving vertex `v` through edge `e`, the vertex reached and the edge to leave it by;
/// `None` when `e` is a mirror.
fn step(edges: &[Edge], n: usize, v: usize, e: usize) -> Option<(usize, usize)> {
    let EdgeKind::Paired { partner } = edges[e].kind else {
        return None;
    };
    let reverses = edges[e].reverses_orientation();
    let at_start = v == e; // edge e runs from vertex e to vertex e + 1
    let (start, end) = (partner, (partner + 1) % n);
    // An orientation-preserving pairing takes the partner's start to this edge's end.
    let next = match (reverses, at_start) {
        (false, true) => end,
        (false, false) => start,
        (true, true) => start,
        (true, false) => end,
    };
    let (incoming, outgoing) = edges_at(next, n);
    let other = if partner == incoming {
        outgoing
    } else {
        incoming
    };
    Some((next, other))
}

/// The vertex cycles of a polygon whose vertex `i` has the declared order `orders[i]`.
pub(crate) fn cycles(vertices: &[Vertex], edges: &[Edge], orders: &[Order]) -> Vec<Cycle> {
    let n = vertices.len();
    let mut seen = vec![false; n];
    let mut out = Vec::new();
    // Open cycles first, each walked from a corner on a mirror, away from it.
    for v in 0..n {
        let (incoming, outgoing) = edges_at(v, n);
        let mirror_in = edges[incoming].kind == EdgeKind::Mirror;
        let mirror_out = edges[outgoing].kind == EdgeKind::Mirror;
        if seen[v] || !(mirror_in || mirror_out) {
            continue;
        }
        let leave = if mirror_in { outgoing } else { incoming };
        let members = walk(edges, n, v, leave);
        out.push(make(vertices, orders, members, false, &mut seen));
    }
    for v in 0..n {
        if !seen[v] {
            let members = walk(edges, n, v, v);
            out.push(make(vertices, orders, members, true, &mut seen));
        }
    }
    out
}

/// The corners visited from `v` leaving through `e`, until the walk closes or meets a mirror.
fn walk(edges: &[Edge], n: usize, v: usize, e: usize) -> Vec<usize> {
    let mut members = vec![v];
    let (mut at, mut leave) = (v, e);
    // A cycle visits each (corner, edge) state at most once: 2n steps bound it.
    for _ in 0..2 * n {
        match step(edges, n, at, leave) {
            None => break,
            Some((next, other)) if (next, other) == (v, e) => break,
            Some((next, other)) => {
                members.push(next);
                (at, leave) = (next, other);
            }
        }
    }
    members
}

fn make(
    vertices: &[Vertex],
    orders: &[Order],
    members: Vec<usize>,
    closed: bool,
    seen: &mut [bool],
) -> Cycle {
    for &m in &members {
        seen[m] = true;
    }
    let angle_sum = members.iter().map(|&m| vertices[m].angle).sum();
    let order = orders[members[0]];
    let kind = if members.iter().any(|&m| vertices[m].ideal) {
        CycleKind::Ideal
    } else if !closed {
        CycleKind::Corner
    } else if order.is_one() {
        CycleKind::Regular
    } else {
        CycleKind::Cone
    };
    Cycle {
        vertices: members,
        kind,
        order,
        angle_sum,
        closed,
    }
}
