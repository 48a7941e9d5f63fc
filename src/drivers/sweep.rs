//! Parameter sweeps of the density spectrum (PH95 Figs. 8-10): a list of
//! points, each an ensemble of spectrum runs through the figure's ensemble
//! runner (saved per run, resumable, shardable with `--shard`), reduced to
//! alpha and the wave velocity v with their standard errors over runs.
//!
//! A run that leaves the model's domain of validity (more rest particles than
//! sites, or a stuck relocation walk: MODEL.md A4) is recorded as invalid
//! instead of stopping the sweep, so a sweep over rho can report where the
//! model ends. So is a run whose series cannot be measured (a
//! [`ErrorKind::BadSeries`]: constant or too short, e.g. no particle moves):
//! the point counts it as invalid, with the reason, and the sweep goes on.

use super::spectra::{bin_spectrum, combine, SpectrumEnsemble, SpectrumRun, SpectrumSetup};
use crate::analysis::grading::{Claim, Estimate};
use crate::error::{ErrorKind, Result};
use crate::pipe::{Params, Rules};
use crate::run::{mean_sem, Tier};
use serde::{Deserialize, Serialize};

/// One point of a sweep.
#[derive(Debug, Clone)]
pub struct SweepPoint {
    /// Unique name of the point (names its saved runs), e.g. `p0.05`.
    pub label: String,
    /// The swept parameter value(s), written as the first CSV columns.
    pub x: Vec<f64>,
    /// The pipe at this point.
    pub params: Params,
}

/// A run's outcome: a spectrum, or the reason the model became undefined.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub enum RunOutcome {
    /// The run finished; its spectrum and fit.
    Valid(SpectrumRun),
    /// The run stopped outside the model's validity (MODEL.md A4): the
    /// error message (rest particles exceed sites, or a stuck relocation).
    Invalid(String),
}

/// The reduced result of one sweep point.
#[derive(Debug, Clone)]
pub struct PointResult {
    /// The point.
    pub point: SweepPoint,
    /// Mean over valid runs of the per-run alpha (NaN if none is valid).
    pub alpha: f64,
    /// Standard error of that mean (the fit error for a single valid run).
    pub alpha_err: f64,
    /// Mean over valid runs of the per-run peak velocity v = L j / (T0 2m).
    pub v: f64,
    /// Standard error of that mean (0 for a single valid run).
    pub v_err: f64,
    /// Number of valid runs.
    pub valid: usize,
    /// Number of runs that left the model's domain of validity.
    pub invalid: usize,
    /// The combined ensemble of the valid runs (None if none is valid).
    pub ensemble: Option<SpectrumEnsemble>,
    /// At the acceptance tier, alpha and v of the averaged spectrum with
    /// their resampled SEs ([`Estimator::AveragedSpectrum`]); what the
    /// point is graded and plotted with when present.
    pub of_mean: Option<OfMean>,
}

/// alpha and v of a point's averaged spectrum, with their bootstrap SEs over
/// runs (`analysis::mean_spectrum`).
#[derive(Debug, Clone, Copy)]
pub struct OfMean {
    /// alpha of the averaged spectrum, bootstrap SE.
    pub alpha: Estimate,
    /// v of the peak of the averaged spectrum, bootstrap SE.
    pub v: Estimate,
}

/// How a sweep point's alpha and v are estimated for grading: one rule
/// per tier, fixed before the acceptance runs (EXPERIMENTS.md "Acceptance at
/// the published set-ups": chosen on PH94 Fig. 2's pilot, applied to every
/// spectrum ensemble graded at the acceptance tier).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Estimator {
    /// Mean of the per-run values, SE of their spread (quick, standard, paper).
    PerRun,
    /// alpha and v of the averaged spectrum, resampled SEs (acceptance).
    AveragedSpectrum,
}

impl Estimator {
    /// The estimator of `tier`.
    pub fn of_tier(tier: crate::run::Tier) -> Self {
        if tier.is_acceptance() {
            Estimator::AveragedSpectrum
        } else {
            Estimator::PerRun
        }
    }

    /// How the estimate is described in a check's note.
    pub fn describe(self) -> &'static str {
        match self {
            Estimator::PerRun => "per-run values, SEs combined",
            Estimator::AveragedSpectrum => {
                "averaged spectra: alpha and v bootstrap SEs over runs; SEs combined"
            }
        }
    }
}

impl PointResult {
    /// CSV row: the swept values, then alpha, alpha_err, v, v_err,
    /// alpha of the mean spectrum, v of its peak, valid and invalid runs.
    pub fn row(&self) -> Vec<f64> {
        let mut r = self.point.x.clone();
        let (a_mean, v_mean) = match &self.ensemble {
            Some(e) => (e.fit_of_mean.fit.alpha, e.v_peak),
            None => (f64::NAN, f64::NAN),
        };
        r.extend([
            self.alpha,
            self.alpha_err,
            self.v,
            self.v_err,
            a_mean,
            v_mean,
            self.valid as f64,
            self.invalid as f64,
        ]);
        r
    }
}

/// Header of [`PointResult::row`] after the swept columns `x_names`.
pub fn header<'a>(x_names: &[&'a str]) -> Vec<&'a str> {
    let mut h = x_names.to_vec();
    h.extend([
        "alpha",
        "alpha_err",
        "v",
        "v_err",
        "alpha_of_mean_spectrum",
        "v_of_mean_spectrum",
        "valid_runs",
        "invalid_runs",
    ]);
    h
}

pub use crate::pipe::is_validity_limit;

