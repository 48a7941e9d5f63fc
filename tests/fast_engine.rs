//! The fast, bit-sliced engine (`granular_automata::pipe::fast`)
//! against the reference engine `Pipe`: site by site wherever a step has no
//! random choice, conservation and bookkeeping (MODEL.md A7), the same
//! errors, and the observables of one state. Its random steps are compared
//! with the reference's exact one-step tables by `validate --candidate fast`.

mod common;

use common::certain::Certain;
use common::models::pipe;
use granular_automata::pipe::engine::{EngineBuilder, PipeEngine, Reference};
use granular_automata::pipe::fast::{Fast, FastPipe};
use granular_automata::pipe::{
    Boundary, Flux, GravityWording, LaneCollide, Params, Pipe, RestPlacement, Rules,
};
use granular_automata::ErrorKind;
use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use std::cell::Cell;
use std::rc::Rc;

/// Every random choice of this file derives from this seed.
const SEED: u64 = 20_261_213;

fn params(width: usize, length: usize, open: bool, p: f64, g: f64, b: f64) -> Params {
    Params {
        width,
        length,
        bin: 1,
        rho: 1.0,
        p,
        g,
        b,
        boundary: if open {
            Boundary::Open { inject: 0.0 }
        } else {
            Boundary::Periodic
        },
    }
}

fn flux_change(now: Flux, before: Flux) -> [u64; 3] {
    [
        now.injected - before.injected,
        now.out_bottom - before.out_bottom,
        now.out_top - before.out_top,
    ]
}

/// The two engines stepped side by side from the same prepared state.
struct Lockstep {
    reference: Pipe<Certain>,
    fast: FastPipe,
    choices: Rc<Cell<u64>>,
    /// Steps compared site by site, steps with a random choice (resynced).
    compared: u64,
    random: u64,
}

impl Lockstep {
    fn new(params: Params, rules: Rules, init: &[(usize, usize, u8)]) -> Self {
        let certain = Certain::default();
        let choices = certain.choices.clone();
        let mut reference = Pipe::new(params, rules, SEED).unwrap().with_draws(certain);
        reference.clear();
        let mut fast = FastPipe::new(params, rules, SEED).unwrap();
        fast.clear();
        for &(x, y, s) in init {
            reference.set_site(x, y, s);
            fast.set_site(x, y, s);
        }
        Lockstep {
            reference,
            fast,
            choices,
            compared: 0,
            random: 0,
        }
    }

    /// One step of both. A step without random choice must give the same
    /// sites and flux; after one with a choice the fast engine takes the
    /// reference's state (unless `certain`, where a choice is a failure).
    fn step(&mut self, certain: bool, what: &str) -> bool {
        let w = self.fast.params().width;
        let (rf, ff) = (self.reference.flux(), self.fast.flux());
        self.choices.set(0);
        let r = self.reference.step();
        let f = self.fast.step();
        let kind = |e: &Result<(), granular_automata::Error>| e.as_ref().err().map(|e| e.kind);
        let too_many = Some(ErrorKind::RestExceedsSites);
        if self.choices.get() > 0 {
            assert!(!certain, "{what}: the reference made a random choice");
            // the count of rest particles is certain, a walk's length is not
            assert_eq!(kind(&r) == too_many, kind(&f) == too_many, "{what}");
            if r.is_err() || f.is_err() {
                return false;
            }
            self.random += 1;
            for x in 0..w {
                for (y, &s) in self.reference.column(x).iter().enumerate() {
                    self.fast.set_site(x, y, s);
                }
            }
            return true;
        }
        assert_eq!(r, f, "{what}: the same errors");
        if r.is_err() {
            return false; // the state is left as the error found it
        }
        self.compared += 1;
        let t = self.reference.time();
        // the occupied sites of the reference, and no particle elsewhere
        for x in 0..w {
            for (y, &s) in self.reference.column(x).iter().enumerate() {
                if s != 0 {
                    assert_eq!(
                        self.fast.site(x, y),
                        s,
                        "{what}: site ({x}, {y}) after step {t}"
                    );
                }
            }
        }
        assert_eq!(
            self.fast.particle_count(),
            self.reference.particle_count(),
            "{what}: particles after step {t}"
        );
        assert_eq!(self.fast.time(), t);
        assert_eq!(
            flux_change(self.fast.flux(), ff),
            flux_change(self.reference.flux(), rf),
            "{what}: flux of step {t}"
        );
        true
    }
}

/// The readings with certain outcomes at the given g and b of
/// `lone_particles_move_as_in_the_reference`.
fn certain_configs() -> Vec<(&'static str, f64, f64)> {
    vec![
        ("ph94", 0.0, 0.0),
        ("ph94", 0.0, 1.0),
        ("ph94", 1.0, 1.0),
        ("any-mover", 1.0, 0.0),
        ("up-to-rest", 1.0, 1.0),
        ("ph94+wall-move", 0.0, 0.0),
        ("default", 1.0, 1.0),
        ("ph94+wall-drag", 0.0, 1.0),
        (
            "any-mover+wall-drag+gravity-first+wall-move+rest-slide",
            1.0,
            1.0,
        ),
        ("ph94+gravity-last+wall-move+fhp-rest", 1.0, 1.0),
        ("rest-ahead+gravity-last", 1.0, 0.0),
        ("default+literal-labels", 1.0, 1.0),
        ("default+wall-sites", 1.0, 0.0),
        ("any-mover+wall-sites+literal-labels", 1.0, 1.0),
        ("ph94+wall-sites", 0.0, 1.0),
    ]
}

