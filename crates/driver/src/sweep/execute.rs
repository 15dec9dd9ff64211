//! The sweep itself: every mesh of the plan, coarse to fine (meshed, assembled and its floor
//! timed), every point of it solved and written as it finishes, then the final output set.

use std::collections::HashSet;
use std::path::Path;

use signorini_core::linalg::FactorInfo;
use signorini_core::mesh::MeshLimits;
use signorini_core::model::Model;
use signorini_core::qp::{QpStatus, SolveOptions};
use signorini_core::scene::Scene;
use signorini_core::solve::{self, ScaledQp, Solution};

use super::accuracy::{max_displacement, probes_text};
use super::measure::{median, reset_peak_rss};
use super::plan::{grid, key, plan_index, Grid};
use super::set::checkpoint;
use super::shard::{self, Manifest};
use super::solutions::{pvd_entries, write_solution};
use super::{
    better_reference, error_vs, fill_error_vs_finest, peak_rss_mb, read_for_resume, scene_hash,
    solution_file_name, sweep_members, validate_plan, with_hmax, write_csv, write_pvd, Point,
    SweepError, SweepOutcome, SweepPlan, SOLUTIONS_DIR, SOLUTIONS_FILE, SWEEP_FILE,
};
use crate::backends::{make_backend, BackendKind};
use crate::outdir::{DirLock, OutputSet};
use crate::run::{self, RunError};

/// Runs the sweep into `dir/sweep.csv` and its plots (see the [module docs](self) for the
/// files).  Plot headings use the part of the scene title before any colon.
///
/// `progress(done, total, what)` is called when a mesh starts (meshing, the floor), when each
/// point starts (`what` names it, ending in `: solving`) and when it ends (`done` counts the
/// finished points of this run's share of the plan, `total` is that share).
///
/// With `plan.shard`, only that shard's points run (see [`shard`]): the error columns are left
/// empty, `shard.json` and `displacements/` are written for `sweep merge`.  With `plan.vtu`,
/// every point run writes `solutions/<point>.vtu` and the set gets [`SOLUTIONS_FILE`].
///
/// Points whose backend fails (any status other than `solved`) are written like the others and
/// counted in [`SweepOutcome::failed`]; an error that stops a whole mesh (meshing, assembly, a
/// scene without contact rows) ends the sweep with an error, keeping the points written so far.
pub fn sweep(
    scene: &Scene,
    plan: &SweepPlan,
    options: &SolveOptions,
    limits: &MeshLimits,
    dir: &Path,
    mut progress: impl FnMut(usize, usize, &str),
) -> Result<SweepOutcome, SweepError> {
    let mut run = Sweep::open(scene, plan, options, limits, dir)?;
    for ih in 0..run.grid.0.len() {
        run.mesh(ih, &mut progress)?;
    }
    run.finish()
}

/// The solve-independent measures of one mesh: the model, its scaled QP, the floor's factor and
/// the median times.
struct MeshRun {
    /// The scene at this hmax.
    scene: Scene,
    /// The assembled model.
    model: Model,
    /// Its QP, scaled for the backends.
    qp: ScaledQp,
    /// The floor's factor (ordering, nnz(L)).
    floor_info: FactorInfo,
    /// Median meshing time, s.
    mesh_s: f64,
    /// Median assembly time, s.
    assemble_s: f64,
    /// Median floor time, s.
    floor_s: f64,
}

/// A sweep under way: the plan, the output directory's locks and the points so far.
struct Sweep<'a> {
    scene: &'a Scene,
    plan: &'a SweepPlan,
    options: &'a SolveOptions,
    limits: &'a MeshLimits,
    dir: &'a Path,
    /// This scene's [`scene_hash`].
    hash: String,
    /// The output directory's lock.
    lock: DirLock,
    /// Every point of the file so far, resumed ones included.
    points: Vec<Point>,
    /// The keys ([`key`]) of the resumed points.
    done: HashSet<String>,
    /// The plan's grid.
    grid: Grid,
    /// Points of the whole plan.
    plan_total: usize,
    /// Points of this run's share of the plan.
    total: usize,
    /// `shard.json`'s contents, with a shard.
    manifest: Option<Manifest>,
    /// The lock of `displacements/`, with a shard.
    displacements: Option<DirLock>,
    /// The lock of `solutions/`, with `vtu`.
    solutions: Option<DirLock>,
    /// Points of this run's share finished (or skipped) so far.
    count: usize,
    /// Backends that hit the time limit, skipped on the finer meshes.
    given_up: HashSet<BackendKind>,
}

