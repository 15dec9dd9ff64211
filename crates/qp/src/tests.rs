//! Unit tests of the QP contract.

use super::*;
use sprs::TriMat;
use std::time::Duration;

fn tiny() -> QpProblem {
    // min ½(x0² + x1²) − x0 − x1  s.t.  x0 + x1 ≤ 1   →  x = (½, ½), λ = ½
    let mut a = TriMat::new((2, 2));
    a.add_triplet(0, 0, 1.0);
    a.add_triplet(1, 1, 1.0);
    let mut b = TriMat::new((1, 2));
    b.add_triplet(0, 0, 1.0);
    b.add_triplet(0, 1, 1.0);
    QpProblem::try_new(a.to_csc(), vec![1.0, 1.0], b.to_csc(), vec![1.0]).unwrap()
}

#[test]
fn all_zero_problem_has_finite_zero_residuals() {
    let mut a = TriMat::new((1, 1));
    a.add_triplet(0, 0, 1.0);
    let b = TriMat::new((0, 1));
    let p = QpProblem::try_new(a.to_csc(), vec![0.0], b.to_csc(), vec![]).unwrap();
    let r = kkt_residuals(&p, &[0.0], &[]);
    assert_eq!(r, KktResiduals::default());
}

#[test]
fn exact_optimum_has_zero_residuals() {
    let r = kkt_residuals(&tiny(), &[0.5, 0.5], &[0.5]);
    assert_eq!(r.worst(), 0.0);
}

#[test]
fn each_violation_is_seen() {
    // tiny(): k̄ = 1, ‖f‖₁ = 2, ‖f‖∞ = 1, g = [1] → X = 2, F = 1 (see ResidualScales).
    let p = tiny();
    let s = ResidualScales::of(&p);
    assert_eq!((s.force, s.length), (1.0, 2.0));
    // Bx − g = 0.4 → 0.4 / X̃ with X̃ = min(X, M) = 0.7, the motion of the row's DOFs.
    let pen = kkt_residuals(&p, &[0.7, 0.7], &[0.3]);
    assert!((pen.max_penetration - 0.4).abs() < 1e-15);
    assert!((pen.relative_penetration - 0.4 / 0.7).abs() < 1e-15);
    // Ax − f + Bᵀλ = (−0.5, −0.5) → 0.5 / F.
    assert!((kkt_residuals(&p, &[0.5, 0.5], &[0.0]).stationarity - 0.5).abs() < 1e-15);
    // λ s = 0.6 · 0.2 → 0.12 / (F X).
    let comp = kkt_residuals(&p, &[0.4, 0.4], &[0.6]).complementarity;
    assert!((comp - 0.06).abs() < 1e-15, "{comp}");
    let neg = kkt_residuals(&p, &[1.0, 1.0], &[-0.5]);
    assert!((neg.min_multiplier + 0.5).abs() < 1e-15);
    let nan = kkt_residuals(&p, &[f64::NAN, 0.5], &[0.5]);
    assert_eq!(
        checked_status(QpStatus::Solved, &nan, 1e-6),
        QpStatus::NumericalError
    );
    // An infeasibility certificate is kept even though its x is no solution.
    assert_eq!(
        checked_status(QpStatus::PrimalInfeasible, &nan, 1e-6),
        QpStatus::PrimalInfeasible
    );
}

#[test]
fn solved_is_downgraded_when_residuals_miss() {
    let p = tiny();
    let r = kkt_residuals(&p, &[0.5, 0.5 + 1e-6], &[0.5]);
    assert_eq!(
        checked_status(QpStatus::Solved, &r, 1e-9),
        QpStatus::Inaccurate
    );
    assert_eq!(checked_status(QpStatus::Solved, &r, 1e-3), QpStatus::Solved);
    assert_eq!(
        checked_status(QpStatus::MaxIterations, &r, 1e-3),
        QpStatus::MaxIterations
    );
}

#[test]
fn scaling_round_trips_and_preserves_residuals() {
    let mut p = tiny();
    p.stiffness = p.stiffness.map(|v| v * 2e11);
    p.load = p.load.iter().map(|v| v * 2e11 * 1e-5).collect();
    p.gap = p.gap.iter().map(|v| v * 1e-5).collect();
    let s = QpScaling::of(&p);
    let scaled = s.scale(&p);
    assert!((scaled.load[0] - 1.0).abs() < 1e-12);
    let sol = QpSolution {
        x: vec![0.5, 0.5],
        multipliers: vec![0.5],
        status: QpStatus::Solved,
        iterations: 0,
        solve_time: Duration::ZERO,
        message: None,
    };
    let back = s.unscale(sol);
    let r = kkt_residuals(&p, &back.x, &back.multipliers);
    assert!(r.meet(1e-14), "{r:?}");
    assert!((back.x[0] - 0.5e-5).abs() < 1e-18);
}

