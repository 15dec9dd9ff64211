//! Meshes of the bodies: P1 triangles (constrained Delaunay with refinement, every edge ≤ hmax,
//! minimum angle bound) and structured Q1 quadrilaterals for axis-aligned rectangles.
//!
//! Boundary discretisation is deterministic so that two touching bodies with equal `hmax` get
//! coincident interface nodes (conforming), and every requested break point on the boundary
//! (other bodies' corners, region-box crossings) becomes a mesh vertex.
//!
//! **Boundary rule.**  On every polygon edge the break points are its two end vertices plus every
//! given break point within `tol` of the edge (projected onto it), sorted along the edge; each
//! sub-interval between consecutive break points is split evenly into
//! `k = ceil(len / hmax − 1e-9)` pieces.  Points of a sub-interval are computed from its
//! lexicographically smaller end, so two bodies sharing a sub-interval get the same points
//! whatever their orientations; unequal `hmax` give non-conforming interfaces.
//!
//! **P1.**  The discretised boundary plus an equilateral seed lattice (spacing 0.9 hmax, kept
//! 0.54 hmax from the boundary) are bulk-loaded into spade's constrained Delaunay
//! triangulation; Ruppert refinement (angle bound `min_angle_deg`, area bound 0.5 hmax²,
//! boundary edges never split; a skinny triangle whose circumcentre encroaches a boundary edge
//! gets that circumcentre anyway when the triangles it makes keep both bounds) and midpoint
//! splitting of every interior edge longer than `hmax` follow.  About `area / (0.35 hmax²)`
//! triangles result.  Coordinates are normalised before they reach spade, so scaling a scene
//! (m → mm) scales the mesh.  Angles reach `min_angle_deg` except where the fixed boundary
//! forbids it: at input angles below it, and next to boundary edges much shorter than their
//! neighbours (a break point 0.01 from a corner at hmax 0.2 gives a 2.9° triangle).
//!
//! **Q1.**  Structured grid on an axis-aligned rectangle: x from the split points of the bottom
//! and top sides, y from those of the left and right sides.
//!
//! **Graded meshes** (`refine` not empty).  The size function is
//! h(x) = min(hmax, min over regions of (h_r + (G − 1) · dist(x, box_r))) with the growth factor
//! G = [`GRADING`] = 1.25 (see `sizing.rs`): h_r inside each box, growing by G per element away
//! from it, hmax beyond.  Boundary: each sub-interval between break points on which h < hmax
//! somewhere is split into n pieces of equal ∫ ds / h, n = ceil(∫ ds / h − 1e-9) raised until
//! every piece is ≤ h at its midpoint; computed from the lexicographically smaller end as
//! before, so two bodies with the same hmax and refine boxes stay conforming (sub-intervals
//! where h ≡ hmax keep the even rule).  P1 seeds: the uniform lattice where h = hmax, nested
//! lattices of spacing 0.9 hmin 2ᵏ where h ∈ [hmin 2ᵏ, hmin 2ᵏ⁺¹) elsewhere; refinement splits
//! every interior edge longer than h at its midpoint (cascades followed locally).  Q1: a
//! tensor grid whose lines split the intervals between the break values (vertices, break
//! points, box sides) by h's minimum over each grid column / row.  Without regions every path
//! above is the uniform one, bit for bit.
//!
//! **Cost on long thin bodies.**  The boundary split, the seed lattice (through a cell grid)
//! and the refinement rounds are near-linear in the node count; spade's bulk loader
//! (`bulk_load_cdt`) is not on elongated point sets: its hull lookup buckets the hull by
//! pseudo-angle around the points' centre, so on a long strip the hull's long sides fall into
//! a few buckets and every insertion walks O(hull) nodes — quadratic overall.  Measured (perf,
//! `signorini check` on `sh scripts/strip-scene.sh --length L --foundation-layers 4`, bodies
//! L × 0.02 and L × 0.04): spade's `Hull::insert` + `Hull::get` take 25 % of the preparation at
//! L = 100 (258 k DOFs, 0.6 s) and 61 % at L = 400 (1.03 M DOFs, 6.8 s); the rest grows 5.9×
//! for 4× the nodes (one run on a loaded machine).  It is not changed here because the mesh
//! must stay bit-identical, and another triangulation route numbers vertices and faces
//! differently and so refines in another order.  The hull lookup itself has a unique answer
//! (the hull edge whose angular span covers a given angle), so a faster index inside spade
//! (re-bucketing the crowded range, or an ordered map by angle) would keep every triangulation
//! identical.

