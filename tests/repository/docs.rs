//! The docs stay a book a student can open from a clone.
//!
//! * every relative link and image of `README.md` and `docs/*.md` names a
//!   file inside the repository;
//! * nothing a reader sees points outside it: no `shared/` in the README,
//!   the docs, the READMEs of `data/` and `tests/fixtures/`, or the
//!   comments of `src/` (a clone has no `../shared`);
//! * no development history in `README.md` and `docs/*.md`: no session
//!   numbers, issue numbers, commit hashes, clock times or load averages
//!   (the git log keeps those; a figure carries its command and machine);
//! * the README and the two chapters on results keep their lengths;
//! * every flag a page shows on a command line (`masssprings CMD … --flag`
//!   or `cargo run --release -- CMD … --flag`) is in that command's
//!   `--help`, so the command tour cannot drift from the program.
//!
//! Every check is a function of the text, so the last test feeds each one
//! the mistake it looks for and sees it reported.

use crate::cli;

use cli::{masssprings, COMMANDS};
use std::fs;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// `README.md` and `docs/*.md`, the pages a student reads.
fn pages() -> Vec<PathBuf> {
    let mut pages = vec![root().join("README.md")];
    let mut docs: Vec<PathBuf> = fs::read_dir(root().join("docs"))
        .expect("docs/ is readable")
        .map(|entry| entry.expect("a docs/ entry").path())
        .filter(|path| path.extension().is_some_and(|e| e == "md"))
        .collect();
    docs.sort();
    pages.extend(docs);
    pages
}

