//! Scenes: the TOML contract of `SCENE.md`, parsed with unknown keys refused, then validated into
//! typed values whose errors name the section, the body and the key at fault.
//!
//! ```
//! use signorini_core::scene::Scene;
//! let scene = Scene::from_toml(r#"
//!     [[body]]
//!     name = "block"
//!     polygon = [[0, 0], [1, 0], [1, 1], [0, 1]]
//!     hmax = 0.5
//!     young = 1.0
//!     poisson = 0.3
//!     [[dirichlet]]
//!     body = "block"
//!     region = [0, 1, 0, 0]
//! "#).unwrap();
//! assert_eq!(scene.bodies[0].name, "block");
//! let err = Scene::from_toml("[[body]]\nname = 'b'\nyoung = -1.0").unwrap_err();
//! assert!(err.to_string().contains("polygon"));
//! ```

mod file;

use std::path::Path;

pub use file::{
    BodySection, Component, ContactSection, DirichletSection, ModelSection, NeumannSection, Plane,
    ProbeSection, SceneFile,
};

use crate::geometry::{self, Point};
use crate::mesh::ElementKind;

/// Relative tolerance (× scene size) used to match regions and points to the geometry.
pub const REGION_TOLERANCE: f64 = 1e-8;

/// A scene that could not be read or is not valid.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file could not be read.
    #[error("cannot read scene file {path}")]
    Read {
        /// The path given.
        path: String,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The TOML is malformed or has unknown or mistyped keys (the message carries line and column).
    #[error("scene is not valid TOML for signorini: {0}")]
    Syntax(String),
    /// A value is out of range or inconsistent.
    #[error("{section}: `{key}` {reason}")]
    Invalid {
        /// Where: e.g. `body "upper"` or `dirichlet #2 (body "lower")`.
        section: String,
        /// The offending key.
        key: &'static str,
        /// What is wrong, with the value.
        reason: String,
    },
}

impl SceneError {
    fn invalid(section: impl Into<String>, key: &'static str, reason: impl Into<String>) -> Self {
        SceneError::Invalid {
            section: section.into(),
            key,
            reason: reason.into(),
        }
    }
}

/// One elastic body.
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    /// Unique name.
    pub name: String,
    /// Vertices, counter-clockwise (reordered if given clockwise).
    pub polygon: Vec<Point>,
    /// Largest element edge.
    pub hmax: f64,
    /// Element type.
    pub element: ElementKind,
    /// Young's modulus E.
    pub young: f64,
    /// Poisson's ratio ν.
    pub poisson: f64,
    /// Mass density (only used with gravity).
    pub density: Option<f64>,
}

/// A prescribed displacement on the boundary nodes in a box.
#[derive(Debug, Clone, PartialEq)]
pub struct Dirichlet {
    /// Body index.
    pub body: usize,
    /// Box `[x1, x2, y1, y2]`.
    pub region: [f64; 4],
    /// Prescribed `[ux, uy]`.
    pub value: [f64; 2],
    /// Which components are prescribed (`[x, y]`).
    pub components: [bool; 2],
}

/// A surface traction field t(x, y) = (a·x + b·y + c) per component.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Traction {
    /// `[[a, b, c] for tx, [a, b, c] for ty]`.
    pub coefficients: [[f64; 3]; 2],
}

impl Traction {
    /// A constant traction.
    pub fn constant(t: [f64; 2]) -> Self {
        Self {
            coefficients: [[0.0, 0.0, t[0]], [0.0, 0.0, t[1]]],
        }
    }

    /// The traction at a point.
    pub fn at(&self, p: Point) -> [f64; 2] {
        let f = |c: &[f64; 3]| c[0] * p[0] + c[1] * p[1] + c[2];
        [f(&self.coefficients[0]), f(&self.coefficients[1])]
    }
}

