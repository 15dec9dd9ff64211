//! The fixed scales the KKT residuals are measured against: one force and one length scale per
//! part of the problem that can act on a row, computed from A, B, f and g only.
//!
//! A residual is only as honest as its yardstick.  A scale summed over the whole problem lets a
//! load that cannot reach a contact row loosen that row's check (a body pulled far away elsewhere
//! in the scene hid a penetration of 1.6 % of a pair's own motion, issue 18), and a stiffness
//! averaged over a row's DOFs lets the Dirichlet lifting of a very stiff body do the same.  So
//! every scale here is *local*: it is built from the connected component of the row (DOFs joined
//! by A or by a common constraint row — nothing outside it can push on the row), and the length
//! is compliance-weighted (a load counts by the displacement it would give where it acts).

use super::bodies::{find, join, Components};
use super::ops::abs_diagonal;
use super::problem::QpProblem;

/// Smallest scale used as a denominator, so that an all-zero problem gives zero residuals.
pub(super) const TINY: f64 = 1e-300;

/// The fixed scales residuals are measured against, computed from A, B, f and g only.
///
/// The DOFs fall into connected components of the graph of A ∪ BᵀB (two DOFs are joined when
/// A couples them or a constraint row touches both): what lies in another component cannot act
/// on a row, at any load.  For a component c with DOFs J(c) and rows I(c):
///
/// * W_c = Σⱼ∈J(c) |fⱼ| / Aⱼⱼ, the compliance-weighted load: each nodal load (a traction, a body
///   force, the lifting of a prescribed displacement) counted by the displacement it would give
///   its own DOF (independent of the mesh size: fⱼ ~ t·h, Aⱼⱼ ~ E; a lifted prescribed value u_d
///   gives |fⱼ|/Aⱼⱼ ≲ u_d, however stiff or incompressible the body);
/// * kᵢ, the harmonic mean of Aⱼⱼ over the DOFs row i touches, and
///   Pᵢ = ‖f_c‖₁ / kᵢ, the displacement the component's whole load would give the row's own
///   springs (a soft loaded body resting on a stiff pair moves the pair by its load over the
///   *pair's* stiffness, not its own);
/// * G_c = max(0, −minᵢ∈I(c) gᵢ), the deepest initial overlap of the component;
/// * the row length Xᵢ = max(G_c, min(W_c, Pᵢ)) — both W_c and Pᵢ bound the motion the loads can
///   cause at the row from one side each, so the smaller is taken; when it is zero (nothing loads
///   the component and nothing overlaps), ‖g‖∞ over I(c), else the whole problem's length X;
/// * the component force F_c = max(‖f_c‖∞, k̄_c G_c), with k̄_c the harmonic mean of A's diagonal
///   over J(c); when zero, k̄_c times the component's length max(G_c, W_c) (or its fallback).
///
/// These are upper bounds fixed by the data.  A component may hold several bodies (the connected
/// components of A alone), and a contact that opens in the answer isolates them: a body pulled
/// far away by a huge load sets W_c and F_c of the pair it has left.  No fixed datum can tell
/// which contacts open, so the residuals tighten the two measures such a load could hide with
/// what the answer shows reaches each body, only ever downwards (a wrong answer cannot buy
/// itself a looser test; see [`super::kkt_residuals`]).  `bodies` and the rows' bodies are
/// recorded here for that.
///
/// The whole problem's scales (`force`, `length`) are kept for reports and heuristics:
/// k̄ = the harmonic mean of A's diagonal, G the deepest overlap, X = max(‖f‖₁ / k̄, G) (‖g‖∞,
/// then 1, when zero) and F = max(‖f‖∞, k̄ G) (k̄ X when zero).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ResidualScales {
    /// Force scale F of the whole problem (reports and heuristics; the residuals use
    /// `dof_forces` and `row_forces`).
    pub force: f64,
    /// Length scale X of the whole problem (reports and heuristics; the residuals use `rows`).
    pub length: f64,
    /// Length scale Xᵢ of each constraint row.
    pub rows: Vec<f64>,
    /// Force scale F_c of each row's component.
    pub row_forces: Vec<f64>,
    /// The force row i's own springs give over its length, min(F_c, kᵢ Xᵢ): the floor below
    /// which the answer's forces no longer tighten the row's force scale (see
    /// [`crate::KktResiduals`]).
    pub row_reach: Vec<f64>,
    /// Force scale F_c of each DOF's component (stationarity is measured DOF by DOF).
    pub dof_forces: Vec<f64>,
    /// The force DOF j's own spring gives over its component's length, min(F_c, Aⱼⱼ L_c): the
    /// floor below which the answer's forces no longer tighten the DOF's force scale.
    pub dof_reach: Vec<f64>,
    /// The bodies: the connected components of A alone (`bodies.label[j]`: the body of DOF j).
    #[serde(skip)]
    pub bodies: Components,
    /// The bodies row i touches are `row_bodies[row_body_starts[i]..row_body_starts[i + 1]]`.
    #[serde(skip)]
    pub row_body_starts: Vec<usize>,
    /// See `row_body_starts`.
    #[serde(skip)]
    pub row_bodies: Vec<usize>,
    /// W_b = Σ |fⱼ| / Aⱼⱼ over the DOFs of each body: the motion its own loads could give it,
    /// the floor of its rows' own-motion tightening ([`crate::BODY_MOTION_FLOOR`]).
    #[serde(skip)]
    pub body_motions: Vec<f64>,
}

