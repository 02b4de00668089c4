//! Word lengths round the vertices of a group's tiling (docs/cover.md, "Why not combinatorial").
//!
//! For each symbol, the certified group cover (`orbifold::pairing::cover`) is enumerated to the
//! largest depth under 60 000 tiles; the tiles round each vertex (a fan, as many as the vertex
//! cycle's angle sum says) are sorted by the direction of their centres, and every fan whose
//! tiles all lie below the last depth is checked against the reflection groups' profile: one
//! nearest tile, and word lengths rising by one per step both ways round to the opposite tile.
//! Prints, per symbol, the fans checked, how many have two nearest tiles, how many break the
//! profile, and the first that does.
//!
//! `cargo run --release -p orbifold --example fan_profiles [SYMBOL …]`
use std::collections::{BTreeMap, HashMap};

use glam::DVec3;
use orbifold::OrbifoldSymbol;
use orbifold::cover::Bound;
use orbifold::pairing::cover::GroupCover;

/// Vertices of the tiling, by their ambient position to 1e-5 (tile vertices of one tiling
/// vertex agree far better than that, distinct vertices are far farther apart).
type Vertex = (i64, i64, i64);

/// A tile round a vertex: the direction of its centre from the vertex, its word length and
/// which vertex of the polygon it has there.
type Corner = (f64, u32, usize);

fn key(p: DVec3) -> Vertex {
    let r = |v: f64| (v * 1e5).round() as i64;
    (r(p.x), r(p.y), r(p.z))
}

/// The deepest cover under 60 000 tiles (all of a finite group).
fn cover(symbol: &OrbifoldSymbol) -> Option<(GroupCover, u32)> {
    let mut best = None;
    for depth in 2..60 {
        match GroupCover::enumerate(symbol, Bound::Depth(depth), true) {
            Ok(c) if c.tiles.len() < 60_000 => best = Some((c, depth as u32)),
            _ => break,
        }
    }
    best
}

fn main() {
    let given: Vec<String> = std::env::args().skip(1).collect();
    let symbols: Vec<String> = if given.is_empty() {
        [
            "632",
            "442",
            "333",
            "2222",
            "o",
            "22×",
            "××",
            "*×",
            "22*",
            "2*22",
            "4*2",
            "3*3",
            "2223",
            "oo",
            "4*3",
            "*2×",
            "×××",
            "o*2",
            "3*33",
            "23*2",
            "*2*3",
            "22222",
            "o2",
            "**2",
            "2*2222",
            "2*234",
            "5*2",
            "237",
            "2333",
            "22*3",
            "*3×",
            "o×",
            "ooo",
            "*2222222",
            "*237",
            "*2323",
            "∞∞∞",
            "2∞∞",
            "*∞∞∞",
            "∞*2",
        ]
        .map(String::from)
        .to_vec()
    } else {
        given
    };
    for s in &symbols {
        let symbol: OrbifoldSymbol = match s.parse() {
            Ok(x) => x,
            Err(e) => {
                println!("{s}: {e}");
                continue;
            }
        };
        let Some((cover, depth)) = cover(&symbol) else {
            println!("{s}: no cover");
            continue;
        };
        let polygon = &cover.polygon;
        let space = polygon.space();
        let centre = polygon.centre_ambient();
        let mut fans: BTreeMap<Vertex, Vec<Corner>> = BTreeMap::new();
        for t in &cover.tiles {
            let c = t.matrix * centre;
            for (j, v) in polygon
                .vertices
                .iter()
                .enumerate()
                .filter(|(_, v)| !v.ideal)
            {
                let p = space.normalize_point(t.matrix * v.ambient);
                let toward = space.log(p, c);
                let [e0, e1] = space.tangent_frame(p);
                let angle = space
                    .point_dot(toward, e1)
                    .atan2(space.point_dot(toward, e0));
                fans.entry(key(p)).or_default().push((angle, t.depth, j));
            }
        }
        // The fan's length: the cycle's vertices times the turns round the point.
        let mut length: HashMap<usize, usize> = HashMap::new();
        for c in polygon.cycles.iter().filter(|c| c.angle_sum > 0.0) {
            let l = c.vertices.len() as f64 * std::f64::consts::TAU / c.angle_sum;
            for &v in &c.vertices {
                length.insert(v, l.round() as usize);
            }
        }
        let (mut checked, mut two, mut broken) = (0, 0, 0);
        let mut example = String::new();
        for fan in fans.values_mut() {
            let l = length[&fan[0].2];
            if fan.len() != l || fan.iter().any(|f| f.1 >= depth) {
                continue;
            }
            fan.sort_by(|a, b| a.0.total_cmp(&b.0));
            let a: Vec<u32> = fan.iter().map(|f| f.1).collect();
            let m = *a.iter().min().expect("a fan has tiles");
            let p = a.iter().position(|&x| x == m).expect("the minimum");
            checked += 1;
            two += usize::from(a.iter().filter(|&&x| x == m).count() == 2);
            if !(0..l).all(|t| a[(p + t) % l] == m + t.min(l - t) as u32) {
                broken += 1;
                if example.is_empty() {
                    example = format!(" e.g. {a:?} (fan of {l})");
                }
            }
        }
        println!(
            "{s}: depth {depth}, {} tiles, {} edges: {checked} fans, {two} with two nearest, \
             {broken} off the profile{example}",
            cover.tiles.len(),
            polygon.edges.len()
        );
    }
}
