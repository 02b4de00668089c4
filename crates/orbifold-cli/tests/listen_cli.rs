//! `orbifold listen` as a process: the impulse response as WAV, its echoes as JSON sorted by
//! time, a room of portals, a clap or a dry sound played through the room, echograms, and clear errors
//! (exit code 2) with no file written.

use assert_cmd::Command;
use predicates::prelude::*;
use serde_json::Value;

fn orbifold() -> Command {
    Command::cargo_bin("orbifold").unwrap()
}

fn temp() -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix("orbifold-listen-cli-")
        .tempdir()
        .unwrap()
}

fn listen_json(args: &[&str]) -> Value {
    let out = orbifold()
        .arg("listen")
        .args(args)
        .arg("--json")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

#[test]
fn a_shoebox_s_echoes_are_written_and_listed_by_time() {
    let dir = temp();
    let wav = dir.path().join("ir.wav");
    let json = listen_json(&["*2222", "-o", wav.to_str().unwrap(), "--seconds", "0.1"]);
    let arrivals = json["arrivals"].as_array().unwrap();
    assert!(arrivals.len() > 20);
    let times: Vec<f64> = arrivals
        .iter()
        .map(|a| a["time"].as_f64().unwrap())
        .collect();
    assert!(times.windows(2).all(|w| w[0] <= w[1]));
    // The direct sound first, with no surfaces; then echoes that name theirs.
    assert_eq!(arrivals[0]["surfaces"].as_array().unwrap().len(), 0);
    assert!(arrivals.iter().any(|a| {
        a["surfaces"]
            .as_array()
            .unwrap()
            .iter()
            .any(|s| s == "floor")
    }));
    // Length over time is the speed of sound.
    let a = &arrivals[3];
    let speed = a["length"].as_f64().unwrap() / a["time"].as_f64().unwrap();
    assert!((speed - 343.0).abs() < 1e-9);
    let reader = hound::WavReader::open(&wav).unwrap();
    assert_eq!(reader.spec().sample_rate, 48_000);
    assert_eq!(reader.spec().channels, 1);
    assert_eq!(reader.len(), 4800);
    assert_eq!(json["channels"], 1);
}

#[test]
fn a_room_of_portals_echoes_off_its_floor_and_ceiling_only() {
    // `632` has no mirror walls: its three cone points pair every wall with another, so sound
    // passes them all, and the only surfaces it meets are the floor and the ceiling.
    let dir = temp();
    let wav = dir.path().join("p6.wav");
    let json = listen_json(&["632", "-o", wav.to_str().unwrap(), "--seconds", "0.1"]);
    let arrivals = json["arrivals"].as_array().unwrap();
    assert!(arrivals.len() > 20);
    assert_eq!(json["lost"], 0);
    let surfaces: Vec<&str> = arrivals
        .iter()
        .flat_map(|a| a["surfaces"].as_array().unwrap())
        .map(|s| s.as_str().unwrap())
        .collect();
    assert!(surfaces.contains(&"floor") && surfaces.contains(&"ceiling"));
    assert!(
        surfaces.iter().all(|&s| s == "floor" || s == "ceiling"),
        "{surfaces:?}"
    );
    assert!(wav.exists());
}

#[test]
fn a_clap_in_stereo_with_an_echogram() {
    let dir = temp();
    let wav = dir.path().join("clap.wav");
    let svg = dir.path().join("echo.svg");
    let json = listen_json(&[
        "*444",
        "-o",
        wav.to_str().unwrap(),
        "--seconds",
        "0.05",
        "--stereo",
        "--convolve",
        "--echogram",
        svg.to_str().unwrap(),
    ]);
    assert_eq!(json["channels"], 2);
    assert!(json["arrivals_right"].as_array().unwrap().len() > 1);
    let reader = hound::WavReader::open(&wav).unwrap();
    assert_eq!(reader.spec().channels, 2);
    // The response and the 0.2 s clap, less one sample.
    assert_eq!(reader.duration(), 2400 + 9600 - 1);
    assert!(std::fs::read_to_string(&svg).unwrap().contains("time (s)"));
}

#[test]
fn a_dry_sound_is_played_through_the_room() {
    let dir = temp();
    let dry = dir.path().join("dry.wav");
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: 24_000,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let mut writer = hound::WavWriter::create(&dry, spec).unwrap();
    for i in 0..2400 {
        writer
            .write_sample(((i as f32 * 0.1).sin() * 10_000.0) as i16)
            .unwrap();
    }
    writer.finalize().unwrap();
    let wet = dir.path().join("wet.wav");
    orbifold()
        .args([
            "listen",
            "*235",
            "-o",
            wet.to_str().unwrap(),
            "--seconds",
            "0.05",
        ])
        .args(["--convolve", dry.to_str().unwrap()])
        .assert()
        .success()
        .stdout(predicate::str::contains("echoes"));
    // Brought to 48 kHz: 4800 samples of dry sound.
    assert_eq!(
        hound::WavReader::open(&wet).unwrap().duration(),
        2400 + 4800 - 1
    );
}

#[test]
fn bad_input_is_refused_with_no_file_written() {
    let dir = temp();
    let out = dir.path().join("x.wav");
    let o = out.to_str().unwrap();
    for (args, message) in [
        (
            vec!["*2222", "-o", "x.mp3"],
            "expected a file ending in .wav",
        ),
        (vec!["*2222", "-o", o, "--seconds", "0"], "--seconds"),
        (
            vec!["*2222", "-o", o, "--convolve", "missing.wav"],
            "cannot read it",
        ),
        (
            vec!["*2222", "-o", o, "--echogram", "e.gif"],
            ".png or .svg",
        ),
        (vec!["*23", "-o", o], "error"),
    ] {
        orbifold()
            .arg("listen")
            .args(&args)
            .assert()
            .code(2)
            .stderr(predicate::str::contains(message));
        assert!(!out.exists(), "{args:?}");
    }
    let scene = dir.path().join("bad.toml");
    std::fs::write(&scene, "[sound]\nspeed = 0\n").unwrap();
    orbifold()
        .args(["listen", scene.to_str().unwrap(), "-o", o])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("bad.toml:2:9: sound.speed"));
}
