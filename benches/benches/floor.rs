//! `factor/…`: the floor every contact solve is measured against — sparse Cholesky (faer, via
//! `signorini_core::linalg`) of the reduced stiffness A = `prepare(..)?.qp.stiffness` of
//! Experiment 3 (both bodies) at each benched `hmax`:
//!
//! * `factor/floor/…` — analyse + factor + one `solve_in_place` (one unconstrained elastic solve
//!   from scratch: the denominator of the solve/floor ratios);
//! * `factor/analyse+factor/…` — `CholeskyPattern::analyse` then `factor`;
//! * `factor/numeric/…` — numeric `factor` with a reused pattern;
//! * `factor/solve_in_place/…` — one triangular solve pair with the cached factor.

use std::time::Duration;

use criterion::{criterion_main, BatchSize, Criterion, SamplingMode};
use signorini_benches::{Case, HMAX};
use signorini_core::linalg::CholeskyPattern;

fn factor(c: &mut Criterion) {
    let mut group = c.benchmark_group("factor");
    group
        .sample_size(10)
        .sampling_mode(SamplingMode::Flat)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    for &hmax in &HMAX {
        let case = Case::new(hmax);
        let a = &case.qp.stiffness;
        let f = &case.qp.load;
        let id = case.id();
        group.bench_function(format!("floor/{id}"), |b| {
            b.iter_batched(
                || f.clone(),
                |mut x| {
                    let pattern = CholeskyPattern::analyse(a).expect("analyse A");
                    let chol = pattern.factor(a).expect("A is positive definite");
                    chol.solve_in_place(&mut x);
                    x
                },
                BatchSize::LargeInput,
            );
        });
        group.bench_function(format!("analyse+factor/{id}"), |b| {
            b.iter(|| {
                let pattern = CholeskyPattern::analyse(a).expect("analyse A");
                pattern.factor(a).expect("A is positive definite")
            });
        });
        let pattern = CholeskyPattern::analyse(a).expect("analyse A");
        group.bench_function(format!("numeric/{id}"), |b| {
            b.iter(|| pattern.factor(a).expect("A is positive definite"));
        });
        let chol = pattern.factor(a).expect("A is positive definite");
        group.bench_function(format!("solve_in_place/{id}"), |b| {
            b.iter_batched(
                || f.clone(),
                |mut x| {
                    chol.solve_in_place(&mut x);
                    x
                },
                BatchSize::LargeInput,
            );
        });
    }
    group.finish();
}

/// Runs the `factor/…` benches with criterion's command-line configuration (what `criterion_group!`
/// would generate, written out so that it carries a doc comment).
fn benches() {
    let mut criterion = Criterion::default().configure_from_args();
    factor(&mut criterion);
}
criterion_main!(benches);
