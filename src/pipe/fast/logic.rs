//! The site rules of MODEL.md A3, A5 and A6 as Boolean operations on the
//! channel words of 64 sites ([`Word`]). Pure functions: the random
//! decisions come in as masks (lanes where the event happened), so that the
//! tests below can check every state against the reference's tables.

use super::grid::Word;
use crate::pipe::GravityWording;

/// The lanes of 64 sites that match each collision rule of MODEL.md A3
/// ("exactly" these channels, so the classes are disjoint).
#[derive(Debug, Clone, Copy, Default)]
pub struct Classes {
    /// R1: a head-on pair {c, c+3}, no rest particle.
    pub r1: u64,
    /// R2: a pair {c, c+2}, no rest particle.
    pub r2: u64,
    /// R3: {1, 3, 5} and {2, 4, 6}, no rest particle.
    pub r3: [u64; 2],
    /// R4: {0, c, c+3}.
    pub r4: u64,
    /// R5: {0, c, c+2}.
    pub r5: u64,
    /// `fhp-rest` (READINGS.md P4, only when named): {0, c}.
    pub fhp: u64,
}

impl Classes {
    /// Lanes of R3 (they need the three-way draw).
    pub fn any_r3(&self) -> u64 {
        self.r3[0] | self.r3[1]
    }
    /// Lanes matching any rule.
    pub fn any(&self) -> u64 {
        self.r1 | self.r2 | self.any_r3() | self.r4 | self.r5 | self.fhp
    }
}

/// The number of moving particles of each lane, as its three bit planes.
fn mover_count(s: &Word) -> [u64; 3] {
    let full_add = |a: u64, b: u64, c: u64| (a ^ b ^ c, (a & b) | (c & (a ^ b)));
    let (a, ca) = full_add(s[1], s[2], s[3]);
    let (b, cb) = full_add(s[4], s[5], s[6]);
    let (ones, c0) = (a ^ b, a & b);
    let (twos, fours) = full_add(ca, cb, c0);
    [ones, twos, fours]
}

/// For each mover channel c = 1..=6 (index c - 1): the channels c-1, c-2
/// and c+1, and which of the head-on pairs {1, 4}, {2, 5}, {3, 6} holds c.
const AROUND: [[usize; 4]; 6] = [
    [6, 5, 2, 0],
    [1, 6, 3, 1],
    [2, 1, 4, 2],
    [3, 2, 5, 0],
    [4, 3, 6, 1],
    [5, 4, 1, 2],
];

/// Classify 64 sites by the rule of MODEL.md A3 they match, with the
/// rest-particle collision {0, c} of `fhp-rest` when `fhp_rest` is set.
#[inline]
pub fn classify(s: &Word, fhp_rest: bool) -> Classes {
    let [ones, twos, fours] = mover_count(s);
    let two = !ones & twos & !fours;
    let three = ones & twos & !fours;
    // with exactly two movers: a head-on pair {c, c+3} or a pair {c, c+2}
    let head_on = two & ((s[1] & s[4]) | (s[2] & s[5]) | (s[3] & s[6]));
    let skew = two
        & ((s[1] & s[3])
            | (s[2] & s[4])
            | (s[3] & s[5])
            | (s[4] & s[6])
            | (s[5] & s[1])
            | (s[6] & s[2]));
    let (rest, none) = (s[0], !s[0]);
    Classes {
        r1: head_on & none,
        r2: skew & none,
        r3: [
            three & s[1] & s[3] & s[5] & none,
            three & s[2] & s[4] & s[6] & none,
        ],
        r4: head_on & rest,
        r5: skew & rest,
        fhp: if fhp_rest {
            ones & !twos & !fours & rest
        } else {
            0
        },
    }
}

/// The random decisions of one collision step, as lane masks.
#[derive(Debug, Clone, Copy, Default)]
pub struct Decisions {
    /// R1 lanes that rotate by +60 degrees ({c+1, c+4}, outcome 0 of the
    /// table); the others rotate by +120 degrees.
    pub r1: u64,
    /// R2 lanes that dissipate.
    pub r2: u64,
    /// R3: lanes whose uniform U lies below the cumulative threshold of
    /// outcome k = 0, 1, 2 ({0, c+k, c+k+3}); nested (r3\[0\] within r3\[1\]
    /// within r3\[2\]); lanes outside r3\[2\] are unchanged.
    pub r3: [u64; 3],
}

/// The result of the collision step on 64 sites.
#[derive(Debug, Clone, Copy)]
pub struct Collided {
    /// The new channel words.
    pub state: Word,
    /// Lanes that leave one extra rest particle (R5).
    pub one_extra: u64,
    /// Lanes that leave two extra rest particles (R4).
    pub two_extras: u64,
}

