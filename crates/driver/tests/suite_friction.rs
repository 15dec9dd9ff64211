//! `signorini suite` on frictional scenes (issue 20): a frictional pair's tangential force is
//! recorded beside its normal force in suite.json's figures (the value result.json reports, and
//! the analytic μN of a full slide), checked against an expectation that records it, and added
//! by `--bless` to one that does not; a frictionless pair's figures stay as they were.

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used)]

mod common;

use common::{json, repo, signorini, succeeded};
use serde_json::Value;

/// Runs `signorini suite` on `scene` (a suite of one) with clarabel; returns suite.json's run.
fn suite_run(dir: &std::path::Path, scene: &str, out: &str) -> Value {
    let o = signorini(
        &[
            "suite",
            scene,
            "--backends",
            "clarabel",
            "--repeat",
            "1",
            "--out",
            out,
        ],
        dir,
    );
    // Exit 0, or non-zero for a regression: both write suite.json; the callers judge the verdict.
    assert!(
        matches!(o.status.code(), Some(0..=2)),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let report = json(&dir.join(out).join("suite.json"));
    report["cases"][0]["runs"][0].clone()
}

#[test]
fn a_frictional_pair_s_tangential_force_is_in_the_suite_figures() {
    let dir = tempfile::tempdir().unwrap();
    // "friction-slide": full slip of a block pressed by N = 1e-3 with μ = 0.3.
    let scene = repo("fixtures/hard/friction-slide.toml");
    let scene = scene.to_str().unwrap();
    let run = suite_run(dir.path(), scene, "suite");
    assert_eq!(run["status"], "solved");
    let pair = &run["figures"]["contact_forces"][0];
    let t = pair["tangential_force"]
        .as_f64()
        .unwrap_or_else(|| panic!("no tangential force: {pair}"));
    // The same scene and backend through `solve`: the value result.json reports (the same
    // deterministic solve, so equal to round-off of the JSON's decimal figures).
    succeeded(&signorini(
        &["solve", scene, "--backend", "clarabel", "--out", "solve"],
        dir.path(),
    ));
    let result = json(&dir.path().join("solve/result.json"));
    let want = result["contacts"][0]["tangential_force"].as_f64().unwrap();
    assert!(
        (t / want - 1.0).abs() < 1e-12,
        "suite {t}, result.json {want}"
    );
    // And physics: a full slide transmits μN = 0.3 × 1e-3 (the fixture's table; within the
    // solver tolerance 1e-9 relative to the pair's forces, checked loosely at 1e-6).
    let n = pair["normal_force"].as_f64().unwrap();
    assert!((n / 1e-3 - 1.0).abs() < 1e-6, "N {n}");
    assert!((t.abs() / 3e-4 - 1.0).abs() < 1e-6, "T {t}");
}

#[test]
fn a_frictionless_pair_has_no_tangential_force_in_the_figures() {
    let dir = tempfile::tempdir().unwrap();
    let scene = repo("fixtures/seed/exp2b.toml");
    let run = suite_run(dir.path(), scene.to_str().unwrap(), "suite");
    let pair = &run["figures"]["contact_forces"][0];
    assert!(pair["normal_force"].as_f64().is_some(), "{pair}");
    assert!(pair.get("tangential_force").is_none(), "{pair}");
}

#[test]
fn bless_records_the_tangential_force_and_the_check_then_holds_it() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // A copy of "friction-slide" and its committed expectation, with the tangential force
    // taken out of the expectation's figures if it is there (as blessed before it was
    // recorded).
    std::fs::copy(
        repo("fixtures/hard/friction-slide.toml"),
        d.join("slide.toml"),
    )
    .unwrap();
    let mut e: Value = json(&repo("fixtures/hard/friction-slide.expected.json"));
    e["figures"]["contact_forces"][0]
        .as_object_mut()
        .unwrap()
        .remove("tangential_force");
    std::fs::write(d.join("slide.expected.json"), e.to_string()).unwrap();
    // Such an expectation checks no tangential force: pass.
    let run = suite_run(d, "slide.toml", "before");
    assert_eq!(run["verdict"], "pass", "{run}");
    // --bless sees the new figure as a change and records it.
    let o = signorini(
        &[
            "suite",
            "slide.toml",
            "--backends",
            "clarabel",
            "--repeat",
            "1",
            "--bless",
            "--out",
            "bless",
        ],
        d,
    );
    let (stdout, stderr) = (
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr),
    );
    assert!(
        stdout.contains("tangential force recorded")
            || stderr.contains("tangential force recorded"),
        "{stdout}\n{stderr}"
    );
    let blessed = json(&d.join("slide.expected.json"));
    let t = blessed["figures"]["contact_forces"][0]["tangential_force"]
        .as_f64()
        .unwrap();
    assert!((t.abs() / 3e-4 - 1.0).abs() < 1e-6, "{t}");
    // A wrong recorded tangential force (1 % off, far beyond rtol 1e-6 of the pair's scale)
    // is now a regression naming the figure.
    let mut wrong = blessed.clone();
    wrong["figures"]["contact_forces"][0]["tangential_force"] = Value::from(t * 1.01);
    std::fs::write(d.join("slide.expected.json"), wrong.to_string()).unwrap();
    let run = suite_run(d, "slide.toml", "after");
    assert_eq!(run["verdict"], "fail", "{run}");
    let notes = run["notes"].to_string();
    assert!(
        notes.contains("pair 1") && notes.contains("tangential force"),
        "{notes}"
    );
}
