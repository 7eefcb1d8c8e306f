//! `DIR/README.md`: what each file of a trace holds and how a student
//! compares their own, written from the table of
//! [`quantities`](super::quantities) and the values of this trace (their
//! shapes and sizes).

use super::compute::Value;
use super::folder::README_START;
use super::manifest::Manifest;
use super::quantities::{Check, Quantity, SPECS};
use masssprings::sim::mistakes::{Mistake, Part};
use std::fmt::Write;

/// The README of a trace.
pub fn readme(manifest: &Manifest, values: &[(Quantity, Value)]) -> String {
    let mut text = String::new();
    header(&mut text, manifest);
    if let Some(mistake) = manifest.mistake.as_deref().and_then(Mistake::from_name) {
        let _ = write!(
            text,
            "**These files hold a mistake on purpose** (`--mistake {mistake}`: `{wrong}` \
             where the handout has `{right}`): the precomputation and step K are a student's \
             who made it, from our `U_prev` and `U_cur`. Trace the scene without `--mistake` \
             and `--compare` the two folders to see which quantity the mistake makes wrong \
             first.\n\n",
            wrong = mistake.wrong(),
            right = mistake.right(),
        );
    }
    gallery(&mut text);
    table(&mut text, values);
    tolerances(&mut text);
    what_a_step_shows(&mut text, manifest);
    how_to_compare(&mut text, manifest);
    text
}

/// Where a student whose cloth misbehaves looks first.
fn gallery(text: &mut String) {
    text.push_str(
        "**Does your cloth sag, explode, fly away or stand still?** Look for its symptom \
         first in the gallery of common mistakes, `docs/mistakes.md` in the masssprings \
         repository: each mistake is drawn beside the handout's step, with the quantity \
         `--compare` finds wrong first for it (`masssprings render SCENE.json --mistake \
         NAME -o OUT.gif` draws one; `masssprings trace SCENE.json --mistake NAME --step 3 \
         -o DIR` writes its files). The handout's own slips, and what following each one \
         does, are listed in `docs/equations.md`.\n\n",
    );
}

fn header(text: &mut String, m: &Manifest) {
    let _ = write!(
        text,
        "{README_START}{scene}, step {step}\n\n\
         Written by `masssprings trace {scene} --step {step} --iterations {iterations} \
         --ordering {ordering}{mistake} -o DIR`: the handout's precomputation and step \
         (`sim::textbook`), run exactly in the handout's order. The state of step {step} \
         comes from {before} handout step(s) from rest (`U_prev = U_cur = V`) under gravity \
         `f_ext = (0, −9.8, 0)` at every vertex; then `p = U_cur` and each iteration computes \
         `d` (local step), `b`, and `p = Q⁻¹ b`. The files `d_k`, `b_k`, `p_k` are those of \
         iteration `k` of step {step}; `p_{iterations}` is what the handout's step returns \
         with {iterations} iteration(s) instead of 50.\n\n\
         n = {n} vertices, m = {springs} springs, |b| = {pins} pinned vertices, \
         Δt = 1/30, w = 1e10.\n\n\
         Every file is Matrix Market, 1-based, 17 significant digits: sparse matrices as \
         `coordinate real general` (every entry, both triangles of `Q`), dense ones as \
         `array real general` (column by column). Rows and columns are in the handout's \
         order: vertices as the rows of `V` (the OBJ's `v` lines), springs as the rows of `E` \
         (libigl's `edges` order), pins as the scene's list `b`; `P` and `L` are in the \
         factor's order (`L Lᵀ = P Q Pᵀ`). The handout leaves the order of the springs and the \
         orientation of each to you: yours may differ from ours, and `--compare` matches them \
         by their two vertices.\n\n",
        scene = m.scene,
        step = m.step,
        iterations = m.iterations,
        ordering = m.ordering,
        mistake = m
            .mistake
            .as_ref()
            .map_or(String::new(), |m| format!(" --mistake {m}")),
        before = m.step - 1,
        n = m.vertices,
        springs = m.springs,
        pins = m.pins,
    );
}

/// One row per file, in the handout's order.
fn table(text: &mut String, values: &[(Quantity, Value)]) {
    text.push_str(
        "| file | symbol | equation | shape | computed by | compare |\n|---|---|---|---|---|---|\n",
    );
    for (quantity, value) in values {
        let spec = quantity.spec;
        let size = match value {
            Value::Sparse(a) => format!("{} × {}, {} entries", a.nrows(), a.ncols(), a.nnz()),
            Value::Dense(a) => format!("{} × {}", a.nrows(), a.ncols()),
        };
        let _ = writeln!(
            text,
            "| `{}` | `{}` | {} | {} ({}) | `{}` | {} |",
            quantity.file_name(),
            quantity.name(),
            spec.equation,
            size,
            spec.shape,
            spec.function,
            rule(spec.check),
        );
    }
    text.push('\n');
}

