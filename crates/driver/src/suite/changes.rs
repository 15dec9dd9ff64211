//! What a comparison with a baseline found (`suite.json`'s `baseline`): the types the report
//! holds and [`super::baseline`] computes, apart from both so that neither imports the other.

use schemars::JsonSchema;
use serde::Serialize;

/// What changed for one backend on one case.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum ChangeKind {
    /// Time ÷ floor grew by more than the factor.
    Slower {
        /// Time ÷ floor before.
        before: f64,
        /// Time ÷ floor now.
        after: f64,
    },
    /// Time ÷ floor fell by more than the factor.
    Faster {
        /// Time ÷ floor before.
        before: f64,
        /// Time ÷ floor now.
        after: f64,
    },
    /// The status changed.
    Status {
        /// The status before.
        before: String,
        /// The status now.
        after: String,
    },
}

/// One change against the baseline.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct BaselineChange {
    /// The case.
    pub case: String,
    /// The backend.
    pub backend: String,
    /// What changed.
    #[serde(flatten)]
    pub change: ChangeKind,
    /// The case's scene file changed since the baseline.
    pub scene_changed: bool,
}

/// The comparison with a baseline (`suite.json`'s `baseline`).
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct BaselineReport {
    /// The baseline file.
    pub path: String,
    /// The factor of time ÷ floor.
    pub factor: f64,
    /// The baseline's tolerance (speed comparisons across tolerances mean little).
    pub tolerance: f64,
    /// Every change, by case then backend.
    pub changes: Vec<BaselineChange>,
    /// Cases of this run the baseline does not have.
    pub new_cases: Vec<String>,
    /// Cases of the baseline this run does not have.
    pub missing_cases: Vec<String>,
}

impl BaselineReport {
    /// The number of slower runs.
    pub fn slower(&self) -> usize {
        self.changes
            .iter()
            .filter(|c| matches!(c.change, ChangeKind::Slower { .. }))
            .count()
    }
}
