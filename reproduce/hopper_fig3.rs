//! BB90 Fig. 3: grains leaving the hopper per iteration over 6144 iterations
//! after opening, raw and averaged over 5 and 11 iterations, and the power
//! spectrum of the outflow (white noise); with orientation on (beta = 1, both
//! readings of "aligned": the default same-orientation first, the literal
//! along-velocity as the comparison) and off (beta = 0) (MODEL.md B4, B6).
//!
//! `cargo run --release --bin hopper-fig3 -- --tier quick`

use clap::Parser;
use granular_automata::analysis::grading::{Claim, Estimate, Kind};
use granular_automata::analysis::spectrum::frequency;
use granular_automata::cli::Common;
use granular_automata::drivers::margins::ALPHA_MARGIN;
use granular_automata::hopper::experiment::{
    analyse_outflow, lag_correlation, open_window_rates, run_cases,
};
use granular_automata::hopper::experiment::{Case, Plan, WINDOW_BLOCK, WINDOW_FULL, WINDOW_SKIP};
use granular_automata::hopper::picture::{outflow_charts, spectrum_chart};
use granular_automata::hopper::{GeometryParams, HopperParams, RainParams};
use granular_automata::run::{derive_seed, mean_sem_by, metrics_of, Check, Figure};
use std::collections::BTreeMap;

#[derive(Parser, Debug)]
#[command(about = "BB90 Fig. 3: hopper outflow per iteration and its power spectrum")]
struct Args {
    /// quick: a small hopper; standard: 174 x 129; paper: 270 x 200, whose
    /// stationary window covers the 6144 iterations. `--runs`: runs per
    /// case (metrics and spectra are averaged over them).
    #[command(flatten)]
    common: Common,
    /// Comma-separated cases (readings) to run, from `Case::ALL`; the rate
    /// of each beta = 1 case is compared with the first beta = 0 case. The
    /// default's first case is the default reading.
    #[arg(long, default_value = "beta1_bond,beta1_same,beta1_along,beta0")]
    cases: String,
}

/// Iterations recorded after opening (BB90 Fig. 3).
const RECORD: u64 = 6144;

/// Margin Delta of "no monotonic variation": the mean outflow rate of the
/// second half within 10% of the first half's (relative to the mean rate),
/// fixed in session 4.
const TREND_MARGIN: f64 = 0.1;

/// Margin Delta of "white" over the whole band (issue 15, fixed before
/// measuring): the lag-1 autocorrelation of the outflow within 0.1 of 0.
const LAG1_MARGIN: f64 = 0.1;

/// Margin Delta of "qualitatively similar results with orientation off"
/// (issue 15, fixed before measuring): the stationary rate with orientation
/// on over the rate with it off, within 0.2 of 1.
const RATE_RATIO_MARGIN: f64 = 0.2;

