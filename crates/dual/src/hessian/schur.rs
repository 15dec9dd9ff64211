//! Condensation through the Schur complement on the touched DOFs.
//!
//! With c the DOFs that B touches and i the others (fixed DOFs of floating bodies removed),
//!
//! ```text
//! S = A_cc − A_ci A_ii⁻¹ A_ic,    H = B_c S⁻¹ B_cᵀ,
//! ```
//!
//! from one sparse factorisation of A_ii, multi-right-hand-side solves on the |c| columns of
//! A_ic, and a dense Cholesky of S.

use std::ops::Range;

use faer::linalg::solvers::Solve;
use faer::{Mat, Side};
use signorini_qp::linalg::SparseCholesky;
use signorini_qp::CscMatrix;

use super::dense::DenseSym;
use super::multi_rhs::{in_blocks, touched_columns};
use crate::dual::DualData;
use crate::error::DualError;

/// Where a full DOF sits in the split.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Part {
    /// Fixed DOF of a floating body (removed).
    Fixed,
    /// Interior DOF, with its index in A_ii.
    Interior(usize),
    /// Touched DOF, with its index in S.
    Touched(usize),
}

/// H = B_c S⁻¹ B_cᵀ via the interior factorisation; `block` right-hand sides at a time.
/// Stops with [`DualError::OutOfTime`] between blocks once `out_of_time` says so.
pub fn interior_schur(
    data: &DualData<'_>,
    block: usize,
    out_of_time: &dyn Fn() -> bool,
) -> Result<DenseSym, DualError> {
    let a = &data.problem.stiffness;
    let split = Split::new(data);
    let chol = if split.interior > 0 {
        let a_ii = interior_block(a, &split.part, split.interior)?;
        Some(
            SparseCholesky::factor(&a_ii).map_err(|source| DualError::Singular {
                source,
                kernel: data.modes.count(),
            })?,
        )
    } else {
        None
    };
    let schur = split.schur_complement(a, chol.as_ref(), block, out_of_time)?;
    split.condensed(&schur, &data.problem.constraints)
}

/// The DOFs split into fixed, interior and touched ones.
struct Split {
    /// Where each full DOF sits.
    part: Vec<Part>,
    /// Size of A_ii.
    interior: usize,
    /// The touched DOFs c: (full index, reduced index), in the order of S.
    touched: Vec<(usize, usize)>,
}

impl Split {
    /// The split of `data`'s DOFs: c the columns of B (not fixed), the interior numbered in
    /// order.
    fn new(data: &DualData<'_>) -> Self {
        let touched = touched_columns(&data.inverse, &data.problem.constraints);
        let mut part: Vec<Part> = (0..data.problem.stiffness.rows())
            .map(|j| match data.inverse.reduced_index(j) {
                Some(_) => Part::Interior(0),
                None => Part::Fixed,
            })
            .collect();
        for (k, &(j, _)) in touched.iter().enumerate() {
            part[j] = Part::Touched(k);
        }
        let mut interior = 0;
        for p in part.iter_mut() {
            if let Part::Interior(i) = p {
                *i = interior;
                interior += 1;
            }
        }
        Self {
            part,
            interior,
            touched,
        }
    }

    /// S = A_cc − A_ci A_ii⁻¹ A_ic, column by column block (`chol` the factor of A_ii, none
    /// when the interior is empty).
    fn schur_complement(
        &self,
        a: &CscMatrix,
        chol: Option<&SparseCholesky>,
        block: usize,
        out_of_time: &dyn Fn() -> bool,
    ) -> Result<Mat<f64>, DualError> {
        let (nc, interior) = (self.touched.len(), self.interior);
        let mut schur = Mat::<f64>::zeros(nc, nc);
        let mut work = vec![0.0; interior * block.min(nc.max(1))];
        let what = "forming the Schur complement on the contact DOFs";
        in_blocks(nc, block, what, out_of_time, |columns| {
            let work = &mut work[..interior * columns.len()];
            self.scatter(a, columns.clone(), work, &mut schur);
            if let Some(chol) = chol {
                chol.solve_many_in_place(work);
            }
            self.subtract_coupling(a, columns, work, &mut schur);
        })?;
        Ok(schur)
    }

