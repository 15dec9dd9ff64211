//! `signorini suite`: scenes through every backend, checked against their expectations.
//!
//! * the seed suite runs through the library with every backend and passes: every case has an
//!   expectation and every answer matches it (the expectations were blessed from one backend,
//!   so each other backend's agreement to 1e-6 is an independent check of it);
//! * the hard suite passes likewise (without dual-uzawa, whose expected failures are its
//!   10-second time limits, to keep the test short; the CLI run is checked by hand and in CI
//!   by the README's command);
//! * a deliberately broken expectation makes the suite fail with exit 2, naming the case and
//!   the figure; expected failures, unexpected passes and scenes without solution behave as
//!   documented; `--bless` writes, reports and leaves unchanged files alone; the JUnit file
//!   parses and counts what the report counts; `--baseline` reports slower cases and status
//!   changes.
#![allow(clippy::unwrap_used)]

mod common;
use common::signorini;

use std::path::{Path, PathBuf};

use signorini::backends::BackendKind;
use signorini::suite::report::Verdict;
use signorini::suite::{self, SuiteSettings};
use signorini_core::mesh::MeshLimits;
use signorini_core::qp::SolveOptions;

fn repo(path: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(path)
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).expect("read")).expect("JSON")
}

fn settings(backends: &[BackendKind]) -> SuiteSettings {
    SuiteSettings {
        backends: backends.iter().copied().filter(|k| k.available()).collect(),
        solve: SolveOptions {
            tol: 1e-9,
            time_limit: Some(std::time::Duration::from_secs(10)),
            ..SolveOptions::default()
        },
        limits: MeshLimits::default(),
        repeat: 1,
        only: Vec::new(),
    }
}

/// A scratch suite: the named fixtures (scene and expectation) copied into a temporary
/// directory.
fn scratch(fixtures: &[&str]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for f in fixtures {
        let scene = repo(&format!("fixtures/{f}.toml"));
        let name = scene.file_name().unwrap();
        std::fs::copy(&scene, dir.path().join(name)).unwrap();
        let expected = suite::expectation::path_for(&scene);
        if expected.exists() {
            std::fs::copy(&expected, dir.path().join(expected.file_name().unwrap())).unwrap();
        }
    }
    dir
}

