//! Sparse Cholesky factorisation of the stiffness (faer), shared by the unconstrained solve, the
//! timing floor and the dual backend.
//!
//! Every factorisation of A takes one path: [`fill_reducing_order`] (AMD or METIS nested
//! dissection, by the rule in [`ordering`]), faer's symbolic Cholesky with that ordering
//! (`SymmetricOrdering::Custom`) — forced supernodal for the factors whose supernodes are read
//! (the dual backends'), faer's own choice of simplicial or supernodal for the timing floor
//! ([`Layout`]) — and the numeric LLᵀ on one thread (`Par::Seq`).  A matrix refactorised many
//! times (pdas's KKT matrix) is instead built in its elimination order and analysed without a
//! permutation, so no factorisation copies it into order: by the project's own simplicial LDLᵀ
//! ([`ldlt`]) where faer's flop rule picks a simplicial factor, else by faer's supernodal one
//! ([`CholeskyPattern::analyse_ordered`]).  The symbolic analysis is kept apart from the numeric factorisation so that one
//! analysis serves many refactorisations of the same pattern, and so that the memory a factor
//! will take ([`FactorInfo::factor_bytes`]) is known before it is allocated.

use std::sync::Arc;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, simplicial, CholeskySymbolicParams, LltRef, SymbolicCholesky,
    SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

use crate::CscMatrix;

pub mod kkt;
pub mod ldlt;
pub mod ordering;

pub use ordering::{fill_reducing_order, kkt_order, order_with, FillOrdering, OrderingMethod};

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
    /// A pivot of an LDLᵀ factor was zero or not finite after the dynamic regularisation
    /// ([`ldlt::Regularisation`]).
    #[error("LDLᵀ pivot {index} of {n} is zero or not finite after the regularisation")]
    ZeroPivot {
        /// Index (in the factorisation's ordering) of the failing pivot.
        index: usize,
        /// Size of the matrix.
        n: usize,
    },
    /// The fill-reducing ordering failed (METIS refused the graph or ran out of memory).
    #[error("fill-reducing ordering failed: {0}")]
    Ordering(String),
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

/// What the symbolic analysis found out about a factor, before any number is computed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FactorInfo {
    /// The fill-reducing ordering used.
    pub ordering: OrderingMethod,
    /// Size n of the matrix.
    pub n: usize,
    /// Nonzeros of the lower triangle of L, diagonal included (the exact count from the
    /// elimination tree).
    pub nnz_l: usize,
    /// Values the supernodal factor stores: its dense diagonal blocks hold their upper
    /// triangles too, and relaxed supernodes hold explicit zeros, so `nnz_l` ≤ `stored_values`.
    pub stored_values: usize,
    /// Supernodes of the factor.
    pub supernodes: usize,
    /// Floating-point operations of the numeric factorisation, Σⱼ cⱼ² over the column counts
    /// cⱼ of L (the usual count; multiply-adds counted as two).
    pub flops: f64,
}

impl FactorInfo {
    /// Bytes of the factor's values (8 per stored value).
    pub fn factor_bytes(&self) -> f64 {
        8.0 * self.stored_values as f64
    }

    fn of(
        symbolic: &SymbolicCholesky<usize>,
        method: OrderingMethod,
        a: &CscMatrix,
    ) -> Result<Self, LinalgError> {
        let n = symbolic.nrows();
        if a.rows() != n || a.cols() != n {
            return Err(LinalgError::Shape {
                rows: a.rows(),
                cols: a.cols(),
            });
        }
        let inverse: Vec<usize> = match symbolic.perm() {
            Some(perm) => perm.arrays().1.to_vec(),
            None => (0..n).collect(),
        };
        let counts = column_counts(a, &inverse)?;
        let supernodes = match symbolic.raw() {
            SymbolicCholeskyRaw::Supernodal(s) => s.n_supernodes(),
            SymbolicCholeskyRaw::Simplicial(_) => 0,
        };
        Ok(Self {
            ordering: method,
            n,
            nnz_l: counts.iter().sum(),
            stored_values: symbolic.len_val(),
            supernodes,
            flops: counts.iter().map(|&c| (c as f64) * (c as f64)).sum(),
        })
    }
}

