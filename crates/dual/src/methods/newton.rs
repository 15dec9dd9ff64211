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

use signorini_qp::{dot, mat_t_vec, mat_vec};

use crate::dual::DualData;
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

/// Relative residual at which an inner (projected, preconditioned) CG solve stops; the outer
/// refinement against the primal residual supplies the remaining digits.
const CG_TOLERANCE: f64 = 1e-8;

/// The Newton system of one active set applied matrix-free: S_FF v = (B A⁺ Bᵀ v)_F through the
/// sparse factor (two triangular solves per product), solved by projected preconditioned CG on
/// {G_F λ_F = r_e}; no m × m array is ever formed.  The preconditioner is Jacobi with the
/// lumped compliance Dᵢ = Σⱼ Bᵢⱼ² / Aⱼⱼ (an estimate of Hᵢᵢ from the diagonal of A).
pub struct MatrixFreeBlock<'d, 'p> {
    data: &'d DualData<'p>,
    /// The active rows F, increasing.
    pub rows: Vec<usize>,
    /// Dᵢ on the rows F.
    diagonal: Vec<f64>,
    /// (G_F G_Fᵀ)⁻¹, k × k row-major.
    gram_inverse: Vec<f64>,
    /// G_F, k rows of length |F|.
    coupling: Vec<Vec<f64>>,
    /// CG iteration cap per solve.
    max_iter: usize,
    /// Stop polling (time limit).
    out_of_time: &'d dyn Fn() -> bool,
}

impl std::fmt::Debug for MatrixFreeBlock<'_, '_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MatrixFreeBlock")
            .field("rows", &self.rows.len())
            .finish()
    }
}

/// Dᵢ = Σⱼ Bᵢⱼ² / Aⱼⱼ (fixed DOFs skipped): the compliance of row i if every DOF were a lone
/// spring; positive for every row that touches a free DOF.
pub fn lumped_compliance(data: &DualData<'_>) -> Vec<f64> {
    let problem = data.problem;
    let mut d = vec![0.0; problem.rows()];
    for (j, col) in problem.constraints.outer_iterator().enumerate() {
        if data.inverse.reduced_index(j).is_none() {
            continue;
        }
        let a_jj = problem.stiffness.get(j, j).copied().unwrap_or(0.0);
        if a_jj > 0.0 {
            for (i, &b) in col.iter() {
                d[i] += b * b / a_jj;
            }
        }
    }
    let max = d.iter().copied().fold(0.0, f64::max);
    d.iter()
        .map(|v| v.max(1e-14 * max).max(f64::MIN_POSITIVE))
        .collect()
}

impl<'d, 'p> MatrixFreeBlock<'d, 'p> {
    /// The operator of the rows where `active` is true; `None` when the active rows do not hold
    /// every rigid mode (G_F G_Fᵀ singular).
    pub fn new(
        data: &'d DualData<'p>,
        active: &[bool],
        lumped: &[f64],
        out_of_time: &'d dyn Fn() -> bool,
    ) -> Option<Self> {
        let rows: Vec<usize> = (0..active.len()).filter(|&i| active[i]).collect();
        let diagonal = rows.iter().map(|&i| lumped[i]).collect();
        let coupling: Vec<Vec<f64>> = data
            .modes
            .coupling
            .iter()
            .map(|row| rows.iter().map(|&i| row[i]).collect())
            .collect();
        let k = coupling.len();
        let gram: Vec<f64> = (0..k * k)
            .map(|ab| dot(&coupling[ab / k], &coupling[ab % k]))
            .collect();
        let gram_inverse = invert_small(&gram, k)?;
        Some(Self {
            data,
            max_iter: (rows.len() + k).clamp(50, 5000),
            rows,
            diagonal,
            gram_inverse,
            coupling,
            out_of_time,
        })
    }

    /// S_FF v (one sparse solve).
    fn apply(&self, v: &[f64]) -> Vec<f64> {
        let mut full = vec![0.0; self.data.rows()];
        for (&i, x) in self.rows.iter().zip(v) {
            full[i] = *x;
        }
        let u = self
            .data
            .inverse
            .solve(&mat_t_vec(&self.data.problem.constraints, &full));
        let y = mat_vec(&self.data.problem.constraints, &u);
        self.rows.iter().map(|&i| y[i]).collect()
    }

    /// Q⁻¹ G_F v (length k).
    fn gram_solve(&self, v: &[f64]) -> Vec<f64> {
        let k = self.coupling.len();
        let gv: Vec<f64> = self.coupling.iter().map(|row| dot(row, v)).collect();
        (0..k)
            .map(|a| (0..k).map(|b| self.gram_inverse[a * k + b] * gv[b]).sum())
            .collect()
    }