fn text(o: &std::process::Output) -> (String, String) {
    (
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

#[test]
fn the_seed_suite_passes_through_the_library() {
    let report = suite::run(
        &repo("fixtures/seed"),
        &settings(&suite::DEFAULT_BACKENDS),
        |_| {},
    )
    .unwrap();
    assert_eq!(report.cases.len(), 19);
    for case in &report.cases {
        assert!(case.error.is_none(), "{}: {:?}", case.name, case.error);
        assert!(case.expectation.is_some(), "{}: no expectation", case.name);
        for run in &case.runs {
            // No seed scene has an expected failure: every backend must solve and match.
            assert_eq!(
                run.verdict,
                Verdict::Pass,
                "{} / {}: {} {:?} {:?}",
                case.name,
                run.backend,
                run.status,
                run.notes,
                run.message
            );
        }
    }
    assert!(report.regressions().is_empty());
    for s in &report.summary {
        assert_eq!(s.success_rate, 1.0, "{}", s.backend);
        assert!(s.sgm_time_s > 0.0 && s.sgm_ratio > 0.0, "{s:?}");
    }
}

#[test]
fn the_hard_suite_passes_through_the_library() {
    let backends = [
        BackendKind::Clarabel,
        BackendKind::Osqp,
        BackendKind::DualPgs,
        BackendKind::DualSsn,
        BackendKind::Pdas,
    ];
    // The partial-contact strip runs apart (below): osqp and dual-pgs spend their whole 10 s
    // limit on it and would double this test's time.
    let mut cases: Vec<String> = std::fs::read_dir(repo("fixtures/hard"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .filter(|name| name != PARTIAL)
        .collect();
    cases.sort();
    let mut most = settings(&backends);
    most.only = cases;
    let report = suite::run(&repo("fixtures/hard"), &most, |_| {}).unwrap();
    assert_eq!(report.cases.len(), 28);
    assert!(
        report.regressions().is_empty(),
        "{}",
        suite::table::table(&report)
    );
    let case = |name: &str| report.cases.iter().find(|c| c.name == name).unwrap();
    // The scene without a solution: every backend rightly says not solved.
    for run in &case("floating-free").runs {
        assert_ne!(run.status, "solved");
        assert_eq!(run.verdict, Verdict::Pass);
    }
    // The known failures are expected, not regressions.
    let verdict = |c: &str, b: &str| {
        case(c)
            .runs
            .iter()
            .find(|r| r.backend == b)
            .map(|r| r.verdict)
    };
    if BackendKind::Osqp.available() {
        assert_eq!(
            verdict("stiffness-contrast", "osqp"),
            Some(Verdict::ExpectedFailure)
        );
    }
    assert_eq!(
        verdict("strip-thin-floating", "dual-pgs"),
        Some(Verdict::ExpectedFailure)
    );
    // No contact row: one linear solve, checked like any answer.
    let inert = case("inert-rows");
    assert_eq!(inert.runs.len(), 1);
    assert_eq!(inert.runs[0].backend, "cholesky");
    assert_eq!(inert.runs[0].verdict, Verdict::Pass);
}

/// The long interface in partial contact (issue 21), a hard case run apart.
const PARTIAL: &str = "strip-thin-partial";

/// The partial-contact strip through the backends that end well within the limit (pdas
/// solves it, clarabel and dual-ssn fail as expected): osqp and dual-pgs reach the 10 s limit
/// there (their expected failures are checked by the CLI run of `signorini suite
/// fixtures/hard`).
#[test]
fn the_partial_contact_strip_passes_through_the_library() {
    let backends = [
        BackendKind::Clarabel,
        BackendKind::DualSsn,
        BackendKind::Pdas,
    ];
    let mut only = settings(&backends);
    only.only = vec![PARTIAL.to_string()];
    let report = suite::run(&repo("fixtures/hard"), &only, |_| {}).unwrap();
    assert_eq!(report.cases.len(), 1);
    assert!(
        report.regressions().is_empty(),
        "{}",
        suite::table::table(&report)
    );
    let pdas = report.cases[0]
        .runs
        .iter()
        .find(|r| r.backend == "pdas")
        .unwrap();
    assert_eq!(pdas.verdict, Verdict::Pass);
}

/// Multiplies the objective of `dir/NAME.expected.json` by `factor`.
fn scale_objective(dir: &Path, name: &str, factor: f64) {
    let path = dir.join(format!("{name}.expected.json"));
    let mut e = json(&path);
    let o = e["figures"]["objective"].as_f64().unwrap();
    e["figures"]["objective"] = serde_json::json!(o * factor);
    std::fs::write(&path, serde_json::to_string_pretty(&e).unwrap()).unwrap();
}

#[test]
fn a_broken_expectation_fails_naming_the_case_and_the_figure() {
    let dir = scratch(&["seed/exp2b", "seed/exp2c"]);
    let out = dir.path().join("out");
    let args = |o: &Path| {
        vec![
            "suite".to_string(),
            ".".to_string(),
            "--backends".to_string(),
            "clarabel,dual-ssn".to_string(),
            "--out".to_string(),
            o.display().to_string(),
        ]
    };
    let run = |o: &Path| {
        let a = args(o);
        signorini(
            &a.iter().map(String::as_str).collect::<Vec<_>>(),
            dir.path(),
        )
    };
    let o = run(&out);
    assert_eq!(o.status.code(), Some(0), "{:?}", text(&o));
    // 1e-5 relative: ten times the default rtol 1e-6, far below any physical change.
    scale_objective(dir.path(), "exp2b", 1.0 + 1e-5);
    let o = run(&out);
    let (stdout, stderr) = text(&o);
    assert_eq!(o.status.code(), Some(2), "{stdout}\n{stderr}");
    assert!(stderr.contains("regressed: exp2b"), "{stderr}");
    assert!(!stderr.contains("exp2c"), "{stderr}");
    assert!(stdout.contains("✗ objective"), "{stdout}");
    assert!(stdout.contains("exp2b / clarabel: objective:"), "{stdout}");
    let report = json(&out.join("suite.json"));
    let case = report["cases"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["name"] == "exp2b")
        .unwrap();
    for r in case["runs"].as_array().unwrap() {
        assert_eq!(r["verdict"], "fail");
    }
    // The JUnit file reports the same failures, one per backend, under the case's name.
    let xml = std::fs::read_to_string(out.join("suite.xml")).unwrap();
    let doc = roxmltree::Document::parse(&xml).expect("well-formed XML");
    let failed: Vec<String> = doc
        .descendants()
        .filter(|n| n.has_tag_name("testcase"))
        .filter(|n| n.children().any(|c| c.has_tag_name("failure")))
        .map(|n| n.attribute("name").unwrap_or("").to_string())
        .collect();
    assert_eq!(failed, vec!["exp2b", "exp2b"], "{xml}");
    let cases = doc
        .descendants()
        .filter(|n| n.has_tag_name("testcase"))
        .count();
    assert_eq!(cases, 4);
    // A tolerance set in the file governs: rtol 1e-4 on the objective lets 1e-5 pass.
    let path = dir.path().join("exp2b.expected.json");
    let mut e = json(&path);
    e["rtol"]["objective"] = serde_json::json!(1e-4);
    std::fs::write(&path, serde_json::to_string_pretty(&e).unwrap()).unwrap();
    let o = run(&out);
    assert_eq!(o.status.code(), Some(0), "{:?}", text(&o));
}

#[test]
fn expected_failures_and_unexpected_passes() {
    if !BackendKind::Osqp.available() {
        return;
    }
    let dir = scratch(&["hard/stiffness-contrast"]);
    let run = || {
        signorini(
            &["suite", ".", "--backends", "clarabel,osqp", "--out", "out"],
            dir.path(),
        )
    };
    // OSQP's known failure on the 1e6 contrast is expected: exit 0.
    let o = run();
    let (stdout, stderr) = text(&o);
    assert_eq!(o.status.code(), Some(0), "{stdout}\n{stderr}");
    assert!(stdout.contains("(✗) inaccurate"), "{stdout}");
    // Without the entry, the same failure is a regression.
    let path = dir.path().join("stiffness-contrast.expected.json");
    let original = std::fs::read_to_string(&path).unwrap();
    let mut e: serde_json::Value = serde_json::from_str(&original).unwrap();
    e["expected_failures"]
        .as_object_mut()
        .unwrap()
        .remove("osqp");
    std::fs::write(&path, serde_json::to_string(&e).unwrap()).unwrap();
    let o = run();
    let (stdout, stderr) = text(&o);
    assert_eq!(o.status.code(), Some(2), "{stdout}\n{stderr}");
    assert!(stderr.contains("regressed: stiffness-contrast"), "{stderr}");
    assert!(
        stdout.contains("status: inaccurate, expected solved"),
        "{stdout}"
    );
    // clarabel listed as failing but solving: reported, not a regression.
    e["expected_failures"]["clarabel"] = serde_json::json!({"why": "test"});
    e["expected_failures"]["osqp"] = serde_json::json!({});
    std::fs::write(&path, serde_json::to_string(&e).unwrap()).unwrap();
    let o = run();
    let (stdout, stderr) = text(&o);
    assert_eq!(o.status.code(), Some(0), "{stdout}\n{stderr}");
    assert!(stdout.contains("✓!"), "{stdout}");
    assert!(
        stdout.contains(
            "stiffness-contrast / clarabel: solved within tolerance though expected to fail: test"
        ),
        "{stdout}"
    );
}

#[test]
fn a_scene_without_solution_must_not_be_solved() {
    let dir = scratch(&["hard/floating-free"]);
    let run = || {
        signorini(
            &["suite", ".", "--backends", "clarabel,pdas", "--out", "out"],
            dir.path(),
        )
    };
    let o = run();
    assert_eq!(o.status.code(), Some(0), "{:?}", text(&o));
    // Claiming the scene is solvable turns the honest refusals into regressions.
    let path = dir.path().join("floating-free.expected.json");
    std::fs::write(
        &path,
        r#"{"status": "solved", "figures": {"objective": -1, "max_displacement": 1,
            "contact_forces": [], "probes": []}}"#,
    )
    .unwrap();
    let o = run();
    let (_, stderr) = text(&o);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("regressed: floating-free"), "{stderr}");
}

#[test]
fn bless_writes_reports_and_leaves_unchanged_files_alone() {
    let dir = tempfile::tempdir().unwrap();
    let sub = dir.path().join("two");
    std::fs::create_dir(&sub).unwrap();
    std::fs::copy(repo("fixtures/seed/exp2b.toml"), sub.join("b.toml")).unwrap();
    std::fs::copy(repo("fixtures/seed/exp4.toml"), dir.path().join("a.toml")).unwrap();
    let run = |extra: &[&str]| {
        let mut args = vec!["suite", ".", "--backends", "clarabel,pdas", "--out", "out"];
        args.extend_from_slice(extra);
        signorini(&args, dir.path())
    };
    // Nothing to check against: a non-zero exit that says how to fix it.
    let o = run(&[]);
    let (_, stderr) = text(&o);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr.contains("no expectation"), "{stderr}");
    assert!(stderr.contains("a, two/b"), "{stderr}");
    let o = run(&["--bless"]);
    let (stdout, _) = text(&o);
    assert_eq!(o.status.code(), Some(0), "{stdout}");
    assert!(stdout.contains("a.expected.json (new)"), "{stdout}");
    assert!(stdout.contains("b.expected.json (new)"), "{stdout}");
    let blessed = sub.join("b.expected.json");
    let e = json(&blessed);
    assert_eq!(e["status"], "solved");
    assert_eq!(e["rtol"]["default"], 1e-6);
    // The stored objective is the solve's (exp2b through `solve`, an independent path).
    let solve_dir = dir.path().join("solve");
    let o = signorini(
        &[
            "solve",
            "two/b.toml",
            "--backend",
            "clarabel",
            "--out",
            solve_dir.to_str().unwrap(),
        ],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(0));
    let result = json(&solve_dir.join("result.json"));
    let (a, b) = (
        result["objective"].as_f64().unwrap(),
        e["figures"]["objective"].as_f64().unwrap(),
    );
    assert!((a - b).abs() <= 1e-6 * b.abs(), "{a} vs {b}");
    let o = run(&[]);
    assert_eq!(o.status.code(), Some(0), "{:?}", text(&o));
    // A changed scene (load doubled) fails, and --bless says what changed and rewrites only it.
    let scene = std::fs::read_to_string(sub.join("b.toml")).unwrap();
    let doubled = scene.replace("traction = [0, -1e-4]", "traction = [0, -2e-4]");
    assert_ne!(doubled, scene, "the fixture's traction line moved");
    std::fs::write(sub.join("b.toml"), doubled).unwrap();
    let o = run(&[]);
    let (_, stderr) = text(&o);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr.contains("regressed: two/b"), "{stderr}");
    let a_before = std::fs::metadata(dir.path().join("a.expected.json"))
        .unwrap()
        .modified()
        .unwrap();
    let o = run(&["--bless"]);
    let (stdout, _) = text(&o);
    assert_eq!(o.status.code(), Some(0), "{stdout}");
    assert!(stdout.contains("b.expected.json (changed)"), "{stdout}");
    assert!(stdout.contains("objective:"), "{stdout}");
    assert!(stdout.contains("1 expectations unchanged"), "{stdout}");
    let a_after = std::fs::metadata(dir.path().join("a.expected.json"))
        .unwrap()
        .modified()
        .unwrap();
    assert_eq!(a_before, a_after, "an unchanged expectation was rewritten");
    // Linear elasticity with contact that stays active: twice the load, four times the work.
    let e2 = json(&blessed);
    let ratio = e2["figures"]["objective"].as_f64().unwrap() / b;
    assert!((ratio - 4.0).abs() < 1e-6, "{ratio}");
    // No staging file is left beside the expectations.
    for entry in std::fs::read_dir(&sub).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        assert!(!name.starts_with(".signorini"), "{name}");
    }
}

