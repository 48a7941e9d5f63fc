//! The ensemble runner shared by the figure binaries: N independent
//! runs with seeds derived from a base seed and the run index
//! ([`derive_seed`]), spread over threads, each finished run saved at once so
//! an interrupted figure resumes where it stopped, and sharding (`--shard i/n`)
//! with a [`merge`] step so a sweep can be spread over machines.
//!
//! Layout: `DIR/<binary>/runs/<key-hash>/run-00012.json`, one file per run,
//! holding the configuration key, the run index, its seed and its result. The
//! key is the figure's configuration (tier, parameters, rules, base seed, as
//! JSON) without the number of runs, so asking for more runs reuses the
//! finished ones, and a run with other parameters never mixes with them. Its
//! 64-bit FNV-1a hash names the folder, and `config.json` inside holds the key
//! in full.
//!
//! Integrity: every run file carries a `checksum`, the FNV-1a hash of its
//! canonical JSON (configuration key, index, seed and result; object keys
//! sorted) without the checksum. Loading a run for the analysis and [`merge`]
//! recompute it, so a hand-edited or damaged run file is rejected with a
//! message naming it, never used silently. (A 64-bit FNV-1a: a check
//! against edits and damage, not against forgery; no dependency needed.)
//! [`merge`] is all or nothing: every file is verified and compared before
//! anything is written, the new files are staged in a temporary folder
//! inside the target and then renamed into place; a failed merge leaves
//! the target as it was.
//!
//! Determinism: each run is a pure function of (configuration, index), so the
//! results are identical for any thread count and any shard split; floats
//! are written in the shortest form that reads back to the same bits
//! (serde_json `float_roundtrip`), so a resumed ensemble gives byte-identical
//! results.
//!
//! ```
//! use granular_automata::ensemble::{Ensemble, Outcome};
//! let dir = std::env::temp_dir().join(format!("ga-doc-ensemble-{}", std::process::id()));
//! let key = serde_json::json!({"figure": "doc", "rho": 1.0});
//! let ens = Ensemble::new(&dir, "doc", &key, 7, 5, None).unwrap().threads(2).quiet();
//! let out = ens.run(1, |_index, seed, _tick| Ok(seed % 100)).unwrap();
//! match out {
//!     Outcome::Complete(v) => assert_eq!(v.len(), 5),
//!     Outcome::ShardDone { .. } => unreachable!(),
//! }
//! std::fs::remove_dir_all(&dir).unwrap();
//! ```

use crate::error::{Error, ErrorKind, Result};
use crate::run::{derive_seed, progress, threads as all_threads, write_atomic};
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::fs;
use std::path::{Path, PathBuf};
use std::str::FromStr;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;

/// One shard of an ensemble: `--shard i/n` runs only the runs r with
/// r mod n = i (0 <= i < n), so n machines or array tasks share the work.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// This shard's index i, in 0..count.
    pub index: usize,
    /// Number of shards n, at least 1.
    pub count: usize,
}

