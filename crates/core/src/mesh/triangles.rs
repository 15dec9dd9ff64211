//! P1 meshes: constrained Delaunay triangulation of the discretised boundary (spade), Ruppert
//! refinement with an angle and an area bound, then midpoint insertion until every edge is
//! ≤ hmax.
//!
//! Coordinates are normalised (translated to the bounding-box minimum, divided by the larger
//! extent, snapped to a 2⁻³⁴ grid) before they reach spade, so a scene written in mm meshes like
//! the same scene in m.  Boundary nodes are returned at their original coordinates (the snapped
//! copies are only spade's view), interior nodes are mapped back.

use std::collections::HashSet;
use std::panic::{catch_unwind, AssertUnwindSafe};

use spade::handles::{FixedFaceHandle, InnerTag};
use spade::{
    AngleLimit, ConstrainedDelaunayTriangulation, Point2, RefinementParameters, Triangulation,
};

use crate::geometry::{bounding_box, Point};

use super::{Cells, Mesh, MeshError, MeshLimits};

type Cdt = ConstrainedDelaunayTriangulation<Point2<f64>>;

/// Largest triangle area handed to spade, as a multiple of hmax² (an equilateral triangle of
/// side hmax has 0.433 hmax²).  Long edges left over are split afterwards.
pub(crate) const AREA_FACTOR: f64 = 0.3;

/// Snapping grid of the normalised coordinates.
const GRID: f64 = 1.0 / (1u64 << 34) as f64;

/// Rounds of "split the edges longer than hmax, refine again" before giving up.
const MAX_ROUNDS: usize = 64;

/// Maps between scene coordinates and spade's normalised, snapped unit box.
struct Normaliser {
    origin: Point,
    extent: f64,
}

impl Normaliser {
    fn to_unit(&self, p: Point) -> Point2<f64> {
        let snap = |u: f64| (u / GRID).round() * GRID;
        Point2::new(
            snap((p[0] - self.origin[0]) / self.extent),
            snap((p[1] - self.origin[1]) / self.extent),
        )
    }

    fn from_unit(&self, p: Point2<f64>) -> Point {
        [
            self.origin[0] + p.x * self.extent,
            self.origin[1] + p.y * self.extent,
        ]
    }
}

/// `x` rounded to 34 significant bits, so that a length scaled by a non-power of two still gives
/// bit-identical thresholds.
fn snap_relative(x: f64) -> f64 {
    if !(x.is_finite() && x > 0.0) {
        return x;
    }
    let scale = x.log2().floor().exp2();
    (x / scale / GRID).round() * GRID * scale
}

/// Triangulates the closed counter-clockwise loop `boundary` (distinct points) with every edge
/// ≤ `hmax`.  `vertex_budget` bounds the Steiner points spade may insert.
pub(crate) fn mesh_polygon(
    boundary: &[Point],
    hmax: f64,
    limits: &MeshLimits,
    vertex_budget: usize,
) -> Result<Mesh, MeshError> {
    let [x0, x1, y0, y1] = bounding_box(boundary);
    let extent = (x1 - x0).max(y1 - y0);
    if !(extent.is_finite() && extent > 0.0) {
        return Err(MeshError::DegeneratePolygon {
            reason: "zero or infinite extent".into(),
        });
    }
    let normaliser = Normaliser {
        origin: [x0, y0],
        extent,
    };
    let h = snap_relative(hmax / extent);
    match catch_unwind(AssertUnwindSafe(|| {
        triangulate(boundary, h, &normaliser, limits, vertex_budget)
    })) {
        Ok(result) => result,
        Err(_) => Err(MeshError::Triangulation {
            reason: "spade panicked (likely loss of precision on a near-degenerate polygon)".into(),
        }),
    }
}