/// The column counts of L (diagonal included) for P A Pᵀ, `inverse[old] = new`: the exact
/// nonzero pattern, without the explicit zeros a relaxed supernodal factor stores.
pub fn column_counts(a: &CscMatrix, inverse: &[usize]) -> Result<Vec<usize>, LinalgError> {
    let n = a.rows();
    let view = faer_view(a)?;
    let sym = view.symbolic();
    // The upper triangle of P A Pᵀ (what faer's elimination-tree routine reads), from either
    // stored triangle of A; duplicates and unsorted rows are harmless there.
    let mut col_ptr = vec![0usize; n + 1];
    for j in 0..n {
        for i in sym.row_idx_of_col(j) {
            let (p, q) = (inverse[i], inverse[j]);
            col_ptr[p.max(q) + 1] += 1;
        }
    }
    for j in 0..n {
        col_ptr[j + 1] += col_ptr[j];
    }
    let mut fill = col_ptr.clone();
    let mut row_idx = vec![0usize; col_ptr[n]];
    for j in 0..n {
        for i in sym.row_idx_of_col(j) {
            let (p, q) = (inverse[i], inverse[j]);
            row_idx[fill[p.max(q)]] = p.min(q);
            fill[p.max(q)] += 1;
        }
    }
    let upper = SymbolicSparseColMatRef::new_unsorted_checked(n, n, &col_ptr, None, &row_idx);
    let mut etree = vec![0isize; n];
    let mut counts = vec![0usize; n];
    let mut buffer = MemBuffer::try_new(
        simplicial::prefactorize_symbolic_cholesky_scratch::<usize>(n, 0),
    )
    .map_err(|e| LinalgError::Faer(format!("{e:?}")))?;
    simplicial::prefactorize_symbolic_cholesky(
        &mut etree,
        &mut counts,
        upper,
        MemStack::new(&mut buffer),
    );
    Ok(counts)
}

/// How a symbolic analysis lays the factor out.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Layout {
    /// Supernodal always: every factor of A (the dual backends read the trailing block off
    /// its supernodes).
    Supernodal,
    /// Simplicial or supernodal as faer's flop ratio chooses: the timing floor's LLᵀ of A
    /// (pdas's KKT factor takes the same rule, [`ldlt::EliminationTree::suits_simplicial`], with
    /// the project's own simplicial kernel).
    FaerChoice,
}

/// The symbolic analysis of a sparsity pattern (ordering, elimination tree, supernodes),
/// reusable for every matrix with that pattern.
#[derive(Debug, Clone)]
pub struct CholeskyPattern {
    symbolic: Arc<SymbolicCholesky<usize>>,
    method: OrderingMethod,
}

impl CholeskyPattern {
    /// Orders the pattern of the symmetric matrix `a` by [`fill_reducing_order`] and analyses it
    /// (its lower triangle is read).
    pub fn analyse(a: &CscMatrix) -> Result<Self, LinalgError> {
        let ordering = fill_reducing_order(a)?;
        Self::analyse_with(a, &ordering)
    }

    /// Analyses the pattern of `a` under a given ordering (e.g. [`fill_reducing_order`]'s with
    /// some DOFs moved last), forced supernodal as every factor of A in the project.
    pub fn analyse_with(a: &CscMatrix, ordering: &FillOrdering) -> Result<Self, LinalgError> {
        Self::analyse_laid_out(a, ordering, Layout::Supernodal)
    }

    /// Analyses the pattern of `a` under a given ordering, laid out as `layout` says (the
    /// symbolic factor of every factorisation in the project, LLᵀ of A or LDLᵀ of a KKT
    /// matrix, comes from here).
    pub fn analyse_laid_out(
        a: &CscMatrix,
        ordering: &FillOrdering,
        layout: Layout,
    ) -> Result<Self, LinalgError> {
        let n = a.rows();
        if a.cols() != n {
            return Err(LinalgError::Shape {
                rows: n,
                cols: a.cols(),
            });
        }
        if ordering.forward.len() != n || ordering.inverse.len() != n {
            return Err(LinalgError::Ordering(format!(
                "the ordering has {} entries for a matrix of size {n}",
                ordering.forward.len()
            )));
        }
        let view = faer_view(a)?;
        // inverse ∘ forward = id makes `forward` injective, hence a permutation with inverse
        // `inverse`: what `PermRef::new_checked` asserts, checked here so it cannot panic.
        let is_permutation = ordering
            .forward
            .iter()
            .enumerate()
            .all(|(new, &old)| old < n && ordering.inverse[old] == new);
        if !is_permutation {
            return Err(LinalgError::Ordering(
                "the ordering is not a permutation".into(),
            ));
        }
        let perm = PermRef::new_checked(&ordering.forward, &ordering.inverse, n);
        let symbolic = factorize_symbolic_cholesky(
            view.symbolic(),
            Side::Lower,
            SymmetricOrdering::Custom(perm),
            params(layout),
        )
        .map_err(|e| LinalgError::Faer(format!("{e:?}")))?;
        Ok(Self {
            symbolic: Arc::new(symbolic),
            method: ordering.method,
        })
    }