fn main() -> granular_automata::Result<()> {
    let args = Args::parse();
    let c = &args.common;
    let cases = Case::parse_list(&args.cases)?;
    let cases = &cases[..];
    c.reject_shard("hopper-fig3")?;
    let tier = c.tier;
    let runs = c.runs_or(3, 4, 4);
    let tall = HopperParams {
        geometry: GeometryParams {
            width: 270,
            height: 200,
            outlet_width: 7,
            channel_height: 4,
        },
        rain: RainParams {
            sigma: 18.0,
            ..Default::default()
        },
        ..Default::default()
    };
    let base = tier.pick(HopperParams::quick(), HopperParams::default(), tall);
    let fig = Figure::start("hopper-fig3", "BB90 Fig. 3", tier, base.rules());
    let mut plan = Plan::new(tier.pick(6_000, 12_000, 20_000), vec![]);
    plan.fill_fraction = tier.pick(0.7, 0.85, 0.85);
    plan.min_record = RECORD;
    let m = tier.pick(64, 128, 256);
    let out = fig.output(&c.out)?;
    let seeds: Vec<u64> = (0..runs as u64).map(|r| derive_seed(c.seed, r)).collect();
    let recs = run_cases(base, cases, &seeds, &plan, c.thread_count())?;
    let window_rate = |r: &granular_automata::hopper::experiment::Record| {
        let w = r.window(WINDOW_SKIP, WINDOW_FULL);
        w.iter().sum::<f64>() / w.len().max(1) as f64
    };
    let beta0_rate = cases
        .iter()
        .position(|c| c.beta == 0.0)
        .map(|i| Estimate::of(&recs[i].iter().map(window_rate).collect::<Vec<_>>()));

    let mut metrics = BTreeMap::new();
    let mut checks = Vec::new();
    let mut spectra = Vec::new();
    let mut site_updates = 0.0;
    let mut spec_csv = Vec::new();
    for (c, (case, rs)) in cases.iter().zip(&recs).enumerate() {
        let (key, cap) = (case.key, case.caption);
        site_updates += rs.iter().map(|r| r.site_updates).sum::<f64>();
        let a = analyse_outflow(rs, m)?;
        let open30 = open_window_rates(rs, WINDOW_FULL);
        let fit = a.fit;
        let n = rs.len() as f64;
        spec_csv.extend((0..m).map(|j| vec![c as f64, frequency(j, m), a.spectrum[j]]));
        let (emptied, _) = mean_sem_by(rs, |r| r.empty_iterations as f64);
        let initial = rs.iter().map(|r| r.initial as f64).sum::<f64>() / n;
        let more = [
            ("empty_iterations", emptied),
            ("mean_rate_open_to_30", open30.0),
            ("sd_rate_open_to_30", open30.1),
            ("initial_grains", initial),
        ];
        let named = a.named().into_iter().chain(more);
        metrics.extend(metrics_of(
            named.map(|(name, v)| (format!("{key}_{name}"), v)),
        ));
        let runs = rs.len();
        let r = &a.rates;
        checks.push(Check::published(
            &format!("{key}_no_trend"),
            "BB90 Fig. 3 (no monotonic variation of the flow rate)",
            Estimate::new(
                (r.second - r.first) / r.mean,
                r.first_se.hypot(r.second_se) / r.mean,
                runs,
            ),
            Claim::Within {
                target: 0.0,
                margin: TREND_MARGIN,
            },
            &format!(
                "(second - first half mean rate) / mean rate within Delta = {TREND_MARGIN}; {cap}"
            ),
        ));
        checks.push(Check::published(
            &format!("{key}_white_spectrum"),
            "BB90 Fig. 3 (a flat power spectrum of the outflow)",
            Estimate::new(fit.slope, fit.slope_err, runs),
            Claim::Within {
                target: 0.0,
                margin: ALPHA_MARGIN,
            },
            &format!("log-log slope of the mean spectrum for f <= 1/8 within Delta = {ALPHA_MARGIN} of 0 (the pipe's white-noise margin); {cap}"),
        ));
        checks.push(Check::test(
            &format!("{key}_empties"),
            Kind::Published,
            "BB90 Fig. 3 (the hopper empties)",
            rs.iter().map(|r| r.remaining as f64).sum::<f64>(),
            runs,
            rs.iter().all(|r| r.emptied),
            &format!("the hopper empties without jamming in every run (statistic: grains left, all runs); {cap}"),
        ));
        let lag1: Vec<f64> = rs
            .iter()
            .map(|r| lag_correlation(r.window(WINDOW_SKIP, WINDOW_FULL), 1))
            .collect();
        checks.push(Check::published(
            &format!("{key}_white_lag1"),
            "BB90 Fig. 3 (a flat power spectrum: white noise over the whole band)",
            Estimate::of(&lag1),
            Claim::Within {
                target: 0.0,
                margin: LAG1_MARGIN,
            },
            &format!("lag-1 autocorrelation of the outflow in the stationary window (per run) within Delta = {LAG1_MARGIN} of 0 (white noise: 0; a period-2 alternation: negative); {cap}"),
        ));
        if let (Some(b0), true) = (beta0_rate, case.beta != 0.0) {
            let on = Estimate::of(&rs.iter().map(window_rate).collect::<Vec<_>>());
            let ratio = on.mean / b0.mean;
            let se = ratio * ((on.se / on.mean).powi(2) + (b0.se / b0.mean).powi(2)).sqrt();
            checks.push(Check::published(
                &format!("{key}_rate_like_orientation_off"),
                "BB90 Fig. 3 caption (qualitatively similar results with orientation off)",
                Estimate::new(ratio, se, on.n.min(b0.n)),
                Claim::Within {
                    target: 1.0,
                    margin: RATE_RATIO_MARGIN,
                },
                &format!("stationary outflow rate over that of beta = 0 within Delta = {RATE_RATIO_MARGIN} of 1; {cap}"),
            ));
        }
        spectra.push((cap, a.spectrum, fit));
    }

    // Fig. 3a/b: run 0 of each case
    let t: Vec<f64> = (0..RECORD as usize).map(|t| t as f64).collect();
    let q0: Vec<&[f64]> = recs
        .iter()
        .map(|rs| &rs[0].outflow[..RECORD as usize])
        .collect();
    let mut header = vec!["iteration"];
    header.extend(cases.iter().map(|c| c.key));
    let mut columns: Vec<&[f64]> = vec![&t[..]];
    columns.extend(q0.iter().copied());
    out.write_columns("outflow_run0.csv", &header, &columns)?;
    out.write_csv("spectra.csv", &["case", "frequency", "power"], &spec_csv)?;
    for (case, q) in cases.iter().zip(&q0) {
        let path = |fig: &str| out.path(&format!("hopper-fig3{fig}-{}.png", case.key));
        outflow_charts(&path("a"), &path("b"), case.caption, q)?;
    }
    let spectra: Vec<_> = spectra.iter().map(|(c, p, f)| (*c, &p[..], *f)).collect();
    spectrum_chart(&out.path("hopper-fig3-spectrum.png"), &spectra)?;

    let params = serde_json::json!({
        "hopper": base,
        "cases": cases.iter().map(Case::json).collect::<Vec<_>>(),
        "runs": runs,
        "fill_fraction": plan.fill_fraction,
        "record_iterations": RECORD,
        "stationary_window": "iterations after 15% of the grains have left (start-up) while more than 30% remain",
        "block_for_standard_errors": WINDOW_BLOCK, "window_skip": WINDOW_SKIP, "window_full": WINDOW_FULL,
        "spectrum": {"estimator": "NR 1988 spctrm, no overlap, on the stationary window, averaged over runs", "m": m, "window": "Parzen1988", "fit": "least squares of log10 P on log10 f, j = 1..m/4 (f <= 1/8)"},
    });
    fig.finish(&out, seeds, params, site_updates, metrics, checks)
}
