//! `validate`: check another implementation of the pipe automaton against
//! the reference engine (issue 12, VALIDATION.md). A driver layer above the
//! models, like the figure drivers.
//!
//! - Level 1 ([`conformance`]): every one-step outcome distribution of a lone
//!   site, against the reference's exact table, by exact binomial tests with
//!   a Bonferroni family-wise false-alarm rate.
//! - Level 2 ([`scenes`]): observables of short versions of the figures'
//!   set-ups, reference and candidate on disjoint seeds, Welch tests with
//!   Holm's family-wise control.
//!
//! Candidates ([`candidate`]): the reference itself, a mutant of the
//! catalogue ([`mutants`]), or an external program.

pub mod candidate;
pub mod conformance;
pub mod mutants;
pub mod scenes;

use crate::error::{Error, ErrorKind, Result};
use crate::pipe::engine::Reference;
use crate::pipe::{Params, Rules};
use crate::run::Tier;
use candidate::{Builtin, Candidate, External};
use conformance::Level1;
use scenes::Level2;
use serde::Serialize;

/// Family-wise false-alarm rate of each level (fixed, issue 12).
pub const ALPHA: f64 = 0.01;

/// Which levels to run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Level {
    /// Rule conformance only.
    #[value(name = "1")]
    One,
    /// Scenes only.
    #[value(name = "2")]
    Two,
    /// Both.
    All,
}

/// The candidate named by `spec`: `reference`, `mutant:NAME` or `cmd:COMMAND`.
pub fn candidate_from(spec: &str) -> Result<Box<dyn Candidate>> {
    if spec == "reference" {
        return Ok(Box::new(Builtin(Reference)));
    }
    if let Some(name) = spec.strip_prefix("mutant:") {
        let m: mutants::Mutant = name.parse()?;
        return Ok(Box::new(Builtin(m)));
    }
    if let Some(cmd) = spec.strip_prefix("cmd:") {
        if cmd.trim().is_empty() {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "--candidate cmd: needs a command, e.g. cmd:'./my-engine'",
            ));
        }
        return Ok(Box::new(External {
            command: cmd.to_string(),
        }));
    }
    Err(Error::new(
        ErrorKind::InvalidParameter,
        format!(
            "--candidate {spec} is not known; use reference, mutant:NAME (one of: {}) or cmd:'COMMAND'",
            mutants::MUTANTS
                .iter()
                .map(|(n, _)| *n)
                .collect::<Vec<_>>()
                .join(", ")
        ),
    ))
}

/// How much each level computes.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Size {
    /// Level 1: trials per (probe, state).
    pub trials: usize,
    /// Level 2: runs per engine per scene.
    pub runs: usize,
}

impl Size {
    /// quick: 4000 trials, 8 runs; standard: 20000 trials, 16 runs (the
    /// paper tier is the standard one: the scenes are short by design).
    pub fn for_tier(tier: Tier) -> Self {
        Size {
            trials: tier.pick(4000, 20000, 20000),
            runs: tier.pick(8, 16, 16),
        }
    }
}

/// The whole validation report (report.json; report.md is its rendering).
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    /// The candidate.
    pub candidate: String,
    /// The rule reading compared.
    pub rules: String,
    /// The tier.
    pub tier: Tier,
    /// Base seed (the reference's runs; the candidate's use disjoint seeds).
    pub seed: u64,
    /// p, g, b of level 1 (the PH94 Fig. 2 values).
    pub params: Params,
    /// Sizes.
    pub size: Size,
    /// Level 1, if run.
    pub level1: Option<Level1>,
    /// Level 2, if run.
    pub level2: Option<Level2>,
    /// Wall time of the validation.
    pub wall_seconds: f64,
    /// Every level run passed.
    pub pass: bool,
}

