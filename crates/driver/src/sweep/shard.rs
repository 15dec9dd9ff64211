//! Sweeps split across machines: `--shard I/N`, the shard's manifest and its per-point files.
//!
//! # Which points a shard runs
//!
//! The plan's points are the (hmax, tolerance, backend) triples in the order a sweep runs them:
//! hmax coarse to fine, then tolerances tightest first, then backends in the order given
//! (duplicates dropped).  Numbered from 1 in that order, point `p` of a plan with `P` points is
//! run by shard `I` of `N` when `p ≡ I (mod N)`: shard `I` runs points `I, I + N, I + 2N, …`
//! (up to `P`).  Every point belongs to exactly one shard, so shards `1/N … N/N` together cover
//! the whole plan; a shard with `I > P` runs nothing.
//!
//! # What a shard writes
//!
//! Beside `sweep.csv` (its own points, in the same format, `error_vs_reference` and
//! `error_vs_finest` left empty since they need points of other shards) a shard writes:
//!
//! * `shard.json` ([`Manifest`]): the study (scene hash, swept bodies, grid, backends,
//!   tolerances), the shard `I/N`, the plan's point count, whether the shard finished, and
//!   which of its points were skipped after a time limit.  It is part of the sweep's output set,
//!   rewritten with every checkpoint (`complete: false`) and at the end (`complete: true`).
//! * `displacements/<p>.u` for each point `p` it ran ([`write_point_data`]): the residual that
//!   ranks a mesh's reference ([`signorini_core::qp::KktResiduals::worst`]) and the nodal
//!   displacement vector, so that `sweep merge` computes `error_vs_reference` exactly as an
//!   unsharded sweep does.  Layout: the 8 bytes `SIGU\x01\0\0\0`, the residual (f64), the
//!   length `n` (u64), then `n` f64 values, all little-endian.

use std::fmt;
use std::io::{self, Read, Write};
use std::path::Path;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

/// Shard `index` of `count` (`1 ≤ index ≤ count`); parsed from `I/N`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Shard {
    /// `I`, from 1.
    pub index: usize,
    /// `N`, at least 1.
    pub count: usize,
}

impl Shard {
    /// Whether the shard runs point `p` (numbered from 1 in plan order): `p ≡ I (mod N)`.
    pub fn owns(&self, p: usize) -> bool {
        p >= 1 && (p - 1) % self.count == self.index - 1
    }

    /// The points (numbered from 1) of a plan of `total` points this shard runs.
    pub fn points(&self, total: usize) -> Vec<usize> {
        (self.index..=total).step_by(self.count).collect()
    }

