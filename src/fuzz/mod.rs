//! Generated input for every reader of outside input: a structured mutation
//! fuzzer in plain Rust, seeded by the project's generator.
//!
//! For each [`Reader`] it generates valid input (an NDJSON run of the
//! reference, a hopper plan, saved run files, a summary.json, a report.json,
//! command-line values), mutates it ([`mutate`]: flipped bits, truncated and
//! very long lines, invalid UTF-8, NaN, infinities and huge numbers, wrong
//! counts, duplicated or missing fields; and per reader: runs of another
//! seed, tier, reading or version), feeds it to the reader and classifies
//! the outcome: a typed error ([`Tally::refused`]) or a result
//! ([`Tally::accepted`]), checked wherever it can be (a saved run accepted
//! after a flipped byte must equal the original). A panic, an input that
//! takes longer than [`TIME_LIMIT`], or wrong data accepted is a failure.
//!
//! A fuzz run is a pure function of (reader, seed, inputs): the same inputs
//! in the same order on every machine. The `fuzz` binary runs the long
//! budget, `tests/fuzz.rs` a bounded share (docs/reference/generated-input.md).

mod cli;
mod contract;
pub mod mutate;
mod reports;
mod saved;

use crate::error::Result;
use rand::SeedableRng;
use rand_xoshiro::Xoshiro256PlusPlus;
use serde::Serialize;
use std::cell::RefCell;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// The generator of a fuzz run.
pub type Rng = Xoshiro256PlusPlus;

/// The longest one input may take before it counts as a hang (the inputs
/// are small: the slowest reader, `merge`, takes milliseconds).
pub const TIME_LIMIT: Duration = Duration::from_secs(10);

/// Failures kept with their input, per reader and run.
const KEPT: usize = 10;

/// A reader of outside input.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Reader {
    /// The NDJSON samples of an external pipe candidate
    /// (`validate::candidate::read_samples`).
    Samples,
    /// The end line of an external hopper candidate
    /// (`validate::external_hopper::read_end`).
    HopperEnd,
    /// The hopper plan `validate-example hopper --plan -` reads
    /// (`validate::external_hopper::load`, then its action).
    HopperPlan,
    /// A saved run file, on resume (`ensemble::Ensemble::run`).
    RunFile,
    /// Shard folders, merged (`ensemble::merge`).
    Merge,
    /// A figure's summary.json, as `report --no-run` reads it
    /// (`report::read_figure`).
    Summary,
    /// Seed-set folders of summaries, as `report --seed-sets` reads them
    /// (`drivers::acceptance_study::all_seeds`).
    SeedSets,
    /// A report.json, as `report --experiments` reads it
    /// (`experiments::render`).
    ReportJson,
    /// Numbers, names and lists on the command line (`cli`, `--shard`,
    /// pipe sizes, `--rules`, `--engine`, a figure's whole command line).
    Cli,
}

impl Reader {
    /// Every reader.
    pub const ALL: [Reader; 9] = [
        Reader::Samples,
        Reader::HopperEnd,
        Reader::HopperPlan,
        Reader::RunFile,
        Reader::Merge,
        Reader::Summary,
        Reader::SeedSets,
        Reader::ReportJson,
        Reader::Cli,
    ];

    /// Its short name (the `fuzz` binary's `--readers`).
    pub fn name(self) -> &'static str {
        match self {
            Reader::Samples => "samples",
            Reader::HopperEnd => "hopper-end",
            Reader::HopperPlan => "hopper-plan",
            Reader::RunFile => "run-file",
            Reader::Merge => "merge",
            Reader::Summary => "summary",
            Reader::SeedSets => "seed-sets",
            Reader::ReportJson => "report-json",
            Reader::Cli => "cli",
        }
    }
}

impl std::str::FromStr for Reader {
    type Err = crate::error::Error;
    fn from_str(s: &str) -> Result<Self> {
        Reader::ALL
            .into_iter()
            .find(|r| r.name() == s)
            .ok_or_else(|| {
                let names: Vec<&str> = Reader::ALL.iter().map(|r| r.name()).collect();
                crate::error::Error::new(
                    crate::error::ErrorKind::InvalidParameter,
                    format!(
                        "reader {s:?} is not known; use one of: {}",
                        names.join(", ")
                    ),
                )
            })
    }
}

