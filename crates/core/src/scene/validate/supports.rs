//! `[[dirichlet]]`: the body, the box or group, the value and components; where the box meets
//! the boundary, and two supports that prescribe different values at one boundary point.

use super::outlines::Outlines;
use super::place::validate_place;
use super::values::{check_finite, exact, Names};
use crate::geometry::{self, Point};
use crate::scene::draft::{DraftBody, DraftDirichlet, Place};
use crate::scene::file::{Component, DirichletSection};
use crate::scene::SceneError;

/// `dirichlet #i (body "name")`, `i` from 0.
pub(in crate::scene) fn dirichlet_label(i: usize, body: &str) -> String {
    format!("dirichlet #{} (body {:?})", i + 1, body)
}

/// Checks one `[[dirichlet]]` section; with `outlines`, also that its box holds boundary.
pub(super) fn validate_dirichlet(
    i: usize,
    d: DirichletSection,
    bodies: &[DraftBody],
    outlines: Option<&Outlines>,
) -> Result<DraftDirichlet, SceneError> {
    let s = dirichlet_label(i, &d.body);
    let body = Names(bodies).find(&s, "body", &d.body)?;
    let place = validate_place(&s, d.region.as_deref(), d.group.as_deref(), &bodies[body])?;
    let value = match &d.value {
        None => [0.0, 0.0],
        Some(v) => exact::<2>(&s, "value", v)?,
    };
    check_finite(&s, "value", &value)?;
    let components = match d.components {
        None => [true, true],
        Some(list) => components(&s, &list)?,
    };
    if let (Place::Region(region), Some(outlines)) = (&place, outlines) {
        check_dirichlet_boundary(&s, region, body, outlines)?;
    }
    Ok(DraftDirichlet {
        name: d.name,
        body,
        place,
        value,
        components,
    })
}

/// `[x, y]`: which components a non-empty list without repeats names.
fn components(s: &str, list: &[Component]) -> Result<[bool; 2], SceneError> {
    if list.is_empty() {
        return Err(SceneError::invalid(
            s,
            "components",
            "must name at least one of \"x\", \"y\"",
        ));
    }
    let x = list.iter().filter(|c| **c == Component::X).count();
    let y = list.len() - x;
    if x > 1 || y > 1 {
        return Err(SceneError::invalid(s, "components", "repeats a component"));
    }
    Ok([x == 1, y == 1])
}

/// Refuses a support box that holds no boundary node of its body.
pub(in crate::scene) fn check_dirichlet_boundary(
    s: &str,
    region: &[f64; 4],
    body: usize,
    outlines: &Outlines,
) -> Result<(), SceneError> {
    if geometry::boundary_in_box(outlines.polygon(body), region, outlines.tol).is_none() {
        return Err(SceneError::invalid(
            s,
            "region",
            format!(
                "{region:?} matches no boundary node of body {:?}",
                outlines.name(body)
            ),
        ));
    }
    Ok(())
}

/// Refuses two supports of one body that prescribe different values to the same component on
/// boundary points both their boxes hold (the model refuses it after meshing otherwise: the
/// crossings of every box become mesh nodes, so a shared boundary piece always holds a node).
/// Values count as different as in the model: |a − b| > 1e-12 max(|a|, |b|).  Only bodies
/// whose outline `outline` gives are looked at (validation: the polygon bodies; import: the
/// Gmsh bodies).
pub(in crate::scene) fn check_dirichlet_conflicts<'a>(
    dirichlet: &[DraftDirichlet],
    name: impl Fn(usize) -> &'a str,
    outline: impl Fn(usize) -> Option<&'a [Point]>,
) -> Result<(), SceneError> {
    for (l, second) in dirichlet.iter().enumerate() {
        for (k, first) in dirichlet[..l].iter().enumerate() {
            // Groups: the model finds conflicting values node by node (FemError::ConflictingDirichlet).
            let (Place::Region(a), Place::Region(b)) = (&first.place, &second.place) else {
                continue;
            };
            if first.body != second.body {
                continue;
            }
            let Some(polygon) = outline(second.body) else {
                continue;
            };
            let Some(c) = conflicting_component(first, second) else {
                continue;
            };
            let both = [
                a[0].max(b[0]),
                a[1].min(b[1]),
                a[2].max(b[2]),
                a[3].min(b[3]),
            ];
            let n = polygon.len();
            // Only boundary inside both boxes proper is sure to hold a node of both (their
            // crossings); boxes that overlap only within the tolerance are left to the model,
            // so that validation never refuses what the model would accept.
            let place = (0..n).find_map(|i| {
                geometry::clip_segment_to_box(polygon[i], polygon[(i + 1) % n], &both, 0.0)
            });
            if let Some((p, _)) = place {
                return Err(SceneError::invalid(
                    dirichlet_label(l, name(second.body)),
                    "value",
                    format!(
                        "prescribes {} = {} where dirichlet #{} prescribes {} (both regions hold the \
                         boundary at ({}, {})); give both the same value or make the regions \
                         disjoint",
                        ["x", "y"][c],
                        second.value[c],
                        k + 1,
                        first.value[c],
                        p[0],
                        p[1]
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// The first component both supports prescribe, with different values.
fn conflicting_component(first: &DraftDirichlet, second: &DraftDirichlet) -> Option<usize> {
    (0..2).find(|&c| {
        first.components[c]
            && second.components[c]
            && (first.value[c] - second.value[c]).abs()
                > 1e-12 * first.value[c].abs().max(second.value[c].abs())
    })
}
