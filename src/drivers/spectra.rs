//! Density spectra of the pipe (MODEL.md A9; PH94 Fig. 2, PH95 Figs. 6-7):
//! the particle count of one bin recorded every T0 steps, its NR-1988
//! spectrum, the exponent alpha over the fit range with the peak removed, and
//! the wave velocity from the peak; per run and over an ensemble of runs.

use crate::analysis::fit::{estimate_alpha, wave_velocity, AlphaEstimate};
use crate::analysis::grading::{Claim, Estimate};
use crate::analysis::spectrum::{average_spectra, spctrm, SpectrumParams, Window};
use crate::error::Result;
use crate::pipe::Engine;
use crate::pipe::{Params, Rules};
use crate::plot::{line_chart, Line, PALETTE};
use crate::run::{ensemble, mean_sem};
use plotters::chart::SeriesLabelPosition;
use plotters::style::RGBColor;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// What to record and how to estimate the spectrum.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct SpectrumSetup {
    /// The pipe.
    pub params: Params,
    /// The rule reading.
    pub rules: Rules,
    /// The engine that runs it (`--engine`).
    pub engine: Engine,
    /// Steps discarded before recording (transient from the random start).
    pub transient: u64,
    /// T0: steps between samples (10 in the papers).
    pub t0: u64,
    /// m: number of output frequencies (16384 in the papers).
    pub m: usize,
    /// k: 2k segments of 2m samples (4 in the papers).
    pub k: usize,
    /// The bin whose count is recorded.
    pub bin_index: usize,
}

impl SpectrumSetup {
    /// Number of samples recorded per run, 4km.
    pub fn samples(&self) -> usize {
        4 * self.k * self.m
    }

    /// Steps per run (transient plus recording).
    pub fn steps(&self) -> u64 {
        self.transient + self.samples() as u64 * self.t0
    }

    /// The NR estimator's parameters (1988 "Parzen" triangular window).
    pub fn spectrum_params(&self) -> SpectrumParams {
        SpectrumParams {
            m: self.m,
            k: self.k,
            window: Window::Parzen1988,
        }
    }
}

/// One run's spectrum and its fit.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SpectrumRun {
    /// Seed of the run.
    pub seed: u64,
    /// P(j), j = 0..m.
    pub spectrum: Vec<f64>,
    /// alpha of this run (peak removed).
    pub alpha: f64,
    /// Standard error of this run's alpha from the fit.
    pub alpha_err: f64,
    /// Peak bin inside the fit range.
    pub j_peak: usize,
    /// Wave velocity from the peak, L j / (T0 2m).
    pub v_peak: f64,
}

/// Record the bin series of one run and analyse it. `tick(steps)` reports progress.
pub fn bin_spectrum(
    setup: &SpectrumSetup,
    seed: u64,
    tick: &(dyn Fn(u64) + Sync),
) -> Result<SpectrumRun> {
    bin_spectrum_until(setup, seed, tick, &|| false)
}

/// [`bin_spectrum`] that stops with an [`crate::ErrorKind::Interrupted`]
/// error once `stop()` is true (checked every 10000 steps; the Python
/// module's Ctrl-C). A run that is not stopped is the same run.
pub fn bin_spectrum_until(
    setup: &SpectrumSetup,
    seed: u64,
    tick: &(dyn Fn(u64) + Sync),
    stop: &(dyn Fn() -> bool + Sync),
) -> Result<SpectrumRun> {
    let series = bin_series_until(setup, seed, tick, stop)?;
    let spectrum = spctrm(&series, &setup.spectrum_params())?;
    let est = estimate_alpha(&spectrum)?;
    Ok(SpectrumRun {
        seed,
        alpha: est.fit.alpha,
        alpha_err: est.fit.alpha_err,
        j_peak: est.j_peak,
        v_peak: wave_velocity(setup.params.length, est.j_peak, setup.t0 as usize, setup.m),
        spectrum,
    })
}

/// The particle count of the bin every T0 steps after the transient, 4km
/// samples: the series [`bin_spectrum`] analyses.
pub fn bin_series(
    setup: &SpectrumSetup,
    seed: u64,
    tick: &(dyn Fn(u64) + Sync),
) -> Result<Vec<f64>> {
    bin_series_until(setup, seed, tick, &|| false)
}

