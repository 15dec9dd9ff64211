//! clarabel on QPs with hand-known optima beyond the conformance suite (tests/conformance.rs); every answer is checked with the core's residuals.

mod problems;

use std::time::Duration;

use problems::{assert_close, Known};
use signorini_clarabel::{ClarabelBackend, ClarabelSettings, DirectSolver};
use signorini_qp::{
    checked_status, kkt_residuals, QpBackend, QpError, QpProblem, QpSolution, QpStatus,
    SolveOptions,
};

const TOL: f64 = 1e-9;

fn solve(problem: &QpProblem, options: &SolveOptions) -> QpSolution {
    ClarabelBackend::new(ClarabelSettings::default())
        .solve(problem, options)
        .expect("clarabel runs")
}

/// Solves at `TOL` and checks the status, the core's verdict and the known optimum.
fn check(known: &Known) -> QpSolution {
    let options = SolveOptions {
        tol: TOL,
        ..SolveOptions::default()
    };
    let solution = solve(&known.problem, &options);
    let residuals = kkt_residuals(&known.problem, &solution.x, &solution.multipliers);
    assert_eq!(
        checked_status(solution.status, &residuals, TOL),
        QpStatus::Solved,
        "{residuals:?} {:?}",
        solution.message
    );
    assert!(solution.multipliers.iter().all(|&l| l >= 0.0));
    assert_close(&solution, known, 1e-7);
    solution
}

#[test]
fn scalar_with_active_bound() {
    let solution = check(&problems::scalar(1.0));
    assert_eq!(solution.status, QpStatus::Solved);
    assert!(solution.iterations > 0);
}

#[test]
fn badly_scaled_equivalent_gives_the_same_x() {
    let plain = check(&problems::two_rows());
    let scaled = check(&problems::two_rows_scaled(1e11));
    assert!(problems::max_diff(&plain.x, &scaled.x) < 1e-8);
}

#[test]
fn laplacian_with_many_bounds_is_solved_tightly() {
    let problem = problems::laplacian_with_bounds(2000, 50);
    let solution = solve(&problem, &SolveOptions::default());
    let residuals = kkt_residuals(&problem, &solution.x, &solution.multipliers);
    assert_eq!(
        checked_status(solution.status, &residuals, TOL),
        QpStatus::Solved,
        "{residuals:?} {:?}",
        solution.message
    );
}

#[test]
fn infeasible_problem_is_reported_not_raised() {
    let solution = solve(&problems::infeasible(), &SolveOptions::default());
    assert_eq!(solution.status, QpStatus::PrimalInfeasible);
    assert!(solution.x.iter().all(|v| v.is_finite()));
}

#[test]
fn iteration_and_time_limits_are_respected() {
    let problem = problems::laplacian_with_bounds(200, 20);
    let one = SolveOptions {
        max_iter: Some(1),
        ..SolveOptions::default()
    };
    let solution = solve(&problem, &one);
    assert_eq!(solution.status, QpStatus::MaxIterations);
    assert!(solution.iterations <= 1);
    let instant = SolveOptions {
        time_limit: Some(Duration::from_nanos(1)),
        ..SolveOptions::default()
    };
    assert_eq!(solve(&problem, &instant).status, QpStatus::TimeLimit);
}

#[test]
fn bad_dimensions_are_an_error() {
    let mut problem = problems::two_rows().problem;
    problem.gap.push(1.0);
    let result = ClarabelBackend::default().solve(&problem, &SolveOptions::default());
    assert!(matches!(result, Err(QpError::Dimensions(_))));
}

#[test]
fn qdldl_and_no_equilibration_agree() {
    let known = problems::spring_chain();
    let mut backend = ClarabelBackend::new(ClarabelSettings {
        direct_solver: DirectSolver::Qdldl,
        equilibrate: false,
        ..ClarabelSettings::default()
    });
    let solution = backend
        .solve(&known.problem, &SolveOptions::default())
        .expect("runs");
    assert_close(&solution, &known, 1e-7);
}

#[test]
fn faer_without_the_feature_is_unavailable() {
    let mut backend = ClarabelBackend::new(ClarabelSettings {
        direct_solver: DirectSolver::Faer,
        ..ClarabelSettings::default()
    });
    let result = backend.solve(&problems::two_rows().problem, &SolveOptions::default());
    if cfg!(feature = "faer") {
        assert!(result.is_ok());
    } else {
        assert!(matches!(result, Err(QpError::Unavailable { .. })));
    }
}
