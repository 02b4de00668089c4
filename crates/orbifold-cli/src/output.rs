//! Standard output that turns a closed pipe into a quiet stop; files are written atomically by
//! the scene crate's `write_atomic`.

use std::io::{self, BufWriter, StdoutLock};

pub type Out = BufWriter<StdoutLock<'static>>;

pub fn stdout() -> Out {
    BufWriter::new(io::stdout().lock())
}

pub use orbifold_scene::write_atomic;

/// Prints a command's summary: pretty JSON with `json`, else the line `text` makes.
pub fn summary(
    json: bool,
    value: &impl serde::Serialize,
    text: impl FnOnce() -> String,
) -> Result<(), crate::error::CliError> {
    use std::io::Write;
    let mut out = stdout();
    if json {
        serde_json::to_writer_pretty(&mut out, value)?;
        writeln!(out)?;
    } else {
        writeln!(out, "{}", text())?;
    }
    out.flush()?;
    Ok(())
}
