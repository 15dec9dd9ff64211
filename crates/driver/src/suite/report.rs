//! What a suite run measured and concluded: the content of `suite.json`.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use signorini_core::qp::KktResiduals;

/// How one backend's answer on one case compares with the case's expectation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Verdict {
    /// Solved, and every figure within its tolerance of the expectation.
    Pass,
    /// A regression: not solved where a solve was expected, a figure outside its tolerance, or
    /// `solved` on a scene expected to have no solution.
    Fail,
    /// Not solved, as the expectation says this backend does not (not a regression).
    ExpectedFailure,
    /// Solved, with every figure within tolerance, though the expectation says this backend
    /// fails: reported (the expectation wants refreshing with `--bless`), not a regression.
    UnexpectedPass,
    /// The case has no expectation file: nothing was checked.
    Unchecked,
}

impl Verdict {
    /// The verdict's name as written in `suite.json` and `suite.csv`.
    pub fn as_str(self) -> &'static str {
        match self {
            Verdict::Pass => "pass",
            Verdict::Fail => "fail",
            Verdict::ExpectedFailure => "expected-failure",
            Verdict::UnexpectedPass => "unexpected-pass",
            Verdict::Unchecked => "unchecked",
        }
    }
}

/// The forces a contact pair transmits: normal, and for a frictional pair tangential.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PairForce {
    /// The pair's body names, as in the scene.
    pub bodies: [String; 2],
    /// Sum of the pair's multipliers (the scene's force units).
    pub normal_force: f64,
    /// Frictional pairs only: the sum of the tangential multipliers, along each row's tangent
    /// (result.json's `tangential_force`).  Absent for a frictionless pair, and in an
    /// expectation blessed before it was recorded (then not checked).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tangential_force: Option<f64>,
}

/// A probe's displacement.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ProbeValue {
    /// The probe's name, as in the scene.
    pub name: String,
    /// Interpolated displacement `[ux, uy]`.
    pub displacement: [f64; 2],
}

/// The figures of an answer that an expectation holds and a run is checked against.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Figures {
    /// ½uᵀAu − fᵀu.
    pub objective: f64,
    /// Largest nodal displacement magnitude over all bodies.
    pub max_displacement: f64,
    /// Per contact pair, in the scene's order.
    pub contact_forces: Vec<PairForce>,
    /// Per probe, in the scene's order.
    pub probes: Vec<ProbeValue>,
}

/// One backend on one case.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct CaseRun {
    /// Backend name (`cholesky` for a case without contact rows: one linear solve).
    pub backend: String,
    /// Core-checked status (`solved`, `inaccurate`, …, or `error` when the backend could not
    /// run on the problem).
    pub status: String,
    /// The backend's own verdict before the core's check.
    pub backend_status: String,
    /// Backend iterations.
    pub iterations: usize,
    /// Solve wall-clock time, seconds (NaN, written null, when the backend could not run).
    pub solve_s: f64,
    /// `solve_s` ÷ the case's floor.
    pub ratio_to_floor: f64,
    /// The answer's figures (NaN where unmeasured).
    pub figures: Figures,
    /// Core-computed residuals.
    pub residuals: KktResiduals,
    /// The check against the expectation.
    pub verdict: Verdict,
    /// What broke (for `fail`), or what is worth knowing (a failure's status changed, an
    /// unexpected pass): one sentence each, the figure measured and expected.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub notes: Vec<String>,
    /// The backend's message, if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub message: Option<String>,
}

impl CaseRun {
    /// Whether the run answered correctly: verdict `pass` or `unexpected-pass` (`solved` within
    /// tolerance, or — on a scene without a solution — a non-solved status), or, without an
    /// expectation to check against, `solved`.  The success rate and the performance profile
    /// count these.
    pub fn correct(&self) -> bool {
        match self.verdict {
            Verdict::Pass | Verdict::UnexpectedPass => true,
            Verdict::Unchecked => self.status == "solved",
            Verdict::Fail | Verdict::ExpectedFailure => false,
        }
    }
}