#[test]
fn baseline_reports_slower_cases_and_status_changes() {
    let dir = scratch(&["seed/exp2b", "seed/exp6a"]);
    let o = signorini(
        &["suite", ".", "--backends", "clarabel,pdas", "--out", "old"],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(0), "{:?}", text(&o));
    // Doctor the baseline: exp6a's clarabel was 100× faster (relative to its floor), and
    // exp2b's pdas had failed.
    let path = dir.path().join("old/suite.json");
    let mut old = json(&path);
    for case in old["cases"].as_array_mut().unwrap() {
        let name = case["name"].as_str().unwrap().to_string();
        for r in case["runs"].as_array_mut().unwrap() {
            if name == "exp6a" && r["backend"] == "clarabel" {
                let ratio = r["ratio_to_floor"].as_f64().unwrap();
                r["ratio_to_floor"] = serde_json::json!(ratio / 100.0);
                r["solve_s"] = serde_json::json!(0.0);
            }
            if name == "exp2b" && r["backend"] == "pdas" {
                r["status"] = serde_json::json!("max-iterations");
            }
        }
    }
    std::fs::write(&path, serde_json::to_string(&old).unwrap()).unwrap();
    let args = [
        "suite",
        ".",
        "--backends",
        "clarabel,pdas",
        "--out",
        "new",
        "--baseline",
        "old/suite.json",
    ];
    let o = signorini(&args, dir.path());
    let (stdout, stderr) = text(&o);
    // Slower is reported, not a failure, unless asked.
    assert_eq!(o.status.code(), Some(0), "{stdout}\n{stderr}");
    assert!(stdout.contains("exp6a: slower ×"), "{stdout}");
    assert!(
        stdout.contains("exp2b: status max-iterations → solved"),
        "{stdout}"
    );
    let report = json(&dir.path().join("new/suite.json"));
    // The two doctored changes are there (others may be timing noise of a loaded machine: not
    // asserted either way).
    let changes = report["baseline"]["changes"].as_array().unwrap();
    let has = |case: &str, backend: &str, kind: &str| {
        changes
            .iter()
            .any(|c| c["case"] == case && c["backend"] == backend && c["kind"] == kind)
    };
    assert!(has("exp6a", "clarabel", "slower"), "{changes:?}");
    assert!(has("exp2b", "pdas", "status"), "{changes:?}");
    let mut strict = args.to_vec();
    strict.push("--fail-slower");
    let o = signorini(&strict, dir.path());
    assert_eq!(o.status.code(), Some(2), "{:?}", text(&o));
    // A file that is not a suite.json is refused as bad input.
    let o = signorini(
        &["suite", ".", "--out", "x", "--baseline", "exp2b.toml"],
        dir.path(),
    );
    let (_, stderr) = text(&o);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("exp2b.toml is not a suite.json"),
        "{stderr}"
    );
    assert!(!dir.path().join("x").exists(), "refused, yet ran and wrote");
}

