//! The one residual check used for every backend.

use serde::Serialize;

use super::blocks::{row_sets, RowSet};
use super::ops::{mat_t_vec, mat_vec};
use super::problem::QpProblem;
pub use super::scales::ResidualScales;
use super::scales::TINY;

/// How far (x, λ) is from the KKT conditions.  All but `max_penetration` are dimensionless.
///
/// Every measure is taken against scales of the problem's data (see [`ResidualScales`]): the row
/// length scales Xᵢ and the force scales F_c of each connected component c (row i's component
/// c(i), DOF j's component c(j)).  Those are upper bounds: a body that the answer separates from
/// the rest of its component (a contact that opens) is out of reach of the component's other
/// loads, however large, so the two measures such a load could hide are tightened by what the
/// answer shows acts on each body b (a connected component of A alone) — only ever downwards,
/// so a wrong answer cannot loosen its own test:
/// * the motion of the row's bodies Mᵢ = max |xⱼ| over the DOFs of the bodies row i touches,
///   and the row's length X̃ᵢ = max(max(0, −gᵢ), min(Xᵢ, max(Mᵢ, δ Wᵢ))) (a penetration is
///   judged against the pair's own motion, or the row's initial overlap, whichever is larger),
///   with Wᵢ the largest W_b = Σⱼ∈b |fⱼ| / Aⱼⱼ of the row's bodies (the motion their own loads
///   could give them) and δ = [`BODY_MOTION_FLOOR`];
/// * the force on body b, F_b = max |fⱼ| and |(Bᵀλ)ⱼ| over its DOFs (its loads and the contact
///   forces the answer puts on it), and the DOF's force F̃ⱼ = min(F_c(j), max(F_b, δ Rⱼ))
///   with δ = [`BODY_FORCE_FLOOR`] and Rⱼ = min(F_c(j), Aⱼⱼ L_c) the force its own spring gives
///   over its component's length (a body in equilibrium under its own forces, judged against
///   them down to δ of that);
/// * the row's force F̃ᵢ = min(F_c(i), max(min_b F_b, δ Rᵢ)) over the bodies b row i touches,
///   with Rᵢ = min(F_c(i), kᵢ Xᵢ) (its own springs over its length): a row's force acts on
///   every body it touches, so it is no larger than the least loaded of them balances — the
///   lifting of a stiff punch's prescribed motion cannot loosen the check of the forces a very
///   soft foundation takes (issue 41).
///
/// Then:
/// * `max_penetration` = max(0, maxᵢ (Bx − g)ᵢ), in the problem's length unit;
/// * `relative_penetration` = maxᵢ max(0, (Bx − g)ᵢ) / X̃ᵢ;
/// * `stationarity` = maxⱼ |(Ax − f + Bᵀλ)ⱼ| / F̃ⱼ;
/// * `complementarity` = maxᵢ |λᵢ (g − Bx)ᵢ| / (F̃ᵢ Xᵢ);
/// * `min_multiplier` = minᵢ min(0, λᵢ / F̃ᵢ) (zero when every λᵢ ≥ 0).
///
/// Those are the non-negative rows'.  A box row i of bound sᵢ ([`crate::ConstraintBlock::Box`],
/// rᵢ = (Bx − g)ᵢ unrestricted) has no penetration; it adds |sᵢ |rᵢ| − λᵢ rᵢ| / (F̃ᵢ Xᵢ) to
/// `complementarity` and min(0, (sᵢ − |λᵢ|) / F̃ᵢ) to `min_multiplier`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Default, schemars::JsonSchema)]
pub struct KktResiduals {
    /// Largest constraint violation max(0, Bx − g), in length units.
    pub max_penetration: f64,
    /// Largest violation of a row relative to that row's length scale Xᵢ.
    pub relative_penetration: f64,
    /// Relative equilibrium residual maxⱼ |(Ax − f + Bᵀλ)ⱼ| / F_c(j).
    pub stationarity: f64,
    /// Relative complementarity maxᵢ |λᵢ sᵢ| / (F̃ᵢ Xᵢ).
    pub complementarity: f64,
    /// Most negative multiplier relative to its component's force scale (≤ 0).
    pub min_multiplier: f64,
}

impl KktResiduals {
    /// The residuals of an answer that cannot be measured (wrong lengths, non-finite entries,
    /// or no answer at all): every measure infinite, so no tolerance is met.
    pub const UNMEASURABLE: Self = Self {
        max_penetration: f64::INFINITY,
        relative_penetration: f64::INFINITY,
        stationarity: f64::INFINITY,
        complementarity: f64::INFINITY,
        min_multiplier: f64::NEG_INFINITY,
    };

