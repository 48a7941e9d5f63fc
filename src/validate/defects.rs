//! Parametric mutants of the classes a faster implementation gets wrong
//! (VALIDATION.md "What each level can see"): a defect at the boundaries of
//! its own decomposition, or one that starts late. Each is the reference
//! (or the fast engine) with one defect of a stated size, so that the
//! detection table can measure how large a defect `validate` catches.
//!
//! - `seam*S`, `seam-K*S`: after every step, each site of a seam row in an
//!   even column has its moving particles reversed (channel c to c + 3)
//!   with probability S: a halo exchanged with the wrong orientation. The
//!   seam is row 0 alone (`seam`) or every K-th row, 0, K, 2K, ...
//!   (`seam-K`, tiles of K rows). Mass is conserved.
//! - `seam-sticky*S`: row 0 in the even columns, where a falling particle
//!   comes to rest (if the rest channel is free) with probability S per
//!   step: a seam that makes no upward mover.
//! - `lane-boundary*S`: the fast engine (64 rows per word, `pipe::fast`)
//!   with the same reversal at every site of the rows on either side of a
//!   word boundary (rows 64j - 1 and 64j, and the wrap, rows L - 1 and 0).
//! - `KNOB*F@T`: a drift: the reference until step T, then the parametric
//!   mutant `KNOB*F` ([`Scaled`]) from the same state on (its own random
//!   stream): a rule probability that goes wrong after T steps.

use super::mutants::Scaled;
use crate::error::{Error, ErrorKind, Result};
use crate::pipe::collision::threshold;
use crate::pipe::engine::{EngineBuilder, PipeEngine, Reference};
use crate::pipe::fast::Fast;
use crate::pipe::{Flux, Params, Rules};
use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

/// One parametric defect.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Defect {
    /// A seam of rows in the even columns: `every` None for row 0 alone,
    /// Some(K) for rows 0, K, 2K, ...; reversal with probability `strength`.
    Seam {
        /// The period K of the seam rows, if any.
        every: Option<usize>,
        /// Probability per step and site, in [0, 1].
        strength: f64,
    },
    /// A sticky seam: row 0 in the even columns, where a falling particle
    /// (channel `down`) comes to rest, if the rest channel is free, with
    /// probability `strength` per step.
    StickySeam {
        /// Probability per step and site, in [0, 1].
        strength: f64,
    },
    /// The fast engine with reversals at its word boundaries.
    LaneBoundary {
        /// Probability per step and site, in [0, 1].
        strength: f64,
    },
    /// A rule probability scaled from step `start` on.
    Drift {
        /// The scaled probability.
        scaled: Scaled,
        /// The first step run by the mutant.
        start: u64,
    },
}

/// The classes, as `validate --detect` and the detection table name them.
pub const CLASSES: [&str; 4] = ["rule", "seam", "lane-boundary", "drift"];

impl std::str::FromStr for Defect {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        let bad = |why: String| Error::new(ErrorKind::InvalidParameter, why);
        let strength = |v: &str| -> Result<f64> {
            v.parse::<f64>()
                .ok()
                .filter(|x| (0.0..=1.0).contains(x))
                .ok_or_else(|| {
                    bad(format!(
                        "strength `{v}` in `{s}` must be a number in [0, 1]"
                    ))
                })
        };
        if let Some((head, f)) = s.split_once('*') {
            if head == "seam-sticky" {
                let strength = strength(f)?;
                return Ok(Defect::StickySeam { strength });
            }
            if head == "seam" {
                let strength = strength(f)?;
                return Ok(Defect::Seam {
                    every: None,
                    strength,
                });
            }
            if let Some(k) = head.strip_prefix("seam-") {
                let every = k
                    .parse::<usize>()
                    .ok()
                    .filter(|k| (1..=1_000_000).contains(k))
                    .ok_or_else(|| {
                        bad(format!(
                            "seam period `{k}` in `{s}` must be a whole number in [1, 1000000]"
                        ))
                    })?;
                let strength = strength(f)?;
                return Ok(Defect::Seam {
                    every: Some(every),
                    strength,
                });
            }
            if head == "lane-boundary" {
                let strength = strength(f)?;
                return Ok(Defect::LaneBoundary { strength });
            }
            if let Some((knob, start)) = s.split_once('@') {
                let start = start
                    .parse::<u64>()
                    .ok()
                    .filter(|t| *t <= crate::run::MAX_STEPS)
                    .ok_or_else(|| {
                        bad(format!(
                            "drift start `{start}` in `{s}` must be a whole number of steps in [0, {}]",
                            crate::run::MAX_STEPS
                        ))
                    })?;
                let scaled: Scaled = knob.parse()?;
                return Ok(Defect::Drift { scaled, start });
            }
        }
        Err(bad(format!(
            "`{s}` is not a defect; use seam*S, seam-K*S, lane-boundary*S (S in [0, 1]) or KNOB*F@T"
        )))
    }
}

