//! # granular-automata
//!
//! A validated reference implementation of two classic cellular-automaton
//! models of granular flow, with one binary per published figure:
//!
//! - the **pipe lattice gas** of Peng & Herrmann (PH94, PH95): particles on a
//!   triangular lattice in a vertical pipe with dissipative collisions (p),
//!   gravity (g) and rough walls (b), see [`pipe`];
//! - the **hopper automaton** of Baxter & Behringer (BB90).
//!
//! The exact rules are in `../shared/MODEL.md`; every choice the papers leave
//! open is a named variant.
#![deny(missing_docs)]

pub mod analysis;
pub mod cli;
pub mod ensemble;
pub mod error;
pub mod hopper;
pub mod lattice;
pub mod pipe;
pub mod plot;
pub mod report;
pub mod run;

pub use error::{Error, ErrorKind, Result};