    /// The worst of the four dimensionless measures; infinite when any of them is NaN
    /// (`f64::max` would silently drop a NaN).
    pub fn worst(&self) -> f64 {
        let all = [
            self.relative_penetration,
            self.stationarity,
            self.complementarity,
            -self.min_multiplier,
        ];
        if all.iter().any(|v| v.is_nan()) {
            return f64::INFINITY;
        }
        all.into_iter().fold(f64::NEG_INFINITY, f64::max)
    }

    /// True when every dimensionless measure is at most `tol` (and none is NaN).
    pub fn meet(&self, tol: f64) -> bool {
        self.worst() <= tol
    }

    /// Multiplies the length-valued field by `length` (to report in the user's units).
    pub fn with_length_scale(mut self, length: f64) -> Self {
        self.max_penetration *= length;
        self
    }
}

/// The KKT residuals of (x, λ) for `problem`; see [`KktResiduals`] for the definitions.
///
/// ```
/// use signorini_qp::{kkt_residuals, QpProblem};
/// use sprs::TriMat;
/// // min x² − 4x  s.t. x ≤ 1  →  x = 1, λ = 2.
/// let mut a = TriMat::new((1, 1)); a.add_triplet(0, 0, 2.0);
/// let mut b = TriMat::new((1, 1)); b.add_triplet(0, 0, 1.0);
/// let qp = QpProblem::try_new(a.to_csc(), vec![4.0], b.to_csc(), vec![1.0]).unwrap();
/// let r = kkt_residuals(&qp, &[1.0], &[2.0]);
/// assert!(r.meet(1e-15));
/// assert!(!kkt_residuals(&qp, &[1.1], &[2.0]).meet(1e-3));
/// ```
pub fn kkt_residuals(problem: &QpProblem, x: &[f64], multipliers: &[f64]) -> KktResiduals {
    kkt_residuals_with(problem, &ResidualScales::of(problem), x, multipliers)
}

/// As [`kkt_residuals`], with the scales computed once by the caller (e.g. a backend that checks
/// the residuals every iteration).
pub fn kkt_residuals_with(
    problem: &QpProblem,
    scales: &ResidualScales,
    x: &[f64],
    multipliers: &[f64],
) -> KktResiduals {
    let sets: Vec<RowSet> = row_sets(&problem.blocks).collect();
    kkt_residuals_in(problem, &sets, scales, x, multipliers)
}

/// As [`kkt_residuals_with`], with each row's multiplier set given by the caller instead of read
/// from the problem's blocks (Coulomb's rows, whose bounds μ max(0, λₙ) depend on the answer:
/// [`crate::CoulombRows::residuals`]).
pub fn kkt_residuals_in(
    problem: &QpProblem,
    sets: &[RowSet],
    scales: &ResidualScales,
    x: &[f64],
    multipliers: &[f64],
) -> KktResiduals {
    if x.len() != problem.dofs()
        || multipliers.len() != problem.rows()
        || !scales.fit(problem)
        || sets.len() != problem.rows()
        || x.iter().chain(multipliers).any(|v| !v.is_finite())
    {
        return KktResiduals::UNMEASURABLE;
    }
    let ax = mat_vec(&problem.stiffness, x);
    let bx = mat_vec(&problem.constraints, x);
    let btl = mat_t_vec(&problem.constraints, multipliers);
    let (motion, body_force) = body_motion_and_force(problem, scales, x, &btl);
    let stationarity = ax
        .iter()
        .zip(&problem.load)
        .zip(&btl)
        .zip(scales.dof_forces.iter().zip(&scales.dof_reach))
        .zip(&scales.bodies.label)
        .map(|((((a, f), b), (&component, &reach)), &body)| {
            let own = body_force[body].max(BODY_FORCE_FLOOR * reach);
            (a - f + b).abs() / component.min(own)
        })
        .fold(0.0, f64::max);
    let mut max_penetration = 0.0_f64;
    let mut complementarity = 0.0_f64;
    let mut relative_penetration = 0.0_f64;
    let mut min_multiplier = 0.0_f64;
    for (i, (((((bxi, gi), li), xi), force), set)) in bx
        .iter()
        .zip(&problem.gap)
        .zip(multipliers)
        .zip(&scales.rows)
        .zip(scales.row_forces.iter().zip(&scales.row_reach))
        .zip(sets.iter().copied())
        .enumerate()
    {
        let slack = gi - bxi;
        let xi = xi.max(TINY);
        let bodies = scales.bodies_of_row(i);
        let force = row_force(force, bodies, &body_force);
        // F·Xᵢ can underflow to 0 when both are tiny: keep the quotient finite.
        let work = (force * xi).max(TINY);
        match set {
            RowSet::NonNegative => {
                let moved = bodies.iter().map(|&b| motion[b]).fold(0.0, f64::max);
                let own_loads = bodies
                    .iter()
                    .map(|&b| scales.body_motions[b])
                    .fold(0.0, f64::max);
                let own_length = (-gi)
                    .max(xi.min(moved.max(BODY_MOTION_FLOOR * own_loads)))
                    .max(TINY);
                max_penetration = max_penetration.max(-slack);
                relative_penetration = relative_penetration.max(-slack / own_length);
                complementarity = complementarity.max((li * slack).abs() / work);
                min_multiplier = min_multiplier.min(li / force);
            }
            RowSet::Box(bound) => {
                // r = −slack may take any value; sᵢ|r| − λᵢ r ≥ 0 when |λᵢ| ≤ sᵢ, zero exactly at
                // stick below the bound or slip at it (crate::blocks); |λᵢ| beyond sᵢ is the
                // multiplier set's violation, like a negative λ on a one-sided row.
                let r = -slack;
                complementarity = complementarity.max((bound * r.abs() - li * r).abs() / work);
                min_multiplier = min_multiplier.min((bound - li.abs()) / force);
            }
        }
    }
    let finite_or_inf = |v: f64| if v.is_finite() { v } else { f64::INFINITY };
    KktResiduals {
        max_penetration,
        relative_penetration: finite_or_inf(relative_penetration),
        stationarity: finite_or_inf(stationarity),
        complementarity: finite_or_inf(complementarity),
        min_multiplier,
    }
}

