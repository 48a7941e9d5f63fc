//! The studies behind the acceptance tier (MODEL.md A10): the pilot that
//! compares candidate estimators over disjoint groups of runs and measures
//! the spread over the papers' open choices ([`pilot`],
//! [`open_choice_values`]), the power analysis ([`runs_to_decide`]), and
//! the stability of the verdicts over base seeds ([`stability`]); the whole
//! pilot of one figure, printed and saved ([`pilot_study`]). The
//! `acceptance` binary runs them; EXPERIMENTS.md "Acceptance at the
//! published set-ups" records what they gave.

use crate::analysis::fit::{
    default_peak_half_width, exclude_peak, find_peak_contrast, fit_power_law, wave_velocity,
    PowerLawParams,
};
use crate::analysis::grading::{Claim, Estimate, Verdict};
use crate::analysis::mean_spectrum::{
    alpha_of_mean, refined_peak, v_of_mean, v_of_mean_refined, BOOTSTRAP_RESAMPLES, BOOTSTRAP_SEED,
};
use crate::analysis::resample::{bootstrap_se, mean_of_rows};
use crate::analysis::spectrum::{spctrm, SpectrumParams, Window};
use crate::error::Result;
use crate::run::median;
use serde::Serialize;
use std::collections::BTreeMap;

use super::acceptance::margin;
use super::spectra::{bin_series, resumable_ensemble, tier_setup, SpectrumRun, SpectrumSetup};
use crate::cli::Common;
use crate::pipe::{Engine, Params, Rules};
use crate::run::{ensemble_with_threads, run_seeds, write_atomic};

/// The median of per-run values with its bootstrap standard error.
fn median_of(values: &[f64]) -> Result<Estimate> {
    let se = bootstrap_se(
        values.len(),
        BOOTSTRAP_RESAMPLES,
        BOOTSTRAP_SEED,
        |idx: &[usize]| Ok(median(&idx.iter().map(|&i| values[i]).collect::<Vec<_>>())),
    )?;
    Ok(Estimate::new(median(values), se, values.len()))
}

/// The candidate estimators the pilot compares: name and estimate.
pub fn candidates(setup: &SpectrumSetup, runs: &[SpectrumRun]) -> Result<Vec<(String, Estimate)>> {
    let rows: Vec<Vec<f64>> = runs.iter().map(|r| r.spectrum.clone()).collect();
    let (length, t0) = (setup.params.length, setup.t0);
    let alphas: Vec<f64> = runs.iter().map(|r| r.alpha).collect();
    let vs: Vec<f64> = runs.iter().map(|r| r.v_peak).collect();
    let mut v_mean_runs_se = v_of_mean(&rows, length, t0)?;
    v_mean_runs_se.se = Estimate::of(&vs).se;
    Ok(vec![
        ("alpha: mean of per-run fits".into(), Estimate::of(&alphas)),
        ("alpha: median of per-run fits".into(), median_of(&alphas)?),
        (
            "alpha: fit of mean spectrum (jackknife)".into(),
            alpha_of_mean(&rows)?,
        ),
        ("v: mean of per-run peaks".into(), Estimate::of(&vs)),
        ("v: median of per-run peaks".into(), median_of(&vs)?),
        (
            "v: peak of mean spectrum, SE of per-run peaks".into(),
            v_mean_runs_se,
        ),
        (
            "v: peak of mean spectrum (bootstrap)".into(),
            v_of_mean(&rows, length, t0)?,
        ),
        (
            "v: refined peak of mean spectrum (jackknife)".into(),
            v_of_mean_refined(&rows, length, t0)?,
        ),
    ])
}

/// What the pilot says of one candidate estimator: its value on all pilot
/// runs, and over disjoint groups of runs its stated SE against the spread
/// of its values.
#[derive(Debug, Clone, Serialize)]
pub struct CandidateReport {
    /// The estimator.
    pub name: String,
    /// Its value on all the pilot's runs.
    pub pooled: f64,
    /// Runs per group.
    pub group_runs: usize,
    /// Number of groups.
    pub groups: usize,
    /// Mean stated SE over groups.
    pub mean_se: f64,
    /// Standard deviation of the group values.
    pub sd_between: f64,
    /// sd_between / mean_se (1 when the stated SE is honest).
    pub ratio: f64,
    /// Share of groups whose interval value +- 2 SE holds the pooled value.
    pub coverage: f64,
}

/// Compare the [`candidates`] on disjoint groups of `group` runs of the
/// pilot's `runs` (see [`CandidateReport`]).
pub fn pilot(
    setup: &SpectrumSetup,
    runs: &[SpectrumRun],
    group: usize,
) -> Result<Vec<CandidateReport>> {
    let pooled = candidates(setup, runs)?;
    let groups: Vec<Vec<(String, Estimate)>> = runs
        .chunks_exact(group)
        .map(|g| candidates(setup, g))
        .collect::<Result<_>>()?;
    Ok(pooled
        .iter()
        .enumerate()
        .map(|(c, (name, all))| {
            let vals: Vec<f64> = groups.iter().map(|g| g[c].1.mean).collect();
            let ses: Vec<f64> = groups.iter().map(|g| g[c].1.se).collect();
            let g = vals.len() as f64;
            let mean_se = ses.iter().sum::<f64>() / g;
            let sd_between = Estimate::of(&vals).se * g.sqrt();
            let covered = vals
                .iter()
                .zip(&ses)
                .filter(|(v, s)| (*v - all.mean).abs() <= 2.0 * *s)
                .count();
            CandidateReport {
                name: name.clone(),
                pooled: all.mean,
                group_runs: group,
                groups: vals.len(),
                mean_se,
                sd_between,
                ratio: sd_between / mean_se,
                coverage: covered as f64 / g,
            }
        })
        .collect())
}

/// One of the choices the paper leaves open, applied to a recorded series.
#[derive(Debug, Clone, Copy)]
pub struct OpenChoice {
    /// Short name.
    pub name: &'static str,
    /// The spectrum estimator.
    pub spectrum: SpectrumParams,
    /// Half-width of the removed peak, in bins of m = 16384 (scaled to m).
    pub peak_half_width_16384: usize,
}

/// The open choices measured for s_open: the default (NR 1988 "Parzen",
/// k = 4, m = 16384, peak +-16 bins), the 1992 NR triangle, the two other
/// readings of "S = 4 segments" (4 segments of 64K samples: m = 32768,
/// k = 2; segments of M = 16384 samples over the whole series: m = 8192,
/// k = 8), and half and double the removed peak width.
pub fn open_choices() -> Vec<OpenChoice> {
    let base = SpectrumParams::default();
    let c = |name, spectrum, peak_half_width_16384| OpenChoice {
        name,
        spectrum,
        peak_half_width_16384,
    };
    vec![
        c("default", base, 16),
        c(
            "window bartlett1992",
            SpectrumParams {
                window: Window::Bartlett1992,
                ..base
            },
            16,
        ),
        c(
            "segments m=32768 k=2",
            SpectrumParams {
                m: 32768,
                k: 2,
                ..base
            },
            16,
        ),
        c(
            "segments m=8192 k=8",
            SpectrumParams {
                m: 8192,
                k: 8,
                ..base
            },
            16,
        ),
        c("peak half-width 8", base, 8),
        c("peak half-width 32", base, 32),
    ]
}