/// Whether a reading can run on a pipe `w` wide (`wall-sites` needs W >= 3)
/// and site column `x` can hold channel `c` under it.
fn holds(rules: &str, w: usize, x: usize, c: usize) -> bool {
    let r: Rules = rules.parse().unwrap();
    (!r.wall_sites || w >= 3) && r.channels_of_column(x, w) >> c & 1 == 1
}

/// One particle of every channel, started in the wall columns and next to
/// them, in the first and last row, 50 steps: crossing the periodic seam
/// both ways, leaving both open ends, hitting both walls at b = 0 and 1,
/// every gravity wording at g = 1, wall-move and wall-drag at b = 1;
/// W = 1, 2, 3, 5, 11 and L around a word of 64 rows.
#[test]
fn lone_particles_move_as_in_the_reference() {
    let mut compared = 0;
    for (w, l) in [(1usize, 7usize), (2, 64), (3, 13), (5, 128), (11, 65)] {
        let mut xs = vec![0, 1, w.saturating_sub(2), w - 1];
        xs.retain(|&x| x < w);
        xs.sort_unstable();
        xs.dedup();
        for open in [false, true] {
            for (rules, g, b) in certain_configs() {
                for c in 0..7 {
                    for &x in &xs {
                        if !holds(rules, w, x, c) {
                            continue;
                        }
                        for y in [0, l - 1] {
                            let what = format!(
                                "W {w} L {l} open {open} {rules} g {g} b {b}: channel {c} at ({x}, {y})"
                            );
                            let p = params(w, l, open, 0.5, g, b);
                            let mut s = Lockstep::new(p, rules.parse().unwrap(), &[(x, y, 1 << c)]);
                            for _ in 0..50 {
                                assert!(s.step(true, &what));
                            }
                            compared += s.compared;
                        }
                    }
                }
            }
        }
    }
    assert!(compared > 50_000, "{compared}");
}

/// Random prepared states (about rho = 1 and some rest particles) at p, g,
/// b in {0, 1} and I in {0, 1}: every step without a random choice of the
/// reference (R1, R3, relocation walks and rest-slide coins are random)
/// compared site by site, with its flux.
#[test]
fn dense_states_agree_wherever_the_step_is_certain() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(SEED);
    let (mut compared, mut random) = (0, 0);
    let readings = [
        "ph94",
        "any-mover",
        "up-to-rest+rest-up",
        "default",
        "ph94+wall-drag+rest-up",
        "up-to-rest+gravity-first+wall-move+wall-drag+rest-up",
        "rest-ahead",
        "rest-ahead+gravity-first+wall-move+fhp-rest",
        "ph94+gravity-last+wall-move+fhp-rest",
        "rest-ahead+gravity-last+rest-slide",
        "default+inject-down",
        "ph94+wall-drag+wall-move+inject-late",
        "rest-ahead+gravity-last+inject-down+inject-late",
        "default+literal-labels",
        "any-mover+rest-up+fhp-rest+literal-labels",
        "default+wall-sites",
        "up-to-rest+rest-up+wall-sites",
        "rest-ahead+gravity-last+rest-slide+literal-labels+wall-sites",
    ];
    for (w, l) in [(1, 7), (2, 9), (3, 65), (11, 13)] {
        for open in [false, true] {
            for rules in readings {
                let reading: Rules = rules.parse().unwrap();
                if reading.wall_sites && w < 3 {
                    continue;
                }
                for (p, g, b) in [
                    (0.0, 0.0, 0.0),
                    (1.0, 1.0, 1.0),
                    (1.0, 0.0, 1.0),
                    (0.0, 1.0, 0.0),
                ] {
                    let mut pp = params(w, l, open, p, g, b);
                    if open {
                        pp.boundary = Boundary::Open {
                            inject: (rng.next_u32() & 1) as f64,
                        };
                    }
                    let mut init = Vec::new();
                    for x in 0..w {
                        for y in 0..l {
                            // movers with probability 1/6 each, rest 1/8
                            let mut s = 0u8;
                            for c in 1..=6 {
                                if rng.next_u32() % 6 == 0 {
                                    s |= 1 << c;
                                }
                            }
                            if rng.next_u32() % 8 == 0 {
                                s |= 1;
                            }
                            // only the channels a site has (`wall-sites`)
                            init.push((x, y, s & reading.channels_of_column(x, w)));
                        }
                    }
                    let what = format!("W {w} L {l} open {open} {rules} p {p} g {g} b {b}");
                    let mut s = Lockstep::new(pp, rules.parse().unwrap(), &init);
                    for _ in 0..50 {
                        if !s.step(false, &what) {
                            break;
                        }
                    }
                    compared += s.compared;
                    random += s.random;
                }
            }
        }
    }
    assert!(
        compared > 2500 && random > 600,
        "{compared} certain, {random} random"
    );
}

/// The occupied sites after one step of both engines from `init`, a step
/// that must have no random choice (the engines agree site by site).
fn after_one_step(p: Params, rules: &str, init: &[(usize, usize, u8)]) -> Vec<(usize, usize, u8)> {
    let mut s = Lockstep::new(p, rules.parse().unwrap(), init);
    assert!(s.step(true, rules));
    let mut v = Vec::new();
    for x in 0..p.width {
        for (y, &b) in s.reference.column(x).iter().enumerate() {
            if b != 0 {
                v.push((x, y, b));
            }
        }
    }
    v
}

/// `gravity-last` (READINGS.md P9): at g = 1 a lone rest particle falls
/// after propagation, so it ends the step on its own site in channel 4;
/// with gravity before propagation (`default`, `ph94`) it has already moved
/// one row down.
#[test]
fn gravity_last_makes_a_rest_particle_fall_in_place() {
    let p = params(5, 9, false, 0.0, 1.0, 0.0);
    let init = [(2, 4, 1)];
    assert_eq!(
        after_one_step(p, "ph94+gravity-last+wall-move", &init),
        [(2, 4, 1 << 4)]
    );
    for rules in ["default", "ph94", "rest-ahead+gravity-first+wall-move"] {
        assert_eq!(after_one_step(p, rules, &init), [(2, 3, 1 << 4)], "{rules}");
    }
}

