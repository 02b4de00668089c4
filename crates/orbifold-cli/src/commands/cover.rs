//! `orbifold cover`: the tiles of the universal cover, counted by word length. Kaleidoscopic
//! signatures use the combinatorial reflection-group cover; every other good orbifold symbol the
//! certified enumeration of its group from the side pairings (`orbifold::pairing::cover`).

use std::io::Write;
use std::time::Instant;

use orbifold::cover::{Bound, Cover, Tile};
use orbifold::growth::growth_series;
use orbifold::pairing::cover::{GroupCover, GroupTile};
use orbifold::{OrbifoldSymbol, Signature};
use serde::Serialize;

use crate::args::CoverArgs;
use crate::error::CliError;
use crate::output;

pub fn run(args: &CoverArgs) -> Result<(), CliError> {
    let signature = match args.signature.parse::<Signature>() {
        Ok(signature) => signature,
        Err(e) => match args.signature.parse::<OrbifoldSymbol>() {
            Ok(symbol) if symbol.as_kaleidoscopic().is_none() => {
                return run_group(args, &symbol);
            }
            _ => return Err(CliError::Input(format!("{e}\n{}", e.snippet()))),
        },
    };
    let bound = bound(args)?;
    let start = Instant::now();
    let cover = Cover::enumerate(&signature, bound, args.tiles)
        .map_err(|e| CliError::Input(e.to_string()))?;
    let seconds = start.elapsed().as_secs_f64();
    let total: u64 = cover.counts_by_depth.iter().sum();
    let mut out = output::stdout();
    if args.json {
        let tiles = args
            .tiles
            .then(|| cover.tiles.iter().map(TileJson::from).collect());
        let name = signature.to_string();
        let geometry = signature.geometry().name();
        write_json(
            &mut out,
            name,
            geometry,
            &cover.counts_by_depth,
            seconds,
            tiles,
        )?;
    } else {
        write_text(&mut out, &signature, &cover, total, seconds)?;
    }
    out.flush()?;
    Ok(())
}

fn bound(args: &CoverArgs) -> Result<Bound, CliError> {
    Ok(match (args.depth, args.radius, args.max_tiles) {
        (Some(d), _, _) => Bound::Depth(d),
        (_, Some(r), _) if r.is_finite() && r >= 0.0 => Bound::Radius(r),
        (_, Some(r), _) => {
            return Err(CliError::Input(format!(
                "--radius must be a non-negative number, not {r}"
            )));
        }
        (_, _, Some(m)) => Bound::Tiles(m),
        (None, None, None) => Bound::All,
    })
}

/// A symbol with side pairings: the tiles of its group.
fn run_group(args: &CoverArgs, symbol: &OrbifoldSymbol) -> Result<(), CliError> {
    let bound = bound(args)?;
    let start = Instant::now();
    let cover = GroupCover::enumerate(symbol, bound, args.tiles)
        .map_err(|e| CliError::Input(e.to_string()))?;
    let seconds = start.elapsed().as_secs_f64();
    let total: u64 = cover.counts_by_depth.iter().sum();
    let mut out = output::stdout();
    if args.json {
        let tiles = args
            .tiles
            .then(|| cover.tiles.iter().map(TileJson::from).collect());
        let name = symbol.to_string();
        let geometry = symbol.geometry().name();
        write_json(
            &mut out,
            name,
            geometry,
            &cover.counts_by_depth,
            seconds,
            tiles,
        )?;
    } else {
        writeln!(
            out,
            "{}  {}  ({} polygon, {} edges)",
            symbol,
            symbol.geometry(),
            cover.polygon.construction.name(),
            cover.polygon.edges.len()
        )?;
        writeln!(out, "  depth  tiles")?;
        for (d, count) in cover.counts_by_depth.iter().enumerate() {
            writeln!(out, "  {d:<5}  {count}")?;
        }
        writeln!(out, "  total  {total}")?;
        if let Some(order) = symbol.group_order() {
            writeln!(out, "  group order 2/χ = {order}")?;
        }
        let rate = total as f64 / seconds.max(1e-9);
        writeln!(
            out,
            "  {seconds:.3} s, {:.2} million tiles per second",
            rate / 1e6
        )?;
    }
    out.flush()?;
    Ok(())
}

#[derive(Serialize)]
struct TileJson {
    depth: u32,
    reflected: bool,
    wall: Option<u32>,
    /// The isometry: a 3×3 matrix on ambient coordinates, row by row.
    isometry: [[f64; 3]; 3],
}

impl From<&GroupTile> for TileJson {
    fn from(tile: &GroupTile) -> Self {
        let m = tile.matrix;
        TileJson {
            depth: tile.depth,
            reflected: tile.reflected,
            wall: tile.edge,
            isometry: [
                m.row(0).to_array(),
                m.row(1).to_array(),
                m.row(2).to_array(),
            ],
        }
    }
}

impl From<&Tile> for TileJson {
    fn from(tile: &Tile) -> Self {
        let m = tile.matrix;
        TileJson {
            depth: tile.depth,
            reflected: tile.reflected,
            wall: tile.wall,
            isometry: [
                m.row(0).to_array(),
                m.row(1).to_array(),
                m.row(2).to_array(),
            ],
        }
    }
}

#[derive(Serialize)]
struct CoverJson {
    signature: String,
    geometry: &'static str,
    counts_by_depth: Vec<u64>,
    total: u64,
    seconds: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    tiles: Option<Vec<TileJson>>,
}

/// The `--json` report, one line: the same keys for reflection groups and groups with side
/// pairings.
fn write_json(
    out: &mut impl Write,
    signature: String,
    geometry: &'static str,
    counts_by_depth: &[u64],
    seconds: f64,
    tiles: Option<Vec<TileJson>>,
) -> Result<(), CliError> {
    let report = CoverJson {
        signature,
        geometry,
        counts_by_depth: counts_by_depth.to_vec(),
        total: counts_by_depth.iter().sum(),
        seconds,
        tiles,
    };
    serde_json::to_writer(&mut *out, &report)?;
    writeln!(out)?;
    Ok(())
}

fn write_text(
    out: &mut impl Write,
    signature: &Signature,
    cover: &Cover,
    total: u64,
    seconds: f64,
) -> std::io::Result<()> {
    writeln!(out, "{}  {}", signature, signature.geometry())?;
    let depth = cover.counts_by_depth.len().saturating_sub(1);
    let series = growth_series(signature, depth);
    writeln!(out, "  depth  tiles")?;
    for (d, count) in cover.counts_by_depth.iter().enumerate() {
        writeln!(out, "  {d:<5}  {count}")?;
    }
    writeln!(out, "  total  {total}")?;
    if let Some(series) = series {
        let agrees = series
            .iter()
            .zip(&cover.counts_by_depth)
            .all(|(a, &b)| *a == u128::from(b));
        writeln!(
            out,
            "  growth series (Steinberg's formula) {}",
            if agrees { "agrees" } else { "differs" }
        )?;
    }
    let rate = total as f64 / seconds.max(1e-9);
    writeln!(
        out,
        "  {seconds:.3} s, {:.2} million tiles per second",
        rate / 1e6
    )
}
