//! One step solved by one method, iteration by iteration: the curve of
//! energy, relative gradient and time that `converge` prints, writes and
//! plots, and what is read off it (the first iterate to reach an energy,
//! Chebyshev's `ρ` from plain's step norms).

use crate::app::error::AppError;
use masssprings::sim::energy::free_norm;
use masssprings::sim::methods::chebyshev::estimate_rho;
use masssprings::sim::monitor::Iterate;
use masssprings::sim::{Simulation, Sparse, Start, StepControl, StepMethod, Stop};
use std::time::{Duration, Instant};

/// One row of the CSV.
#[derive(Debug, Clone, Copy)]
pub(super) struct Sample {
    pub(super) iteration: usize,
    pub(super) energy: f64,
    pub(super) relative_gradient: f64,
    pub(super) elapsed_ms: f64,
    /// `‖pₖ − pₖ₋₁‖` (0 at iteration 0).
    pub(super) step_norm: f64,
}

/// One method's curve.
pub(super) struct Curve {
    pub(super) method: StepMethod,
    pub(super) samples: Vec<Sample>,
    pub(super) stop: Stop,
    /// The rounding `η` of the step's energy differences
    /// (`StepEnergy::rounding`).
    pub(super) rounding: f64,
}

/// The control of the yardstick runs (plain-50, plain-200): the
/// assignment's iteration from the assignment's start, whatever `--start`
/// says for the methods compared with it.
pub(super) fn yardstick(control: &StepControl) -> StepControl {
    StepControl {
        start: Start::Current,
        ..*control
    }
}

/// Step `simulation`'s next step by `method` for up to `iterations`,
/// recording every iterate (on a copy: `simulation` does not move).
pub(super) fn trace(
    simulation: &Simulation<Sparse>,
    control: &StepControl,
    method: StepMethod,
    iterations: usize,
) -> Result<Curve, AppError> {
    let control = StepControl {
        method,
        iterations,
        ..control.without_stopping_rules()
    };
    let failed = |e: masssprings::sim::SimulationError| AppError::Failed(format!("{method}: {e}"));
    let mut copy = warmed_up(simulation, &control)?;
    let mut samples = Vec::with_capacity(iterations.saturating_add(1));
    let mut gradient = vec![[0.0; 3]; copy.positions().len()];
    let mut previous = copy.positions().to_vec();
    let mut initial_gradient = 0.0;
    let mut rounding = 0.0;
    let mut not_counted = Duration::ZERO;
    let started = Instant::now();
    let mut record = |iterate: &Iterate<'_>| {
        let now = Instant::now();
        let elapsed = now - started - not_counted;
        if iterate.iteration == 0 {
            // ‖∇E(pᵗ)‖: the step's start, which the first iterate need not be
            iterate.energy.gradient(iterate.energy.start, &mut gradient);
            initial_gradient = free_norm(&gradient, iterate.pinned);
            rounding = iterate.energy.rounding();
        }
        iterate.energy.gradient(iterate.positions, &mut gradient);
        let norm = free_norm(&gradient, iterate.pinned);
        samples.push(Sample {
            iteration: iterate.iteration,
            energy: iterate.energy.change(iterate.positions).total(),
            relative_gradient: if initial_gradient > 0.0 {
                norm / initial_gradient
            } else {
                0.0
            },
            elapsed_ms: 1e3 * elapsed.as_secs_f64(),
            step_norm: distance(iterate.positions, &previous),
        });
        previous.copy_from_slice(iterate.positions);
        not_counted += now.elapsed();
    };
    let report = copy
        .step_with(&control, Some(&mut record))
        .map_err(failed)?;
    Ok(Curve {
        method,
        samples,
        stop: report.stop,
        rounding,
    })
}

/// A copy of `simulation` that has run one untimed iteration of `control`'s
/// method and is back at `simulation`'s state: the iteration made the
/// method's work arrays, so that a clock started just before the next step
/// counts what every step pays: the step's setup (the first iterate, the
/// initial gradient) and the iterations.
fn warmed_up(
    simulation: &Simulation<Sparse>,
    control: &StepControl,
) -> Result<Simulation<Sparse>, AppError> {
    let method = control.method;
    let failed = |e: masssprings::sim::SimulationError| AppError::Failed(format!("{method}: {e}"));
    let mut copy = simulation.clone();
    let warm_up = StepControl {
        iterations: 1,
        ..*control
    };
    copy.step_with(&warm_up, None).map_err(failed)?;
    let (u_prev, u_cur) = (simulation.previous_positions(), simulation.positions());
    copy.set_state(u_prev, u_cur, simulation.steps())
        .map_err(failed)?;
    Ok(copy)
}

/// The `ρ` Chebyshev's first step would measure, from a plain run's step
/// norms.
pub(super) fn rho_from(plain: &Curve) -> f64 {
    let norms: Vec<f64> = plain.samples[1..].iter().map(|s| s.step_norm).collect();
    estimate_rho(&norms)
}

/// `‖a − b‖` over all coordinates.
fn distance(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| (0..3).map(|c| (p[c] - q[c]).powi(2)).sum::<f64>())
        .sum::<f64>()
        .sqrt()
}

/// The first sample at or below `energy` (with a relative slack of 1e-12
/// for rounding).
pub(super) fn first_reaching(curve: &Curve, energy: f64) -> Option<&Sample> {
    let slack = 1e-12 * energy.abs();
    curve.samples.iter().find(|s| s.energy <= energy + slack)
}
