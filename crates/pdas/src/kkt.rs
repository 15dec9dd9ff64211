//! The KKT matrix with a pattern fixed once for every active set.
//!
//! ```text
//!     [ A + ρI    Bᵀ ]        row i active:    B row as given,   Dᵢᵢ = δ
//! K = [              ],
//!     [   B      −D  ]        row i inactive:  B row of zeros,   Dᵢᵢ = s
//! ```
//!
//! K is built straight from A and B in the elimination order of its factor and in the
//! triangle faer's numeric kernel reads ([`KktMatrix::new`]), column by column (each new
//! column gathers one column of A and of B, or one row of B), so that no factorisation has to
//! copy it into order: faer's numeric LDLᵀ with a permutation first lays the matrix out in
//! that order, a scattered pass over every entry on every factorisation.  The ordering itself
//! reads K's graph, taken from A and B as well ([`signorini_qp::linalg::kkt::kkt_graph`]).
//! An inactive row keeps its entries as explicit zeros, so the sparsity pattern — and with it
//! the ordering and the symbolic factor — is the same for every set; its equation reads
//! −s λᵢ = 0, i.e. λᵢ = 0.  With δ > 0 (and ρ > 0 when A is singular) K is quasi-definite: a
//! positive definite block, a negative definite block, so an LDLᵀ factorisation without
//! pivoting exists in any symmetric ordering.

use faer::sparse::{SparseColMat, SparseColMatRef, SymbolicSparseColMat};
use faer::Side;
use signorini_qp::linalg::FillOrdering;
use signorini_qp::QpProblem;

use crate::error::PdasError;

/// K's fixed pattern in its factor's elimination order, its values for the current set, and
/// where the B entries and the diagonal sit in the value array.
#[derive(Debug, Clone)]
pub struct KktMatrix {
    /// P K Pᵀ, (n + m) × (n + m), the triangle `side`, CSC (rows unsorted within a column, as
    /// faer's own permutation leaves them).
    matrix: SparseColMat<usize, f64>,
    /// The stored triangle.
    side: Side,
    /// `forward[stored] = K's index`.
    forward: Vec<usize>,
    /// `inverse[K's index] = stored`.
    inverse: Vec<usize>,
    /// n.
    dofs: usize,
    /// For every stored entry of B (in B's CSC order): (slot in the values, its value).
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

/// B's rows: for row r, the (column, index in B's CSC order) of its entries.
struct Rows {
    starts: Vec<usize>,
    entries: Vec<(usize, usize)>,
}

impl Rows {
    fn of(b: &signorini_qp::CscMatrix) -> Self {
        let m = b.rows();
        let mut starts = vec![0usize; m + 1];
        for (_, (r, _)) in b.iter() {
            starts[r + 1] += 1;
        }
        for r in 0..m {
            starts[r + 1] += starts[r];
        }
        let mut next = starts.clone();
        let mut entries = vec![(0, 0); starts[m]];
        let mut k = 0;
        for (j, col) in b.outer_iterator().enumerate() {
            for (r, _) in col.iter() {
                entries[next[r]] = (j, k);
                next[r] += 1;
                k += 1;
            }
        }
        Self { starts, entries }
    }

    fn of_row(&self, r: usize) -> &[(usize, usize)] {
        &self.entries[self.starts[r]..self.starts[r + 1]]
    }
}

/// The columns of P K Pᵀ being laid down, in order.
struct Columns {
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    values: Vec<f64>,
}

impl Columns {
    /// Appends the entry (row, current column) and returns its slot.
    fn push(&mut self, row: usize, value: f64) -> usize {
        self.row_idx.push(row);
        self.values.push(value);
        self.row_idx.len() - 1
    }

