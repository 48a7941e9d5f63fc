//! Exploration: band statistics (contrast C, S(1..3)/random-start value,
//! channel occupations) of single runs at any set-up, for the rule search of
//! MODEL.md A11. Not a figure; its numbers go to EXPERIMENTS.md with the
//! command line that produced them.
//!
//! `cargo run --release --bin explore -- --rules any-mover --p 0.1 --length 2200`

use clap::Parser;
use granular_automata::cli::{parse_runs, PipeRules};
use granular_automata::pipe::record::{bands, record};
use granular_automata::pipe::Params;
use granular_automata::run::{derive_seed, ensemble};

#[derive(Parser)]
#[command(about = "Band statistics of single pipe runs (rule search, MODEL.md A11)")]
struct Args {
    #[command(flatten)]
    rules: PipeRules,
    /// Dissipation p.
    #[arg(long, default_value_t = 0.1, allow_negative_numbers = true)]
    p: f64,
    /// Wall roughness b.
    #[arg(long, default_value_t = 0.5, allow_negative_numbers = true)]
    b: f64,
    /// Gravity g.
    #[arg(long, default_value_t = 0.5, allow_negative_numbers = true)]
    g: f64,
    /// Density rho.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    rho: f64,
    /// Pipe length L.
    #[arg(long, default_value_t = 2200, allow_negative_numbers = true)]
    length: usize,
    /// Pipe width W.
    #[arg(long, default_value_t = 11, allow_negative_numbers = true)]
    width: usize,
    /// Steps (sampled every 80; statistics over the second half).
    #[arg(long, default_value_t = 40000, allow_negative_numbers = true)]
    steps: u64,
    /// Number of seeds, 1..=100000.
    #[arg(long, default_value_t = 3, value_parser = parse_runs, allow_negative_numbers = true)]
    runs: usize,
    /// Base seed.
    #[arg(long, default_value_t = 1, allow_negative_numbers = true)]
    seed: u64,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let a = Args::parse();
    let rules = a.rules.parse()?;
    let engine = a.rules.engine()?;
    let params = Params {
        length: a.length,
        width: a.width,
        rho: a.rho,
        p: a.p,
        g: a.g,
        b: a.b,
        ..Params::default()
    };
    params.validate()?;
    let lines = ensemble(a.runs, |i| -> granular_automata::Result<String> {
        let seed = derive_seed(a.seed, i as u64);
        let mut pipe = engine.build(params, rules, seed)?;
        let rec = record(pipe.as_mut(), a.steps, 80, |_| {})?;
        let s = bands(&rec, rec.n.len() / 2, a.rho, params.bin, params.width);
        Ok(format!(
            "{rules} ({engine}) p={} b={} g={} rho={} L={} seed={seed}: C={:.3} s_low={:.2} var_ratio={:.3} channels(0..6)={:?}",
            a.p, a.b, a.g, a.rho, a.length, s.contrast, s.s_low, s.var_ratio, pipe.channel_counts()
        ))
    });
    for l in lines {
        println!("{}", l?);
    }
    Ok(())
}
