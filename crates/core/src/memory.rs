//! How much memory the machine can give a run, and the one check every large allocation of a
//! backend (a sparse factor, a dense dual Hessian) goes through before it is made.

/// Bytes in a GiB.
pub const GIB: f64 = 1024.0 * 1024.0 * 1024.0;

/// Memory the process may still allocate, in bytes: `MemAvailable` of `/proc/meminfo` (Linux),
/// `None` where it cannot be read (then nothing is refused).
pub fn available_bytes() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    parse_available(&text)
}

fn parse_available(meminfo: &str) -> Option<u64> {
    let line = meminfo.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

/// `Err(QpError::TooLarge)` when `needed_bytes` exceeds the available memory.
pub fn check_fits(
    backend: &'static str,
    what: impl FnOnce() -> String,
    needed_bytes: f64,
) -> Result<(), crate::qp::QpError> {
    match available_bytes() {
        Some(available) if needed_bytes > available as f64 => Err(crate::qp::QpError::TooLarge {
            backend,
            what: what(),
            needed: needed_bytes / GIB,
            available: available as f64 / GIB,
        }),
        _ => Ok(()),
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
}
