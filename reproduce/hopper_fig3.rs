//! BB90 Fig. 3: grains leaving the hopper per iteration over 6144 iterations
//! after opening, raw and averaged over 5 and 11 iterations, and the power
//! spectrum of the outflow (white noise); with orientation on (beta = 1, three
//! readings of "aligned": the default along-bond first, then same-orientation
//! and the literal along-velocity as comparisons) and off (beta = 0)
//! (MODEL.md B4, B6).
//!
//! `cargo run --release --bin hopper-fig3 -- --tier quick`

use clap::Parser;
use granular_automata::cli::Common;
use granular_automata::drivers::hopper_figures::{
    cases_of, draw_fig3, fig3_readings, fig3_setup, FIG3_RECORD,
};
use granular_automata::hopper::experiment::{run_cases, Case};
use granular_automata::hopper::experiment::{WINDOW_BLOCK, WINDOW_FULL, WINDOW_SKIP};
use granular_automata::run::{run_seeds, Figure};

#[derive(Parser, Debug)]
#[command(about = "BB90 Fig. 3: hopper outflow per iteration and its power spectrum")]
#[command(mut_arg("shard", |a| a.hide(true)))] // its runs stay in one process
struct Args {
    /// quick: a small hopper; standard: 174 x 129; paper: 270 x 200, whose
    /// stationary window covers the 6144 iterations. `--runs`: runs per
    /// case (metrics and spectra are averaged over them).
    #[command(flatten)]
    common: Common,
    /// Comma-separated cases (readings) to run, from `Case::ALL`; the rate
    /// of each beta = 1 case is compared with the first beta = 0 case. The
    /// default's first case is the default reading.
    #[arg(long, default_value = "beta1_bond,beta1_same,beta1_along,beta0")]
    cases: String,
}

granular_automata::main_of!(body);

fn body() -> granular_automata::Result<()> {
    let args = Args::parse();
    let c = &args.common;
    let cases = cases_of(c, &args.cases, "hopper-fig3")?;
    let cases = &cases[..];
    let tier = c.tier;
    let accepted = granular_automata::drivers::acceptance::margin("hopper-fig3", "white_spectrum");
    let runs = c.runs_for(3, 4, 4, accepted.map_or(4, |m| m.runs));
    let (base, plan, m) = fig3_setup(tier);
    let fig = Figure::start("hopper-fig3", "BB90 Fig. 3", tier, base.rules());
    let out = fig.output(&c.out)?;
    let seeds: Vec<u64> = run_seeds(c.seed, runs);
    let recs = run_cases(base, cases, &seeds, &plan, c.thread_count())?;
    let readings = fig3_readings(cases, &recs, m, tier)?;
    // Fig. 3a/b from run 0 of each case; the spectra
    draw_fig3(&out, cases, &recs, &readings)?;

    let params = serde_json::json!({
        "hopper": base,
        "cases": cases.iter().map(Case::json).collect::<Vec<_>>(),
        "runs": runs,
        "fill_fraction": plan.fill_fraction,
        "record_iterations": FIG3_RECORD,
        "stationary_window": "iterations after 15% of the grains have left (start-up) while more than 30% remain",
        "block_for_standard_errors": WINDOW_BLOCK, "window_skip": WINDOW_SKIP, "window_full": WINDOW_FULL,
        "spectrum": {"estimator": "NR 1988 spctrm, no overlap, on the stationary window, averaged over runs", "m": m, "window": "Parzen1988", "fit": "least squares of log10 P on log10 f, j = 1..m/4 (f <= 1/8)"},
    });
    let (metrics, checks) = (readings.metrics, readings.checks);
    fig.finish(&out, seeds, params, readings.site_updates, metrics, checks)
}
