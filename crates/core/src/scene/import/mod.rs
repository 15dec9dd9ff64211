//! The import stage: a validated [`Draft`] becomes a [`Scene`].  It reads each Gmsh body's file
//! (relative to the scene file's directory), fills in what comes from the mesh (outline, element,
//! size), resolves physical groups into the nodes and boxes they select, and — for a scene with
//! a Gmsh body, whose tolerance depends on the files — runs the checks of where boxes, probes
//! and supports lie that validation could not run (the same functions, in the same order).
//!
//! [`bodies`] reads the files and checks what they give; [`groups`] resolves the groups.

mod bodies;
mod groups;

use std::path::Path;

use crate::geometry::Point;
use crate::scene::draft::{Draft, DraftDirichlet, DraftNeumann};
use crate::scene::types::{Body, ContactPair, Dirichlet, Neumann, Probe};
use crate::scene::validate::contact::{check_contact_region, contact_label};
use crate::scene::validate::held::{check_rigid_modes, in_contact};
use crate::scene::validate::loads::{check_neumann_boundary, neumann_label};
use crate::scene::validate::outlines::Outlines;
use crate::scene::validate::probes::{check_probe_inside, probe_label};
use crate::scene::validate::supports::{
    check_dirichlet_boundary, check_dirichlet_conflicts, dirichlet_label,
};
use crate::scene::{Scene, SceneError};

/// Imports a validated scene whose Gmsh files are relative to `base` (None: the scene came as
/// text, and a Gmsh body is refused).
pub(super) fn import(draft: Draft, base: Option<&Path>) -> Result<Scene, SceneError> {
    let deferred = !draft.outlines_known();
    let bodies = draft
        .bodies
        .into_iter()
        .map(|b| bodies::import_body(b, draft.gravity, draft.thickness, base))
        .collect::<Result<Vec<_>, _>>()?;
    let (dirichlet, neumann) = {
        let outlines = Outlines::new(bodies.iter().map(|b| (b.name.as_str(), &b.polygon[..])));
        let dirichlet = import_dirichlet(&draft.dirichlet, &bodies, &outlines, deferred)?;
        let neumann = import_neumann(&draft.neumann, &bodies, &outlines, deferred)?;
        check_contacts(&draft.contacts, &bodies, &outlines, deferred)?;
        if deferred {
            check_probes(&draft.probes, &outlines)?;
            check_rigid_bodies(&bodies, &draft.contacts, &draft.dirichlet, &outlines)?;
        }
        (dirichlet, neumann)
    };
    Ok(Scene {
        title: draft.title,
        plane: draft.plane,
        thickness: draft.thickness,
        gravity: draft.gravity,
        bodies,
        dirichlet,
        neumann,
        contacts: draft.contacts,
        probes: draft.probes,
        reference: draft.reference,
        load_names: draft.load_names,
        steps: draft.steps,
    })
}

/// The supports with their groups resolved (and, when `deferred`, their boxes checked), then
/// the conflicts between the boxes of each Gmsh body.
fn import_dirichlet(
    drafts: &[DraftDirichlet],
    bodies: &[Body],
    outlines: &Outlines,
    deferred: bool,
) -> Result<Vec<Dirichlet>, SceneError> {
    let mut dirichlet = Vec::with_capacity(drafts.len());
    for (i, d) in drafts.iter().enumerate() {
        let s = dirichlet_label(i, &bodies[d.body].name);
        let (region, group) = groups::resolve_place(&s, &d.place, &bodies[d.body], false)?;
        if deferred && group.is_none() {
            check_dirichlet_boundary(&s, &region, d.body, outlines)?;
        }
        dirichlet.push(Dirichlet {
            name: d.name.clone(),
            body: d.body,
            region,
            group,
            value: d.value,
            components: d.components,
        });
    }
    // Validation looked at the polygon bodies.
    check_dirichlet_conflicts(
        drafts,
        |k| &bodies[k].name,
        |k| bodies[k].imported.as_ref().map(|_| &bodies[k].polygon[..]),
    )?;
    Ok(dirichlet)
}

/// The tractions with their groups resolved (and, when `deferred`, their boxes checked).
fn import_neumann(
    drafts: &[DraftNeumann],
    bodies: &[Body],
    outlines: &Outlines,
    deferred: bool,
) -> Result<Vec<Neumann>, SceneError> {
    let mut neumann = Vec::with_capacity(drafts.len());
    for (i, n) in drafts.iter().enumerate() {
        let s = neumann_label(i, &bodies[n.body].name);
        let (region, group) = groups::resolve_place(&s, &n.place, &bodies[n.body], true)?;
        if deferred && group.is_none() {
            check_neumann_boundary(&s, &region, n.body, outlines)?;
        }
        neumann.push(Neumann {
            name: n.name.clone(),
            body: n.body,
            region,
            group,
            traction: n.traction,
        });
    }
    Ok(neumann)
}

/// The contact pairs' boxes (when `deferred`) and groups.
fn check_contacts(
    contacts: &[ContactPair],
    bodies: &[Body],
    outlines: &Outlines,
    deferred: bool,
) -> Result<(), SceneError> {
    for (i, c) in contacts.iter().enumerate() {
        let s = contact_label(i, &c.bodies.map(|k| &bodies[k].name));
        if let (Some(r), true) = (&c.region, deferred) {
            check_contact_region(&s, r, c.bodies, outlines)?;
        }
        if let Some(name) = &c.group {
            groups::check_contact_group(&s, name, c.bodies, bodies)?;
        }
    }
    Ok(())
}

/// Every probe inside its body.
fn check_probes(probes: &[Probe], outlines: &Outlines) -> Result<(), SceneError> {
    for (i, p) in probes.iter().enumerate() {
        check_probe_inside(&probe_label(i, &p.name), p.point, p.body, outlines)?;
    }
    Ok(())
}

/// Every body in no contact pair held by its supports (validation refused the ones without).
fn check_rigid_bodies(
    bodies: &[Body],
    contacts: &[ContactPair],
    dirichlet: &[DraftDirichlet],
    outlines: &Outlines,
) -> Result<(), SceneError> {
    for (k, body) in bodies.iter().enumerate() {
        if in_contact(k, contacts) {
            continue;
        }
        let group_points = |name: &str| -> Vec<Point> { groups::boundary_points(body, name) };
        check_rigid_modes(k, outlines, dirichlet, &group_points)?;
    }
    Ok(())
}
