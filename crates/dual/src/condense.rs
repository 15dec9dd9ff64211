//! Condensation of A onto the contact rows: the dense dual Hessian H = B A⁺ Bᵀ (m × m).
//!
//! [`Condensation::TrailingBlock`] reads H off the factor with the contact DOFs last
//! (see [`crate::trailing`]); [`Condensation::MultiRhs`] solves A Y = Bᵀ for blocks of `block_size` right-hand sides with
//! the cached factor and keeps only B Y (the rows of Y that B touches).
//! [`Condensation::InteriorSchur`] lives in [`crate::schur`].

use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::{Accum, Mat, MatRef, Par};
use signorini_core::qp::CscMatrix;

use crate::dual::DualData;
use crate::error::DualError;
use crate::inverse::StiffnessInverse;
use crate::kernel::RigidModes;
use crate::settings::{Condensation, DualSettings};

/// A dense symmetric m × m matrix, column-major.
#[derive(Debug, Clone, PartialEq)]
pub struct DenseSym {
    /// Entries, column-major (equal to row-major by symmetry).
    pub values: Vec<f64>,
    /// Order m.
    pub size: usize,
}

impl DenseSym {
    /// Column (= row) `j`.
    pub fn col(&self, j: usize) -> &[f64] {
        &self.values[j * self.size..(j + 1) * self.size]
    }

    /// Diagonal entry (j, j).
    pub fn diag(&self, j: usize) -> f64 {
        self.values[j * self.size + j]
    }

    /// y = H v.
    pub fn mul(&self, v: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; self.size];
        for (j, vj) in v.iter().enumerate() {
            if *vj != 0.0 {
                y.iter_mut()
                    .zip(self.col(j))
                    .for_each(|(yi, hij)| *yi += vj * hij);
            }
        }
        y
    }

    /// Replaces H by (H + Hᵀ)/2 to remove round-off asymmetry.
    fn symmetrise(&mut self) {
        let m = self.size;
        for j in 0..m {
            for i in (j + 1)..m {
                let avg = 0.5 * (self.values[j * m + i] + self.values[i * m + j]);
                self.values[j * m + i] = avg;
                self.values[i * m + j] = avg;
            }
        }
    }

    /// H += c Gᵀ G, the augmented-Lagrangian penalty of the floating-body equality.
    pub fn add_penalty(&mut self, modes: &RigidModes, penalty: f64) {
        if penalty == 0.0 {
            return;
        }
        let m = self.size;
        for row in &modes.coupling {
            for (j, gj) in row.iter().enumerate() {
                if *gj != 0.0 {
                    let col = &mut self.values[j * m..(j + 1) * m];
                    col.iter_mut()
                        .zip(row)
                        .for_each(|(h, gi)| *h += penalty * gj * gi);
                }
            }
        }
    }

    /// λ_max estimated by power iteration (from above: the returned value is at least the
    /// Rayleigh quotient, raised by 5 %).
    pub fn largest_eigenvalue(&self, iterations: usize) -> f64 {
        power_iteration(self.size, iterations, |v| self.mul(v))
    }
}

/// λ_max of a symmetric positive semidefinite operator by power iteration from a fixed
/// pseudo-random positive vector; the largest Rayleigh quotient times 1.05 (a safety margin for
/// step sizes).  An operator that vanishes on every iterate gives 0.
pub fn power_iteration(
    size: usize,
    iterations: usize,
    mut apply: impl FnMut(&[f64]) -> Vec<f64>,
) -> f64 {
    if size == 0 {
        return 0.0;
    }
    let raw: Vec<f64> = (0..size)
        .map(|i| 1.0 + 0.5 * (1.0 + i as f64).sin())
        .collect();
    let raw_norm = raw.iter().map(|x| x * x).sum::<f64>().sqrt();
    let mut v: Vec<f64> = raw.iter().map(|x| x / raw_norm).collect();
    let mut estimate = 0.0_f64;
    for _ in 0..iterations {
        let w = apply(&v);
        let quotient: f64 = v.iter().zip(&w).map(|(a, b)| a * b).sum();
        let norm = w.iter().map(|x| x * x).sum::<f64>().sqrt();
        estimate = estimate.max(quotient);
        if !(norm > 0.0 && norm.is_finite()) {
            break;
        }
        v = w.iter().map(|x| x / norm).collect();
    }
    1.05 * estimate
}

