//! A generalised inverse A⁺ of the stiffness, from one sparse Cholesky factorisation.
//!
//! When A is positive definite, A⁺ = A⁻¹.  When A has a kernel spanned by R (n × k, floating
//! bodies), k "fixing" DOFs are chosen such that the k × k block of R on them is invertible (see
//! [`crate::kernel`]); the remaining block A_ff is then positive definite and
//!
//! ```text
//! A⁺ = [ A_ff⁻¹  0 ]
//!      [   0     0 ]      satisfies  A A⁺ A = A,
//! ```
//!
//! which is all the FETI-style dual needs.  This keeps the factor as sparse as A's own.

use signorini_core::linalg::SparseCholesky;
use signorini_core::qp::CscMatrix;

use crate::error::DualError;
use crate::trailing::TrailingCholesky;

/// Marker in the full → reduced index map for a fixed DOF.
const FIXED: usize = usize::MAX;

/// The factor behind A⁺ (of A, or of A_ff when DOFs are fixed).
#[derive(Debug)]
pub enum Factor {
    /// Fill-reducing (AMD) order, through the core wrapper.
    Plain(SparseCholesky),
    /// The DOFs B touches ordered last; the trailing block is the Schur complement's factor.
    Trailing(Box<TrailingCholesky>),
}

impl Factor {
    fn dim(&self) -> usize {
        match self {
            Factor::Plain(chol) => chol.dim(),
            Factor::Trailing(chol) => chol.dim(),
        }
    }

    fn solve_many_in_place(&self, block: &mut [f64]) {
        match self {
            Factor::Plain(chol) => chol.solve_many_in_place(block),
            Factor::Trailing(chol) => chol.solve_many_in_place(block),
        }
    }
}

/// A⁺ applied through a cached sparse Cholesky factor.
#[derive(Debug)]
pub struct StiffnessInverse {
    factor: Factor,
    /// Full index → reduced index (`FIXED` for fixed DOFs); empty when nothing is fixed.
    reduced: Vec<usize>,
    /// With a [`Factor::Trailing`]: the full indices of the trailing DOFs, in trailing order.
    trailing: Vec<usize>,
    n: usize,
}

impl StiffnessInverse {
    /// Factors A with the DOFs in `fixed` removed (rows and columns).  With
    /// `trailing_for = Some(B)`, the DOFs that B touches are ordered last
    /// ([`Factor::Trailing`]).
    pub fn new(
        a: &CscMatrix,
        fixed: &[usize],
        kernel_count: usize,
        trailing_for: Option<&CscMatrix>,
    ) -> Result<Self, DualError> {
        let n = a.rows();
        let singular = |source| DualError::Singular {
            source,
            kernel: kernel_count,
        };
        let mut reduced = Vec::new();
        let mut sub = None;
        if !fixed.is_empty() {
            reduced = vec![0; n];
            for &i in fixed {
                reduced[i] = FIXED;
            }
            let mut next = 0;
            for r in reduced.iter_mut() {
                if *r != FIXED {
                    *r = next;
                    next += 1;
                }
            }
            sub = Some(submatrix(a, &reduced, next)?);
        }
        let matrix = sub.as_ref().unwrap_or(a);
        let mut trailing = Vec::new();
        let factor = match trailing_for {
            Some(constraints) => {
                let mut touched_reduced = Vec::new();
                for (j, col) in constraints.outer_iterator().enumerate() {
                    let r = if reduced.is_empty() { j } else { reduced[j] };
                    if col.nnz() > 0 && r != FIXED {
                        trailing.push(j);
                        touched_reduced.push(r);
                    }
                }
                Factor::Trailing(Box::new(
                    TrailingCholesky::factor(matrix, &touched_reduced).map_err(singular)?,
                ))
            }
            None => Factor::Plain(SparseCholesky::factor(matrix).map_err(singular)?),
        };
        Ok(Self {
            factor,
            reduced,
            trailing,
            n,
        })
    }

    /// The factor.
    pub fn factor(&self) -> &Factor {
        &self.factor
    }

    /// Full indices of the trailing DOFs (empty for a [`Factor::Plain`]).
    pub fn trailing(&self) -> &[usize] {
        &self.trailing
    }

    /// Size of the factored block (n minus the fixed DOFs).
    pub fn reduced_dim(&self) -> usize {
        self.factor.dim()
    }

    /// Reduced index of full index `i`, `None` for a fixed DOF.
    pub fn reduced_index(&self, i: usize) -> Option<usize> {
        if self.reduced.is_empty() {
            Some(i)
        } else {
            let r = self.reduced[i];
            (r != FIXED).then_some(r)
        }
    }

    /// Overwrites the column-major reduced block (reduced_dim × k) with A_ff⁻¹ times it.
    pub fn solve_reduced_many(&self, block: &mut [f64]) {
        self.factor.solve_many_in_place(block);
    }

    /// A⁺ rhs for a full-length right-hand side (zero on fixed DOFs).
    pub fn solve(&self, rhs: &[f64]) -> Vec<f64> {
        if self.reduced.is_empty() {
            let mut x = rhs.to_vec();
            self.factor.solve_many_in_place(&mut x);
            return x;
        }
        let mut y = vec![0.0; self.reduced_dim()];
        for (i, &r) in self.reduced.iter().enumerate() {
            if r != FIXED {
                y[r] = rhs[i];
            }
        }
        self.factor.solve_many_in_place(&mut y);
        let mut x = vec![0.0; self.n];
        for (i, &r) in self.reduced.iter().enumerate() {
            if r != FIXED {
                x[i] = y[r];
            }
        }
        x
    }
}

/// The rows and columns of `a` whose `reduced` index is not `FIXED`, renumbered.
fn submatrix(a: &CscMatrix, reduced: &[usize], size: usize) -> Result<CscMatrix, DualError> {
    let mut indptr = Vec::with_capacity(size + 1);
    let mut indices = Vec::with_capacity(a.nnz());
    let mut data = Vec::with_capacity(a.nnz());
    indptr.push(0);
    for (j, col) in a.outer_iterator().enumerate() {
        if reduced[j] == FIXED {
            continue;
        }
        for (i, &v) in col.iter() {
            if reduced[i] != FIXED {
                indices.push(reduced[i]);
                data.push(v);
            }
        }
        indptr.push(indices.len());
    }
    CscMatrix::try_new_csc((size, size), indptr, indices, data)
        .map_err(|(_, _, _, e)| DualError::Structure(format!("reduced stiffness: {e}")))
}
