//! PH95 Fig. 4: the profile of the strongest wave. For each run, 2048
//! density fields in the steady state are shifted along the pipe to overlap
//! maximally, hierarchically (pairs, then pairs of pairs, ...; [PH95 B],
//! `pipe::overlap::align_hierarchical`) and averaged; the run profiles are
//! aligned the same way and averaged over runs. Several lengths L, W = 11,
//! rho = 1, p = 0.1, g = b = 0.5.
//!
//! Choices (not in the paper): bins of 4 rows (the lengths are powers of two;
//! finer bins resolve the front); a warm-up before the first field (by
//! tier); fields every T0 = 40 steps. Metrics per run, on the run's profile
//! centred on its maximum: the amplitude (max - mean) / mean; the half-widths
//! at half the excess maximum on the front side (downstream, towards lower y:
//! the waves travel down, waves-fig2/fig5) and on the back side; the width
//! (their sum, rows); the asymmetry (back - front) / (back + front), > 0 for
//! a steep front. Alignment makes even pure noise look like a bump, so each
//! run also aligns as many white-noise fields with the run's own per-bin
//! variance (over its fields; generator seeded from the run's seed with a
//! fixed offset): the excess amplitude over that null is the wave's
//! (`pipe::overlap::profile_run`).
//!
//! `cargo run --release --bin waves-fig4 -- --tier quick`

use clap::Parser;
use granular_automata::cli::WaveOptions;
use granular_automata::drivers::profiles::{draw_fig4, fig4_readings, LengthRuns};
use granular_automata::pipe::overlap::{profile_run, FIELDS_EVERY, FIG4_BIN};
use granular_automata::pipe::record::Steady;
use serde_json::json;

#[derive(Parser)]
#[command(about = "PH95 Fig. 4: profile of the strongest wave (maximal-overlap average)")]
struct Args {
    #[command(flatten)]
    wave: WaveOptions,
    /// Pipe lengths (multiples of 4), comma separated.
    #[arg(long, value_delimiter = ',', default_values_t = vec![128usize, 256, 512, 1024], allow_hyphen_values = true)]
    lengths: Vec<usize>,
}

const T0: u64 = FIELDS_EVERY;
const BIN: usize = FIG4_BIN;

granular_automata::main_of!(body);

fn body() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    let (fig, rules, engine, c) = args.wave.start("waves-fig4", "PH95 Fig. 4")?;
    let runs = c.runs_or(4, 16, 64);
    granular_automata::cli::reject_duplicates("--lengths", &args.lengths)?;
    for &length in &args.lengths {
        args.wave.pipe(length, BIN)?; // a bad length fails before any run
    }
    let steady = Steady::ph95(c.tier, c.tier.pick(512, 2048, 2048), T0);
    let (fields, warmup) = (steady.fields, steady.warmup);
    let mut per_l = Vec::new();
    let mut seeds = Vec::new();
    for &length in &args.lengths {
        let params = args.wave.pipe(length, BIN)?;
        // "analysis": bump when the per-run computation changes, so stale run
        // files are not reused (ensemble resume)
        let key = json!({"analysis": 2, "params": params, "rules": rules.to_string(), "engine": engine, "fields": fields, "warmup": warmup, "T0": T0});
        let ens = c.ensemble(fig.binary, &key, runs)?;
        let mean = (BIN * params.width) as f64 * params.rho;
        let outcome = ens.run(steady.steps(), |_, seed, tick| {
            let f = steady.record(params, rules, engine, seed, tick)?;
            Ok(profile_run(&f, mean, BIN, seed))
        })?;
        seeds = ens.seeds();
        per_l.push((params, outcome.complete(&format!("L = {length}: "))));
    }
    let Some(per_l) = per_l
        .into_iter()
        .map(|(p, res)| res.map(|r| (p, r)))
        .collect::<Option<Vec<LengthRuns>>>()
    else {
        return Ok(());
    };
    let out = fig.output(&c.out)?;

    let (metrics, checks) = fig4_readings(&per_l, c.tier);
    let p = args.wave.p;
    draw_fig4(&out, &per_l, p, runs, fields, rules)?;
    let summary_params = json!({"L": args.lengths, "W": 11, "rho": 1.0, "p": p, "g": 0.5, "b": 0.5, "bin": BIN, "fields": fields, "T0": T0, "warmup": warmup, "runs": runs});
    let site_updates = per_l
        .iter()
        .map(|(p, _)| (runs as u64 * steady.steps() * p.sites() as u64) as f64)
        .sum();
    fig.finish(&out, seeds, summary_params, site_updates, metrics, checks)?;
    Ok(())
}
