//! `mesh/…` and `assemble/…`: meshing (`core::model::mesh_scene`) and assembly
//! (`core::model::assemble`) of Experiment 3 (both bodies) at each benched `hmax`, timed
//! separately.  Names carry the model's DOF count, e.g. `assemble/exp3-both/dofs=2124`.

use std::time::Duration;

use criterion::{criterion_main, BatchSize, Criterion, SamplingMode};
use signorini_benches::{Case, HMAX};
use signorini_core::mesh::MeshLimits;
use signorini_core::model;

fn prepare(c: &mut Criterion) {
    let cases: Vec<Case> = HMAX.iter().map(|&h| Case::new(h)).collect();
    let limits = MeshLimits::default();

    let mut group = c.benchmark_group("mesh");
    group
        .sample_size(10)
        .sampling_mode(SamplingMode::Flat)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    for case in &cases {
        group.bench_function(case.id(), |b| {
            b.iter(|| model::mesh_scene(&case.scene, &limits).expect("exp3-both meshes"));
        });
    }
    group.finish();

    let mut group = c.benchmark_group("assemble");
    group
        .sample_size(10)
        .sampling_mode(SamplingMode::Flat)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    for case in &cases {
        let meshes = case.meshes();
        group.bench_function(case.id(), |b| {
            b.iter_batched(
                || meshes.clone(),
                |m| model::assemble(&case.scene, m).expect("exp3-both assembles"),
                BatchSize::LargeInput,
            );
        });
    }
    group.finish();
}

/// Runs the `mesh/…` and `assemble/…` benches with criterion's command-line configuration (what `criterion_group!`
/// would generate, written out so that it carries a doc comment).
fn benches() {
    let mut criterion = Criterion::default().configure_from_args();
    prepare(&mut criterion);
}
criterion_main!(benches);
