//! The catalogue of mutant engines (VALIDATION.md): the reference engine with one
//! plausible bug each. `validate` must fail every one of them; the power
//! table of EXPERIMENTS.md says which level catches which, at what cost.
//! Defects of decomposition and time with a stated size (seams, lane
//! boundaries, drifts) are in [`super::defects`].

use crate::error::{Error, ErrorKind, Result};
use crate::hopper::energy::{aligned, f_shear, motion, pair_index, EnergyTable, STATES};
use crate::hopper::engine::{self as hopper_engine, HopperBuilder, HopperEngine};
use crate::hopper::{Hopper, HopperParams};
use crate::pipe::collision::{threshold, CollisionTable, Rule};
use crate::pipe::draws::Draws;
use crate::pipe::engine::{EngineBuilder, PipeEngine};
use crate::pipe::fast::FastPipe;
use crate::pipe::{Boundary, GravityWording, Params, Pipe, Rules};
use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

/// One plausible bug.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mutant {
    /// The dissipation p used is 10% too large (p -> min(1, 1.1 p)).
    PPlus10,
    /// The gravity probability g is 10% too large.
    GPlus10,
    /// The wall roughness b is 10% too large.
    BPlus10,
    /// The wall-reflection timing of the other reading (`wall-move` toggled).
    WallTiming,
    /// Gravity turns every mover, not only those colliding with a rest
    /// particle (`any-mover` for `ph94`, `ph94` otherwise).
    GravityEveryMover,
    /// R1 always rotates to the same side (+60 degrees) instead of +-60 with
    /// probability 1/2 each.
    R1SameSide,
    /// Extra rest particles of R4/R5 are dropped instead of relocated.
    ExtrasDropped,
    /// The random stream has lost its top bit (a signed/unsigned slip): every
    /// probability q is used as min(1, 2q).
    BiasedStream,
    /// Correlated draws, exact marginals: the random stream
    /// starts afresh from the same state at every step, as a counter-based
    /// generator keyed by site but not by time would. Every single draw is
    /// uniform; the draws of step t + 1 repeat those of step t.
    DrawsRepeatEachStep,
    /// Correlated draws, exact marginals: the fast
    /// (bit-sliced) engine with two neighbouring lanes sharing their random
    /// bits, as a lane mask built one bit too wide would: rows 2j and 2j + 1
    /// of a column make the same random choices. Every one-site
    /// distribution is exact.
    LanesSharedByPairs,
    /// Hopper: the sign of beta flipped, F_orient^(-beta) (MODEL.md B4): an
    /// aligned pair costs 1/S instead of S. The pipe engine is the reference.
    HopperBetaSign,
    /// Hopper: the rays of the spacing one step too long, K + 1 instead of K
    /// (MODEL.md B4). The pipe engine is the reference.
    HopperSpacingOffByOne,
}

/// Every mutant with its name, as `--candidate mutant:NAME` takes it.
pub const MUTANTS: [(&str, Mutant); 12] = [
    ("p+10%", Mutant::PPlus10),
    ("g+10%", Mutant::GPlus10),
    ("b+10%", Mutant::BPlus10),
    ("wall-timing", Mutant::WallTiming),
    ("gravity-every-mover", Mutant::GravityEveryMover),
    ("r1-same-side", Mutant::R1SameSide),
    ("extras-dropped", Mutant::ExtrasDropped),
    ("biased-stream", Mutant::BiasedStream),
    ("draws-repeat-each-step", Mutant::DrawsRepeatEachStep),
    ("lanes-shared-by-pairs", Mutant::LanesSharedByPairs),
    ("hopper-beta-sign", Mutant::HopperBetaSign),
    ("hopper-spacing-off-by-one", Mutant::HopperSpacingOffByOne),
];

impl std::str::FromStr for Mutant {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        MUTANTS
            .iter()
            .find(|(n, _)| *n == s)
            .map(|&(_, m)| m)
            .ok_or_else(|| {
                let names: Vec<&str> = MUTANTS.iter().map(|(n, _)| *n).collect();
                Error::new(
                    ErrorKind::InvalidParameter,
                    format!(
                        "unknown mutant `{s}`; the mutants are: {}",
                        names.join(", ")
                    ),
                )
            })
    }
}

