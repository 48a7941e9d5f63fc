//! Random draws of the fast engine, 64 lanes at a time (MODEL.md A2: every
//! draw comes from the run's xoshiro256++ generator).
//!
//! The reference decides an event of probability q by a uniform 32-bit
//! number U < t with t = round(q 2^32) ([`super::super::collision::threshold`]).
//! Here every lane of a word has its own U, compared with t bit by bit from
//! the most significant bit, and its bits are drawn only as long as the
//! comparison is undecided: at bit i one random word r gives bit i of the U
//! of every lane. Where t has a 1, lanes whose bit is 0 are below t; where t
//! has a 0, lanes whose bit is 1 are above. Lanes still equal to t when the
//! remaining bits of t are all zero are not below it. The probability of
//! every lane is therefore exactly t / 2^32, as in the reference, and lanes
//! are independent (each depends only on its own bits). q = 1/2 costs one
//! word, a word of lanes that need no decision costs nothing.

use rand::Rng;

/// 2^32: a threshold this large is always met.
const ALWAYS: u64 = 1 << 32;

/// For each threshold `t[k]` (at most 2^32), the lanes of `need[k]` whose
/// uniform 32-bit number U is below it. Each lane has one U for all its
/// comparisons: for increasing thresholds with the same need, the lanes with
/// `t[k-1] <= U < t[k]` take outcome k with probability
/// `(t[k] - t[k-1]) / 2^32`, as `Entry::cumulative` of the reference; with
/// disjoint needs, one draw serves lanes of different thresholds.
pub fn below_each<const N: usize>(rng: &mut impl Rng, t: [u64; N], need: [u64; N]) -> [u64; N] {
    let mut below = [0u64; N];
    // lanes whose U equals t[k] in the bits drawn so far
    let mut open = [0u64; N];
    for k in 0..N {
        if t[k] >= ALWAYS {
            below[k] = need[k];
        } else if t[k] > 0 {
            open[k] = need[k];
        }
    }
    for i in (0..32).rev() {
        let mut undecided = false;
        for k in 0..N {
            if t[k] & ((2u64 << i) - 1) == 0 {
                open[k] = 0; // the rest of t is zero: U >= t
            }
            undecided |= open[k] != 0;
        }
        if !undecided {
            break;
        }
        let r = rng.next_u64();
        for k in 0..N {
            if t[k] >> i & 1 == 1 {
                below[k] |= open[k] & !r;
                open[k] &= r;
            } else {
                open[k] &= !r;
            }
        }
    }
    below
}

/// The lanes of `need` for which an event of probability `t / 2^32` happens
/// ([`below_each`] with one threshold, written out for speed).
#[inline]
pub fn bernoulli(rng: &mut impl Rng, t: u64, need: u64) -> u64 {
    if need == 0 || t == 0 {
        return 0;
    }
    if t >= ALWAYS {
        return need;
    }
    // bits of t below `last` are zero: lanes still equal there are not below
    let last = t.trailing_zeros();
    let (mut below, mut open) = (0u64, need);
    let mut i = 31;
    loop {
        let r = rng.next_u64();
        if t >> i & 1 == 1 {
            below |= open & !r;
            open &= r;
        } else {
            open &= !r;
        }
        if open == 0 || i == last {
            return below;
        }
        i -= 1;
    }
}

/// Independent events of one probability `t / 2^32` for the lanes of `a`
/// and of `b`: one draw for both when they have no lane in common (each
/// lane still gets its own bits), else one each.
#[inline]
pub fn bernoulli_pair(rng: &mut impl Rng, t: u64, a: u64, b: u64) -> (u64, u64) {
    if a & b == 0 {
        let hit = bernoulli(rng, t, a | b);
        (hit & a, hit & b)
    } else {
        (bernoulli(rng, t, a), bernoulli(rng, t, b))
    }
}

/// A fair coin for every lane of `need` (one word).
#[inline]
pub fn coins(rng: &mut impl Rng, need: u64) -> u64 {
    bernoulli(rng, 1 << 31, need)
}

/// A uniform integer in `0..n` (n >= 1), exactly: Lemire's multiply with
/// rejection of the `2^32 mod n` low products that would bias it.
pub fn below(rng: &mut impl Rng, n: u32) -> u32 {
    let first = rng.next_u32();
    below_from(rng, first, n)
}

