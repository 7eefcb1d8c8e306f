//! `masssprings converge SCENE.json`: one time step solved by every method,
//! iteration by iteration.
//!
//! Runs the canonical simulation (plain, 50 iterations) up to step `K`,
//! then solves step `K` again with each method, up to `N` iterations, and
//! records per iteration the energy `E(p) − E(p⁰)` (cancellation-free, so it
//! is ≤ 0 and falls), the relative gradient `‖∇E(p)‖ / ‖∇E(p⁰)‖` over the
//! free vertices, and the wall time since the method began (the time spent
//! recording is not counted). Prints, per method, the iterations and
//! milliseconds it needed to reach the energy of 50 and of 200 plain
//! iterations (plain is always run to 200 for that); writes the curves as
//! CSV and as a two-panel plot.
//!
//! With `--steps S` it does this for each of the canonical steps 1…S and
//! prints medians; with a stopping rule as well, each method solves each
//! step as `simulate` would. Its CSV then has one row per step and method
//! (when the method reached plain-50's energy, or where its rule stopped
//! it beside plain-50's energy), so that the steps behind a median can be
//! read one by one. With `--accuracy` instead of a rule, it compares the
//! accuracy's settings with the assignment's over whole animations
//! ([`accuracy`]).

mod accuracy;
mod convergence_plot;
mod steps_plot;

use super::draw::plot::Scale;
use super::error::AppError;
use super::file_plan::{load_scene, plan_scene_inputs};
use super::flags::{between, choice, whole, FactorFlags, StepRules};
use super::limits::{check_kept, precompute};
use masssprings::files::{write_file, FilePlan};
use masssprings::mesh::Scene;
use masssprings::sim::energy::free_norm;
use masssprings::sim::methods::chebyshev::estimate_rho;
use masssprings::sim::monitor::Iterate;
use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::{Accuracy, Start, DELTA_T};
use masssprings::sim::{Simulation, Sparse, StepControl, StepMethod, Stop};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};
use steps_plot::{StepPlot, StepSeries};

/// One row of the CSV.
#[derive(Debug, Clone, Copy)]
struct Sample {
    iteration: usize,
    energy: f64,
    relative_gradient: f64,
    elapsed_ms: f64,
    /// `‖pₖ − pₖ₋₁‖` (0 at iteration 0).
    step_norm: f64,
}

/// One method's curve.
struct Curve {
    method: StepMethod,
    samples: Vec<Sample>,
    stop: Stop,
    /// The rounding `η` of the step's energy differences
    /// (`StepEnergy::rounding`).
    rounding: f64,
}

pub(super) struct Request {
    scene: PathBuf,
    step: usize,
    methods: Vec<StepMethod>,
    control: StepControl,
    csv: Option<PathBuf>,
    plot: Option<PathBuf>,
    /// `--steps S`: instead of one step, steps 1…S, medians only.
    over_steps: Option<usize>,
    /// The canonical simulation: plain, 50 iterations, the pins and the
    /// factorization given.
    pub(super) canonical: SimulationOptions,
    /// `--accuracy A` (with `--steps`): the accuracy's settings against the
    /// assignment's, over whole animations.
    accuracy: Option<Accuracy>,
}

/// Plain iterations whose energies are the yardsticks.
const YARDSTICKS: [usize; 2] = [50, 200];

/// Solve one time step by every method, iteration by iteration.
#[derive(clap::Args, Debug)]
#[command(
    group(clap::ArgGroup::new("rules")
        .args(["accuracy", "tolerance", "energy_tolerance", "at_least_plain"])
        .multiple(true)
        .requires("steps")),
    after_help = "\
Runs the canonical simulation (plain, 50 iterations) up to step K, then
solves step K again with each method, up to N iterations, recording per
iteration the energy E(p) − E(p⁰), the relative gradient and the wall time.
Prints, per method, the iterations and milliseconds it needed to reach the
energy of 50 and of 200 plain iterations; writes the curves as CSV and as a
two-panel plot.

