//! A symmetric matrix stored in the order its factor eliminates it.
//!
//! faer's numeric factorisation with a fill-reducing permutation first copies the matrix into
//! that order (P A Pᵀ, in the triangle its kernel reads): a pass over every stored entry with
//! scattered writes, on every factorisation.  A matrix refactorised many times with new values
//! on one pattern (pdas's KKT matrix, one numeric LDLᵀ per active set) is cheaper kept in that
//! order once and for all: [`OrderedMatrix::reorder`] lays it out, the caller writes new values
//! straight into their places (the slot map it returns), and the symbolic analysis of the
//! ordered pattern ([`super::CholeskyPattern::analyse_ordered`]) carries no permutation, so the
//! numeric factorisation reads the matrix in place.  Measured on the m = 2 001 partial strip
//! (`fixtures/hard/strip-thin-partial.toml`): the copy was a quarter of each of pdas's numeric
//! factorisations (BENCHMARKS.md, "The KKT matrix in its elimination order").

use faer::sparse::{SparseColMat, SparseColMatRef, SymbolicSparseColMat};
use faer::Side;

use super::LinalgError;

/// One triangle of a symmetric matrix A, stored as the triangle `side` of P A Pᵀ (rows
/// unsorted within a column, as faer's own permutation leaves them), with P's inverse (A's
/// index → stored index), so that entries can still be looked up by A's own indices.
#[derive(Debug, Clone)]
pub struct OrderedMatrix {
    matrix: SparseColMat<usize, f64>,
    inverse: Vec<usize>,
    side: Side,
}

impl OrderedMatrix {
    /// A in its own order, which stores the triangle `side` (the diagonal may be stored).
    ///
    /// # Errors
    /// [`LinalgError::Shape`] when `a` is not square, [`LinalgError::Ordering`] when it
    /// stores an entry outside that triangle.
    pub fn new(a: SparseColMat<usize, f64>, side: Side) -> Result<Self, LinalgError> {
        let n = a.nrows();
        if a.ncols() != n {
            return Err(LinalgError::Shape {
                rows: n,
                cols: a.ncols(),
            });
        }
        let sym = a.symbolic();
        let outside = (0..n).any(|j| {
            sym.row_idx_of_col(j).any(|i| match side {
                Side::Upper => i > j,
                Side::Lower => i < j,
            })
        });
        if outside {
            return Err(LinalgError::Ordering(format!(
                "the matrix stores entries outside its {side:?} triangle"
            )));
        }
        Ok(Self {
            matrix: a,
            inverse: (0..n).collect(),
            side,
        })
    }

    /// Moves the stored index p to `inverse[p]` (a permutation of the stored order, e.g. a
    /// fill-reducing ordering of [`OrderedMatrix::as_ref`]'s pattern) and stores the triangle
    /// `side`.  Returns, for each place among the values before, its place after: a caller's
    /// slot k moves to `map[k]`.
    ///
    /// # Errors
    /// [`LinalgError::Ordering`] when `inverse` is not a permutation of the matrix's size.
    pub fn reorder(&mut self, inverse: &[usize], side: Side) -> Result<Vec<usize>, LinalgError> {
        let n = self.dim();
        check_permutation(inverse, n)?;
        let a = self.matrix.as_ref();
        let sym = a.symbolic();
        // Each stored entry's new (row, column), counted per new column.
        let place = |i: usize, j: usize| {
            let (p, q) = (inverse[i], inverse[j]);
            match side {
                Side::Upper => (p.min(q), p.max(q)),
                Side::Lower => (p.max(q), p.min(q)),
            }
        };
        let mut col_ptr = vec![0usize; n + 1];
        for j in 0..n {
            for i in sym.row_idx_of_col(j) {
                col_ptr[place(i, j).1 + 1] += 1;
            }
        }
        for j in 0..n {
            col_ptr[j + 1] += col_ptr[j];
        }
        let nnz = col_ptr[n];
        let mut next = col_ptr.clone();
        let mut row_idx = vec![0usize; nnz];
        let mut values = vec![0.0; nnz];
        let mut map = Vec::with_capacity(nnz);
        for j in 0..n {
            for (i, &v) in sym.row_idx_of_col(j).zip(a.val_of_col(j)) {
                let (row, column) = place(i, j);
                let at = next[column];
                next[column] += 1;
                row_idx[at] = row;
                values[at] = v;
                map.push(at);
            }
        }
        // One triangle, each entry once (a CSC matrix), and P one to one: no entry meets
        // another.
        let symbolic = SymbolicSparseColMat::new_unsorted_checked(n, n, col_ptr, None, row_idx);
        self.matrix = SparseColMat::new(symbolic, values);
        for stored in &mut self.inverse {
            *stored = inverse[*stored];
        }
        self.side = side;
        Ok(map)
    }

