//! The QP's data: matrices, vectors and their checks.

use super::blocks::{row_sets, BlockKind, ConstraintBlock, RowSet};
use super::ops::{dot, mat_vec};

pub use super::ops::CscMatrix;

/// Why a QP could not even be attempted (as opposed to a solve that did not converge, which is a
/// [`QpStatus`](super::QpStatus)).
#[derive(Debug, thiserror::Error)]
pub enum QpError {
    /// Matrix or vector dimensions disagree.
    #[error("QP dimensions disagree: {0}")]
    Dimensions(String),
    /// A matrix is not stored in compressed-sparse-column form.
    #[error("QP matrix `{0}` must be in CSC storage")]
    NotCsc(&'static str),
    /// An entry is NaN or infinite.
    #[error("QP data `{0}` holds a NaN or infinite entry")]
    NotFinite(&'static str),
    /// The backend was not compiled in or cannot run on this problem.
    #[error("backend `{backend}` cannot run: {reason}")]
    Unavailable {
        /// Backend name.
        backend: &'static str,
        /// What is missing.
        reason: String,
    },
    /// The work would need more memory than the machine has free (checked before allocating it,
    /// see [`crate::memory`]).
    #[error(
        "backend `{backend}` refused: {what} would need {} but {} is available",
        crate::memory::gib_f64(*.needed),
        crate::memory::gib_f64(*.available)
    )]
    TooLarge {
        /// Backend name.
        backend: &'static str,
        /// What would be allocated (e.g. "the sparse factor of A (nnz(L) = 1.2e8)").
        what: String,
        /// Estimated need, GiB.
        needed: f64,
        /// Memory available to the process, GiB.
        available: f64,
    },
    /// The problem holds a block of constraint rows the backend does not solve (see
    /// [`crate::QpBackend::supports`]).
    #[error("backend `{backend}` does not solve {kind} constraint rows (it solves: {supported})")]
    UnsupportedBlock {
        /// Backend name.
        backend: &'static str,
        /// The kind it does not solve.
        kind: BlockKind,
        /// The kinds it solves, comma-separated.
        supported: String,
    },
    /// The backend failed in a way it could not express as a status.
    #[error("backend `{backend}` failed: {reason}")]
    Backend {
        /// Backend name.
        backend: &'static str,
        /// The backend's message.
        reason: String,
    },
}

/// `min ½ xᵀ A x − fᵀ x  s.t.  B x ≤ g`, all matrices in CSC; the rows of B and g come in
/// [`ConstraintBlock`]s (one non-negative block unless [`QpProblem::with_blocks`] says otherwise).
#[derive(Debug, Clone)]
pub struct QpProblem {
    /// A: symmetric stiffness on the free DOFs, n×n, both triangles stored.
    pub stiffness: CscMatrix,
    /// f: load vector, length n.
    pub load: Vec<f64>,
    /// B: contact constraint rows, m×n.
    pub constraints: CscMatrix,
    /// g: right-hand side of the constraints (initial gaps), length m.
    pub gap: Vec<f64>,
    /// A basis of the null space of A known from the model (rigid-body modes of bodies that only
    /// contact holds), each vector of length n; empty when A is positive definite.
    pub kernel: Vec<Vec<f64>>,
    /// The rows of B and g in consecutive blocks, each with its multiplier set; their row counts
    /// add up to m.
    pub blocks: Vec<ConstraintBlock>,
}

impl QpProblem {
    /// Checks dimensions, storage and finiteness, then builds the problem.
    ///
    /// ```
    /// use signorini_qp::QpProblem;
    /// use sprs::TriMat;
    /// let mut a = TriMat::new((1, 1));
    /// a.add_triplet(0, 0, 2.0);
    /// let mut b = TriMat::new((1, 1));
    /// b.add_triplet(0, 0, 1.0);
    /// let qp = QpProblem::try_new(a.to_csc(), vec![4.0], b.to_csc(), vec![1.0]).unwrap();
    /// assert_eq!((qp.dofs(), qp.rows()), (1, 1));
    /// ```
    pub fn try_new(
        stiffness: CscMatrix,
        load: Vec<f64>,
        constraints: CscMatrix,
        gap: Vec<f64>,
    ) -> Result<Self, QpError> {
        let rows = constraints.rows();
        let problem = Self {
            stiffness,
            load,
            constraints,
            gap,
            kernel: Vec::new(),
            blocks: vec![ConstraintBlock::NonNegative { rows }],
        };
        problem.validate()?;
        Ok(problem)
    }

