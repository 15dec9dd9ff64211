//! Validation of a parsed [`SceneFile`] into a [`Scene`]: every error names the section and the
//! key at fault.
//!
//! Besides ranges and references, validation refuses what would otherwise fail only after
//! meshing, so that `check` and `solve` agree: arrays of the wrong length, names with control
//! characters, elastic constants or body forces that overflow, contact boxes that hold no
//! boundary of one of the pair's bodies, and bodies that nothing holds.

use super::file::{
    BodySection, Component, ContactSection, DirichletSection, ModelSection, NeumannSection, Plane,
    ProbeSection, ReferenceSection, SceneFile,
};
use super::types::{Body, ContactPair, Dirichlet, Neumann, Probe, Reference, Traction};
use super::{Scene, SceneError, REGION_TOLERANCE};
use std::path::Path;
use std::sync::Arc;

use crate::geometry::{self, Point};
use crate::mesh::gmsh::ImportedMesh;
use crate::mesh::{self, Cells, ElementKind, Refinement};

/// Largest elastic stiffness coefficient, (λ + 2μ)·thickness in plane strain or
/// E/(1 − ν²)·thickness in plane stress, and largest body force ρ·|g|·thickness·area of a body,
/// that a scene may ask for: `1e-10 × f64::MAX` ≈ 1.8e298.
///
/// Element matrices multiply the coefficient by geometric factors (up to the cotangent of the
/// smallest angle) and assembly sums a few elements per node; the margin of 10¹⁰ keeps all of
/// that finite.  Only overflow is refused: tiny values (E = 1e-200) are legitimate, since the
/// program nondimensionalises the problem before a backend sees it.
pub const MAX_COEFFICIENT: f64 = 1e-10 * f64::MAX;

/// The smallest stiffness coefficient accepted, 1 / [`MAX_COEFFICIENT`] ≈ 5.6e-299: below it the
/// element stiffness entries (the coefficient times geometric factors of order one in 2D) come
/// close to the subnormal range and lose their digits or vanish (E = 2.2e-308 gave a zero
/// stiffness matrix), so the Cholesky factorisation fails after `check` accepted the scene.
pub const MIN_COEFFICIENT: f64 = 1.0 / MAX_COEFFICIENT;

/// Characters refused in names and the title: Unicode control characters (C0, DEL, C1) and the
/// non-characters U+FFFE and U+FFFF — all of them invalid or unsafe in the XML and JSON the
/// program writes (SVG, VTU, result.json).
pub fn name_forbidden(c: char) -> bool {
    c.is_control() || c == '\u{FFFE}' || c == '\u{FFFF}'
}

/// `body "name"` with the name escaped (quotes, backslashes and control characters).
fn body_label(name: &str) -> String {
    format!("body {name:?}")
}

fn plural(n: usize, one: &str, many: &str) -> String {
    if n == 1 {
        format!("{n} {one}")
    } else {
        format!("{n} {many}")
    }
}

fn numbers(n: usize) -> String {
    plural(n, "number", "numbers")
}

/// A fixed-length array from a list, refusing any other length.
fn exact<const N: usize>(
    section: &str,
    key: &'static str,
    values: &[f64],
) -> Result<[f64; N], SceneError> {
    <[f64; N]>::try_from(values).map_err(|_| {
        SceneError::invalid(
            section,
            key,
            format!("has {}, needs {N}", numbers(values.len())),
        )
    })
}

/// A list of points, each of exactly two numbers (`what`: "vertex" or "point", numbered from 1).
fn points(
    section: &str,
    key: &'static str,
    what: &str,
    list: &[Vec<f64>],
) -> Result<Vec<Point>, SceneError> {
    list.iter()
        .enumerate()
        .map(|(i, p)| {
            <[f64; 2]>::try_from(p.as_slice()).map_err(|_| {
                SceneError::invalid(
                    section,
                    key,
                    format!("{what} {} has {}, needs 2", i + 1, numbers(p.len())),
                )
            })
        })
        .collect()
}

/// Refuses a name or title holding a character that [`name_forbidden`] rejects.
fn check_text(section: &str, key: &'static str, text: &str) -> Result<(), SceneError> {
    match text.chars().find(|c| name_forbidden(*c)) {
        Some(c) => Err(SceneError::invalid(
            section,
            key,
            format!(
                "contains the control character U+{:04X}; use printable characters only",
                c as u32
            ),
        )),
        None => Ok(()),
    }
}

