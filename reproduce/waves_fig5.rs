//! PH95 Fig. 5: the real-space wave speed. For each run, 2048 density
//! fields n_i(t) in the steady state, every T0 = 40 steps; for each time
//! interval tau = m T0 the shift of maximal overlap s(tau) of all field pairs
//! (t, t + tau) (MODEL.md A9, [PH95 C, eq. 2]; `pipe::overlap`); the speed is
//! the slope of s against tau. Averaged over 64 runs; L = 512, W = 11,
//! rho = 1, p = 0.1, g = b = 0.5.
//!
//! Choices (not in the paper): bins of 8 rows (512 is not a multiple of 10);
//! a warm-up before the first field (by tier); fields every T0 = 40 steps;
//! lags 1..=20 (800 steps); sub-bin shifts by a parabola through the overlap
//! maximum. The spectral speed of the same runs (MODEL.md A9, "Wave velocity
//! from the peak"): the NR `spctrm` of each bin's series (k = 1, m = fields/4,
//! 1988 "Parzen" window), averaged over bins, peak = largest power in
//! 2..=m/4 (the fundamental) refined by a parabola in log P; v = L j / (T0 2m).
//!
//! `cargo run --release --bin waves-fig5 -- --tier quick`

use clap::Parser;
use granular_automata::analysis::spectrum::{SpectrumParams, Window};
use granular_automata::cli::WaveOptions;
use granular_automata::drivers::profiles::fig5_readings;
use granular_automata::pipe::overlap::{SpeedRun, FIELDS_EVERY, FIG5_BIN, FIG5_MAX_LAG};
use granular_automata::pipe::record::Steady;
use serde_json::json;

#[derive(Parser)]
#[command(about = "PH95 Fig. 5: real-space wave speed from the shift of maximal overlap")]
struct Args {
    #[command(flatten)]
    wave: WaveOptions,
    /// Pipe length L (the figure: 512); a multiple of 8.
    #[arg(long, default_value_t = 512, allow_negative_numbers = true)]
    length: usize,
}

const T0: u64 = FIELDS_EVERY;
const MAX_LAG: usize = FIG5_MAX_LAG;
const BIN: usize = FIG5_BIN;

granular_automata::main_of!(body);

fn body() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    let (fig, rules, engine, c) = args.wave.start("waves-fig5", "PH95 Fig. 5")?;
    let accepted = granular_automata::drivers::acceptance::margin("waves-fig5", "wave_speed");
    let runs = c.runs_for(8, 16, 64, accepted.map_or(64, |m| m.runs));
    let params = args.wave.pipe(args.length, BIN)?;
    let steady = Steady::ph95(c.tier, c.tier.pick(1024, 2048, 2048), T0);
    let (fields, warmup) = (steady.fields, steady.warmup);
    let spec = SpectrumParams {
        m: fields / 4,
        k: 1,
        window: Window::Parzen1988,
    };
    spec.validate()?;
    // "analysis": bump when the per-run computation changes, so stale run
    // files are not reused (ensemble resume)
    let key = json!({"analysis": 3, "params": params, "rules": rules.to_string(), "engine": engine, "fields": fields, "warmup": warmup, "T0": T0, "max_lag": MAX_LAG});
    let ens = c.ensemble(fig.binary, &key, runs)?;
    let outcome = ens.run(steady.steps(), |_, seed, tick| {
        let n = steady.record(params, rules, engine, seed, tick)?;
        SpeedRun::measure(&n, &params, T0, MAX_LAG, &spec)
    })?;
    let Some(results) = outcome.complete("") else {
        return Ok(());
    };
    let out = fig.output(&c.out)?;
    let seeds = ens.seeds();

    // the speed both ways, over all runs and over the runs with bands
    let readings = fig5_readings(&results, params.length, T0, spec.m, c.tier)?;
    let fig = readings.explain_missing(fig);
    readings.draw(&out, &results, &seeds, &params, rules)?;
    let summary_params = json!({"L": params.length, "W": params.width, "rho": params.rho, "p": params.p, "g": params.g, "b": params.b, "bin": BIN, "fields": fields, "T0": T0, "warmup": warmup, "max_lag": MAX_LAG, "spectrum": {"m": spec.m, "k": spec.k, "window": spec.window.name()}, "runs": runs});
    let site_updates = (runs as u64 * steady.steps() * params.sites() as u64) as f64;
    let (metrics, checks) = (readings.metrics, readings.checks);
    fig.finish(&out, seeds, summary_params, site_updates, metrics, checks)?;
    Ok(())
}
