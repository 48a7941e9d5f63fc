//! PH95 Fig. 10: (a) alpha against the wall roughness b (p = g = 0.5,
//! rho = 1) and against gravity g (p = b = 0.5); (b) the wave speed v against
//! b from 0.25 to 1 for g = 0.5 and the smaller g = 0.2. L = 220, W = 11.
//! Blind reproduction: the published values are not used.
//!
//! `cargo run --release --bin waves-fig10 -- --tier quick`

use clap::Parser;
use granular_automata::cli::{Common, PipeRules};
use granular_automata::pipe::spectra::tier_setup;
use granular_automata::pipe::sweep::{
    exceeds, fig7_check, header, point_metrics, run_sweep, site_updates, PointResult, SweepPoint,
    FIG7_QUICK_ALPHA_B0,
};
use granular_automata::pipe::Params;
use granular_automata::plot::{errorbar_chart, ErrSeries, PALETTE};
use granular_automata::run::{derive_seed, Check, Output, Summary};
use serde_json::json;
use std::collections::BTreeMap;
use std::time::Instant;

#[derive(Parser)]
#[command(about = "PH95 Fig. 10: alpha against b and g, wave speed against b for two gravities")]
struct Args {
    #[command(flatten)]
    common: Common,
    #[command(flatten)]
    rules: PipeRules,
}

