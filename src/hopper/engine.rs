//! The engine contract of the hopper automaton (MODEL.md Part B): what any
//! implementation of BB90's hopper offers, so that `validate` can check it
//! against the reference engine [`Hopper`], in the style of
//! [`crate::pipe::engine`].
//!
//! An engine is built from ([`HopperParams`], seed), runs the fill/empty
//! protocol of MODEL.md B5 one iteration at a time, and exposes the lattice
//! (site values, spacings D_i) and, for the rule checks of level 1, the
//! energies E_i of a grain's candidate states (MODEL.md B3-B4) and set-up
//! hooks. A run must be a pure function of (parameters, seed, engine).

use super::geometry::Geometry;
use super::model::{Hopper, HopperParams, StepReport};
use crate::error::{Error, Result};

/// One implementation of the hopper automaton (MODEL.md Part B).
pub trait HopperEngine: Send {
    /// The parameters of this run.
    fn params(&self) -> &HopperParams;
    /// The container (site indices `y * width + x`, neighbour table, MODEL.md B2).
    fn geometry(&self) -> &Geometry;
    /// One iteration (MODEL.md B3), with rain on the top row if `rain` (B5).
    fn step(&mut self, rain: bool) -> StepReport;
    /// Open the plug (MODEL.md B5).
    fn open(&mut self);
    /// Whether the plug is open.
    fn is_open(&self) -> bool;
    /// Site values: `HOLE` (0), `WALL` (255) or a grain `1 + 7 O + v`
    /// (orientation O, motion v, MODEL.md B1; [`super::model::grain`]).
    fn sites(&self) -> &[u8];
    /// Running mean spacing D_i of every site (meaningful on grains, MODEL.md B4).
    fn spacing(&self) -> &[f64];
    /// Grains added by rain or [`HopperEngine::set_site`] so far.
    fn added(&self) -> u64;
    /// Grains that left through the outlet so far.
    fn removed(&self) -> u64;
    /// Iterations done.
    fn iteration(&self) -> u64;
    /// Grains inside.
    fn grains(&self) -> u64 {
        self.added() - self.removed()
    }
    /// Rain until `target` grains were added or `max_iterations` passed, then
    /// settle without rain until nothing moves (at most `max_settle`
    /// iterations); the iterations done (MODEL.md B5).
    fn fill(&mut self, target: u64, max_iterations: u64, max_settle: u64) -> u64 {
        let start = self.iteration();
        while self.added() < target && self.iteration() - start < max_iterations {
            self.step(true);
        }
        for _ in 0..max_settle {
            if self.step(false).moved == 0 {
                break;
            }
        }
        self.iteration() - start
    }
    /// Set site `i` (an inside site) to a hole or a grain value (prepared
    /// states of level 1); the grain count follows.
    fn set_site(&mut self, i: usize, value: u8) -> Result<()>;
    /// Set the running mean spacing D_i of site `i` (prepared states).
    fn set_spacing(&mut self, i: usize, d: f64) -> Result<()>;
    /// E_i (MODEL.md B4) of every state the grain at site `i` may take in the
    /// interaction step (rest, or a motion towards a hole; 3 orientations
    /// each), as `(state, E)`, in the current configuration.
    fn energies(&self, i: usize) -> Result<Vec<(usize, f64)>>;
    /// Work done, for the report (grain evaluations plus site scans).
    fn site_updates(&self) -> f64 {
        0.0
    }
    /// `n` iterations without rain: per iteration its report and the
    /// moving grains of each orientation after it ([`moving_by_orientation`]).
    /// An engine behind a process (`validate`'s external contract) does
    /// them in one run of its program.
    fn empty_steps(&mut self, n: u64) -> Vec<(StepReport, [u64; 3])> {
        (0..n)
            .map(|_| {
                let r = self.step(false);
                (r, moving_by_orientation(self.sites()))
            })
            .collect()
    }
    /// The first error met by a method that cannot return one (`step`,
    /// `fill`, `empty_steps`, `open`): an engine behind a process whose
    /// program broke the contract. In-process engines have none.
    fn error(&self) -> Result<()> {
        Ok(())
    }
}

/// Moving grains (motion v != 0) of each orientation O = 0, 1, 2
/// (MODEL.md B1) among the site values `sites`.
pub fn moving_by_orientation(sites: &[u8]) -> [u64; 3] {
    use super::energy::{motion, orientation};
    use super::model::{grain_state, is_grain};
    let mut moving = [0u64; 3];
    for &s in sites {
        if is_grain(s) && motion(grain_state(s)) != 0 {
            moving[orientation(grain_state(s))] += 1;
        }
    }
    moving
}

