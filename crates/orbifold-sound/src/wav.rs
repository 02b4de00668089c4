//! WAV files: the response written as 16-bit PCM (mono or stereo), and dry sounds read in any
//! PCM or float format, mixed down to mono and brought to the response's sample rate.

use std::io::Cursor;

use crate::error::SoundError;

/// The peak a written signal is scaled to (a little below full scale).
pub const PEAK: f32 = 0.9;

/// Channels as a 16-bit PCM WAV file, scaled together so that the loudest sample is [`PEAK`];
/// returns the bytes and the scale applied (the samples' pressure times it).
///
/// ```
/// use orbifold_sound::wav::{encode, decode_mono};
/// let (bytes, scale) = encode(&[vec![0.0, 0.5, -0.25]], 8000).unwrap();
/// assert!((scale - 1.8).abs() < 1e-6);
/// let (back, rate) = decode_mono(&bytes).unwrap();
/// assert_eq!(rate, 8000);
/// assert!((back[1] - 0.9).abs() < 1e-4);
/// ```
pub fn encode(channels: &[Vec<f32>], sample_rate: u32) -> Result<(Vec<u8>, f32), SoundError> {
    let count = channels.len();
    if !(1..=2).contains(&count) {
        return Err(SoundError::Wav(format!(
            "{count} channels: only mono and stereo are written"
        )));
    }
    let peak = channels
        .iter()
        .flatten()
        .map(|x| x.abs())
        .fold(0.0f32, f32::max);
    let scale = if peak > 0.0 && peak.is_finite() {
        PEAK / peak
    } else {
        1.0
    };
    let spec = hound::WavSpec {
        channels: count as u16,
        sample_rate,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let mut bytes = Cursor::new(Vec::new());
    let wav_error = |e: hound::Error| SoundError::Wav(format!("cannot write the WAV file: {e}"));
    {
        let mut writer = hound::WavWriter::new(&mut bytes, spec).map_err(wav_error)?;
        let n = channels.iter().map(Vec::len).max().unwrap_or(0);
        for i in 0..n {
            for channel in channels {
                let x = channel.get(i).copied().unwrap_or(0.0) * scale;
                let v = (x * f32::from(i16::MAX)).round().clamp(-32768.0, 32767.0) as i16;
                writer.write_sample(v).map_err(wav_error)?;
            }
        }
        writer.finalize().map_err(wav_error)?;
    }
    Ok((bytes.into_inner(), scale))
}

/// A WAV file's samples, mixed down to mono, in [−1, 1], and its sample rate.
pub fn decode_mono(bytes: &[u8]) -> Result<(Vec<f32>, u32), SoundError> {
    let bad = |e: hound::Error| SoundError::Wav(format!("not a WAV file that can be read: {e}"));
    let mut reader = hound::WavReader::new(Cursor::new(bytes)).map_err(bad)?;
    let spec = reader.spec();
    let channels = usize::from(spec.channels.max(1));
    let samples: Vec<f32> = match spec.sample_format {
        hound::SampleFormat::Float => reader
            .samples::<f32>()
            .collect::<Result<_, _>>()
            .map_err(bad)?,
        hound::SampleFormat::Int => {
            let full = 2f32.powi(i32::from(spec.bits_per_sample.clamp(1, 32)) - 1);
            reader
                .samples::<i32>()
                .map(|s| s.map(|v| v as f32 / full))
                .collect::<Result<_, _>>()
                .map_err(bad)?
        }
    };
    let mono = samples
        .chunks(channels)
        .map(|frame| frame.iter().sum::<f32>() / channels as f32)
        .collect();
    Ok((mono, spec.sample_rate))
}

/// A signal brought from one sample rate to another by linear interpolation (enough for a dry
/// sound to play through a room; not a studio-grade resampler).
///
/// ```
/// use orbifold_sound::wav::resample;
/// assert_eq!(resample(&[0.0, 1.0], 1, 2), vec![0.0, 0.5, 1.0, 1.0]);
/// ```
pub fn resample(signal: &[f32], from: u32, to: u32) -> Vec<f32> {
    if from == to || signal.is_empty() {
        return signal.to_vec();
    }
    let n = (signal.len() as u64 * u64::from(to)).div_ceil(u64::from(from)) as usize;
    let step = f64::from(from) / f64::from(to);
    (0..n)
        .map(|i| {
            let x = i as f64 * step;
            let k = x.floor() as usize;
            let t = (x - k as f64) as f32;
            let a = signal[k.min(signal.len() - 1)];
            let b = signal[(k + 1).min(signal.len() - 1)];
            a + (b - a) * t
        })
        .collect()
}
