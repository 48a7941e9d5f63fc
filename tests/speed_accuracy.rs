//! The `speed-accuracy` binary on its cheapest figures:
//! it runs each (figure, tier, engine) once, reads `cpu_seconds` and the
//! key statistic from the summaries, resumes from them, and rejects bad
//! input with a message naming the value and the allowed values.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const EXE: &str = env!("CARGO_BIN_EXE_speed-accuracy");

fn fresh(tag: &str) -> PathBuf {
    common::fresh_dir(&format!("speed-{tag}"))
}

fn speed(out: &Path, args: &[&str]) -> Output {
    Command::new(EXE)
        .args(["--tiers", "quick", "--out"])
        .arg(out)
        .args(args)
        .output()
        .expect("speed-accuracy runs")
}

fn csv_rows(out: &Path) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(out.join("speed-accuracy/speed-accuracy.csv")).expect("csv");
    text.lines()
        .skip(1)
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect()
}

#[test]
fn one_row_per_figure_and_engine_with_cpu_time_and_a_resume_that_reruns_nothing() {
    let out = fresh("two");
    let args = ["--figures", "waves-fig5,hopper-fig3"];
    let r = speed(&out, &args);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let rows = csv_rows(&out);
    // waves-fig5 with both engines, the hopper with the reference only
    let keys: Vec<(String, String)> = rows.iter().map(|r| (r[0].clone(), r[2].clone())).collect();
    assert_eq!(
        keys,
        [
            ("waves-fig5".into(), "reference".into()),
            ("waves-fig5".into(), "fast".into()),
            ("hopper-fig3".into(), "reference".into())
        ]
    );
    for row in &rows {
        let cpu: f64 = row[4].parse().unwrap();
        let se: f64 = row[8].parse().unwrap();
        assert!(cpu > 0.0 && se > 0.0, "{row:?}");
    }
    // the two engines measure the same statistic: their values agree
    let v = |i: usize| -> (f64, f64) { (rows[i][7].parse().unwrap(), rows[i][8].parse().unwrap()) };
    let ((a, sa), (b, sb)) = (v(0), v(1));
    assert!(
        (a - b).abs() <= 4.0 * sa.hypot(sb),
        "{a} +- {sa} vs {b} +- {sb}"
    );
    assert!(out.join("speed-accuracy/speed-accuracy.png").exists());
    // one recommendation per figure, also when --from adds more points of it
    let with_from = speed(
        &out,
        &[
            &args[..],
            &[
                "--from",
                out.join("speed-accuracy/runs/quick-fast").to_str().unwrap(),
            ],
        ]
        .concat(),
    );
    assert!(with_from.status.success());
    let printed = String::from_utf8_lossy(&with_from.stdout);
    assert_eq!(
        printed
            .lines()
            .filter(|l| l.starts_with("waves-fig5: "))
            .count(),
        1,
        "{printed}"
    );
    // a second call reads the summaries: same rows, no figure rerun
    let summary = out.join("speed-accuracy/runs/quick-fast/waves-fig5/summary.json");
    let written = std::fs::metadata(&summary)
        .and_then(|m| m.modified())
        .expect("summary");
    let again = speed(&out, &args);
    assert!(again.status.success());
    assert_eq!(csv_rows(&out), rows);
    assert_eq!(
        std::fs::metadata(&summary)
            .and_then(|m| m.modified())
            .unwrap(),
        written
    );
    // a summary of another revision of the engine (Engine::label) is run again
    let text = std::fs::read_to_string(&summary).unwrap();
    let mut s: serde_json::Value = serde_json::from_str(&text).unwrap();
    s["engine"] = "fast@0".into();
    std::fs::write(&summary, s.to_string()).unwrap();
    let rerun = speed(&out, &args);
    assert!(rerun.status.success());
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&summary).unwrap()).unwrap();
    assert_eq!(s["engine"], "fast", "the stale summary was replaced");
}

#[test]
fn bad_input_names_the_value_and_the_choices() {
    let out = fresh("bad");
    for (args, want) in [
        (&["--engines", "gpu"][..], "gpu"),
        (&["--figures", "waves-fig9"][..], "waves-fig9"),
        (&["--engines", "fast,fast"][..], "more than once"),
        (&["--threads", "0"][..], "1..=1024"),
    ] {
        let r = speed(&out, args);
        assert!(!r.status.success(), "{args:?} must fail");
        let err = String::from_utf8_lossy(&r.stderr);
        assert!(err.contains(want), "{args:?}: {err}");
    }
}
