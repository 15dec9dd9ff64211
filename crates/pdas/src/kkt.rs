//! The KKT matrix with a pattern fixed once for every active set.
//!
//! ```text
//!     [ A + ρI    Bᵀ ]        row i active:    B row as given,   Dᵢᵢ = δ
//! K = [              ],
//!     [   B      −D  ]        row i inactive:  B row of zeros,   Dᵢᵢ = s
//! ```
//!
//! It is built as a lower triangle in the unknowns' own order, which the fill-reducing
//! ordering reads, and then stored in that elimination order and in the triangle faer's
//! numeric kernel reads ([`KktMatrix::reorder`]), so that no factorisation copies it into
//! order again.  An inactive row keeps its
//! entries as explicit zeros, so the sparsity pattern — and with it the ordering and the
//! symbolic factor — is the same for every set; its equation reads −s λᵢ = 0, i.e. λᵢ = 0.
//! With δ > 0 (and ρ > 0 when A is singular) K is quasi-definite: a positive definite block,
//! a negative definite block, so an LDLᵀ factorisation without pivoting exists in any
//! symmetric ordering.

use faer::sparse::{SparseColMat, SparseColMatRef, SymbolicSparseColMat};
use faer::Side;
use signorini_qp::linalg::{FillOrdering, OrderedMatrix};
use signorini_qp::QpProblem;

use crate::error::PdasError;

/// K's fixed pattern, its values for the current set, and where the B entries and the
/// diagonal sit in the value array.  K is built in the unknowns' own order (which the
/// ordering reads) and then moved to its factor's elimination order ([`KktMatrix::reorder`]),
/// where every new set's values are written.
#[derive(Debug, Clone)]
pub struct KktMatrix {
    /// K, (n + m) × (n + m): built as the lower triangle in the unknowns' own order, then
    /// stored as [`KktMatrix::reorder`] says; the matrix [`KktMatrix::set_values`] fills.
    stored: OrderedMatrix,
    /// n.
    dofs: usize,
    /// Where the values sit in `stored`.
    slots: Slots,
    /// Row of B of each entry in `slots.b`.
    b_rows: Vec<usize>,
    /// The values of A's diagonal (0 where A stores none).
    a_diagonal: Vec<f64>,
}

/// Places in a value array of K.
#[derive(Debug, Clone, Default)]
struct Slots {
    /// For every stored entry of B (in B's CSC order): (slot, its value).
    b: Vec<(usize, f64)>,
    /// Slot of the diagonal of each primal column j (the entry of A, or an added zero).
    primal_diagonal: Vec<usize>,
    /// Slot of the diagonal of each multiplier row i.
    dual_diagonal: Vec<usize>,
}

impl Slots {
    /// The same places after the values moved, `map[old slot] = new slot`.
    fn moved(&self, map: &[usize]) -> Self {
        Self {
            b: self.b.iter().map(|&(slot, v)| (map[slot], v)).collect(),
            primal_diagonal: self.primal_diagonal.iter().map(|&s| map[s]).collect(),
            dual_diagonal: self.dual_diagonal.iter().map(|&s| map[s]).collect(),
        }
    }
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
        let symbolic =
            SymbolicSparseColMat::new_unsorted_checked(n + m, n + m, indptr, None, indices);
        let own_order = OrderedMatrix::new(SparseColMat::new(symbolic, data), Side::Lower)
            .map_err(|e| PdasError::Symbolic(format!("KKT pattern: {e}")))?;
        Ok(Self {
            stored: own_order,
            dofs: n,
            slots: Slots {
                b: b_slots,
                primal_diagonal,
                dual_diagonal,
            },
            b_rows,
            a_diagonal,
        })
    }

    /// Moves K's stored index p to `ordering.inverse[p]` (an ordering of
    /// [`KktMatrix::matrix`]'s pattern as it is stored now) and stores the triangle `side`:
    /// the order and triangle its factor reads in place.  The values move with it.
    pub fn reorder(&mut self, ordering: &FillOrdering, side: Side) -> Result<(), PdasError> {
        let map = self
            .stored
            .reorder(&ordering.inverse, side)
            .map_err(|e| PdasError::Symbolic(e.to_string()))?;
        self.slots = self.slots.moved(&map);
        Ok(())
    }

    /// K as stored, in its elimination order, with the values of the last
    /// [`KktMatrix::set_values`] or [`KktMatrix::set_diagonal`].
    pub fn matrix(&self) -> SparseColMatRef<'_, usize, f64> {
        self.stored.as_ref()
    }

    /// K as stored, with its order and triangle.
    pub fn stored(&self) -> &OrderedMatrix {
        &self.stored
    }

    /// The stored entry (i, j) of K, in K's own indices (either order), if K's pattern has it.
    pub fn get(&self, i: usize, j: usize) -> Option<f64> {
        self.stored.get(i, j)
    }

    /// n + m.
    pub fn dim(&self) -> usize {
        self.stored.dim()
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
        let slots = &self.slots;
        let data = self.stored.values_mut();
        for (&slot, &a) in slots.primal_diagonal.iter().zip(&self.a_diagonal) {
            data[slot] = a + rho;
        }
        for (&(slot, v), &i) in slots.b.iter().zip(&self.b_rows) {
            data[slot] = if active[i] { v } else { 0.0 };
        }
        for (&slot, &on) in slots.dual_diagonal.iter().zip(active) {
            data[slot] = if on { -delta } else { -inactive };
        }
    }
}