/// One scene of the suite.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct CaseReport {
    /// The case's name: the scene's path relative to the suite directory, without `.toml`
    /// (`exp1`, `strips/thin`).
    pub name: String,
    /// The scene file's path as given.
    pub scene: String,
    /// SHA-256 of the scene file's bytes.
    pub sha256: String,
    /// The scene's title (empty when it could not be read).
    pub title: String,
    /// Free DOFs.
    pub dofs: usize,
    /// Contact rows.
    pub constraints: usize,
    /// The problem's load Σ|fᵢ| (free DOFs): the floor of a pair force's scale in the check.
    pub load: f64,
    /// One unconstrained factorisation + solve of A, seconds (median of three; NaN when the
    /// case could not be prepared).
    pub floor_s: f64,
    /// The expectation file checked against, when there is one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub expectation: Option<String>,
    /// Why the case could not be run at all (an unreadable scene, a mesh refused): a regression
    /// of the whole case.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// One per backend, in the order asked for; a single `cholesky` run when the case has no
    /// contact row.
    pub runs: Vec<CaseRun>,
}

impl CaseReport {
    /// True when the case regressed: it could not run, or a run's verdict is [`Verdict::Fail`].
    pub fn regressed(&self) -> bool {
        self.error.is_some() || self.runs.iter().any(|r| r.verdict == Verdict::Fail)
    }
}

/// One backend over the whole suite, as qpbenchmark summarises a solver.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct BackendSummary {
    /// Backend name.
    pub backend: String,
    /// Cases counted: every case where backends run, a case that could not run at all
    /// included (a failure of every backend); cases without contact rows, where no backend
    /// runs, are not counted (see [`crate::suite::summary`]).
    pub cases: usize,
    /// Cases answered correctly: `solved` with every figure within tolerance, or a non-solved
    /// status on a scene expected to have no solution (see [`crate::suite::summary`]).
    pub correct: usize,
    /// `correct` ÷ `cases` (NaN when no case).
    pub success_rate: f64,
    /// Runs whose verdict is [`Verdict::Fail`].
    pub regressions: usize,
    /// Runs whose verdict is [`Verdict::ExpectedFailure`].
    pub expected_failures: usize,
    /// Runs whose verdict is [`Verdict::UnexpectedPass`].
    pub unexpected_passes: usize,
    /// Shifted geometric mean of the solve time, seconds, shift 10 ms; a case the backend did
    /// not answer correctly, or that could not run, counts at the time limit (see
    /// [`crate::suite::summary`]).
    pub sgm_time_s: f64,
    /// The same of time ÷ floor, shift 1 (one floor), over the cases with a floor (a case
    /// that could not run has none).
    pub sgm_ratio: f64,
    /// `sgm_time_s` ÷ the smallest `sgm_time_s` of the suite's backends (1 for the best).
    pub sgm_time_relative: f64,
}

/// `suite.json`.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct SuiteReport {
    /// Where the run can be traced to: program version, settings, cores.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub provenance: Option<signorini_core::report::Provenance>,
    /// The suite directory as given.
    pub dir: String,
    /// Relative KKT tolerance every backend was asked to meet.
    pub tolerance: f64,
    /// Seconds each backend could take per case (null: none).
    pub time_limit_s: Option<f64>,
    /// Solves timed per backend and case (their median is reported; only solves under a second
    /// are repeated).
    pub repeat: usize,
    /// The backends, in the order run.
    pub backends: Vec<String>,
    /// One per scene, sorted by name.
    pub cases: Vec<CaseReport>,
    /// One per backend, in the order of `backends`.
    pub summary: Vec<BackendSummary>,
    /// The comparison with an earlier run (`--baseline`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub baseline: Option<super::changes::BaselineReport>,
}

impl SuiteReport {
    /// The names of the cases that regressed, in order.
    pub fn regressions(&self) -> Vec<&str> {
        self.cases
            .iter()
            .filter(|c| c.regressed())
            .map(|c| c.name.as_str())
            .collect()
    }
}
