//! [`ClarabelBackend`]: our QP handed to clarabel's interior-point method.

use std::time::{Duration, Instant};

use clarabel::algebra::CscMatrix as ClarabelCsc;
use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT};
use signorini_qp::{
    checked_status, csc_parts, kkt_residuals_with, AuxiliaryForm, BlockKind, KktResiduals,
    QpBackend, QpError, QpProblem, QpScaling, QpSolution, QpStatus, SolveOptions,
};

use crate::settings::{ClarabelSettings, MIN_TOL};
use crate::NAME;

/// The clarabel interior-point solver behind [`QpBackend`].
///
/// # Example
/// ```
/// use signorini_clarabel::{ClarabelBackend, ClarabelSettings};
/// use signorini_qp::{kkt_residuals, QpBackend, QpProblem, QpStatus, SolveOptions};
/// use sprs::TriMat;
/// // min x² − 4x  s.t.  x ≤ 1   →  x = 1, λ = 2
/// let mut a = TriMat::new((1, 1));
/// a.add_triplet(0, 0, 2.0);
/// let mut b = TriMat::new((1, 1));
/// b.add_triplet(0, 0, 1.0);
/// let qp = QpProblem::try_new(a.to_csc(), vec![4.0], b.to_csc(), vec![1.0])?;
/// let mut backend = ClarabelBackend::new(ClarabelSettings::default());
/// let solution = backend.solve(&qp, &SolveOptions::default())?;
/// assert_eq!(solution.status, QpStatus::Solved);
/// assert!((solution.x[0] - 1.0).abs() < 1e-8 && (solution.multipliers[0] - 2.0).abs() < 1e-8);
/// assert!(kkt_residuals(&qp, &solution.x, &solution.multipliers).meet(1e-9));
/// # Ok::<(), signorini_qp::QpError>(())
/// ```
#[derive(Debug, Clone, Default)]
pub struct ClarabelBackend {
    /// Settings used by every solve.
    pub settings: ClarabelSettings,
}

impl ClarabelBackend {
    /// A backend with the given settings.
    pub fn new(settings: ClarabelSettings) -> Self {
        Self { settings }
    }
}

impl QpBackend for ClarabelBackend {
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
            let judge = |s: &QpSolution| form.original_residuals(problem, &s.x, &s.multipliers);
            let solution =
                self.solve_judged(&form.problem, &options.for_another_problem(), &judge)?;
            return Ok(form.recover(solution));
        }
        let scales = options.residual_scales(problem);
        let judge = |s: &QpSolution| kkt_residuals_with(problem, &scales, &s.x, &s.multipliers);
        self.solve_judged(problem, options, &judge)
    }
}

