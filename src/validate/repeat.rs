//! `validate --repeat N` (the calibration of VALIDATION.md): N validations
//! of one candidate on fresh seed sets, one CSV row each, saved as it goes
//! so a rerun skips the seeds already done. For `reference` the failures
//! count false alarms; for a mutant, they measure power.

use super::candidate::Candidate;
use super::{validate, Level, Plan};
use crate::error::{Error, ErrorKind, Result};
use crate::run::{progress, write_atomic, Output};

/// What is repeated: the candidate (as named on the command line) and
/// the plan of each validation; validation k uses base seed `plan.seed + k`.
pub struct Repeat<'a> {
    /// The candidate as `--candidate` names it.
    pub name: &'a str,
    /// The plan of the first validation.
    pub plan: Plan<'a>,
}

/// Columns of `repeat-CANDIDATE.csv` (after its configuration line).
const HEADER: &str = "seed,pass,level1_pass,level1_differences,level2_pass,level2_differing,hopper_level1_pass,hopper_level1_differences,hopper_level2_pass,hopper_level2_differing,wall_seconds";

/// The base seeds of `n` validations from `seed`: `seed..=seed + n - 1`,
/// refused when that passes u64::MAX (it used to wrap into no validation
/// at all) or when `n` is 0.
pub fn seeds(seed: u64, n: usize) -> Result<std::ops::RangeInclusive<u64>> {
    let last = (n as u64)
        .checked_sub(1)
        .and_then(|k| seed.checked_add(k))
        .ok_or_else(|| {
            Error::new(
                ErrorKind::InvalidParameter,
                format!(
                    "--seed {seed} with --repeat {n}: the seeds seed..seed+N-1 must lie in 0..=18446744073709551615 and N >= 1; choose --seed <= {}",
                    u64::MAX - (n as u64).saturating_sub(1)
                ),
            )
        })?;
    Ok(seed..=last)
}

/// Whether a validation runs a level: its CSV columns are filled, empty,
/// or either (the hopper's, which a candidate may not provide).
#[derive(Clone, Copy, PartialEq)]
enum Ran {
    Yes,
    No,
    Maybe,
}

/// One row of `repeat-CANDIDATE.csv`, checked: 11 fields, a seed of the
/// run's range, verdicts `true`/`false` (empty where the level was not
/// run), counts as whole numbers (empty likewise), a finite wall time.
fn check_row(
    line: &str,
    levels: &[Ran; 4],
    seeds: &std::ops::RangeInclusive<u64>,
) -> std::result::Result<u64, String> {
    let f: Vec<&str> = line.split(',').collect();
    if f.len() != 11 {
        return Err(format!("{} fields instead of 11", f.len()));
    }
    let seed: u64 = f[0]
        .parse()
        .map_err(|_| format!("seed {:?} is not a whole number", f[0]))?;
    if !seeds.contains(&seed) {
        return Err(format!(
            "seed {seed} is not one of this run's {}..={}",
            seeds.start(),
            seeds.end()
        ));
    }
    if !matches!(f[1], "true" | "false") {
        return Err(format!("pass {:?} is neither true nor false", f[1]));
    }
    // a validation that stopped early (a FAIL) leaves the levels after it empty
    let stopped = f[1] == "false";
    for (i, ran) in levels.iter().enumerate() {
        let (verdict, count) = (f[2 + 2 * i], f[3 + 2 * i]);
        let col = HEADER.split(',').nth(2 + 2 * i).unwrap_or("");
        let present = matches!(verdict, "true" | "false") && count.parse::<u64>().is_ok();
        let empty = verdict.is_empty() && count.is_empty();
        match ran {
            Ran::Yes | Ran::Maybe if !present && !(empty && (*ran == Ran::Maybe || stopped)) => {
                return Err(format!("{col} {verdict:?} with count {count:?}: a level that ran needs true/false and a whole count"));
            }
            Ran::No if !empty => {
                return Err(format!(
                    "{col} {verdict:?} for a level this run does not validate"
                ));
            }
            _ => {}
        }
    }
    match f[10].parse::<f64>() {
        Ok(w) if w.is_finite() && w >= 0.0 => Ok(seed),
        _ => Err(format!("wall_seconds {:?} is not a finite time", f[10])),
    }
}

