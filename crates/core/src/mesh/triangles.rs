//! P1 meshes: constrained Delaunay triangulation of the discretised boundary (spade), Ruppert
//! refinement with an angle and an area bound, then midpoint insertion until every edge is
//! ≤ hmax.  The boundary is kept (never split), so spade drops a skinny face whose circumcentre
//! encroaches a boundary edge; that circumcentre is inserted anyway when every face it makes
//! keeps both bounds (see [`relieve`]).
//!
//! Coordinates are normalised (translated to the bounding-box minimum, divided by the larger
//! extent, snapped to a 2⁻³⁴ grid) before they reach spade, so a scene written in mm meshes like
//! the same scene in m.  Boundary nodes are returned at their original coordinates (the snapped
//! copies are only spade's view), interior nodes are mapped back.

use std::panic::{catch_unwind, AssertUnwindSafe};

use spade::handles::{FixedFaceHandle, FixedVertexHandle, InnerTag};
use spade::{
    AngleLimit, ConstrainedDelaunayTriangulation, Point2, RefinementParameters, Triangulation,
};

use crate::geometry::{bounding_box, Point};

use super::lattice::{lattice_points, lattice_points_in};
use super::sizing::SizeField;
use super::{Cells, Mesh, MeshError, MeshLimits};

type Cdt = ConstrainedDelaunayTriangulation<Point2<f64>>;

/// Largest triangle area handed to spade, as a multiple of hmax² (an equilateral triangle of
/// side hmax has 0.433 hmax²).  Long edges left over are split afterwards.
pub(crate) const AREA_FACTOR: f64 = 0.5;

/// Spacing of the interior seed lattice, as a multiple of hmax.
const LATTICE: f64 = 0.9;

/// Distance kept between seed points and the boundary, as a multiple of the lattice spacing.
const GAP: f64 = 0.6;

/// Snapping grid of the normalised coordinates.
const GRID: f64 = 1.0 / (1u64 << 34) as f64;

/// Rounds of "split the edges longer than hmax, refine again" before giving up.
const MAX_ROUNDS: usize = 4096;