    /// Checks dimensions, CSC storage and finiteness.  The fields are public, so a backend calls
    /// this before handing the data to a solver whose constructors assert.
    pub fn validate(&self) -> Result<(), QpError> {
        let n = self.stiffness.rows();
        if self.stiffness.cols() != n {
            return Err(QpError::Dimensions(format!(
                "A is {}×{}, not square",
                n,
                self.stiffness.cols()
            )));
        }
        if self.load.len() != n {
            return Err(QpError::Dimensions(format!(
                "f has length {} but A is {n}×{n}",
                self.load.len()
            )));
        }
        if self.constraints.cols() != n {
            return Err(QpError::Dimensions(format!(
                "B has {} columns but A is {n}×{n}",
                self.constraints.cols()
            )));
        }
        if self.gap.len() != self.constraints.rows() {
            return Err(QpError::Dimensions(format!(
                "g has length {} but B has {} rows",
                self.gap.len(),
                self.constraints.rows()
            )));
        }
        if let Some(v) = self.kernel.iter().find(|v| v.len() != n) {
            return Err(QpError::Dimensions(format!(
                "kernel vector has length {} but A is {n}×{n}",
                v.len()
            )));
        }
        let block_rows: usize = self.blocks.iter().map(ConstraintBlock::rows).sum();
        if block_rows != self.constraints.rows() {
            return Err(QpError::Dimensions(format!(
                "the constraint blocks hold {block_rows} rows but B has {}",
                self.constraints.rows()
            )));
        }
        if !self.stiffness.is_csc() {
            return Err(QpError::NotCsc("A"));
        }
        if !self.constraints.is_csc() {
            return Err(QpError::NotCsc("B"));
        }
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        if !finite(self.stiffness.data()) {
            return Err(QpError::NotFinite("A"));
        }
        if !finite(&self.load) {
            return Err(QpError::NotFinite("f"));
        }
        if !finite(self.constraints.data()) {
            return Err(QpError::NotFinite("B"));
        }
        if !finite(&self.gap) {
            return Err(QpError::NotFinite("g"));
        }
        if self.kernel.iter().any(|v| !finite(v)) {
            return Err(QpError::NotFinite("kernel"));
        }
        for block in &self.blocks {
            if let ConstraintBlock::Box { bounds } = block {
                if !finite(bounds) {
                    return Err(QpError::NotFinite("box bounds"));
                }
                if let Some(s) = bounds.iter().find(|s| **s < 0.0) {
                    return Err(QpError::Dimensions(format!(
                        "a box row's bound is {s}, not ≥ 0"
                    )));
                }
            }
        }
        Ok(())
    }

    /// Sets the constraint blocks (see [`QpProblem::blocks`]), checked like the rest.
    ///
    /// ```
    /// use signorini_qp::{ConstraintBlock, QpProblem};
    /// use sprs::TriMat;
    /// let mut a = TriMat::new((1, 1));
    /// a.add_triplet(0, 0, 1.0);
    /// let mut b = TriMat::new((2, 1));
    /// b.add_triplet(0, 0, 1.0);
    /// b.add_triplet(1, 0, -1.0);
    /// let qp = QpProblem::try_new(a.to_csc(), vec![1.0], b.to_csc(), vec![1.0, 0.0]).unwrap();
    /// let friction = vec![
    ///     ConstraintBlock::NonNegative { rows: 1 },
    ///     ConstraintBlock::Box { bounds: vec![0.5] },
    /// ];
    /// assert!(qp.clone().with_blocks(friction).is_ok());
    /// let short = vec![ConstraintBlock::NonNegative { rows: 1 }];
    /// assert!(qp.with_blocks(short).is_err());
    /// ```
    pub fn with_blocks(mut self, blocks: Vec<ConstraintBlock>) -> Result<Self, QpError> {
        self.blocks = blocks;
        self.validate()?;
        Ok(self)
    }

    /// The kinds of block the problem holds, each once, in the order they first appear.
    pub fn block_kinds(&self) -> Vec<BlockKind> {
        let mut kinds = Vec::new();
        for kind in self.blocks.iter().map(ConstraintBlock::kind) {
            if !kinds.contains(&kind) {
                kinds.push(kind);
            }
        }
        kinds
    }
    /// Attaches a known null-space basis of A (see [`QpProblem::kernel`]).
    pub fn with_kernel(mut self, kernel: Vec<Vec<f64>>) -> Result<Self, QpError> {
        self.kernel = kernel;
        self.validate()?;
        Ok(self)
    }

    /// Number of unknowns n.
    pub fn dofs(&self) -> usize {
        self.stiffness.rows()
    }

    /// Number of constraint rows m.
    pub fn rows(&self) -> usize {
        self.constraints.rows()
    }

    /// The objective ½ xᵀ A x − fᵀ x, plus Σ sᵢ |(B x − g)ᵢ| over the box rows.
    pub fn objective(&self, x: &[f64]) -> f64 {
        let ax = mat_vec(&self.stiffness, x);
        let quadratic = 0.5 * dot(x, &ax) - dot(&self.load, x);
        if !self.blocks.iter().any(|b| b.kind() == BlockKind::Box) {
            return quadratic;
        }
        let r = mat_vec(&self.constraints, x);
        let slip: f64 = row_sets(&self.blocks)
            .zip(r.iter().zip(&self.gap))
            .map(|(set, (bx, g))| match set {
                RowSet::Box(s) => s * (bx - g).abs(),
                RowSet::NonNegative => 0.0,
            })
            .sum();
        quadratic + slip
    }
}
