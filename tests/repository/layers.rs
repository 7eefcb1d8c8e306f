//! The shape of the code, checked from its source:
//!
//! * the files of `src/sim` import one another without a loop: data flows
//!   one way, from the vocabulary and the kernels up to the simulation (a
//!   file that used a re-export of `sim/mod.rs` would close a loop through
//!   it, so each file names the file it takes from);
//! * `src/app` stands in declared floors ([`APP_FLOORS`]: shared plumbing,
//!   subsystems, commands, the dispatcher), each file or folder importing
//!   only from the floors below its own, and its files import one another
//!   without a loop;
//! * `src/linalg` imports only `std` and itself, so that it can be lifted
//!   out;
//! * no function in `src` is longer than 60 lines, and the handout's step,
//!   `fast_mass_springs_step_sparse`, fits in 40.
//!
//! The `use` lines are read as text: braces expanded, `super::`, `self::`
//! and `crate::` resolved against the folder layout (a `mod name {` inside
//! a file is followed, so that its `super::` means the file itself). Paths
//! written in the code without a `use` (`super::timing::median(..)`, a
//! child module's `accuracy::run(..)`) count as imports too.

use crate::source;

use source::rust_files;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

fn src_folder() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

fn sim_folder() -> PathBuf {
    src_folder().join("sim")
}

fn app_folder() -> PathBuf {
    src_folder().join("app")
}

/// The module path of a file: `src/sim/methods/plain.rs` → `sim::methods::plain`,
/// `src/sim/methods/mod.rs` → `sim::methods` (`src/app` is the module
/// `app` of the binary, `crate::app`, as `src/sim` is `crate::sim` of the
/// library).
fn module_of(file: &Path) -> Vec<String> {
    let relative = file.strip_prefix(src_folder()).unwrap();
    let mut path = Vec::new();
    for part in relative.iter() {
        let part = part.to_str().unwrap().trim_end_matches(".rs");
        if part != "mod" {
            path.push(part.to_string());
        }
    }
    path
}

