//! PH95 Fig. 7: density spectra without dissipation (p = 0, b = 0.5) and
//! without wall roughness (b = 0, p = 0.5); g = 0.5, rho = 1, L = 220, W = 11.
//! Published: white noise (alpha about 0) in both; with b = 0 a large peak at
//! v = 1/2 exactly.
//!
//! `cargo run --release --bin waves-fig7 -- --tier quick`

use granular_automata::analysis::grading::Claim;
use granular_automata::analysis::mean_spectrum::{alpha_of_mean, v_of_mean};
use granular_automata::cli::PipeArgs;
use granular_automata::drivers::acceptance::margin;
use granular_automata::drivers::margins::ALPHA_MARGIN;
use granular_automata::drivers::spectra::{
    resumable_ensemble, spectra_chart, spectrum_lines, spectrum_rows, tier_setup, SpectrumEnsemble,
    SpectrumSetup, DISCREPANCY,
};
use granular_automata::pipe::Params;
use granular_automata::run::{derive_seed, mark_discrepancies, Check, Output, Summary};
use serde_json::json;
use std::collections::BTreeMap;
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = PipeArgs::parse_about(
        "PH95 Fig. 7: white-noise spectra at p = 0 and at b = 0 (peak at v = 1/2)",
    );
    let rules = args.rules.parse()?;
    let engine = args.rules.engine(args.common.tier)?;
    // L = 220, W = 11, rho = 1, g = 0.5
    let base = Params::default();
    let cases = [
        (
            "p0",
            Params {
                p: 0.0,
                b: 0.5,
                ..base
            },
        ),
        (
            "b0",
            Params {
                p: 0.5,
                b: 0.0,
                ..base
            },
        ),
    ];
    let acceptance = args.common.tier.is_acceptance();
    let runs = args.common.runs_for(
        4,
        8,
        8,
        margin("waves-fig7", "alpha_p0").map_or(8, |m| m.runs),
    );
    let seeds: Vec<u64> = (0..runs as u64)
        .map(|i| derive_seed(args.common.seed, i))
        .collect();
    let out = Output::new(&args.common.out, "waves-fig7")?;

    let start = Instant::now();
    let setup0 = tier_setup(args.common.tier, base, rules, engine);
    let mut ens = Vec::new();
    for (name, params) in cases {
        let setup = tier_setup(args.common.tier, params, rules, engine);
        let Some(e) = resumable_ensemble(&args.common, "waves-fig7", name, &setup, runs)? else {
            continue; // a shard: nothing to analyse
        };
        out.write_csv(
            &format!("spectrum_{name}.csv"),
            &["j", "frequency", "P"],
            &spectrum_rows(&e),
        )?;
        ens.push(e);
    }
    if ens.len() < cases.len() {
        return Ok(());
    }
    let wall = start.elapsed().as_secs_f64();

    let mut lines = spectrum_lines(&ens[0], "p = 0, b = 0.5", 0);
    lines.extend(spectrum_lines(&ens[1], "b = 0, p = 0.5", 3));
    spectra_chart(
        &out.path("waves-fig7.png"),
        &format!("PH95 Fig. 7: spectra without dissipation or roughness, L = 220, {runs} runs, rules {rules}"),
        &lines,
    )?;

    let mut metrics = BTreeMap::new();
    for (e, name) in ens.iter().zip(["p0", "b0"]) {
        metrics.insert(format!("alpha_{name}"), e.alpha);
        metrics.insert(format!("alpha_{name}_err"), e.alpha_err);
        metrics.insert(format!("v_peak_{name}"), e.v_peak);
        metrics.insert(format!("v_peak_{name}_err"), e.v_err);
        metrics.insert(format!("peak_contrast_{name}"), e.fit_of_mean.contrast);
    }
    let bin_width_v = base.length as f64 / (10.0 * 2.0 * setup0.m as f64);
    let white = |name: &str, e: &SpectrumEnsemble, what: &str| {
        Check::published(
            name,
            "PH95 Fig. 7 (alpha about 0)",
            e.alpha_estimate(),
            Claim::Within {
                target: 0.0,
                margin: ALPHA_MARGIN,
            },
            &format!("white noise at {what}; mean of the per-run fitted alpha, margin Delta = {ALPHA_MARGIN} as in pipe-matrix"),
        )
    };
    let mut checks = if acceptance {
        acceptance_checks(&setup0, &ens)?
    } else {
        vec![
        white("alpha_p0", &ens[0], "p = 0"),
        white("alpha_b0", &ens[1], "b = 0"),
        // "exactly 1/2" is a spectral line: its position in the averaged
        // spectrum is fixed to a frequency bin, so the margin is two bins
        Check::published(
            "v_peak_b0",
            "PH95 Fig. 7 (peak at v = 1/2 exactly)",
            ens[1].v_estimate(),
            Claim::Within {
                target: 0.5,
                margin: 2.0 * bin_width_v,
            },
            "peak of the averaged spectrum at b = 0, SE of the per-run peaks; margin Delta = two frequency bins",
        ),
        ]
    };
    mark_discrepancies(&mut checks, DISCREPANCY);
    out.finish(&Summary {
        figure: "waves-fig7".into(),
        paper: "PH95 Fig. 7".into(),
        tier: args.common.tier,
        seeds,
        params: json!({"p0": cases[0].1, "b0": cases[1].1, "setup": setup0}),
        rules: rules.to_string(),
        engine: engine.label(),
        wall_seconds: wall,
        site_updates: (2 * runs as u64 * setup0.steps() * base.sites() as u64) as f64,
        metrics,
        missing_metrics: Default::default(),
        checks,
    })?;
    Ok(())
}

/// The checks at the acceptance tier: the estimators and margins of
/// `drivers::acceptance` (fit of the averaged spectrum, jackknife SE; peak
/// of the averaged spectrum, bootstrap SE).
fn acceptance_checks(
    setup: &SpectrumSetup,
    ens: &[SpectrumEnsemble],
) -> granular_automata::Result<Vec<Check>> {
    let mut checks = Vec::new();
    for (check, e) in [("alpha_p0", &ens[0]), ("alpha_b0", &ens[1])] {
        if let Some(m) = margin("waves-fig7", check) {
            checks.push(Check::published(
                check,
                m.source,
                alpha_of_mean(&e.spectra())?,
                m.claim(),
                &format!(
                    "fit of the averaged spectrum, jackknife SE over runs; {}",
                    m.note()
                ),
            ));
        }
    }
    if let Some(m) = margin("waves-fig7", "v_peak_b0") {
        checks.push(Check::published(
            "v_peak_b0",
            m.source,
            v_of_mean(&ens[1].spectra(), setup.params.length, setup.t0)?,
            m.claim(),
            &format!(
                "peak of the averaged spectrum at b = 0, bootstrap SE over runs; {}",
                m.note()
            ),
        ));
    }
    Ok(checks)
}
