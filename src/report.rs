//! The reproduction report (the claims of MODEL.md A10 and B6): run every
//! figure binary at one tier (finished runs are resumed from `--out`, so a
//! rerun only re-analyses),
//! read each `DIR/<binary>/summary.json` and write `DIR/report/REPORT.md`,
//! a self-contained `DIR/report/index.html` (no network, no JavaScript,
//! relative links) and `DIR/report/report.json`.
//!
//! Every line of the Markdown and HTML that carries a wall time ends with
//! [`TIMING_MARK`] (Markdown) or contains [`HTML_TIMING_MARK`], so two reports
//! of the same finished runs compare equal once those lines are removed
//! ([`without_timing`]).

use crate::error::{Error, ErrorKind, Result};
use crate::run::{write_atomic, Tier};
use serde::Serialize;
use serde_json::Value;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::io::{BufRead, BufReader, Write as _};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Instant;

/// The crate's `Cargo.toml`, read at compile time: its `[[bin]]` entries
/// are the figure binaries.
const CARGO_TOML: &str = include_str!("../Cargo.toml");

/// Binaries that are not figures (no `summary.json` of a figure): never run.
const NOT_FIGURES: [&str; 13] = [
    "acceptance",
    "bench",
    "bridge",
    "explore",
    "fuzz",
    "merge",
    "readings-map",
    "report",
    "sequential-design",
    "speed-accuracy",
    "validate",
    "validate-detection",
    "validate-example",
];

/// Figures run only when named with `--only` (the rule-reading matrix:
/// about half an hour of CPU at the quick tier).
const ON_REQUEST: [&str; 1] = ["pipe-matrix"];

/// Marker ending every Markdown line that carries a wall time.
pub const TIMING_MARK: &str = "<!-- timing -->";
/// Marker inside every HTML line that carries a wall time.
pub const HTML_TIMING_MARK: &str = "data-timing";

/// Characters of a rule reading shown in a table cell (the full reading is
/// in the headline's list and the stamp).
const RULES_CELL: usize = 40;

/// Lines of stderr kept for a failed figure.
const STDERR_TAIL: usize = 15;

/// The heading of EXPERIMENTS.md the known discrepancies link to.
const DISCREPANCY_HEADING: &str = "## Known discrepancies";

/// What the report runs and where it writes.
#[derive(Debug, Clone)]
pub struct Options {
    /// Tier passed to every figure.
    pub tier: Tier,
    /// The figures to run (see [`select`]).
    pub figures: Vec<String>,
    /// The output folder of the figures; the report goes to `out/report/`.
    pub out: PathBuf,
    /// `--seed` passed to every figure, if given.
    pub seed: Option<u64>,
    /// `--threads` passed to every figure, if given.
    pub threads: Option<usize>,
    /// `--engine` passed to the pipe figures (not the hopper's), if given.
    pub engine: Option<String>,
    /// Extra arguments of single figures (`binary -> args`), appended last.
    pub extra: BTreeMap<String, Vec<String>>,
    /// The folder holding the figure binaries (that of the report's own
    /// executable).
    pub bin_dir: PathBuf,
    /// The report's command line, as recorded in the stamp.
    pub command_line: String,
    /// Do not run the figures: read the summaries already in `out`
    /// (`--no-run`, to re-render a report or a published copy).
    pub no_run: bool,
    /// A folder of committed seed sets, `<dir>/<binary>/<seed folder>/`
    /// (`--seed-sets`, e.g. `docs/acceptance`): the published checks are
    /// also graded over every seed set of a figure that has at least
    /// [`MIN_SEED_SETS`] ([`SeedSets`]), or of a cut of it ([`cuts_of`]).
    pub seed_sets: Option<PathBuf>,
}

/// The fewest seed sets over which the report grades a check as one
/// ensemble: the 20 base seeds of the acceptance tier's stability study.
pub const MIN_SEED_SETS: usize = 20;

/// Every `[[bin]]` name of Cargo.toml, in file order.
pub fn all_binaries() -> Vec<&'static str> {
    let mut names = vec![];
    let mut in_bin = false;
    for line in CARGO_TOML.lines().map(str::trim) {
        if line.starts_with('[') {
            in_bin = line == "[[bin]]";
        } else if in_bin {
            if let Some(v) = line.strip_prefix("name") {
                if let Some(v) = v.trim_start().strip_prefix('=') {
                    names.push(v.trim().trim_matches('"'));
                }
            }
        }
    }
    names
}

/// The figures a report runs by default: every `[[bin]]` except the tools
/// (bench, explore, merge, report, speed-accuracy, validate and its
/// example) and the on-request pipe-matrix.
pub fn default_figures() -> Vec<&'static str> {
    all_binaries()
        .into_iter()
        .filter(|b| !NOT_FIGURES.contains(b) && !ON_REQUEST.contains(b))
        .collect()
}

/// The figures to run for `--only` (comma-separated names; `None`: the
/// defaults), in Cargo.toml order. An unknown or non-figure name, or an
/// empty list, is an [`ErrorKind::InvalidParameter`] error listing the
/// allowed names.
pub fn select(only: Option<&str>) -> Result<Vec<String>> {
    let allowed: Vec<&str> = all_binaries()
        .into_iter()
        .filter(|b| !NOT_FIGURES.contains(b))
        .collect();
    let Some(only) = only else {
        return Ok(default_figures().into_iter().map(String::from).collect());
    };
    let names: Vec<&str> = only
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .collect();
    let unknown: Vec<&str> = names
        .iter()
        .copied()
        .filter(|n| !allowed.contains(n))
        .collect();
    if names.is_empty() || !unknown.is_empty() {
        return Err(Error::new(
            ErrorKind::InvalidParameter,
            format!(
                "--only {only:?}: unknown figure(s) {unknown:?}; choose a comma-separated list of {}",
                allowed.join(", ")
            ),
        ));
    }
    Ok(allowed
        .into_iter()
        .filter(|b| names.contains(b))
        .map(String::from)
        .collect())
}

/// Parse `--args-for BIN=ARGS` (ARGS split at whitespace) for one of the
/// selected `figures`.
pub fn parse_extra(spec: &str, figures: &[String]) -> Result<(String, Vec<String>)> {
    let bad = |why: &str| {
        Error::new(
            ErrorKind::InvalidParameter,
            format!("--args-for {spec:?}: {why}; write BIN=ARGS, e.g. fig2=\"--runs 8\", with BIN one of {}", figures.join(", ")),
        )
    };
    let (bin, args) = spec.split_once('=').ok_or_else(|| bad("no '='"))?;
    if !figures.iter().any(|f| f == bin) {
        return Err(bad("not a figure of this report"));
    }
    Ok((bin.to_string(), shell_split(args).map_err(|e| bad(&e))?))
}

/// Split `s` into words as a POSIX shell does for plain words: white space
/// separates them, single quotes keep everything, double quotes keep all
/// but `\"` and `\\`, and a backslash outside quotes escapes the next
/// character. No expansions.
///
/// Errors: an unterminated quote or a trailing backslash.
pub fn shell_split(s: &str) -> std::result::Result<Vec<String>, String> {
    let (mut words, mut word, mut in_word) = (vec![], String::new(), false);
    let mut chars = s.chars();
    while let Some(c) = chars.next() {
        match c {
            c if c.is_whitespace() => {
                if in_word {
                    words.push(std::mem::take(&mut word));
                    in_word = false;
                }
            }
            '\'' => {
                in_word = true;
                loop {
                    match chars.next() {
                        Some('\'') => break,
                        Some(c) => word.push(c),
                        None => return Err("an unterminated ' quote".into()),
                    }
                }
            }
            '"' => {
                in_word = true;
                loop {
                    match chars.next() {
                        Some('"') => break,
                        Some('\\') => match chars.next() {
                            Some(c @ ('"' | '\\')) => word.push(c),
                            Some(c) => {
                                word.push('\\');
                                word.push(c);
                            }
                            None => return Err("an unterminated \" quote".into()),
                        },
                        Some(c) => word.push(c),
                        None => return Err("an unterminated \" quote".into()),
                    }
                }
            }
            '\\' => {
                in_word = true;
                word.push(chars.next().ok_or("a trailing backslash")?);
            }
            c => {
                in_word = true;
                word.push(c);
            }
        }
    }
    if in_word {
        words.push(word);
    }
    Ok(words)
}

/// `arg` as one shell word: unchanged when it holds only characters a
/// shell leaves alone, else in single quotes (a `'` written `'\''`).
pub fn shell_quote(arg: &str) -> String {
    let plain = |c: char| c.is_ascii_alphanumeric() || "-_./=:,+%@".contains(c);
    if !arg.is_empty() && arg.chars().all(plain) {
        arg.to_string()
    } else {
        format!("'{}'", arg.replace('\'', "'\\''"))
    }
}

/// How one figure binary ended.
#[derive(Debug, Clone, Serialize)]
pub struct FigureRun {
    /// Binary name.
    pub binary: String,
    /// Whether it exited with status 0.
    pub ok: bool,
    /// Why not ("exit status 2", "interrupted by signal 9", "not found ...").
    pub failure: Option<String>,
    /// The last lines of its stderr (failed figures only).
    pub stderr_tail: Vec<String>,
    /// Wall-clock seconds of the subprocess.
    pub wall_seconds: f64,
}

/// Whether figure `binary` runs the pipe (and takes `--engine`): every
/// figure but the hopper's.
pub fn is_pipe_figure(binary: &str) -> bool {
    !binary.starts_with("hopper-")
}

/// The arguments passed to figure `binary`.
pub fn figure_args(opts: &Options, binary: &str) -> Vec<String> {
    let mut a = vec![
        "--tier".to_string(),
        opts.tier.name().to_string(),
        "--out".to_string(),
        opts.out.display().to_string(),
    ];
    if let Some(s) = opts.seed {
        a.extend(["--seed".to_string(), s.to_string()]);
    }
    if let Some(t) = opts.threads {
        a.extend(["--threads".to_string(), t.to_string()]);
    }
    if let Some(e) = opts.engine.as_ref().filter(|_| is_pipe_figure(binary)) {
        a.extend(["--engine".to_string(), e.clone()]);
    }
    if let Some(x) = opts.extra.get(binary) {
        a.extend(x.iter().cloned());
    }
    a
}

/// Run figure `binary` from `opts.bin_dir`: stdout passes through, stderr
/// is forwarded line by line and its tail kept. Never fails: a missing
/// binary, a non-zero exit or a signal is recorded in the result.
pub fn run_figure(opts: &Options, binary: &str) -> FigureRun {
    let exe = opts
        .bin_dir
        .join(format!("{binary}{}", std::env::consts::EXE_SUFFIX));
    let start = Instant::now();
    let fail = |failure: String, tail: Vec<String>| FigureRun {
        binary: binary.to_string(),
        ok: false,
        failure: Some(failure),
        stderr_tail: tail,
        wall_seconds: start.elapsed().as_secs_f64(),
    };
    let child = Command::new(&exe)
        .args(figure_args(opts, binary))
        .stdin(Stdio::null())
        .stdout(Stdio::inherit())
        .stderr(Stdio::piped())
        .spawn();
    let mut child = match child {
        Ok(c) => c,
        Err(e) => {
            return fail(
                format!(
                    "cannot start {}: {e}; build the figures first (cargo build --release --bins)",
                    exe.display()
                ),
                vec![],
            )
        }
    };
    let mut tail: Vec<String> = vec![];
    if let Some(err) = child.stderr.take() {
        let mut stderr = std::io::stderr();
        for line in BufReader::new(err).lines() {
            let Ok(line) = line else { break };
            let _ = writeln!(stderr, "{line}");
            tail.push(line);
            if tail.len() > STDERR_TAIL {
                tail.remove(0);
            }
        }
    }
    match child.wait() {
        Ok(s) if s.success() => FigureRun {
            binary: binary.to_string(),
            ok: true,
            failure: None,
            stderr_tail: vec![],
            wall_seconds: start.elapsed().as_secs_f64(),
        },
        Ok(s) => match s.code() {
            Some(c) => fail(format!("exit status {c}"), tail),
            None => fail(format!("interrupted ({s})"), tail),
        },
        Err(e) => fail(format!("cannot wait for {binary}: {e}"), tail),
    }
}

/// One check of one figure, as read from its summary.json (missing fields
/// of the older check format tolerated: see [`Row::from_json`]).
#[derive(Debug, Clone, Serialize)]
pub struct Row {
    /// Binary name.
    pub binary: String,
    /// Paper, e.g. `PH94`.
    pub paper: String,
    /// Figure within the paper, e.g. `Fig. 2`.
    pub figure: String,
    /// Check name.
    pub name: String,
    /// published | pinned | identity | unstated.
    pub kind: String,
    /// reproduced | not-reproduced | undecided.
    pub verdict: String,
    /// Measured value (None when null / not finite).
    pub measured: Option<f64>,
    /// Its standard error.
    pub error: Option<f64>,
    /// Number of runs, when stated.
    pub runs: Option<u64>,
    /// Published value, when there is one.
    pub published: Option<f64>,
    /// Margin |measured - published| allowed, when stated.
    pub tolerance: Option<f64>,
    /// Where the published claim is (e.g. `PH95 III B`), when stated.
    pub source: String,
    /// The check's note, in full.
    pub note: String,
    /// Rule reading of the figure.
    pub rules: String,
    /// Site updates of the figure (all its runs).
    pub site_updates: Option<f64>,
    /// The test of the claim: `within`, `above`, `below` (empty when none).
    pub test: String,
    /// The key of the non-default reading this check belongs to (a case of
    /// the summary's `cases` with `default_reading: false`, whose key
    /// prefixes the check's name); `None` for the default reading.
    pub reading: Option<String>,
    /// The check over every committed seed set, when the report was given
    /// `--seed-sets` and the figure has at least [`MIN_SEED_SETS`].
    pub seed_sets: Option<SeedSets>,
}

