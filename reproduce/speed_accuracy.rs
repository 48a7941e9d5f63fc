//! Speed against accuracy: each figure's key statistic,
//! its error bar against the CPU-seconds it cost, per tier and engine;
//! writes `OUT/speed-accuracy/{speed-accuracy.csv, speed-accuracy.png,
//! summary.json}` and prints which tier and engine resolve each key most
//! cheaply ([`granular_automata::speed`]).
//!
//! `cargo build --release --bins && target/release/speed-accuracy --tiers quick,standard`

use clap::Parser;
use granular_automata::cli::parse_threads;
use granular_automata::pipe::Engine;
use granular_automata::run::Tier;
use granular_automata::speed::{measure, recommend, select_keys, write, Plan};
use std::path::PathBuf;

#[derive(Parser, Debug)]
#[command(
    about = "Error bar of each figure's key statistic against its CPU cost, per tier and engine"
)]
struct Args {
    /// Comma-separated tiers to run: quick, standard, paper.
    #[arg(long, value_delimiter = ',', default_value = "quick,standard")]
    tiers: Vec<Tier>,
    /// Comma-separated pipe engines to run: reference, fast (the hopper
    /// figure runs the reference only).
    #[arg(long, default_value = "reference,fast")]
    engines: String,
    /// Comma-separated figures (default: fig1, fig2, waves-fig5,
    /// waves-fig8, hopper-fig3).
    #[arg(long)]
    figures: Option<String>,
    /// Output folder; results go to OUT/speed-accuracy/.
    #[arg(long, default_value = "results")]
    out: PathBuf,
    /// Worker threads of every figure, 1..=1024 (default 1: CPU seconds then
    /// equal wall seconds on an idle machine).
    #[arg(long, default_value = "1", value_parser = parse_threads, allow_negative_numbers = true)]
    threads: usize,
    /// Base seed of every figure.
    #[arg(long, default_value_t = 1, allow_negative_numbers = true)]
    seed: u64,
    /// Also read the summaries of earlier figure runs in this --out folder
    /// (repeatable), e.g. a paper tier run; only those with cpu_seconds.
    #[arg(long)]
    from: Vec<PathBuf>,
}

fn main() {
    granular_automata::cli::exit_on_error("speed-accuracy", run);
}

fn run() -> granular_automata::Result<()> {
    let a = Args::parse();
    let engines = a
        .engines
        .split(',')
        .map(|e| e.trim().parse::<Engine>().map(|e| e.name().to_string()))
        .collect::<granular_automata::Result<Vec<_>>>()?;
    granular_automata::cli::reject_duplicates("--engines", &engines)?;
    let tiers: Vec<&str> = a.tiers.iter().map(|t| t.name()).collect();
    granular_automata::cli::reject_duplicates("--tiers", &tiers)?;
    let plan = Plan {
        tiers: a.tiers.clone(),
        engines,
        keys: select_keys(a.figures.as_deref())?,
        out: a.out.clone(),
        threads: a.threads,
        seed: a.seed,
        bin_dir: std::env::current_exe()
            .ok()
            .and_then(|p| p.parent().map(PathBuf::from))
            .unwrap_or_else(|| PathBuf::from(".")),
        from: a.from.clone(),
    };
    let points = measure(&plan)?;
    let dir = a.out.join("speed-accuracy");
    write(&dir, &points)?;
    println!("wrote {}", dir.display());
    for (figure, text) in recommend(&points) {
        println!("{figure}: {text}");
    }
    Ok(())
}
