//! The measurement behind the ordering rule of [`super::ordering`] (run by hand; prints a
//! Markdown table):
//!
//! ```text
//! SIGNORINI_MEASURE_SCENES="a.toml b.toml" \
//!   cargo test --release -p signorini-core --lib linalg::measure -- --ignored --nocapture
//! ```
//!
//! For each scene: mesh, assemble, then for AMD and METIS the ordering, the symbolic analysis
//! and the numeric LLᵀ (forced supernodal, one thread) of the reduced stiffness A, timed apart,
//! with nnz(L).  A singular A (a body held by contact only) gets the floor's diagonal shift.
#![cfg(test)]
#![allow(clippy::unwrap_used)]

use std::time::Instant;

use super::{order_with, CholeskyPattern, OrderingMethod};
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
        let a = crate::solve::floor_matrix(&qp);
        let a = a.as_ref().unwrap_or(&qp.stiffness);
        let name = std::path::Path::new(path)
            .file_stem()
            .unwrap()
            .to_string_lossy()
            .to_string();
        for method in [OrderingMethod::Amd, OrderingMethod::Metis] {
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
            let info = chol.info();
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
        }
    }
}
