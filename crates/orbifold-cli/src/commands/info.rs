//! `orbifold info`: classify signatures.

use std::io::Write;

use orbifold::OrbifoldSymbol;

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
            Ok(symbol) => reports.push(Report::of_symbol(&symbol, Some(input))),
            Err(e) => errors.push(format!("{e}\n{}", e.snippet())),
        }
    }
    if !errors.is_empty() {
        return Err(CliError::Input(errors.join("\nerror: ")));
    }
    let mut out = output::stdout();
    if args.json {
        serde_json::to_writer_pretty(&mut out, &reports)?;
        writeln!(out)?;
    } else {
        for (i, report) in reports.iter().enumerate() {
            if i > 0 {
                writeln!(out)?;
            }
            report.write_text(&mut out)?;
        }
    }
    out.flush()?;
    Ok(())
}
