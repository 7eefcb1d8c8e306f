//! Memory: how much a command may allocate here, and refusing early (with
//! the estimate and the limit) what would need more.
//!
//! A declared size (a Matrix Market size line, the corners of an OBJ face,
//! `generate grid N`, a PNG header, `--dense`, `--steps`) is turned into an
//! estimate of the bytes it will cost *before* anything is allocated for it,
//! and [`check`] compares the estimate with the limit of this machine:
//!
//! * **the limit** is half of the memory the kernel says is available now
//!   (`MemAvailable` in `/proc/meminfo`): the other half is left for the
//!   work that follows the allocation being checked (an ordering, a
//!   factorization, the frames) and for the other programs of the machine.
//!   Where `/proc/meminfo` cannot be read the limit is a conservative 2 GB.
//!   The environment variable `MASSSPRINGS_MEMORY_LIMIT_GB` (a number of GB,
//!   decimals allowed) replaces it, to allow more on a dedicated machine or
//!   less in a test.
//! * **an estimate** is a count times the bytes of one item, computed with
//!   saturating arithmetic, so a size of 2⁶⁴ − 1 gives "too large", not an
//!   overflow.
//!
//! The message names what the memory is for, the estimate, the limit and
//! what to do instead, e.g. `the dense path would need 1440 GB for n =
//! 300,000 (two n × n matrices of f64); the limit here is 11.8 GB (half of
//! MemAvailable); use the sparse path (without --dense)`.
//!
//! This module reads one file of the operating system and knows nothing
//! about scenes or matrices: the estimates are made where the sizes are
//! read, from the sizes of the structures they allocate.

use std::fmt;
use std::sync::OnceLock;

/// Bytes in a (decimal) gigabyte, the unit of the messages.
const GB: f64 = 1e9;
/// The limit when `/proc/meminfo` cannot be read.
const FALLBACK_LIMIT_BYTES: u64 = 2_000_000_000;
/// The environment variable that replaces the limit (in GB).
pub const LIMIT_VARIABLE: &str = "MASSSPRINGS_MEMORY_LIMIT_GB";

/// The memory one command may allocate here, and where the figure came from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limit {
    /// The limit in bytes.
    pub bytes: u64,
    /// How it was decided, for messages: "half of MemAvailable", ...
    pub source: &'static str,
}

/// The limit of this process (decided once, on first use).
pub fn limit() -> Limit {
    static LIMIT: OnceLock<Limit> = OnceLock::new();
    *LIMIT.get_or_init(decide_limit)
}

fn decide_limit() -> Limit {
    if let Some(gb) = std::env::var(LIMIT_VARIABLE)
        .ok()
        .and_then(|text| text.trim().parse::<f64>().ok())
        .filter(|gb| gb.is_finite() && *gb > 0.0)
    {
        return Limit {
            bytes: (gb * GB) as u64,
            source: LIMIT_VARIABLE,
        };
    }
    match std::fs::read_to_string("/proc/meminfo")
        .ok()
        .as_deref()
        .and_then(mem_available_bytes)
    {
        Some(available) => Limit {
            bytes: available / 2,
            source: "half of MemAvailable",
        },
        None => Limit {
            bytes: FALLBACK_LIMIT_BYTES,
            source: "no /proc/meminfo: a fixed conservative limit",
        },
    }
}

/// `MemAvailable` of a `/proc/meminfo` text, in bytes.
pub fn mem_available_bytes(meminfo: &str) -> Option<u64> {
    let line = meminfo
        .lines()
        .find_map(|line| line.strip_prefix("MemAvailable:"))?;
    let mut words = line.split_whitespace();
    let kilobytes: u64 = words.next()?.parse().ok()?;
    (words.next() == Some("kB")).then_some(kilobytes.saturating_mul(1024))
}

/// `count` items of `each` bytes, saturating at `u64::MAX`.
pub fn bytes_for(count: u64, each: u64) -> u64 {
    count.saturating_mul(each)
}

