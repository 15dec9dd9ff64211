//! The sparse LDLᵀ factor of the KKT matrix: one symbolic analysis, a numeric factorisation per
//! active set, and solves with it.  K is ordered by [`signorini_qp::linalg::kkt_order`] and
//! built in that order ([`KktMatrix::new`]), so the analysis carries no permutation: the
//! numeric factorisation reads K in place, and the solves permute their right-hand sides
//! instead.
//!
//! Two kernels, chosen by faer's flop rule on K's column counts
//! ([`EliminationTree::suits_simplicial`]): the project's simplicial LDLᵀ
//! ([`signorini_qp::linalg::ldlt`], which keeps the pattern of every row of L from the analysis
//! instead of finding it again on every factorisation) where L's columns are short — the long,
//! thin contact strips pdas is for — and faer's supernodal LDLᵀ (through the project's shared
//! [`CholeskyPattern`]) where they are long enough for dense kernels.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::ldlt::factor::LdltRegularization;
use faer::sparse::linalg::cholesky::{LdltRef, SymbolicCholesky};
use faer::{Conj, MatMut, Par, Side};
use signorini_qp::linalg::kkt::kkt_graph;
use signorini_qp::linalg::ldlt::{
    EliminationTree, Regularisation, SimplicialLdlt, SimplicialPattern,
};
use signorini_qp::linalg::{kkt_order, CholeskyPattern, Layout, LinalgError, OrderingMethod};
use signorini_qp::QpProblem;

use crate::error::PdasError;
use crate::kkt::KktMatrix;

/// The symbolic factor of K's pattern and the numeric values of the last factorisation.
pub struct KktFactor {
    kernel: Kernel,
    /// The ordering method that ordered K.
    method: OrderingMethod,
    /// +1 on the primal block, −1 on the multiplier block (the dynamic regularisation's
    /// expected signs), in the elimination order.
    signs: Vec<i8>,
    /// The elimination order, `forward[new] = old`.
    forward: Vec<usize>,
    /// A right-hand side in the elimination order.
    work: Vec<f64>,
}

/// The factorisation's kernel: its symbolic analysis and, once allocated, its values.
enum Kernel {
    /// The project's simplicial LDLᵀ.
    Simplicial {
        pattern: SimplicialPattern,
        factor: Option<SimplicialLdlt>,
    },
    /// faer's supernodal LDLᵀ.
    Supernodal {
        pattern: CholeskyPattern,
        values: Vec<f64>,
        buffer: MemBuffer,
        scratch_bytes: usize,
    },
}

impl std::fmt::Debug for KktFactor {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("KktFactor")
            .field("dim", &self.signs.len())
            .field("nnz_l", &self.nnz_l())
            .field(
                "simplicial",
                &matches!(self.kernel, Kernel::Simplicial { .. }),
            )
            .field("method", &self.method)
            .finish()
    }
}

impl KktFactor {
    /// Orders K's graph (read off A and B, the first n unknowns primal), builds K in that
    /// order and in the triangle the numeric factorisation reads, and analyses it.  The values
    /// of the factor are not allocated yet (see [`KktFactor::bytes_needed`],
    /// [`KktFactor::allocate`]).
    pub fn analyse(problem: &QpProblem) -> Result<(Self, KktMatrix), PdasError> {
        Self::analyse_laid_out(problem, Layout::FaerChoice)
    }