/// The smaller gravity of panel (b).
const G_LOW: f64 = 0.2;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    let rules = args.rules.parse()?;
    let c = &args.common;
    let bs: &[f64] = c.tier.pick(
        &[0.0, 0.05, 0.25, 0.5, 1.0][..],
        &[0.0, 0.02, 0.05, 0.1, 0.25, 0.5, 0.75, 1.0][..],
        &[0.0, 0.02, 0.05, 0.1, 0.25, 0.4, 0.5, 0.6, 0.75, 0.9, 1.0][..],
    );
    let gs: &[f64] = c.tier.pick(
        &[0.2, 0.5, 1.0][..],
        &[0.1, 0.2, 0.3, 0.5, 0.7, 1.0][..],
        &[0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0][..],
    );
    let bv: Vec<f64> = bs.iter().copied().filter(|&b| b >= 0.25).collect();
    let base = Params {
        length: 220,
        width: 11,
        rho: 1.0,
        p: 0.5,
        g: 0.5,
        b: 0.5,
        ..Params::default()
    };
    let point = |b: f64, g: f64| SweepPoint {
        label: format!("b{b}_g{g}"),
        x: vec![b, g],
        params: Params { b, g, ..base },
    };
    // panel (a) over b, panel (a) over g, panel (b) at G_LOW (g = 0.5 is the first)
    let panel_b: Vec<SweepPoint> = bs.iter().map(|&b| point(b, 0.5)).collect();
    let panel_g: Vec<SweepPoint> = gs.iter().map(|&g| point(0.5, g)).collect();
    let panel_low: Vec<SweepPoint> = bv.iter().map(|&b| point(b, G_LOW)).collect();
    let mut points: Vec<SweepPoint> = Vec::new();
    for p in panel_b.iter().chain(&panel_g).chain(&panel_low) {
        if !points.iter().any(|q| q.label == p.label) {
            points.push(p.clone());
        }
    }
    let runs = c.runs_or(2, 8, 32);
    let setup_of = |p| tier_setup(c.tier, p, rules);
    let start = Instant::now();
    let Some(res) = run_sweep(c, "waves-fig10", &points, runs, setup_of)? else {
        return Ok(());
    };
    let wall = start.elapsed().as_secs_f64();
    let find = |p: &SweepPoint| -> &PointResult {
        res.iter()
            .find(|r| r.point.label == p.label)
            .expect("point computed")
    };
    let rb: Vec<&PointResult> = panel_b.iter().map(find).collect();
    let rg: Vec<&PointResult> = panel_g.iter().map(find).collect();
    let rv_hi: Vec<&PointResult> = rb
        .iter()
        .copied()
        .filter(|r| r.point.x[0] >= 0.25)
        .collect();
    let rv_lo: Vec<&PointResult> = panel_low.iter().map(find).collect();

    let out = Output::new(&c.out, "waves-fig10")?;
    let h = header(&["b", "g"]);
    let rows = |v: &[&PointResult]| -> Vec<Vec<f64>> { v.iter().map(|r| r.row()).collect() };
    let all: Vec<&PointResult> = res.iter().collect();
    out.write_csv("waves-fig10.csv", &h, &rows(&all))?;
    out.write_csv("waves-fig10a_b.csv", &h, &rows(&rb))?;
    out.write_csv("waves-fig10a_g.csv", &h, &rows(&rg))?;
    let mut vb = rv_hi.clone();
    vb.extend(rv_lo.iter().copied());
    out.write_csv("waves-fig10b.csv", &h, &rows(&vb))?;

    let title =
        format!("PH95 Fig. 10: L = 220, rho = 1, p = 0.5, {runs} runs/point, rules {rules}");
    let alpha = |v: &[&PointResult], xi: usize| -> Vec<(f64, f64, f64)> {
        v.iter()
            .map(|r| (r.point.x[xi], r.alpha, r.alpha_err))
            .collect()
    };
    let speed = |v: &[&PointResult]| -> Vec<(f64, f64, f64)> {
        v.iter().map(|r| (r.point.x[0], r.v, r.v_err)).collect()
    };
    errorbar_chart(
        &out.path("waves-fig10a_b.png"),
        &format!("{title}: (a) alpha against b"),
        "wall roughness b (bounce-back probability)",
        "alpha (mean over runs +- SE)",
        &[ErrSeries::new("g = 0.5", alpha(&rb, 0), PALETTE[0])],
    )?;
    errorbar_chart(
        &out.path("waves-fig10a_g.png"),
        &format!("{title}: (a) alpha against g"),
        "gravity g (probability of a gravity move)",
        "alpha (mean over runs +- SE)",
        &[ErrSeries::new("b = 0.5", alpha(&rg, 1), PALETTE[2])],
    )?;
    errorbar_chart(
        &out.path("waves-fig10b.png"),
        &format!("{title}: (b) v against b"),
        "wall roughness b (bounce-back probability)",
        "v from the spectral peak, rows/step (mean +- SE)",
        &[
            ErrSeries::new("g = 0.5", speed(&rv_hi), PALETTE[0]),
            ErrSeries::new(&format!("g = {G_LOW}"), speed(&rv_lo), PALETTE[1]),
        ],
    )?;

    let mut metrics = BTreeMap::new();
    for r in &res {
        point_metrics(r, &mut metrics);
    }
    let b0 = rb[0];
    let bmid = find(&point(0.5, 0.5));
    let checks =
        vec![
        fig7_check("b0_matches_waves_fig7", b0, FIG7_QUICK_ALPHA_B0, "b = 0, p = 0.5"),
        Check::claim(
            "alpha_rises_with_b",
            bmid.alpha - b0.alpha,
            (bmid.alpha_err.powi(2) + b0.alpha_err.powi(2)).sqrt(),
            exceeds((bmid.alpha, bmid.alpha_err), (b0.alpha, b0.alpha_err), 3.0),
            "internal consistency (PH95 Figs. 2, 7): alpha(b = 0.5) - alpha(b = 0) > 3 combined SE",
        ),
    ];
    out.finish(&Summary {
        figure: "waves-fig10".into(),
        paper: "PH95 Fig. 10".into(),
        tier: c.tier,
        seeds: (0..runs as u64).map(|i| derive_seed(c.seed, i)).collect(),
        params: json!({"base": base, "b": bs, "g": gs, "b_for_v": bv, "g_low": G_LOW, "setup": setup_of(base)}),
        rules: rules.to_string(),
        wall_seconds: wall,
        site_updates: site_updates(&points, runs, setup_of),
        metrics,
        checks,
    })?;
    Ok(())
}
