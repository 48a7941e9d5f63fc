//! How the group-sequential designs of [`crate::analysis::sequential`]
//! behave before any figure trusts them: the wrong-verdict rate and the mean
//! runs spent, against the distance of the truth from the published value
//! (in margins), for synthetic normal runs and for resampled committed runs
//! of PH94 Fig. 2 and PH95 Fig. 6; beside the fixed design of the acceptance
//! tier (one look at the maximum, k = max(2, t)). `sequential-design`
//! writes the table and the plots.

use crate::analysis::fit::alpha_prefix;
use crate::analysis::grading::{Claim, Verdict};
use crate::analysis::sequential::{simulate, simulate_claim, Design, Simulated, Source, Spending};
use crate::error::{Error, ErrorKind, Result};
use crate::plot::{line_chart, Line, PALETTE};
use crate::run::Output;
use plotters::chart::SeriesLabelPosition;
use std::path::Path;

/// Distances of the truth from the published value, in margins: inside
/// (0, 0.5), on the edge (1) and outside (1.5, 2).
pub const DISTANCES: [f64; 5] = [0.0, 0.5, 1.0, 1.5, 2.0];

/// The stated chance of each kind of wrong verdict over all looks.
pub const ALPHA: f64 = 0.025;

/// The first look of the sequential designs (runs).
pub const FIRST_LOOK: usize = 16;

/// A design under study, with its name.
pub struct Named {
    /// Name in the table, e.g. `obrien-fleming 16..128`.
    pub name: String,
    /// The design.
    pub design: Design,
}

/// The designs compared up to `max` runs: the fixed one (a single look at
/// `max`), O'Brien-Fleming and Pocock from [`FIRST_LOOK`] doubling to `max`.
pub fn designs(max: usize) -> Result<Vec<Named>> {
    let mut out = vec![Named {
        name: format!("fixed {max}"),
        design: Design::new(vec![max], ALPHA, Spending::OBrienFleming)?,
    }];
    for s in [Spending::OBrienFleming, Spending::Pocock] {
        out.push(Named {
            name: format!("{} {FIRST_LOOK}..{max}", s.name()),
            design: Design::doubling(FIRST_LOOK, max, ALPHA, s)?,
        });
    }
    Ok(out)
}

/// A source of runs with the margin of its claim.
pub struct Case {
    /// Name in the table.
    pub name: String,
    /// The margin Delta of the claim.
    pub margin: f64,
    /// Where the runs come from.
    pub source: Source,
}

/// The per-run `column` of a committed runs.csv and the margin of check
/// `check` in the summary.json beside it.
fn committed(dir: &Path, column: &str, check: &str) -> Result<(Vec<f64>, f64)> {
    let bad = |what: String| Error::new(ErrorKind::Io, format!("{}: {what}", dir.display()));
    let text =
        std::fs::read_to_string(dir.join("runs.csv")).map_err(|e| bad(format!("runs.csv: {e}")))?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let i = header
        .iter()
        .position(|h| *h == column)
        .ok_or_else(|| bad(format!("runs.csv has no column {column}")))?;
    let values = lines
        .map(|l| l.split(',').nth(i).and_then(|v| v.parse::<f64>().ok()))
        .collect::<Option<Vec<f64>>>()
        .ok_or_else(|| bad(format!("runs.csv: a row without a number in {column}")))?;
    Ok((values, committed_margin(dir, check)?))
}

/// The margin of check `check` in `dir/summary.json`.
/// The largest margin a committed check may state (alpha and v are of
/// order one; the acceptance margins are below 0.2).
const MAX_MARGIN: f64 = 1.0;

fn committed_margin(dir: &Path, check: &str) -> Result<f64> {
    let bad = |what: String| Error::new(ErrorKind::Io, format!("{}: {what}", dir.display()));
    let summary: serde_json::Value = std::fs::read_to_string(dir.join("summary.json"))
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok())
        .ok_or_else(|| bad("summary.json unreadable".into()))?;
    let margin = summary["checks"]
        .as_array()
        .and_then(|cs| cs.iter().find(|c| c["name"] == check))
        .and_then(|c| c["tolerance"].as_f64())
        .ok_or_else(|| bad(format!("summary.json has no check {check} with a margin")))?;
    // a margin of alpha or v: refused at once when it cannot be one, before
    // any trial is simulated
    if !(margin > 0.0 && margin <= MAX_MARGIN) {
        return Err(bad(format!(
            "summary.json: check {check} has the margin {margin}, outside the allowed range (0, {MAX_MARGIN}]"
        )));
    }
    Ok(margin)
}

