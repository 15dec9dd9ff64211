//! Free directions of a solved answer: rigid motions of floating bodies along which the answer
//! is not unique ([`ModelWarning::FreeDirection`]).
//!
//! Two minimisers of a convex QP differ by a d with A d = 0 (A is positive definite off its
//! kernel, so d is a rigid motion of the floating bodies, a combination of the model's
//! `kernel`), and, for a small d, with the objective flat along it and every row that binds in
//! the answer unchanged by it.  So the answer x is one of many exactly when some rigid motion v
//! of the floating bodies has
//!
//! * (B v)ᵢ = 0 on every row that holds: a normal row whose multiplier is
//!   [active](super::is_active) or whose gap is closed (slack ≤ 10⁻⁶ of |gᵢ| + ‖Bᵢ‖₁ max|u|: the
//!   same 10⁻⁶ as the active threshold), and a tangential row that sticks (its bound is active
//!   and its slip within the [stick/slip threshold](super::friction::SLIP_FRACTION)) — a sticking
//!   row holds the motion, a slipping one does not;
//! * a flat objective along v: (−f + Bᵀλ)ᵀ v = 0.  For frictionless pairs, with B v = 0 on the
//!   active rows, this is fᵀ v = 0; with friction it is the load minus the slipping rows' friction
//!   (a block slid at exactly its friction capacity is free too).  Stationarity makes it hold for
//!   any kernel v of a solved answer, so it only keeps an answer that is not stationary along v
//!   (the QP would be unbounded along it, not non-unique) from being called non-unique.
//!
//! Rows that hold in one direction only (a closed gap whose row v would open) are taken as
//! holding: only two-sided directions are reported.  The check is made after the solve because
//! which rows hold is the answer's (a disc's contact zone, stick or slip), not the data's.
//!
//! **Tolerances.**  Each row is divided by ‖Bᵢ‖₁ and each direction scaled to a largest nodal
//! motion of order 1, so (B v)ᵢ / ‖Bᵢ‖₁ is the row's change per unit of motion relative to its
//! largest possible change.  A direction is free when every such figure is below
//! [`ROW_TOLERANCE`] = 10⁻⁸: B's entries are normals and weights computed from coordinates,
//! exact for a straight interface up to round-off (10⁻¹⁶ times L/h, L the coordinates' size, h
//! the element: below 10⁻¹⁰ for L/h ≤ 10⁶), while any geometric coupling one would model (a
//! curved or tilted interface, a row of a neighbouring facet) is a slope far above 10⁻⁸.  The
//! flatness figure is divided by ‖f‖₁ + ‖Bᵀλ‖₁ over the bodies' DOFs and must be below
//! [`SLOPE_TOLERANCE`] = 10⁻³: a solved answer's stationarity residual is ≤ the tolerance (10⁻⁶
//! by default) of its force scale, while a load with a real component along v makes the figure
//! of order 1.

use nalgebra::DMatrix;

use crate::geometry::Point;
use crate::model::{FreeMotion, Model, ModelWarning};
use crate::qp::{mat_t_vec, mat_vec, QpStatus};
use crate::scene::Scene;
use crate::solve::Solution;

use super::active::{active_scale, is_active};
use super::friction::SLIP_FRACTION;

/// A row's change along a direction, relative to its largest possible change, below which the
/// row does not resist the direction (the module's tolerances).
pub const ROW_TOLERANCE: f64 = 1e-8;

/// The objective's slope along a direction, relative to the forces on its bodies, below which
/// it is flat (the module's tolerances).
pub const SLOPE_TOLERANCE: f64 = 1e-3;

/// Relative size below which a coefficient of a direction counts as zero when it is described
/// (a translation with no rotation, a translation along x with no y part).
const DESCRIBE_ZERO: f64 = 1e-9;

