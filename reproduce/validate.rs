//! `validate`: check another implementation of the pipe and hopper automata
//! against the reference engines (VALIDATION.md). Writes
//! `OUT/validate/report.md` and `report.json`; exits 1 when it fails.
//!
//! `cargo run --release --bin validate -- --candidate mutant:p+10% --level 1`

use clap::Parser;
use granular_automata::cli::{parse_count, parse_real};
use granular_automata::pipe::Rules;
use granular_automata::run::{progress, Output, Tier};
use granular_automata::validate::candidate::Candidate;
use granular_automata::validate::conformance::{MAX_TRIALS, MIN_TRIALS};
use granular_automata::validate::repeat::Repeat;
use granular_automata::validate::{
    self, candidate_from, conformance, detect, Level, Model, Plan, Size,
};
use std::path::PathBuf;
use std::time::Duration;

/// Validate a candidate engine against the reference (VALIDATION.md).
#[derive(Debug, Parser)]
#[command(about = "Validate an implementation of the pipe automaton against the reference engine")]
struct Args {
    /// reference | fast | mutant:NAME | cmd:'COMMAND' (external program, VALIDATION.md).
    #[arg(long, default_value = "reference")]
    candidate: String,
    /// 1 (rule conformance), 2 (scenes) or all.
    #[arg(long, value_enum, default_value_t = Level::All)]
    level: Level,
    /// pipe, hopper (MODEL.md Part B) or all.
    #[arg(long, value_enum, default_value_t = Model::All)]
    model: Model,
    /// quick (seconds) or standard (minutes); paper = standard.
    #[arg(long, value_enum, default_value_t = Tier::Quick)]
    tier: Tier,
    /// Rule reading compared (names joined by '+').
    #[arg(long, default_value = "default")]
    rules: String,
    /// Base seed of the reference's runs (the candidate's are disjoint).
    #[arg(long, default_value_t = 1, allow_negative_numbers = true)]
    seed: u64,
    /// Level-1 trials per (probe, state), 100..=1000000 (default: by tier;
    /// below 100 the exact tests cannot reject, VALIDATION.md).
    #[arg(long, value_parser = |s: &str| parse_count("--trials", s, MIN_TRIALS, MAX_TRIALS), allow_negative_numbers = true)]
    trials: Option<usize>,
    /// Level-2 runs per engine per scene (default: by tier), 3..=10000.
    #[arg(long, value_parser = |s: &str| parse_count("--runs", s, 3, 10_000), allow_negative_numbers = true)]
    runs: Option<usize>,
    /// Hopper level-2 runs per engine per scene (default: by tier), 3..=10000.
    #[arg(long, value_parser = |s: &str| parse_count("--hopper-runs", s, 3, 10_000), allow_negative_numbers = true)]
    hopper_runs: Option<usize>,
    /// Output folder; the report goes to OUT/validate/.
    #[arg(long, default_value = "results")]
    out: PathBuf,
    /// Wall-time limit in seconds of each run of a `cmd:` candidate,
    /// 0.001..=1000000 (default: one minute plus 10 microseconds per site
    /// update of the run's plan); a run over it is stopped and named.
    #[arg(long, value_parser = |s: &str| parse_real("--run-timeout", s, 0.001, 1e6), allow_negative_numbers = true)]
    run_timeout: Option<f64>,
    /// Trials and runs that catch a rule probability off by E (e.g. 3%), or
    /// CLASS:E (seam, lane-boundary, drift), with power 0.95; prints them and the cost.
    #[arg(long, value_parser = detect::parse_target, conflicts_with_all = ["trials", "runs"])]
    detect: Option<detect::Target>,
    /// Write the reference pipe's exact level-1 table as JSON to this file and exit.
    #[arg(long)]
    export_table: Option<PathBuf>,
    /// Calibration: repeat the validation with base seeds seed, seed+1, ...,
    /// seed+N-1 (fresh seed sets for both engines each time), 1..=10000, and
    /// count the failures (false-alarm rate for `reference`, power for a
    /// mutant). Writes OUT/validate/repeat-CANDIDATE.csv and resumes from it.
    #[arg(long, value_parser = |s: &str| parse_count("--repeat", s, 1, 10_000), allow_negative_numbers = true)]
    repeat: Option<usize>,
}

/// Exit 2 with the message on a usage error (VALIDATION.md), 1 when the
/// candidate fails or cannot be run.
fn main() {
    let args = Args::parse();
    granular_automata::validate::candidate::running::stop_on_interrupt();
    let setup = usage(&args).unwrap_or_else(|e| {
        eprintln!("Error: {e:?}");
        std::process::exit(2)
    });
    match run(&args, setup) {
        Ok(true) => {}
        Ok(false) => std::process::exit(1),
        Err(e) => {
            eprintln!("Error: {e:?}");
            std::process::exit(1)
        }
    }
}

/// What the command line asks for, checked before anything runs.
enum Setup {
    /// `--export-table`: the rules to export.
    Export(Rules),
    /// A validation of this candidate with these sizes.
    Validate(Box<dyn Candidate>, Size),
}

/// Check the command line: every error here is a usage error.
fn usage(args: &Args) -> granular_automata::Result<Setup> {
    let rules: Rules = args.rules.parse()?;
    if args.export_table.is_some() {
        conformance::exportable(args.model)?;
        return Ok(Setup::Export(rules));
    }
    if let Some(n) = args.repeat {
        granular_automata::validate::repeat::seeds(args.seed, n)?;
    }
    let mut size = Size::for_tier(args.tier).with(args.trials, args.runs, args.hopper_runs);
    if let Some(e) = args.detect {
        println!("{}", detect::resize(&mut size, e, args.tier, args.level)?);
    }
    let cand = candidate_from(
        &args.candidate,
        args.run_timeout.map(Duration::from_secs_f64),
    )?;
    validate::check_model(cand.as_ref(), args.model)?;
    Ok(Setup::Validate(cand, size))
}

/// Run what `setup` asks for: whether the candidate passed.
fn run(args: &Args, setup: Setup) -> Result<bool, Box<dyn std::error::Error>> {
    let (cand, size) = match setup {
        Setup::Export(rules) => {
            let path = args.export_table.as_ref().expect("export asked for");
            conformance::export_table(path, rules)?;
            let path = path.display();
            println!("wrote the exact level-1 table of `{rules}` to {path}");
            return Ok(true);
        }
        Setup::Validate(cand, size) => (cand, size),
    };
    let (levels, model, tier) = (args.level, args.model, args.tier);
    let plan = Plan::new(&args.rules, levels, model, tier, size, args.seed);
    let out = Output::new(&args.out, "validate")?;
    if let Some(n) = args.repeat {
        let name = args.candidate.as_str();
        println!("{}", Repeat { name, plan }.run(cand.as_ref(), &out, n)?);
        return Ok(true);
    }
    let jobs = validate::jobs(levels, model, tier, size, args.rules.parse()?);
    let pb = progress(jobs, "validate");
    let report = validate::validate(cand.as_ref(), &plan, &|| pb.inc(1))?;
    pb.finish_and_clear();
    validate::write_report(&report, &out)?;
    Ok(report.pass)
}
