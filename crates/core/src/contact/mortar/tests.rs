//! Unit tests of the mortar geometry and rows against hand-computed values.

use super::geometry::{dual, nodal_normals, SlaveSegment, GAUSS};
use super::{pair_rows, Frame, MIN_SHARE};
use crate::contact::{pair_rows as node_to_segment, ContactRow, Search};
use crate::geometry::Point;
use crate::mesh::{Cells, Mesh};

/// A boundary polyline as a mesh (no cells: the rows read only nodes and boundary edges).
/// The body lies to the left of each edge a → b.
fn polyline(points: &[Point]) -> Mesh {
    Mesh {
        nodes: points.to_vec(),
        cells: Cells::Triangles(Vec::new()),
        boundary: (1..points.len()).map(|i| [i - 1, i]).collect(),
    }
}

/// A slave above y = `y` (nodes at `xs`, left to right: outward normal −y).
fn slave_flat(xs: &[f64], y: f64) -> Mesh {
    polyline(&xs.iter().map(|&x| [x, y]).collect::<Vec<_>>())
}

/// A master below y = `y` (nodes at `xs`, given left to right, stored right to left: outward
/// normal +y).
fn master_flat(xs: &[f64], y: f64) -> Mesh {
    polyline(&xs.iter().rev().map(|&x| [x, y]).collect::<Vec<_>>())
}

fn rows(slave: &Mesh, master: &Mesh) -> super::Built {
    rows_in(slave, master, Frame::Master)
}

fn rows_in(slave: &Mesh, master: &Mesh, frame: Frame) -> super::Built {
    let cs = vec![true; slave.nodes.len()];
    let inside = vec![None; slave.nodes.len()];
    pair_rows(
        slave,
        master,
        &cs,
        &master.boundary,
        &inside,
        1e-12,
        1.0,
        frame,
    )
}

fn weight_sum(r: &ContactRow) -> f64 {
    r.masters.iter().map(|m| m.1).sum()
}

/// Hat function of node `k` of the sorted abscissae `xs` at x (0 outside its support).
fn hat(xs: &[f64], k: usize, x: f64) -> f64 {
    if k > 0 && x >= xs[k - 1] && x <= xs[k] {
        return (x - xs[k - 1]) / (xs[k] - xs[k - 1]);
    }
    if k + 1 < xs.len() && x >= xs[k] && x <= xs[k + 1] {
        return (xs[k + 1] - x) / (xs[k + 1] - xs[k]);
    }
    0.0
}

/// Dual function of node `j` of `xs` at x: on each segment 2N_j − N_other.
fn psi(xs: &[f64], j: usize, x: f64) -> f64 {
    for s in 0..xs.len() - 1 {
        if x >= xs[s] && x <= xs[s + 1] && (s == j || s + 1 == j) {
            let nj = hat(xs, j, x);
            return 2.0 * nj - (1.0 - nj);
        }
    }
    0.0
}

/// ∫ f over [a, b] by Simpson's rule on every interval between consecutive `breaks`: exact for
/// the piecewise quadratics ψ_j N_k (an oracle independent of the clipping and Gauss code).
fn integrate(breaks: &[f64], f: impl Fn(f64) -> f64) -> f64 {
    let mut b: Vec<f64> = breaks.to_vec();
    b.sort_by(f64::total_cmp);
    b.dedup();
    b.windows(2)
        .map(|w| {
            let (l, r) = (w[0], w[1]);
            // Evaluate just inside the interval so that hats and duals see one piece.
            let e = 1e-13 * (r - l);
            (r - l) / 6.0 * (f(l + e) + 4.0 * f(0.5 * (l + r)) + f(r - e))
        })
        .sum()
}

#[test]
fn dual_basis_is_biorthogonal_on_a_segment() {
    // ∫₀¹ ψ_i N_j dξ = δ_ij / 2 and ψ₁ + ψ₂ = 1: the 3-point rule is exact for these quadratics.
    let n = |xi: f64| [1.0 - xi, xi];
    for i in 0..2 {
        for j in 0..2 {
            let v: f64 = GAUSS.iter().map(|&(x, w)| w * dual(x)[i] * n(x)[j]).sum();
            let want = if i == j { 0.5 } else { 0.0 };
            assert!((v - want).abs() < 1e-15, "∫ψ{i}N{j} = {v}");
        }
    }
    for x in [0.0, 0.3, 1.0] {
        assert!((dual(x)[0] + dual(x)[1] - 1.0).abs() < 1e-15);
    }
}