/// alpha, v (peak bin) and v (refined peak) of the averaged spectrum of
/// `series` (one per run) under each open choice: rows (choice, alpha, v,
/// v refined).
pub fn open_choice_values(
    setup: &SpectrumSetup,
    series: &[Vec<f64>],
) -> Result<Vec<(&'static str, f64, f64, f64)>> {
    open_choices()
        .into_iter()
        .map(|c| {
            let rows = series
                .iter()
                .map(|s| spctrm(s, &c.spectrum))
                .collect::<Result<Vec<_>>>()?;
            let all: Vec<usize> = (0..rows.len()).collect();
            let p = mean_of_rows(&rows, &all);
            let m = p.len();
            let mut params = PowerLawParams::default_for(m);
            let (j, _) = find_peak_contrast(&p, params.j_lo, params.j_hi)?;
            let hw = (c.peak_half_width_16384 * m / 16384).max(1);
            debug_assert!(hw >= 1 && default_peak_half_width(16384) == 16);
            params.exclude.push(exclude_peak(j, hw));
            let alpha = fit_power_law(&p, &params)?.alpha;
            let v = wave_velocity(setup.params.length, j, setup.t0 as usize, m);
            let v_refined =
                setup.params.length as f64 * refined_peak(&p)? / (setup.t0 as f64 * 2.0 * m as f64);
            Ok((c.name, alpha, v, v_refined))
        })
        .collect()
}

pub use super::acceptance::runs_to_decide;

/// The run counts [`power`] weighs: the paper tier's 32, and the doublings
/// up to Fig. 8's affordable 128 (about 1 h wall for PH95 Figs. 9 and 10
/// together on 2 cores).
pub const POWER_COUNTS: [usize; 3] = [32, 64, 128];

/// The distance of a check's value `x` from the edge of its claim: the
/// statistic's gap that k SE must clear to decide it.
fn gap_to_edge(x: f64, claim: crate::analysis::grading::Claim) -> f64 {
    use crate::analysis::grading::Claim;
    match claim {
        Claim::Within { target, margin } => (x - target).abs() - margin,
        Claim::Above { threshold } | Claim::Below { threshold } => x - threshold,
    }
}

/// The power of a pilot: from a pilot's `summary.json`
/// (a figure run with few runs per point on pilot seeds), for each published
/// check with a value, an SE and at least 3 runs, its spread per run
/// (SE x sqrt(runs)) and the runs per point that decide it in 95 % of seed
/// sets ([`runs_to_decide`], scaled by the point's share of valid runs when
/// the summary lists its seeds); then, for each count of [`POWER_COUNTS`], how many
/// checks it is predicted to decide. The rule that picks a figure's count
/// from this table, fixed before the pilot of Figs. 9-10 was read: the
/// smallest count of [`POWER_COUNTS`] that is predicted to decide
/// as many checks as the largest one.
///
/// Errors: an unreadable or malformed summary ([`crate::ErrorKind::Io`],
/// [`crate::ErrorKind::BadSeries`]).
pub fn power(summary: &std::path::Path) -> Result<(String, usize)> {
    use crate::analysis::grading::Claim;
    use crate::error::{Error, ErrorKind};
    let text = std::fs::read_to_string(summary)
        .map_err(|e| Error::new(ErrorKind::Io, format!("{}: {e}", summary.display())))?;
    let s: serde_json::Value = serde_json::from_str(&text)
        .map_err(|e| Error::new(ErrorKind::BadSeries, format!("{}: {e}", summary.display())))?;
    let mut out = format!(
        "{}: power of the pilot {}\n\n| check | runs | value | SE | claim | spread per run | runs to decide |\n|---|---|---|---|---|---|---|\n",
        s["figure"].as_str().unwrap_or("?"),
        summary.display()
    );
    let total = s["seeds"].as_array().map(|a| a.len()).filter(|&t| t >= 3);
    let mut need = Vec::new();
    for c in s["checks"].as_array().into_iter().flatten() {
        let (Some(x), Some(se), Some(n)) = (
            c["measured"].as_f64(),
            c["error"].as_f64(),
            c["runs"].as_u64(),
        ) else {
            continue;
        };
        let Ok(claim) = serde_json::from_value::<Claim>(c["claim"].clone()) else {
            continue;
        };
        if c["kind"] != "published" || n < 3 || !x.is_finite() || !se.is_finite() {
            continue;
        }
        let sigma = se * (n as f64).sqrt();
        // a point where some runs left the model's validity keeps n of its
        // `total` runs: the count per point needed is larger by total / n
        let share = total.map_or(1.0, |t| t as f64 / n as f64).max(1.0);
        let runs = runs_to_decide(gap_to_edge(x, claim), 0.0, sigma).map(|r| (r * share).ceil());
        need.push(runs);
        out.push_str(&format!(
            "| {} | {n} | {x:.4} | {se:.4} | {} | {sigma:.4} | {} |\n",
            c["name"].as_str().unwrap_or("?"),
            claim.describe(),
            runs.map_or("never (on the edge)".to_string(), |r| format!("{r}"))
        ));
    }
    let decided = |count: usize| {
        need.iter()
            .flatten()
            .filter(|&&r| r <= count as f64)
            .count()
    };
    let best = decided(*POWER_COUNTS.last().expect("non-empty"));
    let pick = *POWER_COUNTS
        .iter()
        .find(|&&c| decided(c) == best)
        .expect("the last one qualifies");
    out.push_str(&format!("\n{} published checks with a value.\n\n| runs per point | predicted decided |\n|---|---|\n", need.len()));
    for c in POWER_COUNTS {
        out.push_str(&format!("| {c} | {} |\n", decided(c)));
    }
    out.push_str(&format!("\nThe rule's count: {pick} runs per point.\n"));
    Ok((out, pick))
}

/// The file of a figure's seed-set folder that holds each seed set's seal
/// ([`seal_of`]): one line per summary, its path below the folder and its
/// seal, separated by a tab.
pub const SEALS: &str = "seals.tsv";

/// The seal of a committed seed set's summary `s`: a 64-bit FNV-1a hash of
/// its results (the set-up's names, seeds, metrics, and each check's value,
/// SE, verdict, claim, runs and kind: the results two runs of the same
/// seeds share) as canonical JSON, in
/// hex. An edit of any of them that does not also recompute the seal
/// breaks it; it is a check of the filing, not a signature
/// (docs/reference/grading.md, "Seed sets").
pub fn seal_of(s: &serde_json::Value) -> String {
    let text = serde_json::to_string(&results_of(s)).expect("a map of JSON values serialises");
    format!("{:016x}", crate::ensemble::fnv1a64(text.as_bytes()))
}

/// The seals of `from` ([`SEALS`]): path below `from` -> seal; empty when
/// the file does not exist.
fn read_seals(from: &std::path::Path) -> Result<BTreeMap<String, String>> {
    use crate::error::{Error, ErrorKind};
    let path = from.join(SEALS);
    let text = match std::fs::read_to_string(&path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(BTreeMap::new()),
        Err(e) => {
            return Err(Error::new(
                ErrorKind::Io,
                format!("{}: {e}", path.display()),
            ))
        }
    };
    text.lines()
        .filter(|l| !l.trim().is_empty())
        .enumerate()
        .map(|(i, l)| match l.split_once('\t') {
            Some((p, seal)) => Ok((p.to_string(), seal.trim().to_string())),
            None => Err(Error::new(
                ErrorKind::BadSeries,
                format!("{} line {}: not PATH<TAB>SEAL", path.display(), i + 1),
            )),
        })
        .collect()
}

/// The path of summary `path` below the seed-set folder `from`, with `/`.
fn below(from: &std::path::Path, path: &std::path::Path) -> String {
    path.strip_prefix(from)
        .unwrap_or(path)
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect::<Vec<_>>()
        .join("/")
}

