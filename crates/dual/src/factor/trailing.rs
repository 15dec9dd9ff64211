//! Sparse Cholesky with the contact DOFs ordered last, so that the trailing block of the factor
//! is the Cholesky factor of the Schur complement on them:
//!
//! ```text
//! P A Pᵀ = [ A_ii  A_ic ] = [ L_ii   0   ] [ L_iiᵀ  L_ciᵀ ]      S = A_cc − A_ci A_ii⁻¹ A_ic
//!          [ A_ci  A_cc ]   [ L_ci  L_cc ] [   0    L_ccᵀ ],       = L_cc L_ccᵀ.
//! ```
//!
//! Then H = B_c S⁻¹ B_cᵀ = Yᵀ Y with Y = L_cc⁻¹ B_cᵀ: no sparse solve at all, only dense work of
//! order |c|² m.  The interior is ordered by the project's one fill-reducing ordering,
//! [`signorini_qp::linalg::fill_reducing_order`] (the floor's ordering path), with the contact
//! DOFs moved to the end; the symbolic analysis and the numeric LLᵀ are the project's shared
//! factor path ([`CholeskyPattern`], [`SparseCholesky`]).  The same factor serves every later
//! solve with A.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::supernodal::SupernodalLltRef;
use faer::sparse::linalg::cholesky::SymbolicCholeskyRaw;
use faer::{Conj, Mat, MatMut, MatRef, Par};
use signorini_qp::linalg::{
    fill_reducing_order, CholeskyPattern, FillOrdering, LinalgError, OrderingMethod, SparseCholesky,
};
use signorini_qp::CscMatrix;

/// Which half of a solve [`TrailingCholesky::substitute`] makes: L z = b, or Lᵀ x = z.
#[derive(Debug, Clone, Copy)]
enum Half {
    Forward,
    Backward,
}

/// A Cholesky factor of A with the `touched` DOFs last, and its dense trailing block.
#[derive(Debug)]
pub struct TrailingCholesky {
    factor: SparseCholesky,
    n: usize,
    /// L_cc, |c| × |c| lower triangular; row/column k is `touched[k]`.
    trailing: Mat<f64>,
    /// minⱼ Lⱼⱼ² / Aⱼⱼ: near zero when A is (numerically) singular.
    min_pivot_ratio: f64,
    /// The fill-reducing ordering of the interior.
    ordering: OrderingMethod,
    /// Whether the touched DOFs are last (else the trailing block is empty).
    has_trailing: bool,
    /// The factor's permutation, new → old.
    forward: Vec<usize>,
}

/// Whether ordering the |c| touched DOFs last pays for `rows` contact rows: it adds a dense
/// trailing block whose factorisation costs ~|c|³/3 flops and then gives H for |c|² m more,
/// against m multi-right-hand-side solves with the plain factor (~4 nnz(L) flops each).  A long
/// interface (|c| in the thousands: a thin strip on a foundation) makes the dense separator
/// dominate the factor — measured on the 3 × 0.02 strips of fixtures/hard (m = 301, |c| ≈ 1 200):
/// nnz(L) 13× larger and dual-ssn 2.8× slower with the contact DOFs last; a short one (the seed,
/// or m = 500 rows across a 1e5 Laplacian) gains 10× (crate docs).
pub fn trailing_pays(touched: usize, rows: usize, plain_entries: usize) -> bool {
    let c = touched as f64;
    let m = rows as f64;
    c * c * c / 3.0 + c * c * m < 4.0 * m * plain_entries as f64
}

