//! The site rules of MODEL.md A3, A5 and A6 as Boolean operations on the
//! channel words of 64 sites ([`Word`]). Pure functions: the random
//! decisions come in as masks (lanes where the event happened), so that the
//! tests below can check every state against the reference's tables.

use super::grid::Word;
use crate::pipe::GravityWording;

/// The lanes of 64 sites that match each collision rule of MODEL.md A3
/// (each lane matches at most one pattern: "exactly" these channels).
#[derive(Debug, Clone, Copy, Default)]
pub struct Classes {
    /// R1 {c, c+3}, no rest particle, c = 1..=3.
    pub r1: [u64; 3],
    /// R2 {c, c+2}, no rest particle, c = 1..=6.
    pub r2: [u64; 6],
    /// R3 {c, c+2, c+4}, no rest particle, c = 1..=2.
    pub r3: [u64; 2],
    /// R4 {0, c, c+3}, c = 1..=3.
    pub r4: [u64; 3],
    /// R5 {0, c, c+2}, c = 1..=6.
    pub r5: [u64; 6],
}

fn or(masks: &[u64]) -> u64 {
    masks.iter().fold(0, |a, &m| a | m)
}

impl Classes {
    /// Lanes of R1 (they need a fair choice).
    pub fn any_r1(&self) -> u64 {
        or(&self.r1)
    }
    /// Lanes of R2 (they need a draw with probability p).
    pub fn any_r2(&self) -> u64 {
        or(&self.r2)
    }
    /// Lanes of R3 (they need the three-way draw).
    pub fn any_r3(&self) -> u64 {
        or(&self.r3)
    }
    /// Lanes matching any rule.
    pub fn any(&self) -> u64 {
        self.any_r1() | self.any_r2() | self.any_r3() | or(&self.r4) | or(&self.r5)
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

/// Head-on pairs {c, c+3}, c = 1..=3 (R1, R4), with the two R1 outcomes
/// {c+1, c+4} and {c+2, c+5}.
const HEAD_ON: [[usize; 6]; 3] = [[1, 4, 2, 5, 3, 6], [2, 5, 3, 6, 4, 1], [3, 6, 4, 1, 5, 2]];
/// Pairs {c, c+2}, c = 1..=6 (R2, R5), with the mover c+1 of the outcome.
const SKEW: [[usize; 3]; 6] = [
    [1, 3, 2],
    [2, 4, 3],
    [3, 5, 4],
    [4, 6, 5],
    [5, 1, 6],
    [6, 2, 1],
];
/// Triples {c, c+2, c+4}, c = 1, 2 (R3), with the pairs {c+j, c+j+3} of
/// the outcomes j = 0, 1, 2.
const TRIPLE: [([usize; 3], [[usize; 2]; 3]); 2] = [
    ([1, 3, 5], [[1, 4], [2, 5], [3, 6]]),
    ([2, 4, 6], [[2, 5], [3, 6], [4, 1]]),
];

/// Classify 64 sites by the rule of MODEL.md A3 they match.
#[inline]
pub fn classify(s: &Word) -> Classes {
    let [ones, twos, fours] = mover_count(s);
    let two = !ones & twos & !fours;
    let three = ones & twos & !fours;
    let rest = s[0];
    let mut k = Classes::default();
    for (i, &[a, b, ..]) in HEAD_ON.iter().enumerate() {
        let pair = s[a] & s[b] & two;
        k.r1[i] = pair & !rest;
        k.r4[i] = pair & rest;
    }
    for (i, &[a, b, _]) in SKEW.iter().enumerate() {
        let pair = s[a] & s[b] & two;
        k.r2[i] = pair & !rest;
        k.r5[i] = pair & rest;
    }
    for (i, &([a, b, c], _)) in TRIPLE.iter().enumerate() {
        k.r3[i] = s[a] & s[b] & s[c] & three & !rest;
    }
    k
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

/// The collision step of MODEL.md A3 on 64 sites of classes `k`.
#[inline]
pub fn collide(s: &Word, k: &Classes, d: &Decisions) -> Collided {
    let mut add = [0u64; 7];
    let mut changed = 0u64;
    for (i, &[_, _, a, b, c, e]) in HEAD_ON.iter().enumerate() {
        // R1: {c, c+3} -> {c+1, c+4} or {c+2, c+5}
        let (plus, twice) = (k.r1[i] & d.r1, k.r1[i] & !d.r1);
        add[a] |= plus;
        add[b] |= plus;
        add[c] |= twice;
        add[e] |= twice;
        // R4: {0, c, c+3} -> {0} and two extra rest particles
        add[0] |= k.r4[i];
        changed |= k.r1[i] | k.r4[i];
    }
    for (i, &[_, _, m]) in SKEW.iter().enumerate() {
        // R2 (dissipating) and R5 have the same outgoing state {0, c+1}
        let out = (k.r2[i] & d.r2) | k.r5[i];
        add[0] |= out;
        add[m] |= out;
        changed |= out;
    }
    for (i, (_, outcomes)) in TRIPLE.iter().enumerate() {
        // R3: {c, c+2, c+4} -> {0, c+j, c+j+3} for U in [t_{j-1}, t_j)
        let mut lower = 0u64;
        for (j, &[a, b]) in outcomes.iter().enumerate() {
            let out = k.r3[i] & d.r3[j] & !lower;
            lower |= d.r3[j];
            add[0] |= out;
            add[a] |= out;
            add[b] |= out;
            changed |= out;
        }
    }
    let mut state = [0u64; 7];
    for (c, v) in state.iter_mut().enumerate() {
        *v = (s[c] & !changed) | add[c];
    }
    Collided {
        state,
        one_extra: or(&k.r5),
        two_extras: or(&k.r4),
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
        GravityWording::AnyMover | GravityWording::UpToRest => u64::MAX,
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
        for p in [0.0, 1e-12, 0.1, 0.5, 0.9, 1.0] {
            let table = CollisionTable::new(p);
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
                    let k = classify(w);
                    let out = collide(w, &k, &d);
                    for j in 0..64 {
                        let s = 64 * h + j;
                        let e = &table.entries[s];
                        let o = e.outcomes[e.cumulative.iter().position(|&c| u < c).unwrap()];
                        let extra = ((out.one_extra >> j) & 1) + 2 * ((out.two_extras >> j) & 1);
                        assert_eq!(
                            (lane(&out.state, j), extra as u8),
                            (o.state, o.extra),
                            "p {p} u {u} state {s:#09b}"
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
        ] {
            let table = crate::pipe::gravity_table(wording);
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
    fn the_pattern_tables_are_the_rotations_of_model_a3() {
        use crate::lattice::rotate;
        for (i, row) in HEAD_ON.iter().enumerate() {
            let c = i + 1;
            assert_eq!(*row, [1, 4, 2, 5, 3, 6].map(|k| rotate(c, k - 1)));
        }
        for (i, row) in SKEW.iter().enumerate() {
            assert_eq!(*row, [0, 2, 1].map(|k| rotate(i + 1, k)));
        }
        for (i, (t, outs)) in TRIPLE.iter().enumerate() {
            let c = i + 1;
            assert_eq!(*t, [0, 2, 4].map(|k| rotate(c, k)));
            for (j, o) in outs.iter().enumerate() {
                assert_eq!(*o, [rotate(c, j), rotate(c, j + 3)]);
            }
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
