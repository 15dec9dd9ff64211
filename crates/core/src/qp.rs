//! The quadratic program every backend solves, and the one residual check used for all of them.
//!
//! ```text
//! minimise   ½ xᵀ A x − fᵀ x
//! subject to B x ≤ g
//! ```
//!
//! `A` (`stiffness`, n×n) is the symmetric positive (semi-)definite stiffness on the free degrees
//! of freedom, `f` (`load`) the load vector after Dirichlet lifting, `B` (`constraints`, m×n) the
//! node-to-segment contact rows and `g` (`gap`) the initial normal gaps.  The KKT conditions are
//!
//! ```text
//! A x − f + Bᵀ λ = 0,   B x ≤ g,   λ ≥ 0,   λᵢ (g − B x)ᵢ = 0,
//! ```
//!
//! with λ the contact forces.  [`kkt_residuals`] measures how far a pair (x, λ) is from them, the
//! same way for every backend, and [`checked_status`] turns a backend's own verdict into the
//! status the program reports: `solved` only when these residuals meet the requested tolerance.

use std::time::Duration;

use serde::Serialize;
use sprs::CsMat;

/// Sparse matrix type of the QP: compressed sparse columns, `f64` values.
pub type CscMatrix = CsMat<f64>;

/// Why a QP could not even be attempted (as opposed to a solve that did not converge, which is a
/// [`QpStatus`]).
#[derive(Debug, thiserror::Error)]
pub enum QpError {
    /// Matrix or vector dimensions disagree.
    #[error("QP dimensions disagree: {0}")]
    Dimensions(String),
    /// A matrix is not stored in compressed-sparse-column form.
    #[error("QP matrix `{0}` must be in CSC storage")]
    NotCsc(&'static str),
    /// An entry is NaN or infinite.
    #[error("QP data `{0}` holds a NaN or infinite entry")]
    NotFinite(&'static str),
    /// The backend was not compiled in or cannot run on this problem.
    #[error("backend `{backend}` cannot run: {reason}")]
    Unavailable {
        /// Backend name.
        backend: &'static str,
        /// What is missing.
        reason: String,
    },
    /// The backend failed in a way it could not express as a status.
    #[error("backend `{backend}` failed: {reason}")]
    Backend {
        /// Backend name.
        backend: &'static str,
        /// The backend's message.
        reason: String,
    },
}

/// `min ½ xᵀ A x − fᵀ x  s.t.  B x ≤ g`, all matrices in CSC.
#[derive(Debug, Clone)]
pub struct QpProblem {
    /// A: symmetric stiffness on the free DOFs, n×n, both triangles stored.
    pub stiffness: CscMatrix,
    /// f: load vector, length n.
    pub load: Vec<f64>,
    /// B: contact constraint rows, m×n.
    pub constraints: CscMatrix,
    /// g: right-hand side of the constraints (initial gaps), length m.
    pub gap: Vec<f64>,
    /// A basis of the null space of A known from the model (rigid-body modes of bodies that only
    /// contact holds), each vector of length n; empty when A is positive definite.
    pub kernel: Vec<Vec<f64>>,
}

impl QpProblem {
    /// Checks dimensions, storage and finiteness, then builds the problem.
    ///
    /// ```
    /// use signorini_core::qp::QpProblem;
    /// use sprs::TriMat;
    /// let mut a = TriMat::new((1, 1));
    /// a.add_triplet(0, 0, 2.0);
    /// let mut b = TriMat::new((1, 1));
    /// b.add_triplet(0, 0, 1.0);
    /// let qp = QpProblem::try_new(a.to_csc(), vec![4.0], b.to_csc(), vec![1.0]).unwrap();
    /// assert_eq!((qp.dofs(), qp.rows()), (1, 1));
    /// ```
    pub fn try_new(
        stiffness: CscMatrix,
        load: Vec<f64>,
        constraints: CscMatrix,
        gap: Vec<f64>,
    ) -> Result<Self, QpError> {
        let problem = Self {
            stiffness,
            load,
            constraints,
            gap,
            kernel: Vec::new(),
        };
        problem.validate()?;
        Ok(problem)
    }

    /// Checks dimensions, CSC storage and finiteness.  The fields are public, so a backend calls
    /// this before handing the data to a solver whose constructors assert.
    pub fn validate(&self) -> Result<(), QpError> {
        let n = self.stiffness.rows();
        if self.stiffness.cols() != n {
            return Err(QpError::Dimensions(format!(
                "A is {}×{}, not square",
                n,
                self.stiffness.cols()
            )));
        }
        if self.load.len() != n {
            return Err(QpError::Dimensions(format!(
                "f has length {} but A is {n}×{n}",
                self.load.len()
            )));
        }
        if self.constraints.cols() != n {
            return Err(QpError::Dimensions(format!(
                "B has {} columns but A is {n}×{n}",
                self.constraints.cols()
            )));
        }
        if self.gap.len() != self.constraints.rows() {
            return Err(QpError::Dimensions(format!(
                "g has length {} but B has {} rows",
                self.gap.len(),
                self.constraints.rows()
            )));
        }
        if let Some(v) = self.kernel.iter().find(|v| v.len() != n) {
            return Err(QpError::Dimensions(format!(
                "kernel vector has length {} but A is {n}×{n}",
                v.len()
            )));
        }
        if !self.stiffness.is_csc() {
            return Err(QpError::NotCsc("A"));
        }
        if !self.constraints.is_csc() {
            return Err(QpError::NotCsc("B"));
        }
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        if !finite(self.stiffness.data()) {
            return Err(QpError::NotFinite("A"));
        }
        if !finite(&self.load) {
            return Err(QpError::NotFinite("f"));
        }
        if !finite(self.constraints.data()) {
            return Err(QpError::NotFinite("B"));
        }
        if !finite(&self.gap) {
            return Err(QpError::NotFinite("g"));
        }
        if self.kernel.iter().any(|v| !finite(v)) {
            return Err(QpError::NotFinite("kernel"));
        }
        Ok(())
    }
    /// Attaches a known null-space basis of A (see [`QpProblem::kernel`]).
    pub fn with_kernel(mut self, kernel: Vec<Vec<f64>>) -> Result<Self, QpError> {
        self.kernel = kernel;
        self.validate()?;
        Ok(self)
    }

    /// Number of unknowns n.
    pub fn dofs(&self) -> usize {
        self.stiffness.rows()
    }

    /// Number of constraint rows m.
    pub fn rows(&self) -> usize {
        self.constraints.rows()
    }

    /// The objective ½ xᵀ A x − fᵀ x.
    pub fn objective(&self, x: &[f64]) -> f64 {
        let ax = mat_vec(&self.stiffness, x);
        0.5 * dot(x, &ax) - dot(&self.load, x)
    }
}

/// What became of a solve.  Not converging is data, not an error.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
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
}

impl QpStatus {
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
        }
    }
}

