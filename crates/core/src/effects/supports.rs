//! Supports (`[[dirichlet]]`): prescribed displacement components on selected boundary nodes.

use super::{Contribution, Discretisation, Effect, EffectError, ModelParts, Selection};
use crate::fem::{boundary_nodes, Dofs, FemError};
use crate::mesh::Mesh;
use crate::scene::Scene;

/// One support.
#[derive(Debug, Clone)]
pub struct Support<'a> {
    /// Body index.
    pub body: usize,
    /// Body name (for messages).
    pub body_name: &'a str,
    /// The nodes it holds.
    pub selection: Selection<'a>,
    /// The scene's region box (for messages; with a group, the group's bounding box).
    pub region: [f64; 4],
    /// Prescribed `[ux, uy]`.
    pub value: [f64; 2],
    /// Which components are prescribed (`[x, y]`).
    pub components: [bool; 2],
}

/// Every support of the scene, in scene order.
#[derive(Debug, Clone)]
pub struct Supports<'a> {
    /// The supports.
    pub list: Vec<Support<'a>>,
    /// Geometric tolerance of the box selections.
    pub tol: f64,
}

impl<'a> Supports<'a> {
    /// The scene's `[[dirichlet]]` sections.
    pub fn of(scene: &'a Scene) -> Self {
        let list = scene
            .dirichlet
            .iter()
            .map(|d| {
                let body = &scene.bodies[d.body];
                Support {
                    body: d.body,
                    body_name: &body.name,
                    selection: Selection::of(d.group.as_deref(), d.region, body),
                    region: d.region,
                    value: d.value,
                    components: d.components,
                }
            })
            .collect();
        Self {
            list,
            tol: scene.tolerance(),
        }
    }

    /// Fixes the selected DOFs in `fixed` (value, index of the first support fixing it).
    /// Refuses two supports that prescribe different values to one DOF, and a support that
    /// selects no node.
    pub fn prescribe(
        &self,
        meshes: &[Mesh],
        dofs: &Dofs,
        fixed: &mut [Option<(f64, usize)>],
    ) -> Result<(), FemError> {
        for (k, d) in self.list.iter().enumerate() {
            let mesh = &meshes[d.body];
            let mut matched = false;
            for n in boundary_nodes(mesh) {
                let p = mesh.nodes[n];
                if !d.selection.node(n, p, self.tol) {
                    continue;
                }
                matched = true;
                for c in (0..2).filter(|c| d.components[*c]) {
                    let dof = dofs.dof(d.body, n, c);
                    let value = d.value[c];
                    match fixed[dof] {
                        Some((old, first))
                            if (old - value).abs() > 1e-12 * old.abs().max(value.abs()) =>
                        {
                            return Err(FemError::ConflictingDirichlet {
                                first: first + 1,
                                second: k + 1,
                                body: d.body_name.to_string(),
                                component: ["x", "y"][c],
                                x: p[0],
                                y: p[1],
                                a: old,
                                b: value,
                            });
                        }
                        Some(_) => {}
                        None => fixed[dof] = Some((value, k)),
                    }
                }
            }
            if !matched {
                return Err(FemError::EmptyRegion {
                    section: format!("dirichlet #{}", k + 1),
                    region: d.region,
                    body: d.body_name.to_string(),
                    what: "node",
                });
            }
        }
        Ok(())
    }
}

impl Contribution for Supports<'_> {
    fn effect(&self) -> Effect {
        Effect::Dirichlet
    }

    fn contribute(
        &self,
        on: Discretisation<'_>,
        parts: &mut ModelParts,
    ) -> Result<(), EffectError> {
        Ok(self.prescribe(on.meshes, on.dofs, &mut parts.fixed)?)
    }
}
