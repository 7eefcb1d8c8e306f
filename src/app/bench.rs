//! `masssprings bench`: how each cost grows with the size of the cloth.
//!
//! For each `grid-N` (the scene of `generate grid N`, built in memory by
//! [`procedural::grid`], no files), one fresh child process of this same
//! program (`bench --one N`) measures, in this order:
//!
//! 1. the simulation: precomputation, then `--steps` full steps (median);
//!    then the process's peak resident memory (`VmHWM` of
//!    `/proc/self/status`): what a simulation of that size needs. A fresh
//!    process per size, so that sizes do not share a high-water mark;
//! 2. the pass over the springs of one local/global iteration, on that
//!    simulation's springs and positions (medians): the local step with
//!    `Aᵀd` formed as it goes, as the plain iteration runs it
//!    ([`project_springs_into_transpose`]), and, apart, the textbook's two
//!    passes it replaces: the local step (`d`, [`project_springs`]) and
//!    `Aᵀd` (from the spring list, [`incidence_transpose_mul_points`]);
//! 3. the sparse Cholesky pipeline on that simulation's `Q`, phase by phase,
//!    as `masssprings analyze` times it (medians): AMD ordering, symbolic
//!    analysis, supernodal numeric factorization, a 3-column solve.
//!
//! An iteration of the step is the local step with `Aᵀd`, then
//! `b = k Aᵀd + y + w CᵀC V` and the 3-column solve, so the report gives the solve and
//! the pass over the springs as shares of one iteration (a step's time
//! over its [`ITERATIONS`]); the rest (`b`'s sum, copies, the step's
//! energy and gradient at its start) is what the two shares leave. The
//! two textbook passes are given as shares too, for comparison.
//!
//! The parent measures the machine's memory bandwidth itself (a STREAM
//! triad, `a = b + s c` over 3 × 32 MB, best of 10, counting 24 bytes per
//! element as STREAM does), then fits, for each time and for the peak
//! memory, the exponent `p` of `cost ≈ c nᵖ` by least squares on
//! `(ln n, ln cost)`. The solve's bandwidth is the bytes of `L` it reads
//! (two sweeps over `nnz(L)` values of 8 bytes and over the row indices
//! of 4, which the supernodal factor keeps once per supernode) over
//! its time.
//!
//! On more than one thread (`--threads N`, default the cores available)
//! the simulation, the factorization and the solve run on `N` threads, and
//! each child also times the numeric factorization, the solve and the
//! step on one thread, in rounds interleaved with those on `N`: the report
//! gives both and the speedups. The results are the same bits on any
//! number of threads, so the two simulations step alike.
//!
//! Output: a table, or with `--json` one object `{triad_gbps, steps,
//! sizes: [...], slopes: {...}}`; `--csv OUT` writes the sizes as CSV;
//! `--plot OUT.png` draws the times of the phases and the peak memory
//! against `n` on log-log axes ([`plot`](super::draw::plot)), each
//! series labelled with its fitted exponent. Progress goes to stderr.

use super::analysis::{analyze, HowFactored};
use super::draw::plot::{Figure, Panel, Scale, Series};
use super::error::AppError;
use super::flags::{whole, JsonFlag, ThreadsFlag};
use super::limits::check_grid;
use super::timing::{interleaved_medians, median_seconds, Repeats};
use masssprings::files::{write_file, FilePlan};
use masssprings::linalg::benchmark_right_hand_side;
use masssprings::linalg::sparse::{Method, Ordering, Relaxation, Triangle};
use masssprings::mesh::procedural;
use masssprings::sim::signed_incidence::incidence_transpose_mul_points;
use masssprings::sim::simd::local_step::{project_springs, project_springs_into_transpose};
use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::{Simulation, Sparse, ITERATIONS};
use std::io::Write;
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::Instant;

/// Full steps timed per size when `--steps` is not given.
const DEFAULT_STEPS: usize = 3;

/// Bytes of `L` one solve reads: two sweeps over `nnz(L)` values (8 bytes
/// each) and over the rows kept, once per supernode (32-bit).
fn solve_bytes(nnz_l_stored: usize, rows_kept: usize) -> f64 {
    2.0 * (8.0 * nnz_l_stored as f64 + 4.0 * rows_kept as f64)
}

