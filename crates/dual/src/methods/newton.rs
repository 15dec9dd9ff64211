//! The linear algebra of one active-set (Newton) step: the system on the active rows F,
//!
//! ```text
//! [ H_FF  G_Fᵀ ] [ λ_F ]   [ r_F ]
//! [ G_F    0   ] [  μ  ] = [ r_e ],
//! ```
//!
//! factored once per active set and then applied to several right-hand sides (the first step
//! and the corrections of the refinement against the primal residual, see [`super::ssn`]).

use faer::linalg::solvers::Solve;
use faer::{Mat, Side};

use crate::hessian::DenseSym;
use crate::kernel::RigidModes;

/// Relative Tikhonov shift of the active block (× max Hᵢᵢ) so that dependent contact rows (a
/// singular but consistent H_FF) do not break the factorisation; its effect is removed by the
/// refinement.
const SHIFT: f64 = 1e-13;

/// Refinement steps against the unshifted dense matrix inside one solve (cheap: O(|F|²)).
const DENSE_REFINEMENT_STEPS: usize = 2;

/// A dense factorisation of the (shifted) Newton matrix.
enum Factor {
    /// Symmetric positive definite block (no kernel).
    Cholesky(faer::linalg::solvers::Llt<f64>),
    /// Indefinite bordered system, or a failed Cholesky.
    Lu(faer::linalg::solvers::PartialPivLu<f64>),
}

impl Factor {
    fn solve(&self, rhs: &mut Mat<f64>) {
        match self {
            Factor::Cholesky(llt) => llt.solve_in_place(rhs.as_mut()),
            Factor::Lu(lu) => lu.solve_in_place(rhs.as_mut()),
        }
    }
}

/// The factored Newton matrix of one active set.
pub struct DenseBlock {
    /// The active rows F, increasing.
    pub rows: Vec<usize>,
    kernel: usize,
    matrix: Mat<f64>,
    factor: Factor,
}

impl std::fmt::Debug for DenseBlock {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DenseBlock")
            .field("rows", &self.rows.len())
            .field("kernel", &self.kernel)
            .finish()
    }
}

impl DenseBlock {
    /// Factors the bordered matrix of the rows where `active` is true.
    pub fn factor(hessian: &DenseSym, modes: &RigidModes, active: &[bool]) -> Self {
        let rows: Vec<usize> = (0..active.len()).filter(|&i| active[i]).collect();
        let p = rows.len();
        let k = modes.count();
        let size = p + k;
        let max_diag = (0..hessian.size)
            .map(|i| hessian.diag(i))
            .fold(0.0, f64::max);
        let shift = SHIFT * max_diag;
        let matrix = Mat::<f64>::from_fn(size, size, |a, b| match (a < p, b < p) {
            (true, true) => hessian.col(rows[b])[rows[a]],
            (true, false) => modes.coupling[b - p][rows[a]],
            (false, true) => modes.coupling[a - p][rows[b]],
            (false, false) => 0.0,
        });
        let shifted = Mat::<f64>::from_fn(size, size, |a, b| {
            matrix[(a, b)] + if a == b && a < p { shift } else { 0.0 }
        });
        let factor = if k == 0 {
            match shifted.llt(Side::Lower) {
                Ok(llt) => Factor::Cholesky(llt),
                Err(_) => Factor::Lu(shifted.partial_piv_lu()),
            }
        } else {
            Factor::Lu(shifted.partial_piv_lu())
        };
        Self {
            rows,
            kernel: k,
            matrix,
            factor,
        }
    }

    /// Solves for (λ_F, μ) given (r_F, r_e); `None` when the result is not finite (a singular
    /// system).
    pub fn solve(&self, rhs_rows: &[f64], rhs_kernel: &[f64]) -> Option<(Vec<f64>, Vec<f64>)> {
        let p = self.rows.len();
        let size = p + self.kernel;
        let rhs = Mat::<f64>::from_fn(size, 1, |a, _| {
            if a < p {
                rhs_rows[a]
            } else {
                rhs_kernel[a - p]
            }
        });
        let mut solution = rhs.clone();
        self.factor.solve(&mut solution);
        for _ in 0..DENSE_REFINEMENT_STEPS {
            let mut residual = &rhs - &self.matrix * &solution;
            self.factor.solve(&mut residual);
            solution += residual;
        }
        if (0..size).any(|a| !solution[(a, 0)].is_finite()) {
            return None;
        }
        let lambda = (0..p).map(|a| solution[(a, 0)]).collect();
        let mu = (p..size).map(|a| solution[(a, 0)]).collect();
        Some((lambda, mu))
    }
}
