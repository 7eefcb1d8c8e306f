//! Each command speaks for itself, in the command line's words:
//!
//! * a command's `--help` names only its own flags, and its flags'
//!   descriptions name no other command (a text shared between commands
//!   once described `--json` as "(simulate and render: without progress)"
//!   in `analyze` and `bench`, and converge's default of `--iterations` in
//!   `simulate`);
//! * no output, text, `--json` or CSV, carries Rust's debug name of a
//!   public enum (`EnergyTolerance` where the flag says
//!   `energy-tolerance`);
//! * progress off a terminal is one line per update, never rewritten in
//!   place with `\r`.
use crate::cli;
use crate::source;

use cli::{data, masssprings, stderr, stdout, temp_folder};
use source::rust_files;
use std::collections::BTreeSet;
use std::path::Path;

/// The commands listed under `Commands:` in a help text (`help` left out).
fn commands_in(help: &str) -> Vec<String> {
    section(help, "Commands:")
        .lines()
        .filter_map(|line| line.split_whitespace().next())
        .filter(|name| *name != "help")
        .map(str::to_string)
        .collect()
}

/// The lines of a help text from `title` to the next blank line.
fn section(help: &str, title: &str) -> String {
    let Some(start) = help.find(&format!("\n{title}\n")) else {
        return String::new();
    };
    let body = &help[start + title.len() + 2..];
    body.split("\n\n").next().unwrap_or("").to_string()
}

/// Every command's path and help, subcommands included (`generate grid`).
fn every_help() -> Vec<(Vec<String>, String)> {
    let mut found = Vec::new();
    let mut todo: Vec<Vec<String>> = commands_in(&stdout(&masssprings(&["--help"])))
        .into_iter()
        .map(|c| vec![c])
        .collect();
    while let Some(path) = todo.pop() {
        let mut args: Vec<&str> = path.iter().map(String::as_str).collect();
        args.push("--help");
        let output = masssprings(&args);
        assert!(output.status.success(), "{args:?}");
        let help = stdout(&output);
        for sub in commands_in(&help) {
            let mut deeper = path.clone();
            deeper.push(sub);
            todo.push(deeper);
        }
        found.push((path, help));
    }
    found
}

/// The flags a text names: `--word-word`.
fn flags_named(text: &str) -> BTreeSet<String> {
    let mut flags = BTreeSet::new();
    for (at, _) in text.match_indices("--") {
        let name: String = text[at + 2..]
            .chars()
            .take_while(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || *c == '-')
            .collect();
        let before = text[..at].chars().next_back();
        if !name.is_empty() && before.is_none_or(|c| !c.is_alphanumeric() && c != '-') {
            flags.insert(format!("--{}", name.trim_end_matches('-')));
        }
    }
    flags
}

/// The flags a command takes: those its `Options:` lines start with.
fn own_flags(help: &str) -> BTreeSet<String> {
    section(help, "Options:")
        .lines()
        .filter(|line| line.trim_start().starts_with('-'))
        .flat_map(|line| {
            let head = line.trim_start().split("  ").next().unwrap_or("");
            flags_named(head)
        })
        .collect()
}

/// Help texts that still name a flag their command does not take, each
/// with the reason: the test fails when one no longer does, so that the
/// list only shrinks.
const STILL_NAMING_ANOTHER_COMMANDS_FLAG: [(&str, &str); 0] = [];

#[test]
fn each_commands_help_names_only_its_own_flags() {
    let helps = every_help();
    assert!(helps.len() >= 14, "{} helps read", helps.len());
    let mut strangers = BTreeSet::new();
    for (path, help) in &helps {
        let own = own_flags(help);
        assert!(own.contains("--help"), "{path:?}: {own:?}");
        for flag in flags_named(help).difference(&own) {
            strangers.insert((path.join(" "), flag.clone()));
        }
    }
    let known: BTreeSet<(String, String)> = STILL_NAMING_ANOTHER_COMMANDS_FLAG
        .iter()
        .map(|&(c, f)| (c.to_string(), f.to_string()))
        .collect();
    let new: Vec<_> = strangers.difference(&known).collect();
    assert!(
        new.is_empty(),
        "flags named in a help whose command lacks them: {new:?}"
    );
    let gone: Vec<_> = known.difference(&strangers).collect();
    assert!(
        gone.is_empty(),
        "no longer named, take them off STILL_NAMING_ANOTHER_COMMANDS_FLAG: {gone:?}"
    );
}

/// Where a text speaks of command `name` rather than uses the word (the
/// verbs "simulate" and "converge" are English too): `name:` as in "(default
/// 50; converge: 200)" or "(simulate and render: without progress)", and
/// `name's`.
fn speaks_of(text: &str, name: &str) -> bool {
    [":", "'s"].iter().any(|after| {
        text.match_indices(&format!("{name}{after}"))
            .any(|(at, _)| {
                let before = text[..at].chars().next_back();
                before.is_none_or(|c| !c.is_alphanumeric() && c != '-')
            })
    })
}

#[test]
fn no_flag_description_speaks_of_another_command() {
    let helps = every_help();
    let commands: BTreeSet<String> = helps.iter().map(|(path, _)| path.join(" ")).collect();
    for (path, help) in &helps {
        let options = section(help, "Options:");
        for other in commands.iter().filter(|c| **c != path.join(" ")) {
            assert!(
                !speaks_of(&options, other),
                "{path:?}'s flags speak of {other}:\n{options}"
            );
        }
    }
}

