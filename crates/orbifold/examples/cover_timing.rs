//! The group cover's speed against the combinatorial cover of a related reflection group, at
//! about 30 000 tiles, as the fastest of many runs (docs/benchmarks.md, "Group covers").
//!
//! Each cover is bounded by depth: the deepest whole depths within 30 000 tiles, so that each
//! does the work of exactly the tiles it reports, and the ratio is per tile. The group cover is
//! also timed under the tile bound itself (`--max-tiles 30000`): it cannot know the next
//! layer's size beforehand, so it builds part of that layer before abandoning it.
//!
//! Criterion's mean (`cargo bench -p orbifold --bench cover`) moves by ±15 % on a shared
//! machine; the fastest of N runs is what the code costs when nothing interferes. Run it with
//! glibc's heap kept between runs, or a third of each run is page faults for memory the previous
//! one gave back:
//!
//! `MALLOC_TRIM_THRESHOLD_=1000000000 MALLOC_MMAP_THRESHOLD_=1000000000 cargo run --release -p orbifold --example cover_timing [RUNS]`
use std::time::Instant;

use orbifold::cover::{Bound, Cover};
use orbifold::pairing::FundamentalPolygon;
use orbifold::pairing::cover::GroupCover;
use orbifold::{OrbifoldSymbol, Signature};

/// The fastest of `runs` calls of `f`, in seconds, and the tiles of the last.
fn fastest(runs: usize, mut f: impl FnMut() -> u64) -> (f64, u64) {
    let mut best = f64::INFINITY;
    let mut tiles = 0;
    for _ in 0..runs {
        let start = Instant::now();
        tiles = f();
        best = best.min(start.elapsed().as_secs_f64());
    }
    (best, tiles)
}

/// The deepest depth whose whole layers hold at most `tiles` tiles, from the tile bound.
fn depth_within(counts_by_depth: &[u64]) -> usize {
    counts_by_depth.len().saturating_sub(1)
}

fn main() {
    let runs: usize = std::env::args()
        .nth(1)
        .map_or(300, |r| r.parse().expect("RUNS is a count"));
    let bound = Bound::Tiles(30_000);
    println!(
        "| group | depth | tiles | fastest | under --max-tiles | reflection group | depth | tiles | fastest | ratio per tile |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for (symbol, reflections) in [
        ("632", "*632"),
        ("22×", "*2222"),
        ("2223", "*2223"),
        ("oo", "*22222222"),
        ("*2222222", "*2222222"),
    ] {
        let parsed: OrbifoldSymbol = symbol.parse().expect("a symbol");
        let polygon = FundamentalPolygon::new(&parsed, &Default::default()).expect("a polygon");
        let enumerate = |bound| GroupCover::enumerate_polygon(polygon.clone(), bound, false);
        let depth = depth_within(&enumerate(bound).expect("a cover").counts_by_depth);
        let (group, group_tiles) = fastest(runs, || {
            let cover = enumerate(Bound::Depth(depth)).expect("a cover");
            cover.counts_by_depth.iter().sum()
        });
        let (capped, _) = fastest(runs, || {
            let cover = enumerate(bound).expect("a cover");
            cover.counts_by_depth.iter().sum()
        });
        let signature: Signature = reflections.parse().expect("a signature");
        let reflection_depth = depth_within(
            &Cover::enumerate(&signature, bound, false)
                .expect("a cover")
                .counts_by_depth,
        );
        let (combinatorial, tiles) = fastest(runs, || {
            let cover = Cover::enumerate(&signature, Bound::Depth(reflection_depth), false)
                .expect("a cover");
            cover.counts_by_depth.iter().sum()
        });
        let ratio = (group / group_tiles as f64) / (combinatorial / tiles as f64);
        println!(
            "| `{symbol}` | {depth} | {group_tiles} | {:.2} ms | {:.2} ms | `{reflections}` | {reflection_depth} | {tiles} | {:.2} ms | {ratio:.1}× |",
            group * 1e3,
            capped * 1e3,
            combinatorial * 1e3
        );
    }
    // Bounded by a radius, as the preview's and the rooms' copies are: the search expands only
    // tiles within the radius plus the polygon's reach.
    println!();
    println!("| group | --radius | tiles | fastest |");
    println!("|---|---|---|---|");
    for (symbol, radius) in [("2223", 6.5), ("22×", 100.0), ("oo", 4.5)] {
        let parsed: OrbifoldSymbol = symbol.parse().expect("a symbol");
        let polygon = FundamentalPolygon::new(&parsed, &Default::default()).expect("a polygon");
        let (time, tiles) = fastest(runs, || {
            let cover =
                GroupCover::enumerate_polygon(polygon.clone(), Bound::Radius(radius), false);
            cover.expect("a cover").counts_by_depth.iter().sum()
        });
        println!("| `{symbol}` | {radius} | {tiles} | {:.2} ms |", time * 1e3);
    }
}