#[test]
fn projection_with_parallel_normals_is_orthogonal_on_a_skew_segment() {
    // Skew segment (1, 1)–(3, 2), normal ⟂ to it: ξ is the orthogonal projection parameter.
    let (x1, x2) = ([1.0, 1.0], [3.0, 2.0]);
    let n = [1.0 / 5f64.sqrt(), -2.0 / 5f64.sqrt()];
    let seg = SlaveSegment {
        x1,
        x2,
        n1: n,
        n2: n,
    };
    for y in [[2.0, 0.0], [4.5, 1.0], [0.0, 3.0]] {
        let d = [x2[0] - x1[0], x2[1] - x1[1]];
        let want = ((y[0] - x1[0]) * d[0] + (y[1] - x1[1]) * d[1]) / 5.0;
        let got = seg.project(y).unwrap();
        // Round-off of a few operations on O(1) numbers.
        assert!((got - want).abs() < 1e-14, "{got} vs {want}");
    }
    // Clipping: the image of the master segment (4.5, 1)–(2, 0) is [0.2, 1.4] → [0.2, 1].
    let piece = seg.clip([4.5, 1.0], [2.0, 0.0]).unwrap();
    assert!(
        (piece.lo - 0.2).abs() < 1e-14 && piece.hi == 1.0,
        "{piece:?}"
    );
    // A master segment beyond the slave's end covers nothing.
    assert!(seg.clip([5.0, 1.0], [4.0, 0.0]).is_none());
}

#[test]
fn projection_along_radial_normals_on_a_curved_segment() {
    // A chord of the circle of radius R about the origin with radial nodal normals: x(ξ) = R n(ξ),
    // so the normal line through x(ξ) passes through the origin and the projection of y is the
    // ξ with n(ξ) ∥ y: ξ = n₁ × y / (n₁ × y − n₂ × y).
    let r = 2.0;
    let (t1, t2) = (-1.2_f64, -0.9_f64);
    let n1 = [t1.cos(), t1.sin()];
    let n2 = [t2.cos(), t2.sin()];
    let seg = SlaveSegment {
        x1: [r * n1[0], r * n1[1]],
        x2: [r * n2[0], r * n2[1]],
        n1,
        n2,
    };
    let cross = |a: Point, b: Point| a[0] * b[1] - a[1] * b[0];
    for (t, rho) in [(-1.1_f64, 2.3), (-0.95, 2.05), (-1.3, 2.5), (-0.8, 1.9)] {
        let y = [rho * t.cos(), rho * t.sin()];
        let want = cross(n1, y) / (cross(n1, y) - cross(n2, y));
        let got = seg.project(y).unwrap();
        assert!((got - want).abs() < 1e-13, "θ {t}: {got} vs {want}");
    }
    // Gauss points of the image of a concentric master chord at radius 2.3 (angles −1.1, −0.95):
    // every slave point's gap lies along the ray through the origin, η in [0, 1], and the gap
    // |y| − |x| lies between 0.3 less the master chord's sagitta 2.3 (1 − cos 0.075) and 0.3
    // plus the slave chord's 2 (1 − cos 0.15).
    let (ya, yb) = (
        [2.3 * (-0.95_f64).cos(), 2.3 * (-0.95_f64).sin()],
        [2.3 * (-1.1_f64).cos(), 2.3 * (-1.1_f64).sin()],
    );
    let piece = seg.clip(ya, yb).unwrap();
    let points = seg.gauss_points(piece, ya, yb).unwrap();
    for g in points {
        let x = seg.point(g.xi);
        let y = [
            ya[0] + g.eta * (yb[0] - ya[0]),
            ya[1] + g.eta * (yb[1] - ya[1]),
        ];
        // x, y and the origin are collinear.
        assert!(cross(x, y).abs() < 1e-13, "{g:?}");
        assert!((0.0..=1.0).contains(&g.eta));
        let (lo, hi) = (
            0.3 - 2.3 * (1.0 - 0.075_f64.cos()),
            0.3 + 2.0 * (1.0 - 0.15_f64.cos()),
        );
        assert!(g.gap > lo && g.gap < hi, "{g:?}");
        assert!((g.gap - (y[0].hypot(y[1]) - x[0].hypot(x[1]))).abs() < 1e-14);
    }
}

