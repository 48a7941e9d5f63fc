//! The calibrated bridge between the lane and the gas (READINGS.md P23):
//! the plan of docs/notebook/2026-12-07-calibrated-bridge-plan.md run as
//! committed. Every grid point `default+lane-collide:q` is graded on the 39
//! claims of the reproduction matrix (saved per reading in `variants/`,
//! shared with `pipe-matrix` and reused); q is picked on the calibration
//! half by `drivers::bridge::choose`, then the picked reading and the
//! default are compared on the test half by `drivers::bridge::decide`.
//!
//! `cargo run --release --bin bridge -- --tier standard --engine fast`

use clap::Parser;
use granular_automata::cli::Common;
use granular_automata::drivers::bridge::{chart, choose, decide, reading, score_rows, split, GRID};
use granular_automata::drivers::claims::{Group, MatrixSize};
use granular_automata::drivers::matrix::{heat_map, write_tables, Matrix};
use granular_automata::pipe::{Engine, Rules};
use granular_automata::run::write_atomic;
use granular_automata::run::Output;
use std::time::Instant;

#[derive(Parser)]
#[command(about = "lane-collide:q calibrated on half the claims, tested on the other half")]
#[command(mut_arg("shard", |a| a.hide(true)))]
#[command(mut_arg("runs", |a| a.help(granular_automata::cli::MATRIX_RUNS_HELP).long_help(None::<&str>)))]
struct Args {
    #[command(flatten)]
    common: Common,
    /// Engine: reference or fast (validated against the reference).
    #[arg(long, default_value = "fast")]
    engine: String,
}

granular_automata::main_of!(body);

fn body() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    args.common.reject_shard("bridge")?;
    let (tier, seed) = (args.common.tier, args.common.seed);
    let mut size = MatrixSize::for_tier(tier);
    if let Some(r) = args.common.runs {
        size = size.with_runs(r);
    }
    let readings: Vec<Rules> = GRID.iter().map(|&q| reading(q)).collect::<Result<_, _>>()?;
    let out = Output::new(&args.common.out, "bridge")?;
    let cache = out.path("variants");
    std::fs::create_dir_all(&cache)?;
    let engine: Engine = args.engine.parse()?;
    let matrix = Matrix {
        tier,
        size,
        seed,
        engine,
        groups: &Group::ALL,
    };
    let start = Instant::now();
    let rows = matrix.grade(&readings, &cache)?;
    let wall = start.elapsed().as_secs_f64();
    let grid: Vec<(f64, _)> = GRID
        .iter()
        .zip(&rows)
        .map(|(&q, r)| (q, r.1.clone()))
        .collect();

    // the rule sees the calibration half only
    let (calibration, test) = split();
    let q = choose(&grid, &calibration)?;
    println!(
        "calibration half ({} claims): picked q = {q}",
        calibration.len()
    );
    let picked = &grid.iter().find(|g| g.0 == q).expect("q is a grid point").1;
    let decision = decide(q, &grid[0].1, picked, &test);
    let scores = score_rows(&grid);
    write_tables(&out, &rows, (tier, size, seed))?;
    heat_map(&out, &rows, tier, size.runs)?;
    chart(&out.path("bridge.png"), &scores, q)?;
    let mut csv = String::from("q,half,kind,reproduced,not_reproduced,undecided\n");
    for r in &scores {
        let s = r.score;
        let kind = format!("{:?}", r.kind).to_lowercase();
        csv += &format!(
            "{},{},{kind},{},{},{}\n",
            r.q, r.half, s.reproduced, s.not_reproduced, s.undecided
        );
    }
    write_atomic(&out.path("bridge.csv"), csv.as_bytes())?;
    let summary = serde_json::json!({
        "figure": "bridge", "tier": tier.name(), "seed": seed, "engine": engine.label(),
        "grid": GRID, "calibration": calibration, "test": test,
        "decision": decision, "wall_seconds": wall,
    });
    write_atomic(
        &out.path("summary.json"),
        serde_json::to_string_pretty(&summary)?.as_bytes(),
    )?;
    let (d, p) = (decision.default_test, decision.picked_test);
    println!(
        "test half ({} claims): default {}/{}/{}, q = {q}: {}/{}/{} (reproduced/not/undecided)",
        test.len(),
        d.reproduced,
        d.not_reproduced,
        d.undecided,
        p.reproduced,
        p.not_reproduced,
        p.undecided
    );
    println!(
        "turned {:?}, lost {:?}, headline lost {:?}: {}",
        decision.turned,
        decision.lost,
        decision.headline_lost,
        if decision.adopt {
            "becomes the default by the plan's rule"
        } else {
            "stays a named reading; the default is unchanged"
        }
    );
    Ok(())
}
