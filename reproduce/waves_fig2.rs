//! PH95 Fig. 2: wave formation from the random start. (a) Nine successive
//! snapshots of the bin densities n_i every 2000 steps from t = 0, stacked
//! with time upward and gravity from left to right; (b) the space-time plot
//! of n_i every 80 steps over 40000 steps, same orientation. L = 2200,
//! W = 11, rho = 1, p = 0.1, g = b = 0.5, bins of 10 rows (MODEL.md A9).
//!
//! The pictures show run 0. Over all runs the binary measures the band
//! statistic s_low (MODEL.md A11) and the contrast C over the late half, and
//! the real-space speed of the pattern (shift of maximal overlap against the
//! time interval, [`granular_automata::pipe::overlap`]) over the late half.
//!
//! `cargo run --release --bin waves-fig2 -- --tier quick`

use clap::Parser;
use granular_automata::analysis::fit::linear_fit;
use granular_automata::cli::{Common, PipeRules};
use granular_automata::ensemble::Outcome;
use granular_automata::pipe::overlap::shift_against_lag;
use granular_automata::pipe::record::{bands, record, Record};
use granular_automata::pipe::{Params, Pipe};
use granular_automata::plot::{plot_err, register_fonts, FONT, PALETTE};
use granular_automata::run::{mean_sem, Check, Output, Summary};
use plotters::prelude::*;
use serde::{Deserialize, Serialize};
use serde_json::json;
use std::collections::BTreeMap;
use std::time::Instant;

#[derive(Parser)]
#[command(about = "PH95 Fig. 2: wave formation (snapshots and space-time plot)")]
struct Args {
    #[command(flatten)]
    common: Common,
    #[command(flatten)]
    rules: PipeRules,
    /// Dissipation p (the figure: 0.1); p = 0 is the wave-free control.
    #[arg(long, default_value_t = 0.1)]
    p: f64,
}

/// Waves if s_low - 2 SE > 2 (as in fig1; an uncorrelated gas gives 1).
const WAVE_THRESHOLD: f64 = 2.0;
const STEPS: u64 = 40_000;
const EVERY: u64 = 80;
const SNAP_EVERY: u64 = 2000;
const SNAPS: usize = 9;
/// Lags (in samples of 80 steps) of the real-space speed fit: up to 2000 steps.
const MAX_LAG: usize = 25;

#[derive(Debug, Clone, Serialize, Deserialize)]
struct RunResult {
    /// The space-time record (run 0 only, for the pictures).
    record: Option<Record>,
    /// s_low over the late half.
    s_low: f64,
    /// Mean contrast over the late half.
    contrast: f64,
    /// Real-space speed (rows per step, + = up) over the late half.
    speed: f64,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    let tier = args.common.tier;
    let rules = args.rules.parse()?;
    let runs = args.common.runs_or(2, 8, 32);
    let params = Params {
        length: 2200,
        width: 11,
        rho: 1.0,
        p: args.p,
        g: 0.5,
        b: 0.5,
        bin: 10,
        ..Params::default()
    };
    params.validate()?;
    let key = json!({"analysis": 1, "params": params, "rules": rules.to_string(), "steps": STEPS, "every": EVERY});
    let ens = args.common.ensemble("waves-fig2", &key, runs)?;
    let start = Instant::now();
    let outcome = ens.run(STEPS, |index, seed, tick| {
        let mut pipe = Pipe::new(params, rules, seed)?;
        let rec = record(&mut pipe, STEPS, EVERY, |_| tick(EVERY))?;
        let half = rec.n.len() / 2;
        let b = bands(&rec, half, params.rho, params.bin, params.width);
        let s = shift_against_lag(&rec.n[half..], MAX_LAG);
        let tau: Vec<f64> = (1..=s.len()).map(|m| (m as u64 * EVERY) as f64).collect();
        let rows: Vec<f64> = s.iter().map(|v| v * params.bin as f64).collect();
        let speed = linear_fit(&tau, &rows)?.slope;
        Ok(RunResult {
            record: (index == 0).then_some(rec),
            s_low: b.s_low,
            contrast: b.contrast,
            speed,
        })
    })?;
    let results: Vec<RunResult> = match outcome {
        Outcome::Complete(v) => v,
        Outcome::ShardDone { shard, runs, dir } => {
            println!("shard {shard} done: {runs} runs in {}; merge the shard folders with the `merge` binary, then rerun without --shard", dir.display());
            return Ok(());
        }
    };
    let wall = start.elapsed().as_secs_f64();
    let out = Output::new(&args.common.out, "waves-fig2")?;
    let seeds = ens.seeds();
    let rec = results[0].record.as_ref().expect("run 0 keeps its record");

