//! The measurement behind the ordering rule of [`crate::linalg::ordering`] (run by hand; prints a
//! Markdown table):
//!
//! ```text
//! SIGNORINI_MEASURE_SCENES="a.toml b.toml" \
//!   cargo test --release -p signorini-core --lib linalg_measure -- --ignored --nocapture
//! ```
//!
//! (`SIGNORINI_MEASURE_METHODS="metis"` restricts the orderings measured.)
//!
//! For each scene: mesh, assemble, then for AMD and METIS the ordering, the symbolic analysis
//! and the numeric LLᵀ (forced supernodal, one thread) of the reduced stiffness A, timed apart,
//! with nnz(L).  A singular A (a body held by contact only) gets the floor's diagonal shift.
#![cfg(test)]
#![allow(clippy::unwrap_used)]

use std::time::Instant;

use crate::linalg::{order_with, CholeskyPattern, OrderingMethod};
use crate::mesh::MeshLimits;
use crate::model;
use crate::scene::Scene;

#[test]
#[ignore = "measurement: run by hand with --release --nocapture"]
fn measure_orderings() {
    let scenes = std::env::var("SIGNORINI_MEASURE_SCENES").unwrap_or_default();
    println!("| scene | n | nnz(A) | ordering | order s | symbolic s | numeric s | total s | nnz(L) | flops | solve s |");
    println!("|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|");
    for path in scenes.split_whitespace() {
        let scene = Scene::from_path(std::path::Path::new(path)).unwrap();
        let limits = MeshLimits {
            max_elements: 50_000_000,
            ..MeshLimits::default()
        };
        let meshes = model::mesh_scene(&scene, &limits).unwrap();
        let qp = model::assemble(&scene, meshes).unwrap().qp;
        let (estimate, _) = crate::preflight::check_factor_memory(&qp, u64::MAX).unwrap();
        let gib = |b: f64| b / crate::memory::GIB;
        println!(
            "|   (memory estimate: total {:.2} GiB, factor {:.2}, scratch {:.2}, matrices {:.2}, vectors {:.2}) |",
            gib(estimate.total()),
            gib(estimate.factor),
            gib(estimate.scratch),
            gib(estimate.matrices),
            gib(estimate.vectors)
        );
        let a = crate::solve::floor_matrix(&qp);
        let a = a.as_ref().unwrap_or(&qp.stiffness);
        let name = std::path::Path::new(path)
            .file_stem()
            .unwrap()
            .to_string_lossy()
            .to_string();
        let methods = std::env::var("SIGNORINI_MEASURE_METHODS").unwrap_or("amd metis".into());
        for method in OrderingMethod::ALL {
            if !methods.split_whitespace().any(|m| m == method.as_str()) {
                continue;
            }
            let t0 = Instant::now();
            let ordering = order_with(a, method).unwrap();
            let t1 = Instant::now();
            let pattern = CholeskyPattern::analyse_with(a, &ordering).unwrap();
            let t2 = Instant::now();
            let chol = pattern.factor(a).unwrap();
            let t3 = Instant::now();
            let mut x = qp.load.clone();
            chol.solve_in_place(&mut x);
            let t4 = Instant::now();
            let info = chol.info(a).unwrap();
            let s = |a: Instant, b: Instant| (b - a).as_secs_f64();
            println!(
                "| {name} | {} | {} | {method} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3e} | {:.2e} | {:.3} |",
                a.rows(),
                a.nnz(),
                s(t0, t1),
                s(t1, t2),
                s(t2, t3),
                s(t0, t3),
                info.nnz_l as f64,
                info.flops,
                s(t3, t4),
            );
            drop(chol);
            let t5 = Instant::now();
            let counts = crate::linalg::column_counts(a, &ordering.inverse).unwrap();
            println!(
                "|   (column counts alone: {:.3} s, nnz(L) {}) |",
                t5.elapsed().as_secs_f64(),
                counts.iter().sum::<usize>()
            );
        }
        if methods.split_whitespace().any(|m| m == "old") {
            // The floor before issue 9: faer's own symbolic analysis (its AMD, its supernodal
            // threshold), numeric LLᵀ with faer's default parallelism, one solve.
            use faer::linalg::solvers::Solve;
            use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
            let view = crate::linalg::faer_view(a).unwrap();
            let t0 = Instant::now();
            let symbolic = SymbolicLlt::try_new(view.symbolic(), faer::Side::Lower).unwrap();
            let t1 = Instant::now();
            let llt = Llt::try_new_with_symbolic(symbolic, view, faer::Side::Lower).unwrap();
            let t2 = Instant::now();
            let mut x = qp.load.clone();
            llt.solve_in_place(faer::MatMut::from_column_major_slice_mut(
                &mut x,
                a.rows(),
                1,
            ));
            let t3 = Instant::now();
            let s = |a: Instant, b: Instant| (b - a).as_secs_f64();
            println!(
                "| {name} | {} | {} | old (faer default) | – | {:.3} | {:.3} | {:.3} | – | – | {:.3} |",
                a.rows(),
                a.nnz(),
                s(t0, t1),
                s(t1, t2),
                s(t0, t3),
                s(t2, t3),
            );
        }
    }
}