/// The pages, the READMEs of `data/` and `tests/fixtures/*/`, and every
/// source file of `src/`: all that must not point into `../shared`.
fn everything_a_reader_sees() -> Vec<PathBuf> {
    let mut files = pages();
    files.push(root().join("data/README.md"));
    for entry in fs::read_dir(root().join("tests/fixtures")).expect("tests/fixtures/ is readable") {
        let readme = entry.expect("a fixtures entry").path().join("README.md");
        if readme.is_file() {
            files.push(readme);
        }
    }
    rust_files(&root().join("src"), &mut files);
    files
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in fs::read_dir(dir).expect("src/ is readable") {
        let path = entry.expect("a src entry").path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// `path` as the repository names it.
fn shown(path: &Path) -> String {
    path.strip_prefix(root())
        .unwrap_or(path)
        .display()
        .to_string()
}

fn read(path: &Path) -> String {
    fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The text without fenced code blocks and inline code spans, where `[a](b)`
/// is code, not a link.
fn prose(text: &str) -> String {
    let mut out = String::new();
    let mut fenced = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            out.push('\n');
            continue;
        }
        if !fenced {
            let mut in_code = false;
            for c in line.chars() {
                if c == '`' {
                    in_code = !in_code;
                } else if !in_code {
                    out.push(c);
                }
            }
        }
        out.push('\n');
    }
    out
}

/// The targets of the Markdown links and images `[text](target)` and of
/// HTML `src="…"`/`href="…"`, each with its line number.
fn link_targets(text: &str) -> Vec<(usize, String)> {
    let mut targets = Vec::new();
    for (number, line) in prose(text).lines().enumerate() {
        let mut rest = line;
        while let Some(at) = rest.find("](") {
            let after = &rest[at + 2..];
            let end = after.find(')').unwrap_or(after.len());
            let target = after[..end].split_whitespace().next().unwrap_or("");
            targets.push((number + 1, target.to_string()));
            rest = &after[end..];
        }
        for attribute in ["src=\"", "href=\""] {
            let mut rest = line;
            while let Some(at) = rest.find(attribute) {
                let after = &rest[at + attribute.len()..];
                let end = after.find('"').unwrap_or(after.len());
                targets.push((number + 1, after[..end].to_string()));
                rest = &after[end..];
            }
        }
    }
    targets
}

/// Each relative link of `page` that does not name a file or folder inside
/// `repository`.
fn broken_links(page: &Path, text: &str, repository: &Path) -> Vec<String> {
    let repository = repository
        .canonicalize()
        .expect("the repository's root exists");
    let folder = page.parent().expect("a page is in a folder");
    let mut broken = Vec::new();
    for (line, target) in link_targets(text) {
        let external = ["http://", "https://", "mailto:"]
            .iter()
            .any(|s| target.starts_with(s));
        let path = target.split('#').next().unwrap_or("");
        if external || path.is_empty() {
            continue;
        }
        let inside = folder
            .join(path)
            .canonicalize()
            .is_ok_and(|resolved| resolved.starts_with(&repository));
        if !inside {
            broken.push(format!("{}:{line}: {target}", shown(page)));
        }
    }
    broken
}

/// Each line that points into the folder beside the clone.
fn outside_references(text: &str) -> Vec<usize> {
    let lines = text.lines().enumerate();
    lines
        .filter(|(_, line)| line.contains("shared/"))
        .map(|(n, _)| n + 1)
        .collect()
}

/// Whether `word`, case aside, is followed (after spaces and a `#`) by a digit
/// somewhere in `line`: "session 4", "Issue #11".
fn word_then_number(line: &str, word: &str) -> bool {
    let lower = line.to_lowercase();
    lower.match_indices(word).any(|(at, _)| {
        let before = lower[..at].chars().next_back();
        let after = lower[at + word.len()..]
            .trim_start_matches(' ')
            .trim_start_matches('#');
        !before.is_some_and(char::is_alphanumeric)
            && lower[at + word.len()..].starts_with(' ')
            && after.starts_with(|c: char| c.is_ascii_digit())
    })
}

/// `#12` after a space, a bracket or the start of the line: an issue or pull
/// request number.
fn hash_number(line: &str) -> bool {
    line.match_indices('#').any(|(at, _)| {
        let before = line[..at].chars().next_back();
        let open = before.is_none_or(|c| c.is_whitespace() || "([".contains(c));
        open && line[at + 1..].starts_with(|c: char| c.is_ascii_digit())
    })
}

/// `` `f220a0f` ``: seven to forty hexadecimal digits, at least one a letter,
/// alone in backticks.
fn commit_hash(line: &str) -> bool {
    line.split('`').skip(1).step_by(2).any(|span| {
        (7..=40).contains(&span.len())
            && span
                .chars()
                .all(|c| c.is_ascii_digit() || ('a'..='f').contains(&c))
            && span.chars().any(|c| c.is_ascii_alphabetic())
    })
}

/// `03:57 UTC`: a clock time.
fn clock_time(line: &str) -> bool {
    line.match_indices(" UTC").any(|(at, _)| {
        let time = line[..at].chars().rev().take(5).collect::<String>();
        let time: Vec<char> = time.chars().rev().collect();
        time.len() == 5 && time[2] == ':' && [0, 1, 3, 4].iter().all(|&i| time[i].is_ascii_digit())
    })
}

/// Each line with a development-history marker, and what it is.
fn history(text: &str) -> Vec<(usize, &'static str)> {
    let mut found = Vec::new();
    for (number, line) in text.lines().enumerate() {
        let checks: [(bool, &'static str); 6] = [
            (word_then_number(line, "session"), "a session number"),
            (word_then_number(line, "issue"), "an issue number"),
            (hash_number(line), "an issue number (#N)"),
            (commit_hash(line), "a commit hash"),
            (clock_time(line), "a clock time"),
            (
                line.to_lowercase().contains("load average"),
                "a load average",
            ),
        ];
        found.extend(
            checks
                .iter()
                .filter(|(hit, _)| *hit)
                .map(|&(_, what)| (number + 1, what)),
        );
    }
    found
}

#[test]
fn every_relative_link_and_image_names_a_file_inside_the_repository() {
    let broken: Vec<String> = pages()
        .iter()
        .flat_map(|page| broken_links(page, &read(page), &root()))
        .collect();
    assert!(
        broken.is_empty(),
        "links that lead nowhere or out of the repository:\n{}",
        broken.join("\n")
    );
}

#[test]
fn nothing_points_into_the_folder_beside_the_clone() {
    let mut found = Vec::new();
    for file in everything_a_reader_sees() {
        for line in outside_references(&read(&file)) {
            found.push(format!("{}:{line}", shown(&file)));
        }
    }
    assert!(
        found.is_empty(),
        "references to shared/, which a clone does not have:\n{}",
        found.join("\n")
    );
}

#[test]
fn the_docs_hold_no_development_history() {
    let mut found = Vec::new();
    for page in pages() {
        for (line, what) in history(&read(&page)) {
            found.push(format!("{}:{line}: {what}", shown(&page)));
        }
    }
    assert!(
        found.is_empty(),
        "development history (it belongs in the git log):\n{}",
        found.join("\n")
    );
}

#[test]
fn the_readme_and_the_chapters_on_results_keep_their_lengths() {
    for (page, most) in [
        ("README.md", 150),
        ("docs/performance.md", 335), // a section on threads joined the 300
        ("docs/convergence.md", 450),
    ] {
        let lines = read(&root().join(page)).lines().count();
        assert!(lines <= most, "{page} has {lines} lines, more than {most}");
    }
}

/// `(line, command, flag)` for every flag shown after a command of
/// [`COMMANDS`] on one line: from `masssprings CMD` or `-- CMD` to the end
/// of the code span (a backtick) or of the line.
fn flags_shown(text: &str) -> Vec<(usize, &'static str, String)> {
    let mut found = Vec::new();
    for (number, line) in text.lines().enumerate() {
        for (start, _) in line
            .match_indices("masssprings ")
            .chain(line.match_indices("-- "))
        {
            let rest = &line[start..];
            let rest = rest.split_once(' ').map_or("", |(_, after)| after);
            let Some(&command) = COMMANDS
                .iter()
                .find(|&&c| rest.split_whitespace().next() == Some(c))
            else {
                continue;
            };
            let span = rest.split('`').next().unwrap_or("");
            for word in span.split_whitespace().skip(1) {
                let word = word.split('=').next().unwrap_or(word);
                let word = word.trim_end_matches([',', '.', ')', ';', ':', '"']);
                let is_flag = word.starts_with("--") && word.len() > 2 || word == "-o";
                if is_flag {
                    found.push((number + 1, command, word.to_string()));
                }
            }
        }
    }
    found
}

#[test]
fn every_flag_the_pages_show_is_in_its_commands_help() {
    let mut pages = pages();
    pages.push(root().join("data/README.md"));
    let mut helps = std::collections::HashMap::new();
    let (mut unknown, mut checked) = (Vec::new(), 0);
    for page in &pages {
        for (line, command, flag) in flags_shown(&read(page)) {
            checked += 1;
            let help = helps.entry(command).or_insert_with(|| {
                let output = masssprings(&[command, "--help"]);
                assert!(output.status.success(), "{command} --help");
                String::from_utf8(output.stdout).expect("UTF-8 help")
            });
            let listed = help.contains(&format!("{flag} ")) || help.contains(&format!("{flag},"));
            if !listed {
                unknown.push(format!("{}:{line}: {command} {flag}", shown(page)));
            }
        }
    }
    assert!(unknown.is_empty(), "flags not in the help: {unknown:#?}");
    assert!(checked >= 50, "only {checked} flags found on the pages");
}

#[test]
fn each_check_reports_the_mistake_it_looks_for() {
    let shown = flags_shown("run `masssprings analyze M.mtx --method simplicial`, then --later");
    assert_eq!(shown, vec![(1, "analyze", "--method".to_string())]);
    let shown = flags_shown("cargo run --release -- render x.json -o x.gif --every 2");
    let flags: Vec<&str> = shown.iter().map(|(_, _, flag)| flag.as_str()).collect();
    assert_eq!(flags, ["-o", "--every"]);

    let repository = root();
    let page = repository.join("docs/example.md");
    let good = "[equations](equations.md), ![flag](images/flag.gif), [x](#anchor), \
                [handout](https://github.com/alecjacobson/computer-graphics-mass-spring-systems)";
    assert!(broken_links(&page, good, &repository).is_empty());
    for bad in [
        "[gone](missing.md)",
        "![gone](images/missing.png)",
        "[out](../../../etc/passwd)",
        "<img src=\"nope.png\">",
    ] {
        assert_eq!(broken_links(&page, bad, &repository).len(), 1, "{bad}");
    }
    assert!(broken_links(&page, "`[code](missing.md)`", &repository).is_empty());

    assert_eq!(
        outside_references("fine\nsee ../shared/anchors.md\n"),
        vec![2]
    );

    let clean = "A session of the viewer; the issue of rounding; `Aᵀd`; ## 9. Pictures; \
                 `1234567`; 12:34 on the clock; an average load";
    assert!(history(clean).is_empty(), "{:?}", history(clean));
    for (bad, what) in [
        ("measured in Session 22", "a session number"),
        ("since session 4,", "a session number"),
        ("targets (issue 11)", "an issue number"),
        ("as issue #7 asks", "an issue number"),
        ("fixed in #25", "an issue number (#N)"),
        ("main at `f220a0f`", "a commit hash"),
        ("(03:57 UTC)", "a clock time"),
        ("load average 1.1", "a load average"),
    ] {
        assert!(
            history(bad).iter().any(|&(_, found)| found == what),
            "{bad}: {:?}",
            history(bad)
        );
    }
}