/// Inputs of `reader` in the long run (the `fuzz` binary's default):
/// 1.15 million in all, fewer for the readers of files, which take
/// milliseconds per input.
pub fn long_inputs(reader: Reader) -> u64 {
    match reader {
        Reader::Samples => 200_000,
        Reader::HopperEnd | Reader::HopperPlan | Reader::ReportJson => 150_000,
        Reader::RunFile => 50_000,
        Reader::Merge => 20_000,
        Reader::Summary => 100_000,
        Reader::SeedSets => 30_000,
        Reader::Cli => 300_000,
    }
}

/// The counts as CSV: a header, one line per tally.
pub fn csv(tallies: &[Tally]) -> String {
    let mut s = String::from("reader,inputs,accepted,refused,panics,hangs,silent,seconds\n");
    for t in tallies {
        s.push_str(&format!(
            "{},{},{},{},{},{},{},{:.1}\n",
            t.reader, t.inputs, t.accepted, t.refused, t.panics, t.hangs, t.silent, t.seconds
        ));
    }
    s
}

/// What became of one input.
#[derive(Debug, Clone, PartialEq)]
pub enum Verdict {
    /// A result, checked where it can be.
    Accepted,
    /// A typed error.
    Refused,
    /// A result holding wrong data: what is wrong.
    Silent(String),
}

/// The counts of a fuzz run of one reader.
#[derive(Debug, Clone, Default, Serialize)]
pub struct Tally {
    /// The reader's name.
    pub reader: String,
    /// Inputs fed.
    pub inputs: u64,
    /// Inputs that gave a result.
    pub accepted: u64,
    /// Inputs that gave a typed error.
    pub refused: u64,
    /// Inputs that made the reader panic.
    pub panics: u64,
    /// Inputs that took longer than [`TIME_LIMIT`].
    pub hangs: u64,
    /// Inputs accepted with wrong data.
    pub silent: u64,
    /// Wall time, seconds.
    pub seconds: f64,
    /// The first failures: what happened, and the input's start.
    pub failures: Vec<String>,
}

impl Tally {
    /// Whether no input failed: no panic, no hang, no silent acceptance.
    pub fn clean(&self) -> bool {
        self.panics == 0 && self.hangs == 0 && self.silent == 0
    }

    /// The counts of `other` added to these.
    pub fn add(&mut self, other: &Tally) {
        self.inputs += other.inputs;
        self.accepted += other.accepted;
        self.refused += other.refused;
        self.panics += other.panics;
        self.hangs += other.hangs;
        self.silent += other.silent;
        self.seconds += other.seconds;
        for f in &other.failures {
            if self.failures.len() < KEPT {
                self.failures.push(f.clone());
            }
        }
    }
}

/// One reader's generator of inputs: [`Case::one`] makes an input from the
/// run's generator, feeds it to the reader and judges the outcome; the
/// input's start is kept in [`Case::input`] for the report of a failure.
pub(crate) trait Case {
    /// Generate, mutate, feed and judge one input.
    fn one(&mut self, rng: &mut Rng) -> Verdict;
    /// The start of the last input (for a failure's report).
    fn input(&self) -> String;
}

thread_local! {
    /// The message of the last panic caught on this thread while fuzzing.
    static PANIC: RefCell<Option<String>> = const { RefCell::new(None) };
    /// Whether this thread is fuzzing (its panics are caught and counted).
    static FUZZING: RefCell<bool> = const { RefCell::new(false) };
}

/// Install, once, a panic hook that records the panics of fuzzing threads
/// silently and hands every other panic to the hook it replaced.
fn install_hook() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if FUZZING.with(|f| *f.borrow()) {
                let at = info
                    .location()
                    .map(|l| format!(" at {}:{}", l.file(), l.line()))
                    .unwrap_or_default();
                let msg = info
                    .payload()
                    .downcast_ref::<&str>()
                    .map(|s| s.to_string())
                    .or_else(|| info.payload().downcast_ref::<String>().cloned())
                    .unwrap_or_default();
                PANIC.with(|p| *p.borrow_mut() = Some(format!("{msg}{at}")));
            } else {
                previous(info);
            }
        }));
    });
}