impl Shard {
    /// Whether run `r` belongs to this shard.
    pub fn owns(&self, r: usize) -> bool {
        r % self.count == self.index
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl FromStr for Shard {
    type Err = Error;

    /// Parse `i/n` with 0 <= i < n (e.g. `$SLURM_ARRAY_TASK_ID/8`).
    fn from_str(s: &str) -> Result<Self> {
        let (index, count) = crate::error::parse_pair(
            s,
            '/',
            "--shard",
            "i/n with 0 <= i < n (e.g. 0/4 .. 3/4); write the shard index, a slash and the number of shards",
            |i, n| i < n,
        )?;
        Ok(Shard { index, count })
    }
}

/// Largest number of runs of one ensemble (`--runs`): far above any
/// published ensemble (64 runs), small enough that the per-run bookkeeping
/// never exhausts memory.
pub const MAX_RUNS: usize = 100_000;

/// 64-bit FNV-1a hash (stable across platforms and versions), used to name
/// the folder of a configuration.
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// What [`Ensemble::run`] returns.
#[derive(Debug)]
pub enum Outcome<T> {
    /// All runs are done; results in run order.
    Complete(Vec<T>),
    /// A shard finished its runs; the figure is analysed after [`merge`].
    ShardDone {
        /// The shard.
        shard: Shard,
        /// Runs of this shard (computed now or found finished).
        runs: usize,
        /// The folder holding the run files.
        dir: PathBuf,
    },
}

impl<T> Outcome<T> {
    /// The results, in run order, when every run is done. After a shard,
    /// print where its runs were saved and how to go on (prefixed by
    /// `label`, e.g. `"L = 128: "`, or empty) and return `None`: the figure
    /// then stops without analysing.
    pub fn complete(self, label: &str) -> Option<Vec<T>> {
        match self {
            Outcome::Complete(v) => Some(v),
            Outcome::ShardDone { shard, runs, dir } => {
                println!(
                    "{label}shard {shard} done: {runs} runs in {}; merge the shard folders with the `merge` binary, then rerun without --shard",
                    dir.display()
                );
                None
            }
        }
    }
}

#[derive(Serialize, Deserialize)]
struct RunFile<T> {
    key: serde_json::Value,
    index: usize,
    seed: u64,
    result: T,
}

/// An [`ErrorKind::Io`] error of `what` at `path`.
fn io_error(path: &Path, what: &str, e: impl fmt::Display) -> Error {
    Error::new(
        ErrorKind::Io,
        format!("cannot {what} {}: {e}", path.display()),
    )
}

/// The checksum of a run file's JSON object without its `checksum` field:
/// FNV-1a of the canonical (key-sorted) JSON text, as 16 hex digits.
fn checksum_of(body: &serde_json::Map<String, serde_json::Value>) -> String {
    let mut body = body.clone();
    body.remove("checksum");
    let canonical = serde_json::Value::Object(body).to_string();
    format!("{:016x}", fnv1a64(canonical.as_bytes()))
}

/// The text of a run file with its checksum.
fn seal<T: Serialize>(file: &RunFile<T>) -> Result<String> {
    let mut body = match serde_json::to_value(file) {
        Ok(serde_json::Value::Object(m)) => m,
        Ok(_) => unreachable!("a run file serialises to an object"),
        Err(e) => {
            return Err(Error::new(
                ErrorKind::Io,
                format!("cannot serialise run {}: {e}", file.index),
            ))
        }
    };
    let sum = checksum_of(&body);
    body.insert("checksum".into(), serde_json::Value::String(sum));
    Ok(serde_json::Value::Object(body).to_string())
}

/// Verify the checksum of run file `path` holding `text`: its parsed
/// object, or an [`ErrorKind::Io`] error naming the file.
pub fn verify_run_file(
    path: &Path,
    text: &str,
) -> Result<serde_json::Map<String, serde_json::Value>> {
    let bad = |why: String| {
        Error::new(
            ErrorKind::Io,
            format!(
                "run file {} {why}; it was edited, damaged or written by an older version: \
                 delete it to recompute that run",
                path.display()
            ),
        )
    };
    let body = match serde_json::from_str::<serde_json::Value>(text) {
        Ok(serde_json::Value::Object(m)) => m,
        Ok(_) => return Err(bad("is not a JSON object".into())),
        Err(e) => return Err(bad(format!("is not JSON ({e})"))),
    };
    let stated = match body.get("checksum") {
        Some(serde_json::Value::String(s)) => s.clone(),
        _ => return Err(bad("has no checksum".into())),
    };
    let actual = checksum_of(&body);
    if stated != actual {
        return Err(bad(format!(
            "fails its checksum (stated {stated}, content gives {actual})"
        )));
    }
    Ok(body)
}

/// An ensemble of independent runs of one figure configuration, with resume
/// from per-run files and sharding (module docs).
#[derive(Debug, Clone)]
pub struct Ensemble {
    dir: PathBuf,
    key: serde_json::Value,
    base_seed: u64,
    runs: usize,
    shard: Option<Shard>,
    threads: usize,
    show_progress: bool,
    note: String,
}

impl Ensemble {
    /// An ensemble of `runs` runs of the configuration `key` (a JSON value
    /// describing everything but the number of runs) with base seed
    /// `base_seed`, saving into `out/<binary>/runs/<hash>/`. Creates the
    /// folder and its `config.json`; errors if the folder cannot be written.
    pub fn new(
        out: &Path,
        binary: &str,
        key: &serde_json::Value,
        base_seed: u64,
        runs: usize,
        shard: Option<Shard>,
    ) -> Result<Self> {
        if !(1..=MAX_RUNS).contains(&runs) {
            return Err(Error::out_of_range(
                "--runs",
                runs,
                &format!("1..={MAX_RUNS}"),
            ));
        }
        let key = serde_json::json!({"binary": binary, "base_seed": base_seed, "config": key});
        let text = serde_json::to_string(&key)
            .map_err(|e| Error::new(ErrorKind::Io, format!("cannot serialise key: {e}")))?;
        let dir = out
            .join(binary)
            .join("runs")
            .join(format!("{:016x}", fnv1a64(text.as_bytes())));
        fs::create_dir_all(&dir).map_err(|e| {
            Error::new(
                ErrorKind::Io,
                format!(
                    "cannot create {}: {e}; choose a writable --out",
                    dir.display()
                ),
            )
        })?;
        let config = dir.join("config.json");
        if config.exists() {
            let old = fs::read_to_string(&config)?;
            if old != text {
                return Err(Error::new(
                    ErrorKind::Io,
                    format!(
                        "{} holds another configuration (hash collision or edited file); \
                         remove that folder or choose another --out",
                        config.display()
                    ),
                ));
            }
        } else {
            write_atomic(&config, text.as_bytes())?;
        }
        Ok(Ensemble {
            dir,
            key,
            base_seed,
            runs,
            shard,
            threads: all_threads(),
            show_progress: true,
            note: String::new(),
        })
    }

    /// Use `n` worker threads (default: all cores). Results do not depend on it.
    pub fn threads(mut self, n: usize) -> Self {
        self.threads = n.max(1);
        self
    }

    /// Words the progress bar shows before its run count (e.g. the claims
    /// a sequential design still has open).
    pub fn note(mut self, note: &str) -> Self {
        self.note = note.to_string();
        self
    }

    /// No progress bar (for tests and doctests).
    pub fn quiet(mut self) -> Self {
        self.show_progress = false;
        self
    }

    /// The folder holding this configuration's run files.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Number of runs N.
    pub fn runs(&self) -> usize {
        self.runs
    }

    /// The seed of run `index`: [`derive_seed`](base seed, index).
    pub fn seed(&self, index: usize) -> u64 {
        derive_seed(self.base_seed, index as u64)
    }

    /// The seeds of all N runs, in run order.
    pub fn seeds(&self) -> Vec<u64> {
        (0..self.runs).map(|i| self.seed(i)).collect()
    }

    /// Path of the file of run `index`.
    pub fn run_path(&self, index: usize) -> PathBuf {
        self.dir.join(format!("run-{index:05}.json"))
    }

    /// Check that series `name` of every run has `want` samples, as the
    /// run's schedule asks: a run file that passes its checksum but was
    /// written (or re-sealed) with another series would otherwise break the
    /// analysis. `len(k)` is the length in run k.
    ///
    /// Errors: the first run whose series is of another length, naming its
    /// file ([`ErrorKind::Io`]).
    pub fn check_lengths(
        &self,
        name: &str,
        runs: usize,
        len: impl Fn(usize) -> usize,
        want: usize,
    ) -> Result<()> {
        match (0..runs).find(|&k| len(k) != want) {
            None => Ok(()),
            Some(k) => Err(Error::new(
                ErrorKind::Io,
                format!(
                    "{}: its `{name}` series has {} samples, the run's schedule asks for {want}; delete the file to redo that run",
                    self.run_path(k).display(),
                    len(k)
                ),
            )),
        }
    }

    /// Indices of the runs whose files exist.
    pub fn finished(&self) -> Vec<usize> {
        (0..self.runs)
            .filter(|&i| self.run_path(i).exists())
            .collect()
    }

    fn load<T: DeserializeOwned>(&self, index: usize) -> Result<T> {
        let path = self.run_path(index);
        let text = fs::read_to_string(&path).map_err(|e| io_error(&path, "read", e))?;
        let body = verify_run_file(&path, &text)?;
        let file: RunFile<T> =
            serde_json::from_value(serde_json::Value::Object(body)).map_err(|e| {
                Error::new(
                    ErrorKind::Io,
                    format!(
                    "{} is not a run file of this figure ({e}); delete it to recompute that run",
                    path.display()
                ),
                )
            })?;
        if file.index != index || file.seed != self.seed(index) || file.key != self.key {
            let mut what = Vec::new();
            if file.index != index {
                what.push(format!("index: {} vs {index}", file.index));
            }
            if file.seed != self.seed(index) {
                what.push(format!("seed: {} vs {}", file.seed, self.seed(index)));
            }
            what.extend(json_differences(&file.key, &self.key));
            return Err(Error::new(
                ErrorKind::Io,
                format!(
                    "{} belongs to another run ({}; this file vs this configuration); delete it to recompute run {index}",
                    path.display(),
                    what.join("; ")
                ),
            ));
        }
        Ok(file.result)
    }

    fn save<T: Serialize>(&self, index: usize, result: &T) -> Result<()> {
        let file = RunFile {
            key: self.key.clone(),
            index,
            seed: self.seed(index),
            result,
        };
        let text = seal(&file)?;
        write_atomic(&self.run_path(index), text.as_bytes())
    }

    /// Compute every run (of this shard) whose file is missing, saving each
    /// one as soon as it finishes, and return all results in run order, or
    /// [`Outcome::ShardDone`] when sharded.
    ///
    /// `f(index, seed, tick)` computes one run; it must be a pure function of
    /// (index, seed) and may call `tick(steps)` to advance the progress bar,
    /// whose length is `steps_per_run` per run. The first error stops the
    /// workers from starting new runs; runs finished so far stay saved.
    pub fn run<T, F>(&self, steps_per_run: u64, f: F) -> Result<Outcome<T>>
    where
        T: Serialize + DeserializeOwned + Send,
        F: Fn(usize, u64, &(dyn Fn(u64) + Sync)) -> Result<T> + Sync,
    {
        self.run_inner(steps_per_run, f, None::<fn(&T) -> bool>)
    }

    /// [`Ensemble::run`] for a sequential decision: the runs in index order
    /// up to and including the first whose result `decides` (all runs when
    /// none does). Runs past that index are not started (those already
    /// saved, or finished by another worker, stay saved); every run before
    /// it is computed, so the result does not depend on the thread count.
    /// Not for sharded ensembles (an error).
    pub fn run_until<T, F, D>(&self, steps_per_run: u64, f: F, decides: D) -> Result<Vec<T>>
    where
        T: Serialize + DeserializeOwned + Send,
        F: Fn(usize, u64, &(dyn Fn(u64) + Sync)) -> Result<T> + Sync,
        D: Fn(&T) -> bool + Sync,
    {
        if self.shard.is_some() {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "--shard: this ensemble stops at its first deciding run, which needs every run in one process; run it without --shard",
            ));
        }
        match self.run_inner(steps_per_run, f, Some(decides))? {
            Outcome::Complete(v) => Ok(v),
            Outcome::ShardDone { .. } => unreachable!("not sharded"),
        }
    }