/// A check graded over every committed seed set of its figure at the
/// report's tier: the seeds' mean value with the SE of their spread, graded
/// with n = seeds by the acceptance margin or the claim the seeds state
/// ([`crate::drivers::acceptance_study::all_seeds`]). The runs are the
/// tier's, repeated over independent base seeds: what the power analysis
/// asks of the claims one seed set cannot decide.
#[derive(Debug, Clone, Serialize)]
pub struct SeedSets {
    /// Seed sets with a value.
    pub seeds: usize,
    /// Their mean.
    pub measured: Option<f64>,
    /// The SE of their spread.
    pub error: Option<f64>,
    /// reproduced | not-reproduced | undecided.
    pub verdict: String,
    /// Where the seed sets lie.
    pub from: String,
}

/// The key of the non-default case of summary `s` (`params.cases`, or
/// `cases`) whose key prefixes check name `name` (the longest such key), if
/// any.
fn other_reading(s: &Value, name: &str) -> Option<String> {
    s["params"]["cases"]
        .as_array()
        .or_else(|| s["cases"].as_array())?
        .iter()
        .filter_map(|c| Some((c["key"].as_str()?, c["default_reading"].as_bool()?)))
        .filter(|(k, _)| name.strip_prefix(k).is_some_and(|r| r.starts_with('_')))
        .max_by_key(|(k, _)| k.len())
        .filter(|(_, default)| !default)
        .map(|(k, _)| k.to_string())
}

impl Row {
    /// The row of check `c` of figure `binary` whose summary is `s`.
    /// Missing `kind` reads as `unstated`; a missing `verdict` is derived
    /// from `pass` (true: reproduced, false: not-reproduced).
    pub fn from_json(binary: &str, s: &Value, c: &Value) -> Row {
        let (paper, figure) = split_paper(s["paper"].as_str().unwrap_or(binary));
        let text = |v: &Value| v.as_str().unwrap_or("").to_string();
        let verdict = match c["verdict"].as_str() {
            Some(v) => v.to_string(),
            None => match c["pass"].as_bool() {
                Some(true) => "reproduced".into(),
                Some(false) => "not-reproduced".into(),
                None => "undecided".into(),
            },
        };
        Row {
            binary: binary.to_string(),
            paper,
            figure,
            name: text(&c["name"]),
            kind: c["kind"].as_str().unwrap_or("unstated").to_string(),
            verdict,
            measured: finite(&c["measured"]),
            error: finite(&c["error"]),
            runs: c["runs"].as_u64(),
            published: finite(&c["published"]),
            tolerance: finite(&c["tolerance"]),
            source: text(&c["source"]),
            note: text(&c["note"]),
            rules: text(&s["rules"]),
            site_updates: finite(&s["site_updates"]),
            test: text(&c["claim"]["test"]),
            reading: other_reading(s, c["name"].as_str().unwrap_or("")),
            seed_sets: None,
        }
    }

    /// Whether this is a published claim: kind `published`, or (older
    /// format, kind unstated) a check against a published number.
    pub fn is_published_claim(&self) -> bool {
        self.kind == "published" || (self.kind == "unstated" && self.published.is_some())
    }

    /// Whether this is a published claim of the default reading: the claims
    /// the project makes (the headline counts these only).
    pub fn is_default_claim(&self) -> bool {
        self.is_published_claim() && self.reading.is_none()
    }

    /// The verdict over every committed seed set where there is one, else
    /// the verdict of this run.
    pub fn final_verdict(&self) -> &str {
        self.seed_sets
            .as_ref()
            .map_or(self.verdict.as_str(), |s| s.verdict.as_str())
    }

    /// What would decide an undecided check under the grading rule (|d| +-
    /// k SE against the margin, k = max(2, Student t)): the number of runs
    /// at which it decides, taking the SE to shrink as 1/sqrt(n); or why no
    /// run count does. With the verdict over every committed seed set when
    /// there is one ([`SeedSets`]).
    pub fn what_would_decide(&self) -> String {
        let runs = self.runs_to_decide_note();
        match &self.seed_sets {
            Some(ss) => format!(
                "{runs}; over {} committed seed sets: {}",
                ss.seeds, ss.verdict
            ),
            None => runs,
        }
    }

    /// [`Row::what_would_decide`] from this run alone.
    fn runs_to_decide_note(&self) -> String {
        let (Some(x), Some(se), Some(margin)) = (self.measured, self.error, self.tolerance) else {
            return "no value with a standard error: more runs (at least 3)".into();
        };
        // distance to the margin's edge: |d| vs margin for `within`, the
        // value vs the threshold for `above` / `below`
        let gap = match (self.test.as_str(), self.published) {
            ("within", Some(p)) => ((x - p).abs() - margin).abs(),
            ("above" | "below", _) => (x - margin).abs(),
            _ => return "the check states no claim to decide".into(),
        };
        // on the edge up to rounding: no SE is small enough
        if gap <= 1e-12 * (1.0 + margin.abs()) || se <= 0.0 {
            return "the value sits on the margin's edge: no run count decides it".into();
        }
        let edge = if self.test == "within" {
            "|d| lies {gap} from the margin"
        } else {
            "the value lies {gap} from the threshold"
        }
        .replace("{gap}", &sig(gap, 2));
        match self.runs.filter(|&n| n >= 3) {
            Some(n) => match runs_to_decide(n as usize, se, gap) {
                Some(m) => format!(
                    "{edge}, SE {} over {n} runs: about {m} runs decide it",
                    sig(se, 2)
                ),
                None => format!(
                    "{edge}, SE {} over {n} runs: more than {MAX_RUNS_TO_DECIDE} runs",
                    sig(se, 2)
                ),
            },
            None => format!(
                "SE {} needed (now {}), with at least 3 runs",
                sig(gap / 2.0, 2),
                sig(se, 2)
            ),
        }
    }
}

/// The largest run count [`runs_to_decide`] looks at.
const MAX_RUNS_TO_DECIDE: usize = 1_000_000_000;

/// The fewest runs m > n at which k(m) SE sqrt(n / m) <= gap, the SE of `n`
/// runs being `se` (k: [`coverage_factor`]); `None` beyond
/// [`MAX_RUNS_TO_DECIDE`].
fn runs_to_decide(n: usize, se: f64, gap: f64) -> Option<usize> {
    let decides = |m: usize| {
        crate::analysis::grading::coverage_factor(m)
            .is_some_and(|k| k * se * (n as f64 / m as f64).sqrt() <= gap)
    };
    let mut hi = n.max(3) + 1;
    while !decides(hi) {
        if hi >= MAX_RUNS_TO_DECIDE {
            return None;
        }
        hi = (hi * 2).min(MAX_RUNS_TO_DECIDE);
    }
    let mut lo = n.max(3); // lo does not decide (or is n itself)
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if decides(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Some(hi)
}

fn finite(v: &Value) -> Option<f64> {
    v.as_f64().filter(|x| x.is_finite())
}

/// `PH94 Fig. 2` -> (`PH94`, `Fig. 2`).
fn split_paper(p: &str) -> (String, String) {
    match p.split_once(' ') {
        Some((a, b)) => (a.to_string(), b.to_string()),
        None => (p.to_string(), String::new()),
    }
}

/// What the report knows of one figure.
#[derive(Debug, Clone, Serialize)]
pub struct FigureReport {
    /// How its binary ended.
    pub run: FigureRun,
    /// Paper and figure from its summary.
    pub paper: String,
    /// Tier of its summary.
    pub tier: String,
    /// Rule reading.
    pub rules: String,
    /// Seeds of its runs.
    pub seeds: Vec<u64>,
    /// wall_seconds of its summary (this invocation's analysis and runs).
    pub summary_wall_seconds: Option<f64>,
    /// cpu_seconds of its summary: CPU of this invocation, all threads
    /// (runs resumed from `--out` cost only their reading).
    pub cpu_seconds: Option<f64>,
    /// Site updates of all its runs.
    pub site_updates: Option<f64>,
    /// PNG files of its folder, sorted.
    pub pngs: Vec<String>,
    /// CSV files of its folder, sorted.
    pub csvs: Vec<String>,
    /// Why its summary could not be read, if so.
    pub summary_problem: Option<String>,
}

/// The whole report.
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    /// Tier of the report.
    pub tier: String,
    /// One entry per figure run.
    pub figures: Vec<FigureReport>,
    /// One row per check of every figure that succeeded.
    pub rows: Vec<Row>,
    /// Reproducibility stamp.
    pub stamp: Stamp,
    /// Link from the page to the known-discrepancies section of
    /// EXPERIMENTS.md.
    pub discrepancy_link: String,
    /// Path from the page to the figures' folders: `../` beside `--out`,
    /// empty in a published copy ([`publish`]).
    pub figures_base: String,
    /// Paragraphs shown under the headline (a published copy says what it
    /// left out).
    pub preface: Vec<String>,
}

/// What identifies a report's computation.
#[derive(Debug, Clone, Serialize)]
pub struct Stamp {
    /// Crate version.
    pub version: String,
    /// `git rev-parse HEAD` of the source tree ("unknown" outside git),
    /// with " (modified)" when the tree has uncommitted changes.
    pub commit: String,
    /// The report's command line.
    pub command_line: String,
    /// The command that regenerates the report from a clone at `commit`.
    pub regenerate: String,
    /// The `--seed` given ("default" when not).
    pub seed: String,
    /// Cores available.
    pub cores: usize,
    /// `--threads` given ("default" when not).
    pub threads: String,
    /// Wall-clock seconds of the whole report.
    pub wall_seconds: f64,
}

/// The source commit: `git rev-parse HEAD` in the crate's folder.
pub fn git_commit() -> String {
    let dir = env!("CARGO_MANIFEST_DIR");
    let out = Command::new("git")
        .args(["-C", dir, "rev-parse", "HEAD"])
        .stderr(Stdio::null())
        .output();
    let Ok(out) =
        out.as_ref()
            .map_err(|_| ())
            .and_then(|o| if o.status.success() { Ok(o) } else { Err(()) })
    else {
        return "unknown".into();
    };
    let head = String::from_utf8_lossy(&out.stdout).trim().to_string();
    let dirty = Command::new("git")
        .args(["-C", dir, "status", "--porcelain", "--untracked-files=no"])
        .stderr(Stdio::null())
        .output()
        .map(|o| !o.stdout.is_empty())
        .unwrap_or(false);
    if dirty {
        format!("{head} (modified)")
    } else {
        head
    }
}

/// The verdicts a check may carry.
const VERDICTS: [&str; 3] = ["reproduced", "not-reproduced", "undecided"];

/// The kinds a check may state (a check of the older format states none).
const KINDS: [&str; 3] = ["published", "pinned", "identity"];

/// Refuse a summary.json the report cannot grade: no `checks` list (or an
/// empty one), a check without a name, a kind or verdict outside the known
/// ones, or a decided verdict without a finite measured value. Names the
/// check and field.
fn check_summary(s: &Value) -> std::result::Result<(), String> {
    let checks = match s.get("checks") {
        Some(Value::Array(c)) if !c.is_empty() => c,
        Some(Value::Array(_)) => return Err("malformed: `checks` is empty".into()),
        Some(_) => return Err("malformed: `checks` is not a list".into()),
        None => return Err("malformed: no `checks` field".into()),
    };
    for (i, c) in checks.iter().enumerate() {
        let Some(name) = c["name"].as_str().filter(|n| !n.is_empty()) else {
            return Err(format!("malformed: check {i} has no `name`"));
        };
        let bad =
            |field: &str, what: String| Err(format!("malformed: check {name}: `{field}` {what}"));
        match &c["kind"] {
            Value::Null => {}
            Value::String(k) if KINDS.contains(&k.as_str()) => {}
            k => return bad("kind", format!("is {k}, not one of {}", KINDS.join(", "))),
        }
        let verdict = match &c["verdict"] {
            Value::Null => None,
            Value::String(v) if VERDICTS.contains(&v.as_str()) => Some(v.as_str()),
            v => {
                return bad(
                    "verdict",
                    format!("is {v}, not one of {}", VERDICTS.join(", ")),
                )
            }
        };
        let decided = verdict.map_or(c["pass"].is_boolean(), |v| v != "undecided");
        if decided && finite(&c["measured"]).is_none() {
            return bad(
                "measured",
                format!(
                    "is {}, but a decided check needs a finite measured value",
                    c["measured"]
                ),
            );
        }
        // every verdict recomputed by the one rule: a hand-edited value,
        // SE, margin or verdict that disagree is refused, not taken at its word
        crate::run::verify_check(c).map_err(|e| format!("malformed: check {name}: {e}"))?;
    }
    match s.get("metrics") {
        None | Some(Value::Object(_)) => {}
        Some(m) => {
            return Err(format!(
                "malformed: `metrics` is {m}, not an object of named numbers"
            ))
        }
    }
    Ok(())
}

