//! `validate`: check another implementation of the pipe automaton against
//! the reference engine (MODEL.md Part A, VALIDATION.md). A driver layer above the
//! models, like the figure drivers.
//!
//! - Level 1 ([`conformance`]): every one-step outcome distribution of a lone
//!   site, against the reference's exact table, by exact binomial tests with
//!   a Bonferroni family-wise false-alarm rate.
//! - Level 2 ([`scenes`]): observables of short versions of the figures'
//!   set-ups, reference and candidate on disjoint seeds, Welch tests with
//!   Holm's family-wise control; the symmetry probes ([`symmetry`]: rows,
//!   mirror, early and late windows) join the same family.
//!
//! Candidates ([`candidate`]): the reference itself, a mutant of the
//! catalogue ([`mutants`]), a defect of decomposition or time
//! ([`defects`]), or an external program.

pub mod candidate;
pub mod conformance;
pub mod defects;
pub mod detect;
pub mod external_hopper;
pub mod hopper;
pub mod memory;
pub mod mutants;
pub mod repeat;
pub mod scenes;
pub mod symmetry;

use crate::error::{Error, ErrorKind, Result};
use crate::hopper::engine::HopperBuilder;
use crate::pipe::engine::Reference;
use crate::pipe::{Params, Rules};
use crate::run::Tier;
use candidate::{Builtin, Candidate, External};
use conformance::Level1;
use scenes::Level2;
use serde::Serialize;

/// Family-wise false-alarm rate of each level (fixed).
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

/// Which automaton to validate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Model {
    /// The pipe lattice gas (MODEL.md Part A).
    Pipe,
    /// The hopper (MODEL.md Part B), when the candidate provides one.
    Hopper,
    /// Both.
    All,
}

impl Model {
    fn pipe(self) -> bool {
        self != Model::Hopper
    }
    fn hopper(self) -> bool {
        self != Model::Pipe
    }
}

