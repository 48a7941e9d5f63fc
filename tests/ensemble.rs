//! Tests of the ensemble runner: resume after an interruption gives
//! byte-identical results, merged shards equal the unsharded ensemble, and
//! results do not depend on the thread count. Every run is a small seeded
//! pipe run (L = 40, W = 5, 300 steps), so the tests are exact, not
//! statistical.

mod common;

use granular_automata::ensemble::{merge, Ensemble, Outcome, Shard};
use granular_automata::error::{Error, ErrorKind};
use granular_automata::pipe::record::{record, Record};
use granular_automata::pipe::{Params, Pipe, Rules};
use std::ffi::OsStr;
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

/// The base seed of every ensemble in this file.
const SEED: u64 = 20260611;
const RUNS: usize = 7;

fn fresh(tag: &str) -> PathBuf {
    common::fresh_dir(&format!("ensemble-{tag}"))
}

fn key() -> serde_json::Value {
    serde_json::json!({"L": 40, "W": 5, "steps": 300})
}

fn one_run(seed: u64) -> granular_automata::Result<Record> {
    let params = Params {
        length: 40,
        width: 5,
        p: 0.1,
        ..Params::default()
    };
    let mut pipe = Pipe::new(params, Rules::default(), seed)?;
    record(&mut pipe, 300, 20, |_| {})
}

fn complete<T>(o: Outcome<T>) -> Vec<T> {
    match o {
        Outcome::Complete(v) => v,
        Outcome::ShardDone { .. } => panic!("expected a complete ensemble"),
    }
}

/// Run the ensemble `e` to completion: its results, and how many runs it
/// computed (the others were read back from their saved files).
fn run_counted(e: &Ensemble) -> (Vec<Record>, usize) {
    let calls = AtomicUsize::new(0);
    let got = complete(
        e.run(300, |_, seed, _| {
            calls.fetch_add(1, Ordering::SeqCst);
            one_run(seed)
        })
        .unwrap(),
    );
    (got, calls.load(Ordering::SeqCst))
}

/// The uninterrupted, unsharded ensemble on one thread, in `ensemble-<tag>`.
fn reference(tag: &str) -> Vec<Record> {
    let dir = fresh(tag);
    let e = Ensemble::new(&dir, "t", &key(), SEED, RUNS, None)
        .unwrap()
        .threads(1)
        .quiet();
    complete(e.run(300, |_, seed, _| one_run(seed)).unwrap())
}

#[test]
fn resume_after_interruption_is_byte_identical() {
    let want = reference("reference-resume");
    let dir = fresh("resume");
    let e = Ensemble::new(&dir, "t", &key(), SEED, RUNS, None)
        .unwrap()
        .threads(1)
        .quiet();
    // interrupted: run 4 fails (as if the machine stopped there)
    let err = e
        .run(300, |i, seed, _| {
            if i == 4 {
                Err(Error::new(ErrorKind::Io, "simulated interruption"))
            } else {
                one_run(seed)
            }
        })
        .unwrap_err();
    assert_eq!(err.message, "simulated interruption");
    assert_eq!(e.finished(), vec![0, 1, 2, 3], "runs before the stop saved");
    // resumed: only the missing runs are computed
    let (got, computed) = run_counted(&e);
    assert_eq!(computed, RUNS - 4);
    assert_eq!(
        serde_json::to_string(&got).unwrap(),
        serde_json::to_string(&want).unwrap()
    );
    // and the run files themselves are byte-identical to the uninterrupted ones
    let ref_dir = Ensemble::new(
        &PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("ensemble-reference-resume"),
        "t",
        &key(),
        SEED,
        RUNS,
        None,
    )
    .unwrap();
    for i in 0..RUNS {
        assert_eq!(
            std::fs::read(e.run_path(i)).unwrap(),
            std::fs::read(ref_dir.run_path(i)).unwrap(),
            "run file {i}"
        );
    }
    // more runs later reuse the finished ones
    let e9 = Ensemble::new(&dir, "t", &key(), SEED, RUNS + 2, None)
        .unwrap()
        .quiet();
    let (got9, computed) = run_counted(&e9);
    assert_eq!(computed, 2);
    assert_eq!(got9[..RUNS], want[..]);
}