/// One run of a sweep point: the spectrum, or `Invalid` when the model
/// leaves its domain or the run's series cannot be measured
/// ([`ErrorKind::BadSeries`]); other errors (bad input, i/o) propagate.
pub fn sweep_run(
    setup: &SpectrumSetup,
    seed: u64,
    tick: &(dyn Fn(u64) + Sync),
) -> Result<RunOutcome> {
    match bin_spectrum(setup, seed, tick) {
        Ok(r) => Ok(RunOutcome::Valid(r)),
        Err(e) if is_validity_limit(e.kind) => Ok(RunOutcome::Invalid(e.message)),
        Err(e) if e.kind == ErrorKind::BadSeries => Ok(RunOutcome::Invalid(format!(
            "cannot be measured: {}",
            e.message
        ))),
        Err(e) => Err(e),
    }
}

/// Reduce the outcomes of one point; with [`Estimator::AveragedSpectrum`]
/// (and at least 3 valid runs) also the estimates of the averaged spectrum.
pub fn reduce(
    point: &SweepPoint,
    setup: &SpectrumSetup,
    outcomes: Vec<RunOutcome>,
    estimator: Estimator,
) -> Result<PointResult> {
    let mut valid = Vec::new();
    let mut invalid = 0;
    for o in outcomes {
        match o {
            RunOutcome::Valid(r) => valid.push(r),
            RunOutcome::Invalid(_) => invalid += 1,
        }
    }
    let n_valid = valid.len();
    if valid.is_empty() {
        return Ok(PointResult {
            point: point.clone(),
            alpha: f64::NAN,
            alpha_err: f64::NAN,
            v: f64::NAN,
            v_err: f64::NAN,
            valid: 0,
            invalid,
            ensemble: None,
            of_mean: None,
        });
    }
    let vs: Vec<f64> = valid.iter().map(|r| r.v_peak).collect();
    let (v, v_err) = mean_sem(&vs);
    let ens = combine(setup, valid)?;
    let of_mean = match estimator {
        Estimator::AveragedSpectrum if n_valid >= 3 => {
            use crate::analysis::mean_spectrum::{alpha_of_mean, v_of_mean};
            let rows = ens.spectra();
            Some(OfMean {
                alpha: alpha_of_mean(&rows)?,
                v: v_of_mean(&rows, setup.params.length, setup.t0)?,
            })
        }
        _ => None,
    };
    Ok(PointResult {
        point: point.clone(),
        alpha: ens.alpha,
        alpha_err: ens.alpha_err,
        v,
        v_err,
        valid: n_valid,
        invalid,
        ensemble: Some(ens),
        of_mean,
    })
}

/// Run every point of a sweep with `runs` runs each through the ensemble
/// runner of `binary` (one saved ensemble per point, named by its label;
/// `--shard` honoured). `setup_of(params)` gives the spectrum set-up of a
/// point (normally [`super::spectra::tier_setup`]). Returns `None` when only
/// a shard was computed.
pub fn run_sweep(
    common: &crate::cli::Common,
    binary: &str,
    points: &[SweepPoint],
    runs: usize,
    setup_of: impl Fn(Params) -> SpectrumSetup,
) -> Result<Option<Vec<PointResult>>> {
    let mut out = Vec::new();
    let mut sharded = false;
    for (k, point) in points.iter().enumerate() {
        let setup = setup_of(point.params);
        eprintln!(
            "{binary}: point {}/{} ({}), {runs} runs of {} steps",
            k + 1,
            points.len(),
            point.label,
            setup.steps()
        );
        match sweep_point(common, binary, point, runs, &setup)? {
            Some(r) => out.push(r),
            None => sharded = true,
        }
    }
    if sharded {
        println!(
            "{binary}: shard done; merge the shard folders with the `merge` binary, then rerun without --shard"
        );
        return Ok(None);
    }
    Ok(Some(out))
}

/// The first `runs` runs of one sweep point through the ensemble runner of
/// `binary` (saved, resumed; named by the point's label), reduced; `None`
/// when only a shard was computed (said on stdout).
pub fn sweep_point(
    common: &crate::cli::Common,
    binary: &str,
    point: &SweepPoint,
    runs: usize,
    setup: &SpectrumSetup,
) -> Result<Option<PointResult>> {
    noted_point(common, binary, point, runs, setup, "")
}

/// [`sweep_point`] whose progress bar shows `note` before its run count (a
/// sequential design's look and open claims).
pub fn noted_point(
    common: &crate::cli::Common,
    binary: &str,
    point: &SweepPoint,
    runs: usize,
    setup: &SpectrumSetup,
    note: &str,
) -> Result<Option<PointResult>> {
    use crate::ensemble::Outcome;
    let key = serde_json::json!({"sweep-point": point.label, "spectrum": setup});
    let ens = common.ensemble(binary, &key, runs)?.note(note);
    match ens.run(setup.steps(), |_, seed, tick| sweep_run(setup, seed, tick))? {
        Outcome::Complete(v) => reduce(point, setup, v, Estimator::of_tier(common.tier)).map(Some),
        Outcome::ShardDone { shard, runs, dir } => {
            println!(
                "{binary} {}: shard {shard} done, {runs} runs in {}",
                point.label,
                dir.display()
            );
            Ok(None)
        }
    }
}