    fn run_inner<T, F, D>(&self, steps_per_run: u64, f: F, decides: Option<D>) -> Result<Outcome<T>>
    where
        T: Serialize + DeserializeOwned + Send,
        F: Fn(usize, u64, &(dyn Fn(u64) + Sync)) -> Result<T> + Sync,
        D: Fn(&T) -> bool + Sync,
    {
        let mine: Vec<usize> = (0..self.runs)
            .filter(|&r| self.shard.is_none_or(|s| s.owns(r)))
            .collect();
        // the first run (in index order) known to decide; runs after it are
        // not started
        let decided_at = AtomicUsize::new(usize::MAX);
        if let Some(d) = &decides {
            for r in self.finished() {
                if d(&self.load::<T>(r)?) {
                    decided_at.store(r, Ordering::SeqCst);
                    break;
                }
            }
        }
        let todo: Vec<usize> = mine
            .iter()
            .copied()
            .filter(|&r| !self.run_path(r).exists() && r < decided_at.load(Ordering::SeqCst))
            .collect();
        let pb = progress(todo.len() as u64 * steps_per_run, "runs");
        if !self.show_progress {
            pb.set_draw_target(indicatif::ProgressDrawTarget::hidden());
        }
        let note = if self.note.is_empty() {
            String::new()
        } else {
            format!("{}: ", self.note)
        };
        pb.set_message(format!(
            "{note}{}/{} runs",
            mine.len() - todo.len(),
            mine.len()
        ));
        let done = AtomicUsize::new(mine.len() - todo.len());
        let next = AtomicUsize::new(0);
        let stop = AtomicBool::new(false);
        let first_error: Mutex<Option<Error>> = Mutex::new(None);
        let tick = |n: u64| pb.inc(n);
        std::thread::scope(|s| {
            for _ in 0..self.threads.min(todo.len().max(1)) {
                s.spawn(|| loop {
                    if stop.load(Ordering::SeqCst) {
                        break;
                    }
                    let k = next.fetch_add(1, Ordering::SeqCst);
                    if k >= todo.len() {
                        break;
                    }
                    let r = todo[k];
                    if r > decided_at.load(Ordering::SeqCst) {
                        break; // todo is in index order: the rest is later still
                    }
                    let res = f(r, self.seed(r), &tick).and_then(|v| {
                        self.save(r, &v)?;
                        if decides.as_ref().is_some_and(|d| d(&v)) {
                            decided_at.fetch_min(r, Ordering::SeqCst);
                        }
                        Ok(())
                    });
                    match res {
                        Ok(()) => {
                            let d = done.fetch_add(1, Ordering::SeqCst) + 1;
                            pb.set_message(format!("{note}{d}/{} runs", mine.len()));
                        }
                        Err(e) => {
                            stop.store(true, Ordering::SeqCst);
                            let mut slot = first_error.lock().expect("no poisoned lock");
                            if slot.is_none() {
                                *slot = Some(e);
                            }
                            break;
                        }
                    }
                });
            }
        });
        pb.finish_and_clear();
        if let Some(e) = first_error.into_inner().expect("no poisoned lock") {
            return Err(e);
        }
        if let Some(shard) = self.shard {
            return Ok(Outcome::ShardDone {
                shard,
                runs: mine.len(),
                dir: self.dir.clone(),
            });
        }
        let last = decided_at.load(Ordering::SeqCst).min(self.runs - 1);
        let results = (0..=last)
            .map(|r| self.load(r))
            .collect::<Result<Vec<T>>>()?;
        Ok(Outcome::Complete(results))
    }
}