#[test]
fn normals_at_corners() {
    // A block above y = 0 seen as its boundary from its left side down to its right side: its
    // side edges do not face a master below, so the corners take the bottom edge's normal.
    let block = polyline(&[[0.0, 0.5], [0.0, 0.0], [0.5, 0.0], [1.0, 0.0], [1.0, 0.5]]);
    let base = master_flat(&[-1.0, 0.3, 2.0], 0.0);
    let b = rows(&block, &base);
    assert_eq!(b.rows.len(), 3);
    // The two side nodes face nothing: counted, not dropped.
    assert_eq!(b.unmatched, 2);
    for r in &b.rows {
        assert_eq!(r.normal, [0.0, 1.0], "node {}", r.slave_node);
    }
    // A wedge whose two edges face the master: the tip takes the bisector, the ends their own.
    let wedge = polyline(&[[-1.0, 0.5], [0.0, 0.0], [1.0, 0.5]]);
    let normals = nodal_normals(&wedge.nodes, &wedge.boundary);
    let s = 5f64.sqrt();
    let close = |a: Point, b: Point| (a[0] - b[0]).abs() < 1e-15 && (a[1] - b[1]).abs() < 1e-15;
    assert!(close(normals[0].unwrap(), [-0.5 / s * 2.0, -2.0 / s]));
    assert!(close(normals[1].unwrap(), [0.0, -1.0]));
    assert!(close(normals[2].unwrap(), [1.0 / s, -2.0 / s]));
    let b = rows(&wedge, &master_flat(&[-2.0, -0.1, 0.4, 2.0], -0.1));
    assert_eq!(b.rows.len(), 3);
    // The rows act along the (flat) master's normal, whatever the slave's normals.
    for r in &b.rows {
        assert!(close(r.normal, [0.0, 1.0]), "{:?}", r.normal);
    }
    for r in &b.rows {
        assert!((weight_sum(r) - 1.0).abs() < 1e-15);
    }
}

#[test]
fn full_coverage_gives_the_lumped_mass_and_the_exact_mortar_integrals() {
    // Non-matching flat interface, gap 0.01, master longer than the slave on both sides.
    let xs = [0.0, 0.13, 0.4, 0.55, 0.81, 1.0];
    let xm = [-0.3, 0.07, 0.29, 0.5, 0.66, 0.9, 1.2];
    let b = rows(&slave_flat(&xs, 0.0), &master_flat(&xm, -0.01));
    assert_eq!(b.rows.len(), xs.len());
    assert_eq!(b.unmatched, 0);
    let mut total = 0.0;
    // Master node index in the stored (reversed) master mesh.
    let stored = |k: usize| xm.len() - 1 - k;
    let mut breaks: Vec<f64> = xs.to_vec();
    breaks.extend(xm.iter().copied().filter(|x| (0.0..=1.0).contains(x)));
    for (j, r) in b.rows.iter().enumerate() {
        assert_eq!(r.slave_node, j);
        // D_jj = ∫N_j = half the adjacent lengths (1e-15: sums of a few O(1) products).
        let lumped = 0.5 * (xs[(j + 1).min(xs.len() - 1)] - xs[j.saturating_sub(1)]);
        assert!(
            (r.tributary - lumped).abs() < 1e-15,
            "D {j}: {}",
            r.tributary
        );
        assert!((weight_sum(r) - 1.0).abs() < 1e-15);
        assert!((r.gap - 0.01).abs() < 1e-15, "gap {j}: {}", r.gap);
        assert_eq!(r.normal, [0.0, 1.0]);
        for k in 0..xm.len() {
            let m = integrate(&breaks, |x| psi(&xs, j, x) * hat(&xm, k, x));
            let got = r
                .masters
                .iter()
                .find(|e| e.0 == stored(k))
                .map_or(0.0, |e| e.1 * r.tributary);
            // Simpson on the quadratic pieces is exact; 1e-14 is their round-off.
            assert!((got - m).abs() < 1e-14, "M[{j}][{k}] = {got} vs {m}");
        }
        total += r.tributary;
    }
    // Σ_j D_jj = ∫ Σψ_j = the covered slave length.
    assert!((total - 1.0).abs() < 1e-14);
}