#[test]
fn merged_shards_equal_the_unsharded_ensemble() {
    let want = reference("reference-shards");
    let mut parts = Vec::new();
    for i in 0..3 {
        let dir = fresh(&format!("shard{i}"));
        let shard = Shard { index: i, count: 3 };
        let e = Ensemble::new(&dir, "t", &key(), SEED, RUNS, Some(shard))
            .unwrap()
            .quiet();
        match e.run(300, |_, seed, _| one_run(seed)).unwrap() {
            Outcome::ShardDone { runs, .. } => assert_eq!(runs, (RUNS + 2 - i) / 3),
            Outcome::Complete(_) => panic!("a shard does not analyse"),
        }
        parts.push(dir);
    }
    let merged = fresh("merged");
    let rep = merge(&merged, &parts).unwrap();
    assert_eq!((rep.copied, rep.identical), (RUNS, 0));
    // merging again finds identical files
    let rep = merge(&merged, &parts).unwrap();
    assert_eq!((rep.copied, rep.identical), (0, RUNS));
    let e = Ensemble::new(&merged, "t", &key(), SEED, RUNS, None)
        .unwrap()
        .quiet();
    let got = complete(
        e.run(300, |_, _, _| -> granular_automata::Result<Record> {
            panic!("every run is merged, nothing to compute")
        })
        .unwrap(),
    );
    assert_eq!(got, want);
    // a shard computed with other code or parameters does not merge silently
    let other = fresh("tampered");
    let e0 = Ensemble::new(&parts[0], "t", &key(), SEED, RUNS, None).unwrap();
    let target = other.join("t/runs").join(e0.dir().file_name().unwrap());
    std::fs::create_dir_all(&target).unwrap();
    std::fs::write(target.join("run-00000.json"), b"{}").unwrap();
    let err = merge(&other, &parts).unwrap_err();
    assert_eq!(err.kind, ErrorKind::Io);
    assert!(err.message.contains("differ"), "{}", err.message);
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    let want = reference("reference-threads");
    for threads in [2, 5] {
        let dir = fresh(&format!("threads{threads}"));
        let e = Ensemble::new(&dir, "t", &key(), SEED, RUNS, None)
            .unwrap()
            .threads(threads)
            .quiet();
        let got = complete(e.run(300, |_, seed, _| one_run(seed)).unwrap());
        assert_eq!(got, want, "{threads} threads");
    }
}

#[test]
fn other_parameters_do_not_reuse_runs() {
    let dir = fresh("keys");
    let a = Ensemble::new(&dir, "t", &key(), SEED, 2, None)
        .unwrap()
        .quiet();
    complete(a.run(1, |_, seed, _| one_run(seed)).unwrap());
    let b = Ensemble::new(&dir, "t", &serde_json::json!({"L": 80}), SEED, 2, None).unwrap();
    assert_ne!(a.dir(), b.dir());
    assert!(b.finished().is_empty());
    let c = Ensemble::new(&dir, "t", &key(), SEED + 1, 2, None).unwrap();
    assert!(c.finished().is_empty(), "another base seed, other runs");
}

