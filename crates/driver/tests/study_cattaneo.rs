//! `signorini study` on a frictional scene (issue 20): `fixtures/accuracy/cattaneo.toml`, the
//! graded Hertz cylinder of `hertz-graded.toml` pressed and then shifted with Coulomb μ = 0.3
//! (the scene of `cattaneo.rs`), against its Cattaneo–Mindlin `[reference]`: with P and Q the
//! pair's forces, a = √(4PR/(πE*)), p₀ = 2P/(πa), c = a √(1 − Q/(μP)) and
//! q(x) = μ p₀/a (√(a² − x²) − √(c² − x²)) for |x| < c, μ p(x) for c < |x| < a (Johnson 1985,
//! §7.1).  The reference's own keys are refused when missing or wrong, naming the key.

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used)]

mod common;

use common::{json, repo, signorini, succeeded};
use serde_json::Value;
use signorini::study::read_points;
use signorini_core::scene::Scene;

const MU: f64 = 0.3;
/// Both bodies E = 1, ν = 0.3, plane strain: E* = E / (2 (1 − ν²)).
const E_STAR: f64 = 1.0 / (2.0 * (1.0 - 0.09));
/// The cylinder's radius and the centre of the contact.
const R: f64 = 1.0;
const CENTRE: f64 = 0.8;

/// Cattaneo's (a, p₀, c) for the pair's forces, computed here from result.json (not by the
/// code under test).
fn theory(pair: &Value) -> (f64, f64, f64) {
    let p = pair["normal_force"].as_f64().unwrap();
    let q = pair["tangential_force"].as_f64().unwrap().abs();
    let a = (4.0 * p * R / (std::f64::consts::PI * E_STAR)).sqrt();
    (
        a,
        2.0 * p / (std::f64::consts::PI * a),
        a * (1.0 - q / (MU * p)).sqrt(),
    )
}

/// The rms relative error of the tangential traction over |x| < a, node weights as lengths,
/// the traction's sign aligned with the pair's tangential force (docs/scene.md, study).
fn traction_rms(pair: &Value) -> f64 {
    let (a, p0, c) = theory(pair);
    let sign = pair["tangential_force"].as_f64().unwrap().signum();
    let root = |r: f64, x: f64| (r * r - x * x).max(0.0).sqrt();
    let (mut err, mut norm) = (0.0, 0.0);
    for n in pair["nodes"].as_array().unwrap() {
        let x = n["x"].as_f64().unwrap() - CENTRE;
        if x.abs() >= a {
            continue;
        }
        let want = if x.abs() < c {
            MU * p0 / a * (root(a, x) - root(c, x))
        } else {
            MU * p0 / a * root(a, x)
        };
        let got = sign * n["tangential_traction"].as_f64().unwrap();
        let w = n["weight"].as_f64().unwrap();
        err += w * (got - want).powi(2);
        norm += w * want * want;
    }
    (err / norm).sqrt()
}

#[test]
fn the_cattaneo_study_converges_and_finds_cattaneo_s_stick_zone() {
    let dir = tempfile::tempdir().unwrap();
    let scene = repo("fixtures/accuracy/cattaneo.toml");
    let scene = scene.to_str().unwrap();
    // Contact-zone sizes 0.008, 0.004, 0.002 (the refine boxes scale with --hmax): a/4, a/8
    // and a/16 for a ≈ 0.033 at this press.  The last level is the fixture as written.
    let out = succeeded(&signorini(
        &[
            "study",
            scene,
            "--hmax",
            "0.064,0.032,0.016",
            "--formulations",
            "mortar",
            "--meshes",
            "graded",
            "--elements",
            "p1",
            "--out",
            "study",
        ],
        dir.path(),
    ));
    assert!(out.contains("err c") && out.contains("err q"), "{out}");
    let points = read_points(&dir.path().join("study/study.csv")).unwrap();
    assert_eq!(points.len(), 3);
    assert!(points.iter().all(|p| p.solved()), "{points:?}");
    let (coarse, fine) = (&points[0], &points[2]);
    assert_eq!((coarse.hmax, fine.hmax), (0.064, 0.016));

    // The same finest scene solved by `solve`: the study's figures must be the ones computed
    // here from its result.json with Cattaneo's formulas (an independent computation of the
    // reference and of the error), to round-off of the CSV's decimal figures.
    succeeded(&signorini(&["solve", scene, "--out", "solve"], dir.path()));
    let result = json(&dir.path().join("solve/result.json"));
    let pair = &result["contacts"][0];
    let (_, _, c) = theory(pair);
    let rms = traction_rms(pair);
    let study_rms = fine.error_tangential_traction.unwrap();
    assert!((study_rms / rms - 1.0).abs() < 1e-9, "{study_rms} vs {rms}");
    let study_c = fine.stick_half_width.unwrap();
    let study_error = fine.error_stick_half_width.unwrap();
    assert!(
        ((1.0 + study_error) * c / study_c - 1.0).abs() < 1e-9,
        "c {study_c}, error {study_error}, Cattaneo {c}"
    );

    // c within 2 % of Cattaneo's on the finest level (the tolerance, as in
    // cattaneo.rs): the moment estimator's own bias is (1/3)(h/c)² = 0.3 % at h = c/10.6, and
    // the tangential traction the press locks in (the finite bodies expand differently, an odd
    // q of ≈ 1–2 % of μp₀) shifts the zone sideways, which moves a second moment about the
    // centre only at second order.
    assert!(
        (study_c / c - 1.0).abs() < 0.02,
        "c = {study_c}, Cattaneo {c}"
    );

    // The traction error falls with h.  Write it e² = D² + F²: D the discretisation error,
    // carried mostly by the nodes next to q's square-root cusps at |x| = c and |x| = a, which
    // falls at least like h^½ (the finite element rate for a square-root singularity), so
    // D(a/16) ≤ D(a/4)/2; F the tangential traction the press locks in (the finite bodies
    // expand sideways differently, which Cattaneo's half-spaces do not: odd in x), which no
    // mesh removes.  Then e(a/16)/e(a/4) ≤ √(1/4 + 3φ/4), φ = F²/e(a/4)², which is below 0.85
    // as long as F < 0.79 e(a/4).  Solving the press alone gives an odd traction of ≈ 1–2 % of
    // μp₀, and the odd part of the error at a/4 is ≈ 2 % of the ≈ 6 % total (φ ≈ 0.14).
    let (e0, e2) = (
        coarse.error_tangential_traction.unwrap(),
        fine.error_tangential_traction.unwrap(),
    );
    assert!(e2 < 0.85 * e0, "rms {e0} at a/4, {e2} at a/16");

    // The plot has Cattaneo's two panels.
    let svg = std::fs::read_to_string(dir.path().join("study/accuracy.svg")).unwrap();
    assert!(svg.contains("stick half-width c (Cattaneo)"), "{svg}");
    assert!(svg.contains("tangential q, rms (Cattaneo)"));
}

