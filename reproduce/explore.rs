//! Exploration: band statistics (contrast C, S(1..3)/random-start value,
//! channel occupations) of single runs at any set-up, for the rule search of
//! MODEL.md A11. Not a figure; its numbers go to EXPERIMENTS.md with the
//! command line that produced them.
//!
//! `cargo run --release --bin explore -- --rules any-mover --p 0.1 --length 2200`
//!
//! `--mechanism`: instead, PH95 Fig. 5's record at `--tier` (as `waves-fig5`)
//! read for what moves and what stands (`pipe::mechanism`), a CSV table:
//! `explore -- --mechanism --length 512 --bin 8 --p 0.1 --runs 8`

use clap::Parser;
use granular_automata::cli::{check_populated, check_steps, parse_runs, PipeRules};
use granular_automata::pipe::mechanism::table;
use granular_automata::pipe::record::{bands, record};
use granular_automata::pipe::stops::count_stops;
use granular_automata::pipe::Engine;
use granular_automata::pipe::Params;
use granular_automata::run::{derive_seed, ensemble, Tier};

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
    /// Rows per bin.
    #[arg(long, default_value_t = 10, allow_negative_numbers = true)]
    bin: usize,
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
    /// Instead of the band statistics: which collision rule stops the movers
    /// over the second half of each run (`pipe::stops`, reference engine).
    #[arg(long)]
    stops: bool,
    /// Instead: the mechanism table of `pipe::mechanism` (fields as waves-fig5 at --tier).
    #[arg(long)]
    mechanism: bool,
    /// Tier of --mechanism's record.
    #[arg(long, value_enum, default_value_t = Tier::Quick)]
    tier: Tier,
}

granular_automata::main_of!(body);

fn body() -> Result<(), Box<dyn std::error::Error>> {
    let a = Args::parse();
    let rules = a.rules.parse()?;
    let engine = a.rules.engine(a.tier)?;
    let params = Params {
        length: a.length,
        width: a.width,
        rho: a.rho,
        p: a.p,
        g: a.g,
        b: a.b,
        bin: a.bin,
        ..Params::default()
    };
    params.validate()?;
    check_populated(&params)?;
    if a.mechanism {
        print!("{}", table(params, rules, engine, a.tier, a.runs, a.seed)?);
        return Ok(());
    }
    // band statistics: the second half of the samples, one every 80 steps;
    // --stops: the second half of the steps
    let min_steps = if a.stops { 2 } else { 160 };
    check_steps(
        a.steps,
        min_steps,
        "statistics over the second half of the run",
    )?;
    if a.stops {
        if engine != Engine::Reference {
            return Err(granular_automata::Error::out_of_range(
                "--engine",
                engine,
                "reference (--stops watches the reference engine's collisions)",
            )
            .into());
        }
        return stops(&a, params, rules);
    }
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

/// `--stops`: per run, the movers each rule stops per step over the second
/// half, at the nucleation of a jam and on a jam (the site below holds a rest
/// particle), and the share of the stops on jams made by the p-rules R2, R3.
fn stops(
    a: &Args,
    params: Params,
    rules: granular_automata::pipe::Rules,
) -> Result<(), Box<dyn std::error::Error>> {
    let half = a.steps / 2;
    let lines = ensemble(a.runs, |i| -> granular_automata::Result<String> {
        let seed = derive_seed(a.seed, i as u64);
        let c = count_stops(params, rules, seed, a.steps - half, half)?;
        let mut line = format!(
            "{rules} (reference) p={} b={} g={} rho={} L={} W={} seed={seed} stops per step [nucleation, on jam]:",
            a.p, a.b, a.g, a.rho, a.length, a.width
        );
        line.push_str(&c.describe(&params));
        Ok(line)
    });
    for l in lines {
        println!("{}", l?);
    }
    Ok(())
}