/// Run `levels` for `cand` against the reference with the rule reading
/// `rules`; `tick` is called once per finished job (progress).
pub fn validate(
    cand: &dyn Candidate,
    rules: &str,
    levels: Level,
    tier: Tier,
    size: Size,
    seed: u64,
    tick: &(dyn Fn() + Sync),
) -> Result<Report> {
    let start = std::time::Instant::now();
    let _: Rules = rules.parse()?;
    let params = Params::default();
    let level1 = match levels {
        Level::One | Level::All => Some(conformance::level1(
            cand,
            &params,
            rules,
            size.trials,
            seed,
            ALPHA,
            tick,
        )?),
        Level::Two => None,
    };
    let level2 = match levels {
        Level::Two | Level::All => Some(scenes::level2(
            &Builtin(Reference),
            cand,
            &scenes::scenes(tier),
            rules,
            size.runs,
            seed,
            ALPHA,
            tick,
        )?),
        Level::One => None,
    };
    let pass = level1.as_ref().is_none_or(|l| l.pass) && level2.as_ref().is_none_or(|l| l.pass);
    Ok(Report {
        candidate: cand.name(),
        rules: rules.parse::<Rules>()?.to_string(),
        tier,
        seed,
        params,
        size,
        level1,
        level2,
        wall_seconds: start.elapsed().as_secs_f64(),
        pass,
    })
}

/// Jobs [`validate`] reports through `tick`.
pub fn jobs(levels: Level, tier: Tier, size: Size) -> u64 {
    let l1 = conformance::probes().len() as u64 * 128;
    let l2 = 2 * size.runs as u64 * scenes::scenes(tier).len() as u64;
    match levels {
        Level::One => l1,
        Level::Two => l2,
        Level::All => l1 + l2,
    }
}

/// The report as Markdown.
pub fn markdown(r: &Report) -> String {
    let verdict = |p: bool| if p { "PASS" } else { "FAIL" };
    let mut s = format!(
        "# Validation of `{}` against the reference\n\n\
         Rules `{}`, tier {}, seed {}, p = {}, g = {}, b = {} (level 1); {:.1} s.\n\n\
         **Verdict: {}**\n\n",
        r.candidate,
        r.rules,
        r.tier.name(),
        r.seed,
        r.params.p,
        r.params.g,
        r.params.b,
        r.wall_seconds,
        verdict(r.pass)
    );
    if let Some(l) = &r.level1 {
        s.push_str(&format!(
            "## Level 1: rule conformance — {}\n\n{} probes x 128 states, {} trials each; {} exact binomial tests, Bonferroni family-wise false-alarm rate {} (an outcome the reference cannot produce fails outright).\n\n",
            verdict(l.pass),
            conformance::probes().len(),
            l.trials,
            l.tests,
            l.alpha
        ));
        if !l.differences.is_empty() {
            s.push_str(&format!(
                "{} differences (first 40):\n\n| probe | state | outcome | reference q | observed | p-value |\n|---|---|---|---|---|---|\n",
                l.differences.len()
            ));
            for d in l.differences.iter().take(40) {
                s.push_str(&format!(
                    "| {} | {} | `{}` | {:.4} | {:.4} | {:.2e} |\n",
                    d.probe,
                    crate::pipe::collision::names(d.state),
                    d.outcome,
                    d.expected,
                    d.observed,
                    d.p_value
                ));
            }
            s.push('\n');
        }
    }
    if let Some(l) = &r.level2 {
        s.push_str(&format!(
            "## Level 2: scenes — {}\n\n{} runs per engine per scene, disjoint seeds; Welch two-sided tests, Holm family-wise false-alarm rate {}.\n\n\
             | scene | observable | reference | candidate | difference | p-value | differs |\n|---|---|---|---|---|---|---|\n",
            verdict(l.pass),
            l.runs,
            l.alpha
        ));
        for c in &l.comparisons {
            s.push_str(&format!(
                "| {} | {} | {:.5} ± {:.5} | {:.5} ± {:.5} | {:+.5} | {:.2e} | {} |\n",
                c.scene,
                c.observable,
                c.reference.0,
                c.reference.1,
                c.candidate.0,
                c.candidate.1,
                c.difference,
                c.p_value,
                if c.differs { "**yes**" } else { "no" }
            ));
        }
    }
    s
}
