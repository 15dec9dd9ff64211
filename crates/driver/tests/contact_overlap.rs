//! Initial overlap of two bodies in a contact pair (issue 8): slave nodes that start inside the
//! master get rows with negative gaps that push them out, a warning names the pair and the
//! deepest node, overlaps deeper than the pair's larger hmax are refused, and no row projects a
//! node through the master onto its far side.

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used)]

use std::path::PathBuf;

use signorini_core::contact::ContactError;
use signorini_core::mesh::MeshLimits;
use signorini_core::model::{self, Model, ModelError, ModelWarning};
use signorini_core::qp::{mat_vec, QpStatus, SolveOptions};
use signorini_core::scene::Scene;
use signorini_core::solve::solve_model;
use signorini_dual::DualBackend;

fn fixture(name: &str) -> Scene {
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("../../fixtures/hard/{name}.toml"));
    Scene::from_path(&path).unwrap()
}

fn assemble(scene: &Scene) -> Result<Model, ModelError> {
    assemble_qp(scene).map(|a| a.model)
}

fn assemble_qp(scene: &Scene) -> Result<model::Assembly, ModelError> {
    let meshes = model::mesh_scene(scene, &MeshLimits::default()).unwrap();
    model::assemble(scene, meshes)
}

/// Two blocks, `lower` = [0,2]×[0,1] clamped at its bottom and `upper` (polygon given) clamped
/// at its top y = 1.95, in one contact pair (`pair` holds extra keys); hmax 0.2 unless given.
fn two_blocks(upper: &str, upper_hmax: f64, pair: &str) -> Scene {
    Scene::from_toml(&format!(
        r#"
[[body]]
name = "upper"
polygon = {upper}
hmax = {upper_hmax}
young = 1.0
poisson = 0.3
[[body]]
name = "lower"
polygon = [[0, 0], [2, 0], [2, 1], [0, 1]]
hmax = 0.2
young = 1.0
poisson = 0.3
[[dirichlet]]
body = "lower"
region = [-10, 10, 0, 0]
[[dirichlet]]
body = "upper"
region = [-10, 10, 1.95, 1.95]
[[contact]]
bodies = ["upper", "lower"]
{pair}
"#
    ))
    .unwrap()
}

fn overlap_warning(model: &Model) -> &ModelWarning {
    model
        .warnings
        .iter()
        .find(|w| matches!(w, ModelWarning::InitialOverlap { .. }))
        .unwrap()
}

/// Constrained (uniaxial-strain) modulus in plane strain: σ_yy = M ε_yy when ε_xx = 0.
fn constrained_modulus(young: f64, nu: f64) -> f64 {
    young * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu))
}

/// The fixture `hard/initial-overlap.toml` has an exact answer (uniform uniaxial strain, which
/// P1 elements reproduce exactly): the overlap is undone, every row ends at gap 0, and the
/// displacements are the analytic ones.  Before the fix the upper block's side nodes at
/// y = 1 (on the lower's corners) got rows projected through the lower onto its opposite side
/// edge (gap −1 against two rollers: infeasible).
#[test]
fn overlap_is_pushed_out_to_the_exact_answer() {
    let scene = fixture("initial-overlap");
    let model::Assembly { model, qp } = assemble_qp(&scene).unwrap();
    let lower = 1;
    assert_eq!(
        model.rows(),
        5,
        "one row per bottom node of the upper block"
    );
    let delta = 0.05;
    for r in &model.contacts[0].rows {
        assert!(
            (r.gap + delta).abs() < 1e-12,
            "gap {} at {:?}",
            r.gap,
            r.position
        );
    }
    match overlap_warning(&model) {
        ModelWarning::InitialOverlap {
            pair, nodes, depth, ..
        } => {
            assert_eq!(*pair, 1);
            // The three interior bottom nodes x = 0.75, 1, 1.25 lie strictly inside; the corners
            // lie on the lower's side edges.
            assert_eq!(*nodes, 3);
            assert!((depth - delta).abs() < 1e-12);
        }
        _ => unreachable!(),
    }
    let p = 1e-5;
    let m_upper = constrained_modulus(0.0021, 0.3);
    let m_lower = constrained_modulus(0.0012, 0.34);
    // KKT tolerance 1e-12; the displacement scale is delta = 0.05 and the conditioning of this
    // 2×(5×5-node) problem is modest (~1e4), so 1e-9 absolute leaves a wide margin while any
    // real error (a missed or dropped row: error ≥ 1e-3) fails by orders of magnitude.
    let options = SolveOptions {
        tol: 1e-12,
        ..SolveOptions::default()
    };
    for mut backend in [
        DualBackend::active_set(Default::default()),
        DualBackend::pgs(Default::default()),
    ] {
        let s = solve_model(&model, &qp, &mut backend, &options).unwrap();
        assert_eq!(
            s.status,
            QpStatus::Solved,
            "{:?} {:?}",
            s.residuals,
            s.message
        );
        let u = &s.displacement;
        for (b, mesh) in model.meshes.iter().enumerate() {
            for (i, x) in mesh.nodes.iter().enumerate() {
                let exact_uy = if b == lower {
                    -p * x[1] / m_lower
                } else {
                    delta - p / m_lower - p * (x[1] - 0.95) / m_upper
                };
                let ux = u[model.dofs.dof(b, i, 0)];
                let uy = u[model.dofs.dof(b, i, 1)];
                assert!(ux.abs() < 1e-9, "body {b} node {x:?}: ux {ux}");
                assert!(
                    (uy - exact_uy).abs() < 1e-9,
                    "body {b} node {x:?}: uy {uy}, exact {exact_uy}"
                );
            }
        }
        // Final gaps g − B u: zero on every row (all active), never negative.
        let bu = mat_vec(&model.constraints, u);
        for (g, b) in model.gap.iter().zip(&bu) {
            assert!((g - b).abs() < 1e-9, "final gap {}", g - b);
        }
        assert!(s.residuals.max_penetration < 1e-9);
        // The contact is the upper block's only vertical support: Σλ = p × width (1).
        let total: f64 = s.multipliers.iter().sum();
        assert!((total - p).abs() < 1e-6 * p, "contact force {total}");
    }
}