/// An allocation that would not fit: what it was for, its estimate, the
/// limit, and what to do instead.
#[derive(Debug, Clone, PartialEq)]
pub struct TooLarge {
    /// What needs the memory: "the dense path for n = 300,000 (...)".
    pub what: String,
    /// The estimate in bytes.
    pub needed: u64,
    /// The limit it was compared with.
    pub limit: Limit,
    /// What to do instead: "use the sparse path (without --dense)".
    pub advice: String,
}

impl fmt::Display for TooLarge {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} would need {}; the limit here is {} ({}, see docs/reliability.md)",
            self.what,
            gigabytes(self.needed),
            gigabytes(self.limit.bytes),
            self.limit.source,
        )?;
        if !self.advice.is_empty() {
            write!(f, "; {}", self.advice)?;
        }
        Ok(())
    }
}

impl std::error::Error for TooLarge {}

/// `bytes` in GB for a message: `1440 GB`, `0.016 GB`, `more than 18 EB`.
fn gigabytes(bytes: u64) -> String {
    if bytes == u64::MAX {
        return "more than 18 million TB (the size overflows 64 bits)".into();
    }
    let gb = bytes as f64 / GB;
    if gb >= 100.0 {
        format!("{gb:.0} GB")
    } else if gb >= 1.0 {
        format!("{gb:.1} GB")
    } else {
        format!("{gb:.3} GB")
    }
}

/// `Ok` when `needed` bytes fit in the [`limit`]; otherwise the refusal,
/// saying `what` the memory is for and `advice` on what to do instead.
///
/// # Errors
/// [`TooLarge`] when `needed` exceeds the limit.
pub fn check(needed: u64, what: impl FnOnce() -> String, advice: &str) -> Result<(), TooLarge> {
    check_against(limit(), needed, what, advice)
}

/// [`check`] against a given limit (for tests).
///
/// # Errors
/// [`TooLarge`] when `needed` exceeds `limit`.
pub fn check_against(
    limit: Limit,
    needed: u64,
    what: impl FnOnce() -> String,
    advice: &str,
) -> Result<(), TooLarge> {
    if needed <= limit.bytes {
        return Ok(());
    }
    Err(TooLarge {
        what: what(),
        needed,
        limit,
        advice: advice.to_string(),
    })
}

/// `n` with thousands separators, for messages: `300,000`.
pub fn thousands(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::with_capacity(digits.len() + digits.len() / 3);
    for (i, digit) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(digit);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mem_available_is_read_in_kilobytes() {
        let text = "MemTotal:       24683656 kB\nMemAvailable:   1000 kB\n";
        assert_eq!(mem_available_bytes(text), Some(1_024_000));
        assert_eq!(mem_available_bytes("MemTotal: 5 kB\n"), None);
        assert_eq!(mem_available_bytes("MemAvailable: x kB\n"), None);
    }

    #[test]
    fn a_refusal_gives_the_estimate_the_limit_and_the_advice() {
        let limit = Limit {
            bytes: 2_000_000_000,
            source: "test",
        };
        assert!(check_against(limit, 2_000_000_000, || unreachable!(), "").is_ok());
        let refusal = check_against(
            limit,
            bytes_for(300_000 * 300_000, 16),
            || "the dense path for n = 300,000".into(),
            "use the sparse path",
        )
        .unwrap_err()
        .to_string();
        assert_eq!(
            refusal,
            "the dense path for n = 300,000 would need 1440 GB; the limit here is 2.0 GB \
             (test, see docs/reliability.md); use the sparse path"
        );
        let overflow = check_against(limit, bytes_for(u64::MAX, 2), || "x".into(), "");
        assert!(overflow
            .unwrap_err()
            .to_string()
            .contains("overflows 64 bits"));
    }

    #[test]
    fn thousands_are_separated() {
        assert_eq!(thousands(0), "0");
        assert_eq!(thousands(999), "999");
        assert_eq!(thousands(300_000), "300,000");
        assert_eq!(thousands(1_234_567), "1,234,567");
    }
}
