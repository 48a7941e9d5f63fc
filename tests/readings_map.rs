//! The map of claims by readings (`readings-map`) end to end without
//! running a figure: the committed report's pipe summaries (acceptance
//! tier, the default reading) stand in for one reading's runs, and
//! `--no-run` renders the map from them. Every published check of the 13
//! pipe figures becomes a row, the counts are the report's, and bad input
//! is refused naming the value.

mod common;

use std::path::PathBuf;
use std::process::Command;

#[test]
fn the_committed_reports_pipe_checks_render_as_one_column() {
    let Some(report) = common::in_repository("docs/report") else {
        return;
    };
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("readings-map");
    let _ = std::fs::remove_dir_all(&out);
    let mut published = 0;
    let figures = granular_automata::readings_map::figures();
    assert_eq!(figures.len(), 13);
    for f in figures {
        let dir = out.join("default").join(f);
        std::fs::create_dir_all(&dir).unwrap();
        let text = std::fs::read_to_string(report.join(f).join("summary.json")).unwrap();
        let s: serde_json::Value = serde_json::from_str(&text).unwrap();
        let checks = s["checks"].as_array().unwrap();
        published += checks.iter().filter(|c| c["kind"] == "published").count();
        std::fs::write(dir.join("summary.json"), text).unwrap();
    }
    let o = Command::new(env!("CARGO_BIN_EXE_readings-map"))
        .args([
            "--tier",
            "acceptance",
            "--readings",
            "default",
            "--no-run",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let dir = out.join("readings-map");
    for f in [
        "map.png",
        "matrix.csv",
        "matrix.md",
        "conflicts.md",
        "map.json",
    ] {
        assert!(dir.join(f).exists(), "{f}");
    }
    let csv = std::fs::read_to_string(dir.join("matrix.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + published, "{csv}");
    // one reading: no conflict, and the default stays
    let md = std::fs::read_to_string(dir.join("conflicts.md")).unwrap();
    assert!(md.contains("\n0 pairs."), "{md}");
    assert!(stdout.contains("the default stays"), "{stdout}");
    let reproduced = csv.lines().filter(|l| l.contains(",reproduced,")).count();
    assert!(
        stdout.contains(&format!(
            "| default | `default` | {reproduced} of {published} |"
        )),
        "{stdout}"
    );
}

#[test]
fn unknown_readings_and_empty_folders_are_refused_with_exit_2() {
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("readings-map-empty");
    let _ = std::fs::remove_dir_all(&out);
    let run = |args: &[&str]| {
        let o = Command::new(env!("CARGO_BIN_EXE_readings-map"))
            .args(args)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        // usage errors exit 2, as in every binary
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        String::from_utf8_lossy(&o.stderr).to_string()
    };
    let e = run(&["--readings", "default,nonsense", "--no-run"]);
    assert!(
        e.contains("'nonsense'") && e.contains("literal-labels"),
        "{e}"
    );
    let e = run(&["--readings", "default,default", "--no-run"]);
    assert!(e.contains("--readings"), "{e}");
    let e = run(&["--readings", "default", "--no-run"]);
    assert!(e.contains("no published check"), "{e}");
}
