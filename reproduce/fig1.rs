//! PH94 Fig. 1: space-time plots of the bin densities in a periodic pipe.
//! (a) p = 0.1: density waves form; (b) p = 0: none; (c) (b) continued with
//! p = 0.1: waves return; (d) b = 0: none. L = 2200, W = 11, rho = 1,
//! g = b = 0.5, 40000 steps, bins of 10 rows sampled every 80 steps.
//!
//! `cargo run --release --bin fig1 -- --tier quick`

use clap::Parser;
use granular_automata::cli::{Common, PipeRules};
use granular_automata::pipe::record::{fig1_panels, Bands, Record};
use granular_automata::pipe::Params;
use granular_automata::plot::{plot_err, register_fonts, SpaceTime};
use granular_automata::run::{derive_seed, ensemble, mean_sem, progress, Check, Output, Summary};
use plotters::prelude::*;
use serde_json::json;
use std::collections::BTreeMap;
use std::time::Instant;

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
    args.common.reject_shard("fig1")?;
    let tier = args.common.tier;
    let rules = args.rules.parse()?;
    // Bands need the full length and duration (shorter pipes or runs do not form
    // them reliably, EXPERIMENTS.md), so the tiers differ in the number of runs.
    let (length, steps) = (2200, 40000);
    let runs = args.common.runs_or(4, 8, 16);
    let every = 80;
    let base = Params {
        length,
        width: 11,
        rho: 1.0,
        p: 0.1,
        g: 0.5,
        b: 0.5,
        ..Params::default()
    };
    base.validate()?;
    let out = Output::new(&args.common.out, "fig1")?;
    let seeds: Vec<u64> = (0..runs as u64)
        .map(|i| derive_seed(args.common.seed, i))
        .collect();

    let start = Instant::now();
    let pb = progress(runs as u64 * 4 * steps, "fig1 steps");
    let tick = |n: u64| pb.inc(n);
    let results = ensemble(runs, |i| {
        fig1_panels(base, rules, seeds[i], steps, every, &tick)
    });
    pb.finish();
    let results: Vec<Vec<(Record, Bands)>> = results.into_iter().collect::<Result<_, _>>()?;
    let wall = start.elapsed().as_secs_f64();

    // analyse: mean and standard error over seeds, per panel
    let mut metrics = BTreeMap::new();
    let mut stat = BTreeMap::new();
    let mut rows = Vec::new();
    for (k, name) in PANELS.iter().enumerate() {
        let c: Vec<f64> = results.iter().map(|r| r[k].1.contrast).collect();
        let s: Vec<f64> = results.iter().map(|r| r[k].1.s_low).collect();
        let (cm, ce) = mean_sem(&c);
        let (sm, se) = mean_sem(&s);
        metrics.insert(format!("contrast_{name}"), cm);
        metrics.insert(format!("contrast_{name}_err"), ce);
        metrics.insert(format!("s_low_{name}"), sm);
        metrics.insert(format!("s_low_{name}_err"), se);
        stat.insert(*name, (sm, se));
        for (i, r) in results.iter().enumerate() {
            rows.push(vec![
                k as f64,
                seeds[i] as f64,
                r[k].1.contrast,
                r[k].1.s_low,
            ]);
        }
    }
    out.write_csv(
        "panel_stats.csv",
        &["panel(0=a..3=d)", "seed", "contrast", "s_low"],
        &rows,
    )?;
    for (k, name) in PANELS.iter().enumerate() {
        let rec = &results[0][k].0;
        let header: Vec<String> = std::iter::once("t".to_string())
            .chain((0..rec.n[0].len()).map(|i| format!("n{i}")))
            .collect();
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
        out.write_csv(&format!("bins_{name}.csv"), &header, &rows)?;
    }

    // plot: one PNG per panel and the four panels together (first seed)
    let titles = [
        "(a) p = 0.1, b = 0.5",
        "(b) p = 0, b = 0.5",
        "(c) (b) continued with p = 0.1",
        "(d) p = 0.1, b = 0",
    ];
    register_fonts();
    let draw = |area: &DrawingArea<BitMapBackend, plotters::coord::Shift>,
                k: usize|
     -> Result<(), Box<dyn std::error::Error>> {
        let rec = &results[0][k].0;
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
        let title = format!(
            "PH94 Fig. 1{} (n_i: white {lo:.0}, black {hi:.0}; S_low = {:.2})",
            titles[k], results[0][k].1.s_low
        );
        st.draw(area, &title)?;
        Ok(())
    };
    for (k, name) in PANELS.iter().enumerate() {
        let path = out.path(&format!("fig1_{name}.png"));
        let root = BitMapBackend::new(&path, (1100, 650)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        draw(&root, k)?;
        root.present().map_err(plot_err)?;
    }
    let path = out.path("fig1.png");
    let root = BitMapBackend::new(&path, (1800, 1150)).into_drawing_area();
    root.fill(&WHITE).map_err(plot_err)?;
    let root = root.titled(&format!("PH94 Fig. 1: bin densities, L = {length}, W = 11, rho = 1, g = 0.5, rules {rules}, seed {}", seeds[0]), ("sans-serif", 24)).map_err(plot_err)?;
    for (k, area) in root.split_evenly((2, 2)).iter().enumerate() {
        draw(area, k)?;
    }
    root.present().map_err(plot_err)?;

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
    let summary = Summary {
        figure: "fig1".into(),
        paper: "PH94 Fig. 1".into(),
        tier,
        seeds: seeds.clone(),
        params: json!({"L": length, "W": 11, "rho": 1.0, "g": 0.5, "b": [0.5, 0.5, 0.5, 0.0], "p": [0.1, 0.0, 0.1, 0.1], "steps": steps, "every": every, "bin": base.bin}),
        rules: rules.to_string(),
        wall_seconds: wall,
        site_updates: (runs as u64 * 4 * steps * base.sites() as u64) as f64,
        metrics,
        checks,
    };
    out.finish(&summary)?;
    Ok(())
}
