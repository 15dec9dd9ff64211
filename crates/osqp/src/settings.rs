//! Knobs of the OSQP backend, with their defaults.

use std::time::Duration;

use signorini_qp::{QpError, SolveOptions};

/// The ADMM stages of one solve (see [`OsqpSettings::continuation`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Plan {
    /// ε_abs of the first stage.
    pub eps_start: f64,
    /// ε_abs of the last stage.
    pub eps_target: f64,
    /// Iterations over all stages.
    pub max_iter: u32,
    /// The core's tolerance that ends the continuation early.
    pub tol: f64,
    /// Wall-clock limit over all stages.
    pub time_limit: Option<Duration>,
}

/// Settings of [`OsqpBackend`](crate::OsqpBackend).
///
/// OSQP stops when ‖B x − z‖∞ ≤ ε_abs + ε_rel·max(‖Bx‖∞, ‖z‖∞) and
/// ‖A x − f + Bᵀy‖∞ ≤ ε_abs + ε_rel·max(‖Ax‖∞, ‖Bᵀy‖∞, ‖f‖∞).  The relative term lets it stop
/// early on large problems, so the default is ε_rel = 0 with ε_abs derived from
/// [`SolveOptions::tol`] and the (rescaled) load.
///
/// ```
/// use signorini_osqp::OsqpSettings;
/// // OSQP's own low-accuracy defaults: fast, and reported honestly as not solved at 1e-9.
/// let loose = OsqpSettings { eps_abs: Some(1e-3), eps_rel: 1e-3, polish: false,
///     ..OsqpSettings::default() };
/// assert!(loose.validate().is_ok());
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct OsqpSettings {
    /// Absolute tolerance ε_abs; `None` → `tol · ‖f‖∞` of the rescaled problem (`tol` if f = 0).
    /// Default `None`.
    pub eps_abs: Option<f64>,
    /// Relative tolerance ε_rel.  Default `0` (OSQP's own default is 1e-3).
    pub eps_rel: f64,
    /// Threshold of OSQP's primal and dual infeasibility certificates (`eps_prim_inf`,
    /// `eps_dual_inf`).  Default `1e-8` (OSQP's 1e-4 reports well-posed but ill-conditioned
    /// contact problems as infeasible).
    pub eps_infeasible: f64,
    /// Polish: after ADMM converges, guess the active set and solve its equality-constrained
    /// KKT system directly.  Default `true`.
    pub polish: bool,
    /// Tolerance continuation (only with `polish`): start ADMM at ε = `continuation_start`·‖f‖∞,
    /// polish, and while the core's KKT residuals miss `tol`, tighten ε 100-fold and continue
    /// from the polished point, down to ε_abs.  Default `true`.
    pub continuation: bool,
    /// First ε of the continuation, relative to ‖f‖∞.  Default `1e-3`.
    pub continuation_start: f64,
    /// Iterative-refinement steps of the polish solve.  Default `10` (OSQP's: 3).
    pub polish_refine_iter: u32,
    /// ADMM iteration cap used when [`SolveOptions::max_iter`] is `None`.  Default `50_000`
    /// (OSQP's 4000 rarely reaches tight tolerances).
    pub max_iter: u32,
    /// Adapt the ADMM step ρ during the iteration.  Default `true`.
    pub adaptive_rho: bool,
    /// Iterations between ρ adaptations; `0` lets OSQP time it from the setup time, which makes
    /// runs irreproducible.  Default `25`.
    pub adaptive_rho_interval: u32,
    /// Initial ADMM step ρ.  Default `0.1` (OSQP's).
    pub rho: f64,
    /// Ruiz scaling iterations inside OSQP; `0` disables.  Default `10` (OSQP's).
    pub scaling: u32,
    /// Start from this backend's previous answer when the next problem has the same n and m.
    /// Default `false` (every solve starts cold, as the other backends do).
    pub warm_start: bool,
    /// Rescale the problem with [`signorini_qp::QpScaling`] (A, f, g to O(1)) before
    /// handing it over, and the answer back.  Default `true`.
    pub rescale: bool,
    /// Print OSQP's iteration log (also on when [`SolveOptions::verbose`]).  Default `false`.
    pub verbose: bool,
}

impl Default for OsqpSettings {
    fn default() -> Self {
        Self {
            eps_abs: None,
            eps_rel: 0.0,
            eps_infeasible: 1e-8,
            polish: true,
            continuation: true,
            continuation_start: 1e-3,
            polish_refine_iter: 10,
            max_iter: 50_000,
            adaptive_rho: true,
            adaptive_rho_interval: 25,
            rho: 0.1,
            scaling: 10,
            warm_start: false,
            rescale: true,
            verbose: false,
        }
    }
}

