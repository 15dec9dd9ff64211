//! `NAME.expected.json`: what a scene of a suite is expected to give, beside `NAME.toml`.
//!
//! ```json
//! {
//!   "scene": "Experiment 2b: …",
//!   "status": "solved",
//!   "figures": {
//!     "objective": -1.23e-7,
//!     "max_displacement": 4.56e-3,
//!     "contact_forces": [{ "bodies": ["upper", "lower"], "normal_force": 7.8e-5 }],
//!     "probes": [{ "name": "tip", "displacement": [1e-4, -2e-3] }]
//!   },
//!   "rtol": { "default": 1e-6, "objective": 1e-8 },
//!   "expected_failures": { "osqp": { "status": "inaccurate", "why": "ADMM stalls at contrast 1e6" } },
//!   "blessed": { "backend": "clarabel", "tolerance": 1e-9, "version": "0.1.0" }
//! }
//! ```
//!
//! * `status` is `"solved"` (every backend not listed in `expected_failures` must solve and
//!   match the figures) or `"not-solved"` (the scene has no solution — a body free to slide —
//!   and every backend must say so; `solved` is then a regression, whatever the figures).
//! * `rtol`: relative tolerances of the figures; `default` applies where no key of its own is
//!   given ([`Tolerances`]).  Each comparison's scale is a fixed figure of the expectation or of
//!   the problem's data, never the measured value itself (see [`crate::suite::check`]).
//! * `expected_failures`: backends known not to solve this scene (with the status seen when
//!   blessed, and why).  Their failure is not a regression; their solving is reported.
//! * `blessed`: which backend, tolerance and program version the figures came from.
//!
//! Unknown keys are refused (a misspelt `"rtol"` key would otherwise silently fall back to the
//! default), naming the key, the file, its line and column.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::report::Figures;

/// The default relative tolerance of every figure: a thousand times the suite's default KKT
/// tolerance 1e-9.  A backend answer meeting relative KKT residuals ε is within about κ·ε of
/// the exact one (κ the conditioning of the scene's QP), and the backends' answers on the seed
/// and hard scenes at ε = 1e-9 agree to 1e-9 relative (max |Δu| in BENCHMARKS.md); a changed
/// mesh, load or formula moves the figures by 1e-4 and more.
pub const DEFAULT_RTOL: f64 = 1e-6;

/// The suffix of an expectation file: `NAME.expected.json` beside `NAME.toml`.
pub const SUFFIX: &str = ".expected.json";

/// What a scene is expected to end with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum ExpectedStatus {
    /// The scene has a solution, which the figures describe.
    Solved,
    /// The scene has no solution (ill-posed): every backend must report a non-solved status.
    NotSolved,
}

/// Relative tolerances of an expectation's figures.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Tolerances {
    /// For every figure without a key of its own.
    #[serde(default = "default_rtol")]
    pub default: f64,
    /// Of the objective, relative to the expected objective's magnitude.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub objective: Option<f64>,
    /// Of the largest displacement, relative to the expected one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_displacement: Option<f64>,
    /// Of each pair's normal force, relative to the larger of the expected force and the
    /// problem's load Σ|fᵢ|.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_force: Option<f64>,
    /// Of each probe's displacement (largest component), relative to the larger of its expected
    /// magnitude and the expected largest displacement.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub probe: Option<f64>,
}

fn default_rtol() -> f64 {
    DEFAULT_RTOL
}

impl Default for Tolerances {
    fn default() -> Self {
        Tolerances {
            default: DEFAULT_RTOL,
            objective: None,
            max_displacement: None,
            contact_force: None,
            probe: None,
        }
    }
}

impl Tolerances {
    /// The tolerance of the objective.
    pub fn objective(&self) -> f64 {
        self.objective.unwrap_or(self.default)
    }
    /// The tolerance of the largest displacement.
    pub fn max_displacement(&self) -> f64 {
        self.max_displacement.unwrap_or(self.default)
    }
    /// The tolerance of a pair's normal force.
    pub fn contact_force(&self) -> f64 {
        self.contact_force.unwrap_or(self.default)
    }
    /// The tolerance of a probe.
    pub fn probe(&self) -> f64 {
        self.probe.unwrap_or(self.default)
    }

