//! The reproduction report (MODEL.md A10, B6): run every figure binary at one tier
//! and write `OUT/report/REPORT.md` and `OUT/report/index.html`, one row per
//! check beside its published value, with thumbnails of every figure.
//! Finished runs are resumed from `--out`, so a rerun only re-analyses.
//!
//! `cargo build --release --bins && target/release/report --tier quick`
//!
//! PH94 Fig. 2 graded over its 20 committed seed sets once this run equals
//! its committed twin (about 2 min on 2 cores):
//! `target/release/report --tier acceptance --only fig2 --seed-sets docs/acceptance --out results-acceptance`

use clap::Parser;
use granular_automata::cli::parse_threads;
use granular_automata::experiments;
use granular_automata::report::{check_folders, parse_extra, publish, run, select, Options};
use granular_automata::run::Tier;
use std::collections::BTreeMap;
use std::path::PathBuf;

#[derive(Parser, Debug)]
#[command(
    about = "Run every figure binary at one tier and write OUT/report/REPORT.md and index.html"
)]
struct Args {
    /// Tier passed to every figure: quick (minutes in all), standard, paper,
    /// acceptance.
    #[arg(long, value_enum, default_value_t = Tier::Quick)]
    tier: Tier,
    /// Comma-separated figures to run (default: every figure binary except
    /// pipe-matrix, which runs only when named here).
    #[arg(long)]
    only: Option<String>,
    /// Output folder of the figures; the report goes to OUT/report/.
    #[arg(long, default_value = "results")]
    out: PathBuf,
    /// Base seed passed to every figure (default: each figure's own, 1).
    #[arg(long, allow_negative_numbers = true)]
    seed: Option<u64>,
    /// Worker threads of every figure, 1..=1024 (default: all cores).
    #[arg(long, value_parser = parse_threads, allow_negative_numbers = true)]
    threads: Option<usize>,
    /// Engine of the pipe figures (reference or fast; the hopper's figures
    /// have one engine). Default: each figure's own (fast at the
    /// acceptance tier, reference below it).
    #[arg(long)]
    engine: Option<String>,
    /// Extra arguments of one figure, BIN=ARGS, e.g. 'waves-fig8=--runs 32'
    /// (repeatable; appended after the report's own).
    #[arg(long, value_name = "BIN=ARGS")]
    args_for: Vec<String>,
    /// Also write a self-contained copy to this folder (e.g. docs/report):
    /// the pages, report.json, every summary.json, reduced pictures and the
    /// small CSVs, a few MB in all.
    #[arg(long)]
    publish: Option<PathBuf>,
    /// Do not run the figures: re-render the report from the summaries
    /// already in --out (e.g. a published copy's folders).
    #[arg(long)]
    no_run: bool,
    /// Committed seed sets, DIR/BINARY/SEED-FOLDER/ or a cut's DIR/NAME/
    /// with cut.txt (e.g. docs/acceptance): the published checks are graded
    /// over every seed set of a figure (or cut) that has at least 20, where
    /// its run here equals its committed twin (same seeds) result for result.
    #[arg(long, value_name = "DIR")]
    seed_sets: Option<PathBuf>,
    /// Also write the current record of every claim (EXPERIMENTS.md) to
    /// this file, from the report and the per-claim notes of --claim-notes.
    #[arg(long, value_name = "FILE")]
    experiments: Option<PathBuf>,
    /// The per-claim notes (binary, check, note; tab-separated) that
    /// --experiments writes beside each claim.
    #[arg(long, value_name = "FILE", default_value = granular_automata::experiments::NOTES)]
    claim_notes: PathBuf,
}

fn main() {
    granular_automata::cli::exit_on_error("report", report);
}

fn report() -> granular_automata::Result<()> {
    let a = Args::parse();
    let figures = select(a.only.as_deref())?;
    check_folders(&a.out, a.publish.as_deref(), a.seed_sets.as_deref())?;
    if a.experiments.is_some() {
        experiments::read_notes_file(&a.claim_notes)?;
    }
    if let Some(e) = &a.engine {
        e.parse::<granular_automata::pipe::Engine>()?;
    }
    let mut extra = BTreeMap::new();
    for spec in &a.args_for {
        let (bin, args) = parse_extra(spec, &figures)?;
        extra.insert(bin, args);
    }
    let opts = Options {
        tier: a.tier,
        figures,
        out: a.out,
        seed: a.seed,
        threads: a.threads,
        engine: a.engine,
        extra,
        bin_dir: granular_automata::report::bin_dir(),
        command_line: std::env::args()
            .map(|a| granular_automata::report::shell_quote(&a))
            .collect::<Vec<_>>()
            .join(" "),
        no_run: a.no_run,
        seed_sets: a.seed_sets,
    };
    let r = run(&opts)?;
    if opts.seed_sets.is_some() {
        // the preface says which seed sets were graded, and why not
        for line in &r.preface {
            println!("{line}");
        }
    }
    for line in granular_automata::report::seed_set_lines(&r) {
        println!("{line}");
    }
    let dir = opts.out.join("report");
    println!(
        "wrote {} and {}",
        dir.join("REPORT.md").display(),
        dir.join("index.html").display()
    );
    if let Some(dest) = &a.publish {
        publish(&opts.out, &r, dest)?;
        println!("published a copy in {}", dest.display());
    }
    if let Some(path) = &a.experiments {
        let dir = a.publish.clone().unwrap_or_else(|| opts.out.join("report"));
        experiments::write(path, &dir.join("report.json"), &a.claim_notes)?;
        println!("wrote {}", path.display());
    }
    granular_automata::report::fail_on_failed_figures(&r)
}