/// Old floor (faer's `SymbolicLlt` + `Llt`) against the new one (`CholeskyPattern::analyse` +
/// `factor` + solve), alternated five times (`SIGNORINI_MEASURE_REPS`) on each scene, minimum
/// of each.
#[test]
#[ignore = "measurement: run by hand with --release --nocapture"]
fn measure_old_vs_new_floor() {
    use faer::linalg::solvers::Solve;
    use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
    let scenes = std::env::var("SIGNORINI_MEASURE_SCENES").unwrap_or_default();
    for path in scenes.split_whitespace() {
        let qp = scene_qp(path);
        let a = crate::solve::floor_matrix(&qp);
        let a = a.as_ref().unwrap_or(&qp.stiffness);
        let (mut old, mut new, mut new_metis) = (f64::MAX, f64::MAX, f64::MAX);
        let reps = reps();
        for _ in 0..reps {
            let t = Instant::now();
            let view = crate::linalg::faer_view(a).unwrap();
            let symbolic = SymbolicLlt::try_new(view.symbolic(), faer::Side::Lower).unwrap();
            let llt = Llt::try_new_with_symbolic(symbolic, view, faer::Side::Lower).unwrap();
            let mut x = qp.load.clone();
            llt.solve_in_place(faer::MatMut::from_column_major_slice_mut(
                &mut x,
                a.rows(),
                1,
            ));
            old = old.min(t.elapsed().as_secs_f64());
            drop(llt);
            let t = Instant::now();
            let ordering = order_with(a, OrderingMethod::Amd).unwrap();
            let chol = CholeskyPattern::analyse_with(a, &ordering)
                .unwrap()
                .factor(a)
                .unwrap();
            let mut x = qp.load.clone();
            chol.solve_in_place(&mut x);
            new = new.min(t.elapsed().as_secs_f64());
            drop(chol);
            let t = Instant::now();
            let ordering = order_with(a, OrderingMethod::Metis).unwrap();
            let chol = CholeskyPattern::analyse_with(a, &ordering)
                .unwrap()
                .factor(a)
                .unwrap();
            let mut x = qp.load.clone();
            chol.solve_in_place(&mut x);
            new_metis = new_metis.min(t.elapsed().as_secs_f64());
        }
        println!(
            "| {path} | {} | old {old:.3} s | new amd {new:.3} s | new metis {new_metis:.3} s |",
            a.rows()
        );
    }
}

