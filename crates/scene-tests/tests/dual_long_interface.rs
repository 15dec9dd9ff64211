//! A scaled-down long interface (issue 9): a thin strip 4 × 0.02 pressed along its whole length
//! onto a thin clamped foundation, hmax 0.01 — every contact row active at the answer, and the
//! dual Hessian of the strip very ill-conditioned (a strip held at one end has the compliance
//! of a cantilever).  The full-size scenes (strip 20 long, 51 k DOFs) are in
//! /work/notes/scenes; this one keeps the slenderness that broke dual-ssn (L/t = 200) at a size
//! a test can afford.
#![allow(clippy::unwrap_used)]

mod common;

use faer::prelude::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::Mat;
use signorini_dual::{DualBackend, DualSettings};
use signorini_qp::{kkt_residuals, QpProblem, QpStatus};

/// The independent answer: the equality KKT system [A B_Sᵀ; B_S 0] [x; λ_S] = [f; g_S] on the
/// rows S, by faer's sparse LU with partial pivoting (no dual, no kernel handling: B holds the
/// strip's rigid mode, so the system is nonsingular).  S starts as every row; rows with λ < 0
/// are dropped until none is (a primal active set), and the caller checks the dropped rows'
/// slack.
fn primal_kkt(p: &QpProblem) -> (Vec<f64>, Vec<f64>) {
    let mut active = vec![true; p.rows()];
    for _ in 0..10 {
        let (x, lambda) = kkt_on(p, &active);
        if lambda.iter().all(|l| *l >= 0.0) {
            return (x, lambda);
        }
        for (a, l) in active.iter_mut().zip(&lambda) {
            *a = *a && *l > 0.0;
        }
    }
    panic!("the reference active set did not settle");
}

fn kkt_on(p: &QpProblem, active: &[bool]) -> (Vec<f64>, Vec<f64>) {
    let (n, m) = (p.dofs(), p.rows());
    let mut t = Vec::new();
    for (j, col) in p.stiffness.outer_iterator().enumerate() {
        for (i, &v) in col.iter() {
            t.push(Triplet::new(i, j, v));
        }
    }
    for (j, col) in p.constraints.outer_iterator().enumerate() {
        for (i, &v) in col.iter().filter(|(i, _)| active[*i]) {
            t.push(Triplet::new(n + i, j, v));
            t.push(Triplet::new(j, n + i, v));
        }
    }
    for (i, _) in active.iter().enumerate().filter(|(_, a)| !**a) {
        t.push(Triplet::new(n + i, n + i, 1.0));
    }
    let kkt = SparseColMat::<usize, f64>::try_new_from_triplets(n + m, n + m, &t).unwrap();
    let lu = kkt.sp_lu().unwrap();
    let rhs = Mat::<f64>::from_fn(n + m, 1, |i, _| match i {
        i if i < n => p.load[i],
        i if active[i - n] => p.gap[i - n],
        _ => 0.0,
    });
    let sol = lu.solve(&rhs);
    let x = (0..n).map(|i| sol[(i, 0)]).collect();
    let lambda = (n..n + m).map(|i| sol[(i, 0)]).collect();
    (x, lambda)
}

fn objective(p: &QpProblem, x: &[f64]) -> f64 {
    let ax = signorini_qp::mat_vec(&p.stiffness, x);
    0.5 * signorini_qp::dot(x, &ax) - signorini_qp::dot(&p.load, x)
}

