//! The `orbifold` command tested as a process: outputs, JSON, exit codes and error messages.

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

#[test]
fn info_default_signature_reads_well() {
    orbifold()
        .args(["info", "*22222"])
        .assert()
        .success()
        .stdout(predicate::str::contains("χ                -1/4"))
        .stdout(predicate::str::contains("hyperbolic"))
        .stdout(predicate::str::contains("free parameters  2"))
        .stdout(predicate::str::contains("π/2 ≈ 1.570796"));
}

#[test]
fn info_json_has_the_documented_keys_and_types() {
    let v = json(&[
        "info",
        "--json",
        "*22222",
        "*632",
        "*∞∞∞",
        "*(3/2)33",
        "*23",
        "*235",
        "*",
        "*(1.5)33",
    ]);
    let items = v.as_array().unwrap();
    assert_eq!(items.len(), 8);
    for item in items {
        for key in [
            "canonical",
            "corners",
            "euler_characteristic",
            "geometry",
            "kind",
            "reason",
            "area",
            "group_order",
            "free_parameters",
        ] {
            assert!(item.get(key).is_some(), "missing {key} in {item}");
        }
    }
    let [
        default,
        p6m,
        ideal,
        non_orbifold,
        bad,
        ih,
        one_mirror,
        decimal,
    ] = items.as_slice()
    else {
        unreachable!()
    };
    assert_eq!(default["canonical"], "*22222");
    assert_eq!(default["euler_characteristic"], "-1/4");
    assert_eq!(default["geometry"], "hyperbolic");
    assert_eq!(default["kind"], "orbifold");
    assert_eq!(default["reason"], Value::Null);
    assert_eq!(default["group_order"], Value::Null);
    assert_eq!(default["free_parameters"], 2);
    assert!((default["area"].as_f64().unwrap() - std::f64::consts::FRAC_PI_2).abs() < 1e-12);

    assert_eq!(p6m["canonical"], "*236");
    assert_eq!(p6m["corners"], serde_json::json!([2, 3, 6]));
    assert_eq!(p6m["euler_characteristic"], "0");
    assert_eq!(p6m["geometry"], "euclidean");
    assert_eq!(p6m["area"], Value::Null);
    assert_eq!(p6m["group"]["name"], "p6m");

    assert_eq!(ideal["canonical"], "*∞∞∞");
    assert_eq!(ideal["corners"], serde_json::json!(["inf", "inf", "inf"]));
    assert_eq!(ideal["euler_characteristic"], "-1/2");

    assert_eq!(non_orbifold["kind"], "non-orbifold");
    assert_eq!(non_orbifold["corners"], serde_json::json!([1.5, 3, 3]));
    assert!(
        non_orbifold["reason"]
            .as_str()
            .unwrap()
            .contains("not an integer")
    );
    assert_eq!(decimal["canonical"], non_orbifold["canonical"]);

    assert_eq!(bad["kind"], "bad");
    assert!(
        bad["reason"]
            .as_str()
            .unwrap()
            .contains("two mirrors that meet twice must meet at the same angle both times")
    );
    assert_eq!(bad["area"], Value::Null);

    assert_eq!(ih["group_order"], 120);
    assert_eq!(ih["euler_characteristic"], "1/60");
    assert_eq!(one_mirror["group_order"], 2);
    assert_eq!(one_mirror["corners"], serde_json::json!([]));
}

#[test]
fn info_of_a_canonical_form_is_a_fixed_point() {
    for sig in ["*3322", "*(12)2∞3", "*632", "*2(3/2)3(5/2)", "*11"] {
        let first = json(&["info", sig, "--json"]);
        let canonical = first[0]["canonical"].as_str().unwrap().to_string();
        let second = json(&["info", &canonical, "--json"]);
        assert_eq!(second[0]["canonical"], canonical.as_str());
        let (mut a, mut b) = (first[0].clone(), second[0].clone());
        a.as_object_mut().unwrap().remove("input");
        b.as_object_mut().unwrap().remove("input");
        assert_eq!(a, b, "{sig}");
    }
}

