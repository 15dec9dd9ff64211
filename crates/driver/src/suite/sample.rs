//! Hand-built suite reports for the unit tests of what presents them (JUnit, the performance
//! profile): one place that knows every field.

use signorini_core::qp::KktResiduals;

use super::report::{CaseReport, CaseRun, Figures, SuiteReport, Verdict};

/// The floor of every sample case, seconds.
pub(crate) const FLOOR_S: f64 = 0.01;

/// A run of `backend` that ended with `status` in `solve_s` seconds, checked as `verdict`.
pub(crate) fn run(backend: &str, status: &str, solve_s: f64, verdict: Verdict) -> CaseRun {
    CaseRun {
        backend: backend.to_string(),
        status: status.to_string(),
        backend_status: status.to_string(),
        iterations: 7,
        solve_s,
        ratio_to_floor: solve_s / FLOOR_S,
        figures: Figures::default(),
        residuals: KktResiduals::default(),
        verdict,
        notes: Vec::new(),
        message: None,
    }
}

/// A case `name` (scene `suite/NAME.toml`, no expectation file) with `runs`.
pub(crate) fn case(name: &str, runs: Vec<CaseRun>) -> CaseReport {
    CaseReport {
        name: name.to_string(),
        scene: format!("suite/{name}.toml"),
        sha256: String::new(),
        title: String::new(),
        dofs: 10,
        constraints: 2,
        load: 1.0,
        floor_s: FLOOR_S,
        expectation: None,
        error: None,
        runs,
    }
}

/// A suite report of `cases` run by `backends` from `dir` at tol 1e-8, its summary filled in.
pub(crate) fn report(
    dir: &str,
    backends: Vec<String>,
    cases: Vec<CaseReport>,
    time_limit_s: Option<f64>,
) -> SuiteReport {
    SuiteReport {
        provenance: None,
        repeat: 1,
        baseline: None,
        dir: dir.to_string(),
        tolerance: 1e-8,
        time_limit_s,
        summary: super::summary::summarise(&backends, &cases, time_limit_s),
        backends,
        cases,
    }
}
