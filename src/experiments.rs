//! EXPERIMENTS.md, the current record of every published claim, written
//! from a report's `report.json` and a committed table of per-claim notes
//! (`docs/claim-notes.tsv`), so that it cannot drift from the results.
//!
//! One section per figure in paper order (PH94, PH95, BB90), each with the
//! command that recomputes it, its runs and cost, and per claim: the
//! published value with its margin and where the margin comes from, the
//! measured value at base seed 1 and over the committed seed sets, the
//! verdict, and for a claim not reproduced or undecided what explains it or
//! what would decide it. `report --experiments FILE` writes it; a test
//! regenerates it from the committed files and compares.

use crate::error::{Error, ErrorKind, Result};
use serde_json::Value;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

/// Where the per-claim notes live, relative to the repository.
pub const NOTES: &str = "docs/claim-notes.tsv";

/// Student-t quantile used to say how many runs would decide a claim
/// (the grading rule's k for many runs, two-sided 95 %).
const K_LARGE_N: f64 = 1.96;

/// Per-claim notes, keyed by (figure binary, check name).
pub type Notes = BTreeMap<(String, String), String>;

/// The per-claim notes: `binary<TAB>check<TAB>note` lines (a `#` line is
/// a comment), keyed by (binary, check).
///
/// Errors: a line without three tab-separated fields, or a key given
/// twice ([`ErrorKind::InvalidParameter`], naming the line).
pub fn read_notes(text: &str) -> Result<Notes> {
    let mut notes = BTreeMap::new();
    for (i, line) in text.lines().enumerate() {
        if line.trim().is_empty() || line.starts_with('#') {
            continue;
        }
        let f: Vec<&str> = line.splitn(3, '\t').collect();
        let bad = |why: &str| {
            Error::new(
                ErrorKind::InvalidParameter,
                format!("{NOTES} line {}: {why}", i + 1),
            )
        };
        if f.len() != 3 || f.iter().any(|x| x.trim().is_empty()) {
            return Err(bad("give binary, check and note, separated by tabs"));
        }
        let key = (f[0].to_string(), f[1].to_string());
        if notes.insert(key, f[2].trim().to_string()).is_some() {
            return Err(bad("this claim has a note already"));
        }
    }
    Ok(notes)
}

/// The notes of file `path` ([`read_notes`]).
///
/// Errors: an unreadable file or a malformed note
/// ([`ErrorKind::InvalidParameter`]).
pub fn read_notes_file(path: &Path) -> Result<Notes> {
    // a file that cannot be read is a failure while running (exit 1,
    // docs/reference/cli.md), not a usage error
    let text = std::fs::read_to_string(path).map_err(|e| {
        Error::new(
            ErrorKind::Io,
            format!("--claim-notes {}: {e}", path.display()),
        )
    })?;
    read_notes(&text)
}

/// Write EXPERIMENTS.md to `path` from the report.json at `json` and the
/// notes at `notes` ([`render`]).
///
/// Errors: an unreadable or malformed input, or the file not written.
pub fn write(path: &Path, json: &Path, notes: &Path) -> Result<()> {
    let report: Value = std::fs::read_to_string(json)
        .map_err(|e| e.to_string())
        .and_then(|t| serde_json::from_str(&t).map_err(|e| e.to_string()))
        .map_err(|e| Error::new(ErrorKind::Io, format!("{}: {e}", json.display())))?;
    let text = render(&report, &read_notes_file(notes)?);
    crate::run::write_atomic(path, text.as_bytes())
}

/// The papers' order of the figure binaries.
pub const ORDER: [&str; 15] = [
    "fig1",
    "fig2",
    "waves-fig2",
    "waves-fig3",
    "waves-fig4",
    "waves-fig5",
    "waves-fig6",
    "waves-fig7",
    "waves-fig8",
    "waves-fig9",
    "waves-fig10",
    "waves-fig11",
    "waves-fig12",
    "hopper-fig2",
    "hopper-fig3",
];

/// A number with 4 significant digits (`-` when absent).
fn num(v: &Value) -> String {
    match v.as_f64() {
        Some(0.0) => "0".into(),
        Some(x) if x.is_finite() => {
            let digits = (3 - x.abs().log10().floor() as i32).clamp(0, 8) as usize;
            format!("{x:.digits$}")
        }
        _ => "-".into(),
    }
}

