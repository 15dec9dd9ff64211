//! The mesh stage: every body meshed (or its Gmsh mesh taken), with nodes where the scene's
//! boxes and the other bodies' corners cross its boundary.

use super::error::ModelError;
use crate::geometry::Point;
use crate::mesh::{self, BodyGeometry, Mesh, MeshLimits};
use crate::scene::Scene;

/// Meshes every body.  Break points make the mesh exact where it matters: other bodies' corners
/// on this boundary (conforming interfaces), the crossings of every region box that names the
/// body (supported and loaded lengths exact for every hmax) and those of the body's
/// `[[body.refine]]` boxes.
pub fn mesh_scene(scene: &Scene, limits: &MeshLimits) -> Result<Vec<Mesh>, ModelError> {
    let tol = scene.tolerance();
    let mut meshes = Vec::with_capacity(scene.bodies.len());
    for (b, body) in scene.bodies.iter().enumerate() {
        // A Gmsh body brings its mesh: nothing to mesh, no break points (its groups select
        // nodes and edges exactly).
        if let Some(imported) = &body.imported {
            meshes.push(imported_mesh(body, imported, limits)?);
            continue;
        }
        let breaks = break_points(scene, b, tol);
        let geometry = BodyGeometry {
            polygon: &body.polygon,
            hmax: body.hmax,
            element: body.element,
            breakpoints: &breaks,
            refine: &body.refine,
            tol,
        };
        let m = mesh::mesh_body(&geometry, limits).map_err(|source| ModelError::Mesh {
            body: body.name.clone(),
            source,
        })?;
        meshes.push(m);
    }
    Ok(meshes)
}

/// A Gmsh body's own mesh, refused beyond the element limit.
pub(super) fn imported_mesh(
    body: &crate::scene::Body,
    imported: &crate::mesh::gmsh::ImportedMesh,
    limits: &MeshLimits,
) -> Result<Mesh, ModelError> {
    let cells = imported.mesh.cells.len();
    if cells > limits.max_elements {
        return Err(ModelError::Mesh {
            body: body.name.clone(),
            source: mesh::MeshError::TooManyElements {
                estimated: cells,
                limit: limits.max_elements,
            },
        });
    }
    Ok(imported.mesh.clone())
}

/// Where body `b`'s boundary must have a node: the other bodies' corners, the crossings of the
/// region boxes of its supports and loads, of its refine boxes (away from corners) and of its
/// contact boxes (away from its own corners, unless nothing else would give the box a node).
pub(super) fn break_points(scene: &Scene, b: usize, tol: f64) -> Vec<Point> {
    let body = &scene.bodies[b];
    let mut breaks: Vec<Point> = scene
        .bodies
        .iter()
        .enumerate()
        .filter(|(o, _)| *o != b)
        .flat_map(|(_, o)| o.polygon.iter().copied())
        .collect();
    let mut regions: Vec<[f64; 4]> = Vec::new();
    regions.extend(
        scene
            .dirichlet
            .iter()
            .filter(|d| d.body == b)
            .map(|d| d.region),
    );
    regions.extend(
        scene
            .neumann
            .iter()
            .filter(|n| n.body == b)
            .map(|n| n.region),
    );
    for r in &regions {
        breaks.extend(mesh::box_crossings(&body.polygon, r, tol));
    }
    // Refined regions' crossings too, so the fine zone starts and ends at a node (and two
    // bodies with the same refine boxes break their shared edges at the same points).  A
    // crossing closer than half the region's size to a vertex would only make a short edge
    // (a sliver) next to a node that is exact already: skipped.  Any body's vertex counts,
    // so that two bodies sharing an edge skip the same crossings and stay conforming.
    for r in &body.refine {
        breaks.extend(
            mesh::box_crossings(&body.polygon, &r.region, tol)
                .into_iter()
                .filter(|p| {
                    scene
                        .bodies
                        .iter()
                        .flat_map(|o| o.polygon.iter())
                        .all(|v| crate::geometry::distance(*v, *p) >= 0.5 * r.hmax)
                }),
        );
    }
    // A contact box only selects candidate nodes; a crossing just beside a corner (the thin
    // box's side along a side edge) would force a sliver element, so those are skipped.
    let near_corner = |p: &Point| {
        body.polygon
            .iter()
            .any(|v| crate::geometry::distance(*v, *p) < 0.25 * body.hmax)
    };
    for c in scene.contacts.iter().filter(|c| c.bodies.contains(&b)) {
        if let Some(r) = &c.region {
            let crossings = mesh::box_crossings(&body.polygon, r, tol);
            let holds_vertex = body
                .polygon
                .iter()
                .any(|v| crate::geometry::in_box(*v, r, tol));
            let kept: Vec<Point> = crossings
                .iter()
                .copied()
                .filter(|p| !near_corner(p))
                .collect();
            // A box that meets the boundary only next to a corner (and holds no vertex)
            // would otherwise hold no mesh node: keep its crossings, sliver or not, so that
            // "the box meets the boundary" (checked at validation) always gives a node.
            if kept.is_empty() && !holds_vertex {
                breaks.extend(crossings);
            } else {
                breaks.extend(kept);
            }
        }
    }
    breaks
}
