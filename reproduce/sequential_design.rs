//! The group-sequential designs of `analysis::sequential` measured before
//! any figure trusts them: for each design (fixed, O'Brien-Fleming,
//! Pocock), source of runs (normal; resampled committed runs of PH94
//! Fig. 2 and PH95 Fig. 6) and distance of the truth from the published
//! value (0 to 2 margins), the share of wrong verdicts and the mean runs.
//! Then the same designs over every published claim of the committed
//! report (`claims.md`). Writes `OUT/sequential-design/{design.csv,
//! design.md, wrong.png, runs.png, claims.md}` and prints each design's
//! worst wrong-verdict rate and its expected verdicts and runs.
//!
//! `cargo run --release --bin sequential-design -- --trials 20000`; with
//! `--spectra suite` the cases are the acceptance tier's own estimator on
//! the saved runs of a `report --out suite` folder.

use clap::Parser;
use granular_automata::drivers::sequential::{
    allowed, cases, committed_claims, designs, measure, plan, spectra_cases, write, write_plan,
    ALPHA,
};
use granular_automata::run::{progress, Output};
use std::path::PathBuf;

#[derive(Parser, Debug)]
#[command(
    about = "Wrong-verdict rate and runs of the sequential designs against the truth's distance"
)]
struct Args {
    /// Simulated claims per design, source and distance, 100..=10000000.
    #[arg(long, default_value_t = 20000, value_parser = |s: &str| count("--trials", s, 100, 10_000_000), allow_negative_numbers = true)]
    trials: u64,
    /// The designs' largest look (runs), 16..=100000.
    #[arg(long, default_value_t = 128, value_parser = |s: &str| count("--max", s, 16, 100_000), allow_negative_numbers = true)]
    max: u64,
    /// Base seed of the simulation, 0..=2^64 - 1.
    #[arg(long, default_value_t = 1, value_parser = |s: &str| granular_automata::cli::parse_seed("--seed", s), allow_negative_numbers = true)]
    seed: u64,
    /// Worker threads, 1..=1024 (default: all cores); the counts do not
    /// depend on it.
    #[arg(long, value_parser = granular_automata::cli::parse_threads, allow_negative_numbers = true)]
    threads: Option<usize>,
    /// The committed report whose per-run alphas are resampled.
    #[arg(long, default_value = "docs/report")]
    report: PathBuf,
    /// Instead of the default cases: the saved runs' spectra of PH94 Fig. 2
    /// and PH95 Fig. 6 under this `report --out` folder, resampled and
    /// graded by the acceptance tier's estimator (alpha of the averaged
    /// spectrum, bootstrap SE). Skips the committed claims' study.
    #[arg(long)]
    spectra: Option<PathBuf>,
    /// Output folder; results go to OUT/sequential-design/.
    #[arg(long, default_value = "results")]
    out: PathBuf,
}

/// A whole number of option `name` in `lo..=hi`.
fn count(name: &str, s: &str, lo: usize, hi: usize) -> granular_automata::Result<u64> {
    granular_automata::cli::parse_count(name, s, lo, hi).map(|n| n as u64)
}

granular_automata::main_of!(body);

fn body() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    let trials = args.trials as usize;
    let mut designs = designs(args.max as usize)?;
    if args.spectra.is_some() {
        // the designs of the acceptance tier: fixed and O'Brien-Fleming
        designs.retain(|d| !d.name.starts_with("pocock"));
    }
    let cases = match &args.spectra {
        Some(dir) => spectra_cases(dir, args.threads.unwrap_or(0))?,
        None => cases(&args.report)?,
    };
    let out = Output::new(&args.out, "sequential-design")?;
    let pb = progress(
        (designs.len() * cases.len() * 5) as u64,
        "design, case, distance",
    );
    let rows = measure(&designs, &cases, trials, args.seed, || pb.inc(1))?;
    pb.finish_and_clear();
    let spectra = args
        .spectra
        .as_ref()
        .map_or(String::new(), |d| format!(" --spectra {}", d.display()));
    let command = format!(
        "sequential-design --trials {trials} --max {} --seed {}{spectra}",
        args.max, args.seed
    );
    write(&out, &designs, &rows, trials, &command)?;
    for d in &designs {
        let worst = rows
            .iter()
            .filter(|r| r.design == d.name)
            .map(|r| r.sim.wrong)
            .fold(0.0, f64::max);
        let ok = worst <= allowed(trials);
        println!(
            "[{}] {}: worst wrong-verdict rate {worst:.4} (stated {ALPHA}, at most {:.4} over {trials} trials); boundaries {:?}",
            if ok { "PASS" } else { "FAIL" },
            d.name,
            allowed(trials),
            d.design.boundaries.iter().map(|k| (k * 1000.0).round() / 1000.0).collect::<Vec<_>>()
        );
    }
    if args.spectra.is_some() {
        println!("wrote {}", out.dir().display());
        return Ok(());
    }
    // the designs over the committed claims (docs/report/report.json)
    let claims = committed_claims(&args.report.join("report.json"))?;
    let trials = (trials / 10).max(100);
    let pb = progress(claims.len() as u64, "committed claims");
    let planned = plan(&claims, trials, args.seed, || pb.inc(1))?;
    pb.finish_and_clear();
    write_plan(&out, &claims, &planned, trials, &command)?;
    for p in &planned {
        println!(
            "{}: {:.1} of {} claims decided, {:.2} against the truth, {:.1} as over the seed sets, {:.0} runs",
            p.design,
            p.decided,
            claims.len(),
            p.wrong,
            p.agree,
            p.runs
        );
    }
    println!("wrote {}", out.dir().display());
    Ok(())
}
