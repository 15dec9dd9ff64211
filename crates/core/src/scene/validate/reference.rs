//! `[reference]`: the scene's analytic answer — a contact pair, and a uniform pressure, a Hertz
//! half-width and peak pressure around a centre, or Cattaneo–Mindlin partial slip (radius,
//! contact modulus and Coulomb's μ) around a centre.

use super::values::{check_finite, exact, plural};
use crate::scene::file::ReferenceSection;
use crate::scene::types::{Cattaneo, ContactPair, Friction, Reference};
use crate::scene::SceneError;

const SECTION: &str = "[reference]";

/// Checks `[reference]` against the scene's contact pairs.
pub(super) fn validate_reference(
    r: ReferenceSection,
    contacts: &[ContactPair],
) -> Result<Reference, SceneError> {
    let s = SECTION;
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
        ("radius", r.radius),
        ("contact_modulus", r.contact_modulus),
        ("friction", r.friction),
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
    let cattaneo = cattaneo(&r, centre.is_some(), &contacts[pair - 1], pair)?;
    if cattaneo.is_none()
        && r.half_width.is_none()
        && r.peak_pressure.is_none()
        && r.pressure.is_none()
    {
        return Err(SceneError::invalid(
            s,
            "pressure",
            "is missing: a reference states `pressure` (uniform), `half_width` / \
             `peak_pressure` (Hertz) or `radius`, `contact_modulus` and `friction` \
             (Cattaneo–Mindlin)",
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
        cattaneo,
    })
}

/// The Cattaneo–Mindlin reference, when any of its keys is given: all three of `radius`,
/// `contact_modulus` and `friction`, a `centre`, none of the other references' values, and a
/// pair with Coulomb friction of that μ.  (Values were checked positive and finite.)
fn cattaneo(
    r: &ReferenceSection,
    has_centre: bool,
    contact: &ContactPair,
    pair: usize,
) -> Result<Option<Cattaneo>, SceneError> {
    let s = SECTION;
    let keys = [
        ("radius", r.radius),
        ("contact_modulus", r.contact_modulus),
        ("friction", r.friction),
    ];
    if keys.iter().all(|(_, v)| v.is_none()) {
        return Ok(None);
    }
    let (Some(radius), Some(contact_modulus), Some(mu)) = (r.radius, r.contact_modulus, r.friction)
    else {
        let key = keys
            .iter()
            .find(|(_, v)| v.is_none())
            .map_or("radius", |k| k.0);
        return Err(SceneError::invalid(
            s,
            key,
            "is missing: a Cattaneo–Mindlin reference states `radius`, `contact_modulus` and \
             `friction` together",
        ));
    };
    for (key, value) in [
        ("half_width", r.half_width),
        ("peak_pressure", r.peak_pressure),
        ("pressure", r.pressure),
    ] {
        if value.is_some() {
            return Err(SceneError::invalid(
                s,
                key,
                "cannot be given with a Cattaneo–Mindlin reference (`radius`, \
                 `contact_modulus`, `friction`): its a and p₀ follow from the run's normal force",
            ));
        }
    }
    if !has_centre {
        return Err(SceneError::invalid(
            s,
            "centre",
            "is required with a Cattaneo–Mindlin reference: the traction profile and the stick \
             zone are measured from it",
        ));
    }
    match contact.friction {
        Some(Friction::Coulomb(pair_mu)) if (pair_mu - mu).abs() <= 1e-12 * pair_mu => {}
        other => {
            let has = match other {
                Some(Friction::Coulomb(m)) => format!("Coulomb friction μ = {m}"),
                Some(Friction::Tresca(t)) => format!("Tresca friction (bound {t})"),
                None => "no friction".to_string(),
            };
            return Err(SceneError::invalid(
                s,
                "friction",
                format!(
                    "= {mu}: contact pair {pair} has {has}; Cattaneo–Mindlin describes Coulomb \
                     friction with the pair's own μ"
                ),
            ));
        }
    }
    Ok(Some(Cattaneo {
        radius,
        contact_modulus,
        friction: mu,
    }))
}
