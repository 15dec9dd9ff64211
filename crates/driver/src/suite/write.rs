//! The suite's files — `suite.json`, `suite.csv`, `suite.xml` (JUnit) and `suite.svg` (the
//! performance profile, when any case was answered correctly) — written as one set (see
//! [`crate::outdir`]): under the directory's lock, staged and moved into place together,
//! `suite.json` last.

use std::path::{Path, PathBuf};

use super::junit::junit_xml;
use super::profile::render_profile_svg;
use super::report::SuiteReport;
use crate::outdir::{DirLock, OutputSet};
use crate::output::OutputError;

/// The files of a suite run, the primary (`suite.json`) first.
pub const SUITE_FILES: [&str; 4] = ["suite.json", "suite.csv", "suite.xml", "suite.svg"];

/// `x` in the CSV: shortest round-trip form, empty for NaN.
fn num(x: f64) -> String {
    if x.is_finite() {
        format!("{x:e}")
    } else {
        String::new()
    }
}

/// Writes the suite's files into `dir` (created if missing).  Returns the paths written.
pub fn write(dir: &Path, report: &SuiteReport) -> Result<Vec<PathBuf>, OutputError> {
    let lock = DirLock::acquire(dir)?;
    let mut set = OutputSet::new(&lock, Some(SUITE_FILES[0]), &SUITE_FILES)?;
    set.write(SUITE_FILES[0], |w| {
        serde_json::to_writer_pretty(&mut *w, report).map_err(std::io::Error::other)?;
        writeln!(w)
    })?;
    set.write(SUITE_FILES[1], |w| {
        let mut csv = csv::Writer::from_writer(w);
        csv.write_record([
            "case",
            "backend",
            "verdict",
            "status",
            "backend_status",
            "iterations",
            "solve_s",
            "floor_s",
            "ratio_to_floor",
            "objective",
            "max_displacement",
            "max_penetration",
            "stationarity",
            "complementarity",
            "min_multiplier",
            "dofs",
            "constraints",
            "notes",
        ])?;
        for case in &report.cases {
            if let Some(error) = &case.error {
                let mut record = vec![String::new(); 18];
                record[0] = case.name.clone();
                record[2] = "fail".to_string();
                record[3] = "error".to_string();
                record[17] = error.clone();
                csv.write_record(&record)?;
                continue;
            }
            for r in &case.runs {
                csv.write_record([
                    case.name.clone(),
                    r.backend.clone(),
                    r.verdict.as_str().to_string(),
                    r.status.clone(),
                    r.backend_status.clone(),
                    r.iterations.to_string(),
                    num(r.solve_s),
                    num(case.floor_s),
                    num(r.ratio_to_floor),
                    num(r.figures.objective),
                    num(r.figures.max_displacement),
                    num(r.residuals.max_penetration),
                    num(r.residuals.stationarity),
                    num(r.residuals.complementarity),
                    num(r.residuals.min_multiplier),
                    case.dofs.to_string(),
                    case.constraints.to_string(),
                    r.notes.join("; "),
                ])?;
            }
        }
        csv.flush()
    })?;
    let xml = junit_xml(report);
    set.write(SUITE_FILES[2], |w| w.write_all(xml.as_bytes()))?;
    if let Some(svg) = render_profile_svg(report)? {
        set.write(SUITE_FILES[3], |w| w.write_all(svg.as_bytes()))?;
    }
    set.commit()
}
