//! Tests of the ensemble runner (issue 6): resume after an interruption gives
//! byte-identical results, merged shards equal the unsharded ensemble, and
//! results do not depend on the thread count. Every run is a small seeded
//! pipe run (L = 40, W = 5, 300 steps), so the tests are exact, not
//! statistical.

use granular_automata::ensemble::{merge, Ensemble, Outcome, Shard};
use granular_automata::error::{Error, ErrorKind};
use granular_automata::pipe::record::{record, Record};
use granular_automata::pipe::{Params, Pipe, Rules};
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

/// The base seed of every ensemble in this file.
const SEED: u64 = 20260611;
const RUNS: usize = 7;

fn fresh(tag: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("ensemble-{tag}"));
    let _ = std::fs::remove_dir_all(&d);
    d
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
    let calls = AtomicUsize::new(0);
    let got = complete(
        e.run(300, |_, seed, _| {
            calls.fetch_add(1, Ordering::SeqCst);
            one_run(seed)
        })
        .unwrap(),
    );
    assert_eq!(calls.load(Ordering::SeqCst), RUNS - 4);
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
    let calls = AtomicUsize::new(0);
    let got9 = complete(
        e9.run(300, |_, seed, _| {
            calls.fetch_add(1, Ordering::SeqCst);
            one_run(seed)
        })
        .unwrap(),
    );
    assert_eq!(calls.load(Ordering::SeqCst), 2);
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