/// Read `out/<binary>/` after its run: the figure's summary fields, its
/// rows (none when the run failed) and its files.
pub fn read_figure(out: &Path, run: FigureRun) -> (FigureReport, Vec<Row>) {
    let dir = out.join(&run.binary);
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .map(|d| {
            d.filter_map(|e| e.ok())
                .filter(|e| e.path().is_file())
                .filter_map(|e| e.file_name().into_string().ok())
                .collect()
        })
        .unwrap_or_default();
    files.sort();
    let with =
        |ext: &str| -> Vec<String> { files.iter().filter(|f| f.ends_with(ext)).cloned().collect() };
    let mut fr = FigureReport {
        paper: run.binary.clone(),
        tier: String::new(),
        rules: String::new(),
        seeds: vec![],
        summary_wall_seconds: None,
        cpu_seconds: None,
        site_updates: None,
        pngs: with(".png"),
        csvs: with(".csv"),
        summary_problem: None,
        run,
    };
    let path = dir.join("summary.json");
    if !fr.run.ok {
        if path.exists() {
            fr.summary_problem =
                Some("a summary.json of an earlier run exists; it is not used".into());
        }
        return (fr, vec![]);
    }
    let s: Value = match std::fs::read_to_string(&path)
        .map_err(|e| e.to_string())
        .and_then(|t| serde_json::from_str(&t).map_err(|e| e.to_string()))
        .and_then(|s| check_summary(&s).map(|()| s))
    {
        Ok(s) => s,
        Err(e) => {
            let problem = format!("cannot read {}: {e}", path.display());
            fr.summary_problem = Some(problem.clone());
            fr.run.ok = false;
            fr.run.failure = Some(problem);
            return (fr, vec![]);
        }
    };
    // files an earlier run left, which this summary's run did not write
    let stale: Vec<&str> = s["stale_files"]
        .as_array()
        .map(|a| a.iter().filter_map(Value::as_str).collect())
        .unwrap_or_default();
    fr.pngs.retain(|f| !stale.contains(&f.as_str()));
    fr.csvs.retain(|f| !stale.contains(&f.as_str()));
    fr.paper = s["paper"].as_str().unwrap_or(&fr.run.binary).to_string();
    fr.tier = s["tier"].as_str().unwrap_or("").to_string();
    fr.rules = s["rules"].as_str().unwrap_or("").to_string();
    fr.seeds = s["seeds"]
        .as_array()
        .map(|a| a.iter().filter_map(Value::as_u64).collect())
        .unwrap_or_default();
    fr.summary_wall_seconds = finite(&s["wall_seconds"]);
    fr.cpu_seconds = finite(&s["cpu_seconds"]);
    fr.site_updates = finite(&s["site_updates"]);
    let rows = s["checks"]
        .as_array()
        .map(|cs| {
            cs.iter()
                .map(|c| Row::from_json(&fr.run.binary, &s, c))
                .collect()
        })
        .unwrap_or_default();
    (fr, rows)
}

/// The GitHub-style anchor of a Markdown heading.
pub fn slug(heading: &str) -> String {
    heading
        .trim_start_matches('#')
        .trim()
        .to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
            _ => None,
        })
        .collect()
}

/// Relative path from folder `from` to file `to` (both made absolute).
fn relative(from: &Path, to: &Path) -> Option<String> {
    let from = std::fs::canonicalize(from).ok()?;
    let to = std::fs::canonicalize(to).ok()?;
    let f: Vec<_> = from.components().collect();
    let t: Vec<_> = to.components().collect();
    let common = f.iter().zip(&t).take_while(|(a, b)| a == b).count();
    let mut parts: Vec<String> = vec!["..".into(); f.len() - common];
    parts.extend(
        t[common..]
            .iter()
            .map(|c| c.as_os_str().to_string_lossy().into_owned()),
    );
    Some(parts.join("/"))
}

/// Link from `report_dir` to the known-discrepancies section of the
/// crate's EXPERIMENTS.md (relative when the file is found).
fn discrepancy_link(report_dir: &Path) -> String {
    let exp = Path::new(env!("CARGO_MANIFEST_DIR")).join("EXPERIMENTS.md");
    let heading = std::fs::read_to_string(&exp)
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with(DISCREPANCY_HEADING))
                .map(String::from)
        })
        .unwrap_or_else(|| DISCREPANCY_HEADING.to_string());
    let file = relative(report_dir, &exp).unwrap_or_else(|| "EXPERIMENTS.md".into());
    format!("{file}#{}", slug(&heading))
}

/// Run the figures of `opts` one after the other and write the report.
/// Returns the report (its `figures` say which failed).
pub fn run(opts: &Options) -> Result<Report> {
    let start = Instant::now();
    let n = opts.figures.len();
    let mut runs = vec![];
    for (i, b) in opts.figures.iter().enumerate() {
        if opts.no_run {
            runs.push(summary_only(&opts.out, b));
            continue;
        }
        eprintln!(
            "report: [{}/{n}] {b} {}",
            i + 1,
            figure_args(opts, b).join(" ")
        );
        let r = run_figure(opts, b);
        match &r.failure {
            None => eprintln!("report: {b} done in {:.1} s", r.wall_seconds),
            Some(f) => eprintln!("report: {b} FAILED ({f}); continuing"),
        }
        runs.push(r);
    }
    let mut report = collect(opts, runs);
    if opts.no_run {
        report.preface.push(format!(
            "Re-rendered with --no-run from the summaries in {}: the CPU and wall times are those of the runs that wrote them.",
            opts.out.display()
        ));
    }
    if let Some(dir) = &opts.seed_sets {
        let (matched, said) = attach_seed_sets(&mut report, &opts.out, dir);
        if !matched.is_empty() {
            report.preface.push(format!(
                "Graded over committed seed sets ({}) where this run's own seed set equals its committed twin in every check and metric they share (a cut of a figure has fewer; a figure graded sequentially is compared by runs, on the checks that ran as many runs as the committed ones), so the code at hand computes what they hold: {}.",
                dir.display(),
                matched.join(", ")
            ));
        }
        report.preface.extend(said);
    }
    report.stamp.wall_seconds = start.elapsed().as_secs_f64();
    write(&opts.out, &report)?;
    Ok(report)
}

/// Figure `binary` as found in `out` without running it (`--no-run`): ok
/// when `out/<binary>/summary.json` exists, with that summary's wall time.
/// The run of figure `binary` as recorded by its summary already in `out`
/// (`--no-run`, or a resumed run): ok when the summary exists.
pub fn summary_only(out: &Path, binary: &str) -> FigureRun {
    let path = out.join(binary).join("summary.json");
    let wall = std::fs::read_to_string(&path)
        .ok()
        .and_then(|t| serde_json::from_str::<Value>(&t).ok())
        .and_then(|s| finite(&s["wall_seconds"]));
    FigureRun {
        binary: binary.to_string(),
        ok: path.is_file(),
        failure: (!path.is_file()).then(|| format!("--no-run and no {} to read", path.display())),
        stderr_tail: vec![],
        wall_seconds: wall.unwrap_or(0.0),
    }
}

/// Grade the published checks over every seed set in
/// `dir/<binary>/` of the figures that have at least [`MIN_SEED_SETS`]
/// ([`SeedSets`]), when the figure's own run in `out` is one of those seed
/// sets, result for result
/// ([`crate::drivers::acceptance_study::committed_twin`]): so the committed
/// seed sets are graded only where the code at hand is shown to compute
/// what they hold. Then the same for each cut of the figure ([`cuts_of`]:
/// fewer checks at the same set-up and seeds, filed by
/// `docs/acceptance/run-seeds.sh --as`), for the checks the whole figure's
/// seed sets left ungraded; a cut's twin is compared on the results it has.
/// Returns the figures so graded, each with the seed folder its run matched,
/// and one sentence per figure or cut whose seed sets were not graded,
/// saying why (also for an unreadable folder). A figure without such a
/// folder keeps its rows as they are.
pub fn attach_seed_sets(report: &mut Report, out: &Path, dir: &Path) -> (Vec<String>, Vec<String>) {
    let (mut matched, mut said) = (vec![], vec![]);
    let binaries: Vec<String> = report
        .figures
        .iter()
        .map(|f| f.run.binary.clone())
        .collect();
    for b in &binaries {
        let whole = std::iter::once((dir.join(b), None));
        let cuts = cuts_of(dir, b).into_iter().map(|(f, args)| (f, Some(args)));
        for (from, cut) in whole.chain(cuts) {
            match seed_sets_of(report, out, b, &from) {
                Ok(Some((folder, n))) => matched.push(match &cut {
                    None => format!("{b} ({folder} of {n})"),
                    Some(args) => format!(
                        "{b} (cut {}, `{args}`: {folder} of {n})",
                        from.file_name()
                            .map_or(String::new(), |f| f.to_string_lossy().into_owned())
                    ),
                }),
                Ok(None) => {}
                Err(why) => said.push(why),
            }
        }
    }
    (matched, said)
}

/// The cuts of figure `binary` in `dir`: each folder holding a `cut.txt`
/// whose first word is `binary` (the rest: the options that cut it), sorted
/// by name. `docs/acceptance/run-seeds.sh --as NAME -- ARGS` writes it.
pub fn cuts_of(dir: &Path, binary: &str) -> Vec<(PathBuf, String)> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return vec![];
    };
    let mut cuts: Vec<(PathBuf, String)> = entries
        .filter_map(|e| {
            let folder = e.ok()?.path();
            let text = std::fs::read_to_string(folder.join("cut.txt")).ok()?;
            let (fig, args) = text.trim().split_once(' ')?;
            (fig == binary).then(|| (folder, args.trim().to_string()))
        })
        .collect();
    cuts.sort();
    cuts
}