/// Rounds after which a uniform mesh, too, follows the cascade of long-edge splits locally (as
/// graded meshes always do) instead of rescanning the whole mesh per round.  A boundary much
/// finer than hmax (a Hertz cap's arc at 0.001 with hmax 0.01) makes each round's splits leave
/// one or two new long edges beside them: 241 full rounds, past the old cap of 64, so such
/// scenes were refused.  Meshes that finish within this many rounds are unchanged (bit for bit).
const LOCAL_AFTER: usize = 64;

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

    fn to_scene(&self, p: Point2<f64>) -> Point {
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
/// ≤ `hmax`, or, for a graded `field`, every interior edge ≤ h at its midpoint.
/// `vertex_budget` bounds the Steiner points spade may insert.
pub(crate) fn mesh_polygon(
    boundary: &[Point],
    hmax: f64,
    field: &SizeField,
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
    let field =
        (!field.is_uniform()).then(|| field.scaled(normaliser.origin, extent, snap_relative));
    match catch_unwind(AssertUnwindSafe(|| {
        triangulate(
            boundary,
            h,
            field.as_ref(),
            &normaliser,
            limits,
            vertex_budget,
        )
    })) {
        Ok(result) => result,
        Err(_) => Err(MeshError::Triangulation {
            reason: "spade panicked (likely loss of precision on a near-degenerate polygon)".into(),
        }),
    }
}

/// Interior seeds of a graded mesh (unit coordinates).  Where h(p) = hmax: the uniform
/// lattice (spacing 0.9 hmax).  Elsewhere nested equilateral lattices anchored at the finest
/// size hmin: level k has spacing 0.9 hmin 2ᵏ and keeps the points where h(p) ∈
/// [hmin 2ᵏ, hmin 2ᵏ⁺¹) (below hmax), so the finest boxes get exactly the uniform lattice of
/// their size and every seed's spacing lies in (0.45, 0.9] h(p).  The levels' lattices are
/// nested, so their seeds are never closer than the finer spacing; the last level and the
/// hmax lattice are not, so its seeds within 0.7 × its spacing of a kept hmax-lattice point
/// are dropped.  Seeds keep 0.54 × the level's largest h from the boundary (a seed closer to
/// a boundary edge of length ≈ h makes a sliver there that the refinement may not split:
/// boundary edges are kept).  Each level visits only the box where h is below its upper bound.
fn graded_seeds(unit: &[Point], field: &SizeField) -> Vec<Point> {
    let h = field.hmax();
    let coarse = LATTICE * h;
    let mut seeds = lattice_points_in(unit, coarse, GAP * coarse, None, |p| field.at(p) >= h);
    // Is a point of the hmax lattice with h ≥ hmax within `r` of p?  (The lattice is analytic:
    // rows y = j R, R = S √3 / 2, odd rows shifted by S / 2.)
    let row = coarse * 3f64.sqrt() / 2.0;
    let near_coarse = |p: Point, r: f64| {
        let j0 = (p[1] / row).round() as i64;
        (j0 - 1..=j0 + 1).any(|j| {
            let shift = if j.rem_euclid(2) == 1 {
                0.5 * coarse
            } else {
                0.0
            };
            let k0 = ((p[0] - shift) / coarse).round() as i64;
            (k0 - 1..=k0 + 1).any(|k| {
                let q = [k as f64 * coarse + shift, j as f64 * row];
                let d = (q[0] - p[0]).hypot(q[1] - p[1]);
                d < r && field.at(q) >= h
            })
        })
    };
    let mut low = field.hmin();
    while low < h && low > h * 1e-12 {
        let top = (2.0 * low).min(h);
        let last = top >= h;
        let spacing = LATTICE * low;
        if let Some(window) = field.zone_below(top) {
            seeds.extend(lattice_points_in(
                unit,
                spacing,
                GAP * LATTICE * top,
                Some(window),
                |p| {
                    let hp = field.at(p);
                    hp >= low && hp < top && !(last && near_coarse(p, 0.7 * spacing))
                },
            ));
        }
        low *= 2.0;
    }
    seeds
}

fn triangulate(
    boundary: &[Point],
    h: f64,
    field: Option<&SizeField>,
    normaliser: &Normaliser,
    limits: &MeshLimits,
    vertex_budget: usize,
) -> Result<Mesh, MeshError> {
    let n = boundary.len();
    let mut cdt = initial_cdt(boundary, h, field, normaliser)?;
    let split = Splitter {
        field,
        uniform2: threshold2(h),
        max_vertices: n.saturating_add(vertex_budget),
    };
    let inside = refine(&mut cdt, n, h, limits, &split)?;
    Ok(extract(&cdt, &inside, n, normaliser, boundary))
}

/// The constrained Delaunay triangulation of the boundary (in the unit box) and the interior
/// seeds; refuses a boundary whose edges cross or touch, or whose points merge when snapped.
fn initial_cdt(
    boundary: &[Point],
    h: f64,
    field: Option<&SizeField>,
    normaliser: &Normaliser,
) -> Result<Cdt, MeshError> {
    let n = boundary.len();
    let mut vertices: Vec<Point2<f64>> = boundary.iter().map(|&p| normaliser.to_unit(p)).collect();
    let unit: Vec<Point> = vertices.iter().map(|p| [p.x, p.y]).collect();
    let seeds = match field {
        None => lattice_points(&unit, LATTICE * h, GAP * LATTICE * h),
        Some(field) => graded_seeds(&unit, field),
    };
    let expected = n + seeds.len();
    vertices.extend(seeds.into_iter().map(|[x, y]| Point2::new(x, y)));
    let edges: Vec<[usize; 2]> = (0..n).map(|i| [i, (i + 1) % n]).collect();
    let mut conflicts = 0usize;
    let cdt = Cdt::try_bulk_load_cdt(vertices, edges, |_| conflicts += 1).map_err(|e| {
        MeshError::Triangulation {
            reason: format!("constrained Delaunay triangulation failed: {e:?}"),
        }
    })?;
    if conflicts > 0 || cdt.num_vertices() != expected {
        return Err(MeshError::DegeneratePolygon {
            reason: format!(
                "boundary edges cross or touch ({conflicts} conflicts, {} of {n} boundary points \
                 distinct at the snapping resolution)",
                cdt.num_vertices()
            ),
        });
    }
    Ok(cdt)
}

/// The squared length above which an edge of target size `h` is split.  Decisions are taken on
/// the snapped h with a margin that covers the difference between the snapped boundary points
/// spade sees and the original ones the mesh returns.
fn threshold2(h: f64) -> f64 {
    let margin = 1e-9 + 4.0 * GRID / h;
    (h * (1.0 - margin)).powi(2)
}

/// Which edges are too long, and how many vertices the mesh may have.
struct Splitter<'a> {
    /// The graded size function, if any.
    field: Option<&'a SizeField>,
    /// [`threshold2`] of the uniform size.
    uniform2: f64,
    /// Boundary points plus the vertex budget.
    max_vertices: usize,
}

