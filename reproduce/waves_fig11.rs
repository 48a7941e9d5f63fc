//! PH95 Fig. 11: the open pipe (MODEL.md A7). (a) Space-time plot, L = 1000,
//! W = 5, 100 bins, injection I = 0.5, p = b = 0.5, g = 0.2, 40000 steps from
//! an empty pipe; (b) the two-point correlation C(R, T) of MODEL.md A9 against
//! T at R = 30 bins, its peak T_c and the speed v = R * bin / T_c over runs.
//!
//! With the default reading the published I = 0.5 fills the pipe with rest
//! particles within a few thousand steps (the model's validity limit, MODEL.md
//! A4: a clog). That is measured and reported; the correlation is measured at
//! I = 0.3 (stationary at this set-up), stated in every output.
//!
//! `cargo run --release --bin waves-fig11 -- --tier quick`

use clap::Parser;
use granular_automata::cli::{check_steps, PipeArgs};
use granular_automata::drivers::fig11::{
    corr_ensembles, draw_correlation, draw_space_time, fig11_readings, I_CORR,
};
use granular_automata::drivers::open_pipe::{fig11_pipe, FIG11_CORR, FIG11_INJECT};
use granular_automata::run::{derive_seed, run_seeds, Output, Summary};
use serde_json::json;
use std::time::Instant;

#[derive(Parser)]
#[command(about = "PH95 Fig. 11: open pipe space-time plot and two-point correlation")]
struct Args {
    #[command(flatten)]
    pipe: PipeArgs,
    /// Steps per run from the empty pipe (default 40000, the paper's); the
    /// correlation uses the samples from step 10000 on, so at least 13020.
    #[arg(long, default_value_t = 40_000, allow_negative_numbers = true)]
    steps: u64,
    /// Only the correlation at I = 0.3: skip the published rate I = 0.5,
    /// whose runs clogged with the earlier default
    /// `ph94+gravity-first+wall-move` (no
    /// waves-fig11a_I0.5.png, no waves-fig11b_I0.5.png, no check
    /// paper_setup_flows, no clog metrics).
    #[arg(long)]
    correlation_only: bool,
}

/// The published injection rate.
const I_PAPER: f64 = FIG11_INJECT;
/// R in bins, sampling of C(R, T) (shared with the reproduction matrix).
const R: isize = FIG11_CORR.r;
const EVERY: u64 = FIG11_CORR.every;
const SKIP: usize = FIG11_CORR.skip;
const T_MAX: usize = FIG11_CORR.t_max;

granular_automata::main_of!(body);

fn body() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    let rules = args.pipe.rules.parse()?;
    let engine = args.pipe.rules.engine(args.pipe.common.tier)?;
    let c = &args.pipe.common;
    let steps = check_steps(
        args.steps,
        (SKIP + T_MAX + 2) as u64 * EVERY,
        "the skipped samples and the correlation lags",
    )?;
    let rates: &[f64] = if args.correlation_only {
        &[I_CORR]
    } else {
        &[I_PAPER, I_CORR]
    };
    let base = fig11_pipe(I_PAPER);
    let runs = c.runs_or(4, 8, 32);
    let start = Instant::now();
    let Some(results) = corr_ensembles(c, rates, rules, engine, steps, runs)? else {
        return Ok(());
    };
    let wall = start.elapsed().as_secs_f64();
    let out = Output::new(&c.out, "waves-fig11")?;

    // (a) space-time plots of run 0 at each rate, n_i every 80 steps
    for &inject in rates {
        draw_space_time(&out, inject, rules, engine, derive_seed(c.seed, 0), steps)?;
    }
    // (b) the correlation at I_CORR; at the published rate (when run) its
    // clogging, and its own correlation panel once it flows
    let paper = (!args.correlation_only).then(|| &results[0][..]);
    let corr = results.last().expect("the correlation rate ran");
    let readings = fig11_readings(paper, corr, steps);
    draw_correlation(&out, "waves-fig11b", I_CORR, &readings.corr)?;
    if let Some(ps) = readings.paper.as_ref().filter(|ps| ps.valid > 0) {
        draw_correlation(&out, &format!("waves-fig11b_I{I_PAPER}"), I_PAPER, ps)?;
    }
    out.finish(&Summary {
        figure: "waves-fig11".into(),
        paper: "PH95 Fig. 11".into(),
        tier: c.tier,
        seeds: run_seeds(c.seed, runs),
        params: json!({"paper": fig11_pipe(I_PAPER), "correlation": fig11_pipe(I_CORR), "steps": steps, "every": EVERY, "skip_samples": SKIP, "t_max_samples": T_MAX, "R_bins": R}),
        rules: rules.to_string(),
        engine: engine.label(),
        wall_seconds: wall,
        site_updates: (rates.len() as u64 * runs as u64 * steps * base.sites() as u64) as f64,
        metrics: readings.metrics,
        missing_metrics: Default::default(),
        checks: readings.checks,
    })?;
    Ok(())
}
