//! Progress of a long run on standard error: on a terminal, one line
//! rewritten in place (`\r`) a few times a second with the step, the time
//! per step and an estimate of the time left; otherwise (a pipe, a log
//! file) a plain line every few seconds. The estimate is the steps left
//! times the mean time per step so far.

use std::io::{IsTerminal, Write};
use std::time::{Duration, Instant};

/// How often the line is rewritten on a terminal.
const TERMINAL_PERIOD: Duration = Duration::from_millis(200);
/// How often a plain line is written elsewhere.
const PLAIN_PERIOD: Duration = Duration::from_secs(5);

/// The progress of `total` steps.
pub struct Progress {
    total: usize,
    started: Instant,
    last_shown: Instant,
    terminal: bool,
    /// A line is on screen that the next output must clear.
    line_shown: bool,
    enabled: bool,
}

impl Progress {
    /// Starts timing `total` steps; shows nothing when not `enabled`.
    pub fn new(total: usize, enabled: bool) -> Self {
        let now = Instant::now();
        Progress {
            total,
            started: now,
            last_shown: now,
            terminal: std::io::stderr().is_terminal(),
            line_shown: false,
            enabled,
        }
    }

    /// Step `step` is done (1-based).
    pub fn step_done(&mut self, step: usize) {
        let period = if self.terminal {
            TERMINAL_PERIOD
        } else {
            PLAIN_PERIOD
        };
        if !self.enabled || self.last_shown.elapsed() < period {
            return;
        }
        self.last_shown = Instant::now();
        let line = self.line(step);
        let mut err = std::io::stderr().lock();
        // Progress is a courtesy: a closed stderr must not stop the run.
        let _ = if self.terminal {
            self.line_shown = true;
            write!(err, "\r{line}\x1b[K")
        } else {
            writeln!(err, "{line}")
        };
        let _ = err.flush();
    }

    /// `step 120/1000 · 3.2 ms/step · 2.8 s left`.
    fn line(&self, step: usize) -> String {
        let elapsed = self.started.elapsed().as_secs_f64();
        let per_step = elapsed / step.max(1) as f64;
        let left = per_step * self.total.saturating_sub(step) as f64;
        format!(
            "step {step}/{} · {:.1} ms/step · {} left",
            self.total,
            1e3 * per_step,
            duration(left)
        )
    }

    /// Clears the line and returns the time since the start, in seconds.
    pub fn finish(&mut self) -> f64 {
        if self.line_shown {
            let _ = write!(std::io::stderr(), "\r\x1b[K");
            self.line_shown = false;
        }
        self.started.elapsed().as_secs_f64()
    }
}

/// `0.4 s`, `12 s`, `3 min 20 s`.
pub fn duration(seconds: f64) -> String {
    if seconds < 10.0 {
        format!("{seconds:.1} s")
    } else if seconds < 60.0 {
        format!("{seconds:.0} s")
    } else {
        let whole = seconds.round() as u64;
        format!("{} min {} s", whole / 60, whole % 60)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn durations_read_naturally() {
        assert_eq!(duration(0.42), "0.4 s");
        assert_eq!(duration(12.3), "12 s");
        assert_eq!(duration(200.0), "3 min 20 s");
    }

    #[test]
    fn the_line_names_step_rate_and_time_left() {
        let progress = Progress::new(1000, true);
        let line = progress.line(120);
        assert!(line.starts_with("step 120/1000 · "), "{line}");
        assert!(
            line.contains("ms/step") && line.ends_with(" left"),
            "{line}"
        );
    }
}
