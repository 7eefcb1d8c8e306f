//! `masssprings converge SCENE --steps S --accuracy assignment`: an
//! accuracy's settings against the assignment's, over whole animations.
//!
//! Two comparisons, both over the canonical steps 1…S:
//!
//! * **step by step, from the same states** (the loop of `--steps` with a
//!   rule): the canonical simulation (plain, 50 iterations) advances; at
//!   each of its states plain-50 and the accuracy's settings solve the next
//!   step, interleaved in one process. So the energies compare: a step is
//!   *above* plain-50's when
//!
//!   ```text
//!   E(p) − E(p_plain-50) > 10⁻⁹ · (E(pᵗ) − E(p_plain-50))
//!   ```
//!
//!   and the times add up to each one's total. Both energies are changes
//!   `E − E(pᵗ)` computed term by term as differences (never as two
//!   totals subtracted), so they round to the size of the terms' changes,
//!   not of `E`. Where the step itself is that small (a cloth at rest), the
//!   iterates' energies jitter by rounding: plain's energy, which in exact
//!   arithmetic never rises, rises by up to that jitter once it has
//!   converged. A step is therefore above only when it exceeds plain-50's
//!   energy by more than `10⁻⁹` of its decrease and than the rounding of
//!   the energy there: the larger of how far plain's energy wanders over
//!   its 50 iterations from the same state once it first rises (0 where it
//!   never does), measured in an untimed pass, and the rounding `η` that
//!   [`StepEnergy::rounding`](masssprings::sim::energy::StepEnergy::rounding)
//!   estimates from the springs' forces (which plain's jitter matches).
//! * **each on its own** (what a user gets, printed first): two
//!   simulations from rest, one by plain-50, one by the accuracy's
//!   settings, each stepped alone as `simulate` steps it: the median step time of
//!   each, and after every step how far apart their vertices are: the
//!   largest distance `maxᵢ ‖aᵢ − bᵢ‖`, the RMS `√(Σᵢ ‖aᵢ − bᵢ‖² / n)` and
//!   the distance between the centroids. Its own trajectory is not the
//!   assignment's, so each of its steps is compared, too, in an untimed
//!   second pass, with plain-50 from the same (its own) state.

use super::request::Request;
use super::steps::{draw_rule, measured_decrease, rule_rows, timed_step, write_rule_csv, RuleRow};
use crate::app::error::AppError;
use crate::app::limits::precompute;
use masssprings::mesh::Scene;
use masssprings::sim::monitor::Iterate;
use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::{Accuracy, Simulation, Sparse, StepControl};
use std::time::Instant;

/// A step ends above plain-50's when its energy exceeds plain-50's by more
/// than this fraction of plain-50's decrease.
pub const ABOVE: f64 = 1e-9;

/// Runs both comparisons and prints them (and `--plot`: time and energy
/// per step against plain-50's).
pub fn run(
    request: &Request,
    scene: &Scene,
    steps: usize,
    accuracy: Accuracy,
) -> Result<(), AppError> {
    let (scene_name, rows) = rule_rows(request, scene, steps)?;
    let rounding = plain_rounding(request, scene, steps)?;
    let totals = Totals::of(&rows, &rounding);
    let apart = trajectories(request, scene, steps)?;
    print(request, accuracy, steps, &totals, &apart);
    if let Some(path) = &request.plot {
        let title = format!(
            "{scene_name}, --accuracy {}: each step against plain-50's",
            accuracy.name()
        );
        draw_rule(path, title, &request.methods, &rows)?;
    }
    if let Some(path) = &request.csv {
        masssprings::files::write_file(path, |out| write_rule_csv(out, &rows))?;
    }
    Ok(())
}

/// The step-by-step comparison, summed.
struct Totals {
    plain_50_ms: f64,
    ms: f64,
    /// Each step's time over plain-50's (the median is robust to the
    /// pauses of a shared machine, which the totals are not).
    step_ratios: Vec<f64>,
    iterations: usize,
    /// The steps above plain-50's energy, and by how much (over plain-50's
    /// decrease).
    above: Vec<(usize, f64)>,
    /// The step closest to (or furthest above) plain-50's energy: its
    /// number and its shortfall over plain-50's decrease (negative: below).
    worst: (usize, f64),
}