/// Builds runs of one hopper engine.
pub trait HopperBuilder: Sync + Send {
    /// Name of the engine (e.g. `reference`).
    fn name(&self) -> String;
    /// A new, empty hopper with the plug closed (validated parameters).
    fn build(&self, params: HopperParams, seed: u64) -> Result<Box<dyn HopperEngine>>;
}

/// A value [`HopperEngine::set_site`] accepts: a hole or a grain.
pub fn check_value(value: u8) -> Result<()> {
    if value == super::model::WALL || value as usize > super::energy::STATES {
        return Err(Error::out_of_range(
            "site value",
            value,
            "0 (hole) or a grain 1..=21",
        ));
    }
    Ok(())
}

fn check_site(h: &Hopper, i: usize) -> Result<()> {
    use super::geometry::SiteKind;
    let n = h.sites().len();
    if i >= n || h.geometry().kind[i] != SiteKind::Inside {
        return Err(Error::out_of_range(
            "site index",
            i,
            &format!("an inside site of the {n}-site hopper"),
        ));
    }
    Ok(())
}

impl HopperEngine for Hopper {
    fn params(&self) -> &HopperParams {
        Hopper::params(self)
    }
    fn geometry(&self) -> &Geometry {
        Hopper::geometry(self)
    }
    fn step(&mut self, rain: bool) -> StepReport {
        Hopper::step(self, rain)
    }
    fn open(&mut self) {
        Hopper::open(self)
    }
    fn is_open(&self) -> bool {
        Hopper::is_open(self)
    }
    fn sites(&self) -> &[u8] {
        Hopper::sites(self)
    }
    fn spacing(&self) -> &[f64] {
        Hopper::spacing(self)
    }
    fn added(&self) -> u64 {
        Hopper::added(self)
    }
    fn removed(&self) -> u64 {
        Hopper::removed(self)
    }
    fn iteration(&self) -> u64 {
        Hopper::iteration(self)
    }
    fn grains(&self) -> u64 {
        Hopper::grains(self)
    }
    fn fill(&mut self, target: u64, max_iterations: u64, max_settle: u64) -> u64 {
        Hopper::fill(self, target, max_iterations, max_settle)
    }
    fn set_site(&mut self, i: usize, value: u8) -> Result<()> {
        check_site(self, i)?;
        check_value(value)?;
        Hopper::set_site(self, i, value);
        Ok(())
    }
    fn set_spacing(&mut self, i: usize, d: f64) -> Result<()> {
        check_site(self, i)?;
        crate::error::check_range("spacing D", d, 1.0, 1e6)?;
        Hopper::set_spacing(self, i, d);
        Ok(())
    }
    fn energies(&self, i: usize) -> Result<Vec<(usize, f64)>> {
        check_site(self, i)?;
        if !super::model::is_grain(self.sites()[i]) {
            return Err(Error::out_of_range(
                "site index",
                i,
                "a site holding a grain (energies are those of a grain)",
            ));
        }
        Ok(self.debug_energies(i))
    }
    fn site_updates(&self) -> f64 {
        Hopper::site_updates(self)
    }
}

/// The reference hopper engine, [`Hopper`].
#[derive(Debug, Clone, Copy, Default)]
pub struct Reference;

impl HopperBuilder for Reference {
    fn name(&self) -> String {
        "reference".into()
    }
    fn build(&self, params: HopperParams, seed: u64) -> Result<Box<dyn HopperEngine>> {
        Ok(Box::new(Hopper::new(params, seed)?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_contract_runs_the_reference_bit_identically() {
        let p = HopperParams::quick();
        let mut a = Hopper::new(p, 5).unwrap();
        let mut b = Reference.build(p, 5).unwrap();
        assert_eq!(a.fill(300, 200, 50), b.fill(300, 200, 50));
        a.open();
        b.open();
        for _ in 0..30 {
            assert_eq!(a.step(false), b.step(false));
        }
        assert_eq!(a.sites(), b.sites());
        assert_eq!(a.spacing(), b.spacing());
    }

    #[test]
    fn set_up_hooks_reject_bad_input() {
        let mut h = Reference.build(HopperParams::quick(), 1).unwrap();
        assert!(h.set_site(0, 1).unwrap_err().message.contains("site index"));
        let i = h.geometry().index(h.geometry().centre_column, 20);
        assert!(h.set_site(i, 22).is_err());
        assert!(h.set_spacing(i, 0.5).is_err());
        assert!(h.energies(i).is_err());
        h.set_site(i, 1).unwrap();
        assert_eq!(h.grains(), 1);
        assert_eq!(h.energies(i).unwrap().len(), 21);
    }
}