#[test]
fn zone_ends_integrate_the_covered_part_only() {
    let xs = [0.0, 0.25, 0.5, 0.75, 1.0];
    // Master from x = 0.3: the slave segment [0.25, 0.5] is covered over c = 0.8 from its far
    // end, so D(0.25) = (3c² − 2c) |e| / 2 = 0.32 × 0.125 = 0.04 ≥ MIN_SHARE × 0.125; node 0 is
    // on no interface segment.
    let b = rows(&slave_flat(&xs, 0.0), &master_flat(&[0.3, 0.6, 1.3], 0.0));
    assert_eq!(b.unmatched, 1);
    assert_eq!(b.rows.len(), 4);
    assert!(
        (b.rows[0].tributary - 0.04).abs() < 1e-15,
        "{}",
        b.rows[0].tributary
    );
    let total: f64 = b.rows.iter().map(|r| r.tributary).sum();
    assert!((total - 0.7).abs() < 1e-14, "Σ D = {total}");
    for r in &b.rows {
        assert!((weight_sum(r) - 1.0).abs() < 1e-14);
        assert_eq!(r.gap, 0.0);
    }
    // Master from x = 0.35: c = 0.6 gives D(0.25) = −0.12 × 0.125 < 0: no row, counted.
    let b = rows(&slave_flat(&xs, 0.0), &master_flat(&[0.35, 0.6, 1.3], 0.0));
    assert_eq!(b.unmatched, 2);
    assert_eq!(b.rows[0].slave_node, 2);
    // The threshold itself: c with 3c² − 2c = MIN_SHARE keeps the row, slightly less drops it.
    let c = (2.0 + (4.0 + 12.0 * MIN_SHARE).sqrt()) / 6.0;
    for (cc, kept) in [(c + 1e-6, true), (c - 1e-6, false)] {
        let start = 0.5 - cc * 0.25;
        let b = rows(&slave_flat(&xs, 0.0), &master_flat(&[start, 0.6, 1.3], 0.0));
        assert_eq!(b.rows.iter().any(|r| r.slave_node == 1), kept, "c = {cc}");
    }
}

/// Slave: a polygonal arc of radius 2 (outward normals radial); master: a non-matching
/// concentric polygonal arc of radius 2.05 around it (its outward normals point inwards).
fn arcs(shift: Point) -> (Mesh, Mesh) {
    let arc = |r: f64, from: f64, to: f64, n: usize| -> Vec<Point> {
        (0..=n)
            .map(|i| {
                let t = from + (to - from) * i as f64 / n as f64;
                [r * t.cos() + shift[0], r * t.sin() + shift[1]]
            })
            .collect()
    };
    // Slave CCW (body inside the circle on the left): angles increasing.
    let slave = polyline(&arc(2.0, -2.0, -1.1, 9));
    // Master outside the circle, body on its left: angles decreasing; wider than the slave.
    let master = polyline(&arc(2.05, -1.0, -2.1, 7));
    (slave, master)
}

