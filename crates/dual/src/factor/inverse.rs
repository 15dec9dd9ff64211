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

use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::{Mat, Par};
use signorini_qp::memory;
use signorini_qp::CscMatrix;

use super::trailing::TrailingCholesky;
use crate::error::DualError;

/// Marker in the full → reduced index map for a fixed DOF.
const FIXED: usize = usize::MAX;

/// Most contact DOFs ordered last (the dense trailing block has this many squared entries).
pub const MAX_TRAILING: usize = 6000;

/// Pivot ratio minⱼ Lⱼⱼ²/Aⱼⱼ below which A counts as singular (a floating body whose rigid
/// modes the factorisation got through by round-off).  Elastic stiffness matrices with
/// condition numbers up to ~1e12 stay well above it.
pub const SINGULAR_PIVOT_RATIO: f64 = 1e-13;

/// A⁺ applied through a cached sparse Cholesky factor.
#[derive(Debug)]
pub struct StiffnessInverse {
    factor: TrailingCholesky,
    /// Full index → reduced index (`FIXED` for fixed DOFs); empty when nothing is fixed.
    reduced: Vec<usize>,
    /// Whether the DOFs B touches are ordered last.
    contact_last: bool,
    /// With `contact_last`: the full indices of the trailing DOFs, in trailing order.
    trailing: Vec<usize>,
    n: usize,
    /// The factor's bytes, held for the later checks of this solve (the dense H, the dense
    /// Newton matrices): they are made beside it (see [`memory::hold`]).
    _held: memory::Held,
}

impl StiffnessInverse {
    /// Factors A with the DOFs in `fixed` removed (rows and columns).  With
    /// `trailing_for = Some(B)`, the DOFs that B touches are ordered last, unless there are more
    /// than [`MAX_TRAILING`] of them (the dense trailing block would be too large).
    ///
    /// A pivot ratio minⱼ Lⱼⱼ²/Aⱼⱼ below [`SINGULAR_PIVOT_RATIO`] counts as singular.
    pub fn new(
        a: &CscMatrix,
        fixed: &[usize],
        kernel_count: usize,
        trailing_for: Option<&CscMatrix>,
        backend: &'static str,
    ) -> Result<Self, DualError> {
        let n = a.rows();
        let singular = |e| match e {
            DualError::Linalg(source) => DualError::Singular {
                source,
                kernel: kernel_count,
            },
            e => e,
        };
        let (reduced, kept) = reduced_numbering(n, fixed);
        let sub = if reduced.is_empty() {
            None
        } else {
            Some(submatrix(a, &reduced, kept)?)
        };
        let matrix = sub.as_ref().unwrap_or(a);
        let (mut trailing, mut touched_reduced) =
            trailing_for.map_or_else(Default::default, |b| touched_dofs(b, &reduced));
        // The dense trailing block (|c|² entries) is an optimisation: when it does not fit, the
        // contact DOFs are simply not ordered last.
        let block_fits = || {
            let bytes = 8.0 * (trailing.len() as f64).powi(2);
            memory::check_fits(backend, String::new, bytes).is_ok()
        };
        let contact_last = trailing_for.is_some() && trailing.len() <= MAX_TRAILING && block_fits();
        if !contact_last {
            trailing.clear();
            touched_reduced.clear();
        }
        let trailing_count = touched_reduced.len();
        let admit = |entries: usize| -> Result<(), DualError> {
            let bytes = 8.0 * (entries as f64 + (trailing_count as f64).powi(2));
            memory::check_fits(
                backend,
                || {
                    format!(
                        "the sparse factor of A ({entries} stored entries of L, with a dense trailing block on {trailing_count} contact DOFs)"
                    )
                },
                bytes,
            )?;
            Ok(())
        };
        let rows = trailing_for.map_or(0, CscMatrix::rows);
        let factor =
            TrailingCholesky::factor(matrix, &touched_reduced, rows, admit).map_err(singular)?;
        // The factor may decline to order the contact DOFs last (it would not pay).
        let contact_last = contact_last && factor.has_trailing();
        if !contact_last {
            trailing.clear();
        }
        let dense_block = if factor.has_trailing() {
            (trailing_count as f64).powi(2)
        } else {
            0.0
        };
        let held = memory::hold(8.0 * (factor.factor_entries() as f64 + dense_block));
        let ratio = factor.min_pivot_ratio();
        if ratio < SINGULAR_PIVOT_RATIO {
            return Err(DualError::NearlySingular {
                ratio,
                kernel: kernel_count,
            });
        }
        Ok(Self {
            factor,
            reduced,
            contact_last,
            trailing,
            n,
            _held: held,
        })
    }

    /// "ordering amd, nnz(L) 1.2e6": the ordering and the stored entries of the factor, for the
    /// solution message.
    pub fn describe(&self) -> String {
        format!(
            "ordering {}, nnz(L) {:.3e}",
            self.factor.ordering(),
            self.factor.factor_entries() as f64
        )
    }

    /// The factor.
    pub fn factor(&self) -> &TrailingCholesky {
        &self.factor
    }