#[test]
fn the_help_check_sees_a_stranger() {
    let help = "Usage: x\n\nOptions:\n      --json  Print JSON (simulate and render: see --out)\n  -h, --help  Print help\n";
    let own = own_flags(help);
    assert_eq!(own, BTreeSet::from(["--json".into(), "--help".into()]));
    let named = flags_named(help);
    assert_eq!(named.difference(&own).collect::<Vec<_>>(), vec!["--out"]);
    assert_eq!(
        commands_in("x\n\nCommands:\n  grid  a\n  help  b\n\nOptions:\n"),
        ["grid"]
    );
    assert!(speaks_of(help, "render") && speaks_of("(default 50; converge: 200)", "converge"));
    assert!(!speaks_of(
        "while they converge fast; preconverge: x",
        "converge"
    ));
}

/// The variants of every `pub enum` under `src`, by their Rust names:
/// what `{:?}` would print.
fn debug_names() -> BTreeSet<String> {
    let mut names = BTreeSet::new();
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    for file in rust_files(&src) {
        let text = std::fs::read_to_string(&file).unwrap();
        let code = text.split("#[cfg(test)]").next().unwrap();
        for block in code.split("pub enum ").skip(1) {
            let body = block.split_once('{').map_or("", |(_, body)| body);
            let mut depth = 0;
            for line in body.lines() {
                let line = line.trim();
                if depth == 0 && !line.starts_with("//") && !line.starts_with('#') {
                    let name: String = line.chars().take_while(|c| c.is_alphanumeric()).collect();
                    if name.starts_with(|c: char| c.is_ascii_uppercase()) {
                        names.insert(name);
                    }
                }
                depth += line.matches(['{', '(']).count() as i32;
                depth -= line.matches(['}', ')']).count() as i32;
                if depth < 0 {
                    break;
                }
            }
        }
    }
    names
}

/// The debug names among `names` that `text` holds as whole words.
fn found_in(text: &str, names: &BTreeSet<String>) -> Vec<String> {
    let words: BTreeSet<&str> = text.split(|c: char| !c.is_alphanumeric()).collect();
    names
        .iter()
        .filter(|n| words.contains(n.as_str()))
        .cloned()
        .collect()
}

#[test]
fn the_debug_names_are_read_from_the_source() {
    let names = debug_names();
    for name in [
        "EnergyTolerance",
        "AtLeastPlain",
        "Stalled",
        "Lbfgs",
        "Inertial",
        "Supernodal",
    ] {
        assert!(names.contains(name), "{name} missing from {names:?}");
    }
    assert_eq!(
        found_in("stopped by EnergyTolerance 5, tolerance 2", &names),
        ["EnergyTolerance"]
    );
}

/// Runs `args`, which must succeed, and returns what it printed on both
/// streams.
fn printed(args: &[&str]) -> String {
    let output = masssprings(args);
    assert!(output.status.success(), "{args:?}: {}", stderr(&output));
    format!("{}{}", stdout(&output), stderr(&output))
}

#[test]
fn no_output_carries_a_rust_debug_name() {
    let names = debug_names();
    let folder = temp_folder("own-words");
    let file = |name: &str| folder.join(name).display().to_string();
    let (net, flag) = (data("net.json"), data("flag.json"));
    let mut outputs = Vec::new();
    for rule in [
        &["--tolerance", "0.01"][..],
        &["--energy-tolerance", "0.1"],
        &["--at-least-plain", "2"],
        &["--accuracy", "assignment"],
    ] {
        let mut args = vec!["simulate", net.as_str(), "--steps", "3"];
        args.extend(rule);
        outputs.push(printed(&args));
        args.push("--json");
        outputs.push(printed(&args));
    }
    let (one, steps) = (file("one.csv"), file("steps.csv"));
    outputs.push(printed(&[
        "converge",
        &net,
        "--iterations",
        "60",
        "--csv",
        &one,
    ]));
    outputs.push(printed(&[
        "converge",
        &flag,
        "--steps",
        "2",
        "--energy-tolerance",
        "0.1",
        "--csv",
        &steps,
    ]));
    let accuracy = file("accuracy.csv");
    outputs.push(printed(&[
        "converge",
        &net,
        "--steps",
        "2",
        "--accuracy",
        "assignment",
        "--csv",
        &accuracy,
    ]));
    let q = file("q.mtx");
    outputs.push(printed(&["export-q", &net, "-o", &q]));
    outputs.push(printed(&["analyze", &q, "--repeats", "1"]));
    outputs.push(printed(&["analyze", &q, "--repeats", "1", "--json"]));
    let bench = file("bench.csv");
    outputs.push(printed(&[
        "bench", "--sizes", "4,5", "--steps", "1", "--json", "--csv", &bench,
    ]));
    outputs.push(printed(&[
        "render",
        &net,
        "--steps",
        "2",
        "-o",
        &file("net.png"),
        "--json",
    ]));
    for csv in [one, steps, accuracy, bench] {
        outputs.push(std::fs::read_to_string(csv).unwrap());
    }
    for output in &outputs {
        let found = found_in(output, &names);
        assert!(found.is_empty(), "Rust's names {found:?} in:\n{output}");
    }
}

#[test]
fn progress_off_a_terminal_is_one_line_per_update() {
    // converge's progress over its steps, and simulate's (render and bench
    // write theirs the same way): never a carriage return into a pipe
    for args in [
        &["converge", "NET", "--steps", "3", "--tolerance", "0.01"][..],
        &["converge", "NET", "--steps", "2"],
        &["simulate", "NET", "--steps", "5"],
    ] {
        let net = data("net.json");
        let args: Vec<&str> = args
            .iter()
            .map(|&a| if a == "NET" { net.as_str() } else { a })
            .collect();
        let output = masssprings(&args);
        assert!(output.status.success(), "{args:?}");
        let err = stderr(&output);
        assert!(!err.contains('\r'), "{args:?}: {err:?}");
        assert!(err.is_empty() || err.ends_with('\n'), "{args:?}: {err:?}");
    }
}
