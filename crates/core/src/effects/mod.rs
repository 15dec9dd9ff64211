//! The physical effects a scene names, each a typed input built once from the scene and each
//! contributing to the model only when the scene names it: supports ([`supports`]), surface
//! tractions ([`tractions`]), the body force ([`body_force`]) and contact ([`contact`]).
//!
//! [`Effects::of`] is the one place that reads the scene's sections into these values; the
//! numerics behind them (FEM loads, the contact search) take the typed values, never the scene.
//! Assembly ([`crate::model::assemble`]) runs every named effect's [`Contribution`] in the
//! order [`Effects::contributions`] gives — loads, then supports, then (after the model has
//! checked that supports or contact pairs hold every body) the constraints — into one
//! [`ModelParts`].  Adding an effect is one file here, one field of [`Effects`] and one variant
//! of [`Effect`] (docs/architecture.md, "Adding an effect").

pub mod body_force;
pub mod contact;
pub mod select;
pub mod supports;
pub mod tractions;

use serde::Serialize;

use crate::contact::{ContactError, PairRows};
use crate::fem::{Dofs, FemError};
use crate::mesh::Mesh;
use crate::scene::Scene;

pub use body_force::BodyForce;
pub use contact::ContactEffect;
pub use select::Selection;
pub use supports::Supports;
pub use tractions::Tractions;

/// Something that a scene asks the program to simulate (listed in `result.json`'s `effects`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, schemars::JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Effect {
    /// Prescribed displacements.
    Dirichlet,
    /// Surface tractions.
    Neumann,
    /// Body force from `[model] gravity`.
    Gravity,
    /// Contact constraints (a QP instead of one linear solve).
    Contact,
}

/// Why an effect could not contribute.
#[derive(Debug, thiserror::Error)]
pub enum EffectError {
    /// Supports or loads are inconsistent with the mesh.
    #[error(transparent)]
    Fem(#[from] FemError),
    /// Contact rows could not be built.
    #[error(transparent)]
    Contact(#[from] ContactError),
}

/// What the effects contribute to: the meshes and their numbering.
#[derive(Debug, Clone, Copy)]
pub struct Discretisation<'m> {
    /// Per-body meshes, in scene order.
    pub meshes: &'m [Mesh],
    /// Global numbering of their nodes and DOFs.
    pub dofs: &'m Dofs,
}

/// The model's parts the effects fill in.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelParts {
    /// Applied nodal forces on all DOFs.
    pub load: Vec<f64>,
    /// Prescribed value of each DOF with the 0-based support that prescribed it first
    /// (`None`: free).
    pub fixed: Vec<Option<(f64, usize)>>,
    /// Contact rows per pair, in pair order.
    pub pairs: Vec<PairRows>,
}

impl ModelParts {
    /// Nothing contributed yet: no load, no support, no row, on `dofs` unknowns.
    pub fn empty(dofs: usize) -> Self {
        Self {
            load: vec![0.0; dofs],
            fixed: vec![None; dofs],
            pairs: Vec::new(),
        }
    }

    /// The prescribed value of each DOF (`None`: free).
    pub fn prescribed(&self) -> Vec<Option<f64>> {
        self.fixed.iter().map(|f| f.map(|(v, _)| v)).collect()
    }
}

/// An effect's contribution to the model.
pub trait Contribution {
    /// Which effect this is.
    fn effect(&self) -> Effect;

    /// True for constraints that need every support in place first (contact rows are screened
    /// against the prescribed DOFs, and run only once supports or pairs hold every body).
    fn after_supports(&self) -> bool {
        false
    }

    /// Adds this effect's part to `parts`.
    fn contribute(&self, on: Discretisation<'_>, parts: &mut ModelParts)
        -> Result<(), EffectError>;
}

/// The effects a scene names, as typed inputs (`None` or empty: not named, not simulated).
#[derive(Debug, Clone)]
pub struct Effects<'a> {
    /// `[[neumann]]`.
    pub tractions: Option<Tractions<'a>>,
    /// `[model] gravity` with the bodies' densities.
    pub body_force: Option<BodyForce>,
    /// `[[dirichlet]]`.
    pub supports: Option<Supports<'a>>,
    /// `[[contact]]`.
    pub contact: Option<ContactEffect<'a>>,
}

impl<'a> Effects<'a> {
    /// The effects `scene` names, read into their typed inputs.
    pub fn of(scene: &'a Scene) -> Self {
        Self {
            tractions: (!scene.neumann.is_empty()).then(|| Tractions::of(scene)),
            body_force: scene.gravity.map(|g| BodyForce::of(scene, g)),
            supports: (!scene.dirichlet.is_empty()).then(|| Supports::of(scene)),
            contact: (!scene.contacts.is_empty()).then(|| ContactEffect::of(scene)),
        }
    }

    /// The named effects' contributions, in assembly order: loads (tractions, body force), then
    /// supports, then contact — also the order in which their refusals are reported.
    pub fn contributions(&self) -> Vec<&dyn Contribution> {
        let mut list: Vec<&dyn Contribution> = Vec::new();
        if let Some(t) = &self.tractions {
            list.push(t);
        }
        if let Some(b) = &self.body_force {
            list.push(b);
        }
        if let Some(s) = &self.supports {
            list.push(s);
        }
        if let Some(c) = &self.contact {
            list.push(c);
        }
        list
    }

