//! PH94 Fig. 1: space-time plots of the bin densities in a periodic pipe.
//! (a) p = 0.1: density waves form; (b) p = 0: none; (c) (b) continued with
//! p = 0.1: waves return; (d) b = 0: none. L = 2200, W = 11, rho = 1,
//! g = b = 0.5, 40000 steps, bins of 10 rows sampled every 80 steps.
//!
//! `cargo run --release --bin fig1 -- --tier quick`

use clap::Parser;
use granular_automata::cli::{Common, PipeRules};
use granular_automata::pipe::record::{fig1_panels, fig1_pipe, Bands, Record};
use granular_automata::plot::{plot_err, png, value_range, SpaceTime};
use granular_automata::run::{derive_seed, ensemble, mean_sem_by, progress, stat_metrics};
use granular_automata::run::{Check, Figure};
use plotters::coord::Shift;
use plotters::prelude::*;
use serde_json::json;
use std::collections::BTreeMap;

#[derive(Parser)]
#[command(about = "PH94 Fig. 1: density waves in a pipe (space-time plots, panels a-d)")]
struct Args {
    #[command(flatten)]
    common: Common,
    #[command(flatten)]
    rules: PipeRules,
}

/// S(1..3) above twice its random-start value (lower 2-sigma bound) means
/// travelling bands; below it (upper 2-sigma bound), none. The factor 2 is
/// fixed a priori: an uncorrelated gas gives 1.
const WAVE_THRESHOLD: f64 = 2.0;
const PANELS: [&str; 4] = ["a", "b", "c", "d"];

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    let c = &args.common;
    c.reject_shard("fig1")?;
    let rules = args.rules.parse()?;
    let fig = Figure::start("fig1", "PH94 Fig. 1", c.tier, rules.to_string());
    // Bands need the full length and duration (shorter pipes or runs do not form
    // them reliably, EXPERIMENTS.md), so the tiers differ in the number of runs.
    let steps = 40000;
    let runs = c.runs_or(4, 8, 16);
    let every = 80;
    let base = fig1_pipe();
    base.validate()?;
    let out = fig.output(&c.out)?;
    let seeds: Vec<u64> = (0..runs as u64).map(|i| derive_seed(c.seed, i)).collect();

    let pb = progress(runs as u64 * 4 * steps, "fig1 steps");
    let tick = |n: u64| pb.inc(n);
    let results = ensemble(runs, |i| {
        fig1_panels(base, rules, seeds[i], steps, every, &tick)
    });
    pb.finish();
    let results: Vec<Vec<(Record, Bands)>> = results.into_iter().collect::<Result<_, _>>()?;

    // analyse: mean and standard error over seeds, per panel
    let mut metrics = BTreeMap::new();
    let mut stat = BTreeMap::new();
    let mut rows = Vec::new();
    for (k, name) in PANELS.iter().enumerate() {
        let s_low = mean_sem_by(&results, |r| r[k].1.s_low);
        metrics.extend(stat_metrics([
            (
                format!("contrast_{name}"),
                mean_sem_by(&results, |r| r[k].1.contrast),
            ),
            (format!("s_low_{name}"), s_low),
        ]));
        stat.insert(*name, s_low);
        for (r, &seed) in results.iter().zip(&seeds) {
            rows.push(vec![k as f64, seed as f64, r[k].1.contrast, r[k].1.s_low]);
        }
    }
    let header = ["panel(0=a..3=d)", "seed", "contrast", "s_low"];
    out.write_csv("panel_stats.csv", &header, &rows)?;
    for (k, name) in PANELS.iter().enumerate() {
        let rec = &results[0][k].0;
        out.write_csv(
            &format!("bins_{name}.csv"),
            &rec.csv_header(),
            &rec.csv_rows(),
        )?;
    }

    // plot: one PNG per panel and the four panels together (first seed)
    let titles = [
        "(a) p = 0.1, b = 0.5",
        "(b) p = 0, b = 0.5",
        "(c) (b) continued with p = 0.1",
        "(d) p = 0.1, b = 0",
    ];
    let draw = |area: &DrawingArea<BitMapBackend, Shift>, k: usize| {
        let (rec, bands) = &results[0][k];
        let (lo, hi) = value_range(&rec.n);
        let st = SpaceTime {
            values: &rec.n,
            white: lo,
            black: hi,
            t0: rec.t0 as f64,
            dt: rec.every as f64,
            rows_per_bin: base.bin as f64,
            time_right_to_left: false,
            bottom_at_bottom: true,
        };
        let (t, s) = (titles[k], bands.s_low);
        st.draw(
            area,
            &format!("PH94 Fig. 1{t} (n_i: white {lo:.0}, black {hi:.0}; S_low = {s:.2})"),
        )
    };
    for (k, name) in PANELS.iter().enumerate() {
        png(
            &out.path(&format!("fig1_{name}.png")),
            (1100, 650),
            |root| draw(root, k),
        )?;
    }
    png(&out.path("fig1.png"), (1800, 1150), |root| {
        let title = format!(
            "PH94 Fig. 1: bin densities, L = {}, W = 11, rho = 1, g = 0.5, rules {rules}, seed {}",
            base.length, seeds[0]
        );
        let root = root.titled(&title, ("sans-serif", 24)).map_err(plot_err)?;
        for (k, area) in root.split_evenly((2, 2)).iter().enumerate() {
            draw(area, k)?;
        }
        Ok(())
    })?;

    // compare with the published (qualitative) claims
    let waves = |n: &str| stat[n].0 - 2.0 * stat[n].1 > WAVE_THRESHOLD;
    let none = |n: &str| stat[n].0 + 2.0 * stat[n].1 < WAVE_THRESHOLD;
    let gt = |x: &str, y: &str| {
        let d = stat[x].0 - stat[y].0;
        let e = (stat[x].1.powi(2) + stat[y].1.powi(2)).sqrt();
        (d, e, d > 2.0 * e)
    };
    let mut checks = Vec::new();
    for (n, want, what) in [
        ("a", true, "waves form at p = 0.1"),
        ("b", false, "no waves at p = 0"),
        ("c", true, "waves return when p = 0.1 is switched on"),
        ("d", false, "no waves at b = 0"),
    ] {
        let ok = if want { waves(n) } else { none(n) };
        checks.push(Check::claim(
            &format!("waves_{n}"),
            stat[n].0,
            stat[n].1,
            ok,
            &format!("PH94: {what}; statistic s_low = S(1..3)/random-start value, waves if mean - 2 SE > {WAVE_THRESHOLD}, none if mean + 2 SE < {WAVE_THRESHOLD}"),
        ));
    }
    for (x, y) in [("a", "b"), ("a", "d"), ("c", "b"), ("c", "d")] {
        let (d, e, ok) = gt(x, y);
        checks.push(Check::claim(
            &format!("s_low_{x}_gt_{y}"),
            d,
            e,
            ok,
            &format!("s_low_{x} - s_low_{y} > 2 SE"),
        ));
    }
    let params = json!({"L": base.length, "W": 11, "rho": 1.0, "g": 0.5, "b": [0.5, 0.5, 0.5, 0.0], "p": [0.1, 0.0, 0.1, 0.1], "steps": steps, "every": every, "bin": base.bin});
    let site_updates = (runs as u64 * 4 * steps * base.sites() as u64) as f64;
    fig.finish(&out, seeds, params, site_updates, metrics, checks)?;
    Ok(())
}
