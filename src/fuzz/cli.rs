//! The readers of the command line: whole numbers and reals with their
//! ranges (`cli::parse_count`, `parse_real`, `--runs`, `--threads`),
//! `--shard i/n`, pipe sizes `LxW`, `--rules`, `--engine`, and a pipe
//! figure's whole command line (`cli::PipeArgs`).

use super::mutate::mutate;
use super::{excerpt, Case, Rng, Verdict};
use crate::cli::{parse_count, parse_real, parse_runs, parse_threads, PipeArgs, MAX_THREADS};
use crate::ensemble::{Shard, MAX_RUNS};
use crate::pipe::open::PipeSize;
use crate::pipe::{Engine, Rules};
use clap::Parser;
use rand::RngExt;

/// Values of the kinds the command line takes, sound and odd.
const SEEDS: [&str; 24] = [
    "1",
    "64",
    "100000",
    "100001",
    "0",
    "-1",
    "1024",
    "1025",
    "0.5",
    "1e3",
    "nan",
    "inf",
    "3/8",
    "0/1",
    "8/8",
    "220x11",
    "0x5",
    "default",
    "ph94+wall-drag",
    "any-mover+rest-up",
    "fast",
    "reference",
    " 7 ",
    "18446744073709551616",
];

/// A pipe figure's options and sound values for them.
const OPTIONS: [(&str, &[&str]); 7] = [
    ("--tier", &["quick", "standard", "paper", "acceptance"]),
    ("--seed", &["1", "42", "18446744073709551615"]),
    ("--runs", &["1", "64", "100000"]),
    ("--out", &["results", "x/y"]),
    ("--shard", &["0/4", "3/4"]),
    ("--threads", &["1", "2"]),
    ("--rules", &["default", "ph94+gravity-last"]),
];

/// The command-line readers.
#[derive(Default)]
pub(crate) struct CommandLine {
    last: Vec<u8>,
}

/// `v` in `lo..=hi`, or what is wrong.
fn within<T: PartialOrd + std::fmt::Debug>(what: &str, v: T, lo: T, hi: T) -> Verdict {
    if lo <= v && v <= hi {
        Verdict::Accepted
    } else {
        Verdict::Silent(format!("{what} = {v:?} outside {lo:?}..={hi:?}"))
    }
}

impl CommandLine {
    /// One value for one reader.
    fn value(&mut self, rng: &mut Rng) -> Verdict {
        let seed = SEEDS[rng.random_range(0..SEEDS.len())];
        self.last = if rng.random_bool(0.8) {
            mutate(rng, seed.as_bytes())
        } else {
            seed.as_bytes().to_vec()
        };
        // an argument reaches the readers as text (clap refuses invalid UTF-8)
        let Ok(s) = std::str::from_utf8(&self.last) else {
            return Verdict::Refused;
        };
        match rng.random_range(0..8) {
            0 => parse_runs(s).map_or(Verdict::Refused, |n| within("--runs", n, 1, MAX_RUNS)),
            1 => parse_threads(s)
                .map_or(Verdict::Refused, |n| within("--threads", n, 1, MAX_THREADS)),
            2 => parse_count("--count", s, 2, 9)
                .map_or(Verdict::Refused, |n| within("count", n, 2, 9)),
            3 => parse_real("--rho", s, 0.0, 6.0).map_or(Verdict::Refused, |x| {
                if x.is_finite() {
                    within("rho", x, 0.0, 6.0)
                } else {
                    Verdict::Silent(format!("rho = {x}"))
                }
            }),
            4 => match s.parse::<Shard>() {
                Err(_) => Verdict::Refused,
                Ok(sh)
                    if sh.index < sh.count && sh.to_string().parse::<Shard>().ok() == Some(sh) =>
                {
                    Verdict::Accepted
                }
                Ok(sh) => Verdict::Silent(format!("shard {sh:?}")),
            },
            5 => match s.parse::<PipeSize>() {
                Err(_) => Verdict::Refused,
                Ok(p)
                    if p.length > 0
                        && p.width > 0
                        && p.to_string().parse::<PipeSize>().ok() == Some(p) =>
                {
                    Verdict::Accepted
                }
                Ok(p) => Verdict::Silent(format!("pipe size {p:?}")),
            },
            6 => match s.parse::<Rules>() {
                Err(_) => Verdict::Refused,
                Ok(r) if r.validate().is_ok() && r.to_string().parse::<Rules>().ok() == Some(r) => {
                    Verdict::Accepted
                }
                Ok(r) => Verdict::Silent(format!("rules {r:?}")),
            },
            _ => match s.parse::<Engine>() {
                Err(_) => Verdict::Refused,
                Ok(e) if Engine::NAMES.contains(&e.name()) => Verdict::Accepted,
                Ok(e) => Verdict::Silent(format!("engine {e:?}")),
            },
        }
    }

    /// A whole command line of a pipe figure.
    fn line(&mut self, rng: &mut Rng) -> Verdict {
        let mut args = vec!["fig".to_string()];
        for _ in 0..rng.random_range(0..=5) {
            let (name, values) = OPTIONS[rng.random_range(0..OPTIONS.len())];
            args.push(name.to_string());
            args.push(values[rng.random_range(0..values.len())].to_string());
        }
        let joined = args[1..].join("\u{1f}");
        self.last = mutate(rng, joined.as_bytes());
        let text = String::from_utf8_lossy(&self.last);
        let argv = std::iter::once("fig").chain(text.split('\u{1f}'));
        let Ok(a) = PipeArgs::try_parse_from(argv) else {
            return Verdict::Refused;
        };
        let c = &a.common;
        let ok = c.runs.is_none_or(|n| (1..=MAX_RUNS).contains(&n))
            && c.threads.is_none_or(|n| (1..=MAX_THREADS).contains(&n))
            && c.shard.is_none_or(|s| s.index < s.count);
        if ok {
            Verdict::Accepted
        } else {
            Verdict::Silent(format!("options {c:?}"))
        }
    }
}

impl Case for CommandLine {
    fn one(&mut self, rng: &mut Rng) -> Verdict {
        if rng.random_bool(0.8) {
            self.value(rng)
        } else {
            self.line(rng)
        }
    }

    fn input(&self) -> String {
        excerpt(&self.last)
    }
}