impl TrailingCholesky {
    /// Factors the symmetric positive definite `a` (lower triangle read) with the DOFs in
    /// `touched` (distinct, in range) ordered last, in the given order.  `admit` sees the number
    /// of stored entries of L (known after the symbolic analysis, before any numeric memory is
    /// taken) and may refuse.
    ///
    /// The touched DOFs are ordered last only when that pays ([`trailing_pays`]); otherwise the
    /// factor has an empty trailing block ([`TrailingCholesky::has_trailing`] is false).
    pub fn factor<E: From<LinalgError>>(
        a: &CscMatrix,
        touched: &[usize],
        rows: usize,
        admit: impl FnOnce(usize) -> Result<(), E>,
    ) -> Result<Self, E> {
        let n = a.rows();
        let order = fill_reducing_order(a)?;
        let method = order.method;
        let analyse = |forward: &[usize]| {
            let mut inverse = vec![0; n];
            for (new, &old) in forward.iter().enumerate() {
                inverse[old] = new;
            }
            let ordering = FillOrdering {
                forward: forward.to_vec(),
                inverse,
                method,
            };
            CholeskyPattern::analyse_with(a, &ordering)
        };
        // nnz(L) ≥ nnz of A's lower triangle ≥ nnz(A)/2: when the rule already holds with that
        // lower bound, the plain analysis (≈ 10 % of a factorisation) is not needed to decide.
        let surely_pays = !touched.is_empty() && trailing_pays(touched.len(), rows, a.nnz() / 2);
        let plain = if surely_pays {
            None
        } else {
            Some(analyse(&order.forward)?)
        };
        let keep_last = surely_pays
            || plain.as_ref().is_some_and(|p| {
                !touched.is_empty() && trailing_pays(touched.len(), rows, p.stored_values())
            });
        let (forward, pattern, touched) = if keep_last {
            let mut is_touched = vec![false; n];
            for &j in touched {
                is_touched[j] = true;
            }
            let mut forward = order.forward;
            forward.retain(|&j| !is_touched[j]);
            forward.extend_from_slice(touched);
            let pattern = analyse(&forward)?;
            (forward, pattern, touched)
        } else {
            let plain = match plain {
                Some(plain) => plain,
                None => analyse(&order.forward)?,
            };
            (order.forward, plain, &[][..])
        };
        admit(pattern.stored_values())?;
        let factor = pattern.factor(a)?;
        let (symbolic, values) = factor.raw();
        let SymbolicCholeskyRaw::Supernodal(supernodal) = symbolic.raw() else {
            return Err(LinalgError::Faer("expected a supernodal factorisation".into()).into());
        };
        let llt = SupernodalLltRef::new(supernodal, values);
        let trailing = trailing_block(llt, n, touched.len());
        let has_trailing = !touched.is_empty();
        let min_pivot_ratio = pivot_ratio(llt, a, &forward);
        Ok(Self {
            factor,
            n,
            trailing,
            min_pivot_ratio,
            ordering: method,
            has_trailing,
            forward,
        })
    }

    /// Whether the touched DOFs were ordered last (see [`trailing_pays`]).
    pub fn has_trailing(&self) -> bool {
        self.has_trailing
    }

    /// The fill-reducing ordering used for the interior.
    pub fn ordering(&self) -> OrderingMethod {
        self.ordering
    }

    /// Stored entries of L (supernodal: the dense supernode blocks, explicit zeros included).
    pub fn factor_entries(&self) -> usize {
        self.factor.raw().1.len()
    }

    /// minⱼ Lⱼⱼ² / Aⱼⱼ over the pivots (1 for an empty matrix).  A singular A that the
    /// factorisation got through by round-off shows a ratio near machine precision.
    pub fn min_pivot_ratio(&self) -> f64 {
        self.min_pivot_ratio
    }

    /// Size n of A.
    pub fn dim(&self) -> usize {
        self.n
    }

