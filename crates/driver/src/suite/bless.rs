//! `--bless`: expectations written from the answers of a suite run.
//!
//! For each case that ran, the new expectation takes its figures from the most accurate backend
//! that solved (the smallest worst KKT residual, as `compare` picks its reference); every
//! backend that did not solve becomes an expected failure (its status recorded, an earlier
//! `why` kept); the tolerances of an existing file are kept (they may have been set by hand).
//! When no backend solved, the scene is expected to have no solution (`not-solved`).
//!
//! A file is rewritten only when something changed: a new file, another status, figures that
//! moved by more than the existing file's tolerances, or another set of expected failures.  The
//! files are staged beside their targets and renamed into place only once all are staged.

use std::path::{Path, PathBuf};

use super::check;
use super::expectation::{
    self, Blessed, Expectation, ExpectationError, ExpectedFailure, ExpectedStatus,
};
use super::report::{CaseReport, SuiteReport};
use crate::output::OutputError;

/// What blessing did to one case's expectation.
#[derive(Debug, Clone, PartialEq)]
pub enum Change {
    /// There was no expectation file.
    New,
    /// The file changed; what changed, one sentence each.
    Changed(Vec<String>),
    /// Within the existing file's tolerances: the file is left as it is.
    Unchanged,
    /// The case could not run (its error): nothing to bless from.
    Skipped(String),
}

/// One case's blessing.
#[derive(Debug, Clone)]
pub struct Blessing {
    /// The case's name.
    pub case: String,
    /// The expectation file.
    pub path: PathBuf,
    /// The new expectation (`None` when skipped).
    pub expectation: Option<Expectation>,
    /// What changed.
    pub change: Change,
}

/// The expectation a case's runs give, keeping `old`'s tolerances and reasons.
pub fn expectation_from(
    case: &CaseReport,
    tolerance: f64,
    old: Option<&Expectation>,
) -> Expectation {
    let best = case
        .runs
        .iter()
        .filter(|r| r.status == "solved")
        .min_by(|a, b| a.residuals.worst().total_cmp(&b.residuals.worst()));
    let mut expected_failures = old.map(|o| o.expected_failures.clone()).unwrap_or_default();
    let (status, figures, blessed) = match best {
        Some(run) => {
            for r in &case.runs {
                if r.status == "solved" {
                    expected_failures.remove(&r.backend);
                } else {
                    let why = old
                        .and_then(|o| o.expected_failures.get(&r.backend))
                        .and_then(|f| f.why.clone());
                    expected_failures.insert(
                        r.backend.clone(),
                        ExpectedFailure {
                            status: Some(r.status.clone()),
                            why,
                        },
                    );
                }
            }
            (
                ExpectedStatus::Solved,
                Some(run.figures.clone()),
                Some(Blessed {
                    backend: run.backend.clone(),
                    tolerance,
                    version: env!("CARGO_PKG_VERSION").to_string(),
                }),
            )
        }
        None => {
            expected_failures.clear();
            (ExpectedStatus::NotSolved, None, None)
        }
    };
    Expectation {
        scene: case.title.clone(),
        status,
        figures,
        rtol: old.map(|o| o.rtol.clone()).unwrap_or_default(),
        expected_failures,
        blessed,
    }
}

/// What differs between `old` and `new`, one sentence each (empty: nothing beyond `old`'s
/// tolerances); `load` is the case's Σ|fᵢ|.
pub fn differences(old: &Expectation, new: &Expectation, load: f64) -> Vec<String> {
    let mut out = Vec::new();
    if old.status != new.status {
        out.push(format!(
            "status {} → {}",
            status_name(old.status),
            status_name(new.status)
        ));
    }
    if let (Some(o), Some(n)) = (&old.figures, &new.figures) {
        out.extend(check::compare_figures(old, o, n, load));
        // A tangential force the old file did not record (blessed before it was): a change,
        // so that a bless records it and later runs check it.
        for (i, (po, pn)) in o.contact_forces.iter().zip(&n.contact_forces).enumerate() {
            if let (None, Some(t)) = (po.tangential_force, pn.tangential_force) {
                out.push(format!(
                    "pair {} ({}–{}) tangential force recorded: {t:.9e}",
                    i + 1,
                    pn.bodies[0],
                    pn.bodies[1]
                ));
            }
        }
    }
    let keys = |e: &Expectation| e.expected_failures.keys().cloned().collect::<Vec<_>>();
    if keys(old) != keys(new) {
        let list = |v: Vec<String>| {
            if v.is_empty() {
                "none".to_string()
            } else {
                v.join(", ")
            }
        };
        out.push(format!(
            "expected failures {} → {}",
            list(keys(old)),
            list(keys(new))
        ));
    }
    out
}

fn status_name(s: ExpectedStatus) -> &'static str {
    match s {
        ExpectedStatus::Solved => "solved",
        ExpectedStatus::NotSolved => "not-solved",
    }
}

/// The blessing of every case of `report`.
pub fn blessings(report: &SuiteReport) -> Result<Vec<Blessing>, ExpectationError> {
    let mut out = Vec::with_capacity(report.cases.len());
    for case in &report.cases {
        let path = expectation::path_for(Path::new(&case.scene));
        if let Some(error) = &case.error {
            out.push(Blessing {
                case: case.name.clone(),
                path,
                expectation: None,
                change: Change::Skipped(error.clone()),
            });
            continue;
        }
        // An unreadable old file is a case error (above); a readable one is kept in part.
        let old = Expectation::read(&path)?;
        let new = expectation_from(case, report.tolerance, old.as_ref());
        let change = match &old {
            None => Change::New,
            Some(old) => {
                let d = differences(old, &new, case.load);
                if d.is_empty() {
                    Change::Unchanged
                } else {
                    Change::Changed(d)
                }
            }
        };
        out.push(Blessing {
            case: case.name.clone(),
            path,
            expectation: Some(new),
            change,
        });
    }
    Ok(out)
}

/// Writes the new and changed expectations of `blessings`: each staged as a temporary file
/// beside its target, then all renamed into place.  Returns the paths written.
pub fn write(blessings: &[Blessing]) -> Result<Vec<PathBuf>, OutputError> {
    let mut staged = Vec::new();
    for b in blessings {
        let (Some(e), Change::New | Change::Changed(_)) = (&b.expectation, &b.change) else {
            continue;
        };
        let dir = b.path.parent().unwrap_or(Path::new("."));
        let io = |source| OutputError::Io {
            path: b.path.clone(),
            source,
        };
        let mut file = tempfile::Builder::new()
            .prefix(".signorini-bless-")
            .tempfile_in(dir)
            .map_err(io)?;
        std::io::Write::write_all(&mut file, e.to_json().as_bytes()).map_err(io)?;
        file.as_file().sync_all().map_err(io)?;
        staged.push((file, b.path.clone()));
    }
    let mut written = Vec::with_capacity(staged.len());
    for (file, path) in staged {
        file.persist(&path).map_err(|e| OutputError::Io {
            path: path.clone(),
            source: e.error,
        })?;
        written.push(path);
    }
    Ok(written)
}