/// `inject-down` (READINGS.md P17): at I = 1 on an empty open pipe (p = g
/// = b = 0) one step leaves exactly one down-mover on every site of row L -
/// 2; injecting channels 3, 4, 5 (the default) puts 3 W particles in.
#[test]
fn inject_down_fills_only_the_channel_straight_down() {
    let mut p = params(5, 9, true, 0.0, 0.0, 0.0);
    p.boundary = Boundary::Open { inject: 1.0 };
    let want: Vec<_> = (0..5).map(|x| (x, 7, 1 << 4)).collect();
    for rules in ["default+inject-down", "ph94+inject-down+inject-late"] {
        assert_eq!(after_one_step(p, rules, &[]), want, "{rules}");
    }
    let n = |v: Vec<(usize, usize, u8)>| v.iter().map(|s| s.2.count_ones()).sum::<u32>();
    assert_eq!(n(after_one_step(p, "default", &[])), 15);
}

/// The default includes `inject-late` (MODEL.md A11), which acts only
/// in the open pipe: in the periodic pipe the default runs step for step as
/// `ph94+gravity-first+wall-move`, the earlier default, in both
/// engines, so every periodic figure (among them the blind Figs. 9 and 10)
/// is unchanged by the switch. In the open pipe the two differ.
#[test]
fn the_default_is_the_old_default_in_the_periodic_pipe() {
    let old: Rules = "ph94+gravity-first+wall-move".parse().unwrap();
    assert_ne!(Rules::default(), old);
    for boundary in [Boundary::Periodic, Boundary::Open { inject: 0.4 }] {
        let p = pipe(60, 5, boundary);
        let state = |b: &dyn EngineBuilder, r: Rules| {
            let mut e = b.build(p, r, SEED).unwrap();
            e.run(300).unwrap();
            (0..5)
                .flat_map(|x| (0..60).map(move |y| (x, y)))
                .map(|(x, y)| e.site(x, y))
                .collect::<Vec<u8>>()
        };
        for b in [&Reference as &dyn EngineBuilder, &Fast] {
            let same = state(b, Rules::default()) == state(b, old);
            assert_eq!(same, boundary == Boundary::Periodic, "{boundary:?}");
        }
    }
}

/// `inject-late` (READINGS.md P18): a rest particle on the top row, I = 1,
/// `inject-down` and `fhp-rest`, g = 0. Injected at the start of the step,
/// the down-mover meets the rest particle, {0, 4} becomes {3, 5}, and the
/// pair leaves diagonally; injected late, the collision step has passed, the
/// rest particle stays and the down-mover goes straight down.
#[test]
fn inject_late_skips_the_collision_in_the_top_row() {
    let mut p = params(5, 9, true, 0.5, 0.0, 0.0);
    p.boundary = Boundary::Open { inject: 1.0 };
    let init = [(2, 8, 1)];
    let has = |v: &[(usize, usize, u8)], x, y, c: usize| {
        v.iter().any(|s| (s.0, s.1) == (x, y) && s.2 & 1 << c != 0)
    };
    let early = after_one_step(
        p,
        "ph94+gravity-first+wall-move+inject-down+fhp-rest",
        &init,
    );
    assert!(has(&early, 1, 7, 3) && has(&early, 3, 7, 5), "{early:?}");
    assert!(!has(&early, 2, 8, 0) && !has(&early, 2, 7, 4), "{early:?}");
    let late = after_one_step(p, "default+inject-down+fhp-rest", &init);
    assert!(has(&late, 2, 8, 0) && has(&late, 2, 7, 4), "{late:?}");
    assert!(!has(&late, 1, 7, 3) && !has(&late, 3, 7, 5), "{late:?}");
}

/// `fhp-rest` (READINGS.md P4): {rest, up} at (2, 4) becomes {up-left,
/// up-right}, which move to (1, 4) and (3, 4); without it the rest particle
/// stays (g = 0) and the up-mover moves to (2, 5).
#[test]
fn fhp_rest_turns_a_rest_particle_and_a_mover_into_a_pair() {
    let p = params(5, 9, false, 0.5, 0.0, 0.0);
    let init = [(2, 4, 1 | 1 << 1)];
    for rules in [
        "ph94+fhp-rest",
        "default+fhp-rest",
        "rest-ahead+gravity-last+fhp-rest",
    ] {
        assert_eq!(
            after_one_step(p, rules, &init),
            [(1, 4, 1 << 2), (3, 4, 1 << 6)],
            "{rules}"
        );
    }
    assert_eq!(
        after_one_step(p, "default", &init),
        [(2, 4, 1), (2, 5, 1 << 1)]
    );
}