/// A floating body's rigid motions: u(X) = (a, b) + (w / R) (−(Y − c_y), X − c_x) for the
/// coefficients (a, b, w), c its nodes' mean, R their largest distance from c.
struct RigidFrame {
    body: usize,
    centre: Point,
    radius: f64,
    /// Orthonormal coefficient triples (a, b, w) spanning the body's free rigid motions.
    basis: Vec<[f64; 3]>,
}

/// One [`ModelWarning::FreeDirection`] per independent free direction of a solved answer (see
/// the module), empty when the answer is unique along every rigid motion or is not `solved`.
pub fn free_directions(scene: &Scene, model: &Model, solution: &Solution) -> Vec<ModelWarning> {
    if solution.status != QpStatus::Solved || model.floating.is_empty() || model.rows() == 0 {
        return Vec::new();
    }
    let u = &solution.displacement;
    if u.len() != model.dofs.len() || solution.multipliers.len() != model.rows() {
        return Vec::new();
    }
    let frames = rigid_frames(model);
    let columns: Vec<(usize, usize, Vec<f64>)> = frames
        .iter()
        .enumerate()
        .flat_map(|(f, frame)| {
            frame
                .basis
                .iter()
                .enumerate()
                .map(move |(k, q)| (f, k, rigid_field(model, frame, *q)))
        })
        .collect();
    if columns.is_empty() {
        return Vec::new();
    }
    let held = holding_rows(model, solution);
    let row_norms = row_norms(model);
    // B v for each direction, on the holding rows only.
    let bv: Vec<Vec<f64>> = columns
        .iter()
        .map(|(_, _, v)| mat_vec(&model.constraints, v))
        .collect();
    // −f + Bᵀλ: the objective's gradient along rigid motions (A v = 0).
    let mut gradient = mat_t_vec(&model.constraints, &solution.multipliers);
    let mut force = vec![0.0; gradient.len()];
    for (d, g) in gradient.iter_mut().enumerate() {
        force[d] = model.load[d].abs() + g.abs();
        *g -= model.load[d];
    }
    let components = components(&frames, &columns, &bv, &held);
    let mut warnings = Vec::new();
    for component in components {
        let cols: Vec<usize> = (0..columns.len())
            .filter(|&j| component.contains(&columns[j].0))
            .collect();
        let rows: Vec<usize> = held
            .iter()
            .copied()
            .filter(|&i| row_norms[i] > 0.0 && cols.iter().any(|&j| bv[j][i] != 0.0))
            .collect();
        let scale: f64 = component
            .iter()
            .flat_map(|&f| model.dofs.body_range(frames[f].body))
            .map(|d| force[d])
            .sum();
        let height = (rows.len() + 1).max(cols.len());
        let mut m = DMatrix::<f64>::zeros(height, cols.len());
        for (r, &i) in rows.iter().enumerate() {
            for (c, &j) in cols.iter().enumerate() {
                m[(r, c)] = bv[j][i] / row_norms[i];
            }
        }
        if scale > 0.0 {
            // Scaled so that SLOPE_TOLERANCE of the slope weighs as ROW_TOLERANCE of a row.
            for (c, &j) in cols.iter().enumerate() {
                let slope = crate::qp::dot(&gradient, &columns[j].2);
                m[(rows.len(), c)] = slope / scale * (ROW_TOLERANCE / SLOPE_TOLERANCE);
            }
        }
        let null = null_space(&m);
        if null.is_empty() {
            continue;
        }
        // Each null vector as per-body coefficient triples, then a canonical basis.
        let triples: Vec<Vec<f64>> = null
            .iter()
            .map(|c| {
                let mut t = vec![0.0; 3 * component.len()];
                for (k, &j) in cols.iter().enumerate() {
                    let (f, q) = (columns[j].0, columns[j].1);
                    let slot = component.iter().position(|&x| x == f).unwrap_or(0);
                    for (e, v) in frames[f].basis[q].iter().enumerate() {
                        t[3 * slot + e] += c[k] * v;
                    }
                }
                t
            })
            .collect();
        for row in reduced_echelon(triples) {
            warnings.push(describe(scene, &frames, &component, &row));
        }
    }
    warnings
}