impl ClarabelBackend {
    /// Solves `problem` (no box rows), with clarabel's continuation judged by `judge` (the
    /// residuals of the problem the caller asked about).
    fn solve_judged(
        &mut self,
        problem: &QpProblem,
        options: &SolveOptions,
        judge: &dyn Fn(&QpSolution) -> KktResiduals,
    ) -> Result<QpSolution, QpError> {
        let start = Instant::now();
        let settings = self.settings.to_clarabel(options)?;
        if problem.dofs() == 0 {
            return Ok(no_unknowns(problem, start));
        }
        crate::memory_need(problem)?.check(NAME)?;
        let run = |settings: DefaultSettings<f64>| -> Result<QpSolution, QpError> {
            if self.settings.rescale {
                let scaling = QpScaling::of(problem);
                Ok(scaling.unscale(solve_with_clarabel(&scaling.scale(problem), settings)?))
            } else {
                solve_with_clarabel(problem, settings)
            }
        };
        let meets =
            |s: &QpSolution| checked_status(s.status, &judge(s), options.tol) == QpStatus::Solved;
        let mut solution = run(settings.clone())?;
        let mut iterations = solution.iterations;
        // Continuation: clarabel judges convergence on its equilibrated data, the core on the
        // original; when clarabel is content but the core is not (badly conditioned data, e.g. a
        // 10⁶ stiffness contrast), tighten its tolerances, then try without equilibration.
        if self.settings.continuation && solution.status == QpStatus::Solved && !meets(&solution) {
            let mut attempt = settings;
            let mut stages = 0;
            let mut out_of_time = false;
            loop {
                if attempt.tol_gap_abs > MIN_TOL * 1.01 {
                    attempt.tol_gap_abs = (attempt.tol_gap_abs * 1e-2).max(MIN_TOL);
                    attempt.tol_gap_rel = (attempt.tol_gap_rel * 1e-2).max(MIN_TOL);
                    attempt.tol_feas = (attempt.tol_feas * 1e-2).max(MIN_TOL);
                } else if attempt.equilibrate_enable {
                    attempt.equilibrate_enable = false;
                } else {
                    break;
                }
                // Each stage gets what is left of the limit (it got the whole limit again
                // before, so auto's chain overran a 60 s limit by up to 47 s).
                let Some(timed) = with_time_left(attempt.clone(), options.time_limit, start) else {
                    out_of_time = true;
                    break;
                };
                stages += 1;
                let next = run(timed)?;
                iterations += next.iterations;
                let better = judge(&next).worst() < judge(&solution).worst();
                let done = meets(&next);
                if better {
                    solution = next;
                }
                if done {
                    break;
                }
            }
            let mut note = format!("{stages} continuation stage(s) after clarabel's first answer");
            if out_of_time && !meets(&solution) {
                solution.status = QpStatus::TimeLimit;
                note.push_str("; the time limit ended the continuation");
            }
            solution.message = Some(match solution.message.take() {
                Some(m) => format!("{m}; {note}"),
                None => note,
            });
        }
        solution.iterations = iterations;
        solution.solve_time = start.elapsed();
        Ok(solution)
    }
}

/// The settings of a continuation stage: `attempt` with clarabel's time limit set to what is
/// left of `limit` since `start` (unchanged without a limit); `None` once nothing is left.
fn with_time_left(
    mut attempt: DefaultSettings<f64>,
    limit: Option<Duration>,
    start: Instant,
) -> Option<DefaultSettings<f64>> {
    if let Some(limit) = limit {
        let left = limit
            .checked_sub(start.elapsed())
            .filter(|d| !d.is_zero())?;
        attempt.time_limit = left.as_secs_f64();
    }
    Some(attempt)
}

/// One clarabel solve of `problem` (already checked, n > 0); `solve_time` is left for the caller.
fn solve_with_clarabel(
    problem: &QpProblem,
    settings: DefaultSettings<f64>,
) -> Result<QpSolution, QpError> {
    let (n, m) = (problem.dofs(), problem.rows());

    // P = triu(A), q = −f, A_clarabel = B, b = g, s ∈ ℝᵐ₊.
    let (colptr, rows, values) = csc_parts(&problem.stiffness, |row, col| row <= col);
    let p = ClarabelCsc::new(n, n, colptr, rows, values);
    let (colptr, rows, values) = csc_parts(&problem.constraints, |_, _| true);
    let a = ClarabelCsc::new(m, n, colptr, rows, values);
    let q: Vec<f64> = problem.load.iter().map(|f| -f).collect();
    let cones: Vec<SupportedConeT<f64>> = if m > 0 {
        vec![SupportedConeT::NonnegativeConeT(m)]
    } else {
        Vec::new()
    };

    let mut solver =
        DefaultSolver::new(&p, &q, &a, &problem.gap, &cones, settings).map_err(|error| {
            QpError::Backend {
                backend: NAME,
                reason: error.to_string(),
            }
        })?;
    solver.solve();
    let solution = &solver.solution;
    let (mut status, note) = map_status(solution.status);
    let (mut x, mut multipliers) = match status {
        // clarabel's x, z are then a certificate, not a point: report none.
        QpStatus::PrimalInfeasible | QpStatus::DualInfeasible => (vec![0.0; n], vec![0.0; m]),
        _ => (solution.x.clone(), solution.z.clone()),
    };
    let mut message = format!(
        "clarabel {:?}{note}: primal residual {:.2e}, dual residual {:.2e}",
        solution.status, solution.r_prim, solution.r_dual
    );
    if x.iter().chain(&multipliers).any(|v| !v.is_finite()) {
        status = QpStatus::NumericalError;
        x = vec![0.0; n];
        multipliers = vec![0.0; m];
        message.push_str("; non-finite output replaced by zeros");
    }
    Ok(QpSolution {
        x,
        multipliers,
        status,
        iterations: solution.iterations as usize,
        solve_time: Duration::ZERO,
        message: Some(message),
    })
}

