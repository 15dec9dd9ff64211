//! The tangential figures of frictional pairs: per contact node the tangential multiplier,
//! traction and slip and the node's state (`open`, `stick`, `slip`; docs/scene.md, "Friction").

use schemars::JsonSchema;
use serde::Serialize;

use super::active::is_active;
use crate::model::Model;
use crate::solve::Solution;

/// A contact node's state.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum ContactState {
    /// No normal force (the row is not [active](super::is_active)).
    Open,
    /// In contact, with no slip above the threshold of [`SLIP_FRACTION`].
    Stick,
    /// In contact and slipping.
    Slip,
}

/// A node slips when its slip exceeds max(this, 100 × the tolerance) × the pair's motion U
/// (max |u| over the nodes of the pair's two bodies): an answer meeting the tolerance leaves a
/// sticking node's slip near the tolerance times the motion, never near 10⁻⁶ of it.
pub const SLIP_FRACTION: f64 = 1e-6;

/// The tangential figures of one contact node.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TangentialNode {
    /// λₜ: the tangential force on the slave node along the row's tangent t.
    pub multiplier: f64,
    /// The slip of the slave node relative to the master along t since the reference
    /// configuration, gₜ − (B u)ₜ (the state looks at the last increment's share).
    pub slip: f64,
    /// Its state.
    pub state: ContactState,
}

/// For each normal row: its node's tangential figures, `None` on a frictionless pair.
pub fn tangential_nodes(
    model: &Model,
    solution: &Solution,
    bu: &[f64],
    force_scale: f64,
) -> Vec<Option<TangentialNode>> {
    let tolerance = solution.tolerance;
    // The last increment's slip decides the state (the whole slip with one increment).
    let before = solution
        .previous
        .as_ref()
        .map(|u| crate::qp::mat_vec(&model.constraints, u));
    let normal = model.normal_rows();
    let mut out = vec![None; normal];
    let motion = body_motion(model, &solution.displacement);
    let pair_bodies: Vec<[usize; 2]> = model.contacts.iter().map(|p| [p.slave, p.master]).collect();
    let pair_index = |pair: usize| model.contacts.iter().position(|p| p.pair == pair);
    for (k, t) in model.tangential.iter().enumerate() {
        let row = normal + k;
        let multiplier = solution.multipliers.get(row).copied().unwrap_or(f64::NAN);
        let slip = model.gap[row] - bu[row];
        let step_slip = before
            .as_ref()
            .map_or(slip, |b| t.stick_value(row, &model.gap, b) - bu[row]);
        let lambda_n = solution
            .multipliers
            .get(t.normal_row)
            .copied()
            .unwrap_or(0.0);
        let u = pair_index(t.pair)
            .map(|p| motion[pair_bodies[p][0]].max(motion[pair_bodies[p][1]]))
            .unwrap_or(0.0);
        let state = if !is_active(lambda_n, force_scale) {
            ContactState::Open
        } else if step_slip.abs() > SLIP_FRACTION.max(100.0 * tolerance) * u {
            ContactState::Slip
        } else {
            ContactState::Stick
        };
        out[t.normal_row] = Some(TangentialNode {
            multiplier,
            slip,
            state,
        });
    }
    out
}

impl ContactState {
    /// The state as the VTU's `contact_state` writes it: 0 open (or no row), 1 stick, 2 slip.
    pub fn code(self) -> i32 {
        match self {
            ContactState::Open => 0,
            ContactState::Stick => 1,
            ContactState::Slip => 2,
        }
    }
}

/// One body's nodal friction fields (for the VTU): zero (and state 0) at nodes without a
/// tangential row.
#[derive(Debug, Clone, PartialEq)]
pub struct FrictionField {
    /// λₜ / weight at slave nodes with a tangential row.
    pub tangential_traction: Vec<f64>,
    /// The slip along the row's tangent.
    pub slip: Vec<f64>,
    /// [`ContactState::code`].
    pub state: Vec<i32>,
}

/// Every body's [`FrictionField`], `None` when the model has no tangential row.
pub fn friction_fields(
    model: &Model,
    solution: &Solution,
    force_scale: f64,
) -> Option<Vec<FrictionField>> {
    if model.tangential.is_empty() {
        return None;
    }
    let bu = crate::qp::mat_vec(&model.constraints, &solution.displacement);
    let nodes = tangential_nodes(model, solution, &bu, force_scale);
    let mut fields: Vec<FrictionField> = model
        .meshes
        .iter()
        .map(|m| FrictionField {
            tangential_traction: vec![0.0; m.nodes.len()],
            slip: vec![0.0; m.nodes.len()],
            state: vec![0; m.nodes.len()],
        })
        .collect();
    let rows = model
        .contacts
        .iter()
        .flat_map(|p| p.rows.iter().map(move |r| (p.slave, r)));
    for ((slave, r), t) in rows.zip(&nodes) {
        if let Some(t) = t {
            let f = &mut fields[slave];
            f.tangential_traction[r.slave_node] = t.multiplier / r.tributary;
            f.slip[r.slave_node] = t.slip;
            f.state[r.slave_node] = t.state.code();
        }
    }
    Some(fields)
}

/// max |u| over each body's nodes.
fn body_motion(model: &Model, u: &[f64]) -> Vec<f64> {
    (0..model.meshes.len())
        .map(|b| {
            model
                .body_displacements(b, u)
                .iter()
                .map(|d| d[0].hypot(d[1]))
                .fold(0.0, f64::max)
        })
        .collect()
}