/// Grade the rows of figure `b` that have no seed sets yet over the seed
/// sets in `from` ([`attach_seed_sets`]): `Ok(Some((seed folder matched,
/// seed sets)))` when graded, `Ok(None)` when `from` has none or fewer than
/// [`MIN_SEED_SETS`], `Err(why)` when they were not graded.
fn seed_sets_of(
    report: &mut Report,
    out: &Path,
    b: &str,
    from: &Path,
) -> std::result::Result<Option<(String, usize)>, String> {
    use crate::drivers::acceptance_study::{all_seeds, committed_twin, Twin};
    let (n, all) = match all_seeds(from, b) {
        Ok(x) => x,
        // a figure without seed sets says nothing; an unreadable one says why
        Err(e) if from.is_dir() => return Err(format!("{b}: not graded over its seed sets: {e}")),
        Err(_) => return Ok(None),
    };
    if n < MIN_SEED_SETS {
        return Ok(None);
    }
    let summary = std::fs::read_to_string(out.join(b).join("summary.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<Value>(&t).ok());
    let committed = match summary.map(|s| committed_twin(from, b, &s)) {
        Some(Ok(Twin::Identical { committed })) => committed,
        Some(Ok(Twin::Differs { committed, what })) => return Err(format!(
            "{b}: NOT graded over its {n} committed seed sets: this run has the runs of {} but other results ({what}), so the code that wrote them computes otherwise; refile them (docs/acceptance/run-seeds.sh --refile).",
            committed.display()
        )),
        Some(Ok(Twin::NotAmong)) => return Err(format!(
            "{b}: not graded over its {n} committed seed sets in {}: none has this run's seeds (base seed or tier), so none shows the code at hand computes what they hold.",
            from.display()
        )),
        Some(Err(e)) => return Err(format!("{b}: not graded over its seed sets: {e}")),
        None => return Err(format!(
            "{b}: not graded over its seed sets: no readable {}",
            out.join(b).join("summary.json").display()
        )),
    };
    // the seed folder, e.g. `seed-1`
    let folder = committed
        .strip_prefix(from)
        .ok()
        .and_then(|p| p.components().next())
        .map_or(committed.display().to_string(), |c| {
            c.as_os_str().to_string_lossy().into_owned()
        });
    for a in all {
        let row = report
            .rows
            .iter_mut()
            .find(|r| r.binary == b && r.name == a.check && r.seed_sets.is_none());
        if let Some(row) = row {
            row.seed_sets = Some(SeedSets {
                seeds: a.seeds,
                measured: a.estimate.map(|e| e.mean).filter(|x| x.is_finite()),
                error: a.estimate.map(|e| e.se).filter(|x| x.is_finite()),
                verdict: a.verdict.status().to_string(),
                from: from.display().to_string(),
            });
        }
    }
    Ok(Some((folder, n)))
}

/// One line per published check graded over committed seed sets, for the
/// terminal: the verdict over the seed sets, then this run's.
pub fn seed_set_lines(r: &Report) -> Vec<String> {
    r.rows
        .iter()
        .filter_map(|x| {
            let s = x.seed_sets.as_ref()?;
            let num = |v: Option<f64>| v.map_or("no value".to_string(), |v| format!("{v:.4}"));
            Some(format!(
                "[{}] {} {} over {} seed sets: {} +- {} (this run: {} {} +- {}, {} runs)",
                s.verdict.to_uppercase(),
                x.binary,
                x.name,
                s.seeds,
                num(s.measured),
                num(s.error),
                x.verdict,
                num(x.measured),
                num(x.error),
                x.runs.map_or("?".to_string(), |n| n.to_string()),
            ))
        })
        .collect()
}

/// An error naming the figures of `r` that failed, each with why; `Ok`
/// when none did.
pub fn fail_on_failed_figures(r: &Report) -> Result<()> {
    let failed: Vec<String> = r
        .figures
        .iter()
        .filter(|f| !f.run.ok)
        .map(|f| match &f.run.failure {
            Some(why) => format!("{} ({why})", f.run.binary),
            None => f.run.binary.clone(),
        })
        .collect();
    if failed.is_empty() {
        return Ok(());
    }
    Err(Error::new(
        ErrorKind::Io,
        format!(
            "{} of {} figures failed: {} (listed in the report)",
            failed.len(),
            r.figures.len(),
            failed.join(", ")
        ),
    ))
}

/// The folder of the figure binaries: the report's own.
pub fn bin_dir() -> PathBuf {
    std::env::current_exe()
        .ok()
        .and_then(|p| p.parent().map(PathBuf::from))
        .unwrap_or_else(|| PathBuf::from("."))
}

/// Check the report's folders before anything runs: `--seed-sets` must be
/// a folder, and `--publish` apart from `--out` ([`check_publish_folder`]).
pub fn check_folders(out: &Path, publish: Option<&Path>, seed_sets: Option<&Path>) -> Result<()> {
    if let Some(d) = seed_sets.filter(|d| !d.is_dir()) {
        return Err(Error::new(
            ErrorKind::InvalidParameter,
            format!(
                "--seed-sets {}: not a folder; give the folder of committed seed sets, e.g. docs/acceptance",
                d.display()
            ),
        ));
    }
    publish.map_or(Ok(()), |p| check_publish_folder(out, p))
}

/// Assemble the report from finished `runs` (reads their summaries).
pub fn collect(opts: &Options, runs: Vec<FigureRun>) -> Report {
    let mut figures = vec![];
    let mut rows = vec![];
    for r in runs {
        let (mut f, rs) = read_figure(&opts.out, r);
        if f.run.ok && f.tier != opts.tier.name() {
            let problem = format!(
                "its summary.json is of the {} tier, this report's is {}: rerun with --tier {}",
                if f.tier.is_empty() {
                    "unstated"
                } else {
                    &f.tier
                },
                opts.tier.name(),
                if f.tier.is_empty() { "TIER" } else { &f.tier },
            );
            f.summary_problem = Some(problem.clone());
            f.run.ok = false;
            f.run.failure = Some(problem);
            figures.push(f);
            continue;
        }
        figures.push(f);
        rows.extend(rs);
    }
    let report_dir = opts.out.join("report");
    let _ = std::fs::create_dir_all(&report_dir);
    Report {
        tier: opts.tier.name().to_string(),
        figures,
        rows,
        stamp: Stamp {
            version: env!("CARGO_PKG_VERSION").to_string(),
            commit: git_commit(),
            command_line: opts.command_line.clone(),
            regenerate: regenerate(&opts.command_line),
            seed: opts
                .seed
                .map_or("default of each figure (1)".into(), |s| s.to_string()),
            cores: crate::run::threads(),
            threads: opts
                .threads
                .map_or("default (all cores)".into(), |t| t.to_string()),
            wall_seconds: 0.0,
        },
        discrepancy_link: discrepancy_link(&report_dir),
        figures_base: "../".into(),
        preface: vec![],
    }
}

/// Write `out/report/{REPORT.md, index.html, report.json}`.
pub fn write(out: &Path, report: &Report) -> Result<()> {
    write_pages(&out.join("report"), report)
}

/// Widest image of a published copy, in pixels (the figures' own PNGs
/// are up to a few thousand pixels wide and weigh up to 2 MB each).
pub const PUBLISH_WIDTH: u32 = 640;

/// Largest CSV a published copy keeps, in bytes.
pub const PUBLISH_CSV_BYTES: u64 = 100_000;

/// Write a self-contained copy of `report` (computed in `out`) to `dest`:
/// `REPORT.md`, `index.html` and `report.json` in `dest`, and per figure
/// `dest/<binary>/` with its summary.json, its PNGs reduced to at most
/// [`PUBLISH_WIDTH`] pixels wide and its CSVs of at most
/// [`PUBLISH_CSV_BYTES`]. The page links into `dest` and says what it
/// left out.
///
/// Nothing is deleted before the whole copy is written: every figure is
/// first copied into a staging folder in `dest`, and only then does each
/// replace the figure folder of an earlier copy. A `dest` equal to `out`,
/// inside it or holding it is refused (the copy would overwrite its own
/// sources), and so is a figure folder in `dest` that holds anything a
/// published copy does not write (summary.json, PNG and CSV files).
pub fn publish(out: &Path, report: &Report, dest: &Path) -> Result<()> {
    let io =
        |what: String| move |e: std::io::Error| Error::new(ErrorKind::Io, format!("{what}: {e}"));
    check_publish_folder(out, dest)?;
    std::fs::create_dir_all(dest).map_err(io(format!("cannot create {}", dest.display())))?;
    let mut r = report.clone();
    r.figures_base = String::new();
    r.discrepancy_link = discrepancy_link(dest);
    for f in &r.figures {
        check_replaceable(&dest.join(&f.run.binary))?;
    }
    let staging = dest.join(".publish-staging");
    if staging.exists() {
        std::fs::remove_dir_all(&staging)
            .map_err(io(format!("cannot clear {}", staging.display())))?;
    }
    let mut left_out = vec![];
    for f in &mut r.figures {
        let (src, dst) = (out.join(&f.run.binary), staging.join(&f.run.binary));
        std::fs::create_dir_all(&dst).map_err(io(format!("cannot create {}", dst.display())))?;
        if f.summary_problem.is_none() && f.run.ok {
            let from = src.join("summary.json");
            std::fs::copy(&from, dst.join("summary.json"))
                .map_err(io(format!("cannot copy {}", from.display())))?;
        }
        for p in &f.pngs {
            reduce_png(&src.join(p), &dst.join(p), PUBLISH_WIDTH)?;
        }
        let mut kept = vec![];
        for c in &f.csvs {
            let from = src.join(c);
            let size = std::fs::metadata(&from)
                .map_err(io(format!("cannot read {}", from.display())))?
                .len();
            if size <= PUBLISH_CSV_BYTES {
                std::fs::copy(&from, dst.join(c))
                    .map_err(io(format!("cannot copy {}", from.display())))?;
                kept.push(c.clone());
            } else {
                left_out.push(format!("{}/{c} ({} kB)", f.run.binary, size / 1000));
            }
        }
        f.csvs = kept;
    }
    for f in &r.figures {
        let (staged, dst) = (staging.join(&f.run.binary), dest.join(&f.run.binary));
        if dst.exists() {
            std::fs::remove_dir_all(&dst)
                .map_err(io(format!("cannot replace {}", dst.display())))?;
        }
        std::fs::rename(&staged, &dst).map_err(io(format!("cannot move {}", staged.display())))?;
    }
    std::fs::remove_dir_all(&staging).map_err(io(format!("cannot clear {}", staging.display())))?;
    r.preface.push(format!(
        "This is a published copy: every figure's summary.json, its pictures reduced to at most {PUBLISH_WIDTH} px wide, and its CSVs of at most {} kB{}. The regenerate command writes them all at full size.",
        PUBLISH_CSV_BYTES / 1000,
        if left_out.is_empty() {
            String::new()
        } else {
            format!(" (left out: {})", left_out.join(", "))
        }
    ));
    if dest.join("README.md").is_file() {
        r.preface.push(
            "The CPU column counts only this invocation, which resumed saved runs; the cost of computing everything from nothing is in README.md beside this page."
                .into(),
        );
    }
    write_pages(dest, &r)
}

/// `path` made absolute with its symbolic links resolved, also when it does
/// not exist yet (its nearest existing ancestor is resolved).
fn resolved(path: &Path) -> PathBuf {
    let abs = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    let mut rest = vec![];
    let mut at = abs.as_path();
    loop {
        if let Ok(c) = at.canonicalize() {
            return rest.iter().rev().fold(c, |p, name| p.join(name));
        }
        match (at.parent(), at.file_name()) {
            (Some(parent), Some(name)) => {
                rest.push(name.to_os_string());
                at = parent;
            }
            _ => return abs,
        }
    }
}

/// Refuse a publish folder that is the report's `--out`, lies inside it or
/// holds it: publishing there would replace the summaries it copies from.
pub fn check_publish_folder(out: &Path, dest: &Path) -> Result<()> {
    // a file where the folder should go is refused before any figure runs
    if dest.exists() && !dest.is_dir() {
        return Err(Error::new(
            ErrorKind::InvalidParameter,
            format!(
                "--publish {}: is a file, not a folder; give a folder for the published copy; nothing was written",
                dest.display()
            ),
        ));
    }
    let (o, d) = (resolved(out), resolved(dest));
    if d.starts_with(&o) || o.starts_with(&d) {
        return Err(Error::new(
            ErrorKind::InvalidParameter,
            format!(
                "--publish {}: the copy must go to a folder apart from --out {} (neither inside the other); nothing was written",
                dest.display(),
                out.display()
            ),
        ));
    }
    Ok(())
}

/// A figure folder of an earlier published copy may be replaced: it holds
/// only files a copy writes (summary.json, PNGs, CSVs), no folders.
fn check_replaceable(dir: &Path) -> Result<()> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Ok(());
    };
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let ours = e.file_type().is_ok_and(|t| t.is_file())
            && (name == "summary.json" || name.ends_with(".png") || name.ends_with(".csv"));
        if !ours {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                format!(
                    "--publish: {} holds {name}, which a published copy does not write; refusing to replace it (move it or publish elsewhere); nothing was written",
                    dir.display()
                ),
            ));
        }
    }
    Ok(())
}

/// Copy PNG `from` to `to`, reduced to at most `width` pixels wide (its
/// aspect kept; a narrower image is copied as it is).
fn reduce_png(from: &Path, to: &Path, width: u32) -> Result<()> {
    use image::ImageEncoder;
    let bad = |e: String| {
        Error::new(
            ErrorKind::Io,
            format!("cannot reduce {}: {e}", from.display()),
        )
    };
    let img = image::open(from).map_err(|e| bad(e.to_string()))?;
    if img.width() <= width {
        std::fs::copy(from, to).map_err(|e| bad(e.to_string()))?;
        return Ok(());
    }
    let height =
        (u64::from(img.height()) * u64::from(width) / u64::from(img.width())).max(1) as u32;
    let small = img
        .resize_exact(width, height, image::imageops::FilterType::Triangle)
        .to_rgb8();
    let mut bytes = vec![];
    image::codecs::png::PngEncoder::new_with_quality(
        &mut bytes,
        image::codecs::png::CompressionType::Best,
        image::codecs::png::FilterType::Adaptive,
    )
    .write_image(&small, width, height, image::ColorType::Rgb8)
    .map_err(|e| bad(e.to_string()))?;
    write_atomic(to, &bytes)
}

/// Write `dir/{REPORT.md, index.html, report.json}`.
fn write_pages(dir: &Path, report: &Report) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| {
        Error::new(
            ErrorKind::Io,
            format!("cannot create {}: {e}; choose another --out", dir.display()),
        )
    })?;
    write_atomic(&dir.join("REPORT.md"), markdown(report).as_bytes())?;
    write_atomic(&dir.join("index.html"), html(report).as_bytes())?;
    write_atomic(&dir.join("headline.svg"), headline_svg(report).as_bytes())?;
    let json = serde_json::to_string_pretty(report)
        .map_err(|e| Error::new(ErrorKind::Io, format!("cannot serialise the report: {e}")))?;
    write_atomic(&dir.join("report.json"), json.as_bytes())?;
    Ok(())
}

/// `text` without the lines that carry wall times (for comparing reports).
pub fn without_timing(text: &str) -> String {
    text.lines()
        .filter(|l| !l.contains(TIMING_MARK) && !l.contains(HTML_TIMING_MARK))
        .collect::<Vec<_>>()
        .join("\n")
}

/// A number with about four significant digits ("n/a" when absent).
pub fn num(x: Option<f64>) -> String {
    match x {
        None => "n/a".into(),
        Some(x) => sig(x, 4),
    }
}

fn sig(x: f64, digits: i32) -> String {
    if x == 0.0 {
        return "0".into();
    }
    let mag = x.abs().log10().floor() as i32;
    if !(-3..6).contains(&mag) {
        return format!("{:.*e}", (digits - 1) as usize, x);
    }
    let decimals = (digits - 1 - mag).max(0) as usize;
    format!("{x:.decimals$}")
}

/// `measured ± SE` (the SE with two significant digits).
fn measured(r: &Row) -> String {
    match (r.measured, r.error) {
        (Some(m), Some(e)) if e > 0.0 => format!("{} ± {}", sig(m, 4), sig(e, 2)),
        (m, _) => num(m),
    }
}

/// `published (margin t)`.
fn published(r: &Row) -> String {
    match (r.published, r.tolerance) {
        (None, _) => "—".into(),
        (Some(p), Some(t)) => format!("{} (margin {})", sig(p, 4), sig(t, 2)),
        (Some(p), None) => sig(p, 4),
    }
}

/// The note cut to about `max` characters at a word boundary.
pub fn shorten(note: &str, max: usize) -> String {
    let first = note.split("; NOT REPRODUCED").next().unwrap_or(note).trim();
    if first.chars().count() <= max {
        return first.to_string();
    }
    let cut: String = first.chars().take(max).collect();
    let cut = match cut.rfind(' ') {
        Some(i) if i > max / 2 => &cut[..i],
        _ => &cut[..],
    };
    format!("{}…", cut.trim_end_matches([',', ';', ':', ' ']))
}