/// Why [`OsqpSettings`] cannot be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OsqpSettingsError {
    /// A number that must be positive (or non-negative) and finite is not.
    #[error("OSQP setting `{name}` must be {requirement} and finite, got {value}")]
    OutOfRange {
        /// Field name.
        name: &'static str,
        /// "positive" or "non-negative".
        requirement: &'static str,
        /// Offending value.
        value: f64,
    },
    /// `max_iter` is zero.
    #[error("OSQP max_iter must be at least 1")]
    ZeroIterations,
}

impl From<OsqpSettingsError> for QpError {
    fn from(error: OsqpSettingsError) -> Self {
        QpError::Backend {
            backend: crate::NAME,
            reason: error.to_string(),
        }
    }
}

fn positive(name: &'static str, value: f64) -> Result<(), OsqpSettingsError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(OsqpSettingsError::OutOfRange {
            name,
            requirement: "positive",
            value,
        })
    }
}

/// Smallest ε_abs handed to OSQP: below this ADMM cannot stop in f64.
const MIN_EPS: f64 = 1e-15;

impl OsqpSettings {
    /// Checks every field; called by the backend before each solve.
    pub fn validate(&self) -> Result<(), OsqpSettingsError> {
        if let Some(eps) = self.eps_abs {
            positive("eps_abs", eps)?;
        }
        positive("eps_infeasible", self.eps_infeasible)?;
        if !(self.eps_rel.is_finite() && self.eps_rel >= 0.0) {
            return Err(OsqpSettingsError::OutOfRange {
                name: "eps_rel",
                requirement: "non-negative",
                value: self.eps_rel,
            });
        }
        positive("rho", self.rho)?;
        positive("continuation_start", self.continuation_start)?;
        if self.max_iter == 0 {
            return Err(OsqpSettingsError::ZeroIterations);
        }
        Ok(())
    }

    /// OSQP's settings for the first stage of one solve with `options`, and the plan of the
    /// stages; `load_scale` is ‖f‖∞ of the problem OSQP will see.
    pub(crate) fn to_osqp(
        &self,
        options: &SolveOptions,
        load_scale: f64,
    ) -> Result<(osqp::Settings, Plan), OsqpSettingsError> {
        self.validate()?;
        positive("SolveOptions::tol", options.tol)?;
        let scale = if load_scale > 0.0 && load_scale.is_finite() {
            load_scale
        } else {
            1.0
        };
        let eps_target = self.eps_abs.unwrap_or((options.tol * scale).max(MIN_EPS));
        let eps_start = if self.polish && self.continuation {
            (self.continuation_start * scale).max(eps_target)
        } else {
            eps_target
        };
        let max_iter = match options.max_iter {
            Some(0) => return Err(OsqpSettingsError::ZeroIterations),
            // OSQP stores the cap in a C int.
            Some(cap) => u32::try_from(cap).unwrap_or(u32::MAX).min(i32::MAX as u32),
            None => self.max_iter.min(i32::MAX as u32),
        };
        let plan = Plan {
            eps_start,
            eps_target,
            max_iter,
            tol: options.tol,
            time_limit: options.time_limit,
        };
        let settings = osqp::Settings::default()
            .eps_abs(eps_start)
            .eps_rel(self.eps_rel)
            // OSQP's default certificate thresholds (1e-4) misfire on badly conditioned but
            // well-posed problems (ν → 0.5, stiffness contrast 1e6): a false "dual infeasible".
            .eps_prim_inf(self.eps_infeasible)
            .eps_dual_inf(self.eps_infeasible)
            .polish(self.polish)
            .polish_refine_iter(self.polish_refine_iter.min(i32::MAX as u32))
            .max_iter(max_iter)
            .adaptive_rho(self.adaptive_rho)
            .adaptive_rho_interval(
                (self.adaptive_rho_interval > 0)
                    .then_some(self.adaptive_rho_interval.min(i32::MAX as u32)),
            )
            .rho(self.rho)
            .scaling((self.scaling > 0).then_some(self.scaling.min(i32::MAX as u32)))
            .warm_start(self.warm_start)
            .verbose(self.verbose || options.verbose)
            .time_limit(options.time_limit.map(|limit| {
                // OSQP reads a zero limit as "none".
                limit.max(Duration::from_nanos(1))
            }));
        Ok((settings, plan))
    }
}
