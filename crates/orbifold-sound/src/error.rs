//! What can go wrong when hearing a room.

use std::fmt;

/// Why a response, a sound file or an echogram could not be made.
#[derive(Debug)]
pub enum SoundError {
    /// The scene or its room cannot be heard (the message says why).
    Scene(String),
    /// A sound file could not be read or written.
    Wav(String),
    /// The echogram could not be drawn.
    Echogram(String),
    /// A convolution too long to hold.
    TooLong(usize),
}

impl fmt::Display for SoundError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SoundError::Scene(m) | SoundError::Wav(m) | SoundError::Echogram(m) => f.write_str(m),
            SoundError::TooLong(n) => write!(
                f,
                "the convolved sound would have {n} samples, more than can be held; use a shorter dry sound or response"
            ),
        }
    }
}

impl std::error::Error for SoundError {}