/// `literal-labels` (READINGS.md P1), g = b = 0, at (2, 4): R2 {up,
/// down-left} at p = 0 reverses both movers into {down, up-right} (to (2,
/// 3) and (3, 4)); at p = 1 it leaves a rest particle and the down-right
/// mover (to (3, 3)), the reverse of the pair's momentum. R3 {up,
/// down-left, down-right} at p = 0 rotates into {up-left, down, up-right}.
/// The default reading (MODEL.md A3) keeps both at p = 0 and, at p = 1,
/// sends the R2 pair's momentum on as an up-left mover.
#[test]
fn literal_labels_reverse_r2_and_rotate_r3() {
    let (up, ul, dl, down, dr, ur) = (1 << 1, 1 << 2, 1 << 3, 1 << 4, 1 << 5, 1 << 6);
    let p0 = params(5, 9, false, 0.0, 0.0, 0.0);
    let p1 = params(5, 9, false, 1.0, 0.0, 0.0);
    let r2 = [(2, 4, up | dl)];
    let r3 = [(2, 4, up | dl | dr)];
    for rules in [
        "default+literal-labels",
        "ph94+literal-labels",
        "rest-ahead+gravity-last+fhp-rest+literal-labels",
    ] {
        assert_eq!(
            after_one_step(p0, rules, &r2),
            [(2, 3, down), (3, 4, ur)],
            "{rules}"
        );
        assert_eq!(
            after_one_step(p1, rules, &r2),
            [(2, 4, 1), (3, 3, dr)],
            "{rules}"
        );
        assert_eq!(
            after_one_step(p0, rules, &r3),
            [(1, 4, ul), (2, 3, down), (3, 4, ur)],
            "{rules}"
        );
    }
    assert_eq!(after_one_step(p0, "default", &r2), [(1, 3, dl), (2, 5, up)]);
    assert_eq!(after_one_step(p1, "default", &r2), [(1, 4, ul), (2, 4, 1)]);
    assert_eq!(
        after_one_step(p0, "default", &r3),
        [(1, 3, dl), (2, 5, up), (3, 3, dr)]
    );
}

/// `literal-labels`, R5 at g = 0: {rest, up, down-left} at (2, 4) keeps
/// its rest particle, sends a down-right mover to (3, 3) and one extra rest
/// particle to a neighbour of (2, 4) (the walk of MODEL.md A4, random, so
/// each engine is checked on its own); the default sends an up-left mover
/// to (1, 4) instead.
#[test]
fn literal_labels_r5_reverses_the_pair_and_leaves_an_extra_rest_particle() {
    let p = params(5, 9, false, 0.5, 0.0, 0.0);
    let near = [(2, 5), (2, 3), (1, 4), (1, 3), (3, 4), (3, 3)];
    for (rules, mover) in [
        ("default+literal-labels", (3, 3, 5)),
        ("default", (1, 4, 2)),
    ] {
        for b in [&Reference as &dyn EngineBuilder, &Fast] {
            let mut e = b.build(p, rules.parse().unwrap(), SEED).unwrap();
            for x in 0..5 {
                for y in 0..9 {
                    e.set_site(x, y, 0);
                }
            }
            e.set_site(2, 4, 1 | 1 << 1 | 1 << 3);
            e.run(1).unwrap();
            let what = format!("{rules} {}", b.name());
            assert_eq!(e.site(2, 4) & 1, 1, "{what}");
            assert_ne!(e.site(mover.0, mover.1) & 1 << mover.2, 0, "{what}");
            assert_eq!((e.particle_count(), e.rest_count()), (3, 2), "{what}");
            let placed = near.iter().filter(|&&(x, y)| e.site(x, y) & 1 == 1).count();
            assert_eq!(placed, 1, "{what}");
        }
    }
}

/// `wall-sites` (READINGS.md P12), g = 0: a down-left mover at (1, 4)
/// arrives at the wall site (0, 4) and is reflected there on arrival: into
/// the down-right diagonal at b = 0 (specular), the up-right one at b = 1
/// (bounce-back); the next step takes it back into the pipe, (1, 3) at b =
/// 0. The default wall (MODEL.md A6 with `wall-move`) leaves it heading
/// into the wall in column 0 for a step. The right wall likewise.
#[test]
fn wall_sites_reflect_a_particle_on_arrival() {
    let (dl, dr, ur, ul) = (1 << 3, 1 << 5, 1 << 6, 1 << 2);
    for (b, into_left, into_right) in [(0.0, dr, dl), (1.0, ur, ul)] {
        let p = params(5, 9, false, 0.5, 0.0, b);
        assert_eq!(
            after_one_step(p, "default+wall-sites", &[(1, 4, dl)]),
            [(0, 4, into_left)],
            "b {b}"
        );
        // x = 3 is odd: its down-right neighbour is (4, 4)
        assert_eq!(
            after_one_step(p, "ph94+wall-sites", &[(3, 4, dr)]),
            [(4, 4, into_right)],
            "b {b}"
        );
    }
    let p = params(5, 9, false, 0.5, 0.0, 0.0);
    let mut s = Lockstep::new(p, "default+wall-sites".parse().unwrap(), &[(1, 4, dl)]);
    assert!(s.step(true, "first") && s.step(true, "second"));
    assert_eq!(s.reference.site(1, 3), dr);
    assert_eq!(s.fast.site(1, 3), dr);
    assert_eq!(after_one_step(p, "default", &[(1, 4, dl)]), [(0, 4, dl)]);
}

/// `wall-sites`: gravity does not act at a wall site. Under `any-mover` at
/// g = 1 the up-right mover of the wall site (0, 4) keeps its channel and
/// moves to (1, 4); without wall sites it is turned down-right and moves to
/// (1, 3).
#[test]
fn wall_sites_feel_no_gravity() {
    let p = params(5, 9, false, 0.5, 1.0, 0.0);
    let ur = 1 << 6;
    assert_eq!(
        after_one_step(p, "any-mover+gravity-first+wall-sites", &[(0, 4, ur)]),
        [(1, 4, ur)]
    );
    assert_eq!(
        after_one_step(p, "any-mover+gravity-first", &[(0, 4, ur)]),
        [(1, 3, 1 << 5)]
    );
}

