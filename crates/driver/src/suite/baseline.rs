//! `--baseline OLD/suite.json`: per backend, which cases got slower or faster than an earlier
//! run and which changed status.
//!
//! Speed is compared as time ÷ floor, so that the machine's speed (and its load, when both the
//! floor and the solve feel it) cancels: a case is *slower* when its ratio grew by more than
//! `factor` (default 1.5×) *and* its solve time by more than [`NOISE_S`] (0.1 ms: below it the
//! timer and the scheduler of a shared machine move times by more than 1.5×).  The suite's times
//! are medians of `--repeat` solves (default 3): on this machine, three runs of the seed suite
//! differed by at most 1.29× in time ÷ floor with medians of three, and by up to 22× (a 0.4 ms
//! solve preempted for 8 ms) with single solves.  Only runs that solved in both are compared for
//! speed.  A status change is any change of the core-checked
//! status.  Cases whose scene file changed (another SHA-256) are compared all the same and
//! flagged.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::Deserialize;

pub use super::changes::{BaselineChange, BaselineReport, ChangeKind};
use super::report::SuiteReport;

/// Differences of solve time below this many seconds are never called slower or faster.
pub const NOISE_S: f64 = 1e-4;

/// The default factor of time ÷ floor beyond which a case is slower or faster.
pub const DEFAULT_FACTOR: f64 = 1.5;

/// An earlier `suite.json` could not be used.
#[derive(Debug, thiserror::Error)]
pub enum BaselineError {
    /// The file could not be read.
    #[error("cannot read the baseline {}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// Not a `suite.json`.
    #[error("{} is not a suite.json of `signorini suite`", path.display())]
    Parse {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: serde_json::Error,
    },
}

/// The part of an earlier `suite.json` a comparison needs.
#[derive(Debug, Clone, Deserialize)]
struct OldSuite {
    tolerance: f64,
    cases: Vec<OldCase>,
}

#[derive(Debug, Clone, Deserialize)]
struct OldCase {
    name: String,
    #[serde(default)]
    sha256: String,
    #[serde(default)]
    error: Option<String>,
    #[serde(default)]
    runs: Vec<OldRun>,
}

#[derive(Debug, Clone, Deserialize)]
struct OldRun {
    backend: String,
    status: String,
    solve_s: Option<f64>,
    ratio_to_floor: Option<f64>,
}

/// An earlier run's `suite.json`, read (before the suite runs, so that a bad file is refused
/// at once).
#[derive(Debug, Clone)]
pub struct Baseline {
    path: PathBuf,
    old: OldSuite,
}

impl Baseline {
    /// Reads the `suite.json` at `path`.
    pub fn read(path: &Path) -> Result<Baseline, BaselineError> {
        let text = std::fs::read_to_string(path).map_err(|source| BaselineError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let old: OldSuite = serde_json::from_str(&text).map_err(|source| BaselineError::Parse {
            path: path.to_path_buf(),
            source,
        })?;
        Ok(Baseline {
            path: path.to_path_buf(),
            old,
        })
    }
}

/// Compares `report` with `baseline` (see the module's docs).
pub fn compare(report: &SuiteReport, baseline: &Baseline, factor: f64) -> BaselineReport {
    let (old, path) = (&baseline.old, &baseline.path);
    let old_cases: BTreeMap<&str, &OldCase> =
        old.cases.iter().map(|c| (c.name.as_str(), c)).collect();
    let mut changes = Vec::new();
    let mut new_cases = Vec::new();
    for case in &report.cases {
        let Some(before) = old_cases.get(case.name.as_str()) else {
            new_cases.push(case.name.clone());
            continue;
        };
        let scene_changed = before.sha256 != case.sha256;
        if before.error.is_some() != case.error.is_some() {
            let state = |e: bool| if e { "error" } else { "ran" };
            changes.push(BaselineChange {
                case: case.name.clone(),
                backend: "(case)".to_string(),
                change: ChangeKind::Status {
                    before: state(before.error.is_some()).to_string(),
                    after: state(case.error.is_some()).to_string(),
                },
                scene_changed,
            });
        }
        for run in &case.runs {
            let Some(prev) = before.runs.iter().find(|r| r.backend == run.backend) else {
                continue;
            };
            if prev.status != run.status {
                changes.push(BaselineChange {
                    case: case.name.clone(),
                    backend: run.backend.clone(),
                    change: ChangeKind::Status {
                        before: prev.status.clone(),
                        after: run.status.clone(),
                    },
                    scene_changed,
                });
                continue;
            }
            if run.status != "solved" {
                continue;
            }
            let (Some(r0), Some(t0)) = (prev.ratio_to_floor, prev.solve_s) else {
                continue;
            };
            let (r1, t1) = (run.ratio_to_floor, run.solve_s);
            if !(r0 > 0.0 && r1 > 0.0 && (t1 - t0).abs() > NOISE_S) {
                continue;
            }
            let change = if r1 > factor * r0 {
                ChangeKind::Slower {
                    before: r0,
                    after: r1,
                }
            } else if r0 > factor * r1 {
                ChangeKind::Faster {
                    before: r0,
                    after: r1,
                }
            } else {
                continue;
            };
            changes.push(BaselineChange {
                case: case.name.clone(),
                backend: run.backend.clone(),
                change,
                scene_changed,
            });
        }
    }
    let names: std::collections::BTreeSet<&str> =
        report.cases.iter().map(|c| c.name.as_str()).collect();
    let missing_cases = old
        .cases
        .iter()
        .filter(|c| !names.contains(c.name.as_str()))
        .map(|c| c.name.clone())
        .collect();
    BaselineReport {
        path: path.display().to_string(),
        factor,
        tolerance: old.tolerance,
        changes,
        new_cases,
        missing_cases,
    }
}

/// The comparison as text, grouped by backend.
pub fn text(b: &BaselineReport, tolerance: f64) -> String {
    let mut t = format!(
        "against the baseline {} (factor {} on time ÷ floor):\n",
        b.path, b.factor
    );
    if b.tolerance != tolerance {
        t.push_str(&format!(
            "  note: the baseline ran at tol {:e}, this run at {:e}: times are not comparable\n",
            b.tolerance, tolerance
        ));
    }
    let mut by_backend: BTreeMap<&str, Vec<&BaselineChange>> = BTreeMap::new();
    for c in &b.changes {
        by_backend.entry(c.backend.as_str()).or_default().push(c);
    }
    if by_backend.is_empty() {
        t.push_str("  no case changed status or speed\n");
    }
    for (backend, list) in by_backend {
        t.push_str(&format!("  {backend}:\n"));
        for c in list {
            let flag = if c.scene_changed {
                " (scene file changed)"
            } else {
                ""
            };
            let what = match &c.change {
                ChangeKind::Slower { before, after } => {
                    format!(
                        "slower ×{:.2} (÷floor {before:.2} → {after:.2})",
                        after / before
                    )
                }
                ChangeKind::Faster { before, after } => {
                    format!(
                        "faster ×{:.2} (÷floor {before:.2} → {after:.2})",
                        before / after
                    )
                }
                ChangeKind::Status { before, after } => format!("status {before} → {after}"),
            };
            t.push_str(&format!("    {}: {what}{flag}\n", c.case));
        }
    }
    if !b.new_cases.is_empty() {
        t.push_str(&format!("  new cases: {}\n", b.new_cases.join(", ")));
    }
    if !b.missing_cases.is_empty() {
        t.push_str(&format!(
            "  cases of the baseline not run: {}\n",
            b.missing_cases.join(", ")
        ));
    }
    t
}
