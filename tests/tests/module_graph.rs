//! No module cycles: in `gpu-backend`, `render-model` and `mesher` (every folder of each), no
//! module imports, through others, a module that imports it, so each can be read after the
//! ones it uses.
//!
//! The graph is read from the sources. Every path that starts with `crate::`, `super::` or
//! `self::` outside comments (`use` groups included) is resolved from the file's own module to
//! an absolute module path. For a folder `F`, module `A` of `F` depends on module `B` of `F`
//! when a file inside `A` names a path inside `F::B`.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::Path;

/// A source file: its module path (`render/far/splat.rs` is `[render, far, splat]`,
/// `render/far/mod.rs` is `[render, far]`, `lib.rs` is `[]`) and its text without comments.
struct Source {
    module: Vec<String>,
    code: String,
}

/// Every `.rs` file under `src`.
fn sources(src: &Path) -> Vec<Source> {
    fn walk(dir: &Path, prefix: &[String], out: &mut Vec<Source>) {
        for entry in fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            let name = path.file_stem().unwrap().to_string_lossy().into_owned();
            if path.is_dir() {
                let mut inner = prefix.to_vec();
                inner.push(name);
                walk(&path, &inner, out);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let mut module = prefix.to_vec();
                if name != "mod" && name != "lib" {
                    module.push(name);
                }
                let text = fs::read_to_string(&path).unwrap();
                out.push(Source {
                    module,
                    code: strip_comments(&text),
                });
            }
        }
    }
    let mut out = Vec::new();
    walk(src, &[], &mut out);
    out
}

/// The text with `//` comments removed (doc comments included).
fn strip_comments(text: &str) -> String {
    text.lines()
        .map(|l| l.find("//").map_or(l, |at| &l[..at]))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The leading identifier of `s` and the rest after it.
fn ident(s: &str) -> (&str, &str) {
    let end = s
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .unwrap_or(s.len());
    (&s[..end], &s[end..])
}

/// Expands the path text after a prefix (`a::b::{c, d::e}`) into its paths, segments only
/// (items of any case are kept: the caller matches module names).
fn expand(s: &str, base: &[String], out: &mut Vec<Vec<String>>) {
    let mut path = base.to_vec();
    let mut rest = s;
    loop {
        if let Some(group) = rest.strip_prefix('{') {
            // Split the group at depth-1 commas.
            let mut depth = 0;
            let mut start = 0;
            for (i, c) in group.char_indices() {
                match c {
                    '{' => depth += 1,
                    '}' if depth == 0 => {
                        expand(group[start..i].trim(), &path, out);
                        return;
                    }
                    '}' => depth -= 1,
                    ',' if depth == 0 => {
                        expand(group[start..i].trim(), &path, out);
                        start = i + 1;
                    }
                    _ => {}
                }
            }
            return;
        }
        let (name, after) = ident(rest);
        if name.is_empty() {
            break;
        }
        path.push(name.to_string());
        match after.strip_prefix("::") {
            Some(next) => rest = next,
            None => break,
        }
    }
    out.push(path);
}

/// The absolute module paths a file names.
fn named_paths(source: &Source) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    let code = &source.code;
    for (at, _) in code.match_indices("crate::") {
        if code[..at].ends_with(|c: char| c.is_ascii_alphanumeric() || c == '_' || c == '$') {
            continue;
        }
        expand(&code[at + "crate::".len()..], &[], &mut out);
    }
    // `self::` and `super::` relative to the file's module.
    let own: &[String] = &source.module;
    for (at, _) in code.match_indices("super::") {
        if code[..at].ends_with(|c: char| c.is_ascii_alphanumeric() || c == '_' || c == ':') {
            continue;
        }
        let mut rest = &code[at..];
        let mut base = own.to_vec();
        // `a/b.rs` is `a::b`, its `super` is `a`; `a/mod.rs` is `a`, its `super` the root.
        while let Some(next) = rest.strip_prefix("super::") {
            base.pop();
            rest = next;
        }
        expand(rest, &base, &mut out);
    }
    for (at, _) in code.match_indices("self::") {
        if code[..at].ends_with(|c: char| c.is_ascii_alphanumeric() || c == '_' || c == ':') {
            continue;
        }
        expand(&code[at + "self::".len()..], own, &mut out);
    }
    out
}

