//! Grading a rule reading against the published claims of PH94 Figs. 1-2
//! and PH95 Figs. 3-8, 11-12 (MODEL.md A10; the reproduction matrix of
//! MODEL.md A11). Every claim is measured with its error over runs
//! and graded reproduced / not reproduced / undecided by the one rule of
//! [`crate::analysis::grading`]. Each claim's published value, statistic and
//! margin or threshold is in [`CLAIMS`]; they were fixed before measuring.
//! Where a figure binary grades the same claim, both call the same function
//! (`drivers::relaxation::fig3_checks`, `pipe::overlap::steep_front_check`,
//! `width_grows_check`, `wave_speed_check`, `sweep::same_as_check`,
//! `alpha_check`, `open_pipe::*_check`, `dependence::fig9_claims`,
//! `fig10_claims`). PH95 III F-H (Figs. 9-10), revealed after a blind
//! measurement, joined later (2026-12-04).

use super::dependence::{fig10_claims, fig9_claims, Claimed, FIG10_B, FIG10_G, FIG9_RHO, G_LOW};
use super::margins::{ALPHA_MARGIN, V_MARGIN, V_SAME_MARGIN};
use super::open_pipe::{
    clogs_check, corr_run, corr_speed, fig11_pipe, fig11_speed_check, fig12_pipe, flows_check,
    ic_check, ic_independence_check, trend_test, CLOG_INJECT, FIG11_CORR, FIG11_INJECT,
    FIG11_STEPS,
};
use super::spectra::{tier_setup, SpectrumEnsemble};
use super::sweep::{
    alpha_check, reduce, same_as_check, sweep_run, Estimator, PointResult, Quantity, SweepPoint,
};
use crate::analysis::relaxation::Saturation;
use crate::analysis::spectrum::{SpectrumParams, Window};
use crate::drivers::relaxation::fig3_checks;
use crate::error::{ErrorKind, Result};
use crate::pipe::open::bisect_ic;
use crate::pipe::overlap::{
    profile_run, steep_front_check, wave_speed_check, width_grows_check, ProfileRun, SpeedRun,
    FIELDS_EVERY, FIG4_BIN, FIG5_BIN, FIG5_MAX_LAG,
};
use crate::pipe::record::{
    fig1_panels, fig1_pipe, relaxation, relaxation_schedule, run_bands, sample_times, Steady,
    RELAXATION_EARLY,
};
use crate::pipe::Engine;
use crate::pipe::{Boundary, Params, Rules};
use crate::run::{ensemble, run_seeds, Check, Tier};
use serde::{Deserialize, Serialize};

pub use crate::analysis::grading::Verdict;
use crate::analysis::grading::{all_of, grade as grade_claim, Claim, Estimate};

/// One graded claim.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Graded {
    /// Claim id (see [`CLAIMS`]).
    pub claim: String,
    /// The measured statistic.
    #[serde(deserialize_with = "crate::analysis::grading::f64_or_nan")]
    pub measured: f64,
    /// Its standard error over runs (NaN, written null, for one run).
    #[serde(deserialize_with = "crate::analysis::grading::f64_or_nan")]
    pub error: f64,
    /// The grade.
    pub verdict: Verdict,
    /// What was measured, in words and numbers.
    pub detail: String,
    /// Runs behind the value: the run count of the claim's group
    /// (`Group::runs`); 0 in rows saved before it was recorded.
    #[serde(default)]
    pub runs: usize,
}