/// What [`merge`] did.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct MergeReport {
    /// Run files copied into the target (`config.json` files not counted).
    pub copied: usize,
    /// Run files already present in the target with identical contents
    /// (`config.json` files not counted).
    pub identical: usize,
}

/// The configuration key in `config.json` at `path`, if it is there.
fn read_key(path: &Path) -> Option<serde_json::Value> {
    serde_json::from_slice(&fs::read(path).ok()?).ok()
}

fn read_dir_sorted(dir: &Path) -> Result<Vec<PathBuf>> {
    let mut v: Vec<PathBuf> = fs::read_dir(dir)
        .map_err(|e| Error::new(ErrorKind::Io, format!("cannot read {}: {e}", dir.display())))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .collect();
    v.sort();
    Ok(v)
}

/// Where two JSON values differ, as `path: here vs there` (at most five,
/// e.g. `config.tier: "standard" vs "quick"`).
fn json_differences(here: &serde_json::Value, there: &serde_json::Value) -> Vec<String> {
    fn walk(path: &str, a: &serde_json::Value, b: &serde_json::Value, out: &mut Vec<String>) {
        match (a, b) {
            (serde_json::Value::Object(x), serde_json::Value::Object(y)) => {
                let keys: std::collections::BTreeSet<&String> = x.keys().chain(y.keys()).collect();
                for k in keys {
                    let null = serde_json::Value::Null;
                    let sub = if path.is_empty() {
                        k.clone()
                    } else {
                        format!("{path}.{k}")
                    };
                    walk(
                        &sub,
                        x.get(k).unwrap_or(&null),
                        y.get(k).unwrap_or(&null),
                        out,
                    );
                }
            }
            _ if a != b => out.push(format!("{path}: {a} vs {b}")),
            _ => {}
        }
    }
    let mut out = Vec::new();
    walk("", here, there, &mut out);
    out.truncate(5);
    out
}