/// A traction on the boundary edges in a box.
#[derive(Debug, Clone, PartialEq)]
pub struct Neumann {
    /// Body index.
    pub body: usize,
    /// Box `[x1, x2, y1, y2]`.
    pub region: [f64; 4],
    /// The traction field (force per unit length and unit thickness).
    pub traction: Traction,
}

/// A pair of bodies that may touch.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactPair {
    /// The two body indices.
    pub bodies: [usize; 2],
    /// Optional box limiting candidate nodes.
    pub region: Option<[f64; 4]>,
    /// Slave body, when the scene names it.
    pub slave: Option<usize>,
}

/// A point whose displacement is reported.
#[derive(Debug, Clone, PartialEq)]
pub struct Probe {
    /// Name.
    pub name: String,
    /// Body index.
    pub body: usize,
    /// Point of the undeformed body.
    pub point: Point,
}

/// A validated scene.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// Title (the file's, or "untitled").
    pub title: String,
    /// Plane strain or plane stress.
    pub plane: Plane,
    /// Thickness (1 for plane strain).
    pub thickness: f64,
    /// Body force per unit mass, if any.
    pub gravity: Option<[f64; 2]>,
    /// Bodies.
    pub bodies: Vec<Body>,
    /// Prescribed displacements.
    pub dirichlet: Vec<Dirichlet>,
    /// Tractions.
    pub neumann: Vec<Neumann>,
    /// Contact pairs.
    pub contacts: Vec<ContactPair>,
    /// Probes.
    pub probes: Vec<Probe>,
}

impl Scene {
    /// Reads and validates a scene file.
    pub fn from_path(path: &Path) -> Result<Self, SceneError> {
        let text = std::fs::read_to_string(path).map_err(|source| SceneError::Read {
            path: path.display().to_string(),
            source,
        })?;
        Self::from_toml(&text)
    }

    /// Parses and validates a scene from TOML text.
    pub fn from_toml(text: &str) -> Result<Self, SceneError> {
        let file: SceneFile =
            toml::from_str(text).map_err(|e| SceneError::Syntax(e.to_string()))?;
        validate(file)
    }

    /// Diagonal of the bounding box of all bodies: the scene's length scale.
    pub fn size(&self) -> f64 {
        let b = geometry::bounding_box(self.bodies.iter().flat_map(|b| b.polygon.iter()));
        (b[1] - b[0]).hypot(b[3] - b[2])
    }

    /// Absolute tolerance for matching regions and points: [`REGION_TOLERANCE`] × size.
    pub fn tolerance(&self) -> f64 {
        REGION_TOLERANCE * self.size()
    }

    /// Index of the body with this name.
    pub fn body_index(&self, name: &str) -> Option<usize> {
        self.bodies.iter().position(|b| b.name == name)
    }
}