impl ResidualScales {
    /// Whether these scales have `problem`'s sizes (n DOFs, m rows): the least a caller's
    /// scales must meet to be used for it.
    pub fn fit(&self, problem: &QpProblem) -> bool {
        self.dof_forces.len() == problem.dofs()
            && self.dof_reach.len() == problem.dofs()
            && self.bodies.label.len() == problem.dofs()
            && self.rows.len() == problem.rows()
            && self.row_forces.len() == problem.rows()
            && self.row_reach.len() == problem.rows()
            && self.row_body_starts.len() == problem.rows() + 1
    }

    /// The bodies row `i` touches (distinct, in increasing order).
    pub fn bodies_of_row(&self, i: usize) -> &[usize] {
        &self.row_bodies[self.row_body_starts[i]..self.row_body_starts[i + 1]]
    }
}

/// What one connected component holds.
#[derive(Debug, Clone, Copy, Default)]
struct Component {
    /// ‖f_c‖₁.
    load_1: f64,
    /// ‖f_c‖∞.
    load_inf: f64,
    /// W_c = Σ |fⱼ| / Aⱼⱼ.
    motion: f64,
    /// Number of DOFs with Aⱼⱼ > 0 and Σ 1/Aⱼⱼ over them.
    stiff_count: usize,
    compliance: f64,
    /// G_c.
    overlap: f64,
    /// ‖g‖∞ over the component's rows.
    gap_inf: f64,
}

impl Component {
    /// k̄_c, when the component has a positive diagonal entry.
    fn stiffness(&self) -> Option<f64> {
        harmonic(self.stiff_count, self.compliance)
    }

    /// The component's length max(G_c, W_c), or its fallback.
    fn length(&self, global: f64) -> f64 {
        self.length_of(self.motion, global)
    }

    /// max(G_c, motion) when positive (f64::MAX when it overflows), else ‖g_c‖∞, else `global`.
    fn length_of(&self, motion: f64, global: f64) -> f64 {
        let x = motion.max(self.overlap);
        if x > 0.0 && x.is_finite() {
            x
        } else if x > 0.0 {
            f64::MAX
        } else if self.gap_inf > 0.0 {
            self.gap_inf
        } else {
            global
        }
    }

