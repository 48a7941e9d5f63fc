//! The map of claims by readings (MODEL.md A11; plan and decision rule:
//! docs/decisions/claims-by-readings-map.md): every pipe figure run under
//! each named reading of the rule text, and every published check graded
//! there, into OUT/readings-map/: map.png (claims as rows by
//! kind, readings as columns, coloured by verdict), matrix.csv, matrix.md
//! (with the decision rule applied), conflicts.md and map.json. Each
//! reading's figures go to `OUT/<reading>/`; finished ones are read, not
//! rerun, so an interrupted map resumes.
//!
//! `cargo build --release --bins && target/release/readings-map --tier quick --readings default,literal-labels`

use clap::Parser;
use granular_automata::cli::parse_threads;
use granular_automata::readings_map::{run, select, write};
use granular_automata::report::{bin_dir, shell_quote, Options};
use granular_automata::run::Tier;
use std::collections::BTreeMap;
use std::path::PathBuf;

#[derive(Parser, Debug)]
#[command(
    about = "Every published claim of the pipe graded under each named reading of the rule text"
)]
struct Args {
    /// Tier of every figure (the plan's map: standard).
    #[arg(long, value_enum, default_value_t = Tier::Quick)]
    tier: Tier,
    /// Readings, comma-separated labels of `readings_map::READINGS`, or all.
    #[arg(long, default_value = "all")]
    readings: String,
    /// Output folder: `OUT/<reading>/<figure>/` and OUT/readings-map/.
    #[arg(long, default_value = "results-map")]
    out: PathBuf,
    /// Base seed of every figure (default: each figure's own, 1).
    #[arg(long, allow_negative_numbers = true)]
    seed: Option<u64>,
    /// Worker threads of every figure, 1..=1024 (default: all cores).
    #[arg(long, value_parser = parse_threads, allow_negative_numbers = true)]
    threads: Option<usize>,
    /// Engine of every figure: reference or fast.
    #[arg(long, default_value = "fast")]
    engine: String,
    /// Only re-render the map from the summaries already in OUT.
    #[arg(long)]
    no_run: bool,
}

fn main() {
    granular_automata::cli::exit_on_error("readings-map", body);
}

fn body() -> granular_automata::Result<()> {
    let a = Args::parse();
    let readings = select(&a.readings)?;
    a.engine.parse::<granular_automata::pipe::Engine>()?;
    let command_line: Vec<String> = std::env::args().map(|a| shell_quote(&a)).collect();
    let opts = Options {
        tier: a.tier,
        figures: vec![],
        out: a.out.clone(),
        seed: a.seed,
        threads: a.threads,
        engine: Some(a.engine),
        extra: BTreeMap::new(),
        bin_dir: bin_dir(),
        command_line: command_line.join(" "),
        no_run: a.no_run,
        seed_sets: None,
    };
    let map = run(&opts, &readings)?;
    let md = write(&a.out.join("readings-map"), &map, &opts.command_line)?;
    let text = std::fs::read_to_string(&md)?;
    for line in text.lines().take(8 + readings.len()) {
        println!("{line}");
    }
    println!("wrote {}", md.display());
    Ok(())
}
