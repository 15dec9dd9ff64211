//! The result of a run: full displacements, reactions, stresses, contact pressures and probes, as
//! the `result.json` of `docs/scene.md`.
//!
//! * [`document`]: the types `result.json` is written from ([`RunReport`] and its parts);
//! * [`fields`]: the nodal and element fields of each body (displacements, stresses, pressures,
//!   friction), interpolation at probes; [`active`]: the one threshold of active contact
//!   ([`is_active`]); [`friction`]: tangential figures and stick/slip states;
//! * [`arc`]: positions along an interface; [`balance`]: the force balance of each body;
//! * [`run_report`] (here) puts them together.

use crate::model::Model;
use crate::qp::mat_vec;
use crate::scene::Scene;
use crate::solve::Solution;

pub mod active;
pub mod arc;
pub mod balance;
pub mod document;
pub mod fields;
pub mod free;
pub mod friction;

pub use active::{active_scale, is_active};
pub use arc::{interface_arc, ArcPosition};
pub use balance::{force_balance, BodyBalance, ForceBalance};
pub use document::{
    AttemptReport, BackendSettings, BodyReport, ContactNodeReport, ContactReport, ProbeReport,
    Provenance, RunReport, Timings, WarningReport,
};
pub use fields::{body_fields, interpolate, BodyFields};
pub use friction::{
    friction_fields, tangential_nodes, ContactState, FrictionField, TangentialNode,
};

/// Builds `result.json`'s content.
pub fn run_report(
    scene: &Scene,
    model: &Model,
    solution: &Solution,
    fields: &[BodyFields],
    tolerance: f64,
    timings: Timings,
) -> RunReport {
    let u = &solution.displacement;
    let balance = force_balance(scene, model, u, &solution.multipliers);
    let bodies = body_reports(scene, model, fields, &balance);
    let (contacts, active_total) = contact_reports(scene, model, solution);
    let probes = probe_reports(scene, model, fields);
    RunReport {
        scene: scene.title.clone(),
        backend: solution.backend.clone(),
        status: solution.status.as_str().to_string(),
        tolerance,
        effects: model.effects.clone(),
        dofs: model.free.len(),
        constraints: model.rows(),
        active_constraints: active_total,
        iterations: solution.iterations,
        objective: solution.objective,
        residuals: solution.residuals,
        timing_s: timings,
        bodies,
        contacts,
        probes,
        force_balance: balance.relative,
        message: solution.message.clone(),
        coulomb: solution.coulomb,
        steps: solution.steps.clone(),
        backend_status: solution.backend_status.as_str().to_string(),
        warnings: model
            .warnings
            .iter()
            .cloned()
            .chain(free::free_directions(scene, model, solution))
            .map(|w| WarningReport {
                message: w.to_string(),
                warning: w,
            })
            .collect(),
        attempts: Vec::new(),
        chosen: None,
        reason: None,
        provenance: None,
    }
}

/// One [`BodyReport`] per body: its size, largest displacement and von Mises stress, and its
/// force balance.
fn body_reports(
    scene: &Scene,
    model: &Model,
    fields: &[BodyFields],
    balance: &ForceBalance,
) -> Vec<BodyReport> {
    let mut bodies = Vec::with_capacity(model.meshes.len());
    for (b, mesh) in model.meshes.iter().enumerate() {
        let figures = balance.bodies.get(b).copied().unwrap_or_default();
        let f = &fields[b];
        bodies.push(BodyReport {
            name: scene.bodies[b].name.clone(),
            nodes: mesh.nodes.len(),
            elements: mesh.cells.len(),
            max_displacement: f
                .displacement
                .iter()
                .map(|d| d[0].hypot(d[1]))
                .fold(0.0, f64::max),
            reaction: figures.reaction,
            applied: figures.applied,
            contact_force: figures.contact,
            max_von_mises: f.von_mises.iter().copied().fold(0.0, f64::max),
        });
    }
    bodies
}

/// One [`ContactReport`] per contact pair (its rows in order, with their gaps, multipliers and
/// arc positions), and the number of active rows over all pairs.
fn contact_reports(
    scene: &Scene,
    model: &Model,
    solution: &Solution,
) -> (Vec<ContactReport>, usize) {
    let largest = active_scale(model, solution);
    let bu = mat_vec(&model.constraints, &solution.displacement);
    let tangential = tangential_nodes(model, solution, &bu, largest);
    let mut contacts = Vec::with_capacity(model.contacts.len());
    let mut row = 0;
    let mut active_total = 0;
    for pair in &model.contacts {
        let mut nodes = Vec::with_capacity(pair.rows.len());
        let mut active = 0;
        let mut normal_force = 0.0;
        let mut tangential_force = 0.0;
        let mut force = [0.0; 2];
        let slave_nodes: Vec<usize> = pair.rows.iter().map(|r| r.slave_node).collect();
        let arc = interface_arc(&model.meshes[pair.slave], &slave_nodes);
        for (r, place) in pair.rows.iter().zip(&arc) {
            let l = solution.multipliers.get(row).copied().unwrap_or(0.0);
            let on = is_active(l, largest);
            if on {
                active += 1;
            }
            normal_force += l;
            let t = tangential.get(row).copied().flatten();
            let lt = t.map_or(0.0, |t| t.multiplier);
            tangential_force += lt;
            // λ along the row's normal and λₜ along its tangent, on the slave.
            let (n, tn) = (r.normal, crate::geometry::tangent(r.normal));
            force[0] += l * n[0] + lt * tn[0];
            force[1] += l * n[1] + lt * tn[1];
            nodes.push(ContactNodeReport {
                x: r.position[0],
                y: r.position[1],
                gap: model.gap[row] - bu[row],
                initial_gap: r.gap,
                multiplier: l,
                pressure: l / r.tributary,
                active: on,
                weight: r.tributary,
                s: place.s,
                piece: place.piece,
                tangential_multiplier: t.map(|t| t.multiplier),
                tangential_traction: t.map(|t| t.multiplier / r.tributary),
                slip: t.map(|t| t.slip),
                state: t.map(|t| t.state),
            });
            row += 1;
        }
        active_total += active;
        let spec = &scene.contacts[pair.pair];
        contacts.push(ContactReport {
            bodies: spec.bodies.map(|k| scene.bodies[k].name.clone()),
            slave: scene.bodies[pair.slave].name.clone(),
            formulation: pair.formulation,
            conforming: pair.conforming,
            constraints: pair.rows.len(),
            active,
            normal_force,
            force,
            friction: pair.friction,
            tangential_force: pair.friction.map(|_| tangential_force),
            nodes,
        });
    }
    (contacts, active_total)
}

/// One [`ProbeReport`] per probe: the displacement interpolated at its point (NaN when the point
/// lies in no element).
fn probe_reports(scene: &Scene, model: &Model, fields: &[BodyFields]) -> Vec<ProbeReport> {
    let tol = scene.tolerance();
    scene
        .probes
        .iter()
        .map(|p| ProbeReport {
            name: p.name.clone(),
            body: scene.bodies[p.body].name.clone(),
            point: p.point,
            displacement: interpolate(
                &model.meshes[p.body],
                &fields[p.body].displacement,
                p.point,
                tol,
            )
            .unwrap_or([f64::NAN, f64::NAN]),
        })
        .collect()
}
