//! `signorini compare`: one scene (or QP files), every backend, compare.json and compare.csv.

use anyhow::{Context, Result};
use std::path::PathBuf;

use signorini::backends::{BackendKind, ChoiceParser, Form};
use signorini::exit::Exit;
use signorini::run;

use crate::args::{limits, parse_backends, Common, SolveFlags};
use crate::console::{warn, Console};

/// `signorini compare SCENE …`: the options of a comparison.
#[derive(clap::Args)]
pub(crate) struct CompareArgs {
    #[command(flatten)]
    pub(crate) common: Common,
    /// Comma-separated backends [default: clarabel,osqp,dual-pgs,dual-uzawa, those compiled in].
    #[arg(long, value_delimiter = ',', value_parser = ChoiceParser::<BackendKind>::new())]
    pub(crate) backends: Vec<BackendKind>,
    /// Comma-separated forms each of clarabel and osqp runs in; the other backends run
    /// once, in their own form [default: as named in --backends].
    #[arg(long, value_delimiter = ',', value_parser = ChoiceParser::<Form>::new())]
    pub(crate) forms: Vec<Form>,
    #[command(flatten)]
    pub(crate) solve: SolveFlags,
    /// Output directory for compare.json and compare.csv (created if missing).
    #[arg(long, default_value = "out")]
    pub(crate) out: PathBuf,
    /// Instead of a scene: a directory holding a QP as Matrix Market files A.mtx, f.mtx,
    /// B.mtx, g.mtx (the layout `export` writes; docs/scene.md), from this or another code;
    /// with blocks.csv (row,kind,bound) its box rows are friction's |lambda| <= bound rows,
    /// without it every row is one-sided, Bx <= g.
    #[arg(long, value_name = "DIR", conflicts_with_all = ["scene", "max_elements"])]
    pub(crate) qp: Option<PathBuf>,
    /// Instead of a scene: an FCLIB global problem (HDF5, spacedim 2: M, H, f, w, mu), as
    /// `export --fclib` writes it or another code (Siconos, LMGC90) does; each backend's answer
    /// is also measured against the file's stored /solution (docs/comparing-solvers.md).
    #[arg(long, value_name = "FILE", conflicts_with_all = ["scene", "max_elements", "qp"])]
    pub(crate) fclib: Option<PathBuf>,
}

pub(crate) fn compare(args: &CompareArgs) -> Result<Exit> {
    let (common, out, qp) = (&args.common, args.out.as_path(), args.qp.as_deref());
    let kinds = parse_backends(&args.backends, &args.forms)?;
    let options = args.solve.options();
    let bar = indicatif::ProgressBar::new(kinds.len() as u64).with_style(
        indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let progress = |name: &str| {
        bar.set_message(name.to_string());
        bar.inc(1);
    };
    use signorini::compare::QpCompareError;
    // Each cause as its own error, so that `classify` sees it (a transparent wrapper would hide
    // it): refused files exit 1, a factor that does not fit exits 3.
    let cause = |e: QpCompareError| match e {
        QpCompareError::Files(e) => anyhow::Error::new(e),
        QpCompareError::Fclib(e) => anyhow::Error::new(e),
        QpCompareError::Preflight(e) => anyhow::Error::new(e),
        QpCompareError::Run(e) => anyhow::Error::new(e),
        e @ QpCompareError::NoRows(_) => anyhow::Error::new(e),
    };
    let fclib = args.fclib.as_deref();
    let report = match (qp, fclib) {
        (Some(dir), _) => {
            signorini::compare::compare_qp(dir, &kinds, &options, progress).map_err(cause)?
        }
        (None, Some(file)) => {
            signorini::compare::compare_fclib(file, &kinds, &options, progress).map_err(cause)?
        }
        (None, None) => {
            let scene = run::load_scene(common.scene.as_deref())?;
            signorini::compare::compare(&scene, &kinds, &options, &limits(common), progress)?
        }
    };
    bar.finish_and_clear();
    let mut report = report;
    let settings = signorini_core::report::BackendSettings {
        backend: kinds
            .iter()
            .map(|k| k.name().to_string())
            .collect::<Vec<_>>()
            .join(","),
        form: signorini::contract::forms(&kinds),
        tolerance: options.tol,
        time_limit_s: options.time_limit.map(|t| t.as_secs_f64()),
        max_iter: options.max_iter,
        chain: Vec::new(),
        coulomb: options.coulomb,
    };
    report.provenance = Some(match (qp, fclib) {
        (Some(dir), _) => signorini::contract::qp_provenance(dir, settings)
            .with_context(|| format!("reading {} for its hash", dir.display()))?,
        (None, Some(file)) => signorini::contract::provenance(Some(file), settings)
            .with_context(|| format!("reading {} for its hash", file.display()))?,
        (None, None) => signorini::contract::provenance(common.scene.as_deref(), settings)?,
    });
    let written = signorini::compare::write(out, &report)
        .with_context(|| format!("writing comparison to {}", out.display()))?;
    let mut con = Console::new();
    for line in signorini::compare::table(&report).lines() {
        con.line(line)?;
    }
    for p in &written {
        con.line(format_args!("  wrote {}", p.display()))?;
    }
    con.finish()?;
    let failed: Vec<&str> = report
        .backends
        .iter()
        .filter(|r| r.status != "solved")
        .map(|r| r.backend.as_str())
        .collect();
    if failed.is_empty() {
        Ok(Exit::Success)
    } else {
        warn(format_args!("error: not solved by {}", failed.join(", ")));
        Ok(Exit::NotSolved)
    }
}
