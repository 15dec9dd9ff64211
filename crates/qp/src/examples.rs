//! Small QPs with hand-known optima (and an infeasible one), the same for every backend's tests.
//!
//! ```
//! use signorini_qp::examples::scalar;
//! let k = scalar(1.0); // min x² − 4x s.t. x ≤ 1
//! assert_eq!((k.x[0], k.multipliers[0]), (1.0, 2.0));
//! ```

use crate::{
    checked_status, kkt_residuals, CscMatrix, QpBackend, QpError, QpProblem, QpSolution, QpStatus,
    SolveOptions,
};
use sprs::TriMat;

/// A QP with its known optimum.
pub struct Known {
    /// The problem.
    pub problem: QpProblem,
    /// Its minimiser.
    pub x: Vec<f64>,
    /// Its multipliers.
    pub multipliers: Vec<f64>,
}

/// Builds a CSC matrix from dense rows.
pub fn csc(rows: usize, cols: usize, dense: &[&[f64]]) -> sprs::CsMat<f64> {
    let mut t = TriMat::new((rows, cols));
    for (i, row) in dense.iter().enumerate() {
        for (j, &v) in row.iter().enumerate() {
            if v != 0.0 {
                t.add_triplet(i, j, v);
            }
        }
    }
    t.to_csc()
}

/// Builds a CSC matrix from (row, col, value) triplets; duplicates are summed.
pub fn csc_from_triplets(
    rows: usize,
    cols: usize,
    entries: &[(usize, usize, f64)],
) -> sprs::CsMat<f64> {
    let mut t = TriMat::new((rows, cols));
    for &(i, j, v) in entries {
        t.add_triplet(i, j, v);
    }
    t.to_csc()
}

/// The QP `min ½xᵀAx − fᵀx, Bx ≤ g` with A (n × n) and B (m × n) given as triplets; an error
/// when the data are not a valid QP (see [`QpProblem::try_new`]).
pub fn qp_from_triplets(
    n: usize,
    a: &[(usize, usize, f64)],
    f: Vec<f64>,
    m: usize,
    b: &[(usize, usize, f64)],
    g: Vec<f64>,
) -> Result<QpProblem, crate::QpError> {
    QpProblem::try_new(csc_from_triplets(n, n, a), f, csc_from_triplets(m, n, b), g)
}

/// max |value − reference| / max |reference| (the denominator kept above 1e-300).
pub fn rel_diff(value: &[f64], reference: &[f64]) -> f64 {
    let scale = reference
        .iter()
        .fold(0.0_f64, |m, v| m.max(v.abs()))
        .max(1e-300);
    max_diff(value, reference) / scale
}

fn qp(a: sprs::CsMat<f64>, f: Vec<f64>, b: sprs::CsMat<f64>, g: Vec<f64>) -> QpProblem {
    QpProblem::try_new(a, f, b, g)
        .unwrap_or_else(|e| unreachable!("hand-built example is valid: {e}"))
}

/// min x² − 4x  s.t. x ≤ bound: x = min(2, bound), λ = 2·max(0, 2 − bound).
pub fn scalar(bound: f64) -> Known {
    let problem = qp(
        csc(1, 1, &[&[2.0]]),
        vec![4.0],
        csc(1, 1, &[&[1.0]]),
        vec![bound],
    );
    let x = bound.min(2.0);
    Known {
        problem,
        x: vec![x],
        multipliers: vec![4.0 - 2.0 * x],
    }
}

/// Tresca's 1-D spring on a box row ([`crate::ConstraintBlock::Box`]): min ½ x² − f x + |x|
/// (A = 1, B = \[1\], g = 0, bound 1), solved by hand: stick (x = 0, λ = f) for |f| ≤ 1, else
/// slip x = f − sign f, λ = sign f.
pub fn tresca_spring(f: f64) -> Known {
    let problem = qp(
        csc(1, 1, &[&[1.0]]),
        vec![f],
        csc(1, 1, &[&[1.0]]),
        vec![0.0],
    )
    .with_blocks(vec![crate::ConstraintBlock::Box { bounds: vec![1.0] }])
    .unwrap_or_else(|e| unreachable!("hand-built example is valid: {e}"));
    let (x, multiplier) = if f.abs() <= 1.0 {
        (0.0, f)
    } else {
        (f - f.signum(), f.signum())
    };
    Known {
        problem,
        x: vec![x],
        multipliers: vec![multiplier],
    }
}

