//! The user's memory limit, `SIGNORINI_MEMORY_LIMIT`: bytes with an optional K, M, G or T suffix
//! (powers of 1024; `512M`, `2G`, `1.5G`, `4096`; a trailing `B` or `iB` is accepted).

/// The environment variable that caps the memory a run may use (below `MemAvailable`).
pub const LIMIT_VAR: &str = "SIGNORINI_MEMORY_LIMIT";

/// A value of [`LIMIT_VAR`] that is not a memory size.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "{LIMIT_VAR}={value:?} is not a memory size: give bytes with an optional K, M, G or T suffix \
     (powers of 1024), e.g. {LIMIT_VAR}=512M, or unset it"
)]
pub struct LimitError {
    /// The value as set.
    pub value: String,
}

/// Parses a memory size: a non-negative finite number, optionally followed by K, M, G or T
/// (case-insensitive, powers of 1024) and optionally `B` or `iB`; spaces around are ignored.
///
/// ```
/// use signorini_qp::memory::parse_limit;
/// assert_eq!(parse_limit("512M"), Ok(512 << 20));
/// assert_eq!(parse_limit(" 1.5 GiB "), Ok(3 << 29));
/// assert!(parse_limit("lots").is_err());
/// ```
///
/// # Errors
/// [`LimitError`] for anything else (empty, negative, NaN, an unknown suffix, beyond u64).
pub fn parse_limit(text: &str) -> Result<u64, LimitError> {
    let error = || LimitError {
        value: text.to_string(),
    };
    let lower = text.trim().to_ascii_lowercase();
    let without_b = lower.strip_suffix('b').unwrap_or(&lower);
    let without_i = match without_b.strip_suffix('i') {
        Some(rest) if rest.ends_with(['k', 'm', 'g', 't']) => rest,
        _ => without_b,
    };
    let (number, power) = match without_i.char_indices().last() {
        Some((at, 'k')) => (&without_i[..at], 1),
        Some((at, 'm')) => (&without_i[..at], 2),
        Some((at, 'g')) => (&without_i[..at], 3),
        Some((at, 't')) => (&without_i[..at], 4),
        _ => (without_i, 0),
    };
    let number = number.trim();
    // Only digits and one dot: no sign, exponent, "inf" or "nan".
    if number.is_empty() || !number.chars().all(|c| c.is_ascii_digit() || c == '.') {
        return Err(error());
    }
    let value: f64 = number.parse().map_err(|_| error())?;
    let bytes = value * 1024f64.powi(power);
    // 2⁶⁴ itself does not fit in u64.
    if !(bytes.is_finite() && bytes < 18_446_744_073_709_551_616.0) {
        return Err(error());
    }
    Ok(bytes as u64)
}

/// The limit set in the environment: `Ok(None)` when [`LIMIT_VAR`] is unset.
///
/// # Errors
/// [`LimitError`] when it is set to something [`parse_limit`] refuses (or to non-Unicode).
pub fn limit_from_env() -> Result<Option<u64>, LimitError> {
    match std::env::var(LIMIT_VAR) {
        Ok(text) => parse_limit(&text).map(Some),
        Err(std::env::VarError::NotPresent) => Ok(None),
        Err(std::env::VarError::NotUnicode(value)) => Err(LimitError {
            value: value.to_string_lossy().into_owned(),
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_with_and_without_suffix() {
        assert_eq!(parse_limit("4096"), Ok(4096));
        assert_eq!(parse_limit("0"), Ok(0));
        assert_eq!(parse_limit("64K"), Ok(64 * 1024));
        assert_eq!(parse_limit("64kb"), Ok(64 * 1024));
        assert_eq!(parse_limit("3M"), Ok(3 * 1024 * 1024));
        assert_eq!(parse_limit("2G"), Ok(2 << 30));
        assert_eq!(parse_limit("2GiB"), Ok(2 << 30));
        assert_eq!(parse_limit("1T"), Ok(1 << 40));
        assert_eq!(parse_limit("0.5K"), Ok(512));
        assert_eq!(parse_limit("100B"), Ok(100));
    }

    #[test]
    fn anything_else_is_an_error_naming_the_variable() {
        for bad in [
            "",
            " ",
            "G",
            "-1G",
            "1e9",
            "inf",
            "nan",
            "1.2.3",
            "12X",
            "1 0",
            "1iK",
            "99999999T",
            "+5",
        ] {
            let err = parse_limit(bad).unwrap_err();
            assert!(err.to_string().contains(LIMIT_VAR), "{bad:?}: {err}");
            assert_eq!(err.value, bad);
        }
    }
}
