//! What the simulation thread publishes for the HTTP threads: the frame
//! (positions of every simulation shown) and the status (state,
//! parameters, timings, the last steps of each).

use super::api::{Compared, Status, StepRecord, HISTORY_LENGTH};
use super::rules::converged;
use super::simulation_thread::{Shared, Shown, SimulationThread};
use crate::app::limits::dense_need;
use masssprings::memory::{self, gigabytes};
use masssprings::sim::StepReport;
use std::collections::VecDeque;
use std::time::Duration;

impl SimulationThread {
    /// Writes the current positions into the shared frame.
    pub(super) fn publish_frame(&self) {
        let mut frame = Shared::lock(&self.shared.frame);
        let run = &self.main.run;
        match &self.second {
            None => frame.write(&[run.positions()], run.steps(), run.time()),
            Some(second) => frame.write(
                &[run.positions(), second.run.positions()],
                run.steps(),
                run.time(),
            ),
        }
    }

    /// Writes the current state into the shared status.
    pub(super) fn publish_status(&self) {
        // Never hold the status while taking the watchers' lock.
        let pages = Shared::lock(&self.shared.watchers).count();
        let mut status = Shared::lock(&self.shared.status);
        status.pages = pages;
        status.watched = pages > 0;
        status.animating = self.animating;
        status.show_springs = self.show_springs;
        status.steps_per_second = self.rate.steps_per_second;
        if status.error != self.error {
            status.error.clone_from(&self.error);
        }
        if status.note != self.note {
            status.note.clone_from(&self.note);
        }
        status.refactor_ms = self.refactor.map(|d| 1e3 * d.as_secs_f64());
        status.scene_index = self.scene_index;
        publish_main(&mut status, &self.main);
        match (&self.second, &mut status.compare) {
            (None, compare) => *compare = None,
            (Some(second), Some(compare)) => publish_second(compare, second),
            (Some(second), compare) => {
                let mut fresh = Compared {
                    history: VecDeque::with_capacity(HISTORY_LENGTH),
                    ..Compared::default()
                };
                publish_second(&mut fresh, second);
                *compare = Some(fresh);
            }
        }
    }

    /// Appends what a step of each simulation did to its history (in
    /// place: a history never grows beyond its capacity).
    pub(super) fn record_step(&self, reports: [Option<(StepReport, Duration)>; 2]) {
        let mut status = Shared::lock(&self.shared.status);
        if let Some((report, time)) = reports[0] {
            let record = step_record(&self.main, &report, time);
            push(&mut status.history, record);
        }
        if let (Some((report, time)), Some(second), Some(compare)) =
            (reports[1], &self.second, status.compare.as_mut())
        {
            let record = StepRecord {
                distance: distance(&self.main, second),
                ..step_record(second, &report, time)
            };
            push(&mut compare.history, record);
        }
    }

    /// What the dense path would take for the scene shown, against the
    /// memory rule (the page says it before the solve picker starts it).
    pub(super) fn publish_dense_need(&self) {
        let (bytes, what) = dense_need(&self.scene);
        let limit = memory::limit();
        let mut status = Shared::lock(&self.shared.status);
        status.dense_fits = bytes <= limit.bytes;
        status.dense_memory = match status.dense_fits {
            true => format!("{what}: {}", gigabytes(bytes)),
            false => format!(
                "{what}: {}, more than the {} allowed here ({})",
                gigabytes(bytes),
                gigabytes(limit.bytes),
                limit.source
            ),
        };
    }

    /// Forgets the steps of every history (a reset, another scene).
    pub(super) fn clear_history(&self) {
        let mut status = Shared::lock(&self.shared.status);
        status.history.clear();
        if let Some(compare) = status.compare.as_mut() {
            compare.history.clear();
        }
    }
}

/// The first simulation's part of the status.
fn publish_main(status: &mut Status, main: &Shown) {
    let run = &main.run;
    let options = run.options();
    status.steps = run.steps();
    status.time = run.time();
    status.wind = options.wind;
    status.ms_per_step = main.ms_per_step;
    status.dragged = run.dragged();
    status.k = run.k();
    status.delta_t = options.delta_t;
    status.mass_scale = run.mass_scale();
    status.iterations = options.step.iterations;
    status.method = options.step.method.name();
    status.tolerance = options.step.tolerance;
    status.energy_tolerance = options.step.energy_tolerance;
    status.at_least_plain = options.step.at_least_plain;
    status.plain_first = options.step.plain_first;
    status.start = options.step.start.name();
    status.backend = main.backend.name();
    status.solver = run.solver_name();
    status.functions = run.path();
    status.energy = run.mechanical_energy();
}

/// The second simulation's part of the status.
fn publish_second(compare: &mut Compared, second: &Shown) {
    let options = second.run.options();
    compare.solver = second.run.solver_name();
    compare.backend = second.backend.name();
    compare.method = options.step.method.name();
    compare.functions = second.run.path();
    compare.ms_per_step = second.ms_per_step;
    compare.iterations = options.step.iterations;
    compare.energy = second.run.mechanical_energy();
    compare.ended = second.run.past_its_end();
}

/// The largest distance between a vertex of `main` and the same vertex of
/// `second` (`None` when `second` has run out of frames).
fn distance(main: &Shown, second: &Shown) -> Option<f64> {
    if second.run.past_its_end() {
        return None;
    }
    let pairs = main.run.positions().iter().zip(second.run.positions());
    let squared = pairs.map(|(p, q)| (0..3).map(|c| (p[c] - q[c]).powi(2)).sum::<f64>());
    Some(squared.fold(0.0, f64::max).sqrt())
}

fn push(history: &mut VecDeque<StepRecord>, record: StepRecord) {
    if history.len() == HISTORY_LENGTH {
        history.pop_front();
    }
    history.push_back(record);
}

/// What `report` says of the step `shown` just took in `time`.
fn step_record(shown: &Shown, report: &StepReport, time: Duration) -> StepRecord {
    StepRecord {
        step: shown.run.steps(),
        iterations: report.iterations,
        energy_decrease: report.energy_decrease,
        relative_gradient: report.relative_gradient,
        converged: converged(report.stop),
        stop: report.stop.name(),
        energy: shown.run.mechanical_energy(),
        ms: 1e3 * time.as_secs_f64(),
        distance: None,
    }
}
