//! `masssprings converge SCENE --steps S --accuracy assignment --oracle
//! FILE.png`: what the accuracy's rule spends on each step, beside the
//! least any stopping rule could spend on it.
//!
//! A stopping rule does not know plain-50's energy `E₅₀` from the step's
//! state: it has to bound it from what it measures. An oracle that knows
//! it could stop every method at the first iterate at or below it. So, for
//! each of the steps 1…S along two trajectories, the accuracy's own run
//! and plain-50's, this solves the step from that state (untimed: plain-50
//! itself, for `E₅₀`; timed: each of the methods below, recording every
//! iterate) and writes, per step,
//!
//! ```text
//! the rule       its iterations, time and ending energy, as simulate solves the step
//! L-BFGS         from pᵗ, iterations and time to first reach E₅₀
//! plain, ŷ       plain from the inertial prediction ŷ = 2pᵗ − pᵗ⁻¹, the same
//! L-BFGS, ŷ      L-BFGS from ŷ, the same
//! least          the fastest of the three: what an oracle rule would spend
//! ```
//!
//! each time over plain-50's time from the same state. The plot draws the
//! rule's time and the oracle's least per step, for both trajectories:
//! where the rule spends more than the oracle, it wastes.

use super::accuracy::median;
use super::curve::{trace, Curve};
use super::request::{Request, YARDSTICKS};
use super::steps::timed_step;
use super::steps_plot::{StepPlot, StepSeries};
use crate::app::draw::plot::Scale;
use crate::app::error::AppError;
use crate::app::file_plan::{occupied, starts_with_line};
use crate::app::limits::precompute;
use masssprings::files::{shown, write_file};
use masssprings::mesh::Scene;
use masssprings::sim::{Simulation, Sparse, Start, StepControl, StepMethod};
use std::io::Write;
use std::path::Path;

/// The oracle's methods: a name, the method, and where it starts.
const ORACLES: [(&str, StepMethod, Start); 3] = [
    ("L-BFGS", StepMethod::Lbfgs, Start::Current),
    ("plain, inertial start", StepMethod::Plain, Start::Inertial),
    ("L-BFGS, inertial start", StepMethod::Lbfgs, Start::Inertial),
];

/// The most iterations an oracle method may take to reach `E₅₀`.
const ORACLE_ITERATIONS: usize = 50;

/// One step of one trajectory.
struct OracleRow {
    trajectory: &'static str,
    step: usize,
    plain_50_ms: f64,
    /// `E₅₀ − E(pᵗ)`.
    plain_50_energy: f64,
    rule_iterations: usize,
    rule_ms: f64,
    rule_energy: f64,
    /// How far below `E₅₀` the floor `Eⱼ − (50 − j) δⱼ` lies after plain's
    /// first and after its third iteration, over plain-50's decrease.
    floors_below: [f64; 2],
    /// Per oracle method: iterations and milliseconds to reach `E₅₀`, if
    /// it did within [`ORACLE_ITERATIONS`].
    reached: [Option<(usize, f64)>; 3],
}

impl OracleRow {
    /// The least time any oracle method needed, over plain-50's.
    fn least(&self) -> Option<f64> {
        let least = self
            .reached
            .iter()
            .flatten()
            .map(|r| r.1)
            .reduce(f64::min)?;
        Some(least / self.plain_50_ms)
    }
}

/// Measures both trajectories and writes the plot to `path` and the rows
/// beside it (`path` with `.csv`).
pub fn run(request: &Request, scene: &Scene, steps: usize, path: &Path) -> Result<(), AppError> {
    let mut rows = trajectory(request, scene, steps, "own", request.control)?;
    rows.extend(trajectory(
        request,
        scene,
        steps,
        "plain-50",
        request.canonical.step,
    )?);
    print_summary(&rows);
    let table = path.with_extension("csv");
    write_file(&table, |out| write_csv(out, &rows))?;
    draw(path, &scene.name, &rows)?;
    println!("wrote {} and its rows, {}", shown(path), shown(&table));
    Ok(())
}

