//! Force balance of every body from three independently computed figures.
//!
//! For each body and each component (x, y):
//!
//! * **applied**: the scene's loads integrated analytically: every `[[neumann]]` traction over the
//!   body's boundary edges whose two ends lie in the region box (the traction is linear, so the
//!   integral over an edge is exactly its length times the mean of its end values), times the
//!   thickness; and gravity as density × polygon area × g × thickness, the area taken from the
//!   scene's polygon, not from the mesh.  The assembled load vector is not used.
//! * **contact**: the resultant of the contact forces on the body, −Bᵀλ summed over the body's
//!   DOFs, from the multipliers λ and the contact matrix B alone.
//! * **reaction**: the support reactions from the Dirichlet rows of the unconstrained stiffness
//!   only: (K_D·u)_d − f_d − c_d summed over the body's fixed DOFs d, where K_D are the fixed
//!   columns of K ([`Model::supports`]), and f_d, c_d are what the assembled load and the contact
//!   put on those same DOFs (a support carries whatever the element forces there do not).
//!
//! **Why their sum is not zero by construction.**  K is block diagonal over bodies and every
//! rigid translation e_c of a body lies in its null space, so Σ_all (K u)_d = e_cᵀ K u = 0 over a
//! body's DOFs of one component; hence Σ_D (K u)_d = −Σ_F (K u)_d, and
//!
//! ```text
//! applied + contact + reaction
//!   = Σ_F (f + c − K u)_d  +  (applied − Σ_all f_d)
//!   = −Σ_F r_d             +  (analytic − assembled load)
//! ```
//!
//! where r = K u − f − c is the stationarity (equilibrium) residual of the free DOFs F.  The first
//! term vanishes only if the displacement and the multipliers really satisfy equilibrium — a wrong
//! u at free DOFs next to a support, or a wrong λ, shows up as an imbalance — and the second only if
//! the assembled load vector carries the loads the scene asked for.  (A body with no fixed DOF is
//! insensitive to a perturbation of its own u, since Σ_F K δu = 0 there; its balance then tests
//! the multipliers against the applied loads.)

use crate::effects::Effects;
use crate::geometry::Point;
use crate::model::Model;
use crate::scene::Scene;
use crate::solve::contact_forces;

/// The three force figures of one body (per unit thickness times the thickness, i.e. forces).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BodyBalance {
    /// Loads integrated analytically from the scene `[Fx, Fy]`.
    pub applied: [f64; 2],
    /// Resultant contact force −Bᵀλ on the body `[Cx, Cy]`.
    pub contact: [f64; 2],
    /// Support reactions from the Dirichlet rows of K `[Rx, Ry]`.
    pub reaction: [f64; 2],
}

impl BodyBalance {
    /// applied + contact + reaction, per component (zero for a body in equilibrium).
    pub fn imbalance(&self) -> [f64; 2] {
        [0, 1].map(|c| self.applied[c] + self.contact[c] + self.reaction[c])
    }

    /// The largest magnitude among the three figures.
    pub fn scale(&self) -> f64 {
        self.applied
            .iter()
            .chain(&self.contact)
            .chain(&self.reaction)
            .fold(0.0_f64, |m, v| m.max(v.abs()))
    }
}

/// The balance of every body, and the relative imbalance written to `result.json`.
#[derive(Debug, Clone, PartialEq)]
pub struct ForceBalance {
    /// Per body, in scene order.
    pub bodies: Vec<BodyBalance>,
    /// The largest |applied + contact + reaction| over bodies and components, divided by the
    /// largest of the three figures over bodies and components (the absolute value when all of
    /// them vanish).  NaN when any figure is not finite.
    pub relative: f64,
}

/// Applied loads per body, integrated analytically from the scene's effects (see the module
/// docs): tractions over the selected edges, gravity over the bodies' outlines.
pub fn applied_loads(scene: &Scene, model: &Model) -> Vec<[f64; 2]> {
    let effects = Effects::of(scene);
    let mut applied = vec![[0.0; 2]; model.meshes.len()];
    if let Some(tractions) = &effects.tractions {
        tractions.add_resultants(&model.meshes, |name| scene.final_factor(name), &mut applied);
    }
    if let Some(body_force) = &effects.body_force {
        let outlines: Vec<&[Point]> = scene.bodies.iter().map(|b| b.polygon.as_slice()).collect();
        body_force.add_resultants(&outlines, &mut applied);
    }
    applied
}

/// Resultant contact force per body: −Bᵀλ summed over each body's DOFs.
pub fn contact_resultants(model: &Model, multipliers: &[f64]) -> Vec<[f64; 2]> {
    let c = contact_forces(model, multipliers);
    (0..model.meshes.len())
        .map(|b| {
            let mut r = [0.0; 2];
            for d in model.dofs.body_range(b) {
                r[d % 2] += c[d];
            }
            r
        })
        .collect()
}

