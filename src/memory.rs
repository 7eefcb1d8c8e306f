//! Memory: how much a command may allocate here, and refusing early (with
//! the estimate and the limit) what would need more.
//!
//! A declared size (a Matrix Market size line, the corners of an OBJ face,
//! `generate grid N`, a PNG header, `--dense`, `--steps`) is turned into an
//! estimate of the bytes it will cost *before* anything is allocated for it,
//! and [`check`] compares the estimate with the limit of this machine:
//!
//! * **the limit** is half of the memory this process can still get: the
//!   other half is left for the work that follows the allocation being
//!   checked (an ordering, a factorization, the frames) and for the other
//!   programs of the machine. What the process can still get is the least
//!   of
//!   - the memory the kernel says is available now (`MemAvailable` in
//!     `/proc/meminfo`; where it cannot be read, the limit is a fixed,
//!     conservative 2 GB),
//!   - what the process's address-space limit (`ulimit -v`, `RLIMIT_AS`
//!     in `/proc/self/limits`) leaves beyond what it has mapped already
//!     (`VmSize` in `/proc/self/status`),
//!   - what the memory limit of its control group leaves beyond what the
//!     group uses (cgroup v2 `memory.max` − `memory.current`, v1
//!     `memory.limit_in_bytes` − `memory.usage_in_bytes`, of the group and
//!     each group above it).
//!
//!   The environment variable `MASSSPRINGS_MEMORY_LIMIT_GB` (a number of
//!   GB, decimals allowed) replaces the available memory (not halved), to
//!   allow more on a dedicated machine or less in a test; the process's own
//!   limits still apply, since going past them aborts it.
//!
//!   Where there is no `/proc` to read (WebAssembly in a browser), the host
//!   gives the memory the program may use in all, its budget
//!   ([`set_budget`]: a page gives its tab's), and the limit is half of it.
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
/// A limit at or above this (2⁶²) means "no limit" (cgroup v1 writes
/// 9223372036854771712 for none).
const UNLIMITED: u64 = 1 << 62;
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

/// The limit, once decided.
static LIMIT: OnceLock<Limit> = OnceLock::new();

/// The limit of this process (decided once, on first use).
pub fn limit() -> Limit {
    *LIMIT.get_or_init(decide_limit)
}

/// Decides the limit from a budget the host gives, `bytes` in all (a
/// browser's tab for its WebAssembly memory, where no `/proc` tells what is
/// available): half of it, as the limit is half of `MemAvailable`, the
/// other half left for the work that follows each allocation checked.
/// `source` says where the budget came from, for messages ("half of the
/// page's budget, ..."). To be called before anything is read or checked.
///
/// # Errors
/// The limit in force when it was decided already (it then stays).
pub fn set_budget(bytes: u64, source: &'static str) -> Result<(), Limit> {
    LIMIT
        .set(Limit {
            bytes: bytes / 2,
            source,
        })
        .map_err(|_| limit())
}

/// The limit [`LIMIT_VARIABLE`] asks for, in GB: `Ok(None)` when it is
/// not set.
///
/// # Errors
/// A sentence naming the variable, its value and what is wrong with it
/// (not a number, a unit written after it, a decimal comma, zero or less,
/// not finite), so that a typo is not ignored in silence.
pub fn limit_variable() -> Result<Option<f64>, String> {
    match std::env::var_os(LIMIT_VARIABLE) {
        None => Ok(None),
        Some(value) => parse_limit(&value.to_string_lossy()).map(Some),
    }
}

/// The GB of a value of [`LIMIT_VARIABLE`] (see [`limit_variable`]).
fn parse_limit(text: &str) -> Result<f64, String> {
    let problem = match text.trim().parse::<f64>() {
        Ok(gb) if gb.is_finite() && gb > 0.0 => return Ok(gb),
        Ok(gb) if gb.is_nan() || gb.is_infinite() => "it must be a finite number",
        Ok(_) => "it must be above 0",
        Err(_) if text.contains(',') => "write decimals with a point (2.5), not a comma",
        Err(_) if starts_as_a_number(text) && ends_in_a_letter(text) => {
            "give the number alone, in GB (3, not 3GB)"
        }
        Err(_) => "it is not a number",
    };
    Err(format!(
        "{LIMIT_VARIABLE}={text:?} is not a memory limit: {problem}; give a number of GB above \
         0 (decimals allowed), or unset it to use what the machine has"
    ))
}

/// Does `text` start with a digit (or a point), as `3GB` does?
fn starts_as_a_number(text: &str) -> bool {
    text.trim_start()
        .starts_with(|c: char| c.is_ascii_digit() || c == '.')
}