/// The claims, with what each id means: the published value, the
/// statistic and its margin or threshold (fixed before measuring; the first
/// 11 are those of MODEL.md A10, fixed 2026-11-25; the next 17 were added
/// on 2026-12-02, the next 10, PH95 III F-H, on 2026-12-04, and the last,
/// PH94 Fig. 2's alpha at the published set-up with the acceptance tier's
/// estimator and margin, each written down here and in EXPERIMENTS.md
/// before any reading was graded against them).
pub const CLAIMS: [(&str, &str); 39] = [
    (
        "waves_1a",
        "PH94 Fig. 1a: density waves form at p = 0.1 (s_low of the late half)",
    ),
    ("none_p0", "PH94 Fig. 1b: no waves at p = 0"),
    (
        "return_1c",
        "PH94 Fig. 1c: waves return when p = 0.1 is switched on",
    ),
    ("none_b0", "PH94 Fig. 1d: no waves at b = 0"),
    (
        "rho_window",
        "PH94: waves only for roughly 0.6 <= rho <= 1.6 (rho = 0.3, 0.7, 1.0, 1.5, 2.2)",
    ),
    (
        "alpha_fig2",
        "PH94 Fig. 2: alpha = 1.33 +- 0.02 at p = g = b = 0.5",
    ),
    ("v_fig2", "PH94 Fig. 2: sharp peak at v = 0.40"),
    ("alpha_p08", "PH95 Fig. 6: alpha about 1.33 at p = 0.8"),
    (
        "white_p0",
        "PH95 Fig. 7: white noise (alpha about 0) at p = 0",
    ),
    (
        "white_b0",
        "PH95 Fig. 7: white noise (alpha about 0) at b = 0",
    ),
    (
        "peak_b0",
        "PH95 Fig. 7: a large peak at v = 1/2 exactly at b = 0",
    ),
    (
        "alpha_const_p",
        "PH95 Fig. 8a: alpha the same for every p > 0 (alpha(p) - alpha(0.5) within 0.1 at p = 0.05, 0.2 and 0.8, each)",
    ),
    (
        "v_const_p",
        "PH95 Fig. 8b: v independent of p (v(p) - v(0.5), per-run peak speeds, within 0.05, the published error bar of v, at p = 0.05, 0.2 and 0.8, each)",
    ),
    (
        "contrast_rises",
        "PH95 Fig. 3a: C rises from its start (L = 256, W = 11, p = 0.1, bins of 8; C_sat - C(0) per run > 0)",
    ),
    (
        "contrast_saturates",
        "PH95 Fig. 3a: C saturates (late drift / |C_sat - C(0)| within 0.1 of 0)",
    ),
    (
        "energy_rises",
        "PH95 Fig. 3b: the energy loss E(0) - E(t) rises (its saturation value > 0)",
    ),
    (
        "energy_saturates",
        "PH95 Fig. 3b: E(0) - E(t) saturates (late drift / saturation value within 0.1 of 0)",
    ),
    (
        "steep_front",
        "PH95 Fig. 4: the front is steeper than the back (asymmetry of the aligned profile > 0 at L = 128, 256, 512, 1024, each; p = 0.1)",
    ),
    (
        "width_grows",
        "PH95 Fig. 4: the wave's width grows with L (width at L = 1024 minus width at L = 128 > 0)",
    ),
    (
        "v_fig5",
        "PH95 Fig. 5: v = 0.36 +- 0.05 at L = 512, p = 0.1 (|real-space speed| within 0.05 of 0.36)",
    ),
    (
        "flows_fig11",
        "PH95 Fig. 11: the open pipe L = 1000, W = 5, I = 0.5, p = b = 0.5, g = 0.2 flows (fraction of runs clogging within 40000 steps < 1/2)",
    ),
    (
        "v_fig11",
        "PH95 Fig. 11b: T_c = 880, v = 0.34 at that set-up (per-run 300 / T_c within 0.01 of 0.34; all runs clogged: not reproduced)",
    ),
    (
        "i_c",
        "PH95 Fig. 12: I_c = 0.52 (bisection at L = 220, W = 11, p = b = g = 0.5; within 0.02, error the bisection half-width)",
    ),
    (
        "i_c_size",
        "PH95 III I: I_c independent of the pipe size (I_c at 220x5 and 440x11 minus I_c at 220x11 within 0.02, the larger difference)",
    ),
    (
        "i_c_params",
        "PH95 III I: I_c independent of the model parameters (I_c at g = 0.2 minus I_c at g = 0.5, 220x11, within 0.02)",
    ),
    (
        "one_over_f_ic",
        "PH95 Fig. 12a-b: 1/f noise at I_c (alpha of the bottom bin at the largest rate the bisection found stationary within 0.1 of 1)",
    ),
    (
        "white_half_ic",
        "PH95 Fig. 12a-b: white noise away from I_c (alpha of the bottom bin at 0.5 I_c within 0.1 of 0)",
    ),
    (
        "clogs_054",
        "PH95 Fig. 12c: the pipe clogs at I = 0.54 (220x11, p = b = g = 0.5: a run clogs or the trend test finds N(t) growing)",
    ),
    (
        "alpha_zero_low_rho",
        "PH95 III G, Fig. 9a: white noise for rho <= 0.8 (alpha within 0.1 of 0 at rho = 0.6 and 0.8, each; p = b = g = 0.5, L = 220)",
    ),
    (
        "alpha_rises_rho",
        "PH95 III G, Fig. 9a: alpha rises with rho above 1 (alpha(rho) - alpha(1) > 0 at rho = 1.4 and 2.0, each)",
    ),
    (
        "alpha_rho2",
        "PH95 III G, Fig. 9a: alpha about 1.86 at rho = 2 (within 0.1)",
    ),
    (
        "v_const_rho",
        "PH95 III G, Fig. 9b: v constant in rho (v(rho) - v(1) within 0.05 at rho = 1.4 and 2.0, each)",
    ),
    (
        "alpha_const_b",
        "PH95 III H, Fig. 10a: alpha constant for any b > 0 (alpha(b) - alpha(0.5) within 0.1 at b = 0.05, 0.25, 1, each; g = 0.5)",
    ),
    (
        "alpha_indep_g",
        "PH95 III H: alpha does not change with g (alpha(g) - alpha(0.5) within 0.1 at g = 0.2 and 1, each; b = 0.5)",
    ),
    (
        "v_falls_with_b",
        "PH95 III H, Fig. 10b: v decreases as b goes from 0.25 to 1 (v(0.25) - v(1) > 0 at g = 0.5 and g = 0.2, each)",
    ),
    (
        "v_falls_more_small_g",
        "PH95 III H, Fig. 10b: v is more sensitive to b at the smaller g (the drop v(0.25) - v(1) larger at g = 0.2 than at g = 0.5)",
    ),
    (
        "v_changes_with_g",
        "PH95 III H, Fig. 10b: v changes with g, the larger g above (v(g = 0.5) - v(g = 0.2) > 0 at b = 0.25, 0.5, 1, each)",
    ),
    (
        "alpha_indep_pbg",
        "PH95 III F: alpha does not change with p, b or g (alpha_const_p's, alpha_const_b's and alpha_indep_g's checks, all)",
    ),
    (
        "alpha_fig2_published",
        "PH94 Fig. 2 at the published set-up: alpha = 1.33 +- 0.02 (m = 16384, 128 runs, fit of the averaged spectrum with its bootstrap SE, within the acceptance margin 0.059)",
    ),
];

/// s_low above this (lower 2-SE bound) means bands, below it (upper bound)
/// none; fixed a priori as twice the structureless value 1 (as in `fig1`).
pub const WAVE_THRESHOLD: f64 = 2.0;

/// Version of the grading rules; caches of graded readings carry it, so a
/// change of rule never mixes with old verdicts. 1: the first rule ("|d| <= 2
/// sqrt(SE^2 + e^2)"), 2: the equivalence test `equivalent` with 2 SE,
/// 3: the one rule of [`crate::analysis::grading`] (k = max(2, t(0.975, n-1))
/// SE, fewer than 3 runs undecided); 4: the same rule, 28 claims instead of
/// 11; 5: a censored I_c (no rate up to 1 clogs) can no longer reproduce
/// `i_c_size` or `i_c_params` by a difference of two bounds, and leaves
/// `one_over_f_ic` undecided; 6: 38 claims, PH95 III F-H added; 7: 39,
/// PH94 Fig. 2's alpha at the published set-up added.
pub const GRADING_VERSION: u32 = 7;

/// "Density waves": s_low above [`WAVE_THRESHOLD`] by the one grading rule.
fn waves(s_low: Estimate) -> Verdict {
    grade_claim(
        s_low,
        Claim::Above {
            threshold: WAVE_THRESHOLD,
        },
    )
}

/// A numerical claim "the value is `target`" within `margin` by the one
/// grading rule (an equivalence test, [`crate::analysis::grading`]).
fn equivalent(est: Estimate, target: f64, margin: f64) -> Verdict {
    grade_claim(est, Claim::Within { target, margin })
}

