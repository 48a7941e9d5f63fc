//! The committed reference report (`docs/report/`, written by
//! `report --tier acceptance --engine fast --publish docs/report`) stays
//! honest: every row's verdict is that of its figure's summary.json, it
//! covers every figure binary, its stamp names a commit of this history,
//! and README's headline table is the report's.

mod common;

use granular_automata::report::{default_figures, PUBLISH_WIDTH};
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/report")
}

/// Whether the committed report is here: in a checkout of the repository
/// it must be; the published crate leaves it out, and every test here
/// skips.
fn in_repository() -> bool {
    common::in_repository("docs/report").is_some()
}

fn json(path: &Path) -> Value {
    let text = std::fs::read_to_string(path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn report() -> Value {
    json(&dir().join("report.json"))
}

#[test]
fn every_row_is_its_summary() {
    if !in_repository() {
        return;
    }
    let r = report();
    let rows = r["rows"].as_array().expect("rows");
    assert!(!rows.is_empty());
    let mut summaries: BTreeMap<String, Value> = BTreeMap::new();
    for row in rows {
        let b = row["binary"].as_str().unwrap().to_string();
        let s = summaries
            .entry(b.clone())
            .or_insert_with(|| json(&dir().join(&b).join("summary.json")));
        let name = row["name"].as_str().unwrap();
        let c = s["checks"]
            .as_array()
            .unwrap()
            .iter()
            .find(|c| c["name"] == name)
            .unwrap_or_else(|| panic!("{b}: no check {name} in its summary.json"));
        assert_eq!(row["verdict"], c["verdict"], "{b} {name}: verdict");
        assert_eq!(row["kind"], c["kind"], "{b} {name}: kind");
        assert_eq!(row["measured"], c["measured"], "{b} {name}: measured");
    }
    // and every check of every summary is a row
    for (b, s) in &summaries {
        let n = s["checks"].as_array().unwrap().len();
        let m = rows.iter().filter(|x| x["binary"] == b.as_str()).count();
        assert_eq!(n, m, "{b}: {n} checks in summary.json, {m} rows");
    }
}

#[test]
fn covers_every_figure_binary_at_the_published_set_ups() {
    if !in_repository() {
        return;
    }
    let r = report();
    assert_eq!(r["tier"], "acceptance");
    let figures: Vec<&str> = r["figures"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["run"]["binary"].as_str().unwrap())
        .collect();
    for b in default_figures() {
        assert!(figures.contains(&b), "the committed report lacks {b}");
        assert!(
            dir().join(b).join("summary.json").is_file(),
            "docs/report/{b}/summary.json is missing"
        );
    }
    for f in r["figures"].as_array().unwrap() {
        let b = f["run"]["binary"].as_str().unwrap();
        assert_eq!(f["run"]["ok"], true, "{b} failed in the committed report");
        assert_eq!(f["tier"], "acceptance", "{b}: tier of its summary");
        for p in f["pngs"].as_array().unwrap() {
            assert!(dir().join(b).join(p.as_str().unwrap()).is_file(), "{b}/{p}");
        }
    }
}

#[test]
fn stamp_is_a_commit_of_this_history() {
    if !in_repository() {
        return;
    }
    let r = report();
    let commit = r["stamp"]["commit"].as_str().unwrap();
    assert!(
        commit.len() == 40 && commit.chars().all(|c| c.is_ascii_hexdigit()),
        "the stamp's commit {commit:?} is not a clean commit (a report from a modified tree cannot be regenerated)"
    );
    let ok = Command::new("git")
        .args(["-C", env!("CARGO_MANIFEST_DIR")])
        .args(["merge-base", "--is-ancestor", commit, "HEAD"])
        .status()
        .expect("git is needed to check the stamp");
    assert!(
        ok.success(),
        "stamp commit {commit} is not an ancestor of HEAD"
    );
    let regen = r["stamp"]["regenerate"].as_str().unwrap();
    for page in ["REPORT.md", "index.html"] {
        let text = std::fs::read_to_string(dir().join(page)).unwrap();
        // the top: everything above the overview
        let top = &text[..text.find("Overview").expect("an overview")];
        assert!(top.contains(commit), "{page}: stamp not at the top");
        assert!(
            top.contains(&regen.replace('&', "&amp;")) || top.contains(regen),
            "{page}: regenerate command not at the top"
        );
    }
}

#[test]
fn stays_a_few_megabytes() {
    if !in_repository() {
        return;
    }
    fn size(p: &Path) -> u64 {
        if p.is_dir() {
            std::fs::read_dir(p)
                .unwrap()
                .map(|e| size(&e.unwrap().path()))
                .sum()
        } else {
            p.metadata().unwrap().len()
        }
    }
    let bytes = size(&dir());
    assert!(bytes < 8_000_000, "docs/report weighs {bytes} bytes");
    // pictures are reduced
    for f in report()["figures"].as_array().unwrap() {
        let b = f["run"]["binary"].as_str().unwrap();
        for p in f["pngs"].as_array().unwrap() {
            let path = dir().join(b).join(p.as_str().unwrap());
            let img = image::open(&path).unwrap();
            assert!(img.width() <= PUBLISH_WIDTH, "{}", path.display());
        }
    }
}

/// README's headline table (per paper: reproduced / not / undecided) is
/// the committed report's.
#[test]
fn readme_headline_is_the_report() {
    if !in_repository() {
        return;
    }
    let r = report();
    let mut per_paper: Vec<(String, [usize; 3])> = vec![];
    let mut seed1 = [0; 3];
    // reproduced, not reproduced, undecided
    let column = |v: Option<&str>| match v.unwrap() {
        "reproduced" => 0,
        "not-reproduced" => 1,
        _ => 2,
    };
    for row in r["rows"].as_array().unwrap() {
        let published = row["kind"] == "published"
            || (row["kind"] == "unstated" && !row["published"].is_null());
        if !published || !row["reading"].is_null() {
            continue;
        }
        let paper = row["paper"].as_str().unwrap().to_string();
        seed1[column(row["verdict"].as_str())] += 1;
        // the verdict over the committed seed sets where there is one
        let verdict = row["seed_sets"]["verdict"]
            .as_str()
            .or(row["verdict"].as_str());
        let i = column(verdict);
        match per_paper.iter_mut().find(|(p, _)| *p == paper) {
            Some((_, t)) => t[i] += 1,
            None => {
                let mut t = [0; 3];
                t[i] = 1;
                per_paper.push((paper, t));
            }
        }
    }
    let readme =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("README.md")).unwrap();
    let first: String = readme.lines().take(60).collect::<Vec<_>>().join("\n");
    assert!(
        first.contains("docs/report/index.html") || first.contains("docs/report/REPORT.md"),
        "README's first screen does not link the committed report"
    );
    let table = first
        .split("<!-- paper-table -->")
        .nth(1)
        .and_then(|t| t.split("<!-- /paper-table -->").next())
        .expect("README's first screen has the per-paper table between its markers");
    let mut all = [0; 3];
    for (p, t) in per_paper {
        let line = format!("| {p} | {} | {} | {} |", t[0], t[1], t[2]);
        assert!(
            table.contains(&line),
            "README's headline lacks `{line}` (from docs/report/report.json)"
        );
        (0..3).for_each(|i| all[i] += t[i]);
    }
    let line = format!("| all | {} | {} | {} |", all[0], all[1], all[2]);
    assert!(table.contains(&line), "README's table lacks `{line}`");
    let alone = format!(
        "By base seed 1 alone the counts are {}, {} and {}.",
        seed1[0], seed1[1], seed1[2]
    );
    assert!(
        readme.contains(&alone),
        "README lacks `{alone}` (from docs/report/report.json)"
    );
}

/// README stays short, and says how to validate one's own engine early.
#[test]
fn readme_is_short_and_validating_an_engine_comes_early() {
    if !in_repository() {
        return;
    }
    let readme =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("README.md")).unwrap();
    assert!(
        readme.lines().count() <= 150,
        "README has {} lines",
        readme.lines().count()
    );
    let first: String = readme.lines().take(40).collect::<Vec<_>>().join("\n");
    assert!(
        first.contains("--bin validate") && first.contains("--candidate"),
        "README's first 40 lines lack the command that validates your own engine"
    );
}