    /// The first tolerance that is not a finite number in (0, 1), with its key.
    fn invalid(&self) -> Option<(&'static str, f64)> {
        [
            ("default", Some(self.default)),
            ("objective", self.objective),
            ("max_displacement", self.max_displacement),
            ("contact_force", self.contact_force),
            ("probe", self.probe),
        ]
        .into_iter()
        .find_map(|(key, v)| {
            v.filter(|t| !(t.is_finite() && *t > 0.0 && *t < 1.0))
                .map(|t| (key, t))
        })
    }
}

/// A backend known not to solve the scene.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ExpectedFailure {
    /// The status it ended with when the expectation was blessed (informational: another
    /// non-solved status is still an expected failure, and is noted).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub status: Option<String>,
    /// Why it fails, in a sentence (kept by `--bless`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub why: Option<String>,
}

/// Where the expectation's figures came from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Blessed {
    /// The backend whose answer was stored (the solved one with the smallest residuals).
    pub backend: String,
    /// The KKT tolerance of that run.
    pub tolerance: f64,
    /// The program version that blessed it.
    pub version: String,
}

/// The content of `NAME.expected.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Expectation {
    /// The scene's title when blessed (informational).
    #[serde(default)]
    pub scene: String,
    /// What every backend not in `expected_failures` must end with.
    pub status: ExpectedStatus,
    /// The answer's figures (required when `status` is `solved`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub figures: Option<Figures>,
    /// Relative tolerances of the figures.
    #[serde(default)]
    pub rtol: Tolerances,
    /// Backends known not to solve the scene, by name.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub expected_failures: BTreeMap<String, ExpectedFailure>,
    /// Where the figures came from.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub blessed: Option<Blessed>,
}

/// An expectation file that cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum ExpectationError {
    /// The file could not be read.
    #[error("cannot read {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// Not JSON, or not an expectation (serde names the key, line and column).
    #[error("{path}: {source}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: serde_json::Error,
    },
    /// A value that parses but cannot be meant.
    #[error("{path}: {what}")]
    Invalid {
        /// The file.
        path: PathBuf,
        /// What is wrong, naming the key.
        what: String,
    },
}

/// The expectation file of the scene at `scene` (`x/NAME.toml` → `x/NAME.expected.json`).
pub fn path_for(scene: &Path) -> PathBuf {
    let stem = scene
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    scene.with_file_name(format!("{stem}{SUFFIX}"))
}

impl Expectation {
    /// Reads and checks `path`; `Ok(None)` when there is no such file.
    pub fn read(path: &Path) -> Result<Option<Expectation>, ExpectationError> {
        let text = match std::fs::read_to_string(path) {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(source) => {
                return Err(ExpectationError::Io {
                    path: path.to_path_buf(),
                    source,
                })
            }
        };
        let e = Self::parse(&text).map_err(|err| match err {
            ParseFailure::Json(source) => ExpectationError::Parse {
                path: path.to_path_buf(),
                source,
            },
            ParseFailure::Invalid(what) => ExpectationError::Invalid {
                path: path.to_path_buf(),
                what,
            },
        })?;
        Ok(Some(e))
    }

