//! Maximal overlap of density fields (MODEL.md A9; \[PH95\] sections B and C,
//! Figs. 4 and 5): the shift along the periodic pipe that makes two bin
//! profiles overlap most, the hierarchical alignment and averaging of many
//! fields into one wave profile, and the real-space wave speed from the
//! shift of maximal overlap against the time interval.
//!
//! Conventions: a profile `a` has K bins, bin 0 at the bottom of the pipe.
//! [`shifted`]`(a, s)[i] = a[(i + s) mod K]`, so a pattern that has moved up
//! by `s` bins between `a` and `b` gives `best_shift(a, b) = +s` (up =
//! against gravity). The overlap is the periodic cross-correlation of the
//! mean-subtracted profiles, O(s) = sum_i (a_i - abar) (b_{i+s} - bbar),
//! which has the same maximiser as sum_i a_i b_{i+s} [PH95 eq. 2].
//!
//! ```
//! use granular_automata::pipe::overlap::{best_shift, shifted};
//! let a = vec![0.0, 1.0, 5.0, 1.0, 0.0, 0.0, 0.0, 0.0];
//! let b = shifted(&a, -3); // the bump moved up by 3 bins
//! assert_eq!(best_shift(&a, &b), 3);
//! ```

/// The profile rotated by `s` bins: `out[i] = a[(i + s) mod K]`.
pub fn shifted(a: &[f64], s: i64) -> Vec<f64> {
    let k = a.len() as i64;
    if k == 0 {
        return Vec::new();
    }
    (0..k).map(|i| a[(i + s).rem_euclid(k) as usize]).collect()
}

fn centred(a: &[f64]) -> Vec<f64> {
    let m = a.iter().sum::<f64>() / a.len().max(1) as f64;
    a.iter().map(|v| v - m).collect()
}

/// O(s) for s = 0..K: sum_i (a_i - abar)(b_{(i+s) mod K} - bbar).
pub fn overlaps(a: &[f64], b: &[f64]) -> Vec<f64> {
    assert_eq!(a.len(), b.len(), "profiles of equal length");
    let (a, b) = (centred(a), centred(b));
    let k = a.len();
    (0..k)
        .map(|s| (0..k).map(|i| a[i] * b[(i + s) % k]).sum())
        .collect()
}

/// Add O(s) of (a, b) to `acc` (length K), without allocating centred copies
/// when the caller passes already centred profiles.
pub fn add_overlaps_centred(a: &[f64], b: &[f64], acc: &mut [f64]) {
    let k = a.len();
    for (s, o) in acc.iter_mut().enumerate() {
        let mut sum = 0.0;
        for i in 0..k - s {
            sum += a[i] * b[i + s];
        }
        for i in k - s..k {
            sum += a[i] * b[i + s - k];
        }
        *o += sum;
    }
}

/// Map a shift in 0..K to the signed range (-K/2, K/2].
pub fn signed(s: usize, k: usize) -> i64 {
    let (s, k) = (s as i64, k as i64);
    if s > k / 2 {
        s - k
    } else {
        s
    }
}

/// The argmax of `o` (ties: the lowest index).
pub fn argmax(o: &[f64]) -> usize {
    let mut best = 0;
    for (i, &v) in o.iter().enumerate() {
        if v > o[best] {
            best = i;
        }
    }
    best
}

/// The maximiser of a periodic overlap curve, refined to a fraction of a bin
/// by a parabola through the maximum and its two neighbours; in [0, K).
pub fn refined_argmax(o: &[f64]) -> f64 {
    let k = o.len();
    let j = argmax(o);
    if k < 3 {
        return j as f64;
    }
    let (l, c, r) = (o[(j + k - 1) % k], o[j], o[(j + 1) % k]);
    let den = l - 2.0 * c + r;
    let d = if den < 0.0 {
        (0.5 * (l - r) / den).clamp(-0.5, 0.5)
    } else {
        0.0
    };
    (j as f64 + d).rem_euclid(k as f64)
}

/// The shift of maximal overlap of `b` relative to `a`, signed in
/// (-K/2, K/2]: the number of bins the pattern moved up from `a` to `b`.
pub fn best_shift(a: &[f64], b: &[f64]) -> i64 {
    signed(argmax(&overlaps(a, b)), a.len())
}

