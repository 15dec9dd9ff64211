//! [`DualBackend`]: the `QpBackend` that runs a dual method.

use std::time::Instant;

use signorini_qp::{
    kkt_residuals, norm_inf, BlockKind, QpBackend, QpError, QpProblem, QpSolution, QpStatus,
    SolveOptions,
};

use crate::dual::{DualData, Outcome};
use crate::error::DualError;
use crate::kernel::undeclared_unstiff_unknowns;
use crate::methods::{pgs, ssn, uzawa};
use crate::monitor::Monitor;
use crate::settings::{Condensation, DualMethod, DualSettings};

/// The dual QP backend: condenses the contact problem onto the multipliers and runs projected
/// Gauss–Seidel, Uzawa or the active-set method on it (see the [crate documentation](crate)).
///
/// # Example
/// ```
/// use signorini_qp::{checked_status, kkt_residuals, QpBackend, QpProblem, QpStatus,
///     SolveOptions};
/// use signorini_dual::{DualBackend, DualSettings};
/// use sprs::TriMat;
///
/// // min x² − 4x  s.t.  x ≤ 1   →   x = 1, λ = 2.
/// let mut a = TriMat::new((1, 1));
/// a.add_triplet(0, 0, 2.0);
/// let mut b = TriMat::new((1, 1));
/// b.add_triplet(0, 0, 1.0);
/// let qp = QpProblem::try_new(a.to_csc(), vec![4.0], b.to_csc(), vec![1.0])?;
/// let options = SolveOptions::default();
/// for mut backend in [DualBackend::pgs(DualSettings::default()),
///                     DualBackend::uzawa(DualSettings::default())] {
///     let sol = backend.solve(&qp, &options)?;
///     let r = kkt_residuals(&qp, &sol.x, &sol.multipliers);
///     assert_eq!(checked_status(sol.status, &r, options.tol), QpStatus::Solved);
///     assert!((sol.x[0] - 1.0).abs() < 1e-8 && (sol.multipliers[0] - 2.0).abs() < 1e-8);
/// }
/// # Ok::<(), signorini_qp::QpError>(())
/// ```
#[derive(Debug, Clone)]
pub struct DualBackend {
    settings: DualSettings,
}

impl DualBackend {
    /// A backend running `settings.method`.
    pub fn new(settings: DualSettings) -> Self {
        Self { settings }
    }

    /// Projected Gauss–Seidel on the condensed dual (name `"dual-pgs"`).
    pub fn pgs(settings: DualSettings) -> Self {
        Self::with_method(settings, DualMethod::ProjectedGaussSeidel)
    }

    /// (Accelerated) Uzawa, one solve per step (name `"dual-uzawa"`).
    pub fn uzawa(settings: DualSettings) -> Self {
        Self::with_method(settings, DualMethod::Uzawa)
    }

    /// Primal–dual active set / semismooth Newton on the condensed dual (name `"dual-ssn"`).
    pub fn active_set(settings: DualSettings) -> Self {
        Self::with_method(settings, DualMethod::ActiveSet)
    }

    fn with_method(mut settings: DualSettings, method: DualMethod) -> Self {
        settings.method = method;
        Self { settings }
    }

    /// The settings in use.
    pub fn settings(&self) -> &DualSettings {
        &self.settings
    }

