//! [`OsqpBackend`]: our QP handed to OSQP's ADMM.

use std::borrow::Cow;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::{Duration, Instant};

use osqp::{CscMatrix as OsqpCsc, PolishStatus, Problem, SetupError, Status};
use signorini_qp::{
    csc_parts, kkt_residuals_with, norm_inf, AuxiliaryForm, BlockKind, KktResiduals, QpBackend,
    QpError, QpProblem, QpScaling, QpSolution, QpStatus, SolveOptions,
};

use crate::settings::{OsqpSettings, Plan};
use crate::NAME;

/// Lower bound standing for −∞ (OSQP treats |l| ≥ 1e30 as infinite).
const MINUS_INFINITY: f64 = -1e30;

/// The OSQP (ADMM) solver behind [`QpBackend`].
///
/// # Example
/// ```
/// use signorini_osqp::{OsqpBackend, OsqpSettings};
/// use signorini_qp::{checked_status, kkt_residuals, QpBackend, QpProblem, QpStatus,
///     SolveOptions};
/// use sprs::TriMat;
/// // min x² − 4x  s.t.  x ≤ 1   →  x = 1, λ = 2
/// let mut a = TriMat::new((1, 1));
/// a.add_triplet(0, 0, 2.0);
/// let mut b = TriMat::new((1, 1));
/// b.add_triplet(0, 0, 1.0);
/// let qp = QpProblem::try_new(a.to_csc(), vec![4.0], b.to_csc(), vec![1.0])?;
/// let mut backend = OsqpBackend::new(OsqpSettings::default());
/// let options = SolveOptions::default();
/// let solution = backend.solve(&qp, &options)?;
/// let residuals = kkt_residuals(&qp, &solution.x, &solution.multipliers);
/// assert_eq!(checked_status(solution.status, &residuals, options.tol), QpStatus::Solved);
/// assert!((solution.x[0] - 1.0).abs() < 1e-8 && (solution.multipliers[0] - 2.0).abs() < 1e-8);
/// # Ok::<(), signorini_qp::QpError>(())
/// ```
#[derive(Debug, Clone, Default)]
pub struct OsqpBackend {
    /// Settings used by every solve.
    pub settings: OsqpSettings,
    /// The last finite answer (x, λ) in the caller's units, for [`OsqpSettings::warm_start`].
    previous: Option<(Vec<f64>, Vec<f64>)>,
}

impl OsqpBackend {
    /// A backend with the given settings.
    pub fn new(settings: OsqpSettings) -> Self {
        Self {
            settings,
            previous: None,
        }
    }
}

impl QpBackend for OsqpBackend {
    fn name(&self) -> &'static str {
        NAME
    }

    fn supports(&self, _kind: BlockKind) -> bool {
        // Box rows through auxiliary variables (AuxiliaryForm): every kind there is.
        true
    }

    fn solve_valid(
        &mut self,
        problem: &QpProblem,
        options: &SolveOptions,
    ) -> Result<QpSolution, QpError> {
        if problem.blocks.iter().any(|b| b.kind() == BlockKind::Box) {
            let form = AuxiliaryForm::of(problem)?;
            let judge = |x: &[f64], mu: &[f64]| form.original_residuals(problem, x, mu);
            let solution =
                self.solve_judged(&form.problem, &options.for_another_problem(), &judge)?;
            return Ok(form.recover(solution));
        }
        let scales = options.residual_scales(problem);
        let judge = |x: &[f64], mu: &[f64]| kkt_residuals_with(problem, &scales, x, mu);
        self.solve_judged(problem, options, &judge)
    }
}

/// The residuals an answer (x, λ) of the problem handed to OSQP is judged by (those of the
/// problem the caller asked about).
type Judge<'a> = &'a dyn Fn(&[f64], &[f64]) -> KktResiduals;

