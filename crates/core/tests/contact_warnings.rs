//! Counted contact warnings and the assembly-time check of bodies held only by contact
//! (issue 8): what assembly could not do exactly is reported per pair, never hidden.

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used)]

use signorini_core::mesh::MeshLimits;
use signorini_core::model::{self, Model, ModelError, ModelWarning, NoRowReason};
use signorini_core::scene::Scene;

fn assemble(toml: &str) -> Result<Model, ModelError> {
    let scene = Scene::from_toml(toml).unwrap();
    let meshes = model::mesh_scene(&scene, &MeshLimits::default()).unwrap();
    model::assemble(&scene, meshes).map(|a| a.model)
}

/// A block on a clamped base, 0.5 above it (more than one hmax 0.2), with `block_support` and no
/// region box: the pair has no candidate node, so no row.
fn block_above_base(block_support: &str) -> String {
    format!(
        r#"
[[body]]
name = "block"
polygon = [[0.5, 1.5], [1.5, 1.5], [1.5, 2.5], [0.5, 2.5]]
hmax = 0.2
young = 1.0
poisson = 0.3
[[body]]
name = "base"
polygon = [[0, 0], [2, 0], [2, 1], [0, 1]]
hmax = 0.2
young = 1.0
poisson = 0.3
[[dirichlet]]
body = "base"
region = [0, 2, 0, 0]
{block_support}
[[neumann]]
body = "block"
region = [0.5, 1.5, 2.5, 2.5]
traction = [0, -1e-4]
[[contact]]
bodies = ["block", "base"]
"#
    )
}

/// Held only by contact, but the pair yields no row: refused at assembly (so `check` refuses it
/// too), naming the body and the pair.  Before, assembly accepted it and only the solve failed
/// (`SolveError::Floating`).
#[test]
fn body_held_only_by_contact_without_rows_is_refused() {
    let roller = "[[dirichlet]]\nbody = \"block\"\nregion = [1, 1, 2.5, 2.5]\ncomponents = [\"x\"]";
    let err = assemble(&block_above_base(roller)).unwrap_err();
    match &err {
        ModelError::NotHeld { body, modes, pairs } => {
            assert_eq!(body, "block");
            // The roller removes x translation; y translation and rotation remain.
            assert_eq!(*modes, 2);
            assert!(pairs.contains("#1"), "{pairs}");
        }
        other => panic!("unexpected {other:?}"),
    }
    let text = err.to_string();
    assert!(text.contains("\"block\"") && text.contains("#1"), "{text}");
}

/// The same pair with both bodies clamped: accepted, with a warning that the pair gave no row
/// (the driver printed this itself before; the message names the pair and the reason).
#[test]
fn pair_without_rows_is_a_warning() {
    let clamp = "[[dirichlet]]\nbody = \"block\"\nregion = [0.5, 1.5, 2.5, 2.5]";
    let model = assemble(&block_above_base(clamp)).unwrap();
    assert_eq!(model.rows(), 0);
    let w = model
        .warnings
        .iter()
        .find(|w| matches!(w, ModelWarning::NoContactRow { .. }))
        .unwrap();
    assert_eq!(
        *w,
        ModelWarning::NoContactRow {
            pair: 1,
            bodies: ["block".into(), "base".into()],
            reason: NoRowReason::NoCandidates,
        }
    );
    let text = w.to_string();
    assert!(
        text.starts_with("contact #1 (\"block\" – \"base\") gave no constraint row"),
        "{text}"
    );
    let json = serde_json::to_value(w).unwrap();
    assert_eq!(json["kind"], "no_contact_row");
    assert_eq!(json["reason"], "no_candidates");
    assert_eq!(json["pair"], 1);
}

/// A region box that reaches 0.06 down the lower's left edge catches its side nodes: the box's
/// bottom y = 0.94 is a mesh break point there, so the 0.06 piece gets two segments (hmax 0.05)
/// and side nodes at y = 0.97 and 0.94.  They face no segment of the upper and get no row —
/// counted.
#[test]
fn unmatched_slave_nodes_are_counted() {
    let model = assemble(
        r#"
[[body]]
name = "upper"
polygon = [[0, 1], [1, 1], [2, 1], [2, 2], [1, 2], [0, 2]]
hmax = 0.2
young = 1.0
poisson = 0.3
[[body]]
name = "lower"
polygon = [[1, 0], [3, 0], [3, 1], [2, 1], [1, 1]]
hmax = 0.05
young = 1.0
poisson = 0.3
[[dirichlet]]
body = "upper"
region = [0, 0, 1, 2]
[[dirichlet]]
body = "lower"
region = [3, 3, 0, 1]
[[contact]]
bodies = ["upper", "lower"]
region = [1, 2, 0.94, 1.01]
"#,
    )
    .unwrap();
    let pair = &model.contacts[0];
    assert_eq!(pair.slave, 1, "the finer lower body is the slave");
    // Candidates: the 21 top nodes x = 1, 1.05, …, 2 and the two side nodes.
    assert_eq!(pair.candidates, 23);
    assert_eq!(pair.rows.len(), 21);
    assert_eq!(pair.unmatched, 2);
    let w = model
        .warnings
        .iter()
        .find(|w| matches!(w, ModelWarning::UnmatchedNodes { .. }))
        .unwrap();
    assert_eq!(
        *w,
        ModelWarning::UnmatchedNodes {
            pair: 1,
            slave: "lower".into(),
            master: "upper".into(),
            nodes: 2,
            candidates: 23,
        }
    );
    assert_eq!(w.kind(), "unmatched_nodes");
    assert_eq!(w.pair(), Some(1));
}

/// The seed-like interface (exp2b geometry) gives no warning at all.
#[test]
fn clean_interface_has_no_warning() {
    let model = assemble(
        r#"
[[body]]
name = "upper"
polygon = [[0, 1], [1, 1], [2, 1], [2, 2], [1, 2], [0, 2]]
hmax = 0.2
young = 1.0
poisson = 0.3
[[body]]
name = "lower"
polygon = [[1, 0], [3, 0], [3, 1], [2, 1], [1, 1]]
hmax = 0.2
young = 1.0
poisson = 0.3
[[dirichlet]]
body = "upper"
region = [0, 0, 1, 2]
[[dirichlet]]
body = "lower"
region = [3, 3, 0, 1]
[[contact]]
bodies = ["upper", "lower"]
region = [1, 2, 0.99, 1.01]
"#,
    )
    .unwrap();
    assert_eq!(model.rows(), 6);
    assert!(model.warnings.is_empty(), "{:?}", model.warnings);
}
