//! The one grading rule of the project (docs/reference/grading.md): every
//! check of every figure binary, the reproduction matrix and `validate`
//! grade a claim with the functions here.
//!
//! A measurement is an [`Estimate`]: the mean of `n` independent runs and its
//! standard error SE. Its half-width is `k SE` with the coverage factor
//! k = max(2, t(0.975, n - 1)) ([`coverage_factor`]): the usual 2 SE for
//! large n, Student's t quantile for small n (4.30 at n = 3). Fewer than
//! [`MIN_RUNS`] runs never decide anything.
//!
//! - A numerical claim "the value is `target`" with a margin Delta fixed
//!   before measuring ([`Claim::Within`], an equivalence test): reproduced
//!   when |d| + k SE <= Delta, not reproduced when |d| - k SE > Delta,
//!   otherwise undecided.
//! - A qualitative claim "the statistic exceeds (falls below) a threshold"
//!   fixed in advance ([`Claim::Above`], [`Claim::Below`]): reproduced when
//!   the whole interval mean +- k SE lies on the claimed side, not reproduced
//!   when it lies wholly on the other side, otherwise undecided.
//!
//! Neither rule has a tolerance that widens with SE: more noise can only move
//! a verdict to undecided, never to reproduced.

use super::stats::student_t_isf;
use serde::{Deserialize, Serialize};

/// Read a number that JSON wrote as `null` (a NaN, e.g. the SE of one run)
/// back as NaN (`#[serde(deserialize_with = ...)]`).
pub fn f64_or_nan<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// Fewer independent runs than this leave every statistical claim undecided.
pub const MIN_RUNS: usize = 3;

/// The grade of one claim.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Verdict {
    /// The measurement agrees with the claim beyond its error.
    Reproduced,
    /// The measurement contradicts the claim beyond its error.
    NotReproduced,
    /// The error is too large (or the runs too few) to decide.
    Undecided,
}

impl Verdict {
    /// The status name used in summary.json (`reproduced`, `not-reproduced`,
    /// `undecided`).
    pub fn status(self) -> &'static str {
        match self {
            Verdict::Reproduced => "reproduced",
            Verdict::NotReproduced => "not-reproduced",
            Verdict::Undecided => "undecided",
        }
    }

    /// One-word label for tables (`yes`, `no`, `?`).
    pub fn label(self) -> &'static str {
        match self {
            Verdict::Reproduced => "yes",
            Verdict::NotReproduced => "no",
            Verdict::Undecided => "?",
        }
    }

    /// The verdict of the opposite claim (e.g. "no waves" from "waves").
    pub fn negate(self) -> Verdict {
        match self {
            Verdict::Reproduced => Verdict::NotReproduced,
            Verdict::NotReproduced => Verdict::Reproduced,
            Verdict::Undecided => Verdict::Undecided,
        }
    }

    /// `Reproduced` when `holds`, else `NotReproduced` (for exact identities).
    pub fn of(holds: bool) -> Verdict {
        if holds {
            Verdict::Reproduced
        } else {
            Verdict::NotReproduced
        }
    }
}

/// What a check compares against (docs/reference/outputs.md, summary.json).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Kind {
    /// Against a value or claim of the paper (named in the check's `source`).
    Published,
    /// Against this code's own earlier measurement: a regression guard, never
    /// a validation.
    Pinned,
    /// An exact identity of the model, e.g. conservation of particles.
    Identity,
}

impl Kind {
    /// Lower-case name as written in summary.json.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Published => "published",
            Kind::Pinned => "pinned",
            Kind::Identity => "identity",
        }
    }
}

/// A measured value: the mean over `n` independent runs and its standard
/// error (the spread over runs divided by sqrt(n)).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Estimate {
    /// Mean over runs.
    pub mean: f64,
    /// Standard error of the mean.
    pub se: f64,
    /// Number of independent runs.
    pub n: usize,
}

impl Estimate {
    /// An estimate from its parts.
    pub fn new(mean: f64, se: f64, n: usize) -> Self {
        Estimate { mean, se, n }
    }

    /// An estimate from a `(mean, standard error)` pair over `n` runs.
    pub fn from((mean, se): (f64, f64), n: usize) -> Self {
        Estimate::new(mean, se, n)
    }

    /// Mean and standard error of the per-run values `xs` (n = xs.len();
    /// SE = NaN for fewer than two values, so nothing is decided on it).
    pub fn of(xs: &[f64]) -> Self {
        let n = xs.len();
        if n == 0 {
            return Estimate::new(f64::NAN, f64::NAN, 0);
        }
        let m = xs.iter().sum::<f64>() / n as f64;
        if n < 2 {
            return Estimate::new(m, f64::NAN, n);
        }
        let var = xs.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n as f64 - 1.0);
        Estimate::new(m, (var / n as f64).sqrt(), n)
    }

    /// The difference self - other of two independent estimates, SEs in
    /// quadrature, n the smaller of the two.
    pub fn minus(self, other: Estimate) -> Self {
        Estimate::new(
            self.mean - other.mean,
            (self.se * self.se + other.se * other.se).sqrt(),
            self.n.min(other.n),
        )
    }

    /// The half-width k SE of the interval the grading uses, or `None` when
    /// the estimate cannot decide (fewer than [`MIN_RUNS`] runs, or a
    /// non-finite mean or SE).
    pub fn half_width(&self) -> Option<f64> {
        let k = coverage_factor(self.n)?;
        (self.mean.is_finite() && self.se.is_finite() && self.se >= 0.0).then_some(k * self.se)
    }
}