/// Where METIS's ordering time goes: the adjacency graph, its compression, METIS itself.
#[test]
#[ignore = "measurement: run by hand with --release --nocapture"]
fn measure_metis_steps() {
    let scenes = std::env::var("SIGNORINI_MEASURE_SCENES").unwrap_or_default();
    for path in scenes.split_whitespace() {
        let scene = Scene::from_path(std::path::Path::new(path)).unwrap();
        let meshes = model::mesh_scene(&scene, &MeshLimits::default()).unwrap();
        let qp = model::assemble(&scene, meshes).unwrap().qp;
        let a = &qp.stiffness;
        let t0 = Instant::now();
        let (xadj, adjncy) = crate::linalg::ordering::adjacency(a).unwrap();
        let t1 = Instant::now();
        let c = crate::linalg::ordering::Compressed::of(&xadj, &adjncy);
        let t2 = Instant::now();
        let _ = signorini_metis::node_nd_weighted(&c.xadj, &c.adjncy, Some(&c.weight)).unwrap();
        let t3 = Instant::now();
        let _ = signorini_metis::node_nd(&xadj, &adjncy).unwrap();
        let t4 = Instant::now();
        let _ = order_with(a, OrderingMethod::Amd).unwrap();
        let t5 = Instant::now();
        let s = |a: Instant, b: Instant| (b - a).as_secs_f64();
        println!(
            "| {path} | n {} | groups {} | adjacency {:.3} | compress {:.3} | metis(compressed) {:.3} | metis(DOF graph) {:.3} | amd {:.3} |",
            a.rows(),
            c.weight.len(),
            s(t0, t1),
            s(t1, t2),
            s(t2, t3),
            s(t3, t4),
            s(t4, t5)
        );
    }
}

/// The floor's kernel: forced supernodal against faer's own choice (simplicial or supernodal by
/// its flop ratio), alternated `SIGNORINI_MEASURE_REPS` times (default 5) on each scene, the
/// minimum of each (ordering + symbolic + numeric + solve, as the floor times them).
#[test]
#[ignore = "measurement: run by hand with --release --nocapture"]
fn measure_floor_kernels() {
    use crate::linalg::{fill_reducing_order, Layout};
    use faer::sparse::linalg::cholesky::SymbolicCholeskyRaw;
    let scenes = std::env::var("SIGNORINI_MEASURE_SCENES").unwrap_or_default();
    let reps = reps();
    println!("| scene | n | supernodal s | faer's choice | its s | choice ÷ supernodal |");
    println!("|---|---:|---:|---|---:|---:|");
    for path in scenes.split_whitespace() {
        let qp = scene_qp(path);
        let a = crate::solve::floor_matrix(&qp);
        let a = a.as_ref().unwrap_or(&qp.stiffness);
        let mut best = [f64::MAX; 2];
        let mut chosen = "";
        for _ in 0..reps {
            for (k, layout) in [Layout::Supernodal, Layout::FaerChoice]
                .into_iter()
                .enumerate()
            {
                let t = Instant::now();
                let ordering = fill_reducing_order(a).unwrap();
                let pattern = CholeskyPattern::analyse_laid_out(a, &ordering, layout).unwrap();
                let mut x = qp.load.clone();
                pattern.factor(a).unwrap().solve_in_place(&mut x);
                best[k] = best[k].min(t.elapsed().as_secs_f64());
                if layout == Layout::FaerChoice {
                    chosen = match pattern.symbolic().raw() {
                        SymbolicCholeskyRaw::Supernodal(_) => "supernodal",
                        SymbolicCholeskyRaw::Simplicial(_) => "simplicial",
                    };
                }
            }
        }
        println!(
            "| {path} | {} | {:.4} | {chosen} | {:.4} | {:.2} |",
            a.rows(),
            best[0],
            best[1],
            best[1] / best[0]
        );
    }
}

/// The scene at `path`, meshed and assembled with the default limits: its QP.
fn scene_qp(path: &str) -> crate::qp::QpProblem {
    let scene = Scene::from_path(std::path::Path::new(path)).unwrap();
    let meshes = model::mesh_scene(&scene, &MeshLimits::default()).unwrap();
    model::assemble(&scene, meshes).unwrap().qp
}

/// Repetitions per measurement: `SIGNORINI_MEASURE_REPS`, default 5.
fn reps() -> usize {
    std::env::var("SIGNORINI_MEASURE_REPS")
        .ok()
        .and_then(|r| r.parse().ok())
        .unwrap_or(5)
}
