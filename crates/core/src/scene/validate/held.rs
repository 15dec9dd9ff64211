//! Every body must be held: by supports that remove its rigid-body modes, or by a contact pair
//! (the model then regularises the free modes through the contact).

use super::outlines::Outlines;
use super::values::{body_label, plural};
use crate::geometry::{self, Point};
use crate::scene::draft::{DraftBody, DraftDirichlet, Place};
use crate::scene::types::ContactPair;
use crate::scene::SceneError;

/// Relative eigenvalue below which a rigid-body mode counts as free here.  Smaller than the
/// model's 1e-10 (`fem::free_rigid_modes`), so that validation refuses only bodies the model
/// would refuse too; between the two thresholds the model decides.
const FREE_MODE_THRESHOLD: f64 = 1e-13;

/// True when body `k` is in a contact pair (and so needs no support of its own).
pub(in crate::scene) fn in_contact(k: usize, contacts: &[ContactPair]) -> bool {
    contacts.iter().any(|c| c.bodies.contains(&k))
}

/// Refuses a body in no contact pair that has no support; with `outlines`, also one whose
/// supports leave a rigid-body mode free.
pub(super) fn check_held(
    bodies: &[DraftBody],
    contacts: &[ContactPair],
    dirichlet: &[DraftDirichlet],
    outlines: Option<&Outlines>,
) -> Result<(), SceneError> {
    for (k, body) in bodies.iter().enumerate() {
        if in_contact(k, contacts) {
            continue;
        }
        let supports = dirichlet.iter().filter(|d| d.body == k).count();
        if supports == 0 {
            return Err(SceneError::invalid(
                body_label(&body.name),
                "dirichlet",
                "is missing: nothing holds this body (no [[dirichlet]] support and no [[contact]] \
                 pair); add a support or a contact pair",
            ));
        }
        if let Some(outlines) = outlines {
            // Groups name Gmsh bodies only, whose outlines validation does not know.
            check_rigid_modes(k, outlines, dirichlet, &|_| Vec::new())?;
        }
    }
    Ok(())
}

/// Refuses body `k` when its supports leave a rigid-body mode free; `group_points` gives the
/// boundary nodes of a physical group of the body's mesh.
pub(in crate::scene) fn check_rigid_modes(
    k: usize,
    outlines: &Outlines,
    dirichlet: &[DraftDirichlet],
    group_points: &dyn Fn(&str) -> Vec<Point>,
) -> Result<(), SceneError> {
    let free = free_rigid_modes(k, outlines, dirichlet, group_points);
    if free > 0 {
        return Err(SceneError::invalid(
            body_label(outlines.name(k)),
            "dirichlet",
            format!(
                "supports leave {} free and the body is in no [[contact]] pair; support more \
                 boundary (a point holds no rotation, one component holds no translation \
                 along the other)",
                plural(free, "rigid-body mode", "rigid-body modes")
            ),
        ));
    }
    Ok(())
}

/// Number of rigid-body modes (of 3) that the Dirichlet supports of `body` leave free.
///
/// A support constrains every boundary point inside its box; the constraints of a rigid motion
/// u = (a − θy, b + θx) are linear in the point, so the clipped ends of the boundary pieces
/// inside each box (which become mesh nodes) span them all.  A group holds exactly its
/// boundary nodes (`group_points`).
fn free_rigid_modes(
    body: usize,
    outlines: &Outlines,
    dirichlet: &[DraftDirichlet],
    group_points: &dyn Fn(&str) -> Vec<Point>,
) -> usize {
    let polygon = outlines.polygon(body);
    let bbox = geometry::bounding_box(polygon.iter());
    let centre = [0.5 * (bbox[0] + bbox[1]), 0.5 * (bbox[2] + bbox[3])];
    let size = (bbox[1] - bbox[0])
        .hypot(bbox[3] - bbox[2])
        .max(f64::MIN_POSITIVE);
    let mut gram = nalgebra::Matrix3::<f64>::zeros();
    let mut add = |point: Point, d: &DraftDirichlet| {
        let (x, y) = ((point[0] - centre[0]) / size, (point[1] - centre[1]) / size);
        if d.components[0] {
            let r = nalgebra::Vector3::new(1.0, 0.0, -y);
            gram += r * r.transpose();
        }
        if d.components[1] {
            let r = nalgebra::Vector3::new(0.0, 1.0, x);
            gram += r * r.transpose();
        }
    };
    for d in dirichlet.iter().filter(|d| d.body == body) {
        let points = match &d.place {
            Place::Group(name) => group_points(name),
            Place::Region(region) => clipped_ends(polygon, region, outlines.tol),
        };
        for point in points {
            add(point, d);
        }
    }
    let eig = gram.symmetric_eigen();
    let largest = eig.eigenvalues.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    eig.eigenvalues
        .iter()
        .filter(|v| v.abs() <= FREE_MODE_THRESHOLD * largest.max(1.0))
        .count()
}

/// The ends of the pieces of each boundary edge inside `region`, edge by edge.
fn clipped_ends(polygon: &[Point], region: &[f64; 4], tol: f64) -> Vec<Point> {
    let n = polygon.len();
    (0..n)
        .filter_map(|i| {
            geometry::clip_segment_to_box(polygon[i], polygon[(i + 1) % n], region, tol)
        })
        .flat_map(|(p, q)| [p, q])
        .collect()
}