    /// Parses an expectation from JSON text and checks its values.
    fn parse(text: &str) -> Result<Expectation, ParseFailure> {
        let e: Expectation = serde_json::from_str(text).map_err(ParseFailure::Json)?;
        if let Some((key, t)) = e.rtol.invalid() {
            return Err(ParseFailure::Invalid(format!(
                "rtol.{key} = {t} must be a number in (0, 1)"
            )));
        }
        match (&e.status, &e.figures) {
            (ExpectedStatus::Solved, None) => {
                return Err(ParseFailure::Invalid(
                    "status \"solved\" needs \"figures\" to check the answer against".to_string(),
                ))
            }
            (ExpectedStatus::Solved, Some(f)) => {
                let finite = |x: f64| x.is_finite();
                let bad = if !finite(f.objective) {
                    Some("figures.objective".to_string())
                } else if !(f.max_displacement.is_finite() && f.max_displacement >= 0.0) {
                    Some("figures.max_displacement".to_string())
                } else if let Some(i) = f
                    .contact_forces
                    .iter()
                    .position(|p| !finite(p.normal_force))
                {
                    Some(format!("figures.contact_forces[{i}].normal_force"))
                } else if let Some(i) = f
                    .contact_forces
                    .iter()
                    .position(|p| p.tangential_force.is_some_and(|t| !finite(t)))
                {
                    Some(format!("figures.contact_forces[{i}].tangential_force"))
                } else {
                    f.probes
                        .iter()
                        .position(|p| !p.displacement.iter().all(|x| x.is_finite()))
                        .map(|i| format!("figures.probes[{i}].displacement"))
                };
                if let Some(key) = bad {
                    return Err(ParseFailure::Invalid(format!(
                        "{key} must be a finite number (non-negative for a magnitude)"
                    )));
                }
            }
            (ExpectedStatus::NotSolved, _) => {}
        }
        Ok(e)
    }

    /// The expectation as the JSON text written to its file (pretty, with a final newline).
    pub fn to_json(&self) -> String {
        // Serialising plain data with string keys cannot fail.
        let mut text = serde_json::to_string_pretty(self).unwrap_or_default();
        text.push('\n');
        text
    }
}

enum ParseFailure {
    Json(serde_json::Error),
    Invalid(String),
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Expectation, String> {
        Expectation::parse(text).map_err(|e| match e {
            ParseFailure::Json(e) => e.to_string(),
            ParseFailure::Invalid(s) => s,
        })
    }

    const SOLVED: &str = r#"{
        "status": "solved",
        "figures": {"objective": -1.0, "max_displacement": 2.0,
                    "contact_forces": [{"bodies": ["a", "b"], "normal_force": 3.0}],
                    "probes": [{"name": "p", "displacement": [0.5, -0.5]}]}
    }"#;

    #[test]
    fn a_minimal_expectation_reads_with_the_default_tolerance() {
        let e = parse(SOLVED).unwrap();
        assert_eq!(e.status, ExpectedStatus::Solved);
        assert_eq!(e.rtol.objective(), DEFAULT_RTOL);
        assert_eq!(e.rtol.probe(), DEFAULT_RTOL);
        let again = parse(&e.to_json()).unwrap();
        assert_eq!(again, e);
    }

    #[test]
    fn a_misspelt_key_is_refused_by_name() {
        let text = SOLVED.replace("\"status\"", "\"rtol\": {\"objetive\": 1e-3}, \"status\"");
        let err = parse(&text).unwrap_err();
        assert!(err.contains("objetive"), "{err}");
        let err = parse(&SOLVED.replace("\"figures\"", "\"figure\"")).unwrap_err();
        assert!(err.contains("figure"), "{err}");
    }

    #[test]
    fn impossible_values_are_refused_naming_the_key() {
        let text = SOLVED.replace("\"status\"", "\"rtol\": {\"probe\": 2}, \"status\"");
        assert!(parse(&text).unwrap_err().contains("rtol.probe"));
        let text = SOLVED.replace("\"status\"", "\"rtol\": {\"default\": -1e-6}, \"status\"");
        assert!(parse(&text).unwrap_err().contains("rtol.default"));
        let err = parse(r#"{"status": "solved"}"#).unwrap_err();
        assert!(err.contains("figures"), "{err}");
        let err = parse(&SOLVED.replace("2.0", "-2.0")).unwrap_err();
        assert!(err.contains("figures.max_displacement"), "{err}");
        let err = parse(r#"{"status": "maybe"}"#).unwrap_err();
        assert!(err.contains("maybe"), "{err}");
        // A scene without a solution needs no figures.
        assert!(parse(r#"{"status": "not-solved"}"#).is_ok());
    }

    #[test]
    fn the_file_sits_beside_its_scene() {
        assert_eq!(
            path_for(Path::new("fixtures/seed/exp2b.toml")),
            Path::new("fixtures/seed/exp2b.expected.json")
        );
    }
}
