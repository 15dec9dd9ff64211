//! The interval each multiplier lives in, for the projected methods (PGS, Uzawa) and the
//! active-set method's projection (SSN): [0, ∞) for a contact row, [−s, s] for a box row
//! (Tresca's tangential multipliers; s = 0 is a box row too, whose multiplier is 0).

use signorini_qp::{row_sets, QpProblem, RowSet};

/// Each row's interval [lo, hi], in row order.
pub fn of(problem: &QpProblem) -> Vec<(f64, f64)> {
    row_sets(&problem.blocks).map(RowSet::interval).collect()
}

pub use signorini_qp::project;

/// Each row's box bound s, `None` on a one-sided row.  A zero bound (Coulomb's tangential row
/// where the normal force vanishes) is `Some(0.0)`, never a one-sided row: telling the two
/// apart by the interval's lower end (−0 < 0 is false) is the mistake this avoids.
pub fn box_bounds(problem: &QpProblem) -> Vec<Option<f64>> {
    row_sets(&problem.blocks)
        .map(|set| match set {
            RowSet::NonNegative => None,
            RowSet::Box(s) => Some(s),
        })
        .collect()
}

/// `lambda` projected row by row onto `sets` with [`project`].
pub fn project_all(lambda: &[f64], sets: &[(f64, f64)]) -> Vec<f64> {
    lambda
        .iter()
        .zip(sets)
        .map(|(l, set)| project(*l, *set))
        .collect()
}
