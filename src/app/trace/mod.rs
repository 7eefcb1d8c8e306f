//! `masssprings trace SCENE.json [--step K] [--iterations N] -o DIR`:
//! every quantity of the handout on a scene, one Matrix Market file each,
//! so that a student can compare their own `A`, `r`, `M`, `C`, `Q`, `L`,
//! `y`, `d`, `b`, `p` with ours; and `masssprings trace --compare DIR
//! OTHER`, which does that comparison and names the first quantity that
//! differs.
//!
//! | file | what |
//! |---|---|
//! | [`quantities`] | the table: each file's symbol, equation, shape, function and check |
//! | [`compute`] | the quantities, by the handout's functions in the handout's order |
//! | [`readme`] | `DIR/README.md`, from the table |
//! | [`compare`] | `--compare`: quantity by quantity, the largest difference and where, and the diagnosis |
//! | [`mistaken`] | `--mistake`: the files of a student who made one of the gallery's mistakes |
//! | `masssprings_trace.h` | `--cpp-header`: the C++ header that writes a student's files from the starter code |
//!
//! Sparse matrices are written as `coordinate real general` files, dense
//! ones as `array real general` (column-major), 17 significant digits, both
//! 1-based in the handout's row and column order (`P` and `L`: the factor's
//! order), so Eigen's `loadMarket`, MATLAB's `mmread` and
//! `scipy.io.mmread` read them as they are. `DIR/trace.json` records the
//! scene, step, iterations, ordering and files for `--compare`.

mod compare;
mod compute;
mod folder;
mod manifest;
mod mistaken;
mod quantities;
mod readme;

use super::error::AppError;
use super::file_plan::load_scene;
use super::flags::{choice, whole, JsonFlag, OrderingFlag};
use compute::{labelled, trace, TraceOptions, Value};
use folder::TraceFolder;
use manifest::{Manifest, MANIFEST};
use masssprings::files::{fingerprint, shown};
use masssprings::matrix_market::{write_array, write_coordinate, Symmetry};
use masssprings::mesh::Scene;
use masssprings::sim::mistakes::Mistake;
use masssprings::sim::ITERATIONS;
use quantities::Quantity;
use std::path::{Path, PathBuf};

/// Write every quantity of the handout, to check a solution against.
#[derive(clap::Args, Debug)]
#[command(after_help = "\
Runs the handout's precomputation and step (sim::textbook) on the scene and
writes A, r, M, C, Q, P, L, and for step K: U_prev, U_cur, y, and each of the
first N iterations' d, b and p, one Matrix Market file each (17 significant
digits), with DIR/README.md saying what each holds and how to compare.

With --compare DIR OTHER, compares the files of OTHER (same names and formats,
any subset: yours) with those of DIR (written by trace), in the handout's
order, and exits with 1 when one differs: the first DIFFERS line is the first
quantity to fix, and the diagnosis says what went wrong there (the usual
mistake whose numbers yours are, or the nearest sign, factor, swap or
transpose that holds). With --json, one JSON object instead of the table.

With --mistake NAME, writes instead the files of a student who made one of the
usual mistakes (docs/mistakes.md), from our U_prev and U_cur of step K: trace
the scene into DIR as well, and --compare DIR names the quantity that mistake
makes wrong first. Use a step K of 2 or more: at step 1, U_prev = U_cur hides
some of them.

With --cpp-header, prints masssprings_trace.h: included in the assignment's C++
starter code, one line per quantity writes your files for --compare (its first
lines say where each goes and the environment variables it reads).")]
pub struct TraceArgs {
    /// The scene: JSON that names an OBJ (data/README.md).
    #[arg(value_name = "SCENE.json", required_unless_present_any = ["compare", "cpp_header"])]
    scene: Option<PathBuf>,
    /// The folder to write.
    #[arg(short, long, value_name = "DIR", required_unless_present_any = ["compare", "cpp_header"])]
    out: Option<PathBuf>,
    /// The step to trace, from 1 (3: the first whose U_prev, U_cur and V all
    /// differ, so that no term of the step hides; DIR/README.md says why).
    #[arg(long, value_name = "K", default_value = "3", value_parser = whole(1, usize::MAX))]
    step: usize,
    /// Iterations of step K to write, 1 to 50.
    #[arg(long, value_name = "N", default_value = "2", value_parser = whole(1, ITERATIONS))]
    iterations: usize,
    #[command(flatten)]
    ordering: OrderingFlag,
    /// Write into DIR even though it holds files trace did not write, replacing those of trace's names.
    #[arg(long, conflicts_with = "compare")]
    force: bool,
    /// Write what a student with one of the usual mistakes writes, from our state at step K, to --compare with a trace (docs/mistakes.md).
    #[arg(long, value_name = "NAME", value_parser = choice::<Mistake>(&Mistake::ALL.map(Mistake::name)))]
    mistake: Option<Mistake>,
    /// Compare OTHER's files with DIR's (instead of tracing a scene).
    #[arg(long, num_args = 2, value_names = ["DIR", "OTHER"], conflicts_with_all = ["scene", "out", "step", "iterations", "ordering", "mistake"])]
    compare: Option<Vec<PathBuf>>,
    #[command(flatten)]
    json: JsonFlag,
    /// Print a C++ header (Eigen only) that writes your own files for --compare from the assignment's starter code, one line per quantity.
    #[arg(long, conflicts_with_all = ["scene", "out", "step", "iterations", "ordering", "mistake", "compare", "force"])]
    cpp_header: bool,
}