/// What makes run file `file` (its verified `body`) foreign to the run
/// folder `<binary>/runs/<hash>/` whose configuration key is `folder_key`
/// (its `config.json`, if known): a key that does not hash to the folder's
/// name or differs from `folder_key` (named field by field, e.g. the base
/// seed or `config.tier`), another binary, an index other than its file
/// name's, or a seed other than the one derived from the base seed and
/// the index. `None` when it belongs there.
fn foreign_run(
    file: &Path,
    body: &serde_json::Map<String, serde_json::Value>,
    binary: &str,
    hash: &str,
    folder_key: Option<&serde_json::Value>,
) -> Option<String> {
    let null = serde_json::Value::Null;
    let key = body.get("key").unwrap_or(&null);
    let mut why = Vec::new();
    let key_hash = format!("{:016x}", fnv1a64(key.to_string().as_bytes()));
    match folder_key {
        Some(k) if k != key => why.push(format!(
            "its key differs from the folder's config.json ({}; this file vs the folder)",
            json_differences(key, k).join("; ")
        )),
        _ if key_hash != hash => why.push(format!(
            "its key hashes to {key_hash}, not to the folder name {hash}"
        )),
        _ => {}
    }
    if key["binary"].as_str() != Some(binary) {
        why.push(format!(
            "its key names the binary {}, not {binary}",
            key["binary"]
        ));
    }
    let name = file.file_stem().map(|s| s.to_string_lossy().into_owned());
    let named = name
        .as_deref()
        .and_then(|n| n.strip_prefix("run-")?.parse::<u64>().ok());
    let index = body.get("index").and_then(serde_json::Value::as_u64);
    if index.is_none() || index != named {
        why.push(format!(
            "its index is {}, its file name says {}",
            body.get("index").unwrap_or(&null),
            named.map_or("none".to_string(), |i| i.to_string())
        ));
    }
    let seed = body.get("seed").and_then(serde_json::Value::as_u64);
    if let (Some(base), Some(i)) = (key["base_seed"].as_u64(), index) {
        let want = derive_seed(base, i);
        if seed != Some(want) {
            why.push(format!(
                "its seed is {}, run {i} of base seed {base} has seed {want}",
                body.get("seed").unwrap_or(&null)
            ));
        }
    }
    (!why.is_empty()).then(|| why.join("; "))
}

