//! The interval each multiplier lives in, for the projected methods (PGS, Uzawa): [0, ∞) for a
//! contact row, [−s, s] for a box row (Tresca's tangential multipliers).

use signorini_qp::{row_sets, QpProblem, RowSet};

/// Each row's interval [lo, hi], in row order.
pub fn of(problem: &QpProblem) -> Vec<(f64, f64)> {
    row_sets(&problem.blocks)
        .map(|set| match set {
            RowSet::NonNegative => (0.0, f64::INFINITY),
            RowSet::Box(s) => (-s, s),
        })
        .collect()
}

/// `v` projected onto [lo, hi]: `max` before `min`, so that on a contact row it is `max(0, v)`
/// bit for bit (a NaN lands on lo, as `max(0)` puts it on 0).
pub fn project(v: f64, (lo, hi): (f64, f64)) -> f64 {
    v.max(lo).min(hi)
}