/// [`bin_series`] that stops with an [`crate::ErrorKind::Interrupted`]
/// error once `stop()` is true, checked every 10000 steps.
pub fn bin_series_until(
    setup: &SpectrumSetup,
    seed: u64,
    tick: &(dyn Fn(u64) + Sync),
    stop: &(dyn Fn() -> bool + Sync),
) -> Result<Vec<f64>> {
    let stopped = || {
        crate::Error::new(
            crate::ErrorKind::Interrupted,
            format!("run of seed {seed} interrupted"),
        )
    };
    let mut pipe = setup.engine.build(setup.params, setup.rules, seed)?;
    let chunk = 10_000u64;
    let mut left = setup.transient;
    while left > 0 {
        if stop() {
            return Err(stopped());
        }
        let n = left.min(chunk);
        pipe.run(n)?;
        tick(n);
        left -= n;
    }
    let samples = setup.samples();
    let mut series = Vec::with_capacity(samples);
    for s in 0..samples {
        pipe.run(setup.t0)?;
        series.push(pipe.bin_count(setup.bin_index) as f64);
        if s % 1000 == 999 {
            tick(1000 * setup.t0);
            if stop() {
                return Err(stopped());
            }
        }
    }
    Ok(series)
}

/// An ensemble of runs: per-run estimates and the averaged spectrum.
#[derive(Debug, Clone)]
pub struct SpectrumEnsemble {
    /// The runs, in seed order.
    pub runs: Vec<SpectrumRun>,
    /// The spectrum averaged over runs.
    pub mean_spectrum: Vec<f64>,
    /// Fit of the averaged spectrum.
    pub fit_of_mean: AlphaEstimate,
    /// Mean over runs of the per-run alpha.
    pub alpha: f64,
    /// Standard error of that mean (spread over runs; 0 for one run, where the
    /// fit's own error is used instead).
    pub alpha_err: f64,
    /// Peak of the averaged spectrum.
    pub j_peak: usize,
    /// Velocity of that peak.
    pub v_peak: f64,
    /// Standard error of the per-run peak velocities.
    pub v_err: f64,
}

impl SpectrumEnsemble {
    /// The runs' spectra, one row per run (for the estimators of
    /// [`crate::analysis::mean_spectrum`]).
    pub fn spectra(&self) -> Vec<Vec<f64>> {
        self.runs.iter().map(|r| r.spectrum.clone()).collect()
    }

    /// The per-run alpha as an estimate for grading (mean, SE, runs).
    pub fn alpha_estimate(&self) -> Estimate {
        Estimate::new(self.alpha, self.alpha_err, self.runs.len())
    }

    /// The peak velocity as an estimate for grading (v of the averaged
    /// spectrum, SE of the per-run peaks, runs).
    pub fn v_estimate(&self) -> Estimate {
        Estimate::new(self.v_peak, self.v_err, self.runs.len())
    }
}

/// Run `seeds.len()` independent runs on all cores and combine them.
pub fn spectrum_ensemble(
    setup: &SpectrumSetup,
    seeds: &[u64],
    tick: &(dyn Fn(u64) + Sync),
) -> Result<SpectrumEnsemble> {
    let runs: Vec<SpectrumRun> = ensemble(seeds.len(), |i| bin_spectrum(setup, seeds[i], tick))
        .into_iter()
        .collect::<Result<_>>()?;
    combine(setup, runs)
}

/// The spectra of `runs` runs through the figure's ensemble runner
/// (`crate::ensemble`: each finished run saved under `OUT/<binary>/runs/`,
/// resumed when rerun, `--shard` honoured). `None` when only a shard was
/// computed (the caller reports it and stops); `name` tells set-ups of one
/// binary apart.
pub fn resumable_ensemble(
    common: &crate::cli::Common,
    binary: &str,
    name: &str,
    setup: &SpectrumSetup,
    runs: usize,
) -> Result<Option<SpectrumEnsemble>> {
    noted_ensemble(common, binary, name, setup, runs, "")
}

