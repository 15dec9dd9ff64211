//! Sparse Cholesky factorisation of the stiffness (faer), shared by the unconstrained solve, the
//! timing floor and the dual backend.
//!
//! The symbolic analysis (fill-reducing ordering, elimination tree) is kept apart from the numeric
//! factorisation so that one analysis serves many refactorisations of the same pattern.

use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{MatMut, Side};

use crate::qp::CscMatrix;

mod ordering;

pub use ordering::{fill_reducing_order, FillOrdering, OrderingMethod};

/// Why a factorisation failed.
#[derive(Debug, thiserror::Error)]
pub enum LinalgError {
    /// The matrix is not square or not in CSC storage.
    #[error("matrix must be square and in CSC storage (got {rows}×{cols})")]
    Shape {
        /// Rows of the matrix.
        rows: usize,
        /// Columns of the matrix.
        cols: usize,
    },
    /// A pivot was not positive: the matrix is singular or indefinite (e.g. a floating body).
    #[error("stiffness is not positive definite (pivot {index} of {n} vanished): a body may be free to move rigidly")]
    NotPositiveDefinite {
        /// Index (in the factorisation's ordering) of the failing pivot.
        index: usize,
        /// Size of the matrix.
        n: usize,
    },
    /// Memory or another failure inside faer.
    #[error("sparse Cholesky failed: {0}")]
    Faer(String),
}

/// Borrow a CSC matrix as a faer view (no copy).
pub fn faer_view(m: &CscMatrix) -> Result<SparseColMatRef<'_, usize, f64>, LinalgError> {
    if !m.is_csc() {
        return Err(LinalgError::Shape {
            rows: m.rows(),
            cols: m.cols(),
        });
    }
    let (col_ptr, row_idx, values) = m.view().into_raw_storage();
    if col_ptr.first().copied().unwrap_or(0) != 0 {
        return Err(LinalgError::Faer(
            "column pointer of a sliced matrix does not start at 0".into(),
        ));
    }
    let symbolic = SymbolicSparseColMatRef::new_checked(m.rows(), m.cols(), col_ptr, None, row_idx);
    Ok(SparseColMatRef::new(symbolic, values))
}

/// The symbolic analysis of a sparsity pattern, reusable for every matrix with that pattern.
#[derive(Debug, Clone)]
pub struct CholeskyPattern {
    symbolic: SymbolicLlt<usize>,
    n: usize,
}

impl CholeskyPattern {
    /// Analyses the pattern of the symmetric matrix `a` (its lower triangle is read).
    pub fn analyse(a: &CscMatrix) -> Result<Self, LinalgError> {
        if a.rows() != a.cols() {
            return Err(LinalgError::Shape {
                rows: a.rows(),
                cols: a.cols(),
            });
        }
        let view = faer_view(a)?;
        let symbolic = SymbolicLlt::try_new(view.symbolic(), Side::Lower)
            .map_err(|e| LinalgError::Faer(format!("{e:?}")))?;
        Ok(Self {
            symbolic,
            n: a.rows(),
        })
    }

    /// Numeric factorisation of `a`, which must have the analysed pattern.
    pub fn factor(&self, a: &CscMatrix) -> Result<SparseCholesky, LinalgError> {
        if a.rows() != self.n || a.cols() != self.n {
            return Err(LinalgError::Shape {
                rows: a.rows(),
                cols: a.cols(),
            });
        }
        let view = faer_view(a)?;
        let llt =
            Llt::try_new_with_symbolic(self.symbolic.clone(), view, Side::Lower).map_err(|e| {
                match e {
                    faer::sparse::linalg::LltError::Numeric(
                        faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot { index },
                    ) => LinalgError::NotPositiveDefinite { index, n: self.n },
                    other => LinalgError::Faer(format!("{other:?}")),
                }
            })?;
        Ok(SparseCholesky { llt, n: self.n })
    }
}

/// A numeric Cholesky factorisation L Lᵀ = A.
#[derive(Debug, Clone)]
pub struct SparseCholesky {
    llt: Llt<usize, f64>,
    n: usize,
}

impl SparseCholesky {
    /// Analyses and factors the symmetric positive definite `a` in one go.
    ///
    /// ```
    /// use signorini_core::linalg::SparseCholesky;
    /// use sprs::TriMat;
    /// let mut a = TriMat::new((2, 2));
    /// for (i, j, v) in [(0, 0, 4.0), (1, 1, 3.0), (0, 1, 1.0), (1, 0, 1.0)] {
    ///     a.add_triplet(i, j, v);
    /// }
    /// let chol = SparseCholesky::factor(&a.to_csc()).unwrap();
    /// let mut x = vec![5.0, 4.0];
    /// chol.solve_in_place(&mut x);
    /// assert!((x[0] - 1.0).abs() < 1e-14 && (x[1] - 1.0).abs() < 1e-14);
    /// ```
    pub fn factor(a: &CscMatrix) -> Result<Self, LinalgError> {
        CholeskyPattern::analyse(a)?.factor(a)
    }

    /// Size n of the factored matrix.
    pub fn dim(&self) -> usize {
        self.n
    }

    /// Overwrites `rhs` (length n) with A⁻¹ rhs.
    pub fn solve_in_place(&self, rhs: &mut [f64]) {
        debug_assert_eq!(rhs.len(), self.n);
        let mat = MatMut::from_column_major_slice_mut(rhs, self.n, 1);
        self.llt.solve_in_place(mat);
    }

    /// Overwrites the column-major n×k block `rhs` with A⁻¹ rhs (k = rhs.len() / n).
    pub fn solve_many_in_place(&self, rhs: &mut [f64]) {
        if self.n == 0 {
            return;
        }
        let k = rhs.len() / self.n;
        debug_assert_eq!(rhs.len(), k * self.n);
        let mat = MatMut::from_column_major_slice_mut(rhs, self.n, k);
        self.llt.solve_in_place(mat);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sprs::TriMat;

    fn laplacian(n: usize) -> CscMatrix {
        let mut t = TriMat::new((n, n));
        for i in 0..n {
            t.add_triplet(i, i, 2.0);
            if i + 1 < n {
                t.add_triplet(i, i + 1, -1.0);
                t.add_triplet(i + 1, i, -1.0);
            }
        }
        t.to_csc()
    }

    #[test]
    fn solves_a_laplacian_and_reuses_the_pattern() {
        let a = laplacian(50);
        let pattern = CholeskyPattern::analyse(&a).unwrap();
        for scale in [1.0, 1e11, 1e-14] {
            let a_s = a.map(|v| v * scale);
            let chol = pattern.factor(&a_s).unwrap();
            let x_true: Vec<f64> = (0..50).map(|i| (i as f64).sin()).collect();
            let mut b = crate::qp::mat_vec(&a_s, &x_true);
            chol.solve_in_place(&mut b);
            for (x, y) in b.iter().zip(&x_true) {
                assert!((x - y).abs() < 1e-10, "{x} vs {y} at scale {scale}");
            }
        }
    }

    #[test]
    fn indefinite_matrix_is_a_typed_error() {
        let mut t = TriMat::new((2, 2));
        t.add_triplet(0, 0, 1.0);
        t.add_triplet(1, 1, -1.0);
        assert!(matches!(
            SparseCholesky::factor(&t.to_csc()),
            Err(LinalgError::NotPositiveDefinite { .. })
        ));
    }
}
