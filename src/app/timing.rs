//! Repeated timing with a median, for the figures the commands report.
//! Medians, not means: these machines are shared and a run now and then is
//! slowed by a neighbour.

use std::time::Instant;

/// How many times to repeat a measurement.
#[derive(Debug, Clone, Copy)]
pub enum Repeats {
    /// Exactly this many runs.
    Exactly(usize),
    /// At least 5 runs, then more until about a second has been spent,
    /// at most 101.
    Adaptive,
}

/// The median time, in seconds, of `repeats` runs of `work`.
pub fn median_seconds(repeats: Repeats, mut work: impl FnMut()) -> (f64, usize) {
    let started = Instant::now();
    let mut times = Vec::new();
    loop {
        let t = Instant::now();
        work();
        times.push(t.elapsed().as_secs_f64());
        let done = match repeats {
            Repeats::Exactly(count) => times.len() >= count,
            Repeats::Adaptive => {
                times.len() >= 101 || (times.len() >= 5 && started.elapsed().as_secs_f64() >= 1.0)
            }
        };
        if done {
            break;
        }
    }
    (median(&mut times), times.len())
}

/// The median of `values` (sorted in place).
pub fn median(values: &mut [f64]) -> f64 {
    values.sort_by(f64::total_cmp);
    let n = values.len();
    if n == 0 {
        f64::NAN
    } else if n % 2 == 1 {
        values[n / 2]
    } else {
        0.5 * (values[n / 2 - 1] + values[n / 2])
    }
}