    /// L_cc: the Cholesky factor of the Schur complement on the touched DOFs.
    pub fn trailing(&self) -> MatRef<'_, f64> {
        self.trailing.as_ref()
    }

    /// Overwrites the column-major n × k block `rhs` with A⁻¹ rhs.
    pub fn solve_many_in_place(&self, rhs: &mut [f64]) {
        self.factor.solve_many_in_place(rhs);
    }

    /// z = L⁻¹ P rhs, in the factor's order (the first half of a solve: A⁻¹ rhs =
    /// Pᵀ L⁻ᵀ z, [`TrailingCholesky::backward`]).  Its last |c| entries belong to the trailing
    /// DOFs, in their order.
    pub fn forward(&self, rhs: &[f64]) -> Vec<f64> {
        let mut z: Vec<f64> = self.permutation().iter().map(|&old| rhs[old]).collect();
        self.substitute(&mut z, Half::Forward);
        z
    }

    /// Pᵀ L⁻ᵀ w for w in the factor's order (the second half of a solve, after
    /// [`TrailingCholesky::forward`]), in the original order.
    pub fn backward(&self, mut w: Vec<f64>) -> Vec<f64> {
        self.substitute(&mut w, Half::Backward);
        let mut x = vec![0.0; w.len()];
        for (new, &old) in self.permutation().iter().enumerate() {
            x[old] = w[new];
        }
        x
    }

    /// One triangular substitution through the supernodal L, in place, in the factor's order.
    fn substitute(&self, v: &mut [f64], half: Half) {
        let n = v.len();
        if n == 0 {
            return;
        }
        let llt = self.llt();
        let req = llt.symbolic().solve_in_place_scratch::<f64>(1, Par::Seq);
        let mut buffer = MemBuffer::new(req);
        let rhs = MatMut::from_column_major_slice_mut(v, n, 1);
        let stack = MemStack::new(&mut buffer);
        match half {
            Half::Forward => llt.l_solve_with_conj(Conj::No, rhs, Par::Seq, stack),
            Half::Backward => llt.l_transpose_solve_with_conj(Conj::No, rhs, Par::Seq, stack),
        }
    }

    /// The factor's supernodal view (the factor is supernodal by construction).
    fn llt(&self) -> SupernodalLltRef<'_, usize, f64> {
        let (symbolic, values) = self.factor.raw();
        match symbolic.raw() {
            SymbolicCholeskyRaw::Supernodal(supernodal) => {
                SupernodalLltRef::new(supernodal, values)
            }
            SymbolicCholeskyRaw::Simplicial(_) => {
                unreachable!("TrailingCholesky::factor refuses a simplicial factor")
            }
        }
    }

    /// P as new → old (`forward` of the ordering the factor was analysed with).
    fn permutation(&self) -> &[usize] {
        &self.forward
    }
}

/// minⱼ Lⱼⱼ² / A_{fwd(j) fwd(j)}.  A's diagonal is read in one pass in its own order first
/// (a lookup per pivot in the factor's order would search a column in a random place each).
fn pivot_ratio(llt: SupernodalLltRef<'_, usize, f64>, a: &CscMatrix, forward: &[usize]) -> f64 {
    let diagonal: Vec<f64> = a
        .outer_iterator()
        .enumerate()
        .map(|(j, col)| col.get(j).copied().unwrap_or(0.0))
        .collect();
    let mut ratio = 1.0_f64;
    for s in 0..llt.symbolic().n_supernodes() {
        let node = llt.supernode(s);
        let val = node.val();
        for local in 0..val.ncols() {
            let a_jj = diagonal[forward[node.start() + local]];
            let l_jj = val[(local, local)];
            if a_jj > 0.0 {
                ratio = ratio.min(l_jj * l_jj / a_jj);
            }
        }
    }
    ratio
}

/// Copies the last `size` columns of the supernodal factor into a dense lower-triangular block.
fn trailing_block(llt: SupernodalLltRef<'_, usize, f64>, n: usize, size: usize) -> Mat<f64> {
    let first = n - size;
    let mut block = Mat::<f64>::zeros(size, size);
    for s in 0..llt.symbolic().n_supernodes() {
        let node = llt.supernode(s);
        let start = node.start();
        let val = node.val();
        let width = val.ncols();
        if start + width <= first {
            continue;
        }
        for local in 0..width {
            let col = start + local;
            if col < first {
                continue;
            }
            for row_local in local..width {
                block[(start + row_local - first, col - first)] = val[(row_local, local)];
            }
            for (p, &row) in node.pattern().iter().enumerate() {
                block[(row - first, col - first)] = val[(width + p, local)];
            }
        }
    }
    block
}