/// What one size measured (one object of `sizes`, one row of the CSV).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
struct SizeReport {
    /// `N` of `grid-N`.
    side: usize,
    /// Vertices, `N²`: the order of `Q`.
    n: usize,
    /// Entries of the lower triangle of `Q`, diagonal included.
    nnz_q: usize,
    /// Nonzeros of `L`, diagonal included.
    nnz_l: usize,
    /// Entries of `L` stored, explicit zeros of relaxed supernodes included.
    nnz_l_stored: usize,
    /// Multiply-adds of the factorization, `Σ_j count[j]²`.
    flops: f64,
    ordering_s: f64,
    symbolic_s: f64,
    numeric_s: f64,
    /// Solve of `Q X = B` for three columns.
    solve_s: f64,
    /// One full time step (the assignment's 50 iterations).
    step_s: f64,
    /// The local step of one iteration as a pass of its own: `d` for
    /// every spring.
    local_step_s: f64,
    /// `Aᵀd` of one iteration as a pass of its own, from the spring list.
    atd_s: f64,
    /// The pass over the springs the iteration runs: the local step with
    /// `Aᵀd` formed as it goes.
    springs_pass_s: f64,
    /// The solve, the local step, `Aᵀd` and the springs' pass as shares of
    /// one iteration (`step_s / 50`).
    solve_share: f64,
    local_step_share: f64,
    atd_share: f64,
    springs_pass_share: f64,
    /// Building the simulation: springs, matrices, ordering, factorization.
    precompute_s: f64,
    /// `VmHWM` after precomputation and steps (0 where `/proc` is absent).
    peak_bytes: u64,
    bytes_per_vertex: f64,
    /// Bytes of `L` read by the solve per second, 10⁹.
    solve_gbps: f64,
    /// `‖Q X − B‖ / ‖B‖` of the timed solve.
    residual: f64,
    /// Its normwise backward error (`analyze`'s).
    backward_error: f64,
    /// The threads the simulation, the factorization and the solve ran on.
    threads: usize,
    /// On more than one thread: the numeric factorization, the solve and
    /// the step on one, timed in rounds interleaved with those above.
    numeric_one_thread_s: Option<f64>,
    solve_one_thread_s: Option<f64>,
    step_one_thread_s: Option<f64>,
}

/// The fitted exponents, `null` with fewer than two sizes.
#[derive(Debug, serde::Serialize)]
struct Slopes {
    ordering_s: Option<f64>,
    symbolic_s: Option<f64>,
    numeric_s: Option<f64>,
    solve_s: Option<f64>,
    step_s: Option<f64>,
    peak_bytes: Option<f64>,
}

/// The whole report (`--json`).
#[derive(Debug, serde::Serialize)]
struct BenchReport {
    triad_gbps: f64,
    steps: usize,
    sizes: Vec<SizeReport>,
    slopes: Slopes,
}

/// Scaling benchmark on the grid-N cloths: time and memory against n.
#[derive(clap::Args, Debug)]
#[command(after_help = "\
Scaling benchmark on the grid-N cloths (built in memory), each size in a
fresh process: n, nnz(Q), nnz(L), flops, median times of ordering,
symbolic analysis, numeric factorization, a 3-column solve and a full
step, peak memory (VmHWM), the solve's bandwidth beside a measured triad
bandwidth, and the log-log slope of each cost. On more than one thread
(--threads, default: the cores available) the numeric factorization, the
solve and the step are also timed on one thread, in interleaved rounds,
and the speedups reported. Default sizes 32,100,316 (about a minute);
1000, 2000, 3162 on request. Shows what it is measuring
on standard error, with --json too.")]
pub struct BenchArgs {
    /// Grid sides, each at least 2 (the default takes about a minute on a 2-core machine; 1000, one million vertices, 2000 and 3162 on request).
    #[arg(long, value_name = "N,N,…", value_delimiter = ',', default_value = "32,100,316", value_parser = whole(2, usize::MAX))]
    sizes: Vec<usize>,
    /// Steps timed per size.
    #[arg(long, value_name = "S", default_value_t = DEFAULT_STEPS, value_parser = whole(1, usize::MAX))]
    steps: usize,
    /// Write the table as CSV.
    #[arg(long, value_name = "FILE")]
    csv: Option<PathBuf>,
    /// Draw time and memory against n (log-log).
    #[arg(short = 'o', long, value_name = "FILE.png")]
    plot: Option<PathBuf>,
    #[command(flatten)]
    json: JsonFlag,
    #[command(flatten)]
    threads: ThreadsFlag,
    /// Internal: measure grid-N in this process (what each child runs).
    #[arg(long, hide = true, value_name = "N", value_parser = whole(2, usize::MAX))]
    one: Option<usize>,
}