    /// [`KktFactor::analyse`] with the layout given: `FaerChoice` takes the kernel faer's flop
    /// rule picks, `Supernodal` forces faer's supernodal one (the tests force each).
    fn analyse_laid_out(
        problem: &QpProblem,
        layout: Layout,
    ) -> Result<(Self, KktMatrix), PdasError> {
        let dofs = problem.dofs();
        let (xadj, adjncy) =
            kkt_graph(&problem.stiffness, &problem.constraints).map_err(symbolic_error)?;
        let ordering = kkt_order(&xadj, &adjncy).map_err(symbolic_error)?;
        drop((xadj, adjncy));
        // The simplicial kernel reads the upper triangle, the supernodal one the lower.
        let mut kkt = KktMatrix::new(problem, &ordering, Side::Upper)?;
        let tree = EliminationTree::of(kkt.matrix().symbolic()).map_err(symbolic_error)?;
        let kernel = if layout == Layout::FaerChoice && tree.suits_simplicial() {
            let pattern = SimplicialPattern::analyse(kkt.matrix().symbolic(), &tree)
                .map_err(symbolic_error)?;
            Kernel::Simplicial {
                pattern,
                factor: None,
            }
        } else {
            drop(tree);
            // faer analyses an unpermuted matrix through its upper triangle (whatever side is
            // named), and its supernodal kernel reads the lower one: built so once more.
            let pattern = CholeskyPattern::analyse_ordered(
                kkt.matrix().symbolic(),
                kkt.side(),
                ordering.method,
                Layout::Supernodal,
            )
            .map_err(symbolic_error)?;
            kkt = KktMatrix::new(problem, &ordering, pattern.reads())?;
            let scratch_bytes = scratch(pattern.symbolic()).size_bytes();
            Kernel::Supernodal {
                pattern,
                values: Vec::new(),
                buffer: MemBuffer::new(StackReq::EMPTY),
                scratch_bytes,
            }
        };
        let forward = ordering.forward;
        let signs = forward
            .iter()
            .map(|&old| if old < dofs { 1 } else { -1 })
            .collect();
        let dim = forward.len();
        let factor = Self {
            kernel,
            method: ordering.method,
            signs,
            forward,
            work: vec![0.0; dim],
        };
        Ok((factor, kkt))
    }

    /// Stored entries of the factor L (and D): the length of its value array.
    pub fn nnz_l(&self) -> usize {
        match &self.kernel {
            Kernel::Simplicial { pattern, .. } => pattern.nnz_l(),
            Kernel::Supernodal { pattern, .. } => pattern.stored_values(),
        }
    }

    /// The ordering method that ordered K.
    pub fn method(&self) -> OrderingMethod {
        self.method
    }

    /// Bytes the numeric factorisation will hold: the factor's values plus its workspace.
    pub fn bytes_needed(&self) -> f64 {
        let workspace = match &self.kernel {
            // A dense row and the next free slot of each column.
            Kernel::Simplicial { .. } => 16 * self.signs.len(),
            Kernel::Supernodal { scratch_bytes, .. } => *scratch_bytes,
        };
        (self.nnz_l() * std::mem::size_of::<f64>() + workspace) as f64
    }

    /// Allocates the factor's values and the workspace (call once, after the memory check).
    pub fn allocate(&mut self) -> Result<(), PdasError> {
        let nnz_l = self.nnz_l();
        match &mut self.kernel {
            Kernel::Simplicial { pattern, factor } => {
                *factor = Some(SimplicialLdlt::new(pattern).map_err(numeric_error)?);
            }
            Kernel::Supernodal {
                pattern,
                values,
                buffer,
                ..
            } => {
                *buffer = MemBuffer::try_new(scratch(pattern.symbolic()))
                    .map_err(|e| PdasError::Numeric(format!("{e:?}")))?;
                let mut new = Vec::new();
                new.try_reserve_exact(nnz_l)
                    .map_err(|e| PdasError::Numeric(format!("factor of {nnz_l} entries: {e}")))?;
                new.resize(nnz_l, 0.0);
                *values = new;
            }
        }
        Ok(())
    }

    /// Whether [`KktFactor::allocate`] has run.
    fn allocated(&self) -> bool {
        match &self.kernel {
            Kernel::Simplicial { factor, .. } => factor.is_some(),
            Kernel::Supernodal { values, .. } => values.len() == self.nnz_l(),
        }
    }

