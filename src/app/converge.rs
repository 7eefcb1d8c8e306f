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
//!
//! The files beside this one, each using only those listed before it:
//! [`request`] (the parsed command line), [`curve`] (one step by one
//! method, iterate by iterate), [`steps_plot`] and [`convergence_plot`]
//! (the pictures), [`steps`] (steps 1…S, each method's whole step beside
//! plain-50's), [`accuracy`] (`--accuracy`), [`oracle`] (`--oracle`: the
//! accuracy's cost against the least any rule could spend) and [`motion`]
//! (`--motion`: how much the cloth moves, by how each step is solved).

mod accuracy;
mod convergence_plot;
mod curve;
mod motion;
mod oracle;
mod request;
mod steps;
mod steps_plot;

use super::draw::plot::Scale;
use super::error::AppError;
use super::file_plan::{load_scene, plan_scene_inputs};
use super::flags::{between, choice, whole, FactorFlags, StepRules};
use super::limits::{check_kept, precompute};
use super::progress::Progress;
use curve::{first_reaching, rho_from, trace, yardstick, Curve, Sample};
use masssprings::files::{write_file, FilePlan};
use masssprings::mesh::Scene;
use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::{Sparse, StepMethod, DELTA_T};
use request::{Request, YARDSTICKS};
use std::io::Write;
use std::path::{Path, PathBuf};
use steps::{advance, by_method, draw_rule, rule_rows, write_rule_csv, RuleRow};
use steps_plot::StepPlot;

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
    /// With --accuracy: along the accuracy's own run and plain-50's, each step's time against the least any stopping rule could spend (an oracle that knows plain-50's energy), drawn into FILE.png with the rows in FILE.csv.
    #[arg(long, value_name = "FILE.png", requires = "accuracy")]
    oracle: Option<PathBuf>,
    /// With --accuracy: the kinetic energy and the centroid's speed after each step of three runs from rest, plain-50, the accuracy's and one solved to convergence, drawn into FILE.png.
    #[arg(
        long,
        value_name = "FILE.png",
        requires = "accuracy",
        conflicts_with = "oracle"
    )]
    motion: Option<PathBuf>,
    /// The most iterations each method may take on a step, the length of its curve (default 200; with --accuracy, the accuracy's).
    #[arg(long, value_name = "N", value_parser = whole(1, usize::MAX))]
    iterations: Option<usize>,
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
    if let Some(path) = &request.motion {
        plan.output("--motion", path);
    }
    if let Some(path) = &request.oracle {
        plan.output("--oracle", path);
        plan.output("--oracle's table", &path.with_extension("csv"));
    }
    plan.output("the table", Path::new("-")).check()?;
    if let Some(path) = &request.oracle {
        oracle::check_table(path)?;
    }
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
    sim_options.step.iterations = args.iterations.unwrap_or(sim_options.step.iterations);
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
        oracle: args.oracle,
        motion: args.motion,
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
            "{:<10} {:>6} {:>14.6e} {:>10.2e} {:>20} {:>20}  {}",
            curve.method.name(),
            last.iteration,
            last.energy,
            last.relative_gradient,
            reach(yardsticks[0]),
            reach(yardsticks[1]),
            curve.stop.name()
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
    if let (Some(_), Some(path)) = (request.accuracy, &request.oracle) {
        return oracle::run(request, scene, steps, path);
    }
    if let (Some(_), Some(path)) = (request.accuracy, &request.motion) {
        return motion::run(request, scene, steps, path);
    }
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
    let mut progress = Progress::new(steps, true);
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
        advance(&mut simulation, step, &mut progress)?;
    }
    progress.finish();
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