/// The cases: normal runs with a spread of 0.5, 1 and 2 margins, and the
/// committed per-run alphas of PH94 Fig. 2 and PH95 Fig. 6 under `report`
/// (the committed report's folder), resampled, with their margins.
pub fn cases(report: &Path) -> Result<Vec<Case>> {
    let mut out: Vec<Case> = [0.5, 1.0, 2.0]
        .iter()
        .map(|&sd| Case {
            name: format!("normal, sd {sd} margins"),
            margin: 1.0,
            source: Source::Normal { sd },
        })
        .collect();
    for (fig, name) in [
        ("fig2", "PH94 Fig. 2 alpha"),
        ("waves-fig6", "PH95 Fig. 6 alpha"),
    ] {
        let (values, margin) = committed(&report.join(fig), "alpha", "alpha")?;
        let source = Source::Resampled { values };
        out.push(Case {
            name: format!("{name}, resampled (sd {:.2} margins)", source.sd() / margin),
            margin,
            source,
        });
    }
    Ok(out)
}

/// The spectra of the saved runs of figure `fig` under `suite` (the `--out`
/// folder of an acceptance-tier report: `suite/FIG/runs/KEY/run-*.json`,
/// one run folder), each cut to the bins alpha reads, with m.
fn saved_spectra(suite: &Path, fig: &str) -> Result<(Vec<Vec<f64>>, usize)> {
    let runs = suite.join(fig).join("runs");
    let bad = |what: String| Error::new(ErrorKind::Io, format!("{}: {what}", runs.display()));
    let listed = |dir: &Path| -> Result<Vec<std::path::PathBuf>> {
        let mut v: Vec<_> = std::fs::read_dir(dir)
            .map_err(|e| bad(format!("cannot list {}: {e}", dir.display())))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .collect();
        v.sort();
        Ok(v)
    };
    let folders: Vec<_> = listed(&runs)?.into_iter().filter(|p| p.is_dir()).collect();
    let [folder] = folders.as_slice() else {
        return Err(bad(format!(
            "needs exactly one run folder (one configuration), found {}",
            folders.len()
        )));
    };
    let mut rows = Vec::new();
    let mut m = 0;
    for path in listed(folder)? {
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
        if !(name.starts_with("run-") && name.ends_with(".json")) {
            continue;
        }
        let text =
            std::fs::read_to_string(&path).map_err(|e| bad(format!("{}: {e}", path.display())))?;
        let body = crate::ensemble::verify_run_file(&path, &text)?;
        let spectrum: Vec<f64> = body
            .get("result")
            .and_then(|r| r.get("spectrum"))
            .and_then(|s| serde_json::from_value(s.clone()).ok())
            .ok_or_else(|| bad(format!("{} holds no spectrum", path.display())))?;
        if m == 0 {
            m = spectrum.len();
        }
        if let Some((j, x)) = spectrum
            .iter()
            .enumerate()
            .find(|(_, x)| !(x.is_finite() && **x > 0.0))
        {
            return Err(bad(format!(
                "{}: spectrum bin {j} is {x}, not a finite power > 0",
                path.display()
            )));
        }
        if spectrum.len() != m || m == 0 {
            return Err(bad(format!(
                "{}: a spectrum of {} frequencies among spectra of {m}",
                path.display(),
                spectrum.len()
            )));
        }
        rows.push(spectrum[..alpha_prefix(m)].to_vec());
    }
    if rows.len() < 3 {
        return Err(bad(format!(
            "{}: {} run files (run-*.json); the estimator's bootstrap needs at least 3",
            folder.display(),
            rows.len()
        )));
    }
    Ok((rows, m))
}

/// The cases of the acceptance tier's own estimator: the saved runs'
/// spectra of PH94 Fig. 2 and PH95 Fig. 6 under `suite`, resampled, each
/// look grading alpha of their averaged spectrum with its bootstrap SE;
/// margins from the summaries beside them.
pub fn spectra_cases(suite: &Path, threads: usize) -> Result<Vec<Case>> {
    let mut out = Vec::new();
    for (fig, name) in [
        ("fig2", "PH94 Fig. 2 alpha"),
        ("waves-fig6", "PH95 Fig. 6 alpha"),
    ] {
        let (rows, m) = saved_spectra(suite, fig)?;
        let n = rows.len();
        let margin = committed_margin(&suite.join(fig), "alpha")?;
        let source = Source::Spectra { rows, m, threads };
        out.push(Case {
            name: format!(
                "{name} of the averaged spectrum, {n} runs resampled (sd {:.2} margins)",
                source.sd() / margin
            ),
            margin,
            source,
        });
    }
    Ok(out)
}