/// End to end through the command line: `waves-fig3` run as two shards into
/// two folders, merged with the `merge` binary and analysed without
/// `--shard`, gives the same data file as the unsharded run, byte for byte;
/// so does a second, resumed invocation of the unsharded run (nothing left to
/// compute), whatever `--threads`.
#[test]
fn figure_binary_shards_merge_and_resume() {
    use std::process::Command;
    let fig3 = |out: &PathBuf, extra: &[&str]| {
        let st = Command::new(env!("CARGO_BIN_EXE_waves-fig3"))
            .args([
                "--tier", "quick", "--seed", "5", "--runs", "6", "--steps", "1000",
            ])
            .args(extra)
            .arg("--out")
            .arg(out)
            .output()
            .unwrap();
        assert!(
            st.status.success(),
            "{}",
            String::from_utf8_lossy(&st.stderr)
        );
        String::from_utf8_lossy(&st.stdout).to_string()
    };
    let whole = fresh("cli-whole");
    fig3(&whole, &["--threads", "1"]);
    let want = std::fs::read(whole.join("waves-fig3/fig3.csv")).unwrap();
    // resume: the second invocation finds every run and rewrites the same file
    fig3(&whole, &["--threads", "2"]);
    assert_eq!(
        std::fs::read(whole.join("waves-fig3/fig3.csv")).unwrap(),
        want
    );
    // shards
    let parts: Vec<PathBuf> = (0..2).map(|i| fresh(&format!("cli-part{i}"))).collect();
    for (i, p) in parts.iter().enumerate() {
        let msg = fig3(p, &["--shard", &format!("{i}/2"), "--threads", "2"]);
        assert!(msg.contains("shard"), "{msg}");
        assert!(
            !p.join("waves-fig3/summary.json").exists(),
            "a shard does not analyse"
        );
    }
    let merged = fresh("cli-merged");
    let st = Command::new(env!("CARGO_BIN_EXE_merge"))
        .arg("--out")
        .arg(&merged)
        .args(&parts)
        .output()
        .unwrap();
    assert!(st.status.success());
    assert!(String::from_utf8_lossy(&st.stdout).contains("6 run files copied"));
    fig3(&merged, &[]);
    assert_eq!(
        std::fs::read(merged.join("waves-fig3/fig3.csv")).unwrap(),
        want
    );
    // a bad shard is a clear error naming the value
    let bad = fresh("cli-bad");
    let args = [
        OsStr::new("--shard"),
        "2/2".as_ref(),
        "--out".as_ref(),
        bad.as_ref(),
    ];
    common::fails_with(env!("CARGO_BIN_EXE_waves-fig3"), args, "2/2");
}

#[test]
fn edited_run_files_are_rejected_and_a_failed_merge_leaves_nothing() {
    // two shards; run 1 of shard 1 is edited by hand afterwards
    let mut parts = Vec::new();
    for i in 0..2 {
        let dir = fresh(&format!("edit-shard{i}"));
        let shard = Shard { index: i, count: 2 };
        let e = Ensemble::new(&dir, "t", &key(), SEED, 4, Some(shard))
            .unwrap()
            .quiet();
        e.run(300, |_, seed, _| one_run(seed)).unwrap();
        parts.push(dir);
    }
    let e1 = Ensemble::new(&parts[1], "t", &key(), SEED, 4, None).unwrap();
    let edited = e1.run_path(1);
    let text = std::fs::read_to_string(&edited).unwrap();
    let pos = text.find("\"result\"").unwrap();
    // change one digit of the result, keep the JSON valid
    let digit = text[pos..]
        .find(|c: char| c.is_ascii_digit() && c != '9')
        .unwrap()
        + pos;
    let mut bytes = text.into_bytes();
    bytes[digit] += 1;
    std::fs::write(&edited, &bytes).unwrap();
    let merged = fresh("edit-merged");
    let err = merge(&merged, &parts).unwrap_err();
    assert_eq!(err.kind, ErrorKind::Io);
    assert!(
        err.message.contains(&edited.display().to_string()) && err.message.contains("checksum"),
        "{}",
        err.message
    );
    assert!(!merged.exists(), "a failed merge writes nothing");
    // the analysis rejects it too, naming the file
    let all = Ensemble::new(&parts[1], "t", &key(), SEED, 4, None)
        .unwrap()
        .threads(1)
        .quiet();
    let err = all
        .run(300, |_, seed, _| one_run(seed))
        .map(|_| ())
        .unwrap_err();
    assert!(
        err.message.contains("run-00001.json") && err.message.contains("checksum"),
        "{}",
        err.message
    );
}
