//! # granular-automata
//!
//! A validated reference implementation of two classic cellular-automaton
//! models of granular flow, with one binary per published figure and tests
//! that grade the results against the published values.
//!
//! ## Map
//!
//! **The two automata.**
//!
//! - The **pipe lattice gas** of Peng & Herrmann (PH94, PH95): particles on a
//!   triangular lattice in a vertical pipe, dissipative collisions (p),
//!   gravity (g), rough walls (b). Engine and rule readings in [`pipe`]
//!   ([`pipe::Pipe`], [`pipe::Rules`], default `ph94+gravity-first+wall-move+inject-late`);
//!   the open pipe in [`pipe::open`]; observables in [`pipe::observables`],
//!   [`pipe::overlap`] and [`drivers::spectra`]; the graded claims in
//!   [`drivers::claims`].
//! - The **hopper automaton** of Baxter & Behringer (BB90): oriented grains
//!   choosing the state of least energy in a 60° wedge, filled by rain and
//!   emptied through an outlet. In [`hopper`] ([`hopper::Hopper`]).
//!
//! Both use the lattice of [`lattice`]; spectra, fits and the one grading
//! rule are in [`analysis`].
//!
//! **The figure binaries** (`reproduce/`, one per published figure:
//! `fig1`, `fig2` for PH94; `waves-fig2` ... `waves-fig12` for PH95;
//! `hopper-fig2`, `hopper-fig3` for BB90; plus `pipe-matrix`, the grading of
//! every rule reading against every claim). Each takes `--tier quick`
//! (seconds, what the tests run), `standard` (minutes) or `paper` (the
//! published sizes), see [`run::Tier`], and the shared options of [`cli`];
//! each writes PNGs, CSVs and a `summary.json` with its checks
//! ([`run::Summary`]) under `--out DIR/<binary>/`. Runs are pure functions of
//! (parameters, rules, seed); the ensemble runner is [`ensemble`].
//!
//! **The engine contract** ([`validate`], `VALIDATION.md`): a `validate`
//! command that checks another implementation against this reference
//! engine; the bytes of a run and the golden snapshots in `golden/` are the
//! baseline of the reference engine itself.
//!
//! **The documents** (in the repository root):
//!
//! - `MODEL.md`: the specification: every rule with the papers' item and
//!   section, every choice the papers leave open and the default taken, the
//!   observables, the published targets. The code cites its sections as
//!   "MODEL.md A5".
//! - `READINGS.md`: every place where the papers' text allows more than one
//!   implementation, with the named variant of each option.
//! - `EXPERIMENTS.md`: every measured number with its command, tier, seeds,
//!   ensemble size and wall time.
//!
//! Errors are values of [`Error`]: every failure names the offending value
//! and the allowed range.
#![deny(missing_docs)]

pub mod analysis;
pub mod cli;
pub mod drivers;
pub mod ensemble;
pub mod error;
pub mod experiments;
pub mod fuzz;
pub mod hopper;
pub mod lattice;
pub mod pipe;
pub mod plot;
pub mod report;
pub mod run;
pub mod speed;
pub mod validate;

pub use error::{Error, ErrorKind, Result};