impl OsqpBackend {
    /// Solves `problem` (no box rows); the stages stop when `judge` meets the tolerance.
    fn solve_judged(
        &mut self,
        problem: &QpProblem,
        options: &SolveOptions,
        judge: Judge<'_>,
    ) -> Result<QpSolution, QpError> {
        let start = Instant::now();
        self.settings.validate()?;
        if problem.dofs() == 0 {
            return Ok(no_unknowns(problem, start));
        }
        crate::memory_need(problem)?.check(NAME)?;
        let scaling = if self.settings.rescale {
            QpScaling::of(problem)
        } else {
            QpScaling {
                stiffness: 1.0,
                displacement: 1.0,
            }
        };
        let scaled = if self.settings.rescale {
            Cow::Owned(scaling.scale(problem))
        } else {
            Cow::Borrowed(problem)
        };
        let (settings, plan) = self.settings.to_osqp(options, norm_inf(&scaled.load))?;
        let warm = self
            .previous
            .as_ref()
            .filter(|(x, y)| {
                self.settings.warm_start && x.len() == problem.dofs() && y.len() == problem.rows()
            })
            .map(|(x, y)| {
                let force = scaling.stiffness * scaling.displacement;
                (
                    x.iter()
                        .map(|v| v / scaling.displacement)
                        .collect::<Vec<_>>(),
                    y.iter().map(|v| v / force).collect::<Vec<_>>(),
                )
            });
        // OSQP works on the scaled problem; its answers are judged in the caller's units.
        let force = scaling.stiffness * scaling.displacement;
        let in_units = |x: &[f64], mu: &[f64]| {
            let x: Vec<f64> = x.iter().map(|v| v * scaling.displacement).collect();
            let mu: Vec<f64> = mu.iter().map(|v| v * force).collect();
            judge(&x, &mu)
        };
        let solution = solve_with_osqp(&scaled, &settings, &plan, warm, start, &in_units)?;
        let mut solution = scaling.unscale(solution);
        solution.solve_time = start.elapsed();
        if matches!(
            solution.status,
            QpStatus::Solved | QpStatus::Inaccurate | QpStatus::MaxIterations | QpStatus::TimeLimit
        ) {
            self.previous = Some((solution.x.clone(), solution.multipliers.clone()));
        }
        Ok(solution)
    }
}

/// One OSQP solve of `problem` (already checked, n > 0) in the stages of `plan`; `solve_time`
/// is left for the caller, `start` is when the caller began.
fn solve_with_osqp(
    problem: &QpProblem,
    settings: &osqp::Settings,
    plan: &Plan,
    warm: Option<(Vec<f64>, Vec<f64>)>,
    start: Instant,
    judge: Judge<'_>,
) -> Result<QpSolution, QpError> {
    let (n, m) = (problem.dofs(), problem.rows());
    // P = triu(A), q = −f, A_osqp = B, l = −∞, u = g.
    let p = osqp_matrix(n, n, csc_parts(&problem.stiffness, |row, col| row <= col));
    let a = osqp_matrix(m, n, csc_parts(&problem.constraints, |_, _| true));
    let q: Vec<f64> = problem.load.iter().map(|f| -f).collect();
    let lower = vec![MINUS_INFINITY; m];

    let mut solver = match Problem::new(p, &q, a, &lower, &problem.gap, settings) {
        Ok(solver) => solver,
        Err(SetupError::NonConvex) => {
            return Ok(failed(
                n,
                m,
                QpStatus::NumericalError,
                "OSQP setup: A is not positive semidefinite",
            ))
        }
        // Data OSQP refuses (e.g. bounds beyond its ±1e30 infinity) is a failure of this solve,
        // reported as a status so that `solve` still writes its result: not a refusal of the scene.
        Err(error) => {
            return Ok(failed(
                n,
                m,
                QpStatus::NumericalError,
                &format!("OSQP setup failed: {error}"),
            ))
        }
    };
    if let Some((x, y)) = warm {
        solver.warm_start(&x, &y);
    }
    // osqp 0.6 asserts on a non-zero return of `osqp_solve` (a failed ρ update) and on status
    // codes it does not know; both are numerical failures of this solve, not bugs of ours.
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        run_stages(&mut solver, problem, plan, start, judge)
    }));
    let mut solution = outcome.unwrap_or_else(|_| {
        failed(
            n,
            m,
            QpStatus::NumericalError,
            "OSQP aborted (failed ρ update or unknown status)",
        )
    });
    if solution
        .x
        .iter()
        .chain(&solution.multipliers)
        .any(|v| !v.is_finite())
    {
        solution.status = QpStatus::NumericalError;
        solution.x = vec![0.0; n];
        solution.multipliers = vec![0.0; m];
        if let Some(message) = solution.message.as_mut() {
            message.push_str("; non-finite output replaced by zeros");
        }
    }
    Ok(solution)
}

