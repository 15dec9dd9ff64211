//! `--backend auto` (the chain with fall-back) and `--form dual` (the condensed dual of clarabel
//! and osqp), through the library and the binary.  `measure` (ignored) prints the timings behind
//! auto's rule and the clarabel linear-solver choice.

// Helpers are test code too: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used)]

mod common;
use common::signorini;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

use signorini::auto::{plan, AutoBackend, Features};
use signorini::backends::{make_backend, BackendKind};
use signorini::run;
use signorini_clarabel::{ClarabelBackend, ClarabelSettings, DirectSolver};
use signorini_core::mesh::MeshLimits;
use signorini_core::qp::{
    norm_inf, BlockKind, ContactBody, QpBackend, QpStatus, ResidualScales, SolveOptions,
};
use signorini_core::solve;
use signorini_dual::{DualBackend, DualSettings};

fn fixture(dir: &str, name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("../../fixtures/{dir}/{name}.toml"))
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn result_json(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("result.json")).unwrap()).unwrap()
}

fn solve_with(path: &Path, backend: &mut dyn QpBackend, options: &SolveOptions) -> run::Outcome {
    let scene = run::load_scene(Some(path)).unwrap();
    run::solve_scene(&scene, backend, options, &MeshLimits::default()).unwrap()
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Relative agreement of two solves: max |Δu| / max |u| and max |Δλ| / F, F the larger of
/// max |λ| and the total applied load (λ = 0 without contact, where only the load sets a scale).
fn agreement(a: &run::Outcome, b: &run::Outcome) -> (f64, f64) {
    let (a_u, b_u) = (&a.solution.displacement, &b.solution.displacement);
    let du = max_diff(a_u, b_u) / norm_inf(a_u).max(1e-300);
    let load: f64 = a.model.load.iter().map(|f| f.abs()).sum();
    let force = norm_inf(&a.solution.multipliers).max(load).max(1e-300);
    let dl = max_diff(&a.solution.multipliers, &b.solution.multipliers) / force;
    (du, dl)
}

/// Agreement asked of two answers that both meet the KKT tolerance 1e-9: the brief's 1e-6 of
/// the largest displacement (three orders above the tolerance, for the conditioning of the seed
/// scenes' stiffness: E down to 1.2e-3 with ν = 0.34).
const AGREE: f64 = 1e-6;

#[test]
fn auto_falls_back_when_the_first_backend_fails_and_writes_the_second_answer() {
    let path = fixture("seed", "exp2b");
    let options = SolveOptions::default();
    // dual-pgs with one sweep cannot meet 1e-9 (it takes ~100 on exp2b: compare's table), so it
    // ends with max-iterations and clarabel must take over.
    let first = DualBackend::pgs(DualSettings {
        max_iter: 1,
        ..DualSettings::default()
    });
    let mut auto = AutoBackend::with_backends(
        vec![Box::new(first), Box::new(ClarabelBackend::default())],
        "test chain",
    );
    let outcome = solve_with(&path, &mut auto, &options);
    let record = auto.record().unwrap().clone();
    assert_eq!(record.attempts.len(), 2, "{record:?}");
    assert_eq!(record.attempts[0].backend, "dual-pgs");
    assert_eq!(record.attempts[0].status, Some(QpStatus::MaxIterations));
    assert_eq!(record.attempts[1].backend, "clarabel");
    assert_eq!(record.attempts[1].status, Some(QpStatus::Solved));
    assert_eq!(record.chosen.as_deref(), Some("clarabel"));
    assert_eq!(outcome.solution.status, QpStatus::Solved);
    assert_eq!(outcome.solution.backend, "auto");
    // The answer written is clarabel's own: the same deterministic solve of the same scaled QP,
    // so equal to round-off (1e-12 relative, far below any solver tolerance).
    let alone = solve_with(&path, &mut ClarabelBackend::default(), &options);
    let (du, dl) = agreement(&alone, &outcome);
    assert!(du <= 1e-12 && dl <= 1e-12, "Δu {du:e}, Δλ {dl:e}");

    // result.json lists both attempts.
    let dir = tempfile::tempdir().unwrap();
    let scene = run::load_scene(Some(&path)).unwrap();
    let mut outcome = outcome;
    record.annotate(&mut outcome.report);
    run::write_outputs(dir.path(), &scene, &outcome).unwrap();
    let json = result_json(dir.path());
    assert_eq!(json["backend"], "auto");
    assert_eq!(json["status"], "solved");
    assert_eq!(json["chosen"], "clarabel");
    assert_eq!(json["attempts"][0]["backend"], "dual-pgs");
    assert_eq!(json["attempts"][0]["status"], "max-iterations");
    assert_eq!(json["attempts"][1]["backend"], "clarabel");
    assert_eq!(json["attempts"][1]["status"], "solved");
    assert!(json["attempts"][1]["solve_s"].is_number());
    assert_eq!(json["attempts"].as_array().unwrap().len(), 2);
    assert!(json["reason"].as_str().unwrap().contains("fall-back"));
}

#[test]
fn an_erring_backend_hands_over_from_the_command_line_too() {
    // clarabel/dual refuses a body held by contact alone (no A⁻¹): an error, not a status, and
    // the chain goes on to clarabel, which solves it.
    let dir = tempfile::tempdir().unwrap();
    let scene = fixture("hard", "floating");
    let o = signorini(
        &[
            "solve",
            scene.to_str().unwrap(),
            "--chain",
            "clarabel/dual,clarabel",
            "--out",
            "res",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(err.contains("auto: clarabel/dual") && err.contains("auto: chose clarabel"));
    let json = result_json(&dir.path().join("res"));
    assert_eq!(json["backend"], "auto");
    assert_eq!(json["status"], "solved");
    assert_eq!(json["attempts"][0]["status"], "error");
    assert!(json["attempts"][0]["message"]
        .as_str()
        .unwrap()
        .contains("rigid-body"));
    assert_eq!(json["attempts"][1]["status"], "solved");
    assert_eq!(json["chosen"], "clarabel");
}

#[test]
fn auto_agrees_with_clarabel_on_the_seed_fixtures() {
    let options = SolveOptions::default();
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/seed");
    let mut names: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    names.sort();
    assert!(names.len() >= 10);
    for path in names {
        let auto = solve_with(&path, &mut AutoBackend::default(), &options);
        let clarabel = solve_with(&path, &mut ClarabelBackend::default(), &options);
        assert_eq!(auto.solution.status, QpStatus::Solved, "{path:?}");
        assert_eq!(clarabel.solution.status, QpStatus::Solved, "{path:?}");
        let (du, dl) = agreement(&clarabel, &auto);
        assert!(du <= AGREE, "{path:?}: Δu {du:e}");
        // λ: the same bound (the multipliers are as well determined as u on these scenes: every
        // contact row belongs to a node-to-segment pair with a non-degenerate segment).
        assert!(dl <= AGREE, "{path:?}: Δλ {dl:e}");
    }
}

#[test]
fn the_dual_form_gives_the_primal_forms_answer_on_exp2b() {
    let path = fixture("seed", "exp2b");
    let options = SolveOptions::default();
    for (primal, dual) in [
        (BackendKind::Clarabel, BackendKind::ClarabelDual),
        (BackendKind::Osqp, BackendKind::OsqpDual),
    ] {
        if !primal.available() {
            continue;
        }
        let p = solve_with(&path, make_backend(primal).unwrap().as_mut(), &options);
        let d = solve_with(&path, make_backend(dual).unwrap().as_mut(), &options);
        assert_eq!(p.solution.status, QpStatus::Solved, "{primal}");
        assert_eq!(d.solution.status, QpStatus::Solved, "{dual}");
        assert_eq!(d.solution.backend, dual.name());
        let (du, dl) = agreement(&p, &d);
        assert!(du <= AGREE && dl <= AGREE, "{dual}: Δu {du:e}, Δλ {dl:e}");
    }
}

#[test]
fn form_dual_on_a_floating_scene_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let scene = fixture("hard", "floating");
    let o = signorini(
        &[
            "solve",
            scene.to_str().unwrap(),
            "--backend",
            "clarabel",
            "--form",
            "dual",
            "--out",
            "res",
        ],
        dir.path(),
    );
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(
        err.contains("clarabel/dual") && err.contains("rigid-body") && err.contains("primal"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
    assert!(!dir.path().join("res").exists(), "nothing may be written");
    // A form the backend does not have is a usage error too.
    let o = signorini(
        &["solve", "--backend", "dual-pgs", "--form", "primal"],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("no primal form"), "{}", stderr(&o));
}

#[test]
fn a_tiny_time_limit_ends_the_chain_with_time_limit_and_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let o = signorini(
        &["solve", "--time-limit", "1e-9", "--out", "res"],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(!err.contains("panicked"), "{err}");
    let json = result_json(&dir.path().join("res"));
    assert_eq!(json["backend"], "auto");
    assert_eq!(json["status"], "time-limit");
}

/// A backend that sleeps `sleep` (or until its own time limit, if shorter), records the limit it
/// was given, and answers x = 0, λ = 0 with `status`.
struct Sleeper {
    name: &'static str,
    sleep: Duration,
    status: QpStatus,
    given: std::sync::Arc<std::sync::Mutex<Vec<Option<Duration>>>>,
}

impl QpBackend for Sleeper {
    fn name(&self) -> &'static str {
        self.name
    }
    fn solve_valid(
        &mut self,
        p: &signorini_core::qp::QpProblem,
        o: &SolveOptions,
    ) -> Result<signorini_core::qp::QpSolution, signorini_core::qp::QpError> {
        self.given.lock().unwrap().push(o.time_limit);
        let nap = o.time_limit.map_or(self.sleep, |t| t.min(self.sleep));
        std::thread::sleep(nap);
        let status = if o.time_limit.is_some_and(|t| t <= self.sleep) {
            QpStatus::TimeLimit
        } else {
            self.status
        };
        Ok(signorini_core::qp::QpSolution {
            x: vec![0.0; p.dofs()],
            multipliers: vec![0.0; p.rows()],
            status,
            iterations: 1,
            solve_time: nap,
            message: None,
        })
    }
}

#[test]
fn the_chain_shares_one_time_limit() {
    let path = fixture("seed", "exp2b");
    let limit = Duration::from_millis(400);
    let options = SolveOptions {
        time_limit: Some(limit),
        ..SolveOptions::default()
    };
    let given = std::sync::Arc::new(std::sync::Mutex::new(Vec::new()));
    let sleeper = |name, sleep_ms, status| -> Box<dyn QpBackend> {
        Box::new(Sleeper {
            name,
            sleep: Duration::from_millis(sleep_ms),
            status,
            given: given.clone(),
        })
    };
    // First 150 ms and an inaccurate answer, then one that would take 10 s: the second gets what
    // remains (≤ 250 ms), runs out, and the chain ends there with time-limit; the third never
    // runs.
    let mut auto = AutoBackend::with_backends(
        vec![
            sleeper("first", 150, QpStatus::Inaccurate),
            sleeper("second", 10_000, QpStatus::Solved),
            sleeper("third", 0, QpStatus::Solved),
        ],
        "test chain",
    );
    let outcome = solve_with(&path, &mut auto, &options);
    let record = auto.record().unwrap();
    assert_eq!(outcome.solution.status, QpStatus::TimeLimit, "{record:?}");
    assert_eq!(record.attempts.len(), 2, "{record:?}");
    let limits = given.lock().unwrap().clone();
    // The first gets the whole limit less the microseconds auto spent choosing.
    let first = limits[0].unwrap();
    assert!(
        first <= limit && first >= limit - Duration::from_millis(50),
        "{first:?}"
    );
    let second = limits[1].unwrap();
    assert!(
        second <= limit - Duration::from_millis(150),
        "the second attempt got {second:?}"
    );
    // The whole chain within the limit, plus scheduling slack (50 ms: a sleep overshoots by
    // well under a millisecond on an idle machine, a loaded 2-core one can add tens).
    let took = outcome.solution.solve_time;
    assert!(took <= limit + Duration::from_millis(50), "{took:?}");
}

/// What a member was handed: the residual scales in its options, and those of the problem it got.
type Handed = Option<(std::sync::Arc<ResidualScales>, ResidualScales)>;

/// A backend that records the residual scales its options carry and answers x = 0, λ = 0
/// `inaccurate` (so that the chain goes on to the next member).
struct ScalesRecorder(std::sync::Arc<std::sync::Mutex<Vec<Handed>>>);

impl QpBackend for ScalesRecorder {
    fn name(&self) -> &'static str {
        "recorder"
    }
    fn solve_valid(
        &mut self,
        p: &signorini_core::qp::QpProblem,
        o: &SolveOptions,
    ) -> Result<signorini_core::qp::QpSolution, signorini_core::qp::QpError> {
        let handed = o.scales.clone().map(|s| (s, ResidualScales::of(p)));
        self.0.lock().unwrap().push(handed);
        Ok(signorini_core::qp::QpSolution {
            x: vec![0.0; p.dofs()],
            multipliers: vec![0.0; p.rows()],
            status: QpStatus::Inaccurate,
            iterations: 1,
            solve_time: Duration::ZERO,
            message: None,
        })
    }
}

/// auto computes the residual scales once for its chain (a pass over A and B that cost pdas
/// a tenth of the floor on the partial strip, and was done by auto's check again) and hands
/// the same ones to every member: exactly those of the problem the member gets.
#[test]
fn every_member_of_the_chain_gets_the_chains_residual_scales() {
    let problem = signorini_core::qp::examples::two_rows_scaled(3.0).problem;
    let seen = std::sync::Arc::new(std::sync::Mutex::new(Vec::new()));
    let mut auto = AutoBackend::with_backends(
        vec![
            Box::new(ScalesRecorder(seen.clone())),
            Box::new(ScalesRecorder(seen.clone())),
        ],
        "test chain",
    );
    auto.solve(&problem, &SolveOptions::default()).unwrap();
    let seen = seen.lock().unwrap();
    assert_eq!(seen.len(), 2);
    let (first, own) = seen[0].as_ref().expect("the first member got no scales");
    let (second, _) = seen[1].as_ref().expect("the second member got no scales");
    assert!(std::sync::Arc::ptr_eq(first, second), "computed twice");
    assert_eq!(
        **first, *own,
        "not the scales of the problem the member got"
    );
}

/// A backend that refuses every problem for lack of memory.
struct Refuses(&'static str);

impl QpBackend for Refuses {
    fn name(&self) -> &'static str {
        self.0
    }
    fn solve_valid(
        &mut self,
        _: &signorini_core::qp::QpProblem,
        _: &SolveOptions,
    ) -> Result<signorini_core::qp::QpSolution, signorini_core::qp::QpError> {
        Err(signorini_core::qp::QpError::TooLarge {
            backend: self.0,
            what: "a test allocation".into(),
            needed: 1e6,
            available: 1.0,
        })
    }
}

#[test]
fn too_large_ends_the_chain_only_when_the_rest_would_need_as_much() {
    let scene = run::load_scene(Some(&fixture("seed", "exp2b"))).unwrap();
    let options = SolveOptions::default();
    // A dense dual refused for its m × m matrix: the sparse primal clarabel still runs.
    let mut auto = AutoBackend::with_backends(
        vec![
            Box::new(Refuses("dual-test")),
            Box::new(ClarabelBackend::default()),
        ],
        "test chain",
    );
    let outcome = run::solve_scene(&scene, &mut auto, &options, &MeshLimits::default()).unwrap();
    assert_eq!(outcome.solution.status, QpStatus::Solved);
    assert_eq!(auto.record().unwrap().attempts.len(), 2);
    // A sparse primal method refused for its factor: every later backend factors A too, so the
    // chain ends with the refusal (exit 3 from the command line), clarabel never runs.
    let mut auto = AutoBackend::with_backends(
        vec![
            Box::new(Refuses("primal-test")),
            Box::new(ClarabelBackend::default()),
        ],
        "test chain",
    );
    let error = run::solve_scene(&scene, &mut auto, &options, &MeshLimits::default()).unwrap_err();
    assert!(error.to_string().contains("a test allocation"), "{error}");
    assert_eq!(auto.record().unwrap().attempts.len(), 1);
}

#[test]
fn the_rule_orders_the_chain_from_the_features() {
    // The seed's geometry at ~200k DOFs (measured: n = 206 278, m = 135, 540 touched).
    let seed = Features {
        dofs: 206_278,
        rows: 135,
        touched: 540,
        kernel: 0,
        box_rows: 0,
        body_dofs: 103_139,
        body_interface: 135,
    };
    let p = plan(&seed);
    assert_eq!(p.chain.first(), Some(&BackendKind::DualSsn), "{p:?}");
    assert_eq!(p.chain.last(), Some(&BackendKind::Clarabel), "{p:?}");
    // A thin strip of length 1 (n = 2 594, m = 101, the strip's own 1 113 DOFs: 101/√1113 =
    // 3.0): long, no dual-ssn, osqp before clarabel when built in.
    let strip = Features {
        dofs: 2_594,
        rows: 101,
        touched: 402,
        kernel: 0,
        box_rows: 0,
        body_dofs: 1_113,
        body_interface: 101,
    };
    let p = plan(&strip);
    // pdas first; dual-ssn only as the last resort (slow there, but it solved every long
    // interface measured).
    assert_eq!(p.chain.first(), Some(&BackendKind::Pdas), "{p:?}");
    assert_eq!(p.chain.last(), Some(&BackendKind::DualSsn), "{p:?}");
    assert!(p.chain.contains(&BackendKind::Clarabel), "{p:?}");
    assert_eq!(
        p.chain.contains(&BackendKind::Osqp),
        BackendKind::Osqp.available()
    );
    assert!(p.reason.contains("long interface"), "{}", p.reason);
    // Short but too many rows for a dense dual: no dual-ssn either.
    let wide = Features {
        dofs: 4_000_000,
        rows: 1_500,
        touched: 3_000,
        kernel: 0,
        box_rows: 0,
        body_dofs: 2_000_000,
        body_interface: 1_500,
    };
    assert_ne!(plan(&wide).chain.first(), Some(&BackendKind::DualSsn));
    // Issue 21: a 5 × 0.02 strip on a 5 × 2 block (293 453 DOFs, m = 501, the strip's own
    // 5 555 DOFs).  m/√n of the whole model is 0.92 — short by the model's size, and dual-ssn
    // took 1.8–1.9× the floor there where pdas took 1.0–1.25×; against the strip it runs along
    // the interface is long: 501/√5555 = 6.7.
    let thick = Features {
        dofs: 293_453,
        rows: 501,
        touched: 1_503,
        kernel: 1,
        box_rows: 0,
        body_dofs: 5_555,
        body_interface: 501,
    };
    assert!(thick.length_ratio() > 6.0, "{}", thick.length_ratio());
    assert_eq!(plan(&thick).chain.first(), Some(&BackendKind::Pdas));
    // pdas joins the chain exactly when the build lists it among its backends.
    assert_eq!(
        plan(&seed).chain.contains(&BackendKind::Pdas),
        BackendKind::ALL.contains(&BackendKind::Pdas)
    );
    // Friction's box rows: only backends that solve them, dual-pgs first on a short interface,
    // pdas first on a long one.
    for (features, first) in [(seed, BackendKind::DualPgs), (strip, BackendKind::Pdas)] {
        // One tangential row per normal row: twice the rows, the same interface.
        let frictional = Features {
            rows: 2 * features.rows,
            box_rows: features.rows,
            ..features
        };
        assert_eq!(frictional.length_ratio(), features.length_ratio());
        let p = plan(&frictional);
        assert_eq!(p.chain.first(), Some(&first), "{p:?}");
        for kind in &p.chain {
            let backend = make_backend(*kind).unwrap();
            assert!(backend.supports(BlockKind::Box), "{p:?}: {kind:?}");
        }
        assert!(p.reason.contains("box rows"), "{}", p.reason);
    }
}

/// Issue 21: the Hertz cylinder (a = 0.05 under a 0.4-wide candidate arc, 311 rows on a cap of
/// 12 918 DOFs graded along the arc) scored ℓ = 311/√12918 = 2.74, "long", and auto sent it to
/// pdas, which took 7.27× the floor in 14 steps where dual-ssn took 2.44× (BENCHMARKS.md).  Its
/// interface touches first at a few rows around the apex and grows to a compact zone, so it is
/// short; thin strips laid flush on their foundation touch first along their whole length and
/// stay long (pdas first), a partial load on one included.  Features only, no solve.
#[test]
fn the_interface_that_touches_first_decides_long_or_short() {
    for (dir, name, first) in [
        ("accuracy", "hertz", BackendKind::DualSsn),
        ("hard", "strip-thin-clamped", BackendKind::Pdas),
        ("hard", "strip-thin-floating", BackendKind::Pdas),
        ("hard", "strip-thin-partial", BackendKind::Pdas),
        ("hard", "strip-thick-floating", BackendKind::Pdas),
    ] {
        let scene = run::load_scene(Some(&fixture(dir, name))).unwrap();
        let prepared = run::prepare(&scene, &MeshLimits::default()).unwrap();
        let qp = solve::ScaledQp::new(prepared.qp);
        let f = Features::of(&qp.problem);
        let p = plan(&f);
        assert_eq!(p.chain.first(), Some(&first), "{name}: {f:?} {}", p.reason);
        let all_rows = ContactBody::most_slender(&qp.problem).unwrap();
        if first == BackendKind::Pdas {
            // flush: every normal row touches first (ℓ 4.5–15.8 in `features`)
            assert_eq!(f.body_interface, all_rows.interface, "{name}");
            assert!(f.length_ratio() > 4.0, "{name}: {}", f.length_ratio());
        } else {
            // all 311 rows are long (2.74); the first touch is a few rows at the apex
            assert!(all_rows.slenderness() > 2.0, "{name}: {all_rows:?}");
            assert!(f.body_interface < 20, "{name}: {f:?}");
        }
    }
}

/// The rule's features of scenes (no solve): `SIGNORINI_MEASURE` (colon-separated paths), else
/// every fixture under fixtures/seed, fixtures/hard, fixtures/accuracy and fixtures/validation.
/// Prints m/√n of the whole model beside ℓ (the measure behind `auto::LONG_INTERFACE`'s numbers).
/// `cargo test --release -p signorini --test auto -- --ignored features --nocapture`
#[test]
#[ignore]
fn features() {
    let scenes: Vec<PathBuf> = match std::env::var("SIGNORINI_MEASURE") {
        Ok(list) => list.split(':').map(PathBuf::from).collect(),
        Err(_) => ["seed", "hard", "accuracy", "validation"]
            .iter()
            .flat_map(|dir| {
                let dir = common::repo(&format!("fixtures/{dir}"));
                std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path())
            })
            .filter(|p| p.extension().is_some_and(|e| e == "toml"))
            .collect(),
    };
    for path in scenes {
        let scene = run::load_scene(Some(&path)).unwrap();
        let prepared = run::prepare(&scene, &MeshLimits::default()).unwrap();
        let qp = solve::ScaledQp::new(prepared.qp);
        let f = Features::of(&qp.problem);
        let whole = (f.rows - f.box_rows) as f64 / (f.dofs as f64).sqrt();
        println!(
            "{:<36} n {:>8} m {:>6} body {:>8} DOFs, interface {:>6}: m/√n {whole:>6.2}, ℓ {:>6.2}, first {:?}",
            path.file_name().unwrap().to_string_lossy(),
            f.dofs,
            f.rows,
            f.body_dofs,
            f.body_interface,
            f.length_ratio(),
            plan(&f).chain.first()
        );
    }
}

/// Best time of repeated solves (at least three, more until 0.2 s are spent, at most 50; one
/// when a solve takes over 2 s) and the checked status.
fn timed(
    problem: &solve::ScaledQp,
    make: &dyn Fn() -> Box<dyn QpBackend>,
    options: &SolveOptions,
) -> (f64, String) {
    let mut best = f64::INFINITY;
    let mut verdict = String::new();
    let spent = Instant::now();
    for run in 0..50 {
        if run >= 3 && spent.elapsed() > Duration::from_millis(200) {
            break;
        }
        let mut backend = make();
        let t = Instant::now();
        let result = backend.solve(&problem.problem, options);
        let took = t.elapsed().as_secs_f64();
        best = best.min(took);
        verdict = match result {
            Ok(s) => {
                let r = signorini_core::qp::kkt_residuals(&problem.problem, &s.x, &s.multipliers);
                signorini_core::qp::checked_status(s.status, &r, options.tol)
                    .as_str()
                    .to_string()
            }
            Err(e) => format!("error ({e})"),
        };
        if took > 2.0 || verdict != "solved" {
            break;
        }
    }
    (best, verdict)
}

/// Timings behind auto's rule, the clarabel linear-solver default and the primal-vs-dual forms:
/// best of three solves of the scaled QP, as multiples of the floor (one factorisation + solve
/// of A, best of three).  Scenes from `SIGNORINI_MEASURE` (colon-separated paths), else exp2b
/// and exp3-both-h0.08; backends from `SIGNORINI_BACKENDS` (comma-separated; `clarabel[faer]`
/// etc. pick clarabel's linear solver), else all.  Time limit per solve:
/// `SIGNORINI_LIMIT` seconds (default 60).
/// `cargo test --release -p signorini --features clarabel-faer --test auto -- --ignored measure --nocapture`
#[test]
#[ignore]
fn measure() {
    let scenes: Vec<PathBuf> = match std::env::var("SIGNORINI_MEASURE") {
        Ok(list) => list.split(':').map(PathBuf::from).collect(),
        Err(_) => vec![fixture("seed", "exp2b"), fixture("seed", "exp3-both-h0.08")],
    };
    let names: Vec<String> = match std::env::var("SIGNORINI_BACKENDS") {
        Ok(list) => list.split(',').map(str::to_string).collect(),
        Err(_) => [
            "auto",
            "dual-ssn",
            "dual-pgs",
            "clarabel[qdldl]",
            "clarabel[faer]",
            "clarabel",
            "clarabel/dual",
            "osqp",
            "osqp/dual",
        ]
        .map(str::to_string)
        .to_vec(),
    };
    let limit: f64 = std::env::var("SIGNORINI_LIMIT")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(60.0);
    let options = SolveOptions {
        time_limit: Some(Duration::from_secs_f64(limit)),
        ..SolveOptions::default()
    };
    for path in scenes {
        let scene = run::load_scene(Some(&path)).unwrap();
        let prepared = run::prepare(&scene, &MeshLimits::default()).unwrap();
        let qp = solve::ScaledQp::new(prepared.qp);
        let f = Features::of(&qp.problem);
        let floor = (0..3)
            .map(|_| solve::floor_time(&qp.problem).unwrap().as_secs_f64())
            .fold(f64::INFINITY, f64::min);
        println!("{}: {f:?}, floor {floor:.4} s", path.display());
        let mut rows = Vec::new();
        for name in &names {
            let make: Box<dyn Fn() -> Box<dyn QpBackend>> = match name.as_str() {
                "clarabel[qdldl]" | "clarabel[faer]" | "clarabel[auto]" => {
                    let solver = match name.as_str() {
                        "clarabel[qdldl]" => DirectSolver::Qdldl,
                        "clarabel[faer]" => DirectSolver::Faer,
                        _ => DirectSolver::Auto,
                    };
                    Box::new(move || {
                        Box::new(ClarabelBackend::new(ClarabelSettings {
                            direct_solver: solver,
                            ..ClarabelSettings::default()
                        })) as Box<dyn QpBackend>
                    })
                }
                other => {
                    let kind: BackendKind = other.parse().unwrap();
                    if !kind.available() {
                        continue;
                    }
                    Box::new(move || make_backend(kind).unwrap())
                }
            };
            let (t, status) = timed(&qp, make.as_ref(), &options);
            println!(
                "  {name:<16} {status:<17} {t:>9.4} s {:>8.2}× floor",
                t / floor
            );
            rows.push((name.clone(), t, status));
        }
        let fastest = rows
            .iter()
            .filter(|r| r.2 == "solved" && r.0 != "auto")
            .map(|r| r.1)
            .fold(f64::INFINITY, f64::min);
        if let Some(auto) = rows.iter().find(|r| r.0 == "auto") {
            println!(
                "  auto ÷ fastest other solved backend: {:.2}",
                auto.1 / fastest
            );
        }
    }
}

#[test]
fn coulomb_runs_pdas_s_newton_and_falls_back_to_the_fixed_point_when_it_does_not_solve() {
    // fixtures/hard/friction-slide: a block dragged to full slip, T = μN exactly.
    let path = fixture("hard", "friction-slide");
    let options = SolveOptions::default();
    // A short interface of a block held sideways by friction alone (A has a rigid mode): the
    // rule runs pdas's Newton (issue 41: the fixed point through dual-pgs took 10× as long).
    let mut auto = AutoBackend::default();
    let rule = solve_with(&path, &mut auto, &options);
    assert_eq!(rule.solution.status, QpStatus::Solved);
    let run = rule.solution.coulomb.unwrap();
    assert_eq!(run.method, signorini_core::qp::CoulombMethod::Newton);
    assert_eq!(auto.record().unwrap().chosen.as_deref(), Some("pdas"));
    // A given chain with pdas first: its Newton.
    let mut auto = AutoBackend::with_kinds(vec![BackendKind::Pdas], "test chain");
    let newton = solve_with(&path, &mut auto, &options);
    assert_eq!(newton.solution.status, QpStatus::Solved);
    let run = newton.solution.coulomb.unwrap();
    assert_eq!(run.method, signorini_core::qp::CoulombMethod::Newton);
    assert_eq!(auto.record().unwrap().chosen.as_deref(), Some("pdas"));
    // A pdas allowed one active-set step cannot settle the sets (the slide needs three): the
    // core then runs the fixed point through the same chain, where dual-pgs solves each
    // Tresca problem — and the answer is the Newton one's (both meet the tolerance 1e-9).
    let short = signorini_pdas::PdasBackend::new(signorini_pdas::PdasSettings {
        max_iter: 1,
        ..signorini_pdas::PdasSettings::default()
    });
    let mut auto = AutoBackend::with_backends(
        vec![
            Box::new(short),
            Box::new(DualBackend::pgs(DualSettings::default())),
        ],
        "test chain",
    );
    let fallback = solve_with(&path, &mut auto, &options);
    assert_eq!(fallback.solution.status, QpStatus::Solved);
    let run = fallback.solution.coulomb.unwrap();
    assert_eq!(run.method, signorini_core::qp::CoulombMethod::FixedPoint);
    let message = fallback.solution.message.clone().unwrap_or_default();
    assert!(
        message.contains("own Coulomb method: max-iterations; then the fixed point"),
        "{message}"
    );
    for other in [&rule, &fallback] {
        let (du, dl) = agreement(&newton, other);
        assert!(du <= AGREE && dl <= AGREE, "Δu {du:e}, Δλ {dl:e}");
    }
}

/// From the command line with the default backend: a thin strip pressed onto a foundation 25
/// times thicker (`scripts/strip-scene.sh --length 1 --foundation-layers 50`: 16 013 DOFs,
/// m = 101, m/√n = 0.80) is a long interface for the strip, so auto runs pdas first — before
/// the rule looked at the strip itself, the foundation's DOFs diluted m/√n below the threshold
/// and dual-ssn ran first.
#[test]
fn a_thick_foundation_does_not_hide_a_long_interface_from_the_default_backend() {
    let dir = tempfile::tempdir().unwrap();
    let scene = Command::new("sh")
        .arg(common::repo("scripts/strip-scene.sh"))
        .args(["--length", "1", "--foundation-layers", "50"])
        .output()
        .unwrap();
    assert!(scene.status.success(), "{}", stderr(&scene));
    std::fs::write(dir.path().join("strip.toml"), &scene.stdout).unwrap();
    common::succeeded(&signorini(
        &["solve", "strip.toml", "--out", "out"],
        dir.path(),
    ));
    let json = result_json(&dir.path().join("out"));
    assert_eq!(json["status"], "solved");
    assert_eq!(json["backend"], "auto");
    assert_eq!(json["attempts"][0]["backend"], "pdas", "{json:#}");
    assert_eq!(json["chosen"], "pdas");
    let reason = json["reason"].as_str().unwrap();
    assert!(reason.contains("long interface"), "{reason}");
}

#[test]
fn coulomb_goes_to_newton_on_long_interfaces_and_large_duals_only() {
    // The rule's features as on the Coulomb strip of BENCHMARKS.md (51 575 DOFs, 2 001 normal
    // and 2 001 box rows: m/√n = 8.8) and on the Cattaneo cylinder (61 886 DOFs, 125 + 125
    // rows: m/√n = 0.5), and a short interface whose dual is too large to form densely.
    let strip = Features {
        dofs: 51_575,
        rows: 4_002,
        touched: 12_000,
        kernel: 2,
        box_rows: 2_001,
        body_dofs: 22_225,
        body_interface: 2_001,
    };
    let cylinder = Features {
        dofs: 61_886,
        rows: 250,
        touched: 750,
        kernel: 0,
        box_rows: 125,
        body_dofs: 28_236,
        body_interface: 125,
    };
    let wide = Features {
        dofs: 4_000_000,
        rows: 2_400,
        touched: 7_200,
        kernel: 0,
        box_rows: 1_200,
        body_dofs: 2_000_000,
        body_interface: 1_200,
    };
    // The floating block of fixtures/hard/friction-float-coulomb: a short interface whose
    // block is held by contact alone (three rigid modes).
    let floating = Features {
        dofs: 386,
        rows: 10,
        touched: 22,
        kernel: 3,
        box_rows: 5,
        body_dofs: 130,
        body_interface: 5,
    };
    assert!(signorini::auto::coulomb_by_newton(&strip));
    assert!(!signorini::auto::coulomb_by_newton(&cylinder));
    assert!(signorini::auto::coulomb_by_newton(&wide));
    assert!(signorini::auto::coulomb_by_newton(&floating));
}

#[test]
fn friction_on_bodies_held_by_contact_alone_runs_the_active_sets_before_pgs() {
    // Issue 41: on a floating block or cap held sideways by friction, dual-pgs took 10–200× the
    // floor or did not converge, the active sets 2× (BENCHMARKS.md, "Friction on ordinary
    // scenes"); the Cattaneo cylinder (no rigid mode) keeps dual-pgs first.
    let floating = Features {
        dofs: 1_380,
        rows: 30,
        touched: 48,
        kernel: 3,
        box_rows: 15,
        body_dofs: 396,
        body_interface: 1,
    };
    let plan = signorini::auto::plan(&floating);
    let want: Vec<BackendKind> = signorini::auto::FRICTION_FLOATING_CHAIN
        .into_iter()
        .filter(|k| k.available())
        .collect();
    assert_eq!(plan.chain, want, "{}", plan.reason);
    assert_eq!(plan.chain[0], BackendKind::DualSsn);
    assert!(!plan.chain.contains(&BackendKind::DualPgs));
    assert!(
        plan.reason.contains("held by contact alone"),
        "{}",
        plan.reason
    );
    let cylinder = Features {
        kernel: 0,
        ..floating
    };
    assert_eq!(
        signorini::auto::plan(&cylinder).chain[0],
        BackendKind::DualPgs
    );
}