/// The first line of the rows' table.
const TABLE_HEADER: &str = "trajectory,step,plain_50_energy,plain_50_ms,rule_iterations,\
                            rule_ms,rule_energy,floor_1_below,floor_3_below,lbfgs_iterations,\
                            lbfgs_ms,inertial_plain_iterations,inertial_plain_ms,\
                            inertial_lbfgs_iterations,inertial_lbfgs_ms";

/// Refuses, before any work, a plot `path` whose rows' table (`path` with
/// `.csv`, a name the user did not type) would replace a file that is not
/// such a table: a user's `res.csv` beside `--oracle res.png`.
///
/// # Errors
/// A failure naming the file and the way out.
pub fn check_table(path: &Path) -> Result<(), AppError> {
    let table = path.with_extension("csv");
    if !occupied(&table) || starts_with_line(&table, TABLE_HEADER) {
        return Ok(());
    }
    Err(AppError::Failed(format!(
        "--oracle {}: its rows go to {}, which holds something else (not a table converge \
         --oracle wrote) and would be replaced; move it away, or give --oracle another name",
        shown(path),
        shown(&table)
    )))
}

/// The rows of the steps 1…`steps` along the run advanced by `driver`.
fn trajectory(
    request: &Request,
    scene: &Scene,
    steps: usize,
    name: &'static str,
    driver: StepControl,
) -> Result<Vec<OracleRow>, AppError> {
    let options = masssprings::sim::SimulationOptions {
        step: driver,
        ..request.canonical
    };
    let mut simulation = precompute::<Sparse>(scene, &request.scene, options)?;
    let mut runner = simulation.clone();
    let mut rows = Vec::with_capacity(steps);
    for step in 1..=steps {
        rows.push(oracle_row(request, &simulation, &mut runner, name, step)?);
        simulation
            .step()
            .map_err(|e| AppError::Failed(format!("{name}, step {step}: {e}")))?;
        eprintln!("converge --oracle: {name} step {step}/{steps}");
    }
    Ok(rows)
}

/// The next step from `simulation`'s state: plain-50, the rule (timed in
/// `runner`), and each oracle method until it reaches plain-50's energy.
fn oracle_row(
    request: &Request,
    simulation: &Simulation<Sparse>,
    runner: &mut Simulation<Sparse>,
    trajectory: &'static str,
    step: usize,
) -> Result<OracleRow, AppError> {
    let canonical = request.canonical.step;
    let plain = trace(simulation, &canonical, StepMethod::Plain, YARDSTICKS[0])?;
    let last = plain.samples.last().expect("an iterate at least");
    let (target, plain_50_ms) = (last.energy, last.elapsed_ms);
    let floors_below = [1, 3].map(|j| floor_below(&plain, j, target));
    let (report, rule_ms) = timed_step(runner, simulation, &request.control)?;
    let mut reached = [None; 3];
    for (slot, &(_, method, start)) in reached.iter_mut().zip(&ORACLES) {
        let control = StepControl { start, ..canonical };
        let curve = trace(simulation, &control, method, ORACLE_ITERATIONS)?;
        *slot = first_reaching(&curve, target);
    }
    Ok(OracleRow {
        trajectory,
        step,
        plain_50_ms,
        plain_50_energy: target,
        rule_iterations: report.iterations,
        rule_ms,
        rule_energy: -report.energy_decrease.unwrap_or(f64::NAN),
        floors_below,
        reached,
    })
}

/// How far below `target` (`E₅₀`) the floor `Eⱼ − (50 − j) δⱼ` of plain's
/// `j`-th iterate lies, over plain-50's decrease `−target` (negative: above).
fn floor_below(plain: &Curve, j: usize, target: f64) -> f64 {
    let energy = |i: usize| plain.samples.get(i).map_or(f64::NAN, |s| s.energy);
    let floor = energy(j) - (YARDSTICKS[0] - j) as f64 * (energy(j - 1) - energy(j));
    (target - floor) / -target
}

