//! PH95 Fig. 7: density spectra without dissipation (p = 0, b = 0.5) and
//! without wall roughness (b = 0, p = 0.5); g = 0.5, rho = 1, L = 220, W = 11.
//! Published: white noise (alpha about 0) in both; with b = 0 a large peak at
//! v = 1/2 exactly.
//!
//! `cargo run --release --bin waves-fig7 -- --tier quick`

use granular_automata::cli::PipeArgs;
use granular_automata::drivers::acceptance::margin;
use granular_automata::drivers::spectra::{
    resumable_ensemble, spectra_chart, spectrum_lines, spectrum_rows, tier_setup, DISCREPANCY,
};
use granular_automata::drivers::white_noise;
use granular_automata::pipe::Params;
use granular_automata::run::{mark_discrepancies, run_seeds, Output, Summary};
use serde_json::json;
use std::time::Instant;

granular_automata::main_of!(body);

fn body() -> Result<(), Box<dyn std::error::Error>> {
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
    let runs = args.common.runs_for(
        4,
        8,
        8,
        margin("waves-fig7", "alpha_p0").map_or(8, |m| m.runs),
    );
    let seeds: Vec<u64> = run_seeds(args.common.seed, runs);
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

    let metrics = white_noise::metrics(&ens);
    let mut checks = match args.common.tier.is_acceptance() {
        true => white_noise::acceptance_checks(&setup0, &ens)?,
        false => white_noise::checks(&setup0, &ens),
    };
    // each spectrum with the published alpha (white noise) and its margin
    let mut lines = spectrum_lines(&ens[0], "p = 0, b = 0.5", 0);
    lines.extend(white_noise::published_lines(&checks, "alpha_p0", &ens[0]));
    lines.extend(spectrum_lines(&ens[1], "b = 0, p = 0.5", 3));
    lines.extend(white_noise::published_lines(&checks, "alpha_b0", &ens[1]));
    let title = "PH95 Fig. 7: spectra without dissipation or roughness, L = 220";
    let title = format!("{title}, {runs} runs, rules {rules}");
    spectra_chart(&out.path("waves-fig7.png"), &title, &lines)?;
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