use serde::{Deserialize, Serialize};

use crate::geometry::{bounding_box, distance, signed_area, Point};

mod boundary;
pub mod gmsh;
mod lattice;
mod quads;
mod quality;
mod sizing;
mod triangles;

pub use boundary::box_crossings;

/// The smallest element size the P1 mesher resolves, relative to a body's extent (the larger
/// side of its bounding box): sixteen steps of the grid its coordinates are snapped to (2⁻³⁴ of
/// the extent), ≈ 9.3e-10.  Below it, distinct boundary points snap together and the outline
/// degenerates; validation refuses such sizes by name.
pub const MIN_RELATIVE_SIZE: f64 = 16.0 / (1u64 << 34) as f64;
pub use sizing::GRADING;

/// Element type of a body.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "lowercase")]
pub enum ElementKind {
    /// Linear triangles.
    #[default]
    P1,
    /// Bilinear quadrilaterals on a structured grid (axis-aligned rectangles only).
    Q1,
}

/// Cells of a mesh, counter-clockwise node indices.
#[derive(Debug, Clone, PartialEq)]
pub enum Cells {
    /// Linear triangles.
    Triangles(Vec<[usize; 3]>),
    /// Bilinear quadrilaterals.
    Quads(Vec<[usize; 4]>),
}

impl Cells {
    /// Number of cells.
    pub fn len(&self) -> usize {
        match self {
            Cells::Triangles(t) => t.len(),
            Cells::Quads(q) => q.len(),
        }
    }

    /// True when there are no cells.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The element these cells are.
    pub fn kind(&self) -> ElementKind {
        match self {
            Cells::Triangles(_) => ElementKind::P1,
            Cells::Quads(_) => ElementKind::Q1,
        }
    }

    /// Node indices of cell `i` (3 or 4 of them).
    pub fn cell(&self, i: usize) -> &[usize] {
        match self {
            Cells::Triangles(t) => &t[i],
            Cells::Quads(q) => &q[i],
        }
    }
}

/// One body's mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    /// Node coordinates.
    pub nodes: Vec<Point>,
    /// Elements, counter-clockwise.
    pub cells: Cells,
    /// Boundary edges `[a, b]`, oriented so that the body lies on the left (counter-clockwise).
    pub boundary: Vec<[usize; 2]>,
}

#[cfg(test)]
impl Mesh {
    /// A boundary-only mesh (no cells) of the closed loop `points`, counter-clockwise for a body
    /// on the left: what the contact and report tests build by hand.
    pub(crate) fn boundary_loop(points: Vec<Point>) -> Self {
        let n = points.len();
        Mesh {
            nodes: points,
            cells: Cells::Triangles(Vec::new()),
            boundary: (0..n).map(|i| [i, (i + 1) % n]).collect(),
        }
    }
}

impl Mesh {
    /// Writes the coordinates of cell `c`'s nodes into `points` (cleared first): one buffer
    /// reused across cells, no allocation per cell.
    pub fn cell_points_into(&self, c: usize, points: &mut Vec<Point>) {
        points.clear();
        points.extend(self.cells.cell(c).iter().map(|&n| self.nodes[n]));
    }
}

/// Boundary nodes of a mesh (sorted, unique).
pub fn boundary_nodes(mesh: &Mesh) -> Vec<usize> {
    let mut nodes: Vec<usize> = mesh.boundary.iter().flatten().copied().collect();
    nodes.sort_unstable();
    nodes.dedup();
    nodes
}

