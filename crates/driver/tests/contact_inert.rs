//! Inert contact rows (issue 8): rows whose every DOF is prescribed constrain nothing a solver
//! can change.  Assembly removes them (counted in a warning) before any backend runs, and
//! refuses the scene when the prescribed displacements themselves interpenetrate.

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used)]

use std::path::PathBuf;

use signorini_core::mesh::MeshLimits;
use signorini_core::model::{self, Model, ModelError, ModelWarning, NoRowReason};
use signorini_core::qp::{QpStatus, SolveOptions};
use signorini_core::scene::Scene;
use signorini_core::solve::solve_model;
use signorini_dual::DualBackend;

fn fixture_text(name: &str) -> String {
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("../../fixtures/hard/{name}.toml"));
    std::fs::read_to_string(path).unwrap()
}

fn assemble(scene: &Scene) -> Result<Model, ModelError> {
    assemble_qp(scene).map(|a| a.model)
}

fn assemble_qp(scene: &Scene) -> Result<model::Assembly, ModelError> {
    let meshes = model::mesh_scene(scene, &MeshLimits::default()).unwrap();
    model::assemble(scene, meshes)
}

/// Rows whose every DOF with a non-zero coefficient in B is prescribed.
fn all_fixed_rows(model: &Model) -> usize {
    let mut free_entry = vec![false; model.rows()];
    for (j, col) in model.constraints.outer_iterator().enumerate() {
        if model.fixed[j].is_none() {
            for (i, v) in col.iter() {
                if *v != 0.0 {
                    free_entry[i] = true;
                }
            }
        }
    }
    free_entry.iter().filter(|f| !**f).count()
}

/// `hard/inert-rows.toml`: both sides of the whole interface prescribed alike.  Before the fix
/// its 17 rows reached the backend with B_F = 0 and reduced gaps of ±1e-19 (round-off), and
/// dual-pgs reported `primal_infeasible` (zero dual diagonal: λ grows without bound on a row with
/// a tiny negative gap).  Now every row is removed as inert, with warnings, and the model solves.
#[test]
fn all_fixed_rows_are_removed_and_dual_pgs_solves() {
    let text = fixture_text("inert-rows");
    let scene = Scene::from_toml(&text).unwrap();
    let model::Assembly { model, qp } = assemble_qp(&scene).unwrap();
    // The same scene with the upper's slope free (same meshes: the upper's clamp box crosses
    // its polygon only at vertices) has every row live: the rows the inert scene removed.
    let free_upper = text.replacen(
        "[[dirichlet]]\nbody = \"upper\"\nregion = [1, 2.8, 1, 2]\nvalue = [0.00731, 0.0041]\n",
        "",
        1,
    );
    assert_ne!(free_upper, text);
    let live = assemble(&Scene::from_toml(&free_upper).unwrap()).unwrap();
    assert_eq!(live.rows(), 17);
    assert_eq!(all_fixed_rows(&live), 0);

    assert_eq!(model.rows(), 0, "every row is inert");
    assert!(model.warnings.iter().any(|w| matches!(
        w,
        ModelWarning::InertRows {
            pair: 1,
            rows: 17,
            ..
        }
    )));
    assert!(model.warnings.iter().any(|w| matches!(
        w,
        ModelWarning::NoContactRow {
            pair: 1,
            reason: NoRowReason::AllInert,
            ..
        }
    )));
    let mut pgs = DualBackend::pgs(Default::default());
    let options = SolveOptions {
        tol: 1e-10,
        ..SolveOptions::default()
    };
    let s = solve_model(&model, &qp, &mut pgs, &options).unwrap();
    assert_eq!(
        s.status,
        QpStatus::Solved,
        "{:?} {:?}",
        s.residuals,
        s.message
    );
    assert!(s.displacement.iter().all(|v| v.is_finite()));
    // Prescribed values are kept exactly.
    for (d, f) in model.fixed.iter().enumerate() {
        if let Some(v) = f {
            assert_eq!(s.displacement[d], *v);
        }
    }
}

/// Half the slope prescribed on both sides: those rows are removed, the rest stay live and
/// dual-pgs solves the QP; no remaining row is all-fixed.
#[test]
fn partly_fixed_interface_keeps_live_rows() {
    let text =
        fixture_text("inert-rows").replace("region = [1, 2.8, 1, 2]", "region = [1, 1.9, 1, 1.5]");
    let scene = Scene::from_toml(&text).unwrap();
    let model::Assembly { model, qp } = assemble_qp(&scene).unwrap();
    let removed = model
        .warnings
        .iter()
        .find_map(|w| match w {
            ModelWarning::InertRows { rows, first, .. } => Some((*rows, *first)),
            _ => None,
        })
        .unwrap();
    assert!(removed.0 > 0 && model.rows() > 0);
    // The first removed row's slave node lies in the common clamp box.
    assert!(removed.1[0] <= 1.9 + 1e-9 && removed.1[1] <= 1.5 + 1e-9);
    assert_eq!(all_fixed_rows(&model), 0);
    let mut pgs = DualBackend::pgs(Default::default());
    let s = solve_model(&model, &qp, &mut pgs, &SolveOptions::default()).unwrap();
    assert_eq!(
        s.status,
        QpStatus::Solved,
        "{:?} {:?}",
        s.residuals,
        s.message
    );
}

/// Both faces of a vertical interface prescribed, the left one moved +0.01 into the right one
/// moved −0.01: the supports alone interpenetrate by 0.02.  Refused, naming the pair and point.
#[test]
fn prescribed_interpenetration_is_refused() {
    let scene = Scene::from_toml(
        r#"
[[body]]
name = "left"
polygon = [[0, 0], [1, 0], [1, 1], [0, 1]]
hmax = 0.25
young = 1.0
poisson = 0.3
[[body]]
name = "right"
polygon = [[1, 0], [2, 0], [2, 1], [1, 1]]
hmax = 0.25
young = 1.0
poisson = 0.3
[[dirichlet]]
body = "left"
region = [1, 1, 0, 1]
value = [0.01, 0]
[[dirichlet]]
body = "right"
region = [1, 1, 0, 1]
value = [-0.01, 0]
[[contact]]
bodies = ["left", "right"]
region = [0.99, 1.01, 0, 1]
"#,
    )
    .unwrap();
    let err = assemble(&scene).unwrap_err();
    match &err {
        ModelError::PrescribedPenetration {
            pair, point, gap, ..
        } => {
            assert_eq!(*pair, 1);
            assert_eq!(point[0], 1.0);
            assert!((gap + 0.02).abs() < 1e-12, "reduced gap {gap}");
        }
        other => panic!("unexpected {other:?}"),
    }
    assert!(err.to_string().contains("contact #1"), "{err}");
}