impl Splitter<'_> {
    /// True when an edge of squared length `length2` centred at `centre` must be split.
    fn too_long(&self, length2: f64, centre: Point2<f64>) -> bool {
        match self.field {
            None => length2 > self.uniform2,
            Some(field) => length2 > threshold2(field.at([centre.x, centre.y])),
        }
    }

    /// The refusal of a mesh that needs more than [`Splitter::max_vertices`].
    fn budget_exceeded(&self, cdt: &Cdt) -> MeshError {
        MeshError::RefinementIncomplete {
            vertices: cdt.num_vertices(),
            budget: self.max_vertices,
        }
    }
}

/// Ruppert refinement, then rounds of "split the edges longer than hmax" (a full Ruppert pass
/// again only when a split left an angle below the limit); returns the inside faces.
fn refine(
    cdt: &mut Cdt,
    n: usize,
    h: f64,
    limits: &MeshLimits,
    split: &Splitter,
) -> Result<Vec<bool>, MeshError> {
    let limit = limits.min_angle_deg;
    let mut refine = true;
    let mut rounds = 0;
    loop {
        if refine {
            ruppert(cdt, h, limits, split)?;
        }
        let inside = inside_faces(cdt, n)?;
        let long = long_edge_midpoints(cdt, &inside, &|l, c| split.too_long(l, c));
        if long.is_empty() {
            return Ok(inside);
        }
        rounds += 1;
        if rounds > MAX_ROUNDS || cdt.num_vertices().saturating_add(long.len()) > split.max_vertices
        {
            return Err(split.budget_exceeded(cdt));
        }
        let inserted = insert_midpoints(cdt, long)?;
        let mut worst = worst_angle_at(cdt, &inserted, 180.0);
        if split.field.is_some() || rounds > LOCAL_AFTER {
            // Graded (or a long uniform cascade, see LOCAL_AFTER): splits cascade along the
            // size function's level changes a few edges at a time, so follow them locally
            // instead of one full scan per step.
            worst = follow_cascade(cdt, inserted, split, worst)?;
        }
        // Refine again (a full pass) only when splitting left an angle below the limit.
        refine = worst < limit - 1e-9;
    }
}

/// One pass of spade's Ruppert refinement with the angle limit and an area bound, then
/// [`relieve`] for the skinny faces it leaves next to the kept boundary.
fn ruppert(cdt: &mut Cdt, h: f64, limits: &MeshLimits, split: &Splitter) -> Result<(), MeshError> {
    let max_area = AREA_FACTOR * h * h;
    let parameters = RefinementParameters::<f64>::new()
        .with_angle_limit(AngleLimit::from_deg(limits.min_angle_deg))
        .with_max_allowed_area(max_area)
        .keep_constraint_edges()
        .exclude_outer_faces(true)
        .with_max_additional_vertices(split.max_vertices.saturating_sub(cdt.num_vertices()));
    let result = cdt.refine(parameters);
    if !result.refinement_complete {
        return Err(split.budget_exceeded(cdt));
    }
    let mut outer = vec![false; cdt.num_all_faces()];
    for face in &result.excluded_faces {
        outer[face.index()] = true;
    }
    relieve(cdt, &outer, limits.min_angle_deg, max_area, split)
}

/// Passes of [`relieve`] over the faces it could not mend yet.
const RELIEF_PASSES: usize = 4;