/// `wall-sites` in a pipe of W = 3: R4 at (1, 5) makes two extra rest
/// particles, and the walk of MODEL.md A4 places them in column 1, the only
/// column that is not a wall; the wall columns stay empty. In both engines.
#[test]
fn wall_sites_take_no_rest_particle() {
    let p = params(3, 10, false, 0.5, 0.0, 0.0);
    for b in [&Reference as &dyn EngineBuilder, &Fast] {
        let mut e = b
            .build(p, "default+wall-sites".parse().unwrap(), SEED)
            .unwrap();
        for x in 0..3 {
            for y in 0..10 {
                e.set_site(x, y, 0);
            }
        }
        e.set_site(1, 5, 1 | 1 << 1 | 1 << 4);
        e.run(1).unwrap();
        let rest_in = |x: usize| (0..10).filter(|&y| e.site(x, y) & 1 == 1).count();
        assert_eq!(
            (rest_in(0), rest_in(1), rest_in(2)),
            (0, 3, 0),
            "{}",
            b.name()
        );
        assert_eq!(e.particle_count(), 3);
    }
}

/// `wall-sites`, periodic and open, several readings, both engines: at the
/// end of every step a wall site holds only its two inward diagonals (5 and
/// 6 on the left, 2 and 3 on the right), the periodic pipe conserves its
/// particles and the open pipe balances its books; the start fills each
/// existing moving state with rho W / (6 W - 8), so N(0) is rho W L within
/// five standard deviations.
#[test]
fn wall_sites_hold_only_the_inward_diagonals() {
    for rules in [
        "default+wall-sites",
        "any-mover+rest-up+wall-sites",
        "up-to-rest+fhp-rest+literal-labels+wall-sites",
        "rest-ahead+gravity-last+inject-down+wall-sites",
        "ph94+rest-slide+lane-collide+wall-sites",
    ] {
        let r: Rules = rules.parse().unwrap();
        for boundary in [Boundary::Periodic, Boundary::Open { inject: 0.6 }] {
            let p = pipe(40, 5, boundary);
            for b in [&Reference as &dyn EngineBuilder, &Fast] {
                let mut e = b.build(p, r, SEED).unwrap();
                let n0 = e.particle_count() as i128;
                for t in 0..200 {
                    if let Err(err) = e.run(1) {
                        assert!(
                            granular_automata::pipe::is_validity_limit(err.kind),
                            "{err}"
                        );
                        break;
                    }
                    for x in [0, 4] {
                        for y in 0..40 {
                            let s = e.site(x, y);
                            assert_eq!(
                                s & !r.channels_of_column(x, 5),
                                0,
                                "{rules} {boundary:?} {} step {t}: ({x}, {y}) holds {s:#09b}",
                                b.name()
                            );
                        }
                    }
                    let f = e.flux();
                    let net = f.injected as i128 - f.out_bottom as i128 - f.out_top as i128;
                    assert_eq!(e.particle_count() as i128, n0 + net, "{rules} {}", b.name());
                }
            }
        }
    }
    let p = Params {
        length: 2200,
        rho: 1.5,
        ..Params::default()
    };
    let r: Rules = "default+wall-sites".parse().unwrap();
    for b in [&Reference as &dyn EngineBuilder, &Fast] {
        let e = b.build(p, r, 3).unwrap();
        let mean = 1.5 * p.sites() as f64;
        let q = r.fill_probability(&p);
        let states = (6 * 9 + 4) as f64 * 2200.0;
        let sd = (states * q * (1.0 - q)).sqrt();
        let n = e.particle_count() as f64;
        assert!((n - mean).abs() < 5.0 * sd, "{}: {n} vs {mean}", b.name());
        assert_eq!(e.rest_count(), 0);
        for y in 0..2200 {
            assert_eq!(e.site(0, y) & !0b0110_0000, 0);
            assert_eq!(e.site(10, y) & !0b0000_1100, 0);
        }
    }
}

/// `wall-sites` is refused, with a typed error naming the value, where it
/// cannot run: W < 3 (no column between the walls), rho >= 6 - 8/W, and
/// together with `wall-drag`.
#[test]
fn wall_sites_refuses_what_it_cannot_run() {
    let r: Rules = "default+wall-sites".parse().unwrap();
    for b in [&Reference as &dyn EngineBuilder, &Fast] {
        for w in [1, 2] {
            let e = b
                .build(pipe(40, w, Boundary::Periodic), r, SEED)
                .err()
                .unwrap();
            assert_eq!(e.kind, ErrorKind::InvalidParameter);
            assert!(e.message.contains(&format!("W = {w}")), "{}", e.message);
        }
        let dense = Params {
            rho: 5.4,
            ..Params::default()
        };
        let e = b.build(dense, r, SEED).err().unwrap();
        assert!(e.message.contains("rho = 5.4"), "{}", e.message);
        let open = Params {
            boundary: Boundary::Open { inject: 0.5 },
            ..dense
        };
        assert!(b.build(open, r, SEED).is_ok());
    }
    assert!("default+wall-sites+wall-drag".parse::<Rules>().is_err());
}

