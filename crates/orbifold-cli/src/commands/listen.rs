//! `orbifold listen`: the impulse response of a mirror room (docs/sound.md), as a WAV file,
//! optionally played through the room, with its echoes as JSON and its echogram.

use std::path::Path;

use indicatif::{ProgressBar, ProgressStyle};
use orbifold_sound::{Hearing, Response, clap, convolve, echogram, wav};
use serde::Serialize;

use crate::args::ListenArgs;
use crate::commands::render::load;
use crate::error::CliError;
use crate::output;

#[derive(Serialize)]
struct ArrivalJson {
    /// Seconds.
    time: f64,
    amplitude: f64,
    surfaces: Vec<String>,
    /// Metres.
    length: f64,
}

#[derive(Serialize)]
struct ListenJson {
    output: String,
    sample_rate: u32,
    seconds: f64,
    channels: usize,
    scale: f32,
    lost: usize,
    arrivals: Vec<ArrivalJson>,
    #[serde(skip_serializing_if = "Option::is_none")]
    arrivals_right: Option<Vec<ArrivalJson>>,
}

pub fn run(args: &ListenArgs) -> Result<(), CliError> {
    check_extension(&args.output, &["wav"], "-o")?;
    if let Some(path) = &args.echogram {
        check_extension(path, &["png", "svg"], "--echogram")?;
    }
    let (mut scene, base) = load(args.input.as_deref())?;
    if let Some(t) = args.seconds {
        if !(t.is_finite() && t > 0.0 && t <= 60.0) {
            return Err(CliError::Input(format!(
                "--seconds {t}: expected a length in seconds between 0 and 60"
            )));
        }
        scene.sound.seconds = t;
    }
    // A dry sound is read before the work, so that a bad file fails at once.
    let dry = match &args.convolve {
        None => None,
        Some(None) => Some(clap::clap(scene.sound.sample_rate)),
        Some(Some(path)) => Some(read_dry(path, scene.sound.sample_rate)?),
    };
    let hearing =
        Hearing::from_scene(&scene, base.as_deref()).map_err(|e| CliError::Input(e.to_string()))?;
    let responses = compute(&hearing, args)?;
    let mut channels: Vec<Vec<f32>> = responses.iter().map(|r| hearing.samples(r)).collect();
    if let Some(dry) = &dry {
        channels = channels
            .iter()
            .map(|ir| convolve::convolve(dry, ir))
            .collect::<Result<_, _>>()
            .map_err(|e| CliError::Input(e.to_string()))?;
    }
    let (bytes, scale) = wav::encode(&channels, hearing.settings.sample_rate)
        .map_err(|e| CliError::Runtime(e.to_string()))?;
    output::write_atomic(&args.output, &bytes)?;
    if let Some(path) = &args.echogram {
        write_echogram(&hearing, &responses[0], path)?;
    }
    let json = |r: &Response| arrivals_json(&hearing, r);
    let summary = ListenJson {
        output: args.output.display().to_string(),
        sample_rate: hearing.settings.sample_rate,
        seconds: channels[0].len() as f64 / f64::from(hearing.settings.sample_rate),
        channels: channels.len(),
        scale,
        lost: responses.iter().map(|r| r.lost).sum(),
        arrivals: if args.json {
            json(&responses[0])
        } else {
            Vec::new()
        },
        arrivals_right: (args.json && responses.len() > 1).then(|| json(&responses[1])),
    };
    output::summary(args.json, &summary, || {
        describe(&summary, &responses, &args.echogram)
    })
}

/// The responses (one, or the two ears'), with a progress bar over the tiles of the cover.
fn compute(hearing: &Hearing, args: &ListenArgs) -> Result<Vec<Response>, CliError> {
    let bar = if args.json {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(1)
    };
    bar.set_style(
        ProgressStyle::with_template("{spinner} [{elapsed_precise}] {bar:40} {pos}/{len} images")
            .expect("a valid template"),
    );
    let progress = |done: usize, total: usize| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    };
    let responses = if args.stereo {
        hearing.stereo(&progress).to_vec()
    } else {
        vec![hearing.mono(&progress)]
    };
    bar.finish_and_clear();
    if responses.iter().any(|r| r.truncated) {
        eprintln!(
            "warning: the room has more mirror images or echoes within hearing than can be held; \
             some echoes are missing (raise [sound] min_level or shorten the response)"
        );
    }
    Ok(responses)
}

fn check_extension(path: &Path, allowed: &[&str], option: &str) -> Result<(), CliError> {
    let ok = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| allowed.iter().any(|a| e.eq_ignore_ascii_case(a)));
    if ok {
        Ok(())
    } else {
        Err(CliError::Input(format!(
            "{option} {}: expected a file ending in .{}",
            path.display(),
            allowed.join(" or .")
        )))
    }
}

fn read_dry(path: &Path, rate: u32) -> Result<Vec<f32>, CliError> {
    let bytes = std::fs::read(path).map_err(|e| {
        CliError::Input(format!(
            "--convolve {}: cannot read it: {e}",
            path.display()
        ))
    })?;
    let (samples, from) = wav::decode_mono(&bytes)
        .map_err(|e| CliError::Input(format!("--convolve {}: {e}", path.display())))?;
    if samples.is_empty() {
        return Err(CliError::Input(format!(
            "--convolve {}: the sound is empty",
            path.display()
        )));
    }
    Ok(wav::resample(&samples, from, rate))
}

fn write_echogram(hearing: &Hearing, response: &Response, path: &Path) -> Result<(), CliError> {
    let seconds = hearing.settings.seconds;
    let floor = 20.0 * (4.0 * std::f64::consts::PI * hearing.settings.min_amplitude).log10();
    let title = format!("{}: echoes at the listener", hearing.signature);
    let size = (800, 360);
    let is_png = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    let bytes = if is_png {
        echogram::echogram_png(&response.arrivals, &title, seconds, floor, size)
    } else {
        echogram::echogram_svg(&response.arrivals, &title, seconds, floor, size)
            .map(String::into_bytes)
    }
    .map_err(|e| CliError::Runtime(e.to_string()))?;
    output::write_atomic(path, &bytes)?;
    Ok(())
}

fn arrivals_json(hearing: &Hearing, response: &Response) -> Vec<ArrivalJson> {
    response
        .arrivals
        .iter()
        .map(|a| ArrivalJson {
            time: a.time,
            amplitude: a.amplitude,
            surfaces: response
                .bounces(&hearing.room, a)
                .iter()
                .map(ToString::to_string)
                .collect(),
            length: a.length,
        })
        .collect()
}

fn describe(
    summary: &ListenJson,
    responses: &[Response],
    echogram: &Option<std::path::PathBuf>,
) -> String {
    let echoes: usize = responses.iter().map(|r| r.arrivals.len()).sum();
    let first = responses[0]
        .arrivals
        .first()
        .map_or("none".to_string(), |a| format!("{:.1} ms", a.time * 1e3));
    let mut line = format!(
        "wrote {}: {:.2} s at {} Hz, {}, {echoes} echoes (first at {first}), scaled ×{:.3}",
        summary.output,
        summary.seconds,
        summary.sample_rate,
        if summary.channels == 2 {
            "stereo"
        } else {
            "mono"
        },
        summary.scale
    );
    if let Some(path) = echogram {
        line.push_str(&format!("; echogram {}", path.display()));
    }
    line
}