/// [`resumable_ensemble`] whose progress bar shows `note` before its run
/// count (a sequential design's open claims).
pub fn noted_ensemble(
    common: &crate::cli::Common,
    binary: &str,
    name: &str,
    setup: &SpectrumSetup,
    runs: usize,
    note: &str,
) -> Result<Option<SpectrumEnsemble>> {
    use crate::ensemble::Outcome;
    let key = serde_json::json!({"set-up": name, "spectrum": setup});
    let ens = common.ensemble(binary, &key, runs)?.note(note);
    match ens.run(setup.steps(), |_, seed, tick| {
        bin_spectrum(setup, seed, tick)
    })? {
        Outcome::Complete(v) => combine(setup, v).map(Some),
        Outcome::ShardDone { shard, runs, dir } => {
            println!(
                "{binary} {name}: shard {shard} done, {runs} runs in {}; merge the shard folders with the `merge` binary, then rerun without --shard",
                dir.display()
            );
            Ok(None)
        }
    }
}

/// Combine finished runs into an ensemble (averaged spectrum, spreads).
pub fn combine(setup: &SpectrumSetup, runs: Vec<SpectrumRun>) -> Result<SpectrumEnsemble> {
    let spectra: Vec<Vec<f64>> = runs.iter().map(|r| r.spectrum.clone()).collect();
    let mean_spectrum = average_spectra(&spectra)?;
    let fit_of_mean = estimate_alpha(&mean_spectrum)?;
    let alphas: Vec<f64> = runs.iter().map(|r| r.alpha).collect();
    // one run has no spread: no error bar (not the fit's own error, which
    // is not the SE over runs that every other run count reports)
    let (alpha, alpha_err) = match mean_sem(&alphas) {
        (a, _) if runs.len() < 2 => (a, f64::NAN),
        x => x,
    };
    let vs: Vec<f64> = runs.iter().map(|r| r.v_peak).collect();
    let (_, v_err) = mean_sem(&vs);
    let j_peak = fit_of_mean.j_peak;
    Ok(SpectrumEnsemble {
        v_peak: wave_velocity(setup.params.length, j_peak, setup.t0 as usize, setup.m),
        runs,
        mean_spectrum,
        fit_of_mean,
        alpha,
        alpha_err,
        j_peak,
        v_err,
    })
}

/// Log-log plot of the averaged spectrum with the fitted line over the fit
/// range and the peak marked.
pub fn plot_spectrum(
    path: &Path,
    title: &str,
    ens: &SpectrumEnsemble,
    label: &str,
    published: Option<Published>,
    published_peak: Option<(f64, f64)>,
) -> Result<()> {
    let mut lines = spectrum_lines(ens, label, 0);
    if let Some(alpha) = published {
        lines.extend(published_alpha_lines(ens, alpha));
    }
    // the published wave speed v as the bin j where its peak would be, at
    // the height of the measured peak
    if let Some((v, j)) = published_peak {
        let y = ens.mean_spectrum[ens.j_peak];
        lines.push(
            Line::new(
                &format!("published v = {v} (j = {j:.0})"),
                vec![(j, y)],
                RGBColor(0, 0, 0),
            )
            .markers(),
        );
    }
    spectra_chart(path, title, &lines)
}

/// The published exponent drawn over a spectrum: a line of slope -alpha
/// (black) and the two of slope -(alpha +- margin) (grey, the margin's
/// edges) across the fit window, through the fit of `ens` at the window's
/// geometric centre, so the measured slope is seen against the published.
pub fn published_alpha_lines(ens: &SpectrumEnsemble, (alpha, margin): Published) -> Vec<Line> {
    let fit = &ens.fit_of_mean.fit;
    let (lo, hi) = crate::analysis::fit::default_fit_range(ens.mean_spectrum.len());
    let jc = ((lo * hi) as f64).sqrt();
    let yc = 10f64.powf(fit.log10_amplitude - fit.alpha * jc.log10());
    let line = |a: f64| -> Vec<(f64, f64)> {
        [lo as f64, hi as f64]
            .iter()
            .map(|&j| (j, yc * (j / jc).powf(-a)))
            .collect()
    };
    let (black, grey) = (RGBColor(0, 0, 0), RGBColor(150, 150, 150));
    vec![
        Line::new(
            &format!("published alpha = {}", (alpha * 1e3).round() / 1e3),
            line(alpha),
            black,
        ),
        Line::new(
            &format!("published alpha +- margin {margin:.3}"),
            line(alpha - margin),
            grey,
        ),
        Line::new("", line(alpha + margin), grey),
    ]
}

