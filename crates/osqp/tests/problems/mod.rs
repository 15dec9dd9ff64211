//! Assertions shared by this crate's tests; the problems and the comparison live in
//! `signorini_qp::examples`, the same for every backend.
#![allow(dead_code)]

pub use signorini_qp::examples::*;
use signorini_qp::QpSolution;

/// Asserts x and λ match `known` to `tol` (relative to the largest entry).
pub fn assert_close(solution: &QpSolution, known: &Known, tol: f64) {
    if let Some(what) = known.mismatch(&solution.x, &solution.multipliers, tol) {
        panic!("{what}");
    }
}