With --steps S, does this for steps 1…S and prints medians. The stopping
rules (--tolerance, --energy-tolerance, --at-least-plain) need --steps: each
method then solves every step as simulate would, and the table gives the
median step time against plain-50's and how many steps ended at or below
plain-50's energy. --accuracy (with --steps) runs the accuracy's settings
and the assignment's plain-50 side by side, each step from the same state.")]
pub struct ConvergeArgs {
    /// The scene: JSON that names an OBJ (data/README.md).
    #[arg(value_name = "SCENE.json")]
    scene: PathBuf,
    /// The step to solve, counted from 1 (default 1).
    #[arg(long, value_name = "K", value_parser = whole(1, usize::MAX), conflicts_with = "accuracy")]
    step: Option<usize>,
    /// Comma-separated methods (default: all of them).
    #[arg(long, value_name = "LIST", value_delimiter = ',', value_parser = choice::<StepMethod>(&StepMethod::ALL.map(StepMethod::name)), conflicts_with = "accuracy")]
    methods: Vec<StepMethod>,
    /// Instead of one step, steps 1…S: the median time each method takes to reach plain-50's energy.
    #[arg(long, value_name = "S", value_parser = whole(1, usize::MAX))]
    steps: Option<usize>,
    /// Write the curves as CSV (with --steps: one row per step and method).
    #[arg(long, value_name = "FILE")]
    csv: Option<PathBuf>,
    /// Draw the curves into a PNG (with --steps: each step's cost and accuracy against plain-50's).
    #[arg(short = 'o', long, value_name = "FILE.png")]
    plot: Option<PathBuf>,
    /// The time step in seconds, 1e-4 to 1 (default 1/30, the assignment's).
    #[arg(long, value_name = "DT", value_parser = between(1e-4, 1.0))]
    delta_t: Option<f64>,
    #[command(flatten)]
    rules: StepRules,
    #[command(flatten)]
    factor: FactorFlags,
}

pub fn run(args: ConvergeArgs) -> Result<(), AppError> {
    let request = parse(args);
    let scene = load_scene(&request.scene)?;
    let mut plan = FilePlan::default();
    plan_scene_inputs(&mut plan, &request.scene, &scene);
    for (flag, path) in [("--csv", &request.csv), ("--plot", &request.plot)] {
        if let Some(path) = path {
            plan.output(flag, path);
        }
    }
    plan.output("the table", Path::new("-")).check()?;
    check_records(&request)?;
    if let Some(steps) = request.over_steps {
        return run_over_steps(&request, &scene, steps);
    }
    let mut simulation = precompute::<Sparse>(&scene, &request.scene, request.canonical)?;
    for step in 1..request.step {
        simulation
            .step()
            .map_err(|e| AppError::Failed(format!("step {step}: {e}")))?;
    }
    let plain_reference = trace(
        &simulation,
        &yardstick(&request.control),
        StepMethod::Plain,
        YARDSTICKS[1],
    )?;
    let yardsticks = YARDSTICKS.map(|i| plain_reference.samples.get(i).map(|s| s.energy));
    let mut control = request.control;
    if control.rho.is_none() {
        control.rho = Some(rho_from(&plain_reference));
        eprintln!(
            "converge: ρ = {:.4} (estimated from the plain iteration)",
            control.rho.unwrap_or(0.0)
        );
    }
    let mut curves = Vec::new();
    for &method in &request.methods {
        eprintln!("converge: {method} …");
        curves.push(trace(&simulation, &control, method, control.iterations)?);
    }
    print_table(&request, &curves, yardsticks, plain_reference.rounding);
    if let Some(path) = &request.csv {
        write_file(path, |out| write_csv(out, &curves))?;
    }
    if let Some(path) = &request.plot {
        convergence_plot::draw(path, &scene.name, request.step, &curves_for_plot(&curves))?;
    }
    Ok(())
}

pub(super) fn parse(args: ConvergeArgs) -> Request {
    let mut sim_options = SimulationOptions::default();
    sim_options.step.iterations = 200;
    sim_options.step.measure = true; // every report compares energies
    args.rules.apply(&mut sim_options);
    let accuracy = args.rules.accuracy;
    let methods = match accuracy {
        Some(_) => vec![sim_options.step.method],
        None if args.methods.is_empty() => StepMethod::ALL.to_vec(),
        None => args.methods,
    };
    let mut canonical = SimulationOptions {
        pins: sim_options.pins,
        delta_t: args.delta_t.unwrap_or(DELTA_T),
        ..SimulationOptions::default()
    };
    args.factor.apply(&mut canonical);
    Request {
        scene: args.scene,
        step: args.step.unwrap_or(1),
        methods,
        control: sim_options.step,
        csv: args.csv,
        plot: args.plot,
        canonical,
        over_steps: args.steps,
        accuracy,
    }
}

