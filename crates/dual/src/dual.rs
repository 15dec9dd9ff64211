//! The data every dual method shares: the factor of A (or of its fixed block), A⁺ f, the rigid
//! modes with their augmented-Lagrangian state, and the map λ ↦ x.
//!
//! With a kernel R the dual carries the equality G λ = e (G = Rᵀ Bᵀ, e = Rᵀ f).  It is handled
//! by an augmented Lagrangian with penalty c and multiplier μ: the bound-constrained methods
//! minimise ½ λᵀ(H + c GᵀG)λ − λᵀ(d − Gᵀμ + c Gᵀe) over λ ≥ 0, and μ ← μ + c(Gλ − e) between
//! inner solves.  With μ̃ = μ + c(Gλ − e) the primal point is
//!
//! ```text
//! x(λ) = A⁺(f − Bᵀλ) − R μ̃,
//! ```
//!
//! and the gradient of the inner objective is exactly g − B x(λ).  Without a kernel, c = 0 and
//! x(λ) = A⁻¹(f − Bᵀλ).

use std::cell::OnceCell;

use signorini_qp::{dot, mat_t_vec, mat_vec, norm_inf, QpProblem, QpStatus};

use crate::error::DualError;
use crate::factor::StiffnessInverse;
use crate::kernel::{add_coupling_t, RigidModes};

/// Setup shared by all methods.
#[derive(Debug)]
pub struct DualData<'p> {
    /// The primal problem.
    pub problem: &'p QpProblem,
    /// A⁺ through the cached factor.
    pub inverse: StiffnessInverse,
    /// Rigid modes (empty when A is positive definite).
    pub modes: RigidModes,
    /// A⁺ f, formed when first asked for ([`DualData::base`]).
    base: OnceCell<Vec<f64>>,
    /// z = L⁻¹ P f, the forward half of A⁺ f, when the contact DOFs are ordered last: then
    /// every x(λ) costs one backward substitution ([`StiffnessInverse::solve_shifted`]).
    forward_load: Option<Vec<f64>>,
    /// c, the augmented-Lagrangian penalty (0 without kernel).
    pub penalty: f64,
    /// μ, the multiplier of G λ = e (length k).
    pub multiplier: Vec<f64>,
}

impl<'p> DualData<'p> {
    /// Checks the kernel, chooses fixing DOFs, factors A (or A_ff) and solves A⁺ f.  With
    /// `contact_last`, the DOFs that B touches are ordered last in the factor (see
    /// [`crate::factor`]).
    /// `backend` names the caller in a memory refusal.
    pub fn new(
        problem: &'p QpProblem,
        contact_last: bool,
        backend: &'static str,
    ) -> Result<Self, DualError> {
        let modes = RigidModes::of(problem)?;
        let inverse = StiffnessInverse::new(
            &problem.stiffness,
            &modes.fixed,
            modes.count(),
            contact_last.then_some(&problem.constraints),
            backend,
        )?;
        let forward_load = inverse
            .contact_last()
            .then(|| inverse.forward(&problem.load));
        let multiplier = vec![0.0; modes.count()];
        Ok(Self {
            problem,
            inverse,
            modes,
            base: OnceCell::new(),
            forward_load,
            penalty: 0.0,
            multiplier,
        })
    }

    /// Number of dual unknowns m.
    pub fn rows(&self) -> usize {
        self.problem.rows()
    }

    /// True when A has a kernel.
    pub fn floating(&self) -> bool {
        self.modes.count() > 0
    }

    /// Sets c from an estimate of λ_max(H): c = `factor` · λ_max(H) / ‖G‖_F².
    pub fn set_penalty(&mut self, hessian_norm: f64, factor: f64) {
        let g2 = self.modes.coupling_norm_sq();
        self.penalty = if self.floating() && g2 > 0.0 {
            factor * hessian_norm.max(f64::MIN_POSITIVE) / g2
        } else {
            0.0
        };
    }

    /// A⁺ f (one solve, or its backward half after the forward half made at the start, the
    /// first time).
    pub fn base(&self) -> &[f64] {
        self.base
            .get_or_init(|| self.free_part(&vec![0.0; self.rows()]))
    }

    /// d = B A⁺ f − g.  With the contact DOFs last, B A⁺ f needs A⁺ f on them alone:
    /// L_cc⁻ᵀ z_c, a dense triangular solve ([`StiffnessInverse::contact_part`]).
    pub fn dual_load(&self) -> Vec<f64> {
        let contact = self
            .forward_load
            .as_ref()
            .and_then(|z| self.inverse.contact_part(z));
        let mut d = match contact {
            Some(u) => mat_vec(&self.problem.constraints, &u),
            None => mat_vec(&self.problem.constraints, self.base()),
        };
        d.iter_mut()
            .zip(&self.problem.gap)
            .for_each(|(di, gi)| *di -= gi);
        d
    }

