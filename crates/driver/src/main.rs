//! `signorini`: frictionless contact of elastic bodies in 2D, solved by several QP backends.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use signorini::backends::{make_backend, BackendKind};
use signorini::run;
use signorini_core::mesh::{estimate_elements, MeshLimits};
use signorini_core::qp::{QpStatus, SolveOptions};

#[derive(Parser)]
#[command(
    name = "signorini",
    version,
    about = "2D frictionless contact of elastic bodies by FEM, through several QP backends"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(clap::Args)]
struct Common {
    /// Scene file (TOML, see SCENE.md); the seed's Experiment 2b when omitted.
    scene: Option<PathBuf>,
    /// Largest number of elements a scene may ask for before it is refused.
    #[arg(long, default_value_t = 5_000_000)]
    max_elements: usize,
}

#[derive(Subcommand)]
enum Command {
    /// Mesh, assemble and solve a scene; write result.json, solution.vtu and deformed.svg.
    Solve {
        #[command(flatten)]
        common: Common,
        /// QP backend: clarabel, osqp, dual-pgs, dual-uzawa or dual-ssn.
        #[arg(long, default_value = "clarabel")]
        backend: String,
        /// Relative KKT tolerance the answer must meet to count as solved.
        #[arg(long, default_value_t = 1e-9)]
        tol: f64,
        /// Output directory (created if missing).
        #[arg(long, default_value = "out")]
        out: PathBuf,
    },
    /// Mesh and assemble once, then solve the same QP with several backends and compare them.
    Compare {
        #[command(flatten)]
        common: Common,
        /// Comma-separated backends.
        #[arg(
            long,
            value_delimiter = ',',
            default_value = "clarabel,osqp,dual-pgs,dual-uzawa"
        )]
        backends: Vec<String>,
        /// Relative KKT tolerance every backend is asked to meet.
        #[arg(long, default_value_t = 1e-9)]
        tol: f64,
        /// Output directory for compare.json and compare.csv (created if missing).
        #[arg(long, default_value = "out")]
        out: PathBuf,
    },
    /// Refine the mesh and time every backend and tolerance; write sweep.csv and plots.
    Sweep {
        #[command(flatten)]
        common: Common,
        /// Comma-separated mesh sizes, e.g. 0.2,0.1,0.05.
        #[arg(long, value_delimiter = ',', required = true)]
        hmax: Vec<f64>,
        /// Comma-separated bodies whose hmax is swept (default: all).
        #[arg(long, value_delimiter = ',')]
        bodies: Vec<String>,
        /// Comma-separated backends.
        #[arg(
            long,
            value_delimiter = ',',
            default_value = "clarabel,osqp,dual-pgs,dual-uzawa"
        )]
        backends: Vec<String>,
        /// Comma-separated tolerances.
        #[arg(long, value_delimiter = ',', default_value = "1e-9")]
        tol: Vec<f64>,
        /// Runs per point (medians are reported).
        #[arg(long, default_value_t = 1)]
        repeat: usize,
        /// Seconds one solve may take; a backend that exceeds it is skipped on finer meshes.
        #[arg(long)]
        time_limit: Option<f64>,
        /// Keep the points already in DIR/sweep.csv (verified to be this scene's and this grid's)
        /// and run only the missing ones.
        #[arg(long)]
        resume: bool,
        /// Replace an existing DIR/sweep.csv (without this or --resume, an existing file is
        /// refused); it is replaced once the new sweep writes its first point.  Excludes --resume.
        #[arg(long)]
        overwrite: bool,
        /// Output directory for sweep.csv and the plots (created if missing).
        #[arg(long, default_value = "out")]
        out: PathBuf,
    },
    /// Write the scene's QP (A, f, B, g as Matrix Market) and its DOF and row maps.
    Export {
        #[command(flatten)]
        common: Common,
        /// Output directory (created if missing).
        #[arg(long, default_value = "out")]
        out: PathBuf,
    },
    /// Validate a scene without solving it.
    Check {
        #[command(flatten)]
        common: Common,
    },
}

fn limits(common: &Common) -> MeshLimits {
    MeshLimits {
        max_elements: common.max_elements,
        ..MeshLimits::default()
    }
}

fn check_tol(tol: f64) -> Result<()> {
    anyhow::ensure!(
        tol.is_finite() && tol > 0.0 && tol < 1.0,
        "--tol must lie in (0, 1), got {tol}"
    );
    Ok(())
}

