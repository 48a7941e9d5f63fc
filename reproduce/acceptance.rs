//! The studies behind `--tier acceptance` (issue 29): `pilot` compares the
//! candidate estimators and measures the spread over the papers' open
//! choices on pilot seeds; `stability` reads the summaries of acceptance runs
//! over many base seeds and tabulates each check's verdicts and coverage.
//!
//! `cargo run --release --bin acceptance -- pilot --figure fig2 --tier paper --seed 9001 --runs 384`

use clap::{Parser, Subcommand};
use granular_automata::cli::Common;
use granular_automata::drivers::acceptance::margin;
use granular_automata::drivers::acceptance_study::{open_choice_values, pilot, runs_to_decide};
use granular_automata::drivers::spectra::{bin_series, resumable_ensemble, tier_setup};
use granular_automata::pipe::Engine;
use granular_automata::pipe::{Params, Rules};
use granular_automata::run::{derive_seed, ensemble_with_threads, write_atomic};
use std::path::PathBuf;

#[derive(Parser)]
#[command(about = "Pilot and stability studies of the acceptance tier (issue 29)")]
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
        /// waves-fig7-b0 (PH95 Fig. 7, p = 0 or b = 0).
        #[arg(long)]
        figure: String,
        /// Runs per group, at least 3.
        #[arg(long, default_value_t = 32)]
        group: usize,
        /// Runs re-simulated for the open choices (their series are not saved).
        #[arg(long, default_value_t = 32)]
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
}

/// A pilot's set-up: the figure binary, its ensemble's name, the pipe, and
/// the acceptance checks of its alpha and v (if any).
struct PilotCase {
    binary: &'static str,
    name: &'static str,
    params: Params,
    alpha_check: &'static str,
    v_check: Option<&'static str>,
}

fn case_of(figure: &str) -> granular_automata::Result<PilotCase> {
    let base = Params::default();
    let case = |binary, name, params, alpha_check, v_check| PilotCase {
        binary,
        name,
        params,
        alpha_check,
        v_check,
    };
    match figure {
        "fig2" => Ok(case("fig2", "spectrum", base, "alpha", Some("v_peak"))),
        "waves-fig6" => Ok(case(
            "waves-fig6",
            "spectrum",
            Params { p: 0.8, ..base },
            "alpha",
            None,
        )),
        "waves-fig7-p0" => Ok(case(
            "waves-fig7",
            "p0",
            Params { p: 0.0, ..base },
            "alpha_p0",
            None,
        )),
        "waves-fig7-b0" => Ok(case(
            "waves-fig7",
            "b0",
            Params { b: 0.0, ..base },
            "alpha_b0",
            Some("v_peak_b0"),
        )),
        other => Err(granular_automata::Error::out_of_range(
            "--figure",
            other,
            "{fig2, waves-fig6, waves-fig7-p0, waves-fig7-b0}",
        )),
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    match Args::parse().what {
        What::Pilot {
            figure,
            group,
            open_runs,
            common,
        } => {
            let case = case_of(&figure)?;
            let setup = tier_setup(common.tier, case.params, Rules::default(), Engine::Fast);
            let runs = common.runs.unwrap_or(384);
            if group < 3 || group > runs {
                return Err(granular_automata::Error::out_of_range(
                    "--group",
                    group,
                    &format!("[3, {runs}]"),
                )
                .into());
            }
            let Some(ens) = resumable_ensemble(&common, case.binary, case.name, &setup, runs)?
            else {
                return Ok(());
            };
            let report = pilot(&setup, &ens.runs, group)?;
            println!(
                "{figure}: {runs} pilot runs, base seed {}, groups of {group}",
                common.seed
            );
            println!(
                "{:48} {:>9} {:>9} {:>9} {:>6} {:>8}",
                "estimator", "pooled", "mean SE", "SD grp", "ratio", "coverage"
            );
            for c in &report {
                println!(
                    "{:48} {:>9.4} {:>9.4} {:>9.4} {:>6.2} {:>8.2}",
                    c.name, c.pooled, c.mean_se, c.sd_between, c.ratio, c.coverage
                );
            }
            let n_open = open_runs.min(runs);
            let seeds: Vec<u64> = (0..n_open as u64)
                .map(|i| derive_seed(common.seed, i))
                .collect();
            let series = ensemble_with_threads(n_open, common.thread_count(), |i| {
                bin_series(&setup, seeds[i], &|_| {})
            })
            .into_iter()
            .collect::<granular_automata::Result<Vec<_>>>()?;
            let open = if n_open >= 1 {
                open_choice_values(&setup, &series)?
            } else {
                Vec::new()
            };
            let (mut sa, mut sv, mut sr) = (0f64, 0f64, 0f64);
            if let Some(&(_, a0, v0, r0)) = open.first() {
                println!("open choices on the first {n_open} runs (alpha, v, v refined of the averaged spectrum):");
                for (name, a, v, r) in &open {
                    println!(
                        "  {name:24} alpha {a:.4} ({:+.4})  v {v:.4} ({:+.4})  v refined {r:.4} ({:+.4})",
                        a - a0,
                        v - v0,
                        r - r0
                    );
                    sa = sa.max((a - a0).abs());
                    sv = sv.max((v - v0).abs());
                    sr = sr.max((r - r0).abs());
                }
                println!("s_open: alpha {sa:.4}, v {sv:.4}, v refined {sr:.4}");
            }
            // power: runs to decide each check from the pilot's pooled value
            // and its per-run spread (SE of a group x sqrt(group)).
            for (check, cand) in [
                (
                    Some(case.alpha_check),
                    "alpha: fit of mean spectrum (jackknife)",
                ),
                (case.v_check, "v: peak of mean spectrum (bootstrap)"),
            ] {
                let (Some(check), Some(c)) = (check, report.iter().find(|c| c.name == cand)) else {
                    continue;
                };
                let Some(m) = margin(case.binary, check) else {
                    println!("power {check}: no acceptance margin yet");
                    continue;
                };
                let sigma = c.mean_se * (group as f64).sqrt();
                let d = c.pooled - m.published;
                let n = runs_to_decide(d, m.delta(), sigma);
                println!(
                    "power {check}: d = {d:+.4}, Delta = {:.4}, sigma per run = {sigma:.4}: {} runs decide in 95 % of seed sets",
                    m.delta(),
                    n.map_or("no number of".to_string(), |n| format!("{:.0}", n.ceil()))
                );
            }
            let json = serde_json::json!({
                "figure": figure, "seed": common.seed, "runs": runs, "group": group,
                "candidates": report,
                "open_choices": open.iter().map(|(n, a, v, r)| serde_json::json!({"choice": n, "alpha": a, "v": v, "v_refined": r})).collect::<Vec<_>>(),
                "s_open_alpha": sa, "s_open_v": sv, "s_open_v_refined": sr,
            });
            let path = common
                .out
                .join(case.binary)
                .join(format!("pilot-{}-group{group}.json", case.name));
            write_atomic(&path, serde_json::to_string_pretty(&json)?.as_bytes())?;
            println!("wrote {}", path.display());
        }
        What::Stability { from, figure } => {
            let table = granular_automata::drivers::acceptance_study::stability(&from, &figure)?;
            print!("{table}");
        }
    }
    Ok(())
}