/// The claim cell: shortened note, with the source when stated.
fn claim(r: &Row) -> String {
    let s = shorten(&r.note, 90);
    if r.source.is_empty() {
        s
    } else {
        format!("{s} [{}]", r.source)
    }
}

/// Site updates as `6.83e9`.
fn updates(x: Option<f64>) -> String {
    match x {
        Some(x) if x > 0.0 => format!("{x:.2e}"),
        Some(_) => "0".into(),
        None => "n/a".into(),
    }
}

/// Counts of the report's rows.
struct Counts {
    published: usize,
    verdicts: BTreeMap<String, usize>,
    kinds: BTreeMap<String, usize>,
    readings: BTreeMap<String, usize>,
}

fn counts(r: &Report) -> Counts {
    let mut c = Counts {
        published: 0,
        verdicts: BTreeMap::new(),
        kinds: BTreeMap::new(),
        readings: BTreeMap::new(),
    };
    for row in &r.rows {
        *c.verdicts.entry(row.verdict.clone()).or_default() += 1;
        *c.kinds.entry(row.kind.clone()).or_default() += 1;
        if row.is_default_claim() {
            c.published += 1;
        }
    }
    for f in r.figures.iter().filter(|f| !f.rules.is_empty()) {
        *c.readings.entry(f.rules.clone()).or_default() += 1;
    }
    c
}

fn list(m: &BTreeMap<String, usize>) -> String {
    m.iter()
        .map(|(k, v)| format!("{v} {k}"))
        .collect::<Vec<_>>()
        .join(", ")
}

fn headline(r: &Report) -> String {
    let c = counts(r);
    // readings that differ only past the cut (e.g. the hopper's figure
    // set-up, rain sigma 12 or 18) are counted as one
    let mut short: BTreeMap<String, usize> = BTreeMap::new();
    for (k, v) in &c.readings {
        *short.entry(shorten(k, 70)).or_default() += v;
    }
    let readings = short
        .iter()
        .map(|(k, v)| format!("`{k}` ({v} figure{})", if *v == 1 { "" } else { "s" }))
        .collect::<Vec<_>>()
        .join(", ");
    let failed = r.figures.iter().filter(|f| !f.run.ok).count();
    let [yes, no, open] = tally(r.rows.iter());
    let mut s = format!(
        "{yes} of {} published claims of the default reading reproduced at the {} tier, {no} not reproduced, {open} undecided ({} figure{} run{}), default rule readings: {}.",
        c.published,
        r.tier,
        r.figures.len(),
        if r.figures.len() == 1 { "" } else { "s" },
        if failed > 0 {
            format!(", {failed} FAILED")
        } else {
            String::new()
        },
        if readings.is_empty() { "none".into() } else { readings }
    );
    if c.kinds.contains_key("unstated") {
        s.push_str(" Checks of the older format state no kind: those with a published number count as published claims.");
    }
    if let Some(t) = seed_sets_sentence(r) {
        s.push(' ');
        s.push_str(&t);
    }
    s
}

/// The default reading's published claims with a verdict over every
/// committed seed set ([`SeedSets`]).
fn seed_set_rows(r: &Report) -> Vec<&Row> {
    r.rows
        .iter()
        .filter(|x| x.is_default_claim() && x.seed_sets.is_some())
        .collect()
}

/// The headline's count with the verdicts over every committed seed set
/// where there are (None when there are none).
fn seed_sets_sentence(r: &Report) -> Option<String> {
    let rows = seed_set_rows(r);
    if rows.is_empty() {
        return None;
    }
    let changed = rows
        .iter()
        .filter(|x| x.final_verdict() != x.verdict)
        .count();
    let mut t = [0usize; 3];
    for x in r.rows.iter().filter(|x| x.is_default_claim()) {
        match x.final_verdict() {
            "reproduced" => t[0] += 1,
            "not-reproduced" => t[1] += 1,
            _ => t[2] += 1,
        }
    }
    let all = t[0] + t[1] + t[2];
    let mut figures: Vec<&str> = rows.iter().map(|x| x.binary.as_str()).collect();
    figures.dedup();
    Some(format!(
        "Graded over every committed seed set (at least {MIN_SEED_SETS} base seeds of this tier: {}), {} published claims get a verdict of all their runs, {changed} of them a different one; with those verdicts {} reproduced, {} not reproduced, {} undecided: {} of {all} decided ({:.1} %).",
        figures.join(", "),
        rows.len(),
        t[0],
        t[1],
        t[2],
        t[0] + t[1],
        100.0 * (t[0] + t[1]) as f64 / all.max(1) as f64
    ))
}

/// The default reading's published claims that are not reproduced.
fn discrepancies(r: &Report) -> Vec<&Row> {
    r.rows
        .iter()
        .filter(|x| x.is_default_claim() && x.verdict == "not-reproduced")
        .collect()
}

/// The default reading's published claims that are undecided.
fn undecided(r: &Report) -> Vec<&Row> {
    r.rows
        .iter()
        .filter(|x| x.is_default_claim() && x.verdict == "undecided")
        .collect()
}

/// One list item per row of `rows` (the known discrepancies, the undecided
/// claims): the claim, its published and measured values and `why` of it;
/// in markdown, or escaped in HTML when `html`.
fn claim_items(out: &mut String, rows: &[&Row], html: bool, why: impl Fn(&Row) -> String) {
    for x in rows {
        let [paper, figure, name, given, got, why] = [
            x.paper.clone(),
            x.figure.clone(),
            x.name.clone(),
            published(x),
            measured(x),
            why(x),
        ]
        .map(|t| if html { esc(&t) } else { t });
        let _ = if html {
            writeln!(
                out,
                "<li>{paper} {figure} <code>{name}</code>: published {given}, measured {got}: {why}</li>"
            )
        } else {
            writeln!(
                out,
                "- {paper} {figure} `{name}`: published {given}, measured {got}: {why}"
            )
        };
    }
}

/// The figures of `r` whose binary failed.
fn failed_figures(r: &Report) -> Vec<&FigureReport> {
    r.figures.iter().filter(|f| !f.run.ok).collect()
}

/// Why figure `f` failed: its binary's failure, then why its summary could
/// not be read, if so, in parentheses.
fn why_failed(f: &FigureReport) -> String {
    let failure = f.run.failure.as_deref().unwrap_or("");
    match &f.summary_problem {
        Some(p) => format!("{failure} ({p})"),
        None => failure.to_string(),
    }
}

/// Published claims of the default reading: (reproduced, not reproduced,
/// undecided) of the rows `rows`.
fn tally<'a>(rows: impl Iterator<Item = &'a Row>) -> [usize; 3] {
    let mut t = [0; 3];
    for x in rows.filter(|x| x.is_default_claim()) {
        match x.verdict.as_str() {
            "reproduced" => t[0] += 1,
            "not-reproduced" => t[1] += 1,
            _ => t[2] += 1,
        }
    }
    t
}

/// One line per paper (and per figure of it): the default reading's
/// published claims reproduced / not reproduced / undecided.
fn per_paper(r: &Report) -> Vec<(String, [usize; 3])> {
    // papers in order of first appearance
    let mut papers: Vec<String> = r.rows.iter().map(|x| x.paper.clone()).collect();
    let mut seen = std::collections::BTreeSet::new();
    papers.retain(|p| seen.insert(p.clone()));
    papers
        .into_iter()
        .map(|p| {
            let t = tally(r.rows.iter().filter(|x| x.paper == p));
            (p, t)
        })
        .collect()
}

/// The first line of `note`, cut to `max` characters: the one-line
/// mechanism of a discrepancy.
fn one_line(note: &str, max: usize) -> String {
    shorten(note.lines().next().unwrap_or(""), max)
}

/// Characters of a note shown as a discrepancy's mechanism.
const MECHANISM_CHARS: usize = 240;

fn md_cell(s: &str) -> String {
    s.replace('|', "\\|").replace('\n', " ")
}

/// The report as Markdown.
pub fn markdown(r: &Report) -> String {
    let mut m = String::new();
    let c = counts(r);
    let _ = writeln!(
        m,
        "# Reproduction report: granular-automata {}, {} tier\n",
        r.stamp.version, r.tier
    );
    let _ = writeln!(m, "![{0}](headline.svg)\n\n**{0}**\n", short_headline(r));
    let _ = writeln!(m, "{}\n", headline(r));
    // the stamp carries this invocation's CPU time: a timing line
    let _ = writeln!(m, "{} {TIMING_MARK}\n", top_stamp(r).replace('`', "'"));
    let _ = writeln!(m, "Regenerate: `{}`\n", r.stamp.regenerate);
    for p in &r.preface {
        let _ = writeln!(m, "{p}\n");
    }
    let _ = writeln!(m, "- checks by verdict: {}", list(&c.verdicts));
    let _ = writeln!(m, "- checks by kind: {}", list(&c.kinds));
    let _ = writeln!(m, "- figures: {}\n", r.figures.len());
    let failed = failed_figures(r);
    if !failed.is_empty() {
        let _ = writeln!(m, "## Failed figures\n");
        for f in failed {
            let _ = writeln!(m, "- **{}**: {}", f.run.binary, why_failed(f));
            if !f.run.stderr_tail.is_empty() {
                let _ = writeln!(m, "\n  ```text");
                for l in &f.run.stderr_tail {
                    let _ = writeln!(m, "  {l}");
                }
                let _ = writeln!(m, "  ```");
            }
        }
        m.push('\n');
    }
    let _ = writeln!(m, "## Overview\n");
    let _ = writeln!(
        m,
        "Published claims of the default reading per paper: reproduced / not reproduced / undecided.\n"
    );
    let _ = writeln!(m, "| paper | reproduced | not reproduced | undecided |");
    let _ = writeln!(m, "|---|---|---|---|");
    for (p, [y, n, u]) in per_paper(r) {
        let _ = writeln!(m, "| {p} | {y} | {n} | {u} |");
    }
    let _ = writeln!(
        m,
        "\n| figure | paper | reproduced | not reproduced | undecided | status | CPU (this invocation) | wall time |"
    );
    let _ = writeln!(m, "|---|---|---|---|---|---|---|---|");
    for f in &r.figures {
        let [y, n, u] = tally(r.rows.iter().filter(|x| x.binary == f.run.binary));
        let _ = writeln!(
            m,
            "| [`{b}`]({base}{b}/) | {} | {y} | {n} | {u} | {} | {} | {:.1} s {TIMING_MARK} |",
            f.paper,
            status(f),
            cpu(f.cpu_seconds),
            f.run.wall_seconds,
            b = f.run.binary,
            base = r.figures_base
        );
    }
    let ss = seed_set_rows(r);
    if !ss.is_empty() {
        let _ = writeln!(m, "\n## Over every committed seed set ({})\n", ss.len());
        let _ = writeln!(
            m,
            "The published claims whose figure has at least {MIN_SEED_SETS} committed seed sets at this tier: the seeds' mean with the SE of their spread, graded by the same rule with n = seeds (against the acceptance margin table, or else the claim every seed's summary states). \"This run\" is the verdict of this report's own seed set.\n"
        );
        let _ = writeln!(
            m,
            "| figure | check | this run | seed sets | mean +- SE | published (margin) | verdict over the seed sets |"
        );
        let _ = writeln!(m, "|---|---|---|---|---|---|---|");
        for x in ss {
            let s = x.seed_sets.as_ref().expect("filtered");
            let _ = writeln!(
                m,
                "| {} {} (`{}`) | `{}` | {} | {} | {} +- {} | {} | **{}** |",
                x.paper,
                x.figure,
                x.binary,
                x.name,
                x.verdict,
                s.seeds,
                num(s.measured),
                num(s.error),
                published(x),
                s.verdict
            );
        }
    }
    let d = discrepancies(r);
    let _ = writeln!(m, "\n## Known discrepancies ({})\n", d.len());
    let _ = writeln!(
        m,
        "Published claims of the default reading not reproduced at this tier, each with the mechanism its check records; the explanations are in [EXPERIMENTS.md]({}).\n",
        r.discrepancy_link
    );
    claim_items(&mut m, &d, false, |x| {
        md_cell(&one_line(&x.note, MECHANISM_CHARS))
    });
    let u = undecided(r);
    let _ = writeln!(m, "\n## Undecided ({})\n", u.len());
    let _ = writeln!(
        m,
        "Published claims of the default reading that this tier does not decide, each with what would decide it (the grading rule, |d| +- k SE against the margin with k = max(2, Student t), the SE shrinking as 1/sqrt(runs)).\n"
    );
    claim_items(&mut m, &u, false, Row::what_would_decide);
    let table = |m: &mut String, rows: &[&Row]| {
        let _ = writeln!(m, "| paper | figure | check: claim | published | measured ± SE | verdict | kind | rule reading | site updates |");
        let _ = writeln!(m, "|---|---|---|---|---|---|---|---|---|");
        for x in rows {
            let _ = writeln!(
                m,
                "| {} | {} (`{}`) | `{}`: {} | {} | {} | {} | {} | `{}` | {} |",
                x.paper,
                x.figure,
                x.binary,
                x.name,
                md_cell(&claim(x)),
                published(x),
                measured(x),
                x.verdict,
                x.kind,
                shorten(&x.rules, RULES_CELL),
                updates(x.site_updates)
            );
        }
    };
    let (own, other): (Vec<&Row>, Vec<&Row>) = r.rows.iter().partition(|x| x.reading.is_none());
    let _ = writeln!(m, "\n## Checks\n");
    table(&mut m, &own);
    if !other.is_empty() {
        let _ = writeln!(m, "\n## Checks of other readings ({})\n", other.len());
        let _ = writeln!(
            m,
            "Comparisons: the same checks for readings that are not the default (the case key prefixes each name); not claims of the project and not counted above.\n"
        );
        table(&mut m, &other);
    }
    let _ = writeln!(m, "\n## Figures and cost\n");
    let _ = writeln!(m, "Wall times: `process` is the figure's subprocess, `summary` its own summary.json (a figure that resumed saved runs reports only the analysis); site updates count all its runs.\n");
    let _ = writeln!(
        m,
        "| figure | paper | status | runs (seeds) | site updates | wall time |"
    );
    let _ = writeln!(m, "|---|---|---|---|---|---|");
    for f in &r.figures {
        let _ = writeln!(
            m,
            "| `{}` | {} | {} | {} | {} | process {:.1} s, summary {} s {TIMING_MARK} |",
            f.run.binary,
            f.paper,
            status(f),
            f.seeds.len(),
            updates(f.site_updates),
            f.run.wall_seconds,
            f.summary_wall_seconds
                .map_or("n/a".into(), |w| format!("{w:.1}"))
        );
    }
    let _ = writeln!(m, "\n## Pictures and data\n");
    for f in r
        .figures
        .iter()
        .filter(|f| !f.pngs.is_empty() || !f.csvs.is_empty())
    {
        let _ = writeln!(m, "### {} (`{}`)\n", f.paper, f.run.binary);
        for p in &f.pngs {
            let _ = writeln!(
                m,
                "[![{p}]({base}{0}/{p})]({base}{0}/{p})",
                f.run.binary,
                base = r.figures_base
            );
        }
        let csv: Vec<String> = f
            .csvs
            .iter()
            .map(|c| format!("[{c}]({}{}/{c})", r.figures_base, f.run.binary))
            .collect();
        if !csv.is_empty() {
            let _ = writeln!(m, "\nData: {}", csv.join(", "));
        }
        m.push('\n');
    }
    let _ = writeln!(m, "## Reproducibility stamp\n");
    for (k, v) in stamp_lines(r) {
        let mark = if k == CPU_LINE { TIMING_MARK } else { "" };
        let line = format!("- {k}: {} {mark}", v.replace('`', "'"));
        let _ = writeln!(m, "{}", line.trim_end());
    }
    let _ = writeln!(
        m,
        "- report wall time: {:.1} s {TIMING_MARK}",
        r.stamp.wall_seconds
    );
    m
}