/// `a::{b, c::{d, e}}` → `[a::b, a::c::d, a::c::e]`.
fn expand(tree: &str) -> Vec<String> {
    let tree: String = tree.split_whitespace().collect();
    let Some(open) = tree.find('{') else {
        return vec![tree];
    };
    let (prefix, inner) = (&tree[..open], &tree[open + 1..tree.len() - 1]);
    let (mut parts, mut depth, mut start) = (Vec::new(), 0, 0);
    for (i, ch) in inner.char_indices() {
        match ch {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                parts.push(&inner[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    parts.push(&inner[start..]);
    parts
        .into_iter()
        .filter(|p| !p.is_empty())
        .flat_map(|p| expand(&format!("{prefix}{p}")))
        .collect()
}

/// The code of a file, its tests left out.
fn code_of(file: &Path) -> String {
    let text = std::fs::read_to_string(file).unwrap();
    text.split("#[cfg(test)]").next().unwrap().to_string()
}

/// The paths a file imports (tests excluded), each with the module path it
/// is written in (a file's inline `mod name {` included): its `use` trees,
/// expanded, and the paths its code names without a `use`, those that start
/// with `crate::`, `super::` or a child module the file declares.
fn uses(file: &Path) -> Vec<(Vec<String>, String)> {
    let code = code_of(file);
    let children = child_modules(&code);
    let (mut found, mut inline, mut depth) = (Vec::new(), Vec::<(String, i32)>::new(), 0);
    let mut pending: Option<String> = None;
    for line in code.lines() {
        let line = line.split("//").next().unwrap().trim();
        let mut module = module_of(file);
        module.extend(inline.iter().map(|(name, _)| name.clone()));
        if let Some(tree) = pending.as_mut() {
            tree.push_str(line);
        } else if let Some(rest) = line.strip_prefix("use ").or(line.strip_prefix("pub use ")) {
            pending = Some(rest.to_string());
        } else if let Some(name) = inline_module(line) {
            inline.push((name, depth));
        } else {
            for path in paths_in(line, &children) {
                found.push((module.clone(), path));
            }
        }
        if let Some(tree) = pending.take_if(|t| t.ends_with(';')) {
            for path in expand(tree.trim_end_matches(';')) {
                let path = path.split(" as ").next().unwrap().to_string();
                found.push((module.clone(), path));
            }
        }
        depth += line.matches('{').count() as i32 - line.matches('}').count() as i32;
        inline.retain(|&(_, opened)| depth > opened);
    }
    found
}

/// The modules a file declares in files of their own (`mod name;`).
fn child_modules(code: &str) -> Vec<String> {
    code.lines()
        .filter_map(|line| {
            let line = line.trim().trim_start_matches("pub(crate) ");
            let line = line
                .trim_start_matches("pub(super) ")
                .trim_start_matches("pub ");
            Some(line.strip_prefix("mod ")?.strip_suffix(';')?.to_string())
        })
        .collect()
}

/// The paths a line of code names that start with `crate::`, `super::` or
/// one of `children`: `super::timing::median(x)` → `super::timing::median`.
fn paths_in(line: &str, children: &[String]) -> Vec<String> {
    let is_path_char = |c: char| c.is_alphanumeric() || c == '_' || c == ':';
    let mut found = Vec::new();
    let mut rest = line;
    while let Some(at) = rest.find("::") {
        let start = rest[..at]
            .rfind(|c: char| !is_path_char(c))
            .map_or(0, |i| i + 1);
        let end = rest[at..]
            .find(|c: char| !is_path_char(c))
            .map_or(rest.len(), |i| at + i);
        let path = rest[start..end].trim_end_matches(':');
        let first = path.split("::").next().unwrap();
        if ["crate", "super"].contains(&first) || children.iter().any(|c| c == first) {
            found.push(path.to_string());
        }
        rest = &rest[end..];
    }
    found
}

/// `mod name {` (not `mod name;`): the name.
fn inline_module(line: &str) -> Option<String> {
    let rest = line
        .trim_start_matches("pub(crate) ")
        .trim_start_matches("pub ");
    let name = rest.strip_prefix("mod ")?.strip_suffix('{')?.trim();
    Some(name.to_string())
}

/// The module path a use path (written in `module`) names, or `None` for
/// one of another crate (`std`, `masssprings` seen from the binary).
fn resolve(module: &[String], path: &str) -> Option<Vec<String>> {
    let mut resolved: Vec<String> = Vec::new();
    for (i, segment) in path.split("::").enumerate() {
        match (i, segment) {
            (0, "crate") => {}
            (0, "super") => resolved = module[..module.len() - 1].to_vec(),
            (0, "self") => resolved = module.to_vec(),
            (0, _) if !module.is_empty() => {
                // a child module of the file, named without `self::`
                resolved = module.to_vec();
                resolved.push(segment.to_string());
            }
            (_, "super") => {
                resolved.pop();
            }
            (_, "self") => {}
            _ => resolved.push(segment.to_string()),
        }
    }
    Some(resolved)
}

/// The file of `files` that a use path (written in `module`) takes from,
/// if any: the longest prefix of the resolved path that is a file.
fn target(
    module: &[String],
    path: &str,
    files: &BTreeMap<Vec<String>, PathBuf>,
) -> Option<PathBuf> {
    let first = path.split("::").next().unwrap();
    if !["crate", "super", "self"].contains(&first) && !files.contains_key(&child(module, first)) {
        return None; // std, another crate
    }
    let resolved = resolve(module, path)?;
    (1..=resolved.len())
        .rev()
        .find_map(|len| files.get(&resolved[..len]).cloned())
}

/// `module::name`.
fn child(module: &[String], name: &str) -> Vec<String> {
    let mut path = module.to_vec();
    path.push(name.to_string());
    path
}

/// Which files each file under `folder` imports from, among them.
fn import_graph(folder: &Path) -> BTreeMap<PathBuf, BTreeSet<PathBuf>> {
    let files: BTreeMap<Vec<String>, PathBuf> = rust_files(folder)
        .into_iter()
        .map(|f| (module_of(&f), f))
        .collect();
    let mut graph = BTreeMap::new();
    for file in files.values() {
        let mut targets = BTreeSet::new();
        for (module, path) in uses(file) {
            if let Some(to) = target(&module, &path, &files).filter(|to| to != file) {
                targets.insert(to);
            }
        }
        graph.insert(file.clone(), targets);
    }
    graph
}

/// A cycle through `start`'s descendants, if there is one (depth first).
fn find_cycle(graph: &BTreeMap<PathBuf, BTreeSet<PathBuf>>) -> Option<Vec<PathBuf>> {
    fn visit(
        node: &PathBuf,
        graph: &BTreeMap<PathBuf, BTreeSet<PathBuf>>,
        path: &mut Vec<PathBuf>,
        done: &mut BTreeSet<PathBuf>,
    ) -> Option<Vec<PathBuf>> {
        if let Some(at) = path.iter().position(|p| p == node) {
            return Some(path[at..].to_vec());
        }
        if !done.insert(node.clone()) {
            return None;
        }
        path.push(node.clone());
        for next in &graph[node] {
            if let Some(cycle) = visit(next, graph, path, done) {
                return Some(cycle);
            }
        }
        path.pop();
        None
    }
    let mut done = BTreeSet::new();
    graph
        .keys()
        .find_map(|node| visit(node, graph, &mut Vec::new(), &mut done))
}

#[test]
fn the_files_of_sim_import_one_another_without_a_loop() {
    let graph = import_graph(&sim_folder());
    assert!(graph.len() > 20, "{} files read", graph.len());
    let textbook = sim_folder().join("textbook.rs");
    assert!(
        graph[&textbook].contains(&sim_folder().join("precomputation.rs")),
        "the reader must see textbook.rs take from precomputation.rs: {:?}",
        graph[&textbook]
    );
    let short = |p: &PathBuf| p.strip_prefix(sim_folder()).unwrap().display().to_string();
    if let Some(cycle) = find_cycle(&graph) {
        let names: Vec<String> = cycle.iter().map(short).collect();
        panic!("import loop: {} → back to the first", names.join(" → "));
    }
}

/// The floors of `src/app`, from the ground up: each file or folder of
/// `src/app` (a folder with its `NAME.rs` is one room) imports only from
/// floors below its own, and from the library.
const APP_FLOORS: [&[&str]; 6] = [
    // the error every layer returns
    &["error"],
    // shared plumbing
    &[
        "flags",
        "limits",
        "progress",
        "timing",
        "file_plan",
        "closed_pipe",
    ],
    // the frames of simulate: their format, their folder (its lock, what it
    // may replace: file_plan) and resuming from them
    &["resume"],
    // subsystems that several commands use
    &["draw", "matrix_input", "analysis"],
    // the commands, one file or folder each
    &[
        "simulate", "render", "view", "converge", "trace", "analyze", "bench", "spy", "etree",
        "generate", "export_q",
    ],
    // the dispatcher
    &["mod"],
];

/// The room of a file of `src/app`: its first name under `src/app`,
/// without `.rs` (`src/app/draw/plot.rs` → `draw`, `src/app/mod.rs` → `mod`).
fn app_room(file: &Path) -> String {
    let relative = file.strip_prefix(app_folder()).unwrap();
    let first = relative.iter().next().unwrap().to_str().unwrap();
    first.trim_end_matches(".rs").to_string()
}

fn app_floor(room: &str) -> usize {
    APP_FLOORS
        .iter()
        .position(|floor| floor.contains(&room))
        .unwrap_or_else(|| panic!("src/app/{room} stands on no floor of APP_FLOORS: declare it"))
}

#[test]
fn the_files_of_app_import_only_from_the_floors_below() {
    let graph = import_graph(&app_folder());
    assert!(graph.len() > 40, "{} files read", graph.len());
    for room in APP_FLOORS.iter().flat_map(|floor| floor.iter()) {
        let (file, folder) = (
            app_folder().join(format!("{room}.rs")),
            app_folder().join(room),
        );
        assert!(
            file.exists() || folder.is_dir(),
            "src/app/{room} is declared but absent"
        );
    }
    let short = |p: &PathBuf| p.strip_prefix(app_folder()).unwrap().display().to_string();
    let mut upward = Vec::new();
    for (from, targets) in &graph {
        let (room, floor) = (app_room(from), app_floor(&app_room(from)));
        for to in targets.iter().filter(|to| app_room(to) != room) {
            if app_floor(&app_room(to)) >= floor {
                upward.push(format!("{} → {}", short(from), short(to)));
            }
        }
    }
    assert!(
        upward.is_empty(),
        "imports that do not run down: {upward:#?}"
    );
    let (tangled, rest) = split_rooms(&graph, &APP_ROOMS_STILL_TANGLED);
    if let Some(cycle) = find_cycle(&rest) {
        let names: Vec<String> = cycle.iter().map(short).collect();
        panic!("import loop: {} → back to the first", names.join(" → "));
    }
    for (room, inside) in tangled {
        assert!(
            find_cycle(&inside).is_some(),
            "src/app/{room} has no import loop any more: take it off APP_ROOMS_STILL_TANGLED"
        );
    }
}

/// Rooms of `src/app` whose own files still import one another in a loop
/// (a command file and the helpers it declares, which take back from it):
/// the floors hold between rooms, and no loop runs through any other room;
/// the test fails when one of these is untangled, so that the list only
/// shrinks.
const APP_ROOMS_STILL_TANGLED: [&str; 0] = [];

/// `graph` without the imports inside the rooms `tangled`, and for each of
/// those rooms, the graph of its own files.
#[allow(clippy::type_complexity)]
fn split_rooms(
    graph: &BTreeMap<PathBuf, BTreeSet<PathBuf>>,
    tangled: &[&str],
) -> (
    Vec<(String, BTreeMap<PathBuf, BTreeSet<PathBuf>>)>,
    BTreeMap<PathBuf, BTreeSet<PathBuf>>,
) {
    let inside = |from: &PathBuf, to: &PathBuf| {
        app_room(from) == app_room(to) && tangled.contains(&app_room(from).as_str())
    };
    let rest = graph
        .iter()
        .map(|(from, targets)| {
            let kept = targets.iter().filter(|to| !inside(from, to)).cloned();
            (from.clone(), kept.collect())
        })
        .collect();
    let rooms = tangled
        .iter()
        .map(|room| {
            let files = graph.iter().filter(|(from, _)| app_room(from) == *room);
            let own = files.map(|(from, targets)| {
                let kept = targets.iter().filter(|to| app_room(to) == *room).cloned();
                (from.clone(), kept.collect())
            });
            (room.to_string(), own.collect())
        })
        .collect();
    (rooms, rest)
}

#[test]
fn the_app_check_sees_an_import_written_without_use() {
    let graph = import_graph(&app_folder());
    let dispatcher = app_folder().join("mod.rs");
    assert!(
        graph[&dispatcher].contains(&app_folder().join("simulate.rs")),
        "mod.rs calls simulate::run: {:?}",
        graph[&dispatcher]
    );
}

#[test]
fn linalg_imports_only_std_and_itself() {
    let linalg = src_folder().join("linalg");
    let mut outside = Vec::new();
    for file in rust_files(&linalg) {
        for (module, path) in uses(&file) {
            let first = path.split("::").next().unwrap();
            let inside = match resolve(&module, &path) {
                _ if ["std", "core", "alloc"].contains(&first) => true,
                Some(resolved) if ["crate", "super", "self"].contains(&first) => {
                    resolved.first().is_some_and(|name| name == "linalg")
                }
                _ => child_modules(&code_of(&file)).iter().any(|c| c == first),
            };
            if !inside {
                outside.push(format!("{}: {path}", file.display()));
            }
        }
    }
    assert!(
        outside.is_empty(),
        "linalg imports from outside: {outside:#?}"
    );
}

#[test]
fn the_loop_finder_finds_a_loop() {
    let (a, b) = (PathBuf::from("a.rs"), PathBuf::from("b.rs"));
    let mut graph = BTreeMap::new();
    graph.insert(a.clone(), BTreeSet::from([b.clone()]));
    graph.insert(b.clone(), BTreeSet::from([a.clone()]));
    assert_eq!(find_cycle(&graph), Some(vec![a, b]));
}

/// Each function of `text`: its name and its length in lines, from `fn`
/// to its closing brace (a brace in a character literal, `'{'`, is none).
fn functions(text: &str) -> Vec<(String, usize)> {
    let text = text.replace("'{'", "").replace("'}'", "");
    let lines: Vec<&str> = text.lines().collect();
    let mut found = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let code = lines[i].split("//").next().unwrap();
        let Some(name) = function_name(code) else {
            i += 1;
            continue;
        };
        let (mut depth, mut opened, mut end) = (0i32, false, i);
        for (j, line) in lines.iter().enumerate().skip(i) {
            let code = line.split("//").next().unwrap();
            depth += code.matches('{').count() as i32 - code.matches('}').count() as i32;
            opened |= code.contains('{');
            end = j;
            if (opened && depth == 0) || (!opened && code.trim_end().ends_with(';')) {
                break;
            }
        }
        if opened {
            found.push((name, end - i + 1));
        }
        i = end + 1;
    }
    found
}

/// The name of the function a line declares, if it does.
fn function_name(code: &str) -> Option<String> {
    let words: Vec<&str> = code.split_whitespace().collect();
    let at = words.iter().position(|&w| w == "fn")?;
    let before_ok = words[..at]
        .iter()
        .all(|w| w.starts_with("pub") || ["const", "unsafe", "extern", "async"].contains(w));
    let name = words.get(at + 1)?.split(['<', '(']).next()?;
    before_ok.then(|| name.to_string())
}

#[test]
fn no_function_in_src_is_longer_than_60_lines() {
    let mut long = Vec::new();
    let mut count = 0;
    for file in rust_files(&src_folder()) {
        for (name, lines) in functions(&std::fs::read_to_string(&file).unwrap()) {
            count += 1;
            if lines > 60 {
                long.push(format!("{} {name}: {lines} lines", file.display()));
            }
        }
    }
    assert!(count > 1000, "only {count} functions found");
    assert!(long.is_empty(), "{long:#?}");
}

#[test]
fn the_handouts_sparse_step_fits_in_40_lines() {
    let text = std::fs::read_to_string(sim_folder().join("textbook.rs")).unwrap();
    let step = functions(&text)
        .into_iter()
        .find(|(name, _)| name == "fast_mass_springs_step_sparse")
        .expect("textbook.rs holds fast_mass_springs_step_sparse");
    assert!(step.1 <= 40, "{} lines", step.1);
}

#[test]
fn the_function_measure_counts_a_function_from_fn_to_its_brace() {
    let text = "/// doc\npub fn a(x: u8) -> u8 {\n    if x > 0 {\n        1\n    } else { 0 }\n}\nfn b();\n";
    assert_eq!(functions(text), vec![("a".to_string(), 5)]);
}
