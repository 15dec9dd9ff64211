//! The one threshold of active contact (docs/scene.md, "Active contact"): result.json's
//! `active`, the VTU's pressure, the SVG's contact edges and the friction states use it.

use crate::model::Model;
use crate::solve::Solution;

/// A row counts as active when its multiplier exceeds 10⁻⁶ of the force scale (the larger of the
/// largest multiplier and the total applied load), so round-off multipliers never count.
pub fn is_active(multiplier: f64, force_scale: f64) -> bool {
    multiplier > 1e-6 * force_scale && multiplier > 0.0
}

/// The force scale of [`is_active`] for a solution: the larger of the largest normal multiplier
/// and the total applied load Σ|fᵢ|.
pub fn active_scale(model: &Model, solution: &Solution) -> f64 {
    solution
        .multipliers
        .iter()
        .take(model.normal_rows())
        .copied()
        .fold(0.0, f64::max)
        .max(model.load.iter().map(|f| f.abs()).sum())
}
