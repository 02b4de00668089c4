//! `orbifold layout` as a process: JSON that independent code can check, pictures, errors.

use std::f64::consts::PI;

use assert_cmd::Command;
use predicates::prelude::*;
use proptest::prelude::*;
use serde_json::Value;

fn orbifold() -> Command {
    Command::cargo_bin("orbifold").expect("binary built")
}

fn layout_json(args: &[&str]) -> Value {
    let output = orbifold()
        .arg("layout")
        .args(args)
        .arg("--json")
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    serde_json::from_slice(&output.stdout).expect("valid JSON")
}

type C = (f64, f64);

fn mul(a: C, b: C) -> C {
    (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0)
}

fn div(a: C, b: C) -> C {
    let d = b.0 * b.0 + b.1 * b.1;
    (mul(a, (b.0, -b.1)).0 / d, mul(a, (b.0, -b.1)).1 / d)
}

/// The direction at z of the geodesic towards w, from the model alone: move z to the origin by
/// the isometry (ζ − z)/(1 + κ z̄ ζ), whose derivative at z is real and positive.
fn direction(kappa: f64, z: C, w: C) -> C {
    let num = (w.0 - z.0, w.1 - z.1);
    let zw = mul((z.0, -z.1), w);
    let den = (1.0 + kappa * zw.0, kappa * zw.1);
    div(num, den)
}

/// Recomputes every corner angle and checks convexity from the JSON vertices alone.
fn check_json(v: &Value) {
    let kappa = match v["geometry"].as_str().unwrap() {
        "spherical" => 1.0,
        "euclidean" => 0.0,
        _ => -1.0,
    };
    assert_eq!(
        v["model"],
        match kappa {
            1.0 => "stereographic",
            0.0 => "euclidean",
            _ => "poincare",
        }
    );
    let vertices = v["vertices"].as_array().unwrap();
    let n = vertices.len();
    assert_eq!(v["edges"].as_array().unwrap().len(), n.max(1));
    let point = |i: usize| {
        (
            vertices[i]["x"].as_f64().unwrap(),
            vertices[i]["y"].as_f64().unwrap(),
        )
    };
    for i in 0..n {
        let corner = &vertices[i];
        let order = &corner["order"];
        let expected = if order == "inf" {
            0.0
        } else {
            PI / order.as_f64().unwrap()
        };
        assert!((corner["angle"].as_f64().unwrap() - expected).abs() < 1e-12);
        let edge = &v["edges"][i];
        assert_eq!(edge["from"], i);
        assert_eq!(edge["to"], (i + 1) % n);
        assert!(edge.get("circle").is_some() || edge.get("line").is_some());
        if corner["ideal"].as_bool().unwrap() {
            let (x, y) = point(i);
            assert!(((x * x + y * y).sqrt() - 1.0).abs() < 1e-12);
            assert!(edge["length"].is_null());
            continue;
        }
        if n < 3 {
            continue;
        }
        let (next, prev) = (
            direction(kappa, point(i), point((i + 1) % n)),
            direction(kappa, point(i), point((i + n - 1) % n)),
        );
        let turn = div(prev, next);
        let angle = turn.1.atan2(turn.0);
        assert!(
            (angle - expected).abs() < 1e-9,
            "corner {i}: {angle} vs {expected} in {}",
            v["signature"]
        );
        assert!(angle > 0.0 && angle < PI, "not convex at corner {i}");
    }
}