impl<'a> Sweep<'a> {
    /// Checks the plan, takes the directory's lock, reads the points to resume and the locks of
    /// the point files' directories.
    fn open(
        scene: &'a Scene,
        plan: &'a SweepPlan,
        options: &'a SolveOptions,
        limits: &'a MeshLimits,
        dir: &'a Path,
    ) -> Result<Self, SweepError> {
        validate_plan(scene, plan, limits)?;
        let hash = scene_hash(scene, &plan.bodies);
        let csv_path = dir.join(SWEEP_FILE);
        // Read-only checks first, so that a refusal does not even create the directory.
        if csv_path.exists() && !plan.resume && !plan.overwrite {
            return Err(SweepError::Exists(csv_path));
        }
        let lock = DirLock::acquire(dir)?;
        let exists = std::fs::symlink_metadata(&csv_path).is_ok();
        if exists && !plan.resume && !plan.overwrite {
            return Err(SweepError::Exists(csv_path));
        }
        let points = if plan.resume && exists {
            read_for_resume(&csv_path, &hash, plan)?
        } else {
            Vec::new()
        };
        let done: HashSet<String> = points
            .iter()
            .map(|p| key(p.hmax, &p.backend, p.tol))
            .collect();
        let the_grid = grid(plan);
        let (hmaxes, tols, backends) = &the_grid;
        let per_mesh = tols.len() * backends.len();
        let plan_total = hmaxes.len() * per_mesh;
        let owns = |p: usize| plan.shard.is_none_or(|s| s.owns(p));
        let total = (1..=plan_total).filter(|&p| owns(p)).count();
        let manifest = new_manifest(scene, plan, &hash, &the_grid, plan_total);
        let displacements = plan
            .shard
            .map(|_| DirLock::acquire(&dir.join(shard::DISPLACEMENTS_DIR)))
            .transpose()?;
        let solutions = plan
            .vtu
            .then(|| DirLock::acquire(&dir.join(SOLUTIONS_DIR)))
            .transpose()?;
        Ok(Sweep {
            scene,
            plan,
            options,
            limits,
            dir,
            hash,
            lock,
            points,
            done,
            grid: the_grid,
            plan_total,
            total,
            manifest,
            displacements,
            solutions,
            count: 0,
            given_up: HashSet::new(),
        })
    }

    /// Whether point `p` of the plan is this run's.
    fn owns(&self, p: usize) -> bool {
        self.plan.shard.is_none_or(|s| s.owns(p))
    }

    /// The number (from 1) of point (hmax `ih`, tolerance `it`, backend `ib`) in the plan.
    fn index(&self, ih: usize, it: usize, ib: usize) -> usize {
        1 + (ih * self.grid.1.len() + it) * self.grid.2.len() + ib
    }

    /// Runs the points of mesh `ih` that are this run's and not already done.
    fn mesh(
        &mut self,
        ih: usize,
        progress: &mut impl FnMut(usize, usize, &str),
    ) -> Result<(), SweepError> {
        let (tols, backends) = (&self.grid.1, &self.grid.2);
        let h = self.grid.0[ih];
        let mine: Vec<(usize, usize)> = (0..tols.len())
            .flat_map(|it| (0..backends.len()).map(move |ib| (it, ib)))
            .filter(|&(it, ib)| self.owns(self.index(ih, it, ib)))
            .collect();
        let todo = mine
            .iter()
            .filter(|&&(it, ib)| !self.done.contains(&key(h, backends[ib].name(), tols[it])))
            .count();
        if todo == 0 {
            self.count += mine.len();
            if !mine.is_empty() {
                progress(self.count, self.total, &format!("hmax {h}: already done"));
            }
            return Ok(());
        }
        progress(
            self.count,
            self.total,
            &format!("hmax {h}: meshing and assembling"),
        );
        let Some(mesh) = self.prepare_mesh(h, progress)? else {
            return Ok(());
        };
        let mut reference: Option<(f64, Vec<f64>)> = None; // (residual, displacement)
        for &(it, ib) in &mine {
            self.point(&mesh, (ih, it, ib), &mut reference, progress)?;
        }
        Ok(())
    }