/// The comparison rule of a check, in a few words.
fn rule(check: Check) -> String {
    match check {
        Check::Incidence => "the same springs, in any order and orientation".into(),
        Check::Entries { tolerance: 0.0 } => "exactly".into(),
        Check::Entries { tolerance } => format!("entries, {tolerance:e} relative"),
        Check::Ordering => "any permutation (reported)".into(),
        Check::Factor { tolerance } => format!("L Lᵀ = P Q Pᵀ, {tolerance:e} relative"),
        Check::Sum { tolerance } => format!("entries, {tolerance:e} of their terms"),
    }
}

/// Why each tolerance, and which quantities are unique.
fn tolerances(text: &mut String) {
    text.push_str(
        "## Tolerances, and which quantities are unique\n\n\
         An entry agrees when `|ours − yours| ≤ tolerance · s`, with `s` the largest of \
         `|ours|`, `|yours|` and the largest `|ours|` in its row (so a zero next to large \
         entries is held to its row's scale, and a row of pins to its `w = 1e10`).\n\n",
    );
    for spec in &SPECS {
        let _ = writeln!(
            text,
            "* `{}` ({}): {}.",
            spec.symbol,
            rule(spec.check),
            spec.why
        );
    }
    text.push_str(
        "\nEverything but `P` and `L` is unique: it follows from the scene, the step and the \
         iteration alone, so a correct solution matches it whatever its ordering or solver. \
         `L` is unique once `P` is chosen, but a different ordering (Eigen's AMD is not \
         ours) gives different entries, so `L` is checked through `L Lᵀ = P Q Pᵀ` with your \
         `P`; `p` does not depend on the ordering (only its last bits do).\n\n",
    );
}

/// A row of the table of what each step shows: the mistake, the first
/// file it makes wrong, and whether steps 1, 2 and 3 show it (from the
/// gallery's entry, which `tests/sim/mistakes.rs` holds to the program).
fn step_row(mistake: Mistake) -> String {
    let entry = mistake.entry();
    let (from, why) = entry.shows_from;
    let at = |step: usize| match (step >= from, step) {
        (true, _) => "shows".to_string(),
        (false, 1) => format!("cannot: {why}"),
        (false, _) => format!("cannot: {why} still"),
    };
    let first = match entry.part {
        Part::Loop => format!("`{}` (written by your own steps from rest)", entry.first),
        _ => format!("`{}`", entry.first),
    };
    format!(
        "| `{}`: `{}` | {first} | {} | {} | {} |",
        entry.name,
        entry.wrong,
        at(1),
        at(2),
        at(3)
    )
}

/// Which mistakes each step can and cannot show, and why `trace` traces
/// step 3 unless told otherwise.
fn what_a_step_shows(text: &mut String, m: &Manifest) {
    text.push_str(
        "## What this step can and cannot show\n\n\
         Every term of the step shows in the files only when it changes something. At step 1 \
         `U_prev = U_cur = V` and every spring is at its rest length, so a step that swaps \
         `U_prev` and `U_cur`, rest lengths measured on `U_cur` or a loop that loses the \
         velocity give the same files as the handout's. At step 2 `U_prev` is still `V`. \
         Step 3 is the first at which \
         `V`, `U_prev` and `U_cur` all differ and the springs are stretched, which is why \
         `trace` traces it unless `--step` says otherwise; it is also early enough that two \
         correct solutions started from rest still agree to the tolerances above.\n\n\
         The mistakes of the gallery (`docs/mistakes.md` in the masssprings repository):\n\n\
         | mistake | first file it makes wrong (from our `U_prev`, `U_cur`) | step 1 | step 2 | step 3 and later |\n\
         |---|---|---|---|---|\n",
    );
    for mistake in Mistake::ALL {
        let _ = writeln!(text, "{}", step_row(mistake));
    }
    let hidden: Vec<String> = Mistake::ALL
        .iter()
        .filter(|mistake| mistake.entry().shows_from.0 > m.step)
        .map(|mistake| format!("`{mistake}`"))
        .collect();
    let warning = match hidden.is_empty() {
        true => String::new(),
        false => format!(": {} pass unseen here; trace step 3 too", hidden.join(", ")),
    };
    let _ = writeln!(text, "\nThis trace is of step {}{warning}.\n", m.step);
}

