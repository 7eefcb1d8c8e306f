//! The application layer: the command line. Thin by design: it parses
//! arguments, reads and writes files, times things, and calls the library.

mod analyze;
mod args;
mod bench;
mod converge;
mod convergence_flags;
mod convergence_plot;
mod etree;
mod export_q;
mod factorization_flags;
mod generate;
mod render;
mod simulate;
mod spy;
mod timing;
mod view;

/// What went wrong, and whether it was the way the program was called.
#[derive(Debug)]
pub enum AppError {
    /// Wrong arguments: exit code 2, with a hint to see the usage.
    Usage(String),
    /// Bad input or a failure while working: exit code 1.
    Failed(String),
}

impl<E: std::error::Error> From<E> for AppError {
    fn from(error: E) -> Self {
        AppError::Failed(error.to_string())
    }
}

const USAGE: &str = "\
usage: masssprings <command> [options]

commands:
  analyze MATRIX.mtx [--ordering amd|natural] [--method supernodal|simplicial]
                     [--relax cholmod|none] [--repeats N] [--json]
      Sparse Cholesky of a symmetric positive definite Matrix Market matrix:
      n, nnz, nnz(L), flops, median times of ordering, symbolic analysis,
      numeric factorization and a 3-column solve, and the relative residual.
      The right-hand side is MATRIX.b.mtx (an n×3 array) when it exists.
      --relax cholmod merges supernodes by CHOLMOD's rule (relaxed
      supernodes, storing some zeros) before the supernodal factorization;
      the default, none, keeps the fundamental supernodes.
  bench [--sizes 32,100,316] [--steps S] [--csv OUT.csv] [--plot OUT.png]
        [--json]
      Scaling benchmark on the grid-N cloths (built in memory), each size in
      a fresh process: n, nnz(Q), nnz(L), flops, median times of ordering,
      symbolic analysis, numeric factorization, a 3-column solve and a full
      step (S steps, default 3), peak memory (VmHWM), the solve's bandwidth
      beside a measured triad bandwidth, and the log-log slope of each cost;
      --plot draws them (time and memory against n, log-log).
      Default sizes 32,100,316 (about a minute); 1000, 2000, 3162 on request.
  export-q SCENE.json -o Q.mtx
      Writes the scene's Q = k AᵀA + M/Δt² + w CᵀC, as the simulation
      builds it, as a Matrix Market file (lower triangle) for analyze.
  generate grid N [--out DIR]
      Writes DIR/grid-N.json and .obj (DIR defaults to .): the N×N cloth of
      the benchmarks, the same bytes as the reference tool's `ref grid N`.
  generate examples [--out DIR]
      Writes the five teaching scenes (single-spring-horizontal,
      horizontal-chain, net, flag, skirt) and their PNG textures.
  simulate SCENE.json [--dense] [--steps N] [--every K] [--out DIR] [--wind]
                      [--ordering amd|natural]
                      [--factorization supernodal|simplicial] [--json]
      Runs the simulation (sparse unless --dense) for N steps (default 100).
      The sparse Q is ordered by AMD and factored by supernodes unless
      --ordering/--factorization say otherwise; `--ordering natural
      --factorization simplicial` runs the textbook code end to end.
      With --out, writes DIR/frame-NNNNNN.obj for step 0 and every K-th step.
      Ends with n, springs, precomputation time and the median step time.
  render SCENE.json -o OUT.gif|OUT.png [--steps N] [--every K] [--size WxH]
                    [--dense] [--wind] [--springs]
      Simulates N steps (default 100) and draws step 0 and every K-th step
      (default 2) with the viewer's look into a looping GIF that plays in
      real time, or draws the last step into a PNG. Size default 480x360.
      Cloths show their surface and pins; --springs adds every spring and
      point mass (always drawn for scenes made only of springs).
  view SCENE.json [--port P] [--address ADDR] [--dense]
                  [--ordering amd|natural]
                  [--factorization supernodal|simplicial]
      Serves an interactive viewer on http://127.0.0.1:P/ (P defaults to
      8080, 0 picks a free port; --address serves on another address) and
      prints its URL. The simulation runs here in real time; the page draws
      it with WebGL. Keys: space step, A animate, L springs, R reset,
      W wind; drag to orbit, wheel to zoom, shift-drag to pull a vertex.
      Ctrl-C stops it.
  spy MATRIX.mtx|SCENE.json -o OUT.png [--ordering amd|natural] [--factor]
                            [--size S]
      Draws the pattern of Q (a scene's, or a Matrix Market matrix's lower
      triangle mirrored) in the order the factorization uses (AMD unless
      --ordering natural), or with --factor that of its Cholesky factor L,
      fill-in in orange; S pixels a side (default 480). Prints n, nnz and
      the fill nnz(L)/nnz(tril Q).
  etree MATRIX.mtx|SCENE.json -o OUT.png [--ordering amd|natural]
                              [--size WxH]
      Draws the elimination tree of Q in the same order, each supernode in
      its own colour (default 720x360; at most 4096 columns). Prints the
      tree's height and the number of supernodes.
  help
      This text.
";

/// Runs the command line `args` (without the program name); returns the
/// exit code.
pub fn run(args: &[String]) -> i32 {
    let result = match args.first().map(String::as_str) {
        Some("analyze") => analyze::run(&args[1..]),
        Some("bench") => bench::run(&args[1..]),
        Some("export-q") => export_q::run(&args[1..]),
        Some("spy") => spy::run(&args[1..]),
        Some("etree") => etree::run(&args[1..]),
        Some("simulate") => simulate::run(&args[1..]),
        Some("generate") => generate::run(&args[1..]),
        Some("view") => view::run(&args[1..]),
        Some("render") => render::run(&args[1..]),
        Some("converge") => converge::run(&args[1..]),
        Some("help" | "--help" | "-h") => {
            print!("{USAGE}");
            Ok(())
        }
        Some(other) => Err(AppError::Usage(format!("unknown command '{other}'"))),
        None => Err(AppError::Usage("no command given".into())),
    };
    match result {
        Ok(()) => 0,
        Err(AppError::Usage(message)) => {
            eprintln!("masssprings: {message}\n(see `masssprings help`)");
            2
        }
        Err(AppError::Failed(message)) => {
            eprintln!("masssprings: error: {message}");
            1
        }
    }
}