/// Merge shard output folders: copy every `<binary>/runs/<hash>/` file of
/// each folder in `from` into `into` (same layout). Every run file must
/// pass its checksum and every `config.json` must hash to its folder's
/// name; a file present on both sides must be byte-identical (runs are pure
/// functions of their seed). All or nothing: everything is verified before
/// anything is written, new files are staged in a temporary folder inside
/// `into` and then renamed into place, and any failure removes what this
/// merge wrote; errors name the file. After the merge, running the figure
/// without `--shard` on `into` finds every run finished and only analyses.
pub fn merge(into: &Path, from: &[PathBuf]) -> Result<MergeReport> {
    let mut report = MergeReport::default();
    let named: Vec<String> = from.iter().map(|p| p.display().to_string()).collect();
    crate::error::reject_duplicates("merge: shard folder", &named)?;
    // 1. verify and plan: (destination, bytes) of every new file
    let mut plan: Vec<(PathBuf, Vec<u8>)> = Vec::new();
    // the configuration key of every run folder whose config.json was read
    let mut keys: std::collections::BTreeMap<PathBuf, serde_json::Value> = Default::default();
    for src in from {
        if !src.is_dir() {
            let what = if src.exists() {
                "is a file, not a folder"
            } else {
                "does not exist"
            };
            return Err(Error::new(
                ErrorKind::Io,
                format!(
                    "shard folder {} {what}; pass the --out folders of the shards",
                    src.display()
                ),
            ));
        }
        let mut run_folders = 0;
        for bin_dir in read_dir_sorted(src)? {
            let runs = bin_dir.join("runs");
            if !runs.is_dir() {
                continue;
            }
            let binary = bin_dir.file_name().expect("a folder name").to_owned();
            for cfg in read_dir_sorted(&runs)? {
                if !cfg.is_dir() {
                    continue;
                }
                run_folders += 1;
                let hash = cfg.file_name().expect("a folder name").to_owned();
                let target = into.join(&binary).join("runs").join(&hash);
                // the folder's key: its config.json in the target, in an
                // earlier shard or here (checked below, it comes first)
                let mut folder_key = keys
                    .get(&target)
                    .cloned()
                    .or_else(|| read_key(&target.join("config.json")));
                for file in read_dir_sorted(&cfg)? {
                    let name = file.file_name().expect("a file name").to_owned();
                    let name_s = name.to_string_lossy();
                    if !name_s.ends_with(".json") {
                        continue; // temporary files of an interrupted write
                    }
                    let is_run = name_s.starts_with("run-");
                    let bytes = fs::read(&file).map_err(|e| io_error(&file, "read", e))?;
                    if is_run {
                        // as the resume reads it: text, never a lossy
                        // conversion of damaged bytes
                        let text = std::str::from_utf8(&bytes).map_err(|e| {
                            Error::new(
                                ErrorKind::Io,
                                format!(
                                    "run file {} is not UTF-8 text ({e}); it was damaged: nothing was merged, \
                                     remove it from the shard and rerun the shard",
                                    file.display()
                                ),
                            )
                        })?;
                        let body = verify_run_file(&file, text)?;
                        let (b, h) = (binary.to_string_lossy(), hash.to_string_lossy());
                        if let Some(why) = foreign_run(&file, &body, &b, &h, folder_key.as_ref()) {
                            return Err(Error::new(
                                ErrorKind::Io,
                                format!(
                                    "run file {} does not belong in {}: {why}; it was copied from another \
                                     run (seed, tier or parameters): nothing was merged, remove it from the shard",
                                    file.display(),
                                    target.display()
                                ),
                            ));
                        }
                    } else if name_s == "config.json" {
                        if format!("{:016x}", fnv1a64(&bytes)) != hash.to_string_lossy() {
                            return Err(Error::new(
                                ErrorKind::Io,
                                format!(
                                    "{} does not hash to its folder name {}; it was edited or moved: \
                                     delete that folder from the shard and rerun the shard",
                                    file.display(),
                                    hash.to_string_lossy()
                                ),
                            ));
                        }
                        folder_key = serde_json::from_slice(&bytes).ok();
                        if let Some(k) = &folder_key {
                            keys.insert(target.clone(), k.clone());
                        }
                    }
                    let dest = target.join(&name);
                    let planned = plan.iter().find(|(d, _)| *d == dest).map(|(_, b)| b);
                    let existing = if let Some(b) = planned {
                        Some(b.clone())
                    } else if dest.exists() {
                        Some(fs::read(&dest).map_err(|e| io_error(&dest, "read", e))?)
                    } else {
                        None
                    };
                    match existing {
                        Some(old) if old != bytes => {
                            return Err(Error::new(
                                ErrorKind::Io,
                                format!(
                                    "{} and {} differ although they hold the same run; \
                                     the shards were run with different code or parameters",
                                    file.display(),
                                    dest.display()
                                ),
                            ));
                        }
                        Some(_) => report.identical += is_run as usize,
                        None => {
                            report.copied += is_run as usize;
                            plan.push((dest, bytes));
                        }
                    }
                }
            }
        }
        if run_folders == 0 {
            return Err(Error::new(
                ErrorKind::Io,
                format!(
                    "shard folder {} holds no run folder (<binary>/runs/<hash>/): nothing to merge; \
                     pass the --out folders of the shards",
                    src.display()
                ),
            ));
        }
    }
    if plan.is_empty() {
        return Ok(report);
    }
    // 2. stage, then rename into place; undo everything on failure
    fs::create_dir_all(into).map_err(|e| io_error(into, "create", e))?;
    let staging = into.join(format!(".merge-staging-{}", std::process::id()));
    let mut created: Vec<PathBuf> = Vec::new();
    let mut placed: Vec<PathBuf> = Vec::new();
    let result = (|| -> Result<()> {
        fs::create_dir_all(&staging).map_err(|e| io_error(&staging, "create", e))?;
        let mut staged = Vec::new();
        for (k, (dest, bytes)) in plan.iter().enumerate() {
            let tmp = staging.join(format!("{k:06}.json"));
            fs::write(&tmp, bytes).map_err(|e| io_error(&tmp, "write", e))?;
            staged.push((tmp, dest));
        }
        for (tmp, dest) in staged {
            let dir = dest.parent().expect("a run folder");
            // remember the folders this merge creates, outermost first
            let mut new_dirs: Vec<PathBuf> = dir
                .ancestors()
                .take_while(|d| !d.exists())
                .map(Path::to_path_buf)
                .collect();
            new_dirs.reverse();
            fs::create_dir_all(dir).map_err(|e| io_error(dir, "create", e))?;
            created.extend(new_dirs);
            fs::rename(&tmp, dest).map_err(|e| io_error(dest, "move into place", e))?;
            placed.push(dest.clone());
        }
        Ok(())
    })();
    let _ = fs::remove_dir_all(&staging);
    if let Err(e) = result {
        for f in &placed {
            let _ = fs::remove_file(f);
        }
        for d in created.iter().rev() {
            let _ = fs::remove_dir(d);
        }
        return Err(e);
    }
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shard_parses_and_rejects_bad_input() {
        assert_eq!(
            "2/4".parse::<Shard>().unwrap(),
            Shard { index: 2, count: 4 }
        );
        for bad in ["4/4", "1/0", "x/2", "3", "-1/2"] {
            let e = bad.parse::<Shard>().unwrap_err();
            assert_eq!(e.kind, ErrorKind::InvalidParameter);
            assert!(e.message.contains(bad), "{}", e.message);
        }
        let s = Shard { index: 1, count: 3 };
        let owned: Vec<usize> = (0..8).filter(|&r| s.owns(r)).collect();
        assert_eq!(owned, vec![1, 4, 7]);
    }

    #[test]
    fn run_files_carry_a_checksum_that_catches_edits() {
        let file = RunFile {
            key: serde_json::json!({"rho": 1.0}),
            index: 3,
            seed: 42,
            result: vec![0.5, 1.25],
        };
        let text = seal(&file).unwrap();
        let path = Path::new("run-00003.json");
        assert!(verify_run_file(path, &text).is_ok());
        let edited = text.replace("1.25", "1.5");
        let e = verify_run_file(path, &edited).unwrap_err();
        assert!(e.message.contains("run-00003.json") && e.message.contains("checksum"));
        let old = serde_json::to_string(&file).unwrap(); // no checksum
        assert!(verify_run_file(path, &old).is_err());
    }

    /// `run_until` returns the runs up to the first deciding one in index
    /// order, whatever the thread count and whatever was saved before (runs
    /// after it that other workers had started stay saved); `run` on the
    /// same ensemble still gives all.
    #[test]
    fn run_until_stops_at_the_first_deciding_run_in_index_order() {
        let dir = std::env::temp_dir().join(format!("ga-run-until-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        let key = serde_json::json!({"test": "run_until"});
        // run r "decides" when its seed-derived value is r = 5 or r = 9
        let f = |r: usize, _seed: u64, _t: &(dyn Fn(u64) + Sync)| -> Result<usize> { Ok(r) };
        let decides = |v: &usize| *v == 5 || *v == 9;
        for threads in [1, 2, 7] {
            let sub = dir.join(format!("t{threads}"));
            let ens = Ensemble::new(&sub, "test", &key, 1, 16, None)
                .unwrap()
                .threads(threads)
                .quiet();
            let v = ens.run_until(10, f, decides).unwrap();
            assert_eq!(v, (0..=5).collect::<Vec<_>>(), "{threads} threads");
            assert!((0..=5).all(|r| ens.run_path(r).exists()));
            if threads == 1 {
                assert!((6..16).all(|r| !ens.run_path(r).exists()), "none after 5");
            }
        }
        // a later run saved first does not hide an earlier decision
        let sub = dir.join("saved");
        let ens = Ensemble::new(&sub, "test", &key, 1, 16, None)
            .unwrap()
            .quiet();
        ens.save(9, &9usize).unwrap();
        assert_eq!(ens.run_until(10, f, decides).unwrap().len(), 6);
        match ens.run(10, f).unwrap() {
            Outcome::Complete(all) => assert_eq!(all, (0..16).collect::<Vec<_>>()),
            Outcome::ShardDone { .. } => unreachable!(),
        }
        // no deciding run: all of them
        let none = Ensemble::new(&dir.join("none"), "test", &key, 1, 4, None)
            .unwrap()
            .quiet();
        assert_eq!(none.run_until(10, f, |_: &usize| false).unwrap().len(), 4);
        // sharded: refused
        let sharded = Ensemble::new(
            &dir.join("sh"),
            "test",
            &key,
            1,
            4,
            Some(Shard { index: 0, count: 2 }),
        )
        .unwrap()
        .quiet();
        let e = sharded.run_until(10, f, decides).unwrap_err();
        assert!(e.message.contains("--shard"), "{}", e.message);
        let _ = fs::remove_dir_all(&dir);
    }

    #[test]
    fn fnv_known_values() {
        assert_eq!(fnv1a64(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a64(b"a"), 0xaf63_dc4c_8601_ec8c);
    }
}
