//! The repository carries its own specification: every section
//! of MODEL.md that the code and the documents cite ("MODEL.md A5",
//! "MODEL.md B3-B5", "MODEL.md Part B") has a heading in MODEL.md, every
//! document the README names is in the repository, and no file sends the
//! reader outside it (`../shared/`, or a temporary folder in a document).

mod common;

use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Whether the documents under docs/ are here: in a checkout of the
/// repository they must be; the published crate leaves them out, and the
/// tests that read them skip.
fn in_repository() -> bool {
    common::in_repository("docs").is_some()
}

/// Push every file below `dir` whose name ends in `.ext` onto `out`,
/// descending into folders when `deep`.
fn walk(dir: &Path, ext: &str, deep: bool, out: &mut Vec<PathBuf>) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            if deep {
                walk(&p, ext, deep, out);
            }
        } else if p.extension().is_some_and(|x| x == ext) {
            out.push(p);
        }
    }
}

/// The files whose citations are checked: every `.rs` file under src/,
/// reproduce/ and tests/, and the top-level documents.
fn cited_files() -> Vec<PathBuf> {
    let r = root();
    let mut files = Vec::new();
    for d in ["src", "reproduce", "tests"] {
        walk(&r.join(d), "rs", true, &mut files);
    }
    for f in ["README.md", "EXPERIMENTS.md", "READINGS.md"] {
        if r.join(f).exists() {
            files.push(r.join(f));
        }
    }
    files.sort();
    files
}

/// Text with line breaks and the comment markers of continuation lines
/// removed, so that a citation split over two comment lines reads as one.
fn joined(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for line in text.lines() {
        let t = line.trim_start();
        let t = ["//!", "///", "//"]
            .iter()
            .find_map(|m| t.strip_prefix(m))
            .unwrap_or(t);
        out.push_str(t.trim());
        out.push(' ');
    }
    out
}

/// A section label at the start of `s`: "A5", "B", "C12" (a letter A-C,
/// then digits, then not a letter or digit). Returns (label, rest).
fn label(s: &str) -> Option<(String, &str)> {
    let b = s.as_bytes();
    if b.is_empty() || !(b'A'..=b'C').contains(&b[0]) {
        return None;
    }
    let n = 1 + b[1..].iter().take_while(|c| c.is_ascii_digit()).count();
    if b.get(n).is_some_and(|c| c.is_ascii_alphanumeric()) {
        return None;
    }
    Some((s[..n].to_string(), &s[n..]))
}

/// Every section label cited as "MODEL.md X" in `text`, with lists and
/// ranges: "MODEL.md A4, A7", "MODEL.md B3-B5", "MODEL.md Part B".
fn citations(text: &str) -> Vec<String> {
    let text = joined(text);
    let mut out = Vec::new();
    for (pos, _) in text.match_indices("MODEL.md") {
        let mut rest = text[pos + "MODEL.md".len()..].trim_start_matches([' ', '§']);
        rest = rest.strip_prefix("Part ").unwrap_or(rest);
        let Some((first, mut rest)) = label(rest) else {
            continue;
        };
        out.push(first);
        loop {
            let next = rest
                .strip_prefix(", ")
                .or_else(|| rest.strip_prefix('-'))
                .or_else(|| rest.strip_prefix("..."))
                .or_else(|| rest.strip_prefix(" and "));
            match next.and_then(label) {
                Some((l, r)) if l.len() > 1 => {
                    out.push(l);
                    rest = r;
                }
                _ => break,
            }
        }
    }
    out
}

/// The section labels of MODEL.md's headings: "### A5. Gravity" gives "A5",
/// "## Part B. ..." gives "B".
fn headings(model: &str) -> BTreeSet<String> {
    model
        .lines()
        .filter(|l| l.starts_with('#'))
        .filter_map(|l| {
            let t = l.trim_start_matches('#').trim_start();
            let t = t.strip_prefix("Part ").unwrap_or(t);
            label(t).map(|(l, _)| l)
        })
        .collect()
}