    /// Meshes and assembles the scene at `h` (`repeat` times) and times its floor; `None` only
    /// when nothing was assembled.
    fn prepare_mesh(
        &self,
        h: f64,
        progress: &mut impl FnMut(usize, usize, &str),
    ) -> Result<Option<MeshRun>, SweepError> {
        let repeat = self.plan.repeat;
        let s = with_hmax(self.scene, &self.plan.bodies, h);
        let mut mesh_times = Vec::with_capacity(repeat);
        let mut assemble_times = Vec::with_capacity(repeat);
        let mut prepared = None;
        for _ in 0..repeat {
            let p = run::prepare(&s, self.limits)?;
            mesh_times.push(p.mesh_s);
            assemble_times.push(p.assemble_s);
            prepared = Some(p);
        }
        let Some(prepared) = prepared else {
            return Ok(None);
        };
        if prepared.model.rows() == 0 {
            return Err(RunError::NoContact(format!("the mesh at hmax {h}")).into());
        }
        progress(
            self.count,
            self.total,
            &format!(
                "hmax {h}: timing the floor ({} DOFs)",
                prepared.model.free.len()
            ),
        );
        let qp = solve::ScaledQp::new(prepared.qp);
        let (floor_info, floors) = time_floor(&qp, repeat)?;
        let (mesh_s, assemble_s, floor_s) =
            (median(mesh_times), median(assemble_times), median(floors));
        Ok(Some(MeshRun {
            scene: s,
            model: prepared.model,
            qp,
            floor_info,
            mesh_s,
            assemble_s,
            floor_s,
        }))
    }

    /// Runs point `(ih, it, ib)` of `mesh` (or skips it: already done, or its backend gave up),
    /// updates the mesh's `reference` and writes the point with its files.
    fn point(
        &mut self,
        mesh: &MeshRun,
        (ih, it, ib): (usize, usize, usize),
        reference: &mut Option<(f64, Vec<f64>)>,
        progress: &mut impl FnMut(usize, usize, &str),
    ) -> Result<(), SweepError> {
        let h = self.grid.0[ih];
        let (t, kind, p) = (self.grid.1[it], self.grid.2[ib], self.index(ih, it, ib));
        let label = format!("hmax {h} {} tol {t:e}", kind.name());
        let skip_row = self.done.contains(&key(h, kind.name(), t));
        // The tightest tolerance is always solved (again, if resuming) to fix the reference;
        // a shard leaves the reference to `sweep merge`.
        let needed_for_reference = self.plan.shard.is_none() && it == 0 && reference.is_none();
        if (skip_row && !needed_for_reference) || self.given_up.contains(&kind) {
            self.count += 1;
            let why = if skip_row {
                "already done"
            } else {
                "skipped (time limit on a coarser mesh)"
            };
            progress(self.count, self.total, &format!("{label}: {why}"));
            return Ok(());
        }
        progress(self.count, self.total, &format!("{label}: solving"));
        let Some((sol, times)) = self.solve_point(mesh, kind, t)? else {
            return Ok(());
        };
        if sol.status == QpStatus::TimeLimit {
            self.given_up.insert(kind);
        }
        let worst = sol.residuals.worst();
        if it == 0
            && sol.status == QpStatus::Solved
            && better_reference(reference.as_ref().map(|r| r.0), worst)
        {
            *reference = Some((worst, sol.displacement.clone()));
        }
        self.count += 1;
        progress(
            self.count,
            self.total,
            &format!("{label}: {}", sol.status.as_str()),
        );
        if skip_row {
            return Ok(());
        }
        let error_vs_reference = if self.plan.shard.is_some() {
            None
        } else {
            reference
                .as_ref()
                .map(|(_, u_ref)| error_vs(u_ref, &sol.displacement))
        };
        let point = self.row(mesh, (h, kind, t), &sol, median(times), error_vs_reference);
        // The point's own files first, so that every row of sweep.csv has its files.
        self.write_point_files(mesh, p, (h, kind, t), worst, &sol)?;
        self.points.push(point);
        checkpoint(&self.lock, &self.points, self.manifest.as_ref())?;
        Ok(())
    }

