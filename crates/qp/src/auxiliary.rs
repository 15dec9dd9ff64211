//! Box rows as non-negative rows on auxiliary variables: the primal form of a problem with
//! box rows ([`crate::ConstraintBlock::Box`]) for the generic solvers (clarabel, OSQP), whose
//! cones hold one-sided rows only.
//!
//! With one auxiliary unknown tᵢ ≥ |rᵢ| per box row i (rᵢ = (B x − g)ᵢ),
//!
//! ```text
//! minimise ½ xᵀ A x − fᵀ x + Σᵢ sᵢ tᵢ
//! subject to  (B x − g)ⱼ ≤ 0     on the non-negative rows j,
//!             rᵢ − tᵢ ≤ 0,  −rᵢ − tᵢ ≤ 0   on the box rows i,
//! ```
//!
//! has the same x as the problem with the term sᵢ |rᵢ| (at the optimum tᵢ = |rᵢ|).  A box row
//! with sᵢ = 0 adds nothing to the objective and its multiplier is 0: it is left out (with it,
//! tᵢ would be free to grow at no cost, a ray of optima that interior-point methods only
//! approach as AlmostSolved).  Its KKT conditions give the box
//! row's multiplier as λᵢ = μᵢ⁺ − μᵢ⁻ (the multipliers of the two rows), with μᵢ⁺ + μᵢ⁻ = sᵢ from
//! stationarity in tᵢ, so |λᵢ| ≤ sᵢ, and the complementarity of the two rows gives sᵢ |rᵢ| = λᵢ rᵢ.
//! The auxiliary unknowns have no stiffness (A's block for them is zero); the kernel of A is
//! carried over padded with zeros (the t-directions are bounded by the rows, not free modes).

use sprs::TriMat;

use super::blocks::{row_sets, ConstraintBlock, RowSet};
use super::problem::{QpError, QpProblem};
use super::residuals::{kkt_residuals, KktResiduals};
use super::solution::QpSolution;

/// A problem with box rows rewritten on auxiliary variables, and what is needed to bring its
/// answer back.
#[derive(Debug, Clone)]
pub struct AuxiliaryForm {
    /// The rewritten problem: unknowns (x, t), non-negative rows only.
    pub problem: QpProblem,
    /// The original unknowns n.
    dofs: usize,
    /// For each original row: where its multiplier comes from (one row, or a +/− pair).
    origin: Vec<Origin>,
}

/// Where an original row's multiplier is read in the rewritten problem.
#[derive(Debug, Clone, Copy)]
enum Origin {
    /// A non-negative row, kept as it is.
    Kept(usize),
    /// A box row: λ = μ⁺ − μ⁻ of these two rows.
    Split(usize, usize),
    /// A box row of bound 0, left out: λ = 0.
    Zero,
}

impl AuxiliaryForm {
    /// Rewrites `problem` (whose blocks must be valid): non-negative rows first in their order,
    /// then each box row's two rows.
    pub fn of(problem: &QpProblem) -> Result<Self, QpError> {
        let n = problem.dofs();
        let sets: Vec<RowSet> = row_sets(&problem.blocks).collect();
        let kept: Vec<usize> = (0..sets.len())
            .filter(|&i| sets[i] == RowSet::NonNegative)
            .collect();
        let boxed: Vec<(usize, f64)> = sets
            .iter()
            .enumerate()
            .filter_map(|(i, s)| match s {
                RowSet::Box(bound) if *bound > 0.0 => Some((i, *bound)),
                RowSet::Box(_) | RowSet::NonNegative => None,
            })
            .collect();
        let k = boxed.len();
        let mut a = TriMat::with_capacity((n + k, n + k), problem.stiffness.nnz());
        for (v, (i, j)) in problem.stiffness.iter() {
            a.add_triplet(i, j, *v);
        }
        let mut load = problem.load.clone();
        load.extend(boxed.iter().map(|(_, s)| -s));
        let rows_out = kept.len() + 2 * k;
        let b_rows = problem.constraints.to_csr();
        let mut b = TriMat::with_capacity((rows_out, n + k), 2 * problem.constraints.nnz() + 2 * k);
        let mut gap = Vec::with_capacity(rows_out);
        let mut origin = vec![Origin::Zero; sets.len()];
        for (out, &i) in kept.iter().enumerate() {
            if let Some(row) = b_rows.outer_view(i) {
                for (j, v) in row.iter() {
                    b.add_triplet(out, j, *v);
                }
            }
            gap.push(problem.gap[i]);
            origin[i] = Origin::Kept(out);
        }
        for (t, &(i, _)) in boxed.iter().enumerate() {
            let (plus, minus) = (kept.len() + 2 * t, kept.len() + 2 * t + 1);
            if let Some(row) = b_rows.outer_view(i) {
                for (j, v) in row.iter() {
                    b.add_triplet(plus, j, *v);
                    b.add_triplet(minus, j, -*v);
                }
            }
            b.add_triplet(plus, n + t, -1.0);
            b.add_triplet(minus, n + t, -1.0);
            gap.push(problem.gap[i]);
            gap.push(-problem.gap[i]);
            origin[i] = Origin::Split(plus, minus);
        }
        let kernel = problem
            .kernel
            .iter()
            .map(|v| {
                v.iter()
                    .copied()
                    .chain(std::iter::repeat_n(0.0, k))
                    .collect()
            })
            .collect();
        let rewritten = QpProblem::try_new(a.to_csc(), load, b.to_csc(), gap)?
            .with_kernel(kernel)?
            .with_blocks(vec![ConstraintBlock::NonNegative { rows: rows_out }])?;
        Ok(Self {
            problem: rewritten,
            dofs: n,
            origin,
        })
    }