fn solve(common: &Common, backend: &str, tol: f64, out: &std::path::Path) -> Result<ExitCode> {
    check_tol(tol)?;
    let kind: BackendKind = backend.parse()?;
    let mut backend = make_backend(kind)?;
    let scene = run::load_scene(common.scene.as_deref())?;
    let options = SolveOptions {
        tol,
        ..SolveOptions::default()
    };
    let outcome = run::solve_scene(&scene, backend.as_mut(), &options, &limits(common))?;
    let written = run::write_outputs(out, &scene, &outcome)
        .with_context(|| format!("writing results to {}", out.display()))?;
    let r = &outcome.report;
    println!("{}", r.scene);
    println!(
        "  {} DOFs, {} contact rows ({} active); backend {}: {} in {} iterations",
        r.dofs, r.constraints, r.active_constraints, r.backend, r.status, r.iterations
    );
    for b in &r.bodies {
        println!(
            "  body {:<10} {:>7} nodes {:>7} elements  max |u| = {:.6e}  reaction = [{:.4e}, {:.4e}]",
            b.name, b.nodes, b.elements, b.max_displacement, b.reaction[0], b.reaction[1]
        );
    }
    for c in &r.contacts {
        if c.constraints == 0 {
            eprintln!(
                "warning: contact {} – {} gave no constraint row: no boundary node of either body is within one element of the other (give the pair a region box if they are meant to touch)",
                c.bodies[0], c.bodies[1]
            );
            continue;
        }
        println!(
            "  contact {} – {} (slave {}): normal force {:.6e}",
            c.bodies[0], c.bodies[1], c.slave, c.normal_force
        );
    }
    println!(
        "  residuals: penetration {:.2e}, stationarity {:.2e}, complementarity {:.2e}, min multiplier {:.2e}",
        r.residuals.max_penetration,
        r.residuals.stationarity,
        r.residuals.complementarity,
        r.residuals.min_multiplier
    );
    println!(
        "  time: mesh {:.4} s, assemble {:.4} s, solve {:.4} s, total {:.4} s",
        r.timing_s.mesh, r.timing_s.assemble, r.timing_s.solve, r.timing_s.total
    );
    for p in &written {
        println!("  wrote {}", p.display());
    }
    if outcome.solution.status == QpStatus::Solved {
        Ok(ExitCode::SUCCESS)
    } else {
        eprintln!(
            "error: status {} (residuals miss --tol {tol:e}){}",
            outcome.solution.status,
            outcome
                .solution
                .message
                .as_deref()
                .map(|m| format!(": {m}"))
                .unwrap_or_default()
        );
        Ok(ExitCode::from(2))
    }
}

