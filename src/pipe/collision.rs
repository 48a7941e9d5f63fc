//! The collision rules R1-R5 of MODEL.md A3 as a table: for each of the 128
//! states of a site (bit `c` = channel `c`, bit 0 = rest), the list of
//! outcomes with their probabilities and the number of extra rest particles
//! each outcome leaves for relocation (A4). The notation of \[PH94 (1)-(5)\]
//! is read as MODEL.md A3 reads it (arrival bonds in, velocities out), or
//! with `literal-labels` as velocities on both sides (READINGS.md P1).
//!
//! The table is data: [`CollisionTable::describe`] prints it for checking.

use super::Rules;
use crate::lattice::{rotate, CHANNEL_NAMES};

/// Bit of channel `c` in a site byte.
pub const fn bit(c: usize) -> u8 {
    1 << c
}

/// Mask of the six moving channels.
pub const MOVERS: u8 = 0b0111_1110;
/// Mask of the rest channel.
pub const REST_BIT: u8 = 1;

/// Probability `q` as a threshold for a uniform `u32` draw: the event
/// happens when `draw < threshold` (exact for q = 0 and q = 1).
pub fn threshold(q: f64) -> u64 {
    (q * 4_294_967_296.0).round() as u64
}

/// Which rule of MODEL.md A3 a state matches.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rule {
    /// No rule: the state passes through unchanged.
    None,
    /// R1: head-on pair `{c, c+3}` rotates by +-60 degrees.
    R1,
    /// R2: `{c, c+2}` -> `{0, c+1}` with probability p (dissipation);
    /// with `literal-labels` `{0, c+4}` with p, `{c+3, c+5}` with 1 - p.
    R2,
    /// R3: `{c, c+2, c+4}` -> `{0, c', c'+3}` with probability p; with
    /// `literal-labels` the 1 - p branch is `{c+1, c+3, c+5}`.
    R3,
    /// R4: `{0, c, c+3}` -> three rest particles (two extra).
    R4,
    /// R5: `{0, c, c+2}` -> `{0, c+1}` plus one extra rest particle; with
    /// `literal-labels` `{0, c+4}` plus one.
    R5,
    /// `fhp-rest` (READINGS.md P4, with that rule only): `{0, c}` ->
    /// `{c-1, c+1}` with certainty.
    FhpRest,
}

/// One possible outcome of a collision.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Outcome {
    /// The site's new state (at most one rest particle).
    pub state: u8,
    /// Extra rest particles to relocate (A4): 0, 1 or 2.
    pub extra: u8,
    /// Probability of this outcome.
    pub prob: f64,
}

/// The outcomes of one incoming state.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    /// The rule the state matches.
    pub rule: Rule,
    /// Outcomes with non-zero probability (at least one).
    pub outcomes: Vec<Outcome>,
    /// Cumulative thresholds for a `u32` draw, one per outcome (last = 2^32).
    pub cumulative: Vec<u64>,
}

impl Entry {
    /// True when the state passes through unchanged with certainty.
    pub fn is_identity(&self, state: u8) -> bool {
        self.outcomes.len() == 1 && self.outcomes[0].state == state && self.outcomes[0].extra == 0
    }
}

/// The collision table for a dissipation probability `p` (MODEL.md A3).
#[derive(Debug, Clone)]
pub struct CollisionTable {
    /// Entry of each state 0..128.
    pub entries: Vec<Entry>,
}

fn set(channels: &[usize]) -> u8 {
    channels.iter().fold(0u8, |s, &c| s | bit(c))
}

/// (state, extra rest particles, probability) while the table is built.
type RawOutcome = (u8, u8, f64);

impl CollisionTable {
    /// Build the table of R1-R5 for dissipation probability `p`.
    pub fn new(p: f64) -> Self {
        Self::build(p, false, false)
    }

    /// The table of a rule reading: R1-R5 in the notation it names
    /// (`literal-labels` or not), plus the rest-particle collision of
    /// `fhp-rest` when named.
    pub fn for_rules(p: f64, rules: Rules) -> Self {
        Self::build(p, rules.fhp_rest, rules.literal_labels)
    }

