//! Site updates per second of the pipe engines, one thread, side by side
//! (MODEL.md A1-A7): the reference engine and the fast engine at the PH94 Fig. 2
//! set-up (L = 220) and the Fig. 1 set-up (L = 2200), W = 11, rho = 1,
//! p = g = b = 0.5; then, where relocation's walk dominates, the lower end
//! of waves-fig12 (open pipe just below I_c, PH95 Fig. 12). `cargo run
//! --release --bin bench`
use clap::Parser;
use granular_automata::drivers::open_pipe::fig12_pipe;
use granular_automata::pipe::Engine;
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

granular_automata::main_of!(body);

fn body() -> Result<(), Box<dyn std::error::Error>> {
    let a = Args::parse();
    let rules: Rules = a.rules.parse()?;
    // L = 2200 runs a tenth of the steps: fewer than 10 would time nothing
    granular_automata::cli::check_steps(a.steps, 10, "L = 2200 runs a tenth of them")?;
    let engines: Vec<Engine> = a
        .engines
        .split(',')
        .map(|s| s.trim().parse())
        .collect::<Result<_, _>>()?;
    granular_automata::error::reject_duplicates("--engines", &engines)?;
    for length in [220usize, 2200] {
        let params = Params {
            length,
            width: 11,
            ..Params::default()
        };
        let what = format!("L = {length:5}, W = 11, rules {rules}");
        // 2000 steps leave the random start
        time(
            &what,
            &engines,
            params,
            rules,
            a.seed,
            2000,
            a.steps * 220 / length as u64,
        )?;
    }
    // the open pipe at the lower end of the paper-tier waves-fig12 run
    // (L = 220, W = 11, I = 0.5078, just below its I_c = 0.5117): the bottom
    // fills with rest particles and most of the time goes to relocation's
    // walk (MODEL.md A4); timed from the empty start over 5x the steps
    let params = fig12_pipe(220, 11, 0.5078);
    let what = format!("L =   220, W = 11, open I = 0.5078 (waves-fig12 lower end), rules {rules}");
    time(&what, &engines, params, rules, a.seed, 0, 5 * a.steps)
}

/// Time `steps` steps of each engine after `warm` untimed ones, and print
/// the rate and its ratio to the first engine's (and the rest particles at
/// the end, the load of relocation's walk).
fn time(
    what: &str,
    engines: &[Engine],
    params: Params,
    rules: Rules,
    seed: u64,
    warm: u64,
    steps: u64,
) -> Result<(), Box<dyn std::error::Error>> {
    let mut first = None;
    for &engine in engines {
        let mut pipe = engine.build(params, rules, seed)?;
        pipe.run(warm)?;
        let t = Instant::now();
        pipe.run(steps)?;
        let dt = t.elapsed().as_secs_f64();
        let rate = (params.sites() as u64 * steps) as f64 / dt;
        let ratio = *first.get_or_insert(rate);
        println!(
            "{what}, engine {engine:9}: {steps} steps in {dt:.3} s = {rate:.3e} site updates/s ({:.2}x the first), {} rest particles at the end",
            rate / ratio,
            pipe.rest_count()
        );
    }
    Ok(())
}