/// `lane-collide` (READINGS.md P23, an extension), p = 1, g = b = 0: the
/// down-mover of {3, 4} at (2, 4) has a down-mover below it at (2, 3), so
/// it is deflected into the one free channel, 5, and the pair {3, 5} leaves
/// for (1, 3) and (3, 3); the lower mover has nothing below and falls to
/// (2, 2). Without the extension both down-movers fall. At row 0 the
/// periodic pipe finds the mover of row L-1 below, the open pipe no site.
#[test]
fn lane_collide_deflects_a_down_mover_resting_on_another() {
    let (dl, down, dr) = (1 << 3, 1 << 4, 1 << 5);
    let p = params(5, 9, false, 1.0, 0.0, 0.0);
    let init = [(2, 3, down), (2, 4, dl | down)];
    for rules in [
        "default+lane-collide",
        "ph94+lane-collide",
        "rest-ahead+gravity-last+lane-collide",
    ] {
        assert_eq!(
            after_one_step(p, rules, &init),
            [(1, 3, dl), (2, 2, down), (3, 3, dr)],
            "{rules}"
        );
    }
    assert_eq!(
        after_one_step(p, "default", &init),
        [(1, 3, dl), (2, 2, down), (2, 3, down)]
    );
    let p0 = Params { p: 0.0, ..p };
    assert_eq!(
        after_one_step(p0, "default+lane-collide", &init),
        [(1, 3, dl), (2, 2, down), (2, 3, down)]
    );
    let ends = [(2, 0, dl | down), (2, 8, down)];
    assert_eq!(
        after_one_step(p, "default+lane-collide", &ends),
        [(1, 8, dl), (2, 7, down), (3, 8, dr)]
    );
    let open = params(5, 9, true, 1.0, 0.0, 0.0);
    assert_eq!(
        after_one_step(open, "default+lane-collide", &ends),
        [(2, 7, down)]
    );
    // `lane-collide:q`: q alone decides, whatever p is
    let deflected = [(1, 3, dl), (2, 2, down), (3, 3, dr)];
    let fallen = [(1, 3, dl), (2, 2, down), (2, 3, down)];
    assert_eq!(
        after_one_step(p0, "default+lane-collide:1", &init),
        deflected
    );
    assert_eq!(after_one_step(p, "default+lane-collide:0", &init), fallen);
    assert_eq!(after_one_step(p0, "default+lane-collide:0", &init), fallen);
}

/// `lane-collide:0` draws nothing and changes nothing: a run of it is the
/// default's run, byte for byte, in both engines; `lane-collide:q` at q = p
/// is `lane-collide`, byte for byte.
#[test]
fn lane_collide_at_q_zero_is_the_default_and_at_p_is_lane_collide() {
    let p = params(11, 64, false, 0.5, 0.5, 0.5);
    let run = |rules: &str, fast: bool| {
        let r: Rules = rules.parse().unwrap();
        let mut e = if fast {
            Fast.build(p, r, SEED).unwrap()
        } else {
            Reference.build(p, r, SEED).unwrap()
        };
        for _ in 0..300 {
            e.step().unwrap();
        }
        let sites = (0..p.width).flat_map(|x| (0..p.length).map(move |y| (x, y)));
        sites.map(|(x, y)| e.site(x, y)).collect::<Vec<u8>>()
    };
    for fast in [false, true] {
        assert_eq!(run("default", fast), run("default+lane-collide:0", fast));
        assert_eq!(
            run("default+lane-collide", fast),
            run("default+lane-collide:0.5", fast)
        );
        assert_ne!(run("default", fast), run("default+lane-collide:0.5", fast));
    }
}

/// What `lane-collide` does to the gas (EXPERIMENTS.md "Extensions beyond
/// the text"), at PH94 Fig. 2's set-up (L = 220, W = 11,
/// p = g = b = 0.5, rho = 1) after 20000 steps: the default puts more than 95 % of
/// the movers in channel 4 (one lane); with the extension fewer than half
/// are there. A fast engine that ignored the rule would fail this.
#[test]
fn lane_collide_breaks_the_lane_of_down_movers() {
    let p = Params::default();
    let share = |rules: &str| {
        let mut e = FastPipe::new(p, rules.parse().unwrap(), SEED).unwrap();
        e.run(20_000).unwrap();
        let c = e.channel_counts();
        c[4] as f64 / c[1..].iter().sum::<u64>() as f64
    };
    let (lane, broken) = (share("default"), share("default+lane-collide"));
    assert!(lane > 0.95, "default: {lane}");
    assert!(broken < 0.5, "lane-collide: {broken}");
}

/// `rest-ahead` (READINGS.md P7), g = 1, p = 0: an up-left mover at (2, 4)
/// whose next site (1, 4) holds a rest particle is turned down (2 -> 3) and
/// lands on (1, 3) with the fallen rest particle (which still counts as
/// ahead: the neighbours are read before the gravity moves); under `ph94`
/// it is not turned (its own site holds no rest particle). With the rest
/// particle on (3, 4) instead, not ahead of it, `rest-ahead` leaves it and
/// `any-mover` turns it.
#[test]
fn rest_ahead_turns_only_a_mover_heading_for_a_rest_particle() {
    let p = params(5, 9, false, 0.0, 1.0, 0.0);
    let (up_left, down_left, down) = (1 << 2, 1 << 3, 1 << 4);
    let ahead = [(1, 4, 1), (2, 4, up_left)];
    assert_eq!(
        after_one_step(p, "rest-ahead+gravity-first+wall-move", &ahead),
        [(1, 3, down_left | down)]
    );
    assert_eq!(
        after_one_step(p, "default", &ahead),
        [(1, 3, down), (1, 4, up_left)]
    );
    let aside = [(2, 4, up_left), (3, 4, 1)];
    assert_eq!(
        after_one_step(p, "rest-ahead+gravity-first+wall-move", &aside),
        [(1, 4, up_left), (3, 3, down)]
    );
    assert_eq!(
        after_one_step(p, "any-mover+gravity-first+wall-move", &aside),
        [(1, 3, down_left), (3, 3, down)]
    );
}

