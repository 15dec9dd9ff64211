//! Bench-like measurements of the two condensations (run by hand, prints timings):
//!
//! ```text
//! cargo test -p signorini-dual --release --lib measure -- --ignored --nocapture
//! ```
#![cfg(test)]
#![allow(clippy::unwrap_used)]

use std::time::Instant;

use signorini_qp::{CscMatrix, QpProblem};
use sprs::TriMat;

use crate::dual::DualData;
use crate::hessian::{interior_schur, multi_rhs, touched_columns, trailing_hessian};

/// 5-point Laplacian on side × side nodes plus `m` rows: bound rows (1 DOF each) or
/// segment-like rows x_s − ½(x_a + x_b) across two neighbouring grid lines (3 DOFs each,
/// masters shared between neighbours).
fn problem(side: usize, m: usize, segment_like: bool) -> QpProblem {
    let n = side * side;
    let id = |i: usize, j: usize| j * side + i;
    let mut a = TriMat::new((n, n));
    for j in 0..side {
        for i in 0..side {
            a.add_triplet(id(i, j), id(i, j), 4.0);
            if i + 1 < side {
                a.add_triplet(id(i, j), id(i + 1, j), -1.0);
                a.add_triplet(id(i + 1, j), id(i, j), -1.0);
            }
            if j + 1 < side {
                a.add_triplet(id(i, j), id(i, j + 1), -1.0);
                a.add_triplet(id(i, j + 1), id(i, j), -1.0);
            }
        }
    }
    let mut b = TriMat::new((m, n));
    for r in 0..m {
        // Distinct DOFs: rows fill grid lines side/2, side/2 + 2, … (one node apart when m < side).
        let per_line = m.min(side - 1);
        let line = side / 2 + 2 * (r / per_line);
        let i = ((r % per_line) * side) / per_line;
        if segment_like {
            let i2 = (i + 1).min(side - 1);
            b.add_triplet(r, id(i, line), 1.0);
            b.add_triplet(r, id(i, line + 1), -0.5);
            b.add_triplet(r, id(i2, line + 1), -0.5);
        } else {
            b.add_triplet(r, id(i, line), -1.0);
        }
    }
    let a: CscMatrix = a.to_csc();
    // Bound rows: an obstacle 0.01 below.  3-DOF rows: gaps of both signs (about half the rows
    // end up active, pushing the two lines apart).
    let gap = (0..m)
        .map(|r| {
            if segment_like {
                1e-3 * (r as f64).sin()
            } else {
                0.01
            }
        })
        .collect();
    QpProblem::try_new(a, vec![-1.0 / n as f64; n], b.to_csc(), gap).unwrap()
}

#[test]
#[ignore = "measurement: run by hand with --release --nocapture"]
fn measure_condensations() {
    println!("| n | m | rows | touched DOFs | factor A | (a) multi-RHS | (a) total | (b) A_ii + Schur + H | (c) factor c-last | (c) H from L_cc | (c) total | max |H_a − H_b|, |H_a − H_c| |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    for side in [100, 316] {
        for m in [50, 500] {
            for segment_like in [false, true] {
                let p = problem(side, m, segment_like);
                let t0 = Instant::now();
                let data = DualData::new(&p, false, "dual-ssn").unwrap();
                let factor = t0.elapsed();
                let t1 = Instant::now();
                let ha = multi_rhs(&data.inverse, &p.constraints, 64, &|| false).unwrap();
                let a_time = t1.elapsed();
                let t2 = Instant::now();
                let hb = interior_schur(&data, 64, &|| false).unwrap();
                let b_time = t2.elapsed();
                let t3 = Instant::now();
                let data_c = DualData::new(&p, true, "dual-ssn").unwrap();
                let c_factor = t3.elapsed();
                let t4 = Instant::now();
                assert!(data_c.inverse.contact_last());
                let hc = trailing_hessian(
                    data_c.inverse.factor().trailing(),
                    data_c.inverse.trailing(),
                    &p.constraints,
                );
                let c_time = t4.elapsed();
                let touched = touched_columns(&data.inverse, &p.constraints).len();
                let diff = |h: &[f64]| {
                    ha.values
                        .iter()
                        .zip(h)
                        .fold(0.0_f64, |mx, (x, y)| mx.max((x - y).abs()))
                };
                let ms = |d: std::time::Duration| d.as_secs_f64() * 1e3;
                println!(
                    "| {} | {m} | {} | {touched} | {:.1} ms | {:.1} ms | {:.1} ms | {:.1} ms | {:.1} ms | {:.1} ms | {:.1} ms | {:.0e}, {:.0e} |",
                    side * side,
                    if segment_like { "3-DOF" } else { "bound" },
                    ms(factor),
                    ms(a_time),
                    ms(factor + a_time),
                    ms(b_time),
                    ms(c_factor),
                    ms(c_time),
                    ms(c_factor + c_time),
                    diff(&hb.values),
                    diff(&hc.values),
                );
            }
        }
    }
}

