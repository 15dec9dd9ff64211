//! `[model]` and `[[body]]`: the plane, thickness and gravity; each body's geometry (a polygon,
//! or the keys of a Gmsh body), material and density.  The measures of an outline, the element
//! size and the body force are checked here for polygon bodies and by the import for Gmsh bodies
//! (their outline comes from the file), with the same functions.

use super::values::{check_finite, check_region, exact, points};
use super::{MAX_COEFFICIENT, MIN_COEFFICIENT};
use crate::geometry::{self, Point};
use crate::mesh::{ElementKind, Refinement};
use crate::scene::draft::{DraftBody, PolygonBody, Shape};
use crate::scene::file::{BodySection, ModelSection, Plane, RefineSection};
use crate::scene::{SceneError, REGION_TOLERANCE};

/// The validated `[model]` section.
pub(in crate::scene) struct ModelContext {
    /// Plane strain or plane stress.
    pub plane: Plane,
    /// Thickness (1 for plane strain).
    pub thickness: f64,
    /// Body force per unit mass, if any.
    pub gravity: Option<[f64; 2]>,
}

/// Checks `[model]`: a thickness only in plane stress, positive; gravity two finite numbers.
pub(super) fn validate_model(model: Option<ModelSection>) -> Result<ModelContext, SceneError> {
    let model = model.unwrap_or(ModelSection {
        plane: Plane::Strain,
        thickness: None,
        gravity: None,
    });
    let thickness = match (model.plane, model.thickness) {
        (_, None) => 1.0,
        (Plane::Strain, Some(_)) => {
            return Err(SceneError::invalid(
                "[model]",
                "thickness",
                "applies only to plane = \"stress\" (plane strain is per unit thickness)",
            ))
        }
        (Plane::Stress, Some(t)) if t.is_finite() && t > 0.0 => t,
        (Plane::Stress, Some(t)) => {
            return Err(SceneError::invalid(
                "[model]",
                "thickness",
                format!("must be positive and finite, got {t}"),
            ))
        }
    };
    let gravity = match &model.gravity {
        None => None,
        Some(g) => {
            let g = exact::<2>("[model]", "gravity", g)?;
            check_finite("[model]", "gravity", &g)?;
            Some(g)
        }
    };
    Ok(ModelContext {
        plane: model.plane,
        thickness,
        gravity,
    })
}

/// Checks one `[[body]]` section (`s`: its label).  A polygon body is checked whole; a Gmsh body
/// for the keys it may not have, its material and density (the rest needs its file).
pub(super) fn validate_body(
    b: BodySection,
    s: &str,
    model: &ModelContext,
) -> Result<DraftBody, SceneError> {
    let shape = match body_shape(&b, s)? {
        Some(polygon) => Shape::Polygon(validate_polygon_body(&b, s, polygon, model)?),
        None => {
            check_material(s, b.young, b.poisson, model)?;
            check_density(s, b.density, model)?;
            Shape::Gmsh(b.mesh.unwrap_or_default())
        }
    };
    Ok(DraftBody {
        name: b.name,
        young: b.young,
        poisson: b.poisson,
        density: b.density,
        shape,
    })
}

/// The keys that say what a body is: its polygon's vertices (a polygon body), or `None` for a
/// Gmsh body (`mesh` without `hmax`, `element` or `refine`).
fn body_shape(b: &BodySection, s: &str) -> Result<Option<Vec<Point>>, SceneError> {
    match (&b.polygon, &b.mesh) {
        (Some(_), Some(_)) => Err(SceneError::invalid(
            s,
            "mesh",
            "cannot be combined with `polygon`: a body is a polygon (meshed here) or a Gmsh mesh",
        )),
        (None, None) => Err(SceneError::invalid(
            s,
            "polygon",
            "is missing: give `polygon` (with `hmax`) or `mesh` (a Gmsh .msh file)",
        )),
        (None, Some(_)) => {
            for (given, key) in [
                (b.hmax.is_some(), "hmax"),
                (b.element.is_some(), "element"),
                (!b.refine.is_empty(), "refine"),
            ] {
                if given {
                    return Err(SceneError::invalid(
                        s,
                        key,
                        "does not apply to a body with `mesh`: the Gmsh file fixes the elements",
                    ));
                }
            }
            Ok(None)
        }
        (Some(polygon), None) => {
            if b.hmax.is_none() {
                return Err(SceneError::invalid(
                    s,
                    "hmax",
                    "is missing: a `polygon` body needs `hmax`",
                ));
            }
            Ok(Some(points(s, "polygon", "vertex", polygon)?))
        }
    }
}

