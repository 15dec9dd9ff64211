//! The condensed dual form: any [`QpBackend`] run on the dual of the contact QP instead of the
//! primal.
//!
//! The primal
//!
//! ```text
//! minimise ½ xᵀ A x − fᵀ x   subject to   B x ≤ g          (A: n × n, positive definite)
//! ```
//!
//! has the dual, on the contact multipliers alone,
//!
//! ```text
//! minimise ½ λᵀ H λ − dᵀ λ   subject to   λ ≥ 0,
//! H = B A⁻¹ Bᵀ (m × m, dense),   d = B A⁻¹ f − g,   and then   x = A⁻¹ (f − Bᵀ λ).
//! ```
//!
//! [`CondensedDual`] forms H with one sparse Cholesky factorisation of A
//! ([`SparseCholesky`]) and multi-right-hand-side solves `A Y = Bᵀ` in blocks of columns
//! (`H = B Y`, symmetrised), hands the dual to its inner backend as an ordinary [`QpProblem`]
//! (stiffness H stored as a full CSC matrix, load d, constraints −I, gap 0) and maps the answer
//! back: λ is the inner x (clipped at 0), x = A⁻¹(f − Bᵀλ).  The inner multipliers μ = Hλ − d
//! are the slacks g − Bx, so the primal KKT conditions are those of the inner problem: the core
//! checks (x, λ) on the primal as for every backend.
//!
//! The inner backend judges its answer on the dual's residuals, whose scales differ from the
//! primal's; when it says `solved` but the primal residuals miss the tolerance, the dual is solved
//! again with the tolerance ×10⁻² (twice at most, while time remains).
//!
//! Limits: H takes 8 m² bytes (and its CSC row indices as many again), checked with
//! [`crate::memory::check_fits`] before anything is allocated; a body held only by contact
//! (a non-empty [`QpProblem::kernel`]: A is singular, A⁻¹ does not exist) is refused with
//! [`QpError::Unavailable`] — the dual backends (`dual-*`) handle that case with the FETI dual.
//!
//! ```
//! use signorini_qp::examples::two_rows;
//! use signorini_qp::{CondensedDual, QpBackend, QpProblem, QpSolution, QpStatus, QpError,
//!     SolveOptions};
//! /// Projected Gauss–Seidel on `min ½xᵀAx − fᵀx, x ≥ 0` written as `−x ≤ 0` (enough for a tiny
//! /// dual).
//! struct Pgs;
//! impl QpBackend for Pgs {
//!     fn name(&self) -> &'static str { "pgs" }
//!     fn solve_valid(&mut self, p: &QpProblem, _: &SolveOptions) -> Result<QpSolution, QpError> {
//!         let n = p.dofs();
//!         let a = |i: usize, j: usize| p.stiffness.get(i, j).copied().unwrap_or(0.0);
//!         let mut x = vec![0.0; n];
//!         for _ in 0..10_000 {
//!             for i in 0..n {
//!                 let r: f64 = p.load[i] - (0..n).map(|j| a(i, j) * x[j]).sum::<f64>();
//!                 x[i] = (x[i] + r / a(i, i)).max(0.0);
//!             }
//!         }
//!         let ax = signorini_qp::mat_vec(&p.stiffness, &x);
//!         let mu = ax.iter().zip(&p.load).map(|(h, d)| h - d).collect();
//!         Ok(QpSolution { x, multipliers: mu, status: QpStatus::Solved, iterations: 10_000,
//!             solve_time: Default::default(), message: None })
//!     }
//! }
//! let known = two_rows();
//! let mut dual = CondensedDual::new(Pgs, "pgs/dual");
//! let s = dual.solve(&known.problem, &SolveOptions::default())?;
//! assert!((s.x[0] - 0.5).abs() < 1e-12 && (s.multipliers[0] - 0.5).abs() < 1e-12);
//! # Ok::<(), QpError>(())
//! ```

use std::time::{Duration, Instant};

use sprs::{CsMat, TriMat};

use super::backend::{QpBackend, QpSolution, SolveOptions};
use super::blocks::ConstraintBlock;
use super::ops::{mat_t_vec, mat_vec};
use super::problem::{CscMatrix, QpError, QpProblem};
use super::residuals::kkt_residuals;
use super::status::{checked_status, QpStatus};
use crate::linalg::SparseCholesky;

/// Bytes the dual needs per entry of H: 8 for the value and 8 for its CSC row index, plus an
/// allowance of 24 for the inner backend's own copy and factorisation of H (clarabel copies the
/// upper triangle, with indices, into its KKT matrix and factors it densely filled; OSQP the
/// same).  Used only for the memory check.
pub const BYTES_PER_DUAL_ENTRY: f64 = 40.0;

/// Memory given to one block of right-hand sides `A Y = Bᵀ` (n × k doubles).
const BLOCK_BYTES: usize = 64 << 20;

