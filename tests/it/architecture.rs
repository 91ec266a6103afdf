//! The architecture's invariants (docs/architecture.md), checked on the source:
//! - the paper's rules and the model import nothing from the extensions;
//! - no two files of `src/` import each other, directly or through others;
//! - no file is over 600 lines and no function over 80, unless a comment says why
//!   (`// long-file: why` anywhere in the file, `// long-fn: why` on the line above the `fn`).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

const MAX_FILE_LINES: usize = 600;
const MAX_FN_LINES: usize = 80;

/// Every `.rs` file under `src/`, by its path relative to `src/`, with its text.
fn sources() -> BTreeMap<String, String> {
    fn walk(dir: &Path, root: &Path, out: &mut BTreeMap<String, String>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                walk(&path, root, out);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let rel = path
                    .strip_prefix(root)
                    .unwrap()
                    .to_string_lossy()
                    .replace('\\', "/");
                out.insert(rel, std::fs::read_to_string(&path).unwrap());
            }
        }
    }
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut out = BTreeMap::new();
    walk(&root, &root, &mut out);
    out
}

/// `text` without its comments and without its unit-test module (what the file itself uses).
fn code_of(text: &str) -> String {
    let text = match text.find("#[cfg(test)]\nmod tests") {
        Some(i) => &text[..i],
        None => text,
    };
    text.lines()
        .map(|l| match l.find("//") {
            Some(i) => &l[..i],
            None => l,
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The binary's files (`src/main.rs` and the modules it declares), which reach the library as
/// `sonarmap::`.
fn in_binary(rel: &str) -> bool {
    let roots = ["main.rs", "cli.rs", "convert.rs", "figure_args.rs"];
    roots.contains(&rel) || rel.starts_with("cli/")
}

/// The module path of file `rel`: `("lib" | "bin", segments)`.
fn module_of(rel: &str) -> (&'static str, Vec<String>) {
    let crate_name = if in_binary(rel) { "bin" } else { "lib" };
    let mut parts: Vec<String> = rel
        .trim_end_matches(".rs")
        .split('/')
        .map(String::from)
        .collect();
    if matches!(
        parts.last().map(String::as_str),
        Some("mod" | "lib" | "main")
    ) {
        parts.pop();
    }
    (crate_name, parts)
}

/// `use` trees flattened: `a::{b, c::{d}}` to `a::b`, `a::c::d`.
fn flatten(tree: &str) -> Vec<String> {
    let tree = tree.trim();
    let Some(open) = tree.find('{') else {
        return vec![tree.split(" as ").next().unwrap().trim().to_string()];
    };
    let prefix = tree[..open].trim_end_matches("::");
    let body = &tree[open + 1..tree.rfind('}').unwrap()];
    let (mut items, mut depth, mut current) = (Vec::new(), 0, String::new());
    for c in body.chars() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            _ => {}
        }
        if c == ',' && depth == 0 {
            items.push(std::mem::take(&mut current));
        } else {
            current.push(c);
        }
    }
    items.push(current);
    items
        .iter()
        .filter(|i| !i.trim().is_empty())
        .flat_map(|i| flatten(i))
        .map(|i| {
            if i == "self" {
                prefix.to_string()
            } else {
                format!("{prefix}::{i}")
            }
        })
        .collect()
}

/// The paths a file's code names: its `use` trees and the `crate::`/`super::`/`sonarmap::`
/// paths written inline.
fn paths_in(code: &str) -> Vec<String> {
    let mut paths = Vec::new();
    let mut rest = code;
    while let Some(i) = rest.find("use ") {
        let before = rest[..i].chars().last();
        let after = &rest[i + 4..];
        rest = after;
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
            continue;
        }
        if let Some(end) = after.find(';') {
            paths.extend(flatten(&after[..end]));
        }
    }
    for start in ["crate::", "super::", "sonarmap::"] {
        let mut from = 0;
        while let Some(i) = code[from..].find(start) {
            let at = from + i;
            from = at + start.len();
            let before = code[..at].chars().last();
            if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':') {
                continue;
            }
            let end = code[at..]
                .find(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':'))
                .map_or(code.len(), |e| at + e);
            paths.push(code[at..end].trim_end_matches(':').to_string());
        }
    }
    paths
}

