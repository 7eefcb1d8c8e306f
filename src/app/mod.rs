//! The application layer: the command line. Thin by design: it parses
//! arguments, reads and writes files, times things, and calls the library.
//!
//! This file is the dispatcher only: it parses the line, runs one command
//! and maps its error to an exit code. Below it, each floor uses only the
//! floors under it (`tests/repository/layers.rs` checks it):
//!
//! ```text
//! commands           simulate, render, view/, converge/, trace/, analyze, bench,
//!                    spy, etree, generate, export_q: each reads like its --help
//! subsystems         draw/ (rasterizer, plots, PNG/GIF), matrix_input (the matrix
//!                    of analyze, spy, etree, export-q), analysis (the timed
//!                    sparse Cholesky of analyze and bench)
//! frames             resume/ (the frames' format and folder, resuming from them)
//! shared plumbing    flags, limits, progress, timing, file_plan
//! the error          error (AppError)
//! library            masssprings::{sim, mesh, linalg, files, memory}
//! ```

mod analysis;
mod analyze;
mod bench;
mod closed_pipe;
mod converge;

mod draw;
mod error;
mod etree;
mod export_q;
mod file_plan;
mod flags;
mod generate;
mod limits;
mod matrix_input;
mod progress;
mod render;
mod resume;
mod simulate;
mod spy;

mod timing;
mod trace;
mod view;

use clap::error::ErrorKind;
use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
use error::AppError;
use std::ffi::{OsStr, OsString};

/// `masssprings`: its version, and one subcommand per command, each
/// declared in its own file.
#[derive(Parser, Debug)]
#[command(
    name = "masssprings",
    version,
    about = "Fast simulation of mass-spring systems (Liu et al. 2013)",
    arg_required_else_help = true
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// Every command, in the order `masssprings help` lists them.
#[derive(Subcommand, Debug)]
enum Command {
    Simulate(simulate::SimulateArgs),
    Render(render::RenderArgs),
    View(view::ViewArgs),
    Converge(converge::ConvergeArgs),
    Analyze(analyze::AnalyzeArgs),
    Bench(bench::BenchArgs),
    ExportQ(export_q::ExportQArgs),
    Spy(spy::SpyArgs),
    Etree(etree::EtreeArgs),
    Trace(trace::TraceArgs),
    Generate(generate::GenerateArgs),
    /// Print a completion script for a shell (`masssprings completions bash > masssprings.bash`).
    Completions {
        #[arg(value_name = "SHELL")]
        shell: clap_complete::Shell,
    },
    /// The version (as `--version`).
    #[command(hide = true)]
    Version,
}

impl Command {
    fn run(self) -> Result<(), AppError> {
        match self {
            Command::Simulate(args) => simulate::run(args),
            Command::Render(args) => render::run(args),
            Command::View(args) => view::run(args),
            Command::Converge(args) => converge::run(args),
            Command::Analyze(args) => analyze::run(args),
            Command::Bench(args) => bench::run(args),
            Command::ExportQ(args) => export_q::run(args),
            Command::Spy(args) => spy::run(args),
            Command::Etree(args) => etree::run(args),
            Command::Trace(args) => trace::run(args),
            Command::Generate(args) => generate::run(args),
            Command::Completions { shell } => {
                let mut command = Cli::command();
                clap_complete::generate(shell, &mut command, "masssprings", &mut std::io::stdout());
                Ok(())
            }
            Command::Version => {
                println!("masssprings {}", env!("CARGO_PKG_VERSION"));
                Ok(())
            }
        }
    }
}

/// Parses `args`; help asked for anywhere before a `--` wins over any
/// error on the line (`simulate x --bogus -h` shows `simulate`'s help).
fn parse(args: &[OsString]) -> Result<Cli, clap::Error> {
    let line =
        std::iter::once(OsStr::new("masssprings")).chain(args.iter().map(OsString::as_os_str));
    // `--energy-tolerance -0.1` is a bad value, not an unknown flag `-0`
    let command = Cli::command().mut_subcommands(|c| c.allow_negative_numbers(true));
    let matches = command.try_get_matches_from(line);
    matches
        .and_then(|m| Cli::from_arg_matches(&m))
        .map_err(|error| {
            let asks_for_help = args
                .iter()
                .take_while(|arg| *arg != "--")
                .any(|arg| arg == "-h" || arg == "--help");
            match args.first() {
                Some(command) if asks_for_help && error.kind() != ErrorKind::DisplayHelp => {
                    let help = [
                        OsStr::new("masssprings"),
                        command.as_os_str(),
                        OsStr::new("--help"),
                    ];
                    Cli::try_parse_from(help).err().unwrap_or(error)
                }
                _ => error,
            }
        })
}

/// Runs the command line `args` (without the program name, as the system
/// gives them: not UTF-8 perhaps); returns the exit code: 0, 2 for a usage
/// error (clap's or a command's), 1 for a failure.
pub fn run(args: &[OsString]) -> i32 {
    let command = match parse(args) {
        Ok(cli) => cli.command,
        Err(error) => {
            let _ = error.print();
            return error.exit_code();
        }
    };
    if let Err(problem) = masssprings::memory::limit_variable() {
        eprintln!("masssprings: error: {problem}");
        return 1;
    }
    if !matches!(command, Command::View(_)) {
        closed_pipe::end_quietly_when_the_reader_goes();
    }
    match command.run() {
        Ok(()) => 0,
        Err(AppError::Usage(message)) => {
            let name = args
                .first()
                .map_or("".into(), |name| name.to_string_lossy());
            eprintln!("masssprings: {message}\n(see `masssprings {name} --help`)");
            2
        }
        Err(AppError::Failed(message)) => {
            eprintln!("masssprings: error: {message}");
            1
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The command `line` parses into.
    fn command(line: &[&str]) -> Command {
        let args: Vec<OsString> = line.iter().map(OsString::from).collect();
        parse(&args).expect("a valid line").command
    }

    #[test]
    fn the_declaration_is_consistent() {
        Cli::command().debug_assert();
    }

    #[test]
    fn render_and_converge_pass_the_factorization_to_their_simulation() {
        use masssprings::linalg::sparse::{Method, Ordering, SupernodeMerging};
        let flags = [
            "--ordering",
            "natural",
            "--factorization",
            "simplicial",
            "--supernodes",
            "fundamental",
        ];
        let options = match command(&[&["converge", "x.json"][..], &flags].concat()) {
            Command::Converge(args) => converge::parse(args).canonical,
            _ => unreachable!("converge"),
        };
        let factor = |o: masssprings::sim::simulation::SimulationOptions| {
            (o.ordering, o.factorization, o.supernodes)
        };
        let expected = (
            Ordering::Natural,
            Method::Simplicial,
            SupernodeMerging::Fundamental,
        );
        assert_eq!(factor(options), expected);
        let options = match command(&[&["render", "x.json", "-o", "x.gif"][..], &flags].concat()) {
            Command::Render(args) => render::options(&args),
            _ => unreachable!("render"),
        };
        assert_eq!(factor(options), expected);
    }
}
