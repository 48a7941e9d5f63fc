//! The Peng-Herrmann pipe lattice gas (MODEL.md Part A; \[PH94\], \[PH95\]).
//!
//! Particles on a triangular lattice of `W` columns and `L` rows, seven
//! Boolean channels per site (bit `c` = channel `c`, bit 0 = rest particle).
//! One step (MODEL.md A2): injection (open pipe), collision (A3) with the
//! relocation of extra rest particles (A4), gravity (A5), walls (A6),
//! propagation; the [`Rules`] choose the reading of each. A run is a pure
//! function of its parameters, rules, seed and engine.
//!
//! Where things are: the parameters here; the reference engine [`Pipe`] in
//! [`mod@reference`], the fast engine in [`fast`], their common contract in
//! [`engine`], the choice between them (`--engine`) in [`choice`]; the rules' tables in [`collision`] and [`rules`], the shared
//! relocation in [`relocation`], the random draws in [`draws`]; what a run
//! measures in [`observables`], [`record`], [`overlap`] and [`open`].
//!
//! ```
//! use granular_automata::pipe::{Params, Pipe, Rules};
//! let params = Params { length: 60, width: 5, ..Params::default() };
//! let mut pipe = Pipe::new(params, Rules::default(), 7).unwrap();
//! let n0 = pipe.particle_count();
//! pipe.run(100).unwrap();
//! assert_eq!(pipe.particle_count(), n0); // the periodic pipe conserves mass
//! assert_eq!(pipe.bin_counts().len(), 6); // bins of 10 rows
//! ```

pub mod choice;
pub mod collision;
pub mod draws;
pub mod engine;
pub mod fast;
pub mod mechanism;
pub mod observables;
pub mod open;
mod order;
pub mod overlap;
pub mod record;
pub mod reference;
pub mod relocation;
pub mod rules;
pub mod stops;

pub use choice::Engine;
pub use observables::Flux;
pub use reference::Pipe;
pub use relocation::is_validity_limit;
pub use rules::{GravityWording, LaneCollide, Probability, RestPlacement, Rules};

use crate::error::{check_min, check_range, check_unit, Error, ErrorKind, Result};
use serde::{Deserialize, Serialize};

/// What happens at the two ends of the pipe (MODEL.md A7).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Boundary {
    /// Rows wrap around: row L-1 neighbours row 0.
    Periodic,
    /// Open pipe \[PH95 I\]: starts empty; each step every empty inward channel
    /// (3, 4, 5) of the top row is filled with probability `inject`; particles
    /// leaving below row 0 are outflow, particles leaving above row L-1 are
    /// lost (counted separately).
    Open {
        /// Injection probability I per empty inward channel of the top row.
        inject: f64,
    },
}

/// The allowed densities of the periodic pipe, open at both ends (A8): rho
/// counts moving particles per site and a site has 6 moving channels, so
/// rho = 0 is an empty pipe (every bin density n_i / rho is 0/0) and rho = 6
/// a full one (every channel occupied, nothing can move, every observable
/// is constant). Both make the measured quantities NaN, so both are rejected.
pub const RHO_RANGE: (f64, f64) = (0.0, 6.0);

/// Parameters of a pipe run (MODEL.md A1-A9).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Params {
    /// W: number of columns (pipe width), >= 1.
    pub width: usize,
    /// L: number of rows (pipe length), a multiple of `bin`.
    pub length: usize,
    /// rho: moving particles per site at the start (A8, \[PH95 III A\]), in [`RHO_RANGE`]; the open pipe starts empty.
    pub rho: f64,
    /// p: probability of a dissipative collision, R2 and R3 (A3, \[PH94 (2)-(3)\]).
    pub p: f64,
    /// g: probability of each gravity move (A5, \[PH94 (6)\], \[PH95 Fig. 1c\]).
    pub g: f64,
    /// b: wall roughness, the bounce-back probability at a wall (A6, \[PH94 (7)\]).
    pub b: f64,
    /// Rows per bin for the bin densities n_i (A9), 10 in the papers.
    pub bin: usize,
    /// Periodic or open pipe (A7).
    pub boundary: Boundary,
}