/// The file-level import graph of `src/`: each file to the files its code names. A name
/// re-exported by a `mod.rs` (or `lib.rs`) counts as the file that defines it.
fn import_graph(files: &BTreeMap<String, String>) -> BTreeMap<String, BTreeSet<String>> {
    let modules: BTreeMap<(&str, Vec<String>), &String> =
        files.keys().map(|rel| (module_of(rel), rel)).collect();
    let resolve = |crate_name: &'static str, path: &[String]| -> Option<(String, usize)> {
        (0..=path.len()).rev().find_map(|n| {
            modules
                .get(&(crate_name, path[..n].to_vec()))
                .map(|rel| ((*rel).clone(), n))
        })
    };
    let absolute = |rel: &str, path: &str| -> Option<(&'static str, Vec<String>)> {
        let (mut crate_name, here) = module_of(rel);
        let mut segments: Vec<String> = path
            .split("::")
            .filter(|s| !s.is_empty() && *s != "self")
            .map(String::from)
            .collect();
        let mut base = match segments.first().map(String::as_str) {
            Some("crate") => Vec::new(),
            Some("sonarmap") => {
                crate_name = "lib";
                Vec::new()
            }
            Some("super") => here.clone(),
            _ => return None,
        };
        if segments[0] == "super" {
            while segments.first().is_some_and(|s| s == "super") {
                base.pop();
                segments.remove(0);
            }
        } else {
            segments.remove(0);
        }
        base.extend(segments);
        Some((crate_name, base))
    };
    // Names re-exported by module files: (file, name) to the defining file.
    let mut reexports: BTreeMap<(String, String), String> = BTreeMap::new();
    for (rel, text) in files {
        if !matches!(
            rel.rsplit('/').next(),
            Some("mod.rs" | "lib.rs" | "main.rs")
        ) {
            continue;
        }
        let code = code_of(text);
        for line in code.split(';') {
            let line = line.trim();
            let Some(tree) = line
                .strip_prefix("pub use ")
                .or_else(|| line.strip_prefix("pub(crate) use "))
            else {
                continue;
            };
            for path in flatten(tree) {
                let path = if path.starts_with("crate::") || path.starts_with("super::") {
                    path
                } else {
                    format!("self::{path}")
                };
                let full = match path.strip_prefix("self::") {
                    Some(local) => Some((module_of(rel).0, {
                        let mut m = module_of(rel).1;
                        m.extend(local.split("::").map(String::from));
                        m
                    })),
                    None => absolute(rel, &path),
                };
                if let Some((c, segments)) = full {
                    if let Some((target, _)) = resolve(c, &segments) {
                        if target != *rel {
                            let name = segments.last().unwrap().clone();
                            reexports.insert((rel.clone(), name), target);
                        }
                    }
                }
            }
        }
    }
    let mut graph = BTreeMap::new();
    for (rel, text) in files {
        let mut targets = BTreeSet::new();
        for path in paths_in(&code_of(text)) {
            let Some((c, segments)) = absolute(rel, &path) else {
                continue;
            };
            let Some((mut target, used)) = resolve(c, &segments) else {
                continue;
            };
            if let Some(name) = segments.get(used) {
                if let Some(defining) = reexports.get(&(target.clone(), name.clone())) {
                    target = defining.clone();
                }
            }
            if target != *rel {
                targets.insert(target);
            }
        }
        graph.insert(rel.clone(), targets);
    }
    graph
}

/// The strongly connected components of more than one file (Tarjan).
fn cycles(graph: &BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    struct State<'a> {
        graph: &'a BTreeMap<String, BTreeSet<String>>,
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        on_stack: BTreeSet<&'a str>,
        found: Vec<Vec<String>>,
    }
    fn visit<'a>(s: &mut State<'a>, v: &'a str) {
        let n = s.index.len();
        s.index.insert(v, n);
        s.low.insert(v, n);
        s.stack.push(v);
        s.on_stack.insert(v);
        for w in s.graph.get(v).into_iter().flatten() {
            let w = w.as_str();
            if !s.index.contains_key(w) {
                visit(s, w);
                let low = s.low[v].min(s.low[w]);
                s.low.insert(v, low);
            } else if s.on_stack.contains(w) {
                let low = s.low[v].min(s.index[w]);
                s.low.insert(v, low);
            }
        }
        if s.low[v] == s.index[v] {
            let mut component = Vec::new();
            while let Some(w) = s.stack.pop() {
                s.on_stack.remove(w);
                component.push(w.to_string());
                if w == v {
                    break;
                }
            }
            if component.len() > 1 {
                component.sort();
                s.found.push(component);
            }
        }
    }
    let mut s = State {
        graph,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        found: Vec::new(),
    };
    for v in graph.keys() {
        if !s.index.contains_key(v.as_str()) {
            visit(&mut s, v);
        }
    }
    s.found
}

