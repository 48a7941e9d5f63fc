//! PH95 Fig. 9: alpha and the wave speed v against the mean density rho
//! (L = 220, W = 11, p = b = g = 0.5). Above some rho the model's own
//! validity ends (rest particles outnumber sites, MODEL.md A4): such runs are
//! counted per point and the limit is reported, not a crash. Blind
//! reproduction: the published values are not used.
//!
//! `cargo run --release --bin waves-fig9 -- --tier quick`

use clap::Parser;
use granular_automata::cli::{Common, PipeRules};
use granular_automata::pipe::spectra::tier_setup;
use granular_automata::pipe::sweep::{
    header, plot_alpha_v, point_metrics, run_sweep, site_updates, Curve, SweepPoint,
};
use granular_automata::pipe::Params;
use granular_automata::plot::{errorbar_chart_at, ErrSeries, PALETTE};
use granular_automata::run::{derive_seed, Check, Output, Summary};
use plotters::chart::SeriesLabelPosition;
use serde_json::json;
use std::collections::BTreeMap;
use std::time::Instant;

#[derive(Parser)]
#[command(
    about = "PH95 Fig. 9: alpha and wave speed against the density rho, with the model's validity limit"
)]
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
    let rhos: &[f64] = c.tier.pick(
        &[0.2, 0.6, 1.0, 1.4, 2.0, 3.0][..],
        &[0.2, 0.4, 0.6, 0.8, 1.0, 1.2, 1.4, 1.6, 1.8, 2.0, 2.5, 3.0][..],
        &[
            0.2, 0.4, 0.6, 0.8, 1.0, 1.2, 1.4, 1.6, 1.8, 2.0, 2.2, 2.5, 3.0,
        ][..],
    );
    let base = Params {
        length: 220,
        width: 11,
        p: 0.5,
        g: 0.5,
        b: 0.5,
        ..Params::default()
    };
    let points: Vec<SweepPoint> = rhos
        .iter()
        .map(|&rho| SweepPoint {
            label: format!("rho{rho}"),
            x: vec![rho],
            params: Params { rho, ..base },
        })
        .collect();
    let runs = c.runs_or(2, 8, 32);
    let setup_of = |p| tier_setup(c.tier, p, rules);
    let start = Instant::now();
    let Some(res) = run_sweep(c, "waves-fig9", &points, runs, setup_of)? else {
        return Ok(());
    };
    let wall = start.elapsed().as_secs_f64();

    let out = Output::new(&c.out, "waves-fig9")?;
    let rows: Vec<Vec<f64>> = res.iter().map(|r| r.row()).collect();
    out.write_csv("waves-fig9.csv", &header(&["rho"]), &rows)?;
    let all: Vec<_> = res.iter().collect();
    let title = format!("PH95 Fig. 9: L = 220, p = b = g = 0.5, {runs} runs/point, rules {rules}");
    plot_alpha_v(
        out.dir(),
        "waves-fig9",
        &title,
        "mean density rho (particles per site)",
        &[Curve {
            label: "valid runs only",
            points: &all,
            xi: 0,
        }],
    )?;
    let frac: Vec<(f64, f64, f64)> = res
        .iter()
        .map(|r| (r.point.x[0], r.invalid as f64 / runs as f64, 0.0))
        .collect();
    errorbar_chart_at(
        &out.path("waves-fig9_validity.png"),
        &format!("{title}: model validity (MODEL.md A4)"),
        "mean density rho (particles per site)",
        "fraction of runs stopped: rest particles exceed sites",
        &[ErrSeries::new("invalid runs / runs", frac, PALETTE[1])],
        SeriesLabelPosition::UpperLeft,
    )?;

    let mut metrics = BTreeMap::new();
    for r in &res {
        point_metrics(r, &mut metrics);
        metrics.insert(
            format!("invalid_fraction_{}", r.point.label),
            r.invalid as f64 / runs as f64,
        );
    }
    // the validity limit: smallest swept rho where any / all runs are invalid
    let any = res.iter().find(|r| r.invalid > 0).map(|r| r.point.x[0]);
    let all_inv = res.iter().find(|r| r.valid == 0).map(|r| r.point.x[0]);
    if let Some(x) = any {
        metrics.insert("rho_limit_any_invalid".into(), x);
    }
    if let Some(x) = all_inv {
        metrics.insert("rho_limit_all_invalid".into(), x);
    }
    let below: Vec<_> = res.iter().filter(|r| r.point.x[0] <= 1.0).collect();
    let invalid_below: usize = below.iter().map(|r| r.invalid).sum();
    let last = res.last().expect("at least one point");
    let checks = vec![
        Check::claim(
            "valid_up_to_rho_1",
            invalid_below as f64,
            0.0,
            invalid_below == 0,
            "internal consistency: no run at rho <= 1 leaves the model's validity (MODEL.md A11: only rho ~ 2 did)",
        ),
        Check::claim(
            "validity_limit_detected",
            last.invalid as f64,
            0.0,
            last.invalid > 0,
            &format!(
                "the sweep reaches the model's validity limit: at least one run at the largest rho = {} stops with RestExceedsSites/RelocationStuck and is counted, not fatal",
                last.point.x[0]
            ),
        ),
    ];
    out.finish(&Summary {
        figure: "waves-fig9".into(),
        paper: "PH95 Fig. 9".into(),
        tier: c.tier,
        seeds: (0..runs as u64).map(|i| derive_seed(c.seed, i)).collect(),
        params: json!({"base": base, "rho": rhos, "setup": setup_of(base)}),
        rules: rules.to_string(),
        wall_seconds: wall,
        site_updates: site_updates(&points, runs, setup_of),
        metrics,
        checks,
    })?;
    Ok(())
}