/// One row of the study.
pub struct Row {
    /// The design's name.
    pub design: String,
    /// The case's name.
    pub case: String,
    /// The truth's distance from the published value, in margins.
    pub distance: f64,
    /// What was measured.
    pub sim: Simulated,
}

/// Simulate every design, case and distance with `trials` trials each;
/// `seed` + the cell's index seeds each cell; `tick` after each cell.
pub fn measure(
    designs: &[Named],
    cases: &[Case],
    trials: usize,
    seed: u64,
    tick: impl Fn(),
) -> Result<Vec<Row>> {
    let mut rows = Vec::new();
    for d in designs {
        for c in cases {
            for &distance in &DISTANCES {
                let cell = seed.wrapping_add(rows.len() as u64);
                let sim = simulate(&d.design, c.margin, distance, &c.source, trials, cell)?;
                rows.push(Row {
                    design: d.name.clone(),
                    case: c.name.clone(),
                    distance,
                    sim,
                });
                tick();
            }
        }
    }
    Ok(rows)
}

/// The largest wrong-verdict rate a design may show over `trials` trials
/// when its true rate is [`ALPHA`]: ALPHA plus three binomial SDs.
pub fn allowed(trials: usize) -> f64 {
    ALPHA + 3.0 * (ALPHA * (1.0 - ALPHA) / trials.max(1) as f64).sqrt()
}

/// Write `design.csv`, `design.md` (the table, with the boundaries) and two
/// plots, `wrong.png` and `runs.png`, against the distance.
pub fn write(
    out: &Output,
    designs: &[Named],
    rows: &[Row],
    trials: usize,
    command: &str,
) -> Result<()> {
    let mut csv =
        String::from("design,case,distance,reproduced,not_reproduced,undecided,wrong,mean_runs\n");
    let mut md = format!(
        "# Sequential designs: wrong verdicts and runs\n\nWritten by `{command}`. Each cell: {trials} simulated claims \"within Delta of the published value\", the truth `distance` margins away. Wrong: not reproduced although the truth is within the margin (distance <= 1), reproduced although it is outside. Stated level {ALPHA} per kind of wrong verdict; a cell above {:.4} (three binomial SDs more) would contradict it.\n\n",
        allowed(trials)
    );
    md.push_str("| design | looks | boundaries k_j |\n|---|---|---|\n");
    for d in designs {
        let ks: Vec<String> = d
            .design
            .boundaries
            .iter()
            .map(|k| format!("{k:.3}"))
            .collect();
        md.push_str(&format!(
            "| {} | {:?} | {} |\n",
            d.name,
            d.design.looks,
            ks.join(", ")
        ));
    }
    md.push_str("\n| design | case | distance | reproduced | not reproduced | undecided | wrong | mean runs |\n|---|---|---|---|---|---|---|---|\n");
    for r in rows {
        let s = &r.sim;
        let shares = [s.reproduced, s.not_reproduced, s.undecided, s.wrong];
        let row = |share: &dyn Fn(f64) -> String, runs: String, sep: &str| {
            let cells: Vec<String> = [r.design.clone(), r.case.clone(), r.distance.to_string()]
                .into_iter()
                .chain(shares.iter().map(|&x| share(x)))
                .chain([runs])
                .collect();
            cells.join(sep)
        };
        csv.push_str(&row(&|x| x.to_string(), s.mean_runs.to_string(), ","));
        csv.push('\n');
        md.push_str(&format!(
            "| {} |\n",
            row(&|x| format!("{x:.4}"), format!("{:.1}", s.mean_runs), " | ")
        ));
    }
    crate::run::write_atomic(&out.path("design.csv"), csv.as_bytes())?;
    crate::run::write_atomic(&out.path("design.md"), md.as_bytes())?;
    // wrong.png: each design's worst normal and worst resampled case at each
    // distance; runs.png: each
    // design on the first normal case and on the first committed one
    let of = |d: &Named,
              keep: &dyn Fn(&Row) -> bool,
              f: &dyn Fn(&Simulated) -> f64|
     -> Vec<(f64, f64)> {
        DISTANCES
            .iter()
            .map(|&x| {
                let ys = rows
                    .iter()
                    .filter(|r| r.design == d.name && r.distance == x && keep(r));
                (x, ys.map(|r| f(&r.sim)).fold(f64::NAN, f64::max))
            })
            .collect()
    };
    let picked: Vec<&String> = ["normal, sd 1", "PH94 Fig. 2"]
        .iter()
        .filter_map(|p| rows.iter().map(|r| &r.case).find(|c| c.starts_with(p)))
        .collect();
    let mut wrong = Vec::new();
    let mut runs = Vec::new();
    for (i, d) in designs.iter().enumerate() {
        for (j, (what, normal)) in [("normal", true), ("resampled", false)]
            .into_iter()
            .enumerate()
        {
            let color = PALETTE[(i + 3 * j) % PALETTE.len()];
            let keep = move |r: &Row| r.case.starts_with("normal") == normal;
            let label = format!("{}, {what}", d.name);
            wrong.push(Line::new(&label, of(d, &keep, &|s| s.wrong), color).markers());
            wrong.push(Line::new("", of(d, &keep, &|s| s.wrong), color));
        }
        for (j, case) in picked.iter().enumerate() {
            let color = PALETTE[(i + 3 * j) % PALETTE.len()];
            let pts = of(d, &|r| &&r.case == case, &|s| s.mean_runs);
            runs.push(Line::new(&format!("{}; {case}", d.name), pts, color));
        }
    }
    wrong.push(Line::new(
        &format!("stated level {ALPHA}"),
        vec![(0.0, ALPHA), (2.0, ALPHA)],
        plotters::style::BLACK,
    ));
    line_chart(
        &out.path("wrong.png"),
        &format!("Worst wrong-verdict rate of normal and of resampled committed runs ({trials} trials per point)"),
        "distance of the truth from the published value (margins)",
        "share of wrong verdicts",
        &wrong,
        false,
        SeriesLabelPosition::UpperRight,
    )?;
    line_chart(
        &out.path("runs.png"),
        &format!("Mean runs spent against the truth's distance ({trials} trials per point)"),
        "distance of the truth from the published value (margins)",
        "mean runs per claim",
        &runs,
        false,
        SeriesLabelPosition::LowerMiddle,
    )
}