/// H = B A⁺ Bᵀ by the strategy of `settings`.
pub fn dual_hessian(data: &DualData<'_>, settings: &DualSettings) -> Result<DenseSym, DualError> {
    if data.inverse.contact_last() {
        return Ok(trailing_hessian(
            data.inverse.factor().trailing(),
            data.inverse.trailing(),
            &data.problem.constraints,
        ));
    }
    match settings.condensation {
        // Too many contact DOFs to order last: fall back to multi-RHS solves.
        Condensation::TrailingBlock | Condensation::MultiRhs => Ok(multi_rhs(
            &data.inverse,
            &data.problem.constraints,
            settings.block_size,
        )),
        Condensation::InteriorSchur => crate::schur::interior_schur(data, settings.block_size),
    }
}

/// H = Yᵀ Y with Y = L_cc⁻¹ B_cᵀ; `touched[k]` is the full DOF of row/column k of L_cc.
pub fn trailing_hessian(
    factor: MatRef<'_, f64>,
    touched: &[usize],
    constraints: &CscMatrix,
) -> DenseSym {
    let m = constraints.rows();
    let mut y = Mat::<f64>::zeros(touched.len(), m);
    for (k, &j) in touched.iter().enumerate() {
        if let Some(col) = constraints.outer_view(j) {
            for (i, &v) in col.iter() {
                y[(k, i)] = v;
            }
        }
    }
    solve_lower_triangular_in_place(factor, y.as_mut(), Par::Seq);
    let mut h = Mat::<f64>::zeros(m, m);
    matmul(
        h.as_mut(),
        Accum::Replace,
        y.transpose(),
        y.as_ref(),
        1.0,
        Par::Seq,
    );
    let mut values = vec![0.0; m * m];
    for j in 0..m {
        for i in 0..m {
            values[j * m + i] = 0.5 * (h[(i, j)] + h[(j, i)]);
        }
    }
    DenseSym { values, size: m }
}

/// Columns of B with at least one entry that are not fixed: (full index, reduced index).
pub fn touched_columns(inverse: &StiffnessInverse, constraints: &CscMatrix) -> Vec<(usize, usize)> {
    constraints
        .outer_iterator()
        .enumerate()
        .filter(|(_, col)| col.nnz() > 0)
        .filter_map(|(j, _)| inverse.reduced_index(j).map(|r| (j, r)))
        .collect()
}

/// H = B (A⁺ Bᵀ), blocks of `block` right-hand sides at a time.
pub fn multi_rhs(inverse: &StiffnessInverse, constraints: &CscMatrix, block: usize) -> DenseSym {
    let m = constraints.rows();
    let nr = inverse.reduced_dim();
    let rows = constraints.to_csr();
    let touched = touched_columns(inverse, constraints);
    let mut h = DenseSym {
        values: vec![0.0; m * m],
        size: m,
    };
    let mut work = vec![0.0; nr * block.min(m.max(1))];
    for start in (0..m).step_by(block) {
        let count = block.min(m - start);
        let work = &mut work[..nr * count];
        work.fill(0.0);
        for k in 0..count {
            if let Some(row) = rows.outer_view(start + k) {
                for (j, v) in row.iter() {
                    if let Some(r) = inverse.reduced_index(j) {
                        work[k * nr + r] += v;
                    }
                }
            }
        }
        inverse.solve_reduced_many(work);
        for k in 0..count {
            let y = &work[k * nr..(k + 1) * nr];
            let col = &mut h.values[(start + k) * m..(start + k + 1) * m];
            for &(j, r) in &touched {
                let yr = y[r];
                if yr != 0.0 {
                    if let Some(bcol) = constraints.outer_view(j) {
                        for (i, v) in bcol.iter() {
                            col[i] += v * yr;
                        }
                    }
                }
            }
        }
    }
    h.symmetrise();
    h
}
