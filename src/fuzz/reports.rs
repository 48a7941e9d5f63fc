//! The readers of the outputs the `report` command reads back: a figure's
//! summary.json (`report --no-run`), the seed-set folders of summaries
//! (`report --seed-sets`) and report.json (`report --experiments`).

use super::mutate::mutate;
use super::{excerpt, Case, Rng, TempDir, Verdict};
use crate::drivers::acceptance_study::{all_seeds, seal};
use crate::error::Result;
use crate::report::{read_figure, FigureRun, Row};
use rand::RngExt;
use serde_json::{json, Value};
use std::fs;

/// The figure whose summaries are generated.
const FIGURE: &str = "fig2";

/// A summary.json of [`FIGURE`] over `seeds`, with a random check list.
fn summary(rng: &mut Rng, seeds: &[u64], tier: &str) -> Value {
    let mut checks = vec![];
    for name in ["alpha", "v_peak", "contrast", "speed"] {
        if rng.random_bool(0.2) {
            continue;
        }
        use crate::analysis::grading::{grade, Claim, Estimate};
        let kind = ["published", "pinned", "identity"][rng.random_range(0..3)];
        let claim = match rng.random_range(0..3) {
            0 => Claim::Within {
                target: 1.33,
                margin: 0.059,
            },
            1 => Claim::Above { threshold: 0.45 },
            _ => Claim::Below { threshold: 2.0 },
        };
        let (published, tolerance) = match claim {
            Claim::Within { target, margin } => (json!(target), json!(margin)),
            Claim::Above { threshold } | Claim::Below { threshold } => {
                (Value::Null, json!(threshold))
            }
        };
        let (measured, error, runs) = (
            rng.random_range(0.0..2.0),
            rng.random_range(0.0..0.1),
            rng.random_range(1..200u64),
        );
        // the verdict the one rule gives, as a figure writes it (the report
        // recomputes it)
        let verdict = grade(Estimate::new(measured, error, runs as usize), claim).status();
        checks.push(json!({
            "name": name,
            "kind": kind,
            "verdict": verdict,
            "pass": verdict == "reproduced",
            "measured": measured,
            "error": error,
            "published": published,
            "tolerance": tolerance,
            "runs": runs,
            "claim": claim,
            "note": "a note",
            "source": "PH94 Fig. 2",
        }));
    }
    if checks.is_empty() {
        checks.push(
            json!({"name": "alpha", "kind": "published", "verdict": "undecided",
            "measured": null, "claim": {"test": "within", "target": 1.33, "margin": 0.059}}),
        );
    }
    json!({
        "figure": FIGURE,
        "paper": "PH94 Fig. 2",
        "tier": tier,
        "rules": "default",
        "engine": "reference",
        "seeds": seeds,
        "wall_seconds": rng.random_range(0.0..100.0),
        "cpu_seconds": 1.5,
        "site_updates": 1e9,
        "metrics": {"alpha_fit": 1.26},
        "checks": checks,
    })
}

/// Whether row `r`, read from a summary the report accepted, is one it can
/// grade: a name, a known kind and verdict, a finite value when decided.
fn row_fault(r: &Row) -> Option<String> {
    let kinds = ["published", "pinned", "identity", "unstated"];
    let verdicts = ["reproduced", "not-reproduced", "undecided"];
    let ok = !r.name.is_empty()
        && kinds.contains(&r.kind.as_str())
        && verdicts.contains(&r.verdict.as_str())
        && (r.verdict == "undecided" || r.measured.is_some_and(f64::is_finite));
    (!ok).then(|| format!("row {r:?}"))
}

/// A figure's summary.json as `report --no-run` reads it.
pub(crate) struct Summary {
    dir: TempDir,
    last: Vec<u8>,
}

impl Summary {
    /// A folder for the figure's output.
    pub fn new() -> Result<Self> {
        let dir = TempDir::new("summary")?;
        fs::create_dir_all(dir.path().join(FIGURE))?;
        Ok(Summary { dir, last: vec![] })
    }
}

impl Case for Summary {
    fn one(&mut self, rng: &mut Rng) -> Verdict {
        let seeds: [u64; 2] = [rng.random(), rng.random()];
        let s = summary(rng, &seeds, "quick");
        self.last = mutate(rng, s.to_string().as_bytes());
        let path = self.dir.path().join(FIGURE).join("summary.json");
        if let Err(e) = fs::write(&path, &self.last) {
            return Verdict::Silent(format!("the fuzzer cannot write: {e}"));
        }
        let run = FigureRun {
            binary: FIGURE.into(),
            ok: true,
            failure: None,
            stderr_tail: vec![],
            wall_seconds: 1.0,
        };
        let (fr, rows) = read_figure(self.dir.path(), run);
        if fr.summary_problem.is_some() {
            return Verdict::Refused;
        }
        if rows.is_empty() {
            return Verdict::Silent("a summary without checks was read".into());
        }
        match rows.iter().find_map(row_fault) {
            Some(why) => Verdict::Silent(why),
            None => Verdict::Accepted,
        }
    }

