//! OSQP's memory estimate against a factor size known analytically.
#![allow(clippy::unwrap_used)]

use signorini_qp::examples::laplacian_with_bounds;

/// A chain of n springs with c contact rows on distinct nodes: the KKT graph
/// [A, Bᵀ; B, −ρ⁻¹I] is a tree (the chain, one leaf per row), which minimum degree eliminates
/// leaf by leaf without any fill, so nnz(L) = (n + c) diagonal + (n − 1 + c) edges exactly.
#[test]
fn osqp_prices_two_exact_factors_of_a_tree_kkt() {
    for (n, c) in [(200, 7), (5_000, 300)] {
        let qp = laplacian_with_bounds(n, c);
        let estimate = signorini_osqp::memory_need(&qp).unwrap();
        let nnz_l = 2 * n + 2 * c - 1;
        assert_eq!(estimate.dim, n + c);
        // AMD finds the no-fill ordering of a tree: the count is exact (the forced supernodal
        // storage, 7× nnz(L) here, was the estimate's measure before and over-priced it).
        assert_eq!(estimate.nnz_l, nnz_l, "n {n}, c {c}");
        // Two factors (ADMM's, the polish's) at 16 B per nonzero (Lx, Li with 64-bit c_int).
        assert_eq!(estimate.factor, 2.0 * 16.0 * nnz_l as f64);
    }
}