#[test]
fn a_scene_file_is_a_suite_of_one() {
    let dir = scratch(&["seed/exp2b"]);
    let o = signorini(
        &["suite", "exp2b.toml", "--backends", "pdas", "--out", "out"],
        dir.path(),
    );
    let (stdout, stderr) = text(&o);
    assert_eq!(o.status.code(), Some(0), "{stdout}\n{stderr}");
    let report = json(&dir.path().join("out/suite.json"));
    assert_eq!(report["cases"].as_array().unwrap().len(), 1);
    assert_eq!(report["cases"][0]["name"], "exp2b");
    assert_eq!(report["cases"][0]["runs"][0]["verdict"], "pass");
}

#[test]
fn only_runs_the_cases_named() {
    let dir = scratch(&["seed/exp2b", "seed/exp2c", "seed/exp4"]);
    let o = signorini(
        &[
            "suite",
            ".",
            "--backends",
            "pdas",
            "--only",
            "2c,exp4",
            "--out",
            "out",
        ],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(0), "{:?}", text(&o));
    let report = json(&dir.path().join("out/suite.json"));
    let names: Vec<&str> = report["cases"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["exp2c", "exp4"]);
    // Selecting nothing is a usage error that lists the cases.
    let o = signorini(&["suite", ".", "--only", "strip", "--out", "x"], dir.path());
    let (_, stderr) = text(&o);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("\"strip\"") && stderr.contains("exp2b, exp2c, exp4"),
        "{stderr}"
    );
}