impl Mutant {
    /// Its name in [`MUTANTS`].
    pub fn name(self) -> &'static str {
        MUTANTS
            .iter()
            .find(|(_, m)| *m == self)
            .map(|(n, _)| *n)
            .expect("every mutant is listed")
    }

    /// Whether the bug is in the hopper engine (else in the pipe engine).
    pub fn is_hopper(self) -> bool {
        matches!(self, Mutant::HopperBetaSign | Mutant::HopperSpacingOffByOne)
    }
}

/// The draws of [`Mutant::BiasedStream`]: every 32-bit draw shifted right
/// by one bit.
#[derive(Debug, Clone)]
pub struct TopBitLost(Xoshiro256PlusPlus);

impl Draws for TopBitLost {
    fn uncertain(&mut self, t: u64) -> bool {
        ((self.0.next_u32() >> 1) as u64) < t
    }
    fn pick(&mut self, cumulative: &[u64]) -> usize {
        let u = (self.0.next_u32() >> 1) as u64;
        cumulative
            .iter()
            .position(|&c| u < c)
            .unwrap_or(cumulative.len() - 1)
    }
    fn coin(&mut self) -> bool {
        self.0.next_u32() >> 31 == 1
    }
    fn below(&mut self, n: u32) -> u32 {
        Draws::below(&mut self.0, n)
    }
}

/// The generator of [`Mutant::LanesSharedByPairs`]: in every 64-bit word,
/// bit 2j + 1 is a copy of bit 2j, so lanes 2j and 2j + 1 of the fast
/// engine (rows 2j and 2j + 1 of a column) get the same random bits. Each
/// bit is still fair, and one lane's words are still independent.
#[derive(Debug, Clone)]
pub struct PairedLanes(Xoshiro256PlusPlus);

impl rand::TryRng for PairedLanes {
    type Error = std::convert::Infallible;
    fn try_next_u32(&mut self) -> std::result::Result<u32, Self::Error> {
        Ok(self.0.next_u32())
    }
    fn try_next_u64(&mut self) -> std::result::Result<u64, Self::Error> {
        let even = self.0.next_u64() & 0x5555_5555_5555_5555;
        Ok(even | even << 1)
    }
    fn try_fill_bytes(&mut self, dst: &mut [u8]) -> std::result::Result<(), Self::Error> {
        self.0.fill_bytes(dst);
        Ok(())
    }
}

/// The engine of [`Mutant::DrawsRepeatEachStep`]: the reference whose
/// random stream is reset to the same state before every step.
struct RepeatEachStep {
    pipe: Pipe,
    seed: u64,
}

impl PipeEngine for RepeatEachStep {
    fn params(&self) -> &Params {
        self.pipe.params()
    }
    fn step(&mut self) -> Result<()> {
        *self.pipe.draws_mut() = Xoshiro256PlusPlus::seed_from_u64(self.seed);
        self.pipe.step()
    }
    fn time(&self) -> u64 {
        self.pipe.time()
    }
    fn site(&self, x: usize, y: usize) -> u8 {
        self.pipe.site(x, y)
    }
    fn set_site(&mut self, x: usize, y: usize, state: u8) {
        self.pipe.set_site(x, y, state)
    }
    fn fill_bin_counts(&self, out: &mut [f64]) {
        self.pipe.fill_bin_counts(out)
    }
    fn channel_counts(&self) -> [u64; 7] {
        self.pipe.channel_counts()
    }
    fn flux(&self) -> crate::pipe::Flux {
        self.pipe.flux()
    }
    fn rules(&self) -> Rules {
        self.pipe.rules()
    }
    fn set_p(&mut self, p: f64) -> Result<()> {
        self.pipe.set_p(p)
    }
}

fn plus10(q: f64) -> f64 {
    (1.1 * q).min(1.0)
}

impl EngineBuilder for Mutant {
    fn name(&self) -> String {
        format!("mutant:{}", Mutant::name(*self))
    }

    fn hopper(&self) -> Option<&dyn HopperBuilder> {
        Some(self)
    }