fn status(f: &FigureReport) -> String {
    match (&f.run.failure, &f.summary_problem) {
        (Some(x), _) => format!("FAILED: {x}"),
        (None, Some(p)) => format!("no summary: {p}"),
        (None, None) => "ok".into(),
    }
}

/// CPU seconds of the figures' summaries together (this invocation).
fn total_cpu(r: &Report) -> Option<f64> {
    let c: Vec<f64> = r.figures.iter().filter_map(|f| f.cpu_seconds).collect();
    (!c.is_empty()).then(|| c.iter().sum())
}

/// CPU seconds as text ("n/a" when absent).
fn cpu(x: Option<f64>) -> String {
    x.map_or("n/a".into(), |c| format!("{c:.0} s"))
}

/// The one-line stamp at the top of the page (the full one ends it).
fn top_stamp(r: &Report) -> String {
    format!(
        "Stamp: commit {}, {} tier, {} cores (--threads {}), CPU {} in this invocation (runs resumed from --out count only their reading); the full stamp ends the page.",
        r.stamp.commit,
        r.tier,
        r.stamp.cores,
        r.stamp.threads,
        cpu(total_cpu(r))
    )
}

/// The command that regenerates a report run as `command_line`: build,
/// then the same arguments from the clone's `target/release/` (without
/// `--no-run`: from a clone the figures must run).
pub fn regenerate(command_line: &str) -> String {
    // a re-rendering (--no-run) is regenerated by the run it re-renders;
    // the command line is shell-quoted word by word ([`shell_quote`])
    let words = shell_split(command_line)
        .unwrap_or_else(|_| command_line.split_whitespace().map(String::from).collect());
    let args: Vec<String> = words
        .iter()
        .skip(1)
        .filter(|a| *a != "--no-run")
        .map(|a| shell_quote(a))
        .collect();
    format!(
        "cargo build --release --bins && target/release/report {}",
        args.join(" ")
    )
    .trim_end()
    .to_string()
}

/// The stamp's line of this invocation's CPU time (a timing line).
const CPU_LINE: &str = "CPU of the figures in this invocation";

fn stamp_lines(r: &Report) -> Vec<(&'static str, String)> {
    let s = &r.stamp;
    let mut v = vec![
        ("crate version", s.version.clone()),
        ("git commit", s.commit.clone()),
        ("command", s.command_line.clone()),
        ("regenerate", s.regenerate.clone()),
        (CPU_LINE, cpu(total_cpu(r))),
        ("tier", r.tier.clone()),
        ("--seed", s.seed.clone()),
        ("--threads", s.threads.clone()),
        ("cores", s.cores.to_string()),
    ];
    for (k, n) in counts(r).readings {
        v.push(("rule reading", format!("{k} ({n} figures)")));
    }
    for f in r.figures.iter().filter(|f| !f.seeds.is_empty()) {
        let seeds: Vec<String> = f.seeds.iter().map(u64::to_string).collect();
        v.push(("seeds", format!("{}: {}", f.run.binary, seeds.join(" "))));
    }
    v
}

/// HTML-escape text.
pub fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