/// A region of a body meshed finer than the body's `hmax` (`[[body.refine]]`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Refinement {
    /// Box `[x1, x2, y1, y2]`.
    pub region: [f64; 4],
    /// Largest element edge inside the box.
    pub hmax: f64,
}

/// One body to mesh.
///
/// ```
/// use signorini_core::mesh::{mesh_body, BodyGeometry, ElementKind, MeshLimits};
/// let polygon = [[0.0, 1.0], [2.0, 1.0], [2.0, 2.0], [0.0, 2.0]];
/// let body = BodyGeometry {
///     polygon: &polygon,
///     hmax: 0.2,
///     element: ElementKind::P1,
///     breakpoints: &[[1.0, 1.0]],
///     refine: &[],
///     tol: 1e-9,
/// };
/// let mesh = mesh_body(&body, &MeshLimits::default()).unwrap();
/// assert!(mesh.max_edge() <= 0.2 * (1.0 + 1e-9));
/// assert!((mesh.area() - 2.0).abs() < 1e-12);
/// ```
#[derive(Debug, Clone, Copy)]
pub struct BodyGeometry<'a> {
    /// Simple polygon, either orientation, ≥ 3 vertices.
    pub polygon: &'a [Point],
    /// Largest allowed element edge length (scene length units).
    pub hmax: f64,
    /// Element type: P1 for any polygon, Q1 only for axis-aligned rectangles.
    pub element: ElementKind,
    /// Points that must become mesh vertices wherever they lie on the boundary (within `tol`);
    /// points off the boundary are ignored.  Typically other bodies' corners and the
    /// [`box_crossings`] of the regions that apply to this body.
    pub breakpoints: &'a [Point],
    /// Regions meshed finer than `hmax`, with a smooth transition to `hmax` outside them.
    pub refine: &'a [Refinement],
    /// Absolute length tolerance for "lies on" (≈ 1e-9 × scene size).
    pub tol: f64,
}

/// Limits of the mesher.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshLimits {
    /// Largest number of elements of one body; larger requests are refused before meshing.
    /// Default 5 000 000.
    pub max_elements: usize,
    /// Smallest triangle angle the refinement aims at, in degrees (boundary permitting).
    /// Default 20; must lie in [0, 34] (Ruppert refinement need not terminate above ≈ 34°).
    pub min_angle_deg: f64,
}

impl Default for MeshLimits {
    fn default() -> Self {
        Self {
            max_elements: 5_000_000,
            min_angle_deg: 20.0,
        }
    }
}

/// Why a body could not be meshed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshError {
    /// The estimated element count exceeds [`MeshLimits::max_elements`].
    #[error(
        "the mesh would have about {estimated} elements, more than the limit of {limit}; \
         increase hmax or raise the limit (--max-elements)"
    )]
    TooManyElements {
        /// Estimated (or actual) number of elements.
        estimated: usize,
        /// The limit.
        limit: usize,
    },
    /// Q1 elements were requested for a polygon that is not an axis-aligned rectangle.
    #[error("Q1 (structured quadrilateral) meshes need an axis-aligned rectangle; use P1 for other polygons")]
    NotARectangle,
    /// A parameter is out of range.
    #[error("mesh parameter `{name}` = {value} is invalid: {expected}")]
    InvalidParameter {
        /// Parameter name.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What is allowed.
        expected: &'static str,
    },
    /// The polygon has fewer than 3 distinct vertices, no area, non-finite coordinates or
    /// crossing edges.
    #[error("degenerate polygon: {reason}")]
    DegeneratePolygon {
        /// What is wrong.
        reason: String,
    },
    /// Delaunay refinement ran out of its vertex budget before meeting the angle and edge bounds.
    #[error(
        "mesh refinement did not finish: {vertices} vertices reached the budget of {budget}; \
         lower min_angle_deg or check the polygon for tiny features"
    )]
    RefinementIncomplete {
        /// Vertices when refinement stopped.
        vertices: usize,
        /// Vertex budget.
        budget: usize,
    },
    /// The triangulation library failed.
    #[error("triangulation failed: {reason}")]
    Triangulation {
        /// The failure.
        reason: String,
    },
}