    /// The shard that runs point `p` (from 1) when the plan is split `count` ways.
    pub fn of_point(p: usize, count: usize) -> usize {
        (p - 1) % count + 1
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl FromStr for Shard {
    type Err = String;

    /// `I/N` with integers `1 ≤ I ≤ N`.
    fn from_str(text: &str) -> Result<Self, Self::Err> {
        let usage = || format!("`{text}` is not I/N (shard I of N, 1 ≤ I ≤ N), e.g. 2/8");
        let (i, n) = text.trim().split_once('/').ok_or_else(usage)?;
        let index: usize = i.trim().parse().map_err(|_| usage())?;
        let count: usize = n.trim().parse().map_err(|_| usage())?;
        if count == 0 {
            return Err(format!(
                "`{text}`: the number of shards N must be at least 1"
            ));
        }
        if index == 0 || index > count {
            return Err(format!(
                "`{text}`: the shard number I must lie in 1..={count} (shards are numbered from 1)"
            ));
        }
        Ok(Shard { index, count })
    }
}

/// The name of a shard's manifest in its output directory.
pub const MANIFEST_FILE: &str = "shard.json";

/// The subdirectory of a shard's per-point displacement files.
pub const DISPLACEMENTS_DIR: &str = "displacements";

/// The value of [`Manifest::format`].
pub const MANIFEST_FORMAT: &str = "signorini-sweep-shard/1";

/// `shard.json`: what identifies a shard and its study (see the [module docs](self)).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Manifest {
    /// Always [`MANIFEST_FORMAT`].
    pub format: String,
    /// The signorini version that wrote the shard.
    pub version: String,
    /// The scene title (used for the merged plots' headings).
    pub title: String,
    /// [`super::scene_hash`] of the scene.
    pub scene_hash: String,
    /// The swept bodies (`--bodies`; empty: all).
    pub bodies: Vec<String>,
    /// The mesh sizes, coarse to fine.
    pub hmax: Vec<f64>,
    /// The backends, in plan order.
    pub backends: Vec<String>,
    /// The tolerances, tightest first.
    pub tols: Vec<f64>,
    /// Runs per point (`--repeat`; absent in manifests of earlier versions).
    #[serde(default)]
    pub repeat: Option<usize>,
    /// The time limit of one solve in seconds (`--time-limit`; absent: none).
    #[serde(default)]
    pub time_limit_s: Option<f64>,
    /// This shard.
    pub shard: Shard,
    /// The number of points of the whole plan.
    pub points: usize,
    /// Whether the shard ran to its end (false while it runs, or if it was interrupted).
    pub complete: bool,
    /// Points of this shard (numbered from 1) not run: their backend hit the time limit on a
    /// coarser mesh of this shard.
    pub skipped: Vec<usize>,
}

impl Manifest {
    /// Writes the manifest as pretty JSON.
    pub fn write(&self, w: &mut dyn Write) -> io::Result<()> {
        serde_json::to_writer_pretty(&mut *w, self).map_err(io::Error::other)?;
        writeln!(w)
    }
}

/// The file name of point `p`'s displacement data inside [`DISPLACEMENTS_DIR`].
pub fn point_data_name(p: usize) -> String {
    format!("{p}.u")
}

const MAGIC: [u8; 8] = *b"SIGU\x01\0\0\0";

/// Writes one point's data (see the [module docs](self) for the layout).
pub fn write_point_data(w: &mut dyn Write, worst: f64, u: &[f64]) -> io::Result<()> {
    w.write_all(&MAGIC)?;
    w.write_all(&worst.to_le_bytes())?;
    w.write_all(&(u.len() as u64).to_le_bytes())?;
    for v in u {
        w.write_all(&v.to_le_bytes())?;
    }
    Ok(())
}

/// Reads one point's data: `(worst residual, displacement)`; a wrong magic, length or a
/// truncated file is an error saying so.
pub fn read_point_data(path: &Path) -> Result<(f64, Vec<f64>), String> {
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|mut f| f.read_to_end(&mut bytes))
        .map_err(|e| e.to_string())?;
    if bytes.len() < 24 || bytes[..8] != MAGIC {
        return Err("not a signorini point data file (bad header)".into());
    }
    let f64_at = |i: usize| {
        let mut b = [0u8; 8];
        b.copy_from_slice(&bytes[i..i + 8]);
        b
    };
    let worst = f64::from_le_bytes(f64_at(8));
    let n = u64::from_le_bytes(f64_at(16));
    let expected = usize::try_from(n)
        .ok()
        .and_then(|n| n.checked_mul(8))
        .and_then(|b| b.checked_add(24));
    if expected != Some(bytes.len()) {
        return Err(format!(
            "{} bytes, but its header announces {n} values ({} bytes): truncated or damaged",
            bytes.len(),
            expected.map_or("too many".to_string(), |e| e.to_string())
        ));
    }
    let u = (0..n as usize)
        .map(|k| f64::from_le_bytes(f64_at(24 + 8 * k)))
        .collect();
    Ok((worst, u))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_partition_the_plan() {
        for total in 0..12 {
            for count in 1..6 {
                let mut all: Vec<usize> = (1..=count)
                    .flat_map(|i| Shard { index: i, count }.points(total))
                    .collect();
                all.sort_unstable();
                assert_eq!(all, (1..=total).collect::<Vec<_>>(), "{total} {count}");
                for p in 1..=total {
                    let owner = Shard::of_point(p, count);
                    assert!(Shard {
                        index: owner,
                        count
                    }
                    .owns(p));
                }
            }
        }
        assert_eq!(Shard { index: 2, count: 3 }.points(8), [2, 5, 8]);
    }

    #[test]
    fn shard_parsing() {
        assert_eq!("2/3".parse(), Ok(Shard { index: 2, count: 3 }));
        for bad in ["0/3", "4/3", "a/b", "1", "1/0", "-1/3", "1/3/4", ""] {
            assert!(bad.parse::<Shard>().is_err(), "{bad}");
        }
    }

    #[test]
    fn point_data_round_trips_and_refuses_truncation() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("1.u");
        let u = [1.5, -2.0, f64::MIN_POSITIVE, 3e300];
        let mut bytes = Vec::new();
        write_point_data(&mut bytes, 1e-10, &u).unwrap();
        std::fs::write(&path, &bytes).unwrap();
        assert_eq!(read_point_data(&path).unwrap(), (1e-10, u.to_vec()));
        std::fs::write(&path, &bytes[..bytes.len() - 1]).unwrap();
        assert!(read_point_data(&path).unwrap_err().contains("truncated"));
        std::fs::write(&path, b"hello world, not data at all").unwrap();
        assert!(read_point_data(&path).unwrap_err().contains("header"));
    }
}