impl Defect {
    /// Whether `spec` (after `mutant:`) names a defect rather than a
    /// catalogue mutant or a [`Scaled`] one.
    pub fn is_defect(spec: &str) -> bool {
        spec.starts_with("seam") || spec.starts_with("lane-boundary") || spec.contains('@')
    }

    /// Its class in [`CLASSES`].
    pub fn class(&self) -> &'static str {
        match self {
            Defect::Seam { .. } | Defect::StickySeam { .. } => "seam",
            Defect::LaneBoundary { .. } => "lane-boundary",
            Defect::Drift { .. } => "drift",
        }
    }
}

/// Reverse the moving particles of a state (channel c to c + 3, the rest
/// particle kept).
pub fn reversed(state: u8) -> u8 {
    let mut out = state & 1;
    for c in 1..7 {
        if state >> c & 1 == 1 {
            out |= 1 << ((c - 1 + 3) % 6 + 1);
        }
    }
    out
}

/// An engine with reversals at fixed sites after every step.
struct Reversing {
    inner: Box<dyn PipeEngine>,
    sites: Vec<(usize, usize)>,
    threshold: u64,
    rng: Xoshiro256PlusPlus,
    /// The change made: [`reversed`] or [`stopped`].
    change: fn(u8) -> u8,
}

impl Reversing {
    fn defect(&mut self) {
        for &(x, y) in &self.sites {
            let s = self.inner.site(x, y);
            let t = (self.change)(s);
            if t != s && (self.rng.next_u32() as u64) < self.threshold {
                self.inner.set_site(x, y, t);
            }
        }
    }
}

/// A falling particle (channel 4) put to rest (channel 0) when the rest
/// channel is free; any other state unchanged.
pub fn stopped(state: u8) -> u8 {
    if state & 1 == 0 && state >> 4 & 1 == 1 {
        (state & !(1 << 4)) | 1
    } else {
        state
    }
}

/// An engine that runs a second engine from step `start` on, from the
/// first one's state.
struct Drifting {
    inner: Box<dyn PipeEngine>,
    then: Option<Box<dyn PipeEngine>>,
    start: u64,
    offset: (u64, Flux),
}

impl Drifting {
    fn switch(&mut self) {
        if let Some(mut next) = self.then.take() {
            let p = *self.inner.params();
            for x in 0..p.width {
                for y in 0..p.length {
                    next.set_site(x, y, self.inner.site(x, y));
                }
            }
            self.offset = (self.inner.time(), self.inner.flux());
            self.inner = next;
        }
    }
}

/// The forwarding methods of the wrappers: the wrapped engine's.
macro_rules! forward {
    () => {
        fn params(&self) -> &Params {
            self.inner.params()
        }
        fn site(&self, x: usize, y: usize) -> u8 {
            self.inner.site(x, y)
        }
        fn set_site(&mut self, x: usize, y: usize, state: u8) {
            self.inner.set_site(x, y, state)
        }
        fn fill_bin_counts(&self, out: &mut [f64]) {
            self.inner.fill_bin_counts(out)
        }
        fn channel_counts(&self) -> [u64; 7] {
            self.inner.channel_counts()
        }
        fn rules(&self) -> Rules {
            self.inner.rules()
        }
        fn set_p(&mut self, p: f64) -> Result<()> {
            self.inner.set_p(p)
        }
    };
}

impl PipeEngine for Reversing {
    forward!();
    fn step(&mut self) -> Result<()> {
        self.inner.step()?;
        self.defect();
        Ok(())
    }
    fn time(&self) -> u64 {
        self.inner.time()
    }
    fn flux(&self) -> Flux {
        self.inner.flux()
    }
}

