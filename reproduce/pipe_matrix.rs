//! The reproduction matrix (issue 4, extended in issue 14): every rule
//! reading graded against every published claim of the pipe papers (PH94
//! Figs. 1-2, PH95 Figs. 3-8, 11-12; `drivers::claims::CLAIMS` lists each
//! with its published value, statistic and margin), with the measured value
//! and its error beside each grade. Each finished reading is saved at once
//! (`variants/<reading>.json`) and reused when the same command is run again.
//!
//! `cargo run --release --bin pipe-matrix -- --tier quick`

use clap::Parser;
use granular_automata::analysis::grading::Kind;
use granular_automata::cli::Common;
use granular_automata::drivers::claims::{
    grade_groups, grade_steps, site_updates, Graded, Group, MatrixSize, Verdict, CLAIMS,
    GRADING_VERSION,
};
use granular_automata::pipe::Engine;
use granular_automata::pipe::Rules;
use granular_automata::plot::{plot_err, register_fonts, FONT};
use granular_automata::run::{progress, write_atomic, Check, Output, Summary};
use plotters::prelude::*;
use serde_json::json;
use std::collections::BTreeMap;
use std::time::Instant;

/// The readings graded by default: every named variant of MODEL.md, the
/// combinations A11 mentions, and `wall-move` (issue 4, session 2) alone and
/// with each of the others.
const READINGS: &str = "ph94,any-mover,up-to-rest,ph94+wall-drag,ph94+gravity-first,ph94+rest-up,\
ph94+wall-drag+gravity-first,any-mover+wall-drag,any-mover+rest-up,ph94+wall-move,\
ph94+gravity-first+wall-move,ph94+rest-up+wall-move,ph94+gravity-first+rest-up+wall-move,\
ph94+wall-drag+wall-move,any-mover+wall-move";

#[derive(Parser)]
#[command(about = "Which reading of the pipe rules reproduces which published claim")]
struct Args {
    #[command(flatten)]
    common: Common,
    /// Readings to grade, comma-separated (each a --rules value).
    #[arg(long, default_value = READINGS)]
    readings: String,
    /// Engine: reference or fast (validated against the reference, issue 13).
    #[arg(long, default_value = "reference")]
    engine: String,
    /// Groups of claims to grade, comma-separated, or all: bands, spectra,
    /// relaxation, profile, speed, fig11, fig12 (the open pipe's two groups
    /// cost minutes of CPU per reading in clogging runs); the others are
    /// listed as not run.
    #[arg(long, default_value = "all")]
    groups: String,
}

/// The grade of claim `id` in `graded`, if its group was run.
fn find<'a>(graded: &'a [Graded], id: &str) -> Option<&'a Graded> {
    graded.iter().find(|g| g.claim == id)
}

