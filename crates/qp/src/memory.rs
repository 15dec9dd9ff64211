//! How much memory the machine can give a run, and the one check every large allocation of a
//! backend (a sparse factor, a KKT factor, a dense dual Hessian) goes through before it is made.
//!
//! A run is priced as a whole before anything large is allocated (the driver's guard: the
//! problem copies the solve path holds plus the backend's own peak, the figure `signorini check`
//! prints).  What the run already holds while a backend allocates is [`hold`]-ed on the running
//! thread, and [`check_fits`] counts it: so each allocation's check is a check of the sum held
//! at that moment, never of the allocation alone (a dense H that fits on its own beside a
//! factor of A that already fills the limit is refused, or, where a backend has a leaner path,
//! not taken).
//!
//! The memory available is `MemAvailable` of `/proc/meminfo`, capped by the user's
//! [`LIMIT_VAR`] (`SIGNORINI_MEMORY_LIMIT`, e.g. `512M`): the binary refuses a bad value of it
//! before it starts (exit 1, naming the variable); a library caller that did not check it gets
//! nothing allocated at all (an unparsable limit counts as 0 bytes, so every check refuses),
//! never a limit silently ignored.

mod kkt;
mod limit;

pub use kkt::{KktEstimate, KktModel};
pub use limit::{limit_from_env, parse_limit, LimitError, LIMIT_VAR};

/// A size in GiB, written for a message: `0.5 GiB (512.0 MiB)`, `12.0 GiB`, `1.20e5 GiB`.
pub fn gib_f64(g: f64) -> String {
    if g < 1.0 {
        format!("{g:.1} GiB ({:.1} MiB)", g * 1024.0)
    } else if g < 1e4 {
        format!("{g:.1} GiB")
    } else {
        format!("{g:.2e} GiB")
    }
}

/// Bytes in a GiB.
pub const GIB: f64 = 1024.0 * 1024.0 * 1024.0;

/// Memory the process may still allocate, in bytes: the smaller of `MemAvailable` of
/// `/proc/meminfo` (Linux) and the limit [`LIMIT_VAR`] sets (0 when its value is not a size:
/// see the module documentation); `None` when neither is known (then nothing is refused).
pub fn available_bytes() -> Option<u64> {
    let limit = limit_from_env().unwrap_or(Some(0));
    let meminfo = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|text| parse_available(&text));
    match (meminfo, limit) {
        (Some(free), Some(cap)) => Some(free.min(cap)),
        (free, cap) => free.or(cap),
    }
}