/// `value +- se` (or `value` alone when the SE is absent).
fn with_se(m: &Value, e: &Value) -> String {
    match e.as_f64() {
        Some(_) => format!("{} +- {}", num(m), num(e)),
        None => num(m),
    }
}

/// The claim as published: `target +- margin`, `> threshold`, `< threshold`.
fn claim(row: &Value) -> String {
    match row["test"].as_str().unwrap_or("") {
        "above" => format!("> {}", num(&row["tolerance"])),
        "below" => format!("< {}", num(&row["tolerance"])),
        // a claim without one published number (its note states it)
        _ if row["published"].is_null() => "as stated below".into(),
        _ => format!("{} +- {}", num(&row["published"]), num(&row["tolerance"])),
    }
}

/// The verdict over the seed sets where there is one, else base seed 1's.
fn final_verdict(row: &Value) -> &str {
    row["seed_sets"]["verdict"]
        .as_str()
        .or(row["verdict"].as_str())
        .unwrap_or("undecided")
}

/// What would decide an undecided claim: the runs (or seed sets) at which
/// the SE, shrinking as 1/sqrt(n), puts the value K_LARGE_N SE clear of
/// its margin, if the value stays where it is.
fn what_decides(row: &Value) -> Option<String> {
    let over = row["seed_sets"].is_object();
    let (m, se, n) = if over {
        let s = &row["seed_sets"];
        (
            s["measured"].as_f64()?,
            s["error"].as_f64()?,
            s["seeds"].as_f64()?,
        )
    } else {
        (
            row["measured"].as_f64()?,
            row["error"].as_f64()?,
            row["runs"].as_f64()?,
        )
    };
    let t = row["tolerance"].as_f64()?;
    let gap = match row["test"].as_str().unwrap_or("") {
        "above" | "below" => (m - t).abs(),
        _ => ((m - row["published"].as_f64()?).abs() - t).abs(),
    };
    if gap == 0.0 || se <= 0.0 {
        return Some("the value sits on its margin: no run count decides it".into());
    }
    let need = (n * (K_LARGE_N * se / gap).powi(2)).ceil();
    Some(if over {
        format!(
            "about {need} seed sets (now {n}) if the mean stays at {}",
            num(&row["seed_sets"]["measured"])
        )
    } else {
        format!(
            "about {need} runs (now {n}) if the value stays at {}",
            num(&row["measured"])
        )
    })
}

