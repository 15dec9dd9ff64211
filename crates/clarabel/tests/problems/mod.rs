//! Assertions shared by this crate's tests; the problems live in `signorini_core::examples`.
#![allow(dead_code)]

pub use signorini_core::examples::*;
use signorini_core::qp::QpSolution;

/// Largest entrywise difference.
pub fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Asserts x and λ match `known` to `tol` (relative to the largest entry).
pub fn assert_close(solution: &QpSolution, known: &Known, tol: f64) {
    let xs = known.x.iter().fold(1e-300_f64, |m, v| m.max(v.abs()));
    let ls = known
        .multipliers
        .iter()
        .fold(1e-300_f64, |m, v| m.max(v.abs()));
    assert!(
        max_diff(&solution.x, &known.x) <= tol * xs,
        "x = {:?}, expected {:?}",
        solution.x,
        known.x
    );
    assert!(
        max_diff(&solution.multipliers, &known.multipliers) <= tol * ls.max(xs.min(1.0)),
        "λ = {:?}, expected {:?}",
        solution.multipliers,
        known.multipliers
    );
}