/// Checks a polygon body in the order its keys are reported: outline, simplicity, `hmax`,
/// material, element, density, refinements; the polygon comes back counter-clockwise.
fn validate_polygon_body(
    b: &BodySection,
    s: &str,
    mut polygon: Vec<Point>,
    model: &ModelContext,
) -> Result<PolygonBody, SceneError> {
    let hmax = b.hmax.unwrap_or_default();
    let element = b.element.unwrap_or_default();
    let outline = check_outline(s, &polygon)?;
    let tol = REGION_TOLERANCE * outline.size;
    if let Some((i, j)) = geometry::self_intersection(&polygon, tol) {
        return Err(SceneError::invalid(
            s,
            "polygon",
            format!("is not simple: edge {i} meets edge {j} (edges numbered from 0 at the first vertex)"),
        ));
    }
    check_hmax(s, hmax)?;
    check_material(s, b.young, b.poisson, model)?;
    if element == ElementKind::Q1 && !is_axis_aligned_rectangle(&polygon, tol) {
        return Err(SceneError::invalid(
            s,
            "element",
            "\"q1\" needs an axis-aligned rectangle (4 vertices); use \"p1\" for other polygons",
        ));
    }
    if let Some((d, g)) = check_density(s, b.density, model)? {
        check_body_force(s, d, g, model.thickness, outline.area)?;
    }
    let refine = b
        .refine
        .iter()
        .enumerate()
        .map(|(i, r)| check_refinement(&format!("{s}, refine #{}", i + 1), r, hmax, &outline))
        .collect::<Result<Vec<_>, _>>()?;
    if outline.area < 0.0 {
        polygon.reverse();
    }
    Ok(PolygonBody {
        polygon,
        hmax,
        element,
        refine,
    })
}

/// The measures of a body's outline.
pub(in crate::scene) struct Outline {
    /// Bounding box `[x1, x2, y1, y2]`.
    pub bbox: [f64; 4],
    /// Its diagonal.
    pub size: f64,
    /// Signed area (negative when the vertices run clockwise).
    pub area: f64,
}

/// Checks an outline (a polygon's vertices, or a Gmsh body's boundary loop): at least three
/// finite vertices, an area that neither overflows nor vanishes.
pub(in crate::scene) fn check_outline(s: &str, polygon: &[Point]) -> Result<Outline, SceneError> {
    if polygon.len() < 3 {
        return Err(SceneError::invalid(
            s,
            "polygon",
            format!("needs at least 3 vertices, got {}", polygon.len()),
        ));
    }
    let coords: Vec<f64> = polygon.iter().flatten().copied().collect();
    check_finite(s, "polygon", &coords)?;
    let bbox = geometry::bounding_box(polygon.iter());
    let size = (bbox[1] - bbox[0]).hypot(bbox[3] - bbox[2]);
    let area = geometry::signed_area(polygon);
    if !(size * size).is_finite() || !area.is_finite() {
        return Err(SceneError::invalid(
            s,
            "polygon",
            format!(
                "spans {size:e}: coordinates this large make its area overflow; rescale the scene"
            ),
        ));
    }
    if size == 0.0 || area.abs() <= REGION_TOLERANCE * size * size {
        return Err(SceneError::invalid(
            s,
            "polygon",
            format!("has zero area ({area:e})"),
        ));
    }
    Ok(Outline { bbox, size, area })
}

/// Refuses an element size that is not positive and finite.
pub(in crate::scene) fn check_hmax(s: &str, hmax: f64) -> Result<(), SceneError> {
    if !(hmax.is_finite() && hmax > 0.0) {
        return Err(SceneError::invalid(
            s,
            "hmax",
            format!("must be positive and finite, got {hmax}"),
        ));
    }
    Ok(())
}

/// The elastic coefficient the element matrices scale with: λ + 2μ (plane strain) or
/// E/(1 − ν²) (plane stress), before the thickness.
fn elastic_coefficient(young: f64, poisson: f64, plane: Plane) -> f64 {
    match plane {
        Plane::Strain => young * (1.0 - poisson) / ((1.0 + poisson) * (1.0 - 2.0 * poisson)),
        Plane::Stress => young / (1.0 - poisson * poisson),
    }
}

