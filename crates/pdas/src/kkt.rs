//! The KKT matrix with a pattern fixed once for every active set.
//!
//! ```text
//!     [ A + ρI    Bᵀ ]        row i active:    B row as given,   Dᵢᵢ = δ
//! K = [              ],
//!     [   B      −D  ]        row i inactive:  B row of zeros,   Dᵢᵢ = s
//! ```
//!
//! K is built straight from A and B in the elimination order of its factor and in the
//! triangle the numeric kernel reads ([`KktMatrix::new`]: the upper one for the simplicial
//! kernel, the lower for faer's supernodal one), so that no factorisation has to copy it into
//! order: faer's numeric LDLᵀ with a permutation first lays the matrix out in that order, a
//! scattered pass over every entry on every factorisation.  The ordering itself
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

/// Where each entry of K goes in the triangle `side` of P K Pᵀ.
#[derive(Clone, Copy)]
struct Placement<'a> {
    inverse: &'a [usize],
    side: Side,
}

impl Placement<'_> {
    /// Whether stored row p belongs to stored column q in the triangle.
    fn in_column(self, p: usize, q: usize) -> bool {
        match self.side {
            Side::Upper => p <= q,
            Side::Lower => p >= q,
        }
    }

    /// The stored (row, column) of the entry between stored indices p and q.
    fn of(self, p: usize, q: usize) -> (usize, usize) {
        if self.in_column(p, q) {
            (p, q)
        } else {
            (q, p)
        }
    }
}

/// Every entry of K once, in A's and B's storage order, with its stored (row, column): A's
/// diagonal (or an added zero), the one of each off-diagonal pair of A that lies in its own
/// column's triangle, B's entries, the multiplier diagonal.  `visit` gets the stored row and
/// column, the value and what the entry is.
fn for_each_entry(
    problem: &QpProblem,
    b: &signorini_qp::CscMatrix,
    place: Placement<'_>,
    mut visit: impl FnMut(usize, usize, f64, Entry),
) {
    let n = problem.dofs();
    let inverse = place.inverse;
    let mut k = 0;
    for (j, col) in problem.stiffness.outer_iterator().enumerate() {
        let q = inverse[j];
        let mut diagonal = false;
        for (&i, &v) in col.indices().iter().zip(col.data()) {
            if i == j {
                diagonal = true;
                visit(q, q, v, Entry::PrimalDiagonal(j));
            } else {
                // Of the pair (i, j), (j, i), the entry in its own column's triangle stays.
                let p = inverse[i];
                if p != q && place.in_column(p, q) {
                    visit(p, q, v, Entry::Stiffness);
                }
            }
        }
        if !diagonal {
            visit(q, q, 0.0, Entry::PrimalDiagonal(j));
        }
        if let Some(b_col) = b.outer_view(j) {
            for (r, &v) in b_col.iter() {
                let (row, column) = place.of(inverse[n + r], q);
                visit(row, column, v, Entry::Constraint { index: k, row: r });
                k += 1;
            }
        }
    }
    for r in 0..b.rows() {
        let p = inverse[n + r];
        visit(p, p, -1.0, Entry::DualDiagonal(r));
    }
}

/// What an entry of K is, for the slots [`KktMatrix::set_values`] writes.
#[derive(Clone, Copy)]
enum Entry {
    /// Off the diagonal of A.
    Stiffness,
    /// The diagonal of A's column j.
    PrimalDiagonal(usize),
    /// B's entry number `index` (CSC order), in row `row`.
    Constraint { index: usize, row: usize },
    /// The diagonal of multiplier row r.
    DualDiagonal(usize),
}

impl KktMatrix {
    /// K for the elimination order `ordering` (of K's unknowns: `forward[new] = old`), stored
    /// as the triangle `side` of P K Pᵀ: A's values (both triangles of A are read, one kept),
    /// B's, and −1 on the multiplier diagonal until [`KktMatrix::set_values`].  Two passes in
    /// A's and B's own order, the first counting each stored column, the second placing the
    /// entries (reading A in order and writing scattered is twice as fast here as gathering
    /// A's columns in the new order).
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
        let b = problem.constraints.to_csc();
        let place = Placement {
            inverse: &ordering.inverse,
            side,
        };
        let mut col_ptr = vec![0usize; dim + 1];
        for_each_entry(problem, &b, place, |_, column, _, _| {
            col_ptr[column + 1] += 1;
        });
        for q in 0..dim {
            col_ptr[q + 1] += col_ptr[q];
        }
        let entries = col_ptr[dim];
        let mut next = col_ptr.clone();
        let mut row_idx = vec![0usize; entries];
        let mut values = vec![0.0; entries];
        let mut b_slots = vec![(0, 0.0); b.nnz()];
        let mut b_rows = vec![0; b.nnz()];
        let mut primal_diagonal = vec![0; n];
        let mut a_diagonal = vec![0.0; n];
        let mut dual_diagonal = vec![0; m];
        for_each_entry(problem, &b, place, |row, column, v, entry| {
            let slot = next[column];
            next[column] += 1;
            row_idx[slot] = row;
            values[slot] = v;
            match entry {
                Entry::Stiffness => {}
                Entry::PrimalDiagonal(j) => {
                    primal_diagonal[j] = slot;
                    a_diagonal[j] = v;
                }
                Entry::Constraint { index, row } => {
                    b_slots[index] = (slot, v);
                    b_rows[index] = row;
                }
                Entry::DualDiagonal(r) => dual_diagonal[r] = slot,
            }
        });
        // Rows unsorted within a column; every index below `dim` by construction.
        let symbolic = SymbolicSparseColMat::new_unsorted_checked(dim, dim, col_ptr, None, row_idx);
        Ok(Self {
            matrix: SparseColMat::new(symbolic, values),
            side,
            forward: ordering.forward.clone(),
            inverse: ordering.inverse.clone(),
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
