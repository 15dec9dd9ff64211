//! Tangential rows of frictional pairs (docs/scene.md, "Friction").
//!
//! A pair with a friction law gives, for each of its (normal) contact rows, one tangential row
//! on the same slave node and master weights, along the row's tangent t = (n_y, −n_x) (the
//! normal turned clockwise by a right angle: +x for a slave resting on a master below it):
//!
//! ```text
//! rₜ = −t·u_X + Σₖ wₖ t·u_k − gₜ,    |λₜ| ≤ s,    s |rₜ| = λₜ rₜ
//! ```
//!
//! so −rₜ is the slave node's slip along t relative to the master, and λₜ the tangential force the master exerts on the slave node,
//! along t (its force on the slave is +λₜ t, as the normal row's is +λₙ n).  At a slipping node
//! λₜ = s sign rₜ: the friction force opposes the slip.  The bound s is Tresca's traction times
//! the row's tributary length (a fixed force), or Coulomb's μ λₙ of the node's normal row
//! (updated by the solve's fixed point, `crate::friction`).  All tangential rows come after all
//! normal rows in B, as one box block ([`crate::qp::ConstraintBlock::Box`]).
//!
//! The reference gₜ is where the slave node sticks: gₜ = k gₙ, k the row's
//! [pairing slope](crate::contact::ContactRow::pairing_slope), so that a node that closes its
//! normal gap gₙ along the direction that paired it with the master and then sticks has not
//! slipped (it lands on its paired point; k = 0 where the row's normal is that direction).
//! Along a load path each increment measures the slip from the previous converged state
//! ([`TangentialRow::stick_value`]).

use crate::contact::PairRows;
use crate::scene::Friction;

/// One tangential row: which normal row it shares its node with, and its friction law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TangentialRow {
    /// Index of the normal row (among the normal rows of B, in pair order).
    pub normal_row: usize,
    /// Index of the pair in the scene.
    pub pair: usize,
    /// The pair's friction law.
    pub law: Friction,
    /// The normal row's tributary length (turns a Tresca traction into the row's force bound).
    pub tributary: f64,
    /// The row's pairing slope k ([`crate::contact::ContactRow::pairing_slope`]).
    pub pairing_slope: f64,
}

impl TangentialRow {
    /// The bound s of the row's multiplier, given its normal row's multiplier λₙ (used by
    /// Coulomb only; a negative round-off λₙ counts as 0).
    pub fn bound(&self, normal_multiplier: f64) -> f64 {
        self.law.bound(normal_multiplier, self.tributary)
    }

    /// The value of (B u)ₜ at which this row (index `row` of B) has not slipped since a state
    /// whose B u was `bu`, with `gap` the model's gaps: (B u)ₜ + k (gₙ − (B u)ₙ) — the row's value
    /// then, plus what closing the normal gap still open then along the pairing direction adds
    /// (nothing for a node already in contact).  With `bu` = 0 (the reference) it is gₜ = k gₙ.
    pub fn stick_value(&self, row: usize, gap: &[f64], bu: &[f64]) -> f64 {
        let n = self.normal_row;
        bu[row] + self.pairing_slope * (gap[n] - bu[n])
    }
}

/// The tangential rows of `contacts`' frictional pairs, in the order of their normal rows.
pub(super) fn tangential_rows(contacts: &[PairRows]) -> Vec<TangentialRow> {
    let mut rows = Vec::new();
    let mut normal_row = 0;
    for pair in contacts {
        for r in &pair.rows {
            if let Some(law) = pair.friction {
                rows.push(TangentialRow {
                    normal_row,
                    pair: pair.pair,
                    law,
                    tributary: r.tributary,
                    pairing_slope: r.pairing_slope,
                });
            }
            normal_row += 1;
        }
    }
    rows
}
