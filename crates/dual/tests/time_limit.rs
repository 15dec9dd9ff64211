//! Every method honours `SolveOptions::time_limit` (issue 9): on a problem each of them needs
//! far longer than the limit for, it stops with `time-limit` (or an earlier honest verdict)
//! within the limit plus one step — one sparse solve or one block of them, milliseconds here.
#![allow(clippy::unwrap_used)]

mod common;

use std::time::{Duration, Instant};

use signorini_dual::{DualBackend, DualSettings};
use signorini_qp::{QpBackend, QpStatus, SolveOptions};

/// A slender 2-D strip of 5-point Laplacian cells, 600 × 4 nodes, clamped at its left end
/// only, pushed down onto an obstacle under its bottom row: every one of the 600 rows is active
/// and the dual is as ill-conditioned as a cantilever's (PGS and Uzawa need minutes).
fn slender_strip() -> signorini_qp::QpProblem {
    let (nx, ny) = (600, 4);
    let n = nx * ny;
    let id = |i: usize, j: usize| j * nx + i;
    let mut a = Vec::new();
    let mut edge = |p: usize, q: usize| {
        a.push((p, p, 1.0));
        a.push((q, q, 1.0));
        a.push((p, q, -1.0));
        a.push((q, p, -1.0));
    };
    for j in 0..ny {
        for i in 0..nx {
            if i + 1 < nx {
                edge(id(i, j), id(i + 1, j));
            }
            if j + 1 < ny {
                edge(id(i, j), id(i, j + 1));
            }
        }
    }
    for j in 0..ny {
        a.push((id(0, j), id(0, j), 1.0));
    }
    // −x ≤ 1e-3: the obstacle 1e-3 below the bottom row, which the load pushes down.
    let b: Vec<_> = (0..nx).map(|i| (i, id(i, 0), -1.0)).collect();
    let g = vec![1e-3; nx];
    common::qp(n, &a, vec![-1.0; n], nx, &b, g)
}

#[test]
fn every_method_stops_within_its_time_limit() {
    let p = slender_strip();
    let limit = Duration::from_millis(300);
    // One step here (a solve of 2 400 unknowns, a block of 64 of them, a sweep over 600 rows)
    // takes well under 50 ms even on a loaded 2-core machine; 0.7 s of slack covers the first
    // factorisation and scheduling noise.
    let slack = Duration::from_millis(700);
    let backends = [
        DualBackend::pgs(DualSettings::default()),
        DualBackend::uzawa(DualSettings::default()),
        DualBackend::active_set(DualSettings {
            matrix_free_rows: 0,
            ..DualSettings::default()
        }),
    ];
    for mut b in backends {
        let options = SolveOptions {
            tol: 1e-12,
            time_limit: Some(limit),
            ..SolveOptions::default()
        };
        let t = Instant::now();
        let sol = b.solve(&p, &options).unwrap();
        let took = t.elapsed();
        assert!(
            took < limit + slack,
            "{} took {took:?}: {:?}",
            b.name(),
            sol.message
        );
        println!(
            "{}: {} in {took:?} ({:?})",
            b.name(),
            sol.status,
            sol.message
        );
        if sol.status != QpStatus::Solved {
            assert!(sol.x.iter().all(|v| v.is_finite()));
        }
    }
}
