//! What a sweep runs: the plan, its grid in plan order (hmax coarse to fine, tolerances tightest
//! first, backends as given), each point's number in it, and the plan's checks against the scene.

use std::time::Duration;

use signorini_core::mesh::{estimate_elements_refined, MeshLimits};
use signorini_core::scene::Scene;

use super::shard::Shard;
use super::{Point, SweepError};
use crate::backends::BackendKind;

/// What to sweep.
#[derive(Debug, Clone)]
pub struct SweepPlan {
    /// Mesh sizes (any order; run coarse to fine).
    pub hmax: Vec<f64>,
    /// Bodies whose hmax is swept (empty: all).
    pub bodies: Vec<String>,
    /// Backends.
    pub backends: Vec<BackendKind>,
    /// Tolerances (any order; run tightest first).
    pub tols: Vec<f64>,
    /// Runs per point; medians are reported.
    pub repeat: usize,
    /// Wall-clock limit of one solve; a backend that exceeds it is skipped on finer meshes.
    pub time_limit: Option<Duration>,
    /// Keep the points of an existing `sweep.csv` (after verifying it) and run the others.
    pub resume: bool,
    /// Replace an existing `sweep.csv` (once the new sweep writes its first point).
    pub overwrite: bool,
    /// Run only this shard's points (see [`shard`]); `None`: every point.
    pub shard: Option<Shard>,
    /// Write each point's solution as `solutions/<point>.vtu` and the collection
    /// `solutions.pvd` (see [`SOLUTIONS_FILE`]).
    pub vtu: bool,
}

/// The plan's grid: hmax values, tolerances, backends, each in plan order.
pub(crate) type Grid = (Vec<f64>, Vec<f64>, Vec<BackendKind>);

/// The scene with hmax set for the named bodies (all when `bodies` is empty).  A body's
/// `[[body.refine]]` sizes scale with it (each keeps its ratio to the body's hmax), so a graded
/// mesh stays graded the same way at every point of the sweep.
pub fn with_hmax(scene: &Scene, bodies: &[String], hmax: f64) -> Scene {
    let mut s = scene.clone();
    for b in &mut s.bodies {
        if bodies.is_empty() || bodies.contains(&b.name) {
            let factor = hmax / b.hmax;
            for r in &mut b.refine {
                r.hmax *= factor;
            }
            b.hmax = hmax;
        }
    }
    s
}

/// A point's identity in the plan, `hmax|backend|tol`, for finding it again.
pub(crate) fn key(hmax: f64, backend: &str, tol: f64) -> String {
    format!("{hmax:e}|{backend}|{tol:e}")
}

/// The plan's grid: hmax coarse to fine, tolerances tightest first, backends in the given order;
/// duplicates dropped.
pub(crate) fn grid(plan: &SweepPlan) -> Grid {
    let mut hmaxes = plan.hmax.clone();
    hmaxes.sort_by(|a, b| b.total_cmp(a));
    hmaxes.dedup();
    let mut tols = plan.tols.clone();
    tols.sort_by(f64::total_cmp);
    tols.dedup();
    let mut backends: Vec<BackendKind> = Vec::new();
    for &b in &plan.backends {
        if !backends.contains(&b) {
            backends.push(b);
        }
    }
    (hmaxes, tols, backends)
}

/// Checks the plan against the scene without touching any file: at least one hmax, backend and
/// tolerance; hmax values positive and finite; tolerances in (0, 1); `repeat` ≥ 1; known body
/// names; not both `resume` and `overwrite`; and at every hmax an estimated total element count
/// (all bodies) within `limits.max_elements`.
pub fn validate_plan(
    scene: &Scene,
    plan: &SweepPlan,
    limits: &MeshLimits,
) -> Result<(), SweepError> {
    let plan_err = |m: String| Err(SweepError::Plan(m));
    if plan.hmax.is_empty() || plan.backends.is_empty() || plan.tols.is_empty() {
        return plan_err("a sweep needs at least one hmax, one backend and one tolerance".into());
    }
    if let Some(h) = plan.hmax.iter().find(|h| !(h.is_finite() && **h > 0.0)) {
        return plan_err(format!("--hmax values must be positive, got {h}"));
    }
    if let Some(t) = plan
        .tols
        .iter()
        .find(|t| !(t.is_finite() && **t > 0.0 && **t < 1.0))
    {
        return plan_err(format!("--tol values must lie in (0, 1), got {t}"));
    }
    if plan.repeat == 0 {
        return plan_err("--repeat must be at least 1, got 0".into());
    }
    if plan.resume && plan.overwrite {
        return plan_err("--resume and --overwrite exclude each other".into());
    }
    for name in &plan.bodies {
        if scene.body_index(name).is_none() {
            return plan_err(format!("--bodies names an unknown body \"{name}\""));
        }
    }
    // A body meshed by Gmsh has no hmax to sweep: every point would repeat its mesh.
    let swept =
        |b: &&signorini_core::scene::Body| plan.bodies.is_empty() || plan.bodies.contains(&b.name);
    if let Some(b) = scene
        .bodies
        .iter()
        .filter(swept)
        .find(|b| b.imported.is_some())
    {
        return plan_err(format!(
            "body \"{}\" takes its mesh from a file (`mesh`), so its hmax cannot be swept; name the polygon bodies to sweep with --bodies",
            b.name
        ));
    }
    for &h in &plan.hmax {
        let s = with_hmax(scene, &plan.bodies, h);
        let total = s
            .bodies
            .iter()
            .map(|b| estimate_elements_refined(&b.polygon, b.hmax, &b.refine, b.element))
            .fold(0usize, usize::saturating_add);
        if total > limits.max_elements {
            return plan_err(format!(
                "--hmax {h}: the scene would have ~{total} elements, more than --max-elements {}",
                limits.max_elements
            ));
        }
    }
    Ok(())
}

/// The number (from 1) of the point (hmax, backend, tol) in the plan order of `grid` (see
/// [`shard`]), if it is part of the grid.
pub(crate) fn plan_index(grid: &Grid, p: &Point) -> Option<usize> {
    let (hmaxes, tols, backends) = grid;
    let ih = hmaxes
        .iter()
        .position(|h| h.to_bits() == p.hmax.to_bits())?;
    let it = tols.iter().position(|t| t.to_bits() == p.tol.to_bits())?;
    let ib = backends.iter().position(|b| b.name() == p.backend)?;
    Some(1 + (ih * tols.len() + it) * backends.len() + ib)
}
