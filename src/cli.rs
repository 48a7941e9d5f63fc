//! Command-line options shared by every figure binary (the output contract
//! of DEVELOPERS.md): `--tier`, `--seed`, `--runs`, `--rules`, `--out`.

use crate::pipe::rules::RULE_NAMES;
use crate::pipe::Rules;
use crate::run::Tier;
use std::path::PathBuf;

/// Options every figure binary takes (flatten into its own `clap::Parser`).
#[derive(Debug, Clone, clap::Args)]
pub struct Common {
    /// How much to compute: quick (seconds), standard (minutes), paper (published sizes).
    #[arg(long, value_enum, default_value_t = Tier::Quick)]
    pub tier: Tier,
    /// Base seed; run i of an ensemble uses derive_seed(seed, i).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Number of independent runs to average (default: set by the tier).
    #[arg(long)]
    pub runs: Option<usize>,
    /// Output folder; the figure writes into OUT/<binary>/.
    #[arg(long, default_value = "results")]
    pub out: PathBuf,
}

/// The `--rules` option of the pipe figures.
#[derive(Debug, Clone, clap::Args)]
pub struct PipeRules {
    /// Rule reading: names joined by '+', e.g. ph94, any-mover, ph94+wall-drag,
    /// any-mover+gravity-first+rest-up ('--rules help' lists them).
    #[arg(long, default_value = "default")]
    pub rules: String,
}

impl PipeRules {
    /// Parse the rules; `help` prints the known names and exits.
    pub fn parse(&self) -> crate::Result<Rules> {
        if self.rules == "help" {
            for (name, what) in RULE_NAMES {
                println!("{name:14} {what}");
            }
            std::process::exit(0);
        }
        self.rules.parse()
    }
}

impl Common {
    /// `--runs` if given, else the tier's default; at least 1.
    pub fn runs_or(&self, quick: usize, standard: usize, paper: usize) -> usize {
        self.runs
            .unwrap_or(self.tier.pick(quick, standard, paper))
            .max(1)
    }
}