#[test]
fn the_citation_parser_reads_lists_ranges_and_split_lines() {
    let text = "see (MODEL.md A4, A7) and MODEL.md B3-B5: x; MODEL.md Part B;\n\
                //! MODEL.md\n//! A11 is split; MODEL.md's default; MODEL.md A9, [PH95]";
    assert_eq!(citations(text), ["A4", "A7", "B3", "B5", "B", "A11", "A9"]);
    let h = headings("# Title\n## Part A. Pipe\n### A5. Gravity\n### A10. Targets\n");
    assert_eq!(h.into_iter().collect::<Vec<_>>(), ["A", "A10", "A5"]);
}

#[test]
fn every_cited_model_section_exists() {
    let model = fs::read_to_string(root().join("MODEL.md")).expect("MODEL.md at the top level");
    let have = headings(&model);
    let mut missing = Vec::new();
    let mut count = 0;
    for f in cited_files() {
        let text = fs::read_to_string(&f).unwrap();
        for l in citations(&text) {
            count += 1;
            if !have.contains(&l) {
                missing.push(format!(
                    "{}: MODEL.md {l}",
                    f.strip_prefix(root()).unwrap().display()
                ));
            }
        }
    }
    assert!(
        count > 100,
        "only {count} citations of MODEL.md found: is the parser broken?"
    );
    assert!(
        missing.is_empty(),
        "cited sections without a heading in MODEL.md (headings: {have:?}):\n{}",
        missing.join("\n")
    );
}

#[test]
fn every_document_the_readme_names_is_in_the_repository() {
    if !in_repository() {
        return;
    }
    let readme = fs::read_to_string(root().join("README.md")).unwrap();
    let mut named = BTreeSet::new();
    // markdown links to .md files: [text](PATH.md) or [text](PATH.md#anchor)
    for (pos, _) in readme.match_indices("](") {
        let target = &readme[pos + 2..];
        let end = target.find(')').unwrap_or(target.len());
        let path = target[..end].split('#').next().unwrap();
        if path.ends_with(".md") && !path.contains("://") {
            named.insert(path.to_string());
        }
    }
    // documents named in the text: an upper-case name ending in .md
    for (pos, _) in readme.match_indices(".md") {
        let start = readme[..pos]
            .rfind(|c: char| !(c.is_ascii_alphanumeric() || "_-./".contains(c)))
            .map_or(0, |i| i + 1);
        let name = &readme[start..pos + 3];
        let stem = name.trim_start_matches("./");
        if stem.chars().next().is_some_and(|c| c.is_ascii_uppercase())
            && stem[..stem.len() - 3]
                .chars()
                .all(|c| c.is_ascii_uppercase() || c == '_' || c == '-')
        {
            named.insert(stem.to_string());
        }
    }
    assert!(named.contains("MODEL.md"), "the README names MODEL.md");
    let missing: Vec<_> = named.iter().filter(|p| !root().join(p).exists()).collect();
    assert!(
        missing.is_empty(),
        "documents named in README.md but not in the repository: {missing:?}"
    );
    for f in ["LICENSE-MIT", "LICENSE-APACHE"] {
        assert!(
            root().join(f).exists(),
            "{f} (Cargo.toml: MIT OR Apache-2.0)"
        );
    }
}

/// The cited files and every other Markdown document: the top-level ones
/// (MODEL.md, HOPPER_READINGS.md, ...) and those under docs/.
fn every_document() -> Vec<PathBuf> {
    let mut files = cited_files();
    walk(&root(), "md", false, &mut files);
    walk(&root().join("docs"), "md", true, &mut files);
    files.sort();
    files.dedup();
    files
}

