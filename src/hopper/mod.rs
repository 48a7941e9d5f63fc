//! The hopper automaton of Baxter & Behringer \[BB90\] (MODEL.md Part B):
//! grains with an orientation and a motion on the triangular lattice of
//! [`crate::lattice`], in a 60° wedge with an outlet, filled by rain and
//! emptied by opening a plug.
//!
//! ```
//! use granular_automata::hopper::{Hopper, HopperParams};
//! let mut h = Hopper::new(HopperParams::quick(), 7).unwrap();
//! h.fill(200, 400, 200);
//! let inside = h.grains();
//! h.open();
//! let mut out = 0;
//! for _ in 0..50 {
//!     out += h.step(false).outflow as u64;
//! }
//! assert_eq!(h.grains() + out, inside); // grains are conserved
//! ```

pub mod energy;
pub mod engine;
pub mod experiment;
pub mod geometry;
pub mod model;
pub mod observables;
pub mod picture;

pub use energy::{Aligned, DilationParams, DilationReading, EnergyParams, EnergyTable, RestPairs};
pub use geometry::{Geometry, GeometryParams};
pub use model::{
    ConflictRule, Dynamics, Hopper, HopperParams, RainParams, StepReport, UpdateOrder,
};
