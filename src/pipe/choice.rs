//! Which implementation runs a pipe figure (`--engine`): the
//! choice between the two engines that implement the contract of
//! [`super::engine`]. It sits above both, so neither engine imports the
//! other.

use super::engine::{EngineBuilder, PipeEngine, Reference};
use super::fast::Fast;
use super::{Params, Rules};
use crate::error::Result;

/// Which implementation runs a pipe figure (`--engine`): the
/// plain reference engine [`Pipe`](super::Pipe) or the bit-sliced fast engine
/// ([`FastPipe`](super::fast::FastPipe)), which `validate` checks against it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Engine {
    /// [`Pipe`](super::Pipe), one byte per site (the default).
    #[default]
    Reference,
    /// [`FastPipe`](super::fast::FastPipe), 64 sites per word and channel.
    Fast,
}

impl Engine {
    /// The engine names `--engine` accepts.
    pub const NAMES: [&'static str; 2] = ["reference", "fast"];

    /// A new run of this engine (validated parameters; MODEL.md A8 start).
    pub fn build(self, params: Params, rules: Rules, seed: u64) -> Result<Box<dyn PipeEngine>> {
        match self {
            Engine::Reference => Reference.build(params, rules, seed),
            Engine::Fast => Fast.build(params, rules, seed),
        }
    }

    /// Its name, as `--engine` takes it.
    pub fn name(self) -> &'static str {
        Engine::NAMES[self as usize]
    }

    /// The revision of this engine's dynamics, from 1. Raise it whenever the
    /// same (parameters, rules, seed) give a different run: a changed rule,
    /// another order or use of the random draws. Saved runs are keyed by
    /// [`Engine::label`], so a resumed ensemble never mixes runs of two
    /// revisions. `tests/engines.rs` pins a fingerprint of each
    /// revision and fails until this is raised.
    pub fn revision(self) -> u32 {
        match self {
            Engine::Reference => 1,
            Engine::Fast => 1,
        }
    }

    /// The engine as the keys of saved runs and summary.json record it: its
    /// name, followed by `@` and the revision from revision 2 on. Revision 1
    /// is the bare name, the label of every run saved before revisions were
    /// recorded, so those runs still resume.
    pub fn label(self) -> String {
        match self.revision() {
            1 => self.name().to_string(),
            r => format!("{}@{r}", self.name()),
        }
    }
}

impl std::fmt::Display for Engine {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Engine {
    type Err = crate::error::Error;
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "reference" => Ok(Engine::Reference),
            "fast" => Ok(Engine::Fast),
            other => Err(crate::error::Error::new(
                crate::error::ErrorKind::InvalidParameter,
                format!(
                    "--engine {other} is not known; use one of: {}",
                    Engine::NAMES.join(", ")
                ),
            )),
        }
    }
}

impl serde::Serialize for Engine {
    /// Serialised as its [`Engine::label`] (name and revision).
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.serialize_str(&self.label())
    }
}