/// The iterations and milliseconds at which `curve` first reaches `target`.
fn first_reaching(curve: &Curve, target: f64) -> Option<(usize, f64)> {
    super::curve::first_reaching(curve, target).map(|s| (s.iteration, s.elapsed_ms))
}

/// Per trajectory: the medians of the rule's and the oracle's time over
/// plain-50's.
fn print_summary(rows: &[OracleRow]) {
    for trajectory in ["own", "plain-50"] {
        let of: Vec<&OracleRow> = rows.iter().filter(|r| r.trajectory == trajectory).collect();
        let rule: Vec<f64> = of.iter().map(|r| r.rule_ms / r.plain_50_ms).collect();
        let least: Vec<f64> = of.iter().filter_map(|r| r.least()).collect();
        let iterations: usize = of.iter().map(|r| r.rule_iterations).sum();
        let below = |j: usize| median(&of.iter().map(|r| r.floors_below[j]).collect::<Vec<_>>());
        let along = match trajectory {
            "own" => "the accuracy's own run",
            _ => "plain-50's run",
        };
        println!(
            "oracle, along {along}: the rule's median step {:.3} of plain-50's \
             ({iterations} iterations), the oracle's least {:.3} (reached on {} of {} steps); \
             the floor after plain's first iteration {:.2}, after its third {:.2} of plain-50's \
             decrease below plain-50's energy (medians)",
            median(&rule),
            median(&least),
            least.len(),
            of.len(),
            below(0),
            below(1)
        );
    }
}

fn write_csv(out: &mut dyn Write, rows: &[OracleRow]) -> std::io::Result<()> {
    writeln!(out, "{TABLE_HEADER}")?;
    for r in rows {
        write!(
            out,
            "{},{},{:e},{:.4},{},{:.4},{:e},{:.4},{:.4}",
            r.trajectory,
            r.step,
            r.plain_50_energy,
            r.plain_50_ms,
            r.rule_iterations,
            r.rule_ms,
            r.rule_energy,
            r.floors_below[0],
            r.floors_below[1]
        )?;
        for reached in &r.reached {
            match reached {
                Some((iterations, ms)) => write!(out, ",{iterations},{ms:.4}")?,
                None => write!(out, ",,")?,
            }
        }
        writeln!(out)?;
    }
    Ok(())
}

/// Left: along the rule's own trajectory; right: along plain-50's. Each
/// the rule's step time and the oracle's least, over plain-50's.
fn draw(path: &Path, scene: &str, rows: &[OracleRow]) -> Result<(), AppError> {
    let series_of = |name: &str, value: &dyn Fn(&OracleRow) -> Option<f64>| -> StepSeries {
        let point = |trajectory: &str, r: &OracleRow| {
            (r.trajectory == trajectory).then(|| value(r)).flatten()
        };
        let mut points = Vec::new();
        for r in rows.iter().filter(|r| r.trajectory == "own") {
            let plain = rows
                .iter()
                .find(|q| q.trajectory == "plain-50" && q.step == r.step);
            let right = plain.and_then(|q| point("plain-50", q)).unwrap_or(f64::NAN);
            points.push((r.step as f64, point("own", r).unwrap_or(f64::NAN), right));
        }
        (name.to_string(), points)
    };
    let series = vec![
        series_of("the rule", &|r| Some(r.rule_ms / r.plain_50_ms)),
        series_of("oracle: least", &|r| r.least()),
    ];
    let plot = StepPlot {
        title: format!("{scene}, --accuracy assignment: the rule against an oracle that knows plain-50's energy"),
        caption: "each step's time over plain-50's from the same state; oracle: the fastest \
                  method, stopped at plain-50's energy"
            .into(),
        left: ("along its own trajectory", "time / plain-50's (log)", Scale::Log10),
        right: ("along plain-50's trajectory", "time / plain-50's (log)", Scale::Log10),
        plain_50_line: true,
    };
    super::steps_plot::draw(path, &plot, &series)
}
