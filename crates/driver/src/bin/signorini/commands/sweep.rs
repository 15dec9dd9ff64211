//! `signorini sweep` and `sweep merge`: mesh refinement × backends × tolerances, sweep.csv and plots.

use std::path::PathBuf;
use std::time::Duration;

use anyhow::Result;
use signorini::backends::{BackendKind, ChoiceParser};
use signorini::exit::Exit;
use signorini::run;
use signorini_core::qp::SolveOptions;

use crate::args::{
    limits, parse_backends, parse_shard, parse_time_limit, parse_tol, time_limit, Common,
};
use crate::console::{warn, Console};

/// `signorini sweep SCENE …`: the options of a sweep.
#[derive(clap::Args)]
pub(crate) struct SweepArgs {
    #[command(flatten)]
    pub(crate) common: Common,
    /// Comma-separated mesh sizes, e.g. 0.2,0.1,0.05.
    #[arg(long, value_delimiter = ',', required = true)]
    pub(crate) hmax: Vec<f64>,
    /// Comma-separated bodies whose hmax is swept (default: all).
    #[arg(long, value_delimiter = ',')]
    pub(crate) bodies: Vec<String>,
    /// Comma-separated backends [default: clarabel,osqp,dual-pgs,dual-uzawa, those compiled in].
    #[arg(long, value_delimiter = ',', value_parser = ChoiceParser::<BackendKind>::new())]
    pub(crate) backends: Vec<BackendKind>,
    /// Comma-separated tolerances.
    #[arg(long, value_delimiter = ',', default_value = "1e-9", value_parser = parse_tol)]
    pub(crate) tol: Vec<f64>,
    /// Runs per point (medians are reported); at least 1.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..))]
    pub(crate) repeat: u32,
    /// Seconds one solve may take; a backend that exceeds it is skipped on finer meshes.
    #[arg(long, value_parser = parse_time_limit)]
    pub(crate) time_limit: Option<f64>,
    /// Keep the points already in DIR/sweep.csv (verified to be this scene's and this grid's)
    /// and run only the missing ones.
    #[arg(long)]
    pub(crate) resume: bool,
    /// Replace an existing DIR/sweep.csv (without this or --resume, an existing file is
    /// refused); it is replaced once the new sweep writes its first point.  Excludes --resume.
    #[arg(long)]
    pub(crate) overwrite: bool,
    /// Run only shard I of N: the plan's points I, I+N, I+2N, … (numbered from 1, hmax coarse to
    /// fine, then tolerances tightest first, then backends); join the N directories with
    /// `signorini sweep merge`.
    #[arg(long, value_name = "I/N", value_parser = parse_shard)]
    pub(crate) shard: Option<signorini::sweep::shard::Shard>,
    /// Also write each point's solution as DIR/solutions/<point>.vtu and the ParaView
    /// collection DIR/solutions.pvd (timestep = the point's number in the plan).
    #[arg(long)]
    pub(crate) vtu: bool,
    /// Output directory for sweep.csv and the plots (created if missing).
    #[arg(long, default_value = "out")]
    pub(crate) out: PathBuf,
}

/// The subcommands of `signorini sweep`.
#[derive(clap::Subcommand)]
pub(crate) enum SweepAction {
    /// Check that the directories hold the shards 1/N … N/N of one sweep (same scene hash,
    /// grid, backends, tolerances; each shard once, complete) and merge them into one
    /// sweep.csv and its plots, computing the error columns over all points.
    Merge {
        /// The shards' output directories.
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// Replace an existing OUT/sweep.csv (without it, an existing file is refused).
        #[arg(long)]
        overwrite: bool,
        /// Output directory for the merged sweep.csv and plots (created if missing).
        #[arg(long, default_value = "out")]
        out: PathBuf,
    },
}

pub(crate) fn sweep(args: &SweepArgs) -> Result<Exit> {
    let backends = parse_backends(&args.backends, &[])?;
    let common = &args.common;
    let scene = run::load_scene(common.scene.as_deref())?;
    let plan = signorini::sweep::SweepPlan {
        hmax: args.hmax.clone(),
        bodies: args.bodies.clone(),
        backends,
        tols: args.tol.clone(),
        repeat: args.repeat as usize,
        time_limit: time_limit(args.time_limit),
        resume: args.resume,
        overwrite: args.overwrite,
        shard: args.shard,
        vtu: args.vtu,
    };
    // The timer ticks on its own (it used to freeze while a point ran: the bar was redrawn only
    // when a point ended), and the message names the step under way, not the last one done.
    let bar = indicatif::ProgressBar::new(0).with_style(
        indicatif::ProgressStyle::with_template("{spinner} {bar:30} {pos}/{len} [{elapsed}] {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar.enable_steady_tick(Duration::from_millis(250));
    let outcome = signorini::sweep::sweep(
        &scene,
        &plan,
        &SolveOptions::default(),
        &limits(common),
        &args.out,
        |done, total, what| {
            bar.set_length(total as u64);
            bar.set_position(done as u64);
            bar.set_message(what.to_string());
        },
    );
    bar.finish_and_clear();
    let outcome = outcome?;
    let title = match args.shard {
        Some(s) => format!("{} (shard {s})", scene.title),
        None => scene.title.clone(),
    };
    let mut written = vec![outcome.csv.clone()];
    written.extend(outcome.plots.iter().cloned());
    written.extend(outcome.files.iter().cloned());
    sweep_report(
        &title,
        &outcome.points,
        &written,
        outcome.failed,
        outcome.skipped,
    )
}

pub(crate) fn sweep_merge(
    dirs: &[PathBuf],
    overwrite: bool,
    out: &std::path::Path,
) -> Result<Exit> {
    let outcome = signorini::sweep::merge::merge(dirs, out, overwrite)?;
    let mut written = vec![outcome.csv.clone()];
    written.extend(outcome.plots.iter().cloned());
    written.extend(outcome.files.iter().cloned());
    sweep_report(
        &format!(
            "{} (merged from {} shards)",
            outcome.manifest.title,
            dirs.len()
        ),
        &outcome.points,
        &written,
        outcome.failed,
        outcome.skipped,
    )
}

/// The table of a sweep's points, the files written and the summary; exit 2 when a point was
/// not solved or skipped.
pub(crate) fn sweep_report(
    title: &str,
    points: &[signorini::sweep::Point],
    written: &[PathBuf],
    failed: usize,
    skipped: usize,
) -> Result<Exit> {
    let mut con = Console::new();
    con.line(format_args!("{title}: {} points", points.len()))?;
    con.line(format_args!(
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
    ))?;
    for p in points {
        con.line(format_args!(
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
        ))?;
    }
    for p in written {
        con.line(format_args!("  wrote {}", p.display()))?;
    }
    let summary = format!(
        "sweep: {} of {} points solved, {} not solved, {} skipped after a time limit",
        points.len() - failed,
        points.len() + skipped,
        failed,
        skipped
    );
    if failed + skipped == 0 {
        con.line(summary)?;
        con.finish()?;
        Ok(Exit::Success)
    } else {
        con.finish()?;
        warn(format_args!("error: {summary}"));
        Ok(Exit::NotSolved)
    }
}