/// A narrower upper block sunk 0.05 into the lower: every bottom node starts inside and gets a
/// row with gap −0.05; its side nodes at y = 0.95 (hmax 0.1) start inside too and are pushed
/// out through the lower's top (the closest way out), not onto the lower's far side edges; the
/// warning counts them.
#[test]
fn side_nodes_inside_get_the_shortest_way_out() {
    let scene = two_blocks(
        "[[0.5, 0.85], [1.5, 0.85], [1.5, 1.95], [0.5, 1.95]]",
        0.1,
        "",
    );
    let model = assemble(&scene).unwrap();
    let pair = &model.contacts[0];
    assert_eq!(pair.slave, 0, "the finer upper block has more candidates");
    // Bottom y = 0.85: 11 nodes at depth 0.15; sides x = 0.5, 1.5: nodes at y = 0.95 at depth
    // 0.05.  All 13 start inside and each has a row whose gap is minus its depth, with the
    // lower's top normal (0, 1).
    let inside: Vec<_> = pair.rows.iter().filter(|r| r.position[1] < 1.0).collect();
    assert_eq!(inside.len(), 13);
    for r in &inside {
        assert_eq!(r.normal, [0.0, 1.0], "{:?}", r.position);
        assert!((r.gap - (r.position[1] - 1.0)).abs() < 1e-12, "{:?}", r);
    }
    match overlap_warning(&model) {
        ModelWarning::InitialOverlap {
            nodes,
            depth,
            deepest,
            deepest_body,
            ..
        } => {
            assert_eq!(*nodes, 13);
            assert!((depth - 0.15).abs() < 1e-12);
            assert!((deepest[1] - 0.85).abs() < 1e-12);
            assert_eq!(deepest_body, "upper");
        }
        _ => unreachable!(),
    }
    // The two side nodes have no slave edge facing the lower's top: their tributary length is a
    // fallback, and counted.
    assert!(model.warnings.iter().any(|w| matches!(
        w,
        ModelWarning::TributaryFallback {
            rows: 2,
            unit_length: 0,
            ..
        }
    )));
    let text = overlap_warning(&model).to_string();
    assert!(
        text.contains("contact #1") && text.contains("(0.5, 0.85)"),
        "{text}"
    );
}

/// The whole width overlapping: the upper's side nodes at y = 1 sit on the lower's corners; the
/// only "facing" segments for them are the lower's far side edges (2 away).  No such row.
#[test]
fn no_row_projects_through_the_master() {
    let scene = two_blocks("[[0, 0.95], [2, 0.95], [2, 1.95], [0, 1.95]]", 0.2, "");
    let model = assemble(&scene).unwrap();
    for r in &model.contacts[0].rows {
        assert!(r.gap >= -0.05 - 1e-12, "row {:?}", r);
    }
    assert_eq!(model.rows(), 11, "the 11 bottom nodes of the upper block");
    // The side nodes within one hmax of the lower (at its corners y = 1, and the next one up
    // on each side) face no segment: counted, not hidden.
    assert!(model.warnings.iter().any(|w| matches!(
        w,
        ModelWarning::UnmatchedNodes {
            nodes: 4,
            candidates: 15,
            ..
        }
    )));
}

