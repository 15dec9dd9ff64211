//! The sparse LDLᵀ factor of the KKT matrix: one symbolic analysis (the project's shared
//! [`CholeskyPattern`], ordered by [`signorini_qp::linalg::kkt_order`]), a numeric
//! factorisation per active set, and solves with it.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::ldlt::factor::LdltRegularization;
use faer::sparse::linalg::cholesky::{LdltRef, SymbolicCholesky};
use faer::{Conj, MatMut, Par, Side};
use signorini_qp::linalg::{
    faer_view, kkt_order, CholeskyPattern, Layout, LinalgError, OrderingMethod,
};
use signorini_qp::CscMatrix;

use crate::error::PdasError;

/// The symbolic factor of K's pattern and the numeric values of the last factorisation.
pub struct KktFactor {
    pattern: CholeskyPattern,
    values: Vec<f64>,
    /// +1 on the primal block, −1 on the multiplier block (faer's dynamic regularisation).
    signs: Vec<i8>,
    buffer: MemBuffer,
    scratch_bytes: usize,
}

impl std::fmt::Debug for KktFactor {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("KktFactor")
            .field("dim", &self.signs.len())
            .field("nnz_l", &self.values.len())
            .field("method", &self.pattern.ordering())
            .finish()
    }
}

impl KktFactor {
    /// Orders the symmetric pattern of `k` (lower triangle of an (n + m) square matrix, the
    /// first `dofs` unknowns primal) and analyses it.  The values are not allocated yet (see
    /// [`KktFactor::bytes_needed`], [`KktFactor::allocate`]).
    pub fn analyse(k: &CscMatrix, dofs: usize) -> Result<Self, PdasError> {
        let dim = k.rows();
        let ordering = kkt_order(k).map_err(|e| PdasError::Symbolic(e.to_string()))?;
        let pattern = CholeskyPattern::analyse_laid_out(k, &ordering, Layout::FaerChoice).map_err(
            |e| match e {
                // faer's own failure, as its message.
                LinalgError::Faer(message) => PdasError::Symbolic(message),
                other => PdasError::Symbolic(other.to_string()),
            },
        )?;
        let scratch = scratch(pattern.symbolic());
        let signs = (0..dim).map(|i| if i < dofs { 1 } else { -1 }).collect();
        Ok(Self {
            pattern,
            values: Vec::new(),
            signs,
            buffer: MemBuffer::new(StackReq::EMPTY),
            scratch_bytes: scratch.size_bytes(),
        })
    }

    /// faer's symbolic factor.
    fn symbolic(&self) -> &SymbolicCholesky<usize> {
        self.pattern.symbolic()
    }

    /// Stored entries of the factor L (and D): the length of its value array.
    pub fn nnz_l(&self) -> usize {
        self.pattern.stored_values()
    }

    /// The ordering method that ordered K.
    pub fn method(&self) -> OrderingMethod {
        self.pattern.ordering()
    }

    /// Bytes the numeric factorisation will hold: the factor's values plus faer's workspace.
    pub fn bytes_needed(&self) -> f64 {
        (self.nnz_l() * std::mem::size_of::<f64>() + self.scratch_bytes) as f64
    }

    /// Allocates the factor's values and the workspace (call once, after the memory check).
    pub fn allocate(&mut self) -> Result<(), PdasError> {
        let scratch = scratch(self.symbolic());
        self.buffer =
            MemBuffer::try_new(scratch).map_err(|e| PdasError::Numeric(format!("{e:?}")))?;
        let mut values = Vec::new();
        values
            .try_reserve_exact(self.nnz_l())
            .map_err(|e| PdasError::Numeric(format!("factor of {} entries: {e}", self.nnz_l())))?;
        values.resize(self.nnz_l(), 0.0);
        self.values = values;
        Ok(())
    }

    /// Numeric LDLᵀ of `k` (same pattern as analysed).  A pivot of the wrong sign or smaller
    /// than `epsilon` in magnitude is replaced by ±`delta` (faer's dynamic regularisation).
    pub fn factor(&mut self, k: &CscMatrix, epsilon: f64, delta: f64) -> Result<(), PdasError> {
        if self.values.len() != self.nnz_l() {
            self.allocate()?;
        }
        let view = faer_view(k).map_err(|e| PdasError::Numeric(e.to_string()))?;
        let regularization = LdltRegularization {
            dynamic_regularization_signs: Some(&self.signs),
            dynamic_regularization_delta: delta,
            dynamic_regularization_epsilon: epsilon,
        };
        self.pattern
            .symbolic()
            .factorize_numeric_ldlt(
                &mut self.values,
                view,
                Side::Lower,
                regularization,
                Par::Seq,
                MemStack::new(&mut self.buffer),
                Default::default(),
            )
            .map(|_| ())
            .map_err(|e| PdasError::Numeric(format!("{e:?}")))
    }

    /// Overwrites the column-major (n + m) × k block `rhs` with K⁻¹ rhs (k = rhs.len() / (n + m)),
    /// one supernodal sweep for all k columns.
    pub fn solve_many_in_place(&mut self, rhs: &mut [f64]) -> Result<(), PdasError> {
        let dim = self.signs.len();
        if dim == 0 || rhs.is_empty() {
            return Ok(());
        }
        let k = rhs.len() / dim;
        let mut buffer =
            MemBuffer::try_new(self.symbolic().solve_in_place_scratch::<f64>(k, Par::Seq))
                .map_err(|e| PdasError::Numeric(format!("{e:?}")))?;
        let ldlt = LdltRef::new(self.pattern.symbolic(), &self.values);
        ldlt.solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, dim, k),
            Par::Seq,
            MemStack::new(&mut buffer),
        );
        Ok(())
    }

    /// Overwrites `rhs` (length n + m) with K⁻¹ rhs for the last factorised K.
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) {
        let dim = self.signs.len();
        if dim == 0 {
            return;
        }
        let ldlt = LdltRef::new(self.pattern.symbolic(), &self.values);
        ldlt.solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, dim, 1),
            Par::Seq,
            MemStack::new(&mut self.buffer),
        );
    }
}

/// The workspace of a numeric LDLᵀ and of a one-column solve with it.
fn scratch(symbolic: &SymbolicCholesky<usize>) -> StackReq {
    StackReq::any_of(&[
        symbolic.factorize_numeric_ldlt_scratch::<f64>(Par::Seq, Default::default()),
        symbolic.solve_in_place_scratch::<f64>(1, Par::Seq),
    ])
}