/// In the periodic pipe `ph94+gravity-last` runs the sub-steps of
/// `ph94+gravity-first` in the same cycle (collisions, walls, propagation,
/// gravity): the first gravity sub-step of `gravity-first` meets a start
/// without rest particles, moves nothing and draws nothing, so both engines
/// put the particles on the same sites at every step, seed for seed (the
/// channels differ by one gravity sub-step). With `any-mover` the first
/// gravity sub-step draws, and the runs part.
#[test]
fn gravity_last_repeats_gravity_first_in_the_periodic_pipe() {
    let p = Params {
        length: 40,
        width: 5,
        ..Params::default()
    };
    let counts = |e: &dyn PipeEngine| -> Vec<u32> {
        (0..5)
            .flat_map(|x| (0..40).map(move |y| (x, y)))
            .map(|(x, y)| e.site(x, y).count_ones())
            .collect()
    };
    let builders: [&dyn EngineBuilder; 2] = [&Reference, &Fast];
    for b in builders {
        let parted = |first: &str, last: &str| {
            let mut f = b.build(p, first.parse().unwrap(), SEED).unwrap();
            let mut l = b.build(p, last.parse().unwrap(), SEED).unwrap();
            for _ in 0..200 {
                f.step().unwrap();
                l.step().unwrap();
                if counts(f.as_ref()) != counts(l.as_ref()) {
                    return true;
                }
            }
            false
        };
        assert!(
            !parted("default", "ph94+gravity-last+wall-move"),
            "{}",
            b.name()
        );
        assert!(
            parted("any-mover+gravity-first", "any-mover+gravity-last"),
            "{}",
            b.name()
        );
    }
}

/// A full row of rest particles with R5 collisions and `rest-up`: the
/// relocation (MODEL.md A4) places the extras in row-major order.
#[test]
fn rest_up_relocation_matches_site_by_site() {
    for open in [false, true] {
        let p = params(4, 9, open, 1.0, 0.0, 0.0);
        let mut init = vec![];
        for x in 0..4 {
            init.push((x, 3, 0b0000_1011)); // R5 {0, 1, 3}
            init.push((x, 4, 1));
            init.push((x, 6, 0b0001_0011)); // R4 {0, 1, 4}
        }
        let mut s = Lockstep::new(p, "ph94+rest-up".parse().unwrap(), &init);
        assert!(s.step(true, "rest-up"));
    }
}

#[test]
fn the_periodic_pipe_conserves_particles_and_the_open_pipe_balances_its_books() {
    let readings = [
        "ph94",
        "default",
        "up-to-rest+wall-drag+rest-slide+rest-up",
        "any-mover+gravity-first",
    ];
    for (i, rules) in readings.iter().enumerate() {
        for (w, l) in [(1, 10), (2, 30), (11, 70)] {
            for (p, g, b) in [
                (0.5, 0.5, 0.5),
                (0.1, 0.9, 0.2),
                (1.0, 1.0, 1.0),
                (0.0, 0.0, 0.0),
            ] {
                let mut pp = params(w, l, false, p, g, b);
                pp.rho = 1.5;
                let mut e = FastPipe::new(pp, rules.parse().unwrap(), SEED + i as u64).unwrap();
                let n0 = e.particle_count();
                for _ in 0..100 {
                    if e.step().is_err() {
                        break; // RestExceedsSites at p = 1: tested below
                    }
                    assert_eq!(e.particle_count(), n0, "{rules} W {w} L {l} p {p}");
                }
                pp.boundary = Boundary::Open { inject: 0.7 };
                let mut e = FastPipe::new(pp, rules.parse().unwrap(), SEED + i as u64).unwrap();
                for _ in 0..200 {
                    if e.step().is_err() {
                        break;
                    }
                    // the open pipe starts empty: injected - out = N
                    let f = e.flux();
                    let n = e.particle_count();
                    assert_eq!(
                        f.injected,
                        n + f.out_bottom + f.out_top,
                        "{rules} W {w} L {l} p {p}"
                    );
                    assert_eq!(e.channel_counts().iter().sum::<u64>(), n);
                    assert_eq!(e.moving_count() + e.rest_count(), n);
                }
                assert!(e.flux().injected > 0);
            }
        }
    }
}

#[test]
fn observables_of_one_state_agree() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(SEED + 1);
    for (w, l, bin) in [(11, 220, 10), (3, 130, 13), (2, 64, 64), (1, 5, 1)] {
        let p = Params {
            width: w,
            length: l,
            bin,
            ..Params::default()
        };
        let mut r = Pipe::new(p, Rules::default(), 1).unwrap();
        let mut f = FastPipe::new(p, Rules::default(), 1).unwrap();
        for x in 0..w {
            for y in 0..l {
                let s = (rng.next_u32() & 0x7f) as u8;
                r.set_site(x, y, s);
                f.set_site(x, y, s | 0x80); // the high bit is ignored
            }
        }
        let (mut a, mut b) = (vec![0.0; p.bins()], vec![0.0; p.bins()]);
        r.fill_bin_counts(&mut a);
        f.fill_bin_counts(&mut b);
        assert_eq!(a, b);
        for i in 0..p.bins() {
            assert_eq!(PipeEngine::bin_count(&f, i), r.bin_count(i));
        }
        assert_eq!(f.channel_counts(), r.channel_counts());
        assert_eq!(f.particle_count(), r.particle_count());
        assert_eq!(f.moving_count(), r.moving_count());
        assert_eq!(f.rest_count(), r.rest_count());
    }
}

#[test]
fn bad_input_gives_the_reference_errors() {
    let good = Params::default();
    let bad = [
        Params { length: 25, ..good },
        Params { rho: 6.0, ..good },
        Params { width: 0, ..good },
        Params { p: 1.5, ..good },
        Params {
            g: f64::NAN,
            ..good
        },
        Params {
            boundary: Boundary::Open { inject: -0.1 },
            ..good
        },
    ];
    for p in bad {
        let r = Pipe::new(p, Rules::default(), 1).unwrap_err();
        let f = Fast.build(p, Rules::default(), 1).err().expect("rejected");
        assert_eq!((f.kind, f.message), (r.kind, r.message));
    }
    let mut f = FastPipe::new(good, Rules::default(), 1).unwrap();
    assert_eq!(f.set_p(1.01).unwrap_err().kind, ErrorKind::InvalidParameter);
    f.set_p(0.25).unwrap();
    assert_eq!(f.params().p, 0.25);
    assert_eq!(Fast.name(), "fast");
    assert!(Fast.hopper().is_none());
}

