//! `solve/<backend>/…`: one contact solve of Experiment 3 (both bodies) at each benched `hmax`
//! through `signorini_core::solve::solve_model` (scaling, backend, unscaling, core KKT check)
//! with `tol = 1e-8`, for clarabel, osqp, dual-pgs, dual-uzawa and dual-ssn (the dual crate's
//! active-set method).  The reduced QP is built once per size, outside the timing.
//!
//! A backend is not registered at a size where one solve takes more than ~20 s (criterion runs it
//! at least 11 times).  Single solves measured with `cargo run --release -p signorini-benches
//! --example once` (2 shared cores), at 117 572 DOFs: clarabel 16.9 s, osqp 16.2 s,
//! **dual-uzawa 21.8 s (skipped)**, dual-pgs 0.49 s, dual-ssn 0.39 s; every solve below 3 s at the
//! two smaller sizes.

use std::time::Duration;

use criterion::{criterion_main, Criterion, SamplingMode};
use signorini_benches::{solve_options, Bench, Case, HMAX};
use signorini_core::solve::solve_model;

/// (backend, hmax) pairs left out: a single solve takes more than ~20 s.
const SKIPPED: &[(&str, f64)] = &[("dual-uzawa", 0.01)];

fn skipped(bench: Bench, hmax: f64) -> bool {
    SKIPPED
        .iter()
        .any(|&(name, h)| name == bench.name() && h == hmax)
}

fn solve(c: &mut Criterion) {
    let cases: Vec<Case> = HMAX.iter().map(|&h| Case::new(h)).collect();
    let options = solve_options();
    for bench in Bench::ALL {
        let mut group = c.benchmark_group(format!("solve/{}", bench.name()));
        group
            .sample_size(10)
            .sampling_mode(SamplingMode::Flat)
            .warm_up_time(Duration::from_millis(500))
            .measurement_time(Duration::from_secs(2));
        let mut backend = bench.backend();
        for case in cases.iter().filter(|case| !skipped(bench, case.hmax)) {
            group.bench_function(case.id(), |b| {
                b.iter(|| {
                    solve_model(&case.model, &case.qp, backend.as_mut(), &options)
                        .expect("the contact solve runs")
                });
            });
        }
        group.finish();
    }
}

/// Runs the `solve/…` benches with criterion's command-line configuration (what `criterion_group!`
/// would generate, written out so that it carries a doc comment).
fn benches() {
    let mut criterion = Criterion::default().configure_from_args();
    solve(&mut criterion);
}
criterion_main!(benches);