/// Runs ADMM (+ polish) with ε_abs tightened 100-fold per stage until the core's residuals meet
/// `plan.tol`, ε_abs reaches `plan.eps_target`, or OSQP stops for another reason.
fn run_stages(
    solver: &mut Problem,
    problem: &QpProblem,
    plan: &Plan,
    start: Instant,
    judge: Judge<'_>,
) -> QpSolution {
    let (n, m) = (problem.dofs(), problem.rows());
    let mut eps = plan.eps_start;
    let mut iterations = 0;
    let mut stages = 0;
    loop {
        let mut result = read_status(&solver.solve(), n, m);
        stages += 1;
        iterations += result.iterations;
        result.iterations = iterations;
        let note = format!(" [stage {stages}, ε_abs {eps:.1e}]");
        if let Some(message) = result.message.as_mut() {
            message.push_str(&note);
        }
        let converged = matches!(result.status, QpStatus::Solved | QpStatus::Inaccurate);
        if !converged
            || eps <= plan.eps_target
            || judge(&result.x, &result.multipliers).meet(plan.tol)
        {
            return result;
        }
        let left = (plan.max_iter as usize).saturating_sub(iterations);
        let remaining = plan
            .time_limit
            .map(|limit| limit.saturating_sub(start.elapsed()));
        if left == 0 || remaining == Some(Duration::ZERO) {
            return result;
        }
        eps = (eps * 1e-2).max(plan.eps_target);
        solver.update_eps_abs(eps);
        solver.update_max_iter(u32::try_from(left).unwrap_or(u32::MAX));
        solver.update_time_limit(remaining);
        solver.update_warm_start(true);
    }
}

/// Builds OSQP's matrix from CSC parts.
fn osqp_matrix(
    nrows: usize,
    ncols: usize,
    (indptr, indices, data): (Vec<usize>, Vec<usize>, Vec<f64>),
) -> OsqpCsc<'static> {
    OsqpCsc {
        nrows,
        ncols,
        indptr: Cow::Owned(indptr),
        indices: Cow::Owned(indices),
        data: Cow::Owned(data),
    }
}

/// OSQP's verdict and iterate as a [`QpSolution`].
fn read_status(status: &Status<'_>, n: usize, m: usize) -> QpSolution {
    let (verdict, solution, note) = match status {
        Status::Solved(s) => (QpStatus::Solved, Some(s), "solved"),
        Status::SolvedInaccurate(s) => (QpStatus::Inaccurate, Some(s), "solved inaccurate"),
        Status::MaxIterationsReached(s) => (QpStatus::MaxIterations, Some(s), "max iterations"),
        Status::TimeLimitReached(s) => (QpStatus::TimeLimit, Some(s), "time limit"),
        Status::PrimalInfeasible(_) => (QpStatus::PrimalInfeasible, None, "primal infeasible"),
        Status::PrimalInfeasibleInaccurate(_) => (
            QpStatus::PrimalInfeasible,
            None,
            "primal infeasible (inaccurate certificate)",
        ),
        Status::DualInfeasible(_) => (QpStatus::DualInfeasible, None, "dual infeasible"),
        Status::DualInfeasibleInaccurate(_) => (
            QpStatus::DualInfeasible,
            None,
            "dual infeasible (inaccurate certificate)",
        ),
        Status::NonConvex(_) => (QpStatus::NumericalError, None, "non-convex"),
        _ => (QpStatus::NumericalError, None, "unknown status"),
    };
    let mut result = failed(n, m, verdict, &format!("OSQP {note}"));
    result.iterations = status.iter() as usize;
    if let Some(solution) = solution {
        result.x = solution.x().to_vec();
        result.multipliers = solution.y().to_vec();
        let polish = match solution.polish_status() {
            PolishStatus::Successful => "polished",
            PolishStatus::Unsuccessful => "polish failed",
            _ => "not polished",
        };
        result.message = Some(format!(
            "OSQP {note}, {polish}: primal residual {:.2e}, dual residual {:.2e}",
            solution.pri_res(),
            solution.dua_res()
        ));
    }
    result
}

/// A solution with x = 0, λ = 0 (no point to report) and the given verdict.
fn failed(n: usize, m: usize, status: QpStatus, message: &str) -> QpSolution {
    QpSolution {
        x: vec![0.0; n],
        multipliers: vec![0.0; m],
        status,
        iterations: 0,
        solve_time: Duration::ZERO,
        message: Some(message.to_string()),
    }
}

/// The answer when there are no unknowns: feasible iff every gap is non-negative.
fn no_unknowns(problem: &QpProblem, start: Instant) -> QpSolution {
    let feasible = problem.gap.iter().all(|&g| g >= 0.0);
    let status = if feasible {
        QpStatus::Solved
    } else {
        QpStatus::PrimalInfeasible
    };
    let mut solution = failed(0, problem.rows(), status, "no unknowns: nothing to solve");
    solution.solve_time = start.elapsed();
    solution
}
