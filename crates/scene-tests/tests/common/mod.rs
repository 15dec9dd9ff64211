//! What the scene-based backend tests share: the long-interface strip of issue 9, and one
//! solve with the core's checked status.
#![allow(dead_code, clippy::unwrap_used)]

use signorini_core::mesh::MeshLimits;
use signorini_core::model::{assemble, mesh_scene};
use signorini_core::scene::Scene;
use signorini_core::solve::ScaledQp;
use signorini_qp::{QpBackend, QpProblem, QpSolution, QpStatus};

/// Solves with `backend` at `tol` and returns the solution with the checked status.
pub fn solve(backend: &mut dyn QpBackend, problem: &QpProblem, tol: f64) -> (QpSolution, QpStatus) {
    solve_in(backend, problem, tol, Units::Own)
}

pub use signorini_qp::examples::Units;

/// [`solve`] in the chosen units.
pub fn solve_in(
    backend: &mut dyn QpBackend,
    problem: &QpProblem,
    tol: f64,
    units: Units,
) -> (QpSolution, QpStatus) {
    signorini_qp::examples::solve_checked(backend, problem, tol, units).unwrap()
}

/// max |x − reference| / max |reference|.
pub fn rel_diff(reference: &[f64], x: &[f64]) -> f64 {
    signorini_qp::examples::rel_diff(x, reference)
}

/// The sizes of a strip scene: a `length` × `strip` strip on a `length` × `foundation`
/// foundation, the interface at y = 1, both meshed with `hmax`, contact searched within
/// `band` of the interface.
#[derive(Debug, Clone, Copy)]
pub struct StripSizes {
    /// Length of strip and foundation.
    pub length: f64,
    /// Largest element edge of both bodies.
    pub hmax: f64,
    /// The strip's thickness.
    pub strip: f64,
    /// The foundation's thickness.
    pub foundation: f64,
    /// Half-height of the contact region around the interface.
    pub band: f64,
}

impl StripSizes {
    /// The long-interface strip of issue 9: `length` × 0.02 on `length` × 0.04, hmax 0.01.
    pub fn issue9(length: f64) -> Self {
        Self {
            length,
            hmax: 0.01,
            strip: 0.02,
            foundation: 0.04,
            band: 0.01,
        }
    }
}

/// The long-interface strip of issue 9 ([`StripSizes::issue9`]), E = 1, ν = 0.3; the strip
/// held at its left end (both components when `clamped`, else x only, so that contact alone
/// holds it in y) and pressed by a traction −1e-3 on its top over x ∈ [load.0, load.1];
/// contact on the whole interface.
pub fn strip_scene(length: f64, clamped: bool, load: (f64, f64)) -> Scene {
    strip_scene_of(StripSizes::issue9(length), clamped, load)
}

/// [`strip_scene`] with any sizes: the foundation held at its base, E = 1, ν = 0.3.
pub fn strip_scene_of(sizes: StripSizes, clamped: bool, load: (f64, f64)) -> Scene {
    let StripSizes {
        length,
        hmax,
        strip,
        foundation,
        band,
    } = sizes;
    let (top, bottom) = (1.0 + strip, 1.0 - foundation);
    let (band_low, band_high) = (1.0 - band, 1.0 + band);
    let (load_from, load_to) = load;
    let components = if clamped { "" } else { "components = [\"x\"]" };
    let toml = format!(
        r#"
title = "strip"
[[body]]
name = "strip"
polygon = [[0, 1], [{length}, 1], [{length}, {top}], [0, {top}]]
hmax = {hmax}
young = 1.0
poisson = 0.3
[[body]]
name = "foundation"
polygon = [[0, {bottom}], [{length}, {bottom}], [{length}, 1], [0, 1]]
hmax = {hmax}
young = 1.0
poisson = 0.3
[[dirichlet]]
body = "foundation"
region = [0, {length}, {bottom}, {bottom}]
[[dirichlet]]
body = "strip"
region = [0, 0, 1, {top}]
{components}
[[neumann]]
body = "strip"
region = [{load_from}, {load_to}, {top}, {top}]
traction = [0, -1e-3]
[[contact]]
bodies = ["strip", "foundation"]
region = [0, {length}, {band_low}, {band_high}]
"#
    );
    Scene::from_toml(&toml).unwrap()
}

/// [`strip_scene`]'s QP in the scene's units.
pub fn strip_qp(length: f64, clamped: bool, load: (f64, f64)) -> QpProblem {
    qp_of(&strip_scene(length, clamped, load))
}

/// A scene's QP in its own units: meshed with the default limits and assembled.
pub fn qp_of(scene: &Scene) -> QpProblem {
    let meshes = mesh_scene(scene, &MeshLimits::default()).unwrap();
    assemble(scene, meshes).unwrap().qp
}

/// [`strip_qp`] nondimensionalised, as the backends see it.
pub fn strip_scaled(length: f64, clamped: bool, load: (f64, f64)) -> QpProblem {
    ScaledQp::new(strip_qp(length, clamped, load)).problem
}
