//! What became of a solve, and the status the program reports after its own residual check.

use serde::Serialize;

use super::residuals::KktResiduals;

/// What became of a solve.  Not converging is data, not an error.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum QpStatus {
    /// The KKT residuals meet the requested tolerance.
    Solved,
    /// The backend stopped but the residuals miss the tolerance.
    Inaccurate,
    /// The iteration limit was reached first.
    MaxIterations,
    /// The time limit was reached first.
    TimeLimit,
    /// No x satisfies B x ≤ g.
    PrimalInfeasible,
    /// The objective is unbounded below (e.g. a floating body pushed away from contact).
    DualInfeasible,
    /// A factorisation or step broke down, or the answer held NaN.
    NumericalError,
    /// The program's verdict only (no backend gives it): the QP is solved, but in the deformed
    /// configuration a slave node ends inside its master beyond what the small-displacement
    /// contact model allows (a node without a row that the master moves over, or one that slid
    /// past its segment).
    DeformedOverlap,
}

impl QpStatus {
    /// Every status, in the order of the variants (and of docs/scene.md's table).
    pub const ALL: [QpStatus; 8] = [
        QpStatus::Solved,
        QpStatus::Inaccurate,
        QpStatus::MaxIterations,
        QpStatus::TimeLimit,
        QpStatus::PrimalInfeasible,
        QpStatus::DualInfeasible,
        QpStatus::NumericalError,
        QpStatus::DeformedOverlap,
    ];

    /// The word used in reports (`"solved"`, `"max-iterations"`, …).
    pub fn as_str(self) -> &'static str {
        match self {
            QpStatus::Solved => "solved",
            QpStatus::Inaccurate => "inaccurate",
            QpStatus::MaxIterations => "max-iterations",
            QpStatus::TimeLimit => "time-limit",
            QpStatus::PrimalInfeasible => "primal-infeasible",
            QpStatus::DualInfeasible => "dual-infeasible",
            QpStatus::NumericalError => "numerical-error",
            QpStatus::DeformedOverlap => "deformed-overlap",
        }
    }
}

impl std::fmt::Display for QpStatus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// The status to report: a backend's `Solved` (or `Inaccurate`) stands as `Solved` only if the
/// residuals meet `tol`, else `Inaccurate`, or `NumericalError` when they are not finite.  Any
/// other verdict (limits, infeasibility certificates) is kept as the backend gave it.
pub fn checked_status(reported: QpStatus, residuals: &KktResiduals, tol: f64) -> QpStatus {
    match reported {
        QpStatus::Solved | QpStatus::Inaccurate if residuals.worst().is_infinite() => {
            QpStatus::NumericalError
        }
        QpStatus::Solved | QpStatus::Inaccurate if residuals.meet(tol) => QpStatus::Solved,
        QpStatus::Solved | QpStatus::Inaccurate => QpStatus::Inaccurate,
        other => other,
    }
}
