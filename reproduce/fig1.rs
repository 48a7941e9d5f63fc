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
use granular_automata::cli::{Common, PipeRules};
use granular_automata::drivers::bands::{
    draw_fig1, fig1_checks, fig1_metrics, write_panel_stats, Fig1Setup,
};
use granular_automata::pipe::record::fig1_pipe;

#[derive(Parser)]
#[command(about = "PH94 Fig. 1: density waves in a pipe (space-time plots, panels a-d)")]
struct Args {
    #[command(flatten)]
    common: Common,
    #[command(flatten)]
    rules: PipeRules,
}

granular_automata::main_of!(body);

fn body() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    let (fig, rules, engine, c) = args.rules.start(&args.common, "fig1", "PH94 Fig. 1")?;
    // Bands need the full length and duration (shorter pipes or runs do not form
    // them reliably, EXPERIMENTS.md), so the tiers differ in the number of runs.
    let setup = Fig1Setup {
        base: fig1_pipe(),
        rules,
        engine,
        steps: 40000,
        every: 80,
    };
    let runs = c.runs_or(4, 8, 16);
    setup.base.validate()?;
    let ens = c.ensemble(fig.binary, &setup.key(), runs)?;
    let outcome = ens.run(4 * setup.steps, |index, seed, tick| {
        setup.run(index, seed, tick)
    })?;
    let Some(results) = outcome.complete("") else {
        return Ok(());
    };
    let out = fig.output(&c.out)?;
    let seeds = ens.seeds();

    // analyse: mean and standard error over seeds, per panel
    let (metrics, stat) = fig1_metrics(&results);
    write_panel_stats(&out, &results, &seeds)?;
    // plot: one PNG per panel and the four panels together (first seed)
    draw_fig1(&out, &setup, &results[0], seeds[0])?;
    // compare with the published (qualitative) claims: s_low above (waves)
    // or below (none) the threshold, by the one grading rule
    let checks = fig1_checks(&stat);
    let site_updates = (runs as u64 * 4 * setup.steps * setup.base.sites() as u64) as f64;
    fig.finish(&out, seeds, setup.params(), site_updates, metrics, checks)?;
    Ok(())
}
