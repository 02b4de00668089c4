//! `orbifold layout`, `cover` and `info` for symbols that are not kaleidoscopic: the JSON is
//! checked from scratch (Poincaré's conditions recomputed from the vertices and matrices alone),
//! and so are group orders, pictures and errors.

use std::f64::consts::PI;

use assert_cmd::Command;
use predicates::prelude::*;
use serde_json::Value;

fn orbifold() -> Command {
    Command::cargo_bin("orbifold").expect("binary built")
}

fn json(args: &[&str]) -> Value {
    let output = orbifold().args(args).output().unwrap();
    assert!(
        output.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    serde_json::from_slice(&output.stdout).expect("valid JSON")
}

type V3 = [f64; 3];

fn kappa(geometry: &str) -> f64 {
    match geometry {
        "spherical" => 1.0,
        "hyperbolic" => -1.0,
        _ => 0.0,
    }
}

/// Ambient coordinates of a JSON vertex (the null direction for an ideal one).
fn ambient(v: &Value, k: f64) -> V3 {
    let (x, y) = (v["x"].as_f64().unwrap(), v["y"].as_f64().unwrap());
    if v["ideal"].as_bool().unwrap() {
        return [x, y, 1.0];
    }
    let r2 = x * x + y * y;
    let d = 1.0 + k * r2;
    [2.0 * x / d, 2.0 * y / d, (1.0 - k * r2) / d]
}

fn matrix(v: &Value) -> [V3; 3] {
    let row = |i: usize| -> V3 {
        let r = v[i].as_array().unwrap();
        [0, 1, 2].map(|j| r[j].as_f64().unwrap())
    };
    [row(0), row(1), row(2)]
}

fn apply(m: &[V3; 3], p: V3) -> V3 {
    [0, 1, 2].map(|i| m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2])
}

