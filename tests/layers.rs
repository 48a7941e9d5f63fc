//! The imports of the library point one way: no module imports
//! a module that imports it back, directly or around a circle, and every
//! top-level module imports only the layers below it (docs/explanation/library.md
//! "Layers"); and every figure binary stays a short script.
//!
//! The test reads `src/` as text: the `use crate::…`, `use super::…` and
//! `use self::…` trees and the `crate::…` and `super::…` paths written
//! inline, outside comments and outside the `#[cfg(test)]` module that ends a
//! file. A path counts as an import of the longest module it names.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The layers from the bottom up; a module may import its own layer's
/// modules and those below, never above. Keep README's "Layout" in step.
const LAYERS: [&[&str]; 9] = [
    &["error", "lattice"],
    &["plot", "analysis"],
    &["run"],
    &["ensemble"],
    &["hopper"],
    &["pipe"],
    &["validate", "cli"],
    &["drivers", "report", "experiments"],
    &["speed", "fuzz", "readings_map"],
];

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// `src/pipe/fast/mod.rs` -> `pipe::fast`; `src/lib.rs` -> ``.
fn module_of(src: &Path, file: &Path) -> String {
    let rel = file.strip_prefix(src).unwrap().with_extension("");
    let mut parts: Vec<String> = rel
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    if matches!(parts.last().map(String::as_str), Some("mod" | "lib")) {
        parts.pop();
    }
    parts.join("::")
}

/// The code of a file without comments and without its test module.
fn code(text: &str) -> String {
    let text = text.split("#[cfg(test)]").next().unwrap();
    text.lines()
        .map(|l| l.split("//").next().unwrap())
        .collect::<Vec<_>>()
        .join("\n")
}

/// The paths of a use tree: `a::{b, c::{d, e}}` -> a::b, a::c::d, a::c::e.
fn expand(tree: &str) -> Vec<String> {
    let tree: String = tree.chars().filter(|c| !c.is_whitespace()).collect();
    let mut out = Vec::new();
    expand_into("", &tree, &mut out);
    out
}

fn expand_into(prefix: &str, tree: &str, out: &mut Vec<String>) {
    let mut depth = 0;
    let mut start = 0;
    let bytes = tree.as_bytes();
    let mut parts = Vec::new();
    for (i, &b) in bytes.iter().enumerate() {
        match b {
            b'{' => depth += 1,
            b'}' => depth -= 1,
            b',' if depth == 0 => {
                parts.push(&tree[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    parts.push(&tree[start..]);
    for part in parts.into_iter().filter(|p| !p.is_empty()) {
        match part.find('{') {
            Some(i) => expand_into(
                &format!("{prefix}{}", &part[..i]),
                &part[i + 1..part.len() - 1],
                out,
            ),
            None => out.push(format!("{prefix}{part}")),
        }
    }
}

/// The identifier path that starts `s` (`a::b::C` of `a::b::C::new(…)`).
fn path_at(s: &str) -> String {
    s.chars()
        .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':')
        .collect()
}

/// Every path `code` names below `crate`, with `super` and `self` resolved
/// against `module` (`is_dir`: the file is a `mod.rs` or `lib.rs`).
fn paths(module: &str, is_dir: bool, code: &str) -> Vec<String> {
    let here: Vec<&str> = module.split("::").filter(|s| !s.is_empty()).collect();
    let parent = if is_dir || here.is_empty() {
        here.clone()
    } else {
        here[..here.len() - 1].to_vec()
    };
    let mut out = Vec::new();
    // use trees
    for stmt in code.split("use ").skip(1) {
        let Some(end) = stmt.find(';') else { continue };
        let tree = &stmt[..end];
        for (root, base) in [("crate::", vec![]), ("super::", parent.clone())] {
            if let Some(rest) = tree.trim_start().strip_prefix(root) {
                for p in expand(rest) {
                    out.push(join(&base, &p));
                }
            }
        }
        if let Some(rest) = tree.trim_start().strip_prefix("self::") {
            for p in expand(rest) {
                out.push(join(&here, &p));
            }
        }
    }
    // inline paths
    for (root, base) in [("crate::", vec![]), ("super::", parent)] {
        let mut from = 0;
        while let Some(i) = code[from..].find(root) {
            let at = from + i;
            let before = code[..at].chars().last();
            if !before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':') {
                out.push(join(&base, &path_at(&code[at + root.len()..])));
            }
            from = at + root.len();
        }
    }
    out
}

fn join(base: &[&str], path: &str) -> String {
    let mut parts: Vec<&str> = base.to_vec();
    parts.extend(path.split("::").filter(|s| !s.is_empty()));
    parts.join("::")
}

/// The module graph of `src/`: module -> the modules it imports (not
/// itself, its ancestors or its descendants).
fn graph() -> BTreeMap<String, BTreeSet<String>> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let modules: BTreeSet<String> = files.iter().map(|f| module_of(&src, f)).collect();
    let resolve = |p: &str| -> Option<String> {
        let mut parts: Vec<&str> = p.split("::").collect();
        while !parts.is_empty() {
            let m = parts.join("::");
            if modules.contains(&m) {
                return Some(m);
            }
            parts.pop();
        }
        None
    };
    let mut g: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for f in &files {
        let m = module_of(&src, f);
        let is_dir = matches!(f.file_stem().and_then(|s| s.to_str()), Some("mod" | "lib"));
        let text = std::fs::read_to_string(f).unwrap();
        let entry = g.entry(m.clone()).or_default();
        for p in paths(&m, is_dir, &code(&text)) {
            if let Some(t) = resolve(&p) {
                let related = t == m
                    || t.starts_with(&format!("{m}::"))
                    || m.starts_with(&format!("{t}::"))
                    || m.is_empty();
                if !related {
                    entry.insert(t);
                }
            }
        }
    }
    g
}

/// The circles of `g` (strongly connected components of two or more).
fn circles(g: &BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    // Tarjan, iterative enough for a few hundred modules by recursion
    struct T<'a> {
        g: &'a BTreeMap<String, BTreeSet<String>>,
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        on: BTreeSet<&'a str>,
        out: Vec<Vec<String>>,
    }
    fn visit<'a>(t: &mut T<'a>, v: &'a str) {
        let i = t.index.len();
        t.index.insert(v, i);
        t.low.insert(v, i);
        t.stack.push(v);
        t.on.insert(v);
        if let Some(ws) = t.g.get(v) {
            for w in ws {
                let w = w.as_str();
                if !t.index.contains_key(w) {
                    visit(t, w);
                    let l = t.low[v].min(t.low[w]);
                    t.low.insert(v, l);
                } else if t.on.contains(w) {
                    let l = t.low[v].min(t.index[w]);
                    t.low.insert(v, l);
                }
            }
        }
        if t.low[v] == t.index[v] {
            let mut comp = Vec::new();
            loop {
                let w = t.stack.pop().unwrap();
                t.on.remove(w);
                comp.push(w.to_string());
                if w == v {
                    break;
                }
            }
            if comp.len() > 1 {
                comp.sort();
                t.out.push(comp);
            }
        }
    }
    let mut t = T {
        g,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on: BTreeSet::new(),
        out: Vec::new(),
    };
    for v in g.keys() {
        if !t.index.contains_key(v.as_str()) {
            visit(&mut t, v);
        }
    }
    t.out
}