impl Totals {
    /// Sums `rows`; `rounding[i]` is the rounding of plain's energy at the
    /// state of `rows[i]` (no more rows are judged than it has).
    fn of(rows: &[RuleRow], rounding: &[f64]) -> Self {
        let mut totals = Totals {
            plain_50_ms: 0.0,
            ms: 0.0,
            step_ratios: Vec::new(),
            iterations: 0,
            above: Vec::new(),
            worst: (0, f64::NEG_INFINITY),
        };
        for (row, &rounding) in rows.iter().zip(rounding) {
            totals.plain_50_ms += row.plain_50_ms;
            totals.ms += row.ms;
            totals.step_ratios.push(row.ms / row.plain_50_ms);
            totals.iterations += row.iterations;
            let shortfall = shortfall(row.energy, row.plain_50_energy);
            if shortfall > ABOVE && row.energy - row.plain_50_energy > rounding {
                totals.above.push((row.step, shortfall));
            }
            if shortfall > totals.worst.1 {
                totals.worst = (row.step, shortfall);
            }
        }
        totals
    }

    /// The median of the steps' time ratios.
    fn median_ratio(&self) -> f64 {
        median(&self.step_ratios)
    }
}

/// The median of `values` (NaN when there are none).
pub(super) fn median(values: &[f64]) -> f64 {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    match sorted.len() {
        0 => f64::NAN,
        n => 0.5 * (sorted[(n - 1) / 2] + sorted[n / 2]),
    }
}

/// `(E(p) − E(p_plain-50)) / (E(pᵗ) − E(p_plain-50))`, from the two energy
/// changes `E − E(pᵗ)`: how far above plain-50's energy a step ended, over
/// plain-50's decrease (the absolute difference where plain-50 took
/// nothing off).
pub fn shortfall(energy: f64, plain_50_energy: f64) -> f64 {
    let decrease = -plain_50_energy;
    if decrease > 0.0 {
        (energy - plain_50_energy) / decrease
    } else {
        energy - plain_50_energy
    }
}

/// For each of the canonical steps 1…`steps`, [`plain_rounding_at`] its
/// state.
fn plain_rounding(request: &Request, scene: &Scene, steps: usize) -> Result<Vec<f64>, AppError> {
    let mut simulation = precompute::<Sparse>(scene, &request.scene, request.canonical)?;
    let mut rises = Vec::with_capacity(steps);
    for step in 1..=steps {
        rises.push(plain_rounding_at(&simulation, &request.canonical.step)?);
        simulation
            .step()
            .map_err(|e| AppError::Failed(format!("step {step}: {e}")))?;
    }
    Ok(rises)
}

/// How far the energy of the next step from `simulation`'s state rounds:
/// the larger of how far plain-50's energy wanders once rounding shows
/// (from the first iterate whose energy rose, which in exact arithmetic
/// none does, the largest minus the least energy of the iterates from the
/// one before it on; 0 when the energy never rises) and the rounding `η`
/// of an energy difference at that state
/// ([`StepEnergy::rounding`](masssprings::sim::energy::StepEnergy::rounding)).
fn plain_rounding_at(
    simulation: &Simulation<Sparse>,
    plain_50: &StepControl,
) -> Result<f64, AppError> {
    let mut last = 0.0_f64;
    let mut range: Option<(f64, f64)> = None;
    let mut eta = 0.0_f64;
    let mut observe = |iterate: &Iterate<'_>| {
        if iterate.iteration == 0 {
            eta = iterate.energy.rounding();
        }
        let energy = iterate.energy.change(iterate.positions).total();
        range = match range {
            Some((low, high)) => Some((low.min(energy), high.max(energy))),
            None if iterate.iteration > 0 && energy > last => Some((last, energy)),
            None => None,
        };
        last = energy;
    };
    simulation
        .clone()
        .step_with(plain_50, Some(&mut observe))
        .map_err(|e| AppError::Failed(format!("plain-50: {e}")))?;
    Ok(range.map_or(0.0, |(low, high)| high - low).max(eta))
}

