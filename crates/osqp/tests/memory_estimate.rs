//! OSQP's memory estimate against a factor size known analytically.
#![allow(clippy::unwrap_used)]

use signorini_core::examples::laplacian_with_bounds;

/// A chain of n springs with c contact rows on distinct nodes: the KKT graph
/// [A, Bᵀ; B, −ρ⁻¹I] is a tree (the chain, one leaf per row), which minimum degree eliminates
/// leaf by leaf without any fill, so nnz(L) = (n + c) diagonal + (n − 1 + c) edges exactly.
#[test]
fn osqp_prices_two_factors_of_a_tree_kkt_within_a_factor_of_three() {
    for (n, c) in [(200, 7), (5_000, 300)] {
        let qp = laplacian_with_bounds(n, c);
        let estimate = signorini_osqp::memory_need(&qp).unwrap();
        let nnz_l = 2 * n + 2 * c - 1;
        assert_eq!(estimate.dim, n + c);
        // The supernodal analysis stores at least nnz(L); relaxed supernodes add explicit zeros
        // and the diagonal blocks' upper triangles, under 3× on a tree (measured 1.0–2.1).
        let ratio = estimate.stored_values as f64 / nnz_l as f64;
        assert!((1.0..3.0).contains(&ratio), "n {n}, c {c}: ratio {ratio}");
        // Two factors (ADMM's, the polish's) at 16 B per value (Lx, Li with 64-bit c_int).
        assert_eq!(estimate.factor, 2.0 * 16.0 * estimate.stored_values as f64);
        assert!(estimate.total() >= 2.0 * 16.0 * nnz_l as f64);
    }
}