#[test]
fn info_explains_conway_symbols() {
    orbifold()
        .args(["info", "632"])
        .assert()
        .success()
        .stdout(predicate::str::contains("p6 (Conway 632)"))
        .stdout(predicate::str::contains("6-fold gyration point"))
        .stdout(predicate::str::contains("paired edges as portals"));
    let v = json(&["info", "--json", "2*22", "22×", "o", "532"]);
    assert_eq!(v[0]["group"]["name"], "cmm");
    assert_eq!(v[0]["notation"], "conway");
    assert_eq!(v[1]["group"]["name"], "pgg");
    assert_eq!(v[2]["group"]["name"], "p1");
    assert_eq!(v[3]["group"]["name"], "I");
    assert_eq!(v[3]["group_order"], 60);
    // Wallpaper groups by name.
    let v = json(&["info", "--json", "p6", "pgg", "p4m"]);
    assert_eq!(v[0]["group"]["name"], "p6");
    assert_eq!(v[1]["group"]["conway"], "22×");
    assert_eq!(v[2]["canonical"], "*244");
    assert_eq!(v[2]["buildable"], true);
}

#[test]
fn malformed_input_exits_2_with_nothing_on_stdout() {
    for (sig, position) in [
        ("*(", 2),
        ("*0", 2),
        ("*-3", 2),
        ("*2q", 3),
        ("*(2/0)", 2),
        ("", 1),
        ("2o", 2),
    ] {
        orbifold()
            .args(["info", "--", sig])
            .assert()
            .code(2)
            .stdout(predicate::str::is_empty())
            .stderr(predicate::str::contains(format!("position {position}")));
    }
    // One bad signature among good ones: still nothing on stdout.
    orbifold()
        .args(["info", "*22222", "*2q", "--json"])
        .assert()
        .code(2)
        .stdout(predicate::str::is_empty());
}

#[test]
fn usage_errors_exit_2() {
    orbifold().assert().code(2);
    orbifold()
        .args(["info"])
        .assert()
        .code(2)
        .stdout(predicate::str::is_empty());
    orbifold()
        .args(["enumerate", "--corners", "3"])
        .assert()
        .code(2);
    orbifold()
        .args(["enumerate", "--corners", "x", "--max-order", "3"])
        .assert()
        .code(2);
    orbifold()
        .args([
            "enumerate",
            "--corners",
            "3",
            "--max-order",
            "3",
            "--geometry",
            "flatland",
        ])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("flatland"));
    orbifold()
        .args(["enumerate", "--corners", "3", "--max-order", "1"])
        .assert()
        .code(2)
        .stdout(predicate::str::is_empty())
        .stderr(predicate::str::contains("at least 2"));
}

#[test]
fn help_explains_with_examples() {
    orbifold()
        .arg("--help")
        .assert()
        .success()
        .stdout(predicate::str::contains("Examples:"));
    orbifold()
        .args(["info", "--help"])
        .assert()
        .success()
        .stdout(predicate::str::contains("*23456789(10)(11)"));
    orbifold()
        .args(["enumerate", "--help"])
        .assert()
        .success()
        .stdout(predicate::str::contains("--max-order"));
}

#[test]
fn enumerate_lists_each_class_once() {
    orbifold()
        .args([
            "enumerate",
            "--corners",
            "3",
            "--max-order",
            "6",
            "--geometry",
            "euclidean",
        ])
        .assert()
        .success()
        .stdout(predicate::str::contains("*236"))
        .stdout(predicate::str::contains(
            "3 orbifolds (0 spherical, 3 euclidean, 0 hyperbolic)",
        ));
    let v = json(&[
        "enumerate",
        "--corners",
        "4",
        "--max-order",
        "4",
        "--ideal",
        "--json",
    ]);
    let names: Vec<&str> = v
        .as_array()
        .unwrap()
        .iter()
        .map(|o| o["canonical"].as_str().unwrap())
        .collect();
    // Bracelets of length 4 over 4 symbols: 55.
    assert_eq!(names.len(), 55);
    assert_eq!(names[0], "*2222");
    assert_eq!(*names.last().unwrap(), "*∞∞∞∞");
    let counts = json(&[
        "enumerate",
        "-n",
        "4",
        "-k",
        "4",
        "--ideal",
        "--count",
        "--json",
    ]);
    assert_eq!(counts["total"], 55);
    assert_eq!(counts["euclidean"], 1);
    assert_eq!(counts["hyperbolic"], 54);
}

