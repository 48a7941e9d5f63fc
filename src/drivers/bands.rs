//! PH94 Fig. 1, density bands in a periodic pipe, over an ensemble of runs
//! (`fig1`): run r is the four panels ((a) p = 0.1; (b) p = 0; (c) (b)
//! continued with p = 0.1; (d) b = 0; [`fig1_panels`](crate::pipe::record::fig1_panels)) for one seed, with
//! the band statistics of MODEL.md A11 over their late halves; the metrics
//! and the checks of the published (qualitative) claims from them, and the
//! space-time plots of run 0. Also the snapshots of PH95 Fig. 2a
//! ([`draw_snapshots`](crate::drivers::bands::draw_snapshots)).

use super::claims::WAVE_THRESHOLD;
use crate::analysis::grading::{Claim, Estimate};
use crate::error::{Error, ErrorKind, Result};
use crate::pipe::record::{fig1_panels, Bands, Record};
use crate::pipe::{Engine, Params, Rules};
use crate::plot::{plot_err, png, stacked_profiles, value_range, SpaceTime};
use crate::run::{mean_sem_by, stat_metrics, Check, Output};
use plotters::coord::Shift;
use plotters::prelude::*;
use serde::{Deserialize, Serialize};
use serde_json::json;
use std::collections::BTreeMap;

/// The panels of PH94 Fig. 1, in run order.
pub const PANELS: [&str; 4] = ["a", "b", "c", "d"];

/// The caption of each panel of PH94 Fig. 1.
const TITLES: [&str; 4] = [
    "(a) p = 0.1, b = 0.5",
    "(b) p = 0, b = 0.5",
    "(c) (b) continued with p = 0.1",
    "(d) p = 0.1, b = 0",
];

/// The set-up of one run of PH94 Fig. 1: the pipe of panel (a), the rules,
/// the engine, the steps per panel and the sampling interval.
#[derive(Debug, Clone, Copy)]
pub struct Fig1Setup {
    /// The pipe of panel (a) ([`crate::pipe::record::fig1_pipe`]).
    pub base: Params,
    /// The rule reading.
    pub rules: Rules,
    /// The engine that runs it.
    pub engine: Engine,
    /// Steps per panel (40000 in the paper).
    pub steps: u64,
    /// Steps between the samples of the bins (80 in the paper).
    pub every: u64,
}

/// What one run of PH94 Fig. 1 keeps (the ensemble's run file).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Fig1Run {
    /// The records of the four panels (run 0 only, for the pictures and
    /// the bins CSVs).
    pub records: Option<Vec<Record>>,
    /// The band statistics of the four panels over their late halves.
    pub bands: Vec<Bands>,
}

impl Fig1Setup {
    /// The configuration key of the ensemble runner: everything that
    /// changes a run's result.
    pub fn key(&self) -> serde_json::Value {
        json!({"analysis": 1, "params": self.base, "rules": self.rules.to_string(), "engine": self.engine, "steps": self.steps, "every": self.every})
    }

    /// Run `index` of the ensemble with `seed`: the four panels, their
    /// records kept for run 0 only. `tick(steps)` reports progress.
    pub fn run(&self, index: usize, seed: u64, tick: &(dyn Fn(u64) + Sync)) -> Result<Fig1Run> {
        let s = self;
        let panels = fig1_panels(s.base, s.rules, s.engine, seed, s.steps, s.every, tick)?;
        let (records, bands): (Vec<Record>, _) = panels.into_iter().unzip();
        let records = (index == 0).then_some(records);
        Ok(Fig1Run { records, bands })
    }

    /// The parameters of `summary.json`.
    pub fn params(&self) -> serde_json::Value {
        json!({"L": self.base.length, "W": 11, "rho": 1.0, "g": 0.5, "b": [0.5, 0.5, 0.5, 0.0], "p": [0.1, 0.0, 0.1, 0.1], "steps": self.steps, "every": self.every, "bin": self.base.bin})
    }
}

/// The band statistics of PH94 Fig. 1 over `results`: per panel the metrics
/// `contrast_<panel>` and `s_low_<panel>` (mean and standard error over
/// runs) and the estimate of s_low that the checks grade.
pub fn fig1_metrics(results: &[Fig1Run]) -> (BTreeMap<String, f64>, BTreeMap<&str, Estimate>) {
    let mut metrics = BTreeMap::new();
    let mut stat = BTreeMap::new();
    for (k, name) in PANELS.iter().enumerate() {
        let s_low = mean_sem_by(results, |r| r.bands[k].s_low);
        metrics.extend(stat_metrics([
            (
                format!("contrast_{name}"),
                mean_sem_by(results, |r| r.bands[k].contrast),
            ),
            (format!("s_low_{name}"), s_low),
        ]));
        stat.insert(*name, Estimate::new(s_low.0, s_low.1, results.len()));
    }
    (metrics, stat)
}

