//! What the scene-based backend tests share: the long-interface strip of issue 9, and one
//! solve with the core's checked status.
#![allow(dead_code, clippy::unwrap_used)]

use signorini_core::mesh::MeshLimits;
use signorini_core::model::{assemble, mesh_scene};
use signorini_core::scene::Scene;
use signorini_core::solve::ScaledQp;
use signorini_qp::{
    checked_status, kkt_residuals, QpBackend, QpProblem, QpSolution, QpStatus, SolveOptions,
};

/// Solves with `backend` at `tol` and returns the solution with the checked status.
pub fn solve(backend: &mut dyn QpBackend, problem: &QpProblem, tol: f64) -> (QpSolution, QpStatus) {
    solve_in(backend, problem, tol, Units::Own)
}

/// The units a test solves in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Units {
    /// `QpBackend::solve`: nondimensionalised first (what the driver hands every backend).
    Own,
    /// `QpBackend::solve_in_given_units`: the problem as built, in the scene's units.
    Given,
}

/// [`solve`] in the chosen units.
pub fn solve_in(
    backend: &mut dyn QpBackend,
    problem: &QpProblem,
    tol: f64,
    units: Units,
) -> (QpSolution, QpStatus) {
    let options = SolveOptions {
        tol,
        ..SolveOptions::default()
    };
    let sol = match units {
        Units::Own => backend.solve(problem, &options),
        Units::Given => backend.solve_in_given_units(problem, &options),
    }
    .unwrap();
    let r = kkt_residuals(problem, &sol.x, &sol.multipliers);
    let status = checked_status(sol.status, &r, tol);
    (sol, status)
}

/// max |x − reference| / max |reference|.
pub fn rel_diff(reference: &[f64], x: &[f64]) -> f64 {
    signorini_qp::examples::rel_diff(x, reference)
}

/// The long-interface strip of issue 9: `length` × 0.02 on a `length` × 0.04 foundation held at
/// its base, hmax 0.01, E = 1, ν = 0.3; the strip held at its left end (both components when
/// `clamped`, else x only, so that contact alone holds it in y) and pressed by a traction
/// −1e-3 on its top over x ∈ [load.0, load.1]; contact on the whole interface.
pub fn strip_scene(length: f64, clamped: bool, load: (f64, f64)) -> Scene {
    let (load_from, load_to) = load;
    let components = if clamped { "" } else { "components = [\"x\"]" };
    let toml = format!(
        r#"
title = "strip"
[[body]]
name = "strip"
polygon = [[0, 1], [{length}, 1], [{length}, 1.02], [0, 1.02]]
hmax = 0.01
young = 1.0
poisson = 0.3
[[body]]
name = "foundation"
polygon = [[0, 0.96], [{length}, 0.96], [{length}, 1], [0, 1]]
hmax = 0.01
young = 1.0
poisson = 0.3
[[dirichlet]]
body = "foundation"
region = [0, {length}, 0.96, 0.96]
[[dirichlet]]
body = "strip"
region = [0, 0, 1, 1.02]
{components}
[[neumann]]
body = "strip"
region = [{load_from}, {load_to}, 1.02, 1.02]
traction = [0, -1e-3]
[[contact]]
bodies = ["strip", "foundation"]
region = [0, {length}, 0.99, 1.01]
"#
    );
    Scene::from_toml(&toml).unwrap()
}

/// [`strip_scene`]'s QP in the scene's units.
pub fn strip_qp(length: f64, clamped: bool, load: (f64, f64)) -> QpProblem {
    let scene = strip_scene(length, clamped, load);
    let meshes = mesh_scene(&scene, &MeshLimits::default()).unwrap();
    assemble(&scene, meshes).unwrap().qp
}

/// [`strip_qp`] nondimensionalised, as the backends see it.
pub fn strip_scaled(length: f64, clamped: bool, load: (f64, f64)) -> QpProblem {
    ScaledQp::new(strip_qp(length, clamped, load)).problem
}