/// Each floating body's frame and an orthonormal basis of its free rigid motions, from the
/// model's kernel vectors (fitted exactly: they are rigid motions).
fn rigid_frames(model: &Model) -> Vec<RigidFrame> {
    let mut frames = Vec::new();
    let mut next = 0;
    for &(b, count) in &model.floating {
        let mesh = &model.meshes[b];
        let n = mesh.nodes.len().max(1) as f64;
        let centre = mesh
            .nodes
            .iter()
            .fold([0.0, 0.0], |c, p| [c[0] + p[0] / n, c[1] + p[1] / n]);
        let radius = mesh
            .nodes
            .iter()
            .map(|p| (p[0] - centre[0]).hypot(p[1] - centre[1]))
            .fold(0.0, f64::max)
            .max(f64::MIN_POSITIVE);
        let mut triples = Vec::new();
        for v in model.kernel.iter().skip(next).take(count) {
            let full = expand(model, v);
            // Least squares on the three orthogonal fields (1, 0), (0, 1), (−y, x)/R about the
            // nodes' mean: each coefficient is a ratio of sums.
            let (mut s, mut rr) = ([0.0; 3], 0.0);
            for (i, p) in mesh.nodes.iter().enumerate() {
                let (x, y) = ((p[0] - centre[0]) / radius, (p[1] - centre[1]) / radius);
                let (ux, uy) = (full[model.dofs.dof(b, i, 0)], full[model.dofs.dof(b, i, 1)]);
                s[0] += ux;
                s[1] += uy;
                s[2] += -y * ux + x * uy;
                rr += x * x + y * y;
            }
            triples.push([s[0] / n, s[1] / n, if rr > 0.0 { s[2] / rr } else { 0.0 }]);
        }
        next += count;
        frames.push(RigidFrame {
            body: b,
            centre,
            radius,
            basis: orthonormal(triples),
        });
    }
    frames
}

/// Gram–Schmidt on coefficient triples, dropping dependent ones.
fn orthonormal(triples: Vec<[f64; 3]>) -> Vec<[f64; 3]> {
    let mut out: Vec<[f64; 3]> = Vec::new();
    for mut t in triples {
        let size = t.iter().map(|x| x * x).sum::<f64>().sqrt();
        for q in &out {
            let p: f64 = (0..3).map(|e| t[e] * q[e]).sum();
            for e in 0..3 {
                t[e] -= p * q[e];
            }
        }
        let norm = t.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm > 1e-8 * size && norm > 0.0 {
            out.push(t.map(|x| x / norm));
        }
    }
    out
}

/// A kernel vector (free DOFs) on all DOFs, zero at the fixed ones.
fn expand(model: &Model, v: &[f64]) -> Vec<f64> {
    let mut full = vec![0.0; model.dofs.len()];
    for (&d, x) in model.free.iter().zip(v) {
        full[d] = *x;
    }
    full
}

/// The rigid motion of coefficients `q` on its body's free DOFs (zero elsewhere).
fn rigid_field(model: &Model, frame: &RigidFrame, q: [f64; 3]) -> Vec<f64> {
    let mut v = vec![0.0; model.dofs.len()];
    for (i, p) in model.meshes[frame.body].nodes.iter().enumerate() {
        let (x, y) = (
            (p[0] - frame.centre[0]) / frame.radius,
            (p[1] - frame.centre[1]) / frame.radius,
        );
        for (c, value) in [(0, q[0] - q[2] * y), (1, q[1] + q[2] * x)] {
            let d = model.dofs.dof(frame.body, i, c);
            if model.fixed[d].is_none() {
                v[d] = value;
            }
        }
    }
    v
}

