//! The shape of the simulation's code, checked from its source:
//!
//! * the files of `src/sim` import one another without a loop: data flows
//!   one way, from the vocabulary and the kernels up to the simulation (a
//!   file that used a re-export of `sim/mod.rs` would close a loop through
//!   it, so each file names the file it takes from);
//! * no function in `src/sim` is longer than 60 lines;
//! * the handout's step, `fast_mass_springs_step_sparse`, fits in 40.
//!
//! The `use` lines are read as text: braces expanded, `super::`, `self::`
//! and `crate::` resolved against the folder layout (a `mod name {` inside
//! a file is followed, so that its `super::` means the file itself).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

fn sim_folder() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src/sim")
}

/// Every `.rs` file under `folder`.
fn rust_files(folder: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(folder).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            files.extend(rust_files(&path));
        } else if path.extension().is_some_and(|e| e == "rs") {
            files.push(path);
        }
    }
    files.sort();
    files
}

/// The module path of a file: `src/sim/methods/plain.rs` → `sim::methods::plain`,
/// `src/sim/methods/mod.rs` → `sim::methods`.
fn module_of(file: &Path) -> Vec<String> {
    let relative = file.strip_prefix(sim_folder()).unwrap();
    let mut path = vec!["sim".to_string()];
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

/// The `use` trees of a file's code (tests excluded), each with the module
/// path it is written in (a file's inline `mod name {` included).
fn uses(file: &Path) -> Vec<(Vec<String>, String)> {
    let text = std::fs::read_to_string(file).unwrap();
    let code = text.split("#[cfg(test)]").next().unwrap();
    let (mut found, mut inline, mut depth) = (Vec::new(), Vec::<(String, i32)>::new(), 0);
    let mut pending: Option<String> = None;
    for line in code.lines() {
        let line = line.split("//").next().unwrap().trim();
        if let Some(tree) = pending.as_mut() {
            tree.push_str(line);
        } else if let Some(rest) = line.strip_prefix("use ").or(line.strip_prefix("pub use ")) {
            pending = Some(rest.to_string());
        } else if let Some(name) = inline_module(line) {
            inline.push((name, depth));
        }
        if let Some(tree) = pending.take_if(|t| t.ends_with(';')) {
            let mut module = module_of(file);
            module.extend(inline.iter().map(|(name, _)| name.clone()));
            found.push((module, tree.trim_end_matches(';').to_string()));
        }
        depth += line.matches('{').count() as i32 - line.matches('}').count() as i32;
        inline.retain(|&(_, opened)| depth > opened);
    }
    found
}

/// `mod name {` (not `mod name;`): the name.
fn inline_module(line: &str) -> Option<String> {
    let rest = line.trim_start_matches("pub(crate) ").trim_start_matches("pub ");
    let name = rest.strip_prefix("mod ")?.strip_suffix('{')?.trim();
    Some(name.to_string())
}

/// The file of `src/sim` that a use path (written in `module`) takes from,
/// if any: the longest prefix of the resolved path that is a file.
fn target(module: &[String], path: &str, files: &BTreeMap<Vec<String>, PathBuf>) -> Option<PathBuf> {
    let mut resolved: Vec<String> = Vec::new();
    for (i, segment) in path.split("::").enumerate() {
        match (i, segment) {
            (0, "crate") => {}
            (0, "super") => resolved = module[..module.len() - 1].to_vec(),
            (0, "self") => resolved = module.to_vec(),
            (0, _) => return None, // std, another crate
            (_, "super") => {
                resolved.pop();
            }
            (_, "self") => {}
            _ => resolved.push(segment.to_string()),
        }
    }
    (1..=resolved.len())
        .rev()
        .find_map(|len| files.get(&resolved[..len]).cloned())
}

/// Which files each file of `src/sim` imports from.
fn import_graph() -> BTreeMap<PathBuf, BTreeSet<PathBuf>> {
    let files: BTreeMap<Vec<String>, PathBuf> = rust_files(&sim_folder())
        .into_iter()
        .map(|f| (module_of(&f), f))
        .collect();
    let mut graph = BTreeMap::new();
    for file in files.values() {
        let mut targets = BTreeSet::new();
        for (module, tree) in uses(file) {
            for path in expand(&tree) {
                let path = path.split(" as ").next().unwrap().to_string();
                if let Some(to) = target(&module, &path, &files).filter(|to| to != file) {
                    targets.insert(to);
                }
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
    let graph = import_graph();
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

#[test]
fn the_loop_finder_finds_a_loop() {
    let (a, b) = (PathBuf::from("a.rs"), PathBuf::from("b.rs"));
    let mut graph = BTreeMap::new();
    graph.insert(a.clone(), BTreeSet::from([b.clone()]));
    graph.insert(b.clone(), BTreeSet::from([a.clone()]));
    assert_eq!(find_cycle(&graph), Some(vec![a, b]));
}

/// Each function of `text`: its name and its length in lines, from `fn`
/// to its closing brace.
fn functions(text: &str) -> Vec<(String, usize)> {
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
    let before_ok = words[..at].iter().all(|w| {
        w.starts_with("pub") || ["const", "unsafe", "extern", "async"].contains(w)
    });
    let name = words.get(at + 1)?.split(['<', '(']).next()?;
    before_ok.then(|| name.to_string())
}

#[test]
fn no_function_in_sim_is_longer_than_60_lines() {
    let mut long = Vec::new();
    let mut count = 0;
    for file in rust_files(&sim_folder()) {
        for (name, lines) in functions(&std::fs::read_to_string(&file).unwrap()) {
            count += 1;
            if lines > 60 {
                long.push(format!("{} {name}: {lines} lines", file.display()));
            }
        }
    }
    assert!(count > 200, "only {count} functions found");
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