#[test]
fn the_paper_and_the_model_import_nothing_from_the_extensions() {
    let files = sources();
    let graph = import_graph(&files);
    let mut offending = Vec::new();
    for (rel, targets) in &graph {
        let core = rel.starts_with("mapping/paper/") || rel.starts_with("mapping/model/");
        for t in targets
            .iter()
            .filter(|t| core && t.starts_with("mapping/ext/"))
        {
            offending.push(format!("{rel} imports {t}"));
        }
    }
    assert!(
        graph["mapping/paper/update.rs"].contains("mapping/paper/fit.rs"),
        "the graph sees the paper's own imports"
    );
    assert_eq!(offending, Vec::<String>::new());
}

#[test]
fn no_two_files_of_src_import_each_other() {
    let files = sources();
    let graph = import_graph(&files);
    assert!(
        graph["mapping/mapper.rs"].contains("mapping/model/map.rs"),
        "the graph follows the re-exports of mod.rs"
    );
    assert_eq!(cycles(&graph), Vec::<Vec<String>>::new());
}

#[test]
fn the_cycle_finder_finds_a_cycle_through_three_files() {
    let edge = |a: &str, b: &[&str]| (a.to_string(), b.iter().map(|s| s.to_string()).collect());
    let graph: BTreeMap<String, BTreeSet<String>> = [
        edge("a", &["b"]),
        edge("b", &["c"]),
        edge("c", &["a", "d"]),
        edge("d", &[]),
    ]
    .into();
    assert_eq!(cycles(&graph), vec![vec!["a", "b", "c"]]);
    let files: BTreeMap<String, String> = [
        ("lib.rs".to_string(), "pub mod x;\npub mod y;\n".to_string()),
        (
            "x.rs".to_string(),
            "use crate::y::Y;\npub struct X;\n".to_string(),
        ),
        (
            "y.rs".to_string(),
            "use super::x::{X};\npub struct Y;\n".to_string(),
        ),
    ]
    .into();
    assert_eq!(cycles(&import_graph(&files)), vec![vec!["x.rs", "y.rs"]]);
}

/// The functions of `text` longer than [`MAX_FN_LINES`] without a `// long-fn:` comment above.
fn long_functions(text: &str) -> Vec<(String, usize)> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let line = lines[i];
        let trimmed = line.trim_start();
        let indent = line.len() - trimmed.len();
        let signature = trimmed
            .trim_start_matches("pub ")
            .trim_start_matches("pub(crate) ")
            .trim_start_matches("pub(super) ")
            .trim_start_matches("const ")
            .trim_start_matches("unsafe ");
        let is_fn = signature.starts_with("fn ")
            || (signature.starts_with("pub(in ") && signature.contains(") fn "));
        if !is_fn {
            i += 1;
            continue;
        }
        let name = signature
            .split("fn ")
            .nth(1)
            .and_then(|s| s.split(|c: char| !(c.is_alphanumeric() || c == '_')).next())
            .unwrap_or("")
            .to_string();
        let mut open = i;
        while open < lines.len() && !lines[open].trim_end().ends_with('{') {
            if lines[open].trim_end().ends_with(';') {
                break;
            }
            open += 1;
        }
        if open >= lines.len() || lines[open].trim_end().ends_with(';') {
            i = open + 1;
            continue;
        }
        let close_prefix = format!("{}}}", " ".repeat(indent));
        let close = (open + 1..lines.len())
            .find(|&k| lines[k].starts_with(&close_prefix))
            .unwrap_or(lines.len() - 1);
        let length = close - i + 1;
        let excused = i > 0 && {
            let mut k = i;
            while k > 0 && lines[k - 1].trim_start().starts_with("#[") {
                k -= 1;
            }
            (k.saturating_sub(12)..k).any(|j| lines[j].contains("// long-fn:"))
        };
        if length > MAX_FN_LINES && !excused {
            out.push((name, length));
        }
        i = close + 1;
    }
    out
}

#[test]
fn no_file_is_over_600_lines_nor_function_over_80_unless_a_comment_says_why() {
    let mut over = Vec::new();
    for (rel, text) in sources() {
        let lines = text.lines().count();
        if lines > MAX_FILE_LINES && !text.contains("// long-file:") {
            over.push(format!("{rel}: {lines} lines"));
        }
        for (name, length) in long_functions(&text) {
            over.push(format!("{rel}: fn {name}, {length} lines"));
        }
    }
    assert_eq!(over, Vec::<String>::new());
}

#[test]
fn a_long_function_is_found_and_a_comment_excuses_it() {
    let body = "    x();\n".repeat(MAX_FN_LINES);
    let text = format!("fn long() {{\n{body}}}\nfn short() {{\n}}\n");
    assert_eq!(
        long_functions(&text),
        vec![("long".to_string(), MAX_FN_LINES + 2)]
    );
    let excused = format!("// long-fn: one table, read top to bottom\n{text}");
    assert!(long_functions(&excused).is_empty());
}