fn layer(module: &str) -> Option<usize> {
    let top = module.split("::").next().unwrap();
    LAYERS.iter().position(|l| l.contains(&top))
}

#[test]
fn no_module_imports_in_a_circle() {
    let g = graph();
    let found = circles(&g);
    let described: Vec<String> = found
        .iter()
        .map(|c| {
            let edges: Vec<String> = c
                .iter()
                .flat_map(|a| {
                    g[a].iter()
                        .filter(|b| c.contains(b))
                        .map(move |b| format!("{a} -> {b}"))
                })
                .collect();
            edges.join(", ")
        })
        .collect();
    assert!(found.is_empty(), "circular imports: {described:?}");
}

#[test]
fn every_import_points_down_the_layers() {
    let g = graph();
    let mut wrong = Vec::new();
    for (m, targets) in &g {
        if m.is_empty() {
            continue;
        }
        let lm = layer(m).unwrap_or_else(|| panic!("{m}: its top module is in no layer of LAYERS"));
        for t in targets {
            let lt = layer(t).unwrap_or_else(|| panic!("{t}: in no layer of LAYERS"));
            if lt > lm {
                wrong.push(format!("{m} -> {t}"));
            }
        }
    }
    assert!(wrong.is_empty(), "imports up the layers: {wrong:?}");
}

#[test]
fn the_parser_sees_a_circle_and_an_upward_import() {
    // the detector itself can fail: two made-up modules that import each other
    let text = "use crate::b::{X, y::Z};\nfn f() { super::c::g(); }";
    let p = paths("a::m", false, &code(text));
    assert!(p.contains(&"b::X".to_string()) && p.contains(&"b::y::Z".to_string()));
    assert!(p.contains(&"a::c::g".to_string()));
    let mut g = BTreeMap::new();
    g.insert("a".to_string(), BTreeSet::from(["b".to_string()]));
    g.insert("b".to_string(), BTreeSet::from(["c".to_string()]));
    g.insert("c".to_string(), BTreeSet::from(["a".to_string()]));
    assert_eq!(circles(&g), vec![vec!["a", "b", "c"]]);
    assert!(layer("analysis::fit") < layer("run"));
    // comments and the test module do not count
    assert!(paths(
        "a",
        false,
        &code("// use crate::z;\n#[cfg(test)]\nuse crate::y;")
    )
    .is_empty());
}

#[test]
fn every_figure_binary_is_a_short_script() {
    // a binary holds its options, set-up, calls, checks and
    // summary; procedures live in src/ (docs/explanation/library.md "Layers")
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("reproduce");
    let mut long = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let lines = std::fs::read_to_string(&path).unwrap().lines().count();
        if lines > 150 {
            long.push(format!("{}: {lines} lines", path.display()));
        }
    }
    assert!(long.is_empty(), "binaries over 150 lines: {long:?}");
}