/// Largest number of right-hand sides solved together.
const MAX_BLOCK: usize = 256;

/// Times the dual is solved again with a tolerance ×10⁻² when the inner backend calls it solved
/// but the primal residuals miss the tolerance.
const TIGHTENINGS: usize = 2;

/// An inner [`QpBackend`] run on the condensed dual of the problem (see the module docs).
#[derive(Debug, Clone)]
pub struct CondensedDual<B: QpBackend> {
    inner: B,
    name: &'static str,
}

impl<B: QpBackend> CondensedDual<B> {
    /// Runs `inner` on the dual; `name` is what reports call it (by convention
    /// `"<inner>/dual"`, e.g. `"clarabel/dual"`).
    pub fn new(inner: B, name: &'static str) -> Self {
        Self { inner, name }
    }

    /// The inner backend.
    pub fn inner(&self) -> &B {
        &self.inner
    }
}

/// The condensed dual of a problem and the factor of A that maps its answer back.
pub struct Condensed {
    /// The dual as a QP: stiffness H, load d, constraints −I, gap 0.
    pub dual: QpProblem,
    /// The Cholesky factor of A.
    pub factor: SparseCholesky,
}

impl std::fmt::Debug for Condensed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Condensed")
            .field("rows", &self.dual.dofs())
            .finish_non_exhaustive()
    }
}

/// What [`condense`] could not do, short of an error.
#[derive(Debug, Clone, PartialEq)]
pub enum CondenseStop {
    /// The time limit passed while H was being formed.
    TimeLimit,
    /// A is not positive definite (the message says where the factorisation stopped).
    Factorisation(String),
    /// H = B A⁻¹ Bᵀ or d overflows the floating-point range (a compliance beyond it).
    Overflow,
}

/// Forms the dual of `problem` (A positive definite: the kernel must be empty), stopping with
/// [`CondenseStop::TimeLimit`] if `deadline` passes between blocks of right-hand sides.
/// `backend` names the caller in errors.
pub fn condense(
    backend: &'static str,
    problem: &QpProblem,
    deadline: Option<Instant>,
) -> Result<Result<Condensed, CondenseStop>, QpError> {
    problem.validate()?;
    if !problem.kernel.is_empty() {
        return Err(QpError::Unavailable {
            backend,
            reason: format!(
                "the condensed dual needs A⁻¹, but {} rigid-body mode(s) are held by contact alone (A is singular); use the primal form or a dual-* backend (they handle floating bodies)",
                problem.kernel.len()
            ),
        });
    }
    let (n, m) = (problem.dofs(), problem.rows());
    let block = (BLOCK_BYTES / (8 * n.max(1)))
        .clamp(1, MAX_BLOCK)
        .min(m.max(1));
    let entries = (m as f64) * (m as f64);
    crate::memory::check_fits(
        backend,
        || format!("the dense dual Hessian H = B A⁻¹ Bᵀ ({m} × {m}) with the inner solver's copy"),
        entries * BYTES_PER_DUAL_ENTRY + (8 * n * block) as f64,
    )?;
    let factor = match SparseCholesky::factor(&problem.stiffness) {
        Ok(f) => f,
        Err(e) => return Ok(Err(CondenseStop::Factorisation(e.to_string()))),
    };
    let Some(mut data) = hessian_columns(&factor, &problem.constraints, block, deadline) else {
        return Ok(Err(CondenseStop::TimeLimit));
    };
    symmetrise(&mut data, m);
    let indptr: Vec<usize> = (0..=m).map(|j| j * m).collect();
    let indices: Vec<usize> = (0..m * m).map(|k| k % m.max(1)).collect();
    let hessian =
        CsMat::try_new_csc((m, m), indptr, indices, data).map_err(|e| QpError::Backend {
            backend,
            reason: format!("building H as CSC: {}", e.3),
        })?;
    let mut a_inv_f = problem.load.clone();
    factor.solve_in_place(&mut a_inv_f);
    let d: Vec<f64> = mat_vec(&problem.constraints, &a_inv_f)
        .iter()
        .zip(&problem.gap)
        .map(|(v, g)| v - g)
        .collect();
    if !(hessian.data().iter().chain(&d).all(|v| v.is_finite())) {
        return Ok(Err(CondenseStop::Overflow));
    }
    let dual = dual_problem(hessian, d);
    Ok(Ok(Condensed { dual, factor }))
}