/// Support reactions per body from the Dirichlet rows of the unconstrained stiffness: Σ over the
/// body's fixed DOFs of (K_D·u)_d − f_d − c_d (assembled load f, contact force c = −Bᵀλ).
pub fn support_reactions(model: &Model, u: &[f64], multipliers: &[f64]) -> Vec<[f64; 2]> {
    let contact = contact_forces(model, multipliers);
    let mut reaction = vec![[0.0; 2]; model.meshes.len()];
    let ku = model.support_forces(u);
    // `fixed_dofs` is sorted and every body's DOFs are one contiguous range.
    let mut body = 0;
    for (&d, k) in model.fixed_dofs.iter().zip(ku) {
        while body + 1 < model.meshes.len() && !model.dofs.body_range(body).contains(&d) {
            body += 1;
        }
        reaction[body][d % 2] += k - model.load[d] - contact[d];
    }
    reaction
}

/// The three figures of every body and the relative imbalance (see the module docs).
///
/// `u` is the full displacement vector (all DOFs), `multipliers` one λ per contact row (empty
/// when the model has none).
pub fn force_balance(scene: &Scene, model: &Model, u: &[f64], multipliers: &[f64]) -> ForceBalance {
    let applied = applied_loads(scene, model);
    let contact = contact_resultants(model, multipliers);
    let reaction = support_reactions(model, u, multipliers);
    let bodies: Vec<BodyBalance> = applied
        .into_iter()
        .zip(contact)
        .zip(reaction)
        .map(|((applied, contact), reaction)| BodyBalance {
            applied,
            contact,
            reaction,
        })
        .collect();
    let mut imbalance = 0.0_f64;
    let mut scale = 0.0_f64;
    let mut finite = true;
    for b in &bodies {
        for v in b.imbalance() {
            finite &= v.is_finite();
            imbalance = imbalance.max(v.abs());
        }
        finite &= b.scale().is_finite();
        scale = scale.max(b.scale());
    }
    let relative = if !finite {
        f64::NAN
    } else if scale > 0.0 {
        imbalance / scale
    } else {
        imbalance
    };
    ForceBalance { bodies, relative }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::MeshLimits;
    use crate::model;

    fn model_of(text: &str) -> (Scene, Model) {
        let scene = Scene::from_toml(text).unwrap();
        let meshes = model::mesh_scene(&scene, &MeshLimits::default()).unwrap();
        let model = model::assemble(&scene, meshes).unwrap().model;
        (scene, model)
    }

    /// A linear traction over part of an edge and gravity, integrated by hand.
    #[test]
    fn applied_loads_are_the_analytic_integrals() {
        let (scene, model) = model_of(
            r#"
            [model]
            plane = "stress"
            thickness = 0.5
            gravity = [0.5, -2.0]
            [[body]]
            name = "b"
            polygon = [[0, 0], [3, 0], [3, 1], [0, 1]]
            hmax = 0.3
            young = 1.0
            poisson = 0.3
            density = 4.0
            [[dirichlet]]
            body = "b"
            region = [0, 0, 0, 1]
            [[neumann]]
            body = "b"
            region = [1, 3, 1, 1]
            points = [[0, 1], [1, 1], [0, 0]]
            tx = [1, 2, 1]
            ty = [0, 3, 5]
            "#,
        );
        // On y = 1: tx = 1 + x, ty = 3x (from the three points); over x ∈ [1, 3]:
        // ∫ tx = 2 + 4 = 6, ∫ ty = 12; times the thickness 0.5.  Gravity: ρ A g t = 4·3·g·0.5.
        let a = applied_loads(&scene, &model)[0];
        let want = [0.5 * 6.0 + 6.0 * 0.5, 0.5 * 12.0 + 6.0 * -2.0];
        for c in 0..2 {
            assert!((a[c] - want[c]).abs() <= 1e-12, "{a:?} vs {want:?}");
        }
    }

    /// Without a solve, u = 0 and λ = 0: the reactions are minus the assembled loads on the
    /// supports, so the imbalance is exactly the load the free DOFs carry.
    #[test]
    fn zero_displacement_leaves_the_free_loads_unbalanced() {
        let (scene, model) = model_of(
            r#"
            [[body]]
            name = "b"
            polygon = [[0, 0], [1, 0], [1, 1], [0, 1]]
            hmax = 0.5
            young = 1.0
            poisson = 0.3
            [[dirichlet]]
            body = "b"
            region = [0, 1, 0, 0]
            [[neumann]]
            body = "b"
            region = [0, 1, 1, 1]
            traction = [0, -1]
            "#,
        );
        let u = vec![0.0; model.dofs.len()];
        let fb = force_balance(&scene, &model, &u, &[]);
        let free_load: f64 = model
            .free
            .iter()
            .filter(|d| *d % 2 == 1)
            .map(|&d| model.load[d])
            .sum();
        assert!((fb.bodies[0].imbalance()[1] - free_load).abs() <= 1e-15);
        assert!((free_load + 1.0).abs() <= 1e-15);
        assert!((fb.relative - 1.0).abs() <= 1e-15);
    }
}
