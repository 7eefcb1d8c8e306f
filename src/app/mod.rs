//! The application layer: the command line. Thin by design: it parses
//! arguments, reads and writes files, times things, and calls the library.

mod analyze;
mod bench;
mod converge;
mod convergence_plot;
mod etree;
mod export_q;
mod flags;
mod frame_folder;
mod frames;
mod generate;
mod limits;
mod output_folder;
mod progress;
mod render;
mod resume;
mod simulate;
mod spy;
mod steps_plot;
mod timing;
mod trace;
mod view;

use clap::error::ErrorKind;
use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
use masssprings::files::FilePlan;
use masssprings::mesh::Scene;
use std::ffi::{OsStr, OsString};
use std::io::Read;
use std::path::Path;

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

/// Reads a scene, first making sure the file is one: a scene is JSON that
/// names an OBJ, and an OBJ (or anything else) given in its place gets a
/// sentence saying so rather than a JSON parser's complaint.
///
/// # Errors
/// That sentence, or the scene reader's error (file, line, problem).
pub fn load_scene(path: &Path) -> Result<Scene, AppError> {
    if !looks_like_json(path) {
        return Err(AppError::Failed(format!(
            "{} is not a scene file: scenes are JSON that name an OBJ; see data/README.md",
            path.display()
        )));
    }
    Ok(masssprings::mesh::load_scene(path)?)
}

/// The files of `scene` (read from `scene_path`): its JSON, its OBJ and
/// its texture, as inputs of `plan`.
pub fn plan_scene_inputs(plan: &mut FilePlan, scene_path: &Path, scene: &Scene) {
    plan.input("the scene", scene_path);
    if let Some(obj) = &scene.obj {
        plan.input("the scene's OBJ", obj);
    }
    if let Some(texture) = &scene.texture {
        plan.input("the scene's texture", texture);
    }
}

/// Refuses an `--out` folder that names nothing, standard output (`-`) or a
/// file; `writes` says what the command puts there, for the message.
///
/// # Errors
/// A usage error for an empty name or `-`, a failure for a file.
pub fn check_output_folder(folder: &Path, writes: &str) -> Result<(), AppError> {
    if folder == Path::new("-") || folder.as_os_str().is_empty() {
        return Err(AppError::Usage(format!(
            "--out '{}': {writes}; name a folder",
            folder.display()
        )));
    }
    if std::fs::metadata(folder).is_ok_and(|m| !m.is_dir()) {
        return Err(AppError::Failed(format!(
            "--out {}: this is a file, not a folder; {writes}",
            folder.display()
        )));
    }
    Ok(())
}

/// Prints a command's one-line report on standard output, or on standard
/// error when its output file is `-` (standard output carries the file).
pub fn report(out: &Path, line: &str) {
    if out == Path::new("-") {
        eprintln!("{line}");
    } else {
        println!("{line}");
    }
}

/// Does the file start (after white space and a byte-order mark) with `{`?
/// True when it cannot be read, is empty or is not a regular file (a FIFO
/// is read once, by the scene reader, which then says what is wrong).
fn looks_like_json(path: &Path) -> bool {
    if !std::fs::metadata(path).is_ok_and(|m| m.is_file()) {
        return true;
    }
    let mut start = [0u8; 512];
    let Ok(read) = std::fs::File::open(path).and_then(|mut file| file.read(&mut start)) else {
        return true;
    };
    let text = start[..read]
        .strip_prefix(b"\xef\xbb\xbf")
        .unwrap_or(&start[..read]);
    match text.iter().find(|byte| !byte.is_ascii_whitespace()) {
        None => true,
        Some(&first) => first == b'{',
    }
}

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