/// Seal the seed sets of `figure` in `from` ([`SEALS`]): the summaries in
/// seed folders named in `only` (e.g. `seed-5`), or every summary that has
/// no seal yet when `only` is empty; the other seals are kept as they are.
/// Each summary sealed must pass [`crate::run::verify_check`]. Returns the
/// paths sealed.
///
/// Errors: as [`stability`], or a check that fails its verification.
pub fn seal(from: &std::path::Path, figure: &str, only: &[String]) -> Result<Vec<String>> {
    use crate::error::{Error, ErrorKind};
    let mut seals = read_seals(from)?;
    let mut sealed = vec![];
    for path in seed_summaries(from, figure)? {
        let rel = below(from, &path);
        let folder = rel.split('/').next().unwrap_or("").to_string();
        let wanted = if only.is_empty() {
            !seals.contains_key(&rel)
        } else {
            only.contains(&folder)
        };
        if !wanted {
            continue;
        }
        let s = read_summary(&path)?;
        verify_summary(&path, &s)?;
        seals.insert(rel.clone(), seal_of(&s));
        sealed.push(rel);
    }
    if let Some(missing) = only.iter().find(|f| {
        !sealed
            .iter()
            .any(|r| r.split('/').next() == Some(f.as_str()))
    }) {
        return Err(Error::new(
            ErrorKind::InvalidParameter,
            format!(
                "{}: no summary of {figure} in seed folder {missing}",
                from.display()
            ),
        ));
    }
    let text: String = seals.iter().map(|(p, s)| format!("{p}\t{s}\n")).collect();
    crate::run::write_atomic(&from.join(SEALS), text.as_bytes())?;
    Ok(sealed)
}

/// Summary `path` as JSON.
fn read_summary(path: &std::path::Path) -> Result<serde_json::Value> {
    use crate::error::{Error, ErrorKind};
    let text = std::fs::read_to_string(path)
        .map_err(|e| Error::new(ErrorKind::Io, format!("{}: {e}", path.display())))?;
    serde_json::from_str(&text)
        .map_err(|e| Error::new(ErrorKind::BadSeries, format!("{}: {e}", path.display())))
}

/// Every check of summary `s` (read from `path`) verified by the one rule
/// ([`crate::run::verify_check`]); the error names the file and the check.
fn verify_summary(path: &std::path::Path, s: &serde_json::Value) -> Result<()> {
    use crate::error::{Error, ErrorKind};
    for c in s["checks"].as_array().into_iter().flatten() {
        crate::run::verify_check(c).map_err(|e| {
            Error::new(
                ErrorKind::BadSeries,
                format!(
                    "{}: check {}: {e}",
                    path.display(),
                    c["name"].as_str().unwrap_or("?")
                ),
            )
        })?;
    }
    Ok(())
}

/// The checks of `figure` over its seed folders ([`seed_checks`]).
struct SeedChecks {
    /// The number of seed folders.
    seeds: usize,
    /// Per check, its (verdict, value, SE) at each seed, in folder order.
    rows: BTreeMap<String, Vec<(String, f64, f64)>>,
    /// Per published check, the claim its summaries state, when every seed
    /// states the same one.
    claims: BTreeMap<String, Claim>,
}

/// The summaries of `figure`'s seed folders in `from`, sorted:
/// `from/<seed folder>/<figure>/summary.json`, or
/// `from/<seed folder>/summary.json` when that summary names the figure.
///
/// Errors: an unreadable folder ([`crate::ErrorKind::Io`]), or no summary at
/// all ([`crate::ErrorKind::InvalidParameter`]).
fn seed_summaries(from: &std::path::Path, figure: &str) -> Result<Vec<std::path::PathBuf>> {
    use crate::error::{Error, ErrorKind};
    let mut dirs: Vec<_> = std::fs::read_dir(from)
        .map_err(|e| Error::new(ErrorKind::Io, format!("{}: {e}", from.display())))?
        .filter_map(|e| {
            // a seed folder is the binary's --out (`<figure>/summary.json`
            // inside) or that figure folder itself, whose summary must then
            // name the figure
            let seed = e.ok()?.path();
            let nested = seed.join(figure).join("summary.json");
            let flat = seed.join("summary.json");
            if nested.is_file() {
                Some(nested)
            } else {
                // an unreadable summary is kept, to be reported below
                let text = std::fs::read_to_string(&flat).ok()?;
                match serde_json::from_str::<serde_json::Value>(&text) {
                    Ok(s) => (s["figure"] == figure).then_some(flat),
                    Err(_) => Some(flat),
                }
            }
        })
        .collect();
    dirs.sort();
    if dirs.is_empty() {
        return Err(Error::new(
            ErrorKind::InvalidParameter,
            format!("{}: no */{figure}/summary.json", from.display()),
        ));
    }
    Ok(dirs)
}

/// The checks of `figure` over the base seeds whose summaries lie in
/// `from/<seed folder>/<figure>/summary.json` (or
/// `from/<seed folder>/summary.json`).
///
/// Errors: an unreadable folder or summary ([`crate::ErrorKind::Io`],
/// [`crate::ErrorKind::BadSeries`]), no summary at all, two seed sets with
/// the same runs (a copy), or seed sets of different tiers, readings or
/// engines ([`crate::ErrorKind::InvalidParameter`]).
fn seed_checks(from: &std::path::Path, figure: &str) -> Result<SeedChecks> {
    use crate::error::{Error, ErrorKind};
    let dirs = seed_summaries(from, figure)?;
    let seals = read_seals(from)?;
    // check -> [(verdict, value, se)]
    let mut rows: BTreeMap<String, Vec<(String, f64, f64)>> = BTreeMap::new();
    // check -> the claim of each seed (None: not a published claim)
    let mut stated: BTreeMap<String, Vec<Option<Claim>>> = BTreeMap::new();
    let mut seen: Vec<(std::path::PathBuf, serde_json::Value)> = vec![];
    let mut shared: Option<(std::path::PathBuf, String)> = None;
    for path in &dirs {
        let s = read_summary(path)?;
        // each seed set graded by the one rule, and as filed (its seal)
        verify_summary(path, &s)?;
        let rel = below(from, path);
        match seals.get(&rel) {
            Some(seal) if *seal == seal_of(&s) => {}
            Some(seal) => return Err(Error::new(
                ErrorKind::BadSeries,
                format!(
                    "{}: its results do not match its seal {seal} in {}: the summary was changed after it was filed; refile it (docs/acceptance/run-seeds.sh --refile)",
                    path.display(),
                    from.join(SEALS).display()
                ),
            )),
            None => return Err(Error::new(
                ErrorKind::BadSeries,
                format!(
                    "{}: no seal in {}: a seed set is graded only as filed; seal it with `acceptance seal --from {} --figure {figure}`",
                    path.display(),
                    from.join(SEALS).display(),
                    from.display()
                ),
            )),
        }
        // every seed set has runs of its own, and all share one set-up
        let set_up = |s: &serde_json::Value| {
            let f = |k: &str| s[k].as_str().unwrap_or("unstated").to_string();
            format!(
                "tier {}, rules {}, engine {}",
                f("tier"),
                f("rules"),
                f("engine")
            )
        };
        let listed = s["seeds"].as_array().is_some_and(|a| !a.is_empty());
        if let Some((other, _)) = seen
            .iter()
            .find(|(_, seeds)| listed && *seeds == s["seeds"])
        {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                format!(
                    "{} has the runs (seeds) of {}: a seed set counts once; remove the copy",
                    path.display(),
                    other.display()
                ),
            ));
        }
        if let Some((first, first_set_up)) = &shared {
            if set_up(&s) != *first_set_up {
                return Err(Error::new(
                    ErrorKind::InvalidParameter,
                    format!(
                        "{} is of {}, {} of {first_set_up}: the seed sets of a figure share one set-up",
                        path.display(),
                        set_up(&s),
                        first.display()
                    ),
                ));
            }
        } else {
            shared = Some((path.clone(), set_up(&s)));
        }
        seen.push((path.clone(), s["seeds"].clone()));
        for c in s["checks"].as_array().into_iter().flatten() {
            let claim = (c["kind"] == "published")
                .then(|| serde_json::from_value::<Claim>(c["claim"].clone()).ok())
                .flatten();
            stated
                .entry(c["name"].as_str().unwrap_or("?").to_string())
                .or_default()
                .push(claim);
            rows.entry(c["name"].as_str().unwrap_or("?").to_string())
                .or_default()
                .push((
                    c["verdict"].as_str().unwrap_or("?").to_string(),
                    c["measured"].as_f64().unwrap_or(f64::NAN),
                    c["error"].as_f64().unwrap_or(f64::NAN),
                ));
        }
    }
    let claims = stated
        .into_iter()
        .filter_map(|(name, cs)| {
            let first = cs.first().copied().flatten()?;
            cs.iter()
                .all(|c| *c == Some(first))
                .then_some((name, first))
        })
        .collect();
    Ok(SeedChecks {
        seeds: dirs.len(),
        rows,
        claims,
    })
}

