//! BB90 Fig. 2: the hopper filling (b) and emptying with beta = 0 (a) and
//! beta = 1 (c-f), for three readings of "aligned" (MODEL.md B4, B6): the
//! default along-bond reading first (`beta1_bond`), the same-orientation
//! reading (`beta1_same`, the default before) and the literal
//! along-velocity reading (`beta1_along`) as comparisons.
//!
//! `cargo run --release --bin hopper-fig2 -- --tier quick`

use clap::Parser;
use granular_automata::cli::Common;
use granular_automata::drivers::hopper_figures::{cases_of, Fig2Runs};
use granular_automata::hopper::experiment::{Case, Plan};
use granular_automata::hopper::HopperParams;
use granular_automata::run::{run_seeds, Figure};

#[derive(Parser, Debug)]
#[command(about = "BB90 Fig. 2: hopper filling and emptying, beta = 0 vs beta = 1")]
#[command(mut_arg("shard", |a| a.hide(true)))] // its runs stay in one process
struct Args {
    /// quick: a small hopper; standard and paper: 174 x 129. `--runs`: runs
    /// per case averaged in the metrics (snapshots show run 0).
    #[command(flatten)]
    common: Common,
    /// Comma-separated cases (readings) to run, from `Case::ALL` (e.g.
    /// `beta0,beta1_rest,beta1_same_narrow`); each gets every check. A
    /// beta = 0 case comes first (its run 0 is the left panel of every
    /// picture); the default's first beta = 1 case is the default reading.
    #[arg(long, default_value = "beta0,beta1_bond,beta1_same,beta1_along")]
    cases: String,
}

granular_automata::main_of!(body);

fn body() -> granular_automata::Result<()> {
    let args = Args::parse();
    let c = &args.common;
    let cases = cases_of(c, &args.cases, "hopper-fig2")?;
    let tier = c.tier;
    let runs = c.runs_or(3, 4, 8);
    let base = tier.pick(
        HopperParams::quick(),
        HopperParams::default(),
        HopperParams::default(),
    );
    let fig = Figure::start("hopper-fig2", "BB90 Fig. 2", tier, base.rules());
    let snaps: Vec<u64> = tier.pick(
        vec![100, 300, 600, 900],
        vec![250, 1000, 2000, 3000],
        vec![250, 1000, 2000, 3000],
    );
    let mut plan = Plan::new(tier.pick(5_000, 20_000, 20_000), snaps.clone());
    // the quick hopper is short: at 85% the rain heap touches the lid of the
    // lattice, whose rays read as dense and hold an arch; fill to 70% instead
    plan.fill_fraction = tier.pick(0.7, 0.85, 0.85);
    let out = fig.output(&c.out)?;
    let seeds: Vec<u64> = run_seeds(c.seed, runs);
    let fig2 = Fig2Runs::run(base, cases, &seeds, &plan, c.thread_count())?;
    let metrics = fig2.metrics();

    // pictures: one per reading of "aligned" (run 0); activity profiles and g(r)
    fig2.draw_snapshots(&out, &snaps, tier.pick(5.0, 2.6, 2.6), tier)?;
    fig2.draw_profiles(&out, plan.rmax)?;

    // checks: the qualitative claims of BB90 Fig. 2 (no published numbers),
    // every claim for every case it applies to
    let checks = fig2.checks();
    let params = serde_json::json!({
        "hopper": base,
        "cases": fig2.cases.iter().map(Case::json).collect::<Vec<_>>(),
        "runs": runs,
        "fill_fraction": plan.fill_fraction,
        "snapshot_iterations": snaps,
        "activity_window": "while more than 50% of the grains remain",
        "core_rows": fig2.rows,
        "inside_sites": fig2.geom.inside,
    });
    fig.finish(&out, seeds, params, fig2.site_updates(), metrics, checks)
}
