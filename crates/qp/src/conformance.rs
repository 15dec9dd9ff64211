//! The backend-neutral conformance suite: the same small QPs, with answers known by hand, run
//! through any [`QpBackend`] and judged by the one residual check ([`crate::kkt_residuals`],
//! [`crate::checked_status`]).  A backend crate runs it with one line in a test:
//!
//! ```
//! # use signorini_qp::{QpBackend, QpError, QpProblem, QpSolution, QpStatus, SolveOptions};
//! # use signorini_qp::conformance::{failures, Conformance};
//! # struct Nothing;
//! # impl QpBackend for Nothing {
//! #     fn name(&self) -> &'static str { "nothing" }
//! #     fn solve_valid(&mut self, p: &QpProblem, _: &SolveOptions) -> Result<QpSolution, QpError> {
//! #         Ok(QpSolution { x: vec![0.0; p.dofs()], multipliers: vec![0.0; p.rows()],
//! #             status: QpStatus::Solved, iterations: 0,
//! #             solve_time: std::time::Duration::ZERO, message: None })
//! #     }
//! # }
//! // A backend that answers zero for everything fails most of the suite:
//! let found = failures(&mut || Box::new(Nothing), &Conformance::default());
//! assert!(found.len() > 5);
//! // In a backend crate: conformance::assert_conforms(&mut || Box::new(MyBackend::default()), &spec);
//! ```
//!
//! The cases (each named in a failure):
//! * **known optima**: one DOF with an active, an inactive and a negative bound; two rows of
//!   which one is active; no rows at all; a chain of springs against a wall;
//! * **scaling**: the two-row problem with A and f multiplied by 10⁻⁸ and 10⁸ (the answer x is
//!   the same, λ scales);
//! * **degenerate**: the same row twice (x is unique, the split of λ between the copies is not:
//!   only x and the residuals are judged);
//! * **floating**: a body of two DOFs joined by a spring, held by nothing but a wall (A is
//!   singular, its kernel given with the problem; the row removes the rigid motion);
//! * **infeasible**: x ≤ −1 and x ≥ 1 — `primal-infeasible` for a backend that certifies it,
//!   otherwise anything but `solved`;
//! * **unbounded**: the floating body loaded with no wall — `dual-infeasible` for a backend
//!   that certifies it, otherwise anything but `solved`;
//! * **blocks**: Tresca's spring on one box row, slipping and sticking — its optimum from a
//!   backend that [supports](QpBackend::supports) box rows, [`QpError::UnsupportedBlock`] from
//!   any other.

use crate::examples::{
    csc, infeasible, scalar, spring_chain, tresca_spring, two_rows, two_rows_scaled, unconstrained,
    Known,
};
use crate::{checked_status, kkt_residuals, QpBackend, QpError, QpProblem, QpStatus, SolveOptions};

/// What a backend promises, and how tightly it is held to it.
#[derive(Debug, Clone, PartialEq)]
pub struct Conformance {
    /// Tolerance the backend is asked for and its answers are judged by.
    pub tol: f64,
    /// Distance to a known optimum accepted, relative to its largest entry (see
    /// [`Known::mismatch`]).
    pub optimum_tol: f64,
    /// The backend certifies primal infeasibility (`primal-infeasible`); otherwise it need only
    /// not call an infeasible problem `solved`.
    pub certifies_infeasibility: bool,
    /// The backend certifies unboundedness (`dual-infeasible`); otherwise it need only not call
    /// an unbounded problem `solved`.
    pub certifies_unboundedness: bool,
}

impl Default for Conformance {
    /// Tolerance 10⁻⁹ (the default of [`SolveOptions`]); optimum within 10⁻⁷ (the known optima
    /// are exact rationals of well-conditioned systems — condition numbers below 10³ — so an
    /// answer meeting 10⁻⁹ is within 10⁻⁷ of them); both certificates.
    fn default() -> Self {
        Self {
            tol: 1e-9,
            optimum_tol: 1e-7,
            certifies_infeasibility: true,
            certifies_unboundedness: true,
        }
    }
}

/// What a case expects of the answer.
enum Expect {
    /// `solved`, with x and λ the known optimum.
    Optimum(Known),
    /// `solved`, with this x (λ is not unique).
    Primal(QpProblem, Vec<f64>),
    /// Not `solved`; `primal-infeasible` when the backend certifies it.
    Infeasible(QpProblem),
    /// Not `solved`; `dual-infeasible` when the backend certifies it.
    Unbounded(QpProblem),
    /// The known optimum when the backend supports every block kind of the problem, otherwise
    /// the refusal [`QpError::UnsupportedBlock`] (never a panic or an answer).
    Blocks(Known),
}

/// The suite's cases, named.
fn cases() -> Vec<(&'static str, Expect)> {
    vec![
        ("one DOF, active bound", Expect::Optimum(scalar(1.0))),
        ("one DOF, inactive bound", Expect::Optimum(scalar(3.0))),
        ("one DOF, negative bound", Expect::Optimum(scalar(-2.0))),
        ("two rows, one active", Expect::Optimum(two_rows())),
        ("no rows", Expect::Optimum(unconstrained())),
        (
            "spring chain against a wall",
            Expect::Optimum(spring_chain()),
        ),
        (
            "two rows, A and f × 1e-8",
            Expect::Optimum(two_rows_scaled(1e-8)),
        ),
        (
            "two rows, A and f × 1e8",
            Expect::Optimum(two_rows_scaled(1e8)),
        ),
        ("the same row twice", duplicated_row()),
        ("floating body against a wall", Expect::Optimum(floating())),
        ("contradicting rows", Expect::Infeasible(infeasible())),
        (
            "floating body, nothing holds it",
            Expect::Unbounded(unbounded()),
        ),
        ("box row, slip", Expect::Blocks(tresca_spring(3.0))),
        ("box row, stick", Expect::Blocks(tresca_spring(-0.5))),
    ]
}