/// The dissipative outcomes of R3 on 64 sites: per head-on pair {1, 4},
/// {2, 5}, {3, 6}, the lanes of R3 that stop into it (outcome j of {c,
/// c+2, c+4} is the pair {c+j, c+j+3}, drawn by `d.r3`); 0 without R3.
#[inline]
fn r3_pairs(k: &Classes, d: &Decisions) -> [u64; 3] {
    if k.any_r3() == 0 {
        return [0; 3];
    }
    let j = [d.r3[0], d.r3[1] & !d.r3[0], d.r3[2] & !d.r3[1]];
    let [a, b] = k.r3;
    [
        (a & j[0]) | (b & j[2]),
        (a & j[1]) | (b & j[0]),
        (a & j[2]) | (b & j[1]),
    ]
}

/// The collision step of MODEL.md A3 on 64 sites of classes `k`, written
/// on whole sets of movers: R1 rotates the pair by +60 or +120 degrees
/// (new c = old c-1 or old c-2); R2 (dissipating) and R5 leave the rest
/// particle and the mover between the two (new c = old c-1 and old c+1);
/// R3 leaves the rest particle and the head-on pair of its outcome; R4 the
/// rest particle alone.
#[inline]
pub fn collide(s: &Word, k: &Classes, d: &Decisions) -> Collided {
    let (turn1, turn2) = (k.r1 & d.r1, k.r1 & !d.r1);
    let middle = (k.r2 & d.r2) | k.r5;
    let pairs = r3_pairs(k, d);
    let r3 = pairs[0] | pairs[1] | pairs[2];
    let changed = k.r1 | k.r4 | middle | r3 | k.fhp;
    let mut state = [0u64; 7];
    state[0] = (s[0] & !k.fhp) | middle | r3;
    for (c, &[before, twice_before, after, pair]) in AROUND.iter().enumerate() {
        let c = c + 1;
        state[c] = (s[c] & !changed)
            | (turn1 & s[before])
            | (turn2 & s[twice_before])
            | (middle & s[before] & s[after])
            | (k.fhp & (s[before] | s[after]))
            | pairs[pair];
    }
    Collided {
        state,
        one_extra: k.r5,
        two_extras: k.r4,
    }
}

/// Channel `c + k` (mod 6 on 1..=6) of mover channel `c`.
const fn turn(c: usize, k: usize) -> usize {
    (c - 1 + k) % 6 + 1
}

/// The collision step of `literal-labels` (READINGS.md P1: the indices of
/// \[PH94 (1)-(5)\] read as velocities on both sides) on 64 sites of classes
/// `k`, with the same classes and draws as [`collide`]: R1, R4 and the
/// dissipating outcomes of R3 as there; R2 dissipating and R5 leave the rest
/// particle and the mover opposite the pair's middle (new c = old c+2 and
/// old c+4); R2 otherwise reverses both movers (new c = old c+3); R3
/// otherwise rotates the triple by 60 degrees (new c = old c-1).
#[inline]
pub fn collide_literal(s: &Word, k: &Classes, d: &Decisions) -> Collided {
    let (turn1, turn2) = (k.r1 & d.r1, k.r1 & !d.r1);
    let opposite = (k.r2 & d.r2) | k.r5;
    let reversed = k.r2 & !d.r2;
    let pairs = r3_pairs(k, d);
    let r3 = k.any_r3();
    let stopped = pairs[0] | pairs[1] | pairs[2];
    let rotated = r3 & !stopped;
    let changed = k.r1 | k.r4 | opposite | reversed | r3 | k.fhp;
    let mut state = [0u64; 7];
    state[0] = (s[0] & !k.fhp) | opposite | stopped;
    for c in 1..=6 {
        let before = s[turn(c, 5)];
        let after = s[turn(c, 1)];
        state[c] = (s[c] & !changed)
            | (turn1 & before)
            | (turn2 & s[turn(c, 4)])
            | (opposite & s[turn(c, 2)] & s[turn(c, 4)])
            | (reversed & s[turn(c, 3)])
            | (rotated & before)
            | (k.fhp & (before | after))
            | pairs[(c - 1) % 3];
    }
    Collided {
        state,
        one_extra: k.r5,
        two_extras: k.r4,
    }
}

/// The gravity moves of MODEL.md A5 possible on 64 sites (each an
/// independent draw with probability g), or, after the draws, those made.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Moves {
    /// 0 -> 4: a rest particle falls.
    pub fall: u64,
    /// 2 -> 3: an up-left mover turns down.
    pub turn2: u64,
    /// 6 -> 5: an up-right mover turns down.
    pub turn6: u64,
    /// 1 -> 0: an up-mover stops (`up-to-rest` only).
    pub stop: u64,
}