impl KktMatrix {
    /// Fills the values with every row's B entries and −`diagonal[i]` on the diagonal of
    /// multiplier row i (the interior-point system), A + ρI on the primal block.
    pub fn set_diagonal(&mut self, rho: f64, diagonal: &[f64]) {
        let slots = &self.slots;
        let data = self.stored.values_mut();
        for (&slot, &a) in slots.primal_diagonal.iter().zip(&self.a_diagonal) {
            data[slot] = a + rho;
        }
        for &(slot, v) in &slots.b {
            data[slot] = v;
        }
        for (&slot, &d) in slots.dual_diagonal.iter().zip(diagonal) {
            data[slot] = -d;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use signorini_qp::examples::two_rows;
    use signorini_qp::linalg::OrderingMethod;

    #[test]
    fn inactive_rows_keep_their_pattern_as_zeros() {
        let p = two_rows().problem;
        let mut k = KktMatrix::new(&p).unwrap();
        let nnz = k.matrix().compute_nnz();
        k.set_values(&[true, false], 0.0, 1e-3, 7.0);
        assert_eq!(k.matrix().compute_nnz(), nnz);
        let at = |k: &KktMatrix, i: usize, j: usize| k.get(i, j).unwrap_or(0.0);
        let m = |i, j| at(&k, i, j);
        // A lower triangle, B row 0 active, row 1 zeroed.
        assert_eq!(m(0, 0), 2.0);
        assert_eq!(m(1, 0), -1.0);
        assert_eq!((m(2, 0), m(2, 1)), (1.0, 1.0));
        assert_eq!((m(3, 0), m(3, 1)), (0.0, 0.0));
        assert_eq!((m(2, 2), m(3, 3)), (-1e-3, -7.0));
        k.set_values(&[false, true], 0.5, 1e-3, 7.0);
        let m = |i, j| at(&k, i, j);
        assert_eq!((m(0, 0), m(3, 0), m(3, 1)), (2.5, 1.0, -1.0));
        assert_eq!(m(2, 0), 0.0);
    }

    #[test]
    fn a_reordered_matrix_takes_each_value_where_the_order_puts_it() {
        let p = two_rows().problem;
        let mut k = KktMatrix::new(&p).unwrap();
        let fill = |k: &mut KktMatrix| k.set_values(&[false, true], 0.5, 1e-3, 7.0);
        fill(&mut k);
        let before: Vec<Option<f64>> = (0..16).map(|e| k.get(e / 4, e % 4)).collect();
        // Reversed, in the upper triangle; then the same order in the lower one: the same
        // entries of K, read in K's own indices.
        let reversed = FillOrdering::from_forward(vec![3, 2, 1, 0], OrderingMethod::Amd);
        let same = FillOrdering::from_forward(vec![0, 1, 2, 3], OrderingMethod::Amd);
        for (ordering, side) in [(&reversed, Side::Upper), (&same, Side::Lower)] {
            k.reorder(ordering, side).unwrap();
            fill(&mut k);
            let after: Vec<Option<f64>> = (0..16).map(|e| k.get(e / 4, e % 4)).collect();
            assert_eq!(after, before);
            assert_eq!(k.stored().forward(), vec![3, 2, 1, 0]);
            assert_eq!(k.stored().side(), side);
            // Stored index 0 is K's 3 (multiplier row 1, active: −δ), alone in its column of
            // the upper triangle.
            if side == Side::Upper {
                assert_eq!(k.matrix().val_of_col(0), &[-1e-3]);
            }
        }
    }
}