/// Hierarchical alignment [PH95 B]: fields are paired (0, 1), (2, 3), ...;
/// the second of each pair is shifted to overlap the first maximally and
/// the two are averaged; the averages are paired again, until one profile
/// remains (an odd one out is carried to the next level unchanged, with its
/// weight). Returns the weighted average profile, in the frame of field 0.
pub fn align_hierarchical(fields: &[Vec<f64>]) -> Vec<f64> {
    assert!(!fields.is_empty(), "at least one field");
    let mut level: Vec<(Vec<f64>, f64)> = fields.iter().map(|f| (f.clone(), 1.0)).collect();
    while level.len() > 1 {
        let mut next = Vec::with_capacity(level.len().div_ceil(2));
        let mut it = level.into_iter();
        while let Some((a, wa)) = it.next() {
            match it.next() {
                Some((b, wb)) => {
                    let s = best_shift(&a, &b);
                    let b = shifted(&b, s);
                    let w = wa + wb;
                    let avg = a
                        .iter()
                        .zip(&b)
                        .map(|(x, y)| (wa * x + wb * y) / w)
                        .collect();
                    next.push((avg, w));
                }
                None => next.push((a, wa)),
            }
        }
        level = next;
    }
    level.pop().expect("one profile").0
}

/// The profile rotated so that its maximum sits at bin K/2.
pub fn centre_on_max(a: &[f64]) -> Vec<f64> {
    let k = a.len();
    let j = argmax(a) as i64;
    shifted(a, j - (k / 2) as i64)
}

/// The shift of maximal overlap s(tau) of a run's fields against the time
/// interval tau = m * (sample spacing), m = 1..=max_lag [PH95 C, Fig. 5]:
/// for each m the overlaps of all pairs (t, t + m) are summed (the
/// two-point correlation of [PH95 eq. 2]), the maximiser is refined to a
/// fraction of a bin ([`refined_argmax`]) and unwrapped so that it changes
/// by less than K/2 from one lag to the next (starting from 0 at m = 0).
/// Returns s(m) in bins for m = 1..=max_lag.
pub fn shift_against_lag(fields: &[Vec<f64>], max_lag: usize) -> Vec<f64> {
    let k = fields[0].len();
    let c: Vec<Vec<f64>> = fields.iter().map(|f| centred(f)).collect();
    let mut out = Vec::with_capacity(max_lag);
    let mut prev = 0.0;
    for m in 1..=max_lag.min(fields.len() - 1) {
        let mut acc = vec![0.0; k];
        for t in 0..fields.len() - m {
            add_overlaps_centred(&c[t], &c[t + m], &mut acc);
        }
        let s = refined_argmax(&acc);
        // unwrap: the representative of s mod K nearest to prev
        let kf = k as f64;
        let s = s + kf * ((prev - s) / kf).round();
        out.push(s);
        prev = s;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bump(k: usize, at: f64, width: f64) -> Vec<f64> {
        (0..k)
            .map(|i| {
                let mut d = (i as f64 - at).abs();
                d = d.min(k as f64 - d);
                10.0 + 5.0 * (-(d * d) / (2.0 * width * width)).exp()
            })
            .collect()
    }

    #[test]
    fn best_shift_finds_a_moved_bump_both_ways() {
        let a = bump(40, 10.0, 2.0);
        assert_eq!(best_shift(&a, &bump(40, 17.0, 2.0)), 7);
        assert_eq!(best_shift(&a, &bump(40, 3.0, 2.0)), -7);
        assert_eq!(best_shift(&a, &bump(40, 38.0, 2.0)), -12, "wraps");
        assert_eq!(shifted(&shifted(&a, 5), -5), a);
    }

    #[test]
    fn refined_shift_is_sub_bin() {
        let a = bump(64, 20.0, 3.0);
        let b = bump(64, 22.4, 3.0);
        let s = refined_argmax(&overlaps(&a, &b));
        assert!((s - 2.4).abs() < 0.15, "{s}");
    }

    #[test]
    fn hierarchical_alignment_recovers_the_bump() {
        // the same bump at 8 positions averages into the unshifted bump
        let fields: Vec<Vec<f64>> = (0..8)
            .map(|j| bump(50, 5.0 + 4.0 * j as f64, 2.0))
            .collect();
        let avg = align_hierarchical(&fields);
        let want = bump(50, 5.0, 2.0);
        for (x, y) in avg.iter().zip(&want) {
            assert!((x - y).abs() < 1e-12);
        }
        let c = centre_on_max(&avg);
        assert_eq!(argmax(&c), 25);
    }

    #[test]
    fn shift_against_lag_is_linear_for_a_travelling_bump() {
        // 0.7 bins per sample, down (negative), wrapping several times
        let fields: Vec<Vec<f64>> = (0..200)
            .map(|t| bump(32, (100.0 - 0.7 * t as f64).rem_euclid(32.0), 2.5))
            .collect();
        let s = shift_against_lag(&fields, 120);
        for (m, v) in s.iter().enumerate() {
            let want = -0.7 * (m + 1) as f64;
            assert!((v - want).abs() < 0.2, "lag {}: {v} vs {want}", m + 1);
        }
    }
}
