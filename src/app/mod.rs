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
mod limits;
mod progress;
mod render;
mod resume;
mod simulate;
mod spy;
mod steps_plot;
mod suggest;
mod timing;
mod trace;
mod view;

use args::CommandSpec;
use masssprings::files::FilePlan;
use masssprings::mesh::Scene;
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

/// Every command, in the order `masssprings help` lists them. Each
/// command's flags live in its own file, in its `COMMAND` table.
const COMMANDS: &[&CommandSpec] = &[
    &simulate::COMMAND,
    &render::COMMAND,
    &view::COMMAND,
    &converge::COMMAND,
    &analyze::COMMAND,
    &bench::COMMAND,
    &export_q::COMMAND,
    &spy::COMMAND,
    &etree::COMMAND,
    &trace::COMMAND,
    &generate::COMMAND,
];

/// `masssprings help`, generated from [`COMMANDS`].
fn usage() -> String {
    let mut text = format!(
        "masssprings {}: fast simulation of mass-spring systems (Liu et al. 2013)\n\n\
         usage: masssprings COMMAND [options]\n\ncommands:\n",
        env!("CARGO_PKG_VERSION")
    );
    for command in COMMANDS {
        args::push_entry(
            &mut text,
            &format!("{} {}", command.name, command.operands),
            command.summary,
        );
    }
    args::push_entry(
        &mut text,
        "help [COMMAND]",
        "This text, or a command's options.",
    );
    args::push_entry(&mut text, "--version", "The version.");
    text.push_str(
        "\n`masssprings help COMMAND` or `masssprings COMMAND --help` shows a command's options.\n",
    );
    text
}

fn find_command(name: &str) -> Result<&'static CommandSpec, AppError> {
    if let Some(command) = COMMANDS.iter().find(|command| command.name == name) {
        return Ok(command);
    }
    let names = COMMANDS.iter().map(|command| command.name);
    let hint = suggest::nearest(name, names.chain(["help"]))
        .map(|name| format!("; did you mean {name}?"))
        .unwrap_or_default();
    Err(AppError::Usage(format!("unknown command '{name}'{hint}")))
}

/// Asks for help: `-h` or `--help` among the arguments (before a `--`).
fn asks_for_help(args: &[String]) -> bool {
    args.iter()
        .take_while(|arg| *arg != "--")
        .any(|arg| arg == "-h" || arg == "--help")
}

/// Runs one command line; help goes to standard output.
fn dispatch(args: &[String]) -> Result<(), AppError> {
    match args.first().map(String::as_str) {
        None => Err(AppError::Usage("no command given".into())),
        Some("help" | "--help" | "-h") => {
            match args.get(1) {
                None => print!("{}", usage()),
                Some(name) => print!("{}", find_command(name)?.help()),
            }
            Ok(())
        }
        Some("--version" | "-V" | "version") => {
            println!("masssprings {}", env!("CARGO_PKG_VERSION"));
            Ok(())
        }
        Some(name) => {
            let command = find_command(name)?;
            if asks_for_help(&args[1..]) {
                print!("{}", command.help());
                return Ok(());
            }
            (command.run)(&args[1..])
        }
    }
}

/// Runs the command line `args` (without the program name); returns the
/// exit code.
pub fn run(args: &[String]) -> i32 {
    match dispatch(args) {
        Ok(()) => 0,
        Err(AppError::Usage(message)) => {
            let see = match args.first().and_then(|name| find_command(name).ok()) {
                Some(command) => format!("masssprings {} --help", command.name),
                None => "masssprings help".to_string(),
            };
            eprintln!("masssprings: {message}\n(see `{see}`)");
            2
        }
        Err(AppError::Failed(message)) => {
            eprintln!("masssprings: error: {message}");
            1
        }
    }
}