/// Largest cavity (faces) [`relieve`] examines for one circumcentre.
const RELIEF_CAVITY: usize = 64;

/// Mends the skinny inside faces spade leaves.  With the boundary kept (never split), spade
/// drops a skinny face whose circumcentre encroaches a boundary edge (lies in its diametral
/// circle) instead of splitting that edge, so the face stays.  Such a circumcentre still lies
/// inside the body, often well away from the boundary: a body one hmax thick (no seed fits)
/// left a 17.3° fan triangle from a boundary node to a short boundary edge, and splitting its
/// long sides kept the angle.  Here the circumcentre is inserted anyway when every face it
/// creates (the constrained Delaunay cavity's boundary joined to it, predicted locally before
/// inserting) keeps the angle limit and the area bound: each insertion removes a skinny face
/// and creates none, so the passes end.  Cost: one scan of the faces (no division, no
/// trigonometry per face), then up to [`RELIEF_PASSES`] passes over the skinny faces left, each
/// looking at a cavity of at most [`RELIEF_CAVITY`] faces.  `outer` marks spade's excluded
/// (outside) faces by index.
fn relieve(
    cdt: &mut Cdt,
    outer: &[bool],
    limit: f64,
    max_area: f64,
    split: &Splitter,
) -> Result<(), MeshError> {
    let sin = limit.to_radians().sin();
    if sin <= 0.0 {
        return Ok(());
    }
    // Skinny as spade judges it: circumradius / shortest edge above 1 / (2 sin limit).
    let ratio2 = (0.5 / sin).powi(2);
    let mut pending: Vec<(FixedFaceHandle<InnerTag>, [FixedVertexHandle; 3])> = cdt
        .inner_faces()
        .filter(|f| !outer.get(f.fix().index()).copied().unwrap_or(false))
        .filter(|f| skinny(f.positions(), ratio2))
        .map(|f| (f.fix(), f.vertices().map(|v| v.fix())))
        .collect();
    for _ in 0..RELIEF_PASSES {
        let before = pending.len();
        let mut left = Vec::new();
        for (face, vertices) in pending {
            // Faces are renumbered by insertions: skip the ones gone.
            let alive = face.index() < cdt.num_all_faces()
                && same_cycle(cdt.face(face).vertices().map(|v| v.fix()), vertices);
            if !alive {
                continue;
            }
            let Some(centre) = mendable(cdt, face, limit, max_area) else {
                left.push((face, vertices));
                continue;
            };
            if cdt.num_vertices() >= split.max_vertices {
                // The mending is optional: a budget spent keeps the faces as spade left them
                // (the refinement after it reports the budget if it needs more).
                return Ok(());
            }
            cdt.insert_with_hint(centre, vertices[0])
                .map_err(|e| MeshError::Triangulation {
                    reason: format!("inserting a circumcentre failed: {e:?}"),
                })?;
        }
        if left.is_empty() || left.len() == before {
            break;
        }
        pending = left;
    }
    Ok(())
}

/// True when the triangle `t` has circumradius² > `ratio2` × shortest side², without dividing:
/// R² = a² b² c² / (16 area²), so the test is (the two longer sides' squared lengths multiplied)
/// > `ratio2` × (2 area)² × 4.
fn skinny(t: [Point2<f64>; 3], ratio2: f64) -> bool {
    let [a, b, c] = [0, 1, 2].map(|k| t[k].distance_2(t[(k + 1) % 3]));
    let twice = (t[1].x - t[0].x) * (t[2].y - t[0].y) - (t[1].y - t[0].y) * (t[2].x - t[0].x);
    let longer = a * b * c / a.min(b).min(c);
    longer > 4.0 * ratio2 * twice * twice
}

/// True when `a` is `b` up to a cyclic shift.
fn same_cycle(a: [FixedVertexHandle; 3], b: [FixedVertexHandle; 3]) -> bool {
    (0..3).any(|k| (0..3).all(|i| a[(i + k) % 3] == b[i]))
}

