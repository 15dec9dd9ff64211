//! `signorini sweep` and `sweep merge`: mesh refinement × backends × tolerances, sweep.csv and plots.

use std::path::PathBuf;
use std::time::Duration;

use anyhow::Result;
use signorini::exit::Exit;
use signorini::run;
use signorini_core::qp::SolveOptions;

use crate::args::{limits, parse_backends, time_limit};
use crate::console::{warn, Console};
use crate::SweepArgs;

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
