//! Physical groups of Gmsh bodies: the box and nodes a support's or traction's group selects,
//! and the groups of contact pairs; errors name the file and list its groups.

use crate::geometry::{self, Point};
use crate::mesh::gmsh::MeshGroup;
use crate::scene::draft::Place;
use crate::scene::types::Body;
use crate::scene::validate::contact::contact_group_missing;
use crate::scene::validate::place::group_needs_mesh;
use crate::scene::SceneError;

/// A section's box and group: its own box, or the bounding box of its group's boundary nodes
/// (which must hold a boundary node, and with `edges` a boundary edge).
pub(super) fn resolve_place(
    s: &str,
    place: &Place,
    body: &Body,
    edges: bool,
) -> Result<([f64; 4], Option<String>), SceneError> {
    let name = match place {
        Place::Region(region) => return Ok((*region, None)),
        Place::Group(name) => name,
    };
    let g = check_group(s, name, body)?;
    let Some(m) = &body.imported else {
        return Err(group_needs_mesh(s, name, &body.name));
    };
    let (mesh, path) = (&m.mesh, &m.path);
    let on_boundary: Vec<usize> = crate::mesh::boundary_nodes(mesh)
        .into_iter()
        .filter(|n| g.has_node(*n))
        .collect();
    if on_boundary.is_empty() || (edges && g.edges.is_empty()) {
        return Err(SceneError::invalid(
            s,
            "group",
            format!(
                "= {name:?} holds no boundary {} of mesh file {path}",
                if edges { "edge" } else { "node" }
            ),
        ));
    }
    let region = geometry::bounding_box(on_boundary.iter().map(|&n| &mesh.nodes[n]));
    Ok((region, Some(name.to_string())))
}

/// The physical group `name` of `body`'s Gmsh mesh; errors name the file and list its groups.
fn check_group<'a>(s: &str, name: &str, body: &'a Body) -> Result<&'a MeshGroup, SceneError> {
    let Some(m) = &body.imported else {
        return Err(group_needs_mesh(s, name, &body.name));
    };
    m.group(name).ok_or_else(|| {
        SceneError::invalid(
            s,
            "group",
            format!(
                "= {name:?} is not a physical group of mesh file {} ({})",
                m.path,
                m.group_list()
            ),
        )
    })
}

/// A contact pair's group: defined by the mesh of at least one of its bodies, holding a
/// boundary edge of each body whose mesh defines it.
pub(super) fn check_contact_group(
    s: &str,
    name: &str,
    pair: [usize; 2],
    bodies: &[Body],
) -> Result<(), SceneError> {
    let holders: Vec<usize> = pair
        .into_iter()
        .filter(|&k| bodies[k].group(name).is_some())
        .collect();
    if holders.is_empty() {
        let files: Vec<String> = pair
            .iter()
            .filter_map(|&k| {
                bodies[k]
                    .imported
                    .as_ref()
                    .map(|m| format!("mesh file {} ({})", m.path, m.group_list()))
            })
            .collect();
        return Err(contact_group_missing(s, name, &files));
    }
    for k in holders {
        let g = check_group(s, name, &bodies[k])?;
        if g.edges.is_empty() {
            return Err(SceneError::invalid(
                s,
                "group",
                format!(
                    "= {name:?} holds no boundary edge of body {:?}",
                    bodies[k].name
                ),
            ));
        }
    }
    Ok(())
}

/// The boundary nodes of `body`'s group `name`, in node order (none when the body has no mesh
/// or the mesh no such group).
pub(super) fn boundary_points(body: &Body, name: &str) -> Vec<Point> {
    let (Some(m), Some(g)) = (&body.imported, body.group(name)) else {
        return Vec::new();
    };
    let boundary = crate::mesh::boundary_nodes(&m.mesh);
    g.nodes
        .iter()
        .filter(|n| boundary.binary_search(n).is_ok())
        .map(|&node| m.mesh.nodes[node])
        .collect()
}