#[test]
fn rejects_bad_dimensions_and_nan() {
    let p = tiny();
    let err = QpProblem::try_new(
        p.stiffness.clone(),
        vec![1.0],
        p.constraints.clone(),
        vec![1.0],
    );
    assert!(matches!(err, Err(QpError::Dimensions(_))));
    let err = QpProblem::try_new(
        p.stiffness.clone(),
        vec![1.0, f64::NAN],
        p.constraints.clone(),
        vec![1.0],
    );
    assert!(matches!(err, Err(QpError::NotFinite("f"))));
}

#[test]
fn a_large_motion_elsewhere_does_not_loosen_a_row() {
    // Three DOFs, the third free of the constraint: the same penetration of 0.1 must give the
    // same relative penetration however large the unconstrained component of a wrong x is.
    // (When X was ‖x‖∞, x₂ = 1e9 shrank it to 1e-10 and a tolerance of 1e-9 was met.)  The
    // answer only tightens a row's length, through the motion of the row's own body:
    // X̃ = min(X = 2, |x₀| = 1.1).
    let mut a = TriMat::new((3, 3));
    for j in 0..3 {
        a.add_triplet(j, j, 1.0);
    }
    let mut b = TriMat::new((1, 3));
    b.add_triplet(0, 0, 1.0);
    let p = QpProblem::try_new(a.to_csc(), vec![2.0, 0.0, 0.0], b.to_csc(), vec![1.0]).unwrap();
    let small = kkt_residuals(&p, &[1.1, 0.0, 0.0], &[0.9]);
    let huge = kkt_residuals(&p, &[1.1, 0.0, 1e9], &[0.9]);
    assert_eq!(small.relative_penetration, huge.relative_penetration);
    assert!((small.relative_penetration - 0.1 / 1.1).abs() < 1e-15);
    assert!(!huge.meet(1e-9));
}

#[test]
fn overlap_sets_the_scales_of_an_unloaded_problem() {
    // No load, an initial overlap of 0.5 on a spring of stiffness 4: X = 0.5, F = 2.
    let mut a = TriMat::new((1, 1));
    a.add_triplet(0, 0, 4.0);
    let mut b = TriMat::new((1, 1));
    b.add_triplet(0, 0, 1.0);
    let p = QpProblem::try_new(a.to_csc(), vec![0.0], b.to_csc(), vec![-0.5]).unwrap();
    let s = ResidualScales::of(&p);
    assert_eq!((s.force, s.length), (2.0, 0.5));
    // The optimum x = −0.5, λ = 2 meets any tolerance; x = 0 penetrates by the whole overlap.
    assert!(kkt_residuals(&p, &[-0.5], &[2.0]).meet(1e-15));
    assert!((kkt_residuals(&p, &[0.0], &[0.0]).relative_penetration - 1.0).abs() < 1e-15);
}

#[test]
fn a_nan_residual_is_never_met() {
    // f64::max drops NaN: worst() used to return the largest of the other three.
    let r = KktResiduals {
        stationarity: f64::NAN,
        ..KktResiduals::default()
    };
    assert_eq!(r.worst(), f64::INFINITY);
    assert!(!r.meet(1.0));
    assert_eq!(
        checked_status(QpStatus::Solved, &r, 1.0),
        QpStatus::NumericalError
    );
}

#[test]
fn an_overlap_bounds_the_scaled_gaps() {
    // A load of 1e-40 beside an overlap of 1: scaling by the load alone gave ĝ = −1e40.
    let mut a = TriMat::new((1, 1));
    a.add_triplet(0, 0, 1.0);
    let mut b = TriMat::new((1, 1));
    b.add_triplet(0, 0, 1.0);
    let p = QpProblem::try_new(a.to_csc(), vec![1e-40], b.to_csc(), vec![-1.0]).unwrap();
    let s = QpScaling::of(&p);
    assert_eq!(s.displacement, 1.0);
    assert_eq!(s.scale(&p).gap, vec![-1.0]);
}

#[test]
fn a_soft_dof_elsewhere_does_not_loosen_a_stiff_row() {
    // DOF 0 (stiffness 1) carries the load and the constraint; DOF 1 is 1e-200 stiff and in no
    // row. The global harmonic mean k̄ ≈ 2e-200 makes X ≈ 5e199, but row 0 touches only DOF 0:
    // X₀ = ‖f‖₁ / 1 = 1, so a penetration of 1e-3 is seen as 1e-3 (found by the fuzz harness:
    // a 1e-200 body under a stiff pair let a slave node sink 6e-5 and still be `solved`).
    let mut a = TriMat::new((2, 2));
    a.add_triplet(0, 0, 1.0);
    a.add_triplet(1, 1, 1e-200);
    let mut b = TriMat::new((1, 2));
    b.add_triplet(0, 0, 1.0);
    let p = QpProblem::try_new(a.to_csc(), vec![1.0, 0.0], b.to_csc(), vec![0.5]).unwrap();
    let s = ResidualScales::of(&p);
    assert!(s.length > 1e199);
    assert_eq!(s.rows, vec![1.0]);
    // The answer tightens it further to the row's own motion 0.501.
    let r = kkt_residuals(&p, &[0.501, 0.0], &[0.499]);
    assert!(
        (r.relative_penetration - 1e-3 / 0.501).abs() < 1e-12,
        "{r:?}"
    );
}