/// The rows that hold in the answer (see the module), in increasing order.
fn holding_rows(model: &Model, solution: &Solution) -> Vec<usize> {
    let u = &solution.displacement;
    let lambda = &solution.multipliers;
    let bu = mat_vec(&model.constraints, u);
    let norms = row_norms(model);
    let scale = active_scale(model, solution);
    let u_max = u.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let normal = model.normal_rows();
    let mut held: Vec<usize> = (0..normal)
        .filter(|&i| {
            let slack = model.gap[i] - bu[i];
            is_active(lambda[i], scale) || slack <= 1e-6 * (model.gap[i].abs() + norms[i] * u_max)
        })
        .collect();
    let before = solution
        .previous
        .as_ref()
        .map(|p| mat_vec(&model.constraints, p));
    let slip_fraction = SLIP_FRACTION.max(100.0 * solution.tolerance);
    for (k, t) in model.tangential.iter().enumerate() {
        let row = normal + k;
        let bound = t.bound(lambda[t.normal_row]);
        let step_slip = before.as_ref().map_or(model.gap[row] - bu[row], |b| {
            t.stick_value(row, &model.gap, b) - bu[row]
        });
        let motion = pair_motion(model, t.pair, u);
        if is_active(bound, scale) && step_slip.abs() <= slip_fraction * motion {
            held.push(row);
        }
    }
    held
}

/// max |u| over the nodes of pair `pair`'s two bodies.
fn pair_motion(model: &Model, pair: usize, u: &[f64]) -> f64 {
    let Some(p) = model.contacts.iter().find(|p| p.pair == pair) else {
        return 0.0;
    };
    [p.slave, p.master]
        .iter()
        .flat_map(|&b| model.body_displacements(b, u))
        .map(|d| d[0].hypot(d[1]))
        .fold(0.0, f64::max)
}

/// ‖Bᵢ‖₁ over the free DOFs, per row.
fn row_norms(model: &Model) -> Vec<f64> {
    let mut norms = vec![0.0; model.rows()];
    for (j, col) in model.constraints.outer_iterator().enumerate() {
        if model.fixed.get(j).is_some_and(Option::is_some) {
            continue;
        }
        for (i, v) in col.iter() {
            norms[i] += v.abs();
        }
    }
    norms
}

/// The floating bodies (indices into `frames`) grouped by the holding rows that couple them.
fn components(
    frames: &[RigidFrame],
    columns: &[(usize, usize, Vec<f64>)],
    bv: &[Vec<f64>],
    held: &[usize],
) -> Vec<Vec<usize>> {
    let mut parent: Vec<usize> = (0..frames.len()).collect();
    fn root(parent: &mut [usize], mut x: usize) -> usize {
        while parent[x] != x {
            parent[x] = parent[parent[x]];
            x = parent[x];
        }
        x
    }
    for &i in held {
        let mut first: Option<usize> = None;
        for (j, (f, _, _)) in columns.iter().enumerate() {
            if bv[j][i] == 0.0 {
                continue;
            }
            match first {
                None => first = Some(*f),
                Some(g) => {
                    let (a, b) = (root(&mut parent, g), root(&mut parent, *f));
                    parent[a] = b;
                }
            }
        }
    }
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut of_root: Vec<Option<usize>> = vec![None; frames.len()];
    for f in 0..frames.len() {
        let r = root(&mut parent, f);
        match of_root[r] {
            Some(g) => groups[g].push(f),
            None => {
                of_root[r] = Some(groups.len());
                groups.push(vec![f]);
            }
        }
    }
    groups
}

/// An orthonormal basis of {c : ‖M c‖ ≤ ROW_TOLERANCE ‖c‖} (M has at least as many rows as
/// columns).
fn null_space(m: &DMatrix<f64>) -> Vec<Vec<f64>> {
    if m.ncols() == 0 {
        return Vec::new();
    }
    let svd = m.clone().svd(false, true);
    let Some(v_t) = svd.v_t else {
        return Vec::new();
    };
    svd.singular_values
        .iter()
        .enumerate()
        .filter(|(_, s)| **s <= ROW_TOLERANCE)
        .map(|(k, _)| v_t.row(k).iter().copied().collect())
        .collect()
}