/// Mean P1 triangle area produced by [`mesh_body`], as a multiple of hmax² (measured).
const P1_AREA_PER_ELEMENT: f64 = 0.3;

/// Number of elements along x and y of the structured Q1 grid on the bounding box, as floats
/// (possibly infinite).
fn q1_divisions(polygon: &[Point], hmax: f64) -> [f64; 2] {
    let [x0, x1, y0, y1] = bounding_box(polygon);
    [
        ((x1 - x0) / hmax - 1e-9).ceil().max(1.0),
        ((y1 - y0) / hmax - 1e-9).ceil().max(1.0),
    ]
}

/// Perimeter of a closed polygon.
fn perimeter(polygon: &[Point]) -> f64 {
    (0..polygon.len())
        .map(|i| distance(polygon[i], polygon[(i + 1) % polygon.len()]))
        .sum()
}

/// A non-negative float count as `usize`, saturating: `usize::MAX` for anything beyond it,
/// infinite or NaN.  Never wraps, never panics.
fn saturating_count(x: f64) -> usize {
    if x.is_nan() {
        usize::MAX
    } else {
        // `as` saturates: +inf and values ≥ 2⁶⁴ give usize::MAX, negative values 0.
        x.ceil() as usize
    }
}

/// Cheap estimate of the number of elements [`mesh_body`] creates, used to refuse oversized
/// requests before allocating.  Saturates: `usize::MAX` for a non-positive or non-finite `hmax`,
/// an empty polygon, or any count beyond `usize` (hmax = 1e-300); never wraps or panics.
///
/// P1: area / (0.3 hmax²) + perimeter / hmax (measured: the mesher's mean triangle is
/// ≈ 0.35 hmax², so fine meshes are over-estimated by 8–15 %; coarse ones of ~100 elements,
/// where the boundary dominates, under-estimated by up to 8 %).  Q1: the structured grid's cell
/// count, exact.
///
/// ```
/// use signorini_core::mesh::{estimate_elements, ElementKind};
/// let square = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
/// assert_eq!(estimate_elements(&square, 0.1, ElementKind::Q1), 100);
/// assert!(estimate_elements(&square, 0.1, ElementKind::P1) > 100);
/// assert_eq!(estimate_elements(&square, 1e-300, ElementKind::P1), usize::MAX);
/// ```
pub fn estimate_elements(polygon: &[Point], hmax: f64, element: ElementKind) -> usize {
    estimate_elements_refined(polygon, hmax, &[], element)
}

/// [`estimate_elements`] for a body with `[[body.refine]]` regions: what [`mesh_body`] creates
/// with `refine`.  Without regions (or with none finer than `hmax`) it is [`estimate_elements`]
/// exactly.  Saturates like it (also when the integrals below would take more than ≈ 10⁸ steps).
///
/// P1: ∫ dA / (c h(x)²) + ∫ ds / h(x) over the polygon and its boundary, with h the size
/// function (see the module docs), c = 0.3 where h = hmax or h = the finest region's size
/// and [`P1_GRADED_AREA_PER_ELEMENT`] elsewhere (measured: the graded seeds' spacing lies
/// between 0.45 and 0.9 h there).
/// Q1: the graded tensor grid's cell count on the bounding box, without break points (they
/// add a few lines; exact without them).
///
/// ```
/// use signorini_core::mesh::{estimate_elements, estimate_elements_refined, ElementKind, Refinement};
/// let block = [[0.0, 0.0], [0.8, 0.0], [0.8, 0.4], [0.0, 0.4]];
/// let fine = [Refinement { region: [0.35, 0.45, 0.38, 0.4], hmax: 0.0025 }];
/// let graded = estimate_elements_refined(&block, 0.05, &fine, ElementKind::P1);
/// assert!(graded > estimate_elements(&block, 0.05, ElementKind::P1));
/// assert!(graded < estimate_elements(&block, 0.0025, ElementKind::P1) / 10);
/// assert_eq!(
///     estimate_elements_refined(&block, 0.05, &[], ElementKind::Q1),
///     estimate_elements(&block, 0.05, ElementKind::Q1)
/// );
/// ```
pub fn estimate_elements_refined(
    polygon: &[Point],
    hmax: f64,
    refine: &[Refinement],
    element: ElementKind,
) -> usize {
    if !(hmax.is_finite() && hmax > 0.0) || polygon.len() < 3 {
        return usize::MAX;
    }
    let field = sizing::SizeField::new(hmax, refine);
    let estimate = match element {
        ElementKind::Q1 if field.is_uniform() => {
            let [nx, ny] = q1_divisions(polygon, hmax);
            nx * ny
        }
        ElementKind::P1 if field.is_uniform() => {
            signed_area(polygon).abs() / (P1_AREA_PER_ELEMENT * hmax * hmax)
                + perimeter(polygon) / hmax
        }
        ElementKind::Q1 => {
            let [nx, ny] = q1_graded_divisions(polygon, &field);
            nx * ny
        }
        ElementKind::P1 => p1_graded_elements(polygon, &field),
    };
    saturating_count(estimate)
}

