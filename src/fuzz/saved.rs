//! The readers of saved runs (`src/ensemble.rs`): a run file on resume, and
//! shard folders in `merge`. A file with a flipped byte, cut short, edited
//! and re-sealed with a valid checksum, or copied from a run of another
//! seed, tier, reading, engine version or index must be refused, or give
//! exactly the original runs.

use super::mutate::mutate;
use super::{excerpt, Case, Rng, TempDir, Verdict};
use crate::ensemble::{fnv1a64, merge, Ensemble, Outcome};
use crate::error::Result;
use rand::RngExt;
use serde_json::{json, Value};
use std::fs;
use std::path::{Path, PathBuf};

/// The binary whose runs the fuzzer saves.
const BINARY: &str = "fuzz-runs";

/// Runs per ensemble.
const RUNS: usize = 3;

/// Base seed of the ensemble under test.
const SEED: u64 = 7;

/// The result of a run: pure in (index, seed).
type Res = (Vec<f64>, u64, String);

fn result(index: usize, seed: u64) -> Res {
    let x = (seed % 1_000_003) as f64 / 7.0;
    (
        vec![x, -x * 1e-9, 0.1 + index as f64, f64::MIN_POSITIVE],
        seed,
        format!("run {index}"),
    )
}

/// The configuration key of the ensemble under test.
fn key() -> Value {
    json!({"tier": "quick", "rules": "default", "engine": "reference", "rho": 1.0, "L": 220})
}

/// An ensemble of `binary` with `key` and base seed `seed` in `out`, run
/// to completion: its results.
fn run_ensemble(out: &Path, key: &Value, seed: u64) -> Result<Vec<Res>> {
    let ens = Ensemble::new(out, BINARY, key, seed, RUNS, None)?
        .threads(1)
        .quiet();
    match ens.run(1, |i, s, _| Ok(result(i, s)))? {
        Outcome::Complete(v) => Ok(v),
        Outcome::ShardDone { .. } => unreachable!("not sharded"),
    }
}

/// The run file of run `index` of the ensemble with `key` and `seed` in `out`.
fn run_path(out: &Path, key: &Value, seed: u64, index: usize) -> Result<PathBuf> {
    Ok(Ensemble::new(out, BINARY, key, seed, RUNS, None)?.run_path(index))
}

/// `body` sealed with its checksum, as `ensemble` writes a run file (the
/// FNV-1a of the canonical JSON without the checksum): an edit that a
/// damaged file would not carry, so only the key, index and seed checks
/// stand against it.
fn reseal(mut body: serde_json::Map<String, Value>) -> Vec<u8> {
    body.remove("checksum");
    let sum = format!(
        "{:016x}",
        fnv1a64(Value::Object(body.clone()).to_string().as_bytes())
    );
    body.insert("checksum".into(), Value::String(sum));
    Value::Object(body).to_string().into_bytes()
}

/// Saved run files on resume (`merge: false`) or in a shard folder merged
/// into a new target (`merge: true`).
pub(crate) struct RunFiles {
    dir: TempDir,
    merge: bool,
    /// The ensemble under test: its results and its run files' bytes.
    want: Vec<Res>,
    files: Vec<Vec<u8>>,
    /// Run files of ensembles of another seed, tier, reading, engine
    /// version and binary: (what, bytes of run 0..RUNS).
    foreign: Vec<(&'static str, Vec<Vec<u8>>)>,
    /// The folder of the ensemble under test, relative to its --out.
    folder: PathBuf,
    config: Vec<u8>,
    last: Vec<u8>,
    round: u64,
}

impl RunFiles {
    /// Save the ensemble under test and its foreign twins.
    pub fn new(merge: bool) -> Result<Self> {
        let dir = TempDir::new(if merge { "merge" } else { "run-file" })?;
        let home = dir.path().join("home");
        let want = run_ensemble(&home, &key(), SEED)?;
        let files = (0..RUNS)
            .map(|i| fs::read(run_path(&home, &key(), SEED, i)?).map_err(Into::into))
            .collect::<Result<Vec<_>>>()?;
        let run0 = run_path(&home, &key(), SEED, 0)?;
        let cfg_dir = run0.parent().expect("a run folder");
        let folder = cfg_dir.strip_prefix(&home).expect("inside").to_path_buf();
        let config = fs::read(cfg_dir.join("config.json"))?;
        let mut foreign = Vec::new();
        let edits: [(&str, &str, Value); 4] = [
            ("tier", "another tier", json!("standard")),
            ("rules", "another reading", json!("ph94")),
            ("engine", "another engine version", json!("reference@2")),
            ("L", "another pipe", json!(221)),
        ];
        let other = dir.path().join("other");
        for (field, what, value) in edits {
            let mut k = key();
            k[field] = value;
            run_ensemble(&other, &k, SEED)?;
            let bytes = (0..RUNS)
                .map(|i| fs::read(run_path(&other, &k, SEED, i)?).map_err(Into::into))
                .collect::<Result<Vec<_>>>()?;
            foreign.push((what, bytes));
        }
        run_ensemble(&other, &key(), SEED + 1)?;
        let bytes = (0..RUNS)
            .map(|i| fs::read(run_path(&other, &key(), SEED + 1, i)?).map_err(Into::into))
            .collect::<Result<Vec<_>>>()?;
        foreign.push(("another seed", bytes));
        Ok(RunFiles {
            dir,
            merge,
            want,
            files,
            foreign,
            folder,
            config,
            last: vec![],
            round: 0,
        })
    }