/// How far apart two trajectories are, the largest over the steps.
#[derive(Default)]
struct Apart {
    max_vertex: f64,
    rms: f64,
    centroid: f64,
    /// Wall time of each step of each run on its own (ms).
    plain_50_ms: Vec<f64>,
    ms: Vec<f64>,
    /// Along the settings' own trajectory: its steps, each against plain-50
    /// from its state, and the rounding of plain's energy there.
    own: Vec<RuleRow>,
    own_rounding: Vec<f64>,
}

/// Runs plain-50 and the request's settings from rest, each on its own,
/// `steps` steps, timing each step and measuring how far apart they are after
/// each; then runs the settings' trajectory again, untimed, to solve each
/// of its steps by plain-50 too.
fn trajectories(request: &Request, scene: &Scene, steps: usize) -> Result<Apart, AppError> {
    let mut apart = timed_runs(request, scene, steps)?;
    own_steps(request, scene, steps, &mut apart)?;
    Ok(apart)
}

/// The timed part of [`trajectories`]: each run stepped as `simulate`
/// steps it, alone (plain-50's whole run, then the settings' whole run:
/// interleaving them step by step would evict each one's factor from the
/// caches before its next step, which a user's run does not do).
fn timed_runs(request: &Request, scene: &Scene, steps: usize) -> Result<Apart, AppError> {
    let fast_options = SimulationOptions {
        step: StepControl {
            measure: false,
            ..request.control
        },
        ..request.canonical
    };
    Ok(Apart {
        plain_50_ms: timed_run(request, scene, steps, request.canonical)?,
        ms: timed_run(request, scene, steps, fast_options)?,
        ..Apart::default()
    })
}

/// The milliseconds each of `steps` steps from rest by `options` took.
fn timed_run(
    request: &Request,
    scene: &Scene,
    steps: usize,
    options: SimulationOptions,
) -> Result<Vec<f64>, AppError> {
    let mut simulation = precompute::<Sparse>(scene, &request.scene, options)?;
    let mut ms = Vec::with_capacity(steps);
    for step in 1..=steps {
        let started = Instant::now();
        simulation
            .step()
            .map_err(|e| AppError::Failed(format!("step {step}: {e}")))?;
        ms.push(1e3 * started.elapsed().as_secs_f64());
    }
    Ok(ms)
}

/// The untimed part of [`trajectories`]: each step of the settings' own
/// run, and plain-50 from the same state with the rounding of its energy
/// there, into `apart.own` and `apart.own_rounding`; and, beside it,
/// plain-50's own run, to measure how far apart the two are.
fn own_steps(
    request: &Request,
    scene: &Scene,
    steps: usize,
    apart: &mut Apart,
) -> Result<(), AppError> {
    let fast_options = SimulationOptions {
        step: request.control,
        ..request.canonical
    };
    let mut fast = precompute::<Sparse>(scene, &request.scene, fast_options)?;
    let plain_50 = StepControl {
        measure: true,
        ..request.canonical.step
    };
    let mut plain_from_fast = precompute::<Sparse>(scene, &request.scene, request.canonical)?;
    let mut plain = plain_from_fast.clone();
    for step in 1..=steps {
        let (plain_report, _) = timed_step(&mut plain_from_fast, &fast, &plain_50)?;
        apart
            .own_rounding
            .push(plain_rounding_at(&fast, &plain_50)?);
        let report = fast
            .step()
            .map_err(|e| AppError::Failed(format!("step {step}: {e}")))?;
        apart.own.push(RuleRow {
            step,
            method: report.method,
            iterations: report.iterations,
            stop: report.stop,
            energy: -measured_decrease(&report),
            plain_50_energy: -measured_decrease(&plain_report),
            ms: apart.ms.get(step - 1).copied().unwrap_or(f64::NAN),
            plain_50_ms: f64::NAN,
        });
        plain
            .step()
            .map_err(|e| AppError::Failed(format!("plain-50, step {step}: {e}")))?;
        let [max_vertex, rms, centroid] = distances(plain.positions(), fast.positions());
        apart.max_vertex = apart.max_vertex.max(max_vertex);
        apart.rms = apart.rms.max(rms);
        apart.centroid = apart.centroid.max(centroid);
    }
    Ok(())
}

