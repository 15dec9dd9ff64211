//! One scene as one qpbenchmark problem: `min ½xᵀPx + qᵀx  s.t.  Gx ≤ h` with P = A, q = −f,
//! G = B, h = g (the nondimensionalised QP the backends see, or the user's units with `raw`),
//! box rows (Tresca friction) rewritten through [`AuxiliaryForm`], and the reference answer of
//! our `auto` backend carried along.

use std::path::Path;
use std::time::Instant;

use signorini_core::mesh::MeshLimits;
use signorini_core::qp::{
    kkt_residuals, row_sets, AuxiliaryForm, CscMatrix, KktResiduals, QpProblem, QpScaling,
    QpStatus, RowSet, SolveOptions,
};
use signorini_core::scene::{Friction, Scene};
use signorini_core::solve::{solve_scaled, ScaledQp};

use crate::backends::{make_backend, BackendKind};
use crate::run;

use super::QpsetError;

/// What kind of contact problem a scene gives.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ProblemKind {
    /// Normal rows only.
    Frictionless,
    /// Tresca friction: box rows, exported through the auxiliary form.
    Tresca,
}

/// The reference answer of a problem (our `auto` backend at the set's tolerance, `solved`).
#[derive(Debug, Clone, serde::Serialize)]
pub struct Reference {
    /// The backend `auto` ended with.
    pub backend: String,
    /// Its iterations.
    pub iterations: usize,
    /// Its solve time, seconds.
    pub solve_s: f64,
    /// Our KKT residuals of the answer on the original (not auxiliary) problem.
    pub residuals: KktResiduals,
    /// x of the exported problem (with the auxiliary unknowns tᵢ = |rᵢ| for Tresca).
    #[serde(skip)]
    pub x: Vec<f64>,
    /// Multipliers z ≥ 0 of the exported rows Gx ≤ h.
    #[serde(skip)]
    pub z: Vec<f64>,
    /// ½xᵀPx + qᵀx at `x`.
    pub objective: f64,
}

/// One exported problem.
#[derive(Debug, Clone)]
pub struct ContactQp {
    /// Scene title.
    pub title: String,
    /// Frictionless or Tresca.
    pub kind: ProblemKind,
    /// The units x = `displacement`·x̂, A = `stiffness`·Â of the nondimensionalised form
    /// (also given for a raw export, where they were not applied).
    pub scaling: QpScaling,
    /// Whether the data are in the user's units (`--raw`).
    pub raw: bool,
    /// Unknowns and rows of the contact QP before the auxiliary rewriting.
    pub original_size: (usize, usize),
    /// Time to mesh and assemble, seconds.
    pub prepare_s: f64,
    /// The exported QP: P = `problem.stiffness`, q = −`problem.load`, G = `problem.constraints`,
    /// h = `problem.gap`, one-sided rows only.
    pub problem: QpProblem,
    /// The reference: `auto`'s answer, `solved` (a scene it does not solve is skipped).
    pub reference: Reference,
}

/// A scene that is not one QP, or has no QP to solve.
#[derive(Debug, Clone)]
pub enum Built {
    /// The scene's problem.
    Problem(Box<ContactQp>),
    /// Why the scene is left out.
    Skipped(String),
}

/// Scales every element size of `scene` so that it has about `target` unknowns given that it has
/// `dofs` now (unknowns grow as h⁻² in 2D); a scene already that large is left as it is.
pub fn refined(scene: &Scene, dofs: usize, target: usize) -> Option<Scene> {
    if dofs == 0 || dofs >= target {
        return None;
    }
    let factor = (dofs as f64 / target as f64).sqrt();
    let mut s = scene.clone();
    for b in &mut s.bodies {
        b.hmax *= factor;
        b.refine.iter_mut().for_each(|r| r.hmax *= factor);
    }
    Some(s)
}

/// Why `scene`'s model is not a single QP, if it is not.
fn not_one_qp(model: &signorini_core::model::Model) -> Option<String> {
    if model
        .tangential
        .iter()
        .any(|t| matches!(t.law, Friction::Coulomb(_)))
    {
        return Some(
            "Coulomb friction: a fixed point over Tresca problems (each bound depends on the normal force), not one QP".into(),
        );
    }
    if model.path.as_ref().is_some_and(|p| p.increments.len() > 1) {
        return Some(
            "a load path: one QP per increment, each depending on the previous one".into(),
        );
    }
    None
}