    /// A damaged or foreign version of run file `k`.
    fn bad_file(&self, rng: &mut Rng, k: usize) -> Vec<u8> {
        match rng.random_range(0..6) {
            // damaged: flipped bits, cut short, long runs, odd numbers ...
            0..=2 => mutate(rng, &self.files[k]),
            // another run's file, as it was saved
            3 => {
                let (_, f) = &self.foreign[rng.random_range(0..self.foreign.len())];
                f[k].clone()
            }
            // another index's file of the same ensemble
            4 => self.files[(k + rng.random_range(1..RUNS)) % RUNS].clone(),
            // edited and re-sealed: another index, seed or key field, or
            // no checksum (an older version)
            _ => {
                let Ok(Value::Object(mut body)) = serde_json::from_slice(&self.files[k]) else {
                    unreachable!("a run file is an object")
                };
                match rng.random_range(0..5) {
                    0 => body["index"] = json!(k as u64 + rng.random_range(1..5)),
                    1 => {
                        let s = body["seed"].as_u64().unwrap_or(0);
                        body["seed"] = json!(s ^ (1u64 << rng.random_range(0..64)));
                    }
                    2 => body["key"]["base_seed"] = json!(SEED + rng.random_range(1..5)),
                    3 => {
                        let fields = ["tier", "rules", "engine", "rho", "L"];
                        let f = fields[rng.random_range(0..fields.len())];
                        body["key"]["config"][f] = json!("edited");
                    }
                    _ => {
                        body.remove("checksum");
                        return Value::Object(body).to_string().into_bytes();
                    }
                }
                reseal(body)
            }
        }
    }

    /// Resume the ensemble under test in `out`: its results, checked.
    fn resume(&self, out: &Path) -> Verdict {
        let ens = match Ensemble::new(out, BINARY, &key(), SEED, RUNS, None) {
            Ok(e) => e.threads(1).quiet(),
            Err(_) => return Verdict::Refused,
        };
        match ens.run(1, |i, s, _| Ok(result(i, s))) {
            Err(_) => Verdict::Refused,
            Ok(Outcome::Complete(v)) if v == self.want => Verdict::Accepted,
            Ok(Outcome::Complete(v)) => Verdict::Silent(format!(
                "the runs read back are {v:?}, the saved ones {:?}",
                self.want
            )),
            Ok(Outcome::ShardDone { .. }) => unreachable!("not sharded"),
        }
    }
}

impl Case for RunFiles {
    fn one(&mut self, rng: &mut Rng) -> Verdict {
        self.round += 1;
        let k = rng.random_range(0..RUNS);
        let bad = self.bad_file(rng, k);
        self.last = bad.clone();
        let err = |e: std::io::Error| Verdict::Silent(format!("the fuzzer cannot write: {e}"));
        if !self.merge {
            // one folder, resumed with run k replaced
            let out = self.dir.path().join("home");
            let path = out.join(&self.folder).join(format!("run-{k:05}.json"));
            if let Err(e) = fs::write(&path, &bad) {
                return err(e);
            }
            let v = self.resume(&out);
            if let Err(e) = fs::write(&path, &self.files[k]) {
                return err(e);
            }
            return v;
        }
        // a shard folder with run k replaced (or its config.json damaged),
        // merged into a new target, sometimes beside a sound shard
        let round = self.dir.path().join(format!("round-{}", self.round));
        let shard = round.join("shard");
        let folder = shard.join(&self.folder);
        let write = || -> std::io::Result<()> {
            fs::create_dir_all(&folder)?;
            fs::write(folder.join("config.json"), &self.config)?;
            for (i, f) in self.files.iter().enumerate() {
                fs::write(folder.join(format!("run-{i:05}.json")), f)?;
            }
            Ok(())
        };
        if let Err(e) = write() {
            return err(e);
        }
        let target = if rng.random_bool(0.1) {
            self.last = mutate(rng, &self.config);
            folder.join("config.json")
        } else {
            folder.join(format!("run-{k:05}.json"))
        };
        if let Err(e) = fs::write(&target, &self.last) {
            return err(e);
        }
        let mut shards = vec![shard];
        if rng.random_bool(0.3) {
            shards.push(self.dir.path().join("home"));
            if rng.random_bool(0.5) {
                shards.reverse();
            }
        }
        let into = round.join("into");
        let v = match merge(&into, &shards) {
            Err(_) => Verdict::Refused,
            // what merge took, the resume must read back as saved
            Ok(_) => match self.resume(&into) {
                Verdict::Refused => {
                    Verdict::Silent("merge took a file that the resume then refuses".into())
                }
                v => v,
            },
        };
        let _ = fs::remove_dir_all(&round);
        v
    }

    fn input(&self) -> String {
        excerpt(&self.last)
    }
}
