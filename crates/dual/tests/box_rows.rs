//! dual-pgs on box rows (Tresca's tangential multipliers, |λ| ≤ s): a block pressed and
//! dragged on a rigid base, answered by hand, and a coupled chain checked against every
//! stick/slip/contact pattern solved directly; dual-uzawa and dual-ssn the same.  Both again
//! with a zero bound (Coulomb's tangential rows where the normal force vanishes): the row's
//! multiplier is 0 and its slip free.

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used)]

use signorini_dual::{DualBackend, DualSettings};
use signorini_qp::examples::qp_from_triplets;
use signorini_qp::{
    checked_status, kkt_residuals, ConstraintBlock, QpBackend, QpProblem, QpStatus, SolveOptions,
};

const TOL: f64 = 1e-10;

/// Each projected method's answer, solved to [`TOL`].
fn projected(problem: &QpProblem) -> Vec<(Vec<f64>, Vec<f64>)> {
    let options = SolveOptions {
        tol: TOL,
        ..SolveOptions::default()
    };
    [
        DualBackend::pgs(DualSettings::default()),
        DualBackend::uzawa(DualSettings::default()),
        DualBackend::active_set(DualSettings::default()),
    ]
    .into_iter()
    .map(|mut backend| {
        let sol = backend.solve(problem, &options).unwrap();
        let r = kkt_residuals(problem, &sol.x, &sol.multipliers);
        assert_eq!(
            checked_status(sol.status, &r, TOL),
            QpStatus::Solved,
            "{}: {r:?} {:?}",
            backend.name(),
            sol.message
        );
        (sol.x, sol.multipliers)
    })
    .collect()
}

/// DOFs (u_n, u_t) of a block 0.1 above a rigid base: normal stiffness 4, tangential 2; pressed
/// by P = 3 (row −u_n ≤ 0.1), dragged by Q with the slip bound `s` (box row u_t).  (The gap
/// makes the block move: a row whose bodies do not move at all has no length to measure a
/// penetration against — docs/scene.md, the residuals.)
fn pressed_block(q: f64, s: f64) -> QpProblem {
    qp_from_triplets(
        2,
        &[(0, 0, 4.0), (1, 1, 2.0)],
        vec![-3.0, q],
        2,
        &[(0, 0, -1.0), (1, 1, 1.0)],
        vec![0.1, 0.0],
    )
    .unwrap()
    .with_blocks(vec![
        ConstraintBlock::NonNegative { rows: 1 },
        ConstraintBlock::Box { bounds: vec![s] },
    ])
    .unwrap()
}

/// By hand: the block comes down to u_n = −0.1, the normal row carries P − 4·0.1 = 2.6; below
/// the bound the block sticks
/// (u_t = 0, λ_t = Q), above it slides (u_t = (Q − s·sign Q)/2, λ_t = s·sign Q).  Tolerance:
/// the KKT tolerance 1e-10 on data of size one, with a factor 10 for the dual's round-off.
/// With s = 0 the block slides under any Q: u_t = Q/2, λ_t = 0 (dual-ssn took a zero-bound
/// row for a one-sided one, u_t ≤ 0: stuck under Q > 0 with λ_t = Q, |λ_t| beyond its bound —
/// the Cattaneo path's `inaccurate` Coulomb solves).
#[test]
fn a_pressed_block_sticks_below_the_bound_and_slides_above_it() {
    for (q, s, ut, lt) in [
        (0.4, 1.0, 0.0, 0.4),
        (-0.9, 1.0, 0.0, -0.9),
        (2.5, 1.0, 0.75, 1.0),
        (-4.0, 1.0, -1.5, -1.0),
        (0.4, 0.0, 0.2, 0.0),
        (-0.9, 0.0, -0.45, 0.0),
    ] {
        for (x, lambda) in projected(&pressed_block(q, s)) {
            let want = [(x[0], -0.1), (x[1], ut), (lambda[0], 2.6), (lambda[1], lt)];
            for (got, expected) in want {
                assert!(
                    (got - expected).abs() < 1e-9,
                    "Q = {q}, s = {s}: {got} vs {expected}"
                );
            }
        }
    }
}

