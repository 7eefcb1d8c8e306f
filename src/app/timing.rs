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

/// The median time, in seconds, of `repeats` runs of `work`, and the number
/// of runs. The times are kept in a [`BoundedSample`], so memory does not
/// grow with the number of runs (`--repeats 1000000000`).
pub fn median_seconds(repeats: Repeats, mut work: impl FnMut()) -> (f64, usize) {
    let started = Instant::now();
    let mut times = BoundedSample::new();
    let mut runs = 0usize;
    loop {
        let t = Instant::now();
        work();
        times.push(t.elapsed().as_secs_f64());
        runs += 1;
        let done = match repeats {
            Repeats::Exactly(count) => runs >= count,
            Repeats::Adaptive => {
                runs >= 101 || (runs >= 5 && started.elapsed().as_secs_f64() >= 1.0)
            }
        };
        if done {
            break;
        }
    }
    (times.median(), runs)
}

/// The median times, in seconds, of two pieces of work timed in
/// interleaved rounds (`first`, then `second`, again and again), and the
/// number of rounds: a neighbour that slows the machine for a while slows
/// both alike, so their ratio holds (the thread counts `analyze` and
/// `bench` compare). Rounds as [`median_seconds`] counts runs.
pub fn interleaved_medians(
    repeats: Repeats,
    mut first: impl FnMut(),
    mut second: impl FnMut(),
) -> ([f64; 2], usize) {
    let mut times = [BoundedSample::new(), BoundedSample::new()];
    let timed = |sample: &mut BoundedSample, work: &mut dyn FnMut()| {
        let t = Instant::now();
        work();
        sample.push(t.elapsed().as_secs_f64());
    };
    let (_, rounds) = median_seconds(repeats, || {
        let [a, b] = &mut times;
        timed(a, &mut first);
        timed(b, &mut second);
    });
    let [mut a, mut b] = times;
    ([a.median(), b.median()], rounds)
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

/// At most [`BoundedSample::CAPACITY`] values spread evenly over a run of
/// any length (a step time per step of `--steps 10¹²` would be 8 TB): when
/// the sample is full, every other value is dropped and from then on only
/// every `stride`-th value is kept, the stride doubling each time.
#[derive(Debug, Clone)]
pub struct BoundedSample {
    values: Vec<f64>,
    stride: u64,
    seen: u64,
}

impl BoundedSample {
    /// The most values kept.
    pub const CAPACITY: usize = 4096;

    pub fn new() -> Self {
        BoundedSample {
            values: Vec::new(),
            stride: 1,
            seen: 0,
        }
    }

    /// Offers one value to the sample.
    pub fn push(&mut self, value: f64) {
        if self.seen.is_multiple_of(self.stride) {
            if self.values.len() == Self::CAPACITY {
                let mut index = 0;
                self.values.retain(|_| {
                    index += 1;
                    index % 2 == 1
                });
                self.stride = self.stride.saturating_mul(2);
            }
            if self.seen.is_multiple_of(self.stride) {
                self.values.push(value);
            }
        }
        self.seen = self.seen.saturating_add(1);
    }

    /// The median of the values kept (NaN when there are none).
    pub fn median(&mut self) -> f64 {
        median(&mut self.values)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bounded_sample_stays_bounded_and_keeps_every_stride_th_value() {
        let mut sample = BoundedSample::new();
        for i in 0..100_000u32 {
            sample.push(f64::from(i));
        }
        assert!(sample.values.len() <= BoundedSample::CAPACITY);
        assert!(sample
            .values
            .iter()
            .all(|&v| (v as u64).is_multiple_of(sample.stride)));
        let median = sample.median();
        assert!((median - 50_000.0).abs() < 100.0, "{median}");
        let mut few = BoundedSample::new();
        for v in [3.0, 1.0, 2.0] {
            few.push(v);
        }
        assert_eq!(few.median(), 2.0);
    }
}
