//! [`PdasBackend`]: the `QpBackend` that runs the active-set iteration.

use std::time::Instant;

use signorini_qp::{
    BlockKind, CoulombRows, QpBackend, QpError, QpProblem, QpSolution, QpStatus, SolveOptions,
};

use crate::active_set::{ActiveSet, Outcome, SetupError};
use crate::kernel::{check_kernel, unrestrained_mode};
use crate::settings::PdasSettings;

/// The primal–dual active-set backend (name `"pdas"`): semismooth Newton on the sparse primal
/// KKT system with one symbolic LDLᵀ analysis for every active set (see the
/// [crate documentation](crate)).
///
/// # Example
/// ```
/// use signorini_qp::{checked_status, kkt_residuals, QpBackend, QpProblem, QpStatus,
///     SolveOptions};
/// use signorini_pdas::PdasBackend;
/// use sprs::TriMat;
///
/// // min x² − 4x  s.t.  x ≤ 1   →   x = 1, λ = 2.
/// let mut a = TriMat::new((1, 1));
/// a.add_triplet(0, 0, 2.0);
/// let mut b = TriMat::new((1, 1));
/// b.add_triplet(0, 0, 1.0);
/// let qp = QpProblem::try_new(a.to_csc(), vec![4.0], b.to_csc(), vec![1.0])?;
/// let options = SolveOptions::default();
/// let sol = PdasBackend::default().solve(&qp, &options)?;
/// let r = kkt_residuals(&qp, &sol.x, &sol.multipliers);
/// assert_eq!(checked_status(sol.status, &r, options.tol), QpStatus::Solved);
/// assert!((sol.x[0] - 1.0).abs() < 1e-12 && (sol.multipliers[0] - 2.0).abs() < 1e-12);
/// # Ok::<(), signorini_qp::QpError>(())
/// ```
#[derive(Debug, Clone, Default)]
pub struct PdasBackend {
    /// The settings in use.
    pub settings: PdasSettings,
}

impl PdasBackend {
    /// A backend with `settings`.
    pub fn new(settings: PdasSettings) -> Self {
        Self { settings }
    }

    fn run(
        &self,
        problem: &QpProblem,
        options: &SolveOptions,
        start: Instant,
        coulomb: Option<&CoulombRows>,
    ) -> Result<Outcome, QpError> {
        if let Err(e) = check_kernel(problem) {
            return Ok(failure(problem, QpStatus::NumericalError, e.to_string()));
        }
        if let Some(j) = unrestrained_mode(problem) {
            return Ok(failure(
                problem,
                QpStatus::DualInfeasible,
                format!("kernel vector {j} (a rigid motion) is not held by any contact row but the load drives it: the objective is unbounded below"),
            ));
        }
        let mut method = match ActiveSet::new(problem, &self.settings, options, start, coulomb) {
            Ok(method) => method,
            Err(SetupError::TooLarge(e)) => return Err(e),
            Err(SetupError::Pdas(e)) => {
                return Ok(failure(problem, QpStatus::NumericalError, e.to_string()))
            }
        };
        Ok(method.run())
    }
}

impl QpBackend for PdasBackend {
    fn name(&self) -> &'static str {
        "pdas"
    }

    /// One-sided rows and friction's box rows (sticking rows active, slipping rows at ±s).
    fn supports(&self, _kind: BlockKind) -> bool {
        true
    }

    fn solve_valid(
        &mut self,
        problem: &QpProblem,
        options: &SolveOptions,
    ) -> Result<QpSolution, QpError> {
        self.solve_with(problem, None, options)
    }

    /// Coulomb's conditions by the same semismooth Newton iteration: a slipping row's
    /// multiplier is tied to its normal row's, λₜ = ±μ λₙ (see the crate documentation).
    fn solves_coulomb(&self, _problem: &QpProblem) -> bool {
        true
    }

    fn solve_coulomb_valid(
        &mut self,
        problem: &QpProblem,
        coulomb: &CoulombRows,
        options: &SolveOptions,
    ) -> Result<QpSolution, QpError> {
        self.solve_with(problem, Some(coulomb), options)
    }
}

impl PdasBackend {
    /// The iteration on `problem`, Coulomb's rows tied to their normal rows when given.
    fn solve_with(
        &self,
        problem: &QpProblem,
        coulomb: Option<&CoulombRows>,
        options: &SolveOptions,
    ) -> Result<QpSolution, QpError> {
        let start = Instant::now();
        self.settings.validate().map_err(|e| QpError::Backend {
            backend: "pdas",
            reason: e.to_string(),
        })?;
        let outcome = self.run(problem, options, start, coulomb)?;
        let solution = QpSolution {
            x: outcome.x,
            multipliers: outcome.multipliers,
            status: outcome.status,
            iterations: outcome.iterations,
            solve_time: start.elapsed(),
            message: Some(outcome.message),
        };
        if options.verbose {
            eprintln!(
                "pdas: {} after {} iterations ({})",
                solution.status,
                solution.iterations,
                solution.message.as_deref().unwrap_or("")
            );
        }
        Ok(solution)
    }
}

/// A finite (all-zero) answer with a non-solved status.
fn failure(problem: &QpProblem, status: QpStatus, message: String) -> Outcome {
    Outcome {
        x: vec![0.0; problem.dofs()],
        multipliers: vec![0.0; problem.rows()],
        status,
        iterations: 0,
        message,
    }
}