pub fn run(args: BenchArgs) -> Result<(), AppError> {
    let (steps, threads) = (args.steps, args.threads.count());
    // the hidden `--one N`: measure one size here, for the parent process
    if let Some(side) = args.one {
        check_grid(side)?;
        let report = measure_one(side, steps, threads)?;
        println!(
            "{}",
            serde_json::to_string(&report).expect("plain numbers serialise")
        );
        return Ok(());
    }
    let sides = args.sizes;
    for &side in &sides {
        check_grid(side)?;
    }
    let (csv, plot) = (args.csv, args.plot);
    let mut plan = FilePlan::default();
    for (flag, path) in [("--csv", &csv), ("--plot", &plot)] {
        if let Some(path) = path {
            plan.output(flag, path);
        }
    }
    plan.output("the table", std::path::Path::new("-"))
        .check()?;
    eprintln!("bench: memory bandwidth (triad)");
    let triad_gbps = triad_gbps();
    let mut sizes = Vec::with_capacity(sides.len());
    for &side in &sides {
        sizes.push(measure_in_child(side, steps, threads)?);
    }
    let report = BenchReport {
        triad_gbps,
        steps,
        slopes: fit_slopes(&sizes),
        sizes,
    };
    if let Some(path) = &csv {
        write_file(path, |out| write_csv(out, &report.sizes))?;
    }
    if let Some(path) = &plot {
        draw_plot(path, &report)?;
    }
    if args.json.json {
        println!(
            "{}",
            serde_json::to_string(&report).expect("plain numbers serialise")
        );
    } else {
        print_table(&report);
    }
    Ok(())
}

/// Times of the phases (left) and peak memory (right) against `n`, log-log.
fn draw_plot(path: &std::path::Path, report: &BenchReport) -> Result<(), AppError> {
    let slopes = &report.slopes;
    let label = |name: &str, slope: Option<f64>| match slope {
        Some(p) => format!("{name} (n^{p:.2})"),
        None => name.to_string(),
    };
    let series = |name: &str, slope: Option<f64>, value: fn(&SizeReport) -> f64| {
        let points = report
            .sizes
            .iter()
            .map(|s| (s.n as f64, value(s)))
            .collect();
        Series::new(label(name, slope), points).with_markers()
    };
    let times = vec![
        series("ordering", slopes.ordering_s, |s| s.ordering_s),
        series("symbolic", slopes.symbolic_s, |s| s.symbolic_s),
        series("numeric", slopes.numeric_s, |s| s.numeric_s),
        series("solve, 3 columns", slopes.solve_s, |s| s.solve_s),
        series("step, 50 iterations", slopes.step_s, |s| s.step_s),
    ];
    let memory = vec![
        series("peak resident", slopes.peak_bytes, |s| {
            s.peak_bytes as f64 / 1e6
        }),
        series("values of L", None, |s| s.nnz_l_stored as f64 * 8.0 / 1e6),
    ];
    let panel = |title: &str, y_label: &str, series: Vec<Series>| Panel {
        title: title.into(),
        x_label: "n (vertices)".into(),
        y_label: y_label.into(),
        x_scale: Scale::Log10,
        y_scale: Scale::Log10,
        series,
        ..Panel::default()
    };
    let figure = Figure {
        title: "masssprings bench: cost against size, grid-N cloths".into(),
        caption: format!(
            "medians; fitted exponents in the legends; triad bandwidth {:.1} GB/s",
            report.triad_gbps
        ),
        panels: vec![
            panel("time of each phase", "seconds", times),
            panel("memory", "MB", memory),
        ],
        width: 1200,
        height: 560,
    };
    figure.write_png(path)
}

