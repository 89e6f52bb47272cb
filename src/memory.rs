//! How much memory the machine can still give, so that a run too large for it fails with a
//! clear error before it allocates instead of being aborted (or killed) mid-allocation.

use crate::error::{Error, Result};

/// Memory the system can give a new allocation without swapping, bytes: `MemAvailable` of
/// `/proc/meminfo` on Linux; `None` elsewhere or when it cannot be read (no check then).
#[must_use]
pub fn available_bytes() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    parse_mem_available(&text)
}

/// The most memory this process has held so far, bytes: `VmHWM` of `/proc/self/status` on
/// Linux; `None` elsewhere.
#[must_use]
pub fn peak_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kb.checked_mul(1024)
}

/// `MemAvailable` of a `/proc/meminfo` text, bytes.
fn parse_mem_available(text: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let mut fields = line.split_whitespace().skip(1);
    let value: u64 = fields.next()?.parse().ok()?;
    match fields.next() {
        Some("kB") | None => value.checked_mul(1024),
        _ => None,
    }
}

/// An error when `bytes` for `what` (e.g. `100000000 particles`) exceed `available`
/// (`None`: unknown, no check); `fix` says what to change.
///
/// # Errors
///
/// [`Error::TooLarge`] when `available` is known and `bytes` exceeds it; the message gives both
/// in GB and ends with `fix`.
pub fn check_fits(what: &str, bytes: u64, available: Option<u64>, fix: &str) -> Result<()> {
    match available {
        Some(free) if bytes > free => Err(Error::too_large(
            format!("the memory {what} need"),
            format!("{:.1} GB", bytes as f64 / 1e9),
            format!("the {:.1} GB this machine has available", free as f64 / 1e9),
            fix,
        )),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_mem_available_in_bytes() {
        let text = "MemTotal:       32000000 kB\nMemFree:  100 kB\nMemAvailable:   2048 kB\n";
        assert_eq!(parse_mem_available(text), Some(2048 * 1024));
        assert_eq!(parse_mem_available("MemTotal: 1 kB\n"), None);
        assert_eq!(parse_mem_available("MemAvailable: x kB\n"), None);
    }

    #[test]
    fn a_run_larger_than_memory_is_refused_with_the_way_out() {
        assert!(check_fits("x", 10, None, "").is_ok());
        assert!(check_fits("x", 10, Some(10), "").is_ok());
        let e = check_fits(
            "100 particles",
            8_000_000_000,
            Some(2_000_000_000),
            "use fewer",
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("8.0 GB") && e.contains("2.0 GB") && e.contains("use fewer"),
            "{e}"
        );
    }
}