impl std::fmt::Display for QpStatus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Settings common to every backend.  Backend-specific knobs live in the backend crates.
#[derive(Debug, Clone)]
pub struct SolveOptions {
    /// Relative KKT tolerance the answer must meet to be called `solved` (see [`KktResiduals`]).
    /// Default `1e-9`.
    pub tol: f64,
    /// Iteration cap; `None` lets the backend choose.  Default `None`.
    pub max_iter: Option<usize>,
    /// Wall-clock limit; `None` for none.  Default `None`.
    pub time_limit: Option<Duration>,
    /// Print the backend's own progress.  Default `false`.
    pub verbose: bool,
}

impl Default for SolveOptions {
    fn default() -> Self {
        Self {
            tol: 1e-9,
            max_iter: None,
            time_limit: None,
            verbose: false,
        }
    }
}

/// A backend's answer: primal x, multipliers λ ≥ 0 (one per constraint row), and how it went.
#[derive(Debug, Clone)]
pub struct QpSolution {
    /// Primal solution x (length n).
    pub x: Vec<f64>,
    /// Multipliers λ of B x ≤ g (length m), the contact forces.
    pub multipliers: Vec<f64>,
    /// The backend's own verdict (to be passed through [`checked_status`]).
    pub status: QpStatus,
    /// Iterations the backend took (its own notion of an iteration).
    pub iterations: usize,
    /// Wall-clock time inside the backend, including its setup and factorisations.
    pub solve_time: Duration,
    /// Free-form note from the backend (why it stopped, what it detected).
    pub message: Option<String>,
}

