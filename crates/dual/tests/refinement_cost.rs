//! dual-ssn pays for its refinement only where it is needed: on a well-conditioned problem the
//! settled set is refined with at most two plain sparse solves, and the moving sets cost none.
//! (Regression: when the refinement landed, every active-set step was refined and re-evaluated
//! with mixed-precision solves — 10 refinement solves on the seed's 117k-DOF scene and 3× the
//! time of the plain method; it still solved, so only the count shows it.)

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used)]

use signorini_dual::{DualBackend, DualSettings};
use signorini_qp::examples::laplacian_with_bounds;
use signorini_qp::{checked_status, kkt_residuals, QpBackend, QpStatus, SolveOptions};

/// "…, N refinement solves; …" in the solution message.
fn refinement_solves(message: &str) -> usize {
    let before = message
        .split(" refinement solves")
        .next()
        .unwrap()
        .rsplit(' ')
        .next()
        .unwrap();
    before.parse().unwrap()
}

#[test]
fn a_well_conditioned_dual_needs_at_most_two_refinement_solves() {
    at_most_two_refinement_solves(false);
}

/// The same chain nondimensionalised (what `solve`, and the driver, hand dual-ssn).  Ignored
/// while it took three refinement solves; found taking two (and passing at 2f873a3 already)
/// when the strict gaps of issue 21 were run again.
#[test]
fn a_well_conditioned_dual_needs_at_most_two_refinement_solves_in_its_own_units() {
    at_most_two_refinement_solves(true);
}

fn at_most_two_refinement_solves(own_units: bool) {
    // A 2000-node spring chain (condition number ~1.6e6) with 40 bound rows, most active.
    let problem = laplacian_with_bounds(2000, 40);
    let options = SolveOptions {
        tol: 1e-10,
        ..SolveOptions::default()
    };
    let mut backend = DualBackend::active_set(DualSettings::default());
    // `solve` nondimensionalises first; `solve_in_given_units` takes the example as built (as
    // this test measured it when it was written).
    let solution = if own_units {
        backend.solve(&problem, &options)
    } else {
        backend.solve_in_given_units(&problem, &options)
    }
    .unwrap();
    let residuals = kkt_residuals(&problem, &solution.x, &solution.multipliers);
    assert_eq!(
        checked_status(solution.status, &residuals, options.tol),
        QpStatus::Solved
    );
    let message = solution.message.unwrap();
    // Plain refinement of the settled set: one correction, sometimes a second (the tolerance
    // is met after the first on a problem of this conditioning; two leaves room for round-off).
    assert!(refinement_solves(&message) <= 2, "{message}");
    assert!(
        solution.iterations >= 2,
        "the set must have moved: {message}"
    );
}