    /// Numeric LDLᵀ of K with the values `kkt` holds (the matrix analysed).  A pivot of the
    /// wrong sign or smaller than `epsilon` in magnitude is replaced by ±`delta` (dynamic
    /// regularisation).
    pub fn factor(&mut self, kkt: &KktMatrix, epsilon: f64, delta: f64) -> Result<(), PdasError> {
        if !self.allocated() {
            self.allocate()?;
        }
        match &mut self.kernel {
            Kernel::Simplicial {
                pattern,
                factor: Some(factor),
            } => {
                let regularisation = Regularisation {
                    signs: &self.signs,
                    epsilon,
                    delta,
                };
                factor
                    .factor(pattern, kkt.matrix(), regularisation)
                    .map(|_| ())
                    .map_err(numeric_error)
            }
            Kernel::Simplicial { factor: None, .. } => {
                Err(PdasError::Numeric("the factor was not allocated".into()))
            }
            Kernel::Supernodal {
                pattern,
                values,
                buffer,
                ..
            } => {
                let regularization = LdltRegularization {
                    dynamic_regularization_signs: Some(&self.signs),
                    dynamic_regularization_delta: delta,
                    dynamic_regularization_epsilon: epsilon,
                };
                pattern
                    .symbolic()
                    .factorize_numeric_ldlt(
                        values,
                        kkt.matrix(),
                        kkt.side(),
                        regularization,
                        Par::Seq,
                        MemStack::new(buffer),
                        Default::default(),
                    )
                    .map(|_| ())
                    .map_err(|e| PdasError::Numeric(format!("{e:?}")))
            }
        }
    }

    /// Overwrites the column-major (n + m) × k block `rhs` with K⁻¹ rhs (k = rhs.len() / (n + m)).
    pub fn solve_many_in_place(&mut self, rhs: &mut [f64]) -> Result<(), PdasError> {
        let dim = self.signs.len();
        if dim == 0 || rhs.is_empty() {
            return Ok(());
        }
        let k = rhs.len() / dim;
        let mut ordered = vec![0.0; dim * k];
        for (from, to) in rhs.chunks_exact(dim).zip(ordered.chunks_exact_mut(dim)) {
            gather(&self.forward, from, to);
        }
        match &self.kernel {
            Kernel::Simplicial {
                pattern,
                factor: Some(factor),
            } => {
                for column in ordered.chunks_exact_mut(dim) {
                    factor.solve_in_place(pattern, column);
                }
            }
            Kernel::Simplicial { factor: None, .. } => {
                return Err(PdasError::Numeric("the factor was not allocated".into()))
            }
            Kernel::Supernodal {
                pattern, values, ..
            } => {
                let mut buffer = MemBuffer::try_new(
                    pattern
                        .symbolic()
                        .solve_in_place_scratch::<f64>(k, Par::Seq),
                )
                .map_err(|e| PdasError::Numeric(format!("{e:?}")))?;
                LdltRef::new(pattern.symbolic(), values).solve_in_place_with_conj(
                    Conj::No,
                    MatMut::from_column_major_slice_mut(&mut ordered, dim, k),
                    Par::Seq,
                    MemStack::new(&mut buffer),
                );
            }
        }
        for (from, to) in ordered.chunks_exact(dim).zip(rhs.chunks_exact_mut(dim)) {
            scatter(&self.forward, from, to);
        }
        Ok(())
    }

    /// Overwrites `rhs` (length n + m) with K⁻¹ rhs for the last factorised K.
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) {
        let dim = self.signs.len();
        if dim == 0 {
            return;
        }
        gather(&self.forward, rhs, &mut self.work);
        match &mut self.kernel {
            Kernel::Simplicial {
                pattern,
                factor: Some(factor),
            } => factor.solve_in_place(pattern, &mut self.work),
            // Not factorised (the iteration never asks before it has): no answer, loudly.
            Kernel::Simplicial { factor: None, .. } => {
                rhs.fill(f64::NAN);
                return;
            }
            Kernel::Supernodal {
                pattern,
                values,
                buffer,
                ..
            } => LdltRef::new(pattern.symbolic(), values).solve_in_place_with_conj(
                Conj::No,
                MatMut::from_column_major_slice_mut(&mut self.work, dim, 1),
                Par::Seq,
                MemStack::new(buffer),
            ),
        }
        scatter(&self.forward, &self.work, rhs);
    }
}

