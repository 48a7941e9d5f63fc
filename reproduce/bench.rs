//! Site updates per second of the pipe engines, one thread, side by side
//! (issue 13): the reference engine and the fast engine at the PH94 Fig. 2
//! set-up (L = 220) and the Fig. 1 set-up (L = 2200), W = 11, rho = 1,
//! p = g = b = 0.5. `cargo run --release --bin bench`
use clap::Parser;
use granular_automata::pipe::engine::Engine;
use granular_automata::pipe::{Params, Rules};
use std::time::Instant;

#[derive(Parser)]
#[command(about = "Pipe engine speed: site updates per second on one thread, both engines")]
struct Args {
    /// Steps per measurement at L = 220 (a tenth at L = 2200), 10..=10^9.
    #[arg(long, default_value_t = 20000, allow_negative_numbers = true)]
    steps: u64,
    /// Rule variant (see `--rules help` of the figure binaries).
    #[arg(long, default_value = "default")]
    rules: String,
    /// Seed.
    #[arg(long, default_value_t = 1, allow_negative_numbers = true)]
    seed: u64,
    /// Engines to time, comma-separated (reference, fast).
    #[arg(long, default_value = "reference,fast")]
    engines: String,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let a = Args::parse();
    let rules: Rules = a.rules.parse()?;
    if !(10..=1_000_000_000).contains(&a.steps) {
        // L = 2200 runs a tenth of the steps: fewer than 10 would time nothing
        return Err(granular_automata::Error::out_of_range(
            "--steps",
            a.steps,
            "10..=1000000000 (L = 2200 runs a tenth of them)",
        )
        .into());
    }
    let engines: Vec<Engine> = a
        .engines
        .split(',')
        .map(|s| s.trim().parse())
        .collect::<Result<_, _>>()?;
    for length in [220usize, 2200] {
        let params = Params {
            length,
            width: 11,
            ..Params::default()
        };
        let mut first = None;
        for &engine in &engines {
            let mut pipe = engine.build(params, rules, a.seed)?;
            pipe.run(2000)?; // leave the random start
            let steps = a.steps * 220 / length as u64;
            let t = Instant::now();
            pipe.run(steps)?;
            let dt = t.elapsed().as_secs_f64();
            let rate = (params.sites() as u64 * steps) as f64 / dt;
            let ratio = *first.get_or_insert(rate);
            println!(
                "L = {length:5}, W = 11, rules {rules}, engine {engine:9}: {steps} steps in {dt:.3} s = {rate:.3e} site updates/s ({:.2}x the first)",
                rate / ratio
            );
        }
    }
    Ok(())
}
