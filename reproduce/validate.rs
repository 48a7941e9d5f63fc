//! `validate`: check another implementation of the pipe automaton against
//! the reference engine (issue 12, VALIDATION.md). Writes
//! `OUT/validate/report.md` and `report.json`; exits non-zero when the
//! candidate fails.
//!
//! `cargo run --release --bin validate -- --candidate mutant:p+10% --level 1`

use clap::Parser;
use granular_automata::cli::parse_count;
use granular_automata::pipe::Rules;
use granular_automata::run::{progress, write_atomic, Output, Tier};
use granular_automata::validate::candidate::Candidate;
use granular_automata::validate::conformance::{MAX_TRIALS, MIN_TRIALS};
use granular_automata::validate::{self, candidate_from, conformance, Level, Model, Size};
use std::path::PathBuf;

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
    /// pipe, hopper (MODEL.md Part B; Rust candidates only) or all.
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
    #[arg(long, value_parser = trials, allow_negative_numbers = true)]
    trials: Option<usize>,
    /// Level-2 runs per engine per scene (default: by tier), 3..=10000.
    #[arg(long, value_parser = runs, allow_negative_numbers = true)]
    runs: Option<usize>,
    /// Hopper level-2 runs per engine per scene (default: by tier), 3..=10000.
    #[arg(long, value_parser = hopper_runs, allow_negative_numbers = true)]
    hopper_runs: Option<usize>,
    /// Output folder; the report goes to OUT/validate/.
    #[arg(long, default_value = "results")]
    out: PathBuf,
    /// Write the reference's exact level-1 table as JSON to this file and exit.
    #[arg(long)]
    export_table: Option<PathBuf>,
    /// Calibration: repeat the validation with base seeds seed, seed+1, ...,
    /// seed+N-1 (fresh seed sets for both engines each time), 1..=10000, and
    /// count the failures (false-alarm rate for `reference`, power for a
    /// mutant). Writes OUT/validate/repeat-CANDIDATE.csv and resumes from it.
    #[arg(long, value_parser = repeats, allow_negative_numbers = true)]
    repeat: Option<usize>,
}

fn trials(s: &str) -> granular_automata::Result<usize> {
    parse_count("--trials", s, MIN_TRIALS, MAX_TRIALS)
}

fn runs(s: &str) -> granular_automata::Result<usize> {
    parse_count("--runs", s, 3, 10_000)
}

fn hopper_runs(s: &str) -> granular_automata::Result<usize> {
    parse_count("--hopper-runs", s, 3, 10_000)
}

fn repeats(s: &str) -> granular_automata::Result<usize> {
    parse_count("--repeat", s, 1, 10_000)
}

/// Exit 2 with the message on a usage error (VALIDATION.md), 1 when the
/// candidate fails or cannot be run.
fn main() {
    let args = Args::parse();
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
        return Ok(Setup::Export(rules));
    }
    let mut size = Size::for_tier(args.tier);
    size.trials = args.trials.unwrap_or(size.trials);
    size.runs = args.runs.unwrap_or(size.runs);
    size.hopper_runs = args.hopper_runs.unwrap_or(size.hopper_runs);
    let cand = candidate_from(&args.candidate)?;
    validate::check_model(cand.as_ref(), args.model)?;
    Ok(Setup::Validate(cand, size))
}

/// Run what `setup` asks for: whether the candidate passed.
fn run(args: &Args, setup: Setup) -> Result<bool, Box<dyn std::error::Error>> {
    let (cand, size) = match setup {
        Setup::Export(rules) => {
            let path = args.export_table.as_ref().expect("export asked for");
            let base = granular_automata::pipe::Params::default();
            let t = conformance::table(&base, rules)?;
            let text = serde_json::to_string(&t)?;
            write_atomic(path, text.as_bytes())?;
            println!(
                "wrote the exact level-1 table of `{rules}` to {}",
                path.display()
            );
            return Ok(true);
        }
        Setup::Validate(cand, size) => (cand, size),
    };
    if let Some(n) = args.repeat {
        repeat(args, cand.as_ref(), size, n)?;
        return Ok(true);
    }
    let pb = progress(
        validate::jobs(args.level, args.model, args.tier, size),
        "validate",
    );
    let report = validate::validate(
        cand.as_ref(),
        &args.rules,
        args.level,
        args.model,
        args.tier,
        size,
        args.seed,
        &|| pb.inc(1),
    )?;
    pb.finish_and_clear();
    let out = Output::new(&args.out, "validate")?;
    let md = validate::markdown(&report);
    write_atomic(&out.path("report.md"), md.as_bytes())?;
    write_atomic(
        &out.path("report.json"),
        serde_json::to_string_pretty(&report)?.as_bytes(),
    )?;
    if let Some(l) = &report.level1 {
        println!(
            "level 1: {} ({} differences in {} tests, {} trials per state)",
            if l.pass { "PASS" } else { "FAIL" },
            l.differences.len(),
            l.tests,
            l.trials
        );
    }
    if let Some(l) = &report.level2 {
        let n = l.comparisons.iter().filter(|c| c.differs).count();
        println!(
            "level 2: {} ({n} of {} observables differ, {} runs per engine)",
            if l.pass { "PASS" } else { "FAIL" },
            l.comparisons.len(),
            l.runs
        );
    }
    if let Some(h) = &report.hopper {
        println!("hopper: {}", h.status);
        if let Some(l) = &h.level1 {
            println!(
                "hopper level 1: {} ({} differences; {} energies, {} conflicts, {} spacings)",
                if l.pass { "PASS" } else { "FAIL" },
                l.failed,
                l.energies,
                l.conflicts,
                l.spacings
            );
        }
        if let Some(l) = &h.level2 {
            let n = l.comparisons.iter().filter(|c| c.differs).count();
            println!(
                "hopper level 2: {} ({n} of {} observables differ, {} runs per engine)",
                if l.pass { "PASS" } else { "FAIL" },
                l.comparisons.len(),
                l.runs
            );
        }
    }
    println!(
        "{}: {} ({:.1} s); report in {}",
        report.candidate,
        if report.pass { "PASS" } else { "FAIL" },
        report.wall_seconds,
        out.dir().display()
    );
    Ok(report.pass)
}

