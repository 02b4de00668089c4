//! `orbifold info`: classify signatures; for a symbol that is not kaleidoscopic, describe its
//! fundamental polygon and side pairings (`orbifold::pairing`).

use std::io::Write;

use orbifold::OrbifoldSymbol;
use orbifold::layout::LayoutOptions;
use orbifold::pairing::{EdgeKind, FundamentalPolygon};

use super::layout::{PolygonJson, pairing_text, parameter_summary};
use crate::args::InfoArgs;
use crate::error::CliError;
use crate::output;
use crate::report::Report;

pub fn run(args: &InfoArgs) -> Result<(), CliError> {
    // Read every signature before printing anything, so that bad input leaves stdout empty.
    let mut reports = Vec::new();
    let mut errors = Vec::new();
    for input in &args.signatures {
        match input.parse::<OrbifoldSymbol>() {
            Ok(symbol) => {
                let polygon = polygon(&symbol);
                reports.push((Report::of_symbol(&symbol, Some(input)), polygon));
            }
            Err(e) => errors.push(format!("{e}\n{}", e.snippet())),
        }
    }
    if !errors.is_empty() {
        return Err(CliError::Input(errors.join("\nerror: ")));
    }
    let mut out = output::stdout();
    if args.json {
        let values = reports
            .iter()
            .map(|(report, polygon)| {
                let mut value = serde_json::to_value(report)?;
                if let (Some(object), Some(Ok(polygon))) = (value.as_object_mut(), polygon) {
                    let json = PolygonJson::new(polygon, &LayoutOptions::default());
                    object.insert("polygon".into(), serde_json::to_value(json)?);
                }
                Ok(value)
            })
            .collect::<Result<Vec<_>, serde_json::Error>>()?;
        serde_json::to_writer_pretty(&mut out, &values)?;
        writeln!(out)?;
    } else {
        for (i, (report, polygon)) in reports.iter().enumerate() {
            if i > 0 {
                writeln!(out)?;
            }
            write_text(&mut out, report, polygon.as_ref())?;
        }
    }
    out.flush()?;
    Ok(())
}

/// The polygon of a good symbol that is not kaleidoscopic (`None` for kaleidoscopic and bad
/// ones; the error when it cannot be built).
fn polygon(symbol: &OrbifoldSymbol) -> Option<Result<FundamentalPolygon, String>> {
    (symbol.as_kaleidoscopic().is_none() && !symbol.is_bad()).then(|| {
        FundamentalPolygon::new(symbol, &LayoutOptions::default()).map_err(|e| e.to_string())
    })
}

/// The report, with the polygon and its pairings in place of the line on rooms.
fn write_text(
    out: &mut impl Write,
    report: &Report,
    polygon: Option<&Result<FundamentalPolygon, String>>,
) -> std::io::Result<()> {
    let mut text = Vec::new();
    report.write_text(&mut text)?;
    let text = String::from_utf8_lossy(&text);
    let Some(polygon) = polygon else {
        return out.write_all(text.as_bytes());
    };
    for line in text
        .lines()
        .filter(|l| !l.trim_start().starts_with("rooms "))
    {
        writeln!(out, "{line}")?;
    }
    let row = |out: &mut dyn Write, key: &str, value: &str| writeln!(out, "  {key:<16} {value}");
    match polygon {
        Ok(p) => {
            let mirrors = p
                .edges
                .iter()
                .filter(|e| e.kind == EdgeKind::Mirror)
                .count();
            row(
                out,
                "polygon",
                &format!(
                    "{} construction: {} edges ({} paired, {mirrors} mirror{}), {} vertices in {} cycles",
                    p.construction.name(),
                    p.edges.len(),
                    p.edges.len() - mirrors,
                    if mirrors == 1 { "" } else { "s" },
                    p.vertices.len(),
                    p.cycles.len()
                ),
            )?;
            for (i, e) in p.edges.iter().enumerate() {
                if let EdgeKind::Paired { partner } = e.kind
                    && partner < i
                {
                    continue;
                }
                row(
                    out,
                    if i == 0 { "pairings" } else { "" },
                    &format!("edge {i}: {}", pairing_text(p, i)),
                )?;
            }
            row(out, "shape", &parameter_summary(p))?;
        }
        Err(why) => row(out, "polygon", &format!("not built: {why}"))?,
    }
    row(
        out,
        "rooms",
        "the room over this polygon has its mirror edges as mirror walls and its paired edges as \
         portals: `orbifold render`, `trace`, `room`, `preview` and the studio take this symbol",
    )
}