/// The moves of MODEL.md A5 possible on 64 sites under `wording`, from
/// the state before gravity; each only into an empty channel.
pub fn gravity_moves(s: &Word, wording: GravityWording) -> Moves {
    let turning = match wording {
        GravityWording::Ph94 => s[0], // only at a site holding a rest particle
        // `rest-ahead`: the turns the state allows; the engine keeps those
        // with a rest particle ahead (neighbours are not in the word)
        GravityWording::AnyMover | GravityWording::UpToRest | GravityWording::RestAhead => u64::MAX,
    };
    Moves {
        fall: s[0] & !s[4],
        turn2: turning & s[2] & !s[3],
        turn6: turning & s[6] & !s[5],
        stop: if wording == GravityWording::UpToRest {
            s[1] & !s[0]
        } else {
            0
        },
    }
}

/// Apply the gravity moves `m` (disjoint in the channels they empty and
/// fill: 0 -> 4 needs a rest particle, 1 -> 0 its absence).
pub fn apply_moves(s: &Word, m: &Moves) -> Word {
    let mut n = *s;
    n[0] = (n[0] & !m.fall) | m.stop;
    n[4] |= m.fall;
    n[2] &= !m.turn2;
    n[3] |= m.turn2;
    n[6] &= !m.turn6;
    n[5] |= m.turn6;
    n[1] &= !m.stop;
    n
}

/// `rest-slide` (MODEL.md A5): lanes whose rest particle was blocked by an
/// occupied channel 4 before gravity (`before`) and that have a diagonal 3
/// or 5 free after the moves (`after`).
pub fn slide_candidates(before: &Word, after: &Word) -> u64 {
    before[0] & before[4] & !(after[3] & after[5])
}

/// Lanes of `slid` with both diagonals free (they need a fair coin).
pub fn slide_choices(after: &Word, slid: u64) -> u64 {
    slid & !after[3] & !after[5]
}

/// The rest particle of the lanes `slid` moves down a free diagonal: where
/// both are free, to 5 where `coin` is set, else to 3.
pub fn apply_slide(after: &Word, slid: u64, coin: u64) -> Word {
    let (free3, free5) = (!after[3], !after[5]);
    let mut n = *after;
    n[0] &= !slid;
    n[5] |= slid & free5 & (!free3 | coin);
    n[3] |= slid & free3 & (!free5 | !coin);
    n
}