/// The coverage factor k = max(2, t(0.975, n - 1)) of an estimate over `n`
/// runs, or `None` for n < [`MIN_RUNS`].
pub fn coverage_factor(n: usize) -> Option<f64> {
    if n < MIN_RUNS {
        return None;
    }
    // t(0.975, df) falls with df and is below 2 from df = 61 on (1.99962):
    // k = 2 there without evaluating t, whose cost grows with df (a check
    // over 10^9 runs must not take seconds; tested below)
    if n > FLOOR_DF {
        return Some(2.0);
    }
    let t = student_t_isf(0.025, n - 1).expect("n - 1 >= 2 degrees of freedom");
    Some(t.max(2.0))
}

/// The fewest degrees of freedom at which t(0.975, df) < 2, so that the
/// coverage factor is the floor 2 from there on.
pub const FLOOR_DF: usize = 61;

/// A claim about one statistic, with its target or threshold fixed before
/// measuring.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase", tag = "test")]
pub enum Claim {
    /// The statistic equals `target` within `margin` (equivalence test).
    Within {
        /// The claimed value.
        target: f64,
        /// The agreement margin Delta, fixed before measuring.
        margin: f64,
    },
    /// The statistic exceeds `threshold`.
    Above {
        /// The threshold, fixed before measuring.
        threshold: f64,
    },
    /// The statistic falls below `threshold`.
    Below {
        /// The threshold, fixed before measuring.
        threshold: f64,
    },
}

impl Claim {
    /// The rule in words, for notes and reports.
    pub fn describe(&self) -> String {
        match *self {
            Claim::Within { target, margin } => format!(
                "equivalence: reproduced if |x - {target}| + k SE <= {margin}, not if |x - {target}| - k SE > {margin}"
            ),
            Claim::Above { threshold } => format!(
                "reproduced if x - k SE > {threshold}, not if x + k SE <= {threshold}"
            ),
            Claim::Below { threshold } => format!(
                "reproduced if x + k SE < {threshold}, not if x - k SE >= {threshold}"
            ),
        }
    }
}

/// The verdict of a claim made of several parts that must all hold (e.g.
/// "waves inside the density window and none outside", "alpha the same at
/// every p > 0"): reproduced when every part is reproduced, not reproduced
/// when any part is not reproduced, otherwise undecided. An empty list is
/// undecided.
pub fn all_of(parts: impl IntoIterator<Item = Verdict>) -> Verdict {
    let (mut n, mut yes) = (0, 0);
    for v in parts {
        n += 1;
        match v {
            Verdict::NotReproduced => return Verdict::NotReproduced,
            Verdict::Reproduced => yes += 1,
            Verdict::Undecided => {}
        }
    }
    if n > 0 && yes == n {
        Verdict::Reproduced
    } else {
        Verdict::Undecided
    }
}

/// Grade `est` against `claim` by the one rule (module docs).
pub fn grade(est: Estimate, claim: Claim) -> Verdict {
    match coverage_factor(est.n) {
        Some(k) => grade_with(est, claim, k),
        None => Verdict::Undecided,
    }
}

