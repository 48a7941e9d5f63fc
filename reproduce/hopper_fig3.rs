//! BB90 Fig. 3: grains leaving the hopper per iteration over 6144 iterations
//! after opening, raw and averaged over 5 and 11 iterations, and the power
//! spectrum of the outflow (white noise); with orientation on (beta = 1, both
//! readings of "aligned") and off (beta = 0) (MODEL.md B6).
//!
//! `cargo run --release --bin hopper-fig3 -- --tier quick`

use clap::Parser;
use granular_automata::analysis::spectrum::frequency;
use granular_automata::hopper::experiment::{
    analyse_outflow, run, Plan, Record, WINDOW_FULL, WINDOW_SKIP,
};
use granular_automata::hopper::observables::running_mean;
use granular_automata::hopper::picture::{time_chart, TimeSeries};
use granular_automata::hopper::{Aligned, GeometryParams, HopperParams, RainParams};
use granular_automata::plot::{line_chart, Line, PALETTE};
use granular_automata::run::{
    derive_seed, ensemble, mean_sem, progress, Check, Output, Summary, Tier,
};
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::Instant;

#[derive(Parser, Debug)]
#[command(about = "BB90 Fig. 3: hopper outflow per iteration and its power spectrum")]
struct Args {
    /// quick (small hopper), standard (174 x 129) or paper (270 x 200, whose
    /// stationary window covers the 6144 iterations).
    #[arg(long, value_enum, default_value = "quick")]
    tier: Tier,
    /// Base seed; run r uses derive_seed(seed, r).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Runs per case (metrics and spectra are averaged over them).
    #[arg(long)]
    runs: Option<usize>,
    /// Output folder.
    #[arg(long, default_value = "results")]
    out: PathBuf,
}

/// The three cases: (key, caption, beta, aligned).
const CASES: [(&str, &str, f64, Aligned); 3] = [
    (
        "beta1_along",
        "beta = 1, aligned = along-velocity",
        1.0,
        Aligned::AlongVelocity,
    ),
    (
        "beta1_same",
        "beta = 1, aligned = same-orientation",
        1.0,
        Aligned::SameOrientation,
    ),
    (
        "beta0",
        "beta = 0 (orientation off)",
        0.0,
        Aligned::AlongVelocity,
    ),
];

/// Iterations recorded after opening (BB90 Fig. 3).
const RECORD: u64 = 6144;

