//! A long thin strip loaded on part of its length only (the scene of the issue's
//! strip-partial: a 20 × 0.02 strip floating in y on a 20 × 0.04 foundation, hmax 0.01,
//! traction on [8, 12]; 51 575 DOFs, 2001 contact rows).  Plain primal–dual active-set steps
//! flip tens of rows a step here and never settle (the contact Schur complement of a thin
//! strip is no M-matrix: releasing a row at the edge of the contact zone moves the strip far
//! away); before the interior-point continuation the backend stopped at `max-iterations`
//! after 100 steps (KKT residuals ~1e-2).
//!
//! The reference is an independent solve by a different algorithm: signorini's dual-ssn
//! backend (semismooth Newton on the dense condensed dual, `signorini solve
//! strip-partial.toml --backend dual-ssn`: solved, KKT residuals 3.0e-11, 789 steps) finds
//! the contact zone to be exactly rows 799..=1201 (403 rows, the loaded part plus one row on
//! each side), every other row open.  The set is a discrete fact, so it is compared exactly;
//! the answer itself is checked by the core's KKT residuals at the default tolerance 1e-9
//! (first-order conditions are sufficient for this convex QP, so meeting them bounds the
//! distance to the optimum).
#![allow(clippy::unwrap_used)]

mod common;

use common::solve;
use signorini_core::mesh::MeshLimits;
use signorini_core::model::{assemble, mesh_scene};
use signorini_core::scene::Scene;
use signorini_core::solve::ScaledQp;
use signorini_qp::{kkt_residuals, QpProblem, QpStatus};

fn strip_loaded_in_its_middle(clamped: bool) -> QpProblem {
    let components = if clamped { "" } else { "components = [\"x\"]" };
    let toml = format!(
        r#"
title = "strip loaded on [8, 12]"
[[body]]
name = "strip"
polygon = [[0, 1], [20, 1], [20, 1.02], [0, 1.02]]
hmax = 0.01
young = 1.0
poisson = 0.3
[[body]]
name = "foundation"
polygon = [[0, 0.96], [20, 0.96], [20, 1], [0, 1]]
hmax = 0.01
young = 1.0
poisson = 0.3
[[dirichlet]]
body = "foundation"
region = [0, 20, 0.96, 0.96]
[[dirichlet]]
body = "strip"
region = [0, 0, 1, 1.02]
{components}
[[neumann]]
body = "strip"
region = [8, 12, 1.02, 1.02]
traction = [0, -1e-3]
[[contact]]
bodies = ["strip", "foundation"]
region = [0, 20, 0.99, 1.01]
"#
    );
    let scene = Scene::from_toml(&toml).unwrap();
    let meshes = mesh_scene(&scene, &MeshLimits::default()).unwrap();
    ScaledQp::new(assemble(&scene, meshes).unwrap().qp).problem
}

#[test]
fn strip_loaded_on_part_of_its_length_is_solved() {
    let p = strip_loaded_in_its_middle(false);
    assert_eq!(p.rows(), 2001);
    let (sol, status) = solve(&p, 1e-9);
    assert_eq!(status, QpStatus::Solved, "{:?}", sol.message);
    assert_eq!(sol.status, QpStatus::Solved, "{:?}", sol.message);
    let r = kkt_residuals(&p, &sol.x, &sol.multipliers);
    assert!(r.meet(1e-9), "{r:?}");
    let active: Vec<usize> = (0..p.rows())
        .filter(|&i| sol.multipliers[i] > 0.0)
        .collect();
    assert_eq!(
        active,
        (799..=1201).collect::<Vec<_>>(),
        "{:?}",
        sol.message
    );
}

/// The same strip clamped at its left end (A positive definite, no kernel; plain steps flip
/// here too), checked by the core's KKT residuals only (no independent reference run).
#[test]
fn clamped_strip_loaded_on_part_of_its_length_is_solved() {
    let p = strip_loaded_in_its_middle(true);
    let (sol, status) = solve(&p, 1e-9);
    assert_eq!(status, QpStatus::Solved, "{:?}", sol.message);
    let r = kkt_residuals(&p, &sol.x, &sol.multipliers);
    assert!(r.meet(1e-9), "{r:?}");
}