/// The wall rule of MODEL.md A6 for the two channels heading into a wall,
/// `first` and `second` (left wall: 2 and 3, right wall: 6 and 5), with
/// bounce-back in the lanes `bounce` (drawn for lone particles only).
/// Returns the reflected channels (left wall: 5 and 6, right wall: 3 and
/// 2): a lone first goes to the first on bounce-back, else to the second; a
/// lone second the other way round; a pair fills both.
pub fn reflect(first: u64, second: u64, bounce: u64) -> (u64, u64) {
    let both = first & second;
    let lone_first = first & !second;
    let lone_second = second & !first;
    (
        both | (lone_first & bounce) | (lone_second & !bounce),
        both | (lone_first & !bounce) | (lone_second & bounce),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipe::collision::{bit, CollisionTable};
    use crate::pipe::fast::CollisionThresholds;

    /// Words holding the 128 states: lane j of word h is state 64 h + j.
    fn all_states() -> [Word; 2] {
        let mut w = [[0u64; 7]; 2];
        for s in 0..128usize {
            for (c, p) in w[s / 64].iter_mut().enumerate() {
                *p |= (((s >> c) & 1) as u64) << (s % 64);
            }
        }
        w
    }

    fn lane(w: &Word, j: usize) -> u8 {
        (0..7).fold(0u8, |s, c| s | (((w[c] >> j) & 1) as u8) << c)
    }

    #[test]
    fn every_state_collides_as_the_table_says_for_every_uniform_draw() {
        for (p, name) in [0.0, 1e-12, 0.1, 0.5, 0.9, 1.0].into_iter().flat_map(|p| {
            [
                "ph94",
                "ph94+fhp-rest",
                "ph94+literal-labels",
                "ph94+fhp-rest+literal-labels",
            ]
            .map(|n| (p, n))
        }) {
            let rules: crate::pipe::Rules = name.parse().unwrap();
            let (fhp_rest, literal) = (rules.fhp_rest, rules.literal_labels);
            let table = CollisionTable::for_rules(p, rules);
            let t = CollisionThresholds::new(&table);
            // every boundary of every cumulative threshold, and the ends
            let mut us: Vec<u64> = vec![0, (1 << 32) - 1];
            for e in &table.entries {
                for &c in &e.cumulative {
                    us.extend([c.saturating_sub(1), c.min((1 << 32) - 1)]);
                }
            }
            for u in us {
                let lt = |t: u64| if u < t { u64::MAX } else { 0 };
                let d = Decisions {
                    r1: lt(t.r1),
                    r2: lt(t.r2),
                    r3: [lt(t.r3[0]), lt(t.r3[1]), lt(t.r3[2])],
                };
                for (h, w) in all_states().iter().enumerate() {
                    let k = classify(w, fhp_rest);
                    let out = if literal {
                        collide_literal(w, &k, &d)
                    } else {
                        collide(w, &k, &d)
                    };
                    for j in 0..64 {
                        let s = 64 * h + j;
                        let e = &table.entries[s];
                        let o = e.outcomes[e.cumulative.iter().position(|&c| u < c).unwrap()];
                        let extra = ((out.one_extra >> j) & 1) + 2 * ((out.two_extras >> j) & 1);
                        assert_eq!(
                            (lane(&out.state, j), extra as u8),
                            (o.state, o.extra),
                            "p {p} {name} u {u} state {s:#09b}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn every_state_falls_as_the_gravity_table_says() {
        for wording in [
            GravityWording::Ph94,
            GravityWording::AnyMover,
            GravityWording::UpToRest,
            GravityWording::RestAhead,
        ] {
            let table = crate::pipe::reference::gravity_table(wording);
            // each subset of the four move kinds drawn true
            for drawn in 0..16u32 {
                let pick = |i: u32| if drawn >> i & 1 == 1 { u64::MAX } else { 0 };
                for (h, w) in all_states().iter().enumerate() {
                    let m = gravity_moves(w, wording);
                    let made = Moves {
                        fall: m.fall & pick(0),
                        turn2: m.turn2 & pick(1),
                        turn6: m.turn6 & pick(2),
                        stop: m.stop & pick(3),
                    };
                    let out = apply_moves(w, &made);
                    for j in 0..64 {
                        let s = (64 * h + j) as u8;
                        let mv = table[s as usize];
                        let mut expect = s;
                        for &(from, to) in &mv.moves[..mv.n as usize] {
                            let kind = match (from, to) {
                                (0, 4) => 0,
                                (2, 3) => 1,
                                (6, 5) => 2,
                                (1, 0) => 3,
                                other => panic!("unknown move {other:?}"),
                            };
                            if drawn >> kind & 1 == 1 {
                                expect = (expect & !bit(from as usize)) | bit(to as usize);
                            }
                        }
                        assert_eq!(lane(&out, j), expect, "{wording:?} state {s:#09b}");
                    }
                }
            }
        }
    }

    #[test]
    fn a_blocked_rest_particle_slides_to_a_free_diagonal() {
        let [lo, hi] = all_states();
        for (h, w) in [lo, hi].iter().enumerate() {
            let cand = slide_candidates(w, w);
            for coin in [0, u64::MAX] {
                let out = apply_slide(w, cand, coin);
                for j in 0..64 {
                    let s = (64 * h + j) as u8;
                    let blocked = s & 0b1_0001 == 0b1_0001;
                    let (f3, f5) = (s & bit(3) == 0, s & bit(5) == 0);
                    let expect = if blocked && (f3 || f5) {
                        let to = match (f3, f5) {
                            (true, true) if coin != 0 => 5,
                            (true, _) => 3,
                            _ => 5,
                        };
                        (s & !1) | bit(to)
                    } else {
                        s
                    };
                    assert_eq!(lane(&out, j), expect, "state {s:#09b}");
                    let both = (slide_choices(w, cand) >> j) & 1 == 1;
                    assert_eq!(both, blocked && f3 && f5);
                }
            }
        }
    }

    #[test]
    fn the_neighbour_table_follows_the_rotations_of_model_a1() {
        use crate::lattice::rotate;
        for (i, row) in AROUND.iter().enumerate() {
            let c = i + 1;
            assert_eq!(row[..3], [rotate(c, 5), rotate(c, 4), rotate(c, 1)]);
            assert_eq!(row[3], (c - 1) % 3);
        }
    }

    #[test]
    fn walls_reflect_as_model_a6() {
        // lanes: lone first, lone second, both, none
        let (first, second) = (0b0101, 0b0110);
        assert_eq!(reflect(first, second, 0b1111), (0b0101, 0b0110));
        assert_eq!(reflect(first, second, 0), (0b0110, 0b0101));
    }
}