/// Log-log chart of spectra against j (lines from [`spectrum_lines`]), the
/// legend at the lower left. The samples are T0 = 10 steps apart at every
/// tier ([`tier_setup`]).
pub fn spectra_chart(path: &Path, title: &str, lines: &[Line]) -> Result<()> {
    line_chart(
        path,
        title,
        "j (frequency j/(2m) per sample of 10 steps)",
        "P(j)",
        lines,
        true,
        SeriesLabelPosition::LowerLeft,
    )
}

/// The lines of one spectrum (data, fit, peak) in colour `c` of the palette.
pub fn spectrum_lines(ens: &SpectrumEnsemble, label: &str, c: usize) -> Vec<Line> {
    let p = &ens.mean_spectrum;
    let data: Vec<(f64, f64)> = (1..p.len()).map(|j| (j as f64, p[j])).collect();
    let fit = &ens.fit_of_mean.fit;
    let (lo, hi) = crate::analysis::fit::default_fit_range(p.len());
    let fitted: Vec<(f64, f64)> = [lo, hi]
        .iter()
        .map(|&j| {
            (
                j as f64,
                10f64.powf(fit.log10_amplitude - fit.alpha * (j as f64).log10()),
            )
        })
        .collect();
    vec![
        Line::new(label, data, PALETTE[c % PALETTE.len()]),
        Line::new(
            &match ens.alpha_err.is_finite() {
                true => format!(
                    "fit {lo}..{hi}: alpha = {:.2} (runs: {:.2} +- {:.2})",
                    fit.alpha, ens.alpha, ens.alpha_err
                ),
                false => format!("fit {lo}..{hi}: alpha = {:.2} (one run)", fit.alpha),
            },
            fitted,
            PALETTE[(c + 1) % PALETTE.len()],
        ),
        Line::new(
            &format!("peak j = {}, v = {:.3}", ens.j_peak, ens.v_peak),
            vec![(ens.j_peak as f64, p[ens.j_peak])],
            PALETTE[(c + 2) % PALETTE.len()],
        )
        .markers(),
    ]
}

/// Rows of the per-run table: seed, alpha, alpha_err, j_peak, v_peak.
pub fn run_rows(ens: &SpectrumEnsemble) -> Vec<Vec<f64>> {
    ens.runs
        .iter()
        .map(|r| {
            vec![
                r.seed as f64,
                r.alpha,
                r.alpha_err,
                r.j_peak as f64,
                r.v_peak,
            ]
        })
        .collect()
}

/// Rows of the spectrum table: j, frequency (cycles per sample), mean P(j).
pub fn spectrum_rows(ens: &SpectrumEnsemble) -> Vec<Vec<f64>> {
    let m = ens.mean_spectrum.len();
    ens.mean_spectrum
        .iter()
        .enumerate()
        .map(|(j, &p)| vec![j as f64, j as f64 / (2 * m) as f64, p])
        .collect()
}

/// The spectrum set-up of a tier: `quick` m = 4096 (65536 samples per run),
/// `standard` m = 8192, `paper` m = 16384 (the papers' 256K samples); always
/// k = 4, T0 = 10, bin 0, and a transient of 50000 steps.
pub fn tier_setup(
    tier: crate::run::Tier,
    params: Params,
    rules: Rules,
    engine: Engine,
) -> SpectrumSetup {
    SpectrumSetup {
        params,
        rules,
        engine,
        transient: 50_000,
        t0: 10,
        m: tier.pick(4096, 8192, 16384),
        k: 4,
        bin_index: 0,
    }
}

/// Sensitivity of alpha (fit of a spectrum) to the width of the excluded
/// peak (`alpha_hw<w>` for the half-widths of
/// [`crate::analysis::fit::default_sensitivity_widths`]) and to log-binning
/// (`alpha_logbins`, 20 bins per decade, default exclusion).
pub fn alpha_sensitivity_metrics(p: &[f64], j_peak: usize) -> Result<Vec<(String, f64)>> {
    use crate::analysis::fit::{
        alpha_sensitivity, default_peak_half_width, default_sensitivity_widths, exclude_peak,
        fit_power_law, Binning, PowerLawParams,
    };
    let m = p.len();
    let params = PowerLawParams::default_for(m);
    let mut out: Vec<(String, f64)> =
        alpha_sensitivity(p, &params, j_peak, &default_sensitivity_widths(m))?
            .into_iter()
            .map(|(w, f)| (format!("alpha_hw{w}"), f.alpha))
            .collect();
    let mut logb = params.clone();
    logb.binning = Binning::LogBins { per_decade: 20 };
    logb.exclude
        .push(exclude_peak(j_peak, default_peak_half_width(m)));
    out.push(("alpha_logbins".to_string(), fit_power_law(p, &logb)?.alpha));
    Ok(out)
}

