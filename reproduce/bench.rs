//! Site updates per second of the pipe engine, single thread, default rules
//! (issue 2, Performance). `cargo run --release --bin bench`
use clap::Parser;
use granular_automata::pipe::{Params, Pipe, Rules};
use std::time::Instant;

#[derive(Parser)]
#[command(about = "Pipe engine speed: site updates per second on one thread")]
struct Args {
    /// Steps per measurement.
    #[arg(long, default_value_t = 20000)]
    steps: u64,
    /// Rule variant (see `--rules help` of the figure binaries).
    #[arg(long, default_value = "default")]
    rules: String,
    /// Seed.
    #[arg(long, default_value_t = 1)]
    seed: u64,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let a = Args::parse();
    let rules: Rules = a.rules.parse()?;
    for length in [220usize, 2200] {
        let params = Params {
            length,
            width: 11,
            ..Params::default()
        };
        let mut pipe = Pipe::new(params, rules, a.seed)?;
        pipe.run(2000)?; // leave the random start
        let steps = a.steps * 220 / length as u64;
        let t = Instant::now();
        pipe.run(steps)?;
        let dt = t.elapsed().as_secs_f64();
        let su = (params.sites() as u64 * steps) as f64;
        println!(
            "L = {length:5}, W = 11, rules {rules}: {steps} steps in {dt:.3} s = {:.3e} site updates/s",
            su / dt
        );
    }
    Ok(())
}
