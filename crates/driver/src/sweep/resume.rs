//! `--resume`: an existing `sweep.csv` read and verified against this scene and plan.

use std::collections::HashMap;
use std::path::Path;

use super::plan::{grid, key, plan_index};
use super::rows::read_rows_strict;
use super::shard::Shard;
use super::{Point, SweepError, SweepPlan};
use crate::output::OutputError;

/// Reads an existing `sweep.csv` for `--resume` and verifies it against this scene and plan:
/// a header equal to [`COLUMNS`] (a file without `scene_hash` was written by an older version),
/// every line ended by a line break, every row complete and readable, its `scene_hash` equal to
/// `hash`, its hmax, backend and tolerance part of the plan, and no (hmax, backend, tolerance)
/// twice.  The first violation is refused with [`SweepError::Resume`] naming its line.
pub fn read_for_resume(
    path: &Path,
    hash: &str,
    plan: &SweepPlan,
) -> Result<Vec<Point>, SweepError> {
    let refuse = |line: u64, reason: String| SweepError::Resume {
        path: path.to_path_buf(),
        line,
        reason,
    };
    let bytes = std::fs::read(path).map_err(|source| OutputError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let the_grid = grid(plan);
    let (hmaxes, tols, backends) = &the_grid;
    let mut seen: HashMap<String, u64> = HashMap::new();
    let mut points = Vec::new();
    read_rows_strict(bytes, refuse, |line, p| {
        if p.scene_hash != hash {
            return Err(refuse(
                line,
                format!(
                    "scene_hash {} is not this scene's {hash}: the file belongs to another scene (or other --bodies)",
                    p.scene_hash
                ),
            ));
        }
        if !hmaxes.iter().any(|h| h.to_bits() == p.hmax.to_bits()) {
            return Err(refuse(line, format!("hmax {} is not in --hmax", p.hmax)));
        }
        if !tols.iter().any(|t| t.to_bits() == p.tol.to_bits()) {
            return Err(refuse(line, format!("tol {:e} is not in --tol", p.tol)));
        }
        if !backends.iter().any(|b| b.name() == p.backend) {
            return Err(refuse(
                line,
                format!("backend \"{}\" is not in --backends", p.backend),
            ));
        }
        if let (Some(s), Some(k)) = (plan.shard, plan_index(&the_grid, &p)) {
            if !s.owns(k) {
                return Err(refuse(
                    line,
                    format!(
                        "point {k} of the plan belongs to shard {}/{}, not to this shard {s}",
                        Shard::of_point(k, s.count),
                        s.count
                    ),
                ));
            }
        }
        if let Some(first) = seen.insert(key(p.hmax, &p.backend, p.tol), line) {
            return Err(refuse(
                line,
                format!(
                    "repeats the point of line {first} (hmax {}, {}, tol {:e})",
                    p.hmax, p.backend, p.tol
                ),
            ));
        }
        points.push(p);
        Ok(())
    })?;
    Ok(points)
}