/// What backs the engine's results, for summary.json: the fast engine is
/// validated against the reference by `validate` (VALIDATION.md).
pub fn engine_validation(engine: Engine) -> &'static str {
    match engine {
        Engine::Reference => "reference engine: the specification (MODEL.md)",
        Engine::Fast => {
            "fast engine: validated against the reference engine by `validate` (VALIDATION.md: levels 1 and 2, every mutant caught)"
        }
    }
}

/// Why a spectral check may fail: the reason recorded with every failing check.
pub const DISCREPANCY: &str =
    "known discrepancy of this rule reading, see EXPERIMENTS.md 'Known discrepancies'";

/// "The published fit is a typical single run of the model"
/// ([`crate::analysis::representative`], docs/decisions/representative-spectrum.md):
/// the published alpha inside the central 95 % of the per-run fits at the
/// published set-up, each fit's error included. Its value is the share of
/// the per-run fits below the published alpha (the mixture's distribution
/// function there) with the SE of that mean over runs.
pub fn representative_check(
    fig: &SpectrumFigure,
    ens: &SpectrumEnsemble,
    seed: u64,
) -> Result<crate::run::Check> {
    use crate::analysis::representative::{representative, CENTRAL};
    use crate::analysis::sequential::normal_sf;
    let runs: Vec<(f64, f64)> = ens.runs.iter().map(|r| (r.alpha, r.alpha_err)).collect();
    let published = fig.alpha.0;
    let r = representative(&runs, published, seed ^ 0x7265_7072)?;
    let below: Vec<f64> = runs
        .iter()
        .map(|&(a, e)| {
            if e > 0.0 {
                1.0 - normal_sf((published - a) / e)
            } else {
                f64::from(u8::from(a <= published))
            }
        })
        .collect();
    let (share, se) = crate::analysis::stats::mean_sem(&below);
    Ok(crate::run::Check::with_verdict(
        "alpha_representative",
        crate::analysis::grading::Kind::Published,
        &format!("{} (one run's spectrum, S = 4 segments)", fig.paper),
        share,
        se,
        runs.len(),
        r.verdict,
        &format!(
            "the published fit as a typical single run: alpha = {published} inside the central {:.0} % of the per-run fitted alpha, each run a normal of its fit error; ends {:.4} +- {:.4} and {:.4} +- {:.4} (bootstrap SE over runs), each graded against {published} by the one rule; the value is the share of per-run fits below {published}",
            CENTRAL * 100.0,
            r.low.mean,
            r.low.se,
            r.high.mean,
            r.high.se
        ),
    ))
}

/// A published value with its agreement margin Delta: `(value, margin)`,
/// graded by the equivalence rule of [`crate::analysis::grading`].
pub type Published = (f64, f64);

/// What a single-spectrum figure (PH94 Fig. 2, PH95 Fig. 6) runs and checks.
#[derive(Debug, Clone)]
pub struct SpectrumFigure<'a> {
    /// Binary name and output folder, e.g. `fig2`.
    pub binary: &'a str,
    /// Paper and figure, e.g. `PH94 Fig. 2`.
    pub paper: &'a str,
    /// The pipe.
    pub params: Params,
    /// Published alpha and the margin Delta.
    pub alpha: Published,
    /// Published peak velocity and the margin Delta, if any.
    pub v_peak: Option<Published>,
    /// Note appended to every check (e.g. why a value is a known discrepancy).
    pub note: &'a str,
}

impl SpectrumFigure<'_> {
    /// [`run_figure`] with the reading, engine and design of the command
    /// line `args`.
    pub fn run(&self, args: &crate::cli::SequentialArgs) -> Result<Option<crate::run::Summary>> {
        let factor = args.sequential()?.then_some(args.sequential_max);
        let rules = args.pipe.rules.parse()?;
        let engine = args.pipe.rules.engine(args.pipe.common.tier)?;
        run_figure(self, &args.pipe.common, rules, engine, factor)
    }
}