    /// F_c (see [`ResidualScales`]).
    fn force(&self, global_stiffness: f64, global_length: f64) -> f64 {
        let k = self.stiffness().unwrap_or(global_stiffness);
        let force = self.load_inf.max(k * self.overlap);
        let force = if force > 0.0 {
            force
        } else {
            k * self.length(global_length)
        };
        force.max(TINY)
    }
}

/// The harmonic mean count / compliance, when it is a positive finite number.
fn harmonic(count: usize, compliance: f64) -> Option<f64> {
    (count > 0 && compliance > 0.0 && compliance.is_finite()).then(|| count as f64 / compliance)
}

/// The bodies (connected components of A alone) and components (of A ∪ BᵀB) of a problem.
struct Partition {
    /// Component of every DOF, numbered 0..components.
    of_dof: Vec<usize>,
    /// Component of every row (None for a row that touches no DOF).
    of_row: Vec<Option<usize>>,
    components: usize,
    /// The bodies.
    bodies: Components,
}

/// The bodies and the components of `problem`: the components of A's graph, then those joined
/// by a common constraint row (a union–find over the bodies, not the DOFs).
fn components(problem: &QpProblem) -> Partition {
    let bodies = Components::of(&problem.stiffness);
    let mut parent: Vec<usize> = (0..bodies.sizes.len()).collect();
    let mut first_body: Vec<Option<usize>> = vec![None; problem.rows()];
    for (j, col) in problem.constraints.outer_iterator().enumerate() {
        let body = bodies.label[j];
        for &i in col.indices() {
            match first_body[i] {
                Some(first) => {
                    let root = find(&mut parent, first);
                    join(&mut parent, root, body);
                }
                None => first_body[i] = Some(body),
            }
        }
    }
    let joined = Components::of_forest(&mut parent);
    let of_dof = bodies.label.iter().map(|&b| joined.label[b]).collect();
    let of_row = first_body
        .iter()
        .map(|b| b.map(|b| joined.label[b]))
        .collect();
    Partition {
        of_dof,
        of_row,
        components: joined.sizes.len(),
        bodies,
    }
}

/// The bodies each row touches, as (starts, bodies) in compressed rows.
fn row_bodies(problem: &QpProblem, body_of_dof: &[usize]) -> (Vec<usize>, Vec<usize>) {
    let mut per_row: Vec<Vec<usize>> = vec![Vec::new(); problem.rows()];
    for (j, col) in problem.constraints.outer_iterator().enumerate() {
        for (i, _) in col.iter() {
            per_row[i].push(body_of_dof[j]);
        }
    }
    let mut starts = Vec::with_capacity(problem.rows() + 1);
    let mut all = Vec::new();
    starts.push(0);
    for mut row in per_row {
        row.sort_unstable();
        row.dedup();
        all.extend(row);
        starts.push(all.len());
    }
    (starts, all)
}