    fn input(&self) -> String {
        excerpt(&self.last)
    }
}

/// Seed-set folders of [`FIGURE`], as `report --seed-sets` grades them.
pub(crate) struct SeedSets {
    dir: TempDir,
    sound: Vec<Vec<u8>>,
    last: Vec<u8>,
}

/// Seed sets per generated folder.
const SETS: usize = 4;

impl SeedSets {
    /// [`SETS`] seed folders, each with its summary.
    pub fn new() -> Result<Self> {
        let dir = TempDir::new("seed-sets")?;
        Ok(SeedSets {
            dir,
            sound: vec![],
            last: vec![],
        })
    }

    fn path(&self, k: usize) -> std::path::PathBuf {
        self.dir
            .path()
            .join(format!("seed-{k}"))
            .join(FIGURE)
            .join("summary.json")
    }
}

impl Case for SeedSets {
    fn one(&mut self, rng: &mut Rng) -> Verdict {
        // sound seed sets: the same checks, each its own seeds
        self.sound = (0..SETS)
            .map(|k| {
                let s = summary(rng, &[1000 + k as u64, 2000 + k as u64], "quick");
                s.to_string().into_bytes()
            })
            .collect();
        let k = rng.random_range(0..SETS);
        // a damaged seed set, or one that must be refused: a copy of
        // another (the same runs), or of another tier or reading
        let (bad, must_refuse) = match rng.random_range(0..5) {
            0 => (self.sound[(k + 1) % SETS].clone(), true),
            1 => {
                let mut s: Value = serde_json::from_slice(&self.sound[k]).expect("json");
                let (field, value) = [("tier", "standard"), ("rules", "ph94"), ("engine", "fast")]
                    [rng.random_range(0..3)];
                s[field] = json!(value);
                (s.to_string().into_bytes(), true)
            }
            _ => (mutate(rng, &self.sound[k]), false),
        };
        self.last = bad.clone();
        // the sound seed sets filed and sealed, then seed set k replaced
        // by the bad one (its seal that of the sound one)
        for (i, s) in self.sound.iter().enumerate() {
            let path = self.path(i);
            let written = path
                .parent()
                .map_or(Ok(()), fs::create_dir_all)
                .and_then(|()| fs::write(&path, s));
            if let Err(e) = written {
                return Verdict::Silent(format!("the fuzzer cannot write: {e}"));
            }
        }
        let folders: Vec<String> = (0..SETS).map(|i| format!("seed-{i}")).collect();
        if let Err(e) = seal(self.dir.path(), FIGURE, &folders) {
            return Verdict::Silent(format!("the fuzzer cannot seal sound seed sets: {e}"));
        }
        if let Err(e) = fs::write(self.path(k), &bad) {
            return Verdict::Silent(format!("the fuzzer cannot write: {e}"));
        }
        match all_seeds(self.dir.path(), FIGURE) {
            Err(_) => Verdict::Refused,
            Ok(_) if must_refuse => {
                Verdict::Silent("a copied or foreign seed set was graded".into())
            }
            Ok((n, all)) => {
                if n != SETS {
                    return Verdict::Silent(format!("{n} seed sets of {SETS}"));
                }
                // a verdict only from finite estimates
                let wrong = all.iter().find(|a| {
                    let finite = a.estimate.is_some_and(|e| e.mean.is_finite());
                    !finite && a.verdict != crate::analysis::grading::Verdict::Undecided
                });
                match wrong {
                    Some(a) => Verdict::Silent(format!("graded without a finite mean: {a:?}")),
                    None => Verdict::Accepted,
                }
            }
        }
    }

    fn input(&self) -> String {
        excerpt(&self.last)
    }
}

/// A report.json as `report --experiments` renders it.
#[derive(Default)]
pub(crate) struct ReportJson {
    last: Vec<u8>,
}

impl Case for ReportJson {
    fn one(&mut self, rng: &mut Rng) -> Verdict {
        let s = summary(rng, &[1, 2], "acceptance");
        let rows: Vec<Row> = s["checks"]
            .as_array()
            .into_iter()
            .flatten()
            .map(|c| Row::from_json(FIGURE, &s, c))
            .collect();
        let report = json!({
            "tier": "acceptance",
            "stamp": {"commit": "0123abc", "date": "2026-12-06"},
            "rows": rows,
            "figures": [{"paper": "PH94 Fig. 2", "run": {"binary": FIGURE, "ok": true}}],
        });
        self.last = mutate(rng, report.to_string().as_bytes());
        // as `experiments::write` reads it
        let Ok(value) = std::str::from_utf8(&self.last)
            .map_err(|e| e.to_string())
            .and_then(|t| serde_json::from_str::<Value>(t).map_err(|e| e.to_string()))
        else {
            return Verdict::Refused;
        };
        let text = crate::experiments::render(&value, &Default::default());
        if text.is_empty() {
            return Verdict::Silent("an empty EXPERIMENTS.md".into());
        }
        Verdict::Accepted
    }

    fn input(&self) -> String {
        excerpt(&self.last)
    }
}
