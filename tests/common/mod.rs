//! Helpers shared by the tests: running a figure binary and reading its
//! `summary.json` (here), the model tests' set-ups ([`models`]), the
//! reference's draws for comparing certain steps ([`certain`]).
#![allow(dead_code)]

pub mod certain;
pub mod models;

use std::ffi::OsStr;
use std::path::PathBuf;
use std::process::Command;

/// The repository's file or folder `rel` (under docs/: the committed
/// report and seed sets, which the published crate leaves out): `Some` where
/// it is; in a checkout of the repository (a `.git` beside Cargo.toml) it
/// must be there. `None` outside a checkout, saying what is skipped.
pub fn in_repository(rel: &str) -> Option<PathBuf> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let path = root.join(rel);
    if path.exists() {
        return Some(path);
    }
    assert!(
        !root.join(".git").exists(),
        "{rel} is missing from the checkout {}",
        root.display()
    );
    eprintln!("skipped: {rel} is in the repository only, not in the published crate");
    None
}

/// The folder `name` of the test target directory, emptied first.
pub fn fresh_dir(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// The `sleep` processes whose command line contains `needle` (from
/// /proc): what a test's external candidate started, to show it stopped.
pub fn sleeps_with(needle: &str) -> Vec<String> {
    let Ok(dir) = std::fs::read_dir("/proc") else {
        return vec![];
    };
    dir.flatten()
        .filter_map(|e| std::fs::read(e.path().join("cmdline")).ok())
        .map(|c| String::from_utf8_lossy(&c).replace('\0', " "))
        .filter(|c| c.starts_with("sleep") && c.contains(needle))
        .collect()
}

/// Run `exe` with `args`; assert that it fails and that its standard error
/// contains `needle` (a bad input names its value).
pub fn fails_with<I, A>(exe: &str, args: I, needle: &str)
where
    I: IntoIterator<Item = A>,
    A: AsRef<OsStr>,
{
    let o = Command::new(exe)
        .args(args)
        .output()
        .expect("the binary runs");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{exe} succeeded");
    assert!(err.contains(needle), "{exe}: {needle:?} not in {err}");
}

/// Run figure binary `exe` (named `bin`, its output folder) with `args` into a
/// fresh folder of the test target directory tagged `tag` (removed first, so
/// saved runs of an earlier build never stand in for this one); assert that
/// it succeeds and wrote each of `files`; return its summary.json.
pub fn run_figure(
    bin: &str,
    exe: &str,
    args: &[&str],
    tag: &str,
    files: &[&str],
) -> serde_json::Value {
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("{bin}-{tag}"));
    let _ = std::fs::remove_dir_all(&out);
    let status = Command::new(exe)
        .args(args)
        .arg("--out")
        .arg(&out)
        .status()
        .expect("the binary runs");
    assert!(status.success(), "{bin} {args:?} failed");
    for f in files {
        assert!(out.join(bin).join(f).exists(), "{bin}: {f} written");
    }
    let text =
        std::fs::read_to_string(out.join(bin).join("summary.json")).expect("summary.json written");
    serde_json::from_str(&text).expect("summary.json parses")
}

/// [`run_figure`] of the figure binary named `$bin` (its executable found
/// by that name): `run_figure!("fig2", &args, tag, &files)`.
#[macro_export]
macro_rules! run_figure {
    ($bin:literal, $($rest:expr),+ $(,)?) => {
        $crate::common::run_figure($bin, env!(concat!("CARGO_BIN_EXE_", $bin)), $($rest),+)
    };
}

/// Check `name` of a summary.
pub fn check<'a>(s: &'a serde_json::Value, name: &str) -> &'a serde_json::Value {
    let checks = s["checks"].as_array().expect("checks");
    let found = checks.iter().find(|c| c["name"] == name);
    found.unwrap_or_else(|| panic!("check {name} present"))
}

/// Whether check `name` of a summary passed.
pub fn pass(s: &serde_json::Value, name: &str) -> bool {
    check(s, name)["pass"].as_bool().expect("pass is a bool")
}

/// Metric `name` of a summary.
pub fn metric(s: &serde_json::Value, name: &str) -> f64 {
    s["metrics"][name]
        .as_f64()
        .unwrap_or_else(|| panic!("metric {name} present"))
}

/// The verdict (`reproduced`, `not-reproduced`, `undecided`) of check `name`.
pub fn verdict(s: &serde_json::Value, name: &str) -> String {
    let v = check(s, name)["verdict"].as_str();
    v.expect("verdict is a string").to_string()
}

/// Whether the claim of check `name` is contradicted: verdict
/// `not-reproduced` (|d| - k SE > margin under the one grading rule).
///
/// The tests use it where a CI-sized run cannot decide a claim (k SE alone
/// exceeds the margin): the default reading must not be contradicted, and a
/// named wrong reading must be.
pub fn contradicted(s: &serde_json::Value, name: &str) -> bool {
    verdict(s, name) == "not-reproduced"
}