/// How much the matrix computes per tier.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct MatrixSize {
    /// Runs (seeds) per set-up of the bands (PH94 Fig. 1, the density
    /// window) and the spectra (PH94 Fig. 2, PH95 Figs. 6-8).
    pub runs: usize,
    /// Runs per set-up of PH95 Figs. 3-5 (short runs of small pipes).
    pub wave_runs: usize,
    /// Runs per tested rate of the open pipe (PH95 Figs. 11-12).
    pub open_runs: usize,
    /// Steps of the band runs (PH94 Fig. 1 set-up, L = 2200).
    pub band_steps: u64,
    /// Tier of the spectra (m = 4096, 8192, 16384), of the PH95 Fig. 3-5
    /// schedules and of the trend runs of Fig. 12 (20000, 50000, 100000 steps).
    pub spectrum_tier: Tier,
    /// Bisection steps for I_c on [0, 1] (half-width 2^-(n+1)).
    pub bisections: usize,
}

impl MatrixSize {
    /// quick: 3 runs (fewer never decide), m = 4096; standard: 4 runs, m = 8192; paper: 8 runs,
    /// m = 16384. Band runs always use the paper's 40000 steps at L = 2200
    /// (bands do not form reliably in shorter or smaller runs). PH95 Figs.
    /// 3-5: 16, 32, 64 runs (the paper's 64 at the paper tier); the open
    /// pipe: 4, 8, 32 runs per rate (as `waves-fig11`, `waves-fig12`), 7
    /// bisections at every tier (half-width 0.0039, below the I_c margin).
    pub fn for_tier(tier: Tier) -> Self {
        MatrixSize {
            runs: tier.pick(3, 4, 8),
            wave_runs: tier.pick(16, 32, 64),
            open_runs: tier.pick(4, 8, 32),
            band_steps: 40_000,
            spectrum_tier: tier,
            bisections: 7,
        }
    }

    /// The same size with `runs` runs for every set-up (`--runs`).
    pub fn with_runs(self, runs: usize) -> Self {
        MatrixSize {
            runs,
            wave_runs: runs,
            open_runs: runs,
            ..self
        }
    }

    /// The part of the cache key that says how many runs: `3-16-4`.
    pub fn runs_key(&self) -> String {
        format!("{}-{}-{}", self.runs, self.wave_runs, self.open_runs)
    }
}

/// Band statistic s_low over runs at `params`; a run that leaves the model's
/// validity (rest particles outnumber sites) counts as NaN and is reported.
fn band_stat(
    params: Params,
    rules: Rules,
    engine: Engine,
    seeds: &[u64],
    steps: u64,
) -> Result<(Estimate, usize)> {
    let res = ensemble(seeds.len(), |i| {
        let mut pipe = engine.build(params, rules, seeds[i])?;
        run_bands(pipe.as_mut(), steps, 80)
    });
    let mut s = Vec::new();
    let mut invalid = 0;
    for r in res {
        match r {
            Ok(b) => s.push(b.s_low),
            Err(e)
                if matches!(
                    e.kind,
                    ErrorKind::RestExceedsSites | ErrorKind::RelocationStuck
                ) =>
            {
                invalid += 1
            }
            Err(e) => return Err(e),
        }
    }
    Ok((Estimate::of(&s), invalid))
}

/// The groups of claims, each sharing its runs; [`grade_groups`] grades
/// the chosen ones, in the order of [`CLAIMS`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Group {
    /// PH94 Fig. 1 and the density window (`waves_1a` .. `rho_window`).
    Bands,
    /// Spectra of PH94 Fig. 2, PH95 Figs. 6-8 (`alpha_fig2` .. `v_const_p`).
    Spectra,
    /// PH95 Fig. 3 (`contrast_rises` .. `energy_saturates`).
    Relaxation,
    /// PH95 Fig. 4 (`steep_front`, `width_grows`).
    Profile,
    /// PH95 Fig. 5 (`v_fig5`).
    Speed,
    /// PH95 Fig. 11 (`flows_fig11`, `v_fig11`).
    Fig11,
    /// PH95 Fig. 12 (`i_c` .. `clogs_054`).
    Fig12,
    /// PH95 III F-H, Figs. 9-10 (`alpha_zero_low_rho` .. `alpha_indep_pbg`).
    Dependence,
    /// PH94 Fig. 2's alpha at the published set-up (`alpha_fig2_published`):
    /// the acceptance tier's runs whatever the matrix's tier and size.
    Headline,
}

impl Group {
    /// Runs per set-up of this group's claims at `size`.
    fn runs(self, size: MatrixSize) -> usize {
        match self {
            Group::Bands | Group::Spectra | Group::Dependence => size.runs,
            Group::Relaxation | Group::Profile | Group::Speed => size.wave_runs,
            Group::Fig11 | Group::Fig12 => size.open_runs,
            Group::Headline => headline_margin().runs,
        }
    }

    /// The name of the group on the command line (`pipe-matrix --groups`).
    pub fn name(self) -> &'static str {
        match self {
            Group::Bands => "bands",
            Group::Spectra => "spectra",
            Group::Relaxation => "relaxation",
            Group::Profile => "profile",
            Group::Speed => "speed",
            Group::Fig11 => "fig11",
            Group::Fig12 => "fig12",
            Group::Dependence => "dependence",
            Group::Headline => "headline",
        }
    }

    /// Parse a comma-separated list of group names, or `all`; an
    /// [`ErrorKind::InvalidParameter`] error names a value that is not a
    /// group, and the groups there are.
    pub fn parse_list(s: &str) -> Result<Vec<Group>> {
        if s.trim() == "all" {
            return Ok(Group::ALL.to_vec());
        }
        let names: Vec<&str> = Group::ALL.iter().map(|g| g.name()).collect();
        let groups = s
            .split(',')
            .map(|n| {
                let n = n.trim();
                Group::ALL
                    .into_iter()
                    .find(|g| g.name() == n)
                    .ok_or_else(|| {
                        crate::error::Error::new(
                            ErrorKind::InvalidParameter,
                            format!(
                                "--groups: '{n}' is not a group of claims; choose from {} (or `all` alone)",
                                names.join(", ")
                            ),
                        )
                    })
            })
            .collect::<Result<Vec<_>>>()?;
        crate::cli::reject_duplicates(
            "--groups",
            &groups.iter().map(|g| g.name()).collect::<Vec<_>>(),
        )?;
        Ok(groups)
    }

    /// Every group, in the order of [`CLAIMS`].
    pub const ALL: [Group; 9] = [
        Group::Bands,
        Group::Spectra,
        Group::Relaxation,
        Group::Profile,
        Group::Speed,
        Group::Fig11,
        Group::Fig12,
        Group::Dependence,
        Group::Headline,
    ];
}

