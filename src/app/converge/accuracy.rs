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
//!   and the times add up to each one's total.
//! * **each on its own**: two simulations from rest, one by plain-50, one
//!   by the accuracy's settings, and after every step how far apart their
//!   vertices are: the largest distance `maxᵢ ‖aᵢ − bᵢ‖`, the RMS
//!   `√(Σᵢ ‖aᵢ − bᵢ‖² / n)` and the distance between the centroids. Its
//!   own trajectory is not the assignment's, so each of its steps is
//!   compared, too, with plain-50 from the same (its own) state.

use super::{draw_rule, measured_decrease, rule_rows, timed_step, Request, RuleRow};
use crate::app::limits::precompute;
use crate::app::AppError;
use masssprings::mesh::Scene;
use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::{Accuracy, Sparse, StepControl};
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
    let totals = Totals::of(&rows);
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
        masssprings::files::write_file(path, |out| super::write_rule_csv(out, &rows))?;
    }
    Ok(())
}

/// The step-by-step comparison, summed.
struct Totals {
    plain_50_ms: f64,
    ms: f64,
    iterations: usize,
    /// The steps above plain-50's energy, and by how much (over plain-50's
    /// decrease).
    above: Vec<(usize, f64)>,
    /// The step closest to (or furthest above) plain-50's energy: its
    /// number and its shortfall over plain-50's decrease (negative: below).
    worst: (usize, f64),
}

impl Totals {
    fn of(rows: &[RuleRow]) -> Self {
        let mut totals = Totals {
            plain_50_ms: 0.0,
            ms: 0.0,
            iterations: 0,
            above: Vec::new(),
            worst: (0, f64::NEG_INFINITY),
        };
        for row in rows {
            totals.plain_50_ms += row.plain_50_ms;
            totals.ms += row.ms;
            totals.iterations += row.iterations;
            let shortfall = shortfall(row.energy, row.plain_50_energy);
            if shortfall > ABOVE {
                totals.above.push((row.step, shortfall));
            }
            if shortfall > totals.worst.1 {
                totals.worst = (row.step, shortfall);
            }
        }
        totals
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

/// How far apart two trajectories are, the largest over the steps.
#[derive(Default)]
struct Apart {
    max_vertex: f64,
    rms: f64,
    centroid: f64,
    /// Wall time of each run on its own, steps only (ms).
    plain_50_ms: f64,
    ms: f64,
    /// Along the settings' own trajectory: its steps, each against plain-50
    /// from its state.
    own: Vec<RuleRow>,
}

/// Runs plain-50 and the request's settings from rest, each on its own,
/// `steps` steps, and measures how far apart they are after each.
fn trajectories(request: &Request, scene: &Scene, steps: usize) -> Result<Apart, AppError> {
    let fast_options = SimulationOptions {
        step: request.control,
        ..request.canonical
    };
    let mut plain = precompute::<Sparse>(scene, &request.scene, request.canonical)?;
    let mut fast = precompute::<Sparse>(scene, &request.scene, fast_options)?;
    let mut apart = Apart::default();
    let plain_50 = StepControl {
        measure: true,
        ..request.canonical.step
    };
    let mut plain_from_fast = plain.clone();
    for step in 1..=steps {
        let failed =
            |e: masssprings::sim::SimulationError| AppError::Failed(format!("step {step}: {e}"));
        let (plain_report, _) = timed_step(&mut plain_from_fast, &fast, &plain_50)?;
        let started = Instant::now();
        plain.step().map_err(failed)?;
        let middle = Instant::now();
        let report = fast.step().map_err(failed)?;
        let ms = 1e3 * middle.elapsed().as_secs_f64();
        apart.ms += ms;
        apart.plain_50_ms += 1e3 * (middle - started).as_secs_f64();
        apart.own.push(RuleRow {
            step,
            method: report.method,
            iterations: report.iterations,
            stop: report.stop,
            energy: -measured_decrease(&report),
            plain_50_energy: -measured_decrease(&plain_report),
            ms,
            plain_50_ms: f64::NAN,
        });
        let [max_vertex, rms, centroid] = distances(plain.positions(), fast.positions());
        apart.max_vertex = apart.max_vertex.max(max_vertex);
        apart.rms = apart.rms.max(rms);
        apart.centroid = apart.centroid.max(centroid);
    }
    Ok(apart)
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
    println!(
        "from the same states:  plain-50 {:.3} ms, {} {:.3} ms, ratio {:.3} ({} iterations)",
        totals.plain_50_ms,
        accuracy.name(),
        totals.ms,
        totals.ms / totals.plain_50_ms,
        totals.iterations
    );
    let listed: Vec<String> = totals
        .above
        .iter()
        .map(|(step, by)| format!("{step} (+{by:.3e})"))
        .collect();
    println!(
        "steps above plain-50's energy (by more than {ABOVE:e} of its decrease): {} of {steps}{}",
        totals.above.len(),
        match listed.is_empty() {
            true => String::new(),
            false => format!(": {}", listed.join(", ")),
        }
    );
    println!(
        "closest step: {} ({:+.3e} of plain-50's decrease)",
        totals.worst.0, totals.worst.1
    );
    println!(
        "each on its own:       plain-50 {:.3} ms, {} {:.3} ms, ratio {:.3}",
        apart.plain_50_ms,
        accuracy.name(),
        apart.ms,
        apart.ms / apart.plain_50_ms
    );
    let own = Totals::of(&apart.own);
    println!(
        "along its own trajectory, against plain-50 from each of its states: {} of {steps} \
         steps above, closest step {} ({:+.3e}), {} iterations",
        own.above.len(),
        own.worst.0,
        own.worst.1,
        own.iterations
    );
    println!(
        "trajectories apart (largest over the steps): max vertex {:.3e}, RMS {:.3e}, \
         centroid {:.3e}",
        apart.max_vertex, apart.rms, apart.centroid
    );
}