/// One published check over every seed set: the mean of the seeds' values
/// with the SE of their spread (n = seeds), graded by the check's margin in
/// the acceptance table ([`margin`]) or else by the claim its summaries
/// state.
#[derive(Debug, Clone, Serialize)]
pub struct AllSeeds {
    /// Check name.
    pub check: String,
    /// Seed sets with a finite value.
    pub seeds: usize,
    /// Their mean and the SE of their spread; `None` when no seed has a
    /// value.
    pub estimate: Option<Estimate>,
    /// The claim graded.
    pub claim: Claim,
    /// The verdict (undecided when no seed has a value).
    pub verdict: Verdict,
}

impl AllSeeds {
    /// The claim in a table cell: `target +- margin`, `> threshold` or
    /// `< threshold`.
    pub fn claim_cell(&self) -> String {
        match self.claim {
            Claim::Within { target, margin } => format!("{target} +- {margin:.4}"),
            Claim::Above { threshold } => format!("> {threshold}"),
            Claim::Below { threshold } => format!("< {threshold}"),
        }
    }
}

/// The published checks graded over all seed sets (see [`AllSeeds`]);
/// checks with neither a margin nor one claim stated by every seed are left
/// out.
fn all_seeds_of(figure: &str, checks: &SeedChecks) -> Vec<AllSeeds> {
    checks
        .rows
        .iter()
        .filter_map(|(name, v)| {
            let claim = margin(figure, name)
                .map(|m| m.claim())
                .or_else(|| checks.claims.get(name).copied())?;
            let values: Vec<f64> = v.iter().map(|r| r.1).filter(|x| x.is_finite()).collect();
            let estimate = (!values.is_empty()).then(|| Estimate::of(&values));
            Some(AllSeeds {
                check: name.clone(),
                seeds: values.len(),
                estimate,
                claim,
                verdict: estimate.map_or(Verdict::Undecided, |e| {
                    crate::analysis::grading::grade(e, claim)
                }),
            })
        })
        .collect()
}

/// The number of seed folders of `figure` under `from` (as [`stability`]
/// finds them) and its published checks graded over all of them
/// ([`AllSeeds`]).
///
/// Errors: as [`stability`].
pub fn all_seeds(from: &std::path::Path, figure: &str) -> Result<(usize, Vec<AllSeeds>)> {
    let checks = seed_checks(from, figure)?;
    Ok((checks.seeds, all_seeds_of(figure, &checks)))
}

/// How a summary of `figure` stands to the committed seed sets in `from`
/// ([`committed_twin`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Twin {
    /// A committed seed set has the same runs (the same `seeds`) and the same
    /// results: every check's value, SE, verdict and claim, and every metric,
    /// that both have.
    Identical {
        /// The committed summary.
        committed: std::path::PathBuf,
    },
    /// A committed seed set has the same runs but other results: the code
    /// that wrote the committed seed sets computes otherwise.
    Differs {
        /// The committed summary.
        committed: std::path::PathBuf,
        /// The first difference, e.g. `check alpha: measured 1.26 against 1.25`.
        what: String,
    },
    /// No committed seed set has the summary's runs.
    NotAmong,
}

/// The fields of a summary that are its results, which two runs of the same
/// seeds must share: the set-up's names, every metric, and every check's
/// value, SE, verdict and claim (not timing, notes, sources, nor `params`,
/// which lists the cases a run chose with `--cases`).
fn results_of(s: &serde_json::Value) -> BTreeMap<String, serde_json::Value> {
    let mut out = BTreeMap::new();
    for k in ["figure", "tier", "rules", "engine", "seeds"] {
        out.insert(k.to_string(), s[k].clone());
    }
    for (k, v) in s["metrics"].as_object().into_iter().flatten() {
        out.insert(format!("metric {k}"), v.clone());
    }
    for c in s["checks"].as_array().into_iter().flatten() {
        let name = c["name"].as_str().unwrap_or("?");
        for k in ["measured", "error", "verdict", "claim", "runs", "kind"] {
            out.insert(format!("check {name}: {k}"), c[k].clone());
        }
    }
    out
}

/// The results of a sequentially graded summary (a check with a
/// `sequential` field) that a committed summary `c` of the same base seed
/// can show: the set-up's names, and each sequential check's value, SE,
/// claim, kind and runs where `c` has that check over the same runs. The
/// runs of a look are the first runs of the fixed design, so a check that
/// ran as many runs as the committed one is computed from the same runs;
/// its verdict is left out (the design's boundary at that look is not the
/// fixed rule's), as are metrics and checks without a design (computed
/// from points that may have stopped at other looks). In a figure whose
/// design stops only part of its runs ([`super::acceptance::PARTLY_SEQUENTIAL`])
/// the checks without a design come from the fixed runs: they are compared
/// whole, verdict included, as in the fixed design.
fn sequential_results_of(
    s: &serde_json::Value,
    c: &serde_json::Value,
) -> BTreeMap<String, serde_json::Value> {
    let mut out = BTreeMap::new();
    for k in ["figure", "tier", "rules", "engine"] {
        out.insert(k.to_string(), s[k].clone());
    }
    let committed = c["checks"].as_array().cloned().unwrap_or_default();
    let figure = s["figure"].as_str().unwrap_or("");
    let fixed_rest = super::acceptance::PARTLY_SEQUENTIAL.contains(&figure);
    for check in s["checks"].as_array().into_iter().flatten() {
        let name = check["name"].as_str().unwrap_or("?");
        let same_runs = committed
            .iter()
            .any(|x| x["name"] == check["name"] && x["runs"] == check["runs"]);
        let keys: &[&str] = match (check["sequential"].is_null(), fixed_rest) {
            (false, _) if same_runs => &["measured", "error", "claim", "runs", "kind"],
            (true, true) => &["measured", "error", "verdict", "claim", "runs", "kind"],
            _ => &[],
        };
        for k in keys {
            out.insert(format!("check {name}: {k}"), check[k].clone());
        }
    }
    out
}

/// Whether summary `s` was graded by a sequential design (some check has a
/// `sequential` field).
pub fn is_sequential(s: &serde_json::Value) -> bool {
    s["checks"]
        .as_array()
        .into_iter()
        .flatten()
        .any(|c| !c["sequential"].is_null())
}

