//! The KKT matrix with a pattern fixed once for every active set.
//!
//! ```text
//!     [ A + ρI    Bᵀ ]        row i active:    B row as given,   Dᵢᵢ = δ
//! K = [              ],
//!     [   B      −D  ]        row i inactive:  B row of zeros,   Dᵢᵢ = s
//! ```
//!
//! Only the lower triangle is stored (faer reads `Side::Lower`).  An inactive row keeps its
//! entries as explicit zeros, so the sparsity pattern — and with it the ordering and the
//! symbolic factor — is the same for every set; its equation reads −s λᵢ = 0, i.e. λᵢ = 0.
//! With δ > 0 (and ρ > 0 when A is singular) K is quasi-definite: a positive definite block,
//! a negative definite block, so an LDLᵀ factorisation without pivoting exists in any
//! symmetric ordering.

use signorini_qp::{CscMatrix, QpProblem};

use crate::error::PdasError;

/// K's fixed pattern, its values for the current set, and where the B entries and the
/// diagonal sit in the value array.
#[derive(Debug, Clone)]
pub struct KktMatrix {
    /// K, (n + m) × (n + m), lower triangle, CSC.
    matrix: CscMatrix,
    /// n.
    dofs: usize,
    /// For every stored entry of B (in B's CSC order): (slot in K's values, its value).
    b_slots: Vec<(usize, f64)>,
    /// Row of B of each entry in `b_slots`.
    b_rows: Vec<usize>,
    /// Slot of the diagonal of each primal column j (the entry of A, or an added zero).
    primal_diagonal: Vec<usize>,
    /// The values of A's diagonal (0 where A stores none).
    a_diagonal: Vec<f64>,
    /// Slot of the diagonal of each multiplier row i.
    dual_diagonal: Vec<usize>,
}

impl KktMatrix {
    /// The pattern of every row of B, the values of A (lower triangle), B and the diagonal
    /// left to [`KktMatrix::set_values`].
    pub fn new(problem: &QpProblem) -> Result<Self, PdasError> {
        let n = problem.dofs();
        let m = problem.rows();
        let a = &problem.stiffness;
        let b = &problem.constraints;
        let nnz_a = a.nnz();
        let nnz_b = b.nnz();
        let mut indptr = Vec::with_capacity(n + m + 1);
        let mut indices = Vec::with_capacity(nnz_a / 2 + n + nnz_b + m);
        let mut data = Vec::with_capacity(indices.capacity());
        let mut b_slots = Vec::with_capacity(nnz_b);
        let mut b_rows = Vec::with_capacity(nnz_b);
        let mut primal_diagonal = Vec::with_capacity(n);
        let mut a_diagonal = Vec::with_capacity(n);
        indptr.push(0);
        for j in 0..n {
            let a_col = a.outer_view(j);
            let mut has_diagonal = false;
            for (i, &v) in a_col.iter().flat_map(|c| c.iter()) {
                if i < j {
                    continue;
                }
                if i == j {
                    has_diagonal = true;
                    primal_diagonal.push(indices.len());
                    a_diagonal.push(v);
                } else if !has_diagonal {
                    // A stores no diagonal in this column: an explicit zero keeps the slot.
                    has_diagonal = true;
                    primal_diagonal.push(indices.len());
                    a_diagonal.push(0.0);
                    indices.push(j);
                    data.push(0.0);
                }
                indices.push(i);
                data.push(v);
            }
            if !has_diagonal {
                primal_diagonal.push(indices.len());
                a_diagonal.push(0.0);
                indices.push(j);
                data.push(0.0);
            }
            if let Some(b_col) = b.outer_view(j) {
                for (i, &v) in b_col.iter() {
                    b_slots.push((indices.len(), v));
                    b_rows.push(i);
                    indices.push(n + i);
                    data.push(v);
                }
            }
            indptr.push(indices.len());
        }
        let mut dual_diagonal = Vec::with_capacity(m);
        for i in 0..m {
            dual_diagonal.push(indices.len());
            indices.push(n + i);
            data.push(-1.0);
            indptr.push(indices.len());
        }
        let matrix = CscMatrix::try_new_csc((n + m, n + m), indptr, indices, data)
            .map_err(|(_, _, _, e)| PdasError::Symbolic(format!("KKT pattern: {e}")))?;
        Ok(Self {
            matrix,
            dofs: n,
            b_slots,
            b_rows,
            primal_diagonal,
            a_diagonal,
            dual_diagonal,
        })
    }

