//! The studies behind `--tier acceptance` (MODEL.md A10-A11): `pilot` compares the
//! candidate estimators and measures the spread over the papers' open
//! choices on pilot seeds; `stability` reads the summaries of acceptance runs
//! over many base seeds and tabulates each check's verdicts and coverage;
//! `power` reads a pilot's summary and gives the runs that decide each check;
//! `seal` records the seal of filed seed sets, which `report --seed-sets`
//! checks.
//!
//! `cargo run --release --bin acceptance -- pilot --figure fig2 --tier paper --seed 9001 --runs 384`

use clap::{Parser, Subcommand};
use granular_automata::cli::Common;
use granular_automata::drivers::acceptance_study::{pilot_study, power, seal, stability};
use std::path::PathBuf;

#[derive(Parser)]
#[command(about = "Pilot and stability studies of the acceptance tier")]
struct Args {
    #[command(subcommand)]
    what: What,
}

#[derive(Subcommand)]
enum What {
    /// Compare candidate estimators over disjoint groups of pilot runs and
    /// measure the spread over the open choices (pipe on the fast engine).
    Pilot {
        /// fig2 (PH94 Fig. 2), waves-fig6 (PH95 Fig. 6), waves-fig7-p0 or
        /// waves-fig7-b0 (PH95 Fig. 7, p = 0 or b = 0), waves-fig8 (PH95
        /// Fig. 8: the open choices' change of each point's difference to
        /// p = 0.5, over --open-runs runs per point; --group unused),
        /// hopper-fig3 (BB90 Fig. 3's flat spectrum, --open-runs runs per
        /// case of the default reading).
        #[arg(long)]
        figure: String,
        /// Runs per group, at least 3.
        #[arg(long, default_value_t = 32, value_parser = |s: &str| granular_automata::cli::parse_count("--group", s, 3, 100_000), allow_negative_numbers = true)]
        group: usize,
        /// Runs re-simulated for the open choices (their series are not saved).
        #[arg(long, default_value_t = 32, value_parser = |s: &str| granular_automata::cli::parse_count("--open-runs", s, 1, 100_000), allow_negative_numbers = true)]
        open_runs: usize,
        #[command(flatten)]
        common: Common,
    },
    /// Tabulate the checks of `FROM/*/<figure>/summary.json` (one folder per
    /// base seed): verdict counts, values, and the coverage of each
    /// check's interval around the inverse-variance pooled value.
    Stability {
        /// The folder holding one --out folder per base seed.
        #[arg(long)]
        from: PathBuf,
        /// The figure binary whose summaries to read.
        #[arg(long)]
        figure: String,
    },
    /// Seal the filed seed sets of `figure` in `FROM` (FROM/seals.tsv):
    /// those in the seed folders named with --seed-folder, or every summary
    /// without a seal when none is named. Each is verified by the one rule
    /// first.
    Seal {
        /// The folder holding one --out folder per base seed.
        #[arg(long)]
        from: PathBuf,
        /// The figure binary whose summaries to seal.
        #[arg(long)]
        figure: String,
        /// A seed folder to (re)seal, e.g. seed-5; repeatable.
        #[arg(long = "seed-folder")]
        seed_folders: Vec<String>,
    },
    /// The runs that would decide each published check of a pilot's
    /// `summary.json` (a figure run with few runs per point on pilot
    /// seeds), and the run count per point the committed rule picks.
    Power {
        /// The pilot's summary.json.
        #[arg(long)]
        summary: PathBuf,
    },
}

granular_automata::main_of!(body);

fn body() -> Result<(), Box<dyn std::error::Error>> {
    match Args::parse().what {
        What::Pilot {
            figure,
            group,
            open_runs,
            common,
        } => pilot_study(&common, &figure, group, open_runs)?,
        What::Stability { from, figure } => print!("{}", stability(&from, &figure)?),
        What::Power { summary } => print!("{}", power(&summary)?.0),
        What::Seal {
            from,
            figure,
            seed_folders,
        } => {
            for p in seal(&from, &figure, &seed_folders)? {
                println!("sealed {p}");
            }
        }
    }
    Ok(())
}
