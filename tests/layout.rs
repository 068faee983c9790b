//! The source tree's shape: no import cycles between modules, and no source file that keeps
//! growing. Read from the files on disk, so a new module is checked the day it is added.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Every `.rs` file under `dir`, sorted.
fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut dirs = vec![dir.to_path_buf()];
    while let Some(d) = dirs.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                dirs.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

/// `src/gpu/world.rs` -> `["gpu", "world"]`; `src/gpu/mod.rs` -> `["gpu"]`; `src/lib.rs` -> `[]`.
fn module_of(src: &Path, file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(src).unwrap().with_extension("");
    let mut parts: Vec<String> = rel
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    if matches!(
        parts.last().map(String::as_str),
        Some("mod" | "lib" | "main")
    ) {
        parts.pop();
    }
    parts
}

/// The code of a file without its comments (doc links name modules without using them).
fn code_of(text: &str) -> String {
    text.lines()
        .map(|line| match line.find("//") {
            Some(at) => &line[..at],
            None => line,
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// Expands a use tree (`a::{b, c::{d, e}}`) into its paths.
fn expand(tree: &str) -> Vec<String> {
    let tree = tree.trim();
    let Some(open) = tree.find('{') else {
        return vec![tree.to_string()];
    };
    let prefix = &tree[..open];
    let inner = &tree[open + 1..tree.rfind('}').expect("a use tree's closing brace")];
    let mut parts = Vec::new();
    let (mut depth, mut start) = (0, 0);
    for (i, c) in inner.char_indices() {
        match c {
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
        .filter(|p| !p.trim().is_empty())
        .flat_map(|p| expand(p).into_iter().map(|q| format!("{prefix}{q}")))
        .collect()
}

/// The absolute module paths a file names: its `use` trees and its inline `crate::`/`super::`
/// paths, each as segments (`self` and `super` resolved against `module`).
fn paths_named(module: &[String], is_mod_file: bool, code: &str) -> BTreeSet<Vec<String>> {
    let mut raw = Vec::new();
    let mut rest = code;
    while let Some(at) = rest.find("use ") {
        let before = rest[..at].chars().last();
        rest = &rest[at + 4..];
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
            continue;
        }
        let Some(end) = rest.find(';') else { break };
        let tree: String = rest[..end].split_whitespace().collect();
        raw.extend(expand(&tree));
    }
    for start in ["crate::", "super::"] {
        let mut rest = code;
        while let Some(at) = rest.find(start) {
            let before = rest[..at].chars().last();
            let tail = &rest[at..];
            let len = tail
                .find(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':'))
                .unwrap_or(tail.len());
            if !before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':') {
                raw.push(tail[..len].to_string());
            }
            rest = &rest[at + start.len()..];
        }
    }
    // A `mod.rs` file is its module's directory: `super` from it is the parent.
    let here: Vec<String> = module.to_vec();
    raw.into_iter()
        .filter_map(|path| {
            let segs: Vec<&str> = path.split("::").filter(|s| !s.is_empty()).collect();
            let mut out: Vec<String> = match segs.first()? {
                &"crate" => Vec::new(),
                &"super" | &"self" => here.clone(),
                _ if is_mod_file => here.clone(),
                _ => return None,
            };
            let mut first = true;
            for seg in segs {
                match seg {
                    "crate" if first => {}
                    "self" if first => {}
                    "super" => {
                        out.pop();
                    }
                    s => out.push(s.to_string()),
                }
                first = false;
            }
            Some(out)
        })
        .collect()
}

fn is_ancestor(a: &[String], b: &[String]) -> bool {
    a.len() <= b.len() && b[..a.len()] == *a
}

/// The `pub use` statements of `code`, alone.
fn reexports_of(code: &str) -> String {
    let mut out = String::new();
    let mut rest = code;
    while let Some(at) = rest.find("pub use ") {
        rest = &rest[at + 4..];
        let Some(end) = rest.find(';') else { break };
        out.push_str(&rest[..=end]);
        out.push('\n');
    }
    out
}

/// The longest prefix of `path` that is a module of the crate.
fn module_prefix(modules: &BTreeSet<Vec<String>>, path: &[String]) -> Vec<String> {
    (0..=path.len())
        .rev()
        .map(|n| path[..n].to_vec())
        .find(|p| modules.contains(p))
        .unwrap_or_default()
}

/// The modules (`a::b`) each module names, leaving out its own ancestors and descendants. A
/// name a module re-exports (`pub use`) counts as a use of the module that defines it, so an
/// import through a parent's re-export is not hidden by the ancestor rule.
fn module_graph(src: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let files = rust_files(src);
    let modules: BTreeSet<Vec<String>> = files.iter().map(|f| module_of(src, f)).collect();
    let read: Vec<(Vec<String>, bool, String)> = files
        .iter()
        .map(|file| {
            let is_mod_file = file
                .file_name()
                .is_some_and(|n| n == "mod.rs" || n == "lib.rs");
            let code = code_of(&std::fs::read_to_string(file).unwrap());
            (module_of(src, file), is_mod_file, code)
        })
        .collect();
    // (module, name) -> the module the name comes from, followed through chains of re-exports.
    let mut reexported: BTreeMap<(Vec<String>, String), Vec<String>> = BTreeMap::new();
    for (module, is_mod_file, code) in &read {
        for path in paths_named(module, *is_mod_file, &reexports_of(code)) {
            if let Some(name) = path.last() {
                let from = module_prefix(&modules, &path);
                if from != *module {
                    reexported.insert((module.clone(), name.clone()), from);
                }
            }
        }
    }
    let resolve = |path: &[String]| {
        let mut target = module_prefix(&modules, path);
        if let Some(name) = path.get(target.len()) {
            for _ in 0..8 {
                match reexported.get(&(target.clone(), name.clone())) {
                    Some(from) => target = from.clone(),
                    None => break,
                }
            }
        }
        target
    };
    let mut graph = BTreeMap::new();
    for (module, is_mod_file, code) in &read {
        let edges: &mut BTreeSet<String> = graph.entry(module.join("::")).or_default();
        for path in paths_named(module, *is_mod_file, code) {
            let target = resolve(&path);
            if !is_ancestor(&target, module) && !is_ancestor(module, &target) {
                edges.insert(target.join("::"));
            }
        }
    }
    graph
}

/// The cycles of `graph`, each as the modules around it (one per strongly connected group).
fn cycles(graph: &BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    let reach = |from: &str| {
        let mut seen = BTreeSet::new();
        let mut todo = vec![from.to_string()];
        while let Some(m) = todo.pop() {
            for next in graph.get(&m).into_iter().flatten() {
                if seen.insert(next.clone()) {
                    todo.push(next.clone());
                }
            }
        }
        seen
    };
    let reached: BTreeMap<&String, BTreeSet<String>> =
        graph.keys().map(|m| (m, reach(m))).collect();
    let mut groups: Vec<Vec<String>> = Vec::new();
    for m in graph.keys() {
        if !reached[m].contains(m) || groups.iter().any(|g| g.contains(m)) {
            continue;
        }
        let group: Vec<String> = graph
            .keys()
            .filter(|n| reached[m].contains(*n) && reached[*n].contains(m))
            .cloned()
            .collect();
        groups.push(group);
    }
    groups
}

/// The workspace's crates: the core (this package, at the root) and the front ends under
/// crates/, read from the disk so that a new crate is checked the day it is added.
fn crate_roots() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut roots = vec![root.to_path_buf()];
    let mut members: Vec<PathBuf> = std::fs::read_dir(root.join("crates"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.join("Cargo.toml").is_file())
        .collect();
    members.sort();
    assert!(members.len() >= 3, "the front-end crates: {members:?}");
    roots.extend(members);
    roots
}

#[test]
fn no_module_imports_one_that_imports_it_back() {
    // Crates cannot import each other in a cycle (Cargo refuses); modules within each can.
    let mut found = Vec::new();
    let mut graph = BTreeMap::new();
    for root in crate_roots() {
        let name = root.file_name().unwrap().to_string_lossy().into_owned();
        let crate_graph = module_graph(&root.join("src"));
        if root == Path::new(env!("CARGO_MANIFEST_DIR")) {
            assert!(
                crate_graph.contains_key("gpu::world"),
                "{:?}",
                crate_graph.keys()
            );
        }
        for group in cycles(&crate_graph) {
            found.push(
                group
                    .iter()
                    .map(|m| format!("{name}:{m}"))
                    .collect::<Vec<_>>(),
            );
        }
        for (m, to) in crate_graph {
            let to: BTreeSet<String> = to.into_iter().map(|n| format!("{name}:{n}")).collect();
            graph.insert(format!("{name}:{m}"), to);
        }
    }
    let described: Vec<String> = found
        .iter()
        .map(|group| {
            let edges: Vec<String> = group
                .iter()
                .flat_map(|m| {
                    graph[m]
                        .iter()
                        .filter(|n| group.contains(n))
                        .map(move |n| format!("{m} -> {n}"))
                })
                .collect();
            format!("{{{}}}: {}", group.join(", "), edges.join(", "))
        })
        .collect();
    assert!(
        found.is_empty(),
        "import cycles (break each by moving the shared type to a module both can use):\n{}",
        described.join("\n")
    );
}

#[test]
fn the_cycle_check_finds_a_cycle() {
    // The check itself, on a made-up graph: a -> b -> c -> a is one cycle; d stands apart.
    let graph: BTreeMap<String, BTreeSet<String>> = [
        ("a", vec!["b"]),
        ("b", vec!["c"]),
        ("c", vec!["a", "d"]),
        ("d", vec![]),
    ]
    .into_iter()
    .map(|(m, to)| (m.into(), to.into_iter().map(String::from).collect()))
    .collect();
    assert_eq!(cycles(&graph), vec![vec!["a", "b", "c"]]);
    assert_eq!(
        expand("crate::gpu::{world::{World,WorldView},raster::Raster}"),
        vec![
            "crate::gpu::world::World",
            "crate::gpu::world::WorldView",
            "crate::gpu::raster::Raster"
        ]
    );
    assert_eq!(
        reexports_of("use a::B; pub use c::{D, e::F}; pub(crate) fn g() {}"),
        "use c::{D, e::F};\n"
    );
    let module = vec!["gpu".to_string(), "world".to_string()];
    assert_eq!(
        paths_named(&module, false, "use super::visibility::Visibility;"),
        BTreeSet::from([vec![
            "gpu".to_string(),
            "visibility".into(),
            "Visibility".into()
        ]])
    );
}

/// Files already over [`LONGEST`] lines, each with the length it may not grow past until it
/// is split (lower a limit when its file shrinks; remove the entry once it fits).
const TOO_LONG: &[(&str, usize)] = &[];

/// A source file's longest length: past it a file does more than one thing.
const LONGEST: usize = 800;

#[test]
fn no_source_file_grows_past_its_limit() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut over = Vec::new();
    let dirs = crate_roots()
        .into_iter()
        .flat_map(|c| ["src", "tests", "examples"].map(|d| c.join(d)))
        .filter(|d| d.is_dir());
    for dir in dirs {
        for file in rust_files(&dir) {
            let name = file
                .strip_prefix(root)
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/");
            let lines = std::fs::read_to_string(&file).unwrap().lines().count();
            let limit = TOO_LONG
                .iter()
                .find(|(n, _)| *n == name)
                .map_or(LONGEST, |(_, l)| *l);
            if lines > limit {
                over.push(format!("{name}: {lines} lines (limit {limit})"));
            }
        }
    }
    assert!(over.is_empty(), "split these files:\n{}", over.join("\n"));
}