#[test]
fn a_non_finite_answer_becomes_numerical_error_with_zeros() {
    let answer = |x: f64| QpSolution {
        x: vec![1.0, x],
        multipliers: vec![2.0],
        status: QpStatus::Solved,
        iterations: 3,
        solve_time: Duration::ZERO,
        message: Some("done".into()),
    };
    let kept = answer(4.0).finite_or_numerical_error();
    assert_eq!(kept.status, QpStatus::Solved);
    assert_eq!(kept.x, vec![1.0, 4.0]);
    let zeroed = answer(f64::NAN).finite_or_numerical_error();
    assert_eq!(zeroed.status, QpStatus::NumericalError);
    assert_eq!(zeroed.x, vec![0.0, 0.0]);
    assert_eq!(zeroed.multipliers, vec![0.0]);
    assert_eq!(zeroed.iterations, 3);
    assert_eq!(zeroed.message.as_deref(), Some("non-finite answer: done"));
}

/// A QP of uncoupled 1-D springs: diagonal A, loads f, and rows given as (DOF, coefficient)
/// lists with their gaps.
fn springs(diag: &[f64], load: &[f64], rows: &[(&[(usize, f64)], f64)]) -> QpProblem {
    let n = diag.len();
    let mut a = TriMat::new((n, n));
    for (j, d) in diag.iter().enumerate() {
        a.add_triplet(j, j, *d);
    }
    let mut b = TriMat::new((rows.len(), n));
    for (i, (entries, _)) in rows.iter().enumerate() {
        for (j, v) in entries.iter() {
            b.add_triplet(i, *j, *v);
        }
    }
    let gap = rows.iter().map(|(_, g)| *g).collect();
    QpProblem::try_new(a.to_csc(), load.to_vec(), b.to_csc(), gap).unwrap()
}

#[test]
fn a_load_that_cannot_reach_a_row_does_not_loosen_it() {
    // DOF 0 (stiffness 1, load 1) under the row x₀ ≤ 0.5: the optimum is x₀ = 0.5, λ = 0.5.
    // DOF 1 is another body in no pair, pulled by 1e10.  A penetration of 1e-3 (0.2 % of the
    // row's own motion) used to be measured against ‖f‖₁ / k₀ ≈ 1e10 (relative 1e-13, `solved`
    // at 1e-9, as the dual-pgs case of issue 18); DOF 1 is not in row 0's component, so
    // X₀ = W = |f₀| / A₀₀ = 1 and the penetration is 1e-3 of it.
    let p = springs(&[1.0, 1.0], &[1.0, 1e10], &[(&[(0, 1.0)], 0.5)]);
    let s = ResidualScales::of(&p);
    assert_eq!(s.rows, vec![1.0]);
    assert_eq!(s.dof_forces, vec![1.0, 1e10]);
    let exact = kkt_residuals(&p, &[0.5, 1e10], &[0.5]);
    assert!(exact.meet(1e-15), "{exact:?}");
    // The wrong answer keeps equilibrium on DOF 0 (λ = 1 − x₀) and penetrates by 1e-3 (of its
    // own motion 0.501: the answer tightens X₀ = 1 to it).
    let wrong = kkt_residuals(&p, &[0.501, 1e10], &[0.499]);
    assert!(
        (wrong.relative_penetration - 1e-3 / 0.501).abs() < 1e-12,
        "{wrong:?}"
    );
    assert!(!wrong.meet(1e-9));
    // Equilibrium off by 1e-3 on DOF 0 is 1e-3 of DOF 0's own force scale, not 1e-13.
    let unbalanced = kkt_residuals(&p, &[0.5, 1e10], &[0.499]);
    assert!(
        (unbalanced.stationarity - 1e-3).abs() < 1e-12,
        "{unbalanced:?}"
    );
}

