//! Contact (`[[contact]]`): each pair as a typed [`Interface`] for the contact search, whose
//! rows it contributes.

use super::{Contribution, Discretisation, Effect, EffectError, ModelParts};
use crate::contact::{self, Interface, Side};
use crate::fem::element::Material;
use crate::scene::Scene;

/// Every contact pair of the scene, in scene order.
#[derive(Debug, Clone)]
pub struct ContactEffect<'a> {
    /// The pairs.
    pub interfaces: Vec<Interface<'a>>,
    /// Geometric tolerance.
    pub tol: f64,
}

impl<'a> ContactEffect<'a> {
    /// The scene's `[[contact]]` sections.
    pub fn of(scene: &'a Scene) -> Self {
        let interfaces = scene
            .contacts
            .iter()
            .map(|pair| Interface {
                sides: pair.bodies.map(|b| {
                    let body = &scene.bodies[b];
                    Side {
                        body: b,
                        name: &body.name,
                        outline: &body.polygon,
                        hmax: body.hmax,
                        compliance: Material::of_body(body, scene.plane).surface_compliance(),
                        group: pair.group.as_deref().and_then(|g| body.group(g)),
                    }
                }),
                region: pair.region,
                slave: pair.slave,
                formulation: pair.formulation,
                friction: pair.friction,
            })
            .collect();
        Self {
            interfaces,
            tol: scene.tolerance(),
        }
    }

    /// True when some pair has body `b` as one of its sides.
    pub fn touches(&self, b: usize) -> bool {
        self.interfaces.iter().any(|i| i.touches(b))
    }
}

impl Contribution for ContactEffect<'_> {
    fn effect(&self) -> Effect {
        Effect::Contact
    }

    fn after_supports(&self) -> bool {
        true
    }

    fn contribute(
        &self,
        on: Discretisation<'_>,
        parts: &mut ModelParts,
    ) -> Result<(), EffectError> {
        parts.pairs = contact::contact_rows(&self.interfaces, on.meshes, self.tol)?;
        Ok(())
    }
}