/// A = [[2, −1], [−1, 2]], f = (1, 1) (free optimum (1, 1)); x₀ + x₁ ≤ 1 active,
/// x₀ − x₁ ≤ 10 inactive: x = (½, ½), λ = (½, 0).
pub fn two_rows() -> Known {
    let problem = qp(
        csc(2, 2, &[&[2.0, -1.0], &[-1.0, 2.0]]),
        vec![1.0, 1.0],
        csc(2, 2, &[&[1.0, 1.0], &[1.0, -1.0]]),
        vec![1.0, 10.0],
    );
    Known {
        problem,
        x: vec![0.5, 0.5],
        multipliers: vec![0.5, 0.0],
    }
}

/// The same as [`two_rows`] with A and f multiplied by `factor` (λ scales with it).
pub fn two_rows_scaled(factor: f64) -> Known {
    let mut k = two_rows();
    k.problem.stiffness = k.problem.stiffness.map(|v| v * factor);
    k.problem.load.iter_mut().for_each(|v| *v *= factor);
    k.multipliers.iter_mut().for_each(|v| *v *= factor);
    k
}

/// No constraints (m = 0): x = A⁻¹ f = (1, 1).
pub fn unconstrained() -> Known {
    let problem = qp(
        csc(2, 2, &[&[2.0, -1.0], &[-1.0, 2.0]]),
        vec![1.0, 1.0],
        sprs::CsMat::zero((0, 2)).to_csc(),
        vec![],
    );
    Known {
        problem,
        x: vec![1.0, 1.0],
        multipliers: vec![],
    }
}

/// x ≤ −1 and −x ≤ −1 (x ≥ 1): no feasible point.
pub fn infeasible() -> QpProblem {
    qp(
        csc(1, 1, &[&[1.0]]),
        vec![0.0],
        csc(2, 1, &[&[1.0], &[-1.0]]),
        vec![-1.0, -1.0],
    )
}

/// Tridiagonal stiffness of `nodes` unit springs in series, node 0 tied to a fixed support,
/// the last node free.
pub fn spring_chain_stiffness(nodes: usize) -> sprs::CsMat<f64> {
    let mut t = TriMat::new((nodes, nodes));
    for i in 0..nodes {
        t.add_triplet(i, i, if i + 1 == nodes { 1.0 } else { 2.0 });
        if i + 1 < nodes {
            t.add_triplet(i, i + 1, -1.0);
            t.add_triplet(i + 1, i, -1.0);
        }
    }
    t.to_csc()
}

/// A chain of 10 unit springs, its end node pushed by a unit force against a wall 5 units away.
/// Free, the end would move 10; in contact u_i = (i + 1)/2 and the wall force is λ = ½.
pub fn spring_chain() -> Known {
    let nodes = 10;
    let mut load = vec![0.0; nodes];
    load[nodes - 1] = 1.0;
    let mut b = TriMat::new((1, nodes));
    b.add_triplet(0, nodes - 1, 1.0);
    let problem = qp(spring_chain_stiffness(nodes), load, b.to_csc(), vec![5.0]);
    Known {
        problem,
        x: (0..nodes).map(|i| (i + 1) as f64 * 0.5).collect(),
        multipliers: vec![0.5],
    }
}

/// A 1-D Laplacian chain of `nodes` springs, uniform load, with `contacts` evenly spaced nodes
/// held below a gap that makes most of them active.
pub fn laplacian_with_bounds(nodes: usize, contacts: usize) -> QpProblem {
    let stiffness = spring_chain_stiffness(nodes);
    let h = 1.0 / nodes as f64;
    let load = vec![h * h; nodes];
    let mut b = TriMat::new((contacts, nodes));
    let mut gap = Vec::with_capacity(contacts);
    for c in 0..contacts {
        let node = (c + 1) * nodes / (contacts + 1);
        b.add_triplet(c, node, 1.0);
        gap.push(0.05 * (1.0 + (c % 3) as f64 * 0.1));
    }
    qp(stiffness, load, b.to_csc(), gap)
}

/// Largest entrywise difference (infinite when the lengths differ).
pub fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    if a.len() != b.len() {
        return f64::INFINITY;
    }
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