/// Overlap deeper than the pair's larger hmax (0.45 > 0.2): refused, naming pair and place.
/// Before the fix no node was a candidate (none within one hmax of the other's boundary): the
/// pair silently gave no row and the bodies stayed interpenetrating.
#[test]
fn deep_overlap_is_refused() {
    let scene = two_blocks(
        "[[0.5, 0.55], [1.5, 0.55], [1.5, 1.95], [0.5, 1.95]]",
        0.2,
        "",
    );
    let err = assemble(&scene).unwrap_err();
    match &err {
        ModelError::Contact(ContactError::DeepOverlap {
            pair,
            body,
            other,
            point,
            depth,
            limit,
        }) => {
            assert_eq!(*pair, 1);
            assert_eq!((body.as_str(), other.as_str()), ("upper", "lower"));
            assert!((point[1] - 0.55).abs() < 1e-12);
            assert!((depth - 0.45).abs() < 1e-12);
            assert_eq!(*limit, 0.2);
        }
        other => panic!("unexpected {other:?}"),
    }
    let text = err.to_string();
    assert!(
        text.contains("contact #1") && text.contains("upper"),
        "{text}"
    );
}

/// An overlap within the limit but partly outside the pair's region box: the slave nodes inside
/// the master beyond the box can get no row, so the scene is refused.
#[test]
fn overlap_outside_the_region_is_refused() {
    let scene = two_blocks(
        "[[0.5, 0.95], [1.5, 0.95], [1.5, 1.95], [0.5, 1.95]]",
        0.2,
        "region = [0.5, 1.0, 0.9, 1.01]\nslave = \"upper\"",
    );
    match assemble(&scene).unwrap_err() {
        ModelError::Contact(ContactError::OverlapOutsideRegion {
            pair,
            slave,
            nodes,
            point,
            ..
        }) => {
            assert_eq!(pair, 1);
            assert_eq!(slave, "upper");
            // Bottom nodes x = 1.1, 1.3, 1.5 lie beyond the box, all strictly inside the lower
            // (which spans [0, 2]), so all three start inside without a row.
            assert_eq!(nodes, 3);
            assert!(point[0] > 1.0 && (point[1] - 0.95).abs() < 1e-12);
        }
        other => panic!("unexpected {other:?}"),
    }
}

/// Scenes without overlap get no overlap warning (and the seed-like interface is unchanged).
#[test]
fn touching_bodies_have_no_overlap_warning() {
    let scene = two_blocks("[[0.5, 1], [1.5, 1], [1.5, 1.95], [0.5, 1.95]]", 0.2, "");
    let model = assemble(&scene).unwrap();
    assert!(model
        .warnings
        .iter()
        .all(|w| !matches!(w, ModelWarning::InitialOverlap { .. })));
    assert!(model.contacts[0].rows.iter().all(|r| r.gap == 0.0));
}

#[test]
fn an_overlap_only_the_master_makes_is_refused_or_turned_round() {
    // A small block poking 1.5 into the side of a large one whose boundary nodes are 45 apart
    // (found by the fuzz harness): no node of the large body lies inside the small one, so with
    // the large body as slave no row could push the small one out, and it used to be `solved`
    // with the bodies interpenetrating.
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fuzz-cases/interpenetration-initial-overlap.toml");
    let text = std::fs::read_to_string(path).expect("fuzz case");
    assert!(text.contains("slave = \"b0\""));
    let scene = Scene::from_toml(&text).expect("valid scene");
    match assemble(&scene) {
        Err(ModelError::Contact(ContactError::MasterInsideSlave { master, nodes, .. })) => {
            assert_eq!(master, "b1");
            assert!(nodes > 0);
        }
        other => panic!("expected MasterInsideSlave, got {other:?}"),
    }
    // Without a named slave, the body whose nodes start inside the other becomes the slave.
    let scene = Scene::from_toml(&text.replace("slave = \"b0\"", "")).expect("valid scene");
    let model = assemble(&scene).expect("assembles");
    assert_eq!(model.contacts[0].slave, 1, "b1 is the slave");
    assert!(
        model.gap.iter().any(|g| *g < 0.0),
        "rows with negative gaps push it out"
    );
}
