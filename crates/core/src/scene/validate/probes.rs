//! `[[probe]]`: a printable, unique name, a body, and a point inside it.

use super::outlines::Outlines;
use super::values::{check_finite, check_text, exact, Names};
use crate::geometry::{self, Point};
use crate::scene::draft::DraftBody;
use crate::scene::file::ProbeSection;
use crate::scene::types::Probe;
use crate::scene::SceneError;

/// `probe #i "name"`, `i` from 0.
pub(in crate::scene) fn probe_label(i: usize, name: &str) -> String {
    format!("probe #{} {:?}", i + 1, name)
}

/// Checks one `[[probe]]` section against the bodies and the `earlier` probes; with
/// `outlines`, also that its point lies inside its body.
pub(super) fn validate_probe(
    i: usize,
    p: ProbeSection,
    bodies: &[DraftBody],
    earlier: &[Probe],
    outlines: Option<&Outlines>,
) -> Result<Probe, SceneError> {
    let s = probe_label(i, &p.name);
    check_text(&s, "name", &p.name)?;
    let body = Names(bodies).find(&s, "body", &p.body)?;
    let point = exact::<2>(&s, "point", &p.point)?;
    check_finite(&s, "point", &point)?;
    if let Some(outlines) = outlines {
        check_probe_inside(&s, point, body, outlines)?;
    }
    if earlier.iter().any(|q| q.name == p.name) {
        return Err(SceneError::invalid(
            &s,
            "name",
            "is used by more than one probe",
        ));
    }
    Ok(Probe {
        name: p.name,
        body,
        point,
    })
}

/// Refuses a probe point outside its body.
pub(in crate::scene) fn check_probe_inside(
    s: &str,
    point: Point,
    body: usize,
    outlines: &Outlines,
) -> Result<(), SceneError> {
    if !geometry::contains(outlines.polygon(body), point, outlines.tol) {
        return Err(SceneError::invalid(
            s,
            "point",
            format!("{point:?} lies outside body {:?}", outlines.name(body)),
        ));
    }
    Ok(())
}