    /// The matrix as stored.
    pub fn as_ref(&self) -> SparseColMatRef<'_, usize, f64> {
        self.matrix.as_ref()
    }

    /// Its values, to be overwritten in place (the pattern stays).
    pub fn values_mut(&mut self) -> &mut [f64] {
        self.matrix.val_mut()
    }

    /// The stored triangle.
    pub fn side(&self) -> Side {
        self.side
    }

    /// Size n.
    pub fn dim(&self) -> usize {
        self.inverse.len()
    }

    /// The stored order: `forward[stored] = A's index`.
    pub fn forward(&self) -> Vec<usize> {
        let mut forward = vec![0; self.dim()];
        for (own, &stored) in self.inverse.iter().enumerate() {
            forward[stored] = own;
        }
        forward
    }

    /// The stored entry (i, j) of A, in A's own indices (either order), if the pattern has it.
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
}

/// `inverse` maps 0..n onto 0..n one to one.
fn check_permutation(inverse: &[usize], n: usize) -> Result<(), LinalgError> {
    if inverse.len() != n {
        return Err(LinalgError::Ordering(format!(
            "the ordering has {} entries for a matrix of size {n}",
            inverse.len()
        )));
    }
    let mut seen = vec![false; n];
    for &new in inverse {
        if new >= n || std::mem::replace(&mut seen[new], true) {
            return Err(LinalgError::Ordering(
                "the ordering is not a permutation".into(),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::sparse::Triplet;

    /// The lower triangle of a 4 × 4 symmetric matrix with distinct values, and the full one.
    fn lower() -> (SparseColMat<usize, f64>, [[f64; 4]; 4]) {
        let full = [
            [4.0, 1.0, 0.0, 2.0],
            [1.0, 5.0, 3.0, 0.0],
            [0.0, 3.0, 6.0, 7.0],
            [2.0, 0.0, 7.0, 8.0],
        ];
        let mut t = Vec::new();
        for (i, row) in full.iter().enumerate() {
            for (j, &v) in row.iter().enumerate() {
                if i >= j && v != 0.0 {
                    t.push(Triplet::new(i, j, v));
                }
            }
        }
        (
            SparseColMat::try_new_from_triplets(4, 4, &t).expect("valid triplets"),
            full,
        )
    }

    #[test]
    fn every_entry_lands_where_the_permutation_puts_it() {
        let (a, full) = lower();
        let original = a.val().to_vec();
        // Two moves in a row: the second permutes the order the first left.
        let first = [2, 0, 3, 1];
        let second = [3, 2, 0, 1];
        for side in [Side::Upper, Side::Lower] {
            let mut m = OrderedMatrix::new(a.clone(), Side::Lower).unwrap();
            let map1 = m.reorder(&first, Side::Lower).unwrap();
            let map2 = m.reorder(&second, side).unwrap();
            // Read back in A's indices: every entry of A, none added.
            for (i, row) in full.iter().enumerate() {
                for (j, &v) in row.iter().enumerate() {
                    assert_eq!(m.get(i, j), (v != 0.0).then_some(v), "({i}, {j})");
                }
            }
            // Against the permuted matrix written out by hand: A's index i is stored at
            // second[first[i]] = [0, 3, 1, 2], so stored (p, q) holds A(forward[p], forward[q]).
            let forward = [0, 2, 3, 1];
            assert_eq!(m.forward(), forward);
            let r = m.as_ref();
            for q in 0..4 {
                let rows = r.symbolic().row_idx_of_col_raw(q);
                for (&p, &v) in rows.iter().zip(r.val_of_col(q)) {
                    match side {
                        Side::Upper => assert!(p <= q),
                        Side::Lower => assert!(p >= q),
                    }
                    assert_eq!(v, full[forward[p]][forward[q]]);
                }
            }
            // The maps, composed, send a's k-th value to its place.
            for (k, &v) in original.iter().enumerate() {
                assert_eq!(m.as_ref().val()[map2[map1[k]]], v);
            }
        }
    }

    #[test]
    fn a_matrix_outside_its_triangle_or_a_bad_ordering_is_refused() {
        let (a, _) = lower();
        assert!(OrderedMatrix::new(a.clone(), Side::Upper).is_err());
        let mut m = OrderedMatrix::new(a, Side::Lower).unwrap();
        assert!(m.reorder(&[0, 1, 1, 3], Side::Upper).is_err());
        assert!(m.reorder(&[0, 1, 2], Side::Upper).is_err());
    }
}
