//! Every tracked path is one Windows can check out and `cargo package`
//! accepts: no `: * ? " < > |`, no trailing dot or space, no reserved
//! device name (`CON`, `NUL`, ...) in any of its folders or its file name.
//! And the files a figure writes from a rule reading's name are portable:
//! the calibrated bridge finds its committed saved readings under their
//! portable names.
//!
//! The tracked files come from `git ls-files`; outside a checkout of the
//! repository (the published crate) the test says so and checks nothing.

use granular_automata::drivers::bridge::{reading, GRID};
use granular_automata::drivers::claims::{Group, MatrixSize};
use granular_automata::drivers::matrix::Matrix;
use granular_automata::pipe::Engine;
use granular_automata::run::{is_portable_file_name, Tier};
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Whether the crate's folder is a checkout of the repository (`.git`, a
/// folder or a worktree's file); when not, say why the test checks nothing.
fn in_checkout(test: &str) -> bool {
    let git = root().join(".git").exists();
    if !git {
        eprintln!(
            "{test}: skipped, {} is not a git checkout",
            root().display()
        );
    }
    git
}

#[test]
fn every_tracked_path_is_portable() {
    if !in_checkout("every_tracked_path_is_portable") {
        return;
    }
    let out = Command::new("git")
        .arg("-C")
        .arg(root())
        .args(["ls-files", "-z"])
        .output()
        .expect("git runs in a checkout");
    assert!(out.status.success(), "git ls-files failed");
    let files: Vec<String> = out
        .stdout
        .split(|&b| b == 0)
        .filter(|f| !f.is_empty())
        .map(|f| String::from_utf8_lossy(f).into_owned())
        .collect();
    assert!(
        files.iter().any(|f| f == "Cargo.toml"),
        "git ls-files lists the crate"
    );
    let bad: Vec<&String> = files
        .iter()
        .filter(|f| !f.split('/').all(is_portable_file_name))
        .collect();
    assert!(
        bad.is_empty(),
        "tracked paths Windows or cargo package refuse (rename them with run::portable_file_name): {bad:#?}"
    );
}

/// `bridge --tier standard --engine fast --out docs/bridge` reads every
/// grid point's saved grade from the committed cache: no point is
/// recomputed.
#[test]
fn the_bridge_finds_its_committed_saved_readings() {
    if !in_checkout("the_bridge_finds_its_committed_saved_readings") {
        return;
    }
    let cache = root().join("docs/bridge/bridge/variants");
    let matrix = Matrix {
        tier: Tier::Standard,
        size: MatrixSize::for_tier(Tier::Standard),
        seed: 1,
        engine: Engine::Fast,
        groups: &Group::ALL,
    };
    for q in GRID {
        let file = matrix.saved(&cache, reading(q).unwrap());
        let name = file.file_name().unwrap().to_str().unwrap();
        assert!(is_portable_file_name(name), "{name}");
        assert!(file.is_file(), "q = {q}: {} is not committed", show(&file));
    }
}

fn show(p: &Path) -> String {
    p.strip_prefix(root()).unwrap_or(p).display().to_string()
}