/// Builds the problem of the scene at `path` (refined to about `large` unknowns when asked).
pub fn build(
    path: &Path,
    raw: bool,
    tol: f64,
    limits: &MeshLimits,
    large: Option<usize>,
) -> Result<Built, QpsetError> {
    let scene_error = |e: String| QpsetError::Scene {
        path: path.to_path_buf(),
        reason: e,
    };
    let mut scene = run::load_scene(Some(path)).map_err(|e| scene_error(e.to_string()))?;
    let t0 = Instant::now();
    let mut prepared = run::prepare(&scene, limits).map_err(|e| scene_error(format!("{e:#}")))?;
    if let Some(why) = not_one_qp(&prepared.model) {
        return Ok(Built::Skipped(why));
    }
    if let Some(finer) = large.and_then(|t| refined(&scene, prepared.qp.dofs(), t)) {
        prepared = run::prepare(&finer, limits).map_err(|e| scene_error(format!("{e:#}")))?;
        scene = finer;
    }
    let prepare_s = t0.elapsed().as_secs_f64();
    if prepared.qp.rows() == 0 {
        return Ok(Built::Skipped(
            "no contact row: one linear solve, not a QP".into(),
        ));
    }
    let model = prepared.model;
    let original = prepared.qp;
    let original_size = (original.dofs(), original.rows());
    let scaled = ScaledQp::new(original.clone());
    let units = scaled.scaling;
    let options = SolveOptions {
        tol,
        ..SolveOptions::default()
    };
    let mut backend = make_backend(BackendKind::Auto).map_err(|e| scene_error(e.to_string()))?;
    let solution = solve_scaled(&model, &scaled, backend.as_mut(), &options)
        .map_err(|e| scene_error(e.to_string()))?;
    let base = if raw { original } else { scaled.problem };
    // The answer in the exported problem's units.
    let (x_unit, z_unit) = if raw {
        (1.0, 1.0)
    } else {
        (units.displacement, units.stiffness * units.displacement)
    };
    let x: Vec<f64> = model
        .free
        .iter()
        .map(|&d| solution.displacement[d] / x_unit)
        .collect();
    let z: Vec<f64> = solution.multipliers.iter().map(|l| l / z_unit).collect();
    let residuals = kkt_residuals(&base, &x, &z);
    let tresca = base
        .blocks
        .iter()
        .any(|b| b.kind() == signorini_core::qp::BlockKind::Box);
    let (problem, x, z) = if tresca {
        auxiliary(&base, x, z)?
    } else {
        (base, x, z)
    };
    if solution.status != QpStatus::Solved {
        // A benchmark problem needs a known answer (qpbenchmark counts success against it).
        return Ok(Built::Skipped(format!(
            "no reference: auto ended {} at tol {tol:e}{}",
            solution.status,
            solution.message_in_parentheses()
        )));
    }
    let objective = problem.objective(&x);
    let reference = Reference {
        backend: solution.backend.clone(),
        iterations: solution.iterations,
        solve_s: solution.solve_time.as_secs_f64(),
        residuals,
        x,
        z,
        objective,
    };
    Ok(Built::Problem(Box::new(ContactQp {
        title: scene.title.clone(),
        kind: if tresca {
            ProblemKind::Tresca
        } else {
            ProblemKind::Frictionless
        },
        scaling: units,
        raw,
        original_size,
        prepare_s,
        problem,
        reference,
    })))
}

/// The auxiliary form of a problem with box rows, and the answer (x, λ) carried over: tᵢ = |rᵢ|
/// for each box row of bound sᵢ > 0, its two rows' multipliers μ± = (sᵢ ± λᵢ)/2 (so that
/// μ⁺ − μ⁻ = λᵢ and μ⁺ + μ⁻ = sᵢ, the auxiliary form's stationarity in tᵢ).
fn auxiliary(
    problem: &QpProblem,
    x: Vec<f64>,
    lambda: Vec<f64>,
) -> Result<(QpProblem, Vec<f64>, Vec<f64>), QpsetError> {
    let form = AuxiliaryForm::of(problem).map_err(|e| QpsetError::Auxiliary(e.to_string()))?;
    let r: Vec<f64> = signorini_core::qp::mat_vec(&problem.constraints, &x)
        .iter()
        .zip(&problem.gap)
        .map(|(bx, g)| bx - g)
        .collect();
    let sets: Vec<RowSet> = row_sets(&problem.blocks).collect();
    let mut x_aux = x;
    let mut kept = Vec::new();
    let mut split = Vec::new();
    for (i, set) in sets.iter().enumerate() {
        match *set {
            RowSet::NonNegative => kept.push(lambda[i]),
            RowSet::Box(s) if s > 0.0 => {
                x_aux.push(r[i].abs());
                split.push(0.5 * (s + lambda[i]));
                split.push(0.5 * (s - lambda[i]));
            }
            RowSet::Box(_) => {}
        }
    }
    kept.extend(split);
    Ok((form.problem, x_aux, kept))
}

/// P (or G) in compressed-column form: column pointers, row indices, values.
pub fn csc(matrix: &CscMatrix) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
    let owned;
    let m = if matrix.is_csc() {
        matrix
    } else {
        owned = matrix.to_csc();
        &owned
    };
    signorini_core::qp::csc_parts(m, |_, _| true)
}
