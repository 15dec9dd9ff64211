//! `signorini export`: the scene's QP as Matrix Market files.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use signorini::auto::AutoBackend;
use signorini::exit::Exit;
use signorini::export::{self, BoxBounds};
use signorini::fclib::{self, FclibGlobal};
use signorini::run;
use signorini_core::model::{Increment, LoadPath};
use signorini_core::qp::{QpStatus, SolveOptions};
use signorini_core::scene::Scene;
use signorini_core::solve::{self, Solution};

use crate::args::{limits, Common};
use crate::console::{warn, Console};

/// `signorini export SCENE …`: the options of an export.
#[derive(clap::Args)]
pub(crate) struct ExportArgs {
    #[command(flatten)]
    pub(crate) common: Common,
    /// Output directory (created if missing): A.mtx, f.mtx, B.mtx, g.mtx, blocks.csv (each
    /// row's kind: non-negative, or box with its bound for friction's tangential rows), N.mtx
    /// (when A is singular), dofs.csv, rows.csv, README.txt.  A Coulomb scene is solved first and
    /// written as the Tresca problem at the bounds mu*max(0, lambda_n) of its answer (a
    /// snapshot: Coulomb is not a QP); friction along a load path is refused (use --fclib).
    #[arg(long, default_value = "out")]
    pub(crate) out: PathBuf,
    /// Instead of the Matrix Market files, write the problem in FCLIB's global form (HDF5) to
    /// this file, with the default backend's answer as its solution (docs/comparing-solvers.md).
    #[arg(long, value_name = "FILE")]
    pub(crate) fclib: Option<PathBuf>,
}

pub(crate) fn export(args: &ExportArgs) -> Result<Exit> {
    let (common, out) = (&args.common, args.out.as_path());
    let scene = run::load_scene(common.scene.as_deref())?;
    let prepared = run::prepare(&scene, &limits(common))?;
    if let Some(file) = &args.fclib {
        return export_fclib(file, &scene, prepared);
    }
    let model = &prepared.model;
    if !model.tangential.is_empty() && model.path.as_ref().is_some_and(|p| p.increments.len() > 1) {
        warn(format_args!(
            "error: {}: friction along a load path ([[step]]): each increment's problem measures the slip from the previous increment's answer, so no single QP is the scene's; `export --fclib FILE` writes one problem per increment",
            scene.title
        ));
        return Ok(Exit::Input);
    }
    let (snapshot, bounds);
    let qp = if export::has_coulomb(model) {
        // Coulomb is not a QP: the files hold the Tresca problem at the bounds μ max(0, λₙ) of
        // the scene's own answer, which needs that answer first.
        let mut backend = AutoBackend::default();
        let options = SolveOptions::default();
        let solution = solve::solve_model(model, &prepared.qp, &mut backend, &options)?;
        if solution.status != QpStatus::Solved {
            warn(format_args!(
                "error: {}: Coulomb friction is exported as the Tresca problem at the bounds mu*max(0, lambda_n) of the scene's answer, but the default backend ended `{}`{}: nothing written",
                scene.title,
                solution.status,
                solution.message_in_parentheses()
            ));
            return Ok(Exit::NotSolved);
        }
        snapshot = export::coulomb_snapshot(model, &prepared.qp, &solution.multipliers)?;
        bounds = BoxBounds::CoulombSnapshot {
            backend: solution.backend.clone(),
            tolerance: options.tol,
            objective: solution.objective,
        };
        warn(format_args!(
            "note: Coulomb friction is not a QP: the files hold a Tresca snapshot, each Coulomb row bounded by mu*max(0, lambda_n) of the scene's answer ({}, solved to {:e}; see README.txt)",
            solution.backend, options.tol
        ));
        &snapshot
    } else {
        bounds = BoxBounds::Scene;
        &prepared.qp
    };
    let written = export::export(out, &scene, model, qp, &bounds)
        .with_context(|| format!("exporting to {}", out.display()))?;
    let mut con = Console::new();
    let tangential = model.tangential.len();
    if tangential == 0 {
        con.line(format_args!(
            "{}: {} unknowns, {} contact rows",
            scene.title,
            qp.dofs(),
            qp.rows()
        ))?;
    } else {
        con.line(format_args!(
            "{}: {} unknowns, {} contact rows ({} normal, {tangential} tangential box rows: see blocks.csv)",
            scene.title,
            qp.dofs(),
            qp.rows(),
            qp.rows() - tangential
        ))?;
    }
    for p in &written {
        con.line(format_args!("  wrote {}", p.display()))?;
    }
    con.finish()?;
    Ok(Exit::Success)
}