    /// Solves `mesh` with `kind` at tolerance `t`, `repeat` times (stopping at a time limit):
    /// the last solution and every solve's time; `None` only when nothing ran.
    fn solve_point(
        &self,
        mesh: &MeshRun,
        kind: BackendKind,
        t: f64,
    ) -> Result<Option<(Solution, Vec<f64>)>, SweepError> {
        let repeat = self.plan.repeat;
        let mut backend = make_backend(kind).map_err(|e| {
            RunError::from(solve::SolveError::Qp(
                signorini_core::qp::QpError::Unavailable {
                    backend: kind.name(),
                    reason: e.to_string(),
                },
            ))
        })?;
        let point_options = SolveOptions {
            tol: t,
            time_limit: self.plan.time_limit,
            ..self.options.clone()
        };
        // Peak memory of this point: the model (resident now) plus what the backend adds.
        reset_peak_rss();
        let mut times = Vec::with_capacity(repeat);
        let mut last: Option<Solution> = None;
        for _ in 0..repeat {
            let sol = solve::solve_scaled(&mesh.model, &mesh.qp, backend.as_mut(), &point_options)
                .map_err(RunError::from)?;
            times.push(sol.solve_time.as_secs_f64());
            let stop = sol.status == QpStatus::TimeLimit;
            last = Some(sol);
            if stop {
                break;
            }
        }
        Ok(last.map(|sol| (sol, times)))
    }

    /// The row of `sweep.csv` for the point `(h, kind, t)` solved as `sol` in `solve_s` seconds.
    fn row(
        &self,
        mesh: &MeshRun,
        (h, kind, t): (f64, BackendKind, f64),
        sol: &Solution,
        solve_s: f64,
        error_vs_reference: Option<f64>,
    ) -> Point {
        let model = &mesh.model;
        Point {
            hmax: h,
            dofs: model.free.len(),
            constraints: model.rows(),
            backend: kind.name().to_string(),
            tol: t,
            status: sol.status.as_str().to_string(),
            backend_status: sol.backend_status.as_str().to_string(),
            iterations: sol.iterations,
            mesh_s: mesh.mesh_s,
            assemble_s: mesh.assemble_s,
            solve_s,
            floor_s: mesh.floor_s,
            ratio_to_floor: solve_s / mesh.floor_s,
            error_vs_reference,
            error_vs_finest: None,
            max_displacement: max_displacement(&sol.displacement),
            peak_rss_mb: peak_rss_mb(),
            max_penetration: sol.residuals.max_penetration,
            stationarity: sol.residuals.stationarity,
            complementarity: sol.residuals.complementarity,
            probes: probes_text(&mesh.scene, model, &sol.displacement),
            scene_hash: self.hash.clone(),
            floor_ordering: mesh.floor_info.ordering.as_str().to_string(),
            floor_nnz_l: mesh.floor_info.nnz_l,
        }
    }

    /// Point `p`'s own files: its displacements (with a shard) and its solution (with `vtu`).
    fn write_point_files(
        &self,
        mesh: &MeshRun,
        p: usize,
        (h, kind, t): (f64, BackendKind, f64),
        worst: f64,
        sol: &Solution,
    ) -> Result<(), SweepError> {
        if let Some(dlock) = &self.displacements {
            let name = shard::point_data_name(p);
            let mut set = OutputSet::new(dlock, Some(&name), &[&name])?;
            set.write(&name, |w| {
                shard::write_point_data(w, worst, &sol.displacement)
            })?;
            set.commit()?;
        }
        if let Some(slock) = &self.solutions {
            write_solution(
                slock,
                &mesh.scene,
                &mesh.model,
                sol,
                &solution_file_name(p, self.plan_total, h, kind.name(), t),
            )?;
        }
        Ok(())
    }

    /// Fills the error columns (without a shard) and writes the final output set: `sweep.csv`,
    /// the plots, `shard.json` (with a shard) and `solutions.pvd` (with `vtu`).
    fn finish(mut self) -> Result<SweepOutcome, SweepError> {
        let points = &mut self.points;
        if self.plan.shard.is_none() {
            fill_error_vs_finest(points);
        }
        let rows: Vec<crate::plots::SweepRow> = points.iter().map(Point::to_row).collect();
        // Plot titles get the part of the scene title before any colon, to stay on one line.
        let title = &self.scene.title;
        let short = title.split(':').next().unwrap_or(title).trim();
        let plots = crate::plots::render_sweep(&rows, short)?;
        let mut set = OutputSet::new(&self.lock, Some(SWEEP_FILE), &sweep_members())?;
        let csv = set.write(SWEEP_FILE, |w| write_csv(w, points))?;
        let mut plot_paths = Vec::new();
        for (name, svg) in &plots {
            plot_paths.push(set.write(name, |w| w.write_all(svg.as_bytes()))?);
        }
        let mut files = Vec::new();
        if let Some(m) = &mut self.manifest {
            complete_manifest(m, points, &self.grid, self.plan_total);
            files.push(set.write(shard::MANIFEST_FILE, |w| m.write(w))?);
        }
        if self.plan.vtu {
            let entries = pvd_entries(self.dir, &self.grid, self.plan_total, points);
            files.push(set.write(SOLUTIONS_FILE, |w| write_pvd(w, &entries))?);
        }
        set.commit()?;
        let failed = points.iter().filter(|p| p.status != "solved").count();
        Ok(SweepOutcome {
            csv,
            plots: plot_paths,
            skipped: self.total.saturating_sub(points.len()),
            failed,
            points: self.points,
            scene_hash: self.hash,
            files,
        })
    }
}