fn parse_available(meminfo: &str) -> Option<u64> {
    let line = meminfo.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

thread_local! {
    /// Bytes the running thread's solve holds already (see [`hold`]).
    static HELD: std::cell::Cell<f64> = const { std::cell::Cell::new(0.0) };
}

/// Bytes the current thread holds by [`hold`] (0 outside a guarded run).
pub fn held_bytes() -> f64 {
    HELD.with(std::cell::Cell::get)
}

/// Memory a run holds while its backend allocates more, counted by every [`check_fits`] on this
/// thread until the guard is dropped.  Not `Send`: it belongs to the thread that runs the solve.
#[derive(Debug)]
#[must_use = "the bytes are held only while the guard lives"]
pub struct Held {
    bytes: f64,
    _thread: std::marker::PhantomData<*const ()>,
}

impl Held {
    /// The bytes held by this guard.
    pub fn bytes(&self) -> f64 {
        self.bytes
    }
}

/// Counts `bytes` (negative or non-finite values count as 0) as held by the current thread
/// until the returned guard is dropped: every [`check_fits`] meanwhile adds them to its need.
pub fn hold(bytes: f64) -> Held {
    let bytes = if bytes.is_finite() {
        bytes.max(0.0)
    } else {
        0.0
    };
    HELD.with(|h| h.set(h.get() + bytes));
    Held {
        bytes,
        _thread: std::marker::PhantomData,
    }
}

impl Drop for Held {
    fn drop(&mut self) {
        HELD.with(|h| h.set((h.get() - self.bytes).max(0.0)));
    }
}

/// `Err(QpError::TooLarge)` when `needed_bytes`, plus what the current thread holds already
/// ([`hold`]), exceeds the available memory.  The message names the sum.
pub fn check_fits(
    backend: &'static str,
    what: impl FnOnce() -> String,
    needed_bytes: f64,
) -> Result<(), crate::QpError> {
    let held = held_bytes();
    let total = needed_bytes + held;
    match available_bytes() {
        Some(available) if total > available as f64 => Err(crate::QpError::TooLarge {
            backend,
            what: if held > 0.0 {
                format!(
                    "{} beside the {} the run holds already",
                    what(),
                    gib_f64(held / GIB)
                )
            } else {
                what()
            },
            needed: total / GIB,
            available: available as f64 / GIB,
        }),
        _ => Ok(()),
    }
}

/// The memory a run that factors A needs at its peak, from the symbolic analysis of A (before
/// any numeric factorisation): what every path that factors A holds at once (the floor, the
/// direct solve, the dual backends' factor).  Backends add their own terms (a KKT factor, a
/// dense dual Hessian) and check them with [`check_fits`] before allocating them.  So it is a
/// lower bound of a run's peak: a run refused on it cannot fit; one that passes may still be
/// refused later by its backend.  (At 1 276 480 DOFs of the seed geometry it comes to 1.95 GiB
/// — factor 1.36 GiB, scratch 0.28 GiB — where `compare --backends dual-ssn` peaked at 2.34 GiB
/// resident.)
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FactorEstimate {
    /// The factor's values: 8 B per value the supernodal factor stores.
    pub factor: f64,
    /// The numeric factorisation's scratch space (its largest frontal update).
    pub scratch: f64,
    /// A and B in CSC (12 B per nonzero: value + row index, 8 B per column pointer) and the
    /// model's copy of B over all DOFs, counted as B again.
    pub matrices: f64,
    /// Vectors and index arrays of size n: the load, a solution, the permutation and its
    /// inverse, the elimination tree, taken as 8 vectors of 8 B.
    pub vectors: f64,
}

impl FactorEstimate {
    /// Estimates the peak of a run on `qp` whose factor of A was analysed as `pattern`.
    pub fn of(qp: &crate::QpProblem, pattern: &crate::linalg::CholeskyPattern) -> Self {
        let csc = |m: &crate::CscMatrix| 12.0 * m.nnz() as f64 + 8.0 * (m.cols() + 1) as f64;
        let n = qp.dofs() as f64;
        Self {
            factor: 8.0 * pattern.stored_values() as f64,
            scratch: pattern.numeric_scratch_bytes(),
            matrices: csc(&qp.stiffness) + 2.0 * csc(&qp.constraints),
            vectors: 8.0 * 8.0 * n,
        }
    }

    /// The total, bytes.
    pub fn total(&self) -> f64 {
        self.factor + self.scratch + self.matrices + self.vectors
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_mem_available_in_kib() {
        let text = "MemTotal:       24000000 kB\nMemFree:  100 kB\nMemAvailable:   2048 kB\n";
        assert_eq!(parse_available(text), Some(2048 * 1024));
        assert_eq!(parse_available("MemTotal: 1 kB\n"), None);
    }

    #[test]
    fn an_impossible_need_is_refused_with_its_size() {
        if available_bytes().is_none() {
            return;
        }
        let err = check_fits("test", || "a petabyte".into(), 1e15).unwrap_err();
        assert!(err.to_string().contains("a petabyte"), "{err}");
        assert!(check_fits("test", || "a byte".into(), 1.0).is_ok());
    }

    /// What a run holds counts in every check on its thread until the guard is dropped.
    #[test]
    fn held_bytes_count_in_the_check_until_dropped() {
        let Some(available) = available_bytes() else {
            return;
        };
        let half = 0.6 * available as f64;
        assert!(check_fits("test", || "a half".into(), half).is_ok());
        let held = hold(half);
        assert_eq!(held_bytes(), half);
        let err = check_fits("test", || "a half".into(), half).unwrap_err();
        assert!(err.to_string().contains("holds already"), "{err}");
        // Another thread holds nothing.
        let other = std::thread::spawn(move || check_fits("t", String::new, half).is_ok());
        assert!(other.join().unwrap());
        drop(held);
        assert_eq!(held_bytes(), 0.0);
        assert!(check_fits("test", || "a half".into(), half).is_ok());
    }
}
