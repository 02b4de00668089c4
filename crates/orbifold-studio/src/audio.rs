//! Sound out of the speakers, behind a small trait so that the studio's tests check the samples
//! it would play without an audio device ([`Recorder`]). The desktop output is `cpal`'s default
//! device ([`Speakers`]; on Linux through ALSA).

use std::sync::{Arc, Mutex};

/// Something that plays interleaved samples.
pub trait AudioOut {
    /// Plays `samples` (interleaved, `channels` per frame, in [−1, 1]) at `rate` frames per
    /// second, from the start, in place of anything playing.
    fn play(&mut self, samples: &[f32], channels: u16, rate: u32) -> Result<(), String>;
}

/// What a [`Recorder`] was asked to play: samples, channels and rate.
pub type Played = Arc<Mutex<Vec<(Vec<f32>, u16, u32)>>>;

/// An [`AudioOut`] that keeps what it is given (for tests).
///
/// ```
/// use orbifold_studio::audio::{AudioOut, Recorder};
/// let mut recorder = Recorder::default();
/// recorder.play(&[0.0, 0.5], 1, 48_000).unwrap();
/// assert_eq!(recorder.played.lock().unwrap()[0].0, vec![0.0, 0.5]);
/// ```
#[derive(Clone, Default)]
pub struct Recorder {
    /// Everything played so far.
    pub played: Played,
}

impl AudioOut for Recorder {
    fn play(&mut self, samples: &[f32], channels: u16, rate: u32) -> Result<(), String> {
        self.played
            .lock()
            .map_err(|_| "the recorder is poisoned".to_string())?
            .push((samples.to_vec(), channels, rate));
        Ok(())
    }
}

/// The default audio output device. The stream is kept while the sound plays.
#[derive(Default)]
pub struct Speakers {
    stream: Option<cpal::Stream>,
}

impl AudioOut for Speakers {
    fn play(&mut self, samples: &[f32], channels: u16, rate: u32) -> Result<(), String> {
        use cpal::traits::{DeviceTrait, HostTrait, StreamTrait};
        self.stream = None;
        let host = cpal::default_host();
        let device = host
            .default_output_device()
            .ok_or("no audio output device")?;
        let supported = device
            .default_output_config()
            .map_err(|e| format!("the audio device has no output: {e}"))?;
        let config: cpal::StreamConfig = supported.config();
        let out_channels = usize::from(config.channels.max(1));
        // Brought to the device's rate and channels: each device frame takes the nearest
        // sound frame, and channels past the sound's repeat its last.
        let frames = samples.len() / usize::from(channels.max(1));
        let device_rate = sample_rate(&config);
        let step = f64::from(rate) / f64::from(device_rate);
        let total = (frames as f64 / step) as usize;
        let sound: Vec<f32> = (0..total * out_channels)
            .map(|i| {
                let (frame, channel) = (i / out_channels, i % out_channels);
                let source = ((frame as f64 * step) as usize).min(frames.saturating_sub(1));
                let c = channel.min(usize::from(channels) - 1);
                samples[source * usize::from(channels) + c]
            })
            .collect();
        let mut position = 0;
        let stream = device
            .build_output_stream(
                &config,
                move |data: &mut [f32], _| {
                    for v in data.iter_mut() {
                        *v = sound.get(position).copied().unwrap_or(0.0);
                        position += 1;
                    }
                },
                |e| eprintln!("audio output: {e}"),
                None,
            )
            .map_err(|e| format!("cannot open the audio output: {e}"))?;
        stream
            .play()
            .map_err(|e| format!("cannot play on the audio output: {e}"))?;
        self.stream = Some(stream);
        Ok(())
    }
}

/// The stream's frame rate.
fn sample_rate(config: &cpal::StreamConfig) -> u32 {
    config.sample_rate.0
}