/// Run an ensemble of spectra for `fig` at the options `common` and `rules`
/// (resumable and shardable, see [`resumable_ensemble`]; `None` after a
/// shard), write `spectrum.csv`, `runs.csv`, the PNG and `summary.json` (metrics
/// `alpha`, `alpha_err`, `j_peak`, `v_peak`), and print the checks. With
/// `sequential = Some(factor)` (acceptance tier only) the runs grow look by
/// look, up to `factor` times the fixed count, until every acceptance claim
/// is decided ([`super::acceptance::run_looks`]).
pub fn run_figure(
    fig: &SpectrumFigure,
    common: &crate::cli::Common,
    rules: Rules,
    engine: Engine,
    sequential: Option<usize>,
) -> Result<Option<crate::run::Summary>> {
    use crate::analysis::mean_spectrum::{alpha_of_mean, v_of_mean};
    use crate::run::{run_seeds, Check, Output, Summary};
    let setup = tier_setup(common.tier, fig.params, rules, engine);
    let acceptance = common.tier.is_acceptance();
    let margin = |check| super::acceptance::margin(fig.binary, check);
    let fixed = common.runs_for(4, 8, 8, margin("alpha").map_or(8, |m| m.runs));
    // the acceptance claims, with their estimators (drivers::acceptance)
    let graded: Vec<&'static super::acceptance::Margin> = if acceptance {
        let v = margin("v_peak").filter(|_| fig.v_peak.is_some());
        margin("alpha").into_iter().chain(v).collect()
    } else {
        Vec::new()
    };
    let estimate = |m: &super::acceptance::Margin, ens: &SpectrumEnsemble| match m.check {
        "v_peak" => v_of_mean(&ens.spectra(), setup.params.length, setup.t0),
        _ => alpha_of_mean(&ens.spectra()),
    };
    let start = std::time::Instant::now();
    let design = match sequential {
        Some(factor) => Some(super::acceptance::design(fixed, factor)?),
        None => None,
    };
    let (ens, stops) = match &design {
        Some(d) => {
            let claims: Vec<Claim> = graded.iter().map(|m| m.claim()).collect();
            let looks = super::acceptance::run_looks(d, &claims, |n, open| {
                let note = super::acceptance::open_note(d, n, open, claims.len());
                let Some(ens) = noted_ensemble(common, fig.binary, "spectrum", &setup, n, &note)?
                else {
                    return Ok(None);
                };
                let e = graded
                    .iter()
                    .map(|m| estimate(m, &ens))
                    .collect::<Result<_>>()?;
                Ok(Some((ens, e)))
            })?;
            let Some((ens, stops)) = looks else {
                return Ok(None);
            };
            (ens, Some(stops))
        }
        None => {
            let Some(ens) = resumable_ensemble(common, fig.binary, "spectrum", &setup, fixed)?
            else {
                return Ok(None);
            };
            (ens, None)
        }
    };
    let runs = ens.runs.len();
    let seeds: Vec<u64> = run_seeds(common.seed, runs);
    let out = Output::new(&common.out, fig.binary)?;
    let wall = start.elapsed().as_secs_f64();

    out.write_csv(
        "spectrum.csv",
        &["j", "frequency", "P"],
        &spectrum_rows(&ens),
    )?;
    out.write_csv(
        "runs.csv",
        &["seed", "alpha", "alpha_err", "j_peak", "v_peak"],
        &run_rows(&ens),
    )?;
    let p = &fig.params;
    plot_spectrum(
        &out.path(&format!("{}.png", fig.binary)),
        &format!(
            "{}: spectrum of one bin, L = {}, p = {}, g = {}, b = {}, {runs} runs, rules {rules}",
            fig.paper, p.length, p.p, p.g, p.b
        ),
        &ens,
        &format!("P(j), mean of {runs} runs, m = {}", setup.m),
        // the margin the alpha check grades with at this tier
        Some((
            fig.alpha.0,
            margin("alpha")
                .filter(|_| acceptance)
                .map_or(fig.alpha.1, |m| m.delta()),
        )),
        fig.v_peak.map(|(v, _)| {
            (
                v,
                v * 2.0 * setup.m as f64 * setup.t0 as f64 / p.length as f64,
            )
        }),
    )?;
    let mut metrics = std::collections::BTreeMap::new();
    metrics.insert("alpha".to_string(), ens.alpha);
    metrics.insert("alpha_err".to_string(), ens.alpha_err);
    metrics.insert(
        "alpha_of_mean_spectrum".to_string(),
        ens.fit_of_mean.fit.alpha,
    );
    metrics.insert("j_peak".to_string(), ens.j_peak as f64);
    // j in units of the papers' m = 16384, for comparison with PH94's j = 596
    metrics.insert(
        "j_peak_m16384".to_string(),
        ens.j_peak as f64 * 16384.0 / setup.m as f64,
    );
    metrics.insert("v_peak".to_string(), ens.v_peak);
    metrics.insert("v_peak_err".to_string(), ens.v_err);
    metrics.insert("peak_contrast".to_string(), ens.fit_of_mean.contrast);
    for (name, value) in alpha_sensitivity_metrics(&ens.mean_spectrum, ens.j_peak)? {
        metrics.insert(name, value);
    }
    let source = |what: &str| format!("{} {what}", fig.paper);
    let below = ens.runs.iter().filter(|r| r.alpha < fig.alpha.0).count();
    metrics.insert(
        "share_of_runs_with_alpha_below_published".to_string(),
        below as f64 / runs as f64,
    );
    let mut checks = Vec::new();
    // the estimators and margins fixed before measuring (drivers::acceptance)
    for (i, m) in graded.iter().enumerate() {
        let (what, se_metric) = match m.check {
            "v_peak" => ("peak of the averaged spectrum", "v_peak_bootstrap_se"),
            _ => (
                "fit of the averaged spectrum",
                "alpha_of_mean_spectrum_bootstrap_se",
            ),
        };
        let whole = estimate(m, &ens)?;
        metrics.insert(se_metric.to_string(), whole.se);
        let stop = stops.as_ref().map(|s| s[i]);
        let seq_note = match (&design, &stop) {
            (Some(d), Some(st)) => format!("; {}", super::acceptance::stop_note(d, st, m.claim())),
            _ => String::new(),
        };
        let check = Check::published(
            m.check,
            m.source,
            stop.map_or(whole, |s| s.estimate),
            m.claim(),
            &format!(
                "{what}, bootstrap SE over runs; {}{}{seq_note}",
                m.note(),
                fig.note
            ),
        );
        checks.push(match (&design, &stop) {
            (Some(d), Some(st)) => check.stopped(d, st),
            _ => check,
        });
    }
    if acceptance {
        checks.push(representative_check(fig, &ens, common.seed)?);
    }
    if !acceptance {
        checks.push(Check::published(
            "alpha",
            &source("alpha"),
            ens.alpha_estimate(),
            Claim::Within {
                target: fig.alpha.0,
                margin: fig.alpha.1,
            },
            &format!(
                "mean of the per-run fitted alpha; margin Delta = {} fixed before measuring (MODEL.md A10){}",
                fig.alpha.1, fig.note
            ),
        ));
    }
    if let Some(v) = fig.v_peak.filter(|_| !acceptance) {
        checks.push(Check::published(
            "v_peak",
            &source("peak velocity"),
            ens.v_estimate(),
            Claim::Within {
                target: v.0,
                margin: v.1,
            },
            &format!(
                "v of the peak of the averaged spectrum, SE of the per-run peaks; margin Delta = {}{}",
                v.1, fig.note
            ),
        ));
    }
    crate::run::mark_discrepancies(&mut checks, DISCREPANCY);
    let summary = Summary {
        figure: fig.binary.into(),
        paper: fig.paper.into(),
        tier: common.tier,
        seeds,
        params: serde_json::json!({
            "pipe": fig.params,
            "setup": setup,
            "engine_validation": engine_validation(engine),
        }),
        rules: rules.to_string(),
        engine: engine.label(),
        wall_seconds: wall,
        site_updates: (runs as u64 * setup.steps() * p.sites() as u64) as f64,
        metrics,
        missing_metrics: Default::default(),
        checks,
    };
    out.finish(&summary)?;
    Ok(Some(summary))
}