#[test]
fn enumerate_table() {
    orbifold()
        .args(["enumerate", "--table"])
        .assert()
        .success()
        .stdout(predicate::str::contains("*23k (k = 3, 4, 5)"))
        .stdout(predicate::str::contains("*k₁k₂k₃k₄k₅k₆k₇"));
    let v = json(&["enumerate", "--table", "--json"]);
    assert!(
        v.as_array()
            .unwrap()
            .iter()
            .any(|f| f["pattern"] == "*2222" && f["geometry"] == "euclidean")
    );
}

#[test]
fn closed_pipe_is_not_a_panic() {
    // `head` closes the pipe early; the command must not panic (exit code 101).
    let output = std::process::Command::new("sh")
        .arg("-c")
        .arg(format!(
            "'{}' enumerate -n 9 -k 9 | head -n 1",
            assert_cmd::cargo::cargo_bin("orbifold").display()
        ))
        .output()
        .unwrap();
    assert!(output.status.success());
    assert!(!String::from_utf8_lossy(&output.stderr).contains("panicked"));
}

#[test]
fn rays_pass_through_portals_and_say_so() {
    // 632 has no mirrors: every wall is a portal, and a horizontal ray crosses them until the
    // limit, each crossing naming the wall it goes on from.
    let v = json(&[
        "trace",
        "632",
        "--from",
        "0,0,0.5",
        "--yaw",
        "20",
        "--pitch",
        "0",
        "--bounces",
        "5",
        "--json",
    ]);
    let hits = v["hits"].as_array().unwrap();
    assert_eq!(hits.len(), 5);
    assert_eq!(v["end"], "bounce limit");
    for hit in hits {
        assert_eq!(hit["kind"], "portal");
        assert_eq!(hit["mirror"], false);
        assert!(hit["to"].as_u64().is_some(), "{hit}");
    }
    // 4*2 has a mirror beside its portals.
    let v = json(&[
        "trace",
        "4*2",
        "--from",
        "0,0,0.5",
        "--yaw",
        "100",
        "--pitch",
        "0",
        "--bounces",
        "12",
        "--json",
    ]);
    let kinds: Vec<&str> = v["hits"]
        .as_array()
        .unwrap()
        .iter()
        .map(|h| h["kind"].as_str().unwrap())
        .collect();
    assert!(
        kinds.iter().all(|k| ["mirror", "portal"].contains(k)),
        "{kinds:?}"
    );
}

#[test]
fn rooms_with_portals_render_and_export_with_their_group() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("632.png");
    orbifold()
        .args(["render", "632", "--spp", "1", "--size", "16x12", "-o"])
        .arg(&png)
        .assert()
        .success();
    assert!(std::fs::metadata(&png).unwrap().len() > 0);
    // The room of 22× with its copies under the group up to word length 2: every tile of the
    // group's cover but the room itself.
    let obj = dir.path().join("22x.obj");
    let v = json(&[
        "room",
        "22×",
        "--cover",
        "2",
        "--json",
        "-o",
        obj.to_str().unwrap(),
    ]);
    let cover = json(&["cover", "22×", "--depth", "2", "--json"]);
    assert_eq!(
        v["copies"].as_u64().unwrap() + 1,
        cover["total"].as_u64().unwrap(),
        "{v} {cover}"
    );
}
