//! dual-ssn on Coulomb friction's Cattaneo path (the scene of `cattaneo.rs`): every inner Tresca
//! solve has zero-bound tangential rows (no normal force, bound μ·0), which dual-ssn once took
//! for one-sided rows — the run ended `inaccurate` with |λt| up to 4.7e-4 beyond the bound 0.
//! Now it must solve the path and agree with pdas, an independent method (primal active set on
//! the whole system, no condensed dual).

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used)]

mod common;

use common::{json, repo, signorini, succeeded};
use serde_json::Value;

/// The scene of `cattaneo.rs` (`scene(PRESS_THEN_SHIFT)`): the graded Hertz cylinder pressed
/// (uy = −0.002 at the cap's top), then shifted (ux = 0.0005) in two increments, mortar pair with
/// Coulomb friction μ = 0.3.
fn scene() -> String {
    let text = std::fs::read_to_string(repo("fixtures/accuracy/hertz-graded.toml")).unwrap();
    let head = &text[..text.find("[[dirichlet]]\nbody = \"cap\"").unwrap()];
    let top = "[-0.11651513899116794, 1.7165151389911681, 1.4, 1.4]";
    format!(
        r#"{head}[[dirichlet]]
name = "press"
body = "cap"
region = {top}
components = ["y"]
value = [0.0, -0.002]

[[dirichlet]]
name = "shift"
body = "cap"
region = {top}
components = ["x"]
value = [0.0005, 0.0]

[[contact]]
bodies = ["cap", "block"]
region = [0.6, 1.0, 0.79, 0.83]
slave = "block"
formulation = "mortar"
friction = 0.3

[[step]]
loads = {{ press = 1.0 }}
[[step]]
loads = {{ press = 1.0, shift = 1.0 }}
increments = 2"#
    )
}

/// result.json of the scene solved with `backend`.
fn solve(backend: &str) -> Value {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("scene.toml"), scene()).unwrap();
    succeeded(&signorini(
        &[
            "solve",
            "scene.toml",
            "--backend",
            backend,
            "--time-limit",
            "60",
            "--out",
            "out",
        ],
        dir.path(),
    ));
    json(&dir.path().join("out/result.json"))
}

#[test]
fn dual_ssn_solves_the_cattaneo_path_and_agrees_with_pdas() {
    let ssn = solve("dual-ssn");
    let pdas = solve("pdas");
    for r in [&ssn, &pdas] {
        assert_eq!(r["status"], "solved", "{}: {}", r["backend"], r["message"]);
        for step in r["steps"].as_array().unwrap() {
            assert_eq!(step["status"], "solved", "{}: {step}", r["backend"]);
        }
    }
    // 1e-6 relative: both answers meet the KKT tolerance 1e-9 (result.json's `tolerance`); a
    // thousandfold margin covers the conditioning of the stick zone's tangential problem.
    // (Measured: 3e-13 on the forces, 1.3e-12 of max |q| per node.)
    let (a, b) = (&ssn["contacts"][0], &pdas["contacts"][0]);
    for key in ["normal_force", "tangential_force"] {
        let (x, y) = (a[key].as_f64().unwrap(), b[key].as_f64().unwrap());
        assert!(
            (x - y).abs() <= 1e-6 * y.abs(),
            "{key}: dual-ssn {x}, pdas {y}"
        );
    }
    // The shift is resisted: Q = |tangential force| is a sizeable fraction of μP (Cattaneo: the
    // stick zone c = a √(1 − Q/(μP)) is inside the contact), not the ~0 of a wrong answer.
    let q = b["tangential_force"].as_f64().unwrap().abs();
    let p = b["normal_force"].as_f64().unwrap();
    assert!(
        q > 0.1 * 0.3 * p && q < 0.3 * p,
        "Q = {q}, μP = {}",
        0.3 * p
    );
    // Node by node: the same stick/slip states and tangential tractions to 1e-6 of the largest.
    let nodes = |pair: &Value| -> Vec<(String, f64)> {
        pair["nodes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|n| {
                (
                    n["state"].as_str().unwrap().to_string(),
                    n["tangential_traction"].as_f64().unwrap(),
                )
            })
            .collect()
    };
    let (na, nb) = (nodes(a), nodes(b));
    assert_eq!(na.len(), nb.len());
    let scale = nb.iter().map(|n| n.1.abs()).fold(0.0, f64::max);
    for (i, (x, y)) in na.iter().zip(&nb).enumerate() {
        assert_eq!(x.0, y.0, "node {i}: dual-ssn {x:?}, pdas {y:?}");
        assert!(
            (x.1 - y.1).abs() <= 1e-6 * scale,
            "node {i}: dual-ssn {x:?}, pdas {y:?}"
        );
    }
}
