//! Nondimensionalisation of a QP before any backend sees it.

use super::blocks::ConstraintBlock;
use super::ops::{abs_diagonal, norm_inf};
use super::problem::QpProblem;
use super::solution::QpSolution;

/// Scalar scaling that makes a QP dimensionless: x = `displacement` · x̂, A = `stiffness` · Â,
/// f = `stiffness`·`displacement` · f̂, g = `displacement` · ĝ, λ = `stiffness`·`displacement` · λ̂
/// (and a box row's bound s like λ).
///
/// Backends only ever see the scaled problem, so results do not depend on the user's units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QpScaling {
    /// Stiffness unit (the mean diagonal of A).
    pub stiffness: f64,
    /// Displacement unit: the larger of ‖f‖∞ / stiffness unit and the deepest initial overlap
    /// max(0, −minᵢ gᵢ); the largest gap when both are zero; 1 when g is zero too.
    pub displacement: f64,
}

impl QpScaling {
    /// Scales chosen from the problem's data; all-zero data gives unit scales.
    pub fn of(problem: &QpProblem) -> Self {
        let n = problem.dofs();
        let diag_sum: f64 = abs_diagonal(&problem.stiffness).iter().sum();
        let stiffness = if n > 0 && diag_sum > 0.0 {
            diag_sum / n as f64
        } else {
            1.0
        };
        let load = norm_inf(&problem.load);
        // An initial overlap is a displacement the solve must make: scaling by it keeps the
        // scaled gaps ≥ −1 (a tiny load beside an overlap gave ĝ = −1e40, beyond what OSQP
        // accepts as a finite bound).
        let overlap = problem.gap.iter().fold(0.0_f64, |m, g| m.max(-g));
        let displacement = if load > 0.0 || overlap > 0.0 {
            // Kept ≥ 1e-150 ‖g‖∞ so that the scaled gaps stay finite when a tiny load meets a
            // huge stiffness (1e-100 / 1e212 underflowed to 0 and ĝ became infinite).
            (load / stiffness)
                .max(overlap)
                .max(1e-150 * norm_inf(&problem.gap))
        } else {
            let gap = norm_inf(&problem.gap);
            if gap > 0.0 {
                gap
            } else {
                1.0
            }
        };
        Self {
            stiffness,
            displacement,
        }
    }

    /// True when both units are within 10⁻⁹ of one: the problem is in units of its own data
    /// already (as [`QpScaling::scale`] leaves it, up to rounding), and scaling it again would
    /// only change its last bits.
    pub fn is_unit(&self) -> bool {
        (self.stiffness - 1.0).abs() <= 1e-9 && (self.displacement - 1.0).abs() <= 1e-9
    }

    /// Turns `problem` into the dimensionless Â, f̂, B, ĝ without a copy.
    pub fn scale_in_place(&self, problem: &mut QpProblem) {
        let force = self.stiffness * self.displacement;
        problem
            .stiffness
            .data_mut()
            .iter_mut()
            .for_each(|v| *v /= self.stiffness);
        problem.load.iter_mut().for_each(|v| *v /= force);
        problem.gap.iter_mut().for_each(|v| *v /= self.displacement);
        scale_bounds(&mut problem.blocks, force);
    }

    /// The dimensionless problem Â, f̂, B, ĝ.
    pub fn scale(&self, problem: &QpProblem) -> QpProblem {
        let force = self.stiffness * self.displacement;
        let mut scaled = QpProblem {
            stiffness: problem.stiffness.map(|v| v / self.stiffness),
            load: problem.load.iter().map(|v| v / force).collect(),
            constraints: problem.constraints.clone(),
            gap: problem.gap.iter().map(|v| v / self.displacement).collect(),
            kernel: problem.kernel.clone(),
            blocks: problem.blocks.clone(),
        };
        scale_bounds(&mut scaled.blocks, force);
        scaled
    }

    /// Brings a solution of the scaled problem back to the original units.
    pub fn unscale(&self, mut solution: QpSolution) -> QpSolution {
        let force = self.stiffness * self.displacement;
        solution.x.iter_mut().for_each(|v| *v *= self.displacement);
        solution.multipliers.iter_mut().for_each(|v| *v *= force);
        solution
    }
}

/// Divides every box row's bound by the force unit (a bound is a force, like λ).
fn scale_bounds(blocks: &mut [ConstraintBlock], force: f64) {
    for block in blocks {
        if let ConstraintBlock::Box { bounds } = block {
            bounds.iter_mut().for_each(|s| *s /= force);
        }
    }
}