    /// Whether the contact DOFs are ordered last (so [`TrailingCholesky::trailing`] is the
    /// factor of the Schur complement on [`StiffnessInverse::trailing`]).
    pub fn contact_last(&self) -> bool {
        self.contact_last
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

    /// The forward half of A⁺ rhs for a full-length right-hand side (fixed DOFs dropped):
    /// z = L⁻¹ P rhs_f, in the factor's order.  With the contact DOFs last,
    /// [`StiffnessInverse::solve_shifted`] then gives A⁺(rhs − Bᵀλ) for any λ with one backward
    /// substitution.
    pub fn forward(&self, rhs: &[f64]) -> Vec<f64> {
        self.factor.forward(&self.reduce(rhs))
    }

    /// A⁺(rhs − Bᵀλ) from z = [`StiffnessInverse::forward`]`(rhs)`, when the contact DOFs are
    /// ordered last (`None` otherwise): Bᵀλ lives on the trailing DOFs only, so
    /// L⁻¹ P Bᵀλ = [0; L_cc⁻¹ (Bᵀλ)_c] — a dense |c| × |c| triangular solve — and the rest is
    /// one backward substitution, half the sparse work of [`StiffnessInverse::solve`].
    pub fn solve_shifted(
        &self,
        forward_rhs: &[f64],
        constraints: &CscMatrix,
        multipliers: &[f64],
    ) -> Option<Vec<f64>> {
        if !self.contact_last {
            return None;
        }
        let trailing = self.factor.trailing();
        let c = self.trailing.len();
        let mut shift = Mat::<f64>::zeros(c, 1);
        for (k, &j) in self.trailing.iter().enumerate() {
            if let Some(col) = constraints.outer_view(j) {
                shift[(k, 0)] = col.iter().map(|(i, &b)| b * multipliers[i]).sum();
            }
        }
        solve_lower_triangular_in_place(trailing, shift.as_mut(), Par::Seq);
        let mut w = forward_rhs.to_vec();
        let first = w.len() - c;
        for k in 0..c {
            w[first + k] -= shift[(k, 0)];
        }
        Some(self.expand(self.factor.backward(w)))
    }

    /// A⁺ rhs on the contact DOFs alone, zero elsewhere (a full-length vector B can multiply),
    /// from z = [`StiffnessInverse::forward`]`(rhs)` when the contact DOFs are ordered last
    /// (`None` otherwise): the backward substitution's last |c| rows are L_cc⁻ᵀ z_c and need
    /// nothing before them.
    pub fn contact_part(&self, forward_rhs: &[f64]) -> Option<Vec<f64>> {
        if !self.contact_last {
            return None;
        }
        let c = self.trailing.len();
        let first = forward_rhs.len() - c;
        let mut tail = Mat::<f64>::from_fn(c, 1, |k, _| forward_rhs[first + k]);
        solve_upper_triangular_in_place(
            self.factor.trailing().transpose(),
            tail.as_mut(),
            Par::Seq,
        );
        let mut u = vec![0.0; self.n];
        for (k, &j) in self.trailing.iter().enumerate() {
            u[j] = tail[(k, 0)];
        }
        Some(u)
    }

    /// The reduced right-hand side (fixed DOFs dropped).
    fn reduce(&self, rhs: &[f64]) -> Vec<f64> {
        if self.reduced.is_empty() {
            return rhs.to_vec();
        }
        let mut y = vec![0.0; self.reduced_dim()];
        for (i, &r) in self.reduced.iter().enumerate() {
            if r != FIXED {
                y[r] = rhs[i];
            }
        }
        y
    }

    /// The full-length vector of a reduced one (zero on fixed DOFs).
    fn expand(&self, y: Vec<f64>) -> Vec<f64> {
        if self.reduced.is_empty() {
            return y;
        }
        let mut x = vec![0.0; self.n];
        for (i, &r) in self.reduced.iter().enumerate() {
            if r != FIXED {
                x[i] = y[r];
            }
        }
        x
    }

    /// A⁺ rhs for a full-length right-hand side (zero on fixed DOFs).
    pub fn solve(&self, rhs: &[f64]) -> Vec<f64> {
        let mut y = self.reduce(rhs);
        self.factor.solve_many_in_place(&mut y);
        self.expand(y)
    }
}

/// The rows and columns of `a` whose `reduced` index is not `FIXED`, renumbered.
/// The full → reduced index map with the DOFs in `fixed` removed (`FIXED` for them) and the
/// number of DOFs kept; an empty map when nothing is fixed.
fn reduced_numbering(n: usize, fixed: &[usize]) -> (Vec<usize>, usize) {
    if fixed.is_empty() {
        return (Vec::new(), n);
    }
    let mut reduced = vec![0; n];
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
    (reduced, next)
}

/// The DOFs the constraints touch and are not fixed: their full indices and their indices in
/// the reduced numbering `reduced` (empty: nothing fixed).
fn touched_dofs(constraints: &CscMatrix, reduced: &[usize]) -> (Vec<usize>, Vec<usize>) {
    let mut full = Vec::new();
    let mut in_reduced = Vec::new();
    for (j, col) in constraints.outer_iterator().enumerate() {
        let r = if reduced.is_empty() { j } else { reduced[j] };
        if col.nnz() > 0 && r != FIXED {
            full.push(j);
            in_reduced.push(r);
        }
    }
    (full, in_reduced)
}

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