    /// The matrix (lower triangle) with the values of the last [`KktMatrix::set_values`].
    pub fn matrix(&self) -> &CscMatrix {
        &self.matrix
    }

    /// n + m.
    pub fn dim(&self) -> usize {
        self.matrix.rows()
    }

    /// n.
    pub fn dofs(&self) -> usize {
        self.dofs
    }

    /// A's diagonal (0 where A stores none), in DOF order.
    pub fn a_diagonal(&self) -> &[f64] {
        &self.a_diagonal
    }

    /// Fills the values for the active set `active` (length m): B rows and −δ on the diagonal
    /// of active rows, zeros and −`inactive` on inactive ones, A + ρI on the primal block.
    pub fn set_values(&mut self, active: &[bool], rho: f64, delta: f64, inactive: f64) {
        let data = self.matrix.data_mut();
        for (&slot, &a) in self.primal_diagonal.iter().zip(&self.a_diagonal) {
            data[slot] = a + rho;
        }
        for (&(slot, v), &i) in self.b_slots.iter().zip(&self.b_rows) {
            data[slot] = if active[i] { v } else { 0.0 };
        }
        for (&slot, &on) in self.dual_diagonal.iter().zip(active) {
            data[slot] = if on { -delta } else { -inactive };
        }
    }
}

impl KktMatrix {
    /// Fills the values with every row's B entries and −`diagonal[i]` on the diagonal of
    /// multiplier row i (the interior-point system), A + ρI on the primal block.
    pub fn set_diagonal(&mut self, rho: f64, diagonal: &[f64]) {
        let data = self.matrix.data_mut();
        for (&slot, &a) in self.primal_diagonal.iter().zip(&self.a_diagonal) {
            data[slot] = a + rho;
        }
        for &(slot, v) in &self.b_slots {
            data[slot] = v;
        }
        for (&slot, &d) in self.dual_diagonal.iter().zip(diagonal) {
            data[slot] = -d;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use signorini_qp::examples::two_rows;

    #[test]
    fn inactive_rows_keep_their_pattern_as_zeros() {
        let p = two_rows().problem;
        let mut k = KktMatrix::new(&p).unwrap();
        let nnz = k.matrix().nnz();
        k.set_values(&[true, false], 0.0, 1e-3, 7.0);
        assert_eq!(k.matrix().nnz(), nnz);
        let at = |k: &KktMatrix, i: usize, j: usize| k.matrix().get(i, j).copied().unwrap_or(0.0);
        let m = |i, j| at(&k, i, j);
        // A lower triangle, B row 0 active, row 1 zeroed.
        assert_eq!(m(0, 0), 2.0);
        assert_eq!(m(1, 0), -1.0);
        assert_eq!(m(0, 1), 0.0, "upper triangle is not stored");
        assert_eq!((m(2, 0), m(2, 1)), (1.0, 1.0));
        assert_eq!((m(3, 0), m(3, 1)), (0.0, 0.0));
        assert_eq!((m(2, 2), m(3, 3)), (-1e-3, -7.0));
        k.set_values(&[false, true], 0.5, 1e-3, 7.0);
        let m = |i, j| at(&k, i, j);
        assert_eq!((m(0, 0), m(3, 0), m(3, 1)), (2.5, 1.0, -1.0));
        assert_eq!(m(2, 0), 0.0);
    }
}