    /// Analyses the pattern `a` of a matrix already laid out in its elimination order (found
    /// by `method`), which stores the triangle `side`: no permutation, so every numeric
    /// factorisation reads the matrix in place — when `side` is the triangle faer's kernel
    /// reads, see [`CholeskyPattern::reads`].  Rows may be unsorted within a column.
    pub fn analyse_ordered(
        a: SymbolicSparseColMatRef<'_, usize>,
        side: Side,
        method: OrderingMethod,
        layout: Layout,
    ) -> Result<Self, LinalgError> {
        let symbolic =
            factorize_symbolic_cholesky(a, side, SymmetricOrdering::Identity, params(layout))
                .map_err(|e| LinalgError::Faer(format!("{e:?}")))?;
        Ok(Self {
            symbolic: Arc::new(symbolic),
            method,
        })
    }

    /// The triangle the numeric factorisation reads in place (the upper one for a simplicial
    /// factor, the lower for a supernodal one); the other is copied over on every
    /// factorisation.
    pub fn reads(&self) -> Side {
        match self.symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(_) => Side::Upper,
            SymbolicCholeskyRaw::Supernodal(_) => Side::Lower,
        }
    }

    /// What the analysis found: ordering, nnz(L), flops, for the matrix `a` it analysed.  The
    /// exact nnz(L) costs one more elimination-tree pass over A (≈ 8 % of a factorisation at
    /// 10⁵ DOFs), which is why it is asked for apart, outside the timed floor.
    pub fn info(&self, a: &CscMatrix) -> Result<FactorInfo, LinalgError> {
        FactorInfo::of(&self.symbolic, self.method, a)
    }

    /// The ordering used.
    pub fn ordering(&self) -> OrderingMethod {
        self.method
    }

    /// Size n of the analysed matrix.
    pub fn dim(&self) -> usize {
        self.symbolic.nrows()
    }

    /// faer's symbolic factor (supernodal), for callers that read the factor's blocks (the dual
    /// backend's trailing block) through faer's `SupernodalLltRef`.
    pub fn symbolic(&self) -> &SymbolicCholesky<usize> {
        &self.symbolic
    }

    /// Values the supernodal factor will store (8 B each), known before it is computed.
    pub fn stored_values(&self) -> usize {
        self.symbolic.len_val()
    }

    /// Bytes of the scratch space the numeric factorisation allocates besides the factor (the
    /// largest frontal update), from the symbolic analysis.
    pub fn numeric_scratch_bytes(&self) -> f64 {
        self.symbolic
            .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default())
            .size_bytes() as f64
    }

    /// Numeric factorisation of `a`, which must have the analysed pattern (one thread).
    pub fn factor(&self, a: &CscMatrix) -> Result<SparseCholesky, LinalgError> {
        let n = self.dim();
        if a.rows() != n || a.cols() != n {
            return Err(LinalgError::Shape {
                rows: a.rows(),
                cols: a.cols(),
            });
        }
        let values = numeric_llt(&self.symbolic, a)?;
        Ok(SparseCholesky {
            symbolic: Arc::clone(&self.symbolic),
            values,
            method: self.method,
        })
    }
}

/// faer's symbolic parameters for a layout.
fn params(layout: Layout) -> CholeskySymbolicParams<'static> {
    match layout {
        Layout::Supernodal => CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
            ..Default::default()
        },
        Layout::FaerChoice => CholeskySymbolicParams::default(),
    }
}

/// The numeric LLᵀ (one thread) of `a` on the supernodal or simplicial `symbolic` analysis of its
/// pattern: the factor's values.  The one numeric factorisation of A in the project — the floor,
/// the no-contact solve and the dual backends' contact-last factor all come through here.
pub fn numeric_llt(
    symbolic: &SymbolicCholesky<usize>,
    a: &CscMatrix,
) -> Result<Vec<f64>, LinalgError> {
    let n = symbolic.nrows();
    let view = faer_view(a)?;
    let oom = |e: faer::dyn_stack::mem::AllocError| LinalgError::Faer(format!("{e:?}"));
    let mut values = Vec::new();
    values
        .try_reserve_exact(symbolic.len_val())
        .map_err(|e| LinalgError::Faer(format!("cannot allocate the factor: {e}")))?;
    values.resize(symbolic.len_val(), 0.0);
    let mut buffer = MemBuffer::try_new(
        symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
    )
    .map_err(oom)?;
    symbolic
        .factorize_numeric_llt(
            &mut values,
            view,
            Side::Lower,
            Default::default(),
            Par::Seq,
            MemStack::new(&mut buffer),
            Default::default(),
        )
        .map_err(|e| match e {
            faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot { index } => {
                LinalgError::NotPositiveDefinite { index, n }
            }
        })?;
    Ok(values)
}

/// A numeric Cholesky factorisation P A Pᵀ = L Lᵀ.
#[derive(Debug, Clone)]
pub struct SparseCholesky {
    symbolic: Arc<SymbolicCholesky<usize>>,
    values: Vec<f64>,
    method: OrderingMethod,
}

