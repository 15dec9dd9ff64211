//! `[[neumann]]`: the body, the box or group, a constant traction or a linear field through
//! three points; where the box meets the boundary.

use super::outlines::Outlines;
use super::place::validate_place;
use super::values::{check_finite, exact, plural, points, Names};
use crate::geometry::{self, Point};
use crate::scene::draft::{DraftBody, DraftNeumann, Place};
use crate::scene::file::NeumannSection;
use crate::scene::types::Traction;
use crate::scene::SceneError;

/// `neumann #i (body "name")`, `i` from 0.
pub(in crate::scene) fn neumann_label(i: usize, body: &str) -> String {
    format!("neumann #{} (body {:?})", i + 1, body)
}

/// Checks one `[[neumann]]` section; with `outlines`, also that its box holds a boundary edge.
pub(super) fn validate_neumann(
    i: usize,
    n: NeumannSection,
    bodies: &[DraftBody],
    outlines: Option<&Outlines>,
) -> Result<DraftNeumann, SceneError> {
    let s = neumann_label(i, &n.body);
    let body = Names(bodies).find(&s, "body", &n.body)?;
    let place = validate_place(&s, n.region.as_deref(), n.group.as_deref(), &bodies[body])?;
    let traction =
        match (n.traction, n.points, n.tx, n.ty) {
            (Some(t), None, None, None) => {
                let t = exact::<2>(&s, "traction", &t)?;
                check_finite(&s, "traction", &t)?;
                Traction::constant(t)
            }
            (None, Some(list), Some(tx), Some(ty)) => linear_traction(&s, &list, &tx, &ty)?,
            (Some(_), _, _, _) => return Err(SceneError::invalid(
                &s,
                "traction",
                "cannot be combined with points/tx/ty: give a constant traction or a linear field",
            )),
            _ => {
                return Err(SceneError::invalid(
                    &s,
                    "traction",
                    "is missing: give `traction = [tx, ty]` or all of `points`, `tx`, `ty`",
                ))
            }
        };
    if let (Place::Region(region), Some(outlines)) = (&place, outlines) {
        check_neumann_boundary(&s, region, body, outlines)?;
    }
    Ok(DraftNeumann {
        name: n.name,
        body,
        place,
        traction,
    })
}

/// The linear field through `tx` and `ty` at three non-collinear points.
fn linear_traction(
    s: &str,
    list: &[Vec<f64>],
    tx: &[f64],
    ty: &[f64],
) -> Result<Traction, SceneError> {
    let list = points(s, "points", "point", list)?;
    let points = <[Point; 3]>::try_from(list.as_slice()).map_err(|_| {
        SceneError::invalid(
            s,
            "points",
            format!("has {}, needs 3", plural(list.len(), "point", "points")),
        )
    })?;
    let tx = exact::<3>(s, "tx", tx)?;
    let ty = exact::<3>(s, "ty", ty)?;
    let coords: Vec<f64> = points.iter().flatten().copied().collect();
    check_finite(s, "points", &coords)?;
    check_finite(s, "tx", &tx)?;
    check_finite(s, "ty", &ty)?;
    let collinear = || {
        SceneError::invalid(
            s,
            "points",
            format!("must not be collinear, got {points:?}"),
        )
    };
    let spread = geometry::distance(points[0], points[1])
        .max(geometry::distance(points[1], points[2]))
        .max(geometry::distance(points[0], points[2]));
    let twice_area = geometry::orient(points[0], points[1], points[2]).abs();
    if spread == 0.0 || twice_area <= 1e-10 * spread * spread {
        return Err(collinear());
    }
    let (Some(cx), Some(cy)) = (
        linear_coefficients(&points, &tx),
        linear_coefficients(&points, &ty),
    ) else {
        return Err(collinear());
    };
    Ok(Traction {
        coefficients: [cx, cy],
    })
}

/// Solves for (a, b, c) with a·x + b·y + c = value at three points.
fn linear_coefficients(points: &[Point; 3], values: &[f64; 3]) -> Option<[f64; 3]> {
    let m = nalgebra::Matrix3::new(
        points[0][0],
        points[0][1],
        1.0,
        points[1][0],
        points[1][1],
        1.0,
        points[2][0],
        points[2][1],
        1.0,
    );
    let rhs = nalgebra::Vector3::new(values[0], values[1], values[2]);
    m.lu().solve(&rhs).map(|v| [v[0], v[1], v[2]])
}

/// Refuses a traction box that holds no boundary edge of its body (a box touching the boundary
/// in a single point clips only O(tol) of it).
pub(in crate::scene) fn check_neumann_boundary(
    s: &str,
    region: &[f64; 4],
    body: usize,
    outlines: &Outlines,
) -> Result<(), SceneError> {
    let tol = outlines.tol;
    match geometry::boundary_in_box(outlines.polygon(body), region, tol) {
        Some(len) if len > 10.0 * tol => Ok(()),
        _ => Err(SceneError::invalid(
            s,
            "region",
            format!(
                "{region:?} contains no boundary edge of body {:?}",
                outlines.name(body)
            ),
        )),
    }
}