#[test]
fn an_unloaded_soft_body_cannot_drift_into_its_partner() {
    // The default-backend case of issue 18 in one dimension: body b1 (DOF 1, stiffness 1) is
    // pushed by 1 towards b0 (DOF 0, stiffness 1e-12, unloaded, held only by contact) across a
    // gap of 0.1: row x₁ − x₀ ≤ 0.1.  A wrong answer lets b1 end 0.045 inside b0 while each DOF
    // is in equilibrium with λ = 1e-12 x₀.  Against ‖f‖₁ / k₀ (the row's harmonic stiffness
    // 2e-12) the penetration was 9e-14 of the scale — `solved` at 1e-9; the load that can act on
    // the row moves b1 by W = 1 (b0 carries none), so the penetration is 0.045 of the scale.
    let p = springs(&[1e-12, 1.0], &[0.0, 1.0], &[(&[(0, -1.0), (1, 1.0)], 0.1)]);
    let x1 = 1.0 - 1e-12;
    let x0 = x1 - 0.1 - 0.045;
    let lambda = 1e-12 * x0;
    let wrong = kkt_residuals(&p, &[x0, 1.0 - lambda], &[lambda]);
    assert!(wrong.stationarity < 1e-15, "{wrong:?}");
    assert!(
        (wrong.relative_penetration - 0.045).abs() < 1e-9,
        "{wrong:?}"
    );
    assert!(!wrong.meet(1e-9));
}

#[test]
fn lifting_forces_count_by_the_displacement_they_prescribe() {
    // A 1e30-stiff DOF whose load is the lifting of a prescribed displacement of 1e-3
    // (f₀ = A₀₀ · 1e-3), touching a soft unloaded DOF: row x₀ − x₁ ≤ 0.  The row's harmonic
    // stiffness is ≈ 2, so ‖f‖₁ / kᵢ ≈ 5e26 hid a penetration of 1 % of the motion (the first
    // fuzz known gap); W = f₀ / A₀₀ = 1e-3 is the motion itself.
    let p = springs(&[1e30, 1.0], &[1e27, 0.0], &[(&[(0, 1.0), (1, -1.0)], 0.0)]);
    let s = ResidualScales::of(&p);
    assert!((s.rows[0] - 1e-3).abs() < 1e-18, "{s:?}");
    let wrong = kkt_residuals(&p, &[1e-3, 1e-3 - 1e-5], &[1e-3 - 1e-5]);
    assert!(
        (wrong.relative_penetration - 1e-2).abs() < 1e-9,
        "{wrong:?}"
    );
    assert!(!wrong.meet(1e-9));
}

#[test]
fn a_soft_loaded_body_on_a_stiff_pair_is_judged_by_the_pair_s_stiffness() {
    // Not stricter than physics allows: a soft body (DOF 0, stiffness 1e-3) pushed by 1 rests on
    // a stiff one (DOF 1, stiffness 1e3) across a gap of 0.1: row x₀ − x₁ ≤ 0.1.  Its load
    // reaches the row, and moves the row's DOFs by about ‖f‖₁ / kᵢ = 500 (kᵢ = 2e-3, the
    // harmonic mean), less than W = 1000.  The exact answer (closed form below) meets 1e-12;
    // the stiff body's motion (≈ 1e-3) is well inside the scale, so a penetration of 1e-7 of
    // the row scale is still seen.
    let p = springs(&[1e-3, 1e3], &[1.0, 0.0], &[(&[(0, 1.0), (1, -1.0)], 0.1)]);
    let s = ResidualScales::of(&p);
    assert!(
        (s.rows[0] - 1.0 / (2.0 / (1e3 + 1e-3))).abs() < 1e-9,
        "{s:?}"
    );
    // Active row: x₀ = x₁ + 0.1 and 1e-3 x₀ − 1 + λ = 0, 1e3 x₁ − λ = 0.
    let x1 = (1.0 - 1e-4) / (1e3 + 1e-3);
    let x0 = x1 + 0.1;
    let lambda = 1e3 * x1;
    assert!(kkt_residuals(&p, &[x0, x1], &[lambda]).meet(1e-12));
    let deeper = kkt_residuals(&p, &[x0 + 5e-5, x1], &[lambda]);
    assert!(deeper.relative_penetration > 9e-8, "{deeper:?}");
}

