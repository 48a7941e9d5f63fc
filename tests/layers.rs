//! The imports between the library's top-level modules point one way (issue
//! 32): the graph of `crate::<module>` references in code (comments
//! excluded) between `src/<module>` trees has no cycle. Within a module
//! (e.g. `drivers::claims` and `drivers::sweep`) this test does not look.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

type Graph = BTreeMap<String, BTreeSet<String>>;

/// Every `.rs` file under `dir`.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in fs::read_dir(dir).unwrap().flatten() {
        let p = e.path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The top-level modules each top-level module of `src/` names as
/// `crate::<module>` outside comments.
fn module_graph() -> Graph {
    let src = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = vec![];
    rust_files(&src, &mut files);
    let mut g = Graph::new();
    for f in files {
        let rel = f.strip_prefix(&src).unwrap();
        let top = rel
            .components()
            .next()
            .unwrap()
            .as_os_str()
            .to_string_lossy();
        let top = top.trim_end_matches(".rs").to_string();
        if top == "lib" {
            continue;
        }
        let entry = g.entry(top.clone()).or_default();
        for line in fs::read_to_string(&f).unwrap().lines() {
            let code = line.split("//").next().unwrap();
            for (i, _) in code.match_indices("crate::") {
                let rest = &code[i + "crate::".len()..];
                let names: Vec<&str> = if let Some(group) = rest.strip_prefix('{') {
                    group
                        .split('}')
                        .next()
                        .unwrap()
                        .split(',')
                        .map(|s| s.trim().split("::").next().unwrap())
                        .collect()
                } else {
                    vec![rest
                        .split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                        .next()
                        .unwrap()]
                };
                for n in names.into_iter().filter(|n| !n.is_empty() && *n != top) {
                    entry.insert(n.to_string());
                }
            }
        }
    }
    g
}

/// A cycle of `g` (its modules in order, the first repeated at the end), if
/// any.
fn find_cycle(g: &Graph) -> Option<Vec<String>> {
    fn visit(
        n: &str,
        g: &Graph,
        stack: &mut Vec<String>,
        done: &mut BTreeSet<String>,
    ) -> Option<Vec<String>> {
        if let Some(i) = stack.iter().position(|s| s == n) {
            let mut c = stack[i..].to_vec();
            c.push(n.to_string());
            return Some(c);
        }
        if done.contains(n) {
            return None;
        }
        stack.push(n.to_string());
        for m in g.get(n).into_iter().flatten() {
            if let Some(c) = visit(m, g, stack, done) {
                return Some(c);
            }
        }
        stack.pop();
        done.insert(n.to_string());
        None
    }
    let mut done = BTreeSet::new();
    g.keys()
        .find_map(|n| visit(n, g, &mut Vec::new(), &mut done))
}

#[test]
fn the_top_level_modules_import_one_way() {
    let g = module_graph();
    assert!(
        g.contains_key("pipe") && g.contains_key("analysis"),
        "{g:?}"
    );
    if let Some(c) = find_cycle(&g) {
        panic!("circular imports between modules: {}", c.join(" -> "));
    }
    // the lowest layers import nothing above them
    assert!(g["error"].is_empty(), "error imports {:?}", g["error"]);
    assert!(
        g["analysis"].iter().all(|m| m == "error"),
        "analysis imports {:?}",
        g["analysis"]
    );
}

#[test]
fn a_cycle_is_found() {
    let edge = |a: &str, b: &[&str]| (a.to_string(), b.iter().map(|s| s.to_string()).collect());
    let g: Graph = [edge("run", &["analysis"]), edge("analysis", &["run"])].into();
    assert_eq!(find_cycle(&g).unwrap(), ["analysis", "run", "analysis"]);
    let g: Graph = [edge("run", &["analysis"]), edge("analysis", &[])].into();
    assert_eq!(find_cycle(&g), None);
}