    /// v − G_Fᵀ (G_F G_Fᵀ)⁻¹ G_F v: the projection onto {G_F v = 0}.
    fn project(&self, v: &mut [f64]) {
        if self.coupling.is_empty() {
            return;
        }
        let c = self.gram_solve(v);
        for (row, cj) in self.coupling.iter().zip(&c) {
            v.iter_mut().zip(row).for_each(|(x, g)| *x -= cj * g);
        }
    }

    /// Solves for (λ_F, μ) given (r_F, r_e) to [`CG_TOLERANCE`] (or the iteration cap); `None`
    /// when the iteration breaks down.
    pub fn solve(&self, rhs_rows: &[f64], rhs_kernel: &[f64]) -> Option<(Vec<f64>, Vec<f64>)> {
        let k = self.coupling.len();
        // λ₀ = G_Fᵀ Q⁻¹ r_e satisfies G_F λ₀ = r_e.
        let mut lambda = vec![0.0; self.rows.len()];
        if k > 0 {
            let c: Vec<f64> = (0..k)
                .map(|a| {
                    (0..k)
                        .map(|b| self.gram_inverse[a * k + b] * rhs_kernel[b])
                        .sum()
                })
                .collect();
            for (row, cj) in self.coupling.iter().zip(&c) {
                lambda.iter_mut().zip(row).for_each(|(x, g)| *x += cj * g);
            }
        }
        let mut s_lambda = if k > 0 {
            self.apply(&lambda)
        } else {
            vec![0.0; lambda.len()]
        };
        let mut residual: Vec<f64> = rhs_rows.iter().zip(&s_lambda).map(|(r, s)| r - s).collect();
        self.project(&mut residual);
        let start = dot(&residual, &residual).sqrt();
        let precondition = |r: &[f64]| -> Vec<f64> {
            let mut z: Vec<f64> = r.iter().zip(&self.diagonal).map(|(x, d)| x / d).collect();
            self.project(&mut z);
            z
        };
        let mut z = precondition(&residual);
        let mut direction = z.clone();
        let mut rz = dot(&residual, &z);
        for _ in 0..self.max_iter {
            if start == 0.0 || (self.out_of_time)() {
                break;
            }
            let s_dir = self.apply(&direction);
            let mut q = s_dir.clone();
            self.project(&mut q);
            let curvature = dot(&direction, &q);
            if curvature.is_nan() || curvature <= 0.0 {
                break;
            }
            let alpha = rz / curvature;
            lambda
                .iter_mut()
                .zip(&direction)
                .for_each(|(x, d)| *x += alpha * d);
            s_lambda
                .iter_mut()
                .zip(&s_dir)
                .for_each(|(x, d)| *x += alpha * d);
            residual
                .iter_mut()
                .zip(&q)
                .for_each(|(r, d)| *r -= alpha * d);
            if dot(&residual, &residual).sqrt() <= CG_TOLERANCE * start {
                break;
            }
            z = precondition(&residual);
            let rz_next = dot(&residual, &z);
            let beta = rz_next / rz;
            rz = rz_next;
            direction
                .iter_mut()
                .zip(&z)
                .for_each(|(d, zi)| *d = zi + beta * *d);
        }
        // μ: least squares G_Fᵀ μ ≈ r_F − S_FF λ_F.
        let rest: Vec<f64> = rhs_rows.iter().zip(&s_lambda).map(|(r, s)| r - s).collect();
        let mu = self.gram_solve(&rest);
        let finite = lambda.iter().chain(&mu).all(|v| v.is_finite());
        finite.then_some((lambda, mu))
    }
}

/// The inverse of a small k × k row-major matrix by Gauss–Jordan with partial pivoting; `None`
/// when it is (numerically) singular.
fn invert_small(matrix: &[f64], k: usize) -> Option<Vec<f64>> {
    let mut a = matrix.to_vec();
    let mut inv: Vec<f64> = (0..k * k)
        .map(|ab| if ab / k == ab % k { 1.0 } else { 0.0 })
        .collect();
    let scale = (0..k).map(|i| a[i * k + i].abs()).fold(0.0, f64::max);
    for c in 0..k {
        let pivot = (c..k).max_by(|&x, &y| a[x * k + c].abs().total_cmp(&a[y * k + c].abs()))?;
        if a[pivot * k + c].abs() <= 1e-12 * scale {
            return None;
        }
        for q in 0..k {
            a.swap(c * k + q, pivot * k + q);
            inv.swap(c * k + q, pivot * k + q);
        }
        let p = a[c * k + c];
        for q in 0..k {
            a[c * k + q] /= p;
            inv[c * k + q] /= p;
        }
        for r in 0..k {
            if r != c {
                let f = a[r * k + c];
                for q in 0..k {
                    a[r * k + q] -= f * a[c * k + q];
                    inv[r * k + q] -= f * inv[c * k + q];
                }
            }
        }
    }
    Some(inv)
}
