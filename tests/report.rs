//! Acceptance tests of the `report` binary on the two cheapest
//! figures (the hopper's, a few seconds each at the quick tier on one thread).

mod common;

use granular_automata::drivers::acceptance_study::seal;
use granular_automata::report::without_timing;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const EXE: &str = env!("CARGO_BIN_EXE_report");

/// A fresh output folder of the test target directory.
fn fresh(tag: &str) -> PathBuf {
    common::fresh_dir(&format!("report-{tag}"))
}

fn report(out: &Path, args: &[&str]) -> Output {
    Command::new(EXE)
        .args(["--tier", "quick", "--threads", "1", "--out"])
        .arg(out)
        .args(args)
        .output()
        .expect("report runs")
}

fn read(path: PathBuf) -> String {
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The rows of the Markdown checks tables of section `heading`: (binary,
/// check name, verdict).
fn md_rows(md: &str, heading: &str) -> Vec<(String, String, String)> {
    let Some(table) = md.split(heading).nth(1) else {
        return vec![];
    };
    let table = table.split("\n## ").next().unwrap();
    let mut lines = table.lines().filter(|l| l.starts_with('|'));
    let header: Vec<String> = lines
        .next()
        .expect("header")
        .split('|')
        .map(|c| c.trim().to_string())
        .collect();
    let col = |name: &str| header.iter().position(|h| h == name).expect(name);
    let (fig, check, verdict) = (col("figure"), col("check: claim"), col("verdict"));
    lines
        .skip(1)
        .take_while(|l| !l.starts_with("| figure |"))
        .map(|l| {
            let cells: Vec<&str> = l.split('|').map(str::trim).collect();
            let tick = |s: &str| s.split('`').nth(1).expect("`name`").to_string();
            (
                tick(cells[fig]),
                tick(cells[check]),
                cells[verdict].to_string(),
            )
        })
        .collect()
}

#[test]
fn report_of_two_figures_agrees_with_their_summaries_and_is_reproducible() {
    let out = fresh("two");
    let only = ["--only", "hopper-fig3,hopper-fig2"];
    let first = report(&out, &only);
    assert!(
        first.status.success(),
        "{}",
        String::from_utf8_lossy(&first.stderr)
    );
    let md = read(out.join("report/REPORT.md"));
    let html = read(out.join("report/index.html"));
    assert!(html.starts_with("<!DOCTYPE html>") && !html.contains("<script"));
    assert!(
        !html.contains("http://") && !html.contains("https://"),
        "offline page"
    );
    assert!(
        html.contains("src=\"../hopper-fig2/hopper-fig2-gr.png\""),
        "thumbnail"
    );

    // the default reading's checks, then those of other readings
    let own = md_rows(&md, "\n## Checks\n");
    let other = md_rows(&md, "\n## Checks of other readings");
    assert!(!other.is_empty(), "hopper comparisons listed apart");
    for (_, name, _) in &other {
        assert!(
            !name.starts_with("beta0_") && !name.starts_with("beta1_bond_"),
            "{name}: a default case's check among the other readings"
        );
    }
    for (_, name, _) in &own {
        assert!(
            !name.starts_with("beta1_same_") && !name.starts_with("beta1_along_"),
            "{name}: another reading's check among the default's"
        );
    }
    let mut rows = own.clone();
    rows.extend(other.iter().cloned());
    rows.sort();
    let mut expected = vec![];
    for bin in ["hopper-fig2", "hopper-fig3"] {
        let s: serde_json::Value =
            serde_json::from_str(&read(out.join(bin).join("summary.json"))).unwrap();
        for c in s["checks"].as_array().unwrap() {
            let verdict = match c["verdict"].as_str() {
                Some(v) => v.to_string(),
                None if c["pass"].as_bool().unwrap() => "reproduced".into(),
                None => "not-reproduced".into(),
            };
            expected.push((
                bin.to_string(),
                c["name"].as_str().unwrap().to_string(),
                verdict,
            ));
        }
    }
    assert!(!expected.is_empty());
    expected.sort();
    assert_eq!(
        rows, expected,
        "one row per check, verdict as in summary.json"
    );
    for (_, name, verdict) in &expected {
        assert!(
            html.contains(&format!("<code>{name}</code>")) && html.contains(verdict.as_str()),
            "{name} in the HTML"
        );
    }

    // the same command again: only timing lines differ
    let second = report(&out, &only);
    assert!(second.status.success());
    let md2 = read(out.join("report/REPORT.md"));
    let html2 = read(out.join("report/index.html"));
    assert_eq!(without_timing(&md), without_timing(&md2));
    assert_eq!(without_timing(&html), without_timing(&html2));
}

#[test]
fn a_failing_figure_is_listed_and_does_not_stop_the_others() {
    let out = fresh("failing");
    // hopper-fig2 gets an option it does not know: clap exits with status 2
    let r = report(
        &out,
        &[
            "--only",
            "hopper-fig2,hopper-fig3",
            "--args-for",
            "hopper-fig2=--no-such-option",
        ],
    );
    assert!(!r.status.success(), "a failed figure fails the report");
    let md = read(out.join("report/REPORT.md"));
    let failed = md
        .split("## Failed figures")
        .nth(1)
        .expect("failed section");
    assert!(failed.contains("**hopper-fig2**: exit status 2"), "{md}");
    assert!(failed.contains("--no-such-option"), "stderr tail shown");
    assert!(md.contains("`hopper-fig3`: ") || md.contains("(`hopper-fig3`)"));
    let rows = md_rows(&md, "\n## Checks\n");
    assert!(rows.iter().all(|(b, _, _)| b == "hopper-fig3"));
    assert!(
        !rows.is_empty(),
        "the figure after the failed one still ran"
    );
    let html = read(out.join("report/index.html"));
    assert!(html.contains("Failed figures") && html.contains("hopper-fig2"));
}

#[test]
fn unknown_figures_are_a_typed_error_up_front() {
    let out = fresh("unknown");
    let r = report(&out, &["--only", "hopper-fig2,fig99"]);
    assert_eq!(r.status.code(), Some(2));
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(
        err.contains("fig99") && err.contains("hopper-fig2"),
        "{err}"
    );
    assert!(!out.join("hopper-fig2").exists(), "nothing ran");
}

#[test]
fn an_unknown_engine_is_a_typed_error_up_front() {
    let out = fresh("engine");
    let r = report(&out, &["--only", "hopper-fig2", "--engine", "gpu"]);
    assert_eq!(r.status.code(), Some(2));
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(err.contains("gpu") && err.contains("fast"), "{err}");
    assert!(!out.join("hopper-fig2").exists(), "nothing ran");
}

/// A fig2 summary of the acceptance tier with base seed `seed`: alpha as
/// given and, when `with_v`, v_peak.
fn fig2_summary(alpha: f64, se: f64, verdict: &str, seed: u32, with_v: bool) -> String {
    let mut checks = vec![serde_json::json!({"name": "alpha", "kind": "published",
        "verdict": verdict, "measured": alpha, "error": se, "runs": 128, "published": 1.33,
        "tolerance": 0.059, "claim": {"test": "within", "target": 1.33, "margin": 0.059}})];
    if with_v {
        checks.push(serde_json::json!({"name": "v_peak", "kind": "published",
            "verdict": "reproduced", "measured": 0.395, "error": 0.0007, "runs": 128,
            "published": 0.40, "tolerance": 0.007, "claim": {"test": "within", "target": 0.40, "margin": 0.007}}));
    }
    serde_json::json!({"figure": "fig2", "paper": "PH94 Fig. 2", "tier": "acceptance",
        "rules": "r", "wall_seconds": 12.5, "seeds": [seed, seed + 100], "checks": checks})
    .to_string()
}

/// `report --tier acceptance --only fig2 --no-run --out OUT EXTRA...`.
fn fig2_no_run(out: &Path, extra: &[&str]) -> Output {
    let args = [
        "--tier",
        "acceptance",
        "--only",
        "fig2",
        "--no-run",
        "--out",
    ];
    let o = Command::new(EXE).args(args).arg(out).args(extra).output();
    o.expect("report runs")
}

/// `--no-run` re-renders from the summaries in `--out` without running a
/// figure, and `--seed-sets` grades the published checks over every
/// committed seed set of a figure that has at least 20: here a
/// fig2 alpha undecided in its own seed set and decided over 20. The seed
/// sets are graded only when the run's own seed set equals its committed
/// twin (same seeds) result for result: a run that differs from it, or whose
/// seeds none has, is not graded over them, and says why.
#[test]
fn no_run_re_renders_and_seed_sets_grade_over_all_seeds() {
    let out = fresh("no-run");
    let sets = fresh("seed-sets");
    let summary = |alpha: f64, se: f64, verdict: &str, seed: u32| {
        fig2_summary(alpha, se, verdict, seed, true)
    };
    let alpha = |s: u32| 1.2634 + 0.0116 * ((s as f64) - 10.5) / 5.9;
    // this run is seed set 1
    std::fs::create_dir_all(out.join("fig2")).unwrap();
    let this_run = |alpha: f64, seed: u32| {
        std::fs::write(
            out.join("fig2/summary.json"),
            summary(alpha, 0.014, "undecided", seed),
        )
        .unwrap()
    };
    this_run(alpha(1), 1);
    // 19 seed sets first: too few to grade over
    let seed = |s: u32| {
        let d = sets.join(format!("fig2/seed-{s}/fig2"));
        std::fs::create_dir_all(&d).unwrap();
        std::fs::write(
            d.join("summary.json"),
            summary(alpha(s), 0.014, "undecided", s),
        )
        .unwrap();
    };
    (1..=19).for_each(seed);
    let sealed = || seal(&sets.join("fig2"), "fig2", &[]).unwrap();
    sealed();
    let no_run = |extra: &[&str]| fig2_no_run(&out, extra);
    let run = |extra: &[&str]| {
        let o = no_run(extra);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        read(out.join("report/REPORT.md"))
    };
    let sets_arg = sets.display().to_string();
    let md = run(&["--seed-sets", &sets_arg]);
    assert!(md.contains("Re-rendered with --no-run"), "{md}");
    assert!(md.contains("| 12.5 s"), "the summary's wall time: {md}");
    assert!(!md.contains("Over every committed seed set"), "{md}");
    assert!(
        md.contains("1 of 2 published claims") && !md.contains("with those verdicts"),
        "{md}"
    );
    // the regenerate command runs the figures
    assert!(!md.contains("Regenerate: `cargo build --release --bins && target/release/report --tier acceptance --only fig2 --no-run"), "{md}");
    seed(20);
    sealed();
    let md = run(&["--seed-sets", &sets_arg]);
    assert!(md.contains("## Over every committed seed set (2)"), "{md}");
    assert!(
        md.contains("| PH94 Fig. 2 (`fig2`) | `alpha` | undecided | 20 |"),
        "{md}"
    );
    assert!(md.contains("| **not-reproduced** |"), "{md}");
    assert!(
        md.contains("with those verdicts 1 reproduced, 1 not reproduced, 0 undecided: 2 of 2 decided (100.0 %)"),
        "{md}"
    );
    assert!(
        md.contains("over 20 committed seed sets: not-reproduced"),
        "{md}"
    );
    assert!(
        md.contains("this run's own seed set equals its committed twin")
            && md.contains("fig2 (seed-1 of 20)"),
        "{md}"
    );
    let o = no_run(&["--seed-sets", &sets_arg]);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("[NOT-REPRODUCED] fig2 alpha over 20 seed sets: 1.2634 +- 0.0026 (this run: undecided 1.2447 +- 0.0140, 128 runs)"),
        "{stdout}"
    );
    // seed set 1's runs with another alpha: the code computes otherwise, so
    // the committed seed sets are not graded
    this_run(alpha(1) + 1e-12, 1);
    let md = run(&["--seed-sets", &sets_arg]);
    assert!(!md.contains("Over every committed seed set"), "{md}");
    assert!(
        md.contains("fig2: NOT graded over its 20 committed seed sets")
            && md.contains("check alpha: measured"),
        "{md}"
    );
    // seeds that no committed seed set has: not graded either
    this_run(alpha(1), 21);
    let md = run(&["--seed-sets", &sets_arg]);
    assert!(!md.contains("Over every committed seed set"), "{md}");
    assert!(md.contains("none has this run's seeds"), "{md}");
    this_run(alpha(1), 1);
    // an unreadable committed summary: not graded, and the page says why
    let broken = sets.join("fig2/seed-21/fig2");
    std::fs::create_dir_all(&broken).unwrap();
    std::fs::write(broken.join("summary.json"), "{broken").unwrap();
    let md = run(&["--seed-sets", &sets_arg]);
    assert!(!md.contains("Over every committed seed set"), "{md}");
    assert!(md.contains("fig2: not graded over its seed sets: "), "{md}");
    std::fs::remove_dir_all(sets.join("fig2/seed-21")).unwrap();
    // without --seed-sets the rows are this run's
    assert!(!run(&[]).contains("Over every committed seed set"));
    // a --seed-sets folder that does not exist is an error naming it
    let o = no_run(&["--seed-sets", "/no/such/folder"]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("--seed-sets /no/such/folder"));
    // --no-run without a summary: the figure is reported as failed
    std::fs::remove_file(out.join("fig2/summary.json")).unwrap();
    assert!(!no_run(&[]).status.success());
    assert!(read(out.join("report/REPORT.md")).contains("--no-run and no"));
}

/// A cut of a figure (`run-seeds.sh --as NAME -- ARGS`: fewer checks at the
/// same set-up and seeds, `NAME/cut.txt` naming the figure) grades its
/// checks over its seed sets where the whole figure has fewer than 20: here
/// the whole fig2 has 1 seed set and a cut with alpha alone has 20, so alpha
/// is graded over the cut and v_peak is not. A cut whose seed set 1 differs
/// from this run is not graded, and says why.
#[test]
fn a_cut_grades_its_checks_over_its_seed_sets() {
    let out = fresh("cut-run");
    let sets = fresh("cut-sets");
    std::fs::create_dir_all(out.join("fig2")).unwrap();
    let alpha = |s: u32| 1.2634 + 0.0116 * ((s as f64) - 10.5) / 5.9;
    let mine = fig2_summary(alpha(1), 0.014, "undecided", 1, true);
    std::fs::write(out.join("fig2/summary.json"), mine).unwrap();
    let file = |folder: &str, s: u32, with_v: bool| {
        let d = sets.join(format!("{folder}/seed-{s}/fig2"));
        std::fs::create_dir_all(&d).unwrap();
        let text = fig2_summary(alpha(s), 0.014, "undecided", s, with_v);
        std::fs::write(d.join("summary.json"), text).unwrap();
    };
    file("fig2", 1, true);
    (1..=20).for_each(|s| file("fig2-alpha", s, false));
    seal(&sets.join("fig2"), "fig2", &[]).unwrap();
    seal(&sets.join("fig2-alpha"), "fig2", &[]).unwrap();
    let render = || {
        let o = fig2_no_run(&out, &["--seed-sets", &sets.display().to_string()]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        read(out.join("report/REPORT.md"))
    };
    // without cut.txt the folder is no cut of fig2
    assert!(!render().contains("Over every committed seed set"));
    std::fs::write(sets.join("fig2-alpha/cut.txt"), "fig2 --alpha-only\n").unwrap();
    let md = render();
    for want in [
        "## Over every committed seed set (1)",
        "| PH94 Fig. 2 (`fig2`) | `alpha` | undecided | 20 |",
        "fig2 (cut fig2-alpha, `--alpha-only`: seed-1 of 20)",
    ] {
        assert!(md.contains(want), "{want} in {md}");
    }
    // a cut of another figure is not this one's
    std::fs::write(sets.join("fig2-alpha/cut.txt"), "waves-fig6 --alpha-only").unwrap();
    assert!(!render().contains("Over every committed seed set"));
    // a cut whose seed set 1 has another alpha: not graded, and says why
    std::fs::write(sets.join("fig2-alpha/cut.txt"), "fig2 --alpha-only").unwrap();
    let d = sets.join("fig2-alpha/seed-1/fig2/summary.json");
    let other = fig2_summary(alpha(1) + 1e-12, 0.014, "undecided", 1, false);
    std::fs::write(d, other).unwrap();
    // refiled: its seal follows
    seal(&sets.join("fig2-alpha"), "fig2", &["seed-1".into()]).unwrap();
    let md = render();
    assert!(!md.contains("Over every committed seed set"), "{md}");
    assert!(
        md.contains("fig2: NOT graded over its 20 committed seed sets"),
        "{md}"
    );
}