fn how_to_compare(text: &mut String, m: &Manifest) {
    let _ = write!(
        text,
        "## Comparing your own solution\n\n\
         Write your quantities of the same scene, step and iteration into a folder, with \
         these names and shapes (any subset), then:\n\n\
         ```sh\n\
         masssprings trace --compare DIR YOURS\n\
         ```\n\n\
         It goes through the quantities in the order above and prints, for each, whether it \
         agrees, its largest difference relative to the scale it names, and where: the \
         vertex, spring or pin counted from 0 as in the handout and Eigen (your spring and ours \
         beside it when your order differs), with the file's row and column counted from 1. \
         The first `DIFFERS` line is the first piece of code to look at, and the `diagnosis:` \
         line says what went wrong there: it computes that quantity again from your own \
         inputs (your files, else ours), by the handout's line and by each mistake of the \
         gallery, and names the mistake that gives your numbers, with its line as written and \
         as it should be; when none does, the nearest thing it can prove (a sign, a factor \
         such as `k` or `Δt`, a swapped pair, a transposed matrix). The exit code is 1 when \
         any quantity differs; `--json` prints one JSON object instead of the table.\n\n\
         Compare twice, in this order:\n\n\
         1. **Your own run from rest**, as your program runs it: the files of step {step} \
         written from the `U_prev` and `U_cur` your own loop over steps reached. This is the \
         comparison that exercises the loop: one that loses the velocity (`U_cur = U_next; \
         U_prev = U_cur`) makes every step right from a wrong state. Where your state differs \
         from ours, the diagnosis says whether the loop did it (your `U_prev` equal to your \
         `U_cur`), and computes your step again from your own state, where a mistake of the \
         step is named as well.\n\
         2. **Your step from our state**: step {step} started from our `U_prev.mtx` and \
         `U_cur.mtx`. Two correct solutions drift apart by their rounding from step to step, \
         slowly on the flag and within a few steps on the skirt, whose buckling turns rounding \
         into centimetres; from the same state, `y`, `d`, `b` and `p` agree to the tolerances \
         above, and the first `DIFFERS` line is the line of your step to fix.\n\n",
        step = m.step,
    );
    writing_your_files(text, m);
}

/// How a student writes their files: from the assignment's C++ with the
/// header of `--cpp-header`, by hand with Eigen, or from Python.
fn writing_your_files(text: &mut String, m: &Manifest) {
    let _ = write!(
        text,
        "## Writing your files\n\n\
         **From the assignment's C++ starter code**, `masssprings trace --cpp-header > \
         include/masssprings_trace.h` writes a header (Eigen only) that writes these files, \
         17 significant digits, with one line per quantity where your code computes it:\n\n\
         ```cpp\n\
         #include \"masssprings_trace.h\"\n\
         // fast_mass_springs_precomputation_sparse, after each is made:\n\
         masssprings_trace::write(\"r\", r);  masssprings_trace::write(\"M\", M);\n\
         masssprings_trace::write(\"A\", A);  masssprings_trace::write(\"C\", C);\n\
         masssprings_trace::write(\"Q\", Q);\n\
         masssprings_trace::write_factor(prefactorization);  // after compute(Q): P and L\n\
         // fast_mass_springs_step_sparse:\n\
         masssprings_trace::start_step(Uprev, Ucur);         // its first line\n\
         masssprings_trace::write(\"y\", y);\n\
         // in each iteration:\n\
         masssprings_trace::write(\"d\", d);  masssprings_trace::write(\"b\", b);  masssprings_trace::write(\"p\", p);\n\
         ```\n\n\
         ```sh\n\
         MASSSPRINGS_TRACE_DIR=mine MASSSPRINGS_TRACE_STEP={step} MASSSPRINGS_TRACE_ITERATIONS={iterations} \
         ./masssprings_sparse ../data/flag.json\n\
         ```\n\n\
         writes your own run's step {step} into `mine` (the first comparison above); \
         `MASSSPRINGS_TRACE_FRAMES=frames` writes every step's positions as OBJ frames too. For \
         the second, move the `start_step` line to `main.cpp`'s step, before `const \
         Eigen::MatrixXd U_stash = U;`, as `masssprings_trace::start_step(Uprev, U);`, and \
         set `MASSSPRINGS_TRACE_FROM=DIR`: the traced step then starts from our `U_prev.mtx` \
         and `U_cur.mtx`. The dense code is written the same way (`Eigen::MatrixXd`, \
         `Eigen::LLT`); trace a small scene for it, since an n × n array of this scene \
         holds {n2} values.\n\n\
         **By hand with Eigen** (`#include <unsupported/Eigen/SparseExtra>`): \
         `Eigen::saveMarket(A, \"A.mtx\")` for a sparse matrix, \
         `Eigen::saveMarketVector(r, \"r.mtx\")` for a vector; Eigen 3.4 has no writer for a \
         dense matrix: write the line `%%MatrixMarket matrix array real general`, then \
         `rows cols`, then the values column by column with `std::setprecision(17)`. `P` of \
         `Eigen::SimplicialLLT` is the triplets `(P.indices()(i), i, 1)` of \
         `permutationP()`, and `L` is `Eigen::SparseMatrix<double> L = \
         prefactorization.matrixL();`.\n\n\
         **From Python**: `scipy.io.mmread(\"A.mtx\")` gives a sparse matrix for a coordinate \
         file and an array for an array file, with the shapes of the table; \
         `scipy.io.mmwrite` writes files `--compare` reads. In MATLAB, `mmread.m` from the \
         Matrix Market site reads both.\n",
        step = m.step,
        iterations = m.iterations,
        n2 = m.vertices * m.vertices,
    );
}