    fn close_column(&mut self) {
        self.col_ptr.push(self.row_idx.len());
    }
}

impl KktMatrix {
    /// K for the elimination order `ordering` (of K's unknowns: `forward[new] = old`), stored
    /// as the triangle `side` of P K Pᵀ: A's values (both triangles of A are read, one kept),
    /// B's, and −1 on the multiplier diagonal until [`KktMatrix::set_values`].
    pub fn new(
        problem: &QpProblem,
        ordering: &FillOrdering,
        side: Side,
    ) -> Result<Self, PdasError> {
        let n = problem.dofs();
        let m = problem.rows();
        let dim = n + m;
        if ordering.forward.len() != dim || ordering.inverse.len() != dim {
            return Err(PdasError::Symbolic(format!(
                "an ordering of {} unknowns for a KKT matrix of {dim}",
                ordering.forward.len()
            )));
        }
        let a = &problem.stiffness;
        let b = problem.constraints.to_csc();
        let rows = Rows::of(&b);
        let (forward, inverse) = (&ordering.forward, &ordering.inverse);
        // Whether stored row p belongs to stored column q's triangle.
        let kept = |p: usize, q: usize| match side {
            Side::Upper => p <= q,
            Side::Lower => p >= q,
        };
        let entries = (a.nnz() + n) / 2 + b.nnz() + m;
        let mut out = Columns {
            col_ptr: Vec::with_capacity(dim + 1),
            row_idx: Vec::with_capacity(entries),
            values: Vec::with_capacity(entries),
        };
        out.col_ptr.push(0);
        let mut b_slots = vec![(0, 0.0); b.nnz()];
        let mut b_rows = vec![0; b.nnz()];
        let mut primal_diagonal = vec![0; n];
        let mut a_diagonal = vec![0.0; n];
        let mut dual_diagonal = vec![0; m];
        let mut b_index = vec![0usize; n + 1];
        for j in 0..n {
            b_index[j + 1] = b_index[j] + b.outer_view(j).map_or(0, |c| c.nnz());
        }
        for (q, &old) in forward.iter().enumerate() {
            if old < n {
                let j = old;
                let mut diagonal = None;
                if let Some(col) = a.outer_view(j) {
                    for (i, &v) in col.iter() {
                        if i == j {
                            a_diagonal[j] = v;
                            diagonal = Some(out.push(q, v));
                        } else if kept(inverse[i], q) {
                            out.push(inverse[i], v);
                        }
                    }
                }
                primal_diagonal[j] = diagonal.unwrap_or_else(|| out.push(q, 0.0));
                if let Some(col) = b.outer_view(j) {
                    for (k, (r, &v)) in (b_index[j]..).zip(col.iter()) {
                        b_rows[k] = r;
                        if kept(inverse[n + r], q) {
                            b_slots[k] = (out.push(inverse[n + r], v), v);
                        }
                    }
                }
            } else {
                let r = old - n;
                for &(j, k) in rows.of_row(r) {
                    if kept(inverse[j], q) {
                        let v = b.data()[k];
                        b_slots[k] = (out.push(inverse[j], v), v);
                    }
                }
                dual_diagonal[r] = out.push(q, -1.0);
            }
            out.close_column();
        }
        // Rows unsorted within a column; every index below `dim` by construction.
        let symbolic =
            SymbolicSparseColMat::new_unsorted_checked(dim, dim, out.col_ptr, None, out.row_idx);
        Ok(Self {
            matrix: SparseColMat::new(symbolic, out.values),
            side,
            forward: forward.clone(),
            inverse: inverse.clone(),
            dofs: n,
            b_slots,
            b_rows,
            primal_diagonal,
            a_diagonal,
            dual_diagonal,
        })
    }

    /// P K Pᵀ as stored (the triangle [`KktMatrix::side`]), with the values of the last
    /// [`KktMatrix::set_values`] or [`KktMatrix::set_diagonal`].
    pub fn matrix(&self) -> SparseColMatRef<'_, usize, f64> {
        self.matrix.as_ref()
    }