#[test]
fn bad_input_is_refused_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let o = signorini(&["suite", "missing"], dir.path());
    let (_, stderr) = text(&o);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("missing"), "{stderr}");
    let o = signorini(&["suite", "."], dir.path());
    let (_, stderr) = text(&o);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("holds no scene"), "{stderr}");
    // A broken scene or expectation is that case's failure; the others still run.
    let dir = scratch(&["seed/exp2b", "seed/exp2c"]);
    std::fs::write(
        dir.path().join("exp2c.expected.json"),
        "{\"status\": \"solved\", \"rtol\": {\"objetive\": 1}}",
    )
    .unwrap();
    std::fs::write(dir.path().join("broken.toml"), "title = 3").unwrap();
    let o = signorini(
        &["suite", ".", "--backends", "pdas", "--out", "out"],
        dir.path(),
    );
    let (stdout, stderr) = text(&o);
    assert_eq!(o.status.code(), Some(2), "{stdout}\n{stderr}");
    assert!(stderr.contains("regressed: broken, exp2c"), "{stderr}");
    assert!(stdout.contains("objetive"), "{stdout}");
    let row = stdout.lines().find(|l| l.starts_with("  exp2b ")).unwrap();
    assert!(row.contains('✓'), "{stdout}");
    assert!(!dir.path().join("out/.signorini-stage").exists());
}

