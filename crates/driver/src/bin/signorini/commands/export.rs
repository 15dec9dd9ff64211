//! `signorini export`: the scene's QP as Matrix Market files.

use std::path::PathBuf;

use anyhow::{Context, Result};
use signorini::exit::Exit;
use signorini::run;

use crate::args::{limits, Common};
use crate::console::Console;

/// `signorini export SCENE …`: the options of an export.
#[derive(clap::Args)]
pub(crate) struct ExportArgs {
    #[command(flatten)]
    pub(crate) common: Common,
    /// Output directory (created if missing).
    #[arg(long, default_value = "out")]
    pub(crate) out: PathBuf,
}

pub(crate) fn export(args: &ExportArgs) -> Result<Exit> {
    let (common, out) = (&args.common, args.out.as_path());
    let scene = run::load_scene(common.scene.as_deref())?;
    let prepared = run::prepare(&scene, &limits(common))?;
    let qp = &prepared.qp;
    let written = signorini::export::export(out, &scene, &prepared.model, qp)
        .with_context(|| format!("exporting to {}", out.display()))?;
    let mut con = Console::new();
    con.line(format_args!(
        "{}: {} unknowns, {} contact rows",
        scene.title,
        qp.dofs(),
        qp.rows()
    ))?;
    for p in &written {
        con.line(format_args!("  wrote {}", p.display()))?;
    }
    con.finish()?;
    Ok(Exit::Success)
}
