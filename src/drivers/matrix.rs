//! The reproduction matrix's procedure (`pipe-matrix`, MODEL.md A11):
//! grade every reading against the claims of [`crate::drivers::claims`], each
//! reading saved once graded and reused, then the matrix as Markdown, CSV,
//! a heat map, the default reading's checks and the list of cells.

use super::claims::{
    grade_groups, grade_steps, Graded, Group, MatrixSize, Verdict, CLAIMS, GRADING_VERSION,
};
use crate::analysis::grading::Kind;
use crate::error::{Error, ErrorKind, Result};
use crate::pipe::{Engine, Rules};
use crate::plot::{plot_err, register_fonts, FONT};
use crate::run::{portable_file_name, progress, write_atomic, Check, Output, Tier};
use plotters::prelude::*;
use serde_json::json;
use std::collections::BTreeMap;
use std::path::Path;

/// A JSON error of `what` (a saved reading, the summary) as an i/o error.
fn json_error(what: &Path) -> impl Fn(serde_json::Error) -> Error + '_ {
    move |e| Error::new(ErrorKind::Io, format!("{}: {e}", what.display()))
}

/// One graded reading: its rules and a grade per claim of the groups run.
pub type Row = (Rules, Vec<Graded>);

/// What a matrix grades: tier, size, seed, engine and groups of claims.
pub struct Matrix<'a> {
    /// The tier (spectra, schedules, trend runs).
    pub tier: Tier,
    /// Runs per set-up.
    pub size: MatrixSize,
    /// Base seed.
    pub seed: u64,
    /// The engine.
    pub engine: Engine,
    /// The groups of claims graded.
    pub groups: &'a [Group],
}

impl Matrix<'_> {
    /// The part of a saved reading's file name that says how it was graded:
    /// any change of tier, seed, runs, grading rules, engine or groups makes
    /// a new file.
    pub fn key(&self) -> String {
        format!(
            "{}-seed{}-runs{}-grading{GRADING_VERSION}{}{}",
            self.tier.name(),
            self.seed,
            self.size.runs_key(),
            match self.engine {
                Engine::Reference => String::new(),
                other => format!("-{other}"),
            },
            if self.groups.len() == Group::ALL.len() {
                String::new()
            } else {
                let names: Vec<&str> = self.groups.iter().map(|g| g.name()).collect();
                format!("-groups-{}", names.join("+"))
            }
        )
    }

    /// The file in `cache` that holds the saved grade of `rules`:
    /// `READING.KEY.json` ([`Matrix::key`]), made portable by
    /// [`portable_file_name`] (`lane-collide:0.1` is saved as
    /// `lane-collide_0.1`).
    pub fn saved(&self, cache: &Path, rules: Rules) -> std::path::PathBuf {
        cache.join(portable_file_name(&format!("{rules}.{}.json", self.key())))
    }

    /// Grade each reading, reading a saved grade from `cache` when there is
    /// one and saving each new one as soon as it is graded (in
    /// [`Matrix::saved`]); a progress bar counts the steps.
    pub fn grade(&self, readings: &[Rules], cache: &Path) -> Result<Vec<Row>> {
        let size = self.size;
        let pb = progress(
            readings.len() as u64 * grade_steps(size),
            "pipe-matrix steps",
        );
        let mut rows = Vec::new();
        for &rules in readings {
            let file = self.saved(cache, rules);
            let graded: Vec<Graded> = match std::fs::read_to_string(&file) {
                Ok(text) => {
                    pb.inc(grade_steps(size));
                    serde_json::from_str(&text).map_err(json_error(&file))?
                }
                Err(_) => {
                    pb.set_message(rules.to_string());
                    let tick = |n| pb.inc(n);
                    let g = grade_groups(
                        rules,
                        self.engine,
                        size,
                        self.seed,
                        self.groups,
                        |p| p,
                        &tick,
                    )?;
                    let text = serde_json::to_string_pretty(&g).map_err(json_error(&file))?;
                    write_atomic(&file, text.as_bytes())?;
                    g
                }
            };
            rows.push((rules, graded));
        }
        pb.finish();
        Ok(rows)
    }
}

/// The grade of claim `id` in `graded`, if its group was run.
pub fn find<'a>(graded: &'a [Graded], id: &str) -> Option<&'a Graded> {
    graded.iter().find(|g| g.claim == id)
}

/// The measured value of a cell: `m +- e`, `n/5 agree` for the density
/// window, `n runs invalid` where every run at a point the paper measured
/// left the model's validity (the statistic is then that count,
/// `drivers::dependence`), `no value` when nothing was measured (never
/// `NaN`).
pub fn value(g: &Graded) -> String {
    if !g.measured.is_finite() {
        "no value".to_string()
    } else if g.detail.contains("left the model's validity (all") {
        format!("{:.0} runs invalid", g.measured)
    } else if g.claim == "rho_window" {
        format!("{:.0}/5 agree", g.measured)
    } else if !g.error.is_finite() {
        format!("{:.3}", g.measured)
    } else {
        format!("{:.3} +- {:.3}", g.measured, g.error)
    }
}

/// Claims reproduced by one reading.
fn reproduced(graded: &[Graded]) -> usize {
    graded
        .iter()
        .filter(|g| g.verdict == Verdict::Reproduced)
        .count()
}