impl Default for Params {
    /// PH94 Fig. 2: L = 220, W = 11, rho = 1, p = g = b = 0.5, bins of 10.
    fn default() -> Self {
        Params {
            width: 11,
            length: 220,
            rho: 1.0,
            p: 0.5,
            g: 0.5,
            b: 0.5,
            bin: 10,
            boundary: Boundary::Periodic,
        }
    }
}

/// Whether a W x L pipe with its wall and halo rows, (W + 2)(L + 2) sites,
/// fits the engines' 32-bit site index.
fn fits(width: usize, length: usize) -> bool {
    width
        .checked_add(2)
        .zip(length.checked_add(2))
        .and_then(|(w, l)| w.checked_mul(l))
        .is_some_and(|n| n <= u32::MAX as usize)
}

impl Params {
    /// Check every parameter against its allowed range (MODEL.md A8).
    pub fn validate(&self) -> Result<()> {
        check_min("W (width)", self.width, 1)?;
        check_min("L (length)", self.length, 1)?;
        check_min("bin", self.bin, 1)?;
        match self.boundary {
            Boundary::Periodic => {
                let (lo, hi) = RHO_RANGE;
                if !(self.rho.is_finite() && self.rho > lo && self.rho < hi) {
                    return Err(Error::new(
                        ErrorKind::InvalidParameter,
                        format!(
                            "rho = {} is outside the allowed range ({lo}, {hi}) (open interval: moving particles per site, \
                             6 channels; rho = 0 is an empty pipe, rho = 6 a full one that cannot move); choose rho in ({lo}, {hi})",
                            crate::error::num(self.rho)
                        ),
                    ));
                }
            }
            Boundary::Open { .. } => check_range("rho", self.rho, 0.0, 6.0)?,
        }
        check_unit("p", self.p)?;
        check_unit("g", self.g)?;
        check_unit("b", self.b)?;
        if let Boundary::Open { inject } = self.boundary {
            check_unit("I (injection)", inject)?;
        }
        if !fits(self.width, self.length) {
            // the exact product (no wrap-around) in the message
            // the sites with the wall and halo rows: (W + 2)(L + 2), exact
            return Err(Error::out_of_range(
                "(W + 2) * (L + 2)",
                format!(
                    "{} * {} = {}",
                    self.width as u128 + 2,
                    self.length as u128 + 2,
                    (self.width as u128 + 2) * (self.length as u128 + 2)
                ),
                &format!("[9, {}]", u32::MAX),
            ));
        }
        if self.length % self.bin != 0 {
            // the nearest lengths that fit: multiples of the bin, at least 2
            // bins, within the size bound (checked first, above)
            let lo = self.length / self.bin * self.bin;
            let near: Vec<String> = [lo, lo + self.bin]
                .iter()
                .filter(|&&l| l >= 2 * self.bin && fits(self.width, l))
                .map(|l| l.to_string())
                .collect();
            let near = match near.is_empty() {
                true => format!("{} or another multiple of it", 2 * self.bin),
                false => near.join(" or "),
            };
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                format!(
                    "L = {} is not a multiple of bin = {}; choose L = {} (a multiple of the bin, at least 2 bins)",
                    self.length,
                    self.bin,
                    near
                ),
            ));
        }
        Ok(())
    }

    /// Number of bins K = L / bin.
    pub fn bins(&self) -> usize {
        self.length / self.bin
    }

    /// Number of sites W * L.
    pub fn sites(&self) -> usize {
        self.width * self.length
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validation_names_the_value() {
        let bad = Params {
            length: 25,
            ..Params::default()
        };
        let e = Pipe::new(bad, Rules::default(), 0).unwrap_err();
        assert!(
            e.message.contains("L = 25") && e.message.contains("bin = 10"),
            "{}",
            e.message
        );
        let bad = Params {
            rho: 6.01,
            ..Params::default()
        };
        assert!(Pipe::new(bad, Rules::default(), 0)
            .unwrap_err()
            .message
            .contains("rho = 6.01"));
    }
}