/// A published claim of the committed report, as a simulation sees it.
pub struct Committed {
    /// `figure/check`.
    pub name: String,
    /// The claim.
    pub claim: Claim,
    /// The plug-in truth: the mean over the committed seed sets where there
    /// are some, else the report's own value.
    pub truth: f64,
    /// The spread of one run: the report's SE x sqrt(runs).
    pub sd: f64,
    /// The report's fixed run count.
    pub fixed: usize,
    /// The verdict over the committed seed sets, where there are some.
    pub seed_sets: Option<Verdict>,
}

/// The published claims of the committed report `report.json` with a
/// value, a spread and at least three runs (exact counts and blind checks
/// have none).
pub fn committed_claims(report_json: &Path) -> Result<Vec<Committed>> {
    let bad =
        |what: String| Error::new(ErrorKind::Io, format!("{}: {what}", report_json.display()));
    let text = std::fs::read_to_string(report_json).map_err(|e| bad(e.to_string()))?;
    let r: serde_json::Value = serde_json::from_str(&text).map_err(|e| bad(e.to_string()))?;
    let rows = r["rows"].as_array().ok_or_else(|| bad("no rows".into()))?;
    let mut out = Vec::new();
    for row in rows.iter().filter(|w| w["kind"] == "published") {
        let num = |k: &str| row[k].as_f64().filter(|x| x.is_finite());
        let (Some(mean), Some(se), Some(runs)) =
            (num("measured"), num("error"), row["runs"].as_u64())
        else {
            continue;
        };
        let tol = num("tolerance");
        let claim = match (row["test"].as_str(), num("published"), tol) {
            (Some("within"), Some(target), Some(margin)) => Claim::Within { target, margin },
            (Some("above"), _, Some(threshold)) => Claim::Above { threshold },
            (Some("below"), _, Some(threshold)) => Claim::Below { threshold },
            _ => continue,
        };
        if runs < 3 || se <= 0.0 {
            continue;
        }
        let truth = row["seed_sets"]["measured"]
            .as_f64()
            .filter(|x| x.is_finite())
            .unwrap_or(mean);
        let seed_sets = match row["seed_sets"]["verdict"].as_str() {
            Some("reproduced") => Some(Verdict::Reproduced),
            Some("not-reproduced") => Some(Verdict::NotReproduced),
            Some("undecided") => Some(Verdict::Undecided),
            _ => None,
        };
        out.push(Committed {
            name: format!(
                "{}/{}",
                row["binary"].as_str().unwrap_or("?"),
                row["name"].as_str().unwrap_or("?")
            ),
            claim,
            truth,
            sd: se * (runs as f64).sqrt(),
            fixed: runs as usize,
            seed_sets,
        });
    }
    Ok(out)
}