/// `matrix.md` (one row per claim, one column per reading, then the claims
/// and every detail) and `matrix.csv` (one line per cell) into `out`; the
/// metrics of the summary (each cell's value and error, each reading's
/// count of reproduced claims).
pub fn write_tables(
    out: &Output,
    rows: &[Row],
    (tier, size, seed): (Tier, MatrixSize, u64),
) -> Result<BTreeMap<String, f64>> {
    let mut md = format!(
        "# Reproduction matrix ({} tier, runs per set-up {} (bands and spectra - PH95 Figs. 3-5 - open pipe), seed {})\n\n| claim | {} |\n|---|{}\n",
        tier.name(),
        size.runs_key(),
        seed,
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
    for (rules, graded) in rows {
        let n = reproduced(graded);
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
    for (rules, graded) in rows {
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
    Ok(metrics)
}

/// The heat map `pipe-matrix.png`: readings x claims, coloured by verdict,
/// with the measured value and its error in each cell.
pub fn heat_map(out: &Output, rows: &[Row], tier: Tier, runs: usize) -> Result<()> {
    register_fonts();
    // the reading names, at about 8 px per character, set the left column
    let names = rows.iter().map(|(r, _)| r.to_string().len()).max();
    let left = 300.max(20 + 8 * names.unwrap_or(0) as i32);
    let (w, h) = (
        left as u32 + 130 * CLAIMS.len() as u32 + 60,
        140 + 60 * rows.len() as u32,
    );
    let path = out.path("pipe-matrix.png");
    let root = BitMapBackend::new(&path, (w, h)).into_drawing_area();
    root.fill(&WHITE).map_err(plot_err)?;
    let title = format!(
        "PH94/PH95 reproduction matrix: readings x published claims ({} tier, {runs} runs per spectrum set-up; every set-up's runs in matrix.md)",
        tier.name()
    );
    let text = |s: &str, at: (i32, i32), size: u32| {
        root.draw(&Text::new(s.to_string(), at, (FONT, size)))
            .map_err(plot_err)
    };
    text(&title, (10, 10), 22)?;
    // staggered on two lines, so that long claim ids do not run into each other
    for (k, (id, _)) in CLAIMS.iter().enumerate() {
        let y = if k % 2 == 0 { 44 } else { 66 };
        text(id, (left + 130 * k as i32 + 8, y), 16)?;
    }
    for (r, (rules, graded)) in rows.iter().enumerate() {
        let y = 90 + 60 * r as i32;
        text(&rules.to_string(), (10, y + 20), 16)?;
        for (k, (id, _)) in CLAIMS.iter().enumerate() {
            let x = left + 130 * k as i32;
            let Some(g) = find(graded, id) else {
                text("not run", (x + 6, y + 6), 16)?;
                continue;
            };
            let color = match g.verdict {
                Verdict::Reproduced => RGBColor(120, 200, 120),
                Verdict::NotReproduced => RGBColor(230, 120, 110),
                Verdict::Undecided => RGBColor(200, 200, 200),
            };
            root.draw(&Rectangle::new([(x, y), (x + 126, y + 56)], color.filled()))
                .map_err(plot_err)?;
            text(g.verdict.label(), (x + 6, y + 6), 18)?;
            let v = value(g);
            let (m, e) = v.split_once(" +- ").unwrap_or((v.as_str(), ""));
            text(m, (x + 6, y + 24), 14)?;
            if !e.is_empty() {
                text(&format!("+- {e}"), (x + 6, y + 39), 13)?;
            }
        }
    }
    text(
        "green: reproduced, red: not reproduced, grey: undecided; numbers: measured +- SE over runs (claims in matrix.md)",
        (10, h as i32 - 30),
        15,
    )?;
    root.present().map_err(plot_err)
}

/// The default reading's grades as the summary's checks (none when the
/// default is not among the readings), and the count of claims it
/// reproduces (NaN then). Each check carries its group's run count; `runs`
/// stands in only for rows saved before that count was recorded.
pub fn default_checks(rows: &[Row], runs: usize) -> (Vec<Check>, f64) {
    let default = Rules::default();
    let defaults = || rows.iter().filter(|(r, _)| *r == default);
    let count = defaults()
        .next()
        .map_or(f64::NAN, |(_, g)| reproduced(g) as f64);
    let checks = defaults()
        .flat_map(|(_, graded)| graded)
        .map(|g| {
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
                if g.runs > 0 { g.runs } else { runs },
                g.verdict,
                &g.detail,
            )
        })
        .collect();
    (checks, count)
}

/// Add the matrix as a list of cells (`matrix`: reading, claim, status,
/// measured, error) to the summary at `summary_path`.
pub fn add_cells(summary_path: &Path, rows: &[Row]) -> Result<()> {
    let matrix: Vec<serde_json::Value> = rows
        .iter()
        .flat_map(|(r, graded)| {
            graded.iter().map(move |g| {
                json!({"variant": r.to_string(), "claim": g.claim, "status": g.verdict.status(),
                       "measured": g.measured, "error": g.error})
            })
        })
        .collect();
    let text = std::fs::read_to_string(summary_path)?;
    let mut summary: serde_json::Value =
        serde_json::from_str(&text).map_err(json_error(summary_path))?;
    summary["matrix"] = json!(matrix);
    let text = serde_json::to_string_pretty(&summary).map_err(json_error(summary_path))?;
    write_atomic(summary_path, text.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each default check carries its own group's run count (a relaxation
    /// claim runs 16 at the quick tier, a band claim 3); a row saved before
    /// the count was recorded falls back to the matrix's `runs`.
    #[test]
    fn default_checks_carry_their_groups_run_count() {
        let g = |claim: &str, runs| Graded {
            claim: claim.to_string(),
            measured: 1.0,
            error: 0.1,
            verdict: Verdict::Undecided,
            detail: String::new(),
            runs,
        };
        let rows = vec![(
            Rules::default(),
            vec![g("energy_rises", 16), g("waves_1a", 0)],
        )];
        let (checks, _) = default_checks(&rows, 3);
        assert_eq!(checks[0].name, "default.energy_rises");
        assert_eq!(checks[0].runs, 16);
        assert_eq!(checks[1].runs, 3);
    }
}