#[test]
fn a_body_pulled_away_from_a_pair_does_not_loosen_its_rows() {
    // The stacked-body fuzz cases of issue 18 in one dimension.  b0 (DOF 0) pushes b1 (DOF 1)
    // with a load of 1: row x₀ − x₁ ≤ 0, optimum x₀ = x₁ = ½, λ₀ = ½.  b2 (DOF 2) lies beyond b1
    // (row x₁ − x₂ ≤ 0) and is pulled away by 1e12: the row opens, and b2's load cannot act on
    // the pair.  Through the rows all three DOFs are one component, so the fixed scale is
    // X₀ = min(W, ‖f‖₁ / k₀) ≈ 1e12 and a penetration of 1e-3 (0.2 % of the pair's motion) was
    // 1e-15 of it; the answer moves the pair's bodies by 0.5005, and the row is judged by that.
    let p = springs(
        &[1.0, 1.0, 1.0],
        &[1.0, 0.0, 1e12],
        &[(&[(0, 1.0), (1, -1.0)], 0.0), (&[(1, 1.0), (2, -1.0)], 0.0)],
    );
    let s = ResidualScales::of(&p);
    assert!(s.rows[0] > 1e11, "{s:?}");
    assert!(kkt_residuals(&p, &[0.5, 0.5, 1e12], &[0.5, 0.0]).meet(1e-15));
    // Equilibrium kept on every DOF (x₀ = 1 − λ₀, x₁ = λ₀), b1 sunk 1e-3 into b0.
    let wrong = kkt_residuals(&p, &[0.5005, 0.4995, 1e12], &[0.4995, 0.0]);
    assert!(wrong.stationarity < 1e-15, "{wrong:?}");
    assert!(
        (wrong.relative_penetration - 1e-3 / 0.5005).abs() < 1e-12,
        "{wrong:?}"
    );
    assert!(!wrong.meet(1e-9));
}

#[test]
fn a_body_left_by_its_contacts_is_judged_by_its_own_forces() {
    // The force side (the mortar fuzz case: a 1e100 lift elsewhere in the component let an
    // unbalanced floating body pass).  b0 (DOF 0) is pushed into b1 (DOF 1) by 1e12: row
    // x₀ − x₁ ≤ 0, x₀ = x₁ = 5e11, λ₀ = 5e11.  b2 (DOF 2, load 1) lies 1e15 beyond b1 (row
    // x₁ − x₂ ≤ 1e15, open): x₂ = 1.  F_c = ‖f‖∞ = 1e12 for the whole component, so a wrong x₂
    // off by 1e3 was 1e-9 of it.  The answer puts no contact force on b2, so its forces are its
    // load (1) — judged against δ F_c = 1e8 (BODY_FORCE_FLOOR), the error is 1e-5.
    let p = springs(
        &[1.0, 1.0, 1.0],
        &[1e12, 0.0, 1.0],
        &[
            (&[(0, 1.0), (1, -1.0)], 0.0),
            (&[(1, 1.0), (2, -1.0)], 1e15),
        ],
    );
    assert_eq!(ResidualScales::of(&p).dof_forces, vec![1e12; 3]);
    assert!(kkt_residuals(&p, &[5e11, 5e11, 1.0], &[5e11, 0.0]).meet(1e-15));
    let wrong = kkt_residuals(&p, &[5e11, 5e11, 1.0 + 1e3], &[5e11, 0.0]);
    let expected = 1e3 / (BODY_FORCE_FLOOR * 1e12);
    assert!(
        (wrong.stationarity - expected).abs() < 1e-12 * expected,
        "{wrong:?}"
    );
    assert!(!wrong.meet(1e-8));
    // A contact force of 1e3 on b2 with no counterpart: b2's forces are now 1e3, still below
    // δ F_c, so the error is again 1e3 / 1e8.
    let pushed = kkt_residuals(&p, &[5e11, 5e11, 1.0], &[5e11, 1e3]);
    assert!(
        (pushed.stationarity - expected).abs() < 1e-12 * expected,
        "{pushed:?}"
    );
}

/// Tresca's 1-D spring: min ½ x² − f x + s |x| (A = 1, B = [1], g = 0, one box row of bound
/// s = 1).  Its answer by hand: stick (x = 0, λ = f) for |f| ≤ s, else slip x = f − s sign f,
/// λ = s sign f.
fn tresca_spring(f: f64) -> QpProblem {
    let mut a = TriMat::new((1, 1));
    a.add_triplet(0, 0, 1.0);
    let mut b = TriMat::new((1, 1));
    b.add_triplet(0, 0, 1.0);
    QpProblem::try_new(a.to_csc(), vec![f], b.to_csc(), vec![0.0])
        .unwrap()
        .with_blocks(vec![ConstraintBlock::Box { bounds: vec![1.0] }])
        .unwrap()
}

#[test]
fn box_rows_meet_the_tolerance_at_the_hand_solved_answers() {
    // Slip (f = 3: x = 2, λ = 1) and stick (f = 0.5: x = 0, λ = 0.5), and their mirrors.
    for (f, x, l) in [
        (3.0, 2.0, 1.0),
        (-3.0, -2.0, -1.0),
        (0.5, 0.0, 0.5),
        (-0.5, 0.0, -0.5),
    ] {
        let r = kkt_residuals(&tresca_spring(f), &[x], &[l]);
        assert_eq!(r.worst(), 0.0, "f = {f}: {r:?}");
        assert_eq!(r.max_penetration, 0.0, "a box row has no penetration");
    }
}