fn check_finite(section: &str, key: &'static str, values: &[f64]) -> Result<(), SceneError> {
    match values.iter().find(|v| !v.is_finite()) {
        Some(v) => Err(SceneError::invalid(
            section,
            key,
            format!("must be finite, got {v}"),
        )),
        None => Ok(()),
    }
}

fn check_region(section: &str, region: &[f64]) -> Result<[f64; 4], SceneError> {
    let region = exact::<4>(section, "region", region)?;
    check_finite(section, "region", &region)?;
    if region[0] > region[1] || region[2] > region[3] {
        return Err(SceneError::invalid(
            section,
            "region",
            format!("must be [x1, x2, y1, y2] with x1 ≤ x2 and y1 ≤ y2, got {region:?}"),
        ));
    }
    Ok(region)
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

/// The elastic coefficient the element matrices scale with: λ + 2μ (plane strain) or
/// E/(1 − ν²) (plane stress), before the thickness.
fn elastic_coefficient(young: f64, poisson: f64, plane: Plane) -> f64 {
    match plane {
        Plane::Strain => young * (1.0 - poisson) / ((1.0 + poisson) * (1.0 - 2.0 * poisson)),
        Plane::Stress => young / (1.0 - poisson * poisson),
    }
}

struct ModelContext {
    plane: Plane,
    thickness: f64,
    gravity: Option<[f64; 2]>,
}

/// Reads a body's Gmsh file (`mesh = "…"`), relative to `base` (the scene file's directory).
fn import_mesh(s: &str, file: &str, base: Option<&Path>) -> Result<ImportedMesh, SceneError> {
    let Some(base) = base else {
        return Err(SceneError::invalid(
            s,
            "mesh",
            format!(
                "= {file:?} is relative to the scene file, but this scene was given as text with \
                 no file: read it with Scene::from_path or Scene::from_toml_in(text, directory)"
            ),
        ));
    };
    let path = base.join(file);
    mesh::gmsh::read_msh(&path, &path.display().to_string()).map_err(|e| {
        SceneError::invalid(s, "mesh", format!("= {file:?} ({}) {}", e.path, e.problem))
    })
}

/// The geometry of a body: polygon, hmax, element and the imported mesh, if any.
type BodyShape = (Vec<Point>, f64, ElementKind, Option<Arc<ImportedMesh>>);

fn body_shape(b: &BodySection, s: &str, base: Option<&Path>) -> Result<BodyShape, SceneError> {
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
        (None, Some(file)) => {
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
            let imported = import_mesh(s, file, base)?;
            let element = match imported.mesh.cells {
                Cells::Triangles(_) => ElementKind::P1,
                Cells::Quads(_) => ElementKind::Q1,
            };
            let hmax = imported.mesh.max_edge();
            Ok((
                imported.outline.clone(),
                hmax,
                element,
                Some(Arc::new(imported)),
            ))
        }
        (Some(polygon), None) => {
            let hmax = b.hmax.ok_or_else(|| {
                SceneError::invalid(s, "hmax", "is missing: a `polygon` body needs `hmax`")
            })?;
            let polygon = points(s, "polygon", "vertex", polygon)?;
            Ok((polygon, hmax, b.element.unwrap_or_default(), None))
        }
    }
}

