//! `--vtu`: each point's solution as `solutions/<point>.vtu` and their ParaView collection
//! (`solutions.pvd`).

use std::path::Path;

use signorini_core::scene::Scene;
use signorini_core::solve::Solution;

use super::plan::{plan_index, Grid};
use super::{Point, SOLUTIONS_DIR};
use crate::outdir::{DirLock, OutputSet};
use crate::output::OutputError;

/// The VTU file of point `p` (from 1) of a plan of `total` points, inside [`SOLUTIONS_DIR`]:
/// `<p>_h<hmax>_<backend>_tol<tol>.vtu`, `p` zero-padded to the width of `total`, a `/` in the
/// backend's name (`clarabel/dual`) written `-`.
pub fn solution_file_name(p: usize, total: usize, hmax: f64, backend: &str, tol: f64) -> String {
    let width = total.max(1).to_string().len();
    format!(
        "{p:0width$}_h{hmax}_{}_tol{tol:e}.vtu",
        backend.replace(['/', '\\'], "-")
    )
}

/// Writes the PVD collection: one `DataSet` per `(timestep, file, label)`.
pub(crate) fn write_pvd(
    w: &mut dyn std::io::Write,
    entries: &[(usize, String, String)],
) -> std::io::Result<()> {
    use crate::output::xml_escape;
    writeln!(w, "<?xml version=\"1.0\"?>")?;
    writeln!(
        w,
        "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">"
    )?;
    writeln!(w, "  <Collection>")?;
    for (step, file, label) in entries {
        // Labels are built from numbers and backend names: no "--" can occur in them.
        writeln!(w, "    <!-- {} -->", label.replace("--", "- -"))?;
        writeln!(
            w,
            "    <DataSet timestep=\"{step}\" group=\"\" part=\"0\" file=\"{}\"/>",
            xml_escape(file)
        )?;
    }
    writeln!(w, "  </Collection>")?;
    writeln!(w, "</VTKFile>")
}

/// The collection's entries: every point of `points` whose VTU exists under `dir`, in plan
/// order.
pub(super) fn pvd_entries(
    dir: &Path,
    grid: &Grid,
    total: usize,
    points: &[Point],
) -> Vec<(usize, String, String)> {
    let mut entries: Vec<(usize, String, String)> = points
        .iter()
        .filter_map(|pt| {
            let p = plan_index(grid, pt)?;
            let name = solution_file_name(p, total, pt.hmax, &pt.backend, pt.tol);
            dir.join(SOLUTIONS_DIR).join(&name).is_file().then(|| {
                (
                    p,
                    format!("{SOLUTIONS_DIR}/{name}"),
                    format!(
                        "point {p}: hmax {}, {}, tol {:e}, {}",
                        pt.hmax, pt.backend, pt.tol, pt.status
                    ),
                )
            })
        })
        .collect();
    entries.sort_by_key(|e| e.0);
    entries
}

/// Writes one point's solution as `name` into the locked `solutions/` directory (its own
/// output set: complete or absent).
pub(super) fn write_solution(
    lock: &DirLock,
    scene: &Scene,
    model: &signorini_core::model::Model,
    sol: &Solution,
    name: &str,
) -> Result<(), OutputError> {
    let fields = signorini_core::report::body_fields(model, sol);
    let bodies = crate::output::BodyField::of_bodies(&model.meshes, &fields, &scene.bodies);
    crate::output::check_fields(&bodies)?;
    let mut set = OutputSet::new(lock, Some(name), &[name])?;
    set.write(name, |w| crate::output::write_vtu_to(w, &bodies))?;
    set.commit().map(drop)
}