#[test]
fn each_violation_of_a_box_row_is_seen_by_its_measure() {
    // Slip with the friction force pushing along the slip (f = 3: x = 4, λ = −1 balances,
    // 4 − 3 − 1 = 0): s|r| − λr = 4 + 4 = 8, against F · X = 3 · 3 (ResidualScales: ‖f‖ = 3,
    // k̄ = 1, no gap): 0.89.
    let r = kkt_residuals(&tresca_spring(3.0), &[4.0], &[-1.0]);
    assert_eq!(r.stationarity, 0.0);
    assert!(r.complementarity > 0.5, "{r:?}");
    // A force beyond the bound at stick (f = 1.5: x = 0, λ = 1.5 balances): |λ| − s = 0.5.
    let r = kkt_residuals(&tresca_spring(1.5), &[0.0], &[1.5]);
    assert_eq!((r.stationarity, r.complementarity), (0.0, 0.0));
    assert!(r.min_multiplier < -0.1, "{r:?}");
    // Slipping below the bound (f = 0.5: x = 0.25, λ = 0.25 balances): s|r| − λr = 0.1875.
    let r = kkt_residuals(&tresca_spring(0.5), &[0.25], &[0.25]);
    assert_eq!((r.stationarity, r.min_multiplier), (0.0, 0.0));
    assert!(r.complementarity > 0.01, "{r:?}");
    // And each is refused by the tolerance.
    for (f, x, l) in [(3.0, 4.0, -1.0), (1.5, 0.0, 1.5), (0.5, 0.25, 0.25)] {
        assert!(!kkt_residuals(&tresca_spring(f), &[x], &[l]).meet(1e-3));
    }
}

#[test]
fn blocks_that_miss_rows_or_bounds_below_zero_are_refused() {
    let p = tresca_spring(1.0);
    let two = vec![ConstraintBlock::NonNegative { rows: 2 }];
    assert!(matches!(
        p.clone().with_blocks(two),
        Err(QpError::Dimensions(_))
    ));
    let negative = vec![ConstraintBlock::Box { bounds: vec![-1.0] }];
    assert!(matches!(
        p.clone().with_blocks(negative),
        Err(QpError::Dimensions(_))
    ));
    let nan = vec![ConstraintBlock::Box {
        bounds: vec![f64::NAN],
    }];
    assert!(matches!(p.with_blocks(nan), Err(QpError::NotFinite(_))));
}

#[test]
fn scaling_carries_a_box_bound_like_a_multiplier() {
    // A = 4, f = 8, bound 2: force unit k̄ · (‖f‖/k̄) = 8; the scaled bound is 2 / 8.
    let mut a = TriMat::new((1, 1));
    a.add_triplet(0, 0, 4.0);
    let mut b = TriMat::new((1, 1));
    b.add_triplet(0, 0, 1.0);
    let p = QpProblem::try_new(a.to_csc(), vec![8.0], b.to_csc(), vec![0.0])
        .unwrap()
        .with_blocks(vec![ConstraintBlock::Box { bounds: vec![2.0] }])
        .unwrap();
    let scaling = QpScaling::of(&p);
    let scaled = scaling.scale(&p);
    assert_eq!(scaled.blocks, [ConstraintBlock::Box { bounds: vec![0.25] }]);
    let mut in_place = p.clone();
    scaling.scale_in_place(&mut in_place);
    assert_eq!(in_place.blocks, scaled.blocks);
}

/// A backend that answers the hand-solved Tresca spring's optimum x = 2, λ = 1 to everything
/// (with the lengths it is told), supporting box rows when `boxes`.  It is handed problems in
/// their own units (`solve` scales), so it answers in the units the spring's scaling gives.
struct Answers {
    boxes: bool,
    lengths: (usize, usize),
}

impl Answers {
    /// The spring's optimum in the units the backend sees.
    fn canned() -> (f64, f64) {
        let units = QpScaling::of(&examples::tresca_spring(3.0).problem);
        (
            2.0 / units.displacement,
            1.0 / (units.stiffness * units.displacement),
        )
    }
}

impl QpBackend for Answers {
    fn name(&self) -> &'static str {
        "answers"
    }
    fn supports(&self, kind: BlockKind) -> bool {
        kind == BlockKind::NonNegative || self.boxes
    }
    fn solve_valid(&mut self, _: &QpProblem, _: &SolveOptions) -> Result<QpSolution, QpError> {
        let (x, lambda) = Self::canned();
        Ok(QpSolution {
            x: vec![x; self.lengths.0],
            multipliers: vec![lambda; self.lengths.1],
            status: QpStatus::Solved,
            iterations: 1,
            solve_time: Duration::ZERO,
            message: None,
        })
    }
}

