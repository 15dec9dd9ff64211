//! The performance profile of a suite (stub; being written).

use crate::output::OutputError;
use crate::suite::report::SuiteReport;

/// The performance profile as SVG (`None` when nothing to draw).
pub fn render_profile_svg(report: &SuiteReport) -> Result<Option<String>, OutputError> {
    let _ = report;
    Ok(None)
}
