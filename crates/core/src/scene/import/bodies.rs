//! A body's geometry: a polygon body's as validated; a Gmsh body's read from its file (outline,
//! element, longest edge), then checked as validation checks a polygon's.

use std::path::Path;
use std::sync::Arc;

use crate::mesh::gmsh::{self, ImportedMesh};
use crate::mesh::{Cells, ElementKind};
use crate::scene::draft::{DraftBody, Shape};
use crate::scene::types::Body;
use crate::scene::validate::bodies::{check_body_force, check_hmax, check_outline};
use crate::scene::validate::values::body_label;
use crate::scene::SceneError;

/// The body of a validated section; a Gmsh body's file is read relative to `base`.
pub(super) fn import_body(
    b: DraftBody,
    gravity: Option<[f64; 2]>,
    thickness: f64,
    base: Option<&Path>,
) -> Result<Body, SceneError> {
    match b.shape {
        Shape::Polygon(p) => Ok(Body {
            name: b.name,
            polygon: p.polygon,
            hmax: p.hmax,
            element: p.element,
            young: b.young,
            poisson: b.poisson,
            density: b.density,
            refine: p.refine,
            imported: None,
        }),
        Shape::Gmsh(ref file) => {
            let s = body_label(&b.name);
            let imported = read_mesh(&s, file, base)?;
            let element = match imported.mesh.cells {
                Cells::Triangles(_) => ElementKind::P1,
                Cells::Quads(_) => ElementKind::Q1,
            };
            let hmax = imported.mesh.max_edge();
            let mut polygon = imported.outline.clone();
            // A Gmsh outline is the boundary of a valid mesh (checked on import): no need to
            // look for crossings among its many vertices.
            let outline = check_outline(&s, &polygon)?;
            check_hmax(&s, hmax)?;
            if let (Some(g), Some(d)) = (gravity, b.density) {
                check_body_force(&s, d, g, thickness, outline.area)?;
            }
            if outline.area < 0.0 {
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
                refine: Vec::new(),
                imported: Some(Arc::new(imported)),
            })
        }
    }
}

/// Reads a body's Gmsh file (`mesh = "…"`), relative to `base` (the scene file's directory).
fn read_mesh(s: &str, file: &str, base: Option<&Path>) -> Result<ImportedMesh, SceneError> {
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
    gmsh::read_msh(&path, &path.display().to_string()).map_err(|e| {
        SceneError::invalid(s, "mesh", format!("= {file:?} ({}) {}", e.path, e.problem))
    })
}
