//! The `signorini` binary end to end: files written on success, clear refusals on bad input with
//! a non-zero exit and nothing written.

mod common;
use common::signorini;

use std::path::{Path, PathBuf};
use std::process::Output;

fn fixtures() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fixtures")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn solve_without_a_scene_runs_experiment_2b_and_writes_four_files() {
    let dir = tempfile::tempdir().unwrap();
    let o = signorini(&["solve", "--out", "res"], dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let out = dir.path().join("res");
    for f in [
        "result.json",
        "solution.vtu",
        "deformed.svg",
        "pressure.svg",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let names: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names.len(), 4, "no stray temporary files: {names:?}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    for key in [
        "scene",
        "backend",
        "status",
        "effects",
        "dofs",
        "constraints",
        "active_constraints",
        "iterations",
        "objective",
        "residuals",
        "timing_s",
        "bodies",
        "contacts",
        "probes",
    ] {
        assert!(json.get(key).is_some(), "result.json lacks {key}");
    }
    assert_eq!(json["status"], "solved");
    assert_eq!(json["backend"], "auto");
    assert_eq!(
        json["effects"],
        serde_json::json!(["dirichlet", "neumann", "contact"])
    );
    for key in [
        "max_penetration",
        "stationarity",
        "complementarity",
        "min_multiplier",
    ] {
        assert!(json["residuals"][key].is_number(), "{key}");
    }
    let node = &json["contacts"][0]["nodes"][0];
    for key in ["x", "y", "gap", "multiplier", "pressure"] {
        assert!(node[key].is_number(), "contact node {key}");
    }
    let svg = std::fs::read_to_string(out.join("deformed.svg")).unwrap();
    assert!(svg.contains("displacement ×"));
}

fn refused(args: &[&str], scene_text: Option<&str>, expect: &[&str]) {
    let dir = tempfile::tempdir().expect("temporary directory");
    let mut full: Vec<String> = args.iter().map(|s| s.to_string()).collect();
    if let Some(text) = scene_text {
        std::fs::write(dir.path().join("scene.toml"), text).expect("write scene");
        full.insert(1, "scene.toml".into());
    }
    full.extend(["--out".to_string(), "res".to_string()]);
    let refs: Vec<&str> = full.iter().map(|s| s.as_str()).collect();
    let o = signorini(&refs, dir.path());
    assert!(!o.status.success(), "should fail: {refs:?}");
    let err = stderr(&o);
    for e in expect {
        assert!(err.contains(e), "stderr lacks {e:?}: {err}");
    }
    assert!(!err.contains("panicked"), "{err}");
    assert!(!dir.path().join("res").exists(), "nothing may be written");
}

#[test]
fn bad_scenes_are_refused_with_the_key_named_and_nothing_written() {
    let base = std::fs::read_to_string(fixtures().join("seed/exp2b.toml")).unwrap();
    refused(
        &["solve"],
        Some(&base.replace("young = 0.0012", "yuong = 0.0012")),
        &["yuong", "line"],
    );
    refused(
        &["solve"],
        Some(&base.replace("poisson = 0.34", "poisson = 0.7")),
        &["lower", "poisson"],
    );
    refused(&["solve"], Some("[[body]\n"), &["line 1", "column"]);
    refused(
        &["solve"],
        Some(&base.replace("region = [3, 3, 0, 1]", "region = [7, 7, 0, 1]")),
        &["dirichlet #2", "region"],
    );
    refused(
        &["solve"],
        Some(&base.replace(
            "bodies = [\"upper\", \"lower\"]",
            "bodies = [\"upper\", \"upper\"]",
        )),
        &["contact #1", "twice"],
    );
}

#[test]
fn oversized_scenes_are_refused_before_meshing() {
    refused(&["solve", "--max-elements", "100"], None, &["100"]);
    let dir = tempfile::tempdir().unwrap();
    let o = signorini(&["check", "--max-elements", "100"], dir.path());
    assert!(!o.status.success());
}

#[test]
fn unknown_backend_and_bad_tolerance_are_clear_errors() {
    refused(
        &["solve", "--backend", "gurobi"],
        None,
        &["unknown backend", "gurobi"],
    );
    refused(&["solve", "--tol", "0"], None, &["--tol"]);
    refused(&["solve", "--tol", "nan"], None, &["--tol"]);
}

#[test]
fn missing_scene_file_is_named() {
    refused(
        &["solve", "no/such/scene.toml"],
        None,
        &["no/such/scene.toml"],
    );
}

#[test]
fn check_accepts_every_fixture() {
    for sub in ["seed", "hard", "accuracy", "gmsh", "validation"] {
        for entry in std::fs::read_dir(fixtures().join(sub)).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "toml") {
                let o = signorini(&["check", path.to_str().unwrap()], Path::new("."));
                assert!(o.status.success(), "{}: {}", path.display(), stderr(&o));
            }
        }
    }
}

/// `check` states the dense contact Hessian the dual backends hold, which its scene-based memory
/// model leaves out: for the thin strip's 301 rows, 8 · 301² B = 724 808 B = 0.7 MiB (by hand).
#[test]
fn check_states_the_dual_backends_dense_hessian() {
    let scene = fixtures().join("hard/strip-thin-floating.toml");
    let o = signorini(&["check", scene.to_str().unwrap()], Path::new("."));
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("8·m² B = 0.7 MiB for m = 301 rows"), "{out}");
}

/// docs/getting-started.md walks its scene through `check` and `solve`: the scene must stay
/// valid and solved, writing the four files the guide lists, and the contact force it quotes is
/// the applied load (traction 10 × width 0.5 = 5: the block is held vertically by the contact
/// alone, so equilibrium fixes it; 1e-7 relative: the stationarity residual, ≤ 1e-9 per DOF of
/// the force scale, summed over the ~10² DOFs of the interface region, as in
/// contact_verification.rs).
#[test]
fn the_getting_started_scene_does_what_the_guide_says() {
    let scene = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../docs/getting-started.toml");
    let dir = tempfile::tempdir().unwrap();
    let o = signorini(&["check", scene.to_str().unwrap()], dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let o = signorini(
        &["solve", scene.to_str().unwrap(), "--out", "out"],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    for f in [
        "result.json",
        "solution.vtu",
        "deformed.svg",
        "pressure.svg",
    ] {
        assert!(dir.path().join("out").join(f).exists(), "{f}");
    }
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("out/result.json")).unwrap())
            .unwrap();
    assert_eq!(r["status"], "solved");
    let force = r["contacts"][0]["normal_force"].as_f64().unwrap();
    assert!((force - 5.0).abs() < 1e-9 * 5.0 * 100.0, "{force}");
    assert_eq!(r["contacts"][0]["formulation"], "mortar");
}

/// `--verbose` hands the backend its iteration log: pdas prints one line per active-set step
/// (exp2b's contact takes at least one), and without the flag it prints none.
#[test]
fn verbose_prints_the_backend_s_iteration_log() {
    let dir = tempfile::tempdir().unwrap();
    for (flag, want) in [(true, true), (false, false)] {
        let mut args = vec!["solve", "--backend", "pdas", "--out"];
        args.push(if flag { "loud" } else { "quiet" });
        if flag {
            args.push("--verbose");
        }
        let o = signorini(&args, dir.path());
        assert!(o.status.success(), "{}", stderr(&o));
        assert_eq!(
            stderr(&o).contains("pdas: iteration 1:"),
            want,
            "--verbose {flag}: {}",
            stderr(&o)
        );
    }
}