/// The text of EXPERIMENTS.md from report.json `report` and the per-claim
/// `notes` ([`read_notes`]).
pub fn render(report: &Value, notes: &Notes) -> String {
    let rows: Vec<&Value> = report["rows"]
        .as_array()
        .map(|r| r.iter().collect())
        .unwrap_or_default();
    let default_claim = |r: &&Value| {
        (r["kind"] == "published" || (r["kind"] == "unstated" && !r["published"].is_null()))
            && r["reading"].is_null()
    };
    let claims: Vec<&Value> = rows.iter().copied().filter(default_claim).collect();
    let count = |v: &str| claims.iter().filter(|r| final_verdict(r) == v).count();
    let stamp = &report["stamp"];
    let mut s = String::new();
    let _ = writeln!(s, "# Experiments: the current record\n");
    let _ = writeln!(
        s,
        "Generated by `report --experiments EXPERIMENTS.md` from [docs/report/report.json](docs/report/report.json) \
         (commit {}, tier {}) and [{NOTES}]({NOTES}); do not edit by hand. How each result was obtained, \
         with its dated measurements, is in the [notebook](docs/notebook/README.md).\n",
        stamp["commit"].as_str().unwrap_or("unknown"),
        report["tier"].as_str().unwrap_or("?"),
    );
    let _ = writeln!(
        s,
        "{} published claims of the default reading: **{} reproduced, {} not reproduced, {} undecided** \
         (the verdict over the committed seed sets where a figure has them, else base seed 1's; \
         the grading rule: [docs/reference/grading.md](docs/reference/grading.md)).\n",
        claims.len(),
        count("reproduced"),
        count("not-reproduced"),
        count("undecided")
    );
    let cpu: f64 = report["figures"]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(|f| f["cpu_seconds"].as_f64())
        .sum();
    let _ = writeln!(
        s,
        "Recompute all of it (the runs recorded here took {:.1} CPU-hours; on 2 cores about half that in wall time):\n",
        cpu / 3600.0
    );
    let _ = writeln!(
        s,
        "```sh\n{}\n```\n",
        stamp["regenerate"].as_str().unwrap_or("?")
    );
    let figures: BTreeMap<&str, &Value> = report["figures"]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(|f| Some((f["run"]["binary"].as_str()?, f)))
        .collect();
    for b in ORDER {
        let Some(f) = figures.get(b) else { continue };
        let mine: Vec<&Value> = claims
            .iter()
            .copied()
            .filter(|r| r["binary"] == b)
            .collect();
        let paper = f["paper"].as_str().unwrap_or(b);
        let _ = writeln!(s, "## {paper}\n");
        let runs = mine.iter().filter_map(|r| r["runs"].as_u64()).max();
        let _ = writeln!(
            s,
            "`report --tier acceptance --only {b} --seed-sets docs/acceptance` (base seed 1{}; \
             {:.0} s wall, {:.0} CPU-s on 2 cores). Figure and files: [docs/report/{b}/](docs/report/{b}/).\n",
            runs.map_or(String::new(), |n| format!(", up to {n} runs per claim")),
            f["summary_wall_seconds"].as_f64().unwrap_or(f64::NAN),
            f["cpu_seconds"].as_f64().unwrap_or(f64::NAN),
        );
        if mine.is_empty() {
            let _ = writeln!(s, "No published claim of the default reading.\n");
            continue;
        }
        let _ = writeln!(
            s,
            "| claim | published | seed 1 (runs) | over the seed sets | verdict |\n|---|---|---|---|---|"
        );
        for r in &mine {
            let sets = &r["seed_sets"];
            let over = if sets.is_object() {
                format!(
                    "{} ({} sets)",
                    with_se(&sets["measured"], &sets["error"]),
                    sets["seeds"]
                )
            } else {
                "-".into()
            };
            let _ = writeln!(
                s,
                "| {} | {} | {} ({}) | {} | {} |",
                r["name"].as_str().unwrap_or("?"),
                claim(r),
                with_se(&r["measured"], &r["error"]),
                r["runs"].as_u64().map_or("?".into(), |n| n.to_string()),
                over,
                final_verdict(r).replace('-', " ")
            );
        }
        let _ = writeln!(s);
        for r in &mine {
            let name = r["name"].as_str().unwrap_or("?");
            let _ = writeln!(
                s,
                "- `{name}` ({}): {}",
                r["source"].as_str().unwrap_or("?"),
                r["note"].as_str().unwrap_or("").trim()
            );
            if let Some(n) = notes.get(&(b.to_string(), name.to_string())) {
                let _ = writeln!(s, "  {n}");
            }
            if final_verdict(r) == "undecided" {
                if let Some(w) = what_decides(r) {
                    let _ = writeln!(s, "  Undecided; what would decide it: {w}.");
                }
            }
        }
        let _ = writeln!(s);
    }
    let _ = writeln!(s, "## Known discrepancies\n");
    let _ = writeln!(
        s,
        "The published claims of the default reading not reproduced; each is also a check with \
         `pass: false` in its figure's summary.json, so a change to it is noticed.\n"
    );
    let mut off: Vec<&Value> = claims
        .iter()
        .copied()
        .filter(|r| final_verdict(r) == "not-reproduced")
        .collect();
    // paper order, then the figure's own order of checks (a stable sort)
    off.sort_by_key(|r| ORDER.iter().position(|b| r["binary"] == *b));
    for r in off {
        let b = r["binary"].as_str().unwrap_or("?");
        let paper = figures
            .get(b)
            .and_then(|f| f["paper"].as_str())
            .unwrap_or(b);
        let name = r["name"].as_str().unwrap_or("?");
        let sets = &r["seed_sets"];
        let value = if sets.is_object() {
            with_se(&sets["measured"], &sets["error"])
        } else {
            with_se(&r["measured"], &r["error"])
        };
        let _ = write!(
            s,
            "- {paper}, `{name}`: published {}, measured {value}",
            claim(r)
        );
        match notes.get(&(b.to_string(), name.to_string())) {
            Some(n) => {
                let _ = writeln!(s, ". {n}");
            }
            None => {
                let _ = writeln!(s, ".");
            }
        }
    }
    s
}
