//! The cost of one iteration of each step method against plain's (the
//! per-iteration overhead), measured in one process, methods interleaved,
//! ratios paired round by round.
//!
//! ```text
//! cargo bench -p masssprings-benches --bench iteration_cost -- [SCENE.json …] [--rounds R] [--methods LIST]
//! ```
//!
//! Default: `data/flag.json` and `data/skirt.json`, 15 rounds,
//! `plain,chebyshev,anderson,lbfgs`. Each method gets its own simulation,
//! run three steps first (Chebyshev measures `ρ` in its first). In each
//! round, method after method, a copy of that simulation takes one step of
//! 50 iterations and another copy the same step with 250; the difference
//! of the two wall times over 200 is the method's time per iteration in
//! that round, free of the step's fixed costs. Its ratio to plain's time
//! in the *same* round is the overhead; the median of those ratios over
//! the rounds is printed, with their range. On a shared, noisy machine a
//! ratio of two runs taken seconds apart (as `benches/iteration_cost.sh`
//! takes them, as separate processes) moves by 10–30%; a paired ratio,
//! each pair taken within a second, moves much less.
//!
//! `plain` without an observer runs its iterations in the factor's order
//! (`sim::methods::factor_order`), 3–4% faster than the textbook loop the
//! other methods' iterations are built on; so each ratio is also given
//! against `plain` run by the textbook loop (`textbook`: the same step
//! with an observer that does nothing, which sends `plain` there).

use masssprings::mesh::load_scene;
use masssprings::sim::monitor::Observer;
use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::{Simulation, Sparse, StepMethod};
use std::path::PathBuf;
use std::time::Instant;

/// Iterations of the short and the long step.
const SHORT: usize = 50;
const LONG: usize = 250;

struct Options {
    scenes: Vec<PathBuf>,
    rounds: usize,
    methods: Vec<StepMethod>,
}

fn options() -> Options {
    let root = bench_common::repository_root();
    let mut options = Options {
        scenes: vec![],
        rounds: 15,
        methods: vec![
            StepMethod::Plain,
            StepMethod::Chebyshev,
            StepMethod::Anderson,
            StepMethod::Lbfgs,
        ],
    };
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--rounds" => {
                let rounds = args.next().and_then(|r| r.parse().ok()).filter(|&r| r > 0);
                options.rounds = rounds.expect("--rounds takes a positive whole number");
            }
            "--methods" => {
                let list = args.next().unwrap_or_default();
                options.methods = list.split(',').map(|m| m.parse().unwrap()).collect();
            }
            flag if flag.starts_with("--") => {} // cargo bench's own (--bench)
            scene => options.scenes.push(PathBuf::from(scene)),
        }
    }
    if options.scenes.is_empty() {
        options.scenes = ["flag", "skirt"]
            .map(|name| root.join(format!("data/{name}.json")))
            .to_vec();
    }
    if options.methods.first() != Some(&StepMethod::Plain) {
        options.methods.insert(0, StepMethod::Plain); // the yardstick
    }
    options
}

/// Seconds per iteration of one step of `simulation` (copies of it); with
/// `textbook`, watched by an observer that does nothing (so that `plain`
/// runs its textbook loop).
fn seconds_per_iteration(simulation: &Simulation<Sparse>, textbook: bool) -> f64 {
    let [short, long] = [SHORT, LONG].map(|iterations| {
        let mut copy = simulation.clone();
        copy.set_iterations(iterations);
        let control = copy.options().step;
        let start = Instant::now();
        let observer: Option<Observer<'_>> = match textbook {
            true => Some(&mut |_| {}),
            false => None,
        };
        copy.step_with(&control, observer)
            .expect("a step of a bundled scene");
        start.elapsed().as_secs_f64()
    });
    (long - short) / (LONG - SHORT) as f64
}

fn median(values: &mut [f64]) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

fn main() {
    let options = options();
    for path in &options.scenes {
        let scene = load_scene(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        // plain, plain by the textbook loop, then the other methods
        let mut rows: Vec<(&str, StepMethod, bool)> = vec![("plain", StepMethod::Plain, false)];
        rows.push(("textbook", StepMethod::Plain, true));
        rows.extend(options.methods[1..].iter().map(|&m| (m.name(), m, false)));
        let simulations: Vec<Simulation<Sparse>> = rows
            .iter()
            .map(|&(_, method, _)| {
                let mut simulation =
                    Simulation::from_scene(&scene, SimulationOptions::default()).unwrap();
                simulation.set_method(method, None);
                for _ in 0..3 {
                    simulation.step().unwrap();
                }
                simulation
            })
            .collect();
        // times[method][round]
        let mut times = vec![vec![]; simulations.len()];
        for _ in 0..options.rounds {
            for ((simulation, row), time) in simulations.iter().zip(&rows).zip(&mut times) {
                time.push(seconds_per_iteration(simulation, row.2));
            }
        }
        println!(
            "{} ({} rounds, step 4 of each method's run):",
            path.display(),
            options.rounds
        );
        for ((name, _, _), time) in rows.iter().zip(&times) {
            let per = median(&mut time.clone()) * 1e3;
            let [(ratio, low, high), (textbook, ..)] = [&times[0], &times[1]].map(|yardstick| {
                let mut ratios: Vec<f64> = time.iter().zip(yardstick).map(|(t, p)| t / p).collect();
                let ratio = median(&mut ratios);
                (ratio, ratios[0], ratios[ratios.len() - 1])
            });
            println!(
                "  {name:<10} {per:.4} ms per iteration   {ratio:.3}x plain (rounds {low:.3}-{high:.3})   {textbook:.3}x textbook"
            );
        }
    }
}