/// A claim graded from one or more checks of the figure binaries' shared
/// functions: all must hold ([`all_of`]); the value shown is that of the
/// deciding check (the first not reproduced, else the first undecided, else
/// the first).
fn from_checks(claim: &str, checks: &[Check]) -> Graded {
    let v = all_of(checks.iter().map(|c| c.verdict));
    let shown = checks
        .iter()
        .find(|c| c.verdict == Verdict::NotReproduced)
        .or_else(|| checks.iter().find(|c| c.verdict == Verdict::Undecided))
        .unwrap_or(&checks[0]);
    Graded {
        claim: claim.to_string(),
        measured: shown.measured,
        error: shown.error,
        verdict: v,
        runs: 0,
        detail: checks
            .iter()
            .map(|c| {
                format!(
                    "{} {}: {} ({} runs; {})",
                    c.name,
                    c.verdict.label(),
                    c.value_text(),
                    c.runs,
                    c.note
                )
            })
            .collect::<Vec<_>>()
            .join("; "),
    }
}

/// Grade `rules` against every claim of [`CLAIMS`]; `tick(steps)` reports
/// progress. Runs use seeds derived from `seed`.
pub fn grade(
    rules: Rules,
    engine: Engine,
    size: MatrixSize,
    seed: u64,
    tick: &(dyn Fn(u64) + Sync),
) -> Result<Vec<Graded>> {
    grade_groups(rules, engine, size, seed, &Group::ALL, |p| p, tick)
}

/// Grade the claims of `groups` (in the order of [`CLAIMS`]), every pipe of
/// every set-up passed through `tweak` first: the identity for the
/// published set-ups, or a named wrong model (e.g. p = 0 everywhere) in the
/// tests that show a claim can fail.
pub fn grade_groups(
    rules: Rules,
    engine: Engine,
    size: MatrixSize,
    seed: u64,
    groups: &[Group],
    tweak: fn(Params) -> Params,
    tick: &(dyn Fn(u64) + Sync),
) -> Result<Vec<Graded>> {
    let mut out = Vec::new();
    for group in Group::ALL.into_iter().filter(|g| groups.contains(g)) {
        let start = out.len();
        let g = Grader {
            model: Model {
                rules,
                engine,
                tweak,
            },
            size,
            seeds: run_seeds(seed, group.runs(size)),
            tick,
        };
        match group {
            Group::Bands => g.bands(&mut out)?,
            Group::Spectra => g.spectra(&mut out)?,
            Group::Relaxation => g.relaxation(&mut out)?,
            Group::Profile => g.profile(&mut out)?,
            Group::Speed => g.speed(&mut out)?,
            Group::Fig11 => g.fig11(&mut out)?,
            Group::Fig12 => g.fig12(&mut out)?,
            Group::Dependence => g.dependence(&mut out)?,
            Group::Headline => g.headline(&mut out)?,
        }
        for graded in &mut out[start..] {
            graded.runs = g.seeds.len();
        }
    }
    Ok(out)
}

/// The model under test: a reading, an engine and the pipe tweak.
struct Model {
    rules: Rules,
    engine: Engine,
    tweak: fn(Params) -> Params,
}

/// One group of claims graded for one model: what every group's runs share.
struct Grader<'a> {
    model: Model,
    size: MatrixSize,
    /// The seeds of the group's runs ([`Group::runs`] of them).
    seeds: Vec<u64>,
    tick: &'a (dyn Fn(u64) + Sync),
}

fn graded(claim: &str, m: f64, e: f64, v: Verdict, d: String) -> Graded {
    Graded {
        claim: claim.to_string(),
        measured: m,
        error: e,
        verdict: v,
        detail: d,
        runs: 0,
    }
}

/// A claim left undecided, with the reason.
fn undecided(claim: &str, why: String) -> Graded {
    graded(claim, f64::NAN, f64::NAN, Verdict::Undecided, why)
}

/// "alpha is `target`" at `r`, within [`ALPHA_MARGIN`].
fn alpha_graded(claim: &str, r: &PointResult, target: f64) -> Graded {
    let (a, e) = (r.alpha, r.alpha_err);
    graded(
        claim,
        a,
        e,
        equivalent(r.alpha_estimate(), target, ALPHA_MARGIN),
        format!("alpha = {a:.3} +- {e:.3}"),
    )
}

/// "the spectrum peaks at v = `target`" at `r`, within `margin` (`what`:
/// the detail after the value); undecided if every run left the model.
fn v_graded(
    claim: &str,
    r: &PointResult,
    target: f64,
    margin: f64,
    what: impl Fn(&SpectrumEnsemble) -> String,
) -> Graded {
    match &r.ensemble {
        Some(ens) => graded(
            claim,
            ens.v_peak,
            ens.v_err,
            equivalent(ens.v_estimate(), target, margin),
            format!("v = {:.4} +- {:.4} ({})", ens.v_peak, ens.v_err, what(ens)),
        ),
        None => undecided(
            claim,
            format!(
                "{}: every run left the model's validity ({} invalid)",
                r.point.label, r.invalid
            ),
        ),
    }
}