    fn build(&self, params: Params, rules: Rules, seed: u64) -> Result<Box<dyn PipeEngine>> {
        let (mut params, mut rules) = (params, rules);
        match self {
            Mutant::PPlus10 => params.p = plus10(params.p),
            Mutant::GPlus10 => params.g = plus10(params.g),
            Mutant::BPlus10 => params.b = plus10(params.b),
            Mutant::WallTiming => rules.wall_move = !rules.wall_move,
            Mutant::GravityEveryMover => {
                rules.gravity = match rules.gravity {
                    GravityWording::Ph94 => GravityWording::AnyMover,
                    _ => GravityWording::Ph94,
                }
            }
            _ => {}
        }
        if *self == Mutant::LanesSharedByPairs {
            let fast = FastPipe::new(params, rules, seed)?;
            let rng = PairedLanes(Xoshiro256PlusPlus::seed_from_u64(seed ^ 0x9A1B));
            return Ok(Box::new(fast.with_rng(rng)));
        }
        let mut pipe = Pipe::new(params, rules, seed)?;
        match self {
            Mutant::R1SameSide | Mutant::ExtrasDropped => {
                let mut table = CollisionTable::for_rules(params.p, rules);
                for e in &mut table.entries {
                    if *self == Mutant::R1SameSide && e.rule == Rule::R1 {
                        e.outcomes.truncate(1);
                        e.outcomes[0].prob = 1.0;
                        e.cumulative = vec![1 << 32];
                    }
                    if *self == Mutant::ExtrasDropped {
                        e.outcomes.iter_mut().for_each(|o| o.extra = 0);
                    }
                }
                pipe.replace_collision_table(table);
                Ok(Box::new(pipe))
            }
            Mutant::BiasedStream => {
                let draws = TopBitLost(Xoshiro256PlusPlus::seed_from_u64(seed ^ 0xB1A5));
                Ok(Box::new(pipe.with_draws(draws)))
            }
            Mutant::DrawsRepeatEachStep => Ok(Box::new(RepeatEachStep {
                pipe,
                seed: seed ^ 0x5EED,
            })),
            _ => Ok(Box::new(pipe)),
        }
    }
}

/// The energy table of [`Mutant::HopperBetaSign`]: F_orient^(-beta).
fn beta_flipped(params: &HopperParams) -> Result<EnergyTable> {
    let p = params.energy;
    let mut t = EnergyTable::new(p)?;
    for a in 0..3 {
        for si in 0..STATES {
            for sn in 0..STATES {
                // direction a + 1 lies along bond axis a
                let orient = if aligned(si, sn, a + 1, p.aligned) {
                    p.s
                } else {
                    1.0
                };
                t.pair[pair_index(a, si, sn)] =
                    f_shear(motion(si), motion(sn)).powf(p.alpha) * orient.powf(-p.beta);
            }
        }
    }
    Ok(t)
}

impl HopperBuilder for Mutant {
    fn name(&self) -> String {
        EngineBuilder::name(self)
    }

    fn build(&self, params: HopperParams, seed: u64) -> Result<Box<dyn HopperEngine>> {
        match self {
            Mutant::HopperBetaSign => {
                let table = beta_flipped(&params)?;
                Ok(Box::new(Hopper::new(params, seed)?.with_table(table)))
            }
            Mutant::HopperSpacingOffByOne => {
                let mut p = params;
                p.dilation.validate()?;
                p.dilation.k += 1;
                Ok(Box::new(Hopper::new(p, seed)?))
            }
            _ => hopper_engine::Reference.build(params, seed),
        }
    }
}

/// Which rule probability a [`Scaled`] mutant changes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Knob {
    /// p in R2 and R3 (MODEL.md A3).
    P,
    /// p in R2 only.
    PR2,
    /// p in R3 only.
    PR3,
    /// The probability 1/2 of R1's first rotation (the split of R1).
    R1Split,
    /// g (MODEL.md A5).
    G,
    /// b, the wall's bounce-back probability (MODEL.md A6): the wall reflection.
    B,
    /// The open pipe's injection rate I (MODEL.md A7).
    Inject,
}

