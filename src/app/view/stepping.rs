//! One step of every simulation shown. When comparing, the two step at
//! once, each on its own thread (this machine's two cores), from the same
//! state, and stay together: a step one of them could not finish
//! (cancelled, or failed) is undone in the other, so both stay at the last
//! step both completed.

use super::simulation_thread::{Reply, Saved, Shown, SimulationThread};
use masssprings::sim::{SimulationError, StepReport};
use std::time::{Duration, Instant};

/// What one simulation's step gave, and how long it took.
type Timed = (Result<StepReport, SimulationError>, Duration);

impl SimulationThread {
    /// One step of every simulation shown, timed and published; a
    /// cancelled step leaves every one where it was and pauses, a failure
    /// stops the animation with its reason.
    pub(super) fn step_once(&mut self) -> Reply {
        let number = self.main.run.steps() + 1;
        let typical = self
            .all_mut()
            .map(|shown| shown.ms_per_step)
            .fold(0.0, f64::max);
        let expected = (typical > 0.0).then(|| Duration::from_secs_f64(typical / 1e3));
        self.busy(format!("step {number}"), expected);
        let started = Instant::now();
        let comparing = self.second.is_some();
        for shown in self.all_mut() {
            save(shown, comparing);
        }
        let (first, second) = step_all(&mut self.main, self.second.as_mut());
        self.done();
        let failure = [&first]
            .into_iter()
            .chain(second.as_ref())
            .find_map(|(result, _)| result.as_ref().err().cloned());
        match failure {
            None => {
                self.finish_step(first, second);
                Ok(())
            }
            Some(error) => self.abandon_step(number, &error, started.elapsed()),
        }
    }

    /// Records a step every simulation completed.
    fn finish_step(&mut self, first: Timed, second: Option<Timed>) {
        let report = |(result, time): Timed| result.ok().map(|report| (report, time));
        let reports = [report(first), second.and_then(report)];
        if let Some((_, time)) = reports[0] {
            self.main.record_time(time);
        }
        if let (Some(shown), Some((_, time))) = (self.second.as_mut(), reports[1]) {
            shown.record_time(time);
        }
        self.rate.record();
        self.note = None; // a step completed: what the note said is over
        self.publish_frame();
        self.record_step(reports);
    }

    /// Undoes step `number` wherever it completed, and says why: a
    /// cancelled step in the note (and pauses), a failure as the error
    /// that stops the animation.
    fn abandon_step(&mut self, number: usize, error: &SimulationError, took: Duration) -> Reply {
        for shown in self.all_mut() {
            restore(shown, number - 1);
        }
        self.set_animating(false);
        let seconds = took.as_secs_f64();
        if *error == SimulationError::Cancelled {
            let note = format!(
                "step {number} cancelled after {seconds:.1} s: the simulation stays at step {}",
                number - 1
            );
            self.note = Some(note.clone());
            return Err(note);
        }
        let message = format!("step {number}: {error}");
        self.error = Some(message.clone());
        Err(message)
    }
}

/// Steps `main` and, when comparing, `second` on a thread of its own.
fn step_all(main: &mut Shown, second: Option<&mut Shown>) -> (Timed, Option<Timed>) {
    let timed = |shown: &mut Shown| {
        let started = Instant::now();
        let result = shown.run.step();
        (result, started.elapsed())
    };
    match second {
        None => (timed(main), None),
        Some(second) => std::thread::scope(|scope| {
            let other = scope.spawn(|| timed(second));
            let first = timed(main);
            let other = other.join().expect("a step does not panic");
            (first, Some(other))
        }),
    }
}

/// Keeps `shown`'s state, to undo its next step, while `comparing` (a
/// lone simulation's step that fails or is cancelled changes nothing).
fn save(shown: &mut Shown, comparing: bool) {
    if !comparing {
        shown.saved = None;
        return;
    }
    let run = &shown.run;
    let saved = shown.saved.get_or_insert_with(|| Saved {
        previous: Vec::with_capacity(run.positions().len()),
        current: Vec::with_capacity(run.positions().len()),
        steps: 0,
        time: 0.0,
    });
    saved.previous.clear();
    saved.previous.extend_from_slice(run.previous_positions());
    saved.current.clear();
    saved.current.extend_from_slice(run.positions());
    saved.steps = run.steps();
    saved.time = run.time();
}

/// Puts `shown` back where it was saved, when its step `steps + 1`
/// completed.
fn restore(shown: &mut Shown, steps: usize) {
    if shown.run.steps() == steps {
        return;
    }
    if let Some(saved) = &shown.saved {
        let run = &mut shown.run;
        run.set_state(&saved.previous, &saved.current, saved.steps);
        run.set_time(saved.time);
    }
}