/// min x² − 4x s.t. x ≤ 1 written twice: x = 1, λ₁ + λ₂ = 2 split any way.
fn duplicated_row() -> Expect {
    let p = QpProblem::try_new(
        csc(1, 1, &[&[2.0]]),
        vec![4.0],
        csc(2, 1, &[&[1.0], &[1.0]]),
        vec![1.0, 1.0],
    );
    match p {
        Ok(p) => Expect::Primal(p, vec![1.0]),
        Err(e) => unreachable_case(e),
    }
}

/// Two DOFs joined by a unit spring, A = [1, −1; −1, 1] (singular: the rigid motion (1, 1),
/// given as the problem's kernel, as the model gives a floating body's rigid modes), pushed by
/// f = (1, 0) against the wall x₁ ≤ ½.  Equilibrium: x₀ − x₁ = 1 and λ = 1, so x = (3/2, 1/2).
fn floating() -> Known {
    let problem = QpProblem::try_new(
        csc(2, 2, &[&[1.0, -1.0], &[-1.0, 1.0]]),
        vec![1.0, 0.0],
        csc(1, 2, &[&[0.0, 1.0]]),
        vec![0.5],
    )
    .and_then(|p| p.with_kernel(vec![vec![1.0, 1.0]]));
    match problem {
        Ok(problem) => Known {
            problem,
            x: vec![1.5, 0.5],
            multipliers: vec![1.0],
        },
        Err(e) => unreachable_case(e),
    }
}

/// The floating body of [`floating`] with its load and no wall: f = (1, 0) has a component
/// fᵀr = 1 along the rigid motion r = (1, 1) that nothing resists, so the objective decreases
/// without bound along r.
fn unbounded() -> QpProblem {
    match QpProblem::try_new(
        csc(2, 2, &[&[1.0, -1.0], &[-1.0, 1.0]]),
        vec![1.0, 0.0],
        sprs::CsMat::zero((0, 2)).to_csc(),
        vec![],
    )
    .and_then(|p| p.with_kernel(vec![vec![1.0, 1.0]]))
    {
        Ok(p) => p,
        Err(e) => unreachable_case(e),
    }
}

/// The suite's own problems are valid by construction.
fn unreachable_case(e: crate::QpError) -> ! {
    panic!("a conformance case is invalid: {e}")
}

/// Runs every case on a fresh backend from `make` and returns one line per failure (empty when
/// the backend conforms).
pub fn failures(make: &mut dyn FnMut() -> Box<dyn QpBackend>, spec: &Conformance) -> Vec<String> {
    let options = SolveOptions {
        tol: spec.tol,
        ..SolveOptions::default()
    };
    let mut found = Vec::new();
    for (name, expect) in cases() {
        let mut backend = make();
        let problem = match &expect {
            Expect::Optimum(k) | Expect::Blocks(k) => &k.problem,
            Expect::Primal(p, _) | Expect::Infeasible(p) | Expect::Unbounded(p) => p,
        };
        let supported = problem
            .block_kinds()
            .into_iter()
            .all(|k| backend.supports(k));
        let refused = matches!(expect, Expect::Blocks(_)) && !supported;
        let solution = match (backend.solve(problem, &options), refused) {
            (Err(QpError::UnsupportedBlock { .. }), true) => continue,
            (Ok(s), true) => {
                found.push(format!(
                    "{}: {name}: {} instead of refusing a block it does not support",
                    backend.name(),
                    s.status
                ));
                continue;
            }
            (Ok(s), false) => s,
            (Err(e), _) => {
                found.push(format!("{}: {name}: error {e}", backend.name()));
                continue;
            }
        };
        let residuals = kkt_residuals(problem, &solution.x, &solution.multipliers);
        let status = checked_status(solution.status, &residuals, spec.tol);
        let why = match &expect {
            Expect::Optimum(known) | Expect::Blocks(known) if status == QpStatus::Solved => known
                .mismatch(&solution.x, &solution.multipliers, spec.optimum_tol)
                .map(|m| format!("solved, but {m}")),
            Expect::Primal(_, x) if status == QpStatus::Solved => {
                let off = crate::examples::max_diff(&solution.x, x);
                (off > spec.optimum_tol).then(|| format!("solved, but x = {:?}", solution.x))
            }
            Expect::Optimum(_) | Expect::Blocks(_) | Expect::Primal(..) => {
                Some(format!("{status} ({residuals:?}), expected solved"))
            }
            Expect::Infeasible(_) => expect_refusal(
                status,
                QpStatus::PrimalInfeasible,
                spec.certifies_infeasibility,
            ),
            Expect::Unbounded(_) => expect_refusal(
                status,
                QpStatus::DualInfeasible,
                spec.certifies_unboundedness,
            ),
        };
        if let Some(why) = why {
            found.push(format!(
                "{}: {name}: {why} (message: {})",
                backend.name(),
                solution.message.as_deref().unwrap_or("none")
            ));
        }
    }
    found
}

/// Why `status` breaks the expectation of a problem without a solution, if it does.
fn expect_refusal(status: QpStatus, certificate: QpStatus, certifies: bool) -> Option<String> {
    if status == QpStatus::Solved || (certifies && status != certificate) {
        Some(format!("{status}, expected {certificate}"))
    } else {
        None
    }
}

/// Panics listing every failure of [`failures`].
pub fn assert_conforms(make: &mut dyn FnMut() -> Box<dyn QpBackend>, spec: &Conformance) {
    let found = failures(make, spec);
    assert!(
        found.is_empty(),
        "{} conformance failure(s):\n{}",
        found.len(),
        found.join("\n")
    );
}
