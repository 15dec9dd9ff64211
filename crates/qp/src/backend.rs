//! The backend contract: options in, a solution out.

use std::sync::Arc;
use std::time::Duration;

use super::blocks::BlockKind;
use super::coulomb::{CoulombMethod, CoulombRows};
use super::problem::{QpError, QpProblem};
use super::scales::ResidualScales;
use super::scaling::QpScaling;

pub use super::solution::QpSolution;

/// Settings common to every backend.  Backend-specific knobs live in the backend crates.
#[derive(Debug, Clone)]
pub struct SolveOptions {
    /// Relative KKT tolerance the answer must meet to be called `solved` (see [`KktResiduals`](super::KktResiduals)).
    /// Default `1e-9`.
    pub tol: f64,
    /// Iteration cap; `None` lets the backend choose.  Default `None`.
    pub max_iter: Option<usize>,
    /// Wall-clock limit; `None` for none.  Default `None`.
    pub time_limit: Option<Duration>,
    /// Print the backend's own progress.  Default `false`.
    pub verbose: bool,
    /// How Coulomb rows are solved (the core's choice between the fixed point and the
    /// backend's own method).  Default [`CoulombMethod::Auto`].
    pub coulomb: CoulombMethod,
    /// A nearby answer to start from (the previous load increment's), in the units of the
    /// problem solved; a backend may use it (pdas: its first active set) or ignore it.  Dropped
    /// by [`QpBackend::solve`] when it nondimensionalises the problem.  Default `None`.
    pub warm_start: Option<Arc<WarmStart>>,
    /// The residual scales of the very problem passed, when the caller has computed them
    /// already (`auto` does once for its whole chain, [`ResidualScales::of`] being a pass over
    /// A and B); a backend judges its answer against them instead of computing its own (see
    /// [`SolveOptions::residual_scales`]).  Scales of another problem give a wrong verdict: the
    /// caller's final check ([`crate::kkt_residuals`]) is the one that counts.  Dropped by
    /// [`QpBackend::solve`] when it nondimensionalises the problem.  Default `None`.
    pub scales: Option<Arc<ResidualScales>>,
}

impl SolveOptions {
    /// The residual scales of `problem`: [`SolveOptions::scales`] when they fit its sizes, else
    /// computed ([`ResidualScales::of`]).
    pub fn residual_scales(&self, problem: &QpProblem) -> Arc<ResidualScales> {
        match &self.scales {
            Some(scales) if scales.fit(problem) => Arc::clone(scales),
            _ => Arc::new(ResidualScales::of(problem)),
        }
    }

    /// These options for a problem other than the caller's (the nondimensionalised one, a
    /// condensed dual, an auxiliary form): the warm start and the residual scales belong to the
    /// caller's problem and are dropped.
    pub fn for_another_problem(&self) -> Self {
        Self {
            warm_start: None,
            scales: None,
            ..self.clone()
        }
    }
}

/// A nearby answer (x, λ) for [`SolveOptions::warm_start`].
#[derive(Debug, Clone, PartialEq)]
pub struct WarmStart {
    /// x, one per unknown.
    pub x: Vec<f64>,
    /// λ, one per row.
    pub multipliers: Vec<f64>,
}

impl WarmStart {
    /// The start when its lengths fit `problem`, else `None`.
    pub fn fitting(&self, problem: &QpProblem) -> Option<&Self> {
        (self.x.len() == problem.dofs() && self.multipliers.len() == problem.rows()).then_some(self)
    }
}

impl Default for SolveOptions {
    fn default() -> Self {
        Self {
            tol: 1e-9,
            max_iter: None,
            time_limit: None,
            verbose: false,
            coulomb: CoulombMethod::Auto,
            warm_start: None,
            scales: None,
        }
    }
}

/// A QP algorithm.
///
/// A backend implements [`QpBackend::solve_valid`]; callers call [`QpBackend::solve`], which runs
/// the steps every backend shares around it: the problem's data ([`QpProblem::validate`]), the
/// kinds of constraint block the backend solves ([`QpBackend::supports`]; any other is refused
/// with [`QpError::UnsupportedBlock`] before it runs), the nondimensionalisation
/// ([`QpScaling`]: a problem not yet in units of its own data is scaled for the backend and its
/// answer brought back; one that is — every problem from the core's `ScaledQp` — goes as is,
/// without a copy), then the answer's lengths and finiteness
/// ([`QpSolution::finite_or_numerical_error`]).
///
/// ```
/// use signorini_qp::{QpBackend, QpProblem, QpSolution, QpStatus, QpError, SolveOptions};
/// /// A "backend" that only knows the unconstrained answer of a 1×1 problem.
/// struct Scalar;
/// impl QpBackend for Scalar {
///     fn name(&self) -> &'static str { "scalar" }
///     fn solve_valid(&mut self, p: &QpProblem, _: &SolveOptions) -> Result<QpSolution, QpError> {
///         let a = p.stiffness.data()[0];
///         Ok(QpSolution { x: vec![p.load[0] / a], multipliers: vec![], status: QpStatus::Solved,
///             iterations: 1, solve_time: Default::default(), message: None })
///     }
/// }
/// ```
pub trait QpBackend: Send {
    /// Short name used on the command line and in reports (`"clarabel"`, `"dual-pgs"`, …).
    fn name(&self) -> &'static str;