/// A QP algorithm.
///
/// ```
/// use signorini_core::qp::{QpBackend, QpProblem, QpSolution, QpStatus, QpError, SolveOptions};
/// /// A "backend" that only knows the unconstrained answer of a 1×1 problem.
/// struct Scalar;
/// impl QpBackend for Scalar {
///     fn name(&self) -> &'static str { "scalar" }
///     fn solve(&mut self, p: &QpProblem, _: &SolveOptions) -> Result<QpSolution, QpError> {
///         let a = p.stiffness.data()[0];
///         Ok(QpSolution { x: vec![p.load[0] / a], multipliers: vec![], status: QpStatus::Solved,
///             iterations: 1, solve_time: Default::default(), message: None })
///     }
/// }
/// ```
pub trait QpBackend: Send {
    /// Short name used on the command line and in reports (`"clarabel"`, `"dual-pgs"`, …).
    fn name(&self) -> &'static str;
    /// Solves the problem.  `Err` only when the backend cannot run at all.
    fn solve(&mut self, problem: &QpProblem, options: &SolveOptions)
        -> Result<QpSolution, QpError>;
}

/// How far (x, λ) is from the KKT conditions.  All but `max_penetration` are dimensionless.
///
/// With the scales `F = max(‖f‖∞, ‖Ax‖∞, ‖Bᵀλ‖∞)` and `X = ‖x‖∞`:
/// * `max_penetration` = max(0, maxᵢ (Bx − g)ᵢ), in the problem's length unit;
/// * `relative_penetration` = `max_penetration` / X;
/// * `stationarity` = ‖Ax − f + Bᵀλ‖∞ / F;
/// * `complementarity` = maxᵢ |λᵢ (g − Bx)ᵢ| / (F X);
/// * `min_multiplier` = min(0, minᵢ λᵢ) / F (zero when every λᵢ ≥ 0).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Default)]
pub struct KktResiduals {
    /// Largest constraint violation max(0, Bx − g), in length units.
    pub max_penetration: f64,
    /// `max_penetration` relative to the largest displacement.
    pub relative_penetration: f64,
    /// Relative equilibrium residual ‖Ax − f + Bᵀλ‖∞ / F.
    pub stationarity: f64,
    /// Relative complementarity maxᵢ |λᵢ sᵢ| / (F X).
    pub complementarity: f64,
    /// Most negative multiplier relative to F (≤ 0).
    pub min_multiplier: f64,
}

impl KktResiduals {
    /// The worst of the four dimensionless measures.
    pub fn worst(&self) -> f64 {
        let m = self
            .relative_penetration
            .max(self.stationarity)
            .max(self.complementarity)
            .max(-self.min_multiplier);
        if m.is_nan() {
            f64::INFINITY
        } else {
            m
        }
    }

    /// True when every dimensionless measure is at most `tol` (and none is NaN).
    pub fn meet(&self, tol: f64) -> bool {
        self.worst() <= tol
    }

    /// Multiplies the length-valued field by `length` (to report in the user's units).
    pub fn with_length_scale(mut self, length: f64) -> Self {
        self.max_penetration *= length;
        self
    }
}