/// Does `text` end in a letter, as `3GB` does?
fn ends_in_a_letter(text: &str) -> bool {
    text.trim_end().ends_with(|c: char| c.is_ascii_alphabetic())
}

fn decide_limit() -> Limit {
    let read = |path: &str| std::fs::read_to_string(path).ok();
    let mut limit = match limit_variable().ok().flatten() {
        Some(gb) => Limit {
            bytes: (gb * GB) as u64,
            source: LIMIT_VARIABLE,
        },
        None => match read("/proc/meminfo")
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
        },
    };
    let address_space = read("/proc/self/limits")
        .zip(read("/proc/self/status"))
        .and_then(|(limits, status)| address_space_left(&limits, &status));
    if let Some(left) = address_space.filter(|left| left / 2 < limit.bytes) {
        limit = Limit {
            bytes: left / 2,
            source: "half of what the address-space limit, ulimit -v, leaves",
        };
    }
    if let Some(left) = cgroup_memory_left(&|path| std::fs::read_to_string(path).ok()) {
        if left / 2 < limit.bytes {
            limit = Limit {
                bytes: left / 2,
                source: "half of what the control group's memory limit leaves",
            };
        }
    }
    limit
}

/// What the soft address-space limit (`Max address space` of a
/// `/proc/self/limits` text) leaves beyond `VmSize` (of a
/// `/proc/self/status` text), in bytes; `None` when unlimited or unknown.
pub fn address_space_left(limits: &str, status: &str) -> Option<u64> {
    let soft = limits
        .lines()
        .find_map(|line| line.strip_prefix("Max address space"))?
        .split_whitespace()
        .next()?
        .parse::<u64>()
        .ok()?;
    let mapped_kb: u64 = status
        .lines()
        .find_map(|line| line.strip_prefix("VmSize:"))?
        .split_whitespace()
        .next()?
        .parse()
        .ok()?;
    Some(soft.saturating_sub(mapped_kb.saturating_mul(1024)))
}

/// What the memory limits of this process's control group, and of every
/// group above it, leave beyond what each uses, in bytes (the least);
/// `None` when no group has a limit. `read` reads a file of `/proc` or
/// `/sys/fs/cgroup` (a parameter, for tests).
pub fn cgroup_memory_left(read: &dyn Fn(&str) -> Option<String>) -> Option<u64> {
    let groups = read("/proc/self/cgroup")?;
    let mounts = read("/proc/self/mountinfo")?;
    let mut least: Option<u64> = None;
    for (mount, group, [max, current]) in cgroup_folders(&groups, &mounts) {
        let mut folder = format!("{mount}{group}");
        loop {
            let number = |name: &str| {
                read(&format!("{folder}/{name}"))?
                    .trim()
                    .parse::<u64>()
                    .ok()
            };
            if let (Some(max), Some(current)) = (number(max), number(current)) {
                if max < UNLIMITED {
                    let left = max.saturating_sub(current);
                    least = Some(least.map_or(left, |l| l.min(left)));
                }
            }
            if folder.len() <= mount.len() {
                break;
            }
            folder.truncate(folder.rfind('/').unwrap_or(0).max(mount.len()));
        }
    }
    least
}