    /// For the touched columns `columns` (positions in S): their interior part A_ic into
    /// `work` (zeroed first), their touched part A_cc added into `schur`.
    fn scatter(
        &self,
        a: &CscMatrix,
        columns: Range<usize>,
        work: &mut [f64],
        schur: &mut Mat<f64>,
    ) {
        let (interior, start) = (self.interior, columns.start);
        work.fill(0.0);
        for k in 0..columns.len() {
            let (j, _) = self.touched[start + k];
            if let Some(col) = a.outer_view(j) {
                for (i, &v) in col.iter() {
                    match self.part[i] {
                        Part::Interior(r) => work[k * interior + r] = v,
                        Part::Touched(t) => schur[(t, start + k)] += v,
                        Part::Fixed => {}
                    }
                }
            }
        }
    }

    /// S[:, columns] −= A_ci W for the solved block W = A_ii⁻¹ A_ic in `work`.
    fn subtract_coupling(
        &self,
        a: &CscMatrix,
        columns: Range<usize>,
        work: &[f64],
        schur: &mut Mat<f64>,
    ) {
        let (interior, start) = (self.interior, columns.start);
        for k in 0..columns.len() {
            let w = &work[k * interior..(k + 1) * interior];
            for (t, &(j, _)) in self.touched.iter().enumerate() {
                // (A_ci W)[t, k] = Σ_i A[i, c_t] W[i, k]  (A symmetric).
                let mut sum = 0.0;
                if let Some(col) = a.outer_view(j) {
                    for (i, &v) in col.iter() {
                        if let Part::Interior(r) = self.part[i] {
                            sum += v * w[r];
                        }
                    }
                }
                schur[(t, start + k)] -= sum;
            }
        }
    }

    /// H = B_c S⁻¹ B_cᵀ (symmetrised) with a dense Cholesky of S (symmetrised).
    fn condensed(&self, schur: &Mat<f64>, b: &CscMatrix) -> Result<DenseSym, DualError> {
        let (nc, m) = (self.touched.len(), b.rows());
        let schur_sym = Mat::<f64>::from_fn(nc, nc, |i, j| 0.5 * (schur[(i, j)] + schur[(j, i)]));
        let llt = schur_sym.llt(Side::Lower).map_err(|e| {
            DualError::Dense(format!("Schur complement on the contact DOFs: {e:?}"))
        })?;
        // B_cᵀ as an nc × m dense block.
        let mut bt = Mat::<f64>::zeros(nc, m);
        for (t, &(j, _)) in self.touched.iter().enumerate() {
            if let Some(col) = b.outer_view(j) {
                for (i, &v) in col.iter() {
                    bt[(t, i)] = v;
                }
            }
        }
        let mut solved = bt.clone();
        llt.solve_in_place(solved.as_mut());
        let h = bt.transpose() * &solved;
        let mut values = vec![0.0; m * m];
        for j in 0..m {
            for i in 0..m {
                values[j * m + i] = 0.5 * (h[(i, j)] + h[(j, i)]);
            }
        }
        Ok(DenseSym { values, size: m })
    }
}

/// A_ii in CSC, renumbered.
fn interior_block(a: &CscMatrix, part: &[Part], size: usize) -> Result<CscMatrix, DualError> {
    let mut indptr = Vec::with_capacity(size + 1);
    let mut indices = Vec::new();
    let mut data = Vec::new();
    indptr.push(0);
    for (j, col) in a.outer_iterator().enumerate() {
        if !matches!(part[j], Part::Interior(_)) {
            continue;
        }
        for (i, &v) in col.iter() {
            if let Part::Interior(r) = part[i] {
                indices.push(r);
                data.push(v);
            }
        }
        indptr.push(indices.len());
    }
    CscMatrix::try_new_csc((size, size), indptr, indices, data)
        .map_err(|(_, _, _, e)| DualError::Structure(format!("interior stiffness block: {e}")))
}