/// The one rule with coverage factor `k` in place of [`coverage_factor`]
/// (a look of a sequential design, `super::sequential`): undecided below
/// [`MIN_RUNS`] runs or for a non-finite or negative SE, mean or k.
pub fn grade_with(est: Estimate, claim: Claim, k: f64) -> Verdict {
    let finite = est.mean.is_finite() && est.se.is_finite() && est.se >= 0.0 && k.is_finite();
    if est.n < MIN_RUNS || !finite {
        return Verdict::Undecided;
    }
    let (x, h) = (est.mean, k * est.se);
    match claim {
        Claim::Within { target, margin } => {
            let d = (x - target).abs();
            if d + h <= margin {
                Verdict::Reproduced
            } else if d - h > margin {
                Verdict::NotReproduced
            } else {
                Verdict::Undecided
            }
        }
        Claim::Above { threshold } => {
            if x - h > threshold {
                Verdict::Reproduced
            } else if x + h <= threshold {
                Verdict::NotReproduced
            } else {
                Verdict::Undecided
            }
        }
        Claim::Below { threshold } => grade_with(
            Estimate::new(-x, est.se, est.n),
            Claim::Above {
                threshold: -threshold,
            },
            k,
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Assert the verdict of each (mean, SE, runs) under `claim`.
    fn verdicts(claim: Claim, cases: &[(f64, f64, usize, Verdict)]) {
        for &(m, se, n, want) in cases {
            let got = grade(Estimate::new(m, se, n), claim);
            assert_eq!(got, want, "{m} +- {se} over {n} runs under {claim:?}");
        }
    }

    #[test]
    fn fewer_than_three_runs_never_decide() {
        use Verdict::*;
        let within = Claim::Within {
            target: 1.0,
            margin: 0.1,
        };
        verdicts(
            within,
            &[
                (1.0, 0.0, 1, Undecided),
                (1.0, 0.0, 2, Undecided),
                (1.0, 0.0, 3, Reproduced),
            ],
        );
        assert_eq!(grade(Estimate::of(&[1.0]), within), Undecided);
        assert_eq!(grade(Estimate::of(&[]), within), Undecided);
        verdicts(within, &[(f64::NAN, 0.1, 10, Undecided)]);
    }

    #[test]
    fn coverage_is_student_t_for_small_n_and_two_for_large() {
        assert!((coverage_factor(3).unwrap() - 4.303).abs() < 1e-3);
        assert!((coverage_factor(8).unwrap() - 2.365).abs() < 1e-3);
        assert_eq!(coverage_factor(200).unwrap(), 2.0);
        assert!(coverage_factor(2).is_none());
    }

    /// The shortcut k = 2 from FLOOR_DF degrees of freedom on is the
    /// quantile's own value there, and the factor of any run count costs
    /// no more than a few microseconds (it used to grow with the count:
    /// seconds at 10^8 runs, a hang at 2^63).
    #[test]
    fn coverage_floor_is_exact_and_cheap() {
        let t = |df| student_t_isf(0.025, df).unwrap();
        assert!(t(FLOOR_DF - 1) > 2.0 && t(FLOOR_DF) < 2.0);
        assert!(coverage_factor(FLOOR_DF).unwrap() > 2.0);
        assert_eq!(coverage_factor(FLOOR_DF + 1), Some(2.0));
        for df in [FLOOR_DF, 100, 1000, 10_000] {
            assert!(t(df) < 2.0 && t(df) > 1.959, "df {df}");
        }
        let start = std::time::Instant::now();
        for n in [1usize << 20, 1 << 40, 1 << 63, usize::MAX] {
            assert_eq!(coverage_factor(n), Some(2.0));
            assert_eq!(
                grade(
                    Estimate::new(1.0, 0.1, n),
                    Claim::Within {
                        target: 1.0,
                        margin: 0.1
                    }
                ),
                Verdict::Undecided
            );
        }
        assert!(start.elapsed().as_millis() < 100, "{:?}", start.elapsed());
    }

    #[test]
    fn equivalence_and_thresholds_follow_the_rule() {
        use Verdict::*;
        let c = Claim::Within {
            target: 1.33,
            margin: 0.1,
        };
        #[rustfmt::skip]
        verdicts(c, &[
            // n = 100: k = 2
            (1.30, 0.02, 100, Reproduced), (1.10, 0.02, 100, NotReproduced), (1.10, 0.2, 100, Undecided),
            // more noise never grades better
            (1.25, 0.005, 100, Reproduced), (1.25, 0.04, 100, Undecided), (1.25, 0.08, 100, Undecided),
            // small n widens the interval: 1.30 +- 0.02 at n = 3 (k = 4.3)
            (1.30, 0.02, 3, Undecided),
        ]);
        // the same three cases, one side of the threshold each
        let cases = |above: Verdict, below: Verdict| {
            [
                (10.0, 1.0, 50, above),
                (1.0, 0.2, 50, below),
                (3.0, 1.0, 50, Undecided),
            ]
        };
        verdicts(
            Claim::Above { threshold: 2.0 },
            &cases(Reproduced, NotReproduced),
        );
        verdicts(
            Claim::Below { threshold: 2.0 },
            &cases(NotReproduced, Reproduced),
        );
    }

    #[test]
    fn all_parts_must_hold() {
        use Verdict::*;
        assert_eq!(all_of([Reproduced, Reproduced]), Reproduced);
        assert_eq!(all_of([Reproduced, Undecided]), Undecided);
        assert_eq!(
            all_of([Undecided, NotReproduced, Reproduced]),
            NotReproduced
        );
        assert_eq!(all_of([]), Undecided);
    }

    #[test]
    fn estimates_of_runs() {
        let e = Estimate::of(&[1.0, 2.0, 3.0]);
        assert_eq!((e.mean, e.n), (2.0, 3));
        assert!((e.se - (1.0f64 / 3.0).sqrt()).abs() < 1e-12);
        let d = Estimate::new(3.0, 3.0, 5).minus(Estimate::new(1.0, 4.0, 4));
        assert_eq!((d.mean, d.se, d.n), (2.0, 5.0, 4));
        assert_eq!(Verdict::Reproduced.negate(), Verdict::NotReproduced);
        assert_eq!(
            serde_json::to_string(&Verdict::NotReproduced).unwrap(),
            "\"not-reproduced\""
        );
        assert_eq!(serde_json::to_string(&Kind::Pinned).unwrap(), "\"pinned\"");
    }
}
