//! Surface tractions (`[[neumann]]`): a linear traction field on selected boundary edges, as
//! consistent nodal forces, and its resultant integrated analytically (for the force balance).

use super::{Contribution, Discretisation, Effect, EffectError, ModelParts, Selection};
use crate::fem::{Dofs, FemError};
use crate::geometry::{self, Point};
use crate::mesh::Mesh;
use crate::scene::{Scene, Traction};

/// One traction.
#[derive(Debug, Clone)]
pub struct Load<'a> {
    /// Its name, for the load path (`[[step]]`).
    pub name: Option<&'a str>,
    /// Body index.
    pub body: usize,
    /// Body name (for messages).
    pub body_name: &'a str,
    /// The edges it acts on.
    pub selection: Selection<'a>,
    /// The scene's region box (for messages; with a group, the group's bounding box).
    pub region: [f64; 4],
    /// The traction field (force per unit length and unit thickness).
    pub traction: Traction,
}

/// Every traction of the scene, in scene order.
#[derive(Debug, Clone)]
pub struct Tractions<'a> {
    /// The tractions.
    pub list: Vec<Load<'a>>,
    /// Out-of-plane thickness.
    pub thickness: f64,
    /// Geometric tolerance of the box selections.
    pub tol: f64,
}

impl<'a> Tractions<'a> {
    /// The scene's `[[neumann]]` sections.
    pub fn of(scene: &'a Scene) -> Self {
        let list = scene
            .neumann
            .iter()
            .map(|n| {
                let body = &scene.bodies[n.body];
                Load {
                    name: n.name.as_deref(),
                    body: n.body,
                    body_name: &body.name,
                    selection: Selection::of(n.group.as_deref(), n.region, body),
                    region: n.region,
                    traction: n.traction,
                }
            })
            .collect();
        Self {
            list,
            thickness: scene.thickness,
            tol: scene.tolerance(),
        }
    }

    /// The boundary edges of `mesh` that `load` acts on, with their ends' positions.
    fn edges<'m>(
        &'m self,
        load: &'m Load<'_>,
        mesh: &'m Mesh,
    ) -> impl Iterator<Item = ([usize; 2], [Point; 2])> + 'm {
        mesh.boundary.iter().filter_map(move |&[a, b]| {
            let (pa, pb) = (mesh.nodes[a], mesh.nodes[b]);
            load.selection
                .edge([a, b], [pa, pb], self.tol)
                .then_some(([a, b], [pa, pb]))
        })
    }

    /// Adds the consistent nodal forces to `f`; refuses a traction that selects no edge.
    pub fn add_nodal(&self, meshes: &[Mesh], dofs: &Dofs, f: &mut [f64]) -> Result<(), FemError> {
        let t = self.thickness;
        for (k, nm) in self.list.iter().enumerate() {
            let mut matched = false;
            for ([a, b], [pa, pb]) in self.edges(nm, &meshes[nm.body]) {
                matched = true;
                // Linear along the edge: consistent loads L(2tₐ + t_b)/6, L(tₐ + 2t_b)/6.
                let len = geometry::distance(pa, pb);
                let (ta, tb) = (nm.traction.at(pa), nm.traction.at(pb));
                for c in 0..2 {
                    f[dofs.dof(nm.body, a, c)] += t * len * (2.0 * ta[c] + tb[c]) / 6.0;
                    f[dofs.dof(nm.body, b, c)] += t * len * (ta[c] + 2.0 * tb[c]) / 6.0;
                }
            }
            if !matched {
                return Err(FemError::EmptyRegion {
                    section: format!("neumann #{}", k + 1),
                    region: nm.region,
                    body: nm.body_name.to_string(),
                    what: "edge",
                });
            }
        }
        Ok(())
    }

    /// Adds each traction's resultant ∫ t ds to its body's entry of `applied` (analytic: over
    /// a straight edge a linear field integrates to length × the mean of its end values), times
    /// `factor` of the traction's name (`None`: unnamed) — the load path's factor at the state
    /// reported ([`crate::scene::Scene::final_factor`]; `|_| 1.0` for the full load).
    pub fn add_resultants(
        &self,
        meshes: &[Mesh],
        factor: impl Fn(Option<&str>) -> f64,
        applied: &mut [[f64; 2]],
    ) {
        for nm in &self.list {
            let Some(mesh) = meshes.get(nm.body) else {
                continue;
            };
            let t = self.thickness * factor(nm.name);
            for (_, [pa, pb]) in self.edges(nm, mesh) {
                let len = geometry::distance(pa, pb);
                let (ta, tb) = (nm.traction.at(pa), nm.traction.at(pb));
                for c in 0..2 {
                    applied[nm.body][c] += t * len * 0.5 * (ta[c] + tb[c]);
                }
            }
        }
    }
}

impl Contribution for Tractions<'_> {
    fn effect(&self) -> Effect {
        Effect::Neumann
    }

    fn contribute(
        &self,
        on: Discretisation<'_>,
        parts: &mut ModelParts,
    ) -> Result<(), EffectError> {
        Ok(self.add_nodal(on.meshes, on.dofs, &mut parts.load)?)
    }
}
