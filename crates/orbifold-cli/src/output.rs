//! Buffered standard output that turns a closed pipe into a quiet stop instead of a panic.

use std::io::{self, BufWriter, StdoutLock};

pub type Out = BufWriter<StdoutLock<'static>>;

pub fn stdout() -> Out {
    BufWriter::new(io::stdout().lock())
}