/// A sweep graded sequentially, point by point: at each look of `design`
/// every point still open gets its runs up to the look (`run_point(point,
/// n)`, resuming the earlier ones; `None` stops everything, e.g. a shard),
/// the checks are computed from all points (`checks_of`), and each check
/// with a claim that is decided at this look (its own boundary k_j), or
/// reaches the last look, is frozen with where it stopped. A point stays
/// open while an open check is computed from it (a check that names no
/// points holds every point open). Returns the points' last results and
/// the checks: the frozen ones as they stopped, the others (exact counts,
/// identities) from the last results.
pub fn sweep_looks(
    design: &crate::analysis::sequential::Design,
    points: &[SweepPoint],
    mut run_point: impl FnMut(&SweepPoint, usize, &str) -> Result<Option<PointResult>>,
    checks_of: impl Fn(&[PointResult]) -> Vec<crate::run::Check>,
) -> Result<Option<(Vec<PointResult>, Vec<crate::run::Check>)>> {
    use crate::analysis::grading::{Estimate, Verdict};
    use crate::analysis::sequential::Stop;
    let mut results: Vec<Option<PointResult>> = vec![None; points.len()];
    let mut open = vec![true; points.len()];
    let mut frozen: Vec<crate::run::Check> = Vec::new();
    // claims still open and in all (unknown before the first look)
    let mut claims: Option<(usize, usize)> = None;
    let last = design.looks.len() - 1;
    for (j, &n) in design.looks.iter().enumerate() {
        let points_open = open.iter().filter(|&&o| o).count();
        let note = format!(
            "look {} of {}, {points_open} of {} points, {} open",
            j + 1,
            design.looks.len(),
            points.len(),
            claims.map_or("all claims".to_string(), |(o, a)| format!(
                "{o} of {a} claims"
            ))
        );
        for (k, point) in points.iter().enumerate() {
            if open[k] {
                let Some(r) = run_point(point, n, &format!("{note}, {}", point.label))? else {
                    return Ok(None);
                };
                results[k] = Some(r);
            }
        }
        let now: Vec<PointResult> = results.iter().flatten().cloned().collect();
        let checks = checks_of(&now);
        let mut still_open = Vec::new();
        for c in checks.into_iter().filter(|c| c.claim.is_some()) {
            if frozen.iter().any(|f| f.name == c.name) {
                continue;
            }
            let k = design.boundaries[j];
            let c = c.regraded(k);
            if c.verdict == Verdict::Undecided && j < last {
                still_open.push(c);
                continue;
            }
            let stop = Stop {
                look: j,
                runs: c.runs,
                boundary: k,
                verdict: c.verdict,
                estimate: Estimate::new(c.measured, c.error, c.runs),
            };
            let note = super::acceptance::stop_note(design, &stop, c.claim.expect("has a claim"));
            let mut c = c.stopped(design, &stop);
            c.note.push_str(&format!("; {note}"));
            frozen.push(c);
        }
        claims = Some((still_open.len(), still_open.len() + frozen.len()));
        for (k, point) in points.iter().enumerate() {
            open[k] = still_open
                .iter()
                .any(|c| c.points.is_empty() || c.points.contains(&point.label));
        }
        if !open.iter().any(|&o| o) {
            break;
        }
    }
    let now: Vec<PointResult> = results.into_iter().flatten().collect();
    let checks = checks_of(&now)
        .into_iter()
        .map(|c| match frozen.iter().position(|f| f.name == c.name) {
            Some(i) => frozen[i].clone(),
            None => c,
        })
        .collect();
    Ok(Some((now, checks)))
}

/// The runs per point of `results` for a chart title: `128 runs/point`, or
/// `16-128 runs/point (sequential)` where points stopped at different looks.
pub fn runs_per_point(results: &[PointResult]) -> String {
    let runs = results.iter().map(|r| r.valid + r.invalid);
    let (lo, hi) = (runs.clone().min().unwrap_or(0), runs.max().unwrap_or(0));
    if lo == hi {
        format!("{hi} runs/point")
    } else {
        format!("{lo}-{hi} runs/point (sequential)")
    }
}

/// Site updates of a sweep's results: each point's own runs (a sequential
/// sweep stops points at different looks) x steps x sites.
pub fn results_site_updates(
    results: &[PointResult],
    setup_of: impl Fn(Params) -> SpectrumSetup,
) -> f64 {
    results
        .iter()
        .map(|r| {
            let runs = (r.valid + r.invalid) as u64;
            (runs * setup_of(r.point.params).steps() * r.point.params.sites() as u64) as f64
        })
        .sum()
}

/// One curve of a sweep plot: a label and the points, with the index of the
/// swept value in [`SweepPoint::x`] used as abscissa.
#[derive(Debug, Clone, Copy)]
pub struct Curve<'a> {
    /// Legend label.
    pub label: &'a str,
    /// The points of the curve.
    pub points: &'a [&'a PointResult],
    /// Which entry of `x` is the abscissa.
    pub xi: usize,
}

/// What a sweep chart shows on its vertical axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// alpha, mean over runs with its standard error.
    Alpha,
    /// The wave velocity from the spectral peak, mean over runs with its SE.
    V,
}

impl Quantity {
    /// `alpha` or `v` (the suffix of the PNG names of [`plot_alpha_v`]).
    pub fn name(self) -> &'static str {
        match self {
            Quantity::Alpha => "alpha",
            Quantity::V => "v",
        }
    }

    /// The axis label for points graded with `estimator`.
    pub fn label(self, estimator: Estimator) -> &'static str {
        match (self, estimator) {
            (Quantity::Alpha, Estimator::PerRun) => "alpha (mean over runs +- SE)",
            (Quantity::Alpha, Estimator::AveragedSpectrum) => {
                "alpha (fit of the averaged spectrum +- bootstrap SE)"
            }
            (Quantity::V, Estimator::PerRun) => "v from the spectral peak, rows/step (mean +- SE)",
            (Quantity::V, Estimator::AveragedSpectrum) => {
                "v from the peak of the averaged spectrum, rows/step (+- bootstrap SE)"
            }
        }
    }

    /// (value, standard error) of a point, as graded.
    pub fn of(self, r: &PointResult) -> (f64, f64) {
        let e = r.estimate(self);
        (e.mean, e.se)
    }
}

