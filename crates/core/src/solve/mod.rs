//! Solving an assembled model: one sparse Cholesky solve when there is no contact row, otherwise
//! the reduced QP through a backend on the nondimensionalised problem, checked by the core's own
//! KKT residuals.

mod coulomb;
mod path;

use std::time::{Duration, Instant};

use crate::linalg::{
    fill_reducing_order, CholeskyPattern, FactorInfo, Layout, LinalgError, SparseCholesky,
};
use crate::model::{Increment, Model, ModelError};
use crate::qp::{
    checked_status, kkt_residuals, mat_t_vec, CscMatrix, KktResiduals, QpBackend, QpError,
    QpProblem, QpScaling, QpSolution, QpStatus, SolveOptions,
};

pub use coulomb::{CoulombRun, MAX_OUTER};
pub use path::{increment_problem, StepRecord};

/// Name reported when no QP was needed.
pub const DIRECT: &str = "cholesky";

/// Why a model could not be solved (as opposed to a solve that did not converge).
#[derive(Debug, thiserror::Error)]
pub enum SolveError {
    /// Building the QP failed.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// The backend could not run.
    #[error(transparent)]
    Qp(#[from] QpError),
    /// The unconstrained stiffness could not be factored.
    #[error(transparent)]
    Linalg(#[from] LinalgError),
    /// A body held only by contact received no contact row, so it is free to move.
    #[error("the stiffness is singular ({modes} rigid-body mode(s) free) and no contact row holds the body; check the contact pair's region")]
    Floating {
        /// Number of free modes.
        modes: usize,
    },
}

/// The outcome of a solve, in the scene's units.
#[derive(Debug, Clone)]
pub struct Solution {
    /// Backend name (`"cholesky"` when no QP was needed).
    pub backend: String,
    /// Full displacement vector (all DOFs, prescribed values included).
    pub displacement: Vec<f64>,
    /// Contact multipliers λ (one per row, force per unit thickness).
    pub multipliers: Vec<f64>,
    /// Final status: the backend's verdict checked against the core's residuals and the
    /// finiteness of every number in the answer (see [`checked_status`]).
    pub status: QpStatus,
    /// The backend's own verdict, before the core's check (`solved` for the direct solve).
    pub backend_status: QpStatus,
    /// Backend iterations (0 for a direct solve).
    pub iterations: usize,
    /// KKT residuals (penetration in length units, the rest dimensionless).
    pub residuals: KktResiduals,
    /// Objective ½uᵀAu − fᵀu of the reduced problem.
    pub objective: f64,
    /// Wall-clock time of the solve.
    pub solve_time: Duration,
    /// A note from the backend.
    pub message: Option<String>,
    /// The Coulomb fixed point's account, when the model has Coulomb rows.
    pub coulomb: Option<CoulombRun>,
    /// The tolerance the answer was judged by (`--tol`); also the stick/slip threshold's.
    pub tolerance: f64,
    /// With a load path (`[[step]]`): every increment run, in order (the answer is the last's).
    pub steps: Vec<StepRecord>,
    /// With a load path: the full displacement of the increment before the last (the
    /// reference of the last increment's slip), `None` for the first or only one.
    pub previous: Option<Vec<f64>>,
}

/// A QP in dimensionless form, together with the units that bring its answers back.  Holding
/// only this (not the unscaled problem too) keeps one copy of A in memory.
#[derive(Debug, Clone)]
pub struct ScaledQp {
    /// Â, f̂, B, ĝ: what backends see.
    pub problem: QpProblem,
    /// x = displacement · x̂, λ = stiffness · displacement · λ̂.
    pub scaling: QpScaling,
}

impl ScaledQp {
    /// Scales `problem` in place (see [`QpScaling::of`]).
    pub fn new(mut problem: QpProblem) -> Self {
        let scaling = QpScaling::of(&problem);
        scaling.scale_in_place(&mut problem);
        Self { problem, scaling }
    }
}

/// Solves the model's QP `qp` (a direct solve without contact rows, else `backend`), on a
/// scaled copy; for repeated solves scale once with [`ScaledQp::new`] and call [`solve_scaled`].
pub fn solve_model(
    model: &Model,
    qp: &QpProblem,
    backend: &mut dyn QpBackend,
    options: &SolveOptions,
) -> Result<Solution, SolveError> {
    solve_scaled(model, &ScaledQp::new(qp.clone()), backend, options)
}

/// Solves the scaled QP of the model (built once, solved many times).  Residuals are computed on
/// the scaled data: the dimensionless ones are unit-free, the penetration is brought back to
/// length units.
///
/// A model with a load path (`[[step]]`) is solved increment by increment
/// ([`StepRecord`]s in the answer); `qp` is then the QP of the last increment, whose A, B and
/// scaling every increment shares.
pub fn solve_scaled(
    model: &Model,
    qp: &ScaledQp,
    backend: &mut dyn QpBackend,
    options: &SolveOptions,
) -> Result<Solution, SolveError> {
    solve_scaled_each(model, qp, backend, options, &mut |_, _| {})
}

/// [`solve_scaled`], handing `each` every increment of a load path and its answer (prescribed
/// values included) as soon as it is known; `each` is not called without a load path of more
/// than one increment.  (`signorini export --fclib` writes one problem per increment this way.)
pub fn solve_scaled_each(
    model: &Model,
    qp: &ScaledQp,
    backend: &mut dyn QpBackend,
    options: &SolveOptions,
    each: &mut dyn FnMut(&Increment, &Solution),
) -> Result<Solution, SolveError> {
    match &model.path {
        Some(path) if path.increments.len() > 1 => {
            path::along(model, path, qp, backend, options, each)
        }
        _ => solve_one(model, qp, backend, options),
    }
}

/// One solve of the scaled QP `qp` (a direct solve, a QP, or Coulomb's fixed point).
fn solve_one(
    model: &Model,
    qp: &ScaledQp,
    backend: &mut dyn QpBackend,
    options: &SolveOptions,
) -> Result<Solution, SolveError> {
    let problem = &qp.problem;
    let units = qp.scaling;
    if problem.rows() == 0 {
        return solve_direct(model, qp, options);
    }
    let force_unit = units.stiffness * units.displacement;
    if !(units.displacement.is_finite() && force_unit.is_finite() && force_unit > 0.0) {
        // ‖f‖/k̄ beyond the floating-point range (E = 1e-200 under a traction of 1e200): the
        // displacements cannot be represented in the scene's units, whatever the backend does.
        return Ok(Solution::no_answer(
            backend.name(),
            model,
            problem.rows(),
            Duration::ZERO,
            format!(
                "the displacement scale ‖f‖∞ / k̄ (k̄ = {:e}) overflows: the answer cannot be represented in the scene's units; rescale them (the backend was not run)",
                units.stiffness
            ),
            options.tol,
        ));
    }
    if problem.load.iter().all(|f| *f == 0.0) && problem.gap.iter().all(|g| *g >= 0.0) {
        // Nothing loads the bodies and nothing overlaps: x = 0, λ = 0 is the exact answer
        // (feasible, stationary, complementary), so no backend runs.  An iterative backend would
        // only add noise of the size its tolerance allows, in units the data do not fix.
        return Ok(Solution {
            backend: backend.name().to_string(),
            displacement: model.expand(&vec![0.0; problem.dofs()]),
            multipliers: vec![0.0; problem.rows()],
            status: QpStatus::Solved,
            backend_status: QpStatus::Solved,
            iterations: 0,
            residuals: KktResiduals::default(),
            objective: 0.0,
            solve_time: Duration::ZERO,
            message: Some("unloaded and no initial overlap: the answer is exactly zero; the backend was not run".into()),
            coulomb: None,
            tolerance: options.tol,
            steps: Vec::new(),
            previous: None,
        }
        .checked_finite());
    }
    if model
        .tangential
        .iter()
        .any(|t| matches!(t.law, crate::scene::Friction::Coulomb(_)))
    {
        return coulomb::solve(model, qp, backend, options);
    }
    let start = Instant::now();
    let raw = backend.solve(problem, options)?;
    Ok(finish(
        model,
        problem,
        units,
        backend.name(),
        raw,
        start.elapsed(),
        options,
    ))
}

/// The solution in the scene's units from a backend's answer `raw` to the scaled `problem`:
/// residuals measured on `problem`, the status checked against them (see [`checked_status`]).
fn finish(
    model: &Model,
    problem: &QpProblem,
    units: QpScaling,
    backend: &str,
    raw: QpSolution,
    elapsed: Duration,
    options: &SolveOptions,
) -> Solution {
    let energy = units.stiffness * units.displacement * units.displacement;
    let residuals =
        kkt_residuals(problem, &raw.x, &raw.multipliers).with_length_scale(units.displacement);
    let status = checked_status(raw.status, &residuals, options.tol);
    let objective = if raw.x.iter().all(|v| v.is_finite()) {
        problem.objective(&raw.x) * energy
    } else {
        f64::NAN
    };
    let backend_status = raw.status;
    let solution = units.unscale(raw);
    Solution {
        backend: backend.to_string(),
        displacement: model.expand(&solution.x),
        multipliers: solution.multipliers,
        status,
        backend_status,
        iterations: solution.iterations,
        residuals,
        objective,
        solve_time: elapsed,
        message: solution.message,
        coulomb: None,
        tolerance: options.tol,
        steps: Vec::new(),
        previous: None,
    }
    .checked_finite()
}

/// The solve without contact rows: one sparse Cholesky factorisation of the scaled stiffness
/// (refused when rigid modes are free, since nothing holds the bodies).
fn solve_direct(
    model: &Model,
    qp: &ScaledQp,
    options: &SolveOptions,
) -> Result<Solution, SolveError> {
    let problem = &qp.problem;
    let units = qp.scaling;
    let energy = units.stiffness * units.displacement * units.displacement;
    if !problem.kernel.is_empty() {
        return Err(SolveError::Floating {
            modes: problem.kernel.len(),
        });
    }
    let start = Instant::now();
    let mut x = problem.load.clone();
    if problem.dofs() > 0 {
        match SparseCholesky::factor(&problem.stiffness) {
            Ok(factor) => factor.solve_in_place(&mut x),
            // The scene was valid and held (assembly checked the rigid modes): a factorisation
            // that breaks down is this solve's numerical failure (a stiffness contrast beyond
            // the floating-point range, say), a status with its reason, not a refusal.
            Err(e) => {
                return Ok(Solution::no_answer(
                    DIRECT,
                    model,
                    0,
                    start.elapsed(),
                    format!("the sparse Cholesky factorisation failed: {e}"),
                    options.tol,
                ));
            }
        }
    }
    let elapsed = start.elapsed();
    let residuals = kkt_residuals(problem, &x, &[]).with_length_scale(units.displacement);
    let status = checked_status(QpStatus::Solved, &residuals, options.tol);
    let objective = problem.objective(&x) * energy;
    x.iter_mut().for_each(|v| *v *= units.displacement);
    Ok(Solution {
        backend: DIRECT.to_string(),
        objective,
        displacement: model.expand(&x),
        multipliers: Vec::new(),
        status,
        backend_status: QpStatus::Solved,
        iterations: 0,
        residuals,
        solve_time: elapsed,
        message: None,
        coulomb: None,
        tolerance: options.tol,
        steps: Vec::new(),
        previous: None,
    }
    .checked_finite())
}

impl Solution {
    /// The backend's message as ` (message)`, or nothing without one: the tail of a refusal
    /// that names why a solve fell short.
    pub fn message_in_parentheses(&self) -> String {
        self.message
            .as_deref()
            .map(|m| format!(" ({m})"))
            .unwrap_or_default()
    }

    /// A `numerical-error` with no answer (NaN displacements and multipliers, unmeasurable
    /// residuals) and the reason in `message`: for solves that fail before or instead of a
    /// backend's run.
    fn no_answer(
        backend: &str,
        model: &Model,
        rows: usize,
        solve_time: Duration,
        message: String,
        tolerance: f64,
    ) -> Self {
        Self {
            backend: backend.to_string(),
            displacement: vec![f64::NAN; model.dofs.len()],
            multipliers: vec![f64::NAN; rows],
            status: QpStatus::NumericalError,
            backend_status: QpStatus::NumericalError,
            iterations: 0,
            residuals: KktResiduals::UNMEASURABLE,
            objective: f64::NAN,
            solve_time,
            message: Some(message),
            coulomb: None,
            tolerance,
            steps: Vec::new(),
            previous: None,
        }
    }

    /// Demotes a `solved` answer to `numerical-error` when any number of it is not finite: the
    /// scaled problem may be solved exactly and still overflow when brought back to the user's
    /// units (E = 1e-200 under a traction of 1e200 gives displacements of 1e400).
    pub fn checked_finite(mut self) -> Self {
        if self.status != QpStatus::Solved {
            return self;
        }
        let bad = |v: &[f64]| v.iter().filter(|x| !x.is_finite()).count();
        let (du, dl) = (bad(&self.displacement), bad(&self.multipliers));
        if du + dl > 0 || !self.objective.is_finite() {
            self.status = QpStatus::NumericalError;
            let note = format!(
                "the answer overflows in the scene's units: {du} displacement(s), {dl} multiplier(s){} not finite",
                if self.objective.is_finite() { "" } else { " and the objective" }
            );
            self.message = Some(match self.message.take() {
                Some(m) => format!("{note}; backend: {m}"),
                None => note,
            });
        }
        self
    }
}

/// The timing floor of a QP, and the factor it measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Floor {
    /// Wall-clock time of the fill-reducing ordering, the symbolic analysis, the numeric LLᵀ and
    /// one solve.
    pub time: Duration,
    /// The factor: ordering and nnz(L).
    pub info: FactorInfo,
    /// ε when the floor factored A + εI rather than A (a known null space, or a Cholesky of A
    /// that broke down); `None` when it factored A itself.
    pub shift: Option<f64>,
}

/// The matrix the floor factors when it is not A itself: with a known null space (a body held
/// only by contact) A + εI, ε = 1e-8 · maxⱼ Aⱼⱼ (same pattern, same cost, positive definite).
pub fn floor_matrix(qp: &QpProblem) -> Option<CscMatrix> {
    if qp.kernel.is_empty() || qp.dofs() == 0 {
        return None;
    }
    Some(shifted_stiffness(qp))
}

/// The floor's ε = 1e-8 · maxⱼ Aⱼⱼ.
fn floor_shift(qp: &QpProblem) -> f64 {
    1e-8 * (0..qp.dofs())
        .map(|j| qp.stiffness.get(j, j).copied().unwrap_or(0.0))
        .fold(0.0, f64::max)
}

/// A + εI, ε = [`floor_shift`].
fn shifted_stiffness(qp: &QpProblem) -> CscMatrix {
    let n = qp.dofs();
    let shift = floor_shift(qp);
    let mut eye = sprs::TriMat::new((n, n));
    for j in 0..n {
        eye.add_triplet(j, j, shift);
    }
    let eye: CscMatrix = eye.to_csc();
    &qp.stiffness + &eye
}

/// One timed ordering + factorisation + solve of `a`, in the kernel faer chooses for its pattern
/// (simplicial or supernodal by its flop ratio: simplicial on long thin strips, where it is the
/// faster one); the analysed pattern is returned for [`floor`]'s count of nnz(L).
fn timed_factor(a: &CscMatrix, load: &[f64]) -> Result<(Duration, CholeskyPattern), LinalgError> {
    let start = Instant::now();
    let mut x = load.to_vec();
    let pattern =
        CholeskyPattern::analyse_laid_out(a, &fill_reducing_order(a)?, Layout::FaerChoice)?;
    pattern.factor(a)?.solve_in_place(&mut x);
    Ok((start.elapsed(), pattern))
}

/// The floor's factorisation of A, or of [`floor_matrix`]; when A has no declared null space
/// but its Cholesky breaks down all the same (a very slender clamped body: a 10⁴-long strip
/// loses its last pivots to round-off), the shifted A + εI is timed instead — the floor is a
/// timing reference, and the shift changes neither the pattern nor the work.
fn floor_factor(
    qp: &QpProblem,
) -> Result<(Duration, CholeskyPattern, Option<CscMatrix>), LinalgError> {
    let shifted = floor_matrix(qp);
    let a = shifted.as_ref().unwrap_or(&qp.stiffness);
    match timed_factor(a, &qp.load) {
        Err(LinalgError::NotPositiveDefinite { .. }) if shifted.is_none() && qp.dofs() > 0 => {
            let shifted = shifted_stiffness(qp);
            let (time, pattern) = timed_factor(&shifted, &qp.load)?;
            Ok((time, pattern, Some(shifted)))
        }
        other => other.map(|(time, pattern)| (time, pattern, shifted)),
    }
}

/// The timing floor: one unconstrained sparse factorisation + solve of the same A, on the path
/// every factor of A in the project takes (the rule's ordering, faer's symbolic analysis,
/// numeric LLᵀ on one thread) in the faster of faer's two kernels as faer judges it
/// ([`Layout::FaerChoice`]: simplicial where its flop ratio says so, else supernodal — the
/// solves that must read supernodes, the dual backends', force that layout and pay for it),
/// timed from the ordering to the end of the solve.  With a known null space (floating bodies)
/// [`floor_matrix`] is factored instead (built before the clock starts), and so is A + εI when
/// A's own Cholesky breaks down.
pub fn floor(qp: &QpProblem) -> Result<Floor, LinalgError> {
    let (time, pattern, shifted) = floor_factor(qp)?;
    let a = shifted.as_ref().unwrap_or(&qp.stiffness);
    Ok(Floor {
        time,
        info: pattern.info(a)?,
        shift: shifted.is_some().then(|| floor_shift(qp)),
    })
}

/// [`floor`]'s time alone (without counting nnz(L), which [`floor`] does after its clock
/// stops).
pub fn floor_time(qp: &QpProblem) -> Result<Duration, LinalgError> {
    Ok(floor_factor(qp)?.0)
}

/// Contact forces on every DOF: −B_fullᵀ λ (the force the contact exerts on the nodes).
pub fn contact_forces(model: &Model, multipliers: &[f64]) -> Vec<f64> {
    if multipliers.is_empty() {
        return vec![0.0; model.dofs.len()];
    }
    mat_t_vec(&model.constraints, multipliers)
        .into_iter()
        .map(|v| -v)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::examples::{eliminated_nnz, two_dof_grid};
    use crate::linalg::fill_reducing_order;

    fn qp_of(a: CscMatrix) -> QpProblem {
        let n = a.rows();
        let b: CscMatrix = sprs::TriMat::new((0, n)).to_csc();
        QpProblem::try_new(a, vec![1.0; n], b, vec![]).unwrap()
    }

    /// Issue 21: the floor takes faer's own kernel.  On a small grid faer's flop ratio picks
    /// the simplicial one; the floor once forced supernodal everywhere (supernodes > 0 here).
    #[test]
    fn the_floor_factors_in_the_kernel_faer_chooses() {
        let qp = qp_of(two_dof_grid(10));
        let floor = floor(&qp).unwrap();
        let ordering = fill_reducing_order(&qp.stiffness).unwrap();
        let choice =
            CholeskyPattern::analyse_laid_out(&qp.stiffness, &ordering, Layout::FaerChoice)
                .unwrap()
                .info(&qp.stiffness)
                .unwrap();
        assert_eq!(choice.supernodes, 0, "faer chooses simplicial here");
        assert_eq!(floor.info.supernodes, choice.supernodes);
        assert_eq!(floor.info.nnz_l, choice.nnz_l);
    }

    #[test]
    fn the_floor_reports_the_rules_ordering_and_the_exact_nnz_of_l() {
        let qp = qp_of(two_dof_grid(10));
        let floor = floor(&qp).unwrap();
        assert_eq!(floor.shift, None, "a definite A is factored as it is");
        let ordering = fill_reducing_order(&qp.stiffness).unwrap();
        assert_eq!(floor.info.ordering, ordering.method);
        assert_eq!(floor.info.n, qp.dofs());
        assert_eq!(
            floor.info.nnz_l,
            eliminated_nnz(&qp.stiffness, &ordering.inverse)
        );
        assert!(floor.time > Duration::ZERO);
    }

    #[test]
    fn a_floating_floor_factors_the_shifted_matrix_and_an_empty_one_nothing() {
        let mut qp = qp_of(two_dof_grid(4));
        qp.kernel = vec![vec![1.0; qp.dofs()]];
        let shifted = floor_matrix(&qp).unwrap();
        // ε = 1e-8 · max Aⱼⱼ = 2e-7 on every diagonal entry, nothing else changed.
        for j in 0..qp.dofs() {
            let d = shifted.get(j, j).unwrap() - qp.stiffness.get(j, j).unwrap();
            // (20 + 2e-7) − 20 is exact to an ulp of 20 (3.6e-15); allow a few.
            assert!((d - 20.0 * 1e-8).abs() < 2e-14, "{d}");
        }
        assert_eq!(shifted.nnz(), qp.stiffness.nnz());
        assert_eq!(floor(&qp).unwrap().shift, Some(20.0 * 1e-8));
        let empty = qp_of(sprs::TriMat::new((0, 0)).to_csc());
        assert_eq!(floor(&empty).unwrap().info.nnz_l, 0);
    }

    /// A matrix whose Cholesky breaks down by round-off (exactly singular in f64, no declared
    /// kernel) still has a floor: the shifted matrix is timed.  Before, compare stopped with
    /// "pivot vanished" on a 200-long clamped strip.
    #[test]
    fn floor_survives_a_numerically_singular_stiffness() {
        let mut t = sprs::TriMat::new((2, 2));
        for (i, j, v) in [(0, 0, 1.0), (0, 1, 1.0), (1, 0, 1.0), (1, 1, 1.0 + 1e-17)] {
            t.add_triplet(i, j, v);
        }
        let qp = qp_of(t.to_csc());
        assert!(crate::linalg::SparseCholesky::factor(&qp.stiffness).is_err());
        let floor = floor(&qp).unwrap();
        assert_eq!(floor.info.n, 2);
        // ε = 1e-8 · max Aⱼⱼ = 1e-8 · (1 + 1e-17), which rounds to 1e-8.
        assert_eq!(floor.shift, Some(1e-8));
        assert!(floor_time(&qp).is_ok());
    }
}
