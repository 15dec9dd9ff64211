//! The QP backends the driver can run, picked by name at run time.

use std::fmt;
use std::str::FromStr;

use signorini_core::qp::QpBackend;

/// A backend the command line can name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BackendKind {
    /// Interior point (clarabel).
    Clarabel,
    /// ADMM (OSQP), when built with the `osqp` feature.
    Osqp,
    /// Projected Gauss–Seidel on the condensed dual.
    DualPgs,
    /// Uzawa / projected gradient on the dual.
    DualUzawa,
    /// Primal–dual active set (semismooth Newton) on the condensed dual.
    DualSsn,
    /// Primal–dual active set on the sparse primal KKT system.
    Pdas,
}

impl BackendKind {
    /// Every backend, in the order reports list them.
    pub const ALL: [BackendKind; 5] = [
        BackendKind::Clarabel,
        BackendKind::Osqp,
        BackendKind::DualPgs,
        BackendKind::DualUzawa,
        BackendKind::DualSsn,
    ];

    /// The command-line name.
    pub fn name(self) -> &'static str {
        match self {
            BackendKind::Clarabel => "clarabel",
            BackendKind::Osqp => "osqp",
            BackendKind::DualPgs => "dual-pgs",
            BackendKind::DualUzawa => "dual-uzawa",
            BackendKind::DualSsn => "dual-ssn",
            BackendKind::Pdas => "pdas",
        }
    }

    /// Whether this build contains the backend.
    pub fn available(self) -> bool {
        match self {
            BackendKind::Osqp => cfg!(feature = "osqp"),
            _ => true,
        }
    }
}

impl fmt::Display for BackendKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A backend name that is not known or not compiled in.
#[derive(Debug, thiserror::Error)]
pub enum BackendError {
    /// Unknown name.
    #[error(
        "unknown backend \"{0}\" (known: clarabel, osqp, dual-pgs, dual-uzawa, dual-ssn, pdas)"
    )]
    Unknown(String),
    /// Known but not in this build.
    #[error("backend \"{0}\" is not compiled in; rebuild with `--features {0}`")]
    NotCompiled(&'static str),
}

impl FromStr for BackendKind {
    type Err = BackendError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        BackendKind::ALL
            .into_iter()
            .find(|k| k.name() == s.trim())
            .ok_or_else(|| BackendError::Unknown(s.to_string()))
    }
}

/// Creates the backend with its default settings.
pub fn make_backend(kind: BackendKind) -> Result<Box<dyn QpBackend>, BackendError> {
    match kind {
        BackendKind::Clarabel => Ok(Box::new(signorini_clarabel::ClarabelBackend::default())),
        #[cfg(feature = "osqp")]
        BackendKind::Osqp => Ok(Box::new(signorini_osqp::OsqpBackend::default())),
        #[cfg(not(feature = "osqp"))]
        BackendKind::Osqp => Err(BackendError::NotCompiled("osqp")),
        BackendKind::DualPgs => Ok(Box::new(signorini_dual::DualBackend::pgs(
            Default::default(),
        ))),
        BackendKind::DualUzawa => Ok(Box::new(signorini_dual::DualBackend::uzawa(
            Default::default(),
        ))),
        BackendKind::DualSsn => Ok(Box::new(signorini_dual::DualBackend::active_set(
            Default::default(),
        ))),
        BackendKind::Pdas => Ok(Box::new(signorini_pdas::PdasBackend::default())),
    }
}