/// δ of [`KktResiduals`]: a body's equilibrium (and a row's force) is judged against the
/// forces the answer shows on it down to this fraction of the force its own springs give over
/// their length (capped by its component's scale).  With a tolerance of 1e-8 that is an
/// equilibrium error of 1e-12 of that force, the accuracy an interior-point or direct solver
/// still reaches where the body's own stiffness sets the scale; a body whose forces the answer
/// gets wrong by more than 1e-4 of it (a load left unbalanced, a contact force without a
/// counterpart) is still caught.
pub const BODY_FORCE_FLOOR: f64 = 1e-4;

/// δ of a row's length in [`KktResiduals`]: a penetration is judged against the pair's own
/// motion Mᵢ down to this fraction of the motion the row's bodies' own loads could give them
/// (Wᵢ, fixed by the data).  Without it a body that does not move at all (a point pressed onto
/// an obstacle, its exact answer xⱼ = 0) judged the round-off of its contact, 1e-17, against
/// its motion, 1e-17: relative penetration 1, and an exact answer could not be certified
/// (FCLIB's four points on a plane through pdas).  Only the row's own bodies count: a load on a
/// body the answer separates from the pair cannot raise the floor (issue 18).  At a tolerance of
/// 1e-8 a penetration of 1e-12 Wᵢ is still caught.
pub const BODY_MOTION_FLOOR: f64 = 1e-4;

/// F̃ᵢ of row i: its component's force scale `component`, tightened to the force the answer
/// shows on the least loaded of the row's `bodies` (down to [`BODY_FORCE_FLOOR`] of
/// `component`).  A row's force acts on every body it touches, so the row can carry no more
/// than the body that carries least can balance: the lifting of a stiff punch's prescribed
/// motion (a huge F_c) cannot loosen the check of the forces a very soft foundation takes.
fn row_force((component, reach): (&f64, &f64), bodies: &[usize], body_force: &[f64]) -> f64 {
    let least = bodies
        .iter()
        .map(|&b| body_force[b])
        .fold(f64::INFINITY, f64::min);
    if least.is_finite() {
        component.min(least.max(BODY_FORCE_FLOOR * reach))
    } else {
        *component
    }
}

/// Per body: the motion max |xⱼ| and the force max(|fⱼ|, |(Bᵀλ)ⱼ|) over its DOFs.
fn body_motion_and_force(
    problem: &QpProblem,
    scales: &ResidualScales,
    x: &[f64],
    btl: &[f64],
) -> (Vec<f64>, Vec<f64>) {
    let bodies = scales.bodies.sizes.len();
    let mut motion = vec![0.0_f64; bodies];
    let mut force = vec![0.0_f64; bodies];
    for (j, &b) in scales.bodies.label.iter().enumerate() {
        motion[b] = motion[b].max(x[j].abs());
        force[b] = force[b].max(problem.load[j].abs()).max(btl[j].abs());
    }
    (motion, force)
}
