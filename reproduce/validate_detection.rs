//! `validate-detection`: the detection table and plots of VALIDATION.md
//! ("The smallest detectable error") from the `--repeat`
//! CSVs of the parametric mutants in a folder (default
//! `docs/validate-detection`): prints the table as Markdown, writes
//! `detection.csv` and one PNG per (tier, level) into the folder.
//!
//! `cargo run --release --bin validate-detection -- docs/validate-detection`

use granular_automata::plot::{line_chart, register_fonts, Line, PALETTE};
use granular_automata::validate::detect::{check_row, defect_table, Row};
use plotters::prelude::{RGBColor, SeriesLabelPosition};
use std::collections::BTreeSet;
use std::path::PathBuf;

granular_automata::main_of!(body);

fn body() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let dir = match &args[..] {
        [] => PathBuf::from("docs/validate-detection"),
        [h] if h == "--help" || h == "-h" => {
            println!("usage: validate-detection [DIR] (default docs/validate-detection): the detection table from the --repeat CSVs of the parametric mutants in DIR");
            return Ok(());
        }
        [d] if !d.starts_with('-') => PathBuf::from(d),
        _ => {
            return Err(granular_automata::Error::new(
                granular_automata::ErrorKind::InvalidParameter,
                format!("usage: validate-detection [DIR]; got {args:?}"),
            )
            .into())
        }
    };
    let mut rows = Vec::new();
    let entries = std::fs::read_dir(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    for entry in entries {
        let path = entry?.path();
        if path.extension().is_some_and(|x| x == "csv") {
            match check_row(&std::fs::read_to_string(&path)?) {
                Ok(Some(r)) => rows.push(r),
                Ok(None) => {}
                Err(why) => return Err(format!("{}: {why}", path.display()).into()),
            }
        }
    }
    let defects: Vec<Row> = rows
        .iter()
        .filter(|r| r.class() != "rule")
        .cloned()
        .collect();
    rows.retain(|r| r.class() == "rule");
    if rows.is_empty() {
        return Err(format!("no --repeat CSV of a mutant:KNOB*F in {}", dir.display()).into());
    }
    let e = |r: &Row| 100.0 * (r.factor - 1.0);
    rows.sort_by(|a, b| {
        (a.tier.as_str(), a.level, a.knob.as_str())
            .cmp(&(b.tier.as_str(), b.level, b.knob.as_str()))
            .then(e(a).abs().total_cmp(&e(b).abs()))
            .then(e(a).total_cmp(&e(b)))
    });
    let mut csv = String::from("tier,level,knob,e_percent,failed,validations\n");
    for r in &rows {
        let cells = [r.tier.clone(), r.level.to_string(), r.knob.clone()];
        let counts = [e(r).to_string(), r.failed.to_string(), r.total.to_string()];
        csv.push_str(&(cells.join(",") + "," + &counts.join(",") + "\n"));
    }
    std::fs::write(dir.join("detection.csv"), csv)?;
    register_fonts();
    let groups: BTreeSet<(String, u8)> = rows.iter().map(|r| (r.tier.clone(), r.level)).collect();
    for (tier, level) in groups {
        let mine: Vec<&Row> = rows
            .iter()
            .filter(|r| r.tier == tier && r.level == level)
            .collect();
        let knobs: BTreeSet<&str> = mine.iter().map(|r| r.knob.as_str()).collect();
        let lines: Vec<Line> = knobs
            .iter()
            .enumerate()
            .map(|(k, knob)| {
                let pts = mine
                    .iter()
                    .filter(|r| r.knob == *knob && r.factor > 1.0)
                    .map(|r| (e(r), r.failed as f64 / r.total as f64))
                    .collect();
                // the palette's six colours, then grey: every knob its own
                let grey = RGBColor(120, 120, 120);
                Line::new(knob, pts, *PALETTE.get(k).unwrap_or(&grey))
            })
            .collect();
        let title = format!("validate level {level}, {tier} tier: detection rate (20 validations)");
        let path = dir.join(format!("detection-{tier}-level{level}.png"));
        let (x, y) = (
            "rule probability too high by e (%)",
            "share of validations that fail",
        );
        line_chart(
            &path,
            &title,
            x,
            y,
            &lines,
            false,
            SeriesLabelPosition::LowerRight,
        )?;
        println!("\n{tier} tier, level {level} ({})\n", path.display());
        let es: BTreeSet<i64> = mine.iter().map(|r| (e(r) * 10.0).round() as i64).collect();
        let head: Vec<String> = es
            .iter()
            .map(|v| format!("{:+} %", *v as f64 / 10.0))
            .collect();
        println!("| knob | {} |", head.join(" | "));
        println!("|---|{}", "---|".repeat(es.len()));
        for knob in &knobs {
            let cells: Vec<String> = es
                .iter()
                .map(|v| {
                    mine.iter()
                        .find(|r| r.knob == *knob && (e(r) * 10.0).round() as i64 == *v)
                        .map_or(String::new(), |r| format!("{} / {}", r.failed, r.total))
                })
                .collect();
            println!("| `{knob}` | {} |", cells.join(" | "));
        }
    }
    if !defects.is_empty() {
        println!(
            "\ndefects of decomposition and time\n\n{}",
            defect_table(&defects)
        );
    }
    Ok(())
}