/// `to[new] = from[forward[new]]`: a vector into the elimination order.
fn gather(forward: &[usize], from: &[f64], to: &mut [f64]) {
    for (t, &old) in to.iter_mut().zip(forward) {
        *t = from[old];
    }
}

/// `to[forward[new]] = from[new]`: a vector back from the elimination order.
fn scatter(forward: &[usize], from: &[f64], to: &mut [f64]) {
    for (&f, &old) in from.iter().zip(forward) {
        to[old] = f;
    }
}

/// A failed numeric factorisation, as the backend's error.
fn numeric_error(e: LinalgError) -> PdasError {
    PdasError::Numeric(e.to_string())
}

/// A failed ordering or analysis, as the backend's error.
fn symbolic_error(e: LinalgError) -> PdasError {
    match e {
        // faer's own failure, as its message.
        LinalgError::Faer(message) => PdasError::Symbolic(message),
        other => PdasError::Symbolic(other.to_string()),
    }
}

/// The workspace of faer's numeric LDLᵀ and of a one-column solve with it.
fn scratch(symbolic: &SymbolicCholesky<usize>) -> StackReq {
    StackReq::any_of(&[
        symbolic.factorize_numeric_ldlt_scratch::<f64>(Par::Seq, Default::default()),
        symbolic.solve_in_place_scratch::<f64>(1, Par::Seq),
    ])
}

#[cfg(test)]
mod tests {
    use super::*;
    use signorini_qp::examples::laplacian_with_bounds;

    /// A supernodal factor reads the lower triangle, a simplicial one the upper: K is laid out
    /// for each, and both solve K z = b to round-off — checked against K applied to z through
    /// A and B themselves (every row active, −δ on the multiplier diagonal).
    #[test]
    fn both_layouts_solve_the_kkt_system() {
        let p = laplacian_with_bounds(60, 15);
        let (n, m) = (p.dofs(), p.rows());
        let delta = 1e-2;
        let b: Vec<f64> = (0..n + m).map(|k| (k as f64 * 0.37).sin()).collect();
        for (layout, side) in [
            (Layout::Supernodal, Side::Lower),
            (Layout::FaerChoice, Side::Upper),
        ] {
            let (mut factor, mut kkt) = KktFactor::analyse_laid_out(&p, layout).unwrap();
            assert_eq!(kkt.side(), side, "{layout:?}");
            kkt.set_values(&vec![true; m], 0.0, delta, 1.0);
            factor.factor(&kkt, 1e-20, 1e-17).unwrap();
            let mut z = b.clone();
            factor.solve_in_place(&mut z);
            let (x, l) = z.split_at(n);
            let ax = signorini_qp::mat_vec(&p.stiffness, x);
            let btl = signorini_qp::mat_t_vec(&p.constraints, l);
            let bx = signorini_qp::mat_vec(&p.constraints, x);
            let residual = (0..n)
                .map(|j| ax[j] + btl[j] - b[j])
                .chain((0..m).map(|i| bx[i] - delta * l[i] - b[n + i]))
                .fold(0.0_f64, |r, v| r.max(v.abs()));
            // Backward-stable LDLᵀ: a residual of a modest multiple of ε ‖K‖ ‖z‖ (‖K‖∞ ≤ 5 here:
            // the Laplacian's rows and a row of B); 1e3 ε leaves room for the growth of a
            // factorisation without pivoting on this quasi-definite K.
            let z_max = z.iter().fold(0.0_f64, |r, v| r.max(v.abs()));
            let bound = 1e3 * f64::EPSILON * 5.0 * z_max;
            assert!(
                residual < bound,
                "{layout:?}: residual {residual:e} over {bound:e}"
            );
        }
    }
}
