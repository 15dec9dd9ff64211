//! The reduction to the free DOFs: restricted matrices with their lifting by the prescribed
//! values, and the refusal of data that overflowed.

use super::error::ModelError;
use crate::qp::CscMatrix;

/// Index of each DOF among the free ones (`usize::MAX` for a fixed DOF).
pub(super) fn free_index(free: &[usize], n: usize) -> Vec<usize> {
    let mut index = vec![usize::MAX; n];
    for (k, &d) in free.iter().enumerate() {
        index[d] = k;
    }
    index
}

/// The listed columns of a CSC matrix, as a new CSC matrix.
pub(super) fn columns(m: &CscMatrix, list: &[usize]) -> CscMatrix {
    let mut col_ptr = Vec::with_capacity(list.len() + 1);
    col_ptr.push(0);
    let mut row_idx = Vec::new();
    let mut values = Vec::new();
    for &j in list {
        if let Some(col) = m.outer_view(j) {
            for (i, v) in col.iter() {
                row_idx.push(i);
                values.push(*v);
            }
        }
        col_ptr.push(row_idx.len());
    }
    CscMatrix::new_csc((m.rows(), list.len()), col_ptr, row_idx, values)
}

/// Keeps the free columns of a CSC matrix (and the free rows too when `rows_too`), renumbered;
/// returns it with the product of the dropped (fixed) columns with their prescribed values.
pub(super) fn restrict(
    m: &CscMatrix,
    fixed: &[Option<f64>],
    free_index: &[usize],
    rows_too: bool,
) -> (CscMatrix, Vec<f64>) {
    let n_free = free_index.iter().filter(|i| **i != usize::MAX).count();
    let n_rows = if rows_too { n_free } else { m.rows() };
    let mut col_ptr = Vec::with_capacity(n_free + 1);
    col_ptr.push(0);
    let mut row_idx = Vec::with_capacity(m.nnz());
    let mut values = Vec::with_capacity(m.nnz());
    let mut lifted = vec![0.0; n_rows];
    for (j, col) in m.outer_iterator().enumerate() {
        match fixed[j] {
            None => {
                for (i, v) in col.iter() {
                    let r = if rows_too { free_index[i] } else { i };
                    if r != usize::MAX {
                        row_idx.push(r);
                        values.push(*v);
                    }
                }
                col_ptr.push(row_idx.len());
            }
            Some(u) if u != 0.0 => {
                for (i, v) in col.iter() {
                    let r = if rows_too { free_index[i] } else { i };
                    if r != usize::MAX {
                        lifted[r] += v * u;
                    }
                }
            }
            Some(_) => {}
        }
    }
    (
        CscMatrix::new_csc((n_rows, n_free), col_ptr, row_idx, values),
        lifted,
    )
}

/// Refuses a reduced stiffness, load or gap that overflowed, naming the scene keys behind it:
/// the material (`young`, `poisson`: the bulk modulus E / (1 − 2ν)(1 + ν)) for A; the lifting
/// K_FD u_D (`young` × [[dirichlet]] `value`) or the applied loads ([[neumann]] `traction`,
/// `gravity`) for f; the lifting B_D u_D ([[dirichlet]] `value`) for g.
pub(super) fn check_finite(stiffness: &[f64], load: &[f64], gap: &[f64]) -> Result<(), ModelError> {
    if stiffness.iter().any(|v| !v.is_finite()) {
        return Err(ModelError::Overflow {
            what: "the stiffness",
            cause: "a body's `young` divided by (1 − 2·`poisson`)(1 + `poisson`), times the element's shape terms",
        });
    }
    if load.iter().any(|v| !v.is_finite()) {
        return Err(ModelError::Overflow {
            what: "the load after lifting the prescribed displacements",
            cause: "the stiffness (`young`) times a prescribed displacement ([[dirichlet]] `value`), or a load ([[neumann]] `traction`, `gravity`) summed over the body",
        });
    }
    if gap.iter().any(|v| !v.is_finite()) {
        return Err(ModelError::Overflow {
            what: "a contact gap after lifting the prescribed displacements",
            cause: "a prescribed displacement ([[dirichlet]] `value`)",
        });
    }
    Ok(())
}