/// A folder of its own under the system's temporary folder, removed when
/// dropped.
pub(crate) struct TempDir(pub PathBuf);

impl TempDir {
    /// A new, empty folder named after `what`.
    pub fn new(what: &str) -> Result<Self> {
        static NEXT: AtomicU64 = AtomicU64::new(0);
        let k = NEXT.fetch_add(1, Ordering::SeqCst);
        let dir = std::env::temp_dir().join(format!(
            "granular-automata-fuzz-{what}-{}-{k}",
            std::process::id()
        ));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).map_err(|e| {
            crate::error::Error::new(
                crate::error::ErrorKind::Io,
                format!("cannot create {}: {e}", dir.display()),
            )
        })?;
        Ok(TempDir(dir))
    }

    /// Its path.
    pub fn path(&self) -> &Path {
        &self.0
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Feed `inputs` generated inputs to `reader`, seeded by `seed`, calling
/// `tick()` after each: the counts. Errors: a temporary folder that cannot
/// be written, or valid input that the reader's own set-up refuses.
pub fn fuzz(reader: Reader, seed: u64, inputs: u64, tick: &dyn Fn()) -> Result<Tally> {
    install_hook();
    let mut rng = Rng::seed_from_u64(seed);
    let mut case: Box<dyn Case> = match reader {
        Reader::Samples => Box::new(contract::Samples::default()),
        Reader::HopperEnd => Box::new(contract::HopperEnd::default()),
        Reader::HopperPlan => Box::new(contract::HopperPlanCase::default()),
        Reader::RunFile => Box::new(saved::RunFiles::new(false)?),
        Reader::Merge => Box::new(saved::RunFiles::new(true)?),
        Reader::Summary => Box::new(reports::Summary::new()?),
        Reader::SeedSets => Box::new(reports::SeedSets::new()?),
        Reader::ReportJson => Box::new(reports::ReportJson::default()),
        Reader::Cli => Box::new(cli::CommandLine::default()),
    };
    let mut t = Tally {
        reader: reader.name().to_string(),
        ..Tally::default()
    };
    let start = Instant::now();
    FUZZING.with(|f| *f.borrow_mut() = true);
    for _ in 0..inputs {
        let began = Instant::now();
        let outcome = catch_unwind(AssertUnwindSafe(|| case.one(&mut rng)));
        let took = began.elapsed();
        t.inputs += 1;
        let failure = match outcome {
            Err(_) => {
                t.panics += 1;
                let msg = PANIC.with(|p| p.borrow_mut().take()).unwrap_or_default();
                Some(format!("panic ({msg})"))
            }
            Ok(Verdict::Silent(why)) => {
                t.silent += 1;
                Some(format!("accepted wrong data: {why}"))
            }
            Ok(v) => {
                if v == Verdict::Accepted {
                    t.accepted += 1;
                } else {
                    t.refused += 1;
                }
                None
            }
        };
        let failure = if took > TIME_LIMIT {
            t.hangs += 1;
            Some(format!("took {:.1} s", took.as_secs_f64()))
        } else {
            failure
        };
        if let Some(f) = failure {
            if t.failures.len() < KEPT {
                t.failures.push(format!(
                    "{} input {}: {f}; input: {}",
                    reader.name(),
                    t.inputs,
                    case.input()
                ));
            }
        }
        tick();
    }
    FUZZING.with(|f| *f.borrow_mut() = false);
    t.seconds = start.elapsed().as_secs_f64();
    Ok(t)
}

/// At most the first 300 characters of `bytes`, as text (invalid UTF-8
/// replaced), quoted.
pub(crate) fn excerpt(bytes: &[u8]) -> String {
    let text = String::from_utf8_lossy(bytes);
    let head: String = text.chars().take(300).collect();
    format!("{head:?} ({} bytes)", bytes.len())
}