#[test]
#[ignore = "measurement: run by hand with --release --nocapture"]
fn measure_methods() {
    use crate::{DualBackend, DualSettings};
    use signorini_qp::linalg::SparseCholesky;
    use signorini_qp::{checked_status, kkt_residuals, QpBackend, SolveOptions};
    println!(
        "| n | m | rows | floor (factor + solve) | method | status | iterations | time | × floor |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    for (side, m) in [(100, 50), (100, 500), (316, 50), (316, 500)] {
        for segment_like in [false, true] {
            let p = problem(side, m, segment_like);
            let t = Instant::now();
            let chol = SparseCholesky::factor(&p.stiffness).unwrap();
            let mut x = p.load.clone();
            chol.solve_in_place(&mut x);
            let floor = t.elapsed().as_secs_f64();
            for mut backend in [
                DualBackend::pgs(DualSettings::default()),
                DualBackend::uzawa(DualSettings::default()),
                DualBackend::active_set(DualSettings::default()),
            ] {
                let options = SolveOptions::default();
                let sol = backend.solve(&p, &options).unwrap();
                let r = kkt_residuals(&p, &sol.x, &sol.multipliers);
                let status = checked_status(sol.status, &r, options.tol);
                let time = sol.solve_time.as_secs_f64();
                println!(
                    "| {} | {m} | {} | {:.1} ms | {} | {status} | {} | {:.1} ms | {:.1} |",
                    side * side,
                    if segment_like { "3-DOF" } else { "bound" },
                    floor * 1e3,
                    backend.name(),
                    sol.iterations,
                    time * 1e3,
                    time / floor
                );
            }
        }
    }
}

#[test]
#[ignore = "measurement: run by hand with --release --nocapture"]
fn measure_newton_modes() {
    use crate::{DualBackend, DualSettings};
    use signorini_qp::linalg::SparseCholesky;
    use signorini_qp::{checked_status, kkt_residuals, QpBackend, SolveOptions};
    println!("| n | m | rows | floor | dense ssn (× floor) | matrix-free ssn (× floor) |");
    println!("|---|---|---|---|---|---|");
    for (side, m) in [(100, 50), (100, 500), (316, 50), (316, 500), (316, 2000)] {
        for segment_like in [false, true] {
            let p = problem(side, m, segment_like);
            let t = Instant::now();
            let chol = SparseCholesky::factor(&p.stiffness).unwrap();
            let mut x = p.load.clone();
            chol.solve_in_place(&mut x);
            let floor = t.elapsed().as_secs_f64();
            let mut cells = Vec::new();
            for rows in [usize::MAX, 0] {
                let mut backend = DualBackend::active_set(DualSettings {
                    matrix_free_rows: rows,
                    ..DualSettings::default()
                });
                let options = SolveOptions::default();
                let sol = backend.solve(&p, &options).unwrap();
                let r = kkt_residuals(&p, &sol.x, &sol.multipliers);
                let status = checked_status(sol.status, &r, options.tol);
                let time = sol.solve_time.as_secs_f64();
                cells.push(format!(
                    "{status} {:.1} ms ({:.1}×)",
                    time * 1e3,
                    time / floor
                ));
            }
            println!(
                "| {} | {m} | {} | {:.1} ms | {} | {} |",
                side * side,
                if segment_like { "3-DOF" } else { "bound" },
                floor * 1e3,
                cells[0],
                cells[1]
            );
        }
    }
}
