//! `converge --steps S`: the canonical simulation advanced step by step,
//! and at each of its states every method's whole step beside plain-50's,
//! timed, stopping by the request's rules: the rows that `--steps` with a
//! rule and `--accuracy` print, write as CSV and plot.

use super::curve::{rho_from, trace, yardstick};
use super::request::{Request, YARDSTICKS};
use super::steps_plot::{self, StepPlot, StepSeries};
use crate::app::draw::plot::Scale;
use crate::app::error::AppError;
use crate::app::limits::precompute;
use crate::app::progress::Progress;
use masssprings::mesh::Scene;
use masssprings::sim::{Simulation, Sparse, StepControl, StepMethod, Stop};
use std::io::Write;
use std::time::Instant;

/// The rows of `--steps S` with a rule: for each of the canonical steps
/// 1…S, plain-50 and then each method solve the step from the same
/// state, each timed whole (interleaved, in one process), stopping by the
/// request's rules; the scene's name beside them.
pub(super) fn rule_rows(
    request: &Request,
    scene: &Scene,
    steps: usize,
) -> Result<(String, Vec<RuleRow>), AppError> {
    let mut simulation = precompute::<Sparse>(scene, &request.scene, request.canonical)?;
    let plain_50 = StepControl {
        method: StepMethod::Plain,
        iterations: YARDSTICKS[0],
        ..yardstick(&request.control).without_stopping_rules()
    };
    let mut control = request.control;
    // One runner per method, kept across steps so that each method's work
    // arrays are made once (as in a simulation), and set to the canonical
    // state before each timed step.
    let mut plain_runner = simulation.clone();
    let mut runners = vec![simulation.clone(); request.methods.len()];
    let mut step_rows = Vec::new();
    let mut progress = Progress::new(steps, true);
    for step in 1..=steps {
        if control.rho.is_none() {
            let plain = trace(&simulation, &control, StepMethod::Plain, YARDSTICKS[0])?;
            control.rho = Some(rho_from(&plain));
        }
        let (plain_report, ms_of_plain) = timed_step(&mut plain_runner, &simulation, &plain_50)?;
        let target = -measured_decrease(&plain_report);
        for (&method, runner) in request.methods.iter().zip(&mut runners) {
            let control = StepControl { method, ..control };
            let (report, ms) = timed_step(runner, &simulation, &control)?;
            step_rows.push(RuleRow {
                step,
                method,
                iterations: report.iterations,
                stop: report.stop,
                energy: -measured_decrease(&report),
                plain_50_energy: target,
                ms,
                plain_50_ms: ms_of_plain,
            });
        }
        advance(&mut simulation, step, &mut progress)?;
    }
    progress.finish();
    Ok((scene.name.clone(), step_rows))
}

/// The canonical simulation's step `step`, shown in `progress`.
pub(super) fn advance(
    simulation: &mut Simulation<Sparse>,
    step: usize,
    progress: &mut Progress,
) -> Result<(), AppError> {
    simulation
        .step()
        .map_err(|e| AppError::Failed(format!("step {step}: {e}")))?;
    progress.step_done(step);
    Ok(())
}

/// One plot series per method, from the rows that give it a point
/// (`point` says whose point a row is, if any).
pub(super) fn by_method<R>(
    methods: &[StepMethod],
    rows: &[R],
    point: impl Fn(&R) -> Option<(StepMethod, (f64, f64, f64))>,
) -> Vec<StepSeries> {
    methods
        .iter()
        .map(|&method| {
            let points = rows
                .iter()
                .filter_map(&point)
                .filter(|&(m, _)| m == method)
                .map(|(_, p)| p)
                .collect();
            (method.name().to_string(), points)
        })
        .collect()
}

/// The plot of `--steps S` with a rule: per step, the step's time and its
/// energy decrease over plain-50's.
pub(super) fn draw_rule(
    path: &std::path::Path,
    title: String,
    methods: &[StepMethod],
    rows: &[RuleRow],
) -> Result<(), AppError> {
    let series = by_method(methods, rows, |r| {
        let (time, decrease) = (r.ms / r.plain_50_ms, r.energy / r.plain_50_energy);
        Some((r.method, (r.step as f64, time, decrease)))
    });
    let plot = StepPlot {
        title,
        caption: "left: step time / plain-50's; right: energy decrease / plain-50's \
                  (at or above 1: the step ended at least as low as plain-50)"
            .into(),
        left: ("cost", "step time / plain-50's (log)", Scale::Log10),
        right: ("accuracy", "decrease / plain-50's (log)", Scale::Log10),
        plain_50_line: true,
    };
    steps_plot::draw(path, &plot, &series)
}

/// `--steps S --csv` with a stopping rule: one method's whole step, beside
/// plain-50's.
pub(super) struct RuleRow {
    pub(super) step: usize,
    pub(super) method: StepMethod,
    pub(super) iterations: usize,
    pub(super) stop: Stop,
    /// `E(p) − E(pᵗ)` where the method stopped, and where plain-50 does.
    pub(super) energy: f64,
    pub(super) plain_50_energy: f64,
    pub(super) ms: f64,
    pub(super) plain_50_ms: f64,
}

pub(super) fn write_rule_csv(out: &mut dyn Write, rows: &[RuleRow]) -> std::io::Result<()> {
    writeln!(
        out,
        "step,method,iterations,stop,energy,plain_50_energy,ms,plain_50_ms"
    )?;
    for r in rows {
        writeln!(
            out,
            "{},{},{},{},{:e},{:e},{:.4},{:.4}",
            r.step,
            r.method.name(),
            r.iterations,
            r.stop.name(),
            r.energy,
            r.plain_50_energy,
            r.ms,
            r.plain_50_ms
        )?;
    }
    Ok(())
}

/// The next step from `simulation`'s state, solved by `runner` as
/// `control` says, and its wall time in milliseconds.
pub(super) fn timed_step(
    runner: &mut Simulation<Sparse>,
    simulation: &Simulation<Sparse>,
    control: &StepControl,
) -> Result<(masssprings::sim::StepReport, f64), AppError> {
    let failed =
        |e: masssprings::sim::SimulationError| AppError::Failed(format!("{}: {e}", control.method));
    runner
        .set_state(
            simulation.previous_positions(),
            simulation.positions(),
            simulation.steps(),
        )
        .map_err(failed)?;
    let started = Instant::now();
    let report = runner.step_with(control, None).map_err(failed)?;
    Ok((report, 1e3 * started.elapsed().as_secs_f64()))
}

/// The energy decrease of a step whose control asked for it
/// (`StepControl::measure`, set for every step `converge` runs).
pub(super) fn measured_decrease(report: &masssprings::sim::StepReport) -> f64 {
    report
        .energy_decrease
        .expect("converge's steps measure their energy")
}