    fn build(p: f64, fhp_rest: bool, literal: bool) -> Self {
        let mut raw: Vec<(Rule, Vec<RawOutcome>)> = (0..128u8)
            .map(|s| (Rule::None, vec![(s, 0, 1.0)]))
            .collect();
        for c in 1..=6 {
            let r = |k| rotate(c, k);
            // R1 {c, c+3} -> {c+1, c+4} or {c+2, c+5}, 1/2 each
            raw[set(&[c, r(3)]) as usize] = (
                Rule::R1,
                vec![(set(&[r(1), r(4)]), 0, 0.5), (set(&[r(2), r(5)]), 0, 0.5)],
            );
            let s2 = set(&[c, r(2)]);
            raw[s2 as usize] = if literal {
                // [PH94 (2)] in velocities: (i, i+2) -> (0, i-2) with p,
                // (i+3, i-1) with 1-p; both reverse the pair's momentum
                (
                    Rule::R2,
                    vec![(set(&[0, r(4)]), 0, p), (set(&[r(3), r(5)]), 0, 1.0 - p)],
                )
            } else {
                // R2 {c, c+2} -> {0, c+1} with p, unchanged with 1-p
                (Rule::R2, vec![(set(&[0, r(1)]), 0, p), (s2, 0, 1.0 - p)])
            };
            // R4 {0, c, c+3} -> three rest particles: one stays, two extra
            raw[set(&[0, c, r(3)]) as usize] = (Rule::R4, vec![(REST_BIT, 2, 1.0)]);
            // R5 {0, c, c+2} -> {0, c+1} plus one extra rest particle; in
            // velocities [PH94 (5)] (i, 0, i+2) -> (0, 0, i-2): {0, c+4}
            let mover = if literal { r(4) } else { r(1) };
            raw[set(&[0, c, r(2)]) as usize] = (Rule::R5, vec![(set(&[0, mover]), 1, 1.0)]);
            if fhp_rest {
                // {0, c} -> {c-1, c+1} with certainty (e_{c-1} + e_{c+1} = e_c)
                raw[set(&[0, c]) as usize] = (Rule::FhpRest, vec![(set(&[r(5), r(1)]), 0, 1.0)]);
            }
        }
        for c in 1..=2 {
            // R3 {c, c+2, c+4} -> {0, c, c+3}, {0, c+1, c+4}, {0, c+2, c+5}: p/3 each
            let r = |k| rotate(c, k);
            let s3 = set(&[c, r(2), r(4)]);
            let mut outs: Vec<(u8, u8, f64)> = (0..3)
                .map(|k| (set(&[0, r(k), r(k + 3)]), 0, p / 3.0))
                .collect();
            // 1-p: unchanged, or in velocities [PH94 (3)] (i+3, i+1, i-1),
            // the other triple (FHP's rotation by 60 degrees)
            let kept = if literal {
                set(&[r(1), r(3), r(5)])
            } else {
                s3
            };
            outs.push((kept, 0, 1.0 - p));
            raw[s3 as usize] = (Rule::R3, outs);
        }
        let entries = raw
            .into_iter()
            .map(|(rule, outs)| {
                let outcomes: Vec<Outcome> = outs
                    .into_iter()
                    .filter(|o| o.2 > 0.0)
                    .map(|(state, extra, prob)| Outcome { state, extra, prob })
                    .collect();
                let mut acc = 0.0;
                let mut cumulative: Vec<u64> = outcomes
                    .iter()
                    .map(|o| {
                        acc += o.prob;
                        threshold(acc)
                    })
                    .collect();
                *cumulative.last_mut().expect("at least one outcome") = 1 << 32;
                Entry {
                    rule,
                    outcomes,
                    cumulative,
                }
            })
            .collect();
        CollisionTable { entries }
    }

    /// Human-readable listing of every state that changes.
    pub fn describe(&self) -> String {
        let mut s = String::from("state -> outcomes (probability, extra rest particles)\n");
        for (state, e) in self.entries.iter().enumerate() {
            if e.is_identity(state as u8) {
                continue;
            }
            s.push_str(&format!("{:?} {} ->", e.rule, names(state as u8)));
            for o in &e.outcomes {
                s.push_str(&format!(
                    " {} ({:.4}, +{})",
                    names(o.state),
                    o.prob,
                    o.extra
                ));
            }
            s.push('\n');
        }
        s
    }
}