/// `panel_stats.csv`: the contrast and s_low of every panel of every run,
/// with its seed (`seeds`, in run order).
pub fn write_panel_stats(out: &Output, results: &[Fig1Run], seeds: &[u64]) -> Result<()> {
    let mut rows = Vec::new();
    for k in 0..PANELS.len() {
        for (r, &seed) in results.iter().zip(seeds) {
            let b = &r.bands[k];
            rows.push(vec![k as f64, seed as f64, b.contrast, b.s_low]);
        }
    }
    let header = ["panel(0=a..3=d)", "seed", "contrast", "s_low"];
    out.write_csv("panel_stats.csv", &header, &rows)?;
    Ok(())
}

/// The published (qualitative) claims of PH94 Fig. 1 from the s_low of each
/// panel (`stat`, from [`fig1_metrics`]): above (waves) or below (none)
/// [`WAVE_THRESHOLD`], and each panel with waves above each without, by
/// the one grading rule.
pub fn fig1_checks(stat: &BTreeMap<&str, Estimate>) -> Vec<Check> {
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
    checks
}

/// The pictures of PH94 Fig. 1 from run 0 (`run0`, seed `seed`) of
/// `setup`: the bins of each panel (`bins_<panel>.csv`), one space-time
/// plot per panel (`fig1_<panel>.png`) and the four panels together
/// (`fig1.png`).
pub fn draw_fig1(out: &Output, setup: &Fig1Setup, run0: &Fig1Run, seed: u64) -> Result<()> {
    let records = run0.records.as_ref().ok_or_else(|| {
        Error::new(
            ErrorKind::BadSeries,
            "run 0 of fig1 kept no records; delete its run file and rerun",
        )
    })?;
    for (k, name) in PANELS.iter().enumerate() {
        let rec = &records[k];
        out.write_csv(
            &format!("bins_{name}.csv"),
            &rec.csv_header(),
            &rec.csv_rows(),
        )?;
    }
    let draw = |area: &DrawingArea<BitMapBackend, Shift>, k: usize| {
        let (rec, bands) = (&records[k], &run0.bands[k]);
        let (lo, hi) = value_range(&rec.n);
        let st = SpaceTime {
            values: &rec.n,
            white: lo,
            black: hi,
            t0: rec.t0 as f64,
            dt: rec.every as f64,
            rows_per_bin: setup.base.bin as f64,
            time_right_to_left: false,
            bottom_at_bottom: true,
        };
        let (t, s) = (TITLES[k], bands.s_low);
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
            "PH94 Fig. 1: bin densities, L = {}, W = 11, rho = 1, g = 0.5, rules {}, seed {seed}",
            setup.base.length, setup.rules
        );
        let root = root.titled(&title, ("sans-serif", 24)).map_err(plot_err)?;
        for (k, area) in root.split_evenly((2, 2)).iter().enumerate() {
            draw(area, k)?;
        }
        Ok(())
    })
}

/// PH95 Fig. 2a at `path`: the bin densities n_i of `rec` at the samples
/// `snap_idx`, one line per snapshot offset by its index (time upward), x
/// the distance from the top of the pipe (gravity from left to right).
pub fn draw_snapshots(
    path: &std::path::Path,
    title: &str,
    rec: &Record,
    snap_idx: &[usize],
    params: &Params,
) -> Result<()> {
    let (l, bin) = (params.length as f64, params.bin as f64);
    let k = params.bins();
    let x: Vec<f64> = (0..k).map(|i| l - (i as f64 + 0.5) * bin).collect();
    let mean = rec.n[0].iter().sum::<f64>() / k as f64;
    let amp = snap_idx
        .iter()
        .flat_map(|&t| rec.n[t].iter().map(move |v| (v - mean).abs()))
        .fold(0.0f64, f64::max)
        .max(1.0);
    let snaps: Vec<(String, &[f64])> = snap_idx
        .iter()
        .map(|&t| (format!("t = {}", rec.time(t)), &rec.n[t][..]))
        .collect();
    stacked_profiles(
        path,
        title,
        "n_i - mean, offset by 2000 steps per line (time upward)",
        l,
        &x,
        &snaps,
        (mean, 1.2 * amp),
    )
}