/// The reduced row echelon form of the rows (pivots in order: first body's x, y, rotation,
/// then the next body's), entries below [`DESCRIBE_ZERO`] of the largest set to zero: a
/// canonical basis of their span (a translation along x before a rotation).
fn reduced_echelon(mut rows: Vec<Vec<f64>>) -> Vec<Vec<f64>> {
    let width = rows.first().map_or(0, Vec::len);
    let mut pivot_row = 0;
    for col in 0..width {
        if pivot_row == rows.len() {
            break;
        }
        let (best, size) = (pivot_row..rows.len())
            .map(|r| (r, rows[r][col].abs()))
            .fold((pivot_row, -1.0), |a, b| if b.1 > a.1 { b } else { a });
        let largest = rows
            .iter()
            .skip(pivot_row)
            .flat_map(|r| r.iter())
            .fold(0.0_f64, |m, x| m.max(x.abs()));
        if size <= DESCRIBE_ZERO * largest {
            continue;
        }
        rows.swap(pivot_row, best);
        let p = rows[pivot_row][col];
        for x in rows[pivot_row].iter_mut() {
            *x /= p;
        }
        let pivot = rows[pivot_row].clone();
        for (r, row) in rows.iter_mut().enumerate() {
            if r != pivot_row {
                let factor = row[col];
                for (x, y) in row.iter_mut().zip(&pivot) {
                    *x -= factor * y;
                }
            }
        }
        pivot_row += 1;
    }
    rows.truncate(pivot_row);
    for row in &mut rows {
        let largest = row.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        for x in row.iter_mut() {
            if x.abs() <= DESCRIBE_ZERO * largest {
                *x = 0.0;
            }
        }
    }
    rows
}

/// The warning for one free direction (coefficient triples per body of `component`).
fn describe(
    scene: &Scene,
    frames: &[RigidFrame],
    component: &[usize],
    row: &[f64],
) -> ModelWarning {
    let mut motions = Vec::new();
    for (slot, &f) in component.iter().enumerate() {
        let frame = &frames[f];
        let [a, b, w] = [row[3 * slot], row[3 * slot + 1], row[3 * slot + 2]];
        if a == 0.0 && b == 0.0 && w == 0.0 {
            continue;
        }
        let body = scene
            .bodies
            .get(frame.body)
            .map_or_else(|| format!("#{}", frame.body + 1), |x| x.name.clone());
        let omega = w / frame.radius;
        let motion = if w == 0.0 {
            let size = a.hypot(b);
            FreeMotion {
                body,
                along: Some([a / size, b / size]),
                about: None,
            }
        } else {
            // u(X) = (a, b) + ω (−(Y − c_y), X − c_x) vanishes at p = c + (−b, a) / ω.
            FreeMotion {
                body,
                along: None,
                about: Some([frame.centre[0] - b / omega, frame.centre[1] + a / omega]),
            }
        };
        motions.push(motion);
    }
    ModelWarning::FreeDirection { motions }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used)] // tests may unwrap

    use super::*;

    #[test]
    fn the_echelon_form_puts_translations_before_rotations() {
        // Span of {rotation about the centre + a bit of x, x translation}: x, then pure rotation.
        let rows = reduced_echelon(vec![vec![0.3, 0.0, 0.8], vec![0.6, 0.0, 0.0]]);
        assert_eq!(rows, vec![vec![1.0, 0.0, 0.0], vec![0.0, 0.0, 1.0]]);
    }

    #[test]
    fn a_matrix_with_a_zero_column_has_that_null_direction() {
        let m = DMatrix::from_row_slice(3, 2, &[0.0, 1.0, 0.0, 0.5, 0.0, 0.0]);
        let null = null_space(&m);
        assert_eq!(null.len(), 1);
        assert!((null[0][0].abs() - 1.0).abs() < 1e-15 && null[0][1].abs() < 1e-15);
        // A column 1e-7 off zero is not null (above ROW_TOLERANCE).
        let m = DMatrix::from_row_slice(2, 2, &[1e-7, 0.0, 0.0, 1.0]);
        assert!(null_space(&m).is_empty());
    }
}