    /// True when some contact pair has body `b` as one of its sides.
    pub fn in_contact(&self, b: usize) -> bool {
        self.contact.as_ref().is_some_and(|c| c.touches(b))
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)] // tests may unwrap

    use super::*;
    use crate::mesh::MeshLimits;
    use crate::model::mesh_scene;

    /// Two blocks, the lower one clamped, under `[model]` lines `model`, each body with its own
    /// material lines (`base`, `block`); `extra` adds sections.
    fn two_blocks(model: &str, [base, block]: [&str; 2], extra: &str) -> Scene {
        Scene::from_toml(&format!(
            r#"
            [model]
            {model}
            [[body]]
            name = "base"
            polygon = [[0, 0], [2, 0], [2, 1], [0, 1]]
            hmax = 0.5
            {base}
            [[body]]
            name = "block"
            polygon = [[0.5, 1], [1.5, 1], [1.5, 2], [0.5, 2]]
            hmax = 0.5
            {block}
            [[dirichlet]]
            body = "base"
            region = [0, 2, 0, 0]
            [[dirichlet]]
            body = "block"
            region = [0.5, 0.5, 1, 2]
            {extra}
            "#
        ))
        .unwrap()
    }

    /// Two blocks of E = 1, ν = 0.3, the lower one clamped; with `gravity`, g = (0, −1) and
    /// densities 2 (base) and 0.5 (block); `extra` adds sections.
    fn scene(gravity: bool, extra: &str) -> Scene {
        let material = "young = 1.0\npoisson = 0.3";
        if gravity {
            two_blocks(
                "gravity = [0, -1]",
                [
                    &format!("{material}\ndensity = 2.0"),
                    &format!("{material}\ndensity = 0.5"),
                ],
                extra,
            )
        } else {
            two_blocks("", [material, material], extra)
        }
    }

    /// Only what the scene names is read and contributed, in assembly order: loads, supports,
    /// contact.
    #[test]
    fn an_effect_contributes_only_when_the_scene_names_it() {
        let plain_scene = scene(false, "");
        let plain = Effects::of(&plain_scene);
        assert!(plain.tractions.is_none() && plain.body_force.is_none());
        assert!(plain.contact.is_none() && plain.supports.is_some());
        let kinds: Vec<Effect> = plain.contributions().iter().map(|c| c.effect()).collect();
        assert_eq!(kinds, [Effect::Dirichlet]);
        let full_scene = scene(
            true,
            "[[neumann]]\nbody = \"block\"\nregion = [0.5, 1.5, 2, 2]\n\
             traction = [0, -1]\n[[contact]]\nbodies = [\"block\", \"base\"]",
        );
        let full = Effects::of(&full_scene);
        let kinds: Vec<Effect> = full.contributions().iter().map(|c| c.effect()).collect();
        assert_eq!(
            kinds,
            [
                Effect::Neumann,
                Effect::Gravity,
                Effect::Dirichlet,
                Effect::Contact
            ]
        );
        assert!(full.in_contact(0) && full.in_contact(1));
        let after: Vec<bool> = full
            .contributions()
            .iter()
            .map(|c| c.after_supports())
            .collect();
        assert_eq!(after, [false, false, false, true]);
    }

    /// Each contact side carries its body's surface compliance 1/E′ under the scene's `plane`:
    /// 1/E in plane stress whatever ν (it was (1 − ν²)/E in both), (1 − ν²)/E in plane strain.
    /// Closed forms; round-off only.
    #[test]
    fn contact_sides_carry_the_surface_compliance_of_the_scene_plane() {
        let compliances = |plane: &str| {
            let s = two_blocks(
                &format!("plane = \"{plane}\""),
                ["young = 2.0\npoisson = 0.1", "young = 5.0\npoisson = 0.45"],
                "[[contact]]\nbodies = [\"block\", \"base\"]",
            );
            let c = Effects::of(&s).contact.unwrap();
            c.interfaces[0].sides.map(|side| side.compliance)
        };
        let [block, base] = compliances("stress");
        assert!((block - 1.0 / 5.0).abs() < 1e-15 && (base - 1.0 / 2.0).abs() < 1e-15);
        let [block, base] = compliances("strain");
        assert!((block - (1.0 - 0.45 * 0.45) / 5.0).abs() < 1e-15);
        assert!((base - (1.0 - 0.1 * 0.1) / 2.0).abs() < 1e-15);
    }

    /// The traction's consistent nodal forces sum to its resultant integrated analytically
    /// (a unit downward traction on the block's top edge of length 1, thickness 1: −1), and
    /// the body force's to ρ·area·g (base: 2 · 2 · −1 = −4; block: 0.5 · 1 · −1 = −0.5).
    #[test]
    fn nodal_loads_sum_to_the_analytic_resultants() {
        let s = scene(
            true,
            "[[neumann]]\nbody = \"block\"\nregion = [0.5, 1.5, 2, 2]\n\
             traction = [0, -1]",
        );
        let meshes = mesh_scene(&s, &MeshLimits::default()).unwrap();
        let dofs = Dofs::new(&meshes.iter().map(|m| m.nodes.len()).collect::<Vec<_>>());
        let effects = Effects::of(&s);
        let mut parts = ModelParts::empty(dofs.len());
        let on = Discretisation {
            meshes: &meshes,
            dofs: &dofs,
        };
        for c in effects.contributions() {
            c.contribute(on, &mut parts).unwrap();
        }
        let body_sum = |b: usize| -> f64 {
            dofs.body_range(b)
                .skip(1)
                .step_by(2)
                .map(|d| parts.load[d])
                .sum()
        };
        assert!((body_sum(1) + 1.5).abs() < 1e-14, "{}", body_sum(1));
        assert!((body_sum(0) + 4.0).abs() < 1e-13, "{}", body_sum(0));
        let mut analytic = vec![[0.0; 2]; 2];
        effects
            .tractions
            .as_ref()
            .unwrap()
            .add_resultants(&meshes, |_| 1.0, &mut analytic);
        assert!((analytic[1][1] + 1.0).abs() < 1e-14 && analytic[0] == [0.0, 0.0]);
    }
}