impl SparseCholesky {
    /// Orders, analyses and factors the symmetric positive definite `a` in one go.
    ///
    /// ```
    /// use signorini_qp::linalg::SparseCholesky;
    /// use sprs::TriMat;
    /// let mut a = TriMat::new((2, 2));
    /// for (i, j, v) in [(0, 0, 4.0), (1, 1, 3.0), (0, 1, 1.0), (1, 0, 1.0)] {
    ///     a.add_triplet(i, j, v);
    /// }
    /// let chol = SparseCholesky::factor(&a.to_csc()).unwrap();
    /// let mut x = vec![5.0, 4.0];
    /// chol.solve_in_place(&mut x);
    /// assert!((x[0] - 1.0).abs() < 1e-14 && (x[1] - 1.0).abs() < 1e-14);
    /// assert_eq!(chol.info(&a.to_csc()).unwrap().nnz_l, 3);
    /// ```
    pub fn factor(a: &CscMatrix) -> Result<Self, LinalgError> {
        CholeskyPattern::analyse(a)?.factor(a)
    }

    /// Size n of the factored matrix.
    pub fn dim(&self) -> usize {
        self.symbolic.nrows()
    }

    /// Ordering and size of the factor of `a` (the matrix factored), see
    /// [`CholeskyPattern::info`].
    pub fn info(&self, a: &CscMatrix) -> Result<FactorInfo, LinalgError> {
        FactorInfo::of(&self.symbolic, self.method, a)
    }

    /// faer's symbolic factor and the numeric values, for callers that read L's blocks through
    /// faer (`LltRef::new(symbolic, values)`, or `SupernodalLltRef` on its supernodal part).
    pub fn raw(&self) -> (&SymbolicCholesky<usize>, &[f64]) {
        (&self.symbolic, &self.values)
    }

    /// Overwrites `rhs` (length n) with A⁻¹ rhs.
    pub fn solve_in_place(&self, rhs: &mut [f64]) {
        debug_assert_eq!(rhs.len(), self.dim());
        self.solve_many_in_place(rhs);
    }

    /// Overwrites the column-major n×k block `rhs` with A⁻¹ rhs (k = rhs.len() / n).
    pub fn solve_many_in_place(&self, rhs: &mut [f64]) {
        let n = self.dim();
        if n == 0 {
            return;
        }
        let k = rhs.len() / n;
        debug_assert_eq!(rhs.len(), k * n);
        let mut buffer = MemBuffer::new(self.symbolic.solve_in_place_scratch::<f64>(k, Par::Seq));
        LltRef::new(&self.symbolic, &self.values).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, n, k),
            Par::Seq,
            MemStack::new(&mut buffer),
        );
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::examples::{eliminated_nnz, two_dof_grid};
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
            let mut b = crate::mat_vec(&a_s, &x_true);
            chol.solve_in_place(&mut b);
            for (x, y) in b.iter().zip(&x_true) {
                assert!((x - y).abs() < 1e-10, "{x} vs {y} at scale {scale}");
            }
        }
    }

    #[test]
    fn amd_and_metis_factors_solve_to_1e10_and_count_l_exactly() {
        let a = two_dof_grid(14);
        let n = a.rows();
        let x_true: Vec<f64> = (0..n).map(|i| (0.37 * i as f64).sin() + 0.1).collect();
        let b = crate::mat_vec(&a, &x_true);
        let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
        for method in OrderingMethod::ALL {
            let ordering = order_with(&a, method).unwrap();
            let pattern = CholeskyPattern::analyse_with(&a, &ordering).unwrap();
            let info = pattern.info(&a).unwrap();
            assert_eq!(info.ordering, method);
            assert_eq!(
                info.nnz_l,
                eliminated_nnz(&a, &ordering.inverse),
                "{method}"
            );
            assert!(info.stored_values >= info.nnz_l);
            let chol = pattern.factor(&a).unwrap();
            let mut x = b.clone();
            chol.solve_in_place(&mut x);
            let err: Vec<f64> = x.iter().zip(&x_true).map(|(p, q)| p - q).collect();
            // The matrix is diagonally dominant (condition number < 10), so a backward-stable
            // Cholesky gives a relative error of a few ulps × n; 1e-10 is the task's bound.
            assert!(
                norm(&err) / norm(&x_true) < 1e-10,
                "{method}: {}",
                norm(&err)
            );
        }
    }

    #[test]
    fn a_permuted_ordering_that_is_not_one_is_refused() {
        let a = laplacian(4);
        let bad = FillOrdering {
            forward: vec![0, 1, 1, 3],
            inverse: vec![0, 1, 2, 3],
            method: OrderingMethod::Amd,
        };
        assert!(matches!(
            CholeskyPattern::analyse_with(&a, &bad),
            Err(LinalgError::Ordering(_))
        ));
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