#[test]
fn json_has_the_documented_keys() {
    let v = layout_json(&["*2333"]);
    for key in [
        "geometry",
        "model",
        "vertices",
        "edges",
        "free_parameters",
        "area",
    ] {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    assert_eq!(v["geometry"], "hyperbolic");
    assert_eq!(v["model"], "poincare");
    assert_eq!(v["free_parameters"], serde_json::json!([1.4]));
    assert!((v["area"].as_f64().unwrap() - PI / 2.0).abs() < 1e-12);
    for key in ["x", "y", "order", "angle", "ideal"] {
        assert!(v["vertices"][0].get(key).is_some(), "vertex lacks {key}");
    }
    for key in ["cx", "cy", "r"] {
        assert!(
            v["edges"][0]["circle"].get(key).is_some(),
            "circle lacks {key}"
        );
    }
    check_json(&v);
}

#[test]
fn every_geometry_and_the_seed_examples() {
    for sig in [
        "*",
        "*33",
        "*222",
        "*235",
        "*333",
        "*244",
        "*236",
        "*2222",
        "*23456",
        "*23456789(10)(11)",
        "*∞∞∞",
        "*∞∞∞∞∞",
        "*2352",
        "*(3/2)33",
    ] {
        let v = layout_json(&[sig]);
        check_json(&v);
    }
    let euclidean = layout_json(&["*236"]);
    assert_eq!(euclidean["model"], "euclidean");
    assert!(euclidean["edges"][0].get("line").is_some());
    let star = layout_json(&["*"]);
    assert_eq!(star["edges"][0]["circle"]["r"], 1.0);
    assert_eq!(star["edges"][0]["from"], Value::Null);
}

#[test]
fn placement_and_parameters() {
    let v = layout_json(&[
        "*22222", "--params", "1,3", "--at", "0.2,-0.3", "--angle", "45",
    ]);
    assert_eq!(v["free_parameters"], serde_json::json!([1.0, 3.0]));
    assert_eq!(v["centre"]["x"], 0.2);
    assert_eq!(v["angle"], 45.0);
    check_json(&v);
    let balanced = layout_json(&["*22222", "--shape", "incircle"]);
    assert_eq!(balanced["free_parameters"], serde_json::json!([1.0, 1.0]));
    let rectangle = layout_json(&["*2222", "--params", "2"]);
    let (a, b) = (
        rectangle["edges"][0]["length"].as_f64().unwrap(),
        rectangle["edges"][1]["length"].as_f64().unwrap(),
    );
    assert!((a / b - 2.0).abs() < 1e-12);
}

#[test]
fn impossible_requests_exit_2_with_a_reason() {
    let cases: &[(&[&str], &str)] = &[
        (&["*23"], "two mirrors that meet twice"),
        (&["*7"], "single mirror"),
        (
            &["*(3/2)(3/2)(3/2)(3/2)"],
            "spherical polygon with 4 corners",
        ),
        (&["*∞∞"], "Euclidean strip"),
        (&["*22222", "--params", "1"], "2 free parameter"),
        (&["*22222", "--params", "1,-1"], "free parameter 2 is -1"),
        (&["*22222", "--params", "1,x"], "item 2"),
        (&["*235", "--params", "1"], "rigid"),
        (&["*22222", "--at", "0.9,0.9"], "Poincaré disk"),
        (&["*22222", "--at", "1"], "two numbers"),
        (&["*2q"], "position 3"),
        // Every good orbifold symbol is laid out (docs/orbifolds.md), but the sphere itself
        // has no polygon.
        (&["1"], "sphere itself"),
    ];
    for (args, message) in cases {
        orbifold()
            .arg("layout")
            .args(*args)
            .assert()
            .code(2)
            .stdout(predicate::str::is_empty())
            .stderr(predicate::str::contains(*message));
    }
}

#[test]
fn pictures_are_written_whole() {
    let tmp = tempfile::Builder::new()
        .prefix("orbifold-layout-test-")
        .tempdir()
        .unwrap();
    let dir = tmp.path();
    let svg = dir.join("room.svg");
    orbifold()
        .args(["layout", "*2333", "-o"])
        .arg(&svg)
        .assert()
        .success();
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.starts_with("<svg") && text.trim_end().ends_with("</svg>"));
    assert_eq!(text.matches("<title>wall").count(), 4);
    let png = dir.join("room.png");
    orbifold()
        .args(["layout", "*∞∞∞", "--size", "200", "-o"])
        .arg(&png)
        .assert()
        .success();
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    // A bad extension writes nothing.
    let bad = dir.join("room.gif");
    orbifold()
        .args(["layout", "*2333", "-o"])
        .arg(&bad)
        .assert()
        .code(2)
        .stderr(predicate::str::contains(".svg or .png"));
    assert!(!bad.exists());
    // No temporary files are left behind.
    let leftovers: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(Result::ok)
        .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(leftovers.is_empty());
}

fn random_signature() -> impl Strategy<Value = String> {
    let order = prop_oneof![8 => (2u64..=20).prop_map(|k| if k < 10 { k.to_string() } else { format!("({k})") }), 1 => Just("∞".to_string())];
    prop::collection::vec(order, 4..=12).prop_map(|c| format!("*{}", c.concat()))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// As an independent checker would: random signatures, parameters and placements, angles
    /// recomputed from the printed vertices alone.
    #[test]
    fn random_layouts_check_from_json(
        sig in random_signature(),
        params in prop::collection::vec(0.05f64..10.0, 9),
        at in (-0.6f64..0.6, -0.6f64..0.6),
        angle in -180.0f64..180.0,
    ) {
        let probe = layout_json(&[&sig]);
        if probe["geometry"] != "hyperbolic" {
            return Ok(());
        }
        let count = probe["free_parameters"].as_array().unwrap().len();
        let list: Vec<String> = params[..count].iter().map(|p| p.to_string()).collect();
        let v = layout_json(&[&sig, "--params", &list.join(","), "--at", &format!("{},{}", at.0, at.1), "--angle", &angle.to_string()]);
        check_json(&v);
    }
}