/// EXPERIMENTS.md is generated: rendered again from the committed
/// report.json and per-claim notes, it is the same text.
#[test]
fn experiments_md_regenerates_from_committed_files() {
    if !in_repository() {
        return;
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let notes = granular_automata::experiments::read_notes_file(
        &root.join(granular_automata::experiments::NOTES),
    )
    .unwrap();
    let text = granular_automata::experiments::render(&report(), &notes);
    let committed = std::fs::read_to_string(root.join("EXPERIMENTS.md")).unwrap();
    assert!(
        text == committed,
        "EXPERIMENTS.md differs from what `report --experiments` writes from docs/report/report.json and {}: regenerate it (README)",
        granular_automata::experiments::NOTES
    );
}

/// A run below the published set-up ends with the committed verdicts at
/// the published set-up: PH94 Fig. 2's alpha, not reproduced over its seed
/// sets, whatever the quick tier's own few runs say.
#[test]
fn a_quick_run_says_what_the_published_set_up_decided() {
    if !in_repository() {
        return;
    }
    let line = granular_automata::run::at_published_set_up("fig2").unwrap();
    assert!(
        line.contains("alpha 1.2634 +- 0.0026 (20 seed sets), not reproduced"),
        "{line}"
    );
    assert!(
        line.contains("--only fig2") && line.contains("smoke test"),
        "{line}"
    );
    assert!(granular_automata::run::at_published_set_up("no-such-figure").is_none());
}

/// The committed report is a page to look at: its headline is a picture,
/// one bar per paper, under it one sentence of at most 25 words, and every
/// figure has a card whose claims are drawn over their measurements.
#[test]
fn the_report_page_shows_its_headline_and_a_card_per_figure() {
    if !in_repository() {
        return;
    }
    let html = std::fs::read_to_string(dir().join("index.html")).unwrap();
    let glance = html
        .split("<figure class=\"glance\">")
        .nth(1)
        .expect("a headline picture");
    let (svg, rest) = glance.split_once("</svg>").unwrap();
    for paper in ["PH94", "PH95", "BB90"] {
        assert!(
            svg.contains(&format!(">{paper}</text>")),
            "a bar for {paper}"
        );
    }
    let caption = rest
        .split("<figcaption>")
        .nth(1)
        .and_then(|c| c.split("</figcaption>").next())
        .unwrap();
    assert!(caption.split_whitespace().count() <= 25, "{caption}");
    let figures = report()["figures"].as_array().unwrap().len();
    assert_eq!(html.matches("<section class=\"fcard\"").count(), figures);
    assert!(
        html.matches("aria-label=\"published").count() >= 100,
        "claims drawn"
    );
    assert!(dir().join("headline.svg").is_file());
    let md = std::fs::read_to_string(dir().join("REPORT.md")).unwrap();
    assert!(md.contains("](headline.svg)"));
}

/// Every figure PNG of the committed report states what the paper publishes
/// about it: the strip `run::PUBLISHED` writes under the picture (light
/// grey at its left edge, where no text reaches), and every figure of the
/// report has such a statement.
#[test]
fn every_figure_png_shows_the_published_values() {
    if !in_repository() {
        return;
    }
    use granular_automata::run::PUBLISHED;
    for f in report()["figures"].as_array().unwrap() {
        let b = f["run"]["binary"].as_str().unwrap();
        assert!(
            PUBLISHED.iter().any(|(fig, _)| *fig == b),
            "{b}: no published statement"
        );
        for p in f["pngs"].as_array().unwrap() {
            let path = dir().join(b).join(p.as_str().unwrap());
            let img = image::open(&path).unwrap().to_rgb8();
            let px = img.get_pixel(1, img.height() - 3);
            assert!(
                px.0.iter().all(|&c| (236..=250).contains(&c)),
                "{}: no published strip at the bottom (pixel {:?})",
                path.display(),
                px.0
            );
        }
    }
}