/// Folder path -> (module -> the sibling modules it depends on), for every folder with at
/// least two child modules.
fn graphs(src: &Path) -> BTreeMap<Vec<String>, BTreeMap<String, BTreeSet<String>>> {
    let files = sources(src);
    // The modules that exist: every file's module and every prefix of it.
    let mut children: BTreeMap<Vec<String>, BTreeSet<String>> = BTreeMap::new();
    for f in &files {
        for n in 1..=f.module.len() {
            children
                .entry(f.module[..n - 1].to_vec())
                .or_default()
                .insert(f.module[n - 1].clone());
        }
    }
    let mut out: BTreeMap<Vec<String>, BTreeMap<String, BTreeSet<String>>> = BTreeMap::new();
    for f in &files {
        for path in named_paths(f) {
            // For every folder both the file and the path lie in, with different children.
            for depth in 0..f.module.len().min(path.len()) {
                if f.module[..depth] != path[..depth] {
                    break;
                }
                let (from, to) = (&f.module[depth], &path[depth]);
                let folder = &f.module[..depth];
                let siblings = &children[folder];
                if from != to && siblings.contains(to) {
                    out.entry(folder.to_vec())
                        .or_default()
                        .entry(from.clone())
                        .or_default()
                        .insert(to.clone());
                }
                if from != to {
                    break;
                }
            }
        }
    }
    out
}

/// A cycle of `graph`, if it has one (depth-first search).
fn cycle(graph: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        node: &str,
        graph: &BTreeMap<String, BTreeSet<String>>,
        path: &mut Vec<String>,
        done: &mut BTreeSet<String>,
    ) -> Option<Vec<String>> {
        if let Some(at) = path.iter().position(|n| n == node) {
            let mut found = path[at..].to_vec();
            found.push(node.to_string());
            return Some(found);
        }
        if done.contains(node) {
            return None;
        }
        path.push(node.to_string());
        for next in graph.get(node).into_iter().flatten() {
            if let Some(found) = visit(next, graph, path, done) {
                return Some(found);
            }
        }
        path.pop();
        done.insert(node.to_string());
        None
    }
    let mut done = BTreeSet::new();
    graph
        .keys()
        .find_map(|node| visit(node, graph, &mut Vec::new(), &mut done))
}

fn crate_src(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(name)
        .join("src")
}

/// The cycles of the folders `check` accepts, as `folder: a -> b -> a` lines.
fn cycles(src: &Path, check: impl Fn(&[String]) -> bool) -> (usize, Vec<String>) {
    let graphs = graphs(src);
    let mut checked = 0;
    let mut found = Vec::new();
    for (folder, graph) in &graphs {
        if !check(folder) {
            continue;
        }
        checked += graph.values().map(BTreeSet::len).sum::<usize>();
        if let Some(c) = cycle(graph) {
            found.push(format!("{}: {}", folder.join("::"), c.join(" -> ")));
        }
    }
    (checked, found)
}

#[test]
fn gpu_backend_modules_import_each_other_without_cycles() {
    let (edges, found) = cycles(&crate_src("gpu-backend"), |_| true);
    assert!(edges > 50, "only {edges} edges found: the reader is broken");
    assert!(found.is_empty(), "module cycles:\n{}", found.join("\n"));
}

#[test]
fn render_model_modules_import_each_other_without_cycles() {
    let (edges, found) = cycles(&crate_src("render-model"), |_| true);
    assert!(edges > 15, "only {edges} edges found: the reader is broken");
    assert!(found.is_empty(), "module cycles:\n{}", found.join("\n"));
}

#[test]
fn mesher_modules_import_each_other_without_cycles() {
    let (edges, found) = cycles(&crate_src("mesher"), |_| true);
    assert!(edges > 40, "only {edges} edges found: the reader is broken");
    assert!(found.is_empty(), "module cycles:\n{}", found.join("\n"));
}

#[test]
fn the_reader_finds_a_cycle_through_groups_and_supers() {
    let dir = std::env::temp_dir().join(format!("module_graph_{}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(dir.join("a")).unwrap();
    fs::write(dir.join("lib.rs"), "mod a; mod b; mod c;").unwrap();
    fs::write(dir.join("a/mod.rs"), "mod x; mod y;").unwrap();
    // a::x -> a::y (a group), a::y -> c (two supers), c -> a::x (crate path), b is left alone
    // (named only in a comment).
    fs::write(dir.join("a/x.rs"), "use super::{y::Y, z};").unwrap();
    fs::write(dir.join("a/y.rs"), "use super::super::c::C; // crate::b").unwrap();
    fs::write(dir.join("c.rs"), "use crate::a::{x::X};").unwrap();
    fs::write(dir.join("b.rs"), "").unwrap();
    let graphs = graphs(&dir);
    let top = &graphs[&Vec::new()];
    assert_eq!(top["a"], ["c".to_string()].into());
    assert_eq!(top["c"], ["a".to_string()].into());
    assert!(!top.contains_key("b"));
    assert_eq!(
        graphs[&vec!["a".to_string()]]["x"],
        ["y".to_string()].into()
    );
    assert_eq!(cycle(top), Some(["a", "c", "a"].map(String::from).to_vec()));
    fs::remove_dir_all(&dir).unwrap();
}