#[test]
fn curved_nonmatching_rows_cover_the_slave_and_are_translation_invariant() {
    let (slave, master) = arcs([0.0, 0.0]);
    let b = rows(&slave, &master);
    assert_eq!(b.rows.len(), slave.nodes.len());
    let length: f64 = slave
        .boundary
        .iter()
        .map(|&[p, q]| crate::geometry::distance(slave.nodes[p], slave.nodes[q]))
        .sum();
    let total: f64 = b.rows.iter().map(|r| r.tributary).sum();
    // Full coverage: Σ D = slave length to round-off.
    assert!(
        (total - length).abs() < 1e-14 * length,
        "{total} vs {length}"
    );
    for r in &b.rows {
        assert!((weight_sum(r) - 1.0).abs() < 1e-14);
        // Gap between the polygons along the radial normal: between the radial clearance
        // 0.05 less the master's sagitta 2.05 (1 − cos(Δ/2)) and 0.05 plus the slave's.
        let sag = |r: f64, n: f64| r * (1.0 - (1.1 / n / 2.0).cos());
        assert!(
            r.gap > 0.05 - sag(2.05, 7.0) && r.gap < 0.05 + sag(2.0, 9.0),
            "{}",
            r.gap
        );
        // The row normal is the ψ-weighted mean of the normals of the master segments over
        // the node's edges: each master normal is radial at its segment's middle, which lies
        // within a slave edge (0.1 rad) plus half a master segment (1.1/14 rad) of the node's
        // direction, so the row normal is within that angle of minus the node's radial
        // direction.
        let x = r.position;
        let len = x[0].hypot(x[1]);
        let cos = -(r.normal[0] * x[0] + r.normal[1] * x[1]) / len;
        assert!(
            cos >= (0.1_f64 + 1.1 / 14.0).cos(),
            "node {}: {cos}",
            r.slave_node
        );
    }
    // Moving both bodies rigidly changes no row (beyond the round-off of coordinates ~ 5).
    let (s2, m2) = arcs([3.7, -1.2]);
    let moved = rows(&s2, &m2);
    assert_eq!(moved.rows.len(), b.rows.len());
    for (r, q) in b.rows.iter().zip(&moved.rows) {
        assert_eq!(r.slave_node, q.slave_node);
        assert!((r.gap - q.gap).abs() < 1e-12);
        assert!((r.tributary - q.tributary).abs() < 1e-12);
        assert!((r.normal[0] - q.normal[0]).abs() < 1e-12);
        assert_eq!(r.masters.len(), q.masters.len());
        for (a, c) in r.masters.iter().zip(&q.masters) {
            assert_eq!(a.0, c.0);
            assert!((a.1 - c.1).abs() < 1e-12);
        }
    }
}

#[test]
fn conforming_meshes_give_the_node_to_segment_rows() {
    // Flat, non-uniform, shared abscissae; and a conforming pair of arcs.
    let xs = [0.0, 0.13, 0.4, 0.55, 0.81, 1.0];
    let flat = (slave_flat(&xs, 0.0), master_flat(&xs, 0.0));
    let curved = {
        let (s, _) = arcs([0.0, 0.0]);
        let m = polyline(&s.nodes.iter().rev().copied().collect::<Vec<_>>());
        (s, m)
    };
    for (slave, master) in [flat, curved] {
        let cs = vec![true; slave.nodes.len()];
        let inside = vec![None; slave.nodes.len()];
        let nts = node_to_segment(
            &slave,
            &master,
            &cs,
            &master.boundary,
            &inside,
            1e-12,
            1.0,
            Search::Indexed,
        );
        let mortar = rows(&slave, &master);
        assert_eq!(mortar.rows.len(), nts.rows.len());
        for (m, n) in mortar.rows.iter().zip(&nts.rows) {
            assert_eq!(m.slave_node, n.slave_node);
            // The coincident master node: node-to-segment's weight 1 (t snapped to an end).
            let &(k, _) = n.masters.iter().find(|e| e.1 == 1.0).unwrap();
            for &(l, w) in &m.masters {
                let want = if l == k { 1.0 } else { 0.0 };
                // Round-off of the clipped pieces' end points (1e-16) times O(1) integrands.
                assert!(
                    (w - want).abs() < 1e-12,
                    "node {}: w[{l}] = {w}",
                    m.slave_node
                );
            }
            assert_eq!(m.gap, n.gap);
            // The tributary length (node-to-segment's facing half lengths) is ∫N_j = D_jj.
            assert!((m.tributary - n.tributary).abs() < 1e-14);
            // Flat: the same normal; curved: the mean of the two master segments' normals at
            // the coincident node instead of one segment's: half the segment angle (0.05 rad).
            let dot = m.normal[0] * n.normal[0] + m.normal[1] * n.normal[1];
            assert!(dot > (0.1_f64 / 2.0).cos() - 1e-12, "{dot}");
        }
    }
}

