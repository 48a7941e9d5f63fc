//! The long run of the fuzzer (`granular_automata::fuzz`): generated and
//! mutated input for every reader of outside input, 1.15 million inputs by
//! default; prints the counts per reader and writes them to
//! `OUT/fuzz/counts.csv` and `OUT/fuzz/counts.json`, with every failure
//! and its input. Exits 1 when any input made a reader panic, took longer
//! than the time limit, or was accepted with wrong data.
//!
//! `cargo run --release --bin fuzz -- --out results`
//! (docs/reference/generated-input.md: the budgets and the measured counts).

use clap::Parser;
use granular_automata::fuzz::{csv, fuzz, long_inputs, Reader, Tally, TIME_LIMIT};
use granular_automata::run::{progress, write_atomic};
use granular_automata::{Error, ErrorKind};
use std::path::PathBuf;

#[derive(Parser)]
#[command(about = "Fuzz every reader of outside input with generated and mutated input")]
struct Args {
    /// Readers, joined by commas (default: all): samples, hopper-end,
    /// hopper-plan, run-file, merge, summary, seed-sets, report-json, cli.
    #[arg(long)]
    readers: Option<String>,
    /// Inputs per reader, 1..=100000000 (default: each reader's long budget,
    /// 1.15 million in all).
    #[arg(long, value_parser = inputs, allow_negative_numbers = true)]
    inputs: Option<u64>,
    /// Seed of the generated inputs, 0..=2^64 - 1.
    #[arg(long, default_value_t = 60, value_parser = seed, allow_negative_numbers = true)]
    seed: u64,
    /// Output folder; the counts go to `OUT/fuzz/`.
    #[arg(long, default_value = "results")]
    out: PathBuf,
}

fn seed(s: &str) -> granular_automata::Result<u64> {
    granular_automata::cli::parse_seed("--seed", s)
}

fn inputs(s: &str) -> granular_automata::Result<u64> {
    granular_automata::cli::parse_count("--inputs", s, 1, 100_000_000).map(|n| n as u64)
}

granular_automata::main_of!(body);

fn body() -> Result<(), Box<dyn std::error::Error>> {
    let a = Args::parse();
    let readers: Vec<Reader> = match &a.readers {
        None => Reader::ALL.to_vec(),
        Some(list) => {
            let names: Vec<&str> = list.split(',').map(str::trim).collect();
            granular_automata::cli::reject_duplicates("--readers", &names)?;
            names
                .iter()
                .map(|n| n.parse())
                .collect::<granular_automata::Result<_>>()?
        }
    };
    // the output folder first: a bad --out fails before any input is tried
    let dir = a.out.join("fuzz");
    std::fs::create_dir_all(&dir).map_err(|e| {
        Error::new(
            ErrorKind::Io,
            format!(
                "--out {}: cannot create {}: {e}",
                a.out.display(),
                dir.display()
            ),
        )
    })?;
    let count = |r: Reader| a.inputs.unwrap_or_else(|| long_inputs(r));
    let total: u64 = readers.iter().map(|&r| count(r)).sum();
    println!(
        "fuzz: {total} inputs over {} readers, seed {}, time limit {} s per input",
        readers.len(),
        a.seed,
        TIME_LIMIT.as_secs()
    );
    let pb = progress(total, "inputs");
    let mut tallies: Vec<Tally> = Vec::new();
    for r in readers {
        pb.set_message(r.name());
        let t = fuzz(r, a.seed, count(r), &|| pb.inc(1))?;
        pb.suspend(|| {
            println!(
                "{:<12} {:>9} inputs: {:>9} accepted, {:>9} refused, {} panics, {} hangs, {} silent, {:.1} s",
                t.reader, t.inputs, t.accepted, t.refused, t.panics, t.hangs, t.silent, t.seconds
            )
        });
        tallies.push(t);
    }
    pb.finish_and_clear();
    let mut all = Tally {
        reader: "all".into(),
        ..Tally::default()
    };
    for t in &tallies {
        all.add(t);
    }
    println!(
        "all: {} inputs, {} accepted, {} refused, {} panics, {} hangs, {} silent, {:.1} s",
        all.inputs, all.accepted, all.refused, all.panics, all.hangs, all.silent, all.seconds
    );
    tallies.push(all.clone());
    write_atomic(&dir.join("counts.csv"), csv(&tallies).as_bytes())?;
    let json = serde_json::json!({"seed": a.seed, "time_limit_seconds": TIME_LIMIT.as_secs(),
        "readers": tallies});
    write_atomic(&dir.join("counts.json"), format!("{json:#}\n").as_bytes())?;
    println!("counts in {}", dir.join("counts.csv").display());
    for f in &all.failures {
        eprintln!("{f}");
    }
    if !all.clean() {
        return Err(Error::new(
            ErrorKind::Io,
            format!(
                "{} panics, {} hangs and {} silent acceptances (first ones above and in counts.json)",
                all.panics, all.hangs, all.silent
            ),
        )
        .into());
    }
    Ok(())
}
