//! What the command line shares: the common scene options, value parsers, the default backends.

use std::path::PathBuf;
use std::time::Duration;

use anyhow::Result;
use signorini::backends::{BackendKind, Form};
use signorini_core::mesh::MeshLimits;
use signorini_core::qp::SolveOptions;

#[derive(clap::Args)]
pub(crate) struct Common {
    /// Scene file (TOML, see docs/scene.md); the seed's Experiment 2b when omitted.
    pub(crate) scene: Option<PathBuf>,
    /// Largest total number of elements (all bodies) a scene may ask for before it is refused.
    #[arg(long, default_value_t = 5_000_000)]
    pub(crate) max_elements: usize,
}

/// What a solve asks of every backend it runs (`solve` and `compare`).
#[derive(clap::Args)]
pub(crate) struct SolveFlags {
    /// Relative KKT tolerance the answer must meet to count as solved.
    #[arg(long, default_value_t = 1e-9, value_parser = parse_tol)]
    pub(crate) tol: f64,
    /// Coulomb friction's method: auto (the backend's own semismooth Newton where it has one —
    /// pdas — else the fixed point over Tresca problems), fixed-point (any backend), or newton
    /// (refused by a backend without one).
    #[arg(long, default_value = "auto", value_parser = parse_coulomb)]
    pub(crate) coulomb: signorini_core::qp::CoulombMethod,
    /// Seconds each backend may take (auto: its whole chain); it then stops with status
    /// time-limit.  Checked after the setup and between iterations: the setup and an iteration
    /// under way (a factorisation and its solves, an interior-point step) finish first.
    #[arg(long, value_parser = parse_time_limit)]
    pub(crate) time_limit: Option<f64>,
    /// Print the backends' iteration logs to stderr (pdas: one line per active-set step;
    /// clarabel and OSQP: their own tables).
    #[arg(long)]
    pub(crate) verbose: bool,
}

impl SolveFlags {
    /// The solve options these flags ask for.
    pub(crate) fn options(&self) -> SolveOptions {
        SolveOptions {
            tol: self.tol,
            time_limit: time_limit(self.time_limit),
            coulomb: self.coulomb,
            verbose: self.verbose,
            ..SolveOptions::default()
        }
    }
}

/// Seconds a backend may take: positive; values from 1e9 s (31 years) up mean no limit.
pub(crate) fn parse_time_limit(text: &str) -> Result<f64, String> {
    let t: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("`{text}` is not a number of seconds"))?;
    if t.is_finite() && t > 0.0 || t == f64::INFINITY {
        Ok(t)
    } else {
        Err(format!("must be a positive number of seconds, got {text}"))
    }
}

/// The limit as a duration; `None` (no limit) for 1e9 s and more, where a `Duration` would be of
/// no use (and `Duration::from_secs_f64` panics beyond its range).
pub(crate) fn time_limit(seconds: Option<f64>) -> Option<Duration> {
    seconds
        .filter(|t| *t < 1e9)
        .and_then(|t| Duration::try_from_secs_f64(t).ok())
}

/// A Coulomb method by name (`auto`, `fixed-point`, `newton`).
pub(crate) fn parse_coulomb(text: &str) -> Result<signorini_core::qp::CoulombMethod, String> {
    use signorini_core::qp::CoulombMethod;
    CoulombMethod::from_name(text.trim()).ok_or_else(|| {
        let names: Vec<&str> = CoulombMethod::ALL.iter().map(|m| m.as_str()).collect();
        format!(
            "unknown Coulomb method `{text}`; choose one of {}",
            names.join(", ")
        )
    })
}

/// A tolerance in (0, 1).
pub(crate) fn parse_tol(text: &str) -> Result<f64, String> {
    let t: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("`{text}` is not a number"))?;
    if t.is_finite() && t > 0.0 && t < 1.0 {
        Ok(t)
    } else {
        Err(format!("must lie in (0, 1), got {text}"))
    }
}

/// A factor > 1.
pub(crate) fn parse_factor(text: &str) -> Result<f64, String> {
    let f: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("`{text}` is not a number"))?;
    if f.is_finite() && f > 1.0 {
        Ok(f)
    } else {
        Err(format!("must be a number above 1, got {text}"))
    }
}

/// `I/N` with 1 ≤ I ≤ N.
pub(crate) fn parse_shard(text: &str) -> Result<signorini::sweep::shard::Shard, String> {
    text.parse()
}

pub(crate) fn limits(common: &Common) -> MeshLimits {
    MeshLimits {
        max_elements: common.max_elements,
        ..MeshLimits::default()
    }
}

/// The backends named (or the defaults), each of clarabel and osqp once per form of `forms`
/// when it is not empty (the other backends once, in their own form).
pub(crate) fn parse_backends(names: &[BackendKind], forms: &[Form]) -> Result<Vec<BackendKind>> {
    let named: Vec<BackendKind> = if names.is_empty() {
        BackendKind::COMPARE_DEFAULT
            .into_iter()
            .filter(|k| k.available())
            .collect()
    } else {
        names.to_vec()
    };
    let mut kinds: Vec<BackendKind> = Vec::with_capacity(named.len() * 2);
    for kind in named {
        if forms.is_empty() || !kind.has_forms() {
            kinds.push(kind);
        } else {
            for &form in forms {
                kinds.push(kind.with_form(form)?);
            }
        }
    }
    let mut seen = std::collections::HashSet::new();
    kinds.retain(|k| seen.insert(*k));
    anyhow::ensure!(!kinds.is_empty(), "--backends names no backend");
    for k in &kinds {
        anyhow::ensure!(
            k.available(),
            "backend \"{k}\" is not compiled in; rebuild with `--features osqp`"
        );
    }
    Ok(kinds)
}
