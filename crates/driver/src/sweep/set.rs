//! The sweep's output set: its members, and the checkpoint written after every point.

use super::rows::write_csv;
use super::shard::{self, Manifest};
use super::{Point, SOLUTIONS_FILE, SWEEP_FILE};
use crate::outdir::{DirLock, OutputSet};
use crate::output::OutputError;

/// The files of a sweep's output set: the CSV (primary), the plots, the shard's manifest and
/// the solutions' collection (the last two are removed when a run does not write them).
pub(crate) fn sweep_members() -> Vec<&'static str> {
    std::iter::once(SWEEP_FILE)
        .chain(crate::plots::PLOT_FILES)
        .chain([shard::MANIFEST_FILE, SOLUTIONS_FILE])
        .collect()
}

/// Replaces `sweep.csv` by `points` (and `shard.json` by `manifest`, if any) and removes the
/// plots (they no longer match).
pub(super) fn checkpoint(
    lock: &DirLock,
    points: &[Point],
    manifest: Option<&Manifest>,
) -> Result<(), OutputError> {
    let mut set = OutputSet::new(lock, Some(SWEEP_FILE), &sweep_members())?;
    set.write(SWEEP_FILE, |w| write_csv(w, points))?;
    if let Some(m) = manifest {
        set.write(shard::MANIFEST_FILE, |w| m.write(w))?;
    }
    set.commit().map(drop)
}
