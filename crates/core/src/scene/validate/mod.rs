//! Validation of a parsed [`SceneFile`] into a [`Draft`]: the TOML's keys, values and
//! cross-references, every error naming the section and the key at fault.  Validation reads no
//! file: a Gmsh body stays a file name and a physical group a name, for the import stage
//! (`scene/import.rs`) to read and check.
//!
//! Besides ranges and references, validation refuses what would otherwise fail only after
//! meshing, so that `check` and `solve` agree: arrays of the wrong length, names with control
//! characters, elastic constants or body forces that overflow, contact boxes that hold no
//! boundary of one of the pair's bodies, and bodies that nothing holds.  The checks of where a
//! box, a probe or a support lies need every body's outline and the scene's tolerance: they run
//! here, section by section, when the TOML gives every outline, and in the import otherwise.
//!
//! One file per section kind: [`bodies`] (`[model]`, `[[body]]`), [`supports`]
//! (`[[dirichlet]]`), [`loads`] (`[[neumann]]`), [`steps`] (names and `[[step]]`), [`contact`],
//! [`probes`], [`reference`], and
//! [`held`] (every body held); [`place`] (box or group), [`values`] (shared checks) and
//! [`outlines`] serve them.

pub(super) mod bodies;
pub(super) mod contact;
pub(super) mod held;
pub(super) mod loads;
pub(super) mod outlines;
pub(super) mod place;
pub(super) mod probes;
pub(super) mod reference;
pub(super) mod steps;
pub(super) mod supports;
pub(super) mod values;

use crate::geometry::Point;
use crate::scene::draft::{Draft, DraftBody};
use crate::scene::file::{BodySection, SceneFile};
use crate::scene::SceneError;

use self::outlines::Outlines;
use self::values::{body_label, check_text};

pub use self::values::name_forbidden;

/// Largest elastic stiffness coefficient, (λ + 2μ)·thickness in plane strain or
/// E/(1 − ν²)·thickness in plane stress, and largest body force ρ·|g|·thickness·area of a body,
/// that a scene may ask for: `1e-10 × f64::MAX` ≈ 1.8e298.
///
/// Element matrices multiply the coefficient by geometric factors (up to the cotangent of the
/// smallest angle) and assembly sums a few elements per node; the margin of 10¹⁰ keeps all of
/// that finite.  Only overflow is refused: tiny values (E = 1e-200) are legitimate, since the
/// program nondimensionalises the problem before a backend sees it.
pub const MAX_COEFFICIENT: f64 = 1e-10 * f64::MAX;

/// The smallest stiffness coefficient accepted, 1 / [`MAX_COEFFICIENT`] ≈ 5.6e-299: below it the
/// element stiffness entries (the coefficient times geometric factors of order one in 2D) come
/// close to the subnormal range and lose their digits or vanish (E = 2.2e-308 gave a zero
/// stiffness matrix), so the Cholesky factorisation fails after `check` accepted the scene.
pub const MIN_COEFFICIENT: f64 = 1.0 / MAX_COEFFICIENT;

/// Validates a parsed scene file, section by section in the file format's order: title,
/// `[model]`, bodies, supports (and their conflicts), tractions, contact pairs, probes, that
/// every body is held, and the reference.
pub(super) fn validate(file: SceneFile) -> Result<Draft, SceneError> {
    if let Some(title) = &file.title {
        check_text("scene", "title", title)?;
    }
    if file.body.is_empty() {
        return Err(SceneError::invalid(
            "scene",
            "body",
            "needs at least one [[body]] table",
        ));
    }
    let model = bodies::validate_model(file.model)?;
    let bodies = validate_bodies(file.body, &model)?;
    let known = polygon_outlines(&bodies);
    let outlines = known.as_ref();

    let dirichlet = file
        .dirichlet
        .into_iter()
        .enumerate()
        .map(|(i, d)| supports::validate_dirichlet(i, d, &bodies, outlines))
        .collect::<Result<Vec<_>, _>>()?;
    supports::check_dirichlet_conflicts(&dirichlet, |k| &bodies[k].name, |k| bodies[k].polygon())?;
    let neumann = file
        .neumann
        .into_iter()
        .enumerate()
        .map(|(i, n)| loads::validate_neumann(i, n, &bodies, outlines))
        .collect::<Result<Vec<_>, _>>()?;
    let load_names = steps::load_names(&dirichlet, &neumann, |k| &bodies[k].name)?;
    let steps = steps::validate_steps(file.step, &load_names)?;
    let mut contacts = Vec::with_capacity(file.contact.len());
    for (i, c) in file.contact.into_iter().enumerate() {
        let pair = contact::validate_contact(i, c, &bodies, &contacts, outlines)?;
        contacts.push(pair);
    }
    let mut probes = Vec::with_capacity(file.probe.len());
    for (i, p) in file.probe.into_iter().enumerate() {
        let probe = probes::validate_probe(i, p, &bodies, &probes, outlines)?;
        probes.push(probe);
    }
    held::check_held(&bodies, &contacts, &dirichlet, outlines)?;
    let reference = file
        .reference
        .map(|r| reference::validate_reference(r, &contacts))
        .transpose()?;

    Ok(Draft {
        title: file.title.unwrap_or_else(|| "untitled".to_string()),
        plane: model.plane,
        thickness: model.thickness,
        gravity: model.gravity,
        bodies,
        dirichlet,
        neumann,
        contacts,
        probes,
        reference,
        load_names,
        steps,
    })
}

/// The bodies: names non-empty, printable and unique; geometry and material sane.
fn validate_bodies(
    sections: Vec<BodySection>,
    model: &bodies::ModelContext,
) -> Result<Vec<DraftBody>, SceneError> {
    let mut bodies: Vec<DraftBody> = Vec::with_capacity(sections.len());
    for b in sections {
        if b.name.trim().is_empty() {
            return Err(SceneError::invalid("[[body]]", "name", "must not be empty"));
        }
        let s = body_label(&b.name);
        check_text(&s, "name", &b.name)?;
        if bodies.iter().any(|o| o.name == b.name) {
            return Err(SceneError::invalid(
                s,
                "name",
                "is used by more than one body",
            ));
        }
        bodies.push(bodies::validate_body(b, &s, model)?);
    }
    Ok(bodies)
}

/// Every body's outline, when the TOML gives them all (no Gmsh body).
fn polygon_outlines(bodies: &[DraftBody]) -> Option<Outlines<'_>> {
    let polygons: Option<Vec<&[Point]>> = bodies.iter().map(DraftBody::polygon).collect();
    let names = bodies.iter().map(|b| b.name.as_str());
    polygons.map(|p| Outlines::new(names.zip(p)))
}