    /// The inner linear term d − Gᵀμ + c Gᵀe, from d = [`DualData::dual_load`].
    pub fn inner_load(&self, dual_load: &[f64]) -> Vec<f64> {
        let shift: Vec<f64> = self
            .modes
            .load
            .iter()
            .zip(&self.multiplier)
            .map(|(e, mu)| self.penalty * e - mu)
            .collect();
        let mut d = dual_load.to_vec();
        add_coupling_t(&self.modes, &shift, &mut d);
        d
    }

    /// u(λ) = A⁺(f − Bᵀλ): one solve, or only its backward half when the contact DOFs are
    /// ordered last.
    pub fn free_part(&self, multipliers: &[f64]) -> Vec<f64> {
        let shifted = self.forward_load.as_ref().and_then(|z| {
            self.inverse
                .solve_shifted(z, &self.problem.constraints, multipliers)
        });
        if let Some(u) = shifted {
            return u;
        }
        self.free_part_full(multipliers)
    }

    /// u(λ) = A⁺(f − Bᵀλ) by a whole solve of the assembled right-hand side (what
    /// [`DualData::free_part`] shortens).
    pub fn free_part_full(&self, multipliers: &[f64]) -> Vec<f64> {
        let mut rhs = mat_t_vec(&self.problem.constraints, multipliers);
        rhs.iter_mut()
            .zip(&self.problem.load)
            .for_each(|(r, f)| *r = f - *r);
        self.inverse.solve(&rhs)
    }

    /// μ̃(λ) = μ + c (G λ − e).
    pub fn kernel_multiplier(&self, multipliers: &[f64]) -> Vec<f64> {
        self.modes
            .equality_residual(multipliers)
            .iter()
            .zip(&self.multiplier)
            .map(|(r, mu)| mu + self.penalty * r)
            .collect()
    }

    /// x = u − R μ̃(λ), from u = [`DualData::free_part`].
    pub fn primal_from(&self, mut free: Vec<f64>, multipliers: &[f64]) -> Vec<f64> {
        if self.floating() {
            let alpha = self.kernel_multiplier(multipliers);
            for (r, a) in self.modes.basis.iter().zip(&alpha) {
                free.iter_mut().zip(r).for_each(|(x, ri)| *x -= a * ri);
            }
        }
        free
    }

    /// u = A⁺(f − Bᵀ(λ + λ_lo)) to (nearly) full accuracy, for multipliers carried as an
    /// unevaluated sum λ + λ_lo (`low` = λ_lo, or `None` for zero): the solve is followed by up
    /// to `max_corrections` steps of iterative refinement whose residual f − Bᵀλ − Bᵀλ_lo − A u
    /// is summed in double-double arithmetic (mixed-precision refinement: the forward error
    /// drops from ~ε cond(A) to ~ε while ε cond(A) < 1).  The corrections stop when they stop
    /// shrinking.
    pub fn free_part_accurate(
        &self,
        multipliers: &[f64],
        low: Option<&[f64]>,
        max_corrections: usize,
    ) -> Vec<f64> {
        let mut u = self.free_part(multipliers);
        let mut last = f64::INFINITY;
        for _ in 0..max_corrections {
            let mut r = compensated_residual(self.problem, multipliers, low, &u);
            for (j, ri) in r.iter_mut().enumerate() {
                if self.inverse.reduced_index(j).is_none() {
                    *ri = 0.0;
                }
            }
            let du = self.inverse.solve(&r);
            let size = norm_inf(&du);
            if size.is_nan() || size >= last || !size.is_finite() {
                break;
            }
            u.iter_mut().zip(&du).for_each(|(ui, di)| *ui += di);
            if size <= 4.0 * f64::EPSILON * norm_inf(&u) {
                break;
            }
            last = 0.5 * size;
        }
        u
    }

    /// x = A⁺(f − Bᵀλ) − R μ for an explicit kernel multiplier μ (length k): one solve.
    pub fn primal_at(&self, multipliers: &[f64], mu: &[f64]) -> Vec<f64> {
        self.primal_at_from(self.free_part(multipliers), mu)
    }

    /// x = u − R μ from u = A⁺(f − Bᵀλ).
    pub fn primal_at_from(&self, free: Vec<f64>, mu: &[f64]) -> Vec<f64> {
        let mut x = free;
        for (r, a) in self.modes.basis.iter().zip(mu) {
            x.iter_mut().zip(r).for_each(|(xi, ri)| *xi -= a * ri);
        }
        x
    }