/// Smallest scale used as a denominator, so that an all-zero problem gives zero residuals.
const TINY: f64 = 1e-300;

/// The KKT residuals of (x, λ) for `problem`; see [`KktResiduals`] for the definitions.
///
/// ```
/// use signorini_core::qp::{kkt_residuals, QpProblem};
/// use sprs::TriMat;
/// // min x² − 4x  s.t. x ≤ 1  →  x = 1, λ = 2.
/// let mut a = TriMat::new((1, 1)); a.add_triplet(0, 0, 2.0);
/// let mut b = TriMat::new((1, 1)); b.add_triplet(0, 0, 1.0);
/// let qp = QpProblem::try_new(a.to_csc(), vec![4.0], b.to_csc(), vec![1.0]).unwrap();
/// let r = kkt_residuals(&qp, &[1.0], &[2.0]);
/// assert!(r.meet(1e-15));
/// assert!(!kkt_residuals(&qp, &[1.1], &[2.0]).meet(1e-3));
/// ```
pub fn kkt_residuals(problem: &QpProblem, x: &[f64], multipliers: &[f64]) -> KktResiduals {
    if x.len() != problem.dofs()
        || multipliers.len() != problem.rows()
        || x.iter().chain(multipliers).any(|v| !v.is_finite())
    {
        return KktResiduals {
            max_penetration: f64::INFINITY,
            relative_penetration: f64::INFINITY,
            stationarity: f64::INFINITY,
            complementarity: f64::INFINITY,
            min_multiplier: f64::NEG_INFINITY,
        };
    }
    let ax = mat_vec(&problem.stiffness, x);
    let bx = mat_vec(&problem.constraints, x);
    let btl = mat_t_vec(&problem.constraints, multipliers);
    let force_scale = norm_inf(&problem.load)
        .max(norm_inf(&ax))
        .max(norm_inf(&btl))
        .max(TINY);
    let length_scale = norm_inf(x).max(TINY);

    let stationarity = ax
        .iter()
        .zip(&problem.load)
        .zip(&btl)
        .map(|((a, f), b)| (a - f + b).abs())
        .fold(0.0, f64::max)
        / force_scale;
    let mut max_penetration = 0.0_f64;
    let mut complementarity = 0.0_f64;
    for ((bxi, gi), li) in bx.iter().zip(&problem.gap).zip(multipliers) {
        let slack = gi - bxi;
        max_penetration = max_penetration.max(-slack);
        complementarity = complementarity.max((li * slack).abs());
    }
    let min_multiplier = multipliers.iter().copied().fold(0.0, f64::min) / force_scale;
    KktResiduals {
        max_penetration,
        relative_penetration: max_penetration / length_scale,
        stationarity,
        // F·X can underflow to 0 when both are tiny: keep the quotient finite.
        complementarity: complementarity / (force_scale * length_scale).max(TINY),
        min_multiplier,
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

/// Column pointers, row indices and values of a CSC matrix, keeping only the entries with
/// `keep(row, col)` (e.g. `|i, j| i <= j` for the upper triangle solvers want); rows stay sorted
/// within each column.
pub fn csc_parts(
    matrix: &CscMatrix,
    keep: impl Fn(usize, usize) -> bool,
) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
    let mut colptr = Vec::with_capacity(matrix.cols() + 1);
    let mut rows = Vec::with_capacity(matrix.nnz());
    let mut values = Vec::with_capacity(matrix.nnz());
    colptr.push(0);
    for (col, column) in matrix.outer_iterator().enumerate() {
        for (row, &value) in column.iter() {
            if keep(row, col) {
                rows.push(row);
                values.push(value);
            }
        }
        colptr.push(rows.len());
    }
    (colptr, rows, values)
}

/// Scalar scaling that makes a QP dimensionless: x = `displacement` · x̂, A = `stiffness` · Â,
/// f = `stiffness`·`displacement` · f̂, g = `displacement` · ĝ, λ = `stiffness`·`displacement` · λ̂.
///
/// Backends only ever see the scaled problem, so results do not depend on the user's units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QpScaling {
    /// Stiffness unit (the mean diagonal of A).
    pub stiffness: f64,
    /// Displacement unit (‖f‖∞ / stiffness unit, or the largest finite gap when unloaded).
    pub displacement: f64,
}