#[test]
fn no_file_sends_the_reader_outside_the_repository() {
    if !in_repository() {
        return;
    }
    let mut outside = Vec::new();
    for f in every_document() {
        if f.ends_with("tests/docs.rs") {
            continue;
        }
        let text = fs::read_to_string(&f).unwrap();
        for (n, line) in text.lines().enumerate() {
            let is_doc = f.extension().is_some_and(|x| x == "md");
            if line.contains("../shared/") || (is_doc && line.contains("/tmp/")) {
                outside.push(format!(
                    "{}:{}: {}",
                    f.strip_prefix(root()).unwrap().display(),
                    n + 1,
                    line.trim()
                ));
            }
        }
    }
    assert!(
        outside.is_empty(),
        "references to files outside the repository (use MODEL.md, and an --out folder a reader can recreate):\n{}",
        outside.join("\n")
    );
}

/// Whether `line` speaks of how the project was made: a numbered session
/// (a session with its number) or the ones who steer it, in any case
/// (the words are split here so that this file does not hold them).
fn speaks_of_history(line: &str) -> bool {
    let l = line.to_lowercase();
    if l.contains(&["steer", "ing"].concat()) {
        return true;
    }
    l.match_indices("session").any(|(i, _)| {
        let rest = &l[i + "session".len()..];
        let rest = rest.strip_prefix('s').unwrap_or(rest);
        rest.strip_prefix(' ')
            .is_some_and(|r| r.starts_with(|c: char| c.is_ascii_digit()))
    })
}

#[test]
fn the_history_detector_reads_numbered_sessions() {
    // the words are split so that this file does not hold them
    let (session, steer) = (["Sess", "ion"].concat(), ["Stee", "ring"].concat());
    assert!(speaks_of_history(&format!("fixed in {session} 2")));
    assert!(speaks_of_history(&format!("{session}s 2-3")));
    assert!(speaks_of_history(&format!("a note to {steer}")));
    assert!(!speaks_of_history(&format!("a {session} of the CLI")));
    assert!(!speaks_of_history(&format!("{session}s-2-3")));
}

/// Every tracked text file describes the project, never how it was made:
/// no numbered session and no word of those who steer it, in documents,
/// code, comments or the committed outputs. History goes by date and commit (CHANGELOG.md,
/// docs/notebook/).
#[test]
fn no_file_speaks_of_how_it_was_made() {
    if !in_repository() {
        return;
    }
    let mut files = vec![];
    for ext in [
        "md", "rs", "py", "sh", "log", "json", "html", "csv", "tsv", "toml", "cff", "txt",
    ] {
        walk(&root(), ext, false, &mut files);
        for dir in ["src", "reproduce", "tests", "docs", "golden", ".ci"] {
            walk(&root().join(dir), ext, true, &mut files);
        }
    }
    files.push(root().join(".ci/run"));
    let mut found = vec![];
    for f in files {
        let Ok(text) = std::fs::read_to_string(&f) else {
            continue;
        };
        for (i, line) in text.lines().enumerate() {
            if speaks_of_history(line) {
                found.push(format!(
                    "{}:{}",
                    f.strip_prefix(root()).unwrap().display(),
                    i + 1
                ));
            }
        }
    }
    assert!(
        found.is_empty(),
        "files that speak of how the project was made: {found:?}"
    );
}

/// The notebook's index (docs/notebook/README.md) links every dated entry
/// in the folder, so a new entry cannot go unlisted.
#[test]
fn the_notebook_index_lists_every_entry() {
    if !in_repository() {
        return;
    }
    let dir = root().join("docs/notebook");
    let index = fs::read_to_string(dir.join("README.md")).unwrap();
    let mut entries = vec![];
    walk(&dir, "md", false, &mut entries);
    let missing: Vec<String> = entries
        .iter()
        .filter_map(|p| p.file_name()?.to_str().map(str::to_owned))
        .filter(|n| n.starts_with("20") && !index.contains(&format!("({n})")))
        .collect();
    assert!(
        missing.is_empty(),
        "notebook entries missing from docs/notebook/README.md: {missing:?}"
    );
}
