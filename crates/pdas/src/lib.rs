//! Primal–dual active-set QP backend of signorini on the sparse primal KKT system.
//!
//! (Skeleton: the method is being written; `solve` reports that it is not available yet.)

use signorini_core::qp::{QpBackend, QpError, QpProblem, QpSolution, SolveOptions};

/// The primal–dual active-set backend (name `"pdas"`).
#[derive(Debug, Clone, Default)]
pub struct PdasBackend {
    _settings: (),
}

impl QpBackend for PdasBackend {
    fn name(&self) -> &'static str {
        "pdas"
    }

    fn solve(
        &mut self,
        _problem: &QpProblem,
        _options: &SolveOptions,
    ) -> Result<QpSolution, QpError> {
        Err(QpError::Backend {
            backend: "pdas",
            reason: "not implemented yet".to_string(),
        })
    }
}