impl ResidualScales {
    /// The scales of `problem` (see the type's docs).
    ///
    /// ```
    /// use signorini_qp::{QpProblem, ResidualScales};
    /// use sprs::TriMat;
    /// let mut a = TriMat::new((2, 2)); a.add_triplet(0, 0, 4.0); a.add_triplet(1, 1, 4.0);
    /// let b = TriMat::new((0, 2));
    /// let qp = QpProblem::try_new(a.to_csc(), vec![1.0, -3.0], b.to_csc(), vec![]).unwrap();
    /// let s = ResidualScales::of(&qp);
    /// assert_eq!((s.force, s.length), (3.0, 1.0));
    /// // Two uncoupled DOFs: each is judged against its own load.
    /// assert_eq!(s.dof_forces, vec![1.0, 3.0]);
    /// ```
    pub fn of(problem: &QpProblem) -> Self {
        let diag = abs_diagonal(&problem.stiffness);
        let Partition {
            of_dof,
            of_row,
            components: count,
            bodies,
        } = components(problem);
        let (row_body_starts, row_bodies) = row_bodies(problem, &bodies.label);
        let mut parts = vec![Component::default(); count];
        let mut whole = Component::default();
        for (j, (&d, &f)) in diag.iter().zip(&problem.load).enumerate() {
            for c in [&mut parts[of_dof[j]], &mut whole] {
                c.load_1 += f.abs();
                c.load_inf = c.load_inf.max(f.abs());
                if d > 0.0 {
                    c.stiff_count += 1;
                    c.compliance += 1.0 / d;
                    c.motion += f.abs() / d;
                }
            }
        }
        for (row, &g) in of_row.iter().zip(&problem.gap) {
            let mut targets = vec![&mut whole];
            if let Some(c) = row {
                targets.push(&mut parts[*c]);
            }
            for c in targets {
                c.overlap = c.overlap.max(-g);
                c.gap_inf = c.gap_inf.max(g.abs());
            }
        }
        let stiffness = whole.stiffness().unwrap_or(1.0);
        // The whole problem's length keeps its earlier definition ‖f‖₁ / k̄ (reports, heuristics).
        let length = whole.length_of(whole.load_1 / stiffness, 1.0);
        let force = {
            let f = whole.load_inf.max(stiffness * whole.overlap);
            if f > 0.0 {
                f
            } else {
                stiffness * length
            }
        };
        let mut body_motions = vec![0.0_f64; bodies.sizes.len()];
        for ((&b, &d), &f) in bodies.label.iter().zip(&diag).zip(&problem.load) {
            if d > 0.0 {
                body_motions[b] += f.abs() / d;
            }
        }
        let (rows, row_stiffness) = Self::row_lengths(problem, &diag, &of_row, &parts, length);
        let component_forces: Vec<f64> = parts.iter().map(|c| c.force(stiffness, length)).collect();
        let row_forces: Vec<f64> = of_row
            .iter()
            .map(|c| c.map_or(force.max(TINY), |c| component_forces[c]))
            .collect();
        let row_reach = row_forces
            .iter()
            .zip(&rows)
            .zip(&row_stiffness)
            .map(|((&f, &x), k)| k.map_or(f, |k| f.min(k * x)).max(TINY))
            .collect();
        let dof_forces: Vec<f64> = of_dof.iter().map(|&c| component_forces[c]).collect();
        let dof_reach = of_dof
            .iter()
            .zip(&diag)
            .zip(&dof_forces)
            .map(|((&c, &d), &f)| {
                let reach = d * parts[c].length(length);
                if reach > 0.0 { f.min(reach) } else { f }.max(TINY)
            })
            .collect();
        Self {
            force: force.max(TINY),
            length: length.max(TINY),
            rows,
            row_forces,
            row_reach,
            dof_forces,
            dof_reach,
            bodies,
            row_body_starts,
            row_bodies,
            body_motions,
        }
    }

    /// Xᵢ = max(G_c, min(W_c, ‖f_c‖₁ / kᵢ)) of every row (see the type's docs), and kᵢ (None
    /// for a row that touches no DOF with a positive diagonal).
    fn row_lengths(
        problem: &QpProblem,
        diag: &[f64],
        of_row: &[Option<usize>],
        parts: &[Component],
        global: f64,
    ) -> (Vec<f64>, Vec<Option<f64>>) {
        let mut row_count = vec![0usize; problem.rows()];
        let mut row_compliance = vec![0.0_f64; problem.rows()];
        for (j, col) in problem.constraints.outer_iterator().enumerate() {
            if diag[j] > 0.0 {
                for (i, _) in col.iter() {
                    row_count[i] += 1;
                    row_compliance[i] += 1.0 / diag[j];
                }
            }
        }
        of_row
            .iter()
            .enumerate()
            .map(|(i, c)| {
                let k = harmonic(row_count[i], row_compliance[i]);
                let Some(c) = c else {
                    return (global, k);
                };
                let part = &parts[*c];
                let reach = k.map_or(part.motion, |k| part.motion.min(part.load_1 / k));
                (part.length_of(reach, global), k)
            })
            .unzip()
    }
}