/// H = B A⁻¹ Bᵀ, column-major (m × m), from `A Y = Bᵀ` solved for `block` right-hand sides at
/// a time (H = B Y); `None` when `deadline` passes between blocks.
fn hessian_columns(
    factor: &SparseCholesky,
    b: &CscMatrix,
    block: usize,
    deadline: Option<Instant>,
) -> Option<Vec<f64>> {
    let (m, n) = (b.rows(), b.cols());
    let rows = b.to_csr();
    let mut data = vec![0.0; m * m];
    let mut y = vec![0.0; n * block];
    let mut start = 0;
    while start < m {
        if deadline.is_some_and(|d| Instant::now() >= d) {
            return None;
        }
        let k = block.min(m - start);
        let y = &mut y[..n * k];
        y.iter_mut().for_each(|v| *v = 0.0);
        for c in 0..k {
            if let Some(row) = rows.outer_view(start + c) {
                for (j, &v) in row.iter() {
                    y[c * n + j] = v;
                }
            }
        }
        factor.solve_many_in_place(y);
        for c in 0..k {
            let yc = &y[c * n..(c + 1) * n];
            let column = &mut data[(start + c) * m..(start + c + 1) * m];
            for (j, col) in b.outer_iterator().enumerate() {
                let yj = yc[j];
                if yj != 0.0 {
                    for (i, v) in col.iter() {
                        column[i] += v * yj;
                    }
                }
            }
        }
        start += k;
    }
    Some(data)
}

/// H is symmetric in exact arithmetic; make it so in floating point (the inner solvers read
/// one triangle, the residual checks both): each pair of entries becomes its mean.
fn symmetrise(data: &mut [f64], m: usize) {
    for j in 0..m {
        for i in 0..j {
            let mean = 0.5 * (data[j * m + i] + data[i * m + j]);
            data[j * m + i] = mean;
            data[i * m + j] = mean;
        }
    }
}

/// The dual as a QP: stiffness H, load d, constraints −I, gap 0, one non-negative block.
fn dual_problem(hessian: CscMatrix, d: Vec<f64>) -> QpProblem {
    let m = d.len();
    let mut minus_identity = TriMat::new((m, m));
    for i in 0..m {
        minus_identity.add_triplet(i, i, -1.0);
    }
    QpProblem {
        stiffness: hessian,
        load: d,
        constraints: minus_identity.to_csc(),
        gap: vec![0.0; m],
        kernel: Vec::new(),
        blocks: vec![ConstraintBlock::NonNegative { rows: m }],
    }
}

/// x = A⁻¹ (f − Bᵀ λ).
pub fn primal_of(problem: &QpProblem, factor: &SparseCholesky, multipliers: &[f64]) -> Vec<f64> {
    let bt_l = mat_t_vec(&problem.constraints, multipliers);
    let mut x: Vec<f64> = problem.load.iter().zip(&bt_l).map(|(f, b)| f - b).collect();
    factor.solve_in_place(&mut x);
    x
}

/// The answer of a run that stopped without one: x = 0, λ = 0, `status`, `message`.
fn stopped(
    problem: &QpProblem,
    status: QpStatus,
    start: Instant,
    iterations: usize,
    message: String,
) -> QpSolution {
    QpSolution {
        x: vec![0.0; problem.dofs()],
        multipliers: vec![0.0; problem.rows()],
        status,
        iterations,
        solve_time: start.elapsed(),
        message: Some(message),
    }
}

/// The answer when [`condense`] could not form the dual.
fn not_condensed(problem: &QpProblem, stop: CondenseStop, start: Instant) -> QpSolution {
    let (status, message) = match stop {
        CondenseStop::TimeLimit => (
            QpStatus::TimeLimit,
            "the time limit passed while the dual Hessian was being formed".into(),
        ),
        CondenseStop::Factorisation(e) => (
            QpStatus::NumericalError,
            format!("the condensed dual needs A⁻¹: {e}"),
        ),
        CondenseStop::Overflow => (
            QpStatus::NumericalError,
            "the condensed dual H = B A⁻¹ Bᵀ (or its load d) overflows the floating-point range: a compliance beyond it; use the primal form".into(),
        ),
    };
    stopped(problem, status, start, 0, message)
}

/// The time left before `deadline` (`Some(None)` without one); `None` once it has passed.
fn time_left(deadline: Option<Instant>) -> Option<Option<Duration>> {
    match deadline {
        Some(d) => match d.checked_duration_since(Instant::now()) {
            Some(r) if r > Duration::ZERO => Some(Some(r)),
            _ => None,
        },
        None => Some(None),
    }
}

/// The inner backend's verdict on the dual as a verdict on the primal.
fn primal_status(inner: QpStatus) -> QpStatus {
    match inner {
        // The dual unbounded below is the primal without a feasible point.
        QpStatus::DualInfeasible => QpStatus::PrimalInfeasible,
        // λ = 0 is always feasible for the dual: a certificate cannot be right.
        QpStatus::PrimalInfeasible => QpStatus::NumericalError,
        other => other,
    }
}

