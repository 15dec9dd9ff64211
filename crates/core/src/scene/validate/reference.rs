//! `[reference]`: the scene's analytic answer — a contact pair, and a uniform pressure or a
//! Hertz half-width and peak pressure around a centre.

use super::values::{check_finite, exact, plural};
use crate::scene::file::ReferenceSection;
use crate::scene::types::{ContactPair, Reference};
use crate::scene::SceneError;

/// Checks `[reference]` against the scene's contact pairs.
pub(super) fn validate_reference(
    r: ReferenceSection,
    contacts: &[ContactPair],
) -> Result<Reference, SceneError> {
    let s = "[reference]";
    let pair = r.pair.unwrap_or(1);
    if pair == 0 || pair > contacts.len() {
        return Err(SceneError::invalid(
            s,
            "pair",
            format!(
                "= {pair} names no contact pair (the scene has {})",
                plural(contacts.len(), "pair", "pairs")
            ),
        ));
    }
    let centre = match &r.centre {
        None => None,
        Some(c) => {
            let c = exact::<2>(s, "centre", c)?;
            check_finite(s, "centre", &c)?;
            Some(c)
        }
    };
    for (key, value) in [
        ("half_width", r.half_width),
        ("peak_pressure", r.peak_pressure),
        ("pressure", r.pressure),
    ] {
        if let Some(v) = value {
            if !(v.is_finite() && v > 0.0) {
                return Err(SceneError::invalid(
                    s,
                    key,
                    format!("must be positive and finite, got {v}"),
                ));
            }
        }
    }
    if r.half_width.is_none() && r.peak_pressure.is_none() && r.pressure.is_none() {
        return Err(SceneError::invalid(
            s,
            "pressure",
            "is missing: a reference states `pressure` (uniform) or `half_width` / \
             `peak_pressure` (Hertz)",
        ));
    }
    if r.half_width.is_some() && centre.is_none() {
        return Err(SceneError::invalid(
            s,
            "centre",
            "is required with `half_width`: the half-width is measured from it",
        ));
    }
    Ok(Reference {
        pair: pair - 1,
        centre,
        half_width: r.half_width,
        peak_pressure: r.peak_pressure,
        pressure: r.pressure,
    })
}