impl QpScaling {
    /// Scales chosen from the problem's data; all-zero data gives unit scales.
    pub fn of(problem: &QpProblem) -> Self {
        let n = problem.dofs();
        let diag_sum: f64 = (0..n)
            .map(|j| problem.stiffness.get(j, j).copied().unwrap_or(0.0).abs())
            .sum();
        let stiffness = if n > 0 && diag_sum > 0.0 {
            diag_sum / n as f64
        } else {
            1.0
        };
        let load = norm_inf(&problem.load);
        let displacement = if load > 0.0 {
            load / stiffness
        } else {
            let gap = norm_inf(&problem.gap);
            if gap > 0.0 {
                gap
            } else {
                1.0
            }
        };
        Self {
            stiffness,
            displacement,
        }
    }

    /// Turns `problem` into the dimensionless Â, f̂, B, ĝ without a copy.
    pub fn scale_in_place(&self, problem: &mut QpProblem) {
        let force = self.stiffness * self.displacement;
        problem
            .stiffness
            .data_mut()
            .iter_mut()
            .for_each(|v| *v /= self.stiffness);
        problem.load.iter_mut().for_each(|v| *v /= force);
        problem.gap.iter_mut().for_each(|v| *v /= self.displacement);
    }

    /// The dimensionless problem Â, f̂, B, ĝ.
    pub fn scale(&self, problem: &QpProblem) -> QpProblem {
        let force = self.stiffness * self.displacement;
        QpProblem {
            stiffness: problem.stiffness.map(|v| v / self.stiffness),
            load: problem.load.iter().map(|v| v / force).collect(),
            constraints: problem.constraints.clone(),
            gap: problem.gap.iter().map(|v| v / self.displacement).collect(),
            kernel: problem.kernel.clone(),
        }
    }

    /// Brings a solution of the scaled problem back to the original units.
    pub fn unscale(&self, mut solution: QpSolution) -> QpSolution {
        let force = self.stiffness * self.displacement;
        solution.x.iter_mut().for_each(|v| *v *= self.displacement);
        solution.multipliers.iter_mut().for_each(|v| *v *= force);
        solution
    }
}

/// y = M x for a CSC matrix.
pub fn mat_vec(m: &CscMatrix, x: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; m.rows()];
    for (j, col) in m.outer_iterator().enumerate() {
        let xj = x[j];
        if xj != 0.0 {
            for (i, v) in col.iter() {
                y[i] += v * xj;
            }
        }
    }
    y
}

/// y = Mᵀ x for a CSC matrix.
pub fn mat_t_vec(m: &CscMatrix, x: &[f64]) -> Vec<f64> {
    m.outer_iterator()
        .map(|col| col.iter().map(|(i, v)| v * x[i]).sum())
        .collect()
}

