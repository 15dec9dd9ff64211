//! Knobs of the clarabel backend, with their defaults.

use signorini_qp::{QpError, SolveOptions};

/// Sparse LDLᵀ factorisation clarabel uses for its KKT systems.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum DirectSolver {
    /// Let clarabel choose (qdldl unless a faster one is compiled in).
    #[default]
    Auto,
    /// clarabel's own QDLDL (always available).
    Qdldl,
    /// faer's supernodal LDLᵀ; needs this crate's `faer` feature.
    Faer,
}

impl DirectSolver {
    /// The name clarabel's `direct_solve_method` setting expects.
    pub fn as_str(self) -> &'static str {
        match self {
            DirectSolver::Auto => "auto",
            DirectSolver::Qdldl => "qdldl",
            DirectSolver::Faer => "faer",
        }
    }
}

/// Settings of [`ClarabelBackend`](crate::ClarabelBackend).
///
/// Tolerances are those of clarabel (relative to its own scaled residuals), not those of
/// [`signorini_qp::kkt_residuals`]; they default to a tenth of [`SolveOptions::tol`] so
/// that clarabel's answer usually also meets ours.
///
/// ```
/// use signorini_clarabel::{ClarabelSettings, DirectSolver};
/// let settings = ClarabelSettings { eps_abs: Some(1e-12), direct_solver: DirectSolver::Qdldl,
///     ..ClarabelSettings::default() };
/// assert!(settings.validate().is_ok());
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct ClarabelSettings {
    /// Absolute duality-gap tolerance (`tol_gap_abs`); `None` → `tol / 100` (clarabel's residuals are measured on its equilibrated data, ours on the original).  Default `None`.
    pub eps_abs: Option<f64>,
    /// Relative duality-gap and primal/dual feasibility tolerance (`tol_gap_rel`, `tol_feas`);
    /// `None` → `tol / 100` (clarabel's residuals are measured on its equilibrated data, ours on the original).  Default `None`.
    pub eps_rel: Option<f64>,
    /// Iteration cap used when [`SolveOptions::max_iter`] is `None`.  Default `200` (clarabel's).
    pub max_iter: u32,
    /// Ruiz equilibration of the data before solving.  Default `true`.
    pub equilibrate: bool,
    /// KKT factorisation.  Default [`DirectSolver::Auto`].
    pub direct_solver: DirectSolver,
    /// clarabel's presolve (drops rows with infinite right-hand side).  Default `true`.
    pub presolve: bool,
    /// Rescale the problem with [`signorini_qp::QpScaling`] (A, f, g to O(1)) before
    /// handing it over, and the answer back.  Default `true`.
    pub rescale: bool,
    /// Re-solve with tolerances ×10⁻² (down to 1e-15), then without equilibration, while
    /// clarabel reports solved but the core's residuals miss `tol`.  Default `true`.
    pub continuation: bool,
    /// Print clarabel's iteration log (also on when [`SolveOptions::verbose`]).  Default `false`.
    pub verbose: bool,
}

impl Default for ClarabelSettings {
    fn default() -> Self {
        Self {
            eps_abs: None,
            eps_rel: None,
            max_iter: 200,
            equilibrate: true,
            direct_solver: DirectSolver::Auto,
            presolve: true,
            rescale: true,
            continuation: true,
            verbose: false,
        }
    }
}

/// Why [`ClarabelSettings`] cannot be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ClarabelSettingsError {
    /// A tolerance is not a positive finite number.
    #[error("clarabel tolerance `{name}` must be positive and finite, got {value}")]
    Tolerance {
        /// Field name.
        name: &'static str,
        /// Offending value.
        value: f64,
    },
    /// `max_iter` is zero.
    #[error("clarabel max_iter must be at least 1")]
    ZeroIterations,
    /// The chosen factorisation was not compiled in.
    #[error("direct solver `{0}` is not compiled in (enable the `faer` feature)")]
    SolverUnavailable(&'static str),
}

impl From<ClarabelSettingsError> for QpError {
    fn from(error: ClarabelSettingsError) -> Self {
        match error {
            ClarabelSettingsError::SolverUnavailable(_) => QpError::Unavailable {
                backend: crate::NAME,
                reason: error.to_string(),
            },
            other => QpError::Backend {
                backend: crate::NAME,
                reason: other.to_string(),
            },
        }
    }
}

/// Smallest tolerance handed to clarabel: below this its stopping tests cannot be met in f64.
pub(crate) const MIN_TOL: f64 = 1e-15;

impl ClarabelSettings {
    /// Checks every field; called by the backend before each solve.
    pub fn validate(&self) -> Result<(), ClarabelSettingsError> {
        for (name, value) in [("eps_abs", self.eps_abs), ("eps_rel", self.eps_rel)] {
            if let Some(value) = value {
                if !(value.is_finite() && value > 0.0) {
                    return Err(ClarabelSettingsError::Tolerance { name, value });
                }
            }
        }
        if self.max_iter == 0 {
            return Err(ClarabelSettingsError::ZeroIterations);
        }
        if self.direct_solver == DirectSolver::Faer && !cfg!(feature = "faer") {
            return Err(ClarabelSettingsError::SolverUnavailable("faer"));
        }
        Ok(())
    }

    /// clarabel's settings for one solve with `options`.
    pub(crate) fn to_clarabel(
        &self,
        options: &SolveOptions,
    ) -> Result<clarabel::solver::DefaultSettings<f64>, ClarabelSettingsError> {
        self.validate()?;
        let tol = options.tol;
        if !(tol.is_finite() && tol > 0.0) {
            return Err(ClarabelSettingsError::Tolerance {
                name: "SolveOptions::tol",
                value: tol,
            });
        }
        let derived = (0.01 * tol).max(MIN_TOL);
        let eps_abs = self.eps_abs.unwrap_or(derived);
        let eps_rel = self.eps_rel.unwrap_or(derived);
        let max_iter = match options.max_iter {
            Some(0) => return Err(ClarabelSettingsError::ZeroIterations),
            Some(cap) => u32::try_from(cap).unwrap_or(u32::MAX),
            None => self.max_iter,
        };
        Ok(clarabel::solver::DefaultSettings {
            max_iter,
            time_limit: options
                .time_limit
                .map_or(f64::INFINITY, |limit| limit.as_secs_f64()),
            verbose: self.verbose || options.verbose,
            tol_gap_abs: eps_abs,
            tol_gap_rel: eps_rel,
            tol_feas: eps_rel,
            equilibrate_enable: self.equilibrate,
            direct_solve_method: self.direct_solver.as_str().to_string(),
            presolve_enable: self.presolve,
            ..clarabel::solver::DefaultSettings::default()
        })
    }
}