/// The measured value of a cell: `m +- e`, `n/5 agree` for the density
/// window, `no value` when nothing was measured (never `NaN`).
fn value(g: &Graded) -> String {
    if !g.measured.is_finite() {
        "no value".to_string()
    } else if g.claim == "rho_window" {
        format!("{:.0}/5 agree", g.measured)
    } else if !g.error.is_finite() {
        format!("{:.3}", g.measured)
    } else {
        format!("{:.3} +- {:.3}", g.measured, g.error)
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    args.common.reject_shard("pipe-matrix")?;
    let tier = args.common.tier;
    let mut size = MatrixSize::for_tier(tier);
    if let Some(r) = args.common.runs {
        size = size.with_runs(r); // 1..=MAX_RUNS, checked when parsed
    }
    let readings: Vec<Rules> = args
        .readings
        .split(',')
        .map(|s| s.trim().parse())
        .collect::<Result<_, _>>()?;
    let out = Output::new(&args.common.out, "pipe-matrix")?;
    let cache = out.path("variants");
    std::fs::create_dir_all(&cache)?;
    let engine: Engine = args.engine.parse()?;
    let groups = Group::parse_list(&args.groups)?;
    let key = format!(
        "{}-seed{}-runs{}-grading{GRADING_VERSION}{}{}",
        tier.name(),
        args.common.seed,
        size.runs_key(),
        match engine {
            Engine::Reference => String::new(),
            other => format!("-{other}"),
        },
        if groups.len() == Group::ALL.len() {
            String::new()
        } else {
            format!(
                "-groups-{}",
                groups
                    .iter()
                    .map(|g| g.name())
                    .collect::<Vec<_>>()
                    .join("+")
            )
        }
    );

    let start = Instant::now();
    let pb = progress(
        readings.len() as u64 * grade_steps(size),
        "pipe-matrix steps",
    );
    let mut rows: Vec<(Rules, Vec<Graded>)> = Vec::new();
    for &rules in &readings {
        let file = cache.join(format!("{rules}.{key}.json"));
        let graded: Vec<Graded> = match std::fs::read_to_string(&file) {
            Ok(text) => {
                pb.inc(grade_steps(size));
                serde_json::from_str(&text)?
            }
            Err(_) => {
                pb.set_message(rules.to_string());
                let g = grade_groups(
                    rules,
                    engine,
                    size,
                    args.common.seed,
                    &groups,
                    |p| p,
                    &|n| pb.inc(n),
                )?;
                write_atomic(&file, serde_json::to_string_pretty(&g)?.as_bytes())?;
                g
            }
        };
        rows.push((rules, graded));
    }
    pb.finish();
    let wall = start.elapsed().as_secs_f64();

    // tables: one row per claim, one column per reading
    let mut md = format!(
        "# Reproduction matrix ({} tier, runs per set-up {} (bands and spectra - PH95 Figs. 3-5 - open pipe), seed {})\n\n| claim | {} |\n|---|{}\n",
        tier.name(),
        size.runs_key(),
        args.common.seed,
        rows.iter().map(|(r, _)| format!("`{r}`")).collect::<Vec<_>>().join(" | "),
        "---|".repeat(rows.len())
    );
    let mut csv = vec![];
    let mut metrics = BTreeMap::new();
    for (id, _) in CLAIMS.iter() {
        let cells: Vec<String> = rows
            .iter()
            .map(|(_, graded)| match find(graded, id) {
                Some(g) => format!("{} {}", g.verdict.label(), value(g)),
                None => "not run (--groups)".to_string(),
            })
            .collect();
        md.push_str(&format!("| `{id}` | {} |\n", cells.join(" | ")));
    }
    let mut totals = Vec::new();
    for (rules, graded) in &rows {
        let n = graded
            .iter()
            .filter(|g| g.verdict == Verdict::Reproduced)
            .count();
        totals.push(format!("{n}/{}", graded.len()));
        metrics.insert(format!("{rules}.reproduced"), n as f64);
        for g in graded {
            metrics.insert(format!("{rules}.{}", g.claim), g.measured);
            metrics.insert(format!("{rules}.{}_err", g.claim), g.error);
            csv.push(format!(
                "{rules},{},{},{},{},\"{}\"",
                g.claim,
                g.verdict.label(),
                g.measured,
                g.error,
                g.detail.replace('"', "'")
            ));
        }
    }
    md.push_str(&format!("| reproduced | {} |\n", totals.join(" | ")));
    md.push_str("\nCells: verdict (yes = reproduced, no = not reproduced, ? = undecided), measured value +- standard error over runs.\n\nClaims:\n\n");
    for (id, what) in CLAIMS {
        md.push_str(&format!("- `{id}`: {what}\n"));
    }
    md.push_str("\nDetails:\n\n");
    for (rules, graded) in &rows {
        for g in graded {
            md.push_str(&format!(
                "- `{rules}` `{}`: {} - {}\n",
                g.claim,
                g.verdict.label(),
                g.detail
            ));
        }
    }
    write_atomic(&out.path("matrix.md"), md.as_bytes())?;
    let csv_text = format!(
        "reading,claim,verdict,measured,error,detail\n{}\n",
        csv.join("\n")
    );
    write_atomic(&out.path("matrix.csv"), csv_text.as_bytes())?;

    // heat map
    register_fonts();
    let (w, h) = (
        300 + 130 * CLAIMS.len() as u32,
        140 + 60 * rows.len() as u32,
    );
    let path = out.path("pipe-matrix.png");
    let root = BitMapBackend::new(&path, (w, h)).into_drawing_area();
    root.fill(&WHITE).map_err(plot_err)?;
    root.draw(&Text::new(
        format!(
            "PH94/PH95 reproduction matrix: readings x published claims ({} tier, {} runs)",
            tier.name(),
            size.runs
        ),
        (10, 10),
        (FONT, 22),
    ))
    .map_err(plot_err)?;
    for (k, (id, _)) in CLAIMS.iter().enumerate() {
        root.draw(&Text::new(
            id.to_string(),
            (300 + 130 * k as i32 + 8, 60),
            (FONT, 16),
        ))
        .map_err(plot_err)?;
    }
    for (r, (rules, graded)) in rows.iter().enumerate() {
        let y = 90 + 60 * r as i32;
        root.draw(&Text::new(rules.to_string(), (10, y + 20), (FONT, 16)))
            .map_err(plot_err)?;
        for (k, (id, _)) in CLAIMS.iter().enumerate() {
            let x = 300 + 130 * k as i32;
            let Some(g) = find(graded, id) else {
                root.draw(&Text::new("not run", (x + 6, y + 6), (FONT, 16)))
                    .map_err(plot_err)?;
                continue;
            };
            let color = match g.verdict {
                Verdict::Reproduced => RGBColor(120, 200, 120),
                Verdict::NotReproduced => RGBColor(230, 120, 110),
                Verdict::Undecided => RGBColor(200, 200, 200),
            };
            root.draw(&Rectangle::new([(x, y), (x + 126, y + 56)], color.filled()))
                .map_err(plot_err)?;
            root.draw(&Text::new(
                g.verdict.label().to_string(),
                (x + 6, y + 6),
                (FONT, 18),
            ))
            .map_err(plot_err)?;
            let text = value(g);
            let (m, e) = text.split_once(" +- ").unwrap_or((text.as_str(), ""));
            root.draw(&Text::new(m.to_string(), (x + 6, y + 24), (FONT, 14)))
                .map_err(plot_err)?;
            if !e.is_empty() {
                root.draw(&Text::new(format!("+- {e}"), (x + 6, y + 39), (FONT, 13)))
                    .map_err(plot_err)?;
            }
        }
    }
    root.draw(&Text::new(
        "green: reproduced, red: not reproduced, grey: undecided; numbers: measured +- SE over runs (claims in matrix.md)",
        (10, h as i32 - 30),
        (FONT, 15),
    ))
    .map_err(plot_err)?;
    root.present().map_err(plot_err)?;

    // checks: the default reading's grades
    let default = Rules::default();
    // issue 4: how many claims the default reproduces (null when the default
    // is not among --readings) and how many were graded
    let default_reproduced = rows
        .iter()
        .find(|(r, _)| *r == default)
        .map(|(_, g)| {
            g.iter()
                .filter(|g| g.verdict == Verdict::Reproduced)
                .count() as f64
        })
        .unwrap_or(f64::NAN);
    metrics.insert("default_reproduced".into(), default_reproduced);
    metrics.insert("claims".into(), CLAIMS.len() as f64);
    let checks: Vec<Check> = rows
        .iter()
        .filter(|(r, _)| *r == default)
        .flat_map(|(_, graded)| {
            graded.iter().map(|g| {
                let source = CLAIMS
                    .iter()
                    .find(|(id, _)| *id == g.claim)
                    .map_or("MODEL.md A10", |(_, what)| what);
                Check::with_verdict(
                    &format!("default.{}", g.claim),
                    Kind::Published,
                    source,
                    g.measured,
                    g.error,
                    size.runs,
                    g.verdict,
                    &g.detail,
                )
            })
        })
        .collect();
    let summary_path = out.finish(&Summary {
        figure: "pipe-matrix".into(),
        paper: "PH94 Figs. 1-2, PH95 Figs. 3-8, 11-12".into(),
        tier,
        seeds: vec![args.common.seed],
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
    // the matrix as a list in summary.json (issue 4)
    let matrix: Vec<serde_json::Value> = rows
        .iter()
        .flat_map(|(r, graded)| {
            graded.iter().map(move |g| {
                json!({"variant": r.to_string(), "claim": g.claim, "status": g.verdict.status(),
                       "measured": g.measured, "error": g.error})
            })
        })
        .collect();
    let mut summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&summary_path)?)?;
    summary["matrix"] = json!(matrix);
    write_atomic(
        &summary_path,
        serde_json::to_string_pretty(&summary)?.as_bytes(),
    )?;
    println!(
        "{}",
        std::fs::read_to_string(out.path("matrix.md"))?
            .lines()
            .take(5 + CLAIMS.len())
            .collect::<Vec<_>>()
            .join("\n")
    );
    Ok(())
}
