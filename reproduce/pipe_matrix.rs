//! The reproduction matrix (MODEL.md A10-A11): every
//! rule reading graded against every published claim of the pipe papers
//! (PH94 Figs. 1-2, PH95 Figs. 3-12 and III F; `drivers::claims::CLAIMS` lists each
//! with its published value, statistic and margin), with the measured value
//! and its error beside each grade. Each finished reading is saved at once
//! (`variants/<reading>.<key>.json`, a portable file name:
//! `Matrix::saved`) and reused when the same command is run again.
//!
//! `cargo run --release --bin pipe-matrix -- --tier quick`

use clap::Parser;
use granular_automata::cli::Common;
use granular_automata::drivers::claims::{site_updates, Group, MatrixSize, CLAIMS};
use granular_automata::drivers::matrix::{
    add_cells, default_checks, heat_map, write_tables, Matrix,
};
use granular_automata::pipe::{Engine, Rules};
use granular_automata::run::{Output, Summary};
use serde_json::json;
use std::time::Instant;

/// The readings graded by default: every named variant of MODEL.md, the
/// combinations A11 mentions, and `wall-move` (MODEL.md A6) alone and
/// with each of the others.
const READINGS: &str = "ph94,any-mover,up-to-rest,ph94+wall-drag,ph94+gravity-first,ph94+rest-up,\
ph94+wall-drag+gravity-first,any-mover+wall-drag,any-mover+rest-up,ph94+wall-move,\
ph94+gravity-first+wall-move,ph94+rest-up+wall-move,ph94+gravity-first+rest-up+wall-move,\
ph94+wall-drag+wall-move,any-mover+wall-move";

#[derive(Parser)]
#[command(about = "Which reading of the pipe rules reproduces which published claim")]
#[command(mut_arg("shard", |a| a.hide(true)))]
#[command(mut_arg("runs", |a| a.help(granular_automata::cli::MATRIX_RUNS_HELP).long_help(None::<&str>)))]
struct Args {
    #[command(flatten)]
    common: Common,
    /// Readings to grade, comma-separated (each a --rules value).
    #[arg(long, default_value = READINGS)]
    readings: String,
    /// Engine: reference or fast (validated against the reference).
    #[arg(long, default_value = "reference")]
    engine: String,
    /// Groups of claims to grade, comma-separated, or all: bands, spectra,
    /// relaxation, profile, speed, fig11, fig12 (the open pipe's two groups
    /// cost minutes of CPU per reading in clogging runs), dependence (PH95
    /// III F-H, Figs. 9-10), headline (PH94 Fig. 2's alpha at the published
    /// set-up: 128 runs of m = 16384 at any tier, about 5 CPU-min per
    /// reading on the fast engine); the others are listed as not run.
    #[arg(long, default_value = "all")]
    groups: String,
}

granular_automata::main_of!(body);

fn body() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    args.common.reject_shard("pipe-matrix")?;
    let (tier, seed) = (args.common.tier, args.common.seed);
    let mut size = MatrixSize::for_tier(tier);
    if let Some(r) = args.common.runs {
        size = size.with_runs(r); // 1..=MAX_RUNS, checked when parsed
    }
    let readings: Vec<Rules> = args
        .readings
        .split(',')
        .map(|s| s.trim().parse())
        .collect::<Result<_, _>>()?;
    granular_automata::error::reject_duplicates("--readings", &readings)?;
    let out = Output::new(&args.common.out, "pipe-matrix")?;
    let cache = out.path("variants");
    std::fs::create_dir_all(&cache)?;
    let engine: Engine = args.engine.parse()?;
    let groups = Group::parse_list(&args.groups)?;
    let matrix = Matrix {
        tier,
        size,
        seed,
        engine,
        groups: &groups,
    };

    let start = Instant::now();
    let rows = matrix.grade(&readings, &cache)?;
    let wall = start.elapsed().as_secs_f64();

    let mut metrics = write_tables(&out, &rows, (tier, size, seed))?;
    heat_map(&out, &rows, tier, size.runs)?;
    // how many claims the default reproduces (null when the default
    // is not among --readings) and how many were graded
    let (checks, default_reproduced) = default_checks(&rows, size.runs);
    metrics.insert("default_reproduced".into(), default_reproduced);
    metrics.insert("claims".into(), CLAIMS.len() as f64);
    let summary_path = out.finish(&Summary {
        figure: "pipe-matrix".into(),
        paper: "PH94 Figs. 1-2, PH95 Figs. 3-8, 11-12".into(),
        tier,
        seeds: vec![seed],
        params: json!({"size": size, "readings": readings.iter().map(|r| r.to_string()).collect::<Vec<_>>()}),
        rules: args.readings.clone(),
        engine: engine.label(),
        wall_seconds: wall,
        // nominal: runs that clog stop early
        site_updates: site_updates(size) * readings.len() as f64,
        metrics,
        missing_metrics: Default::default(),
        checks,
    })?;
    add_cells(&summary_path, &rows)?; // the matrix as a list
    let md = std::fs::read_to_string(out.path("matrix.md"))?;
    let head: Vec<&str> = md.lines().take(5 + CLAIMS.len()).collect();
    println!("{}", head.join("\n"));
    Ok(())
}