/// `[maxᵢ ‖aᵢ − bᵢ‖, √(Σᵢ ‖aᵢ − bᵢ‖² / n), ‖ā − b̄‖]`.
pub fn distances(a: &[[f64; 3]], b: &[[f64; 3]]) -> [f64; 3] {
    let n = a.len().max(1) as f64;
    let (mut max, mut squares, mut offset) = (0.0_f64, 0.0, [0.0; 3]);
    for (p, q) in a.iter().zip(b) {
        let d: [f64; 3] = std::array::from_fn(|c| p[c] - q[c]);
        let square = d.iter().map(|x| x * x).sum::<f64>();
        max = max.max(square.sqrt());
        squares += square;
        for c in 0..3 {
            offset[c] += d[c] / n;
        }
    }
    let centroid = offset.iter().map(|x| x * x).sum::<f64>().sqrt();
    [max, (squares / n).sqrt(), centroid]
}

fn print(request: &Request, accuracy: Accuracy, steps: usize, totals: &Totals, apart: &Apart) {
    let method = request.control.method.name();
    println!(
        "{} steps 1-{steps}, --accuracy {} ({method}) against plain-50",
        request.scene.display(),
        accuracy.name()
    );
    print_own(accuracy, steps, apart);
    println!(
        "from the same states (each step of both from plain-50's state): plain-50 {:.3} ms, \
         {} {:.3} ms, ratio {:.3} ({} iterations), median step ratio {:.3}",
        totals.plain_50_ms,
        accuracy.name(),
        totals.ms,
        totals.ms / totals.plain_50_ms,
        totals.iterations,
        totals.median_ratio()
    );
    println!(
        "  {} of {steps} steps above plain-50's energy (by more than {ABOVE:e} of its decrease \
         and its rounding){}, closest step {} ({:+.3e} of plain-50's decrease)",
        totals.above.len(),
        listed(&totals.above),
        totals.worst.0,
        totals.worst.1
    );
}

/// What a user gets: the two runs each on its own, and the accuracy's
/// steps against plain-50 from its own states.
fn print_own(accuracy: Accuracy, steps: usize, apart: &Apart) {
    let (plain_total, total) = (
        apart.plain_50_ms.iter().sum::<f64>(),
        apart.ms.iter().sum::<f64>(),
    );
    println!(
        "each on its own (what a user gets): plain-50 {plain_total:.3} ms, {} {total:.3} ms, \
         ratio {:.3}, median step ratio {:.3}",
        accuracy.name(),
        total / plain_total,
        median(&apart.ms) / median(&apart.plain_50_ms)
    );
    let own = Totals::of(&apart.own, &apart.own_rounding);
    println!(
        "  along its own trajectory, against plain-50 from each of its states: {} of {steps} \
         steps above{}, closest step {} ({:+.3e}), {} iterations",
        own.above.len(),
        listed(&own.above),
        own.worst.0,
        own.worst.1,
        own.iterations
    );
    println!(
        "  the two trajectories apart (largest over the steps): max vertex {:.3e}, RMS {:.3e}, \
         centroid {:.3e}",
        apart.max_vertex, apart.rms, apart.centroid
    );
}

/// `": 3 (+1.2e-2), 7 (+4.0e-1)"` for steps above, or nothing.
fn listed(above: &[(usize, f64)]) -> String {
    let steps: Vec<String> = above
        .iter()
        .map(|(step, by)| format!("{step} (+{by:.3e})"))
        .collect();
    match steps.is_empty() {
        true => String::new(),
        false => format!(": {}", steps.join(", ")),
    }
}