    /// The stored triangle.
    pub fn side(&self) -> Side {
        self.side
    }

    /// The elimination order, `forward[stored] = K's index`.
    pub fn forward(&self) -> &[usize] {
        &self.forward
    }

    /// The stored entry (i, j) of K, in K's own indices (either order), if K's pattern has it.
    pub fn get(&self, i: usize, j: usize) -> Option<f64> {
        let (p, q) = (*self.inverse.get(i)?, *self.inverse.get(j)?);
        let (row, column) = match self.side {
            Side::Upper => (p.min(q), p.max(q)),
            Side::Lower => (p.max(q), p.min(q)),
        };
        let m = self.matrix.as_ref();
        let rows = m.symbolic().row_idx_of_col_raw(column);
        let at = rows.iter().position(|&r| r == row)?;
        Some(m.val_of_col(column)[at])
    }

    /// n + m.
    pub fn dim(&self) -> usize {
        self.forward.len()
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
        let data = self.matrix.val_mut();
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

    /// Fills the values with every row's B entries and −`diagonal[i]` on the diagonal of
    /// multiplier row i (the interior-point system), A + ρI on the primal block.
    pub fn set_diagonal(&mut self, rho: f64, diagonal: &[f64]) {
        let data = self.matrix.val_mut();
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
    use signorini_qp::linalg::OrderingMethod;

    fn own_order(dim: usize) -> FillOrdering {
        FillOrdering::from_forward((0..dim).collect(), OrderingMethod::Amd)
    }

    #[test]
    fn inactive_rows_keep_their_pattern_as_zeros() {
        let p = two_rows().problem;
        let mut k = KktMatrix::new(&p, &own_order(4), Side::Lower).unwrap();
        let nnz = k.matrix().compute_nnz();
        k.set_values(&[true, false], 0.0, 1e-3, 7.0);
        assert_eq!(k.matrix().compute_nnz(), nnz);
        let at = |k: &KktMatrix, i: usize, j: usize| k.get(i, j).unwrap_or(0.0);
        let m = |i, j| at(&k, i, j);
        // A, B row 0 active, row 1 zeroed.
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

    /// Built in any order and either triangle, K holds the same entries: each stored (p, q)
    /// is K's (forward[p], forward[q]) as the own-order build (checked by hand above) has it,
    /// in the chosen triangle, none lost or repeated.
    #[test]
    fn built_in_another_order_each_value_lands_where_the_order_puts_it() {
        let p = two_rows().problem;
        let fill = |k: &mut KktMatrix| k.set_values(&[false, true], 0.5, 1e-3, 7.0);
        let mut reference = KktMatrix::new(&p, &own_order(4), Side::Lower).unwrap();
        fill(&mut reference);
        let entries = reference.matrix().compute_nnz();
        for forward in [vec![3, 2, 1, 0], vec![2, 0, 3, 1], vec![1, 3, 0, 2]] {
            let ordering = FillOrdering::from_forward(forward.clone(), OrderingMethod::Amd);
            for side in [Side::Upper, Side::Lower] {
                let mut k = KktMatrix::new(&p, &ordering, side).unwrap();
                fill(&mut k);
                assert_eq!((k.forward(), k.side()), (&forward[..], side));
                let stored = k.matrix();
                assert_eq!(stored.compute_nnz(), entries);
                for q in 0..4 {
                    let rows = stored.symbolic().row_idx_of_col_raw(q);
                    for (&row, &v) in rows.iter().zip(stored.val_of_col(q)) {
                        assert!(if side == Side::Upper {
                            row <= q
                        } else {
                            row >= q
                        });
                        assert_eq!(Some(v), reference.get(forward[row], forward[q]));
                    }
                }
            }
        }
        let short = FillOrdering::from_forward(vec![0, 1, 2], OrderingMethod::Amd);
        assert!(KktMatrix::new(&p, &short, Side::Upper).is_err());
    }
}
