//! `signorini qpset`: scenes exported as a qpbenchmark test set (see `signorini::qpset`).

use std::path::PathBuf;

use anyhow::{Context, Result};
use signorini::exit::Exit;
use signorini::qpset::{self, SetOptions};
use signorini_core::mesh::MeshLimits;

use crate::args::{parse_time_limit, parse_tol, time_limit};
use crate::console::{warn, Console};
use signorini::backends::{BackendKind, ChoiceParser};
use signorini_core::qp::SolveOptions;

/// `signorini qpset DIR… --out SET`: the options of a test-set export.
#[derive(clap::Args)]
pub(crate) struct QpsetArgs {
    /// Directories whose scene files (`*.toml`, recursively) become the set's problems.
    #[arg(required_unless_present = "solve")]
    pub(crate) dirs: Vec<PathBuf>,
    /// The set's directory: written whole (built beside it, then renamed into place).  With
    /// `--solve`: the results CSV to write (qpbenchmark's columns).
    #[arg(long)]
    pub(crate) out: PathBuf,
    /// Instead of writing a set: run our backends on the set SET's problems and write one row
    /// per problem and backend in qpbenchmark's results format (CSV) to `--out`.
    #[arg(long, value_name = "SET", conflicts_with_all = ["dirs", "raw", "large", "force"])]
    pub(crate) solve: Option<PathBuf>,
    /// With `--solve`: comma-separated backends [default: every one compiled in, both forms].
    #[arg(long, value_delimiter = ',', value_parser = ChoiceParser::<BackendKind>::new())]
    pub(crate) backends: Vec<BackendKind>,
    /// With `--solve`: the settings name the rows are filed under, which also decides the run
    /// as qpbenchmark's settings do: `high_accuracy` (`mid_accuracy`, `low_accuracy`) drives
    /// each backend to qpbenchmark's absolute residuals of 1e-9 (1e-6, 1e-3), tightening `--tol`
    /// as needed; any other name solves at `--tol`.
    #[arg(long, default_value = "default")]
    pub(crate) settings: String,
    /// With `--solve`: seconds each backend may take per problem.
    #[arg(long, value_parser = parse_time_limit)]
    pub(crate) time_limit: Option<f64>,
    /// Replace an existing non-empty output directory.
    #[arg(long)]
    pub(crate) force: bool,
    /// Export the QP in the scenes' own units instead of the nondimensionalised form the
    /// backends see.
    #[arg(long)]
    pub(crate) raw: bool,
    /// Refine every scene (its element sizes scaled down together) to about this many
    /// unknowns; `--large` alone: 10⁶.
    #[arg(long, value_name = "DOFS", num_args = 0..=1, default_missing_value = "1000000")]
    pub(crate) large: Option<usize>,
    /// Relative KKT tolerance of the reference solve (our `auto` backend); with `--solve`, of
    /// every backend's (first) solve.
    #[arg(long, default_value_t = 1e-9, value_parser = parse_tol)]
    pub(crate) tol: f64,
    /// Largest total number of elements a scene may ask for before it is refused.
    #[arg(long, default_value_t = 5_000_000)]
    pub(crate) max_elements: usize,
}

pub(crate) fn qpset(args: &QpsetArgs) -> Result<Exit> {
    if let Some(set) = &args.solve {
        return solve(args, set);
    }
    let scenes = qpset::scene_files(&args.dirs)?;
    let options = SetOptions {
        raw: args.raw,
        tol: args.tol,
        limits: MeshLimits {
            max_elements: args.max_elements,
            ..MeshLimits::default()
        },
        large: args.large,
        force: args.force,
    };
    let summary = qpset::write_set(&scenes, &args.out, &options, &mut |line| {
        warn(format_args!("{line}"))
    })?;
    let mut con = Console::new();
    con.line(format_args!(
        "wrote {} problems to {} ({} scenes skipped, {} failed)",
        summary.written.len(),
        args.out.display(),
        summary.skipped.len(),
        summary.failed.len()
    ))?;
    con.finish()?;
    Ok(Exit::Success)
}

/// `--solve SET`: our backends on the set, rows in qpbenchmark's results format.
fn solve(args: &QpsetArgs, set: &std::path::Path) -> Result<Exit> {
    let kinds: Vec<BackendKind> = if args.backends.is_empty() {
        BackendKind::ALL
            .into_iter()
            .chain(BackendKind::EXTRA)
            .filter(|k| k.available())
            .collect()
    } else {
        args.backends.clone()
    };
    let options = SolveOptions {
        tol: args.tol,
        time_limit: time_limit(args.time_limit),
        ..SolveOptions::default()
    };
    let rows = qpset::run_set(set, &kinds, &args.settings, &options, &mut |line| {
        warn(format_args!("{line}"))
    })?;
    let mut csv = csv::Writer::from_path(&args.out)
        .with_context(|| format!("writing {}", args.out.display()))?;
    for row in &rows {
        csv.serialize(row)?;
    }
    csv.flush()
        .with_context(|| format!("writing {}", args.out.display()))?;
    let mut con = Console::new();
    con.line(format_args!(
        "{} runs ({} problems x {} backends) written to {}",
        rows.len(),
        rows.len() / kinds.len().max(1),
        kinds.len(),
        args.out.display()
    ))?;
    con.finish()?;
    Ok(Exit::Success)
}