/// Solves the 3×3 system M y = r by Gaussian elimination with partial pivoting.
fn solve3(mut m: [[f64; 3]; 3], mut r: [f64; 3]) -> [f64; 3] {
    for c in 0..3 {
        let p = (c..3)
            .max_by(|&i, &j| m[i][c].abs().total_cmp(&m[j][c].abs()))
            .unwrap();
        m.swap(c, p);
        r.swap(c, p);
        for i in c + 1..3 {
            let f = m[i][c] / m[c][c];
            let pivot = m[c];
            for (mij, mcj) in m[i].iter_mut().zip(pivot).skip(c) {
                *mij -= f * mcj;
            }
            r[i] -= f * r[c];
        }
    }
    let mut y = [0.0; 3];
    for c in (0..3).rev() {
        let s: f64 = (c + 1..3).map(|j| m[c][j] * y[j]).sum();
        y[c] = (r[c] - s) / m[c][c];
    }
    y
}

/// A chain A = tridiag(−1, 2, −1) (3 DOFs) with load (1.5, −2, 0.8): a contact row
/// x₁ ≥ −0.3 (−x₁ ≤ 0.3) and box rows on x₀ (bound 0.5) and x₂ (bound 2).  The reference is
/// found without any iteration: for each of the 18 patterns (contact row active or not, each
/// box row stuck at x = 0 or slipping with λ = ±s) the linear system is solved and the one
/// pattern that satisfies every KKT condition is kept.
#[test]
fn a_coupled_chain_matches_the_pattern_that_satisfies_every_condition() {
    coupled_chain([0.5, 2.0]);
}

/// The same chain with x₀'s bound 0: the load 1.5 drags x₀ forward, free of friction (λ₀ᵗ =
/// 0), next to a box row that sticks or slips at its own bound.
#[test]
fn a_coupled_chain_with_a_zero_bound_matches_the_pattern_that_satisfies_every_condition() {
    coupled_chain([0.0, 2.0]);
}

