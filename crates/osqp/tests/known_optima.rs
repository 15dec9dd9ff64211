//! OSQP on QPs with hand-known optima beyond the conformance suite (tests/conformance.rs); every answer is checked with the core's residuals.

mod problems;

use std::time::Duration;

use problems::{assert_close, Known};
use signorini_osqp::{OsqpBackend, OsqpSettings};
use signorini_qp::{
    checked_status, kkt_residuals, QpBackend, QpError, QpProblem, QpSolution, QpStatus,
    SolveOptions,
};

/// Requested tolerance of the tight tests (polish on, the default).
const TOL: f64 = 1e-9;

fn solve_with(settings: OsqpSettings, problem: &QpProblem, options: &SolveOptions) -> QpSolution {
    OsqpBackend::new(settings)
        .solve(problem, options)
        .expect("OSQP runs")
}

fn solve(problem: &QpProblem, options: &SolveOptions) -> QpSolution {
    solve_with(OsqpSettings::default(), problem, options)
}

fn tight() -> SolveOptions {
    SolveOptions {
        tol: TOL,
        ..SolveOptions::default()
    }
}

/// Solves at `TOL` and checks the core's verdict and the known optimum.
fn check(known: &Known) -> QpSolution {
    let solution = solve(&known.problem, &tight());
    let residuals = kkt_residuals(&known.problem, &solution.x, &solution.multipliers);
    assert_eq!(
        checked_status(solution.status, &residuals, TOL),
        QpStatus::Solved,
        "{residuals:?} {:?}",
        solution.message
    );
    assert_close(&solution, known, 1e-7);
    solution
}

#[test]
fn scalar_with_active_bound() {
    let solution = check(&problems::scalar(1.0));
    assert_eq!(solution.status, QpStatus::Solved);
    assert!(solution.multipliers[0] > 0.0);
}

#[test]
fn badly_scaled_equivalent_gives_the_same_x() {
    let plain = check(&problems::two_rows());
    let scaled = check(&problems::two_rows_scaled(1e11));
    assert!(problems::max_diff(&plain.x, &scaled.x) < 1e-8);
}

#[test]
fn infeasible_problem_is_reported_not_raised() {
    let solution = solve(&problems::infeasible(), &SolveOptions::default());
    assert_eq!(solution.status, QpStatus::PrimalInfeasible);
    assert!(solution.x.iter().all(|v| v.is_finite()));
}

#[test]
fn loose_settings_are_not_relabelled_solved() {
    let problem = problems::laplacian_with_bounds(2000, 50);
    let loose = OsqpSettings {
        eps_abs: Some(1e-3),
        eps_rel: 1e-3,
        polish: false,
        ..OsqpSettings::default()
    };
    let options = SolveOptions {
        tol: 1e-10,
        ..SolveOptions::default()
    };
    let solution = solve_with(loose, &problem, &options);
    let residuals = kkt_residuals(&problem, &solution.x, &solution.multipliers);
    // OSQP itself claims success at its loose tolerance; the core's check must not.
    assert_eq!(solution.status, QpStatus::Solved, "{:?}", solution.message);
    assert_eq!(
        checked_status(solution.status, &residuals, 1e-10),
        QpStatus::Inaccurate,
        "{residuals:?} {:?}",
        solution.message
    );
}

#[test]
fn iteration_and_time_limits_are_respected() {
    let problem = problems::laplacian_with_bounds(200, 20);
    let few = SolveOptions {
        max_iter: Some(25),
        ..tight()
    };
    let solution = solve(&problem, &few);
    assert_eq!(solution.status, QpStatus::MaxIterations);
    assert!(solution.iterations <= 25);
    let instant = SolveOptions {
        time_limit: Some(Duration::from_nanos(1)),
        ..tight()
    };
    assert_eq!(solve(&problem, &instant).status, QpStatus::TimeLimit);
}

#[test]
fn warm_start_reuses_the_previous_answer() {
    let known = problems::spring_chain();
    let mut backend = OsqpBackend::new(OsqpSettings {
        warm_start: true,
        ..OsqpSettings::default()
    });
    let cold = backend.solve(&known.problem, &tight()).expect("runs");
    let warm = backend.solve(&known.problem, &tight()).expect("runs");
    assert_close(&warm, &known, 1e-7);
    assert!(
        warm.iterations <= cold.iterations,
        "{} > {}",
        warm.iterations,
        cold.iterations
    );
}

#[test]
fn bad_dimensions_and_settings_are_errors() {
    let mut problem = problems::two_rows().problem;
    problem.gap.push(1.0);
    let result = OsqpBackend::default().solve(&problem, &SolveOptions::default());
    assert!(matches!(result, Err(QpError::Dimensions(_))));
    let bad = OsqpSettings {
        rho: -1.0,
        ..OsqpSettings::default()
    };
    let result = OsqpBackend::new(bad).solve(&problems::two_rows().problem, &tight());
    assert!(matches!(result, Err(QpError::Backend { .. })));
}

#[test]
fn continuation_reaches_tight_tolerance_in_few_iterations() {
    let problem = problems::laplacian_with_bounds(2000, 50);
    let solution = solve(&problem, &tight());
    let residuals = kkt_residuals(&problem, &solution.x, &solution.multipliers);
    assert_eq!(
        checked_status(solution.status, &residuals, TOL),
        QpStatus::Solved,
        "{residuals:?} {:?}",
        solution.message
    );
    // Plain ADMM to ε_abs = 1e-9 does not converge in 50 000 iterations on this problem.
    assert!(solution.iterations < 2000, "{}", solution.iterations);
}