impl PipeEngine for Drifting {
    forward!();
    fn step(&mut self) -> Result<()> {
        if self.time() >= self.start {
            self.switch();
        }
        self.inner.step()
    }
    fn time(&self) -> u64 {
        self.offset.0 + self.inner.time()
    }
    fn flux(&self) -> Flux {
        let (a, b) = (self.offset.1, self.inner.flux());
        Flux {
            injected: a.injected + b.injected,
            out_bottom: a.out_bottom + b.out_bottom,
            out_top: a.out_top + b.out_top,
        }
    }
}

impl EngineBuilder for Defect {
    fn name(&self) -> String {
        match self {
            Defect::Seam {
                every: None,
                strength,
            } => format!("mutant:seam*{strength}"),
            Defect::Seam {
                every: Some(k),
                strength,
            } => format!("mutant:seam-{k}*{strength}"),
            Defect::LaneBoundary { strength } => format!("mutant:lane-boundary*{strength}"),
            Defect::StickySeam { strength } => format!("mutant:seam-sticky*{strength}"),
            Defect::Drift { scaled, start } => format!("{}@{start}", EngineBuilder::name(scaled)),
        }
    }

    fn hopper(&self) -> Option<&dyn crate::hopper::engine::HopperBuilder> {
        Some(&crate::hopper::engine::Reference)
    }

    fn build(&self, params: Params, rules: Rules, seed: u64) -> Result<Box<dyn PipeEngine>> {
        let (w, l) = (params.width, params.length);
        let rng = Xoshiro256PlusPlus::seed_from_u64(seed ^ 0x5EA3_D1F7);
        match *self {
            Defect::Seam { every, strength } => {
                let rows: Vec<usize> = match every {
                    None => vec![0],
                    Some(k) => (0..l).step_by(k).collect(),
                };
                let sites = rows
                    .iter()
                    .flat_map(|&y| (0..w).step_by(2).map(move |x| (x, y)))
                    .collect();
                Ok(Box::new(Reversing {
                    inner: Reference.build(params, rules, seed)?,
                    sites,
                    threshold: threshold(strength),
                    rng,
                    change: reversed,
                }))
            }
            Defect::StickySeam { strength } => Ok(Box::new(Reversing {
                inner: Reference.build(params, rules, seed)?,
                sites: (0..w).step_by(2).map(|x| (x, 0)).collect(),
                threshold: threshold(strength),
                rng,
                change: stopped,
            })),
            Defect::LaneBoundary { strength } => {
                let mut rows: Vec<usize> = (0..l).filter(|y| y % 64 == 0 || y % 64 == 63).collect();
                rows.push(l - 1);
                rows.sort_unstable();
                rows.dedup();
                let sites = rows
                    .iter()
                    .flat_map(|&y| (0..w).map(move |x| (x, y)))
                    .collect();
                Ok(Box::new(Reversing {
                    inner: Fast.build(params, rules, seed)?,
                    sites,
                    threshold: threshold(strength),
                    rng,
                    change: reversed,
                }))
            }
            Defect::Drift { scaled, start } => Ok(Box::new(Drifting {
                inner: Reference.build(params, rules, seed)?,
                then: Some(scaled.build(params, rules, seed ^ 0xD21F_7000)?),
                start,
                offset: (0, Flux::default()),
            })),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn specs_parse_and_name_themselves() {
        for s in [
            "seam*0.5",
            "seam-16*1",
            "seam-sticky*0.1",
            "lane-boundary*0.25",
            "g*1.05@2000",
        ] {
            let d: Defect = s.parse().unwrap();
            assert_eq!(d.name(), format!("mutant:{s}"));
        }
        for bad in [
            "seam*2",
            "seam-0*1",
            "seam-x*1",
            "g*1.05@-1",
            "lane-boundary*nan",
            "q*1@3",
        ] {
            assert!(bad.parse::<Defect>().is_err(), "{bad}");
        }
    }

    #[test]
    fn reversal_is_an_involution_that_keeps_mass() {
        for s in 0..128u8 {
            assert_eq!(reversed(reversed(s)), s);
            assert_eq!(reversed(s).count_ones(), s.count_ones());
        }
        assert_eq!(reversed(0b10), 0b10000); // up to down
        assert_eq!(stopped(0b10000), 0b1); // down to rest
        assert_eq!(stopped(0b10001), 0b10001); // the rest channel is taken
    }
}
