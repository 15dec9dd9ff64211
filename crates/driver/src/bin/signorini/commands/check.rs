//! `signorini check`: a scene validated as solve would, without solving.

use anyhow::Result;
use signorini::exit::Exit;
use signorini::run;

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

pub(crate) fn check(common: &Common) -> Result<Exit> {
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
    let gib = |b: f64| b / 1024f64.powi(3);
    con.line(format_args!(
        "  memory estimate for solve: {:.2} GiB (clarabel, osqp), {:.2} GiB (dual backends, sparse part)",
        gib(e.bytes as f64),
        gib(e.bytes_dual as f64)
    ))?;
    if report.constraints > 0 {
        // The dual backends also hold the dense m × m contact Hessian H = B A⁻¹ Bᵀ (dual-ssn
        // about three such arrays: H, its Newton matrix and that matrix's factor), which the
        // scene-based model above does not count; with m known after assembly it is exact.
        let m = report.constraints as f64;
        con.line(format_args!(
            "  + the dense contact Hessian of the dual backends: 8·m² B = {} for m = {} rows (dual-ssn holds about three such arrays; each backend checks the memory before forming it)",
            size(8.0 * m * m),
            report.constraints
        ))?;
    }
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