fn main() -> granular_automata::Result<()> {
    let args = Args::parse();
    let start = Instant::now();
    let tier = args.tier;
    let runs = args.runs.unwrap_or(tier.pick(3, 4, 4)).max(1);
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
    let mut plan = Plan::new(tier.pick(6_000, 12_000, 20_000), vec![]);
    plan.fill_fraction = tier.pick(0.7, 0.85, 0.85);
    plan.min_record = RECORD;
    let m = tier.pick(64, 128, 256);
    let out = Output::new(&args.out, "hopper-fig3")?;
    let seeds: Vec<u64> = (0..runs as u64)
        .map(|r| derive_seed(args.seed, r))
        .collect();

    let pb = progress((CASES.len() * runs) as u64, "hopper runs");
    let jobs: Vec<(usize, usize)> = (0..CASES.len())
        .flat_map(|c| (0..runs).map(move |r| (c, r)))
        .collect();
    let results = ensemble(jobs.len(), |j| {
        let (c, r) = jobs[j];
        let mut p = base;
        p.energy.beta = CASES[c].2;
        p.energy.aligned = CASES[c].3;
        let rec = run(p, seeds[r], &plan);
        pb.inc(1);
        rec
    });
    pb.finish();
    let mut recs: Vec<Vec<Record>> = (0..CASES.len()).map(|_| Vec::new()).collect();
    for (j, rec) in results.into_iter().enumerate() {
        recs[jobs[j].0].push(rec?);
    }

    let mut metrics = BTreeMap::new();
    let mut checks = Vec::new();
    let mut spectra = Vec::new();
    let mut site_updates = 0.0;
    let mut spec_csv = Vec::new();
    for (c, (key, cap, ..)) in CASES.iter().enumerate() {
        let rs = &recs[c];
        site_updates += rs.iter().map(|r| r.site_updates).sum::<f64>();
        let a = analyse_outflow(rs, m)?;
        // the window taken literally: from opening while > 30% full
        let mut open30 = (0.0, 0.0);
        for r in rs {
            let w = r.window(0.0, WINDOW_FULL);
            let mu = w.iter().sum::<f64>() / w.len().max(1) as f64;
            let var = w.iter().map(|q| (q - mu).powi(2)).sum::<f64>() / (w.len().max(2) - 1) as f64;
            open30.0 += mu / rs.len() as f64;
            open30.1 += var.sqrt() / rs.len() as f64;
        }
        let (p, fit, k) = (a.spectrum.clone(), a.fit, a.k);
        let n = rs.len() as f64;
        for (j, &pj) in p.iter().enumerate() {
            spec_csv.push(vec![c as f64, frequency(j, m), pj]);
        }
        spectra.push((cap.to_string(), p, fit));
        let (emptied, _) = mean_sem(
            &rs.iter()
                .map(|r| r.empty_iterations as f64)
                .collect::<Vec<_>>(),
        );
        for (name, v) in [
            ("mean_rate", a.mean),
            ("sd_rate", a.sd),
            ("rate_first_half", a.first),
            ("rate_first_half_err", a.first_se),
            ("rate_second_half", a.second),
            ("rate_second_half_err", a.second_se),
            ("trend_z", a.trend_z),
            ("window_iterations", a.window),
            ("spectral_slope", fit.slope),
            ("spectral_slope_err", fit.slope_err),
            ("spectrum_k", k as f64),
            ("spectrum_high_to_low", a.high_to_low),
            ("lag1_correlation", a.lag1),
            ("empty_iterations", emptied),
            ("mean_rate_open_to_30", open30.0),
            ("sd_rate_open_to_30", open30.1),
            (
                "initial_grains",
                rs.iter().map(|r| r.initial as f64).sum::<f64>() / n,
            ),
        ] {
            metrics.insert(format!("{key}_{name}"), v);
        }
        checks.push(Check::claim(
            &format!("{key}_no_trend"),
            a.trend_z,
            1.0,
            a.trend_z.abs() <= 3.0,
            &format!("BB90 Fig. 3: no monotonic variation: (second - first half rate)/combined standard error within +-3 (false alarm 0.3%); {cap}"),
        ));
        checks.push(Check::claim(
            &format!("{key}_white_spectrum"),
            fit.slope,
            fit.slope_err,
            fit.slope.abs() <= 3.0 * fit.slope_err,
            &format!("BB90 Fig. 3: power spectrum flat: log-log slope for f <= 1/8 within 3 standard errors of 0 (false alarm 0.3%); {cap}"),
        ));
        checks.push(Check::claim(
            &format!("{key}_empties"),
            rs.iter().map(|r| r.remaining as f64).sum::<f64>(),
            0.0,
            rs.iter().all(|r| r.emptied),
            &format!("the hopper empties without jamming (grains left, all runs); {cap}"),
        ));
    }

    // Fig. 3a/b: run 0 of each case
    let mut rows = Vec::new();
    for t in 0..RECORD as usize {
        let mut row = vec![t as f64];
        for rs in &recs {
            row.push(rs[0].outflow[t]);
        }
        rows.push(row);
    }
    out.write_csv(
        "outflow_run0.csv",
        &["iteration", "beta1_along", "beta1_same", "beta0"],
        &rows,
    )?;
    out.write_csv("spectra.csv", &["case", "frequency", "power"], &spec_csv)?;
    for (c, (key, cap, ..)) in CASES.iter().enumerate() {
        let q = &recs[c][0].outflow[..RECORD as usize];
        let ts = |label: &str, values: Vec<f64>, color, width| TimeSeries {
            label: label.to_string(),
            values,
            color,
            width,
        };
        time_chart(
            &out.path(&format!("hopper-fig3a-{key}.png")),
            &format!("BB90 Fig. 3a: grains leaving per iteration, {cap} (run 0)"),
            "iterations after opening",
            "grains leaving per iteration",
            &[
                ts("raw", q.to_vec(), RGB_LIGHT, 1),
                ts(
                    "averaged over 5 iterations",
                    running_mean(q, 5),
                    PALETTE[0],
                    1,
                ),
            ],
        )?;
        time_chart(
            &out.path(&format!("hopper-fig3b-{key}.png")),
            &format!("BB90 Fig. 3b: grains leaving per iteration averaged over 11 iterations, {cap} (run 0)"),
            "iterations after opening",
            "grains leaving per iteration",
            &[ts("averaged over 11 iterations", running_mean(q, 11), PALETTE[1], 1)],
        )?;
    }
    let mut lines = Vec::new();
    for (c, (cap, p, fit)) in spectra.iter().enumerate() {
        let pts: Vec<(f64, f64)> = (1..m)
            .map(|j| (frequency(j, m).log10(), p[j].log10()))
            .collect();
        let fitted: Vec<(f64, f64)> = pts[..m / 4]
            .iter()
            .map(|&(lf, _)| (lf, fit.intercept + fit.slope * lf))
            .collect();
        lines.push(Line::new(cap, pts, PALETTE[c]).markers());
        lines.push(Line::new(
            &format!(
                "fit f <= 1/8: slope {:.3} +- {:.3}",
                fit.slope, fit.slope_err
            ),
            fitted,
            PALETTE[c],
        ));
    }
    line_chart(
        &out.path("hopper-fig3-spectrum.png"),
        "BB90 Fig. 3: power spectrum of the outflow (from 15% out until 30% remain)",
        "log10 frequency (cycles per iteration)",
        "log10 power (NR spctrm, averaged over runs)",
        &lines,
        false,
    )?;

    let params = serde_json::json!({
        "hopper": base,
        "cases": CASES.iter().map(|(k, _, b, a)| serde_json::json!({"key": k, "beta": b, "aligned": a.name()})).collect::<Vec<_>>(),
        "runs": runs,
        "fill_fraction": plan.fill_fraction,
        "record_iterations": RECORD,
        "stationary_window": "iterations after 15% of the grains have left (start-up) while more than 30% remain",
        "block_for_standard_errors": granular_automata::hopper::experiment::WINDOW_BLOCK, "window_skip": WINDOW_SKIP, "window_full": WINDOW_FULL,
        "spectrum": {"estimator": "NR 1988 spctrm, no overlap, on the stationary window, averaged over runs", "m": m, "window": "Parzen1988", "fit": "least squares of log10 P on log10 f, j = 1..m/4 (f <= 1/8)"},
    });
    let summary = Summary {
        figure: "hopper-fig3".into(),
        paper: "BB90 Fig. 3".into(),
        tier,
        seeds,
        params,
        rules: base.rules(),
        wall_seconds: start.elapsed().as_secs_f64(),
        site_updates,
        metrics,
        checks,
    };
    out.finish(&summary)?;
    Ok(())
}

/// Light grey for the raw series under its average.
const RGB_LIGHT: plotters::style::RGBColor = plotters::style::RGBColor(170, 170, 170);
