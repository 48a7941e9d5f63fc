//! PH94 Fig. 1: space-time plots of the bin densities in a periodic pipe.
//! (a) p = 0.1: density waves form; (b) p = 0: none; (c) (b) continued with
//! p = 0.1: waves return; (d) b = 0: none. L = 2200, W = 11, rho = 1,
//! g = b = 0.5, 40000 steps, bins of 10 rows sampled every 80 steps.
//!
//! Runs on the ensemble runner (`granular_automata::ensemble`): run r is the
//! four panels for the seed derive_seed(--seed, r), saved as it finishes
//! (resume, `--shard i/n`, `merge`); the pictures and bins CSVs show run 0.
//!
//! `cargo run --release --bin fig1 -- --tier quick`

use clap::Parser;
use granular_automata::analysis::grading::{Claim, Estimate};
use granular_automata::cli::{Common, PipeRules};
use granular_automata::drivers::claims::WAVE_THRESHOLD;
use granular_automata::pipe::record::{fig1_panels, fig1_pipe, Bands, Record};
use granular_automata::plot::{plot_err, png, value_range, SpaceTime};
use granular_automata::run::{mean_sem_by, stat_metrics, Check, Figure};
use plotters::coord::Shift;
use plotters::prelude::*;
use serde::{Deserialize, Serialize};
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

const PANELS: [&str; 4] = ["a", "b", "c", "d"];

#[derive(Debug, Clone, Serialize, Deserialize)]
struct RunResult {
    /// The records of the four panels (run 0 only, for the pictures and
    /// the bins CSVs).
    records: Option<Vec<Record>>,
    /// The band statistics of the four panels over their late halves.
    bands: Vec<Bands>,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    let c = &args.common;
    let rules = args.rules.parse()?;
    let engine = args.rules.engine(args.common.tier)?;
    let mut fig = Figure::start("fig1", "PH94 Fig. 1", c.tier, rules.to_string());
    fig.engine = engine.label();
    // Bands need the full length and duration (shorter pipes or runs do not form
    // them reliably, EXPERIMENTS.md), so the tiers differ in the number of runs.
    let steps = 40000;
    let runs = c.runs_or(4, 8, 16);
    let every = 80;
    let base = fig1_pipe();
    base.validate()?;
    let key = json!({"analysis": 1, "params": base, "rules": rules.to_string(), "engine": engine, "steps": steps, "every": every});
    let ens = c.ensemble(fig.binary, &key, runs)?;
    let outcome = ens.run(4 * steps, |index, seed, tick| {
        let panels = fig1_panels(base, rules, engine, seed, steps, every, tick)?;
        let (records, bands): (Vec<Record>, _) = panels.into_iter().unzip();
        let records = (index == 0).then_some(records);
        Ok(RunResult { records, bands })
    })?;
    let Some(results) = outcome.complete("") else {
        return Ok(());
    };
    let out = fig.output(&c.out)?;
    let seeds = ens.seeds();
    let records = results[0]
        .records
        .as_ref()
        .expect("run 0 keeps its records");

    // analyse: mean and standard error over seeds, per panel
    let mut metrics = BTreeMap::new();
    let mut stat = BTreeMap::new();
    let mut rows = Vec::new();
    for (k, name) in PANELS.iter().enumerate() {
        let s_low = mean_sem_by(&results, |r| r.bands[k].s_low);
        metrics.extend(stat_metrics([
            (
                format!("contrast_{name}"),
                mean_sem_by(&results, |r| r.bands[k].contrast),
            ),
            (format!("s_low_{name}"), s_low),
        ]));
        stat.insert(*name, Estimate::new(s_low.0, s_low.1, results.len()));
        for (r, &seed) in results.iter().zip(&seeds) {
            rows.push(vec![
                k as f64,
                seed as f64,
                r.bands[k].contrast,
                r.bands[k].s_low,
            ]);
        }
    }
    let header = ["panel(0=a..3=d)", "seed", "contrast", "s_low"];
    out.write_csv("panel_stats.csv", &header, &rows)?;
    for (k, name) in PANELS.iter().enumerate() {
        let rec = &records[k];
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
        let (rec, bands) = (&records[k], &results[0].bands[k]);
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

    // compare with the published (qualitative) claims: s_low above (waves)
    // or below (none) the threshold, by the one grading rule
    let mut checks = Vec::new();
    for (n, want, what) in [
        ("a", true, "waves form at p = 0.1"),
        ("b", false, "no waves at p = 0"),
        ("c", true, "waves return when p = 0.1 is switched on"),
        ("d", false, "no waves at b = 0"),
    ] {
        let threshold = WAVE_THRESHOLD;
        let claim = if want {
            Claim::Above { threshold }
        } else {
            Claim::Below { threshold }
        };
        checks.push(Check::published(
            &format!("waves_{n}"),
            &format!("PH94 Fig. 1{n}"),
            stat[n],
            claim,
            &format!("{what}; statistic s_low = S(1..3)/random-start value, threshold {threshold} fixed a priori (twice the structureless value)"),
        ));
    }
    for (x, y) in [("a", "b"), ("a", "d"), ("c", "b"), ("c", "d")] {
        checks.push(Check::published(
            &format!("s_low_{x}_gt_{y}"),
            &format!("PH94 Fig. 1{x} against 1{y}"),
            stat[x].minus(stat[y]),
            Claim::Above { threshold: 0.0 },
            &format!("s_low_{x} - s_low_{y} > 0"),
        ));
    }
    let params = json!({"L": base.length, "W": 11, "rho": 1.0, "g": 0.5, "b": [0.5, 0.5, 0.5, 0.0], "p": [0.1, 0.0, 0.1, 0.1], "steps": steps, "every": every, "bin": base.bin});
    let site_updates = (runs as u64 * 4 * steps * base.sites() as u64) as f64;
    fig.finish(&out, seeds, params, site_updates, metrics, checks)?;
    Ok(())
}