impl Repeat<'_> {
    /// The configuration line that heads the CSV: a file made with another
    /// configuration is started afresh.
    fn config(&self) -> String {
        format!(
            "# candidate={} level={:?} model={:?} tier={:?} rules={} trials={} runs={} hopper_runs={}",
            self.name,
            self.plan.levels,
            self.plan.model,
            self.plan.tier,
            self.plan.rules,
            self.plan.size.trials,
            self.plan.size.runs,
            self.plan.size.hopper_runs
        )
    }

    /// One CSV row: the verdicts and counts of validation `r` at `seed`.
    fn row(seed: u64, r: &super::Report) -> String {
        let l1 = r.level1.as_ref();
        let l2 = r.level2.as_ref();
        let h1 = r.hopper.as_ref().and_then(|h| h.level1.as_ref());
        let h2 = r.hopper.as_ref().and_then(|h| h.level2.as_ref());
        let opt = |b: Option<bool>| b.map_or(String::new(), |b| b.to_string());
        let differing = |l: &super::scenes::Level2| {
            l.comparisons
                .iter()
                .filter(|c| c.differs)
                .count()
                .to_string()
        };
        format!(
            "{seed},{},{},{},{},{},{},{},{},{},{:.2}\n",
            r.pass,
            opt(l1.map(|l| l.pass)),
            l1.map_or(String::new(), |l| l.differences.len().to_string()),
            opt(l2.map(|l| l.pass)),
            l2.map_or(String::new(), differing),
            opt(h1.map(|l| l.pass)),
            h1.map_or(String::new(), |l| l.failed.to_string()),
            opt(h2.map(|l| l.pass)),
            h2.map_or(String::new(), differing),
            r.wall_seconds
        )
    }

    /// Which of pipe level 1, pipe level 2, hopper level 1, hopper level 2
    /// each validation runs (the CSV's columns of the others stay empty).
    /// The hopper's columns may stay empty: a candidate without a hopper
    /// validates the pipe alone.
    fn levels_run(&self) -> [Ran; 4] {
        let (l1, l2) = (
            self.plan.levels != Level::Two,
            self.plan.levels != Level::One,
        );
        let (pipe, hopper) = (self.plan.model.pipe(), self.plan.model.hopper());
        let pipe = |l: bool| if pipe && l { Ran::Yes } else { Ran::No };
        let hopper = |l: bool| if hopper && l { Ran::Maybe } else { Ran::No };
        [pipe(l1), pipe(l2), hopper(l1), hopper(l2)]
    }

    /// Run `n` validations of `cand` into `out` (`repeat-CANDIDATE.csv`),
    /// skipping seeds already in the file; the line that sums them up.
    pub fn run(&self, cand: &dyn Candidate, out: &Output, n: usize) -> Result<String> {
        let safe: String = self
            .name
            .chars()
            .map(|c| match c.is_ascii_alphanumeric() || c == '-' {
                true => c,
                false => '_',
            })
            .collect();
        let path = out.path(&format!("repeat-{safe}.csv"));
        let config = self.config();
        let mut text = match std::fs::read_to_string(&path) {
            Ok(t) if t.lines().next() == Some(config.as_str()) => t,
            _ => format!("{config}\n{HEADER}\n"),
        };
        let seeds = seeds(self.plan.seed, n)?;
        let levels = self.levels_run();
        let mut done = std::collections::BTreeSet::new();
        for (i, line) in text.lines().enumerate().skip(2) {
            let bad = |why: String| {
                Error::new(
                    ErrorKind::Io,
                    format!(
                        "{} line {}: {why}; it holds rows of an earlier --repeat: delete that line (or the file) to redo it",
                        path.display(),
                        i + 1
                    ),
                )
            };
            let seed = check_row(line, &levels, &seeds).or_else(|e| {
                // a row of seeds outside this run's range is kept, unread
                match line.split(',').next().and_then(|s| s.parse::<u64>().ok()) {
                    Some(s) if !seeds.contains(&s) && line.split(',').count() == 11 => Ok(s),
                    _ => Err(bad(e)),
                }
            })?;
            if seeds.contains(&seed) && !done.insert(seed) {
                return Err(bad(format!("seed {seed} appears twice")));
            }
        }
        if !text.ends_with('\n') {
            return Err(Error::new(
                ErrorKind::Io,
                format!(
                    "{}: its last line is cut short; delete it to redo that seed",
                    path.display()
                ),
            ));
        }
        let pb = progress(n as u64, "repeat");
        for seed in seeds.clone() {
            if !done.contains(&seed) {
                let r = validate(cand, &Plan { seed, ..self.plan }, &|| {})?;
                text.push_str(&Self::row(seed, &r));
                write_atomic(&path, text.as_bytes())?;
            }
            pb.inc(1);
        }
        pb.finish_and_clear();
        let rows: Vec<Vec<&str>> = text
            .lines()
            .skip(2)
            .map(|l| l.split(',').collect())
            .filter(|r: &Vec<&str>| r[0].parse::<u64>().is_ok_and(|s| seeds.contains(&s)))
            .collect();
        if rows.len() != n {
            return Err(Error::new(
                ErrorKind::Io,
                format!("{}: {} rows for {n} seeds", path.display(), rows.len()),
            ));
        }
        let count = |col: usize| rows.iter().filter(|r| r[col] == "false").count();
        let names = ["level 1", "level 2", "hopper level 1", "hopper level 2"];
        let parts: Vec<String> = names
            .iter()
            .zip(levels)
            .enumerate()
            .filter(|(_, (_, ran))| *ran != Ran::No)
            .map(|(i, (name, _))| format!("{name}: {}", count(2 + 2 * i)))
            .collect();
        Ok(format!(
            "{}: failed {} of {} validations ({}); rows in {}",
            self.name,
            count(1),
            rows.len(),
            parts.join(", "),
            path.display()
        ))
    }
}