/// Plot `q` against the swept parameter with error bars (one standard error
/// over runs), one series per curve in the palette's order, to `path`; the
/// legend at `legend`, or with `None` in the corner hiding the fewest points.
///
/// The published claims among `checks` that are drawn ([`crate::run::Drawn`])
/// about `q` at points of the curves go on the chart too: bands of the values
/// they allow, and claims without a number in the legend.
pub fn sweep_chart(
    path: &std::path::Path,
    title: &str,
    xlabel: &str,
    q: Quantity,
    curves: &[Curve],
    checks: &[crate::run::Check],
    legend: Option<plotters::chart::SeriesLabelPosition>,
) -> Result<()> {
    use crate::plot::{errorbar_chart_marked, free_corner_rows, ErrSeries, PALETTE};
    let series: Vec<ErrSeries> = curves
        .iter()
        .enumerate()
        .map(|(c, cv)| {
            let pts = cv
                .points
                .iter()
                .map(|r| {
                    let (y, e) = q.of(r);
                    (r.point.x[cv.xi], y, e)
                })
                .collect();
            ErrSeries::new(cv.label, pts, PALETTE[c % PALETTE.len()])
        })
        .collect();
    let marks = chart_marks(q, curves, checks);
    let legend = legend.unwrap_or_else(|| free_corner_rows(&series, series.len() + marks.rows()));
    let estimator = curves
        .iter()
        .flat_map(|cv| cv.points.first())
        .map(|r| r.estimator())
        .next()
        .unwrap_or(Estimator::PerRun);
    let ylabel = q.label(estimator);
    errorbar_chart_marked(path, title, xlabel, ylabel, &series, &marks, legend)
}

/// The drawn claims of `checks` about `q` whose points are on `curves`: the
/// bands grouped by their legend words (in order of first appearance), each
/// at its point's x; the notes whose points are all on the chart.
pub fn chart_marks(
    q: Quantity,
    curves: &[Curve],
    checks: &[crate::run::Check],
) -> crate::plot::Marks {
    use crate::run::Drawn;
    let x_of = |label: &str| {
        curves.iter().find_map(|cv| {
            cv.points
                .iter()
                .find(|r| r.point.label == label)
                .map(|r| r.point.x[cv.xi])
        })
    };
    let mut marks = crate::plot::Marks::default();
    for d in checks.iter().filter_map(|c| c.drawn.as_ref()) {
        if d.quantity() != q.name() {
            continue;
        }
        match d {
            Drawn::Band {
                point,
                lo,
                hi,
                label,
                ..
            } => {
                let Some(x) = x_of(point) else { continue };
                match marks.bands.iter_mut().find(|(l, _)| l == label) {
                    Some((_, boxes)) => boxes.push((x, *lo, *hi)),
                    None => marks.bands.push((label.clone(), vec![(x, *lo, *hi)])),
                }
            }
            Drawn::Note { points, label, .. } => {
                if points.iter().all(|p| x_of(p).is_some()) && !marks.notes.contains(label) {
                    marks.notes.push(label.clone());
                }
            }
        }
    }
    marks
}