/// Runs `bench --one SIDE` in a fresh process of this program and reads
/// its one-line JSON report.
fn measure_in_child(side: usize, steps: usize, threads: usize) -> Result<SizeReport, AppError> {
    let program = std::env::current_exe()
        .map_err(|e| AppError::Failed(format!("cannot find this program to rerun it: {e}")))?;
    let output = Command::new(program)
        .args([
            "bench",
            "--one",
            &side.to_string(),
            "--steps",
            &steps.to_string(),
            "--threads",
            &threads.to_string(),
        ])
        .stdin(Stdio::null())
        .stderr(Stdio::inherit())
        .output()
        .map_err(|e| AppError::Failed(format!("grid-{side}: cannot start the measurement: {e}")))?;
    if !output.status.success() {
        return Err(AppError::Failed(format!(
            "grid-{side}: the measurement failed ({})",
            output.status
        )));
    }
    let text = String::from_utf8_lossy(&output.stdout);
    serde_json::from_str(text.trim()).map_err(|e| {
        AppError::Failed(format!(
            "grid-{side}: unreadable report from the measurement ({e})"
        ))
    })
}

/// Measures one size in this process (the child's side of
/// [`measure_in_child`]).
fn measure_one(side: usize, steps: usize, threads: usize) -> Result<SizeReport, AppError> {
    let name = format!("grid-{side}");
    let failed = |e: &dyn std::fmt::Display| AppError::Failed(format!("{name}: {e}"));
    let (mut simulation, precompute_s, step_s) = timed_simulation(&name, side, steps, threads)?;
    let peak_bytes = peak_resident_bytes();
    let threads = simulation.threads();
    let (step_s, step_one_thread_s) = step_times(&name, side, step_s, &mut simulation, steps)?;
    eprintln!("{name}: local step, Aᵀd");
    let (local_step_s, atd_s, springs_pass_s) = time_spring_passes(&simulation);
    let system = simulation.system().expect(FAST_PATH);
    let lower = system.q().triangle(Triangle::Lower);
    let symbolic = system.prefactorization.symbolic();
    let rows_kept = (0..symbolic.supernodes().len())
        .map(|s| symbolic.supernode_rows(s).len())
        .sum();
    drop(simulation);
    eprintln!("{name}: ordering, symbolic, numeric, solve");
    let rhs = benchmark_right_hand_side(lower.ncols());
    let how = HowFactored {
        ordering: Ordering::Amd,
        method: Method::Supernodal,
        relaxation: Relaxation::NONE, // as the simulation factors
        threads,
    };
    let a = analyze(&lower, &rhs, how, Repeats::Adaptive).map_err(|e| failed(&e))?;
    let iteration_s = step_s / ITERATIONS as f64;
    Ok(SizeReport {
        side,
        n: a.n,
        nnz_q: a.nnz_a,
        nnz_l: a.nnz_l,
        nnz_l_stored: a.nnz_l_stored,
        flops: a.flops,
        ordering_s: a.ordering_s,
        symbolic_s: a.symbolic_s,
        numeric_s: a.numeric_s,
        solve_s: a.solve_s,
        step_s,
        local_step_s,
        atd_s,
        springs_pass_s,
        solve_share: a.solve_s / iteration_s,
        local_step_share: local_step_s / iteration_s,
        atd_share: atd_s / iteration_s,
        springs_pass_share: springs_pass_s / iteration_s,
        precompute_s,
        peak_bytes,
        bytes_per_vertex: peak_bytes as f64 / a.n as f64,
        solve_gbps: solve_bytes(a.nnz_l_stored, rows_kept) / a.solve_s / 1e9,
        residual: a.residual,
        backward_error: a.backward_error,
        threads,
        numeric_one_thread_s: a.one_thread.map(|one| one.numeric_s),
        solve_one_thread_s: a.one_thread.map(|one| one.solve_s),
        step_one_thread_s,
    })
}

/// The median step on `simulation`'s threads (`step_s` when it has one)
/// and, when it has more, on one thread beside it: `(its threads', one
/// thread's)`.
fn step_times(
    name: &str,
    side: usize,
    step_s: f64,
    simulation: &mut Simulation<Sparse>,
    steps: usize,
) -> Result<(f64, Option<f64>), AppError> {
    if simulation.threads() == 1 {
        return Ok((step_s, None));
    }
    let [one, many] = steps_beside_one_thread(name, side, steps, simulation)?;
    Ok((many, Some(one)))
}