/// The channel names of a state, e.g. `{rest, up}`.
pub fn names(state: u8) -> String {
    let v: Vec<&str> = (0..7)
        .filter(|&c| state & bit(c) != 0)
        .map(|c| CHANNEL_NAMES[c])
        .collect();
    format!("{{{}}}", v.join(", "))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lattice::velocity_int;

    fn mass(s: u8) -> u32 {
        s.count_ones()
    }

    fn momentum(s: u8) -> (i32, i32) {
        (1..=6)
            .filter(|&c| s & bit(c) != 0)
            .map(velocity_int)
            .fold((0, 0), |a, v| (a.0 + v.0, a.1 + v.1))
    }

    #[test]
    fn every_outcome_conserves_mass_and_momentum_and_probabilities_sum_to_one() {
        let fhp: Rules = "ph94+fhp-rest".parse().unwrap();
        let tables = [0.0, 0.1, 0.5, 1.0].into_iter().flat_map(|p| {
            [
                (p, CollisionTable::new(p)),
                (p, CollisionTable::for_rules(p, fhp)),
            ]
        });
        for (p, t) in tables {
            for s in 0..128u8 {
                let e = &t.entries[s as usize];
                let total: f64 = e.outcomes.iter().map(|o| o.prob).sum();
                assert!((total - 1.0).abs() < 1e-12, "state {s} p {p}");
                for o in &e.outcomes {
                    assert_eq!(mass(o.state) + o.extra as u32, mass(s), "mass, state {s}");
                    assert_eq!(momentum(o.state), momentum(s), "momentum, state {s}");
                    assert!(o.state < 128);
                }
                assert_eq!(e.cumulative.len(), e.outcomes.len());
                assert_eq!(*e.cumulative.last().unwrap(), 1u64 << 32);
            }
        }
    }

    #[test]
    fn rules_match_the_model_table_and_everything_else_passes_through() {
        let p = 0.3;
        let t = CollisionTable::new(p);
        let mut counts = [0usize; 6];
        for s in 0..128u8 {
            let e = &t.entries[s as usize];
            let movers: Vec<usize> = (1..=6).filter(|&c| s & bit(c) != 0).collect();
            let rest = s & REST_BIT != 0;
            let expected = match (rest, movers.as_slice()) {
                (false, [a, b]) if b - a == 3 => Rule::R1,
                (false, [a, b]) if b - a == 2 || b - a == 4 => Rule::R2,
                (false, [a, b, c]) if b - a == 2 && c - b == 2 => Rule::R3,
                (true, [a, b]) if b - a == 3 => Rule::R4,
                (true, [a, b]) if b - a == 2 || b - a == 4 => Rule::R5,
                _ => Rule::None,
            };
            assert_eq!(e.rule, expected, "state {}", names(s));
            counts[match e.rule {
                Rule::None => 0,
                Rule::R1 => 1,
                Rule::R2 => 2,
                Rule::R3 => 3,
                Rule::R4 => 4,
                Rule::R5 => 5,
                Rule::FhpRest => panic!("fhp-rest in the table of R1-R5"),
            }] += 1;
            match e.rule {
                Rule::None => assert!(e.is_identity(s)),
                Rule::R1 => {
                    assert_eq!(e.outcomes.len(), 2);
                    assert!(e.outcomes.iter().all(|o| o.prob == 0.5 && o.state != s));
                }
                Rule::R2 => {
                    assert_eq!(e.outcomes.len(), 2);
                    assert_eq!(e.outcomes[0].state.count_ones(), 2);
                    assert!(e.outcomes[0].state & REST_BIT != 0);
                    assert_eq!(e.outcomes[0].prob, p);
                    assert_eq!(e.outcomes[1].state, s);
                }
                Rule::R3 => {
                    assert_eq!(e.outcomes.len(), 4);
                    for o in &e.outcomes[..3] {
                        assert!(o.state & REST_BIT != 0);
                        assert!((o.prob - p / 3.0).abs() < 1e-15);
                    }
                }
                Rule::R4 => assert_eq!(
                    e.outcomes,
                    vec![Outcome {
                        state: REST_BIT,
                        extra: 2,
                        prob: 1.0
                    }]
                ),
                Rule::R5 => {
                    assert_eq!(e.outcomes.len(), 1);
                    assert_eq!(e.outcomes[0].extra, 1);
                    assert_eq!(e.outcomes[0].state.count_ones(), 2);
                }
                Rule::FhpRest => unreachable!(),
            }
        }
        // 3 head-on pairs, 6 pairs at 120 degrees, 2 triples, 3 and 6 with rest
        assert_eq!(counts[1..], [3, 6, 2, 3, 6]);
    }

    /// `fhp-rest` changes exactly the six states {0, c}, each into the pair
    /// {c-1, c+1} with certainty: {rest, up} -> {up-left, up-right}; without
    /// it they pass through (the rule can fail: R1-R5 leave them alone).
    #[test]
    fn fhp_rest_splits_a_lone_rest_particle_and_mover_into_a_pair() {
        let base = CollisionTable::new(0.3);
        let fhp = CollisionTable::for_rules(0.3, "default+fhp-rest".parse().unwrap());
        let mut changed = 0;
        for s in 0..128u8 {
            let (a, b) = (&base.entries[s as usize], &fhp.entries[s as usize]);
            if a != b {
                changed += 1;
                assert_eq!(b.rule, Rule::FhpRest);
                assert!(a.is_identity(s), "{}", names(s));
            }
        }
        assert_eq!(changed, 6);
        let e = &fhp.entries[(REST_BIT | bit(1)) as usize];
        assert_eq!(e.outcomes.len(), 1);
        assert_eq!(
            (e.outcomes[0].state, e.outcomes[0].extra),
            (bit(2) | bit(6), 0)
        );
        let e = &fhp.entries[(REST_BIT | bit(4)) as usize];
        assert_eq!(e.outcomes[0].state, bit(3) | bit(5));
    }

    /// `literal-labels` (READINGS.md P1): the rules with velocity labels on
    /// both sides, state by state at c = 1 (up): R1 and R4 as before; R2
    /// {up, down-left} -> {rest, down-right} (p) or {down, up-right} (1 - p);
    /// R3 {up, down-left, down-right} -> the three rest-and-pair outcomes
    /// (p/3 each) or the rotated triple {up-left, down, up-right} (1 - p);
    /// R5 {rest, up, down-left} -> {rest, down-right} and one extra. Mass
    /// is kept everywhere; R2 and R5 reverse the momentum of the movers,
    /// R1, R3 and R4 conserve it; every other state passes through.
    #[test]
    fn literal_labels_read_the_rules_in_velocities_on_both_sides() {
        let p = 0.3;
        let lit: Rules = "default+literal-labels".parse().unwrap();
        let (base, t) = (CollisionTable::new(p), CollisionTable::for_rules(p, lit));
        let out = |s: u8| -> Vec<(u8, u8, f64)> {
            t.entries[s as usize]
                .outcomes
                .iter()
                .map(|o| (o.state, o.extra, o.prob))
                .collect()
        };
        let b = |cs: &[usize]| cs.iter().fold(0u8, |s, &c| s | bit(c));
        assert_eq!(
            out(b(&[1, 4])),
            [(b(&[2, 5]), 0, 0.5), (b(&[3, 6]), 0, 0.5)]
        );
        assert_eq!(
            out(b(&[1, 3])),
            [(b(&[0, 5]), 0, p), (b(&[4, 6]), 0, 1.0 - p)]
        );
        let r3 = out(b(&[1, 3, 5]));
        let states: Vec<u8> = r3.iter().map(|o| o.0).collect();
        assert_eq!(
            states,
            [b(&[0, 1, 4]), b(&[0, 2, 5]), b(&[0, 3, 6]), b(&[2, 4, 6])]
        );
        assert!((r3[3].2 - (1.0 - p)).abs() < 1e-15);
        assert_eq!(out(b(&[2, 4, 6]))[3].0, b(&[1, 3, 5]));
        assert_eq!(out(b(&[0, 1, 4])), [(REST_BIT, 2, 1.0)]);
        assert_eq!(out(b(&[0, 1, 3])), [(b(&[0, 5]), 1, 1.0)]);
        for s in 0..128u8 {
            let (e, e0) = (&t.entries[s as usize], &base.entries[s as usize]);
            assert_eq!(e.rule, e0.rule, "{}", names(s));
            let total: f64 = e.outcomes.iter().map(|o| o.prob).sum();
            assert!((total - 1.0).abs() < 1e-12);
            let m = momentum(s);
            for o in &e.outcomes {
                assert_eq!(mass(o.state) + o.extra as u32, mass(s), "{}", names(s));
                let expect = match e.rule {
                    Rule::R2 | Rule::R5 => (-m.0, -m.1),
                    _ => m,
                };
                assert_eq!(momentum(o.state), expect, "{:?} {}", e.rule, names(s));
            }
            if matches!(e.rule, Rule::None | Rule::R1 | Rule::R4) {
                assert_eq!(e, e0, "{}", names(s));
            }
        }
        // at p = 0 R2 and R3 still act, with certainty
        let t0 = CollisionTable::for_rules(0.0, lit);
        assert_eq!(t0.entries[b(&[1, 3]) as usize].outcomes.len(), 1);
        assert_eq!(
            t0.entries[b(&[1, 3]) as usize].outcomes[0].state,
            b(&[4, 6])
        );
        assert_eq!(
            t0.entries[b(&[1, 3, 5]) as usize].outcomes[0].state,
            b(&[2, 4, 6])
        );
    }

    #[test]
    fn p_zero_makes_r2_and_r3_pass_through_without_a_draw() {
        let t = CollisionTable::new(0.0);
        for s in 0..128u8 {
            let e = &t.entries[s as usize];
            if matches!(e.rule, Rule::R2 | Rule::R3) {
                assert!(e.is_identity(s));
            }
        }
        assert!(CollisionTable::new(0.5)
            .describe()
            .contains("R4 {rest, up, down} -> {rest} (1.0000, +2)"));
    }
}