fn validate_body(
    b: BodySection,
    model: &ModelContext,
    base: Option<&Path>,
) -> Result<Body, SceneError> {
    let s = body_label(&b.name);
    let tol_rel = REGION_TOLERANCE;
    let (polygon, hmax, element, imported) = body_shape(&b, &s, base)?;
    if polygon.len() < 3 {
        return Err(SceneError::invalid(
            &s,
            "polygon",
            format!("needs at least 3 vertices, got {}", polygon.len()),
        ));
    }
    let coords: Vec<f64> = polygon.iter().flatten().copied().collect();
    check_finite(&s, "polygon", &coords)?;
    let bbox = geometry::bounding_box(polygon.iter());
    let size = (bbox[1] - bbox[0]).hypot(bbox[3] - bbox[2]);
    let area = geometry::signed_area(&polygon);
    if !(size * size).is_finite() || !area.is_finite() {
        return Err(SceneError::invalid(
            &s,
            "polygon",
            format!(
                "spans {size:e}: coordinates this large make its area overflow; rescale the scene"
            ),
        ));
    }
    if size == 0.0 || area.abs() <= tol_rel * size * size {
        return Err(SceneError::invalid(
            &s,
            "polygon",
            format!("has zero area ({area:e})"),
        ));
    }
    // A Gmsh outline is the boundary of a valid mesh (checked on import): no need to look for
    // crossings among its many vertices.
    if imported.is_none() {
        if let Some((i, j)) = geometry::self_intersection(&polygon, tol_rel * size) {
            return Err(SceneError::invalid(
                &s,
                "polygon",
                format!("is not simple: edge {i} meets edge {j} (edges numbered from 0 at the first vertex)"),
            ));
        }
    }
    if !(hmax.is_finite() && hmax > 0.0) {
        return Err(SceneError::invalid(
            &s,
            "hmax",
            format!("must be positive and finite, got {hmax}"),
        ));
    }
    if !(b.young.is_finite() && b.young > 0.0) {
        return Err(SceneError::invalid(
            &s,
            "young",
            format!("must be positive and finite, got {}", b.young),
        ));
    }
    if !(b.poisson.is_finite() && b.poisson > -1.0 && b.poisson < 0.5) {
        return Err(SceneError::invalid(
            &s,
            "poisson",
            format!("must lie in (-1, 0.5), got {}", b.poisson),
        ));
    }
    let coefficient = elastic_coefficient(b.young, b.poisson, model.plane) * model.thickness;
    if !(coefficient.is_finite() && (MIN_COEFFICIENT..=MAX_COEFFICIENT).contains(&coefficient)) {
        let what = match model.plane {
            Plane::Strain => "(λ + 2μ)·thickness",
            Plane::Stress => "E/(1 − ν²)·thickness",
        };
        return Err(SceneError::invalid(
            &s,
            "young",
            format!(
                "= {:e} with poisson = {} and thickness {} gives a stiffness {what} of {coefficient:e}, \
                 outside [{MIN_COEFFICIENT:e}, {MAX_COEFFICIENT:e}]: the element stiffness would \
                 overflow or underflow; rescale the scene's units",
                b.young, b.poisson, model.thickness
            ),
        ));
    }
    if imported.is_none()
        && element == ElementKind::Q1
        && !is_axis_aligned_rectangle(&polygon, tol_rel * size)
    {
        return Err(SceneError::invalid(
            &s,
            "element",
            "\"q1\" needs an axis-aligned rectangle (4 vertices); use \"p1\" for other polygons",
        ));
    }
    match (model.gravity, b.density) {
        (Some(_), None) => {
            return Err(SceneError::invalid(
                &s,
                "density",
                "is required because [model] gravity is set",
            ))
        }
        (Some(_), Some(d)) if !(d.is_finite() && d > 0.0) => {
            return Err(SceneError::invalid(
                &s,
                "density",
                format!("must be positive and finite, got {d}"),
            ))
        }
        (Some(g), Some(d)) => {
            let force = d * g[0].abs().max(g[1].abs()) * model.thickness * area.abs();
            if !(force.is_finite() && force <= MAX_COEFFICIENT) {
                return Err(SceneError::invalid(
                    &s,
                    "density",
                    format!(
                        "= {d:e} with gravity {g:?} gives a body force ρ·|g|·thickness·area of \
                         {force:e}, beyond {MAX_COEFFICIENT:e}: the load would overflow; rescale \
                         the scene's units"
                    ),
                ));
            }
        }
        (None, Some(_)) => {
            return Err(SceneError::invalid(
                &s,
                "density",
                "is only used with [model] gravity; remove it or set gravity",
            ))
        }
        (None, None) => {}
    }
    let mut refine = Vec::with_capacity(b.refine.len());
    for (i, r) in b.refine.iter().enumerate() {
        let section = format!("{s}, refine #{}", i + 1);
        let region = check_region(&section, &r.region)?;
        if !(r.hmax.is_finite() && r.hmax > 0.0) {
            return Err(SceneError::invalid(
                &section,
                "hmax",
                format!("must be positive and finite, got {}", r.hmax),
            ));
        }
        if r.hmax >= hmax {
            return Err(SceneError::invalid(
                &section,
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
                &section,
                "hmax",
                format!(
                    "= {:e} is below the mesher's coordinate resolution: element sizes must be \
                     at least {smallest:.2e} (2⁻³⁰ of the body's extent {extent})",
                    r.hmax
                ),
            ));
        }
        let tol = tol_rel * size;
        if region[1] < bbox[0] - tol
            || region[0] > bbox[1] + tol
            || region[3] < bbox[2] - tol
            || region[2] > bbox[3] + tol
        {
            return Err(SceneError::invalid(
                &section,
                "region",
                format!("{region:?} lies outside the body's bounding box {bbox:?}"),
            ));
        }
        refine.push(Refinement {
            region,
            hmax: r.hmax,
        });
    }
    let mut polygon = polygon;
    if area < 0.0 {
        polygon.reverse();
    }
    Ok(Body {
        name: b.name,
        polygon,
        hmax,
        element,
        young: b.young,
        poisson: b.poisson,
        density: b.density,
        refine,
        imported,
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

fn validate_model(model: Option<ModelSection>) -> Result<ModelContext, SceneError> {
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

/// Looks bodies up by name; the error names the section and `key`.
struct Names<'a>(&'a [Body]);

impl Names<'_> {
    fn find(&self, section: &str, key: &'static str, name: &str) -> Result<usize, SceneError> {
        self.0.iter().position(|b| b.name == name).ok_or_else(|| {
            let known: Vec<String> = self.0.iter().map(|b| format!("{:?}", b.name)).collect();
            SceneError::invalid(
                section,
                key,
                format!(
                    "names an unknown body {name:?} (bodies: {})",
                    known.join(", ")
                ),
            )
        })
    }
}

/// What a `[[dirichlet]]` or `[[neumann]]` section acts on: its box, or the physical group of
/// the body's Gmsh mesh (then the box is the group's bounding box).
fn region_or_group(
    s: &str,
    region: Option<&[f64]>,
    group: Option<&str>,
    body: &Body,
    edges: bool,
) -> Result<([f64; 4], Option<String>), SceneError> {
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
        (Some(r), None) => Ok((check_region(s, r)?, None)),
        (None, Some(name)) => {
            let g = check_group(s, name, body)?;
            let (mesh, path) = match &body.imported {
                Some(m) => (&m.mesh, &m.path),
                None => unreachable_group(s)?,
            };
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
    }
}

/// Never reached ([`check_group`] refuses polygon bodies); an error rather than a panic.
fn unreachable_group<T>(s: &str) -> Result<T, SceneError> {
    Err(SceneError::invalid(s, "group", "needs a body with `mesh`"))
}

/// The physical group `name` of `body`'s Gmsh mesh; errors name the file and list its groups.
fn check_group<'a>(
    s: &str,
    name: &str,
    body: &'a Body,
) -> Result<&'a crate::mesh::gmsh::MeshGroup, SceneError> {
    let Some(m) = &body.imported else {
        return Err(SceneError::invalid(
            s,
            "group",
            format!(
                "= {name:?} needs a body with `mesh` (a Gmsh file), but body {:?} is a polygon; \
                 use `region`",
                body.name
            ),
        ));
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

fn validate_dirichlet(
    i: usize,
    d: DirichletSection,
    bodies: &[Body],
    tol: f64,
) -> Result<Dirichlet, SceneError> {
    let s = format!("dirichlet #{} (body {:?})", i + 1, d.body);
    let body = Names(bodies).find(&s, "body", &d.body)?;
    let (region, group) = region_or_group(
        &s,
        d.region.as_deref(),
        d.group.as_deref(),
        &bodies[body],
        false,
    )?;
    let value = match &d.value {
        None => [0.0, 0.0],
        Some(v) => exact::<2>(&s, "value", v)?,
    };
    check_finite(&s, "value", &value)?;
    let components = match d.components {
        None => [true, true],
        Some(list) => {
            if list.is_empty() {
                return Err(SceneError::invalid(
                    &s,
                    "components",
                    "must name at least one of \"x\", \"y\"",
                ));
            }
            let x = list.iter().filter(|c| **c == Component::X).count();
            let y = list.len() - x;
            if x > 1 || y > 1 {
                return Err(SceneError::invalid(&s, "components", "repeats a component"));
            }
            [x == 1, y == 1]
        }
    };
    if group.is_none() && geometry::boundary_in_box(&bodies[body].polygon, &region, tol).is_none() {
        return Err(SceneError::invalid(
            &s,
            "region",
            format!(
                "{region:?} matches no boundary node of body {:?}",
                bodies[body].name
            ),
        ));
    }
    Ok(Dirichlet {
        body,
        region,
        group,
        value,
        components,
    })
}

fn validate_neumann(
    i: usize,
    n: NeumannSection,
    bodies: &[Body],
    tol: f64,
) -> Result<Neumann, SceneError> {
    let s = format!("neumann #{} (body {:?})", i + 1, n.body);
    let body = Names(bodies).find(&s, "body", &n.body)?;
    let (region, group) = region_or_group(
        &s,
        n.region.as_deref(),
        n.group.as_deref(),
        &bodies[body],
        true,
    )?;
    let traction =
        match (n.traction, n.points, n.tx, n.ty) {
            (Some(t), None, None, None) => {
                let t = exact::<2>(&s, "traction", &t)?;
                check_finite(&s, "traction", &t)?;
                Traction::constant(t)
            }
            (None, Some(list), Some(tx), Some(ty)) => {
                let list = points(&s, "points", "point", &list)?;
                let points = <[Point; 3]>::try_from(list.as_slice()).map_err(|_| {
                    SceneError::invalid(
                        &s,
                        "points",
                        format!("has {}, needs 3", plural(list.len(), "point", "points")),
                    )
                })?;
                let tx = exact::<3>(&s, "tx", &tx)?;
                let ty = exact::<3>(&s, "ty", &ty)?;
                let coords: Vec<f64> = points.iter().flatten().copied().collect();
                check_finite(&s, "points", &coords)?;
                check_finite(&s, "tx", &tx)?;
                check_finite(&s, "ty", &ty)?;
                let spread = geometry::distance(points[0], points[1])
                    .max(geometry::distance(points[1], points[2]))
                    .max(geometry::distance(points[0], points[2]));
                let twice_area = geometry::orient(points[0], points[1], points[2]).abs();
                if spread == 0.0 || twice_area <= 1e-10 * spread * spread {
                    return Err(SceneError::invalid(
                        &s,
                        "points",
                        format!("must not be collinear, got {points:?}"),
                    ));
                }
                let (Some(cx), Some(cy)) = (
                    linear_coefficients(&points, &tx),
                    linear_coefficients(&points, &ty),
                ) else {
                    return Err(SceneError::invalid(
                        &s,
                        "points",
                        format!("must not be collinear, got {points:?}"),
                    ));
                };
                Traction {
                    coefficients: [cx, cy],
                }
            }
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
    match geometry::boundary_in_box(&bodies[body].polygon, &region, tol) {
        _ if group.is_some() => {}
        // A box touching the boundary in a single point clips only O(tol) of it.
        Some(len) if len > 10.0 * tol => {}
        _ => {
            return Err(SceneError::invalid(
                &s,
                "region",
                format!(
                    "{region:?} contains no boundary edge of body {:?}",
                    bodies[body].name
                ),
            ))
        }
    }
    Ok(Neumann {
        body,
        region,
        group,
        traction,
    })
}

fn validate_contact(
    i: usize,
    c: ContactSection,
    bodies: &[Body],
    earlier: &[ContactPair],
    tol: f64,
) -> Result<ContactPair, SceneError> {
    let s = format!("contact #{} ({})", i + 1, {
        let names: Vec<String> = c.bodies.iter().map(|n| format!("{n:?}")).collect();
        names.join(" – ")
    });
    let [name_a, name_b] = <[String; 2]>::try_from(c.bodies.clone()).map_err(|_| {
        SceneError::invalid(
            &s,
            "bodies",
            format!(
                "names {}, needs 2",
                plural(c.bodies.len(), "body", "bodies")
            ),
        )
    })?;
    let names = Names(bodies);
    let a = names.find(&s, "bodies", &name_a)?;
    let b = names.find(&s, "bodies", &name_b)?;
    if a == b {
        return Err(SceneError::invalid(
            &s,
            "bodies",
            format!("names body {name_a:?} twice; a pair needs two bodies"),
        ));
    }
    let region = match &c.region {
        None => None,
        Some(r) => Some(check_region(&s, r)?),
    };
    let slave = match c.slave {
        None => None,
        Some(name) => {
            let k = names.find(&s, "slave", &name)?;
            if k != a && k != b {
                return Err(SceneError::invalid(
                    &s,
                    "slave",
                    format!("{name:?} is not one of the pair's bodies"),
                ));
            }
            Some(k)
        }
    };
    if earlier
        .iter()
        .any(|p| p.bodies == [a, b] || p.bodies == [b, a])
    {
        return Err(SceneError::invalid(
            &s,
            "bodies",
            "repeats a pair already given",
        ));
    }
    // The contact search takes candidate nodes of both bodies inside the box; a box that misses
    // one body's boundary would fail only after meshing.
    if let Some(r) = &region {
        for k in [a, b] {
            if geometry::boundary_in_box(&bodies[k].polygon, r, tol).is_none() {
                return Err(SceneError::invalid(
                    &s,
                    "region",
                    format!(
                        "{r:?} holds no boundary of body {:?}; the box must contain part of both \
                         bodies' boundaries",
                        bodies[k].name
                    ),
                ));
            }
        }
    }
    // A group restricts each body of the pair whose Gmsh mesh defines it; at least one must.
    if let Some(name) = &c.group {
        let holders: Vec<usize> = [a, b]
            .into_iter()
            .filter(|&k| bodies[k].group(name).is_some())
            .collect();
        if holders.is_empty() {
            let files: Vec<String> = [a, b]
                .iter()
                .filter_map(|&k| {
                    bodies[k]
                        .imported
                        .as_ref()
                        .map(|m| format!("mesh file {} ({})", m.path, m.group_list()))
                })
                .collect();
            return Err(SceneError::invalid(
                &s,
                "group",
                if files.is_empty() {
                    format!("= {name:?} needs a body with `mesh` (a Gmsh file); both bodies are polygons")
                } else {
                    format!(
                        "= {name:?} is a physical group of neither body: {}",
                        files.join("; ")
                    )
                },
            ));
        }
        for k in holders {
            let g = check_group(&s, name, &bodies[k])?;
            if g.edges.is_empty() {
                return Err(SceneError::invalid(
                    &s,
                    "group",
                    format!(
                        "= {name:?} holds no boundary edge of body {:?}",
                        bodies[k].name
                    ),
                ));
            }
        }
    }
    Ok(ContactPair {
        bodies: [a, b],
        region,
        group: c.group,
        slave,
        formulation: c.formulation,
    })
}

fn validate_probe(
    i: usize,
    p: ProbeSection,
    bodies: &[Body],
    earlier: &[Probe],
    tol: f64,
) -> Result<Probe, SceneError> {
    let s = format!("probe #{} {:?}", i + 1, p.name);
    check_text(&s, "name", &p.name)?;
    let body = Names(bodies).find(&s, "body", &p.body)?;
    let point = exact::<2>(&s, "point", &p.point)?;
    check_finite(&s, "point", &point)?;
    if !geometry::contains(&bodies[body].polygon, point, tol) {
        return Err(SceneError::invalid(
            &s,
            "point",
            format!("{point:?} lies outside body {:?}", bodies[body].name),
        ));
    }
    if earlier.iter().any(|q| q.name == p.name) {
        return Err(SceneError::invalid(
            &s,
            "name",
            "is used by more than one probe",
        ));
    }
    Ok(Probe {
        name: p.name,
        body,
        point,
    })
}

/// Refuses two supports of one body that prescribe different values to the same component on
/// boundary points both their boxes hold (the model refuses it after meshing otherwise: the
/// crossings of every box become mesh nodes, so a shared boundary piece always holds a node).
/// Values count as different as in the model: |a − b| > 1e-12 max(|a|, |b|).
fn check_dirichlet_conflicts(dirichlet: &[Dirichlet], bodies: &[Body]) -> Result<(), SceneError> {
    for (l, second) in dirichlet.iter().enumerate() {
        for (k, first) in dirichlet[..l].iter().enumerate() {
            // Groups: the model finds conflicting values node by node (FemError::ConflictingDirichlet).
            if first.body != second.body || first.group.is_some() || second.group.is_some() {
                continue;
            }
            let Some(c) = (0..2).find(|&c| {
                first.components[c]
                    && second.components[c]
                    && (first.value[c] - second.value[c]).abs()
                        > 1e-12 * first.value[c].abs().max(second.value[c].abs())
            }) else {
                continue;
            };
            let (a, b) = (first.region, second.region);
            let both = [
                a[0].max(b[0]),
                a[1].min(b[1]),
                a[2].max(b[2]),
                a[3].min(b[3]),
            ];
            let polygon = &bodies[second.body].polygon;
            let n = polygon.len();
            // Only boundary inside both boxes proper is sure to hold a node of both (their
            // crossings); boxes that overlap only within the tolerance are left to the model,
            // so that validation never refuses what the model would accept.
            let place = (0..n).find_map(|i| {
                geometry::clip_segment_to_box(polygon[i], polygon[(i + 1) % n], &both, 0.0)
            });
            if let Some((p, _)) = place {
                return Err(SceneError::invalid(
                    format!(
                        "dirichlet #{} (body {:?})",
                        l + 1,
                        bodies[second.body].name
                    ),
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

/// Relative eigenvalue below which a rigid-body mode counts as free here.  Smaller than the
/// model's 1e-10 (`fem::free_rigid_modes`), so that validation refuses only bodies the model
/// would refuse too; between the two thresholds the model decides.
const FREE_MODE_THRESHOLD: f64 = 1e-13;

/// Number of rigid-body modes (of 3) that the Dirichlet supports of `body` leave free.
///
/// A support constrains every boundary point inside its box; the constraints of a rigid motion
/// u = (a − θy, b + θx) are linear in the point, so the clipped ends of the boundary pieces
/// inside each box (which become mesh nodes) span them all.
fn free_rigid_modes(body: usize, bodies: &[Body], dirichlet: &[Dirichlet], tol: f64) -> usize {
    let polygon = &bodies[body].polygon;
    let bbox = geometry::bounding_box(polygon.iter());
    let centre = [0.5 * (bbox[0] + bbox[1]), 0.5 * (bbox[2] + bbox[3])];
    let size = (bbox[1] - bbox[0])
        .hypot(bbox[3] - bbox[2])
        .max(f64::MIN_POSITIVE);
    let mut gram = nalgebra::Matrix3::<f64>::zeros();
    let n = polygon.len();
    let mut add = |point: Point, d: &Dirichlet| {
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
        // A group holds exactly its (boundary) nodes.
        if let (Some(name), Some(m)) = (&d.group, &bodies[body].imported) {
            if let Some(g) = m.group(name) {
                let boundary = crate::mesh::boundary_nodes(&m.mesh);
                for &node in g.nodes.iter().filter(|n| boundary.binary_search(n).is_ok()) {
                    add(m.mesh.nodes[node], d);
                }
            }
            continue;
        }
        for i in 0..n {
            let Some((p, q)) =
                geometry::clip_segment_to_box(polygon[i], polygon[(i + 1) % n], &d.region, tol)
            else {
                continue;
            };
            for point in [p, q] {
                add(point, d);
            }
        }
    }
    let eig = gram.symmetric_eigen();
    let largest = eig.eigenvalues.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    eig.eigenvalues
        .iter()
        .filter(|v| v.abs() <= FREE_MODE_THRESHOLD * largest.max(1.0))
        .count()
}

pub(super) fn validate(file: SceneFile, base: Option<&Path>) -> Result<Scene, SceneError> {
    if let Some(title) = &file.title {
        check_text("scene", "title", title)?;
    }
    if file.body.is_empty() {
        return Err(SceneError::invalid(
            "scene",
            "body",
            "needs at least one [[body]] table",
        ));
    }
    let model = validate_model(file.model)?;

    // Bodies: names unique and printable, geometry and material sane.
    let mut bodies: Vec<Body> = Vec::with_capacity(file.body.len());
    for b in file.body {
        if b.name.trim().is_empty() {
            return Err(SceneError::invalid("[[body]]", "name", "must not be empty"));
        }
        check_text(&body_label(&b.name), "name", &b.name)?;
        if bodies.iter().any(|o| o.name == b.name) {
            return Err(SceneError::invalid(
                body_label(&b.name),
                "name",
                "is used by more than one body",
            ));
        }
        bodies.push(validate_body(b, &model, base)?);
    }
    let bbox = geometry::bounding_box(bodies.iter().flat_map(|b| b.polygon.iter()));
    let tol = REGION_TOLERANCE * (bbox[1] - bbox[0]).hypot(bbox[3] - bbox[2]);

    let dirichlet = file
        .dirichlet
        .into_iter()
        .enumerate()
        .map(|(i, d)| validate_dirichlet(i, d, &bodies, tol))
        .collect::<Result<Vec<_>, _>>()?;
    check_dirichlet_conflicts(&dirichlet, &bodies)?;
    let neumann = file
        .neumann
        .into_iter()
        .enumerate()
        .map(|(i, n)| validate_neumann(i, n, &bodies, tol))
        .collect::<Result<Vec<_>, _>>()?;
    let mut contacts = Vec::with_capacity(file.contact.len());
    for (i, c) in file.contact.into_iter().enumerate() {
        let pair = validate_contact(i, c, &bodies, &contacts, tol)?;
        contacts.push(pair);
    }
    let mut probes = Vec::with_capacity(file.probe.len());
    for (i, p) in file.probe.into_iter().enumerate() {
        let probe = validate_probe(i, p, &bodies, &probes, tol)?;
        probes.push(probe);
    }

    // Every body must be held: by supports that remove its rigid-body modes, or by a contact pair
    // (the model then regularises the free modes through the contact).
    for (k, body) in bodies.iter().enumerate() {
        if contacts.iter().any(|c| c.bodies.contains(&k)) {
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
        let free = free_rigid_modes(k, &bodies, &dirichlet, tol);
        if free > 0 {
            return Err(SceneError::invalid(
                body_label(&body.name),
                "dirichlet",
                format!(
                    "supports leave {} free and the body is in no [[contact]] pair; support more \
                     boundary (a point holds no rotation, one component holds no translation \
                     along the other)",
                    plural(free, "rigid-body mode", "rigid-body modes")
                ),
            ));
        }
    }

    let reference = file
        .reference
        .map(|r| validate_reference(r, &contacts))
        .transpose()?;

    Ok(Scene {
        title: file.title.unwrap_or_else(|| "untitled".to_string()),
        plane: model.plane,
        thickness: model.thickness,
        gravity: model.gravity,
        bodies,
        dirichlet,
        neumann,
        contacts,
        probes,
        reference,
    })
}

fn validate_reference(
    r: ReferenceSection,
    contacts: &[ContactPair],
) -> Result<Reference, SceneError> {
    let s = "[reference]";
    let pair = r.pair.unwrap_or(1);
    if pair == 0 || pair > contacts.len() {
        return Err(SceneError::invalid(
            s,
            "pair",
            format!(
                "= {pair} names no contact pair (the scene has {})",
                plural(contacts.len(), "pair", "pairs")
            ),
        ));
    }
    let centre = match &r.centre {
        None => None,
        Some(c) => {
            let c = exact::<2>(s, "centre", c)?;
            check_finite(s, "centre", &c)?;
            Some(c)
        }
    };
    for (key, value) in [
        ("half_width", r.half_width),
        ("peak_pressure", r.peak_pressure),
        ("pressure", r.pressure),
    ] {
        if let Some(v) = value {
            if !(v.is_finite() && v > 0.0) {
                return Err(SceneError::invalid(
                    s,
                    key,
                    format!("must be positive and finite, got {v}"),
                ));
            }
        }
    }
    if r.half_width.is_none() && r.peak_pressure.is_none() && r.pressure.is_none() {
        return Err(SceneError::invalid(
            s,
            "pressure",
            "is missing: a reference states `pressure` (uniform) or `half_width` / \
             `peak_pressure` (Hertz)",
        ));
    }
    if r.half_width.is_some() && centre.is_none() {
        return Err(SceneError::invalid(
            s,
            "centre",
            "is required with `half_width`: the half-width is measured from it",
        ));
    }
    Ok(Reference {
        pair: pair - 1,
        centre,
        half_width: r.half_width,
        peak_pressure: r.peak_pressure,
        pressure: r.pressure,
    })
}