/// The chain above with box `bounds` on (x₀, x₂), against the enumerated patterns.
fn coupled_chain(bounds: [f64; 2]) {
    let a = [[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 2.0]];
    let f = [1.5, -2.0, 0.8];
    let floor = -0.3;
    let problem = qp_from_triplets(
        3,
        &[
            (0, 0, 2.0),
            (0, 1, -1.0),
            (1, 0, -1.0),
            (1, 1, 2.0),
            (1, 2, -1.0),
            (2, 1, -1.0),
            (2, 2, 2.0),
        ],
        f.to_vec(),
        3,
        &[(0, 1, -1.0), (1, 0, 1.0), (2, 2, 1.0)],
        vec![-floor, 0.0, 0.0],
    )
    .unwrap()
    .with_blocks(vec![
        ConstraintBlock::NonNegative { rows: 1 },
        ConstraintBlock::Box {
            bounds: bounds.to_vec(),
        },
    ])
    .unwrap();
    let mut found = Vec::new();
    // States: contact active?; box rows: 0 = stuck, 1 = slip +, 2 = slip −.
    for contact in [false, true] {
        for s0 in 0..3 {
            for s2 in 0..3 {
                // Unknowns: the DOFs fixed by the pattern are replaced by their multipliers.
                // Stationarity: A x − f + Bᵀλ = 0 with Bᵀλ = (λ₀ᵗ, −λₙ, λ₂ᵗ).
                let mut m = a;
                let mut r = f;
                let mut lam = [0.0; 3]; // (λₙ, λ₀ᵗ, λ₂ᵗ) when known
                let mut x_fixed = [None; 3];
                for (row, state, dof) in [(1usize, s0, 0usize), (2, s2, 2)] {
                    let s = bounds[row - 1];
                    match state {
                        0 => x_fixed[dof] = Some(0.0),
                        1 => lam[row] = s,
                        _ => lam[row] = -s,
                    }
                }
                if contact {
                    x_fixed[1] = Some(floor);
                }
                // Known multipliers move to the right-hand side.
                r[0] -= lam[1];
                r[2] -= lam[2];
                // A fixed DOF's column becomes its multiplier's column.
                for (dof, fixed) in x_fixed.iter().enumerate() {
                    if let Some(v) = fixed {
                        for i in 0..3 {
                            r[i] -= a[i][dof] * v;
                            m[i][dof] = 0.0;
                        }
                        // Its multiplier enters equation `dof` with sign +1 (box) or −1 (contact).
                        m[dof][dof] = if dof == 1 { -1.0 } else { 1.0 };
                    }
                }
                let y = solve3(m, r);
                let x: Vec<f64> = (0..3).map(|d| x_fixed[d].unwrap_or(y[d])).collect();
                let ln = if contact { y[1] } else { 0.0 };
                let l0 = if s0 == 0 { y[0] } else { lam[1] };
                let l2 = if s2 == 0 { y[2] } else { lam[2] };
                let eps = 1e-12;
                let contact_ok = if contact {
                    ln >= -eps
                } else {
                    x[1] >= floor - eps
                };
                let box_ok = |state: usize, xv: f64, l: f64, s: f64| match state {
                    0 => l.abs() <= s + eps,
                    1 => xv >= -eps,
                    _ => xv <= eps,
                };
                if contact_ok && box_ok(s0, x[0], l0, bounds[0]) && box_ok(s2, x[2], l2, bounds[1])
                {
                    found.push((x, vec![ln, l0, l2]));
                }
            }
        }
    }
    assert_eq!(
        found.len(),
        1,
        "one pattern satisfies every condition: {found:?}"
    );
    let (x_ref, l_ref) = &found[0];
    for (x, lambda) in projected(&problem) {
        // 1e-8: the KKT tolerance 1e-10 times the chain's condition number (~6).
        for (got, want) in x.iter().zip(x_ref).chain(lambda.iter().zip(l_ref)) {
            assert!(
                (got - want).abs() < 1e-8,
                "{x:?} {lambda:?} vs {x_ref:?} {l_ref:?}"
            );
        }
    }
}

/// The pressed block's box row written one-sided ([`signorini_qp::AuxiliaryForm`]: unknowns
/// (u_n, u_t, t), rows u_t − t ≤ 0 and −u_t − t ≤ 0): t has no stiffness and no kernel vector
/// is declared, so A is singular and A⁻¹, which every dual method needs, does not exist.  Each
/// dual backend refuses it at once with a reason that names the unknown without stiffness —
/// before, each factored A, met the zero pivot and ended `numerical-error` with a message
/// about rigid-body modes.  The problem itself is sound: the same answer, solved on the box
/// rows, is checked by `a_pressed_block_sticks_below_the_bound_and_slides_above_it`.
#[test]
fn an_unknown_without_stiffness_and_no_kernel_is_refused_at_once_with_why() {
    let form = signorini_qp::AuxiliaryForm::of(&pressed_block(2.5, 1.0)).unwrap();
    assert_eq!(form.problem.dofs(), 3);
    for mut backend in [
        DualBackend::pgs(DualSettings::default()),
        DualBackend::uzawa(DualSettings::default()),
        DualBackend::active_set(DualSettings::default()),
    ] {
        let answer = backend.solve(&form.problem, &SolveOptions::default());
        let Err(signorini_qp::QpError::Unavailable { reason, .. }) = &answer else {
            panic!("{}: {answer:?}", backend.name());
        };
        assert!(
            reason.contains("1 unknown(s) (the first: 2) have no stiffness")
                && reason.contains("no declared kernel vector"),
            "{}: {reason}",
            backend.name()
        );
    }
    // With t's kernel vector e_t declared the refusal does not apply (A⁺ exists on (u_n, u_t)).
    let declared = form
        .problem
        .clone()
        .with_kernel(vec![vec![0.0, 0.0, 1.0]])
        .unwrap();
    let mut ssn = DualBackend::active_set(DualSettings::default());
    assert!(ssn.solve(&declared, &SolveOptions::default()).is_ok());
}