impl Grader<'_> {
    /// `params` as the model under test runs them (the tweak applied).
    fn pipe(&self, params: Params) -> Params {
        (self.model.tweak)(params)
    }

    /// One run per seed of `seeds` over threads, in their order; the first
    /// error, if any.
    fn each<T: Send>(
        &self,
        seeds: &[u64],
        run: impl Fn(u64) -> Result<T> + Sync,
    ) -> Result<Vec<T>> {
        ensemble(seeds.len(), |i| run(seeds[i]))
            .into_iter()
            .collect()
    }

    /// PH94 Fig. 1 panels and the density window.
    fn bands(&self, out: &mut Vec<Graded>) -> Result<()> {
        let (rules, engine, seeds) = (self.model.rules, self.model.engine, &self.seeds);
        let base = self.pipe(Params {
            length: 2200,
            width: 11,
            rho: 1.0,
            p: 0.1,
            g: 0.5,
            b: 0.5,
            ..Params::default()
        });
        let steps = self.size.band_steps;
        let panels = self.each(seeds, |s| {
            fig1_panels(base, rules, engine, s, steps, 80, self.tick)
        })?;
        let stat =
            |k: usize| Estimate::of(&panels.iter().map(|r| r[k].1.s_low).collect::<Vec<_>>());
        for (k, claim, want) in [
            (0, "waves_1a", true),
            (1, "none_p0", false),
            (2, "return_1c", true),
            (3, "none_b0", false),
        ] {
            let est = stat(k);
            let v = if want {
                waves(est)
            } else {
                waves(est).negate()
            };
            let (m, e) = (est.mean, est.se);
            out.push(graded(claim, m, e, v, format!("s_low = {m:.2} +- {e:.2}")));
        }

        // the density window
        let inside = [0.7, 1.0, 1.5];
        let outside = [0.3, 2.2];
        let mut verdicts = Vec::new();
        let mut detail = Vec::new();
        for &rho in inside.iter().chain(outside.iter()) {
            let (est, invalid) = band_stat(Params { rho, ..base }, rules, engine, seeds, steps)?;
            let (m, e) = (est.mean, est.se);
            (self.tick)(seeds.len() as u64 * steps);
            let want = inside.contains(&rho);
            let v = if invalid == seeds.len() {
                // the model is undefined there: no waves
                Verdict::NotReproduced
            } else {
                waves(est)
            };
            verdicts.push(if want { v } else { v.negate() });
            detail.push(format!(
                "rho {rho}: {m:.2} +- {e:.2}{}",
                if invalid > 0 {
                    format!(" ({invalid} runs invalid)")
                } else {
                    String::new()
                }
            ));
        }
        let n = verdicts.len();
        let agree = verdicts
            .iter()
            .filter(|v| **v == Verdict::Reproduced)
            .count();
        out.push(graded(
            "rho_window",
            agree as f64,
            0.0,
            all_of(verdicts),
            format!("{agree}/{n} agree; {}", detail.join("; ")),
        ));
        Ok(())
    }

    /// One spectrum point (PH94 Fig. 2 set-up unless changed) over `seeds`,
    /// runs outside the model's validity counted as invalid.
    fn spectrum_point(&self, label: &str, params: Params, seeds: &[u64]) -> Result<PointResult> {
        let params = self.pipe(params);
        let setup = tier_setup(
            self.size.spectrum_tier,
            params,
            self.model.rules,
            self.model.engine,
        );
        let runs = self.each(seeds, |s| sweep_run(&setup, s, self.tick))?;
        let point = SweepPoint {
            label: label.to_string(),
            x: vec![],
            params,
        };
        reduce(&point, &setup, runs, Estimator::PerRun)
    }

    /// The spectrum claims of PH94 Fig. 2 and PH95 Figs. 6-8.
    fn spectra(&self, out: &mut Vec<Graded>) -> Result<()> {
        // PH94 Fig. 2: L = 220, W = 11, rho = 1, p = g = b = 0.5
        let s_base = Params::default();
        let spec = |label: &str, params: Params| self.spectrum_point(label, params, &self.seeds);
        let fig2 = spec("p0.5", s_base)?;
        out.push(alpha_graded("alpha_fig2", &fig2, 1.33));
        out.push(v_graded("v_fig2", &fig2, 0.40, V_MARGIN, |ens| {
            format!(
                "j = {}, contrast {:.1}",
                ens.j_peak, ens.fit_of_mean.contrast
            )
        }));
        let p08 = spec("p0.8", Params { p: 0.8, ..s_base })?;
        out.push(alpha_graded("alpha_p08", &p08, 1.33));
        for (claim, label, params) in [
            ("white_p0", "p0", Params { p: 0.0, ..s_base }),
            ("white_b0", "b0", Params { b: 0.0, ..s_base }),
        ] {
            let r = spec(label, params)?;
            out.push(alpha_graded(claim, &r, 0.0));
            if claim == "white_b0" {
                let m = self.size.spectrum_tier.pick(4096, 8192, 16384);
                let bin_v = s_base.length as f64 / (10.0 * 2.0 * m as f64);
                let two_bins = 2.0 * bin_v;
                out.push(v_graded("peak_b0", &r, 0.5, two_bins, |_| {
                    format!("tolerance two bins = {two_bins:.4}")
                }));
            }
        }
        // PH95 Fig. 8: alpha and v at p = 0.05, 0.2 (and 0.8, above) against p = 0.5
        let mut others = vec![];
        for p in [0.05, 0.2] {
            others.push(spec(&format!("p{p}"), Params { p, ..s_base })?);
        }
        others.push(p08);
        for (claim, q, margin, source) in [
            (
                "alpha_const_p",
                Quantity::Alpha,
                ALPHA_MARGIN,
                "PH95 Fig. 8a (alpha about constant for every p > 0)",
            ),
            (
                "v_const_p",
                Quantity::V,
                V_SAME_MARGIN,
                "PH95 Fig. 8b (v does not change with p within the error bars)",
            ),
        ] {
            let checks: Vec<Check> = others
                .iter()
                .map(|r| {
                    let name = format!("{}_{}", q.name(), r.point.label);
                    same_as_check(&name, source, q, r, &fig2, margin, "")
                })
                .collect();
            out.push(from_checks(claim, &checks));
        }
        Ok(())
    }

    /// PH95 Fig. 3: contrast and energy loss from the random start.
    fn relaxation(&self, out: &mut Vec<Graded>) -> Result<()> {
        let params = self.pipe(Params {
            length: 256,
            bin: 8,
            ..fig1_pipe()
        });
        let (steps, every) = relaxation_schedule(self.size.spectrum_tier);
        let times = sample_times(steps, every, RELAXATION_EARLY);
        let (rules, engine) = (self.model.rules, self.model.engine);
        let runs = self.each(&self.seeds, |s| {
            relaxation(params, rules, engine, s, &times, self.tick)
        })?;
        let tf: Vec<f64> = times.iter().map(|&t| t as f64).collect();
        let cs: Vec<Vec<f64>> = runs.iter().map(|r| r.contrast.clone()).collect();
        let es: Vec<Vec<f64>> = runs.iter().map(|r| r.energy_loss.clone()).collect();
        let checks = fig3_checks(
            &Saturation::of(&cs, &tf),
            &Saturation::of(&es, &tf),
            runs.len(),
        );
        push_named(
            out,
            &checks,
            &[
                ("contrast_rises", "contrast_rises"),
                ("contrast_saturates", "contrast_saturates"),
                ("energy_rises", "energy_loss_rises"),
                ("energy_saturates", "energy_loss_saturates"),
            ],
        );
        Ok(())
    }

    /// PH95 Fig. 4: the aligned wave profile at four lengths.
    fn profile(&self, out: &mut Vec<Graded>) -> Result<()> {
        let tier = self.size.spectrum_tier;
        let steady = Steady::ph95(tier, tier.pick(512, 2048, 2048), FIELDS_EVERY);
        let (rules, engine) = (self.model.rules, self.model.engine);
        let mut per_l = Vec::new();
        for l in FIG4_LENGTHS {
            let params = self.pipe(Params {
                length: l,
                bin: FIG4_BIN,
                ..fig1_pipe()
            });
            let mean = (FIG4_BIN * params.width) as f64 * params.rho;
            let runs: Vec<ProfileRun> = self.each(&self.seeds, |s| {
                let f = steady.record(params, rules, engine, s, self.tick)?;
                Ok(profile_run(&f, mean, FIG4_BIN, s))
            })?;
            per_l.push((l, runs));
        }
        let steep: Vec<Check> = per_l
            .iter()
            .map(|(l, r)| steep_front_check(*l, r))
            .collect();
        out.push(from_checks("steep_front", &steep));
        let (first, last) = (&per_l[0], &per_l[per_l.len() - 1]);
        let width = width_grows_check((first.0, &first.1), (last.0, &last.1));
        out.push(from_checks("width_grows", &[width]));
        Ok(())
    }

    /// PH95 Fig. 5: the real-space wave speed at L = 512.
    fn speed(&self, out: &mut Vec<Graded>) -> Result<()> {
        let tier = self.size.spectrum_tier;
        let steady = Steady::ph95(tier, tier.pick(1024, 2048, 2048), FIELDS_EVERY);
        let params = self.pipe(Params {
            length: 512,
            bin: FIG5_BIN,
            ..fig1_pipe()
        });
        let spec = SpectrumParams {
            m: steady.fields / 4,
            k: 1,
            window: Window::Parzen1988,
        };
        let (rules, engine) = (self.model.rules, self.model.engine);
        let runs = self.each(&self.seeds, |s| {
            let f = steady.record(params, rules, engine, s, self.tick)?;
            SpeedRun::measure(&f, &params, FIELDS_EVERY, FIG5_MAX_LAG, &spec)
        })?;
        out.push(from_checks("v_fig5", &[wave_speed_check(&runs)]));
        Ok(())
    }

    /// PH95 Fig. 11: the published open-pipe set-up.
    fn fig11(&self, out: &mut Vec<Graded>) -> Result<()> {
        let params = self.pipe(fig11_pipe(FIG11_INJECT));
        let (rules, engine) = (self.model.rules, self.model.engine);
        let runs = self.each(&self.seeds, |s| {
            corr_run(
                params,
                rules,
                engine,
                s,
                FIG11_STEPS,
                &FIG11_CORR,
                self.tick,
            )
        })?;
        out.push(from_checks(
            "flows_fig11",
            &[flows_check(&runs, FIG11_STEPS)],
        ));
        let speed = corr_speed(&runs, &FIG11_CORR, params.bin);
        out.push(from_checks(
            "v_fig11",
            &[fig11_speed_check(&speed, runs.len())],
        ));
        Ok(())
    }

    /// Steps of the trend runs of PH95 Fig. 12 at this size.
    fn trend_steps(&self) -> u64 {
        self.size.spectrum_tier.pick(20_000, 50_000, 100_000)
    }

    /// I_c by bisection at `params` (its injection rate replaced), or the
    /// reason it could not be bracketed.
    fn bisect(&self, params: Params) -> Result<std::result::Result<(f64, f64), String>> {
        let (rules, engine, steps) = (self.model.rules, self.model.engine, self.trend_steps());
        let r = bisect_ic(0.0, 1.0, self.size.bisections, |i| {
            let p = Params {
                boundary: Boundary::Open { inject: i },
                ..params
            };
            Ok(trend_test(p, rules, engine, &self.seeds, steps, true, self.tick)?.0)
        });
        match r {
            Ok((i_c, err, _)) => Ok(Ok((i_c, err))),
            Err(e) if e.kind == ErrorKind::BadSeries => Ok(Err(e.message)),
            Err(e) => Err(e),
        }
    }

    /// PH95 Fig. 12: I_c, its independence of size and parameters, the
    /// spectra at and below I_c, clogging at I = 0.54.
    fn fig12(&self, out: &mut Vec<Graded>) -> Result<()> {
        let runs = self.seeds.len();
        let pipe = |l, w, g| {
            self.pipe(Params {
                g,
                ..fig12_pipe(l, w, 0.0)
            })
        };
        let (i_c, err) = match self.bisect(pipe(220, 11, 0.5))? {
            Ok(x) => x,
            Err(why) => {
                for (id, _) in CLAIMS.iter().skip_while(|(id, _)| *id != "i_c") {
                    out.push(undecided(id, format!("I_c not bracketed: {why}")));
                }
                return Ok(());
            }
        };
        out.push(from_checks(
            "i_c",
            &[ic_check((i_c, err), runs, "L = 220, W = 11")],
        ));
        for (id, name, what, set) in [
            (
                "i_c_size",
                "i_c_independent_of_w_and_l",
                "the pipe size",
                vec![("220x5", pipe(220, 5, 0.5)), ("440x11", pipe(440, 11, 0.5))],
            ),
            (
                "i_c_params",
                "i_c_independent_of_g",
                "the model parameters",
                vec![("g = 0.2", pipe(220, 11, 0.2))],
            ),
        ] {
            let mut others = Vec::new();
            let mut failed = None;
            for (label, p) in set {
                match self.bisect(p)? {
                    Ok((i, e)) => others.push((label.to_string(), i, e)),
                    Err(why) => failed = Some(format!("{label}: I_c not bracketed: {why}")),
                }
            }
            out.push(match failed {
                Some(why) => undecided(id, why),
                None => from_checks(
                    id,
                    &[ic_independence_check(name, what, (i_c, err), &others, runs)],
                ),
            });
        }
        // spectra of the bottom bin at the largest stationary rate and at 0.5 I_c
        let at = |i: f64| Params {
            boundary: Boundary::Open { inject: i },
            ..pipe(220, 11, 0.5)
        };
        let i_lo = i_c - err;
        let spec_seeds: Vec<u64> = self.seeds.iter().copied().take(self.size.runs).collect();
        // half-width 0: no rate up to 1 clogs, so there is no I_c to measure at
        let near = if err > 0.0 {
            Some(self.spectrum_point(&format!("I{i_lo:.4}"), at(i_lo), &spec_seeds)?)
        } else {
            None
        };
        let half =
            self.spectrum_point(&format!("I{:.4}", 0.5 * i_c), at(0.5 * i_c), &spec_seeds)?;
        out.push(match &near {
            Some(near) => from_checks(
                "one_over_f_ic",
                &[alpha_check(
                    "one_over_f_at_i_c",
                    "PH95 Fig. 12a-b (1/f noise at I_c)",
                    near,
                    1.0,
                    ALPHA_MARGIN,
                )],
            ),
            None => undecided(
                "one_over_f_ic",
                format!("I_c not bracketed: no rate up to {i_c} clogs, so there is no I_c to measure the spectrum at"),
            ),
        });
        out.push(from_checks(
            "white_half_ic",
            &[alpha_check(
                "white_at_half_i_c",
                "PH95 Fig. 12a-b (white noise away from I_c)",
                &half,
                0.0,
                ALPHA_MARGIN,
            )],
        ));
        let (rules, engine) = (self.model.rules, self.model.engine);
        let (s, _) = trend_test(
            at(CLOG_INJECT),
            rules,
            engine,
            &self.seeds,
            self.trend_steps(),
            false,
            self.tick,
        )?;
        out.push(from_checks("clogs_054", &[clogs_check(&s, CLOG_INJECT)]));
        Ok(())
    }
}