/// clarabel's verdict as a [`QpStatus`], with a note for verdicts that lose information.
fn map_status(status: SolverStatus) -> (QpStatus, &'static str) {
    match status {
        SolverStatus::Solved => (QpStatus::Solved, ""),
        SolverStatus::AlmostSolved => (QpStatus::Inaccurate, " (reduced tolerances met)"),
        SolverStatus::InsufficientProgress => (QpStatus::Inaccurate, " (stalled)"),
        SolverStatus::MaxIterations => (QpStatus::MaxIterations, ""),
        SolverStatus::MaxTime => (QpStatus::TimeLimit, ""),
        SolverStatus::PrimalInfeasible => (QpStatus::PrimalInfeasible, ""),
        SolverStatus::AlmostPrimalInfeasible => (
            QpStatus::PrimalInfeasible,
            " (reduced-accuracy certificate)",
        ),
        SolverStatus::DualInfeasible => (QpStatus::DualInfeasible, ""),
        SolverStatus::AlmostDualInfeasible => {
            (QpStatus::DualInfeasible, " (reduced-accuracy certificate)")
        }
        SolverStatus::NumericalError => (QpStatus::NumericalError, ""),
        SolverStatus::Unsolved | SolverStatus::CallbackTerminated => {
            (QpStatus::NumericalError, " (solver did not finish)")
        }
    }
}

/// The answer when there are no unknowns: feasible iff every gap is non-negative.
fn no_unknowns(problem: &QpProblem, start: Instant) -> QpSolution {
    let feasible = problem.gap.iter().all(|&g| g >= 0.0);
    QpSolution {
        x: Vec::new(),
        multipliers: vec![0.0; problem.rows()],
        status: if feasible {
            QpStatus::Solved
        } else {
            QpStatus::PrimalInfeasible
        },
        iterations: 0,
        solve_time: start.elapsed(),
        message: Some("no unknowns: nothing to solve".to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A continuation stage gets what is left of the limit, not the whole limit again (before,
    /// every stage ran with the caller's full limit: auto's chain, whose last member was
    /// clarabel, took 85–107 s for a 60 s limit on the 2·10⁵-unknown problems of BENCHMARKS'
    /// high-accuracy run), and none once the limit has passed.
    #[test]
    fn a_continuation_stage_gets_the_time_left() {
        let settings = DefaultSettings::<f64>::default();
        // No limit: clarabel's own (none) is kept.
        let kept = with_time_left(settings.clone(), None, Instant::now()).unwrap();
        assert_eq!(kept.time_limit, settings.time_limit);
        // 10 s of which (almost) nothing is spent: at most 10 s, and more than 9.
        let limit = Duration::from_secs(10);
        let left = with_time_left(settings.clone(), Some(limit), Instant::now()).unwrap();
        assert!(
            left.time_limit <= 10.0 && left.time_limit > 9.0,
            "{}",
            left.time_limit
        );
        // 1 ms, started 50 ms ago: nothing left, no stage.
        let Some(earlier) = Instant::now().checked_sub(Duration::from_millis(50)) else {
            return; // a clock that started less than 50 ms ago: nothing to test
        };
        let limit = Duration::from_millis(1);
        assert!(with_time_left(settings, Some(limit), earlier).is_none());
    }
}
