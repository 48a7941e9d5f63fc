//! PH95 Fig. 8: alpha and the wave speed v against the dissipation p
//! (L = 220, W = 11, rho = 1, b = g = 0.5; spectrum of bin 0 sampled every
//! 10 steps). Blind reproduction: the published values are not used.
//!
//! `cargo run --release --bin waves-fig8 -- --tier quick`

use clap::Parser;
use granular_automata::cli::{Common, PipeRules};
use granular_automata::pipe::spectra::tier_setup;
use granular_automata::pipe::sweep::{
    exceeds, fig7_check, header, plot_alpha_v, point_metrics, run_sweep, site_updates, Curve,
    SweepPoint, FIG7_QUICK_ALPHA_P0,
};
use granular_automata::pipe::Params;
use granular_automata::run::{derive_seed, Check, Output, Summary};
use serde_json::json;
use std::collections::BTreeMap;
use std::time::Instant;

#[derive(Parser)]
#[command(about = "PH95 Fig. 8: alpha and wave speed against the dissipation p")]
struct Args {
    #[command(flatten)]
    common: Common,
    #[command(flatten)]
    rules: PipeRules,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    let rules = args.rules.parse()?;
    let c = &args.common;
    let ps: &[f64] = c.tier.pick(
        &[0.0, 0.05, 0.2, 0.5, 1.0][..],
        &[0.0, 0.02, 0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 1.0][..],
        &[
            0.0, 0.02, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0,
        ][..],
    );
    let base = Params {
        length: 220,
        width: 11,
        rho: 1.0,
        g: 0.5,
        b: 0.5,
        ..Params::default()
    };
    let points: Vec<SweepPoint> = ps
        .iter()
        .map(|&p| SweepPoint {
            label: format!("p{p}"),
            x: vec![p],
            params: Params { p, ..base },
        })
        .collect();
    let runs = c.runs_or(2, 8, 32);
    let setup_of = |p| tier_setup(c.tier, p, rules);
    let start = Instant::now();
    let Some(res) = run_sweep(c, "waves-fig8", &points, runs, setup_of)? else {
        return Ok(());
    };
    let wall = start.elapsed().as_secs_f64();

    let out = Output::new(&c.out, "waves-fig8")?;
    let rows: Vec<Vec<f64>> = res.iter().map(|r| r.row()).collect();
    out.write_csv("waves-fig8.csv", &header(&["p"]), &rows)?;
    let all: Vec<_> = res.iter().collect();
    plot_alpha_v(
        out.dir(),
        "waves-fig8",
        &format!("PH95 Fig. 8: L = 220, rho = 1, b = g = 0.5, {runs} runs/point, rules {rules}"),
        "dissipation p",
        &[Curve {
            label: "b = g = 0.5, rho = 1",
            points: &all,
            xi: 0,
        }],
    )?;

    let mut metrics = BTreeMap::new();
    for r in &res {
        point_metrics(r, &mut metrics);
    }
    let at = |p: f64| {
        res.iter()
            .find(|r| r.point.x[0] == p)
            .expect("point present")
    };
    let (r0, r5) = (at(0.0), at(0.5));
    let checks =
        vec![
        fig7_check("p0_matches_waves_fig7", r0, FIG7_QUICK_ALPHA_P0, "p = 0, b = 0.5"),
        Check::claim(
            "alpha_rises_with_p",
            r5.alpha - r0.alpha,
            (r5.alpha_err.powi(2) + r0.alpha_err.powi(2)).sqrt(),
            exceeds((r5.alpha, r5.alpha_err), (r0.alpha, r0.alpha_err), 3.0),
            "internal consistency (PH95 Figs. 2, 7): alpha(p = 0.5) - alpha(p = 0) > 3 combined SE",
        ),
    ];
    out.finish(&Summary {
        figure: "waves-fig8".into(),
        paper: "PH95 Fig. 8".into(),
        tier: c.tier,
        seeds: (0..runs as u64).map(|i| derive_seed(c.seed, i)).collect(),
        params: json!({"base": base, "p": ps, "setup": setup_of(base)}),
        rules: rules.to_string(),
        wall_seconds: wall,
        site_updates: site_updates(&points, runs, setup_of),
        metrics,
        checks,
    })?;
    Ok(())
}
