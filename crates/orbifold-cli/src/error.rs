//! Errors of the command line and their exit codes.

use std::fmt;
use std::io;

/// What went wrong, and so which exit code to use.
#[derive(Debug)]
pub enum CliError {
    /// The user's input is invalid (exit code 2); the message says what and where.
    Input(String),
    /// Writing the output failed (exit code 1).
    Io(io::Error),
    /// The reader of our output went away (for example `| head`): stop quietly.
    BrokenPipe,
    /// The machine cannot do the work (no GPU adapter, a failing GPU): exit code 1.
    Runtime(String),
    /// The user stopped the work (Ctrl-C) before it was done (exit code 130, as a shell does).
    Interrupted(String),
}

impl CliError {
    pub fn exit_code(&self) -> u8 {
        match self {
            CliError::Input(_) => 2,
            CliError::Io(_) | CliError::Runtime(_) => 1,
            CliError::BrokenPipe => 0,
            CliError::Interrupted(_) => 130,
        }
    }
}

impl From<io::Error> for CliError {
    fn from(error: io::Error) -> Self {
        if error.kind() == io::ErrorKind::BrokenPipe {
            CliError::BrokenPipe
        } else {
            CliError::Io(error)
        }
    }
}

impl From<serde_json::Error> for CliError {
    fn from(error: serde_json::Error) -> Self {
        match error.io_error_kind() {
            Some(io::ErrorKind::BrokenPipe) => CliError::BrokenPipe,
            _ => CliError::Io(io::Error::other(error)),
        }
    }
}

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CliError::Input(message) | CliError::Runtime(message) => write!(f, "error: {message}"),
            CliError::Io(error) => write!(f, "error: could not write the output: {error}"),
            CliError::BrokenPipe => Ok(()),
            CliError::Interrupted(message) => write!(f, "{message}"),
        }
    }
}