fn check(clamped: bool, units: common::Units) {
    let p = common::strip_qp(4.0, clamped, (0.0, 4.0));
    assert!(
        p.rows() > 300 && p.dofs() > 20 * p.rows(),
        "{} {}",
        p.rows(),
        p.dofs()
    );
    assert_eq!(p.kernel.len(), usize::from(!clamped), "kernel");
    let (x_ref, lambda_ref) = primal_kkt(&p);
    // The reference really is the answer (to round-off): no penetration on the dropped rows,
    // and nearly every row carries a force — a long, fully active interface.
    let slack_ok = kkt_residuals(&p, &x_ref, &lambda_ref);
    assert!(slack_ok.meet(1e-8), "reference {slack_ok:?}");
    let active = lambda_ref.iter().filter(|l| **l > 0.0).count();
    assert!(active + 2 >= p.rows(), "{active} of {}", p.rows());
    // 1e-10: the tolerance the issue asks the dual methods to reach (tighter than the 1e-9
    // default) on exactly this kind of problem.
    let tol = 1e-10;
    let mut backend = DualBackend::active_set(DualSettings::default());
    let (sol, status) = common::solve_in(&mut backend, &p, tol, units);
    assert_eq!(status, QpStatus::Solved, "{:?}", sol.message);
    let r = kkt_residuals(&p, &sol.x, &sol.multipliers);
    assert!(r.meet(tol), "{r:?}");
    // Agreement with the independent solve.  The objective is first-order insensitive to the
    // error, so both backward-stable answers give it to ~1e-12 relative; x and λ are limited by
    // the condition of the KKT system (the strip's bending, ~1e6 here), so 1e-6 relative is
    // what two stable solvers can promise.
    let (f_dual, f_ref) = (objective(&p, &sol.x), objective(&p, &x_ref));
    assert!(
        (f_dual - f_ref).abs() <= 1e-10 * f_ref.abs(),
        "objective {f_dual} vs {f_ref}"
    );
    let dx = common::rel_diff(&x_ref, &sol.x);
    let dl = common::rel_diff(&lambda_ref, &sol.multipliers);
    assert!(dx < 1e-6 && dl < 1e-6, "x differs by {dx:e}, λ by {dl:e}");
    println!(
        "{}: {:?}; |Δx| {dx:.1e}, |Δλ| {dl:.1e}",
        if clamped { "clamped" } else { "floating" },
        sol.message
    );
}

/// Regression (issue 9): the refinement against the sparse primal residual is what makes these
/// pass; the dense Newton solve alone left complementarity ~1e-3 (floating) and ~1e-8.
#[test]
fn thin_strip_floating_in_y_is_solved_to_1e_10() {
    check(false, common::Units::Own);
}

/// In the scene's units, as this test was written.
#[test]
fn thin_strip_clamped_at_one_end_is_solved_to_1e_10() {
    check(true, common::Units::Given);
}

/// Nondimensionalised (what the driver hands dual-ssn): solved to 1e-10, but its objective
/// differs from the independent KKT solve's by 1.2e-9 relative, not the 1e-10 the test asks.
#[test]
#[ignore = "dual-ssn on the nondimensionalised clamped strip: objective 1.2e-9 from the reference (bound 1e-10); open in issue 21"]
fn thin_strip_clamped_at_one_end_is_solved_to_1e_10_in_its_own_units() {
    check(true, common::Units::Own);
}

/// The matrix-free Newton steps on the same ill-conditioned strip: projected CG alone cannot
/// reach 1e-10 on a dual this ill-conditioned, but it does not have to — the refinement against
/// the primal residual supplies the digits, so the answer is the same.
#[test]
#[ignore = "slow (~15 s in release): CG on this ill-conditioned dual needs thousands of products; run by hand"]
fn thin_strip_matrix_free_agrees() {
    let p = common::strip_qp(4.0, false, (0.0, 4.0));
    let (x_ref, _) = primal_kkt(&p);
    let mut backend = DualBackend::active_set(DualSettings {
        matrix_free_rows: 0,
        ..DualSettings::default()
    });
    let t = std::time::Instant::now();
    let (sol, status) = common::solve(&mut backend, &p, 1e-10);
    println!("matrix-free: {:?} in {:?}", sol.message, t.elapsed());
    assert_eq!(status, QpStatus::Solved, "{:?}", sol.message);
    let dx = common::rel_diff(&x_ref, &sol.x);
    assert!(dx < 1e-6, "x differs by {dx:e}");
}