/// The figures of a committed expectation.
fn figures(fixture: &str) -> serde_json::Value {
    json(&repo(&format!("fixtures/{fixture}.expected.json")))["figures"].clone()
}

fn force(f: &serde_json::Value, pair: usize) -> f64 {
    f["contact_forces"][pair]["normal_force"].as_f64().unwrap()
}

fn num(f: &serde_json::Value, key: &str) -> f64 {
    f[key].as_f64().unwrap()
}

/// The committed expectations were blessed from the program's answers; these are checks of them
/// against physics, independent of any backend: exact answers and scaling laws stated in the
/// fixtures' headers.  Tolerances: 1e-8 relative where the answer is exact for the elements
/// (linear fields, equilibrium), i.e. the KKT tolerance 1e-9 with a margin of ten.
#[test]
fn committed_expectations_agree_with_physics() {
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
    // SI units: E ×1e10 (Pa), traction ×1e10 (1e6 Pa vs 1e-4): u ×1e-4, forces ×1e10, energy
    // ×1e6 — the same problem in other units.
    let (si, b) = (figures("hard/si-units"), figures("seed/exp2b"));
    assert!(
        rel(
            num(&si, "max_displacement"),
            1e-4 * num(&b, "max_displacement")
        ) < 1e-8
    );
    assert!(rel(force(&si, 0), 1e10 * force(&b, 0)) < 1e-8);
    assert!(rel(num(&si, "objective"), 1e6 * num(&b, "objective")) < 1e-8);
    // A block held up by contact alone carries its whole load 1e-4 (× length 1) to the support.
    assert!(rel(force(&figures("hard/floating"), 0), 1e-4) < 1e-8);
    // Initial overlap (uniaxial strain, exact for P1): force p = 1e-5 over length 1; the largest
    // displacement is the upper block's bottom, pushed out: δ − p / M_lower.
    let o = figures("hard/initial-overlap");
    assert!(rel(force(&o, 0), 1e-5) < 1e-8);
    let m = |e: f64, nu: f64| e * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let exact = 0.05 - 1e-5 / m(0.0012, 0.34);
    assert!(rel(num(&o, "max_displacement"), exact) < 1e-8, "{o}");
    // A long strip on a foundation, floating: contact carries p L = 1e-3 × 3.
    for strip in ["hard/strip-thin-floating", "hard/strip-thick-floating"] {
        assert!(rel(force(&figures(strip), 0), 3e-3) < 1e-8, "{strip}");
    }
    // Open gaps and bodies pulled apart: no force; exp2c (load upward) likewise.
    for open in ["hard/gap-open", "hard/pulling-apart", "seed/exp2c"] {
        assert_eq!(force(&figures(open), 0), 0.0, "{open}");
    }
    // exp6b's prescribed edge: the probe sits on it, (−0.08, 0) exactly.
    let p = &figures("seed/exp6b")["probes"];
    let edge = p
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["name"] == "middle-right")
        .unwrap();
    assert_eq!(edge["displacement"], serde_json::json!([-0.08, 0.0]));
    // The scene without a solution has no figures.
    let free = json(&repo("fixtures/hard/floating-free.expected.json"));
    assert_eq!(free["status"], "not-solved");
    assert!(free.get("figures").is_none());
}