#[test]
fn three_gauss_points_integrate_a_curved_segment_to_order_five_in_its_angle() {
    // Radial normals on a chord spanning Δθ: η(ξ) is a ratio of linear functions whose
    // expansion in ξ has coefficients O(Δθ^k) at degree k, so the 3-point rule (exact to degree
    // 5) misses terms of order Δθ⁵ times its error on ξ⁶ (3 × 10⁻³ relative): the bound below is
    // 10⁻² Δθ⁵ relative.  Reference: the same rule on 64 sub-pieces (error 64⁻⁶ smaller).
    for dtheta in [0.3_f64, 0.1] {
        let (t1, t2) = (-1.0 - 0.5 * dtheta, -1.0 + 0.5 * dtheta);
        let n1 = [t1.cos(), t1.sin()];
        let n2 = [t2.cos(), t2.sin()];
        let seg = SlaveSegment {
            x1: [2.0 * n1[0], 2.0 * n1[1]],
            x2: [2.0 * n2[0], 2.0 * n2[1]],
            n1,
            n2,
        };
        // A master chord at radius 2.2 over a wider angle, covering the whole slave segment.
        let (ta, tb) = (-1.0 + 0.8 * dtheta, -1.0 - 0.7 * dtheta);
        let ya = [2.2 * ta.cos(), 2.2 * ta.sin()];
        let yb = [2.2 * tb.cos(), 2.2 * tb.sin()];
        let moments = |pieces: usize| -> [f64; 3] {
            let whole = seg.clip(ya, yb).unwrap();
            assert!(whole.lo == 0.0 && whole.hi == 1.0);
            let mut m = [0.0; 3];
            for i in 0..pieces {
                let piece = super::geometry::Piece {
                    lo: i as f64 / pieces as f64,
                    hi: (i + 1) as f64 / pieces as f64,
                };
                for g in seg.gauss_points(piece, ya, yb).unwrap() {
                    let psi = dual(g.xi)[0];
                    m[0] += g.weight * psi * (1.0 - g.eta);
                    m[1] += g.weight * psi * g.eta;
                    m[2] += g.weight * psi * g.gap;
                }
            }
            m
        };
        let (coarse, fine) = (moments(1), moments(64));
        for k in 0..3 {
            let rel = (coarse[k] - fine[k]).abs() / fine[k].abs();
            println!("Δθ {dtheta}: moment {k} relative error {rel:.2e}");
            assert!(
                rel <= 1e-2 * dtheta.powi(5),
                "Δθ {dtheta}, moment {k}: {rel:e}"
            );
        }
    }
}

/// A curved slave (a polygonal arc of radius 1, lowest point 0.01 above y = 0) over a flat,
/// non-matching master.  The exact contact condition for a slave point over a flat master is
/// vertical — its height plus its vertical displacement stays ≥ 0 whatever it does sideways —
/// so every row must act along the master's normal +y (a sideways slide of the slave changes
/// no row), and, the vertical distance being linear along each slave edge, the weighted gap
/// g̃_j / D_jj must be node j's height exactly (biorthogonality: ∫ψ_j N_k = δ_jk D_jj on fully
/// covered edges).  Rows along the slave's tilted normals (the linearisation that drops the
/// change of the master point with the slave's sideways motion) failed both: the row of a
/// node at angle θ moved by sin θ per unit slide and measured the gap along the tilted normal.
#[test]
fn rows_on_a_curved_slave_over_a_flat_master_act_along_the_master_normal() {
    let n = 12;
    let arc: Vec<Point> = (0..=n)
        .map(|i| {
            let t = -0.3 + 0.6 * i as f64 / n as f64;
            [t.sin(), 1.01 - t.cos()]
        })
        .collect();
    let slave = polyline(&arc);
    let master = master_flat(&[-0.5, -0.21, 0.02, 0.17, 0.33, 0.5], 0.0);
    let b = rows(&slave, &master);
    assert_eq!(b.rows.len(), arc.len());
    for r in &b.rows {
        // The master is flat: the ψ-weighted mean of its normal is +y to round-off.
        assert!(
            r.normal[0].abs() < 1e-15 && (r.normal[1] - 1.0).abs() < 1e-15,
            "node {}: normal {:?}",
            r.slave_node,
            r.normal
        );
        let height = arc[r.slave_node][1];
        // The 3-point rule integrates ψ_j × (a linear gap) exactly: round-off only.
        assert!(
            (r.gap - height).abs() < 1e-14,
            "node {}: gap {} vs height {height}",
            r.slave_node,
            r.gap
        );
        assert!((weight_sum(r) - 1.0).abs() < 1e-14);
    }
}