/// `shard.json`'s contents at the start of a sharded sweep (`None` without a shard).
fn new_manifest(
    scene: &Scene,
    plan: &SweepPlan,
    hash: &str,
    (hmaxes, tols, backends): &Grid,
    plan_total: usize,
) -> Option<Manifest> {
    plan.shard.map(|shard| Manifest {
        format: shard::MANIFEST_FORMAT.to_string(),
        version: env!("CARGO_PKG_VERSION").to_string(),
        title: scene.title.clone(),
        scene_hash: hash.to_string(),
        bodies: plan.bodies.clone(),
        hmax: hmaxes.clone(),
        backends: backends.iter().map(|b| b.name().to_string()).collect(),
        tols: tols.clone(),
        repeat: Some(plan.repeat),
        time_limit_s: plan.time_limit.map(|t| t.as_secs_f64()),
        shard,
        points: plan_total,
        complete: false,
        skipped: Vec::new(),
    })
}

/// Marks the manifest complete, listing the shard's points that are not in `points` as skipped.
fn complete_manifest(m: &mut Manifest, points: &[Point], grid: &Grid, plan_total: usize) {
    let present: HashSet<usize> = points
        .iter()
        .filter_map(|pt| plan_index(grid, pt))
        .collect();
    m.skipped = m
        .shard
        .points(plan_total)
        .into_iter()
        .filter(|p| !present.contains(p))
        .collect();
    m.complete = true;
}

/// The floor of `qp`: one untimed factorisation (its info), then `repeat` timed ones.
fn time_floor(qp: &ScaledQp, repeat: usize) -> Result<(FactorInfo, Vec<f64>), SweepError> {
    // One untimed factorisation first: the first touch of a large factor's memory costs page
    // faults that later solves (the backends') do not pay; timing it cold inflated the floor
    // twofold at 10⁶ DOFs.
    let floor_info = solve::floor(&qp.problem)
        .map_err(|e| RunError::from(solve::SolveError::from(e)))?
        .info;
    let floors: Vec<f64> = (0..repeat)
        .map(|_| solve::floor_time(&qp.problem).map(|d| d.as_secs_f64()))
        .collect::<Result<_, _>>()
        .map_err(|e| RunError::from(solve::SolveError::from(e)))?;
    Ok((floor_info, floors))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sweep::shard::Shard;

    /// The progress callback names a point when it starts, not only once it is done: the bar
    /// used to show the previous point's label (and no sign of life) while a point ran.
    #[test]
    fn progress_names_each_point_before_it_runs() {
        let scene = run::load_scene(None).unwrap();
        let dir = tempfile::tempdir().unwrap();
        let plan = SweepPlan {
            hmax: vec![0.3, 0.2],
            bodies: Vec::new(),
            backends: vec![BackendKind::Clarabel, BackendKind::DualPgs],
            tols: vec![1e-9],
            repeat: 1,
            time_limit: None,
            resume: false,
            overwrite: false,
            shard: Some(Shard { index: 2, count: 3 }),
            vtu: false,
        };
        let mut calls: Vec<(usize, usize, String)> = Vec::new();
        sweep(
            &scene,
            &plan,
            &SolveOptions::default(),
            &MeshLimits::default(),
            dir.path(),
            |d, t, w| calls.push((d, t, w.to_string())),
        )
        .unwrap();
        // Shard 2/3 of 4 points runs point 2 alone: hmax 0.3, dual-pgs.
        let texts: Vec<&str> = calls.iter().map(|c| c.2.as_str()).collect();
        assert_eq!(
            texts,
            [
                "hmax 0.3: meshing and assembling",
                "hmax 0.3: timing the floor (236 DOFs)",
                "hmax 0.3 dual-pgs tol 1e-9: solving",
                "hmax 0.3 dual-pgs tol 1e-9: solved",
            ]
        );
        let counts: Vec<(usize, usize)> = calls.iter().map(|c| (c.0, c.1)).collect();
        assert_eq!(counts, [(0, 1), (0, 1), (0, 1), (1, 1)]);
    }
}