/// The candidate named by `spec`: `reference`, `fast` (the bit-sliced
/// engine, `crate::pipe::fast`), `mutant:NAME`, `mutant:KNOB*FACTOR` (a
/// rule probability scaled, [`mutants::Scaled`]) or `cmd:COMMAND`; an
/// external command's runs stop after `time_limit` each (`None`: the
/// default of its plan, [`candidate::default_time_limit`]).
pub fn candidate_from(
    spec: &str,
    time_limit: Option<std::time::Duration>,
) -> Result<Box<dyn Candidate>> {
    if spec == "reference" {
        return Ok(Box::new(Builtin(Reference)));
    }
    if spec == "fast" {
        return Ok(Box::new(Builtin(crate::pipe::fast::Fast)));
    }
    if let Some(name) = spec.strip_prefix("mutant:") {
        if defects::Defect::is_defect(name) {
            let d: defects::Defect = name.parse()?;
            return Ok(Box::new(Builtin(d)));
        }
        if name.contains('*') {
            let m: mutants::Scaled = name.parse()?;
            return Ok(Box::new(Builtin(m)));
        }
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
        return Ok(Box::new(External::new(cmd, time_limit)));
    }
    Err(Error::new(
        ErrorKind::InvalidParameter,
        format!(
            "--candidate {spec} is not known; use reference, fast, mutant:NAME (one of: {}), mutant:KNOB*FACTOR (e.g. mutant:p*1.03), a defect mutant:seam*S, mutant:seam-K*S, mutant:lane-boundary*S or mutant:KNOB*FACTOR@STEP, or cmd:'COMMAND'",
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
    /// Hopper level 2: runs per engine per scene.
    pub hopper_runs: usize,
}

impl Size {
    /// quick: 4000 trials, 8 runs, 8 hopper runs; standard: 20000 trials,
    /// 16 runs, 16 hopper runs (the paper tier is the standard one: the
    /// scenes are short by design).
    pub fn for_tier(tier: Tier) -> Self {
        Size {
            trials: tier.pick(4000, 20000, 20000),
            runs: tier.pick(8, 16, 16),
            hopper_runs: tier.pick(8, 16, 16),
        }
    }

    /// These sizes with the counts given (`--trials`, `--runs`,
    /// `--hopper-runs`) in place of their own.
    pub fn with(self, trials: Option<usize>, runs: Option<usize>, hopper: Option<usize>) -> Self {
        Size {
            trials: trials.unwrap_or(self.trials),
            runs: runs.unwrap_or(self.runs),
            hopper_runs: hopper.unwrap_or(self.hopper_runs),
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
    /// Which automata were asked for.
    pub model: Model,
    /// The hopper part, if asked for.
    pub hopper: Option<HopperReport>,
    /// Wall time of the validation.
    pub wall_seconds: f64,
    /// Every level run passed (a hopper the candidate does not provide is
    /// not run: the verdict then covers the pipe only).
    pub pass: bool,
    /// Why the validation stopped before its verdicts, when the candidate
    /// broke the contract or its series cannot be analysed: a FAIL.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub failure: Option<String>,
}

/// The hopper part of a report (VALIDATION.md "Hopper").
#[derive(Debug, Clone, Serialize)]
pub struct HopperReport {
    /// Whether the candidate provides a hopper engine.
    pub provided: bool,
    /// `PASS`, `FAIL` or `not provided by the candidate`.
    pub status: String,
    /// Level 1 (energies, conflicts, spacings), if run.
    pub level1: Option<hopper::HopperLevel1>,
    /// Level 2 (fill-and-empty scenes; its own Holm family), if run.
    pub level2: Option<Level2>,
    /// The scenes of level 2.
    pub scenes: Vec<hopper::HopperScene>,
}

/// Check that `cand` provides what `model` asks for: asking for the
/// hopper alone of a candidate without one is an
/// [`ErrorKind::InvalidParameter`] error.
pub fn check_model(cand: &dyn Candidate, model: Model) -> Result<()> {
    if model == Model::Hopper && cand.hopper().is_none() {
        return Err(Error::new(
            ErrorKind::InvalidParameter,
            format!(
                "--model hopper: the candidate {} provides no hopper engine; use --model pipe or all",
                cand.name()
            ),
        ));
    }
    Ok(())
}

/// What one validation runs (VALIDATION.md): the pipe rule reading, the
/// levels, the automata, the tier with its sizes, and the base seed.
#[derive(Debug, Clone, Copy)]
pub struct Plan<'a> {
    /// The pipe rule reading compared (names joined by '+').
    pub rules: &'a str,
    /// Level 1, level 2 or both.
    pub levels: Level,
    /// The pipe, the hopper or both.
    pub model: Model,
    /// The tier of the scenes.
    pub tier: Tier,
    /// Trials and runs.
    pub size: Size,
    /// Base seed of the reference's runs (the candidate's are disjoint).
    pub seed: u64,
}

impl<'a> Plan<'a> {
    /// A plan of `levels` of `model` for the reading `rules` at `tier` with
    /// `size`, from base seed `seed`.
    pub fn new(
        rules: &'a str,
        levels: Level,
        model: Model,
        tier: Tier,
        size: Size,
        seed: u64,
    ) -> Self {
        Plan {
            rules,
            levels,
            model,
            tier,
            size,
            seed,
        }
    }
}

impl Plan<'static> {
    /// `levels` of `model` at the quick tier and its sizes, default reading.
    pub fn quick(levels: Level, model: Model, seed: u64) -> Self {
        let size = Size::for_tier(Tier::Quick);
        Plan::new("default", levels, model, Tier::Quick, size, seed)
    }
}

/// Run `plan` for `cand` against the reference; `tick` is called once per
/// finished job (progress). Asking for the hopper alone of a candidate
/// without one is an error.
pub fn validate(cand: &dyn Candidate, plan: &Plan, tick: &(dyn Fn() + Sync)) -> Result<Report> {
    let (rules, model, tier) = (plan.rules, plan.model, plan.tier);
    let (size, seed) = (plan.size, plan.seed);
    let start = std::time::Instant::now();
    let _: Rules = rules.parse()?;
    check_model(cand, model)?;
    let params = Params::default();
    let mut report = Report {
        candidate: cand.name(),
        rules: rules.parse::<Rules>()?.to_string(),
        tier,
        seed,
        params,
        size,
        level1: None,
        level2: None,
        model,
        hopper: None,
        wall_seconds: 0.0,
        pass: false,
        failure: None,
    };
    if let Err(e) = run_levels(cand, plan, &mut report, tick) {
        report.failure = Some(e.message);
    }
    report.pass = report.failure.is_none()
        && report.level1.as_ref().is_none_or(|l| l.pass)
        && report.level2.as_ref().is_none_or(|l| l.pass)
        && report.hopper.as_ref().is_none_or(|h| {
            !h.provided
                || (h.level1.as_ref().is_none_or(|l| l.pass)
                    && h.level2.as_ref().is_none_or(|l| l.pass))
        });
    report.wall_seconds = start.elapsed().as_secs_f64();
    Ok(report)
}

/// The levels of `plan` into `report`, in order; the first error (the
/// candidate broke the contract, or a series of its cannot be analysed)
/// stops the validation, keeping the levels already done.
fn run_levels(
    cand: &dyn Candidate,
    plan: &Plan,
    report: &mut Report,
    tick: &(dyn Fn() + Sync),
) -> Result<()> {
    let (rules, levels, model, tier) = (plan.rules, plan.levels, plan.model, plan.tier);
    let (size, seed, params) = (plan.size, plan.seed, report.params);
    let one = levels != Level::Two;
    let two = levels != Level::One;
    if model.pipe() && one {
        report.level1 = Some(conformance::level1(
            cand,
            &params,
            rules,
            size.trials,
            seed,
            ALPHA,
            tick,
        )?);
    }
    if model.pipe() && two {
        let sampling = scenes::Sampling::new(size.runs, seed, ALPHA)?;
        let reference = Builtin(Reference);
        let engines = (&reference as &dyn Candidate, cand);
        let probes = symmetry::compare(engines, tier, rules, sampling, tick)?;
        let updates = symmetry::site_updates(tier, size.runs);
        report.level2 = Some(scenes::level2(
            engines,
            &scenes::scenes(tier),
            rules,
            sampling,
            (probes, updates),
            tick,
        )?);
    }
    if model.hopper() {
        report.hopper = Some(hopper_part(cand, plan, tick)?);
    }
    Ok(())
}

/// The hopper's part of [`validate`].
fn hopper_part(
    cand: &dyn Candidate,
    plan: &Plan,
    tick: &(dyn Fn() + Sync),
) -> Result<HopperReport> {
    let (levels, tier, size, seed) = (plan.levels, plan.tier, plan.size, plan.seed);
    let scenes = hopper::hopper_scenes(tier);
    let Some(h) = cand.hopper() else {
        return Ok(HopperReport {
            provided: false,
            status: "not provided by the candidate".into(),
            level1: None,
            level2: None,
            scenes,
        });
    };
    let level1 = if levels != Level::Two {
        let l = hopper::level1(h, seed)?;
        tick();
        Some(l)
    } else {
        None
    };
    let level2 = if levels != Level::One {
        let sampling = scenes::Sampling::new(size.hopper_runs, seed, ALPHA)?;
        let engines = (&crate::hopper::engine::Reference as &dyn HopperBuilder, h);
        Some(hopper::level2(engines, &scenes, sampling, tick)?)
    } else {
        None
    };
    let pass = level1.as_ref().is_none_or(|l| l.pass) && level2.as_ref().is_none_or(|l| l.pass);
    Ok(HopperReport {
        provided: true,
        status: if pass { "PASS" } else { "FAIL" }.into(),
        level1,
        level2,
        scenes,
    })
}

/// Jobs [`validate`] reports through `tick`, for the pipe reading `rules`
/// (level 1 leaves out the states a reading's site cannot hold).
pub fn jobs(levels: Level, model: Model, tier: Tier, size: Size, rules: Rules) -> u64 {
    let (one, two) = (levels != Level::Two, levels != Level::One);
    let mut n = 0;
    if model.pipe() {
        if one {
            n += conformance::cases(rules).len() as u64 + 2; // + the memory probes
        }
        if two {
            n += 2 * size.runs as u64 * scenes::scenes(tier).len() as u64;
            n += symmetry::jobs(tier, size.runs);
        }
    }
    if model.hopper() {
        if one {
            n += 1;
        }
        if two {
            n += 2 * size.hopper_runs as u64 * hopper::hopper_scenes(tier).len() as u64;
        }
    }
    n
}

/// The report as Markdown.
pub fn markdown(r: &Report) -> String {
    let verdict = |p: bool| if p { "PASS" } else { "FAIL" };
    let mut s = format!(
        "# Validation of `{}` against the reference\n\n\
         Model {}, rules `{}`, tier {}, seed {}, p = {}, g = {}, b = {} (pipe level 1); {:.1} s.\n\n\
         **Verdict: {}**\n\n",
        r.candidate,
        match r.model {
            Model::Pipe => "pipe",
            Model::Hopper => "hopper",
            Model::All => "pipe and hopper",
        },
        r.rules,
        r.tier.name(),
        r.seed,
        r.params.p,
        r.params.g,
        r.params.b,
        r.wall_seconds,
        verdict(r.pass)
    );
    if let Some(f) = &r.failure {
        s.push_str(&format!(
            "The validation stopped: {f}. The candidate fails; the levels below are those done before.\n\n"
        ));
    }
    if let Some(l) = &r.level1 {
        s.push_str(&format!(
            "## Level 1: rule conformance — {}\n\n{} probes x 128 states{}, {} trials each; {} exact binomial tests, Bonferroni family-wise false-alarm rate {} (an outcome the reference cannot produce fails outright).\n\n",
            verdict(l.pass),
            conformance::probes().len(),
            match r.rules.parse::<Rules>().map(conformance::cases) {
                Ok(c) if c.len() < conformance::probes().len() * 128 => format!(
                    " ({} of them: the rest are states a wall site of the reading cannot hold, or pipes too narrow for it)",
                    c.len()
                ),
                _ => String::new(),
            },
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
        level2_markdown(&mut s, "## Level 2: scenes", "Holm family-wise", l);
    }
    if let Some(h) = &r.hopper {
        hopper_markdown(&mut s, h);
    }
    s
}

/// Write `report` as `report.md` and `report.json` into `out`, print its
/// lines ([`summary_lines`]) and, when the validation stopped early, why
/// on stderr.
pub fn write_report(report: &Report, out: &crate::run::Output) -> Result<()> {
    let md = markdown(report);
    crate::run::write_atomic(&out.path("report.md"), md.as_bytes())?;
    let json = serde_json::to_string_pretty(report).map_err(|e| {
        crate::Error::new(
            crate::ErrorKind::Io,
            format!("cannot serialise the report: {e}"),
        )
    })?;
    crate::run::write_atomic(&out.path("report.json"), json.as_bytes())?;
    for line in summary_lines(report, out.dir()) {
        println!("{line}");
    }
    if let Some(f) = &report.failure {
        eprintln!("validate: {} FAILS: {f}", report.candidate);
    }
    Ok(())
}

/// The lines `validate` prints: one per level run (verdict and counts),
/// the hopper's status and levels, then the verdict and where the report
/// is (`dir`).
pub fn summary_lines(r: &Report, dir: &std::path::Path) -> Vec<String> {
    let verdict = |p: bool| if p { "PASS" } else { "FAIL" };
    let level2 = |name: &str, l: &Level2| {
        let differing = l.comparisons.iter().filter(|c| c.differs).count();
        format!(
            "{name}: {} ({differing} of {} observables differ, {} runs per engine)",
            verdict(l.pass),
            l.comparisons.len(),
            l.runs
        )
    };
    let mut lines = Vec::new();
    if let Some(l) = &r.level1 {
        lines.push(format!(
            "level 1: {} ({} differences in {} tests, {} trials per state)",
            verdict(l.pass),
            l.differences.len(),
            l.tests,
            l.trials
        ));
    }
    if let Some(l) = &r.level2 {
        lines.push(level2("level 2", l));
    }
    if let Some(h) = &r.hopper {
        lines.push(format!("hopper: {}", h.status));
        if let Some(l) = &h.level1 {
            lines.push(format!(
                "hopper level 1: {} ({} differences; {} energies, {} conflicts, {} spacings)",
                verdict(l.pass),
                l.failed,
                l.energies,
                l.conflicts,
                l.spacings
            ));
        }
        if let Some(l) = &h.level2 {
            lines.push(level2("hopper level 2", l));
        }
    }
    if let Some(f) = &r.failure {
        lines.push(format!("stopped: {f}"));
    }
    lines.push(format!(
        "{}: {} ({:.1} s); report in {}",
        r.candidate,
        verdict(r.pass),
        r.wall_seconds,
        dir.display()
    ));
    lines
}

fn hopper_markdown(s: &mut String, h: &HopperReport) {
    let verdict = |p: bool| if p { "PASS" } else { "FAIL" };
    s.push_str(&format!("\n## Hopper (MODEL.md Part B) — {}\n\n", h.status));
    if !h.provided {
        s.push_str("The candidate provides no hopper engine: the hopper is not validated, and the verdict above covers the pipe only.\n");
        return;
    }
    if let Some(l) = &h.level1 {
        s.push_str(&format!(
            "### Hopper level 1: energies, conflicts, spacings — {}\n\n{} energies E_i against the formula of MODEL.md B4, {} conflict set-ups (MODEL.md B3), {} spacings D_i (MODEL.md B4); relative tolerance {:e}; {} differences.\n\n",
            verdict(l.pass),
            l.energies,
            l.conflicts,
            l.spacings,
            l.tolerance,
            l.failed
        ));
        if !l.differences.is_empty() {
            s.push_str("| check | case | rule | candidate |\n|---|---|---|---|\n");
            for d in l.differences.iter().take(40) {
                s.push_str(&format!(
                    "| {} | {} | {:.6} | {:.6} |\n",
                    d.check, d.case, d.expected, d.observed
                ));
            }
            s.push('\n');
        }
    }
    if let Some(l) = &h.level2 {
        level2_markdown(
            s,
            "### Hopper level 2: fill-and-empty scenes",
            "one Holm family over the hopper observables, family-wise",
            l,
        );
    }
}

/// A level-2 section: `title`, its verdict, how it tested (`family`: the
/// multiple-testing correction) and the comparisons, one row per observable.
fn level2_markdown(s: &mut String, title: &str, family: &str, l: &Level2) {
    s.push_str(&format!(
        "{title} — {}\n\n{} runs per engine per scene, disjoint seeds; Welch two-sided tests, {family} false-alarm rate {}.\n\n",
        if l.pass { "PASS" } else { "FAIL" },
        l.runs,
        l.alpha
    ));
    s.push_str(
        "| scene | observable | reference | candidate | difference | p-value | differs |\n|---|---|---|---|---|---|---|\n",
    );
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