/// Mean P1 triangle area in the graded zone outside the finest boxes, as a multiple of h(x)²
/// (measured: fits of (elements − uniform part) against ∫ (1/h² − 1/hmax²) dA gave 0.136–0.2
/// on graded blocks of `tests/mesh_grading.rs`; the seed lattices there are spaced 0.45–0.9 h).
/// Inside the finest boxes the seeds are the uniform lattice of their size, and
/// [`estimate_elements`]' 0.3 applies.
pub const P1_GRADED_AREA_PER_ELEMENT: f64 = 0.15;

/// ∫ dA / (c h²) + ∫ ds / h for a graded P1 mesh (c as documented at
/// [`estimate_elements_refined`]).
fn p1_graded_elements(polygon: &[Point], field: &sizing::SizeField) -> f64 {
    let area = signed_area(polygon).abs();
    let hmax = field.hmax();
    let [finest, graded] = field.excess_inverse_square(polygon);
    if !(finest + graded).is_finite() {
        // Beyond any limit already: the boundary integral would only add time.
        return f64::INFINITY;
    }
    (area / (hmax * hmax) + finest) / P1_AREA_PER_ELEMENT
        + graded / P1_GRADED_AREA_PER_ELEMENT
        + graded_boundary_pieces(polygon, field)
}

/// ∫ ds / h over the polygon's boundary.
fn graded_boundary_pieces(polygon: &[Point], field: &sizing::SizeField) -> f64 {
    (0..polygon.len())
        .map(|i| {
            field
                .pieces_along(polygon[i], polygon[(i + 1) % polygon.len()])
                .max(1.0)
        })
        .sum()
}

/// Cells along x and y of the graded Q1 grid on the bounding box (no break points), as floats;
/// beyond 10⁷ lines per axis the integral ∫ dx / h alone (the grid is not built).
fn q1_graded_divisions(polygon: &[Point], field: &sizing::SizeField) -> [f64; 2] {
    let b = bounding_box(polygon);
    let tol = 1e-9 * (b[1] - b[0]).max(b[3] - b[2]);
    let nx = field
        .along_x(&b, tol)
        .pieces_along([b[0], 0.0], [b[1], 0.0]);
    let ny = field
        .along_y(&b, tol)
        .pieces_along([b[2], 0.0], [b[3], 0.0]);
    if !(nx.is_finite() && ny.is_finite() && nx.max(ny) < 1e7) {
        return [nx, ny];
    }
    let corners = [[b[0], b[2]], [b[1], b[2]], [b[1], b[3]], [b[0], b[3]]];
    let (xs, ys) = quads::graded_grid(&corners, field.hmax(), field, &[], &b, tol);
    [
        xs.len().saturating_sub(1) as f64,
        ys.len().saturating_sub(1) as f64,
    ]
}