/// Whether `summary` (a figure's summary.json, as read) is one of the
/// committed seed sets of `figure` in `from` (`seed_summaries`): the
/// committed seed set with the same `seeds` and tier, compared result by
/// result over the results both have ([`Twin`]; a run of more `--cases`
/// than the committed one has more checks, each case seeing the same
/// seeds). A recomputed seed set identical to its committed twin shows
/// that the code at hand computes what the committed seed sets hold, so
/// grading over them grades this code.
///
/// A summary graded sequentially ([`is_sequential`]) ran the first runs of
/// the committed seed set's: its seeds are theirs or the first of theirs,
/// and it is compared by runs, on the checks that ran as many runs as the
/// committed ones (`sequential_results_of`).
///
/// Errors: as [`stability`].
pub fn committed_twin(
    from: &std::path::Path,
    figure: &str,
    summary: &serde_json::Value,
) -> Result<Twin> {
    use crate::error::{Error, ErrorKind};
    for path in seed_summaries(from, figure)? {
        let text = std::fs::read_to_string(&path)
            .map_err(|e| Error::new(ErrorKind::Io, format!("{}: {e}", path.display())))?;
        let c: serde_json::Value = serde_json::from_str(&text)
            .map_err(|e| Error::new(ErrorKind::BadSeries, format!("{}: {e}", path.display())))?;
        let sequential = is_sequential(summary);
        let first_of =
            |a: &serde_json::Value, b: &serde_json::Value| match (a.as_array(), b.as_array()) {
                (Some(a), Some(b)) => !a.is_empty() && a.len() <= b.len() && b[..a.len()] == a[..],
                _ => false,
            };
        let same_seeds = if sequential {
            first_of(&summary["seeds"], &c["seeds"]) || first_of(&c["seeds"], &summary["seeds"])
        } else {
            c["seeds"] == summary["seeds"]
        };
        if !same_seeds || c["tier"] != summary["tier"] {
            continue;
        }
        let (mine, theirs) = if sequential {
            (sequential_results_of(summary, &c), results_of(&c))
        } else {
            (results_of(summary), results_of(&c))
        };
        let shared = theirs.keys().filter(|k| mine.contains_key(*k));
        let checks = shared.clone().filter(|k| k.starts_with("check ")).count();
        let what = shared
            .clone()
            .find(|k| mine[*k] != theirs[*k])
            .map(|k| format!("{k}: {} here against {} committed", mine[k], theirs[k]))
            .or_else(|| {
                (checks == 0).then(|| "no check in common with the committed one".to_string())
            });
        return Ok(match what {
            None => Twin::Identical { committed: path },
            Some(what) => Twin::Differs {
                committed: path,
                what,
            },
        });
    }
    Ok(Twin::NotAmong)
}

/// The verdicts of every check of `figure` over the base seeds whose
/// summaries lie in `from/<seed folder>/<figure>/summary.json` (or
/// `from/<seed folder>/summary.json`): a Markdown
/// table with, per check, the seeds, the verdict counts, the share of the
/// most common verdict, the mean value and mean SE, and the coverage of
/// value +- 2 SE around the inverse-variance pooled value of all seeds;
/// then the published checks over all seeds ([`all_seeds`]).
///
/// Errors: an unreadable folder or summary ([`crate::ErrorKind::Io`],
/// [`crate::ErrorKind::BadSeries`]), or no summary at all.
pub fn stability(from: &std::path::Path, figure: &str) -> Result<String> {
    let checks = seed_checks(from, figure)?;
    let (seeds, rows) = (checks.seeds, &checks.rows);
    let mut out = format!(
        "{figure}: {seeds} base seeds ({})\n\n| check | seeds | reproduced | not reproduced | undecided | modal share | mean value | mean SE | pooled | coverage of +-2 SE |\n|---|---|---|---|---|---|---|---|---|---|\n",
        from.display()
    );
    for (name, v) in rows {
        let count = |w: &str| v.iter().filter(|r| r.0 == w).count();
        let (yes, no, und) = (
            count("reproduced"),
            count("not-reproduced"),
            count("undecided"),
        );
        let n = v.len() as f64;
        let modal = yes.max(no).max(und) as f64 / n;
        // values with a finite SE; the pooled value weighs each by 1/SE^2,
        // or equally when some SE is 0 (e.g. a spectral line in one bin)
        let ok: Vec<_> = v
            .iter()
            .filter(|r| r.1.is_finite() && r.2.is_finite() && r.2 >= 0.0)
            .collect();
        if ok.is_empty() {
            // no seed gave a value (e.g. a check over runs that none had):
            // say so rather than print NaN
            out.push_str(&format!(
                "| {name} | {} | {yes} | {no} | {und} | {modal:.2} | n/a (no seed has a value) | | | |\n",
                v.len()
            ));
            continue;
        }
        let k = ok.len() as f64;
        let mean = ok.iter().map(|r| r.1).sum::<f64>() / k;
        let se = ok.iter().map(|r| r.2).sum::<f64>() / k;
        let pooled = if ok.iter().all(|r| r.2 > 0.0) {
            let w: f64 = ok.iter().map(|r| 1.0 / (r.2 * r.2)).sum();
            ok.iter().map(|r| r.1 / (r.2 * r.2)).sum::<f64>() / w
        } else {
            mean
        };
        let cover = ok
            .iter()
            .filter(|r| (r.1 - pooled).abs() <= 2.0 * r.2)
            .count() as f64
            / k;
        out.push_str(&format!(
            "| {name} | {} | {yes} | {no} | {und} | {modal:.2} | {mean:.4} | {se:.4} | {pooled:.4} | {cover:.2} |\n",
            v.len()
        ));
    }
    // all seeds together: the mean of the seeds' values with the SE of their
    // spread (n = seeds), graded by the acceptance margin
    let mut pooled = String::new();
    for a in all_seeds_of(figure, &checks) {
        let name = &a.check;
        match a.estimate {
            None => pooled.push_str(&format!(
                "| {name} | 0 | n/a (no seed has a value) | {} | undecided |\n",
                a.claim_cell()
            )),
            // one seed has no spread: say so rather than print NaN
            Some(est) if !est.se.is_finite() => pooled.push_str(&format!(
                "| {name} | {} | {:.4} +- n/a (no spread of one seed) | {} | {} |\n",
                est.n,
                est.mean,
                a.claim_cell(),
                a.verdict.status()
            )),
            Some(est) => pooled.push_str(&format!(
                "| {name} | {} | {:.4} +- {:.4} | {} | {} |\n",
                est.n,
                est.mean,
                est.se,
                a.claim_cell(),
                a.verdict.status()
            )),
        }
    }
    if !pooled.is_empty() {
        out.push_str(&format!(
            "\nAll {seeds} seeds as one ensemble (the mean of the seeds' values, the SE of their spread, graded with n = seeds):\n\n| check | seeds | value | claim | verdict |\n|---|---|---|---|---|\n{pooled}"
        ));
    }
    Ok(out)
}

/// A pilot's set-up: the figure binary, its ensemble's name, the pipe, and
/// the acceptance checks of its alpha and v (if any).
struct PilotCase {
    binary: &'static str,
    name: &'static str,
    params: Params,
    alpha_check: &'static str,
    v_check: Option<&'static str>,
}

/// The pilot case of `--figure`.
fn case_of(figure: &str) -> crate::Result<PilotCase> {
    let base = Params::default();
    let case = |binary, name, params, alpha_check, v_check| PilotCase {
        binary,
        name,
        params,
        alpha_check,
        v_check,
    };
    match figure {
        "fig2" => Ok(case("fig2", "spectrum", base, "alpha", Some("v_peak"))),
        "waves-fig6" => Ok(case(
            "waves-fig6",
            "spectrum",
            Params { p: 0.8, ..base },
            "alpha",
            None,
        )),
        "waves-fig7-p0" => Ok(case(
            "waves-fig7",
            "p0",
            Params { p: 0.0, ..base },
            "alpha_p0",
            None,
        )),
        "waves-fig7-b0" => Ok(case(
            "waves-fig7",
            "b0",
            Params { b: 0.0, ..base },
            "alpha_b0",
            Some("v_peak_b0"),
        )),
        other => Err(crate::Error::out_of_range(
            "--figure",
            other,
            "{fig2, waves-fig6, waves-fig7-p0, waves-fig7-b0, waves-fig8, hopper-fig3}",
        )),
    }
}