    /// x(λ): one solve.
    pub fn primal(&self, multipliers: &[f64]) -> Vec<f64> {
        self.primal_from(self.free_part(multipliers), multipliers)
    }

    /// g − B x, the gradient of the inner dual objective at the λ that produced x.
    pub fn dual_gradient(&self, x: &[f64]) -> Vec<f64> {
        let mut w = mat_vec(&self.problem.constraints, x);
        w.iter_mut()
            .zip(&self.problem.gap)
            .for_each(|(wi, gi)| *wi = gi - *wi);
        w
    }

    /// The augmented-Lagrangian update μ ← μ + c (G λ − e).
    ///
    /// Returns a message when the step direction proves the primal unbounded: with
    /// v = −Δμ / ‖Δμ‖ (the direction α = −μ moves in), Gᵀv = B R v ≤ 0 and eᵀv = fᵀ R v > 0
    /// is a rigid motion that never closes a contact and lowers the energy.  Any λ ≥ 0 with
    /// G λ = e would need ‖λ‖₁ ≥ eᵀv / ‖(Gᵀv)⁺‖∞, so the margin asks for that bound to exceed
    /// the current scale a million times.
    pub fn update_multiplier(&mut self, multipliers: &[f64]) -> Option<String> {
        let next = self.kernel_multiplier(multipliers);
        let step: Vec<f64> = self
            .multiplier
            .iter()
            .zip(&next)
            .map(|(old, new)| old - new)
            .collect();
        self.multiplier = next;
        let size = norm_inf(&step);
        if size == 0.0 {
            return None;
        }
        let v: Vec<f64> = step.iter().map(|s| s / size).collect();
        let mut gtv = vec![0.0; self.rows()];
        add_coupling_t(&self.modes, &v, &mut gtv);
        let positive = gtv.iter().fold(0.0_f64, |m, x| m.max(*x));
        let ev = dot(&self.modes.load, &v);
        let g_scale = self.modes.coupling_norm_sq().sqrt().max(f64::MIN_POSITIVE);
        let scale = multipliers
            .iter()
            .map(|l| l.abs())
            .sum::<f64>()
            .max(norm_inf(&self.modes.load) / g_scale);
        (ev > 0.0 && ev > 1e6 * positive * scale).then(|| {
            format!(
                "dual infeasible: a rigid motion R v with B R v ≤ 0 and fᵀ R v = {ev:.3e} > 0 (a floating body is pushed away from every contact); the objective is unbounded below"
            )
        })
    }
}

/// f − Bᵀ(λ + λ_lo) − A u, each entry summed in double-double arithmetic (Knuth's TwoSum and an FMA
/// TwoProduct) and rounded once: accurate to about ε of its own size even when the terms cancel
/// to many digits.  A is symmetric, so row i of A is column i of the CSC matrix.
fn compensated_residual(
    problem: &QpProblem,
    multipliers: &[f64],
    low: Option<&[f64]>,
    u: &[f64],
) -> Vec<f64> {
    let mut out = Vec::with_capacity(u.len());
    let columns = problem
        .stiffness
        .outer_iterator()
        .zip(problem.constraints.outer_iterator());
    for ((a_col, b_col), f) in columns.zip(&problem.load) {
        let mut sum = DoubleDouble::new(*f);
        for (r, b) in b_col.iter() {
            sum.add_product(-b, multipliers[r]);
            if let Some(low) = low {
                sum.add_product(-b, low[r]);
            }
        }
        for (j, a) in a_col.iter() {
            sum.add_product(-a, u[j]);
        }
        out.push(sum.value());
    }
    out
}

/// s = a + b exactly as the pair (s, error) (Knuth's TwoSum).
pub fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// A running sum kept as an unevaluated pair hi + lo.
#[derive(Debug, Clone, Copy)]
struct DoubleDouble {
    hi: f64,
    lo: f64,
}

impl DoubleDouble {
    fn new(value: f64) -> Self {
        Self { hi: value, lo: 0.0 }
    }

    /// self += a · b exactly up to the final rounding of the pair.
    fn add_product(&mut self, a: f64, b: f64) {
        let p = a * b;
        let p_err = a.mul_add(b, -p);
        let (s, s_err) = two_sum(self.hi, p);
        self.hi = s;
        self.lo += s_err + p_err;
    }

    fn value(self) -> f64 {
        self.hi + self.lo
    }
}

/// What a method hands back to the backend.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// Primal x.
    pub x: Vec<f64>,
    /// Multipliers λ.
    pub multipliers: Vec<f64>,
    /// The method's verdict.
    pub status: QpStatus,
    /// Iterations taken.
    pub iterations: usize,
    /// Why it stopped.
    pub message: String,
}