fn body_label(name: &str) -> String {
    format!("body \"{name}\"")
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

fn check_region(section: &str, region: &[f64; 4]) -> Result<(), SceneError> {
    check_finite(section, "region", region)?;
    if region[0] > region[1] || region[2] > region[3] {
        return Err(SceneError::invalid(
            section,
            "region",
            format!("must be [x1, x2, y1, y2] with x1 ≤ x2 and y1 ≤ y2, got {region:?}"),
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

fn validate_body(b: BodySection, tol_rel: f64, gravity: bool) -> Result<Body, SceneError> {
    let s = body_label(&b.name);
    if b.polygon.len() < 3 {
        return Err(SceneError::invalid(
            &s,
            "polygon",
            format!("needs at least 3 vertices, got {}", b.polygon.len()),
        ));
    }
    let coords: Vec<f64> = b.polygon.iter().flatten().copied().collect();
    check_finite(&s, "polygon", &coords)?;
    let bbox = geometry::bounding_box(b.polygon.iter());
    let size = (bbox[1] - bbox[0]).hypot(bbox[3] - bbox[2]);
    let area = geometry::signed_area(&b.polygon);
    if size == 0.0 || area.abs() <= tol_rel * size * size {
        return Err(SceneError::invalid(
            &s,
            "polygon",
            format!("has zero area ({area:e})"),
        ));
    }
    if let Some((i, j)) = geometry::self_intersection(&b.polygon, tol_rel * size) {
        return Err(SceneError::invalid(
            &s,
            "polygon",
            format!("is not simple: edge {i} meets edge {j} (edges numbered from 0 at the first vertex)"),
        ));
    }
    if !(b.hmax.is_finite() && b.hmax > 0.0) {
        return Err(SceneError::invalid(
            &s,
            "hmax",
            format!("must be positive and finite, got {}", b.hmax),
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
    if b.element == ElementKind::Q1 && !is_axis_aligned_rectangle(&b.polygon, tol_rel * size) {
        return Err(SceneError::invalid(
            &s,
            "element",
            "\"q1\" needs an axis-aligned rectangle (4 vertices); use \"p1\" for other polygons",
        ));
    }
    match (gravity, b.density) {
        (true, None) => {
            return Err(SceneError::invalid(
                &s,
                "density",
                "is required because [model] gravity is set",
            ))
        }
        (true, Some(d)) if !(d.is_finite() && d > 0.0) => {
            return Err(SceneError::invalid(
                &s,
                "density",
                format!("must be positive and finite, got {d}"),
            ))
        }
        (false, Some(_)) => {
            return Err(SceneError::invalid(
                &s,
                "density",
                "is only used with [model] gravity; remove it or set gravity",
            ))
        }
        _ => {}
    }
    let mut polygon = b.polygon;
    if area < 0.0 {
        polygon.reverse();
    }
    Ok(Body {
        name: b.name,
        polygon,
        hmax: b.hmax,
        element: b.element,
        young: b.young,
        poisson: b.poisson,
        density: b.density,
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

fn validate(file: SceneFile) -> Result<Scene, SceneError> {
    if file.body.is_empty() {
        return Err(SceneError::invalid(
            "scene",
            "body",
            "needs at least one [[body]] table",
        ));
    }
    let model = file.model.unwrap_or(ModelSection {
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
    if let Some(g) = model.gravity {
        check_finite("[model]", "gravity", &g)?;
    }

    // Bodies: names unique, geometry and material sane.
    let mut bodies = Vec::with_capacity(file.body.len());
    for b in file.body {
        if b.name.trim().is_empty() {
            return Err(SceneError::invalid("[[body]]", "name", "must not be empty"));
        }
        if bodies.iter().any(|o: &Body| o.name == b.name) {
            return Err(SceneError::invalid(
                body_label(&b.name),
                "name",
                "is used by more than one body",
            ));
        }
        bodies.push(validate_body(b, REGION_TOLERANCE, model.gravity.is_some())?);
    }
    let bbox = geometry::bounding_box(bodies.iter().flat_map(|b| b.polygon.iter()));
    let tol = REGION_TOLERANCE * (bbox[1] - bbox[0]).hypot(bbox[3] - bbox[2]);
    let find = |section: &str, name: &str| -> Result<usize, SceneError> {
        bodies.iter().position(|b| b.name == name).ok_or_else(|| {
            let known: Vec<&str> = bodies.iter().map(|b| b.name.as_str()).collect();
            SceneError::invalid(
                section,
                "body",
                format!(
                    "names an unknown body \"{name}\" (bodies: {})",
                    known.join(", ")
                ),
            )
        })
    };

    let mut dirichlet = Vec::with_capacity(file.dirichlet.len());
    for (i, d) in file.dirichlet.into_iter().enumerate() {
        let s = format!("dirichlet #{} (body \"{}\")", i + 1, d.body);
        let body = find(&s, &d.body)?;
        check_region(&s, &d.region)?;
        let value = d.value.unwrap_or([0.0, 0.0]);
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
        if geometry::boundary_in_box(&bodies[body].polygon, &d.region, tol).is_none() {
            return Err(SceneError::invalid(
                &s,
                "region",
                format!(
                    "{:?} matches no boundary node of body \"{}\"",
                    d.region, bodies[body].name
                ),
            ));
        }
        dirichlet.push(Dirichlet {
            body,
            region: d.region,
            value,
            components,
        });
    }

    let mut neumann = Vec::with_capacity(file.neumann.len());
    for (i, n) in file.neumann.into_iter().enumerate() {
        let s = format!("neumann #{} (body \"{}\")", i + 1, n.body);
        let body = find(&s, &n.body)?;
        check_region(&s, &n.region)?;
        let traction = match (n.traction, n.points, n.tx, n.ty) {
            (Some(t), None, None, None) => {
                check_finite(&s, "traction", &t)?;
                Traction::constant(t)
            }
            (None, Some(points), Some(tx), Some(ty)) => {
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
        match geometry::boundary_in_box(&bodies[body].polygon, &n.region, tol) {
            // A box touching the boundary in a single point clips only O(tol) of it.
            Some(len) if len > 10.0 * tol => {}
            _ => {
                return Err(SceneError::invalid(
                    &s,
                    "region",
                    format!(
                        "{:?} contains no boundary edge of body \"{}\"",
                        n.region, bodies[body].name
                    ),
                ))
            }
        }
        neumann.push(Neumann {
            body,
            region: n.region,
            traction,
        });
    }

    let mut contacts = Vec::with_capacity(file.contact.len());
    for (i, c) in file.contact.into_iter().enumerate() {
        let s = format!("contact #{} ({} – {})", i + 1, c.bodies[0], c.bodies[1]);
        let a = find(&s, &c.bodies[0])?;
        let b = find(&s, &c.bodies[1])?;
        if a == b {
            return Err(SceneError::invalid(
                &s,
                "bodies",
                format!(
                    "names body \"{}\" twice; a pair needs two bodies",
                    c.bodies[0]
                ),
            ));
        }
        if let Some(r) = &c.region {
            check_region(&s, r)?;
        }
        let slave = match c.slave {
            None => None,
            Some(name) => {
                let k = find(&s, &name)?;
                if k != a && k != b {
                    return Err(SceneError::invalid(
                        &s,
                        "slave",
                        format!("\"{name}\" is not one of the pair's bodies"),
                    ));
                }
                Some(k)
            }
        };
        if contacts
            .iter()
            .any(|p: &ContactPair| p.bodies == [a, b] || p.bodies == [b, a])
        {
            return Err(SceneError::invalid(
                &s,
                "bodies",
                "repeats a pair already given",
            ));
        }
        contacts.push(ContactPair {
            bodies: [a, b],
            region: c.region,
            slave,
        });
    }

    let mut probes = Vec::with_capacity(file.probe.len());
    for (i, p) in file.probe.into_iter().enumerate() {
        let s = format!("probe #{} \"{}\"", i + 1, p.name);
        let body = find(&s, &p.body)?;
        check_finite(&s, "point", &p.point)?;
        if !geometry::contains(&bodies[body].polygon, p.point, tol) {
            return Err(SceneError::invalid(
                &s,
                "point",
                format!("{:?} lies outside body \"{}\"", p.point, bodies[body].name),
            ));
        }
        if probes.iter().any(|q: &Probe| q.name == p.name) {
            return Err(SceneError::invalid(
                &s,
                "name",
                "is used by more than one probe",
            ));
        }
        probes.push(Probe {
            name: p.name,
            body,
            point: p.point,
        });
    }

    Ok(Scene {
        title: file.title.unwrap_or_else(|| "untitled".to_string()),
        plane: model.plane,
        thickness,
        gravity: model.gravity,
        bodies,
        dirichlet,
        neumann,
        contacts,
        probes,
    })
}