/// Estimate of the number of nodes [`mesh_body`] creates, consistent with
/// [`estimate_elements`]; saturates like it.
///
/// P1 (a triangulated polygon without holes has E = 2N − B − 2 with B boundary nodes):
/// (E + B + 2) / 2 with E from [`estimate_elements`] and B = Σ ⌈edge / hmax⌉.  Q1: the grid's
/// (nx + 1)(ny + 1).
///
/// ```
/// use signorini_core::mesh::{estimate_nodes, ElementKind};
/// let square = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
/// assert_eq!(estimate_nodes(&square, 0.1, ElementKind::Q1), 121);
/// assert_eq!(estimate_nodes(&square, f64::NAN, ElementKind::P1), usize::MAX);
/// ```
pub fn estimate_nodes(polygon: &[Point], hmax: f64, element: ElementKind) -> usize {
    estimate_nodes_refined(polygon, hmax, &[], element)
}

/// [`estimate_nodes`] for a body with `[[body.refine]]` regions, consistent with
/// [`estimate_elements_refined`] (P1: (E + B + 2) / 2 with B = Σ ∫ ds / h over the edges; Q1:
/// (nx + 1)(ny + 1) of the graded grid).  Without regions it is [`estimate_nodes`] exactly.
pub fn estimate_nodes_refined(
    polygon: &[Point],
    hmax: f64,
    refine: &[Refinement],
    element: ElementKind,
) -> usize {
    if !(hmax.is_finite() && hmax > 0.0) || polygon.len() < 3 {
        return usize::MAX;
    }
    let field = sizing::SizeField::new(hmax, refine);
    let estimate = match element {
        ElementKind::Q1 if field.is_uniform() => {
            let [nx, ny] = q1_divisions(polygon, hmax);
            (nx + 1.0) * (ny + 1.0)
        }
        ElementKind::P1 if field.is_uniform() => {
            let elements = signed_area(polygon).abs() / (P1_AREA_PER_ELEMENT * hmax * hmax)
                + perimeter(polygon) / hmax;
            let boundary: f64 = (0..polygon.len())
                .map(|i| {
                    (distance(polygon[i], polygon[(i + 1) % polygon.len()]) / hmax - 1e-9)
                        .ceil()
                        .max(1.0)
                })
                .sum();
            (elements.ceil() + boundary + 2.0) / 2.0
        }
        ElementKind::Q1 => {
            let [nx, ny] = q1_graded_divisions(polygon, &field);
            (nx + 1.0) * (ny + 1.0)
        }
        ElementKind::P1 => {
            let elements = p1_graded_elements(polygon, &field);
            if !elements.is_finite() {
                return usize::MAX;
            }
            let boundary = graded_boundary_pieces(polygon, &field).ceil();
            (elements.ceil() + boundary + 2.0) / 2.0
        }
    };
    saturating_count(estimate)
}