/// The circumcentre of the inside face `face` when inserting it makes only faces with angles
/// ≥ `limit` and areas ≤ `max_area`: the faces whose circumcircle holds it, reached from `face`
/// without crossing a boundary edge, are replaced by its fan to their outline.  `None` when the
/// centre is not strictly inside that cavity (beyond a boundary edge, or on an edge).
fn mendable(
    cdt: &Cdt,
    face: FixedFaceHandle<InnerTag>,
    limit: f64,
    max_area: f64,
) -> Option<Point2<f64>> {
    let centre = cdt.face(face).circumcenter();
    if !(centre.x.is_finite() && centre.y.is_finite()) {
        return None;
    }
    let mut cavity = vec![face];
    let mut stack = vec![face];
    let mut outline: Vec<[Point2<f64>; 2]> = Vec::new();
    let mut found = false;
    while let Some(f) = stack.pop() {
        let f = cdt.face(f);
        found |= strictly_inside(f.positions(), centre);
        for edge in f.adjacent_edges() {
            let neighbour = edge.rev().face().as_inner();
            match neighbour {
                Some(g) if !edge.is_constraint_edge() => {
                    if cavity.contains(&g.fix()) {
                        continue;
                    }
                    if in_circumcircle(g.positions(), centre) {
                        if cavity.len() >= RELIEF_CAVITY {
                            return None;
                        }
                        cavity.push(g.fix());
                        stack.push(g.fix());
                        continue;
                    }
                    outline.push(edge.positions());
                }
                _ => outline.push(edge.positions()),
            }
        }
    }
    if !found {
        return None;
    }
    let mendable = outline.iter().all(|&[a, b]| {
        let twice = (b.x - a.x) * (centre.y - a.y) - (b.y - a.y) * (centre.x - a.x);
        twice > 0.0 && 0.5 * twice <= max_area && face_min_angle([a, b, centre]) >= limit
    });
    mendable.then_some(centre)
}

/// True when `p` lies strictly inside the counter-clockwise triangle `t` (a relative margin
/// keeps points on an edge out).
fn strictly_inside(t: [Point2<f64>; 3], p: Point2<f64>) -> bool {
    (0..3).all(|k| {
        let (a, b) = (t[k], t[(k + 1) % 3]);
        let (dx, dy) = (b.x - a.x, b.y - a.y);
        let twice = dx * (p.y - a.y) - dy * (p.x - a.x);
        twice > 1e-12 * (dx * dx + dy * dy)
    })
}

/// True when `p` lies strictly inside the circumcircle of the counter-clockwise triangle `t`.
fn in_circumcircle(t: [Point2<f64>; 3], p: Point2<f64>) -> bool {
    let rows = t.map(|q| {
        let (x, y) = (q.x - p.x, q.y - p.y);
        [x, y, x * x + y * y]
    });
    let [a, b, c] = rows;
    let det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
        + a[2] * (b[0] * c[1] - b[1] * c[0]);
    det > 0.0
}

/// Inserts edge midpoints (each with a nearby vertex as hint); returns the new vertices.
fn insert_midpoints(
    cdt: &mut Cdt,
    points: Vec<(Point2<f64>, FixedVertexHandle)>,
) -> Result<Vec<FixedVertexHandle>, MeshError> {
    let mut inserted = Vec::with_capacity(points.len());
    for (p, hint) in points {
        let v = cdt
            .insert_with_hint(p, hint)
            .map_err(|e| MeshError::Triangulation {
                reason: format!("inserting an edge midpoint failed: {e:?}"),
            })?;
        inserted.push(v);
    }
    Ok(inserted)
}

/// The smallest of `worst` and the angles of the inner faces at `vertices`, in degrees.
fn worst_angle_at(cdt: &Cdt, vertices: &[FixedVertexHandle], mut worst: f64) -> f64 {
    for &v in vertices {
        for edge in cdt.vertex(v).out_edges() {
            if let Some(face) = edge.face().as_inner() {
                worst = worst.min(face_min_angle(face.positions()));
            }
        }
    }
    worst
}