/// Frictional rows ([`Frame::Interface`]) on a flat slave (outward −y, at y = 0.1) over a flat
/// master tilted by θ = 0.2 (outward normal (−sin θ, cos θ)), non-matching: with equal
/// compliances the row normal is the bisector of the two sides' normals, (−sin θ/2, cos θ/2);
/// with C_s = 3 C_m it is unit(3 n_m + (0, 1)); with a master 10⁶ times stiffer, the master's
/// normal to 10⁻⁶ θ.  The slave points are paired along the slave's normal (vertically) with the
/// master point below, x − y = (0, g(x)), g = 0.1 − x tan θ linear along the slave, so on the
/// fully covered slave the dual basis gives node j's own values (biorthogonality): the gap
/// n̄·(0, g_j) and the tangential reference t̄·(0, g_j) = k × gap, k the pairing slope
/// (t̄·n_j)/(n̄·n_j) = −n̄_x/n̄_y (tan θ/2 for equal compliances).  Round-off only.
#[test]
fn frictional_rows_act_along_the_compliance_weighted_mean_normal() {
    let theta: f64 = 0.2;
    let (c, s) = (theta.cos(), theta.sin());
    let xs = [-0.3, -0.1, 0.05, 0.2, 0.3];
    let slave = slave_flat(&xs, 0.1);
    let along: Vec<Point> = [0.6, 0.27, 0.0, -0.13, -0.6]
        .iter()
        .map(|&t| [t * c, t * s])
        .collect();
    let master = polyline(&along);
    let nm = [-s, c];
    for (cs, cm) in [(1.0, 1.0), (3.0, 1.0), (1.0, 1e-6)] {
        let b = rows_in(
            &slave,
            &master,
            Frame::Interface {
                slave: cs,
                master: cm,
            },
        );
        assert_eq!(b.rows.len(), xs.len());
        let raw = [cs * nm[0], cs * nm[1] + cm];
        let len = raw[0].hypot(raw[1]);
        let want = [raw[0] / len, raw[1] / len];
        if cs == cm {
            let half = 0.5 * theta;
            assert!((want[0] + half.sin()).abs() < 1e-15 && (want[1] - half.cos()).abs() < 1e-15);
        }
        for r in &b.rows {
            let n = r.normal;
            assert!(
                (n[0] - want[0]).abs() < 1e-14 && (n[1] - want[1]).abs() < 1e-14,
                "C {cs}/{cm}, node {}: normal {n:?} vs {want:?}",
                r.slave_node
            );
            let x = xs[r.slave_node];
            let g = 0.1 - x * theta.tan();
            assert!(
                (r.gap - n[1] * g).abs() < 1e-14,
                "C {cs}/{cm}, node {}: gap {} vs {}",
                r.slave_node,
                r.gap,
                n[1] * g
            );
            let slope = -n[0] / n[1];
            assert!((r.pairing_slope - slope).abs() < 1e-14);
            // The tangential reference k gₙ is t̄·(x − y), t̄ = (n̄_y, −n̄_x).
            assert!((r.pairing_slope * r.gap - (-n[0]) * g).abs() < 1e-14);
            assert!((weight_sum(r) - 1.0).abs() < 1e-14);
        }
    }
    // A master 10⁶ times stiffer: the interface is the master's surface.
    let stiff = rows_in(
        &slave,
        &master,
        Frame::Interface {
            slave: 1.0,
            master: 1e-6,
        },
    );
    for r in &stiff.rows {
        assert!((r.normal[0] - nm[0]).abs() < 1e-6 * theta);
    }
}