fn product(a: &[V3; 3], b: &[V3; 3]) -> [V3; 3] {
    [0, 1, 2].map(|i| [0, 1, 2].map(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
}

fn close(a: V3, b: V3, ideal: bool, tol: f64) -> bool {
    let (a, b) = if ideal {
        (
            [a[0] / a[2], a[1] / a[2], 1.0],
            [b[0] / b[2], b[1] / b[2], 1.0],
        )
    } else {
        (a, b)
    };
    let scale = 1.0 + a.iter().chain(&b).fold(0.0f64, |m, x| m.max(x.abs()));
    (0..3).all(|i| (a[i] - b[i]).abs() < tol * scale)
}

fn determinant(m: &[V3; 3]) -> f64 {
    m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
}

/// Poincaré's conditions from the JSON alone.
fn check_layout(symbol: &str) -> Value {
    check_layout_with(symbol, &[])
}

/// Poincaré's conditions from the JSON alone, with more arguments (`--params`).
fn check_layout_with(symbol: &str, more: &[&str]) -> Value {
    let mut args = vec!["layout", symbol, "--json"];
    args.extend(more);
    let v = json(&args);
    let k = kappa(v["geometry"].as_str().unwrap());
    let vertices = v["vertices"].as_array().unwrap();
    let points: Vec<V3> = vertices.iter().map(|x| ambient(x, k)).collect();
    let edges = v["edges"].as_array().unwrap();
    for (i, e) in edges.iter().enumerate() {
        let n = matrix(&e["neighbour"]);
        let (s, t) = (
            e["from"].as_u64().unwrap() as usize,
            e["to"].as_u64().unwrap() as usize,
        );
        match e["kind"].as_str().unwrap() {
            "mirror" => {
                assert!(e["partner"].is_null(), "{symbol}");
                assert!(determinant(&n) < 0.0, "{symbol}");
                for x in [s, t] {
                    let ideal = vertices[x]["ideal"].as_bool().unwrap();
                    assert!(
                        close(apply(&n, points[x]), points[x], ideal, 1e-8),
                        "{symbol}: mirror {i}"
                    );
                }
            }
            "paired" => {
                let j = e["partner"].as_u64().unwrap() as usize;
                let f = &edges[j];
                assert_eq!(f["partner"].as_u64(), Some(i as u64), "{symbol}");
                let id = product(&n, &matrix(&f["neighbour"]));
                let scale = n.iter().flatten().fold(1.0f64, |m, x| m.max(x.abs()));
                for (a, row) in id.iter().enumerate() {
                    for (b, x) in row.iter().enumerate() {
                        let want = if a == b { 1.0 } else { 0.0 };
                        assert!((x - want).abs() < 1e-8 * scale * scale, "{symbol}: {i}·{j}");
                    }
                }
                let (s2, t2) = (
                    f["from"].as_u64().unwrap() as usize,
                    f["to"].as_u64().unwrap() as usize,
                );
                let reverses = determinant(&n) < 0.0;
                // An orientation-preserving pairing reverses the boundary's direction.
                let targets = if reverses {
                    [(s2, s), (t2, t)]
                } else {
                    [(s2, t), (t2, s)]
                };
                for (from, to) in targets {
                    let ideal = vertices[from]["ideal"].as_bool().unwrap();
                    assert!(
                        close(apply(&n, points[from]), points[to], ideal, 1e-7),
                        "{symbol}: edge {i} takes vertex {from} elsewhere than {to}"
                    );
                }
            }
            other => panic!("{symbol}: kind {other}"),
        }
    }
    let mut seen = vec![0; vertices.len()];
    for c in v["cycles"].as_array().unwrap() {
        let members: Vec<usize> = c["vertices"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_u64().unwrap() as usize)
            .collect();
        for &m in &members {
            seen[m] += 1;
        }
        let sum: f64 = members
            .iter()
            .map(|&m| vertices[m]["angle"].as_f64().unwrap())
            .sum();
        assert!(
            (sum - c["angle_sum"].as_f64().unwrap()).abs() < 1e-9,
            "{symbol}"
        );
        let order = c["order"].as_f64().unwrap_or(f64::INFINITY);
        let want = match c["kind"].as_str().unwrap() {
            "cone" | "regular" => 2.0 * PI / order,
            "corner" => PI / order,
            "ideal" => 0.0,
            other => panic!("{other}"),
        };
        assert!(
            (sum - want).abs() < 1e-8,
            "{symbol}: cycle {members:?} sums to {sum}, not {want}"
        );
    }
    assert!(seen.iter().all(|&s| s == 1), "{symbol}: {seen:?}");
    v
}

#[test]
fn every_wallpaper_group_has_a_polygon_with_pairings() {
    for s in [
        "o", "2222", "**", "*×", "××", "22*", "22×", "*2222", "2*22", "442", "*442", "4*2", "333",
        "*333", "3*3", "632", "*632",
    ] {
        let v = check_layout(s);
        assert_eq!(v["geometry"], "euclidean", "{s}");
    }
}

#[test]
fn spherical_and_hyperbolic_families() {
    for s in [
        "532", "432", "332", "3*2", "2*5", "5*", "5×", "55", "225", "×", "2223", "4*3", "*2×",
        "××", "oo", "237", "23∞", "2*34", "***", "×××", "3333", "2*2222", "2*3∞",
    ] {
        let v = check_layout(s);
        if let Some(area) = v["area"].as_f64()
            && v["geometry"] != "euclidean"
        {
            let chi: Vec<f64> = v["euler_characteristic"]
                .as_str()
                .unwrap()
                .split('/')
                .map(|x| x.parse().unwrap())
                .collect();
            let chi = chi[0] / chi.get(1).copied().unwrap_or(1.0);
            assert!(
                (area - 2.0 * PI * chi.abs()).abs() < 1e-8,
                "{s}: area {area}"
            );
        }
    }
}

#[test]
fn kaleidoscopic_layouts_gain_the_new_keys_and_keep_the_old() {
    let v = check_layout("*2333");
    assert_eq!(v["free_parameters"], serde_json::json!([1.4]));
    assert!(v["edges"][0]["circle"].is_object() || v["edges"][0]["line"].is_object());
    assert_eq!(v["edges"][0]["kind"], "mirror");
    assert_eq!(v["cycles"].as_array().unwrap().len(), 4);
}

#[test]
fn parameters_reach_the_polygon() {
    let v = json(&["layout", "2*22", "--params", "0.3", "--json"]);
    assert_eq!(v["free_parameters"], serde_json::json!([0.3]));
    orbifold()
        .args(["layout", "2*22", "--params", "1.5"])
        .assert()
        .failure()
        .stderr(predicate::str::contains("strictly between 0 and 1"));
    orbifold()
        .args(["layout", "632", "--params", "1"])
        .assert()
        .failure()
        .stderr(predicate::str::contains("rigid"));
}

#[test]
fn group_covers_from_the_command_line() {
    for (s, order) in [
        ("532", 60),
        ("432", 24),
        ("3*2", 24),
        ("22(7)", 14),
        ("(6)×", 12),
    ] {
        let v = json(&["cover", s, "--json"]);
        assert_eq!(v["total"], order, "{s}");
    }
    let v = json(&["cover", "2223", "--max-tiles", "500", "--json", "--tiles"]);
    let tiles = v["tiles"].as_array().unwrap();
    assert_eq!(tiles.len() as u64, v["total"].as_u64().unwrap());
    let layout = json(&["layout", "2223", "--json"]);
    let centre = ambient(
        &serde_json::json!({"x": layout["centre"]["x"], "y": layout["centre"]["y"], "ideal": false}),
        -1.0,
    );
    let images: Vec<V3> = tiles
        .iter()
        .map(|t| apply(&matrix(&t["isometry"]), centre))
        .collect();
    for (i, a) in images.iter().enumerate() {
        for b in &images[..i] {
            assert!(!close(*a, *b, false, 1e-6), "two tiles are the same");
        }
    }
    orbifold()
        .args(["cover", "2223"])
        .assert()
        .failure()
        .stderr(predicate::str::contains("infinite"));
}

#[test]
fn info_describes_the_polygon_and_its_pairings() {
    orbifold()
        .args(["info", "22×"])
        .assert()
        .success()
        .stdout(predicate::str::contains("pairings"))
        .stdout(predicate::str::contains("glide reflection"))
        .stdout(predicate::str::contains("star construction"));
    let v = json(&["info", "--json", "632", "*632"]);
    assert_eq!(v[0]["polygon"]["construction"], "doubled triangle");
    assert!(v[1].get("polygon").is_none());
}

#[test]
fn pictures_mark_the_pairings() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("pgg.svg");
    orbifold()
        .args(["layout", "22×", "-o", path.to_str().unwrap()])
        .assert()
        .success();
    let svg = std::fs::read_to_string(&path).unwrap();
    assert_eq!(svg.matches("marker-end").count(), 6);
    // Each edge one path: an arc (or a segment in the Euclidean plane) from end to end.
    assert_eq!(svg.matches(r#"<path d="M"#).count(), 6 + 1, "{svg}");
}

#[test]
fn bad_and_unbuilt_symbols_get_clear_errors() {
    orbifold()
        .args(["layout", "23"])
        .assert()
        .failure()
        .stderr(predicate::str::contains("bad orbifold"));
    orbifold()
        .args(["layout", "1"])
        .assert()
        .failure()
        .stderr(predicate::str::contains("sphere itself"));
    orbifold()
        .args(["layout", "22∞"])
        .assert()
        .failure()
        .stderr(predicate::str::contains("frieze"));
}

/// The hyperbolic star offers every free parameter that `info` counts, and a deformed polygon
/// still meets Poincaré's conditions when rebuilt from the JSON.
#[test]
fn hyperbolic_stars_offer_every_parameter() {
    for (s, params) in [
        ("oo", "0.981,1.019,1.01,0.99,1.0,1.015"),
        ("o*2", "1.01,0.99,1.019,0.985"),
        ("2223", "1.015,0.985"),
        ("*2×", "1.019"),
        // The folded polygon of mirrors takes any positive values, far from the default too.
        ("2*2222", "0.01,50,3"),
        ("2*3∞", "20"),
    ] {
        let v = check_layout(s);
        let count = params.split(',').count();
        assert_eq!(
            v["parameter_meanings"].as_array().unwrap().len(),
            count,
            "{s}"
        );
        assert_eq!(v["missing_parameters"], 0, "{s}");
        // Each given value lies inside its stated range.
        let ranges = v["parameter_ranges"].as_array().unwrap();
        assert_eq!(ranges.len(), count, "{s}");
        for (range, value) in ranges.iter().zip(params.split(',')) {
            let value: f64 = value.parse().unwrap();
            let (low, high) = (range[0].as_f64().unwrap(), range[1].as_f64());
            assert!(
                low < value && high.is_none_or(|h| value < h),
                "{s}: {value} in {range}"
            );
        }
        let shaped = check_layout_with(s, &["--params", params]);
        assert_eq!(shaped["missing_parameters"], 0, "{s}");
        assert_ne!(shaped["vertices"], v["vertices"], "{s}");
    }
    orbifold()
        .args(["layout", "oo", "--params", "1.1,1,1,1,1,1"])
        .assert()
        .failure();
}

/// A lune's two sides join antipodes (a geodesic between them is not unique): each is drawn
/// through its middle point, as two different arcs, one on each side of the corners.
#[test]
fn a_lune_is_drawn_as_two_arcs() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("55.svg");
    orbifold()
        .args(["layout", "55", "-o", path.to_str().unwrap()])
        .assert()
        .success();
    let svg = std::fs::read_to_string(&path).unwrap();
    let arcs: Vec<&str> = svg
        .lines()
        .filter(|l| l.starts_with(r#"<path d="M"#) && l.contains(" A"))
        .collect();
    assert_eq!(arcs.len(), 2, "{svg}");
    // Each runs from one corner to the other and the next back, turning the same way: so they
    // bow to opposite sides of the corners.
    let parts = |l: &str| -> (String, String, String) {
        let d = l.split('"').nth(1).unwrap();
        let (start, arc) = d.trim_start_matches('M').split_once(" A").unwrap();
        let words: Vec<&str> = arc.split(' ').collect();
        (
            start.into(),
            words[4].into(),
            format!("{} {}", words[5], words[6]),
        )
    };
    let ((s0, w0, e0), (s1, w1, e1)) = (parts(arcs[0]), parts(arcs[1]));
    assert_eq!((&s0, &e0), (&e1, &s1), "{svg}");
    assert_eq!(w0, w1, "{svg}");
}
