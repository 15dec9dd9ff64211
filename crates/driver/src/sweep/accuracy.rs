//! The error columns of `sweep.csv`: a point's distance to its mesh's reference
//! (`error_vs_reference`) and to the finest mesh (`error_vs_finest`, over the max displacement and
//! the probes), with the displacement measures they compare.

use std::collections::HashMap;

use signorini_core::report::interpolate;
use signorini_core::scene::Scene;

use super::Point;

/// The largest nodal displacement magnitude of `u` (pairs of components).
pub(super) fn max_displacement(u: &[f64]) -> f64 {
    u.chunks(2).map(|p| p[0].hypot(p[1])).fold(0.0, f64::max)
}

/// The `probes` column: each probe of `scene` as `name:ux:uy` (`{:e}`; NaN where a probe is
/// outside its body), joined by `;`.
pub(super) fn probes_text(
    scene: &Scene,
    model: &signorini_core::model::Model,
    u: &[f64],
) -> String {
    scene
        .probes
        .iter()
        .map(|p| {
            let d = model.body_displacements(p.body, u);
            let v = interpolate(&model.meshes[p.body], &d, p.point, scene.tolerance())
                .unwrap_or([f64::NAN, f64::NAN]);
            format!("{}:{:e}:{:e}", p.name, v[0], v[1])
        })
        .collect::<Vec<_>>()
        .join(";")
}

/// The `probes` column read back: name → displacement (unreadable items dropped).
fn parse_probes(text: &str) -> HashMap<String, [f64; 2]> {
    text.split(';')
        .filter_map(|item| {
            let mut parts = item.split(':');
            let name = parts.next()?.to_string();
            let ux = parts.next()?.parse().ok()?;
            let uy = parts.next()?.parse().ok()?;
            Some((name, [ux, uy]))
        })
        .collect()
}

/// `max |u − u_ref| / max |u_ref|` over the nodes: the `error_vs_reference` column.
pub(crate) fn error_vs(u_ref: &[f64], u: &[f64]) -> f64 {
    let scale = max_displacement(u_ref).max(f64::MIN_POSITIVE);
    u_ref
        .chunks(2)
        .zip(u.chunks(2))
        .map(|(a, b)| (a[0] - b[0]).hypot(a[1] - b[1]))
        .fold(0.0, f64::max)
        / scale
}

/// Whether a solved point at the tightest tolerance with worst residual `worst` becomes its
/// mesh's reference, replacing `current` (the reference so far, in plan order).
pub(crate) fn better_reference(current: Option<f64>, worst: f64) -> bool {
    current.is_none_or(|r| worst < r)
}

/// Fills `error_vs_finest`: for each point, the largest relative difference to the finest mesh's
/// most accurate solved point, over the max displacement and every probe displacement.
pub fn fill_error_vs_finest(points: &mut [Point]) {
    let finest = points
        .iter()
        .filter(|p| p.status == "solved")
        .min_by(|a, b| {
            a.hmax
                .total_cmp(&b.hmax)
                .then(a.tol.total_cmp(&b.tol))
                .then(a.stationarity.total_cmp(&b.stationarity))
        })
        .cloned();
    let Some(finest) = finest else { return };
    let reference_probes = parse_probes(&finest.probes);
    for p in points.iter_mut() {
        let mut err = (p.max_displacement - finest.max_displacement).abs()
            / finest.max_displacement.max(f64::MIN_POSITIVE);
        for (name, u) in parse_probes(&p.probes) {
            if let Some(r) = reference_probes.get(&name) {
                let scale = r[0].hypot(r[1]).max(finest.max_displacement * 1e-3);
                err = err.max((u[0] - r[0]).hypot(u[1] - r[1]) / scale);
            }
        }
        p.error_vs_finest = err.is_finite().then_some(err);
    }
}