/// Meshes one body.
///
/// The boundary is discretised deterministically (see the module docs), so bodies that share an
/// edge and `hmax` get coincident interface nodes.  P1: constrained Delaunay triangulation with
/// refinement; every edge ≤ `hmax` (boundary edges ≤ `hmax (1 + 1e-9)`), angles ≥
/// `limits.min_angle_deg` except where the fixed boundary discretisation forbids it.  Q1:
/// structured grid on an axis-aligned rectangle.  Cells are counter-clockwise; `boundary` lists
/// every boundary edge once with the body on its left.  For P1 the boundary nodes come first
/// (node `i` to `i + 1` is boundary edge `i`).
///
/// With `refine` regions (finer than `hmax`) the mesh is graded: "≤ `hmax`" above becomes
/// "≤ h(midpoint)" with the size function of the module docs, and bodies conform when they
/// share `hmax` and `refine`.  Without them the mesh is the uniform one, bit for bit.
///
/// # Errors
/// [`MeshError`] for invalid parameters, a degenerate polygon, Q1 on a non-rectangle, an
/// estimate above `limits.max_elements` (checked before anything large is allocated) or a
/// refinement that cannot finish.
///
/// # Example
/// The seed's two bodies with equal `hmax` share their interface nodes on y = 1, x ∈ [1, 2]:
/// ```
/// use signorini_core::mesh::{mesh_body, BodyGeometry, Cells, ElementKind, MeshLimits};
/// let upper = [[0.0, 1.0], [2.0, 1.0], [2.0, 2.0], [0.0, 2.0]];
/// let lower = [[1.0, 0.0], [3.0, 0.0], [3.0, 1.0], [1.0, 1.0]];
/// let limits = MeshLimits::default();
/// let mesh = |polygon, corner, element| {
///     let body = BodyGeometry { polygon, hmax: 0.2, element, breakpoints: &[corner], refine: &[], tol: 1e-9 };
///     mesh_body(&body, &limits)
/// };
/// let a = mesh(&upper[..], [1.0, 1.0], ElementKind::P1)?;
/// let b = mesh(&lower[..], [2.0, 1.0], ElementKind::P1)?;
/// let interface = |m: &signorini_core::mesh::Mesh| {
///     let mut x: Vec<f64> = m.nodes.iter()
///         .filter(|p| p[1] == 1.0 && (1.0..=2.0).contains(&p[0])).map(|p| p[0]).collect();
///     x.sort_by(f64::total_cmp);
///     x
/// };
/// assert_eq!(interface(&a).len(), 6);
/// assert!(interface(&a).iter().zip(interface(&b)).all(|(p, q)| (p - q).abs() < 1e-12));
///
/// let quads = mesh(&upper[..], [1.0, 1.0], ElementKind::Q1)?;
/// assert!(matches!(quads.cells, Cells::Quads(ref q) if q.len() == 50));
/// # Ok::<(), signorini_core::mesh::MeshError>(())
/// ```
pub fn mesh_body(geometry: &BodyGeometry, limits: &MeshLimits) -> Result<Mesh, MeshError> {
    let BodyGeometry {
        polygon,
        hmax,
        element,
        breakpoints,
        refine,
        tol,
    } = *geometry;
    if !(hmax.is_finite() && hmax > 0.0) {
        return Err(MeshError::InvalidParameter {
            name: "hmax",
            value: hmax,
            expected: "a positive finite length",
        });
    }
    if !(tol.is_finite() && tol >= 0.0) {
        return Err(MeshError::InvalidParameter {
            name: "tol",
            value: tol,
            expected: "a non-negative finite length",
        });
    }
    if !(limits.min_angle_deg.is_finite() && (0.0..=34.0).contains(&limits.min_angle_deg)) {
        return Err(MeshError::InvalidParameter {
            name: "min_angle_deg",
            value: limits.min_angle_deg,
            expected: "an angle in [0, 34] degrees",
        });
    }
    let polygon = boundary::clean_polygon(polygon, tol)?;
    let field = sizing::SizeField::new(hmax, refine);
    let estimated = estimate_elements_refined(&polygon, hmax, refine, element);
    if estimated > limits.max_elements {
        return Err(MeshError::TooManyElements {
            estimated,
            limit: limits.max_elements,
        });
    }
    let mesh = match element {
        ElementKind::Q1 => quads::mesh_rectangle(&polygon, hmax, &field, breakpoints, tol)?,
        ElementKind::P1 => {
            let points = boundary::discretise(&polygon, hmax, breakpoints, tol, &field);
            let budget = estimated
                .saturating_mul(2)
                .saturating_add(points.len().saturating_mul(10))
                .saturating_add(1000)
                .min(limits.max_elements.saturating_add(points.len()));
            triangles::mesh_polygon(&points, hmax, &field, limits, budget)?
        }
    };
    if mesh.cells.len() > limits.max_elements {
        return Err(MeshError::TooManyElements {
            estimated: mesh.cells.len(),
            limit: limits.max_elements,
        });
    }
    Ok(mesh)
}