/// The median step of a fresh one-thread simulation of the same grid and
/// of `simulation`, in `steps` interleaved rounds: `[one thread, its
/// threads]`.
fn steps_beside_one_thread(
    name: &str,
    side: usize,
    steps: usize,
    simulation: &mut Simulation<Sparse>,
) -> Result<[f64; 2], AppError> {
    let failed = |e: &dyn std::fmt::Display| AppError::Failed(format!("{name}: {e}"));
    eprintln!(
        "{name}: {steps} steps on 1 thread and on {}, interleaved",
        simulation.threads()
    );
    let scene = procedural::grid(side).to_scene().map_err(|e| failed(&e))?;
    let options = SimulationOptions {
        threads: 1,
        ..SimulationOptions::default()
    };
    let mut alone = Simulation::<Sparse>::from_scene(&scene, options).map_err(|e| failed(&e))?;
    drop(scene);
    let (mut first_error, mut second_error) = (None, None);
    let ([one, many], _) = interleaved_medians(
        Repeats::Exactly(steps),
        || {
            if let Err(e) = alone.step() {
                first_error.get_or_insert(e);
            }
        },
        || {
            if let Err(e) = simulation.step() {
                second_error.get_or_insert(e);
            }
        },
    );
    match first_error.or(second_error) {
        Some(e) => Err(failed(&e)),
        None => Ok([one, many]),
    }
}

/// The grid `side`×`side` precomputed and stepped `steps` times: the
/// simulation, the precomputation's seconds and the median step's.
fn timed_simulation(
    name: &str,
    side: usize,
    steps: usize,
    threads: usize,
) -> Result<(Simulation<Sparse>, f64, f64), AppError> {
    let failed = |e: &dyn std::fmt::Display| AppError::Failed(format!("{name}: {e}"));
    eprintln!("{name}: scene");
    let scene = procedural::grid(side).to_scene().map_err(|e| failed(&e))?;
    eprintln!("{name}: precomputation (n = {})", scene.vertices.len());
    let started = Instant::now();
    let options = SimulationOptions {
        threads,
        ..SimulationOptions::default()
    };
    let mut simulation =
        Simulation::<Sparse>::from_scene(&scene, options).map_err(|e| failed(&e))?;
    let precompute_s = started.elapsed().as_secs_f64();
    drop(scene);
    eprintln!("{name}: {steps} steps");
    let mut step_error = None;
    let (step_s, _) = median_seconds(Repeats::Exactly(steps), || {
        if let Err(e) = simulation.step() {
            step_error.get_or_insert(e);
        }
    });
    if let Some(e) = step_error {
        return Err(failed(&e));
    }
    Ok((simulation, precompute_s, step_s))
}

/// The bench simulates on the fast path, which has a precomputed system.
const FAST_PATH: &str = "the bench runs the fast path";

/// Median times of the local step and of `Aᵀd` apart, and of the two in
/// one pass, on `simulation`'s springs at its current positions (after its
/// steps: a cloth in motion).
fn time_spring_passes(simulation: &Simulation<Sparse>) -> (f64, f64, f64) {
    let system = simulation.system().expect(FAST_PATH);
    let mut d = vec![[0.0; 3]; system.springs.len()];
    let mut atd = vec![[0.0; 3]; system.n()];
    let positions = simulation.positions();
    let (local_step_s, _) = median_seconds(Repeats::Adaptive, || {
        project_springs(&system.springs, &system.r, positions, &mut d)
    });
    let (atd_s, _) = median_seconds(Repeats::Adaptive, || {
        incidence_transpose_mul_points(&system.springs, &d, &mut atd)
    });
    let (springs_pass_s, _) = median_seconds(Repeats::Adaptive, || {
        project_springs_into_transpose(&system.springs, &system.r, positions, &mut atd)
    });
    (local_step_s, atd_s, springs_pass_s)
}

/// This process's peak resident set (`VmHWM`, Linux), in bytes; 0 where
/// it cannot be read.
fn peak_resident_bytes() -> u64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|line| line.strip_prefix("VmHWM:"))
        .and_then(|rest| rest.trim().strip_suffix("kB"))
        .and_then(|kb| kb.trim().parse::<u64>().ok())
        .map_or(0, |kb| kb * 1024)
}