/// The designs of the claims study for a claim of `fixed` runs, by name:
/// the fixed count, and O'Brien-Fleming and Pocock from [`FIRST_LOOK`] (or
/// `fixed` when smaller) up to `fixed` and up to 4 `fixed`.
pub fn claim_designs(fixed: usize) -> Result<Vec<(&'static str, Design)>> {
    let seq = |s: Spending, max: usize| Design::doubling(FIRST_LOOK.min(max), max, ALPHA, s);
    Ok(vec![
        (
            "fixed",
            Design::new(vec![fixed], ALPHA, Spending::OBrienFleming)?,
        ),
        (
            "obrien-fleming up to the fixed count",
            seq(Spending::OBrienFleming, fixed)?,
        ),
        (
            "pocock up to the fixed count",
            seq(Spending::Pocock, fixed)?,
        ),
        (
            "obrien-fleming up to 4x",
            seq(Spending::OBrienFleming, 4 * fixed)?,
        ),
        ("pocock up to 4x", seq(Spending::Pocock, 4 * fixed)?),
    ])
}

/// What a design is expected to do over the committed claims.
pub struct Planned {
    /// The design's name.
    pub design: &'static str,
    /// Expected claims decided.
    pub decided: f64,
    /// Expected claims decided against the plug-in truth.
    pub wrong: f64,
    /// Expected runs over all claims (each claim counted alone).
    pub runs: f64,
    /// Expected claims whose verdict equals the one decided over the
    /// committed seed sets (of those where the seed sets decide).
    pub agree: f64,
}

/// Simulate every committed claim (normal runs of its spread around its
/// plug-in truth) under each design of [`claim_designs`], `trials` times.
pub fn plan(
    claims: &[Committed],
    trials: usize,
    seed: u64,
    tick: impl Fn(),
) -> Result<Vec<Planned>> {
    let mut out: Vec<Planned> = Vec::new();
    for (i, c) in claims.iter().enumerate() {
        for (d, (name, design)) in claim_designs(c.fixed)?.into_iter().enumerate() {
            let source = Source::Normal { sd: c.sd };
            let cell = seed.wrapping_add((i * 16 + d) as u64);
            let s = simulate_claim(&design, c.claim, c.truth, &source, trials, cell)?;
            if out.len() <= d {
                out.push(Planned {
                    design: name,
                    decided: 0.0,
                    wrong: 0.0,
                    runs: 0.0,
                    agree: 0.0,
                });
            }
            out[d].agree += match c.seed_sets {
                Some(Verdict::Reproduced) => s.reproduced,
                Some(Verdict::NotReproduced) => s.not_reproduced,
                _ => 0.0,
            };
            out[d].decided += 1.0 - s.undecided;
            out[d].wrong += s.wrong;
            out[d].runs += s.mean_runs;
        }
        tick();
    }
    Ok(out)
}

/// Write `claims.md`: the plan of every design over the committed claims.
pub fn write_plan(
    out: &Output,
    claims: &[Committed],
    plan: &[Planned],
    trials: usize,
    command: &str,
) -> Result<()> {
    let fixed_runs = plan.first().map_or(f64::NAN, |p| p.runs);
    let decided_sets = claims
        .iter()
        .filter(|c| matches!(c.seed_sets, Some(v) if v != Verdict::Undecided))
        .count();
    let mut md = format!(
        "# Sequential designs over the committed claims\n\nWritten by `{command}`. Each of the {} published claims of docs/report/report.json with a value, a spread and at least 3 runs is simulated {trials} times: normal runs with the report's spread per run (SE x sqrt(runs)) around a plug-in truth (the mean over the committed seed sets where there are some, else the report's value), graded by each design. Each claim is counted alone: claims that share runs (one ensemble, one sweep point) would share their cost. Wrong: decided against the plug-in truth. Agree: the verdict of one seed set (base seed 1) equals the one over the committed seed sets, for the {decided_sets} claims those decide.\n\n| design | claims decided (expected) | decided against the truth (expected) | agree with the seed sets (expected, of {decided_sets}) | runs (expected) | runs / fixed |\n|---|---|---|---|---|---|\n",
        claims.len()
    );
    for p in plan {
        md.push_str(&format!(
            "| {} | {:.1} | {:.2} | {:.1} | {:.0} | {:.2} |\n",
            p.design,
            p.decided,
            p.wrong,
            p.agree,
            p.runs,
            p.runs / fixed_runs
        ));
    }
    crate::run::write_atomic(&out.path("claims.md"), md.as_bytes())?;
    Ok(())
}