impl Known {
    /// `None` when `x` and `multipliers` match the optimum to `tol` relative to its largest
    /// entry (λ relative to the larger of its own and, up to 1, x's scale); otherwise what differs.
    /// An optimum x* = 0 (a sticking box row) has no largest entry: x is then measured against
    /// the displacement unit of the problem's data ([`crate::QpScaling::of`], ‖f‖∞ / k̄), the
    /// length every backend's tolerance refers to — an exact zero is more than an
    /// interior-point method or a projected gradient stopped at the tolerance can give.
    pub fn mismatch(&self, x: &[f64], multipliers: &[f64], tol: f64) -> Option<String> {
        let largest = self.x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let xs = if largest > 0.0 {
            largest
        } else {
            crate::QpScaling::of(&self.problem).displacement
        };
        let ls = self
            .multipliers
            .iter()
            .fold(1e-300_f64, |m, v| m.max(v.abs()));
        if max_diff(x, &self.x) > tol * xs {
            return Some(format!("x = {x:?}, expected {:?}", self.x));
        }
        if max_diff(multipliers, &self.multipliers) > tol * ls.max(xs.min(1.0)) {
            return Some(format!(
                "λ = {multipliers:?}, expected {:?}",
                self.multipliers
            ));
        }
        None
    }
}

/// An SPD matrix with a 2D-elasticity-like pattern: a side × side grid of nodes with two
/// DOFs each, coupled to the 8 neighbouring nodes (both DOFs), diagonally dominant.
pub fn two_dof_grid(side: usize) -> CscMatrix {
    let nodes = side * side;
    let mut t = TriMat::new((2 * nodes, 2 * nodes));
    let id = |i: usize, j: usize| j * side + i;
    for j in 0..side {
        for i in 0..side {
            let a = id(i, j);
            for (di, dj) in [(1i64, 0i64), (0, 1), (1, 1), (1, -1)] {
                let (ii, jj) = (i as i64 + di, j as i64 + dj);
                if ii < 0 || jj < 0 || ii >= side as i64 || jj >= side as i64 {
                    continue;
                }
                let b = id(ii as usize, jj as usize);
                for (p, q) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                    let v = -0.5 - 0.1 * ((a + b + p + q) % 3) as f64;
                    t.add_triplet(2 * a + p, 2 * b + q, v);
                    t.add_triplet(2 * b + q, 2 * a + p, v);
                }
            }
            t.add_triplet(2 * a, 2 * a + 1, 0.3);
            t.add_triplet(2 * a + 1, 2 * a, 0.3);
            t.add_triplet(2 * a, 2 * a, 20.0);
            t.add_triplet(2 * a + 1, 2 * a + 1, 20.0);
        }
    }
    t.to_csc()
}

/// nnz of the lower triangle of L, diagonal included, counted by eliminating the graph of
/// P A Pᵀ vertex by vertex (each eliminated vertex joins its later neighbours into a
/// clique): independent of faer's elimination tree and column counts.
pub fn eliminated_nnz(a: &CscMatrix, forward_inverse: &[usize]) -> usize {
    use std::collections::BTreeSet;
    let n = a.rows();
    let mut adj: Vec<BTreeSet<usize>> = vec![BTreeSet::new(); n];
    for (_, (i, j)) in a.iter() {
        let (p, q) = (forward_inverse[i], forward_inverse[j]);
        if p != q {
            adj[p].insert(q);
            adj[q].insert(p);
        }
    }
    let mut nnz = 0;
    for k in 0..n {
        let later: Vec<usize> = adj[k].range(k + 1..).copied().collect();
        nnz += 1 + later.len();
        for &u in &later {
            for &v in &later {
                if u != v {
                    adj[u].insert(v);
                }
            }
        }
    }
    nnz
}

/// The units a test solves in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Units {
    /// [`QpBackend::solve`]: nondimensionalised first (what the driver hands every backend).
    Own,
    /// [`QpBackend::solve_in_given_units`]: the problem as built.
    Given,
}

/// Solves `problem` with `backend` at `tol` in `units` and returns the solution with the status
/// the residual contract gives it ([`checked_status`] of its [`kkt_residuals`]): what the
/// backends' tests compare with known answers.
pub fn solve_checked(
    backend: &mut dyn QpBackend,
    problem: &QpProblem,
    tol: f64,
    units: Units,
) -> Result<(QpSolution, QpStatus), QpError> {
    let options = SolveOptions {
        tol,
        ..SolveOptions::default()
    };
    let sol = match units {
        Units::Own => backend.solve(problem, &options),
        Units::Given => backend.solve_in_given_units(problem, &options),
    }?;
    let r = kkt_residuals(problem, &sol.x, &sol.multipliers);
    let status = checked_status(sol.status, &r, tol);
    Ok((sol, status))
}