/// The pipes of the [`Group::Dependence`] claims, as (label, pipe): PH94
/// Fig. 2's set-up (the reference), then rho of [`FIG9_RHO`], b of
/// [`FIG10_B`] (g = 0.5), g of [`FIG10_G`] (b = 0.5), Fig. 10b's ends at
/// [`G_LOW`] and the p of `alpha_const_p` (0.05, 0.2, 0.8).
fn dependence_pipes() -> Vec<(String, Params)> {
    let base = Params::default();
    let mut v = vec![("ref".to_string(), base)];
    v.extend(FIG9_RHO.map(|rho| (format!("rho{rho}"), Params { rho, ..base })));
    v.extend(FIG10_B.map(|b| (format!("b{b}_g0.5"), Params { b, ..base })));
    v.extend(FIG10_G.map(|g| (format!("b0.5_g{g}"), Params { g, ..base })));
    let (b_lo, b_hi) = super::dependence::FIG10B_RANGE;
    v.extend([b_lo, b_hi].map(|b| {
        (
            format!("b{b}_g{G_LOW}"),
            Params {
                b,
                g: G_LOW,
                ..base
            },
        )
    }));
    v.extend(FIG8_CLAIM_P.map(|p| (format!("p{p}"), Params { p, ..base })));
    v
}