#[test]
fn a_frictionless_study_prints_no_cattaneo_columns() {
    let dir = tempfile::tempdir().unwrap();
    let scene = repo("fixtures/accuracy/patch.toml");
    let out = succeeded(&signorini(
        &[
            "study",
            scene.to_str().unwrap(),
            "--hmax",
            "0.1",
            "--formulations",
            "mortar",
            "--meshes",
            "uniform",
            "--elements",
            "p1",
            "--out",
            "study",
        ],
        dir.path(),
    ));
    assert!(out.contains("patch") && !out.contains("err c"), "{out}");
    let points = read_points(&dir.path().join("study/study.csv")).unwrap();
    assert_eq!(points[0].error_tangential_traction, None);
    assert_eq!(points[0].stick_half_width, None);
}

/// The fixture's text with `from` replaced by `to` (which must occur).
fn edited(from: &str, to: &str) -> String {
    let text = std::fs::read_to_string(repo("fixtures/accuracy/cattaneo.toml")).unwrap();
    assert!(text.contains(from), "{from}");
    text.replacen(from, to, 1)
}

#[test]
fn a_cattaneo_reference_refuses_bad_or_missing_keys_naming_the_key() {
    let reference_friction = "contact_modulus = 0.5494505494505494\nfriction = 0.3";
    let cases = [
        // A missing key of the three.
        (
            edited(reference_friction, "contact_modulus = 0.5494505494505494"),
            "`friction` is missing",
        ),
        (edited("radius = 1.0\n", ""), "`radius` is missing"),
        // Out of range.
        (
            edited(
                "contact_modulus = 0.5494505494505494",
                "contact_modulus = -1",
            ),
            "`contact_modulus` must be positive",
        ),
        // Mixed with Hertz's stated values.
        (
            edited("radius = 1.0\n", "radius = 1.0\nhalf_width = 0.05\n"),
            "`half_width` cannot be given",
        ),
        // No centre.
        (edited("centre = [0.8, 0.8]\n", ""), "`centre` is required"),
        // A μ that is not the pair's, and a frictionless pair.
        (
            edited(
                reference_friction,
                "contact_modulus = 0.5494505494505494\nfriction = 0.2",
            ),
            "`friction` = 0.2: contact pair 1 has Coulomb friction μ = 0.3",
        ),
        (
            edited("friction = 0.3\n\n[[step]]", "\n[[step]]"),
            "`friction` = 0.3: contact pair 1 has no friction",
        ),
    ];
    for (text, want) in cases {
        let err = Scene::from_toml(&text).unwrap_err().to_string();
        assert!(
            err.contains("[reference]") && err.contains(want),
            "{want}: {err}"
        );
    }
    // The fixture itself is accepted, as a Cattaneo reference.
    let scene = Scene::from_path(&repo("fixtures/accuracy/cattaneo.toml")).unwrap();
    let c = scene.reference.unwrap().cattaneo.unwrap();
    assert_eq!((c.radius, c.contact_modulus, c.friction), (R, E_STAR, MU));
}