    /// Whether the backend solves constraint rows of `kind` (see [`crate::ConstraintBlock`]).
    /// Default: the non-negative rows of contact only.
    fn supports(&self, kind: BlockKind) -> bool {
        kind == BlockKind::NonNegative
    }

    /// Solves a problem that passed [`QpBackend::solve`]'s checks (valid data, supported blocks).
    /// `Err` only when the backend cannot run at all.
    fn solve_valid(
        &mut self,
        problem: &QpProblem,
        options: &SolveOptions,
    ) -> Result<QpSolution, QpError>;

    /// Solves the problem with the shared steps around [`QpBackend::solve_valid`] (see the
    /// trait's documentation).  `Err` only when the backend cannot run at all.
    fn solve(
        &mut self,
        problem: &QpProblem,
        options: &SolveOptions,
    ) -> Result<QpSolution, QpError> {
        let scaling = QpScaling::of(problem);
        if scaling.is_unit() {
            return self.solve_in_given_units(problem, options);
        }
        // Checked before scaling too, so that a refusal names the caller's data.
        problem.validate()?;
        let scaled = scaling.scale(problem);
        let options = &options.for_another_problem();
        let answer = self.solve_in_given_units(&scaled, options)?;
        Ok(scaling.unscale(answer).finite_or_numerical_error())
    }

    /// [`QpBackend::solve`] without the nondimensionalisation: for a problem whose units the
    /// caller chose on purpose (the condensed dual's inner solve, in the units of its primal).
    fn solve_in_given_units(
        &mut self,
        problem: &QpProblem,
        options: &SolveOptions,
    ) -> Result<QpSolution, QpError> {
        refuse_unsupported(&*self, problem)?;
        let solution = self.solve_valid(problem, options)?;
        checked_answer(&*self, problem, solution)
    }

    /// Whether the backend would solve Coulomb's rows of `problem` with a method of its own
    /// ([`QpBackend::solve_coulomb_valid`]; a backend that chooses per problem, like `auto`,
    /// says so per problem).  Default: no (the core then runs the fixed point over Tresca
    /// problems through [`QpBackend::solve`]).
    fn solves_coulomb(&self, problem: &QpProblem) -> bool {
        let _ = problem;
        false
    }

    /// Solves a problem whose `coulomb` rows are bounded by μ max(0, λₙ) of the answer itself
    /// (their bounds in `problem`'s box block are a starting guess only), after the checks of
    /// [`QpBackend::solve_coulomb`].  Default: refused as unavailable.
    fn solve_coulomb_valid(
        &mut self,
        problem: &QpProblem,
        coulomb: &CoulombRows,
        options: &SolveOptions,
    ) -> Result<QpSolution, QpError> {
        let _ = (problem, coulomb, options);
        Err(QpError::Unavailable {
            backend: self.name(),
            reason: "it has no method of its own for Coulomb friction (the fixed point over Tresca problems solves it through any backend that solves box rows)".into(),
        })
    }

    /// Solves the Coulomb problem (see [`CoulombRows`]) with the shared steps of
    /// [`QpBackend::solve`] around [`QpBackend::solve_coulomb_valid`] (μ is dimensionless, so
    /// the nondimensionalisation leaves the coupling as it is).
    fn solve_coulomb(
        &mut self,
        problem: &QpProblem,
        coulomb: &CoulombRows,
        options: &SolveOptions,
    ) -> Result<QpSolution, QpError> {
        let scaling = QpScaling::of(problem);
        if scaling.is_unit() {
            refuse_unsupported(&*self, problem)?;
            let solution = self.solve_coulomb_valid(problem, coulomb, options)?;
            return checked_answer(&*self, problem, solution);
        }
        problem.validate()?;
        let scaled = scaling.scale(problem);
        let options = &options.for_another_problem();
        refuse_unsupported(&*self, &scaled)?;
        let solution = self.solve_coulomb_valid(&scaled, coulomb, options)?;
        let answer = checked_answer(&*self, &scaled, solution)?;
        Ok(scaling.unscale(answer).finite_or_numerical_error())
    }
}

/// Refuses invalid data ([`QpProblem::validate`]) and blocks `backend` does not solve.
fn refuse_unsupported<B: QpBackend + ?Sized>(
    backend: &B,
    problem: &QpProblem,
) -> Result<(), QpError> {
    problem.validate()?;
    if let Some(kind) = problem
        .block_kinds()
        .into_iter()
        .find(|k| !backend.supports(*k))
    {
        let supported: Vec<&str> = BlockKind::ALL
            .into_iter()
            .filter(|k| backend.supports(*k))
            .map(BlockKind::as_str)
            .collect();
        return Err(QpError::UnsupportedBlock {
            backend: backend.name(),
            kind,
            supported: supported.join(", "),
        });
    }
    Ok(())
}

/// The answer's lengths checked against the problem, and a non-finite one turned into a
/// numerical error.
fn checked_answer<B: QpBackend + ?Sized>(
    backend: &B,
    problem: &QpProblem,
    solution: QpSolution,
) -> Result<QpSolution, QpError> {
    if solution.x.len() != problem.dofs() || solution.multipliers.len() != problem.rows() {
        return Err(QpError::Backend {
            backend: backend.name(),
            reason: format!(
                "its answer has {} unknowns and {} multipliers for a problem of {} and {}",
                solution.x.len(),
                solution.multipliers.len(),
                problem.dofs(),
                problem.rows()
            ),
        });
    }
    Ok(solution.finite_or_numerical_error())
}
