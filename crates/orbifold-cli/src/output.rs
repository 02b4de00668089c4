//! Standard output that turns a closed pipe into a quiet stop; files are written atomically by
//! the scene crate's `write_atomic`.

use std::io::{self, BufWriter, StdoutLock};

pub type Out = BufWriter<StdoutLock<'static>>;

pub fn stdout() -> Out {
    BufWriter::new(io::stdout().lock())
}

pub use orbifold_scene::write_atomic;