/// `acceptance pilot`: the pilot study of one figure's acceptance check
/// (MODEL.md A10): `runs` pilot runs (default 384, saved and resumed) graded
/// by every candidate estimator over disjoint groups of `group` runs, the
/// spread over the papers' open choices on the first `open_runs` runs, and
/// the runs each check needs to decide; printed and written to
/// `OUT/<binary>/pilot-<name>-group<group>.json`.
pub fn pilot_study(common: &Common, figure: &str, group: usize, open_runs: usize) -> Result<()> {
    match figure {
        "waves-fig8" => return sweep_pilot(common, open_runs),
        "hopper-fig3" => return hopper_pilot(common, open_runs),
        _ => {}
    }
    let case = case_of(figure)?;
    let setup = tier_setup(common.tier, case.params, Rules::default(), Engine::Fast);
    let runs = common.runs.unwrap_or(384);
    if group < 3 || group > runs {
        return Err(crate::Error::out_of_range(
            "--group",
            group,
            &format!("[3, {runs}]"),
        ));
    }
    let Some(ens) = resumable_ensemble(common, case.binary, case.name, &setup, runs)? else {
        return Ok(());
    };
    let report = pilot(&setup, &ens.runs, group)?;
    println!(
        "{figure}: {runs} pilot runs, base seed {}, groups of {group}",
        common.seed
    );
    println!(
        "{:48} {:>9} {:>9} {:>9} {:>6} {:>8}",
        "estimator", "pooled", "mean SE", "SD grp", "ratio", "coverage"
    );
    for c in &report {
        println!(
            "{:48} {:>9.4} {:>9.4} {:>9.4} {:>6.2} {:>8.2}",
            c.name, c.pooled, c.mean_se, c.sd_between, c.ratio, c.coverage
        );
    }
    let n_open = open_runs.min(runs);
    let seeds: Vec<u64> = run_seeds(common.seed, n_open);
    let series = ensemble_with_threads(n_open, common.thread_count(), |i| {
        bin_series(&setup, seeds[i], &|_| {})
    })
    .into_iter()
    .collect::<crate::Result<Vec<_>>>()?;
    let open = if n_open >= 1 {
        open_choice_values(&setup, &series)?
    } else {
        Vec::new()
    };
    let (mut sa, mut sv, mut sr) = (0f64, 0f64, 0f64);
    if let Some(&(_, a0, v0, r0)) = open.first() {
        println!("open choices on the first {n_open} runs (alpha, v, v refined of the averaged spectrum):");
        for (name, a, v, r) in &open {
            println!(
                "  {name:24} alpha {a:.4} ({:+.4})  v {v:.4} ({:+.4})  v refined {r:.4} ({:+.4})",
                a - a0,
                v - v0,
                r - r0
            );
            sa = sa.max((a - a0).abs());
            sv = sv.max((v - v0).abs());
            sr = sr.max((r - r0).abs());
        }
        println!("s_open: alpha {sa:.4}, v {sv:.4}, v refined {sr:.4}");
    }
    // power: runs to decide each check from the pilot's pooled value
    // and its per-run spread (SE of a group x sqrt(group)).
    for (check, cand) in [
        (
            Some(case.alpha_check),
            "alpha: fit of mean spectrum (jackknife)",
        ),
        (case.v_check, "v: peak of mean spectrum (bootstrap)"),
    ] {
        let (Some(check), Some(c)) = (check, report.iter().find(|c| c.name == cand)) else {
            continue;
        };
        let Some(m) = margin(case.binary, check) else {
            println!("power {check}: no acceptance margin yet");
            continue;
        };
        let sigma = c.mean_se * (group as f64).sqrt();
        let d = c.pooled - m.published;
        let n = runs_to_decide(d, m.delta(), sigma);
        println!(
            "power {check}: d = {d:+.4}, Delta = {:.4}, sigma per run = {sigma:.4}: {} runs decide in 95 % of seed sets",
            m.delta(),
            n.map_or("no number of".to_string(), |n| format!("{:.0}", n.ceil()))
        );
    }
    let json = serde_json::json!({
        "figure": figure, "seed": common.seed, "runs": runs, "group": group,
        "candidates": report,
        "open_choices": open.iter().map(|(n, a, v, r)| serde_json::json!({"choice": n, "alpha": a, "v": v, "v_refined": r})).collect::<Vec<_>>(),
        "s_open_alpha": sa, "s_open_v": sv, "s_open_v_refined": sr,
    });
    let path = common
        .out
        .join(case.binary)
        .join(format!("pilot-{}-group{group}.json", case.name));
    write_json(&path, &json)
}

/// `acceptance pilot --figure hopper-fig3`: the pilot of BB90 Fig. 3's
/// flat spectrum at the paper set-up, for the default reading's two cases
/// (beta = 1 along-bond, beta = 0), `runs` runs each (reference engine):
/// the slope of the averaged spectrum with its jackknife SE over runs; its
/// change when m (256, the paper tier's) is halved or doubled, the choice
/// the paper leaves open (s_open); and the runs that decide the check.
pub fn hopper_pilot(common: &Common, runs: usize) -> Result<()> {
    use super::hopper_figures::{fig3_setup, slope_jackknife_se};
    use crate::hopper::experiment::{analyse_outflow, run_cases, Case};
    if runs < 3 {
        return Err(crate::Error::out_of_range("--open-runs", runs, "[3, ...)"));
    }
    let (base, plan, m) = fig3_setup(common.tier);
    let cases = Case::parse_list("beta1_bond,beta0")?;
    let seeds: Vec<u64> = run_seeds(common.seed, runs);
    let recs = run_cases(base, &cases, &seeds, &plan, common.thread_count())?;
    let mut rows = Vec::new();
    println!(
        "hopper-fig3 pilot: {runs} runs per case, base seed {}, m = {m}",
        common.seed
    );
    for (case, rs) in cases.iter().zip(&recs) {
        let slope = analyse_outflow(rs, m)?.fit.slope;
        let se = slope_jackknife_se(rs, m)?;
        let mut s_open = 0f64;
        let mut open = Vec::new();
        for mm in [m / 2, m * 2] {
            let other = analyse_outflow(rs, mm)?.fit.slope;
            s_open = s_open.max((other - slope).abs());
            open.push(serde_json::json!({"m": mm, "slope": other}));
        }
        let delta = super::acceptance::WHITE_THRESHOLD + s_open;
        let n = runs_to_decide(slope, delta, se * (runs as f64).sqrt()).map(f64::ceil);
        println!(
            "  {:12} slope {slope:+.4} +- {se:.4} (jackknife); s_open (m = {}, {}) {s_open:.4}; Delta {delta:.4}: runs to decide {n:?}",
            case.key,
            m / 2,
            m * 2
        );
        rows.push(
            serde_json::json!({"case": case.key, "slope": slope, "jackknife_se": se,
            "open": open, "s_open": s_open, "runs_to_decide": n}),
        );
    }
    let json = serde_json::json!({"figure": "hopper-fig3", "seed": common.seed, "runs": runs,
        "tier": common.tier.name(), "m": m, "cases": rows});
    let path = common.out.join("hopper-fig3").join("pilot.json");
    write_json(&path, &json)
}