/// [`below`] when its first draw `first` is already taken: the further
/// draws, if any, come from `rng`.
#[inline]
pub fn below_from(rng: &mut impl Rng, first: u32, n: u32) -> u32 {
    debug_assert!(n >= 1);
    let mut m = first as u64 * n as u64;
    if (m as u32) < n {
        let reject = n.wrapping_neg() % n;
        while (m as u32) < reject {
            m = rng.next_u32() as u64 * n as u64;
        }
    }
    (m >> 32) as u32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipe::collision::threshold;
    use rand::SeedableRng;
    use rand_xoshiro::Xoshiro256PlusPlus;

    #[test]
    fn certain_events_draw_nothing_and_a_half_draws_one_word() {
        let mut a = Xoshiro256PlusPlus::seed_from_u64(3);
        let mut b = a.clone();
        assert_eq!(bernoulli(&mut a, 0, u64::MAX), 0);
        assert_eq!(bernoulli(&mut a, 1 << 32, 0xf0), 0xf0);
        assert_eq!(bernoulli(&mut a, 1 << 31, 0), 0);
        assert_eq!(a, b);
        let m = bernoulli(&mut a, 1 << 31, u64::MAX);
        assert_eq!(m, !b.next_u64());
        assert_eq!(a, b);
        // 3/4 = 0.11b: at most two words
        bernoulli(&mut a, 3 << 30, u64::MAX);
        b.next_u64();
        b.next_u64();
        assert_eq!(a, b);
    }

    #[test]
    fn bernoulli_is_below_each_with_one_threshold() {
        for t in [
            1u64,
            3,
            1 << 20,
            threshold(0.3),
            threshold(0.5),
            (1 << 32) - 1,
        ] {
            for need in [1u64, 0x8000_0000_0000_0001, u64::MAX] {
                let mut a = Xoshiro256PlusPlus::seed_from_u64(t ^ need);
                let mut b = a.clone();
                for _ in 0..100 {
                    assert_eq!(
                        bernoulli(&mut a, t, need),
                        below_each(&mut b, [t], [need])[0]
                    );
                    assert_eq!(a, b);
                }
            }
        }
    }

    #[test]
    fn disjoint_needs_share_a_draw_and_overlapping_ones_do_not() {
        let mut a = Xoshiro256PlusPlus::seed_from_u64(8);
        let mut b = a.clone();
        let (x, y) = bernoulli_pair(&mut a, 1 << 31, 0x0f, 0xf0);
        let r = !b.next_u64();
        assert_eq!((x, y), (r & 0x0f, r & 0xf0));
        let (x, y) = bernoulli_pair(&mut a, 1 << 31, 0x0f, 0x3c);
        assert_eq!((x, y), (!b.next_u64() & 0x0f, !b.next_u64() & 0x3c));
        assert_eq!(a, b);
    }

    #[test]
    fn frequencies_match_the_thresholds() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(11);
        let t = [threshold(0.1 / 3.0), threshold(0.2 / 3.0), threshold(0.1)];
        let words = 20_000u64;
        let mut hits = [0u64; 3];
        let mut lone = 0u64;
        for _ in 0..words {
            let m = below_each(&mut rng, t, [u64::MAX; 3]);
            for k in 0..3 {
                hits[k] += m[k].count_ones() as u64;
                if k > 0 {
                    assert_eq!(m[k - 1] & !m[k], 0, "monotone");
                }
            }
            lone += bernoulli(&mut rng, threshold(0.3), 0x5555).count_ones() as u64;
            assert_eq!(bernoulli(&mut rng, threshold(0.3), 0x5555) & !0x5555, 0);
        }
        let n = (words * 64) as f64;
        for k in 0..3 {
            let q = t[k] as f64 / 4_294_967_296.0;
            let z = (hits[k] as f64 - n * q) / (n * q * (1.0 - q)).sqrt();
            assert!(z.abs() < 5.0, "threshold {k}: z = {z}");
        }
        let n = (words * 8) as f64;
        let z = (lone as f64 - 0.3 * n) / (n * 0.21).sqrt();
        assert!(z.abs() < 5.0, "z = {z}");
    }

    #[test]
    fn below_is_uniform() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(5);
        for n in 1..=6u32 {
            let mut seen = vec![0u32; n as usize];
            for _ in 0..6000 {
                seen[below(&mut rng, n) as usize] += 1;
            }
            let e = 6000.0 / n as f64;
            assert!(seen.iter().all(|&s| (s as f64 - e).abs() < 6.0 * e.sqrt()));
        }
    }
}
