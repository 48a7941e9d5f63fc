//! The bounded share of the fuzzer (`granular_automata::fuzz`) that CI runs:
//! a few thousand generated and mutated inputs per reader of outside
//! input, each of which must get a typed error or a correct result: no
//! panic, no input past the time limit, no wrong data accepted. The long
//! run is the `fuzz` binary (docs/reference/generated-input.md).

use granular_automata::fuzz::{fuzz, Reader};

/// Inputs per reader in CI: the fast readers take thousands, the readers
/// of files hundreds.
fn inputs(r: Reader) -> u64 {
    match r {
        Reader::RunFile | Reader::Merge | Reader::SeedSets => 400,
        Reader::HopperPlan | Reader::HopperEnd | Reader::Summary => 1500,
        _ => 3000,
    }
}

/// Every reader, seeded by this file's seed: the counts, and every
/// failure with its input.
#[test]
fn every_reader_gives_a_typed_error_or_a_correct_result() {
    let mut failures = vec![];
    for r in Reader::ALL {
        let t = fuzz(r, 60, inputs(r), &|| {}).unwrap();
        eprintln!(
            "{:<12} {:>6} inputs: {:>6} accepted, {:>6} refused, {} panics, {} hangs, {} silent, {:.1} s",
            t.reader, t.inputs, t.accepted, t.refused, t.panics, t.hangs, t.silent, t.seconds
        );
        assert_eq!(t.inputs, inputs(r));
        // the mutations reach both sides of every reader
        assert!(t.refused > 0, "{}: nothing refused", t.reader);
        if r != Reader::Merge {
            assert!(t.accepted > 0, "{}: nothing accepted", t.reader);
        }
        failures.extend(t.failures);
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

// ------------------------------------------- what the fuzzer found, kept

use granular_automata::hopper::engine::{HopperBuilder, HopperEngine, Reference};
use granular_automata::hopper::geometry::SiteKind;
use granular_automata::hopper::HopperParams;
use granular_automata::validate::external_hopper::{
    load, read_end, EndLine, HopperAction, HopperPlan, HopperState,
};

/// A small hopper after some rain: its engine.
fn rained() -> Box<dyn HopperEngine> {
    let mut p = HopperParams::quick();
    p.geometry.width = 9;
    p.geometry.height = 12;
    let mut h = Reference.build(p, 3).unwrap();
    for _ in 0..30 {
        h.step(true);
    }
    h
}

fn state(h: &dyn HopperEngine) -> HopperState {
    HopperState {
        sites: h.sites().to_vec(),
        spacing: h.spacing().to_vec(),
        open: h.is_open(),
    }
}

/// An end line of `h` with its state edited by `edit`, as a program prints it.
fn end_line(h: &dyn HopperEngine, edit: impl Fn(&mut HopperState)) -> String {
    let mut st = state(h);
    edit(&mut st);
    let end = EndLine {
        state: st,
        added: 0,
        removed: 0,
        iterations: 1,
        site_updates: 0.0,
    };
    serde_json::to_string(&end).unwrap()
}

/// The first inside site holding a grain.
fn a_grain(h: &dyn HopperEngine) -> usize {
    (0..h.sites().len())
        .find(|&i| h.sites()[i] != 0 && h.sites()[i] != 255)
        .expect("a grain")
}

/// An end line whose grain is 22..=254 (no state of 21) was taken as a
/// grain; it is refused, naming the site and the allowed values.
#[test]
fn an_end_line_with_a_site_value_past_21_is_refused() {
    let h = rained();
    let i = a_grain(h.as_ref());
    assert!(read_end(h.geometry(), &end_line(h.as_ref(), |_| {})).is_ok());
    for v in [22u8, 98, 254] {
        let e = read_end(h.geometry(), &end_line(h.as_ref(), |s| s.sites[i] = v)).unwrap_err();
        assert!(
            e.contains(&format!("site {i}")) && e.contains("1..=21"),
            "{e}"
        );
    }
}

/// An end line whose grain has a spacing below 1, negative or huge was
/// taken (only NaN and infinities were refused); D is a mean of ray
/// lengths of at least 1, and set_spacing takes [1, 1e6].
#[test]
fn an_end_line_with_a_grain_spacing_outside_1_to_1e6_is_refused() {
    let h = rained();
    let i = a_grain(h.as_ref());
    for d in [0.5, -0.0, -3.0, 1.7e308] {
        let e = read_end(h.geometry(), &end_line(h.as_ref(), |s| s.spacing[i] = d)).unwrap_err();
        assert!(
            e.contains(&format!("site {i}")) && e.contains("[1, 1e6]"),
            "{d}: {e}"
        );
    }
    // a hole's spacing is not read
    let hole = (0..h.sites().len()).find(|&j| h.sites()[j] == 0).unwrap();
    assert!(read_end(
        h.geometry(),
        &end_line(h.as_ref(), |s| s.spacing[hole] = -1.0)
    )
    .is_ok());
}

/// A hopper plan whose state changes a wall or plug site was taken, and
/// the change silently dropped (only inside sites were set); it is
/// refused, naming the site.
#[test]
fn a_plan_state_that_moves_a_wall_is_refused() {
    let h = rained();
    let g = h.geometry();
    let wall = g.kind.iter().position(|k| *k == SiteKind::Wall).unwrap();
    let plug = g.kind.iter().position(|k| *k == SiteKind::Plug).unwrap();
    let plan = |edit: &dyn Fn(&mut HopperState)| {
        let mut st = state(h.as_ref());
        edit(&mut st);
        let p = HopperPlan {
            params: *h.params(),
            seed: 1,
            state: Some(st),
            action: HopperAction::Steps { n: 1, rain: false },
        };
        serde_json::to_string(&p).unwrap()
    };
    assert!(load(&Reference, &mut plan(&|_| {}).as_bytes()).is_ok());
    for (i, v) in [(wall, 251u8), (wall, 0), (wall, 5), (plug, 0), (plug, 5)] {
        let Err(e) = load(&Reference, &mut plan(&|s| s.sites[i] = v).as_bytes()) else {
            panic!("site {i} = {v} taken");
        };
        assert!(e.message.contains(&format!("site {i}")), "{}", e.message);
    }
    // an open plug is a hole
    let plugs: Vec<usize> = (0..g.kind.len())
        .filter(|&i| g.kind[i] == SiteKind::Plug)
        .collect();
    let open = |s: &mut HopperState| {
        s.open = true;
        for &i in &plugs {
            s.sites[i] = 0;
        }
    };
    assert!(load(&Reference, &mut plan(&|s| open(s)).as_bytes()).is_ok());
    let grain_on_plug = |s: &mut HopperState| {
        open(s);
        s.sites[plug] = 5;
    };
    assert!(load(&Reference, &mut plan(&grain_on_plug).as_bytes()).is_err());
}

/// A shard's run file with a byte that is not UTF-8, inside a member that
/// a later copy of the same member overrides (so the parsed file passes
/// its checksum), was merged: merge read it as lossy text, the resume then
/// refused it. Merge refuses it, naming the file.
#[test]
fn merge_refuses_a_run_file_that_is_not_utf8() {
    use granular_automata::ensemble::{merge, Ensemble};
    let root = std::env::temp_dir().join(format!("ga-merge-utf8-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    let shard = root.join("shard");
    let key = serde_json::json!({"tier": "quick"});
    let ens = Ensemble::new(&shard, "utf8", &key, 1, 2, None)
        .unwrap()
        .threads(1)
        .quiet();
    ens.run(1, |i, _, _| Ok(i as u64)).unwrap();
    let path = ens.run_path(1);
    let sound = std::fs::read(&path).unwrap();
    let mut bad = b"{\"key\":\"x\xff\",".to_vec();
    bad.extend_from_slice(&sound[1..]);
    std::fs::write(&path, &bad).unwrap();
    let e = merge(&root.join("into"), std::slice::from_ref(&shard)).unwrap_err();
    assert!(
        e.message.contains("run-00001.json") && e.message.contains("UTF-8"),
        "{}",
        e.message
    );
    assert!(!root.join("into").exists(), "nothing merged");
    // the sound file merges
    std::fs::write(&path, &sound).unwrap();
    merge(&root.join("into"), &[shard]).unwrap();
    let _ = std::fs::remove_dir_all(&root);
}