/// Refuses, before any work, records that would not fit in memory: every
/// iterate of every method's curve (one step), and the rows kept per step
/// and method (`--steps S`).
fn check_records(request: &Request) -> Result<(), AppError> {
    let curves = request.methods.len() as u64 + 1; // and plain's yardstick
    let iterates = (request.control.iterations as u64)
        .max(YARDSTICKS[1] as u64)
        .saturating_add(1)
        .saturating_mul(curves);
    // a sample, and its point in the plot
    let each = (std::mem::size_of::<Sample>() + 3 * std::mem::size_of::<f64>()) as u64;
    check_kept(iterates, "iterates", each, "use fewer --iterations")?;
    if let Some(steps) = request.over_steps {
        let rows = (steps as u64).saturating_mul(curves);
        let each = (std::mem::size_of::<RuleRow>() + 4 * std::mem::size_of::<f64>()) as u64;
        check_kept(rows, "step rows", each, "use fewer --steps")?;
    }
    Ok(())
}

/// The control of the yardstick runs (plain-50, plain-200): the
/// assignment's iteration from the assignment's start, whatever `--start`
/// says for the methods compared with it.
fn yardstick(control: &StepControl) -> StepControl {
    StepControl {
        start: Start::Current,
        ..*control
    }
}

/// Step `simulation`'s next step by `method` for up to `iterations`,
/// recording every iterate (on a copy: `simulation` does not move).
fn trace(
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
fn rho_from(plain: &Curve) -> f64 {
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
fn first_reaching(curve: &Curve, energy: f64) -> Option<&Sample> {
    let slack = 1e-12 * energy.abs();
    curve.samples.iter().find(|s| s.energy <= energy + slack)
}

fn print_table(request: &Request, curves: &[Curve], yardsticks: [Option<f64>; 2], rounding: f64) {
    println!(
        "step {} of {}; energies relative to the step's start (rounding {rounding:.1e}); plain-50 {}, plain-200 {}",
        request.step,
        request.scene.display(),
        yardsticks[0].map_or("-".into(), |e| format!("{e:.6e}")),
        yardsticks[1].map_or("-".into(), |e| format!("{e:.6e}")),
    );
    println!(
        "{:<10} {:>6} {:>14} {:>10} {:>20} {:>20}  stop",
        "method", "iters", "energy", "rel.grad", "to plain-50 (it, ms)", "to plain-200 (it, ms)"
    );
    for curve in curves {
        let last = curve
            .samples
            .last()
            .expect("iteration 0 is always recorded");
        let reach = |target: Option<f64>| match target.and_then(|e| first_reaching(curve, e)) {
            Some(s) => format!("{}, {:.2}", s.iteration, s.elapsed_ms),
            None => "not reached".into(),
        };
        println!(
            "{:<10} {:>6} {:>14.6e} {:>10.2e} {:>20} {:>20}  {:?}",
            curve.method.name(),
            last.iteration,
            last.energy,
            last.relative_gradient,
            reach(yardsticks[0]),
            reach(yardsticks[1]),
            curve.stop
        );
    }
}

fn write_csv(out: &mut dyn Write, curves: &[Curve]) -> std::io::Result<()> {
    writeln!(out, "method,iteration,energy,relative_gradient,elapsed_ms")?;
    for curve in curves {
        for s in &curve.samples {
            writeln!(
                out,
                "{},{},{:e},{:e},{:.4}",
                curve.method.name(),
                s.iteration,
                s.energy,
                s.relative_gradient,
                s.elapsed_ms
            )?;
        }
    }
    Ok(())
}

/// Each curve as (name, [(iteration, energy, ms)]), for the plot.
fn curves_for_plot(curves: &[Curve]) -> Vec<convergence_plot::PlotCurve> {
    curves
        .iter()
        .map(|c| {
            let points = c
                .samples
                .iter()
                .map(|s| (s.iteration as f64, s.energy, s.elapsed_ms))
                .collect();
            (c.method.name().to_string(), points)
        })
        .collect()
}

/// `--steps S`: for each of the canonical steps 1…S, the milliseconds each
/// method needs to reach the energy of 50 plain iterations of that step
/// (the accuracy the assignment settles for); prints, per method, the
/// median over the steps and its ratio to plain-50's median.
fn run_over_steps(request: &Request, scene: &Scene, steps: usize) -> Result<(), AppError> {
    if let Some(accuracy) = request.accuracy {
        return accuracy::run(request, scene, steps, accuracy);
    }
    if request.control.has_stopping_rule() {
        return run_over_steps_to_tolerance(request, scene, steps);
    }
    let mut simulation = precompute::<Sparse>(scene, &request.scene, request.canonical)?;
    let mut control = request.control;
    let mut times: Vec<Vec<f64>> = vec![Vec::new(); request.methods.len()];
    let mut iterations: Vec<Vec<f64>> = vec![Vec::new(); request.methods.len()];
    let mut plain_50_ms = Vec::new();
    let mut rows = Vec::new();
    for step in 1..=steps {
        let plain = trace(
            &simulation,
            &yardstick(&control),
            StepMethod::Plain,
            YARDSTICKS[0],
        )?;
        let target = plain.samples.last().map_or(0.0, |s| s.energy);
        let ms_of_plain = plain.samples.last().map_or(0.0, |s| s.elapsed_ms);
        plain_50_ms.push(ms_of_plain);
        if control.rho.is_none() {
            control.rho = Some(rho_from(&plain));
        }
        for (m, &method) in request.methods.iter().enumerate() {
            let curve = trace(&simulation, &control, method, control.iterations)?;
            let reached = first_reaching(&curve, target);
            times[m].push(reached.map_or(f64::INFINITY, |s| s.elapsed_ms));
            iterations[m].push(reached.map_or(f64::INFINITY, |s| s.iteration as f64));
            rows.push(ReachRow {
                step,
                method,
                reached: reached.map(|s| (s.iteration, s.elapsed_ms)),
                plain_50_ms: ms_of_plain,
            });
        }
        advance(&mut simulation, step, steps)?;
    }
    eprintln!();
    print_reach_table(request, steps, &mut plain_50_ms, &times, &iterations);
    if let Some(path) = &request.csv {
        write_file(path, |out| write_reach_csv(out, &rows))?;
    }
    if let Some(path) = &request.plot {
        draw_reach(path, &scene.name, &request.methods, &rows)?;
    }
    Ok(())
}

/// The table of `--steps S` without a rule: per method, the medians over
/// the steps of the time and the iterations to reach plain-50's energy.
fn print_reach_table(
    request: &Request,
    steps: usize,
    plain_50_ms: &mut [f64],
    times: &[Vec<f64>],
    iterations: &[Vec<f64>],
) {
    let plain_median = super::timing::median(plain_50_ms);
    println!(
        "{} steps 1-{steps}: median over the steps of the time to reach plain-50's energy \
         (plain-50 itself: {plain_median:.3} ms)",
        request.scene.display()
    );
    println!(
        "{:<10} {:>12} {:>10} {:>14}",
        "method", "iterations", "ms", "/ plain-50"
    );
    for (m, method) in request.methods.iter().enumerate() {
        let ms = super::timing::median(&mut times[m].clone());
        println!(
            "{:<10} {:>12} {:>10.3} {:>14.3}",
            method.name(),
            super::timing::median(&mut iterations[m].clone()),
            ms,
            ms / plain_median
        );
    }
}

/// The plot of `--steps S` without a rule: per step, the time to reach
/// plain-50's energy over plain-50's time, and the iterations it took.
fn draw_reach(
    path: &std::path::Path,
    scene: &str,
    methods: &[StepMethod],
    rows: &[ReachRow],
) -> Result<(), AppError> {
    let series = by_method(methods, rows, |r| {
        let (iterations, ms) = r.reached?;
        Some((
            r.method,
            (r.step as f64, ms / r.plain_50_ms, iterations as f64),
        ))
    });
    let plot = StepPlot {
        title: format!("{scene}: reaching the energy of 50 plain iterations, step by step"),
        caption: "left: time to first reach plain-50's energy / plain-50's time; right: \
                  iterations to reach it (steps never reached left out)"
            .into(),
        left: (
            "time to plain-50's energy",
            "/ plain-50's time (log)",
            Scale::Log10,
        ),
        right: (
            "iterations to plain-50's energy",
            "iterations",
            Scale::Linear,
        ),
        plain_50_line: false,
    };
    steps_plot::draw(path, &plot, &series)
}

/// `--steps S --csv`: when one method first reached plain-50's energy on
/// one step.
struct ReachRow {
    step: usize,
    method: StepMethod,
    /// Iterations and milliseconds to reach it; `None`: not reached.
    reached: Option<(usize, f64)>,
    plain_50_ms: f64,
}

fn write_reach_csv(out: &mut dyn Write, rows: &[ReachRow]) -> std::io::Result<()> {
    writeln!(
        out,
        "step,method,iterations_to_plain_50,ms_to_plain_50,plain_50_ms"
    )?;
    for row in rows {
        let (iterations, ms) = match row.reached {
            Some((i, ms)) => (i.to_string(), format!("{ms:.4}")),
            None => (String::new(), String::new()),
        };
        writeln!(
            out,
            "{},{},{iterations},{ms},{:.4}",
            row.step,
            row.method.name(),
            row.plain_50_ms
        )?;
    }
    Ok(())
}

/// `--steps S --tolerance T` (or `--energy-tolerance F`, or both): for
/// each of the canonical steps 1…S, each method solves the step as
/// `simulate` with the same rules would (stopping by them, nobody
/// watching), timed whole; so does plain with 50 iterations. Prints, per
/// method, the median step time, its ratio to plain-50's, the median
/// iterations, and on how many steps the method ended at or below
/// plain-50's energy (the accuracy it is compared at).
fn run_over_steps_to_tolerance(
    request: &Request,
    scene: &Scene,
    steps: usize,
) -> Result<(), AppError> {
    let (scene_name, step_rows) = rule_rows(request, scene, steps)?;
    let mut plain_ms: Vec<f64> = step_rows
        .iter()
        .step_by(request.methods.len())
        .map(|r| r.plain_50_ms)
        .collect();
    let mut rows: Vec<(Vec<f64>, Vec<f64>, usize)> =
        vec![(Vec::new(), Vec::new(), 0); request.methods.len()];
    for (i, r) in step_rows.iter().enumerate() {
        let row = &mut rows[i % request.methods.len()];
        row.0.push(r.ms);
        row.1.push(r.iterations as f64);
        if r.energy <= r.plain_50_energy + 1e-12 * r.plain_50_energy.abs() {
            row.2 += 1;
        }
    }
    let plain_median = super::timing::median(&mut plain_ms);
    let rules = [
        ("--tolerance", request.control.tolerance),
        ("--energy-tolerance", request.control.energy_tolerance),
        ("--at-least-plain", request.control.at_least_plain),
    ]
    .iter()
    .filter_map(|(flag, value)| value.map(|v| format!("{flag} {v}")))
    .collect::<Vec<_>>()
    .join(" ");
    println!(
        "{} steps 1-{steps}, {rules}: median step time against plain-50's \
         ({plain_median:.3} ms)",
        request.scene.display()
    );
    println!(
        "{:<10} {:>12} {:>10} {:>12} {:>26}",
        "method", "iterations", "ms", "/ plain-50", "steps at plain-50's energy"
    );
    for (method, (ms, iterations, reached)) in request.methods.iter().zip(&mut rows) {
        let ms = super::timing::median(ms);
        println!(
            "{:<10} {:>12} {:>10.3} {:>12.3} {:>26}",
            method.name(),
            super::timing::median(iterations),
            ms,
            ms / plain_median,
            format!("{reached} of {steps}")
        );
    }
    if let Some(path) = &request.csv {
        write_file(path, |out| write_rule_csv(out, &step_rows))?;
    }
    if let Some(path) = &request.plot {
        let title = format!("{scene_name}, {rules}: each step against plain-50's");
        draw_rule(path, title, &request.methods, &step_rows)?;
    }
    Ok(())
}

/// The rows of `--steps S` with a rule: for each of the canonical steps
/// 1…S, plain-50 and then each method solve the step from the same
/// state, each timed whole (interleaved, in one process), stopping by the
/// request's rules; the scene's name beside them.
fn rule_rows(
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
        advance(&mut simulation, step, steps)?;
    }
    eprintln!();
    Ok((scene.name.clone(), step_rows))
}

/// The canonical simulation's step `step` of `steps`, with progress.
fn advance(simulation: &mut Simulation<Sparse>, step: usize, steps: usize) -> Result<(), AppError> {
    simulation
        .step()
        .map_err(|e| AppError::Failed(format!("step {step}: {e}")))?;
    eprint!("\rconverge: step {step}/{steps}");
    Ok(())
}

/// One plot series per method, from the rows that give it a point
/// (`point` says whose point a row is, if any).
fn by_method<R>(
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
fn draw_rule(
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
struct RuleRow {
    step: usize,
    method: StepMethod,
    iterations: usize,
    stop: Stop,
    /// `E(p) − E(pᵗ)` where the method stopped, and where plain-50 does.
    energy: f64,
    plain_50_energy: f64,
    ms: f64,
    plain_50_ms: f64,
}

fn write_rule_csv(out: &mut dyn Write, rows: &[RuleRow]) -> std::io::Result<()> {
    writeln!(
        out,
        "step,method,iterations,stop,energy,plain_50_energy,ms,plain_50_ms"
    )?;
    for r in rows {
        writeln!(
            out,
            "{},{},{},{:?},{:e},{:e},{:.4},{:.4}",
            r.step,
            r.method.name(),
            r.iterations,
            r.stop,
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
fn timed_step(
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
fn measured_decrease(report: &masssprings::sim::StepReport) -> f64 {
    report
        .energy_decrease
        .expect("converge's steps measure their energy")
}