/// Every knob with its name, as `--candidate mutant:KNOB*FACTOR` takes it.
pub const KNOBS: [(&str, Knob); 7] = [
    ("p", Knob::P),
    ("p-r2", Knob::PR2),
    ("p-r3", Knob::PR3),
    ("r1-split", Knob::R1Split),
    ("g", Knob::G),
    ("b", Knob::B),
    ("inject", Knob::Inject),
];

/// A parametric mutant: the reference engine with one
/// rule probability q used as min(1, factor q), e.g. `mutant:p*1.03` for
/// p 3 % high or `mutant:r1-split*1.04` for R1 splitting 52/48.
/// `mutant:p*1.1` is the catalogue's `p+10%`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scaled {
    /// The probability changed.
    pub knob: Knob,
    /// Its factor, in (0, 10].
    pub factor: f64,
}

impl std::str::FromStr for Scaled {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        let knobs = || KNOBS.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", ");
        let bad = |why: String| Error::new(ErrorKind::InvalidParameter, why);
        let (name, f) = s.split_once('*').ok_or_else(|| {
            bad(format!(
                "mutant `{s}` is not KNOB*FACTOR; the knobs are: {}",
                knobs()
            ))
        })?;
        let knob = KNOBS
            .iter()
            .find(|(n, _)| *n == name)
            .map(|&(_, k)| k)
            .ok_or_else(|| {
                bad(format!(
                    "unknown knob `{name}` in `{s}`; the knobs are: {}",
                    knobs()
                ))
            })?;
        let factor: f64 = f
            .parse()
            .ok()
            .filter(|x: &f64| *x > 0.0 && *x <= 10.0)
            .ok_or_else(|| bad(format!("factor `{f}` in `{s}` must be a number in (0, 10]")))?;
        Ok(Scaled { knob, factor })
    }
}

impl Scaled {
    fn scale(self, q: f64) -> f64 {
        (q * self.factor).min(1.0)
    }

    /// The knob's name in [`KNOBS`].
    pub fn knob_name(self) -> &'static str {
        KNOBS
            .iter()
            .find(|(_, k)| *k == self.knob)
            .map(|(n, _)| *n)
            .expect("every knob is listed")
    }
}

impl EngineBuilder for Scaled {
    fn name(&self) -> String {
        format!("mutant:{}*{}", self.knob_name(), self.factor)
    }

    fn hopper(&self) -> Option<&dyn HopperBuilder> {
        Some(&hopper_engine::Reference)
    }

    fn build(&self, params: Params, rules: Rules, seed: u64) -> Result<Box<dyn PipeEngine>> {
        let mut params = params;
        match self.knob {
            Knob::P => params.p = self.scale(params.p),
            Knob::G => params.g = self.scale(params.g),
            Knob::B => params.b = self.scale(params.b),
            Knob::Inject => {
                if let Boundary::Open { inject } = params.boundary {
                    params.boundary = Boundary::Open {
                        inject: self.scale(inject),
                    };
                }
            }
            Knob::PR2 | Knob::PR3 | Knob::R1Split => {}
        }
        let mut pipe = Pipe::new(params, rules, seed)?;
        let (rule, p) = match self.knob {
            Knob::PR2 => (Rule::R2, self.scale(params.p)),
            Knob::PR3 => (Rule::R3, self.scale(params.p)),
            Knob::R1Split => (Rule::R1, params.p),
            _ => return Ok(Box::new(pipe)),
        };
        // the rule's entries from the table of the scaled p (R2, R3), or
        // R1's two rotations with probabilities f/2 and 1 - f/2
        let scaled = CollisionTable::for_rules(p, rules);
        let mut table = CollisionTable::for_rules(params.p, rules);
        for (e, new) in table.entries.iter_mut().zip(scaled.entries) {
            if e.rule != rule {
                continue;
            }
            if rule == Rule::R1 {
                let first = self.scale(0.5);
                e.outcomes[0].prob = first;
                e.outcomes[1].prob = 1.0 - first;
                e.cumulative = vec![threshold(first), 1 << 32];
            } else {
                *e = new;
            }
        }
        pipe.replace_collision_table(table);
        Ok(Box::new(pipe))
    }
}
