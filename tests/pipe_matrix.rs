//! Smoke test of the reproduction matrix (issue 4): one reading, one run per
//! set-up at the quick tier; the outputs exist, every claim is graded, one
//! run decides nothing (the one grading rule needs 3), and the cached result
//! is reused on a second call (resume: the cache file is not rewritten and
//! the matrix is the same; no wall-clock comparison, which can fail on
//! shared cores).

use std::path::PathBuf;
use std::process::Command;

#[test]
fn matrix_grades_every_claim_and_resumes_from_its_cache() {
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("pipe-matrix");
    let _ = std::fs::remove_dir_all(&out);
    let run = || {
        let status = Command::new(env!("CARGO_BIN_EXE_pipe-matrix"))
            .args([
                "--tier",
                "quick",
                "--runs",
                "1",
                "--readings",
                "ph94",
                "--out",
            ])
            .arg(&out)
            .status()
            .unwrap();
        assert!(status.success());
    };
    run();
    let dir = out.join("pipe-matrix");
    for f in ["matrix.md", "matrix.csv", "pipe-matrix.png", "summary.json"] {
        assert!(dir.join(f).exists(), "{f}");
    }
    let csv = std::fs::read_to_string(dir.join("matrix.csv")).unwrap();
    assert_eq!(
        csv.lines().count(),
        1 + 11,
        "a header and 11 graded claims:\n{csv}"
    );
    // one run per set-up: every claim is undecided, never reproduced
    assert!(csv.contains("ph94,waves_1a,?"), "{csv}");
    assert!(!csv.contains(",yes,") && !csv.contains(",no,"), "{csv}");
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    let m = s["matrix"].as_array().unwrap();
    assert_eq!(m.len(), 11);
    assert_eq!(m[0]["variant"], "ph94");
    assert_eq!(m[0]["claim"], "waves_1a");
    assert!(m.iter().all(|c| c["status"] == "undecided"), "{m:?}");
    assert_eq!(s["metrics"]["claims"], 11.0);
    // the default reading is not among --readings here
    assert!(s["metrics"]["default_reproduced"].is_null());
    let cached: Vec<_> = std::fs::read_dir(dir.join("variants"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    assert_eq!(cached.len(), 1, "one cached reading: {cached:?}");
    let stamp = |p: &PathBuf| std::fs::metadata(p).unwrap().modified().unwrap();
    let before = stamp(&cached[0]);
    run();
    assert_eq!(
        stamp(&cached[0]),
        before,
        "the second call reuses the saved reading instead of rewriting it"
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("matrix.csv")).unwrap(),
        csv
    );
}