fn triangulate(
    boundary: &[Point],
    h: f64,
    normaliser: &Normaliser,
    limits: &MeshLimits,
    vertex_budget: usize,
) -> Result<Mesh, MeshError> {
    let n = boundary.len();
    let vertices: Vec<Point2<f64>> = boundary.iter().map(|&p| normaliser.to_unit(p)).collect();
    let edges: Vec<[usize; 2]> = (0..n).map(|i| [i, (i + 1) % n]).collect();
    let mut conflicts = 0usize;
    let mut cdt = Cdt::try_bulk_load_cdt(vertices, edges, |_| conflicts += 1).map_err(|e| {
        MeshError::Triangulation {
            reason: format!("constrained Delaunay triangulation failed: {e:?}"),
        }
    })?;
    if conflicts > 0 || cdt.num_vertices() != n {
        return Err(MeshError::DegeneratePolygon {
            reason: format!(
                "boundary edges cross or touch ({conflicts} conflicts, {} of {n} boundary points \
                 distinct at the snapping resolution)",
                cdt.num_vertices()
            ),
        });
    }

    // Decisions are taken on the snapped h with a margin that covers the difference between the
    // snapped boundary points spade sees and the original ones the mesh returns.
    let margin = 1e-9 + 4.0 * GRID / h;
    let threshold2 = (h * (1.0 - margin)).powi(2);
    let max_vertices = n.saturating_add(vertex_budget);
    let parameters = |cdt: &Cdt| {
        RefinementParameters::<f64>::new()
            .with_angle_limit(AngleLimit::from_deg(limits.min_angle_deg))
            .with_max_allowed_area(AREA_FACTOR * h * h)
            .keep_constraint_edges()
            .exclude_outer_faces(true)
            .with_max_additional_vertices(max_vertices.saturating_sub(cdt.num_vertices()))
    };

    let mut excluded: HashSet<FixedFaceHandle<InnerTag>>;
    let mut rounds = 0;
    loop {
        let t0 = std::time::Instant::now();
        let result = cdt.refine(parameters(&cdt));
        eprintln!(
            "refine round {rounds}: {:.3}s, {} vertices",
            t0.elapsed().as_secs_f64(),
            cdt.num_vertices()
        );
        if !result.refinement_complete {
            return Err(MeshError::RefinementIncomplete {
                vertices: cdt.num_vertices(),
                budget: max_vertices,
            });
        }
        excluded = result.excluded_faces.into_iter().collect();
        let long = long_edge_midpoints(&cdt, &excluded, threshold2);
        eprintln!("  long {}", long.len());
        if long.is_empty() {
            break;
        }
        rounds += 1;
        if rounds > MAX_ROUNDS || cdt.num_vertices().saturating_add(long.len()) > max_vertices {
            return Err(MeshError::RefinementIncomplete {
                vertices: cdt.num_vertices(),
                budget: max_vertices,
            });
        }
        for p in long {
            cdt.insert(p).map_err(|e| MeshError::Triangulation {
                reason: format!("inserting an edge midpoint failed: {e:?}"),
            })?;
        }
    }
    Ok(extract(&cdt, &excluded, n, normaliser, boundary))
}

/// Midpoints of the non-boundary edges of kept faces longer than √threshold2.
fn long_edge_midpoints(
    cdt: &Cdt,
    excluded: &HashSet<FixedFaceHandle<InnerTag>>,
    threshold2: f64,
) -> Vec<Point2<f64>> {
    cdt.undirected_edges()
        .filter(|e| !e.is_constraint_edge() && e.length_2() > threshold2)
        .filter(|e| {
            let d = e.as_directed();
            [d, d.rev()].iter().any(|d| {
                d.face()
                    .as_inner()
                    .is_some_and(|f| !excluded.contains(&f.fix()))
            })
        })
        .map(|e| e.center())
        .collect()
}

/// The kept faces as a [`Mesh`]: boundary nodes first (in `boundary` order, original
/// coordinates), then the used Steiner points in spade's vertex order.
fn extract(
    cdt: &Cdt,
    excluded: &HashSet<FixedFaceHandle<InnerTag>>,
    n: usize,
    normaliser: &Normaliser,
    boundary: &[Point],
) -> Mesh {
    let kept: Vec<[usize; 3]> = cdt
        .inner_faces()
        .filter(|f| !excluded.contains(&f.fix()))
        .map(|f| f.vertices().map(|v| v.fix().index()))
        .collect();
    let mut used = vec![false; cdt.num_vertices()];
    for t in &kept {
        for &v in t {
            used[v] = true;
        }
    }
    let mut id: Vec<usize> = (0..n).collect();
    id.resize(cdt.num_vertices(), usize::MAX);
    let mut nodes: Vec<Point> = boundary.to_vec();
    for (v, vertex) in cdt.vertices().enumerate().skip(n) {
        if used[v] {
            id[v] = nodes.len();
            nodes.push(normaliser.from_unit(vertex.position()));
        }
    }
    let triangles: Vec<[usize; 3]> = kept.iter().map(|t| t.map(|v| id[v])).collect();
    let boundary_edges = (0..n).map(|i| [i, (i + 1) % n]).collect();
    Mesh {
        nodes,
        cells: Cells::Triangles(triangles),
        boundary: boundary_edges,
    }
}
