//! `orbifold enumerate`: every good kaleidoscopic orbifold with N corners, or Table 4.1.

use std::io::Write;

use orbifold::table::{FAMILIES, Walls, pattern_in_row};
use orbifold::{Enumeration, EnumerationOptions, Geometry};
use serde::Serialize;

use crate::args::EnumerateArgs;
use crate::error::CliError;
use crate::output::{self, Out};
use crate::report::Report;

pub fn run(args: &EnumerateArgs) -> Result<(), CliError> {
    let mut out = output::stdout();
    if args.table {
        write_table(&mut out, args.json)?;
    } else {
        let options = EnumerationOptions {
            corners: args
                .corners
                .expect("clap requires --corners without --table"),
            max_order: args
                .max_order
                .expect("clap requires --max-order without --table"),
            ideal: args.ideal,
            geometry: args.geometry,
        };
        let enumeration =
            Enumeration::new(options.clone()).map_err(|e| CliError::Input(e.to_string()))?;
        if options.corners == 1 && !args.json && !args.count {
            eprintln!("note: no good orbifold has one corner: *k is bad for every k > 1");
        }
        if args.count {
            write_counts(&mut out, enumeration, args.json)?;
        } else if args.json {
            write_json_list(&mut out, enumeration)?;
        } else {
            write_text_list(&mut out, enumeration)?;
        }
    }
    out.flush()?;
    Ok(())
}

/// Streams the list as a JSON array, so that long enumerations use constant memory.
fn write_json_list(out: &mut Out, enumeration: Enumeration) -> Result<(), CliError> {
    out.write_all(b"[")?;
    for (i, sig) in enumeration.enumerate() {
        out.write_all(if i == 0 { b"\n  " } else { b",\n  " })?;
        serde_json::to_writer(&mut *out, &Report::of_signature(&sig))?;
    }
    out.write_all(b"\n]\n")?;
    Ok(())
}

fn write_text_list(out: &mut Out, enumeration: Enumeration) -> Result<(), CliError> {
    let mut counts = [0u64; 3];
    for sig in enumeration {
        counts[geometry_index(sig.geometry())] += 1;
        Report::of_signature(&sig).write_line(out)?;
    }
    let total: u64 = counts.iter().sum();
    writeln!(
        out,
        "{total} orbifold{} ({} spherical, {} euclidean, {} hyperbolic)",
        if total == 1 { "" } else { "s" },
        counts[0],
        counts[1],
        counts[2]
    )?;
    Ok(())
}

#[derive(Serialize)]
struct Counts {
    total: u64,
    spherical: u64,
    euclidean: u64,
    hyperbolic: u64,
}

fn write_counts(out: &mut Out, enumeration: Enumeration, json: bool) -> Result<(), CliError> {
    let mut counts = [0u64; 3];
    for sig in enumeration {
        counts[geometry_index(sig.geometry())] += 1;
    }
    let counts = Counts {
        total: counts.iter().sum(),
        spherical: counts[0],
        euclidean: counts[1],
        hyperbolic: counts[2],
    };
    if json {
        serde_json::to_writer_pretty(&mut *out, &counts)?;
        writeln!(out)?;
    } else {
        writeln!(
            out,
            "{} ({} spherical, {} euclidean, {} hyperbolic)",
            counts.total, counts.spherical, counts.euclidean, counts.hyperbolic
        )?;
    }
    Ok(())
}

fn geometry_index(g: Geometry) -> usize {
    Geometry::ALL
        .iter()
        .position(|&h| h == g)
        .expect("three geometries")
}

#[derive(Serialize)]
struct FamilyJson {
    walls: usize,
    walls_or_more: bool,
    geometry: &'static str,
    pattern: &'static str,
    examples: &'static [&'static str],
    in_seed: bool,
}

/// The rows of the printed table: 1 to 7 walls; the last family continues for every N ≥ 5.
const TABLE_ROWS: usize = 7;

fn write_table(out: &mut Out, json: bool) -> Result<(), CliError> {
    if json {
        let families: Vec<FamilyJson> = FAMILIES
            .iter()
            .map(|f| {
                let (walls, walls_or_more) = match f.walls {
                    Walls::Exactly(n) => (n, false),
                    Walls::AtLeast(n) => (n, true),
                };
                FamilyJson {
                    walls,
                    walls_or_more,
                    geometry: f.geometry.name(),
                    pattern: f.pattern,
                    examples: f.examples,
                    in_seed: f.in_seed,
                }
            })
            .collect();
        serde_json::to_writer_pretty(&mut *out, &families)?;
        writeln!(out)?;
        return Ok(());
    }
    let header = ["N", "Spherical", "Euclidean", "Hyperbolic"];
    let mut rows: Vec<[Vec<String>; 4]> = Vec::new();
    for n in 1..=TABLE_ROWS {
        let cell = |g: Geometry| -> Vec<String> {
            FAMILIES
                .iter()
                .filter(|f| f.geometry == g && f.walls.contains(n))
                .map(|f| {
                    format!(
                        "{}{}",
                        pattern_in_row(f, n),
                        if f.in_seed { "" } else { " †" }
                    )
                })
                .collect()
        };
        rows.push([
            vec![n.to_string()],
            cell(Geometry::Spherical),
            cell(Geometry::Euclidean),
            cell(Geometry::Hyperbolic),
        ]);
    }
    rows.push([vec!["⋮".into()], vec![], vec![], vec!["⋮".into()]]);
    let width = |col: usize| {
        rows.iter()
            .flat_map(|r| r[col].iter())
            .chain([&header[col].to_string()])
            .map(|s| s.chars().count())
            .max()
            .unwrap_or(0)
    };
    let widths: Vec<usize> = (0..4).map(width).collect();
    let line = |out: &mut Out, cells: [&str; 4]| -> std::io::Result<()> {
        let text: Vec<String> = cells
            .iter()
            .zip(&widths)
            .map(|(c, &w)| format!("{c:<w$}"))
            .collect();
        writeln!(out, "{}", text.join(" │ ").trim_end())
    };
    line(out, header)?;
    let rule: Vec<String> = widths.iter().map(|&w| "─".repeat(w)).collect();
    writeln!(out, "{}", rule.join("─┼─"))?;
    for row in &rows {
        let height = row.iter().map(Vec::len).max().unwrap_or(1).max(1);
        for i in 0..height {
            let cell = |c: usize| row[c].get(i).map_or("", String::as_str);
            line(out, [cell(0), cell(1), cell(2), cell(3)])?;
        }
    }
    writeln!(out)?;
    writeln!(
        out,
        "N is the number of walls (`*` is one mirror with no corner); k may be ∞ wherever"
    )?;
    writeln!(
        out,
        "a pattern allows k ≥ m. † ideal corners: beyond the seed's Table 4.1."
    )?;
    Ok(())
}