/// STREAM's triad `a = b + s c` over three arrays of 32 MB (far beyond the
/// caches), best of 10 runs, in 10⁹ bytes per second (24 bytes moved per
/// element: two reads, one write).
fn triad_gbps() -> f64 {
    const LEN: usize = 1 << 22;
    let b: Vec<f64> = (0..LEN).map(|i| i as f64).collect();
    let c: Vec<f64> = (0..LEN).map(|i| 0.5 * i as f64).collect();
    let mut a = vec![0.0; LEN];
    let s = std::hint::black_box(3.0);
    let mut best = f64::INFINITY;
    for _ in 0..10 {
        let t = Instant::now();
        for ((a, &b), &c) in a.iter_mut().zip(&b).zip(&c) {
            *a = b + s * c;
        }
        std::hint::black_box(&mut a);
        best = best.min(t.elapsed().as_secs_f64());
    }
    24.0 * LEN as f64 / best / 1e9
}

/// Least-squares slope of `ln y` against `ln n` over the sizes where
/// `y > 0`; `None` with fewer than two distinct `n`.
fn log_log_slope(points: impl Iterator<Item = (f64, f64)>) -> Option<f64> {
    let logs: Vec<(f64, f64)> = points
        .filter(|&(n, y)| n > 0.0 && y > 0.0)
        .map(|(n, y)| (n.ln(), y.ln()))
        .collect();
    let count = logs.len() as f64;
    let mean_x = logs.iter().map(|p| p.0).sum::<f64>() / count;
    let mean_y = logs.iter().map(|p| p.1).sum::<f64>() / count;
    let sxx: f64 = logs.iter().map(|p| (p.0 - mean_x).powi(2)).sum();
    let sxy: f64 = logs.iter().map(|p| (p.0 - mean_x) * (p.1 - mean_y)).sum();
    (logs.len() >= 2 && sxx > 0.0).then(|| sxy / sxx)
}

fn fit_slopes(sizes: &[SizeReport]) -> Slopes {
    let slope =
        |cost: fn(&SizeReport) -> f64| log_log_slope(sizes.iter().map(|s| (s.n as f64, cost(s))));
    Slopes {
        ordering_s: slope(|s| s.ordering_s),
        symbolic_s: slope(|s| s.symbolic_s),
        numeric_s: slope(|s| s.numeric_s),
        solve_s: slope(|s| s.solve_s),
        step_s: slope(|s| s.step_s),
        peak_bytes: slope(|s| s.peak_bytes as f64),
    }
}

/// The sizes as CSV, one row each, the keys of `--json` as the header.
fn write_csv(out: &mut dyn Write, sizes: &[SizeReport]) -> std::io::Result<()> {
    writeln!(
        out,
        "side,n,nnz_q,nnz_l,nnz_l_stored,flops,ordering_s,symbolic_s,numeric_s,solve_s,step_s,\
         local_step_s,atd_s,springs_pass_s,solve_share,local_step_share,atd_share,\
         springs_pass_share,\
         precompute_s,peak_bytes,bytes_per_vertex,solve_gbps,residual,backward_error,\
         threads,numeric_one_thread_s,solve_one_thread_s,step_one_thread_s"
    )?;
    let maybe = |v: Option<f64>| v.map_or(String::new(), |v| v.to_string());
    for s in sizes {
        writeln!(
            out,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            s.side,
            s.n,
            s.nnz_q,
            s.nnz_l,
            s.nnz_l_stored,
            s.flops,
            s.ordering_s,
            s.symbolic_s,
            s.numeric_s,
            s.solve_s,
            s.step_s,
            s.local_step_s,
            s.atd_s,
            s.springs_pass_s,
            s.solve_share,
            s.local_step_share,
            s.atd_share,
            s.springs_pass_share,
            s.precompute_s,
            s.peak_bytes,
            s.bytes_per_vertex,
            s.solve_gbps,
            s.residual,
            s.backward_error,
            s.threads,
            maybe(s.numeric_one_thread_s),
            maybe(s.solve_one_thread_s),
            maybe(s.step_one_thread_s)
        )?;
    }
    Ok(())
}

