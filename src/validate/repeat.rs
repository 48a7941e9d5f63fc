//! `validate --repeat N` (the calibration of VALIDATION.md): N validations
//! of one candidate on fresh seed sets, one CSV row each, saved as it goes
//! so a rerun skips the seeds already done. For `reference` the failures
//! count false alarms; for a mutant, they measure power.

use super::candidate::Candidate;
use super::{validate, Plan};
use crate::error::Result;
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
        let done: std::collections::BTreeSet<u64> = text
            .lines()
            .skip(2)
            .filter_map(|l| l.split(',').next()?.parse().ok())
            .collect();
        let seeds = self.plan.seed..self.plan.seed + n as u64;
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
        let count = |col: usize| rows.iter().filter(|r| r[col] == "false").count();
        Ok(format!(
            "{}: failed {} of {} validations (level 1: {}, level 2: {}, hopper level 1: {}, hopper level 2: {}); rows in {}",
            self.name,
            count(1),
            rows.len(),
            count(2),
            count(4),
            count(6),
            count(8),
            path.display()
        ))
    }
}
