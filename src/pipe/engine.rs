//! The engine contract of the pipe lattice gas (MODEL.md Part A): what any
//! implementation of the automaton offers, so that `validate` can check it
//! against the reference engine [`super::Pipe`].
//!
//! An engine is built from (parameters, rules, seed), steps, and reads the
//! state and the observables the figures need. A run must be a pure function
//! of (parameters, rules, seed, engine). Engines outside Rust follow the
//! external-program contract of VALIDATION.md instead
//! (`crate::validate::external`).

use super::draws::Draws;
use super::{Flux, Params, Pipe, Rules};
use crate::error::Result;
use crate::hopper::engine::HopperBuilder;

/// One implementation of the pipe automaton (MODEL.md Part A).
pub trait PipeEngine: Send {
    /// The parameters of this run.
    fn params(&self) -> &Params;
    /// One time step (MODEL.md A2).
    fn step(&mut self) -> Result<()>;
    /// Steps done so far.
    fn time(&self) -> u64;
    /// The state byte of site (x, y): bit c = channel c (MODEL.md A1).
    fn site(&self, x: usize, y: usize) -> u8;
    /// Set the state byte of site (x, y) (prepared states, level-1 probes).
    fn set_site(&mut self, x: usize, y: usize, state: u8);
    /// Bin densities n_i (MODEL.md A9) into `out` (length K = L / bin).
    fn fill_bin_counts(&self, out: &mut [f64]);
    /// Number of particles in each channel 0..=6.
    fn channel_counts(&self) -> [u64; 7];
    /// Injection and outflow counters (open pipe, MODEL.md A7).
    fn flux(&self) -> Flux;
    /// The rule reading of this run.
    fn rules(&self) -> Rules;
    /// Change the dissipation p mid-run (PH94 Fig. 1c); validated.
    fn set_p(&mut self, p: f64) -> Result<()>;
    /// Every occupied site `(x, y, state byte)`, column by column.
    fn occupied_sites(&self) -> Vec<(usize, usize, u8)> {
        let p = self.params();
        let mut v = Vec::new();
        for x in 0..p.width {
            for y in 0..p.length {
                let s = self.site(x, y);
                if s != 0 {
                    v.push((x, y, s));
                }
            }
        }
        v
    }
    /// Advance `steps` steps.
    fn run(&mut self, steps: u64) -> Result<()> {
        for _ in 0..steps {
            self.step()?;
        }
        Ok(())
    }
    /// Total number of particles N (all channels).
    fn particle_count(&self) -> u64 {
        self.channel_counts().iter().sum()
    }
    /// Kinetic energy E = number of moving particles \[PH95 Fig. 3b\].
    fn moving_count(&self) -> u64 {
        self.channel_counts()[1..].iter().sum()
    }
    /// Number of rest particles.
    fn rest_count(&self) -> u64 {
        self.channel_counts()[0]
    }
    /// Bin densities n_i (MODEL.md A9), K = L / bin values.
    fn bin_counts(&self) -> Vec<f64> {
        let mut out = vec![0.0; self.params().bins()];
        self.fill_bin_counts(&mut out);
        out
    }
    /// Particle count of bin `i` alone (MODEL.md A9).
    fn bin_count(&self, i: usize) -> u32 {
        let mut out = vec![0.0; self.params().bins()];
        self.fill_bin_counts(&mut out);
        out[i] as u32
    }
}

/// The body of `impl PipeEngine for $engine`: every method of the contract
/// forwarded to the engine's own method of the same name, so that an engine
/// keeps its methods callable without the trait in scope. Extra methods (an
/// engine's own `run`) follow the macro call in the same `impl` block.
macro_rules! forward_to_inherent {
    ($engine:ident) => {
        fn params(&self) -> &Params {
            $engine::params(self)
        }
        fn step(&mut self) -> Result<()> {
            $engine::step(self)
        }
        fn time(&self) -> u64 {
            $engine::time(self)
        }
        fn site(&self, x: usize, y: usize) -> u8 {
            $engine::site(self, x, y)
        }
        fn set_site(&mut self, x: usize, y: usize, state: u8) {
            $engine::set_site(self, x, y, state)
        }
        fn fill_bin_counts(&self, out: &mut [f64]) {
            $engine::fill_bin_counts(self, out)
        }
        fn channel_counts(&self) -> [u64; 7] {
            $engine::channel_counts(self)
        }
        fn flux(&self) -> Flux {
            $engine::flux(self)
        }
        fn rules(&self) -> Rules {
            $engine::rules(self)
        }
        fn set_p(&mut self, p: f64) -> Result<()> {
            $engine::set_p(self, p)
        }
        fn particle_count(&self) -> u64 {
            $engine::particle_count(self)
        }
        fn moving_count(&self) -> u64 {
            $engine::moving_count(self)
        }
        fn rest_count(&self) -> u64 {
            $engine::rest_count(self)
        }
        fn bin_count(&self, i: usize) -> u32 {
            $engine::bin_count(self, i)
        }
    };
}
pub(crate) use forward_to_inherent;

/// The getters both engines keep inherent, over their fields of the same
/// names: `params`, `rules`, `time` and `flux` (placed inside `impl $engine`).
macro_rules! run_getters {
    () => {
        /// The parameters of this run.
        pub fn params(&self) -> &Params {
            &self.params
        }

        /// The rule reading of this run.
        pub fn rules(&self) -> Rules {
            self.rules
        }

        /// Steps done so far.
        pub fn time(&self) -> u64 {
            self.time
        }

        /// Injection and outflow counters (open pipe, MODEL.md A7).
        pub fn flux(&self) -> Flux {
            self.flux
        }
    };
}
pub(crate) use run_getters;

impl<D: Draws + Send> PipeEngine for Pipe<D> {
    forward_to_inherent!(Pipe);
}

/// Builds runs of one engine: what `validate` and the figures are given.
pub trait EngineBuilder: Sync + Send {
    /// Name of the engine (e.g. `reference`, `mutant:p+10%`).
    fn name(&self) -> String;
    /// A new run (validated parameters; the initial state of MODEL.md A8).
    fn build(&self, params: Params, rules: Rules, seed: u64) -> Result<Box<dyn PipeEngine>>;
    /// The same implementation's hopper engine (MODEL.md Part B), if it has
    /// one (`crate::hopper::engine`); none by default.
    fn hopper(&self) -> Option<&dyn HopperBuilder> {
        None
    }
}

/// The reference engine, [`Pipe`].
#[derive(Debug, Clone, Copy, Default)]
pub struct Reference;

impl EngineBuilder for Reference {
    fn name(&self) -> String {
        "reference".into()
    }
    fn build(&self, params: Params, rules: Rules, seed: u64) -> Result<Box<dyn PipeEngine>> {
        Ok(Box::new(Pipe::new(params, rules, seed)?))
    }
    fn hopper(&self) -> Option<&dyn HopperBuilder> {
        Some(&crate::hopper::engine::Reference)
    }
}
