//! Backend-specific settings: one plain struct, one place for validation.

use crate::error::DualError;

/// Which algorithm runs on the dual problem.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DualMethod {
    /// Projected Gauss–Seidel on the dense condensed Hessian H = B A⁻¹ Bᵀ.
    ProjectedGaussSeidel,
    /// Projected gradient (Uzawa) with one solve of the cached factor per step.
    Uzawa,
    /// Primal–dual active set (semismooth Newton) on the dense condensed Hessian.
    ActiveSet,
}

impl DualMethod {
    /// The backend name this method runs under (`"dual-pgs"`, `"dual-uzawa"`, `"dual-ssn"`).
    pub fn backend_name(self) -> &'static str {
        match self {
            DualMethod::ProjectedGaussSeidel => "dual-pgs",
            DualMethod::Uzawa => "dual-uzawa",
            DualMethod::ActiveSet => "dual-ssn",
        }
    }
}

/// How the dense dual Hessian H = B A⁻¹ Bᵀ is formed (projected Gauss–Seidel, active set).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Condensation {
    /// Factor A with the touched DOFs c ordered last: the trailing block L_cc of the factor is
    /// the Cholesky factor of the Schur complement S on c, and H = Yᵀ Y with Y = L_cc⁻¹ B_cᵀ
    /// (dense work only, no extra sparse solves).  The fastest (see the crate docs).
    TrailingBlock,
    /// Factor A once and solve A Y = Bᵀ for blocks of right-hand sides; H = B Y.
    MultiRhs,
    /// Factor the interior block A_ii (DOFs that B does not touch), form the Schur complement
    /// S = A_cc − A_ci A_ii⁻¹ A_ic on the touched DOFs c with multi-right-hand-side solves on the
    /// columns of A_ic, then H = B_c S⁻¹ B_cᵀ with a dense Cholesky of S.
    InteriorSchur,
}

/// Settings of the dual backend.  Every field has a default (see [`Default`]).
#[derive(Debug, Clone, PartialEq)]
pub struct DualSettings {
    /// Algorithm.  Default [`DualMethod::ProjectedGaussSeidel`] (the constructors
    /// [`crate::DualBackend::pgs`], [`crate::DualBackend::uzawa`], [`crate::DualBackend::active_set`]
    /// set it).
    pub method: DualMethod,
    /// ω, the relaxation of projected Gauss–Seidel, in (0, 2).  Default `1.0` (measured: ω = 1
    /// beat 1.5 and 1.8 by 2–3× in iterations on contact problems).
    pub relaxation: f64,
    /// Iteration cap used when `SolveOptions::max_iter` is `None`.  Default `100_000`
    /// (sweeps for PGS, steps for Uzawa, active-set changes for the active-set method).
    pub max_iter: usize,
    /// The full KKT check (one solve with the factor, then `kkt_residuals`) runs every
    /// `check_every` iterations, and earlier whenever the cheap dual estimate meets the
    /// tolerance.  Projected Gauss–Seidel stretches the period so that these checks take at
    /// most about a tenth of its sweeping time.  Default `10`.
    pub check_every: usize,
    /// How H is formed.  Default [`Condensation::TrailingBlock`].
    pub condensation: Condensation,
    /// Right-hand sides solved together when forming H (bounds the n × block work array).
    /// Default `64`.
    pub block_size: usize,
    /// Uzawa: accelerate with Nesterov/FISTA momentum and gradient restart.  Default `true`.
    pub accelerate: bool,
    /// Uzawa: the step is ρ = `step_factor` / L̂ with L̂ the estimate of λ_max(H); in (0, 2),
    /// and at most 1 with acceleration.  Default `1.0`.
    pub step_factor: f64,
    /// Uzawa: power iterations (one solve each) to estimate λ_max(H).  Default `30`.
    pub power_iterations: usize,
    /// Active set: above this many contact rows m, or when the dense H (m² entries) and the
    /// dense Newton matrices do not fit in the available memory, the Newton steps are solved
    /// matrix-free (projected preconditioned CG with S = B A⁺ Bᵀ applied through the sparse
    /// factor) instead of with a dense H.  Default `20_000` (3.2 GB for H; see the crate docs
    /// for the measured cross-over).
    pub matrix_free_rows: usize,
    /// Floating bodies: the augmented-Lagrangian penalty on Rᵀ(f − Bᵀλ) = 0 is
    /// c = `equality_penalty` · λ_max(H) / λ_max(G Gᵀ), G = Rᵀ Bᵀ.  Default `1.0`.
    pub equality_penalty: f64,
}

impl Default for DualSettings {
    fn default() -> Self {
        Self {
            method: DualMethod::ProjectedGaussSeidel,
            relaxation: 1.0,
            max_iter: 100_000,
            check_every: 10,
            condensation: Condensation::TrailingBlock,
            block_size: 64,
            accelerate: true,
            step_factor: 1.0,
            power_iterations: 30,
            equality_penalty: 1.0,
            matrix_free_rows: 20_000,
        }
    }
}

impl DualSettings {
    /// Checks every field's range.
    pub fn validate(&self) -> Result<(), DualError> {
        let bad = |field: &'static str, reason: &str| {
            Err(DualError::Settings {
                field,
                reason: reason.to_string(),
            })
        };
        if !(self.relaxation > 0.0 && self.relaxation < 2.0) {
            return bad("relaxation", "ω must lie in (0, 2)");
        }
        if self.max_iter == 0 {
            return bad("max_iter", "must be at least 1");
        }
        if self.check_every == 0 {
            return bad("check_every", "must be at least 1");
        }
        if self.block_size == 0 {
            return bad("block_size", "must be at least 1");
        }
        let step_max = if self.accelerate { 1.0 } else { 2.0 };
        if !(self.step_factor > 0.0 && self.step_factor <= step_max) {
            return bad(
                "step_factor",
                "must lie in (0, 1] with acceleration, (0, 2) without",
            );
        }
        if !self.accelerate && self.step_factor >= 2.0 {
            return bad("step_factor", "must be below 2");
        }
        if self.power_iterations == 0 {
            return bad("power_iterations", "must be at least 1");
        }
        if !(self.equality_penalty > 0.0 && self.equality_penalty.is_finite()) {
            return bad("equality_penalty", "must be positive and finite");
        }
        Ok(())
    }
}