/// The p of `alpha_const_p` and `v_const_p` besides the reference 0.5.
const FIG8_CLAIM_P: [f64; 3] = [0.05, 0.2, 0.8];

impl Grader<'_> {
    /// PH95 III F-H (Figs. 9-10) through [`super::dependence`], and III F's
    /// "alpha changes with neither p, b nor g" as all of the p, b and g
    /// checks.
    fn dependence(&self, out: &mut Vec<Graded>) -> Result<()> {
        let mut results = Vec::new();
        for (label, params) in dependence_pipes() {
            results.push(self.spectrum_point(&label, params, &self.seeds)?);
        }
        let all: Vec<&PointResult> = results.iter().collect();
        let reference = all[0];
        // each figure's points and the reference
        let of = |prefix: &str| -> Vec<&PointResult> {
            let own = all.iter().filter(|r| r.point.label.starts_with(prefix));
            std::iter::once(reference).chain(own.copied()).collect()
        };
        let mut claims: Vec<Claimed> = fig9_claims(&of("rho"));
        claims.extend(fig10_claims(&of("b")));
        let const_p: Vec<Check> = all
            .iter()
            .filter(|r| r.point.label.starts_with('p'))
            .map(|r| {
                let name = format!("alpha_{}", r.point.label);
                let source = "PH95 III F, Fig. 8a (alpha about constant for every p > 0)";
                same_as_check(
                    &name,
                    source,
                    Quantity::Alpha,
                    r,
                    reference,
                    ALPHA_MARGIN,
                    "",
                )
            })
            .collect();
        let mut pbg = const_p;
        for c in &claims {
            if c.claim == "alpha_const_b" || c.claim == "alpha_indep_g" {
                pbg.extend(c.checks.iter().cloned());
            }
        }
        claims.push(Claimed {
            claim: "alpha_indep_pbg",
            checks: pbg,
        });
        let ids = CLAIMS.iter().map(|(id, _)| *id);
        let ids = ids.skip_while(|id| *id != "alpha_zero_low_rho");
        let last = ids
            .clone()
            .position(|id| id == "alpha_indep_pbg")
            .unwrap_or(0);
        for id in ids.take(last + 1) {
            out.push(match claims.iter().find(|c| c.claim == id) {
                Some(c) => from_checks(id, &c.checks),
                None => undecided(id, "its points were not measured".to_string()),
            });
        }
        Ok(())
    }
}

/// The acceptance margin of PH94 Fig. 2's alpha ([`super::acceptance::MARGINS`]).
fn headline_margin() -> &'static super::acceptance::Margin {
    super::acceptance::margin("fig2", "alpha").expect("fig2's alpha has an acceptance margin")
}