#[test]
#[should_panic(expected = "outside the pipe")]
fn a_site_outside_the_pipe_panics() {
    FastPipe::new(Params::default(), Rules::default(), 1)
        .unwrap()
        .site(11, 0);
}

/// More rest particles than sites (MODEL.md A4): the same typed error.
#[test]
fn too_many_rest_particles_stop_the_run() {
    let p = params(1, 2, false, 0.5, 0.0, 0.0);
    let mut f = FastPipe::new(p, Rules::MODEL_MD, 1).unwrap();
    f.set_site(0, 0, 0b0001_0011); // R4: three rest particles
    let e = f.step().unwrap_err();
    assert_eq!(e.kind, ErrorKind::RestExceedsSites, "{e}");
    assert!(e.message.contains("3 rest particles for 2 sites"), "{e}");
}

/// The walk's bound (MODEL.md A4), as `relocation_walk_gets_stuck` of the
/// reference: one free site 20000 rows away in a column of rest particles.
#[test]
fn the_relocation_walk_is_bounded() {
    let l = 40_000;
    let p = Params {
        bin: 1,
        ..params(1, l, true, 0.5, 0.0, 0.5)
    };
    let mut f = FastPipe::new(p, Rules::MODEL_MD, SEED).unwrap();
    for y in 0..l {
        f.set_site(0, y, 1);
    }
    f.set_site(0, l / 2, 0);
    f.set_site(0, 0, 1 | (1 << 1) | (1 << 3)); // R5
    let e = f.step().unwrap_err();
    assert_eq!(e.kind, ErrorKind::RelocationStuck, "{e}");
}

/// Runs are pure functions of (parameters, rules, seed).
#[test]
fn runs_repeat_and_seeds_differ() {
    let p = Params {
        length: 100,
        ..Params::default()
    };
    let run = |seed| {
        let mut f = FastPipe::new(p, Rules::default(), seed).unwrap();
        f.run(300).unwrap();
        (0..11)
            .flat_map(|x| (0..100).map(move |y| (x, y)))
            .map(|(x, y)| f.site(x, y))
            .collect::<Vec<u8>>()
    };
    assert_eq!(run(5), run(5));
    assert_ne!(run(5), run(6));
}

/// Every reading runs and conserves particles (in the open pipe: injected -
/// out = N(t) - N(0)); the one invalid combination, `gravity-first` with
/// `gravity-last`, is refused with a typed error.
#[test]
fn every_reading_is_supported() {
    for gravity in [
        GravityWording::Ph94,
        GravityWording::AnyMover,
        GravityWording::UpToRest,
        GravityWording::RestAhead,
    ] {
        for flags in 0..1024u32 {
            let rules = Rules {
                gravity,
                wall_drag: flags & 1 != 0,
                gravity_first: flags & 2 != 0,
                rest: if flags & 4 != 0 {
                    RestPlacement::RestUp
                } else {
                    RestPlacement::RandomWalk
                },
                wall_move: flags & 8 != 0,
                rest_slide: flags & 16 != 0,
                gravity_last: flags & 32 != 0,
                fhp_rest: flags & 64 != 0,
                inject_down: flags & 128 != 0,
                inject_late: flags & 256 != 0,
                lane_collide: if flags & 512 != 0 {
                    LaneCollide::AtP
                } else {
                    LaneCollide::Off
                },
                ..Rules::MODEL_MD
            };
            if rules.gravity_first && rules.gravity_last {
                let e = Fast.build(Params::default(), rules, SEED).err().unwrap();
                assert!(e.message.contains("gravity-last"), "{}", e.message);
                continue;
            }
            for boundary in [Boundary::Periodic, Boundary::Open { inject: 0.5 }] {
                let p = pipe(40, 5, boundary);
                let mut e = Fast.build(p, rules, SEED).unwrap();
                let n = e.particle_count() as i128;
                e.run(50).unwrap();
                let f = e.flux();
                let net = f.injected as i128 - f.out_bottom as i128 - f.out_top as i128;
                assert_eq!(e.particle_count() as i128, n + net, "{rules} {boundary:?}");
            }
        }
    }
}

/// Site updates per second of both engines at W = 11, rho = 1, p = g = b =
/// 0.5, default rules, one thread (the target: at least 4 times the
/// reference). `cargo test --release --test fast_engine -- --ignored --nocapture`
#[test]
#[ignore]
fn speed_against_the_reference() {
    use std::time::Instant;
    for (length, steps) in [(220usize, 20_000u64), (2200, 2_000)] {
        let p = Params {
            length,
            ..Params::default()
        };
        let sites = p.sites() as f64 * steps as f64;
        let rate = |e: &mut dyn PipeEngine| {
            e.run(2000).unwrap();
            let t = Instant::now();
            e.run(steps).unwrap();
            sites / t.elapsed().as_secs_f64()
        };
        let r = rate(&mut Pipe::new(p, Rules::default(), 1).unwrap());
        let f = rate(&mut FastPipe::new(p, Rules::default(), 1).unwrap());
        println!(
            "L = {length}: reference {:.3e}, fast {:.3e} site updates/s, ratio {:.2}",
            r,
            f,
            f / r
        );
    }
}