/// One point of [`sweep_pilot`]: the swept value, the open choices'
/// (alpha, v) of its averaged spectrum, and the acceptance estimates.
struct SweepPilotPoint {
    x: f64,
    open: Vec<(&'static str, f64, f64, f64)>,
    alpha: Estimate,
    v: Estimate,
}

/// `acceptance pilot --figure waves-fig8`: the pilot of PH95 Fig. 8's
/// "same as at p = 0.5" claims at the paper set-up (fast engine, default
/// reading). For each p of [`super::sweep::FIG8_P`] above 0, `runs` runs
/// (series re-simulated, not saved): the difference alpha(p) - alpha(0.5)
/// and v(p) - v(0.5) under each open choice, whose largest change over the
/// choices and the points is s_open of a difference; and the acceptance
/// estimators' SEs, from which the runs that decide each point.
pub fn sweep_pilot(common: &Common, runs: usize) -> Result<()> {
    use super::margins::{ALPHA_MARGIN, V_SAME_MARGIN};
    if runs < 3 {
        return Err(crate::Error::out_of_range("--open-runs", runs, "[3, ...)"));
    }
    let base = Params::default();
    let seeds: Vec<u64> = run_seeds(common.seed, runs);
    let mut points = Vec::new();
    for &x in super::sweep::FIG8_P.iter().filter(|&&x| x > 0.0) {
        let setup = tier_setup(
            common.tier,
            Params { p: x, ..base },
            Rules::default(),
            Engine::Fast,
        );
        eprintln!(
            "waves-fig8 pilot: p = {x}, {runs} runs of {} steps",
            setup.steps()
        );
        let series = ensemble_with_threads(runs, common.thread_count(), |i| {
            bin_series(&setup, seeds[i], &|_| {})
        })
        .into_iter()
        .collect::<Result<Vec<_>>>()?;
        let open = open_choice_values(&setup, &series)?;
        let rows = series
            .iter()
            .map(|s| spctrm(s, &setup.spectrum_params()))
            .collect::<Result<Vec<_>>>()?;
        points.push(SweepPilotPoint {
            x,
            open,
            alpha: alpha_of_mean(&rows)?,
            v: v_of_mean(&rows, setup.params.length, setup.t0)?,
        });
    }
    let Some(reference) = points.iter().find(|p| p.x == 0.5) else {
        return Err(crate::Error::new(
            crate::error::ErrorKind::InvalidParameter,
            "waves-fig8 pilot: p = 0.5 missing from FIG8_P".to_string(),
        ));
    };
    let (mut sa, mut sv) = (0f64, 0f64);
    let mut rows = Vec::new();
    println!(
        "waves-fig8 pilot: {runs} runs per point, base seed {}; change of the difference to p = 0.5 under each open choice",
        common.seed
    );
    for p in points.iter().filter(|p| p.x != 0.5) {
        let (da0, dv0) = (
            p.open[0].1 - reference.open[0].1,
            p.open[0].2 - reference.open[0].2,
        );
        for (c, rc) in p.open.iter().zip(&reference.open).skip(1) {
            let (da, dv) = (c.1 - rc.1 - da0, c.2 - rc.2 - dv0);
            println!("  p = {:<5} {:24} alpha {da:+.4}  v {dv:+.4}", p.x, c.0);
            sa = sa.max(da.abs());
            sv = sv.max(dv.abs());
        }
        rows.push((p, p.alpha.minus(reference.alpha), p.v.minus(reference.v)));
    }
    println!("s_open of a difference: alpha {sa:.4}, v {sv:.4}");
    let mut json_rows = Vec::new();
    for (p, da, dv) in &rows {
        let power = |d: Estimate, delta: f64| {
            runs_to_decide(d.mean, delta, d.se * (runs as f64).sqrt()).map(f64::ceil)
        };
        let (na, nv) = (
            power(*da, ALPHA_MARGIN + sa),
            power(*dv, V_SAME_MARGIN + sv),
        );
        println!(
            "  p = {:<5} alpha diff {:+.4} +- {:.4} (runs to decide {:?})   v diff {:+.4} +- {:.4} (runs to decide {:?})",
            p.x, da.mean, da.se, na, dv.mean, dv.se, nv
        );
        json_rows.push(serde_json::json!({
            "p": p.x, "alpha_diff": da.mean, "alpha_diff_se": da.se, "alpha_runs_to_decide": na,
            "v_diff": dv.mean, "v_diff_se": dv.se, "v_runs_to_decide": nv,
            "open": p.open.iter().map(|(n, a, v, _)| serde_json::json!({"choice": n, "alpha": a, "v": v})).collect::<Vec<_>>(),
        }));
    }
    let json = serde_json::json!({
        "figure": "waves-fig8", "seed": common.seed, "runs": runs, "tier": common.tier.name(),
        "s_open_alpha_difference": sa, "s_open_v_difference": sv,
        "reference_open": reference.open.iter().map(|(n, a, v, _)| serde_json::json!({"choice": n, "alpha": a, "v": v})).collect::<Vec<_>>(),
        "points": json_rows,
    });
    let path = common
        .out
        .join("waves-fig8")
        .join("pilot-open-differences.json");
    write_json(&path, &json)
}

/// Write a pilot's JSON to `path`, making its folder, and say so.
fn write_json(path: &std::path::Path, json: &serde_json::Value) -> Result<()> {
    let io = |e: &dyn std::fmt::Display| {
        crate::Error::new(
            crate::error::ErrorKind::Io,
            format!("{}: {e}", path.display()),
        )
    };
    let text = serde_json::to_string_pretty(json).map_err(|e| io(&e))?;
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).map_err(|e| io(&e))?;
    }
    write_atomic(path, text.as_bytes())?;
    println!("wrote {}", path.display());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stability_counts_verdicts_over_seed_folders() {
        let dir = std::env::temp_dir().join(format!("ga-stability-{}", std::process::id()));
        let write = |seed: u32, verdict: &str, x: f64| {
            let d = dir.join(format!("seed-{seed}")).join("fig2");
            std::fs::create_dir_all(&d).unwrap();
            let s = serde_json::json!({"figure": "fig2", "checks": [
                {"name": "alpha", "verdict": verdict, "measured": x, "error": 0.01},
                {"name": "line", "verdict": "reproduced", "measured": 0.5, "error": 0.0},
                {"name": "wave_runs", "verdict": "undecided", "measured": null, "error": null},
                // graded over the seeds by the claim the summaries state
                {"name": "rises", "kind": "published", "verdict": "undecided", "measured": x - 1.0,
                 "error": 0.2, "claim": {"test": "above", "threshold": 0.0}},
                // not a published claim, or a claim the seeds do not agree on: left out
                {"name": "pinned", "kind": "pinned", "verdict": "reproduced", "measured": x,
                 "error": 0.01, "runs": 10, "claim": {"test": "above", "threshold": 0.0}},
                {"name": "moving", "kind": "published", "verdict": "reproduced", "measured": x,
                 "error": 0.01, "runs": 10, "claim": {"test": "above", "threshold": x - 1.0}},
            ]});
            std::fs::write(d.join("summary.json"), s.to_string()).unwrap();
        };
        write(1, "undecided", 1.265);
        write(2, "undecided", 1.27);
        write(3, "reproduced", 1.315);
        // a seed folder holding the summary itself counts as well
        std::fs::create_dir_all(dir.join("seed-4")).unwrap();
        std::fs::copy(
            dir.join("seed-2/fig2/summary.json"),
            dir.join("seed-4/summary.json"),
        )
        .unwrap();
        std::fs::create_dir_all(dir.join("empty")).unwrap();
        // unsealed seed sets are refused, naming the file; sealed, they count
        let e = stability(&dir, "fig2").unwrap_err().to_string();
        assert!(e.contains("seed-1/fig2/summary.json: no seal"), "{e}");
        assert_eq!(seal(&dir, "fig2", &[]).unwrap().len(), 4);
        let t = stability(&dir, "fig2").unwrap();
        assert!(t.contains("4 base seeds"), "{t}");
        assert!(t.contains("| alpha | 4 | 1 | 0 | 3 | 0.75 |"), "{t}");
        // 1.315 lies more than 2 SE from the pooled 1.280: coverage 3 of 4
        assert!(t.contains("| 0.75 |\n"), "{t}");
        assert!(
            t.contains("| line | 4 | 4 | 0 | 0 | 1.00 | 0.5000 | 0.0000 | 0.5000 | 1.00 |"),
            "{t}"
        );
        assert!(
            t.contains("| wave_runs | 4 | 0 | 0 | 4 | 1.00 | n/a (no seed has a value) |"),
            "{t}"
        );
        assert!(!t.contains("NaN"), "{t}");
        // all seeds as one: 0.28 +- 0.0117 over 4 seeds clears 0 (each seed alone does not)
        assert!(
            t.contains("| rises | 4 | 0.2800 +- 0.0117 | > 0 | reproduced |"),
            "{t}"
        );
        assert!(
            t.contains("| alpha | 4 | 1.2800 +- 0.0117 | 1.33 +- 0.0590 |"),
            "{t}"
        );
        assert!(
            !t.contains("| pinned | 4 | 1.") && !t.contains("| moving | 4 | 1."),
            "{t}"
        );
        // one seed alone: its value, no spread, undecided, and no NaN
        let one = dir.join("one");
        std::fs::create_dir_all(one.join("seed-1")).unwrap();
        std::fs::copy(
            dir.join("seed-1/fig2/summary.json"),
            one.join("seed-1/summary.json"),
        )
        .unwrap();
        seal(&one, "fig2", &[]).unwrap();
        let t1 = stability(&one, "fig2").unwrap();
        assert!(
            t1.contains("| alpha | 1 | 1.2650 +- n/a (no spread of one seed) | 1.33 +- 0.0590 | undecided |"),
            "{t1}"
        );
        assert!(!t1.contains("NaN"), "{t1}");
        assert!(stability(&dir, "nothing").is_err());
        std::fs::write(dir.join("empty/summary.json"), "{").unwrap();
        assert!(stability(&dir, "fig2").is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn power_picks_the_smallest_count_that_decides_what_the_largest_does() {
        let dir = std::env::temp_dir().join(format!("ga-power-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("summary.json");
        let within = serde_json::json!({"test": "within", "target": 0.0, "margin": 0.1});
        let above = serde_json::json!({"test": "above", "threshold": 0.0});
        let check = |name: &str, x: f64, se: f64, claim: &serde_json::Value| serde_json::json!({"name": name, "kind": "published", "measured": x, "error": se, "runs": 16, "claim": claim});
        // spread per run 0.4: 0.3 from the edge decides at (3.645 x 0.4 / 0.3)^2 = 24 runs,
        // 0.2 at 54, 0.12 at 148 (beyond 128); a pinned check is not counted
        let s = serde_json::json!({"figure": "waves-fig9", "checks": [
            check("a", 0.4, 0.1, &within),
            check("b", 0.2, 0.1, &above),
            check("c", 0.22, 0.1, &within),
            {"name": "d", "kind": "pinned", "measured": 1.0, "error": 0.1, "runs": 16, "claim": above},
        ]});
        std::fs::write(&path, s.to_string()).unwrap();
        let (table, pick) = power(&path).unwrap();
        assert_eq!(pick, 64, "{table}");
        assert!(
            table.contains("| 32 | 1 |\n| 64 | 2 |\n| 128 | 2 |"),
            "{table}"
        );
        assert!(table.contains("3 published checks"), "{table}");
        assert!(power(&dir.join("none.json")).is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn runs_to_decide_grow_as_the_gap_closes() {
        let far = runs_to_decide(0.2, 0.05, 0.1).unwrap();
        let near = runs_to_decide(0.06, 0.05, 0.1).unwrap();
        assert!(near > far * 100.0);
        assert!(runs_to_decide(0.05, 0.05, 0.1).is_none());
    }

    /// A sequentially graded summary is its committed seed set's twin when
    /// the checks that ran the committed runs have the committed values;
    /// a check that stopped earlier, metrics and the verdict are not
    /// compared; a changed value at the same runs is found.
    #[test]
    fn a_sequential_summary_is_compared_with_its_twin_by_runs() {
        let dir = std::env::temp_dir().join(format!("ga-twin-{}", std::process::id()));
        let d = dir.join("seed-1").join("fig2");
        std::fs::create_dir_all(&d).unwrap();
        let check = |name: &str, x: f64, runs: usize, verdict: &str| {
            serde_json::json!({"name": name, "kind": "published", "measured": x, "error": 0.01,
                "runs": runs, "verdict": verdict, "claim": {"test": "within", "target": 1.0, "margin": 0.1}})
        };
        let committed = serde_json::json!({"figure": "fig2", "tier": "acceptance",
            "seeds": [11, 12, 13, 14], "metrics": {"alpha": 1.0},
            "checks": [check("alpha", 1.25, 4, "not-reproduced"), check("v", 0.4, 4, "reproduced")]});
        std::fs::write(d.join("summary.json"), committed.to_string()).unwrap();
        let seq = |alpha: f64, seeds: serde_json::Value| {
            let mut a = check("alpha", alpha, 4, "undecided");
            a["sequential"] = serde_json::json!({"look": 2, "runs": 4});
            let mut v = check("v", 0.41, 2, "reproduced");
            v["sequential"] = serde_json::json!({"look": 1, "runs": 2});
            serde_json::json!({"figure": "fig2", "tier": "acceptance", "seeds": seeds,
                "metrics": {"alpha": 2.0}, "checks": [a, v]})
        };
        let same = committed_twin(
            &dir,
            "fig2",
            &seq(1.25, serde_json::json!([11, 12, 13, 14])),
        );
        assert!(matches!(same, Ok(Twin::Identical { .. })), "{same:?}");
        let other = committed_twin(
            &dir,
            "fig2",
            &seq(1.26, serde_json::json!([11, 12, 13, 14])),
        );
        assert!(
            matches!(&other, Ok(Twin::Differs { what, .. }) if what.contains("alpha: measured")),
            "{other:?}"
        );
        // the first runs of the committed ones, but no check ran as many
        let mut early = seq(1.25, serde_json::json!([11, 12]));
        early["checks"][0]["runs"] = 2.into();
        let early = committed_twin(&dir, "fig2", &early);
        assert!(
            matches!(&early, Ok(Twin::Differs { what, .. }) if what.contains("no check in common")),
            "{early:?}"
        );
        // other seeds: not among them
        let none = committed_twin(
            &dir,
            "fig2",
            &seq(1.25, serde_json::json!([21, 22, 23, 24])),
        );
        assert_eq!(none.unwrap(), Twin::NotAmong);
        std::fs::remove_dir_all(&dir).unwrap();
    }
    /// PH95 Fig. 12 stops only its spectrum points: its other checks come
    /// from the fixed bisection runs and are compared with a committed cut
    /// without spectra whole, verdict included.
    #[test]
    fn a_partly_sequential_summary_compares_its_fixed_checks_whole() {
        let dir = std::env::temp_dir().join(format!("ga-twin12-{}", std::process::id()));
        let d = dir.join("seed-1").join("waves-fig12");
        std::fs::create_dir_all(&d).unwrap();
        let check = |name: &str, x: f64, verdict: &str| {
            serde_json::json!({"name": name, "kind": "published", "measured": x, "error": 0.004,
                "runs": 32, "verdict": verdict, "claim": {"test": "within", "target": 0.52, "margin": 0.05}})
        };
        let cut = serde_json::json!({"figure": "waves-fig12", "tier": "acceptance",
            "seeds": [11, 12], "metrics": {}, "checks": [check("i_c", 0.51, "reproduced")]});
        std::fs::write(d.join("summary.json"), cut.to_string()).unwrap();
        let whole = |i_c: f64, verdict: &str| {
            let mut s = check("one_over_f_at_i_c", 0.35, "not-reproduced");
            (s["runs"], s["sequential"]) = (16.into(), serde_json::json!({"look": 1, "runs": 16}));
            serde_json::json!({"figure": "waves-fig12", "tier": "acceptance", "seeds": [11, 12],
                "metrics": {}, "checks": [check("i_c", i_c, verdict), s]})
        };
        let same = committed_twin(&dir, "waves-fig12", &whole(0.51, "reproduced"));
        assert!(matches!(same, Ok(Twin::Identical { .. })), "{same:?}");
        for (i_c, verdict, what) in [
            (0.52, "reproduced", "i_c: measured"),
            (0.51, "undecided", "i_c: verdict"),
        ] {
            let other = committed_twin(&dir, "waves-fig12", &whole(i_c, verdict));
            assert!(
                matches!(&other, Ok(Twin::Differs { what: w, .. }) if w.contains(what)),
                "{other:?}"
            );
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