    /// The answer of the original problem from one of the rewritten problem: x without the
    /// auxiliary unknowns, each box row's λ = μ⁺ − μ⁻.  Status, iterations and message are kept.
    pub fn recover(&self, mut solution: QpSolution) -> QpSolution {
        solution.x.truncate(self.dofs);
        solution.multipliers = self.multipliers(&solution.multipliers);
        solution
    }

    /// The original problem's multipliers from the rewritten problem's `mu`.
    fn multipliers(&self, mu: &[f64]) -> Vec<f64> {
        let at = |r: usize| mu.get(r).copied().unwrap_or(f64::NAN);
        self.origin
            .iter()
            .map(|o| match *o {
                Origin::Kept(r) => at(r),
                Origin::Split(plus, minus) => at(plus) - at(minus),
                Origin::Zero => 0.0,
            })
            .collect()
    }

    /// The residuals of `original` (the problem this form was made of) at the answer (x, μ) of
    /// the rewritten problem: what a backend's own stopping tests must judge by, since the
    /// rewritten problem's scales count the auxiliary loads sᵢ and are looser.
    pub fn original_residuals(&self, original: &QpProblem, x: &[f64], mu: &[f64]) -> KktResiduals {
        let x = &x[..self.dofs.min(x.len())];
        kkt_residuals(original, x, &self.multipliers(mu))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// min ½ x² − 2x + 1·|x|: the box term's slope 1 takes 1 off the load 2, so x = 1 (slip),
    /// λ = 1 (at its bound); with bound 3 > 2 the row sticks: x = 0, λ = 2.  Solved by hand on
    /// the rewritten problem and brought back.
    #[test]
    fn the_rewritten_problem_has_the_box_problem_s_answer() {
        let mut a = TriMat::new((1, 1));
        a.add_triplet(0, 0, 1.0);
        let mut b = TriMat::new((1, 1));
        b.add_triplet(0, 0, 1.0);
        for (bound, x, lambda) in [(1.0_f64, 1.0_f64, 1.0_f64), (3.0, 0.0, 2.0)] {
            let qp = QpProblem::try_new(a.to_csc(), vec![2.0], b.to_csc(), vec![0.0])
                .unwrap()
                .with_blocks(vec![ConstraintBlock::Box {
                    bounds: vec![bound],
                }])
                .unwrap();
            let form = AuxiliaryForm::of(&qp).unwrap();
            assert_eq!(form.problem.dofs(), 2);
            assert_eq!(form.problem.rows(), 2);
            // At the answer: t = |x|; the + row (x − t ≤ 0) carries μ⁺, the − row μ⁻, with
            // μ⁺ + μ⁻ = bound and μ⁺ − μ⁻ = λ.
            let t = x.abs();
            let (plus, minus) = if x > 0.0 {
                (bound, 0.0)
            } else {
                ((bound + lambda) / 2.0, (bound - lambda) / 2.0)
            };
            let aux = vec![x, t];
            let mu = vec![plus, minus];
            assert!(kkt_residuals(&form.problem, &aux, &mu).meet(1e-14));
            let back = form.recover(QpSolution {
                x: aux,
                multipliers: mu,
                status: crate::QpStatus::Solved,
                iterations: 0,
                solve_time: std::time::Duration::ZERO,
                message: None,
            });
            assert_eq!(back.x, vec![x]);
            assert_eq!(back.multipliers, vec![lambda]);
            assert!(kkt_residuals(&qp, &back.x, &back.multipliers).meet(1e-14));
        }
    }
}
