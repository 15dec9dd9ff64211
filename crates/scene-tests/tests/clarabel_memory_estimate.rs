//! clarabel's memory estimate against the factor clarabel really builds: its own AMD ordering
//! and QDLDL's symbolic factorisation (`clarabel::qdldl`, logical only) of the same KKT
//! pattern count nnz(L) independently of the faer analysis the estimate uses.
#![allow(clippy::unwrap_used)]

use clarabel::algebra::CscMatrix as ClarabelCsc;
use clarabel::qdldl::{QDLDLFactorisation, QDLDLSettingsBuilder};
use signorini_core::mesh::MeshLimits;
use signorini_core::model;
use signorini_core::scene::Scene;
use signorini_qp::linalg::kkt::kkt_pattern;
use signorini_qp::QpProblem;

/// The seed's Experiment 3 (two bodies, both meshed) at `hmax`, assembled.
fn seed_qp(hmax: &str) -> QpProblem {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../fixtures/seed/exp3-both-h0.08.toml"
    );
    let text = std::fs::read_to_string(path).unwrap();
    let scene = Scene::from_toml(&text.replace("hmax = 0.08", &format!("hmax = {hmax}"))).unwrap();
    let meshes = model::mesh_scene(&scene, &MeshLimits::default()).unwrap();
    model::assemble(&scene, meshes).unwrap().qp
}

/// nnz(L) (strictly lower, as QDLDL stores it) of clarabel's own factor of the KKT pattern.
fn qdldl_nnz_l(qp: &QpProblem) -> usize {
    let lower = kkt_pattern(&qp.stiffness, &qp.constraints).unwrap();
    let upper = lower.transpose_view().to_csc();
    let (colptr, rowval, nzval) = upper.into_raw_storage();
    let n = colptr.len() - 1;
    let k = ClarabelCsc::new(n, n, colptr, rowval, nzval);
    let settings = QDLDLSettingsBuilder::default()
        .logical(true)
        .build()
        .unwrap();
    QDLDLFactorisation::<f64>::new(&k, Some(settings))
        .unwrap()
        .nnzL()
}

#[test]
fn the_kkt_factor_estimate_matches_clarabels_factor_within_a_quarter() {
    for hmax in ["0.08", "0.04"] {
        let qp = seed_qp(hmax);
        let estimate = signorini_clarabel::memory_need(&qp).unwrap();
        let nnz_l = qdldl_nnz_l(&qp);
        let dim = qp.dofs() + qp.rows();
        assert_eq!(estimate.dim, dim);
        // The estimate counts nnz(L) under faer's AMD, QDLDL under clarabel's port of
        // SuiteSparse AMD: two minimum-degree heuristics whose fill differs by some per cent
        // (measured: equal to 1 % on both meshes); 25 % either way is the stated bound.
        let qdldl_values = nnz_l + dim;
        let ratio = estimate.nnz_l as f64 / qdldl_values as f64;
        assert!(
            (0.8..1.25).contains(&ratio),
            "hmax {hmax}: nnz(L) {} against QDLDL's {qdldl_values}",
            estimate.nnz_l
        );
        // QDLDL holds 16 B per nonzero (Lx, Li): the priced factor covers it within 25 %.
        assert!(estimate.factor >= 0.8 * 16.0 * qdldl_values as f64);
        eprintln!("hmax {hmax}: n + m = {dim}, QDLDL nnz(L) = {nnz_l}, ratio {ratio:.2}");
    }
}