const CSS: &str = "body{font-family:system-ui,sans-serif;margin:1.5em auto;max-width:1400px;padding:0 1em;color:#222;line-height:1.4}
h1{font-size:1.5em}h2{font-size:1.2em;margin-top:1.6em;border-bottom:1px solid #ccc}
.headline{font-size:1.15em;background:#f4f6f8;padding:.6em .9em;border-left:4px solid #357}
table{border-collapse:collapse;width:100%;font-size:.88em}
th,td{border:1px solid #ddd;padding:.3em .45em;vertical-align:top;text-align:left;overflow-wrap:break-word}
th{background:#eef1f4}
td.num{white-space:nowrap;font-variant-numeric:tabular-nums}
.reproduced{background:#dff3e0}.not-reproduced{background:#fbe0e0}.undecided{background:#fff3cd}
.v{font-weight:600;white-space:nowrap}
code{font-size:.92em}
.grid{display:grid;grid-template-columns:repeat(auto-fill,minmax(280px,1fr));gap:1em}
.card{border:1px solid #ddd;padding:.5em;border-radius:4px}
.card img{width:100%;height:220px;object-fit:contain;border:1px solid #eee;margin:.2em 0}
.card h3{font-size:1em;margin:.2em 0}
pre{background:#f6f6f6;padding:.5em;overflow-x:auto;font-size:.85em}
.small{font-size:.85em;color:#555}
img.thumb{width:96px;height:64px;object-fit:contain;border:1px solid #eee}
.scroll{overflow-x:auto}
.glance{margin:1em 0}.glance figcaption{font-size:1.1em;font-weight:600;margin-top:.3em}
.cards{display:grid;grid-template-columns:repeat(auto-fill,minmax(min(100%,520px),1fr));gap:1em}
.fcard{border:1px solid #ddd;border-radius:6px;padding:.6em}
.fcard h3{font-size:1.05em;margin:.1em 0}
.fcard img{width:100%;max-height:260px;object-fit:contain;border:1px solid #eee}
table.claims td{vertical-align:middle}table.claims td.v{width:7em;white-space:normal;text-align:center}table.claims svg{max-width:100%;height:auto}";

/// The report as one self-contained HTML page (inline CSS, no scripts,
/// relative links to the figures' PNGs and CSVs).
pub fn html(r: &Report) -> String {
    let c = counts(r);
    let base = esc(&r.figures_base);
    let mut h = String::new();
    let title = format!(
        "Reproduction report: granular-automata {}, {} tier",
        r.stamp.version, r.tier
    );
    let _ = writeln!(h, "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>{}</title>\n<style>\n{CSS}\n</style>\n</head>\n<body>", esc(&title));
    let _ = writeln!(h, "<h1>{}</h1>", esc(&title));
    let _ = writeln!(
        h,
        "<figure class=\"glance\">{}<figcaption>{}</figcaption></figure>",
        headline_svg(r).replacen(SVG_NS, "", 1),
        esc(&short_headline(r))
    );
    figure_cards(r, &mut h);
    let _ = writeln!(h, "<h2>Details</h2>");
    let head = esc(&headline(r));
    let _ = writeln!(h, "<p class=\"headline\">{}</p>", code_spans(&head));
    let _ = writeln!(
        h,
        "<p class=\"small\" {HTML_TIMING_MARK}>{}</p>",
        esc(&top_stamp(r))
    );
    let _ = writeln!(
        h,
        "<p class=\"small\">Regenerate: <code>{}</code></p>",
        esc(&r.stamp.regenerate)
    );
    for p in &r.preface {
        let _ = writeln!(h, "<p class=\"small\">{}</p>", code_spans(&esc(p)));
    }
    let _ = writeln!(
        h,
        "<p>Checks by verdict: {}. By kind: {}.</p>",
        esc(&list(&c.verdicts)),
        esc(&list(&c.kinds))
    );
    let failed = failed_figures(r);
    if !failed.is_empty() {
        let _ = writeln!(h, "<h2>Failed figures</h2>");
        for f in failed {
            let _ = writeln!(
                h,
                "<p class=\"not-reproduced\"><b>{}</b>: {}</p>",
                esc(&f.run.binary),
                esc(&why_failed(f))
            );
            if !f.run.stderr_tail.is_empty() {
                let _ = writeln!(h, "<pre>{}</pre>", esc(&f.run.stderr_tail.join("\n")));
            }
        }
    }
    let _ = writeln!(h, "<h2>Overview</h2>\n<p>Published claims of the default reading: reproduced / not reproduced / undecided.</p>\n<div class=\"scroll\"><table>\n<thead><tr><th>paper</th><th>reproduced</th><th>not reproduced</th><th>undecided</th></tr></thead>\n<tbody>");
    for (p, [y, n, u]) in per_paper(r) {
        let _ = writeln!(
            h,
            "<tr><td>{}</td><td class=\"num\">{y}</td><td class=\"num\">{n}</td><td class=\"num\">{u}</td></tr>",
            esc(&p)
        );
    }
    let _ = writeln!(h, "</tbody>\n</table></div>\n<div class=\"scroll\"><table>\n<thead><tr><th></th><th>figure</th><th>reproduced</th><th>not</th><th>undecided</th><th>CPU (this invocation)</th><th>wall time</th></tr></thead>\n<tbody>");
    for f in &r.figures {
        let [y, n, u] = tally(r.rows.iter().filter(|x| x.binary == f.run.binary));
        let thumb = f.pngs.first().map_or(String::new(), |p| {
            format!(
                "<a href=\"#fig-{b}\"><img class=\"thumb\" src=\"{base}{b}/{}\" alt=\"{}\"></a>",
                esc(p),
                esc(p),
                b = esc(&f.run.binary)
            )
        });
        let _ = writeln!(
            h,
            "<tr {HTML_TIMING_MARK} class=\"{}\"><td>{thumb}</td><td><a href=\"#fig-{b}\"><code>{b}</code></a><br><span class=\"small\">{}</span></td><td class=\"num\">{y}</td><td class=\"num\">{n}</td><td class=\"num\">{u}</td><td class=\"num\">{}</td><td class=\"num\">{:.1} s</td></tr>",
            if f.run.ok { "" } else { "not-reproduced" },
            esc(&f.paper),
            cpu(f.cpu_seconds),
            f.run.wall_seconds,
            b = esc(&f.run.binary)
        );
    }
    let _ = writeln!(h, "</tbody>\n</table></div>");
    let ss = seed_set_rows(r);
    if !ss.is_empty() {
        let _ = writeln!(h, "<h2>Over every committed seed set ({})</h2>\n<p>The published claims whose figure has at least {MIN_SEED_SETS} committed seed sets at this tier: the seeds' mean with the SE of their spread, graded by the same rule with n = seeds (against the acceptance margin table, or else the claim every seed's summary states). &ldquo;This run&rdquo; is the verdict of this report's own seed set.</p>\n<div class=\"scroll\"><table>\n<thead><tr><th>figure</th><th>check</th><th>this run</th><th>seed sets</th><th>mean &plusmn; SE</th><th>published (margin)</th><th>verdict over the seed sets</th></tr></thead>\n<tbody>", ss.len());
        for x in ss {
            let s = x.seed_sets.as_ref().expect("filtered");
            let _ = writeln!(
                h,
                "<tr><td>{} {} (<code>{}</code>)</td><td><code>{}</code></td><td class=\"{}\">{}</td><td class=\"num\">{}</td><td class=\"num\">{} &plusmn; {}</td><td class=\"num\">{}</td><td class=\"{}\"><b>{}</b></td></tr>",
                esc(&x.paper),
                esc(&x.figure),
                esc(&x.binary),
                esc(&x.name),
                esc(&x.verdict),
                esc(&x.verdict),
                s.seeds,
                num(s.measured),
                num(s.error),
                esc(&published(x)),
                esc(&s.verdict),
                esc(&s.verdict)
            );
        }
        let _ = writeln!(h, "</tbody>\n</table></div>");
    }
    let d = discrepancies(r);
    let _ = writeln!(h, "<h2>Known discrepancies ({})</h2>", d.len());
    let _ = writeln!(h, "<p>Published claims of the default reading not reproduced at this tier, each with the mechanism its check records; the explanations are in <a href=\"{}\">EXPERIMENTS.md, Known discrepancies</a>.</p>\n<ul>", esc(&r.discrepancy_link));
    claim_items(&mut h, &d, true, |x| one_line(&x.note, MECHANISM_CHARS));
    let u = undecided(r);
    let _ = writeln!(h, "</ul>\n<h2>Undecided ({})</h2>\n<p>Published claims of the default reading this tier does not decide, each with what would decide it (the grading rule, |d| +- k SE against the margin with k = max(2, Student t), the SE shrinking as 1/sqrt(runs)).</p>\n<ul>", u.len());
    claim_items(&mut h, &u, true, Row::what_would_decide);
    let (own, other): (Vec<&Row>, Vec<&Row>) = r.rows.iter().partition(|x| x.reading.is_none());
    let table = |h: &mut String, rows: &[&Row]| {
        let _ = writeln!(h, "<div class=\"scroll\"><table>\n<thead><tr><th>paper</th><th>figure</th><th>check: claim</th><th>published (margin)</th><th>measured ± SE</th><th>verdict</th><th>kind</th><th>rule reading</th><th>site updates</th></tr></thead>\n<tbody>");
        for x in rows {
            let _ = writeln!(
                h,
                "<tr class=\"{v}\"><td>{}</td><td>{} <a href=\"{base}{b}/\"><code>{b}</code></a></td><td title=\"{}\"><code>{}</code>: {}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"v\">{v}</td><td>{}</td><td title=\"{}\"><code>{}</code></td><td class=\"num\">{}</td></tr>",
                esc(&x.paper),
                esc(&x.figure),
                esc(&x.note),
                esc(&x.name),
                esc(&claim(x)),
                esc(&published(x)),
                esc(&measured(x)),
                esc(&x.kind),
                esc(&x.rules),
                esc(&shorten(&x.rules, RULES_CELL)),
                updates(x.site_updates),
                v = esc(&x.verdict),
                b = esc(&x.binary),
            );
        }
        let _ = writeln!(h, "</tbody>\n</table></div>");
    };
    let _ = writeln!(h, "</ul>\n<h2>Checks</h2>");
    table(&mut h, &own);
    if !other.is_empty() {
        let _ = writeln!(h, "<h2>Checks of other readings ({})</h2>\n<p>Comparisons: the same checks for readings that are not the default (the case key prefixes each name); not claims of the project and not counted above.</p>", other.len());
        table(&mut h, &other);
    }
    let _ = writeln!(h, "<p class=\"small\">Hover a claim for the check's full note.</p>\n<h2>Figures and cost</h2>");
    let _ = writeln!(h, "<p class=\"small\">Wall times: <i>process</i> is the figure's subprocess, <i>summary</i> its own summary.json (a figure that resumed saved runs reports only the analysis); site updates count all its runs.</p>");
    let _ = writeln!(h, "<table>\n<thead><tr><th>figure</th><th>paper</th><th>status</th><th>runs</th><th>site updates</th><th>wall time</th></tr></thead>\n<tbody>");
    for f in &r.figures {
        let _ = writeln!(
            h,
            "<tr {HTML_TIMING_MARK} class=\"{}\"><td><code>{}</code></td><td>{}</td><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">process {:.1} s, summary {} s</td></tr>",
            if f.run.ok { "" } else { "not-reproduced" },
            esc(&f.run.binary),
            esc(&f.paper),
            esc(&status(f)),
            f.seeds.len(),
            updates(f.site_updates),
            f.run.wall_seconds,
            f.summary_wall_seconds.map_or("n/a".into(), |w| format!("{w:.1}"))
        );
    }
    let _ = writeln!(
        h,
        "</tbody>\n</table>\n<h2>Pictures and data</h2>\n<div class=\"grid\">"
    );
    for f in r
        .figures
        .iter()
        .filter(|f| !f.pngs.is_empty() || !f.csvs.is_empty())
    {
        let b = esc(&f.run.binary);
        let csv: Vec<String> = f
            .csvs
            .iter()
            .map(|c| format!("<a href=\"{base}{b}/{0}\">{0}</a>", esc(c)))
            .collect();
        let data = if csv.is_empty() {
            String::new()
        } else {
            format!("<br>Data: {}", csv.join(", "))
        };
        let pngs: Vec<Option<&String>> = if f.pngs.is_empty() {
            vec![None]
        } else {
            f.pngs.iter().map(Some).collect()
        };
        for (i, p) in pngs.into_iter().enumerate() {
            // the first card of a figure is the overview's link target
            let id = if i == 0 {
                format!(" id=\"fig-{b}\"")
            } else {
                String::new()
            };
            let _ = write!(
                h,
                "<div class=\"card\"{id}><h3>{} (<code>{b}</code>)</h3>",
                esc(&f.paper)
            );
            if let Some(p) = p {
                let p = esc(p);
                let _ = write!(
                    h,
                    "<a href=\"{base}{b}/{p}\"><img src=\"{base}{b}/{p}\" alt=\"{p}\" title=\"{p}\" loading=\"lazy\"></a><p class=\"small\"><a href=\"{base}{b}/{p}\">{p}</a>{data}</p>"
                );
            } else {
                let _ = write!(h, "<p class=\"small\">{}</p>", &data[4..]);
            }
            let _ = writeln!(h, "</div>");
        }
    }
    let _ = writeln!(
        h,
        "</div>\n<h2>Reproducibility stamp</h2>\n<ul class=\"small\">"
    );
    for (k, v) in stamp_lines(r) {
        let li = if k == CPU_LINE {
            "<li data-timing>"
        } else {
            "<li>"
        };
        let _ = writeln!(h, "{li}{k}: <code>{}</code></li>", esc(&v));
    }
    let _ = writeln!(
        h,
        "<li {HTML_TIMING_MARK}>report wall time: {:.1} s</li>\n</ul>\n</body>\n</html>",
        r.stamp.wall_seconds
    );
    h
}

/// Turn Markdown `code` spans of already escaped text into `<code>`.
fn code_spans(s: &str) -> String {
    let mut out = String::new();
    for (i, part) in s.split('`').enumerate() {
        if i % 2 == 1 {
            let _ = write!(out, "<code>{part}</code>");
        } else {
            out.push_str(part);
        }
    }
    out
}

/// The verdicts of the default reading's published claims among `rows`,
/// each over the committed seed sets where there are some ([`Row::final_verdict`]):
/// reproduced, not reproduced, undecided.
fn final_tally<'a>(rows: impl Iterator<Item = &'a Row>) -> [usize; 3] {
    let mut t = [0; 3];
    for x in rows.filter(|x| x.is_default_claim()) {
        match x.final_verdict() {
            "reproduced" => t[0] += 1,
            "not-reproduced" => t[1] += 1,
            _ => t[2] += 1,
        }
    }
    t
}

/// Colours of the verdicts in the pictures: reproduced, not reproduced,
/// undecided.
const VERDICT_COLOURS: [&str; 3] = ["#2e8540", "#c62828", "#9e9e9e"];

/// The headline in one sentence of at most 25 words (under the picture).
pub fn short_headline(r: &Report) -> String {
    let [y, n, u] = final_tally(r.rows.iter());
    let over = if r.rows.iter().any(|x| x.seed_sets.is_some()) {
        "over the committed seed sets where a figure has them"
    } else {
        "one seed set per figure"
    };
    format!(
        "{y} of {} published claims reproduced, {n} not reproduced, {u} undecided ({} tier; {over}).",
        y + n + u,
        r.tier
    )
}

/// The namespace a standalone SVG file needs (an SVG inside the page does
/// not, and the page names no web address).
const SVG_NS: &str = " xmlns=\"http://www.w3.org/2000/svg\"";

/// The headline picture: one bar per paper, split into its published
/// claims reproduced, not reproduced and undecided (SVG).
pub fn headline_svg(r: &Report) -> String {
    let papers = per_paper(r);
    let papers: Vec<(String, [usize; 3])> = papers
        .into_iter()
        .map(|(p, _)| {
            let t = final_tally(r.rows.iter().filter(|x| x.paper == p));
            (p, t)
        })
        .filter(|(_, t)| t.iter().sum::<usize>() > 0)
        .collect();
    let most = papers
        .iter()
        .map(|(_, t)| t.iter().sum::<usize>())
        .max()
        .unwrap_or(1)
        .max(1);
    let (left, width, bar, gap) = (70.0, 520.0, 26.0, 12.0);
    let height = 30.0 + papers.len() as f64 * (bar + gap) + 10.0;
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 {} {height}\" width=\"100%\" style=\"max-width:680px\" role=\"img\" aria-label=\"{}\" font-family=\"sans-serif\" font-size=\"13\">\n",
        left + width + 90.0,
        esc(&short_headline(r))
    );
    let names = ["reproduced", "not reproduced", "undecided"];
    for (k, name) in names.iter().enumerate() {
        let x = left + k as f64 * 150.0;
        let _ = writeln!(
            s,
            "<rect x=\"{x}\" y=\"4\" width=\"12\" height=\"12\" fill=\"{}\"/><text x=\"{}\" y=\"15\">{name}</text>",
            VERDICT_COLOURS[k],
            x + 16.0
        );
    }
    for (i, (paper, t)) in papers.iter().enumerate() {
        let y = 28.0 + i as f64 * (bar + gap);
        let _ = writeln!(
            s,
            "<text x=\"0\" y=\"{}\" font-weight=\"bold\">{}</text>",
            y + bar * 0.68,
            esc(paper)
        );
        let mut x = left;
        for (k, &n) in t.iter().enumerate() {
            let w = width * n as f64 / most as f64;
            if n > 0 {
                let _ = writeln!(
                    s,
                    "<rect x=\"{x:.1}\" y=\"{y}\" width=\"{w:.1}\" height=\"{bar}\" fill=\"{}\"><title>{paper}: {n} {}</title></rect>",
                    VERDICT_COLOURS[k],
                    names[k]
                );
                if w >= 22.0 {
                    let _ = writeln!(
                        s,
                        "<text x=\"{:.1}\" y=\"{}\" fill=\"white\" text-anchor=\"middle\">{n}</text>",
                        x + w / 2.0,
                        y + bar * 0.68
                    );
                }
            }
            x += w;
        }
        let _ = writeln!(
            s,
            "<text x=\"{:.1}\" y=\"{}\">{} claims</text>",
            x + 6.0,
            y + bar * 0.68,
            t.iter().sum::<usize>()
        );
    }
    s.push_str("</svg>\n");
    s
}

/// A published claim drawn over its measured value, on a scale of its own
/// (SVG, 240 x 30): the margin as a band around the published value (or the
/// allowed side of a threshold), the published value as a line, and the
/// measured value (over the seed sets where there are some) as a dot with
/// its +-2 SE bar, coloured by verdict. Empty when there is nothing to draw.
pub fn claim_svg(x: &Row) -> String {
    let (m, se) = match &x.seed_sets {
        Some(s) => (s.measured, s.error),
        None => (x.measured, x.error),
    };
    let (Some(m), Some(t)) = (m, x.tolerance) else {
        return String::new();
    };
    let se = se.filter(|e| e.is_finite()).unwrap_or(0.0);
    // the published interval: [target - margin, target + margin], or the
    // threshold and the side it allows
    let (lo_p, hi_p, line) = match (x.test.as_str(), x.published) {
        ("within", Some(p)) => (p - t, p + t, p),
        ("above", _) => (t, f64::INFINITY, t),
        ("below", _) => (f64::NEG_INFINITY, t, t),
        _ => return String::new(),
    };
    let pts = [m - 2.0 * se, m + 2.0 * se, line, lo_p, hi_p];
    let finite: Vec<f64> = pts.iter().copied().filter(|v| v.is_finite()).collect();
    let (mut lo, mut hi) = finite
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let pad = ((hi - lo) * 0.15).max(1e-9 + 0.05 * m.abs().max(line.abs()));
    lo -= pad;
    hi += pad;
    let (w, h) = (240.0, 30.0);
    let sx = |v: f64| (v.clamp(lo, hi) - lo) / (hi - lo) * (w - 10.0) + 5.0;
    let colour = match x.final_verdict() {
        "reproduced" => VERDICT_COLOURS[0],
        "not-reproduced" => VERDICT_COLOURS[1],
        _ => VERDICT_COLOURS[2],
    };
    let mut s = format!(
        "<svg viewBox=\"0 0 {w} {h}\" width=\"{w}\" height=\"{h}\" role=\"img\" aria-label=\"published {} against measured {}\">",
        esc(&published(x)),
        esc(&measured(x))
    );
    let (a, b) = (sx(lo_p), sx(hi_p));
    let _ = write!(
        s,
        "<rect x=\"{a:.1}\" y=\"4\" width=\"{:.1}\" height=\"16\" fill=\"#cfe8d1\"><title>allowed by the published claim</title></rect>",
        (b - a).max(1.0)
    );
    let _ = write!(
        s,
        "<line x1=\"{0:.1}\" x2=\"{0:.1}\" y1=\"2\" y2=\"22\" stroke=\"#1b5e20\" stroke-width=\"2\"><title>published {1}</title></line>",
        sx(line),
        esc(&sig(line, 4))
    );
    let (e0, e1, c) = (sx(m - 2.0 * se), sx(m + 2.0 * se), sx(m));
    let _ = write!(
        s,
        "<line x1=\"{e0:.1}\" x2=\"{e1:.1}\" y1=\"12\" y2=\"12\" stroke=\"{colour}\" stroke-width=\"2\"/><circle cx=\"{c:.1}\" cy=\"12\" r=\"4\" fill=\"{colour}\"><title>measured {}</title></circle>",
        esc(&sig(m, 4))
    );
    let _ = write!(
        s,
        "<text x=\"2\" y=\"29\" font-size=\"8\" font-family=\"sans-serif\" fill=\"#555\">{}</text><text x=\"{}\" y=\"29\" font-size=\"8\" font-family=\"sans-serif\" fill=\"#555\" text-anchor=\"end\">{}</text></svg>",
        esc(&sig(lo, 3)),
        w - 2.0,
        esc(&sig(hi, 3))
    );
    s
}

/// One card per figure: its first picture, and each published claim of
/// the default reading with the claim drawn over the measurement
/// ([`claim_svg`]) and its verdict.
fn figure_cards(r: &Report, h: &mut String) {
    let base = esc(&r.figures_base);
    let _ = writeln!(
        h,
        "<h2>The figures</h2>\n<p class=\"small\">Each claim: the green band is what the published value and its margin allow, the line the published value, the dot the measured value with &plusmn;2 SE (over the committed seed sets where there are some), coloured by verdict.</p>\n<div class=\"cards\">"
    );
    // the papers' order of figures, then any other
    let mut figures: Vec<&FigureReport> = r.figures.iter().collect();
    let order = crate::experiments::ORDER;
    figures.sort_by_key(|f| {
        order
            .iter()
            .position(|b| *b == f.run.binary)
            .unwrap_or(order.len())
    });
    for f in figures {
        let b = esc(&f.run.binary);
        let claims: Vec<&Row> = r
            .rows
            .iter()
            .filter(|x| x.binary == f.run.binary && x.is_default_claim())
            .collect();
        let [y, n, u] = final_tally(claims.iter().copied());
        let _ = writeln!(
            h,
            "<section class=\"fcard\" id=\"card-{b}\"><h3>{} <code>{b}</code></h3><p class=\"small\">{y} reproduced, {n} not reproduced, {u} undecided</p>",
            esc(&f.paper)
        );
        if let Some(p) = f.pngs.first() {
            let _ = writeln!(
                h,
                "<a href=\"{base}{b}/{p}\"><img src=\"{base}{b}/{p}\" alt=\"{} ({p})\" loading=\"lazy\"></a>",
                esc(&f.paper),
                p = esc(p)
            );
        }
        let _ = writeln!(h, "<table class=\"claims\"><tbody>");
        for x in claims {
            let v = x.final_verdict();
            let _ = writeln!(
                h,
                "<tr><td><code title=\"{}\">{}</code><br><span class=\"small\">published {}<br>measured {}</span><br>{}</td><td class=\"{v} v\">{}</td></tr>",
                esc(&x.note),
                esc(&x.name),
                esc(&published_or_claim(x)),
                esc(&final_measured(x)),
                claim_svg(x),
                esc(&v.replace('-', " "))
            );
        }
        let _ = writeln!(h, "</tbody></table></section>");
    }
    let _ = writeln!(h, "</div>");
}

/// The published value with its margin, or the claim's threshold.
fn published_or_claim(x: &Row) -> String {
    match (x.test.as_str(), x.published, x.tolerance) {
        ("above", _, Some(t)) => format!("> {}", sig(t, 4)),
        ("below", _, Some(t)) => format!("< {}", sig(t, 4)),
        // a claim without one published number: the first clause of its note
        (_, None, _) if !x.note.is_empty() => x.note.split(';').next().unwrap_or("").to_string(),
        _ => published(x),
    }
}

/// The measured value over the seed sets where there are some, else this
/// run's.
fn final_measured(x: &Row) -> String {
    match &x.seed_sets {
        Some(s) => match (s.measured, s.error) {
            (Some(m), Some(e)) => format!("{} ± {} ({} seed sets)", sig(m, 4), sig(e, 2), s.seeds),
            (m, _) => format!("{} ({} seed sets)", num(m), s.seeds),
        },
        None => format!(
            "{}{}",
            measured(x),
            x.runs.map_or(String::new(), |n| format!(" ({n} runs)"))
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn figures_come_from_cargo_toml() {
        let all = all_binaries();
        assert!(all.contains(&"fig1") && all.contains(&"report"));
        let d = default_figures();
        for tool in [
            "acceptance",
            "bench",
            "explore",
            "merge",
            "report",
            "pipe-matrix",
            "validate",
            "validate-example",
        ] {
            assert!(!d.contains(&tool), "{tool} is not a default figure");
        }
        assert!(d.contains(&"hopper-fig2") && d.contains(&"waves-fig12"));
    }

    #[test]
    fn only_is_validated() {
        let s = select(Some("hopper-fig3, fig1")).unwrap();
        assert_eq!(s, vec!["fig1", "hopper-fig3"], "Cargo.toml order");
        assert_eq!(select(Some("pipe-matrix")).unwrap(), vec!["pipe-matrix"]);
        for bad in [
            "fig99",
            "bench",
            "report",
            "validate",
            "validate-example",
            "",
            ",",
        ] {
            let e = select(Some(bad)).unwrap_err();
            assert_eq!(e.kind, ErrorKind::InvalidParameter, "{bad}");
            assert!(e.message.contains("fig1"), "lists the allowed names");
        }
        let figs = vec!["fig2".to_string()];
        let (b, a) = parse_extra("fig2=--runs 8", &figs).unwrap();
        assert_eq!((b.as_str(), a), ("fig2", vec!["--runs".into(), "8".into()]));
        assert!(parse_extra("fig1=--runs 8", &figs).is_err());
        assert!(parse_extra("fig2", &figs).is_err());
    }

    #[test]
    fn old_and_new_check_formats() {
        let s = json!({"paper": "PH94 Fig. 2", "rules": "ph94", "site_updates": 1e9});
        let old = json!({"name": "alpha", "measured": 1.3, "error": 0.04, "published": 1.33,
            "tolerance": 0.09, "pass": false, "note": "n"});
        let r = Row::from_json("fig2", &s, &old);
        assert_eq!((r.paper.as_str(), r.figure.as_str()), ("PH94", "Fig. 2"));
        assert_eq!(r.kind, "unstated");
        assert_eq!(r.verdict, "not-reproduced");
        assert!(r.is_published_claim());
        let claim = json!({"name": "c", "measured": 1.0, "error": 0.0, "published": null,
            "tolerance": null, "pass": true, "note": "n"});
        let r = Row::from_json("fig2", &s, &claim);
        assert_eq!(r.verdict, "reproduced");
        assert!(!r.is_published_claim());
        assert_eq!(r.tolerance, None);
        let new = json!({"name": "alpha", "kind": "published", "measured": 1.3, "error": 0.04,
            "runs": 8, "published": null, "source": "PH94 p. 2", "tolerance": 0.1,
            "verdict": "undecided", "pass": false, "note": "n"});
        let r = Row::from_json("fig2", &s, &new);
        assert_eq!(
            (r.kind.as_str(), r.verdict.as_str()),
            ("published", "undecided")
        );
        assert_eq!(r.runs, Some(8));
        assert!(r.is_published_claim());
    }

    #[test]
    fn other_readings_and_what_would_decide() {
        let s = json!({"paper": "BB90 Fig. 2", "cases": [
            {"key": "beta0", "default_reading": true},
            {"key": "beta1_same", "default_reading": false},
            {"key": "beta1_same_narrow", "default_reading": false},
            {"key": "beta1_bond", "default_reading": true}]});
        let row = |name: &str| {
            Row::from_json(
                "hopper-fig2",
                &s,
                &json!({"name": name, "kind": "published",
                "measured": 1.25, "error": 0.01, "runs": 128, "published": 1.33,
                "tolerance": 0.059, "claim": {"test": "within"}, "verdict": "undecided"}),
            )
        };
        assert_eq!(
            row("beta1_same_order").reading.as_deref(),
            Some("beta1_same")
        );
        assert_eq!(
            row("beta1_same_narrow_order").reading.as_deref(),
            Some("beta1_same_narrow")
        );
        assert_eq!(row("beta1_bond_order").reading, None);
        assert_eq!(row("beta0_structureless").reading, None);
        assert!(!row("beta1_same_order").is_default_claim());
        assert!(row("beta1_bond_order").is_default_claim());
        // |d| = 0.05 lies 0.009 inside the margin; 2 x 0.01 sqrt(128 / m)
        // <= 0.009 from m = 632.1
        let mut r = row("beta1_bond_order");
        r.measured = Some(1.28);
        assert!(
            r.what_would_decide().contains("about 633 runs decide it"),
            "{}",
            r.what_would_decide()
        );
        let mut edge = r.clone();
        edge.measured = Some(1.33 - 0.059);
        assert!(edge.what_would_decide().contains("no run count"));
        // Student's t at small n: 3 runs with k = 4.30
        r.runs = Some(3);
        r.error = Some(0.004);
        let m = runs_to_decide(3, 0.004, 0.009);
        assert_eq!(
            m,
            Some(5),
            "k(4) = 3.18: 0.0110 > 0.009; k(5) = 2.78: 0.0086"
        );
        let mut none = r;
        none.error = None;
        assert!(none.what_would_decide().contains("at least 3"));
    }

    #[test]
    fn engine_goes_to_the_pipe_figures_only() {
        let opts = Options {
            tier: Tier::Acceptance,
            figures: vec![],
            out: PathBuf::from("o"),
            seed: None,
            threads: None,
            engine: Some("fast".into()),
            extra: BTreeMap::new(),
            bin_dir: PathBuf::from("."),
            command_line: String::new(),
            no_run: false,
            seed_sets: None,
        };
        assert!(figure_args(&opts, "fig2").ends_with(&["--engine".into(), "fast".into()]));
        assert!(!figure_args(&opts, "hopper-fig3").contains(&"--engine".to_string()));
    }

    #[test]
    fn shell_words_split_and_quote_as_a_shell_does() {
        let words = shell_split(r#"--runs 8 'a b' "c \"d\"" e\ f"#).unwrap();
        assert_eq!(words, ["--runs", "8", "a b", "c \"d\"", "e f"]);
        assert!(shell_split("'open").is_err());
        assert_eq!(shell_quote("--out"), "--out");
        assert_eq!(shell_quote("fig2=--runs 8"), "'fig2=--runs 8'");
        assert_eq!(shell_quote("it's"), r"'it'\''s'");
        for w in ["a b", "it's", "x\"y", ""] {
            assert_eq!(shell_split(&shell_quote(w)).unwrap(), [w]);
        }
        assert_eq!(
            regenerate("report --args-for 'fig2=--runs 8' --no-run --out suite"),
            "cargo build --release --bins && target/release/report --args-for 'fig2=--runs 8' --out suite"
        );
    }

    #[test]
    fn regenerate_keeps_the_arguments() {
        assert_eq!(
            regenerate("/somewhere/target/release/report --tier acceptance --out suite"),
            "cargo build --release --bins && target/release/report --tier acceptance --out suite"
        );
        assert_eq!(
            regenerate("report"),
            "cargo build --release --bins && target/release/report"
        );
    }

    #[test]
    fn a_published_picture_is_reduced() {
        let dir = std::env::temp_dir().join(format!("ga-reduce-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (big, small) = (dir.join("big.png"), dir.join("small.png"));
        image::RgbImage::from_pixel(2000, 1000, image::Rgb([10, 200, 30]))
            .save(&big)
            .unwrap();
        reduce_png(&big, &small, PUBLISH_WIDTH).unwrap();
        let img = image::open(&small).unwrap();
        assert_eq!(
            (img.width(), img.height()),
            (PUBLISH_WIDTH, PUBLISH_WIDTH / 2)
        );
        // a narrow picture is copied as it is
        reduce_png(&small, &dir.join("copy.png"), PUBLISH_WIDTH).unwrap();
        assert_eq!(
            std::fs::read(&small).unwrap(),
            std::fs::read(dir.join("copy.png")).unwrap()
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn formatting() {
        assert_eq!(sig(1.3748824, 4), "1.375");
        assert_eq!(sig(0.00067138, 2), "6.7e-4");
        assert_eq!(sig(-3.02, 4), "-3.020");
        assert_eq!(sig(1234567.0, 4), "1.235e6");
        assert_eq!(num(None), "n/a");
        assert_eq!(
            shorten("a short note; NOT REPRODUCED: why", 90),
            "a short note"
        );
        let long = "word ".repeat(40);
        let s = shorten(&long, 30);
        assert!(s.ends_with('…') && s.chars().count() <= 31, "{s}");
        assert_eq!(esc("<a & \"b\">"), "&lt;a &amp; &quot;b&quot;&gt;");
        assert_eq!(
            slug("## Known discrepancies of the default reading (`ph94+gravity-first+wall-move`, Figs. 2-3)"),
            "known-discrepancies-of-the-default-reading-ph94gravity-firstwall-move-figs-2-3"
        );
        assert_eq!(
            without_timing(&format!("a\nb {TIMING_MARK}\n<tr {HTML_TIMING_MARK}>\nc")),
            "a\nc"
        );
    }
}