impl Grader<'_> {
    /// PH94 Fig. 2's alpha at the published set-up, as `fig2 --tier
    /// acceptance` grades it: the fit of the averaged spectrum with its
    /// bootstrap SE over the acceptance tier's runs and margin.
    fn headline(&self, out: &mut Vec<Graded>) -> Result<()> {
        let m = headline_margin();
        let params = self.pipe(Params::default());
        let setup = tier_setup(
            Tier::Acceptance,
            params,
            self.model.rules,
            self.model.engine,
        );
        let runs = self.each(&self.seeds, |s| sweep_run(&setup, s, self.tick))?;
        let point = SweepPoint {
            label: "fig2".to_string(),
            x: vec![],
            params,
        };
        let r = reduce(&point, &setup, runs, Estimator::AveragedSpectrum)?;
        let check = Check::published(
            "alpha_fig2_published",
            m.source,
            r.alpha_estimate(),
            m.claim(),
            &format!(
                "fit of the averaged spectrum over {} valid runs ({} invalid), bootstrap SE; {}",
                r.valid,
                r.invalid,
                m.note()
            ),
        );
        out.push(from_checks("alpha_fig2_published", &[check]));
        Ok(())
    }
}

/// The checks of `checks` named `names`, graded as the claims `ids`.
fn push_named(out: &mut Vec<Graded>, checks: &[Check], pairs: &[(&str, &str)]) {
    for (id, name) in pairs {
        let c: Vec<Check> = checks.iter().filter(|c| c.name == *name).cloned().collect();
        out.push(from_checks(id, &c));
    }
}

/// The lengths of the PH95 Fig. 4 claims.
pub const FIG4_LENGTHS: [usize; 4] = [128, 256, 512, 1024];

/// Steps [`grade`] reports through `tick` for one reading (nominal: runs
/// that clog stop early, so the count is an upper bound).
pub fn grade_steps(size: MatrixSize) -> u64 {
    let spec_steps = tier_setup(
        size.spectrum_tier,
        Params::default(),
        Rules::default(),
        Engine::Reference,
    )
    .steps();
    let tier = size.spectrum_tier;
    let (relax, _) = relaxation_schedule(tier);
    let fig4 = Steady::ph95(tier, tier.pick(512, 2048, 2048), FIELDS_EVERY).steps();
    let fig5 = Steady::ph95(tier, tier.pick(1024, 2048, 2048), FIELDS_EVERY).steps();
    let trend = tier.pick(20_000, 50_000, 100_000);
    let (r, w, o) = (
        size.runs as u64,
        size.wave_runs as u64,
        size.open_runs as u64,
    );
    let bisections = 4 * (2 + size.bisections as u64) + 1;
    r * (9 * size.band_steps + 6 * spec_steps)
        + w * (relax + 4 * fig4 + fig5)
        + o * (FIG11_STEPS + bisections * trend)
        + r.min(o) * 2 * spec_steps
        + r * DEPENDENCE_POINTS * spec_steps
        + headline_margin().runs as u64 * headline_steps()
}

/// Steps of one run of [`Group::Headline`] (the paper's spectrum).
fn headline_steps() -> u64 {
    let p = Params::default();
    tier_setup(Tier::Acceptance, p, Rules::default(), Engine::Reference).steps()
}

/// Spectrum points of [`Group::Dependence`] (nominal: as many runs each as
/// the spectra).
const DEPENDENCE_POINTS: u64 = 15;

/// Site updates of one reading (nominal, as [`grade_steps`]).
pub fn site_updates(size: MatrixSize) -> f64 {
    let spec_steps = tier_setup(
        size.spectrum_tier,
        Params::default(),
        Rules::default(),
        Engine::Reference,
    )
    .steps() as f64;
    let tier = size.spectrum_tier;
    let (relax, _) = relaxation_schedule(tier);
    let fig4 = Steady::ph95(tier, tier.pick(512, 2048, 2048), FIELDS_EVERY).steps() as f64;
    let fig5 = Steady::ph95(tier, tier.pick(1024, 2048, 2048), FIELDS_EVERY).steps() as f64;
    let trend = tier.pick(20_000, 50_000, 100_000) as f64;
    let (r, w, o) = (
        size.runs as f64,
        size.wave_runs as f64,
        size.open_runs as f64,
    );
    let b = (2 + size.bisections) as f64;
    let band = 9.0 * size.band_steps as f64 * 24200.0;
    let spectra = 6.0 * spec_steps * 2420.0;
    let waves = relax as f64 * 2816.0 + fig4 * 11.0 * 1920.0 + fig5 * 5632.0;
    let open =
        FIG11_STEPS as f64 * 5000.0 + b * trend * (2420.0 * 2.0 + 1100.0 + 4840.0) + trend * 2420.0;
    r * (band + spectra)
        + w * waves
        + o * open
        + r.min(o) * 2.0 * spec_steps * 2420.0
        + r * DEPENDENCE_POINTS as f64 * spec_steps * 2420.0
        + headline_margin().runs as f64 * headline_steps() as f64 * 2420.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn verdicts_follow_the_stated_rules() {
        let n = 100; // k = 2
        assert_eq!(waves(Estimate::new(10.0, 1.0, n)), Verdict::Reproduced);
        assert_eq!(waves(Estimate::new(1.0, 0.2, n)), Verdict::NotReproduced);
        assert_eq!(waves(Estimate::new(3.0, 1.0, n)), Verdict::Undecided);
        assert_eq!(waves(Estimate::new(10.0, 1.0, 2)), Verdict::Undecided);
        let e = |m, se| equivalent(Estimate::new(m, se, n), 1.33, 0.1);
        assert_eq!(e(1.30, 0.02), Verdict::Reproduced);
        assert_eq!(e(1.10, 0.02), Verdict::NotReproduced);
        assert_eq!(e(1.10, 0.2), Verdict::Undecided);
        // more noise never grades better
        assert_eq!(e(1.25, 0.04), Verdict::Undecided);
        assert_eq!(e(1.25, 0.08), Verdict::Undecided);
        assert_eq!(e(1.25, 0.005), Verdict::Reproduced);
        assert_eq!(CLAIMS.len(), 39);
        assert_eq!(dependence_pipes().len() as u64, DEPENDENCE_POINTS);
    }
}