    fn run(
        &self,
        problem: &QpProblem,
        options: &SolveOptions,
        start: Instant,
    ) -> Result<Outcome, QpError> {
        refuse_unstiff(problem, self.name())?;
        let contact_last = self.settings.method != DualMethod::Uzawa
            && self.settings.condensation == Condensation::TrailingBlock
            && problem.rows() > 0;
        let mut data = match DualData::new(problem, contact_last, self.name()) {
            Ok(data) => data,
            Err(e) => return verdict(problem, e),
        };
        if let Some(j) = data.modes.unrestrained_mode(norm_inf(&problem.load)) {
            return Ok(failure(
                problem,
                QpStatus::DualInfeasible,
                format!("kernel vector {j} (a rigid motion) is not held by any contact row but the load drives it: the objective is unbounded below"),
            ));
        }
        if problem.rows() == 0 {
            return Ok(plain_solve(&data, options.tol));
        }
        let mut monitor = Monitor::new(problem, options, &self.settings, start);
        let result = match self.settings.method {
            DualMethod::ProjectedGaussSeidel => pgs::solve(&mut data, &self.settings, &mut monitor),
            DualMethod::Uzawa => uzawa::solve(&mut data, &self.settings, &mut monitor),
            DualMethod::ActiveSet => ssn::solve(&mut data, &self.settings, &mut monitor),
        };
        let factor = data.inverse.describe();
        match result {
            Ok(mut outcome) => {
                outcome.message = format!("{}; {factor}", outcome.message);
                if outcome.status != QpStatus::Solved {
                    // Why a dual method may not reach the tolerance: the condensed dual inherits
                    // A's conditioning, which the factor's smallest pivot ratio bounds (a thin
                    // strip held at one point is a cantilever: 1e-10 and below).
                    outcome.message = format!(
                        "{}; A's smallest Cholesky pivot ratio minⱼ Lⱼⱼ²/Aⱼⱼ = {:.1e}",
                        outcome.message,
                        data.inverse.factor().min_pivot_ratio()
                    );
                }
                Ok(outcome)
            }
            Err(e) => verdict(problem, e),
        }
    }
}

impl QpBackend for DualBackend {
    fn name(&self) -> &'static str {
        self.settings.method.backend_name()
    }

    /// Contact rows and box rows (friction's tangential multipliers) for every method: PGS and
    /// Uzawa project onto each row's interval, the active-set method gives a box row three
    /// states (stick, slip at ±s).
    fn supports(&self, _kind: BlockKind) -> bool {
        true
    }

    fn solve_valid(
        &mut self,
        problem: &QpProblem,
        options: &SolveOptions,
    ) -> Result<QpSolution, QpError> {
        let start = Instant::now();
        let backend = self.name();
        self.settings
            .validate()
            .map_err(|e: DualError| QpError::Backend {
                backend,
                reason: e.to_string(),
            })?;
        let outcome = self.run(problem, options, start)?;
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
                "{backend}: {} after {} iterations ({})",
                solution.status,
                solution.iterations,
                solution.message.as_deref().unwrap_or("")
            );
        }
        Ok(solution)
    }
}

/// Refuses at once, before any factorisation, a problem with unknowns that have no stiffness
/// and no declared kernel vector: every dual method needs A⁻¹ (or A⁺ with the kernel of A), and
/// factoring such an A only ends in a zero pivot.
fn refuse_unstiff(problem: &QpProblem, backend: &'static str) -> Result<(), QpError> {
    let loose = undeclared_unstiff_unknowns(problem);
    let Some(first) = loose.first() else {
        return Ok(());
    };
    Err(QpError::Unavailable {
        backend,
        reason: format!(
            "A is singular: {} unknown(s) (the first: {first}) have no stiffness (a zero column of A) and no declared kernel vector, and the dual methods need A⁻¹ or the kernel of A (`QpProblem::kernel`); auxiliary unknowns of Tresca rows written one-sided are such unknowns — give a dual-* backend the box rows themselves",
            loose.len()
        ),
    })
}

/// m = 0: x = A⁺ f (the kernel component is arbitrary and set to zero).
fn plain_solve(data: &DualData<'_>, tol: f64) -> Outcome {
    let x = data.base().to_vec();
    let r = kkt_residuals(data.problem, &x, &[]);
    let (status, message) = if r.meet(tol) {
        (QpStatus::Solved, "no contact rows: one solve".to_string())
    } else {
        (
            QpStatus::Inaccurate,
            format!(
                "no contact rows: one solve, KKT residuals {:.1e}",
                r.worst()
            ),
        )
    };
    Outcome {
        x,
        multipliers: Vec::new(),
        status,
        iterations: 0,
        message,
    }
}

/// What a method's error becomes: a refusal is handed to the caller as `Err`, a time limit
/// passed inside a step is `time-limit`, anything else `numerical-error` with the message.
fn verdict(problem: &QpProblem, error: DualError) -> Result<Outcome, QpError> {
    match error {
        DualError::Refused(e) => Err(e),
        DualError::OutOfTime(what) => Ok(failure(
            problem,
            QpStatus::TimeLimit,
            format!("time limit reached {what}"),
        )),
        e => Ok(failure(problem, QpStatus::NumericalError, e.to_string())),
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
