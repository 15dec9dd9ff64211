//! The half solves of a factor with the contact DOFs last (x(λ) by one backward substitution
//! from z = L⁻¹ P f, d from the trailing block alone) against whole solves of the assembled
//! right-hand sides: the same vectors up to round-off, held and floating.
#![cfg(test)]
#![allow(clippy::unwrap_used)]

use signorini_qp::{mat_t_vec, mat_vec, CscMatrix, QpProblem};
use sprs::TriMat;

use crate::dual::DualData;

/// 5-point Laplacian on side × side nodes (uneven weights), tied to the ground along its
/// bottom row when `held` (else a pure Neumann problem with the constants as kernel), and
/// segment-like rows x_s − ½(x_a + x_b) across two neighbouring grid lines.
fn problem(side: usize, rows: usize, held: bool) -> QpProblem {
    let n = side * side;
    let id = |i: usize, j: usize| j * side + i;
    let mut a = TriMat::new((n, n));
    let mut edge = |p: usize, q: usize, w: f64| {
        a.add_triplet(p, p, w);
        a.add_triplet(q, q, w);
        a.add_triplet(p, q, -w);
        a.add_triplet(q, p, -w);
    };
    for j in 0..side {
        for i in 0..side {
            let w = 1.0 + 0.5 * ((i * side + j) as f64).sin();
            if i + 1 < side {
                edge(id(i, j), id(i + 1, j), w);
            }
            if j + 1 < side {
                edge(id(i, j), id(i, j + 1), 1.3 * w);
            }
        }
    }
    if held {
        for i in 0..side {
            a.add_triplet(id(i, 0), id(i, 0), 2.0);
        }
    }
    let line = side / 2;
    let mut b = TriMat::new((rows, n));
    for r in 0..rows {
        let i = (r * (side - 1)) / rows;
        b.add_triplet(r, id(i, line), 1.0);
        b.add_triplet(r, id(i, line + 1), -0.5);
        b.add_triplet(r, id(i + 1, line + 1), -0.5);
    }
    let a: CscMatrix = a.to_csc();
    // A load with no resultant along the constants (a floating body's f must be balanced for
    // A⁺ f to mean anything; the half solves do not care).
    let load: Vec<f64> = (0..n).map(|k| (0.7 * k as f64).cos()).collect();
    let gap = (0..rows).map(|r| 1e-3 * (r as f64).sin()).collect();
    let qp = QpProblem::try_new(a, load, b.to_csc(), gap).unwrap();
    if held {
        qp
    } else {
        qp.with_kernel(vec![vec![1.0; n]]).unwrap()
    }
}

/// max |a − b| / max |b|.
fn relative(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let diff = a
        .iter()
        .zip(b)
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
    diff / scale
}

/// The two ways agree to 1e-12 of the vectors' size: they differ only in the order of the
/// rounding (forward errors of order ε κ(A); κ ≈ 10³ for these 30 × 30 Laplacians, so ≈ 1e-13,
/// a factor 10 under the bound).  A wrong index, sign or permutation in the half solves is an
/// O(1) error.
const AGREE: f64 = 1e-12;

fn check(held: bool) {
    let qp = problem(30, 12, held);
    let data = DualData::new(&qp, true, "dual-ssn").unwrap();
    assert!(
        data.inverse.contact_last(),
        "the half solves need the contact DOFs last"
    );
    assert_eq!(data.floating(), !held);
    let lambda: Vec<f64> = (0..qp.rows()).map(|r| 1.0 + (r as f64).cos()).collect();
    let half = data.free_part(&lambda);
    let whole = data.free_part_full(&lambda);
    assert!(
        relative(&half, &whole) < AGREE,
        "{}",
        relative(&half, &whole)
    );
    let base = data.inverse.solve(&qp.load);
    assert!(relative(data.base(), &base) < AGREE);
    // d = B A⁺ f − g from the trailing block against B times the whole solve.
    let mut d = mat_vec(&qp.constraints, &base);
    d.iter_mut().zip(&qp.gap).for_each(|(di, g)| *di -= g);
    let dual_load = data.dual_load();
    assert!(
        relative(&dual_load, &d) < AGREE,
        "{}",
        relative(&dual_load, &d)
    );
    // And x(λ) really solves A x = f − Bᵀλ on the factored DOFs (not only equals another
    // computation that could share a mistake): residual at round-off of ‖A‖‖x‖.
    if held {
        let ax = mat_vec(&qp.stiffness, &half);
        let btl = mat_t_vec(&qp.constraints, &lambda);
        let r: Vec<f64> = (0..qp.dofs())
            .map(|i| ax[i] - qp.load[i] + btl[i])
            .collect();
        let a_norm = qp
            .stiffness
            .outer_iterator()
            .map(|col| col.data().iter().map(|v| v.abs()).sum::<f64>())
            .fold(0.0_f64, f64::max);
        let scale = a_norm * half.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        assert!(r.iter().all(|v| v.abs() < AGREE * scale));
    }
}

#[test]
fn x_of_lambda_by_one_backward_substitution_equals_the_whole_solve() {
    check(true);
}

#[test]
fn the_half_solves_agree_on_a_floating_body_too() {
    check(false);
}
