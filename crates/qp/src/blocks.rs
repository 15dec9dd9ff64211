//! Constraint blocks: consecutive rows of B and g and the set their multipliers live in (after
//! clarabel's list of cones, `core/cones/`).
//!
//! ```text
//! minimise ½ xᵀ A x − fᵀ x + Σ_{box rows i} sᵢ |(B x − g)ᵢ|
//! subject to (B x − g)ᵢ ≤ 0 on the non-negative rows
//! ```
//!
//! | block | rows | multipliers | KKT conditions per row, rᵢ = (B x − g)ᵢ |
//! |---|---|---|---|
//! | [`ConstraintBlock::NonNegative`] | rᵢ ≤ 0 (contact: no penetration) | λᵢ ≥ 0 | λᵢ rᵢ = 0 |
//! | [`ConstraintBlock::Box`] | any rᵢ (Tresca: the tangential slip) | \|λᵢ\| ≤ sᵢ | sᵢ \|rᵢ\| = λᵢ rᵢ |
//!
//! Stationarity is A x − f + Bᵀλ = 0 over every row.  On a box row, sᵢ |rᵢ| − λᵢ rᵢ ≥ 0 whenever
//! |λᵢ| ≤ sᵢ, and it is zero exactly when the row sticks (rᵢ = 0) below the bound or slips
//! (rᵢ ≠ 0) with λᵢ = sᵢ sign rᵢ at the bound: one complementarity measure for both.  A second-order
//! cone (3-D Coulomb) would be one more variant with its own rows and measures.
//!
//! A frictionless contact problem is one non-negative block; friction adds its tangential rows
//! as one box block after it.  A backend declares the kinds it solves
//! ([`crate::QpBackend::supports`]) and is refused a problem with any other
//! ([`crate::QpError::UnsupportedBlock`]) before it runs.

use serde::Serialize;

/// What a block's multipliers are constrained to (a block's type without its data).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum BlockKind {
    /// One-sided rows B x ≤ g, multipliers λ ≥ 0.
    NonNegative,
    /// Rows with bounded multipliers |λᵢ| ≤ sᵢ and the term sᵢ |(B x − g)ᵢ| in the objective.
    Box,
}

impl BlockKind {
    /// Every kind, in the order of [`ConstraintBlock`]'s variants.
    pub const ALL: [BlockKind; 2] = [BlockKind::NonNegative, BlockKind::Box];

    /// The word used in messages and reports (`"non-negative"`, `"box"`).
    pub fn as_str(self) -> &'static str {
        match self {
            BlockKind::NonNegative => "non-negative",
            BlockKind::Box => "box",
        }
    }
}

impl std::fmt::Display for BlockKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A run of consecutive constraint rows with one kind of multiplier set.
#[derive(Debug, Clone, PartialEq)]
pub enum ConstraintBlock {
    /// `rows` one-sided rows (B x)ᵢ ≤ gᵢ, multipliers λᵢ ≥ 0.
    NonNegative {
        /// Number of rows.
        rows: usize,
    },
    /// Rows with multipliers |λᵢ| ≤ `bounds[i]` (one bound ≥ 0 per row, in force units).
    Box {
        /// The bound sᵢ of each row.
        bounds: Vec<f64>,
    },
}

impl ConstraintBlock {
    /// The block's kind.
    pub fn kind(&self) -> BlockKind {
        match self {
            ConstraintBlock::NonNegative { .. } => BlockKind::NonNegative,
            ConstraintBlock::Box { .. } => BlockKind::Box,
        }
    }

    /// Number of rows the block holds.
    pub fn rows(&self) -> usize {
        match self {
            ConstraintBlock::NonNegative { rows } => *rows,
            ConstraintBlock::Box { bounds } => bounds.len(),
        }
    }
}

/// The multiplier set of one row, as the residual check reads it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RowSet {
    /// λ ≥ 0, r ≤ 0.
    NonNegative,
    /// |λ| ≤ the bound, any r.
    Box(f64),
}

impl RowSet {
    /// The set as an interval [lo, hi]: [0, ∞) or [−s, s] (s = 0: the point 0, still a box row).
    pub fn interval(self) -> (f64, f64) {
        match self {
            RowSet::NonNegative => (0.0, f64::INFINITY),
            RowSet::Box(s) => (-s, s),
        }
    }

    /// `v` projected onto the set ([`project`]).
    pub fn project(self, v: f64) -> f64 {
        project(v, self.interval())
    }
}

/// `v` projected onto [lo, hi]: `max` before `min`, so that on a one-sided row it is
/// `max(0, v)` bit for bit, and a NaN lands on lo (as `max(0)` puts it on 0) — every backend
/// projects with this one function.
pub fn project(v: f64, (lo, hi): (f64, f64)) -> f64 {
    v.max(lo).min(hi)
}

/// Each row's multiplier set, in row order, for `blocks`.
pub fn row_sets(blocks: &[ConstraintBlock]) -> impl Iterator<Item = RowSet> + '_ {
    blocks.iter().flat_map(|block| {
        (0..block.rows()).map(move |i| match block {
            ConstraintBlock::NonNegative { .. } => RowSet::NonNegative,
            ConstraintBlock::Box { bounds } => RowSet::Box(bounds[i]),
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn projection_clips_to_the_set_and_sends_nan_to_the_lower_end() {
        assert_eq!(RowSet::NonNegative.project(-2.0), 0.0);
        assert_eq!(RowSet::NonNegative.project(3.0), 3.0);
        assert_eq!(RowSet::Box(1.5).project(-4.0), -1.5);
        assert_eq!(RowSet::Box(1.5).project(4.0), 1.5);
        assert_eq!(RowSet::Box(1.5).project(0.25), 0.25);
        assert_eq!(RowSet::Box(0.0).project(7.0), 0.0);
        assert_eq!(RowSet::NonNegative.project(f64::NAN), 0.0);
        assert_eq!(RowSet::Box(2.0).project(f64::NAN), -2.0);
    }

    #[test]
    fn row_sets_follow_the_blocks_in_order() {
        let blocks = [
            ConstraintBlock::NonNegative { rows: 2 },
            ConstraintBlock::Box {
                bounds: vec![0.5, 0.0],
            },
            ConstraintBlock::NonNegative { rows: 1 },
        ];
        let sets: Vec<RowSet> = row_sets(&blocks).collect();
        assert_eq!(
            sets,
            [
                RowSet::NonNegative,
                RowSet::NonNegative,
                RowSet::Box(0.5),
                RowSet::Box(0.0),
                RowSet::NonNegative,
            ]
        );
        assert_eq!(blocks.iter().map(ConstraintBlock::rows).sum::<usize>(), 5);
        assert_eq!(blocks[1].kind(), BlockKind::Box);
    }

    #[test]
    fn kinds_have_distinct_names() {
        let names: std::collections::HashSet<&str> =
            BlockKind::ALL.iter().map(|k| k.as_str()).collect();
        assert_eq!(names.len(), BlockKind::ALL.len());
    }
}