/// Splits the long edges at the `frontier` (the vertices just inserted), then at the vertices
/// that inserts, until none is left; returns the smallest of `worst` and the new faces' angles.
fn follow_cascade(
    cdt: &mut Cdt,
    mut frontier: Vec<FixedVertexHandle>,
    split: &Splitter,
    mut worst: f64,
) -> Result<f64, MeshError> {
    loop {
        let mut local: Vec<(Point2<f64>, FixedVertexHandle)> = frontier
            .iter()
            .flat_map(|&v| cdt.vertex(v).out_edges().map(move |e| (v, e)))
            .filter(|(_, e)| {
                let u = e.as_undirected();
                !u.is_constraint_edge() && split.too_long(u.length_2(), u.center())
            })
            .map(|(v, e)| (e.as_undirected().center(), v))
            .collect();
        local.sort_by(|a, b| a.0.x.total_cmp(&b.0.x).then(a.0.y.total_cmp(&b.0.y)));
        local.dedup_by(|a, b| a.0 == b.0);
        if local.is_empty() {
            return Ok(worst);
        }
        if cdt.num_vertices().saturating_add(local.len()) > split.max_vertices {
            return Err(split.budget_exceeded(cdt));
        }
        frontier = insert_midpoints(cdt, local)?;
        worst = worst_angle_at(cdt, &frontier, worst);
    }
}

/// Marks the faces inside the polygon (indexed by face index): flood fill from the left sides
/// of the boundary edges `i → i + 1` (vertices `0..n`), never crossing a constraint edge.
fn inside_faces(cdt: &Cdt, n: usize) -> Result<Vec<bool>, MeshError> {
    let mut inside = vec![false; cdt.num_all_faces()];
    let mut stack = Vec::new();
    for i in 0..n {
        let from = FixedVertexHandle::from_index(i);
        let to = FixedVertexHandle::from_index((i + 1) % n);
        let edge =
            cdt.get_edge_from_neighbors(from, to)
                .ok_or_else(|| MeshError::Triangulation {
                    reason: format!("boundary edge {i} is missing from the triangulation"),
                })?;
        if let Some(face) = edge.face().as_inner() {
            if !inside[face.fix().index()] {
                inside[face.fix().index()] = true;
                stack.push(face.fix());
            }
        }
    }
    while let Some(face) = stack.pop() {
        for edge in cdt.face(face).adjacent_edges() {
            if edge.is_constraint_edge() {
                continue;
            }
            if let Some(next) = edge.rev().face().as_inner() {
                if !inside[next.fix().index()] {
                    inside[next.fix().index()] = true;
                    stack.push(next.fix());
                }
            }
        }
    }
    Ok(inside)
}

/// Smallest angle (degrees) of a triangle.
fn face_min_angle(p: [Point2<f64>; 3]) -> f64 {
    let mut m = f64::INFINITY;
    for k in 0..3 {
        let (a, b, c) = (p[(k + 2) % 3], p[k], p[(k + 1) % 3]);
        let u = [a.x - b.x, a.y - b.y];
        let v = [c.x - b.x, c.y - b.y];
        let cross = u[0] * v[1] - u[1] * v[0];
        let dot = u[0] * v[0] + u[1] * v[1];
        m = m.min(cross.abs().atan2(dot));
    }
    m.to_degrees()
}

/// Midpoints of the non-boundary edges of inside faces that are `too_long(length², midpoint)`.
fn long_edge_midpoints(
    cdt: &Cdt,
    inside: &[bool],
    too_long: &impl Fn(f64, Point2<f64>) -> bool,
) -> Vec<(Point2<f64>, FixedVertexHandle)> {
    cdt.undirected_edges()
        .filter(|e| !e.is_constraint_edge() && too_long(e.length_2(), e.center()))
        .filter(|e| {
            let d = e.as_directed();
            [d, d.rev()]
                .iter()
                .any(|d| d.face().as_inner().is_some_and(|f| inside[f.fix().index()]))
        })
        .map(|e| (e.center(), e.vertices()[0].fix()))
        .collect()
}

/// The kept faces as a [`Mesh`]: boundary nodes first (in `boundary` order, original
/// coordinates), then the used Steiner points in spade's vertex order.
fn extract(
    cdt: &Cdt,
    inside: &[bool],
    n: usize,
    normaliser: &Normaliser,
    boundary: &[Point],
) -> Mesh {
    let kept: Vec<[usize; 3]> = cdt
        .inner_faces()
        .filter(|f| inside[f.fix().index()])
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
            nodes.push(normaliser.to_scene(vertex.position()));
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