fn compare(common: &Common, names: &[String], tol: f64, out: &std::path::Path) -> Result<ExitCode> {
    check_tol(tol)?;
    let kinds: Vec<BackendKind> = names.iter().map(|n| n.parse()).collect::<Result<_, _>>()?;
    anyhow::ensure!(!kinds.is_empty(), "--backends names no backend");
    for k in &kinds {
        anyhow::ensure!(
            k.available(),
            "backend \"{k}\" is not compiled in; rebuild with `--features {k}`"
        );
    }
    let scene = run::load_scene(common.scene.as_deref())?;
    let options = SolveOptions {
        tol,
        ..SolveOptions::default()
    };
    let bar = indicatif::ProgressBar::new(kinds.len() as u64).with_style(
        indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let report = signorini::compare::compare(&scene, &kinds, &options, &limits(common), |name| {
        bar.set_message(name.to_string());
        bar.inc(1);
    })?;
    bar.finish_and_clear();
    let written = signorini::compare::write(out, &report)
        .with_context(|| format!("writing comparison to {}", out.display()))?;
    print!("{}", signorini::compare::table(&report));
    for p in &written {
        println!("  wrote {}", p.display());
    }
    let all_solved = report.backends.iter().all(|r| r.status == "solved");
    Ok(if all_solved {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(2)
    })
}

#[allow(clippy::too_many_arguments)]
fn sweep(
    common: &Common,
    hmax: &[f64],
    bodies: &[String],
    names: &[String],
    tols: &[f64],
    repeat: usize,
    time_limit: Option<f64>,
    resume: bool,
    overwrite: bool,
    out: &std::path::Path,
) -> Result<ExitCode> {
    let backends = parse_backends(names)?;
    let time_limit = time_limit
        .map(|t| {
            std::time::Duration::try_from_secs_f64(t)
                .ok()
                .filter(|d| !d.is_zero())
                .ok_or_else(|| {
                    anyhow::anyhow!("--time-limit must be a positive number of seconds, got {t}")
                })
        })
        .transpose()?;
    let scene = run::load_scene(common.scene.as_deref())?;
    let plan = signorini::sweep::SweepPlan {
        hmax: hmax.to_vec(),
        bodies: bodies.to_vec(),
        backends,
        tols: tols.to_vec(),
        repeat,
        time_limit,
        resume,
        overwrite,
    };
    let bar = indicatif::ProgressBar::new(0).with_style(
        indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} [{elapsed}] {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let outcome = signorini::sweep::sweep(
        &scene,
        &plan,
        &SolveOptions::default(),
        &limits(common),
        out,
        |done, total, what| {
            bar.set_length(total as u64);
            bar.set_position(done as u64);
            bar.set_message(what.to_string());
        },
    )?;
    bar.finish_and_clear();
    let points = &outcome.points;
    println!("{}: {} points", scene.title, points.len());
    println!(
        "  {:>8} {:>9} {:<11} {:>8} {:<15} {:>6} {:>10} {:>10} {:>8} {:>9} {:>9}",
        "hmax",
        "dofs",
        "backend",
        "tol",
        "status",
        "iter",
        "solve s",
        "floor s",
        "÷floor",
        "err ref",
        "err fine"
    );
    for p in points {
        println!(
            "  {:>8} {:>9} {:<11} {:>8.0e} {:<15} {:>6} {:>10.4} {:>10.4} {:>8.2} {:>9.1e} {:>9.1e}",
            p.hmax,
            p.dofs,
            p.backend,
            p.tol,
            p.status,
            p.iterations,
            p.solve_s,
            p.floor_s,
            p.ratio_to_floor,
            p.error_vs_reference.unwrap_or(f64::NAN),
            p.error_vs_finest.unwrap_or(f64::NAN)
        );
    }
    println!("  wrote {}", outcome.csv.display());
    for p in &outcome.plots {
        println!("  wrote {}", p.display());
    }
    let summary = format!(
        "sweep: {} of {} points solved, {} not solved, {} skipped after a time limit",
        points.len() - outcome.failed,
        points.len() + outcome.skipped,
        outcome.failed,
        outcome.skipped
    );
    Ok(if outcome.failed + outcome.skipped == 0 {
        println!("{summary}");
        ExitCode::SUCCESS
    } else {
        eprintln!("error: {summary}");
        ExitCode::from(2)
    })
}

fn parse_backends(names: &[String]) -> Result<Vec<BackendKind>> {
    let kinds: Vec<BackendKind> = names.iter().map(|n| n.parse()).collect::<Result<_, _>>()?;
    anyhow::ensure!(!kinds.is_empty(), "--backends names no backend");
    for k in &kinds {
        anyhow::ensure!(
            k.available(),
            "backend \"{k}\" is not compiled in; rebuild with `--features {k}`"
        );
    }
    Ok(kinds)
}

fn export(common: &Common, out: &std::path::Path) -> Result<ExitCode> {
    let scene = run::load_scene(common.scene.as_deref())?;
    let prepared = run::prepare(&scene, &limits(common))?;
    let qp = prepared.model.qp()?;
    let written = signorini::export::export(out, &scene, &prepared.model, &qp)
        .with_context(|| format!("exporting to {}", out.display()))?;
    println!(
        "{}: {} unknowns, {} contact rows",
        scene.title,
        qp.dofs(),
        qp.rows()
    );
    for p in &written {
        println!("  wrote {}", p.display());
    }
    Ok(ExitCode::SUCCESS)
}

fn check(common: &Common) -> Result<ExitCode> {
    let scene = run::load_scene(common.scene.as_deref())?;
    let limits = limits(common);
    println!("{}: valid", scene.title);
    let mut total = 0;
    for b in &scene.bodies {
        let estimate = estimate_elements(&b.polygon, b.hmax, b.element);
        total += estimate;
        println!(
            "  body {:<10} hmax {:<8} ~{estimate} elements",
            b.name, b.hmax
        );
    }
    println!(
        "  {} dirichlet, {} neumann, {} contact pair(s), {} probe(s)",
        scene.dirichlet.len(),
        scene.neumann.len(),
        scene.contacts.len(),
        scene.probes.len()
    );
    anyhow::ensure!(
        total <= limits.max_elements,
        "the scene asks for ~{total} elements, more than --max-elements {}",
        limits.max_elements
    );
    Ok(ExitCode::SUCCESS)
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Solve {
            common,
            backend,
            tol,
            out,
        } => solve(common, backend, *tol, out),
        Command::Compare {
            common,
            backends,
            tol,
            out,
        } => compare(common, backends, *tol, out),
        Command::Export { common, out } => export(common, out),
        Command::Sweep {
            common,
            hmax,
            bodies,
            backends,
            tol,
            repeat,
            time_limit,
            resume,
            overwrite,
            out,
        } => sweep(
            common,
            hmax,
            bodies,
            backends,
            tol,
            *repeat,
            *time_limit,
            *resume,
            *overwrite,
            out,
        ),
        Command::Check { common } => check(common),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
