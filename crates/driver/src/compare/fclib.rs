//! `compare --fclib FILE`: an FCLIB global problem (see [`crate::fclib_import`]) through every
//! backend, as `compare --qp` runs QP files, each answer also measured against the file's
//! stored `/solution` when it has one.

use std::path::Path;
use std::time::Instant;

use signorini_core::model::Model;
use signorini_core::qp::SolveOptions;
use signorini_core::solve::{self, Solution};

use super::{
    bare_model, componentwise_difference, file_report, run_backends, CompareReport, Judge,
    QpCompareError,
};
use crate::backends::BackendKind;
use crate::fclib_import::{self, ImportedQp, StoredDifference};

/// The bare model of an imported QP: its unknowns all free, its rows' gaps and the Coulomb
/// links of its tangential rows (what the Coulomb solve reads from a model).
fn model_of(imported: &ImportedQp) -> Model {
    let mut model = bare_model(&imported.qp);
    model.gap = imported.qp.gap.clone();
    model.tangential = imported.tangential.clone();
    model
}

/// Reads the FCLIB file `path` and runs every backend of `kinds` on its problem: the floor,
/// scaling, residual check and rows of [`super::compare_qp`]; Coulomb contacts through the
/// Coulomb solve [`SolveOptions::coulomb`] chooses; each row's `stored` the difference of its
/// (v, r) to the file's `/solution`.
pub fn compare_fclib(
    path: &Path,
    kinds: &[BackendKind],
    options: &SolveOptions,
    progress: impl FnMut(&str),
) -> Result<CompareReport, QpCompareError> {
    let start = Instant::now();
    let file = fclib_import::read(path)?;
    let imported = file.to_qp(path)?;
    let read_s = start.elapsed().as_secs_f64();
    if imported.qp.rows() == 0 {
        return Err(QpCompareError::NoRows(path.display().to_string()));
    }
    if let Some(budget) = signorini_core::memory::available_bytes() {
        signorini_core::preflight::check_factor_memory(&imported.qp, budget)?;
    }
    let model = model_of(&imported);
    let force_scale = imported.qp.load.iter().map(|f| f.abs()).sum::<f64>();
    let (dofs, constraints) = (imported.qp.dofs(), imported.qp.rows());
    let stored = |s: &Solution| -> StoredDifference {
        let ours = file.problem.solution(&model, s);
        file.solution
            .as_ref()
            .map(|theirs| StoredDifference::of(&ours, theirs))
            .unwrap_or(StoredDifference {
                v: f64::NAN,
                r: f64::NAN,
            })
    };
    let judge = Judge {
        force_scale,
        difference: componentwise_difference,
        check: &std::convert::identity,
        stored: file
            .solution
            .is_some()
            .then_some(&stored as &dyn Fn(&Solution) -> StoredDifference),
    };
    let qp = solve::ScaledQp::new(imported.qp);
    let runs = run_backends(&model, &qp, kinds, options, &judge, progress)?;
    let source = path.display().to_string();
    let contacts = file.problem.mu.len();
    let scene = format!(
        "FCLIB problem {source}{} ({contacts} contacts, {} with friction{})",
        if file.problem.title.is_empty() {
            String::new()
        } else {
            format!(" \"{}\"", file.problem.title)
        },
        model.tangential.len(),
        if file.solution.is_some() {
            ", stored solution"
        } else {
            ""
        }
    );
    Ok(file_report(
        scene,
        source,
        (dofs, constraints),
        options.tol,
        read_s,
        runs,
    ))
}