fn print_table(report: &BenchReport) {
    println!(
        "{:>9} {:>11} {:>12} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>8} {:>7}",
        "grid",
        "n",
        "nnz(L)",
        "order ms",
        "symbol ms",
        "numeric ms",
        "solve ms",
        "step ms",
        "peak MB",
        "B/vertex",
        "solve GB/s"
    );
    for s in &report.sizes {
        println!(
            "{:>9} {:>11} {:>12} {:>10.3} {:>10.3} {:>10.3} {:>10.3} {:>10.1} {:>10.1} {:>8.0} {:>7.1}",
            format!("grid-{}", s.side),
            s.n,
            s.nnz_l,
            1e3 * s.ordering_s,
            1e3 * s.symbolic_s,
            1e3 * s.numeric_s,
            1e3 * s.solve_s,
            1e3 * s.step_s,
            s.peak_bytes as f64 / 1e6,
            s.bytes_per_vertex,
            s.solve_gbps
        );
    }
    let show = |slope: Option<f64>| slope.map_or("-".to_string(), |p| format!("{p:.2}"));
    let slopes = &report.slopes;
    println!(
        "{:>9} {:>11} {:>12} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}",
        "slope",
        "",
        "",
        show(slopes.ordering_s),
        show(slopes.symbolic_s),
        show(slopes.numeric_s),
        show(slopes.solve_s),
        show(slopes.step_s),
        show(slopes.peak_bytes)
    );
    println!(
        "(cost ≈ c·nᵖ, p fitted by least squares on logs; medians; {} steps per size; \
         triad bandwidth {:.1} GB/s)",
        report.steps, report.triad_gbps
    );
    print_iteration_shares(report);
    print_speedups(report);
}

/// The threads, and with more than one the times on one thread beside
/// theirs and the speedups (one thread's time over theirs).
fn print_speedups(report: &BenchReport) {
    let Some(threads) = report.sizes.first().map(|s| s.threads) else {
        return;
    };
    if report.sizes.iter().all(|s| s.step_one_thread_s.is_none()) {
        println!("\nthreads: {threads}");
        return;
    }
    println!(
        "\n{:>9} {:>7} {:>26} {:>26} {:>26}",
        "grid", "threads", "numeric ms: 1t, Nt (×)", "solve ms: 1t, Nt (×)", "step ms: 1t, Nt (×)"
    );
    let cell = |one: Option<f64>, many: f64| match one {
        Some(one) => format!("{:.3}, {:.3} ({:.2}×)", 1e3 * one, 1e3 * many, one / many),
        None => "-".to_string(),
    };
    for s in &report.sizes {
        println!(
            "{:>9} {:>7} {:>26} {:>26} {:>26}",
            format!("grid-{}", s.side),
            s.threads,
            cell(s.numeric_one_thread_s, s.numeric_s),
            cell(s.solve_one_thread_s, s.solve_s),
            cell(s.step_one_thread_s, s.step_s),
        );
    }
    println!("(one thread and N in interleaved rounds; the same bits on both)");
}

/// One iteration (`step / 50`) and the shares of its solve and its pass
/// over the springs (the local step with `Aᵀd`), then those of the
/// textbook's two passes apart.
fn print_iteration_shares(report: &BenchReport) {
    println!(
        "\n{:>9} {:>13} {:>16} {:>16} {:>7} {:>16} {:>16}",
        "grid",
        "iteration ms",
        "solve ms (%)",
        "springs ms (%)",
        "rest %",
        "apart: local",
        "apart: Aᵀd"
    );
    let cell = |seconds: f64, share: f64| format!("{:.3} ({:.0}%)", 1e3 * seconds, 1e2 * share);
    for s in &report.sizes {
        let rest = 1.0 - s.solve_share - s.springs_pass_share;
        println!(
            "{:>9} {:>13.3} {:>16} {:>16} {:>6.0}% {:>16} {:>16}",
            format!("grid-{}", s.side),
            1e3 * s.step_s / ITERATIONS as f64,
            cell(s.solve_s, s.solve_share),
            cell(s.springs_pass_s, s.springs_pass_share),
            1e2 * rest,
            cell(s.local_step_s, s.local_step_share),
            cell(s.atd_s, s.atd_share),
        );
    }
}
