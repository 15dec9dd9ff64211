//! The outline of every body and the scene's tolerance: what the checks of where a region, a
//! probe or a support lies need.  Validation builds it when the TOML gives every outline (no
//! Gmsh body); otherwise the import builds it once the files are read.

use crate::geometry::{self, Point};
use crate::scene::REGION_TOLERANCE;

/// Every body's name and outline, and the scene's tolerance.
pub(in crate::scene) struct Outlines<'a> {
    /// Body names, by index.
    names: Vec<&'a str>,
    /// Body outlines (counter-clockwise), by index.
    polygons: Vec<&'a [Point]>,
    /// [`REGION_TOLERANCE`] × the diagonal of the bounding box of all outlines.
    pub tol: f64,
}

impl<'a> Outlines<'a> {
    /// The outlines of `bodies` (name and polygon of each), with their tolerance.
    pub fn new(bodies: impl Iterator<Item = (&'a str, &'a [Point])>) -> Self {
        let (names, polygons): (Vec<&str>, Vec<&[Point]>) = bodies.unzip();
        let bbox = geometry::bounding_box(polygons.iter().flat_map(|p| p.iter()));
        let tol = REGION_TOLERANCE * (bbox[1] - bbox[0]).hypot(bbox[3] - bbox[2]);
        Self {
            names,
            polygons,
            tol,
        }
    }

    /// The name of body `k`.
    pub fn name(&self, k: usize) -> &'a str {
        self.names[k]
    }

    /// The outline of body `k`.
    pub fn polygon(&self, k: usize) -> &'a [Point] {
        self.polygons[k]
    }
}