    let (s_low, s_low_err) = mean_sem(&results.iter().map(|r| r.s_low).collect::<Vec<_>>());
    let (c, c_err) = mean_sem(&results.iter().map(|r| r.contrast).collect::<Vec<_>>());
    let (v, v_err) = mean_sem(&results.iter().map(|r| r.speed).collect::<Vec<_>>());
    let mut metrics = BTreeMap::new();
    for (k, x) in [
        ("s_low_late", s_low),
        ("s_low_late_err", s_low_err),
        ("contrast_late", c),
        ("contrast_late_err", c_err),
        ("speed_real_space", v),
        ("speed_real_space_err", v_err),
    ] {
        metrics.insert(k.to_string(), x);
    }

    // data
    let k = params.bins();
    let mut header = vec!["t".to_string()];
    header.extend((0..k).map(|i| format!("n{i}")));
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    let rows: Vec<Vec<f64>> = rec
        .n
        .iter()
        .enumerate()
        .map(|(t, v)| {
            std::iter::once(rec.time(t) as f64)
                .chain(v.iter().copied())
                .collect()
        })
        .collect();
    out.write_csv("fig2b_spacetime_run0.csv", &header, &rows)?;
    let snap_idx: Vec<usize> = (0..SNAPS)
        .map(|j| (j as u64 * SNAP_EVERY / EVERY) as usize)
        .collect();
    out.write_csv(
        "fig2a_snapshots_run0.csv",
        &header,
        &snap_idx
            .iter()
            .map(|&t| rows[t].clone())
            .collect::<Vec<_>>(),
    )?;
    out.write_csv(
        "runs.csv",
        &["seed", "s_low_late", "contrast_late", "speed_real_space"],
        &results
            .iter()
            .zip(&seeds)
            .map(|(r, &s)| vec![s as f64, r.s_low, r.contrast, r.speed])
            .collect::<Vec<_>>(),
    )?;