/// What one solve of the dual gave.
enum Round {
    /// The final answer: the inner backend failed or certified infeasibility.
    Stopped(QpSolution),
    /// (x, λ) mapped back to the primal, and whether the inner backend said `solved` while
    /// the primal residuals miss the tolerance (a tighter inner tolerance may help).
    Answer {
        /// The answer (its `solve_time` is set when it is handed out).
        solution: QpSolution,
        /// Solved on the dual, not on the primal.
        tighten: bool,
    },
}

/// Where the solve of a condensed dual stands: the problem, its dual, and the clock.
struct DualRun<'a> {
    problem: &'a QpProblem,
    condensed: &'a Condensed,
    start: Instant,
    /// Time taken to form the dual.
    formed: Duration,
    /// Inner iterations so far.
    iterations: usize,
}

impl DualRun<'_> {
    /// Solves the dual with `inner` at `options` (its tolerance `options.tol`) and maps the
    /// answer back: λ = max(x_inner, 0), x = A⁻¹(f − Bᵀλ), judged on the primal residuals
    /// at `primal_tol`.
    fn round<B: QpBackend>(
        &mut self,
        inner: &mut B,
        options: &SolveOptions,
        primal_tol: f64,
    ) -> Result<Round, QpError> {
        let (problem, tol) = (self.problem, options.tol);
        let answer = inner.solve_in_given_units(&self.condensed.dual, options)?;
        self.iterations += answer.iterations;
        let status = primal_status(answer.status);
        let note = format!(
            "condensed dual ({m} × {m} H formed in {:.3} s, inner tolerance {tol:.0e}); {}: {}",
            self.formed.as_secs_f64(),
            inner.name(),
            answer.message.as_deref().unwrap_or("no message"),
            m = problem.rows(),
        );
        if matches!(
            status,
            QpStatus::PrimalInfeasible | QpStatus::NumericalError
        ) || answer.x.iter().any(|v| !v.is_finite())
        {
            let status = if status == QpStatus::PrimalInfeasible {
                status
            } else {
                QpStatus::NumericalError
            };
            let out = stopped(problem, status, self.start, self.iterations, note);
            return Ok(Round::Stopped(out));
        }
        let multipliers: Vec<f64> = answer.x.iter().map(|v| v.max(0.0)).collect();
        let x = primal_of(problem, &self.condensed.factor, &multipliers);
        let residuals = kkt_residuals(problem, &x, &multipliers);
        let met = checked_status(status, &residuals, primal_tol) == QpStatus::Solved;
        let solution = QpSolution {
            x,
            multipliers,
            status,
            iterations: self.iterations,
            solve_time: Duration::ZERO,
            message: Some(note),
        };
        let tighten = status == QpStatus::Solved && !met;
        Ok(Round::Answer { solution, tighten })
    }
}

impl<B: QpBackend> QpBackend for CondensedDual<B> {
    fn name(&self) -> &'static str {
        self.name
    }

    fn solve_valid(
        &mut self,
        problem: &QpProblem,
        options: &SolveOptions,
    ) -> Result<QpSolution, QpError> {
        let start = Instant::now();
        let deadline = options.time_limit.map(|t| start + t);
        let condensed = match condense(self.name, problem, deadline)? {
            Ok(c) => c,
            Err(stop) => return Ok(not_condensed(problem, stop, start)),
        };
        let mut run = DualRun {
            problem,
            condensed: &condensed,
            start,
            formed: start.elapsed(),
            iterations: 0,
        };
        let mut tol = options.tol;
        let mut tightenings = 0;
        loop {
            let Some(remaining) = time_left(deadline) else {
                let message = format!(
                    "the time limit passed after forming the dual Hessian ({:.3} s)",
                    run.formed.as_secs_f64()
                );
                let status = QpStatus::TimeLimit;
                return Ok(stopped(problem, status, start, run.iterations, message));
            };
            let inner_options = SolveOptions {
                tol,
                time_limit: remaining,
                ..options.for_another_problem()
            };
            match run.round(&mut self.inner, &inner_options, options.tol)? {
                Round::Stopped(out) => return Ok(out),
                Round::Answer { tighten, .. }
                    if tighten && tightenings < TIGHTENINGS && tol > 1e-14 =>
                {
                    tightenings += 1;
                    tol = (tol * 1e-2).max(1e-15);
                }
                Round::Answer { mut solution, .. } => {
                    solution.solve_time = start.elapsed();
                    return Ok(solution);
                }
            }
        }
    }
}

/// Whether `problem` can be condensed at all (A positive definite as far as the model knows:
/// no kernel).
pub fn condensable(problem: &QpProblem) -> bool {
    problem.kernel.is_empty()
}

/// Entries of the matrix B that a dual form touches: the number of distinct columns (DOFs) with a
/// nonzero in some row of B.
pub fn touched_dofs(b: &CscMatrix) -> usize {
    b.outer_iterator().filter(|col| col.nnz() > 0).count()
}