/// `--fclib FILE`: the FCLIB form (refused before any solve when the scene has no such form),
/// then the default backend's answer; a problem whose answer is not `solved` is written without
/// a solution, said on stderr, and exits with its status.
fn export_fclib(file: &Path, scene: &Scene, prepared: run::Prepared) -> Result<Exit> {
    if let Some(path) = &prepared.model.path {
        return export_fclib_path(file, scene, &prepared, path);
    }
    let problem = FclibGlobal::of(scene, &prepared.model, &prepared.qp)?;
    let mut backend = AutoBackend::default();
    let qp = solve::ScaledQp::new(prepared.qp);
    let solution =
        solve::solve_scaled(&prepared.model, &qp, &mut backend, &SolveOptions::default())?;
    let solved = solution.status == QpStatus::Solved;
    let answer = solved.then(|| problem.solution(&prepared.model, &solution));
    fclib::write(file, &problem, answer.as_ref())
        .with_context(|| format!("exporting to {}", file.display()))?;
    let mut con = Console::new();
    con.line(format_args!(
        "{}: {} unknowns, {} contacts (FCLIB global form, 2D)",
        scene.title,
        problem.f.len(),
        problem.mu.len()
    ))?;
    con.line(format_args!("  wrote {}", file.display()))?;
    con.finish()?;
    if solved {
        Ok(Exit::Success)
    } else {
        eprintln!(
            "warning: the default backend ended `{}`: {} has no /solution",
            solution.status,
            file.display()
        );
        Ok(Exit::NotSolved)
    }
}

/// `--fclib FILE` of a scene with a load path: the whole path solved by the default backend,
/// then one FCLIB file per increment (`STEM-00001.hdf5`, … beside FILE: see
/// [`fclib::numbered`]), each its increment's own problem with that increment's answer.  A path
/// stops at the first increment not `solved` (later ones depend on its state): its file is
/// written without a solution, later ones not at all, and the exit is its status.
fn export_fclib_path(
    file: &Path,
    scene: &Scene,
    prepared: &run::Prepared,
    path: &LoadPath,
) -> Result<Exit> {
    let model = &prepared.model;
    // Refused (Tresca) before any solve.
    fclib::check_laws(model)?;
    let mut backend = AutoBackend::default();
    let qp = solve::ScaledQp::new(prepared.qp.clone());
    let mut answers: Vec<(Increment, Solution)> = Vec::with_capacity(path.increments.len());
    let last = solve::solve_scaled_each(
        model,
        &qp,
        &mut backend,
        &SolveOptions::default(),
        &mut |increment, solution| answers.push((increment.clone(), solution.clone())),
    )?;
    if answers.is_empty() {
        // One increment: solved as the only QP, without the per-increment hook.
        if let Some(only) = path.increments.first() {
            answers.push((only.clone(), last.clone()));
        }
    }
    let mut con = Console::new();
    let mut previous: Option<&[f64]> = None;
    for (k, (increment, solution)) in answers.iter().enumerate() {
        let step_qp = solve::increment_problem(model, path, &prepared.qp, increment, previous);
        let label = (increment.step, increment.increment);
        let problem = FclibGlobal::increment(scene, model, &step_qp, label)?;
        let solved = solution.status == QpStatus::Solved;
        let answer = solved.then(|| problem.solution(model, solution));
        let target = fclib::numbered(file, k + 1);
        fclib::write(&target, &problem, answer.as_ref())
            .with_context(|| format!("exporting to {}", target.display()))?;
        con.line(format_args!(
            "  wrote {} (step {}, increment {}{})",
            target.display(),
            increment.step,
            increment.increment,
            if solved { "" } else { ", no solution" }
        ))?;
        previous = Some(&solution.displacement);
    }
    con.line(format_args!(
        "{}: {} unknowns, {} contacts, {} of {} increments (FCLIB global form, 2D, one file each)",
        scene.title,
        prepared.qp.dofs(),
        model.normal_rows(),
        answers.len(),
        path.increments.len()
    ))?;
    con.finish()?;
    if last.status == QpStatus::Solved {
        Ok(Exit::Success)
    } else {
        eprintln!(
            "warning: the default backend ended `{}`: the path stopped at file {}",
            last.status,
            answers.len()
        );
        Ok(Exit::NotSolved)
    }
}
