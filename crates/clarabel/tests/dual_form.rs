//! clarabel on the condensed dual ([`CondensedDual`]) gives the known optima of the core's
//! examples, and the same x and λ as clarabel on the primal.

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used)]

use signorini_clarabel::{ClarabelBackend, NAME};
use signorini_qp::examples::{self, max_diff, Known};
use signorini_qp::{
    checked_status, kkt_residuals, CondensedDual, QpBackend, QpError, QpProblem, QpSolution,
    QpStatus, SolveOptions,
};

const TOL: f64 = 1e-9;

fn dual() -> CondensedDual<ClarabelBackend> {
    CondensedDual::new(ClarabelBackend::default(), "clarabel/dual")
}

fn solved(backend: &mut dyn QpBackend, problem: &QpProblem) -> QpSolution {
    let options = SolveOptions {
        tol: TOL,
        ..SolveOptions::default()
    };
    let s = backend.solve(problem, &options).unwrap();
    let r = kkt_residuals(problem, &s.x, &s.multipliers);
    assert_eq!(
        checked_status(s.status, &r, TOL),
        QpStatus::Solved,
        "{r:?} {:?}",
        s.message
    );
    s
}

/// Known optimum to 1e-7 relative (the core's residual tolerance 1e-9 on these well-conditioned
/// examples, cond(A) ≤ 400, bounds the error in x and λ by ~4e-7 at worst; clarabel's own
/// primal tests use the same 1e-7).
fn check(known: &Known) {
    let s = solved(&mut dual(), &known.problem);
    if let Some(why) = known.mismatch(&s.x, &s.multipliers, 1e-7) {
        panic!("{why}");
    }
    // And the primal form's answer, to the same bound.
    let p = solved(&mut ClarabelBackend::default(), &known.problem);
    let scale = known.x.iter().fold(1.0_f64, |m, v| m.max(v.abs()));
    let force = known.multipliers.iter().fold(scale, |m, v| m.max(v.abs()));
    assert!(max_diff(&s.x, &p.x) <= 1e-7 * scale);
    assert!(max_diff(&s.multipliers, &p.multipliers) <= 1e-7 * force);
}

#[test]
fn known_optima_through_the_dual() {
    for known in [
        examples::scalar(1.0),
        examples::scalar(3.0),
        examples::two_rows(),
        examples::two_rows_scaled(1e6),
        examples::two_rows_scaled(1e-6),
        examples::unconstrained(),
        examples::spring_chain(),
    ] {
        check(&known);
    }
}

#[test]
fn many_rows_agree_with_the_primal() {
    // 200 springs, 40 bound rows, most active: H is 40 × 40 and formed in one block.
    let problem = examples::laplacian_with_bounds(200, 40);
    let d = solved(&mut dual(), &problem);
    let p = solved(&mut ClarabelBackend::default(), &problem);
    let scale = p.x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    // Both meet 1e-9 on a chain with cond(A) ~ 4·200²: 1e-6 relative is what that allows.
    assert!(
        max_diff(&d.x, &p.x) <= 1e-6 * scale,
        "{}",
        max_diff(&d.x, &p.x)
    );
    let lscale = p.multipliers.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    assert!(max_diff(&d.multipliers, &p.multipliers) <= 1e-6 * lscale);
}

#[test]
fn an_infeasible_primal_is_reported_as_such() {
    // The dual of a primal without feasible point is unbounded below: clarabel's dual-infeasible
    // certificate on the dual must come back as primal-infeasible.
    let s = dual()
        .solve(&examples::infeasible(), &SolveOptions::default())
        .unwrap();
    assert_eq!(s.status, QpStatus::PrimalInfeasible, "{:?}", s.message);
}

#[test]
fn a_singular_stiffness_is_refused_with_its_reason() {
    let mut problem = examples::two_rows().problem;
    problem.kernel = vec![vec![1.0, 1.0]];
    match dual().solve(&problem, &SolveOptions::default()) {
        Err(QpError::Unavailable { backend, reason }) => {
            assert_eq!(backend, "clarabel/dual");
            assert!(reason.contains("rigid-body"), "{reason}");
        }
        other => panic!("expected Unavailable, got {other:?}"),
    }
    assert_eq!(dual().inner().settings, ClarabelBackend::default().settings);
    assert_eq!(NAME, "clarabel");
}