/// A point's label in words: `b0.5_g0.2` -> `b = 0.5, g = 0.2`.
pub fn point_words(label: &str) -> String {
    label
        .split('_')
        .map(|part| {
            let at = part
                .find(|c: char| c.is_ascii_digit() || c == '-')
                .unwrap_or(part.len());
            let (name, value) = part.split_at(at);
            if name.is_empty() || value.is_empty() {
                part.to_string()
            } else {
                format!("{name} = {value}")
            }
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// Plot alpha (`<stem>_alpha.png`) and v (`<stem>_v.png`) against the swept
/// parameter with error bars (one standard error over runs), with the drawn
/// claims of `checks` ([`sweep_chart`]).
pub fn plot_alpha_v(
    out: &crate::run::Output,
    stem: &str,
    title: &str,
    xlabel: &str,
    curves: &[Curve],
    checks: &[crate::run::Check],
) -> Result<()> {
    for q in [Quantity::Alpha, Quantity::V] {
        sweep_chart(
            &out.path(&format!("{stem}_{}.png", q.name())),
            &format!("{title}: {}", q.name()),
            xlabel,
            q,
            curves,
            checks,
            None,
        )?;
    }
    Ok(())
}

/// Metrics of a point: `alpha_<label>`, `alpha_<label>_err`, `v_<label>`,
/// `v_<label>_err` (per-run values), those of the averaged spectrum when it
/// is graded (`alpha_of_mean_<label>`, `..._bootstrap_se`, `v_of_mean_<label>`,
/// `..._bootstrap_se`), and `invalid_<label>` when any run was invalid.
pub fn point_metrics(r: &PointResult, m: &mut std::collections::BTreeMap<String, f64>) {
    let l = &r.point.label;
    m.insert(format!("alpha_{l}"), r.alpha);
    m.insert(format!("alpha_{l}_err"), r.alpha_err);
    m.insert(format!("v_{l}"), r.v);
    m.insert(format!("v_{l}_err"), r.v_err);
    if let Some(o) = r.of_mean {
        m.insert(format!("alpha_of_mean_{l}"), o.alpha.mean);
        m.insert(format!("alpha_of_mean_{l}_bootstrap_se"), o.alpha.se);
        m.insert(format!("v_of_mean_{l}"), o.v.mean);
        m.insert(format!("v_of_mean_{l}_bootstrap_se"), o.v.se);
    }
    if r.invalid > 0 {
        m.insert(format!("invalid_runs_{l}"), r.invalid as f64);
    }
}

/// One of PH95 Fig. 7's two set-ups, the reference points of the sweeps'
/// pinned consistency checks (Fig. 8 at p = 0, Fig. 10 at b = 0).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fig7Case {
    /// p = 0, b = 0.5 (PH95 Fig. 7, dashed).
    P0,
    /// b = 0, p = 0.5 (PH95 Fig. 7, solid).
    B0,
}

/// alpha at a PH95 Fig. 7 set-up as `waves-fig7` measured it at one tier
/// (default reading `ph94+gravity-first+wall-move+inject-late`, EXPERIMENTS.md
/// "The sweeps' Fig. 7 references by tier").
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fig7Reference {
    /// alpha.
    pub alpha: f64,
    /// Its standard error.
    pub se: f64,
    /// How it was measured (tier, seeds, runs).
    pub measured: &'static str,
}

/// The reference of a sweep's pinned check at `tier`: `waves-fig7` at the
/// same tier, so that the sweep point and its reference share the set-up
/// (spectrum length m) and the estimator of alpha (the mean of per-run fits,
/// or at the acceptance tier the fit of the averaged spectrum). Until
/// 2026-12-06 every tier used the quick tier's values; at the acceptance
/// tier that compared Fig. 10's b = 0 point (-3.33) with -3.02 and failed
/// for the set-up, not the model.
pub fn fig7_reference(tier: Tier, case: Fig7Case) -> Fig7Reference {
    let (p0, b0, measured) = match tier {
        Tier::Quick => (
            (-0.6019, 0.0217),
            (-3.0229, 0.0966),
            "quick tier, seed 1, 4 runs, default reading",
        ),
        Tier::Standard => (
            (-0.6223, 0.0127),
            (-3.3002, 0.0167),
            "standard tier, seed 1, 8 runs, default reading",
        ),
        Tier::Paper => (
            (-0.6101, 0.0097),
            (-3.3484, 0.0398),
            "paper tier, seed 1, 8 runs, default reading",
        ),
        Tier::Acceptance => (
            (-0.6324, 0.0100),
            (-3.3118, 0.0125),
            "acceptance tier, the mean of its 20 committed seed sets of 8 runs with the SE of their spread, default reading",
        ),
    };
    let (alpha, se) = match case {
        Fig7Case::P0 => p0,
        Fig7Case::B0 => b0,
    };
    Fig7Reference {
        alpha,
        se,
        measured,
    }
}

/// Margin Delta of the pinned alpha checks of the sweeps: the alpha margin
/// of the matrix ([`super::margins::ALPHA_MARGIN`]), fixed before measuring.
pub const PINNED_ALPHA_MARGIN: f64 = super::margins::ALPHA_MARGIN;

impl PointResult {
    /// A point of `n` valid runs with per-run alpha spread `sigma` around
    /// `alpha` (v = 0.4 +- 0.01): the stand-in of the sequential tests.
    #[cfg(test)]
    pub fn of_alpha(point: &SweepPoint, alpha: f64, sigma: f64, n: usize) -> Self {
        PointResult {
            point: point.clone(),
            alpha,
            alpha_err: sigma / (n as f64).sqrt(),
            v: 0.4,
            v_err: 0.01,
            valid: n,
            invalid: 0,
            ensemble: None,
            of_mean: None,
        }
    }

    /// [`sweep_looks`] of `design` over `points` whose runs stand in as
    /// [`PointResult::of_alpha`] with alpha `alpha(label)` and spread
    /// `sigma`, graded by `checks_of`: the results, the checks, and every
    /// point and count of runs asked for, in order.
    #[cfg(test)]
    pub fn looks_of_alpha(
        design: &crate::analysis::sequential::Design,
        points: &[SweepPoint],
        alpha: impl Fn(&str) -> f64,
        sigma: f64,
        checks_of: impl Fn(&[PointResult]) -> Vec<crate::run::Check>,
    ) -> (
        Vec<PointResult>,
        Vec<crate::run::Check>,
        Vec<(String, usize)>,
    ) {
        let mut asked = Vec::new();
        let run_point = |p: &SweepPoint, n, _: &str| {
            asked.push((p.label.clone(), n));
            Ok(Some(PointResult::of_alpha(p, alpha(&p.label), sigma, n)))
        };
        let (results, checks) = sweep_looks(design, points, run_point, checks_of)
            .unwrap()
            .unwrap();
        (results, checks, asked)
    }

    /// alpha as graded: of the averaged spectrum when [`PointResult::of_mean`]
    /// is present, else the per-run alpha of the valid runs.
    pub fn alpha_estimate(&self) -> Estimate {
        self.estimate(Quantity::Alpha)
    }

    /// v as graded (see [`PointResult::alpha_estimate`]).
    pub fn v_estimate(&self) -> Estimate {
        self.estimate(Quantity::V)
    }

    /// `q` as graded (see [`PointResult::alpha_estimate`]).
    pub fn estimate(&self, q: Quantity) -> Estimate {
        match (q, self.of_mean) {
            (Quantity::Alpha, Some(m)) => m.alpha,
            (Quantity::V, Some(m)) => m.v,
            (Quantity::Alpha, None) => Estimate::new(self.alpha, self.alpha_err, self.valid),
            (Quantity::V, None) => Estimate::new(self.v, self.v_err, self.valid),
        }
    }

    /// The estimator this point is graded with.
    pub fn estimator(&self) -> Estimator {
        match self.of_mean {
            Some(_) => Estimator::AveragedSpectrum,
            None => Estimator::PerRun,
        }
    }
}

/// A regression guard (kind `pinned`): alpha at a sweep point equals a
/// `waves-fig7` reference value within [`PINNED_ALPHA_MARGIN`], graded by the
/// one rule with the SEs of point and reference combined. The reference is
/// `waves-fig7` at the sweep's tier ([`fig7_reference`]), so the check
/// compares one set-up reached by two figures.
pub fn fig7_check(
    name: &str,
    r: &PointResult,
    reference: Fig7Reference,
    what: &str,
) -> crate::run::Check {
    let est = r.alpha_estimate();
    let combined = Estimate::new(est.mean, est.se.hypot(reference.se), est.n);
    crate::run::Check::pinned(
        name,
        &format!(
            "waves-fig7 alpha at {what}: {:.4} +- {:.4} ({})",
            reference.alpha, reference.se, reference.measured
        ),
        combined,
        Claim::Within {
            target: reference.alpha,
            margin: PINNED_ALPHA_MARGIN,
        },
        &format!("internal consistency: alpha at {what} against waves-fig7; error = SE of the point and of the reference combined"),
    )
    .on_points(vec![r.point.label.clone()])
}

/// A published claim "`q` at point `r` equals `q` at `reference`" (PH95
/// Fig. 8: alpha constant for every p > 0, v independent of p): the
/// difference of the two points (SEs in quadrature) within `margin` of 0;
/// `derivation` (empty, or starting with "; ") is appended to the note.
pub fn same_as_check(
    name: &str,
    source: &str,
    q: Quantity,
    r: &PointResult,
    reference: &PointResult,
    margin: f64,
    derivation: &str,
) -> crate::run::Check {
    let centre = reference.estimate(q).mean;
    crate::run::Check::published(
        name,
        source,
        r.estimate(q).minus(reference.estimate(q)),
        Claim::Within {
            target: 0.0,
            margin,
        },
        &format!(
            "{}({}) - {}({}) within Delta = {margin} of 0 ({}){derivation}",
            q.name(),
            r.point.label,
            q.name(),
            reference.point.label,
            r.estimator().describe()
        ),
    )
    .drawn(crate::run::Drawn::Band {
        quantity: q.name(),
        point: r.point.label.clone(),
        lo: centre - margin,
        hi: centre + margin,
        label: format!(
            "published: as at {} (+- Delta)",
            point_words(&reference.point.label)
        ),
    })
    .on_points(vec![r.point.label.clone(), reference.point.label.clone()])
}

/// A published value of alpha at a point: the per-run alpha of its valid
/// runs within `margin` of `target` (e.g. PH95 Fig. 12: 1/f at I_c, alpha =
/// 1; white elsewhere, alpha = 0).
pub fn alpha_check(
    name: &str,
    source: &str,
    r: &PointResult,
    target: f64,
    margin: f64,
) -> crate::run::Check {
    crate::run::Check::published(
        name,
        source,
        r.alpha_estimate(),
        Claim::Within { target, margin },
        &format!(
            "alpha at {} over {} valid runs ({} invalid) within Delta = {margin} of {target}",
            r.point.label, r.valid, r.invalid
        ),
    )
    .drawn(crate::run::Drawn::Band {
        quantity: Quantity::Alpha.name(),
        point: r.point.label.clone(),
        lo: target - margin,
        hi: target + margin,
        label: format!("published: alpha = {target} +- {margin}"),
    })
    .on_points(vec![r.point.label.clone()])
}

/// The dissipation values of PH95 Fig. 8 at the paper and acceptance tiers
/// (the published figure's points).
pub const FIG8_P: [f64; 13] = [
    0.0, 0.02, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0,
];

/// The points of a one-parameter sweep: for each value v, the label
/// `<name><v>` (e.g. `p0.05`), x = `[v]` and the pipe `set(v)`.
pub fn points_1d(name: &str, values: &[f64], set: impl Fn(f64) -> Params) -> Vec<SweepPoint> {
    values
        .iter()
        .map(|&v| SweepPoint {
            label: format!("{name}{v}"),
            x: vec![v],
            params: set(v),
        })
        .collect()
}

/// Check that alpha rises from the point `lo` (named `lo_at`, e.g.
/// `p = 0`) to `hi`: the difference alpha(hi) - alpha(lo) is above 0 by the
/// one grading rule (PH95 Figs. 2 and 7: alpha ~4/3 with dissipation and
/// roughness, ~0 without).
pub fn rise_check(
    name: &str,
    lo: &PointResult,
    hi: &PointResult,
    lo_at: &str,
    hi_at: &str,
) -> crate::run::Check {
    crate::run::Check::published(
        name,
        "PH95 Figs. 2, 7 (alpha ~4/3 at p = b = 0.5, white noise at p = 0 or b = 0)",
        hi.alpha_estimate().minus(lo.alpha_estimate()),
        Claim::Above { threshold: 0.0 },
        &format!("alpha({hi_at}) - alpha({lo_at}) > 0"),
    )
    .drawn(crate::run::Drawn::Note {
        quantity: Quantity::Alpha.name(),
        points: vec![lo.point.label.clone(), hi.point.label.clone()],
        label: format!("published: alpha({hi_at}) > alpha({lo_at})"),
    })
    .on_points(vec![lo.point.label.clone(), hi.point.label.clone()])
}

/// A sweep figure (PH95 Figs. 8-10) after its runs: the figure (name, paper,
/// clock), the options, every point's result and the output folder. Made by
/// [`SweepFigure::run`]; the binary writes its CSVs and plots through it and
/// ends with [`SweepFigure::finish`].
pub struct SweepFigure<'a> {
    /// The figure: binary name (also the output folder), paper, tier, rules.
    pub figure: crate::run::Figure,
    /// The command-line options.
    pub args: &'a crate::cli::PipeArgs,
    /// The parsed rule reading.
    pub rules: Rules,
    /// The engine that runs it (`--engine`).
    pub engine: crate::pipe::Engine,
    /// Runs per point.
    pub runs: usize,
    /// The points, in order.
    pub points: Vec<SweepPoint>,
    /// The result of each point, in the order of `points`.
    pub results: Vec<PointResult>,
    /// The output folder `OUT/<binary>/`.
    pub out: crate::run::Output,
}

impl<'a> SweepFigure<'a> {
    /// Run every point of figure `binary` (reproducing `paper`) with
    /// `--runs` runs (default by tier: quick 2, standard 8, paper 32,
    /// acceptance [`super::acceptance::sweep_runs`]),
    /// spectra of the tier's set-up ([`super::spectra::tier_setup`]),
    /// through [`run_sweep`]. `None` when only a shard was computed.
    pub fn run(
        binary: &'static str,
        paper: &'static str,
        args: &'a crate::cli::PipeArgs,
        points: Vec<SweepPoint>,
    ) -> Result<Option<Self>> {
        let fig = SweepFigure::started(binary, paper, args, points, |c, setup_of, points| {
            let runs = c.runs_for(2, 8, 32, super::acceptance::sweep_runs(binary));
            let results = run_sweep(c, binary, points, runs, setup_of)?;
            Ok(results.map(|results| (results, runs, ())))
        })?;
        Ok(fig.map(|(fig, ())| fig))
    }

    /// [`SweepFigure::run`] with the figure's checks: `checks_of` computes
    /// them from the points' results. At the acceptance tier, unless a count
    /// is fixed, the points run look by look until their checks are decided
    /// ([`sweep_looks`], the acceptance tier's design for the figure's fixed
    /// count); otherwise every point runs the fixed count and the checks are
    /// computed once.
    pub fn run_graded(
        binary: &'static str,
        paper: &'static str,
        args: &'a crate::cli::SequentialArgs,
        points: Vec<SweepPoint>,
        checks_of: impl Fn(&[PointResult]) -> Vec<crate::run::Check>,
    ) -> Result<Option<(Self, Vec<crate::run::Check>)>> {
        let sequential = args.sequential()?;
        if !sequential {
            let Some(fig) = SweepFigure::run(binary, paper, &args.pipe, points)? else {
                return Ok(None);
            };
            let checks = checks_of(&fig.results);
            return Ok(Some((fig, checks)));
        }
        SweepFigure::started(binary, paper, &args.pipe, points, |c, setup_of, points| {
            let design = super::acceptance::design(
                super::acceptance::sweep_runs(binary),
                args.sequential_max,
            )?;
            let looks = sweep_looks(
                &design,
                points,
                |point, n, note| {
                    let setup = setup_of(point.params);
                    noted_point(c, binary, point, n, &setup, note)
                },
                &checks_of,
            )?;
            Ok(looks.map(|(results, checks)| {
                let runs = results
                    .iter()
                    .map(|r| r.valid + r.invalid)
                    .max()
                    .unwrap_or(0);
                (results, runs, checks)
            }))
        })
    }

    /// Starts figure `binary` (reproducing `paper`) and has `results_of`
    /// run its points, given the common options and the spectrum set-up of
    /// a pipe at the figure's tier and rules: the points' results, the runs
    /// per point and whatever else it computed, or `None` when only a shard
    /// was computed.
    fn started<T>(
        binary: &'static str,
        paper: &'static str,
        args: &'a crate::cli::PipeArgs,
        points: Vec<SweepPoint>,
        results_of: impl FnOnce(
            &crate::cli::Common,
            &dyn Fn(Params) -> SpectrumSetup,
            &[SweepPoint],
        ) -> Result<Option<(Vec<PointResult>, usize, T)>>,
    ) -> Result<Option<(Self, T)>> {
        let (figure, rules, engine, c) = args.rules.start(&args.common, binary, paper)?;
        let setup_of = |p| super::spectra::tier_setup(c.tier, p, rules, engine);
        let Some((results, runs, other)) = results_of(c, &setup_of, &points)? else {
            return Ok(None);
        };
        let out = figure.output(&c.out)?;
        let fig = SweepFigure {
            figure,
            args,
            rules,
            engine,
            runs,
            points,
            results,
            out,
        };
        Ok(Some((fig, other)))
    }

    /// The spectrum set-up of a pipe at this figure's tier and rules.
    pub fn setup_of(&self, params: Params) -> SpectrumSetup {
        super::spectra::tier_setup(self.args.common.tier, params, self.rules, self.engine)
    }

    /// The runs per point for a chart title: `128 runs/point`, or
    /// `16-128 runs/point (sequential)` where points stopped at different
    /// looks.
    pub fn runs_per_point(&self) -> String {
        runs_per_point(&self.results)
    }

    /// Every result, in point order.
    pub fn all(&self) -> Vec<&PointResult> {
        self.results.iter().collect()
    }

    /// The result of the point labelled `label` (panics if there is none:
    /// the binary asks only for points it made).
    pub fn find(&self, label: &str) -> &PointResult {
        self.results
            .iter()
            .find(|r| r.point.label == label)
            .unwrap_or_else(|| panic!("{}: no sweep point {label}", self.figure.binary))
    }

    /// Write `name` with the swept columns `x_names` and one row per result
    /// ([`PointResult::row`], [`header`]).
    pub fn write_csv(&self, name: &str, x_names: &[&str], results: &[&PointResult]) -> Result<()> {
        let rows: Vec<Vec<f64>> = results.iter().map(|r| r.row()).collect();
        self.out.write_csv(name, &header(x_names), &rows)?;
        Ok(())
    }

    /// The metrics of every point ([`point_metrics`]).
    pub fn metrics(&self) -> std::collections::BTreeMap<String, f64> {
        let mut m = std::collections::BTreeMap::new();
        for r in &self.results {
            point_metrics(r, &mut m);
        }
        m
    }

    /// Write `summary.json` (seeds and site updates of every point added
    /// here; `params` as given) and print the checks.
    pub fn finish(
        &self,
        params: serde_json::Value,
        metrics: std::collections::BTreeMap<String, f64>,
        checks: Vec<crate::run::Check>,
    ) -> Result<()> {
        let seed = self.args.common.seed;
        let updates = results_site_updates(&self.results, |p| self.setup_of(p));
        self.figure.finish(
            &self.out,
            crate::run::run_seeds(seed, self.runs),
            params,
            updates,
            metrics,
            checks,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drivers::spectra::tier_setup;
    use crate::run::Tier;

    #[test]
    fn invalid_runs_are_counted_not_fatal() {
        let params = Params::default();
        let setup = tier_setup(
            Tier::Quick,
            params,
            Rules::default(),
            crate::pipe::Engine::Reference,
        );
        let point = SweepPoint {
            label: "x".into(),
            x: vec![1.0],
            params,
        };
        let r = reduce(
            &point,
            &setup,
            vec![
                RunOutcome::Invalid("rest".into()),
                RunOutcome::Invalid("rest".into()),
            ],
            Estimator::AveragedSpectrum,
        )
        .unwrap();
        assert_eq!((r.valid, r.invalid), (0, 2));
        assert!(r.alpha.is_nan() && r.ensemble.is_none());
        assert_eq!(r.row().len(), 1 + 8);
        assert_eq!(header(&["rho"]).len(), 9);
    }

    #[test]
    fn a_run_that_cannot_be_measured_is_invalid_not_fatal() {
        // one bin of a periodic pipe: its count is the conserved particle
        // number, a constant series with no spectrum (BadSeries)
        let params = Params {
            width: 1,
            length: 10,
            bin: 10,
            ..Params::default()
        };
        let setup = tier_setup(
            Tier::Quick,
            params,
            Rules::default(),
            crate::pipe::Engine::Reference,
        );
        match sweep_run(&setup, 1, &|_| {}).unwrap() {
            RunOutcome::Invalid(why) => assert!(why.contains("cannot be measured"), "{why}"),
            RunOutcome::Valid(r) => panic!("a constant series gave alpha = {}", r.alpha),
        }
    }

    #[test]
    fn published_claims_are_drawn_at_their_points() {
        assert_eq!(point_words("b0.5_g0.2"), "b = 0.5, g = 0.2");
        assert_eq!(point_words("I0.5_lower_end"), "I = 0.5, lower, end");
        let point = |label: &str, x: f64, alpha: f64| PointResult {
            point: SweepPoint {
                label: label.into(),
                x: vec![x],
                params: Params::default(),
            },
            alpha,
            alpha_err: 0.01,
            v: 0.4,
            v_err: 0.01,
            valid: 4,
            invalid: 0,
            ensemble: None,
            of_mean: None,
        };
        let (r, reference, off) = (
            point("p0.2", 0.2, 0.5),
            point("p0.5", 0.5, 1.3),
            point("p9", 9.0, 1.0),
        );
        let checks = [
            same_as_check("a", "s", Quantity::Alpha, &r, &reference, 0.1, ""),
            alpha_check("b", "s", &reference, 1.33, 0.05),
            // a point that is not on the chart draws nothing
            alpha_check("c", "s", &off, 0.0, 0.1),
            rise_check("d", &r, &reference, "p = 0.2", "p = 0.5"),
        ];
        let pts = [&r, &reference];
        let curve = [Curve {
            label: "c",
            points: &pts,
            xi: 0,
        }];
        let marks = chart_marks(Quantity::Alpha, &curve, &checks);
        assert_eq!(marks.bands.len(), 2, "{marks:?}");
        let (label, boxes) = &marks.bands[0];
        assert!(label.contains("as at p = 0.5"), "{label}");
        assert_eq!(boxes.len(), 1);
        let (x, lo, hi) = boxes[0];
        assert_eq!(x, 0.2);
        assert!((lo - 1.2).abs() < 1e-12 && (hi - 1.4).abs() < 1e-12);
        assert_eq!(marks.bands[1].1, vec![(0.5, 1.33 - 0.05, 1.33 + 0.05)]);
        assert_eq!(
            marks.notes,
            vec!["published: alpha(p = 0.5) > alpha(p = 0.2)".to_string()]
        );
        // nothing about v was claimed
        assert_eq!(chart_marks(Quantity::V, &curve, &checks).rows(), 0);
    }

    #[test]
    fn a_sequential_sweep_stops_the_points_whose_claims_are_decided() {
        let design = crate::analysis::sequential::Design::doubling(
            16,
            128,
            0.025,
            crate::analysis::sequential::Spending::Pocock,
        )
        .unwrap();
        let point = |label: &str, x: f64| SweepPoint {
            label: label.into(),
            x: vec![x],
            params: Params::default(),
        };
        let points = [
            point("p0.5", 0.5),
            point("p0.2", 0.2),
            point("p0.9", 0.9),
            point("p1", 1.0),
        ];
        // alpha per point; one run has spread 0.2
        let truth = |label: &str| match label {
            "p0.2" => 1.3, // the same as the reference: decided early
            "p0.9" => 1.4, // on the margin's edge (0.1): runs to the end
            "p1" => 3.0,   // far off: decided not reproduced at once
            _ => 1.3,
        };
        let (results, checks, asked) =
            PointResult::looks_of_alpha(&design, &points, truth, 0.2, |rs| {
                let reference = rs.iter().find(|r| r.point.label == "p0.5").unwrap();
                rs.iter()
                    .filter(|r| r.point.label != "p0.5")
                    .map(|r| {
                        same_as_check(
                            &format!("a_{}", r.point.label),
                            "s",
                            Quantity::Alpha,
                            r,
                            reference,
                            0.1,
                            "",
                        )
                    })
                    .collect()
            });
        let last = |label: &str| {
            asked
                .iter()
                .filter(|(l, _)| l == label)
                .map(|a| a.1)
                .max()
                .unwrap()
        };
        assert_eq!(last("p0.9"), 128);
        assert_eq!(last("p0.5"), 128, "the reference serves the open claim");
        assert!(last("p0.2") < 128, "{asked:?}");
        assert_eq!(last("p1"), 16);
        assert_eq!(results.len(), 4);
        let by = |n: &str| checks.iter().find(|c| c.name == n).unwrap();
        use crate::analysis::grading::Verdict;
        assert_eq!(by("a_p0.2").verdict, Verdict::Reproduced);
        assert_eq!(by("a_p1").verdict, Verdict::NotReproduced);
        assert_eq!(by("a_p0.9").sequential.as_ref().unwrap().runs, 128);
        assert!(
            by("a_p1").note.contains("stopped at look 1 of 4"),
            "{}",
            by("a_p1").note
        );
    }

    #[test]
    fn validity_errors_are_classified() {
        assert!(is_validity_limit(ErrorKind::RestExceedsSites));
        assert!(is_validity_limit(ErrorKind::RelocationStuck));
        assert!(!is_validity_limit(ErrorKind::InvalidParameter));
    }
}