/// The header `--cpp-header` prints.
const CPP_HEADER: &str = include_str!("masssprings_trace.h");

pub fn run(args: TraceArgs) -> Result<(), AppError> {
    if args.cpp_header {
        print!("{CPP_HEADER}");
        return Ok(());
    }
    if let Some([ours, theirs]) = args.compare.as_deref() {
        return compare::run(ours, theirs, args.json.json);
    }
    if args.json.json {
        return Err(AppError::Usage(
            "--json prints the report of --compare DIR OTHER as JSON; give --compare".into(),
        ));
    }
    let (Some(scene_path), Some(out)) = (args.scene, args.out) else {
        unreachable!("clap requires SCENE.json and -o without --compare");
    };
    let options = TraceOptions {
        step: args.step,
        iterations: args.iterations,
        ordering: args.ordering.ordering,
        mistake: args.mistake,
    };
    let scene = load_scene(&scene_path)?;
    let how = (args.force, options.mistake);
    let mut folder = TraceFolder::open(&out, &scene_path, &scene, how)?;
    let start = std::time::Instant::now();
    let values = match options.mistake {
        Some(mistake) => mistaken::trace(&scene, options, mistake)?,
        None => trace(&scene, options)?,
    };
    let values = labelled(values, options.iterations);
    let manifest = manifest(&scene_path, &scene, options, &values);
    write_all(&mut folder, &scene_path, &values, &manifest)?;
    folder.commit()?;
    println!(
        "{}: {} files of {}{} (n = {}, m = {}), step {}, {} iteration(s), {} ordering, in {:.2} s",
        shown(&out),
        values.len(),
        shown(&scene_path),
        options
            .mistake
            .map_or(String::new(), |m| format!(" with the mistake {m}")),
        scene.vertices.len(),
        scene.springs.len(),
        options.step,
        options.iterations,
        options.ordering.name(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

fn manifest(
    scene_path: &Path,
    scene: &Scene,
    options: TraceOptions,
    values: &[(Quantity, Value)],
) -> Manifest {
    let mut manifest = Manifest {
        scene: scene_path.display().to_string(),
        step: options.step,
        iterations: options.iterations,
        ordering: options.ordering.name().to_string(),
        vertices: scene.vertices.len(),
        springs: scene.springs.len(),
        pins: scene.pinned.len(),
        k: scene.k,
        files: values.iter().map(|(q, _)| q.file_name()).collect(),
        mistake: options.mistake.map(|m| m.name().to_string()),
        trace: None,
    };
    manifest.trace = Some(trace_fingerprint(&manifest, values));
    manifest
}

/// The fingerprint of a trace: of its manifest's fields and of every
/// value's shape and entries (so two traces of the same scene, step,
/// iterations and ordering have the same one, and a mixture of two such
/// loses nothing).
fn trace_fingerprint(manifest: &Manifest, values: &[(Quantity, Value)]) -> String {
    let fields = serde_json::to_string(manifest).expect("plain values serialise");
    let mut words: Vec<u64> = fields.bytes().map(u64::from).collect();
    for (_, value) in values {
        match value {
            Value::Sparse(matrix) => {
                words.extend([matrix.nrows(), matrix.ncols()].map(|n| n as u64));
                words.extend(matrix.col_ptr().iter().map(|&p| p as u64));
                for j in 0..matrix.ncols() {
                    let (rows, entries) = matrix.column(j);
                    words.extend(rows.iter().map(|&i| i as u64));
                    words.extend(entries.iter().map(|x| x.to_bits()));
                }
            }
            Value::Dense(matrix) => {
                words.extend([matrix.nrows(), matrix.ncols()].map(|n| n as u64));
                words.extend(matrix.as_slice().iter().map(|x| x.to_bits()));
            }
        }
    }
    fingerprint(words)
}

/// Every quantity's file, then the README and the manifest (last: a
/// folder with a manifest holds a complete trace), each staged in
/// `folder` until [`TraceFolder::commit`].
fn write_all(
    folder: &mut TraceFolder,
    scene_path: &Path,
    values: &[(Quantity, Value)],
    manifest: &Manifest,
) -> Result<(), AppError> {
    let id = manifest.trace.as_deref().unwrap_or_default();
    for (quantity, value) in values {
        let comment = format!(
            "{}: {} ({}) of {}, step {}\n{}, trace {id}; see README.md",
            quantity.name(),
            quantity.spec.equation,
            quantity.spec.shape,
            shown(scene_path),
            manifest.step,
            folder::WRITTEN_BY,
        );
        folder.write(&quantity.file_name(), |file| match value {
            Value::Sparse(matrix) => write_coordinate(file, matrix, Symmetry::General, &comment),
            Value::Dense(matrix) => write_array(file, matrix, &comment),
        })?;
    }
    let text = readme::readme(manifest, values);
    folder.write("README.md", |file| file.write_all(text.as_bytes()))?;
    let json = serde_json::to_string_pretty(manifest).expect("plain values serialise");
    folder.write(MANIFEST, |file| writeln!(file, "{json}"))?;
    Ok(())
}