/// Dot product.
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Largest absolute entry (0 for an empty slice).
pub fn norm_inf(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use sprs::TriMat;

    fn tiny() -> QpProblem {
        // min ½(x0² + x1²) − x0 − x1  s.t.  x0 + x1 ≤ 1   →  x = (½, ½), λ = ½
        let mut a = TriMat::new((2, 2));
        a.add_triplet(0, 0, 1.0);
        a.add_triplet(1, 1, 1.0);
        let mut b = TriMat::new((1, 2));
        b.add_triplet(0, 0, 1.0);
        b.add_triplet(0, 1, 1.0);
        QpProblem::try_new(a.to_csc(), vec![1.0, 1.0], b.to_csc(), vec![1.0]).unwrap()
    }

    #[test]
    fn all_zero_problem_has_finite_zero_residuals() {
        let mut a = TriMat::new((1, 1));
        a.add_triplet(0, 0, 1.0);
        let b = TriMat::new((0, 1));
        let p = QpProblem::try_new(a.to_csc(), vec![0.0], b.to_csc(), vec![]).unwrap();
        let r = kkt_residuals(&p, &[0.0], &[]);
        assert_eq!(r, KktResiduals::default());
    }

    #[test]
    fn exact_optimum_has_zero_residuals() {
        let r = kkt_residuals(&tiny(), &[0.5, 0.5], &[0.5]);
        assert_eq!(r.worst(), 0.0);
    }

    #[test]
    fn each_violation_is_seen() {
        let p = tiny();
        assert!(kkt_residuals(&p, &[0.6, 0.6], &[0.4]).relative_penetration > 0.1);
        assert!(kkt_residuals(&p, &[0.5, 0.5], &[0.0]).stationarity > 0.1);
        assert!(kkt_residuals(&p, &[0.4, 0.4], &[0.6]).complementarity > 0.01);
        let neg = kkt_residuals(&p, &[1.0, 1.0], &[-0.5]);
        assert!(neg.min_multiplier < -0.1);
        let nan = kkt_residuals(&p, &[f64::NAN, 0.5], &[0.5]);
        assert_eq!(
            checked_status(QpStatus::Solved, &nan, 1e-6),
            QpStatus::NumericalError
        );
        // An infeasibility certificate is kept even though its x is no solution.
        assert_eq!(
            checked_status(QpStatus::PrimalInfeasible, &nan, 1e-6),
            QpStatus::PrimalInfeasible
        );
    }

    #[test]
    fn solved_is_downgraded_when_residuals_miss() {
        let p = tiny();
        let r = kkt_residuals(&p, &[0.5, 0.5 + 1e-6], &[0.5]);
        assert_eq!(
            checked_status(QpStatus::Solved, &r, 1e-9),
            QpStatus::Inaccurate
        );
        assert_eq!(checked_status(QpStatus::Solved, &r, 1e-3), QpStatus::Solved);
        assert_eq!(
            checked_status(QpStatus::MaxIterations, &r, 1e-3),
            QpStatus::MaxIterations
        );
    }

    #[test]
    fn scaling_round_trips_and_preserves_residuals() {
        let mut p = tiny();
        p.stiffness = p.stiffness.map(|v| v * 2e11);
        p.load = p.load.iter().map(|v| v * 2e11 * 1e-5).collect();
        p.gap = p.gap.iter().map(|v| v * 1e-5).collect();
        let s = QpScaling::of(&p);
        let scaled = s.scale(&p);
        assert!((scaled.load[0] - 1.0).abs() < 1e-12);
        let sol = QpSolution {
            x: vec![0.5, 0.5],
            multipliers: vec![0.5],
            status: QpStatus::Solved,
            iterations: 0,
            solve_time: Duration::ZERO,
            message: None,
        };
        let back = s.unscale(sol);
        let r = kkt_residuals(&p, &back.x, &back.multipliers);
        assert!(r.meet(1e-14), "{r:?}");
        assert!((back.x[0] - 0.5e-5).abs() < 1e-18);
    }

    #[test]
    fn rejects_bad_dimensions_and_nan() {
        let p = tiny();
        let err = QpProblem::try_new(
            p.stiffness.clone(),
            vec![1.0],
            p.constraints.clone(),
            vec![1.0],
        );
        assert!(matches!(err, Err(QpError::Dimensions(_))));
        let err = QpProblem::try_new(
            p.stiffness.clone(),
            vec![1.0, f64::NAN],
            p.constraints.clone(),
            vec![1.0],
        );
        assert!(matches!(err, Err(QpError::NotFinite("f"))));
    }
}