/// `--repeat N`: N validations on fresh seed sets, one CSV row each (saved
/// as it goes; a rerun skips the seeds already in the file).
fn repeat(
    args: &Args,
    cand: &dyn Candidate,
    size: Size,
    n: usize,
) -> Result<(), Box<dyn std::error::Error>> {
    let out = Output::new(&args.out, "validate")?;
    let safe: String = args
        .candidate
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect();
    let path = out.path(&format!("repeat-{safe}.csv"));
    let config = format!(
        "# candidate={} level={:?} model={:?} tier={:?} rules={} trials={} runs={} hopper_runs={}",
        args.candidate,
        args.level,
        args.model,
        args.tier,
        args.rules,
        size.trials,
        size.runs,
        size.hopper_runs
    );
    let header = "seed,pass,level1_pass,level1_differences,level2_pass,level2_differing,hopper_level1_pass,hopper_level1_differences,hopper_level2_pass,hopper_level2_differing,wall_seconds";
    let mut text = match std::fs::read_to_string(&path) {
        Ok(t) if t.lines().next() == Some(config.as_str()) => t,
        _ => format!("{config}\n{header}\n"),
    };
    let done: std::collections::BTreeSet<u64> = text
        .lines()
        .skip(2)
        .filter_map(|l| l.split(',').next()?.parse().ok())
        .collect();
    let pb = progress(n as u64, "repeat");
    for seed in args.seed..args.seed + n as u64 {
        if !done.contains(&seed) {
            let r = validate::validate(
                cand,
                &args.rules,
                args.level,
                args.model,
                args.tier,
                size,
                seed,
                &|| {},
            )?;
            let l1 = r.level1.as_ref();
            let l2 = r.level2.as_ref();
            let h1 = r.hopper.as_ref().and_then(|h| h.level1.as_ref());
            let h2 = r.hopper.as_ref().and_then(|h| h.level2.as_ref());
            let opt = |b: Option<bool>| b.map_or(String::new(), |b| b.to_string());
            text.push_str(&format!(
                "{seed},{},{},{},{},{},{},{},{},{},{:.2}\n",
                r.pass,
                opt(l1.map(|l| l.pass)),
                l1.map_or(String::new(), |l| l.differences.len().to_string()),
                opt(l2.map(|l| l.pass)),
                l2.map_or(String::new(), |l| {
                    l.comparisons
                        .iter()
                        .filter(|c| c.differs)
                        .count()
                        .to_string()
                }),
                opt(h1.map(|l| l.pass)),
                h1.map_or(String::new(), |l| l.failed.to_string()),
                opt(h2.map(|l| l.pass)),
                h2.map_or(String::new(), |l| {
                    l.comparisons
                        .iter()
                        .filter(|c| c.differs)
                        .count()
                        .to_string()
                }),
                r.wall_seconds
            ));
            write_atomic(&path, text.as_bytes())?;
        }
        pb.inc(1);
    }
    pb.finish_and_clear();
    let rows: Vec<Vec<&str>> = text
        .lines()
        .skip(2)
        .map(|l| l.split(',').collect())
        .filter(|r: &Vec<&str>| {
            r[0].parse::<u64>()
                .is_ok_and(|s| (args.seed..args.seed + n as u64).contains(&s))
        })
        .collect();
    let count = |col: usize| rows.iter().filter(|r| r[col] == "false").count();
    println!(
        "{}: failed {} of {} validations (level 1: {}, level 2: {}, hopper level 1: {}, hopper level 2: {}); rows in {}",
        args.candidate,
        count(1),
        rows.len(),
        count(2),
        count(4),
        count(6),
        count(8),
        path.display()
    );
    Ok(())
}
