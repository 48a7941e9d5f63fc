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
use granular_automata::analysis::grading::{Claim, Estimate};
use granular_automata::cli::WaveOptions;
use granular_automata::drivers::bands::draw_snapshots;
use granular_automata::drivers::claims::WAVE_THRESHOLD;
use granular_automata::pipe::overlap::real_space_speed;
use granular_automata::pipe::record::{bands, record, Record};
use granular_automata::plot::{space_time_upward, value_range};
use granular_automata::run::{mean_sem_by, stat_metrics, Check};
use serde::{Deserialize, Serialize};
use serde_json::json;

#[derive(Parser)]
#[command(about = "PH95 Fig. 2: wave formation (snapshots and space-time plot)")]
struct Args {
    #[command(flatten)]
    wave: WaveOptions,
}

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

granular_automata::main_of!(body);

fn body() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    let (fig, rules, engine, c) = args.wave.start("waves-fig2", "PH95 Fig. 2")?;
    let runs = c.runs_or(3, 8, 32);
    let params = args.wave.pipe(2200, 10)?;
    let key = json!({"analysis": 1, "params": params, "rules": rules.to_string(), "engine": engine, "steps": STEPS, "every": EVERY});
    let ens = c.ensemble(fig.binary, &key, runs)?;
    let outcome = ens.run(STEPS, |index, seed, tick| {
        let mut pipe = engine.build(params, rules, seed)?;
        let rec = record(pipe.as_mut(), STEPS, EVERY, |_| tick(EVERY))?;
        let half = rec.n.len() / 2;
        let b = bands(&rec, half, params.rho, params.bin, params.width);
        let (_, speed) = real_space_speed(&rec.n[half..], MAX_LAG, EVERY, params.bin)?;
        Ok(RunResult {
            record: (index == 0).then_some(rec),
            s_low: b.s_low,
            contrast: b.contrast,
            speed,
        })
    })?;
    let Some(results) = outcome.complete("") else {
        return Ok(());
    };
    let out = fig.output(&c.out)?;
    let seeds = ens.seeds();
    let rec = results[0].record.as_ref().expect("run 0 keeps its record");

    let (s_low, s_low_err) = mean_sem_by(&results, |r| r.s_low);
    let (v, v_err) = mean_sem_by(&results, |r| r.speed);
    let metrics = stat_metrics([
        ("s_low_late", (s_low, s_low_err)),
        ("contrast_late", mean_sem_by(&results, |r| r.contrast)),
        ("speed_real_space", (v, v_err)),
    ]);

    // data
    let header = rec.csv_header();
    let rows = rec.csv_rows();
    out.write_csv("fig2b_spacetime_run0.csv", &header, &rows)?;
    let snap_idx: Vec<usize> = (0..SNAPS)
        .map(|j| (j as u64 * SNAP_EVERY / EVERY) as usize)
        .collect();
    let snap_rows: Vec<Vec<f64>> = snap_idx.iter().map(|&t| rows[t].clone()).collect();
    out.write_csv("fig2a_snapshots_run0.csv", &header, &snap_rows)?;
    let run_header = ["seed", "s_low_late", "contrast_late", "speed_real_space"];
    out.write_runs("runs.csv", &run_header, &seeds, &results, |r| {
        vec![r.s_low, r.contrast, r.speed]
    })?;

    // (a) snapshots: n_i every 2000 steps, time upward
    let p = params.p;
    let title = format!(
        "PH95 Fig. 2a: n_i every 2000 steps, L = 2200, p = {p}, {rules}, seed {}",
        seeds[0]
    );
    draw_snapshots(&out.path("fig2a.png"), &title, rec, &snap_idx, &params)?;
    // (b) space-time: x as in (a), time upward, darker = denser
    let (lo, hi) = value_range(&rec.n);
    space_time_upward(
        &out.path("fig2b.png"),
        &format!(
            "PH95 Fig. 2b: n_i every 80 steps (white {lo:.0}, black {hi:.0}), p = {p}, {rules}"
        ),
        &rec.n,
        EVERY,
        params.bin,
        (lo, hi),
    )?;

    let checks = vec![Check::published(
        "waves_form",
        "PH95 Fig. 2 (density waves form from the random start)",
        Estimate::new(s_low, s_low_err, results.len()),
        Claim::Above {
            threshold: WAVE_THRESHOLD,
        },
        &format!("s_low = S(1..3) over the late half / random-start value above {WAVE_THRESHOLD} (as fig1)"),
    )];
    let summary_params = json!({"L": params.length, "W": params.width, "rho": params.rho, "p": params.p, "g": params.g, "b": params.b, "bin": params.bin, "steps": STEPS, "every": EVERY, "snapshot_every": SNAP_EVERY, "runs": runs});
    let site_updates = (runs as u64 * STEPS * params.sites() as u64) as f64;
    fig.finish(&out, seeds, summary_params, site_updates, metrics, checks)?;
    Ok(())
}
