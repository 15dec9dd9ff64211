//! `signorini check`: a scene validated as solve would, without solving.

use anyhow::Result;
use signorini::check::MemoryNeeds;
use signorini::exit::Exit;
use signorini::run;
use signorini_core::memory::LIMIT_VAR;

use crate::args::{limits, Common};
use crate::console::Console;

/// `bytes` in GiB, MiB or KiB, whichever shows it with two or three digits.
fn size(bytes: f64) -> String {
    let (kib, mib, gib) = (1024.0, 1024f64.powi(2), 1024f64.powi(3));
    if bytes >= 0.1 * gib {
        format!("{:.2} GiB", bytes / gib)
    } else if bytes >= 0.1 * mib {
        format!("{:.1} MiB", bytes / mib)
    } else {
        format!("{:.1} KiB", bytes / kib)
    }
}

/// `signorini check SCENE`: the options of a check.
#[derive(clap::Args)]
pub(crate) struct CheckArgs {
    #[command(flatten)]
    pub(crate) common: Common,
}

pub(crate) fn check(args: &CheckArgs) -> Result<Exit> {
    let common = &args.common;
    let scene = run::load_scene(common.scene.as_deref())?;
    // Everything solve verifies before its backend runs; "valid" only once all of it passed.
    let report = signorini::check::check(&scene, &limits(common))?;
    let mut con = Console::new();
    con.line(format_args!("{}: valid", scene.title))?;
    let e = &report.estimate;
    for (body, estimate) in scene.bodies.iter().zip(&e.bodies) {
        con.line(format_args!(
            "  body {:<10} hmax {:<8} ~{} elements (estimated before meshing)",
            body.name, body.hmax, estimate.elements
        ))?;
    }
    con.line(format_args!(
        "  {} elements meshed (~{} estimated), {} free DOFs, {} contact rows",
        report.elements, e.elements, report.dofs, report.constraints
    ))?;
    con.line(format_args!(
        "  memory estimate before meshing: {} (clarabel, osqp), {} (dual backends, sparse part)",
        size(e.bytes as f64),
        size(e.bytes_dual as f64)
    ))?;
    if report.constraints > 0 {
        let m = report.constraints as f64;
        con.line(format_args!(
            "  + the dense contact Hessian of the dual backends: 8·m² B = {} for m = {} rows",
            size(8.0 * m * m),
            report.constraints
        ))?;
    }
    print_memory(&mut con, &report.memory)?;
    con.line(format_args!(
        "  {} dirichlet, {} neumann, {} contact pair(s), {} probe(s)",
        scene.dirichlet.len(),
        scene.neumann.len(),
        scene.contacts.len(),
        scene.probes.len()
    ))?;
    con.finish()?;
    Ok(Exit::Success)
}

/// Every backend's memory need from the symbolic analyses, the largest named, against what is
/// available.
fn print_memory(con: &mut Console, needs: &MemoryNeeds) -> Result<()> {
    let available = match needs.available {
        Some(bytes) => format!("{} available", size(bytes as f64)),
        None => "available memory unknown".to_string(),
    };
    con.line(format_args!(
        "  memory from the symbolic analyses ({available}; {LIMIT_VAR} caps it):"
    ))?;
    con.line(format_args!(
        "    {:<14} {:>10}  the factor of A, its scratch, A, B and vectors (solve checks it before any backend; the timing floor and the dual backends factor A)",
        "factor of A",
        size(needs.base)
    ))?;
    let fits = |bytes: f64| match needs.available {
        Some(free) if bytes > free as f64 => "  [does not fit]",
        _ => "",
    };
    for need in &needs.backends {
        con.line(format_args!(
            "    {:<14} {:>10}  {}{}",
            need.backend,
            size(need.bytes),
            need.what,
            fits(need.bytes)
        ))?;
    }
    if let Some(largest) = needs.largest() {
        con.line(format_args!(
            "  largest memory need: {} ({}); solve refuses a backend marked [does not fit] (exit 3)",
            largest.backend,
            size(largest.bytes)
        ))?;
    }
    Ok(())
}
