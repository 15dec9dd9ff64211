//! Backend-specific settings: one plain struct, one place for validation.

use crate::error::PdasError;

/// Which rows are active before the first factorisation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StartSet {
    /// Rows whose initial gap is closed or overlapping: gᵢ ≤ `closed_gap` · Xᵢ, with Xᵢ the
    /// row's length scale of [`signorini_qp::ResidualScales`].  A long interface pressed
    /// along its whole length (gaps all zero) is then solved by the first factorisation.
    ClosedGaps,
    /// No row: the first factorisation gives the unconstrained solution, the second starts from
    /// the rows it violates (the textbook start).
    Empty,
    /// Every row: the bodies glued along the whole interface, the rows in tension dropped
    /// next.  Holds every rigid mode of a floating body from the first factorisation.
    All,
    /// No guess: one interior-point predictor step from the centred start x = 0,
    /// sᵢ = gᵢ⁺ + 0.1 Xᵢ, λᵢ = F (Xᵢ, F the scales of [`signorini_qp::ResidualScales`])
    /// predicts the first set, which is then solved exactly — the crossover of the
    /// interior-point phase (see the crate docs).  One factorisation more than [`StartSet::All`]
    /// where every row ends active, fewer where most rows open.  With box rows (friction, which
    /// the interior-point phase does not know) it is [`StartSet::All`].
    Interior,
    /// [`StartSet::All`] when at least half the one-sided rows touch first
    /// ([`signorini_qp::first_touch`]: a flush interface, which a load may press along its
    /// whole length), else [`StartSet::Interior`] (a curved interface, a cylinder on a block:
    /// gluing every row would glue more open gaps than closed ones).
    Auto,
}

impl StartSet {
    /// Every start, for tests and measurements.
    pub const EVERY: [StartSet; 5] = [
        StartSet::All,
        StartSet::ClosedGaps,
        StartSet::Empty,
        StartSet::Interior,
        StartSet::Auto,
    ];
}

/// Settings of the primal–dual active-set backend.  Every field has a default (see
/// [`Default`]); the regularisations are relative to the mean diagonal of A, so that they mean
/// the same for a scaled and an unscaled problem.
#[derive(Debug, Clone, PartialEq)]
pub struct PdasSettings {
    /// Cap on iterations — active-set steps, interior-point steps and exact solves after
    /// them, one numeric factorisation or low-rank update each — used when
    /// `SolveOptions::max_iter` is `None`.  Default `100`.
    pub max_iter: usize,
    /// c in the active-set rule λᵢ + c (Bx − g)ᵢ > 0, relative to the mean diagonal of A.
    /// Default `1.0`.  (The rule only compares c (Bx − g)ᵢ with 0 off the set and λᵢ with 0
    /// on it, so c matters only for the rows whose status changes in both ways at once.)
    pub penalty: f64,
    /// The first active set.  Default [`StartSet::Auto`] (see the crate docs for the
    /// measurements behind the choice).
    pub start: StartSet,
    /// A gap counts as closed for [`StartSet::ClosedGaps`] when gᵢ ≤ `closed_gap` · Xᵢ.
    /// Default `1e-9`.
    pub closed_gap: f64,
    /// δ: the static regularisation −δ on the diagonal of every active multiplier row, which
    /// makes the KKT matrix quasi-definite (an LDLᵀ exists in any ordering).  Relative to the
    /// mean diagonal of A (δ is a compliance).  Default `1e-8`: measured against 1e-6, 1e-10,
    /// 1e-12 and 1e-14 on the thin strips and the seed scenes, it needs the fewest refinement
    /// steps (one or two; a smaller δ leaves a larger first error, a larger one pollutes the
    /// factor more).  Iterative refinement against the unregularised system removes its effect.
    pub dual_regularization: f64,
    /// ρ: a static +ρ on the primal diagonal, added only when A has a kernel (floating bodies),
    /// so that the factorisation exists while the active rows do not yet hold every rigid mode.
    /// Relative to the mean diagonal of A.  Default `1e-10`.  Removed by refinement as well.
    pub primal_regularization: f64,
    /// The most refinement steps after each factorisation; refinement stops earlier as soon
    /// as the residual stops decreasing.  Default `30`.
    pub refinement_steps: usize,
    /// Refinement also stops once the scaled residual of the KKT system (‖r_x‖∞ / F,
    /// |r_λ,ᵢ| / Xᵢ) is at most `refinement_target` × `SolveOptions::tol`, or within a small
    /// multiple of the round-off in forming that residual.  Default `1e-3`: three digits beyond
    /// what the answer is judged by.
    pub refinement_target: f64,
    /// The most rows by which a set may differ from the factored one to be solved by a
    /// low-rank update of that factor instead of a new factorisation (one extra solve per
    /// changed row, batched and kept until the next factorisation; used only when those
    /// solves are measured to be cheaper than a factorisation and the kept columns take no
    /// more memory than the factor).  `0` factorises every set.  Default `256`.
    pub max_update_rank: usize,
}

impl Default for PdasSettings {
    fn default() -> Self {
        Self {
            max_iter: 100,
            penalty: 1.0,
            start: StartSet::Auto,
            closed_gap: 1e-9,
            dual_regularization: 1e-8,
            primal_regularization: 1e-10,
            refinement_steps: 30,
            refinement_target: 1e-3,
            max_update_rank: 256,
        }
    }
}

impl PdasSettings {
    /// Checks every field's range.
    pub fn validate(&self) -> Result<(), PdasError> {
        let bad = |field: &'static str, reason: &str| {
            Err(PdasError::Settings {
                field,
                reason: reason.to_string(),
            })
        };
        let positive = |v: f64| v > 0.0 && v.is_finite();
        if self.max_iter == 0 {
            return bad("max_iter", "must be at least 1");
        }
        if !positive(self.penalty) {
            return bad("penalty", "must be positive and finite");
        }
        if !(self.closed_gap >= 0.0 && self.closed_gap.is_finite()) {
            return bad("closed_gap", "must be non-negative and finite");
        }
        if !(positive(self.dual_regularization) && self.dual_regularization < 1.0) {
            return bad("dual_regularization", "must lie in (0, 1)");
        }
        if !(positive(self.primal_regularization) && self.primal_regularization < 1.0) {
            return bad("primal_regularization", "must lie in (0, 1)");
        }
        if !(self.refinement_target >= 0.0 && self.refinement_target.is_finite()) {
            return bad("refinement_target", "must be non-negative and finite");
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_bad_values_are_named() {
        assert!(PdasSettings::default().validate().is_ok());
        let s = PdasSettings {
            dual_regularization: 0.0,
            ..Default::default()
        };
        let e = s.validate().unwrap_err().to_string();
        assert!(e.contains("dual_regularization"), "{e}");
        let s = PdasSettings {
            max_iter: 0,
            ..Default::default()
        };
        assert!(s.validate().is_err());
    }
}
