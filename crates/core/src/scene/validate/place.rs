//! What a `[[dirichlet]]` or `[[neumann]]` section acts on: its box, or a physical group of the
//! body's Gmsh mesh (whose existence the import checks, since it needs the file).

use super::values::check_region;
use crate::scene::draft::{DraftBody, Place, Shape};
use crate::scene::SceneError;

/// The section's box (`region`) or group (`group`): exactly one, a box well formed, a group
/// only on a Gmsh body.
pub(super) fn validate_place(
    s: &str,
    region: Option<&[f64]>,
    group: Option<&str>,
    body: &DraftBody,
) -> Result<Place, SceneError> {
    match (region, group) {
        (Some(_), Some(_)) => Err(SceneError::invalid(
            s,
            "group",
            "cannot be combined with `region`: give one of them",
        )),
        (None, None) => Err(SceneError::invalid(
            s,
            "region",
            "is missing: give `region` (a box [x1, x2, y1, y2]) or `group` (a physical group of \
             the body's Gmsh mesh)",
        )),
        (Some(r), None) => Ok(Place::Region(check_region(s, r)?)),
        (None, Some(name)) => match body.shape {
            Shape::Polygon(_) => Err(group_needs_mesh(s, name, &body.name)),
            Shape::Gmsh(_) => Ok(Place::Group(name.to_string())),
        },
    }
}

/// The error for a group named on a polygon body.
pub(in crate::scene) fn group_needs_mesh(s: &str, name: &str, body: &str) -> SceneError {
    SceneError::invalid(
        s,
        "group",
        format!(
            "= {name:?} needs a body with `mesh` (a Gmsh file), but body {body:?} is a polygon; \
             use `region`"
        ),
    )
}
