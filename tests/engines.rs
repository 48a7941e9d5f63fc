//! The `--engine` option of the pipe figures: every pipe figure
//! runs with the fast engine and records it in summary.json, an unknown
//! engine is a typed error naming the known ones, and PH94 Fig. 2 run by the
//! fast engine decides its claims as the reference does (the fast engine is
//! validated by `validate`, tests/fast_engine.rs; this is the figure-level
//! check that the plumbing hands it the figure's runs).

mod common;
use common::models::pipe;
use common::{contradicted, metric, pass, run_figure};
use granular_automata::pipe::engine::{EngineBuilder, Reference};
use granular_automata::pipe::fast::Fast;
use granular_automata::pipe::Engine;
use granular_automata::pipe::{Boundary, Rules};
use granular_automata::validate::mutants::MUTANTS;
use std::process::Command;

/// (binary, executable, the cheapest arguments that exercise it, a file it
/// must write); the arguments are written as one string, split at spaces.
macro_rules! figure {
    ($bin:literal, $args:literal, $file:literal) => {
        (
            $bin,
            env!(concat!("CARGO_BIN_EXE_", $bin)),
            $args.split(' ').collect::<Vec<&'static str>>(),
            $file,
        )
    };
}

/// Every pipe figure, as [`figure!`] writes it.
fn figures() -> Vec<(&'static str, &'static str, Vec<&'static str>, &'static str)> {
    vec![
        figure!("fig1", "--runs 1", "fig1.png"),
        figure!("waves-fig2", "--runs 1", "summary.json"),
        figure!("waves-fig3", "--runs 1 --steps 2000", "summary.json"),
        figure!("waves-fig4", "--runs 1 --lengths 128", "summary.json"),
        figure!("waves-fig5", "--runs 1 --length 128", "summary.json"),
        figure!("waves-fig6", "--runs 1", "summary.json"),
        figure!("waves-fig7", "--runs 1", "summary.json"),
        figure!("waves-fig8", "--runs 1 --p 0,0.5", "summary.json"),
        figure!("waves-fig9", "--runs 1 --rho 1.4", "summary.json"),
        figure!("waves-fig10", "--runs 1", "summary.json"),
        figure!("waves-fig11", "--runs 1 --correlation-only", "summary.json"),
        figure!(
            "waves-fig12",
            "--runs 1 --sizes 220x11 --no-spectra --bisections 3",
            "summary.json"
        ),
    ]
}

#[test]
fn every_pipe_figure_runs_with_the_fast_engine_and_records_it() {
    for (bin, exe, extra, file) in figures() {
        let mut args = vec!["--tier", "quick", "--seed", "1", "--engine", "fast"];
        args.extend(extra);
        let s = run_figure(bin, exe, &args, "fast", &[file]);
        assert_eq!(
            s["engine"],
            Engine::Fast.label(),
            "{bin}: summary.json names the engine and its revision"
        );
    }
}

#[test]
fn an_unknown_engine_is_an_error_naming_the_known_ones() {
    let out = Command::new(env!("CARGO_BIN_EXE_fig2"))
        .args(["--engine", "gpu", "--out"])
        .arg(std::env::temp_dir().join("engines-unknown"))
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("gpu") && err.contains("reference, fast"),
        "{err}"
    );
}

/// PH94 Fig. 2 at the quick tier (4 runs, seed 1) with the fast engine: the
/// same decisions as the reference's in tests/spectra.rs (alpha not
/// contradicted and within the margin 0.1 of 4/3; v_peak reproduced within
/// 0.01 of 0.40), and the reference's default summary names its engine.
#[test]
fn fig2_with_the_fast_engine_decides_as_the_reference() {
    let fig2 = env!("CARGO_BIN_EXE_fig2");
    let args = ["--tier", "quick", "--seed", "1", "--engine", "fast"];
    let s = run_figure("fig2", fig2, &args, "fast-decides", &["fig2.png"]);
    assert_eq!(s["engine"], Engine::Fast.label());
    let (a, ae) = (metric(&s, "alpha"), metric(&s, "alpha_err"));
    assert!(!contradicted(&s, "alpha"), "alpha = {a} +- {ae}");
    assert!((a - 4.0 / 3.0).abs() <= 0.1, "alpha = {a} +- {ae}");
    assert!(pass(&s, "v_peak"), "v_peak = {}", metric(&s, "v_peak"));
}

/// The fingerprint of each engine's revision (`Engine::revision`): (engine,
/// revision, fingerprint). A change of an engine's dynamics changes its
/// fingerprint; then raise its revision, so that resumed ensembles keyed by
/// `Engine::label` do not mix runs of the old and the new dynamics, and add
/// the new fingerprint here (keep the old lines).
const FINGERPRINTS: [(Engine, u32, u64); 2] = [
    (Engine::Reference, 1, 0xf58c_871f_084a_52f7),
    (Engine::Fast, 1, 0x7e8f_ee36_79ef_e2e5),
];

/// FNV-1a over every site byte and the flux counters after 400 steps of a
/// small pipe (or up to the step where it fills), periodic and open (I =
/// 0.9, above I_c, so the rest channels fill and extra rest particles take
/// the relocation walk), for six readings.
fn fingerprint(engine: &dyn EngineBuilder) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |b: u8| {
        h ^= b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    };
    for rules in [
        "default",
        "ph94",
        "any-mover+rest-up",
        "up-to-rest+fhp-rest+wall-drag",
        "rest-ahead+gravity-last+inject-down",
        "ph94+rest-slide",
    ] {
        let rules: Rules = rules.parse().unwrap();
        for boundary in [Boundary::Periodic, Boundary::Open { inject: 0.9 }] {
            let params = pipe(60, 5, boundary);
            let mut e = engine.build(params, rules, 1616).unwrap();
            // a pipe that fills stops with an error: its step is part of the print
            if let Err(err) = e.run(400) {
                err.message.bytes().for_each(&mut eat);
            }
            for y in 0..params.length {
                for x in 0..params.width {
                    eat(e.site(x, y));
                }
            }
            let f = e.flux();
            for n in [f.injected, f.out_bottom, f.out_top] {
                n.to_le_bytes().into_iter().for_each(&mut eat);
            }
        }
    }
    h
}

/// Each engine's dynamics are those of its recorded revision.
#[test]
fn each_engine_revision_has_its_recorded_fingerprint() {
    let builders: [(Engine, &dyn EngineBuilder); 2] =
        [(Engine::Reference, &Reference), (Engine::Fast, &Fast)];
    for (engine, builder) in builders {
        let r = engine.revision();
        let f = fingerprint(builder);
        let recorded = FINGERPRINTS
            .iter()
            .find(|(e, rev, _)| *e == engine && *rev == r)
            .map(|t| t.2);
        assert_eq!(
            recorded,
            Some(f),
            "{engine} revision {r} has fingerprint {f:#018x}: if its dynamics changed, raise Engine::revision and \
             record the new fingerprint in FINGERPRINTS (saved runs are keyed by Engine::label)"
        );
    }
    // revision 1 keeps the bare name, as runs saved before revisions existed
    assert_eq!(Engine::Fast.label(), "fast");
    assert_eq!(Engine::Reference.label(), "reference");
}

/// The fingerprint sees every plausible bug of the mutant catalogue: each
/// pipe mutant of the reference (`validate`) has another fingerprint.
#[test]
fn every_pipe_mutant_changes_the_fingerprint() {
    let reference = fingerprint(&Reference);
    for (name, m) in MUTANTS {
        if !m.is_hopper() {
            assert_ne!(fingerprint(&m), reference, "mutant {name}");
        }
    }
}
