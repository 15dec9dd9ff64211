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

use faer::linalg::solvers::Solve;
use faer::{Mat, Side};
use signorini_qp::linalg::SparseCholesky;
use signorini_qp::CscMatrix;

use super::dense::DenseSym;
use super::multi_rhs::touched_columns;
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
    let b = &data.problem.constraints;
    let n = a.rows();
    let m = b.rows();
    let touched = touched_columns(&data.inverse, b);
    let mut part: Vec<Part> = (0..n)
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
    let nc = touched.len();
    let chol = if interior > 0 {
        let a_ii = interior_block(a, &part, interior)?;
        Some(
            SparseCholesky::factor(&a_ii).map_err(|source| DualError::Singular {
                source,
                kernel: data.modes.count(),
            })?,
        )
    } else {
        None
    };

    // S, column by column block.
    let mut schur = Mat::<f64>::zeros(nc, nc);
    let mut work = vec![0.0; interior * block.min(nc.max(1))];
    for start in (0..nc).step_by(block) {
        if out_of_time() {
            return Err(DualError::OutOfTime(format!(
                "while forming the Schur complement on the contact DOFs ({start} of {nc} columns)"
            )));
        }
        let count = block.min(nc - start);
        let work = &mut work[..interior * count];
        work.fill(0.0);
        for k in 0..count {
            let (j, _) = touched[start + k];
            if let Some(col) = a.outer_view(j) {
                for (i, &v) in col.iter() {
                    match part[i] {
                        Part::Interior(r) => work[k * interior + r] = v,
                        Part::Touched(t) => schur[(t, start + k)] += v,
                        Part::Fixed => {}
                    }
                }
            }
        }
        if let Some(chol) = &chol {
            chol.solve_many_in_place(work);
        }
        for k in 0..count {
            let w = &work[k * interior..(k + 1) * interior];
            for (t, &(j, _)) in touched.iter().enumerate() {
                // (A_ci W)[t, k] = Σ_i A[i, c_t] W[i, k]  (A symmetric).
                let mut sum = 0.0;
                if let Some(col) = a.outer_view(j) {
                    for (i, &v) in col.iter() {
                        if let Part::Interior(r) = part[i] {
                            sum += v * w[r];
                        }
                    }
                }
                schur[(t, start + k)] -= sum;
            }
        }
    }
    let schur_sym = Mat::<f64>::from_fn(nc, nc, |i, j| 0.5 * (schur[(i, j)] + schur[(j, i)]));
    let llt = schur_sym
        .llt(Side::Lower)
        .map_err(|e| DualError::Dense(format!("Schur complement on the contact DOFs: {e:?}")))?;
    // B_cᵀ as an nc × m dense block.
    let mut bt = Mat::<f64>::zeros(nc, m);
    for (t, &(j, _)) in touched.iter().enumerate() {
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
