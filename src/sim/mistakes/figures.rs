//! The figures of a mistake's run, measured against the handout's run on
//! the same scene, both from rest: what `docs/mistakes.md` quotes of each
//! picture and `render --mistake NAME --json` prints.
//!
//! ```text
//! lowest        min over vertices of y, at the last step
//! highest       max over vertices of y, at the last step
//! farthest      max over vertices of ‖pᵢ − Vᵢ‖
//! pins_moved    the same, over the pinned vertices
//! extent        the diagonal of the bounding box at the last step
//! apart         max over vertices of ‖pᵢ − p(handout)ᵢ‖, at the last step
//! swing         max − min of the lowest height, over the second half of the run
//! bottom_ratio  the first step at which the lowest point rises, over the handout's
//! stopped       the first step with a position not finite
//! ```
//!
//! A run that stops being finite is measured at its last finite step.
//! Cost: `O(n)` per step observed.

use super::entry::Measure;

/// The figures of one run against the handout's.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Figures {
    pub steps: usize,
    pub lowest: f64,
    pub handout_lowest: f64,
    pub highest: f64,
    pub farthest: f64,
    pub pins_moved: f64,
    pub extent: f64,
    pub handout_extent: f64,
    pub apart: f64,
    pub swing: f64,
    pub handout_swing: f64,
    /// The first step at which the lowest point rises, if it does.
    pub bottom: Option<usize>,
    pub handout_bottom: Option<usize>,
    /// The first step with a position that is not finite, if any.
    pub stopped: Option<usize>,
}

impl Figures {
    /// The value of `measure` (`bottom_ratio` is NaN when either run never
    /// rises; `stopped` is `steps + 1` when the run stays finite).
    pub fn get(&self, measure: Measure) -> f64 {
        match measure {
            Measure::Lowest => self.lowest,
            Measure::Highest => self.highest,
            Measure::Farthest => self.farthest,
            Measure::PinsMoved => self.pins_moved,
            Measure::Extent => self.extent,
            Measure::Apart => self.apart,
            Measure::Swing => self.swing,
            Measure::BottomRatio => match (self.bottom, self.handout_bottom) {
                (Some(a), Some(b)) => a as f64 / b as f64,
                _ => f64::NAN,
            },
            Measure::Stopped => self.stopped.unwrap_or(self.steps + 1) as f64,
        }
    }
}

/// Watches the two runs step by step.
#[derive(Debug, Clone)]
pub struct Measuring {
    rest: Vec<[f64; 3]>,
    pinned: Vec<usize>,
    steps: usize,
    lowest: [Vec<f64>; 2],
    farthest: f64,
    pins_moved: f64,
    last: [Vec<[f64; 3]>; 2],
    stopped: Option<usize>,
}

impl Measuring {
    /// Before the first step, at rest (`V`, with the pinned vertices).
    pub fn new(rest: &[[f64; 3]], pinned: &[usize]) -> Measuring {
        let low = lowest(rest);
        Measuring {
            rest: rest.to_vec(),
            pinned: pinned.to_vec(),
            steps: 0,
            lowest: [vec![low], vec![low]],
            farthest: 0.0,
            pins_moved: 0.0,
            last: [rest.to_vec(), rest.to_vec()],
            stopped: None,
        }
    }

    /// After one more step: the handout's positions and the student's.
    pub fn observe(&mut self, handout: &[[f64; 3]], student: &[[f64; 3]]) {
        self.steps += 1;
        self.lowest[0].push(lowest(handout));
        self.last[0].copy_from_slice(handout);
        if self.stopped.is_some() {
            return;
        }
        if !student.iter().flatten().all(|x| x.is_finite()) {
            self.stopped = Some(self.steps);
            return;
        }
        self.lowest[1].push(lowest(student));
        self.last[1].copy_from_slice(student);
        let moved = |i: usize| distance(student[i], self.rest[i]);
        self.farthest = (0..student.len()).map(moved).fold(self.farthest, f64::max);
        self.pins_moved = self
            .pinned
            .iter()
            .map(|&i| moved(i))
            .fold(self.pins_moved, f64::max);
    }

    /// The figures of the steps observed.
    pub fn finish(&self) -> Figures {
        let [handout, student] = &self.last;
        let apart = handout.iter().zip(student);
        Figures {
            steps: self.steps,
            lowest: *self.lowest[1].last().expect("the rest shape"),
            handout_lowest: *self.lowest[0].last().expect("the rest shape"),
            highest: highest(student),
            farthest: self.farthest,
            pins_moved: self.pins_moved,
            extent: extent(student),
            handout_extent: extent(handout),
            apart: apart.map(|(a, b)| distance(*a, *b)).fold(0.0, f64::max),
            swing: swing(&self.lowest[1]),
            handout_swing: swing(&self.lowest[0]),
            bottom: first_rise(&self.lowest[1]),
            handout_bottom: first_rise(&self.lowest[0]),
            stopped: self.stopped,
        }
    }
}

/// `‖a − b‖`, without overflow for the far-flung.
fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1]).hypot(a[2] - b[2])
}

fn highest(points: &[[f64; 3]]) -> f64 {
    points
        .iter()
        .map(|p| p[1])
        .fold(f64::NEG_INFINITY, f64::max)
}

fn lowest(points: &[[f64; 3]]) -> f64 {
    points.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min)
}

/// The diagonal of the bounding box of `points`.
fn extent(points: &[[f64; 3]]) -> f64 {
    let (mut low, mut high) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in points {
        for c in 0..3 {
            low[c] = low[c].min(p[c]);
            high[c] = high[c].max(p[c]);
        }
    }
    distance(low, high)
}

/// `max − min` of the second half of `heights` (step 0 is the rest shape).
fn swing(heights: &[f64]) -> f64 {
    let half = &heights[heights.len() / 2..];
    let high = half.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    high - half.iter().copied().fold(f64::INFINITY, f64::min)
}

/// The first step whose lowest point is higher than the step before's.
fn first_rise(heights: &[f64]) -> Option<usize> {
    (1..heights.len()).find(|&s| heights[s] > heights[s - 1])
}