    // (a) snapshots: x = distance from the top of the pipe (gravity left to
    // right), one line per snapshot offset by its index (time upward)
    register_fonts();
    let l = params.length as f64;
    let bin = params.bin as f64;
    let mean = rec.n[0].iter().sum::<f64>() / k as f64;
    let amp = snap_idx
        .iter()
        .flat_map(|&t| rec.n[t].iter().map(move |v| (v - mean).abs()))
        .fold(0.0f64, f64::max)
        .max(1.0);
    let offset = 1.2 * amp;
    let path = out.path("fig2a.png");
    {
        let root = BitMapBackend::new(&path, (1100, 900)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(
                format!(
                    "PH95 Fig. 2a: n_i every 2000 steps, L = 2200, p = {}, {rules}, seed {}",
                    params.p, seeds[0]
                ),
                (FONT, 20),
            )
            .margin(15)
            .x_label_area_size(50)
            .y_label_area_size(80)
            .build_cartesian_2d(0.0..l, -offset..(SNAPS as f64) * offset)
            .map_err(plot_err)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("distance from the top of the pipe, L - y (rows); gravity points left to right")
            .y_desc("n_i - mean, offset by 2000 steps per line (time upward)")
            .y_label_formatter(&|v| format!("{v:.0}"))
            .label_style((FONT, 15))
            .draw()
            .map_err(plot_err)?;
        for (j, &t) in snap_idx.iter().enumerate() {
            let base = j as f64 * offset;
            let pts: Vec<(f64, f64)> = (0..k)
                .map(|i| (l - (i as f64 + 0.5) * bin, base + rec.n[t][i] - mean))
                .collect();
            chart
                .draw_series(LineSeries::new(
                    pts,
                    PALETTE[j % PALETTE.len()].stroke_width(2),
                ))
                .map_err(plot_err)?;
            chart
                .draw_series(std::iter::once(Text::new(
                    format!("t = {}", rec.time(t)),
                    (0.01 * l, base + 0.35 * offset),
                    (FONT, 14),
                )))
                .map_err(plot_err)?;
        }
        root.present().map_err(plot_err)?;
    }

    // (b) space-time: x as in (a), time upward, darker = denser
    let lo = rec
        .n
        .iter()
        .flatten()
        .cloned()
        .fold(f64::INFINITY, f64::min);
    let hi = rec
        .n
        .iter()
        .flatten()
        .cloned()
        .fold(f64::NEG_INFINITY, f64::max);
    let path = out.path("fig2b.png");
    {
        let root = BitMapBackend::new(&path, (1100, 900)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let tmax = (rec.n.len() as u64 * EVERY) as f64;
        let mut chart = ChartBuilder::on(&root)
            .caption(
                format!("PH95 Fig. 2b: n_i every 80 steps (white {lo:.0}, black {hi:.0}), p = {}, {rules}", params.p),
                (FONT, 20),
            )
            .margin(15)
            .x_label_area_size(50)
            .y_label_area_size(80)
            .build_cartesian_2d(0.0..l, 0.0..tmax)
            .map_err(plot_err)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("distance from the top of the pipe, L - y (rows); gravity points left to right")
            .y_desc("time t (steps), upward")
            .x_label_formatter(&|v| format!("{v:.0}"))
            .y_label_formatter(&|v| format!("{v:.0}"))
            .label_style((FONT, 15))
            .draw()
            .map_err(plot_err)?;
        let span = (hi - lo).max(1e-9);
        chart
            .draw_series(rec.n.iter().enumerate().flat_map(|(t, v)| {
                v.iter().enumerate().map(move |(i, &x)| {
                    let g = (255.0 * (1.0 - (x - lo) / span)).round() as u8;
                    let x0 = l - (i as f64 + 1.0) * bin;
                    let t0 = (t as u64 * EVERY) as f64;
                    Rectangle::new(
                        [(x0, t0), (x0 + bin, t0 + EVERY as f64)],
                        RGBColor(g, g, g).filled(),
                    )
                })
            }))
            .map_err(plot_err)?;
        root.present().map_err(plot_err)?;
    }

    let checks = vec![
        Check::claim(
            "waves_form",
            s_low,
            s_low_err,
            s_low - 2.0 * s_low_err > WAVE_THRESHOLD,
            &format!("PH95 Fig. 2: density waves form from the random start; s_low = S(1..3) over the late half / random-start value, waves if mean - 2 SE > {WAVE_THRESHOLD} (as fig1)"),
        ),
        Check::claim(
            "speed_measured",
            v,
            v_err,
            v.is_finite() && v_err.is_finite(),
            "real-space speed of the pattern over the late half (rows per step, + = up, against gravity): reported, compared with waves-fig5",
        ),
    ];
    let summary = Summary {
        figure: "waves-fig2".into(),
        paper: "PH95 Fig. 2".into(),
        tier,
        seeds,
        params: json!({"L": params.length, "W": params.width, "rho": params.rho, "p": params.p, "g": params.g, "b": params.b, "bin": params.bin, "steps": STEPS, "every": EVERY, "snapshot_every": SNAP_EVERY, "runs": runs}),
        rules: rules.to_string(),
        wall_seconds: wall,
        site_updates: (runs as u64 * STEPS * params.sites() as u64) as f64,
        metrics,
        checks,
    };
    out.finish(&summary)?;
    Ok(())
}