#[test]
fn the_shared_checks_refuse_unsupported_blocks_and_answers_of_the_wrong_length() {
    let spring = examples::tresca_spring(3.0).problem;
    let options = SolveOptions::default();
    let mut plain = Answers {
        boxes: false,
        lengths: (1, 1),
    };
    match plain.solve(&spring, &options) {
        Err(e @ QpError::UnsupportedBlock { .. }) => {
            let text = e.to_string();
            assert!(
                text.contains("box") && text.contains("solves: non-negative"),
                "{text}"
            );
        }
        other => panic!("expected a refusal, got {other:?}"),
    }
    let mut boxes = Answers {
        boxes: true,
        lengths: (1, 1),
    };
    let s = boxes.solve(&spring, &options).unwrap();
    // x = 2, λ = 1 back in the spring's units, to the round-off of one division and product.
    assert!((s.x[0] - 2.0).abs() < 1e-15 && (s.multipliers[0] - 1.0).abs() < 1e-15);
    assert_eq!((s.x.len(), s.multipliers.len()), (1, 1));
    let mut short = Answers {
        boxes: true,
        lengths: (1, 0),
    };
    assert!(matches!(
        short.solve(&spring, &options),
        Err(QpError::Backend { .. })
    ));
}

#[test]
fn the_conformance_suite_holds_a_backend_to_the_box_rows_it_claims() {
    // `Answers` with box rows answers (2, 1) to everything: right for the slipping spring, wrong
    // for the sticking one and the rest; without box rows its refusals of the two box cases
    // pass and only the other cases fail.
    let spec = conformance::Conformance::default();
    let with = conformance::failures(
        &mut || {
            Box::new(Answers {
                boxes: true,
                lengths: (1, 1),
            })
        },
        &spec,
    );
    assert!(
        with.iter().any(|f| f.contains("box row, stick")),
        "{with:?}"
    );
    assert!(
        !with.iter().any(|f| f.contains("box row, slip")),
        "{with:?}"
    );
    let without = conformance::failures(
        &mut || {
            Box::new(Answers {
                boxes: false,
                lengths: (1, 1),
            })
        },
        &spec,
    );
    assert!(
        !without.iter().any(|f| f.contains("box row")),
        "{without:?}"
    );
}

#[test]
fn every_status_is_listed_once_in_all() {
    // The match has no wildcard: a new variant does not compile until it is given a place here,
    // and the assertion then asks for it in `QpStatus::ALL`.
    let position = |s: QpStatus| match s {
        QpStatus::Solved => 0,
        QpStatus::Inaccurate => 1,
        QpStatus::MaxIterations => 2,
        QpStatus::TimeLimit => 3,
        QpStatus::PrimalInfeasible => 4,
        QpStatus::DualInfeasible => 5,
        QpStatus::NumericalError => 6,
        QpStatus::DeformedOverlap => 7,
    };
    for (i, s) in QpStatus::ALL.into_iter().enumerate() {
        assert_eq!(position(s), i, "{s}");
    }
}

/// Records the problem it is handed and answers a diagonal problem without contact rows
/// exactly: xᵢ = fᵢ / Aᵢᵢ (no scaling of its own).
struct Diagonal {
    seen: Option<QpProblem>,
}

impl QpBackend for Diagonal {
    fn name(&self) -> &'static str {
        "diagonal"
    }

    fn solve_valid(
        &mut self,
        problem: &QpProblem,
        _: &SolveOptions,
    ) -> Result<QpSolution, QpError> {
        self.seen = Some(problem.clone());
        let x = (0..problem.dofs())
            .map(|j| problem.load[j] / problem.stiffness.get(j, j).copied().unwrap_or(1.0))
            .collect();
        Ok(QpSolution {
            x,
            multipliers: vec![0.0; problem.rows()],
            status: QpStatus::Solved,
            iterations: 1,
            solve_time: Duration::ZERO,
            message: None,
        })
    }
}

/// `solve` nondimensionalises: a backend handed springs of stiffness 1e9 under loads of 1e3
/// (SI-like units) sees a problem whose units are one — mean diagonal 1, ‖f̂‖∞ = 1 — and its
/// answer comes back in the caller's units: x = f / k exactly (1e-6 and 2e-6, to round-off);
/// a problem already in its own units reaches the backend unchanged, bit for bit.
#[test]
fn solve_scales_for_every_backend_and_leaves_a_scaled_problem_alone() {
    let raw = springs(&[1e9, 1e9], &[1e3, 2e3], &[]);
    let mut backend = Diagonal { seen: None };
    let answer = backend.solve(&raw, &SolveOptions::default()).unwrap();
    let seen = backend.seen.take().unwrap();
    assert!(QpScaling::of(&seen).is_unit());
    assert_eq!(seen.stiffness.get(0, 0), Some(&1.0));
    assert!((norm_inf(&seen.load) - 1.0).abs() < 1e-15);
    for (x, want) in answer.x.iter().zip([1e-6, 2e-6]) {
        assert!((x - want).abs() < 1e-15 * want, "{x} vs {want}");
    }
    let scaled = QpScaling::of(&raw).scale(&raw);
    backend.solve(&scaled, &SolveOptions::default()).unwrap();
    let seen = backend.seen.take().unwrap();
    assert_eq!(seen.stiffness.data(), scaled.stiffness.data());
    assert_eq!(seen.load, scaled.load);
    assert_eq!(seen.gap, scaled.gap);
}

