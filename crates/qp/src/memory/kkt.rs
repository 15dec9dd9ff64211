//! The memory a solver that factors the quasidefinite KKT matrix
//! [A + σI, Bᵀ; B, −D] (clarabel, OSQP) needs, from the symbolic analysis of that matrix's
//! pattern ([`crate::linalg::kkt`], ordered by AMD as the solvers order it) before the solver
//! allocates anything.  Each backend states its own [`KktModel`] (how many factors and copies it
//! keeps); the arithmetic is here, once.

use crate::linalg::kkt::{kkt_pattern, kkt_pattern_entries};
use crate::linalg::CholeskyPattern;
use crate::{CscMatrix, QpError, QpProblem};

use super::check_fits;

/// Bytes of one stored entry of a CSC matrix: its value and its row index.
const ENTRY_BYTES: f64 = 16.0;

/// Bytes per entry of K that the symbolic analysis holds at its peak: the pattern itself, its
/// symmetric copy inside the AMD ordering and the elimination-tree work arrays (three patterns'
/// worth, counted generously).
const ANALYSIS_BYTES_PER_ENTRY: f64 = 3.0 * ENTRY_BYTES;

/// How a KKT solver holds its memory, in units the symbolic analysis can price: the documented
/// model of one backend (see the constants of `signorini-clarabel` and `signorini-osqp`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KktModel {
    /// LDLᵀ factors of K held at once (OSQP's polish factors a second KKT matrix, at most as
    /// large, while the first is kept).
    pub factors: f64,
    /// Bytes per nonzero of L: 8 for the value and 8 for a row index (qdldl's `Lx`, `Li`;
    /// faer's supernodal factor, 8 B per stored value with fewer indices, stays below 16 B per
    /// nonzero while it stores fewer than twice nnz(L), as on 2D stiffness patterns).
    pub bytes_per_value: f64,
    /// Copies of K's lower or upper triangle the solver keeps (the assembled K, its permuted
    /// copy), at 16 B per entry plus 8 B for the map from the data into K.
    pub kkt_copies: f64,
    /// Copies of A and B (16 B per stored entry) the solver and the hand-over keep: the
    /// rescaled problem, the CSC parts handed over, the solver's own (equilibrated) data.
    pub data_copies: f64,
    /// Vectors of n + m doubles the solver keeps (iterates, residuals, step directions, scaling,
    /// the answer copied back).
    pub vectors: f64,
}

/// A KKT solver's estimated peak memory, bytes, before it runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KktEstimate {
    /// Size n + m of K.
    pub dim: usize,
    /// Entries of K's lower triangle (diagonal included).
    pub kkt_entries: usize,
    /// Nonzeros of L (lower triangle, diagonal included) under AMD: the exact count from the
    /// elimination tree, what qdldl stores.  (faer's supernodal storage would add explicit
    /// zeros: 1.3–1.4× on 2D stiffness patterns but 7× on a chain, so it is not the measure.)
    pub nnz_l: usize,
    /// The factor(s): `factors × bytes_per_value × nnz_l`.
    pub factor: f64,
    /// The numeric factorisation's scratch space (its largest frontal update).
    pub scratch: f64,
    /// The copies of K and of A and B.
    pub matrices: f64,
    /// The vectors of length n + m.
    pub vectors: f64,
}

impl KktEstimate {
    /// Analyses K's pattern for `problem` and prices it with `model`.  The analysis itself
    /// (O(nnz(K)), well below the factor) is checked with [`check_fits`] before it allocates.
    ///
    /// # Errors
    /// [`QpError::TooLarge`] when even the analysis would not fit; [`QpError::Backend`] when it
    /// fails.
    pub fn of(
        backend: &'static str,
        problem: &QpProblem,
        model: &KktModel,
    ) -> Result<Self, QpError> {
        let (a, b) = (&problem.stiffness, &problem.constraints);
        let dim = problem.dofs() + problem.rows();
        let entries = kkt_pattern_entries(a, b);
        check_fits(
            backend,
            || format!("the symbolic analysis of the {dim}×{dim} KKT matrix ({entries} entries)"),
            ANALYSIS_BYTES_PER_ENTRY * entries as f64 + 8.0 * 8.0 * dim as f64,
        )?;
        let failed = |e: crate::linalg::LinalgError| QpError::Backend {
            backend,
            reason: format!("symbolic analysis of the KKT matrix: {e}"),
        };
        let pattern = kkt_pattern(a, b).map_err(failed)?;
        let analysis = CholeskyPattern::analyse(&pattern).map_err(failed)?;
        let nnz_l = analysis.info(&pattern).map_err(failed)?.nnz_l;
        Ok(Self::priced(&pattern, &analysis, nnz_l, problem, model))
    }

    fn priced(
        pattern: &CscMatrix,
        analysis: &CholeskyPattern,
        nnz_l: usize,
        problem: &QpProblem,
        model: &KktModel,
    ) -> Self {
        let dim = pattern.rows();
        let data = (problem.stiffness.nnz() + problem.constraints.nnz()) as f64;
        Self {
            dim,
            kkt_entries: pattern.nnz(),
            nnz_l,
            factor: model.factors * model.bytes_per_value * nnz_l as f64,
            scratch: analysis.numeric_scratch_bytes(),
            matrices: model.kkt_copies * (ENTRY_BYTES + 8.0) * pattern.nnz() as f64
                + model.data_copies * ENTRY_BYTES * data,
            vectors: model.vectors * 8.0 * dim as f64,
        }
    }

    /// The total, bytes.
    pub fn total(&self) -> f64 {
        self.factor + self.scratch + self.matrices + self.vectors
    }

    /// `Err(QpError::TooLarge)` naming the KKT factor when [`KktEstimate::total`] does not fit.
    pub fn check(&self, backend: &'static str) -> Result<(), QpError> {
        check_fits(
            backend,
            || {
                format!(
                    "the LDLᵀ factor of the {dim}×{dim} KKT matrix (nnz(L) = {nnz:.3e}), \
                     the solver's copies of the data and its vectors",
                    dim = self.dim,
                    nnz = self.nnz_l as f64
                )
            },
            self.total(),
        )
    }
}