/// Checks E > 0, −1 < ν < 0.5 and a stiffness coefficient within
/// [[`MIN_COEFFICIENT`], [`MAX_COEFFICIENT`]].
fn check_material(
    s: &str,
    young: f64,
    poisson: f64,
    model: &ModelContext,
) -> Result<(), SceneError> {
    if !(young.is_finite() && young > 0.0) {
        return Err(SceneError::invalid(
            s,
            "young",
            format!("must be positive and finite, got {young}"),
        ));
    }
    if !(poisson.is_finite() && poisson > -1.0 && poisson < 0.5) {
        return Err(SceneError::invalid(
            s,
            "poisson",
            format!("must lie in (-1, 0.5), got {poisson}"),
        ));
    }
    let coefficient = elastic_coefficient(young, poisson, model.plane) * model.thickness;
    if !(coefficient.is_finite() && (MIN_COEFFICIENT..=MAX_COEFFICIENT).contains(&coefficient)) {
        let what = match model.plane {
            Plane::Strain => "(λ + 2μ)·thickness",
            Plane::Stress => "E/(1 − ν²)·thickness",
        };
        return Err(SceneError::invalid(
            s,
            "young",
            format!(
                "= {young:e} with poisson = {poisson} and thickness {} gives a stiffness {what} of {coefficient:e}, \
                 outside [{MIN_COEFFICIENT:e}, {MAX_COEFFICIENT:e}]: the element stiffness would \
                 overflow or underflow; rescale the scene's units",
                model.thickness
            ),
        ));
    }
    Ok(())
}

fn is_axis_aligned_rectangle(polygon: &[Point], tol: f64) -> bool {
    if polygon.len() != 4 {
        return false;
    }
    (0..4).all(|i| {
        let (a, b) = (polygon[i], polygon[(i + 1) % 4]);
        let horizontal = (a[1] - b[1]).abs() <= tol;
        let vertical = (a[0] - b[0]).abs() <= tol;
        horizontal != vertical
    })
}

/// Checks that `density` is given exactly when `[model] gravity` is, and positive; returns the
/// density and gravity whose body force [`check_body_force`] bounds.
pub(super) fn check_density(
    s: &str,
    density: Option<f64>,
    model: &ModelContext,
) -> Result<Option<(f64, [f64; 2])>, SceneError> {
    match (model.gravity, density) {
        (Some(_), None) => Err(SceneError::invalid(
            s,
            "density",
            "is required because [model] gravity is set",
        )),
        (Some(_), Some(d)) if !(d.is_finite() && d > 0.0) => Err(SceneError::invalid(
            s,
            "density",
            format!("must be positive and finite, got {d}"),
        )),
        (Some(g), Some(d)) => Ok(Some((d, g))),
        (None, Some(_)) => Err(SceneError::invalid(
            s,
            "density",
            "is only used with [model] gravity; remove it or set gravity",
        )),
        (None, None) => Ok(None),
    }
}

/// Refuses a body force ρ·|g|·thickness·area beyond [`MAX_COEFFICIENT`].
pub(in crate::scene) fn check_body_force(
    s: &str,
    d: f64,
    g: [f64; 2],
    thickness: f64,
    area: f64,
) -> Result<(), SceneError> {
    let force = d * g[0].abs().max(g[1].abs()) * thickness * area.abs();
    if !(force.is_finite() && force <= MAX_COEFFICIENT) {
        return Err(SceneError::invalid(
            s,
            "density",
            format!(
                "= {d:e} with gravity {g:?} gives a body force ρ·|g|·thickness·area of \
                 {force:e}, beyond {MAX_COEFFICIENT:e}: the load would overflow; rescale \
                 the scene's units"
            ),
        ));
    }
    Ok(())
}

/// Checks one `[[body.refine]]` (`section`: its label): a finer size than the body's, not below
/// the mesher's resolution, in a box that meets the body's bounding box.
fn check_refinement(
    section: &str,
    r: &RefineSection,
    hmax: f64,
    outline: &Outline,
) -> Result<Refinement, SceneError> {
    let bbox = outline.bbox;
    let region = check_region(section, &r.region)?;
    if !(r.hmax.is_finite() && r.hmax > 0.0) {
        return Err(SceneError::invalid(
            section,
            "hmax",
            format!("must be positive and finite, got {}", r.hmax),
        ));
    }
    if r.hmax >= hmax {
        return Err(SceneError::invalid(
            section,
            "hmax",
            format!(
                "= {} is not below the body's hmax {}: the region would not be refined",
                r.hmax, hmax
            ),
        ));
    }
    let extent = (bbox[1] - bbox[0]).max(bbox[3] - bbox[2]);
    let smallest = crate::mesh::MIN_RELATIVE_SIZE * extent;
    if r.hmax < smallest {
        return Err(SceneError::invalid(
            section,
            "hmax",
            format!(
                "= {:e} is below the mesher's coordinate resolution: element sizes must be \
                 at least {smallest:.2e} (2⁻³⁰ of the body's extent {extent})",
                r.hmax
            ),
        ));
    }
    let tol = REGION_TOLERANCE * outline.size;
    if region[1] < bbox[0] - tol
        || region[0] > bbox[1] + tol
        || region[3] < bbox[2] - tol
        || region[2] > bbox[3] + tol
    {
        return Err(SceneError::invalid(
            section,
            "region",
            format!("{region:?} lies outside the body's bounding box {bbox:?}"),
        ));
    }
    Ok(Refinement {
        region,
        hmax: r.hmax,
    })
}