/// Every problem [`QpScaling::scale`] makes is recognised as scaled, so `solve` passes it on
/// without a copy: loads, overlaps or gaps alone setting the displacement unit, a stiffness
/// spread over 12 decades.
#[test]
fn a_scaled_problem_is_unit() {
    let cases = [
        springs(&[1e-6, 1e6], &[3.0, -2.0], &[(&[(0, 1.0)], 0.5)]),
        springs(&[2e5, 7e5], &[0.0, 0.0], &[(&[(0, 1.0)], -1e-3)]),
        springs(&[4.0, 9.0], &[0.0, 0.0], &[(&[(1, -1.0)], 2e4)]),
        springs(&[1e212, 1.0], &[1e-100, 0.0], &[(&[(0, 1.0)], 1.0)]),
    ];
    for p in cases {
        let s = QpScaling::of(&p);
        assert!(QpScaling::of(&s.scale(&p)).is_unit(), "{s:?}");
    }
}

#[test]
fn a_body_that_does_not_move_is_judged_against_its_own_loads() {
    // A point (DOF 0, stiffness 2) pressed by 2 onto an obstacle at 0 (row −x₀ ≤ 0): x₀ = 0,
    // λ = 2.  An answer with the round-off of a refined solve, x₀ = −1e-17, was judged against
    // the point's own motion, the same 1e-17: relative penetration 1, never `solved` (FCLIB's
    // four points on a plane through pdas).  The floor is δ W₀ = 1e-4 · |f₀| / A₀₀ = 1e-4.
    let p = springs(&[2.0], &[-2.0], &[(&[(0, -1.0)], 0.0)]);
    let exact = kkt_residuals(&p, &[-1e-17], &[2.0]);
    assert!(exact.meet(1e-12), "{exact:?}");
    assert!(
        (exact.relative_penetration - 1e-13).abs() < 1e-25,
        "{exact:?}"
    );
    // A real penetration is still caught at that scale: 1e-9 of the load's own motion.
    let sunk = kkt_residuals(&p, &[-1e-9], &[2.0]);
    assert!(!sunk.meet(1e-9), "{sunk:?}");
}

/// A caller's residual scales are used when they have the problem's sizes (the same `Arc`, no
/// second pass over A and B), recomputed when they do not (scales of another problem).
#[test]
fn given_residual_scales_are_used_only_when_they_fit() {
    let problem = crate::examples::two_rows().problem;
    let own = std::sync::Arc::new(ResidualScales::of(&problem));
    let options = SolveOptions {
        scales: Some(own.clone()),
        ..SolveOptions::default()
    };
    assert!(std::sync::Arc::ptr_eq(
        &options.residual_scales(&problem),
        &own
    ));
    let other = crate::examples::scalar(1.0).problem;
    let recomputed = options.residual_scales(&other);
    assert_eq!(*recomputed, ResidualScales::of(&other));
    assert!(!own.fit(&other));
}

/// `solve` drops the caller's scales when it nondimensionalises the problem: they are in the
/// caller's units, and the backend gets another problem.
#[test]
fn solve_drops_given_scales_when_it_scales_the_problem() {
    struct Handed(Option<bool>);
    impl QpBackend for Handed {
        fn name(&self) -> &'static str {
            "handed"
        }
        fn solve_valid(&mut self, p: &QpProblem, o: &SolveOptions) -> Result<QpSolution, QpError> {
            self.0 = Some(o.scales.is_some());
            Ok(QpSolution {
                x: vec![0.0; p.dofs()],
                multipliers: vec![0.0; p.rows()],
                status: QpStatus::Inaccurate,
                iterations: 0,
                solve_time: Duration::ZERO,
                message: None,
            })
        }
    }
    // Mean diagonal 6: not in its own units, so `solve` scales it.
    let problem = crate::examples::two_rows_scaled(3.0).problem;
    let options = SolveOptions {
        scales: Some(std::sync::Arc::new(ResidualScales::of(&problem))),
        ..SolveOptions::default()
    };
    let mut backend = Handed(None);
    backend.solve(&problem, &options).unwrap();
    assert_eq!(backend.0, Some(false));
    // A problem in its own units goes as is, and so do the scales.
    let unit = QpScaling::of(&problem).scale(&problem);
    let options = SolveOptions {
        scales: Some(std::sync::Arc::new(ResidualScales::of(&unit))),
        ..SolveOptions::default()
    };
    backend.solve(&unit, &options).unwrap();
    assert_eq!(backend.0, Some(true));
}