/// The memory controller's folders of this process: (mount point, group
/// path below it, [limit file, usage file]), for cgroup v2 and v1, from the
/// texts of `/proc/self/cgroup` and `/proc/self/mountinfo`.
fn cgroup_folders(groups: &str, mounts: &str) -> Vec<(String, String, [&'static str; 2])> {
    let mut folders = Vec::new();
    for line in mounts.lines() {
        let Some((before, after)) = line.split_once(" - ") else {
            continue;
        };
        let fields: Vec<&str> = before.split_whitespace().collect();
        let rest: Vec<&str> = after.split_whitespace().collect();
        let (Some(root), Some(mount), Some(kind)) = (fields.get(3), fields.get(4), rest.first())
        else {
            continue;
        };
        let options = rest.get(2).copied().unwrap_or("");
        let (controller, files) = match *kind {
            "cgroup2" => ("", ["memory.max", "memory.current"]),
            "cgroup" if options.split(',').any(|o| o == "memory") => {
                ("memory", ["memory.limit_in_bytes", "memory.usage_in_bytes"])
            }
            _ => continue,
        };
        let group = groups.lines().find_map(|line| {
            let mut parts = line.splitn(3, ':');
            let (_, controllers, path) = (parts.next()?, parts.next()?, parts.next()?);
            let wanted = if controller.is_empty() {
                controllers.is_empty()
            } else {
                controllers.split(',').any(|c| c == controller)
            };
            wanted.then(|| path.to_string())
        });
        if let Some(group) = group {
            let below = group.strip_prefix(root).unwrap_or(&group);
            let below = if below.is_empty() || below.starts_with('/') {
                below.to_string()
            } else {
                format!("/{below}")
            };
            folders.push((
                mount.to_string(),
                below.trim_end_matches('/').to_string(),
                files,
            ));
        }
    }
    folders
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
pub fn gigabytes(bytes: u64) -> String {
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

/// `n` with thousands separators, for messages: `300,000` (any unsigned
/// count up to 128 bits, so that `2³² × 2³²` is shown exactly).
pub fn thousands(n: impl Into<u128>) -> String {
    let digits = n.into().to_string();
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
    fn the_address_space_limit_counts_what_is_mapped_already() {
        let limits = "Limit                     Soft Limit           Hard Limit           Units\n\
                      Max address space         4096000000           unlimited            bytes\n";
        let status = "Name:\tx\nVmSize:\t   96000 kB\n";
        assert_eq!(
            address_space_left(limits, status),
            Some(4_096_000_000 - 96_000 * 1024)
        );
        let unlimited = limits.replace("4096000000", "unlimited");
        assert_eq!(address_space_left(&unlimited, status), None);
    }

    /// A fake `/proc` and `/sys/fs/cgroup`.
    fn files(entries: &[(&str, &str)]) -> impl Fn(&str) -> Option<String> {
        let entries: Vec<(String, String)> = entries
            .iter()
            .map(|(name, text)| (name.to_string(), text.to_string()))
            .collect();
        move |path| {
            entries
                .iter()
                .find(|(name, _)| name == path)
                .map(|(_, text)| text.clone())
        }
    }

    #[test]
    fn the_cgroup_limit_is_the_least_left_by_the_group_and_its_parents() {
        let mountinfo = "30 23 0:26 / /sys/fs/cgroup rw,nosuid - cgroup2 cgroup2 rw\n";
        let v2 = files(&[
            ("/proc/self/cgroup", "0::/user/job\n"),
            ("/proc/self/mountinfo", mountinfo),
            ("/sys/fs/cgroup/user/job/memory.max", "max\n"),
            ("/sys/fs/cgroup/user/job/memory.current", "100\n"),
            ("/sys/fs/cgroup/user/memory.max", "4000000000\n"),
            ("/sys/fs/cgroup/user/memory.current", "1000000000\n"),
        ]);
        assert_eq!(cgroup_memory_left(&v2), Some(3_000_000_000));
        let mountinfo_v1 = "40 25 0:35 / /sys/fs/cgroup/memory rw - cgroup cgroup rw,memory\n";
        let v1 = files(&[
            ("/proc/self/cgroup", "4:memory:/job\n0::/\n"),
            ("/proc/self/mountinfo", mountinfo_v1),
            (
                "/sys/fs/cgroup/memory/job/memory.limit_in_bytes",
                "2000000000\n",
            ),
            (
                "/sys/fs/cgroup/memory/job/memory.usage_in_bytes",
                "500000000\n",
            ),
            (
                "/sys/fs/cgroup/memory/memory.limit_in_bytes",
                "9223372036854771712\n",
            ),
            ("/sys/fs/cgroup/memory/memory.usage_in_bytes", "7\n"),
        ]);
        assert_eq!(cgroup_memory_left(&v1), Some(1_500_000_000));
        let none = files(&[
            ("/proc/self/cgroup", "0::/\n"),
            ("/proc/self/mountinfo", mountinfo),
            ("/sys/fs/cgroup/memory.max", "max\n"),
            ("/sys/fs/cgroup/memory.current", "1\n"),
        ]);
        assert_eq!(cgroup_memory_left(&none), None);
    }

    #[test]
    fn a_limit_that_is_not_a_number_of_gb_is_named() {
        for (bad, why) in [
            ("3GB", "3, not 3GB"),
            ("2,5", "not a comma"),
            ("0", "above 0"),
            ("-1", "above 0"),
            ("nan", "finite"),
            ("inf", "finite"),
            ("abc", "not a number"),
            ("", "not a number"),
        ] {
            let problem = parse_limit(bad).unwrap_err();
            assert!(
                problem.contains(why) && problem.contains(&format!("{LIMIT_VARIABLE}=\"{bad}\"")),
                "{bad}: {problem}"
            );
        }
        assert_eq!(parse_limit(" 2.5 "), Ok(2.5));
    }

    #[test]
    fn thousands_are_separated() {
        assert_eq!(thousands(0u64), "0");
        assert_eq!(thousands(999u64), "999");
        assert_eq!(thousands(300_000u64), "300,000");
        assert_eq!(thousands(1_234_567u64), "1,234,567");
    }
}
