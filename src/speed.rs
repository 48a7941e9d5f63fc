//! Speed against accuracy: for each figure of [`KEYS`],
//! one key statistic's standard error against the CPU-seconds it cost, at
//! each tier and with each engine, so a user can choose the cheapest run
//! that gives the error bar they need.
//!
//! The figures run as subprocesses (the figure binaries beside this one,
//! as in [`crate::report`]), each into a folder of its own
//! (`OUT/speed-accuracy/runs/<tier>-<engine>/`); their `summary.json`
//! carries `cpu_seconds` ([`crate::run::cpu_seconds`]). A configuration
//! whose summary is already there is read, not rerun; one left half done
//! (no summary) is started again from nothing, so that its CPU time counts
//! the whole run.
//!
//! The error bar of a statistic is normalised by a scale fixed here in
//! advance ([`Key::scale`]: the claim's margin, or the threshold of a
//! threshold claim), so every figure fits one plot. A run *resolves* its
//! key when `k SE <= scale / 2` (k of the one grading rule,
//! [`crate::analysis::grading`]): then a measured value within half the
//! margin of the target can still be graded reproduced.

use crate::analysis::grading::{coverage_factor, Estimate};
use crate::error::{Error, ErrorKind, Result};
use crate::plot::{line_chart, Line, PALETTE};
use crate::report::{run_figure, Options};
use crate::run::Tier;
use plotters::prelude::{RGBColor, SeriesLabelPosition};
use serde::Serialize;
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Where a figure's key statistic is read in its `summary.json`.
#[derive(Debug, Clone, Copy)]
pub enum Source {
    /// A check: its `measured`, `error` and `runs`.
    Check(&'static str),
    /// A metric `name` with its error `name_err`; runs = number of seeds.
    Metric(&'static str),
}

/// One figure's key statistic.
#[derive(Debug, Clone, Copy)]
pub struct Key {
    /// The figure binary.
    pub figure: &'static str,
    /// Where its statistic is read.
    pub source: Source,
    /// What the statistic is, in words.
    pub what: &'static str,
    /// The scale its error is measured against (fixed before measuring):
    /// the margin of the claim it decides, or its threshold.
    pub scale: f64,
    /// Whether it is a pipe figure (has `--engine`); the hopper has only
    /// the reference engine.
    pub pipe: bool,
    /// Arguments that restrict the figure to what the statistic needs.
    pub args: &'static [&'static str],
}

/// The figures measured and their key statistics.
pub const KEYS: [Key; 5] = [
    Key {
        figure: "fig1",
        source: Source::Check("waves_a"),
        what: "PH94 Fig. 1a: s_low (waves at p = 0.1), threshold 2",
        scale: crate::drivers::claims::WAVE_THRESHOLD,
        pipe: true,
        args: &[],
    },
    Key {
        figure: "fig2",
        source: Source::Check("alpha"),
        what: "PH94 Fig. 2: alpha, margin 0.1",
        scale: crate::drivers::margins::ALPHA_MARGIN,
        pipe: true,
        args: &[],
    },
    Key {
        figure: "waves-fig5",
        source: Source::Check("wave_speed"),
        what: "PH95 Fig. 5: wave speed at L = 512, margin 0.05",
        scale: 0.05,
        pipe: true,
        args: &[],
    },
    Key {
        figure: "waves-fig8",
        source: Source::Metric("alpha_p0.5"),
        what: "PH95 Fig. 8: alpha at p = 0.5, margin 0.1",
        scale: crate::drivers::margins::ALPHA_MARGIN,
        pipe: true,
        args: &["--p", "0,0.5"],
    },
    Key {
        figure: "hopper-fig3",
        source: Source::Check("beta1_bond_white_spectrum"),
        what: "BB90 Fig. 3: slope of the outflow spectrum (beta = 1, the default reading along-bond), margin 0.1",
        scale: 0.1,
        pipe: false,
        args: &["--cases", "beta1_bond"],
    },
];

/// One measured configuration: a figure at a tier with an engine.
#[derive(Debug, Clone, Serialize)]
pub struct Point {
    /// The figure binary.
    pub figure: String,
    /// Its key statistic ([`Key::what`]).
    pub statistic: String,
    /// Tier.
    pub tier: String,
    /// Engine.
    pub engine: String,
    /// Independent runs behind the standard error.
    pub runs: usize,
    /// CPU seconds of the figure's run (all threads).
    pub cpu_seconds: f64,
    /// Wall seconds of the figure's run.
    pub wall_seconds: f64,
    /// Site updates computed.
    pub site_updates: f64,
    /// The statistic.
    pub measured: f64,
    /// Its standard error over runs.
    pub se: f64,
    /// [`Key::scale`].
    pub scale: f64,
    /// k of the grading rule for `runs`.
    pub k: f64,
    /// k SE / scale: below 1/2 the run resolves its key.
    pub resolution: f64,
    /// CPU seconds at which k SE would reach scale / 2 with this tier and
    /// engine, if SE falls as 1 / sqrt(runs) (an extrapolation; equal to
    /// nothing when SE is zero).
    pub cpu_to_resolve: f64,
}

/// What the `speed-accuracy` command runs.
#[derive(Debug, Clone)]
pub struct Plan {
    /// Tiers to run.
    pub tiers: Vec<Tier>,
    /// Engines to run (pipe figures; the hopper runs the reference only).
    pub engines: Vec<String>,
    /// The keys (figures) to run.
    pub keys: Vec<Key>,
    /// Output folder; this command writes to `out/speed-accuracy/`.
    pub out: PathBuf,
    /// `--threads` of every figure.
    pub threads: usize,
    /// `--seed` of every figure.
    pub seed: u64,
    /// The folder of the figure binaries.
    pub bin_dir: PathBuf,
    /// Further folders of earlier figure runs (their `--out`), read for
    /// summaries with `cpu_seconds` (e.g. a paper tier run elsewhere).
    pub from: Vec<PathBuf>,
}

/// The keys named in `list` (comma-separated figure names), or every key.
pub fn select_keys(list: Option<&str>) -> Result<Vec<Key>> {
    let Some(list) = list else {
        return Ok(KEYS.to_vec());
    };
    let names: Vec<&str> = KEYS.iter().map(|k| k.figure).collect();
    let given: Vec<&str> = list.split(',').map(str::trim).collect();
    crate::error::reject_duplicates("--figures", &given)?;
    list.split(',')
        .map(str::trim)
        .map(|f| {
            KEYS.iter().find(|k| k.figure == f).copied().ok_or_else(|| {
                Error::new(
                    ErrorKind::InvalidParameter,
                    format!(
                        "--figures: '{f}' has no key statistic; choose from {}",
                        names.join(", ")
                    ),
                )
            })
        })
        .collect()
}

/// Read `dir/<figure>/summary.json`: `None` if it is not there, an
/// [`ErrorKind::Io`] error naming it if it cannot be read or is not JSON.
fn read_summary(dir: &Path, figure: &str) -> Result<Option<Value>> {
    let path = dir.join(figure).join("summary.json");
    let bad = |why: String| {
        Error::new(
            ErrorKind::Io,
            format!("{} {why}; delete it or rerun that figure", path.display()),
        )
    };
    let text = match std::fs::read_to_string(&path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(bad(format!("cannot be read ({e})"))),
    };
    serde_json::from_str(&text)
        .map(Some)
        .map_err(|e| bad(format!("is not JSON ({e})")))
}

/// The [`Point`] of `key` in summary `s`, if `s` has CPU time and the
/// statistic has a finite value and error.
pub fn point(key: &Key, s: &Value) -> Option<Point> {
    let cpu = s["cpu_seconds"].as_f64()?;
    let (measured, se, runs) = statistic(key, s)?;
    // fewer than 3 runs have no k (the one rule: undecided): no point
    let half = Estimate::new(measured, se, runs).half_width()?;
    let k = coverage_factor(runs)?;
    let resolution = half / key.scale;
    Some(Point {
        figure: key.figure.to_string(),
        statistic: key.what.to_string(),
        tier: s["tier"].as_str()?.to_string(),
        engine: s["engine"].as_str().unwrap_or("reference").to_string(),
        runs,
        cpu_seconds: cpu,
        wall_seconds: s["wall_seconds"].as_f64()?,
        site_updates: s["site_updates"].as_f64()?,
        measured,
        se,
        scale: key.scale,
        k,
        resolution,
        cpu_to_resolve: cpu * (resolution / 0.5).powi(2),
    })
}

/// `key`'s statistic in summary `s`: (value, standard error, runs).
fn statistic(key: &Key, s: &Value) -> Option<(f64, f64, usize)> {
    let (measured, se, runs) = match key.source {
        Source::Check(name) => {
            let c = s["checks"]
                .as_array()?
                .iter()
                .find(|c| c["name"].as_str() == Some(name))?;
            (
                c["measured"].as_f64()?,
                c["error"].as_f64()?,
                c["runs"].as_u64()? as usize,
            )
        }
        Source::Metric(name) => (
            s["metrics"][name].as_f64()?,
            s["metrics"][format!("{name}_err")].as_f64()?,
            s["seeds"].as_array()?.len(),
        ),
    };
    Some((measured, se, runs))
}

/// Run (or read) every configuration of `plan` and return its points, in
/// the order figure, tier, engine; then those found in `plan.from`.
pub fn measure(plan: &Plan) -> Result<Vec<Point>> {
    // the --from summaries are read before anything runs: a folder that is
    // not there or a damaged summary is named at once
    let mut earlier = Vec::new();
    for dir in &plan.from {
        if !dir.is_dir() {
            return Err(Error::new(
                ErrorKind::Io,
                format!(
                    "--from {}: no such folder; give the --out folder of earlier figure runs",
                    dir.display()
                ),
            ));
        }
        for key in &plan.keys {
            if let Some(p) = read_summary(dir, key.figure)?.and_then(|s| point(key, &s)) {
                earlier.push(p);
            }
        }
    }
    let mut points = Vec::new();
    for key in &plan.keys {
        for &tier in &plan.tiers {
            let engines: Vec<&str> = if key.pipe {
                plan.engines.iter().map(String::as_str).collect()
            } else {
                vec!["reference"]
            };
            for engine in engines {
                let dir = plan
                    .out
                    .join("speed-accuracy")
                    .join("runs")
                    .join(format!("{}-{engine}", tier.name()));
                // a summary of another revision of the engine is run again
                let label = if key.pipe {
                    engine.parse::<crate::pipe::Engine>()?.label()
                } else {
                    "reference".to_string()
                };
                // a damaged summary of our own is run again
                let done = read_summary(&dir, key.figure).ok().flatten().filter(|s| {
                    s["cpu_seconds"].is_number()
                        && s["engine"].as_str().unwrap_or("reference") == label
                });
                let summary = match done {
                    Some(s) => s,
                    None => run_one(plan, key, tier, engine, &dir)?,
                };
                if let Some((_, _, runs @ 0..3)) = statistic(key, &summary) {
                    println!(
                        "{:12} {:8} {:9} {runs} runs: fewer than 3, no error bar by the one grading rule; left out",
                        key.figure,
                        tier.name(),
                        engine
                    );
                    continue;
                }
                let p = point(key, &summary).ok_or_else(|| {
                    Error::new(
                        ErrorKind::Io,
                        format!(
                            "{}/{}/summary.json has no finite {:?} with its error over >= 3 runs (the one grading rule)",
                            dir.display(),
                            key.figure,
                            key.source
                        ),
                    )
                })?;
                println!(
                    "{:12} {:8} {:9} {:>9.1} CPU-s  {:.4} +- {:.4} ({} runs)  k SE/scale = {:.3}",
                    p.figure,
                    p.tier,
                    p.engine,
                    p.cpu_seconds,
                    p.measured,
                    p.se,
                    p.runs,
                    p.resolution
                );
                points.push(p);
            }
        }
    }
    points.extend(earlier);
    Ok(points)
}

/// Run `key`'s figure at `tier` with `engine` into `dir`, from nothing.
fn run_one(plan: &Plan, key: &Key, tier: Tier, engine: &str, dir: &Path) -> Result<Value> {
    let stale = dir.join(key.figure);
    if stale.exists() {
        std::fs::remove_dir_all(&stale).map_err(|e| {
            Error::new(
                ErrorKind::Io,
                format!("cannot remove the unfinished {}: {e}", stale.display()),
            )
        })?;
    }
    let mut extra: Vec<String> = key.args.iter().map(|a| a.to_string()).collect();
    if key.pipe {
        extra.extend(["--engine".to_string(), engine.to_string()]);
    }
    let opts = Options {
        tier,
        figures: vec![key.figure.to_string()],
        out: dir.to_path_buf(),
        seed: Some(plan.seed),
        threads: Some(plan.threads),
        engine: None,
        extra: BTreeMap::from([(key.figure.to_string(), extra)]),
        bin_dir: plan.bin_dir.clone(),
        command_line: String::new(),
        no_run: false,
        seed_sets: None,
    };
    let r = run_figure(&opts, key.figure);
    if !r.ok {
        return Err(Error::new(
            ErrorKind::Io,
            format!(
                "{} --tier {} --engine {engine} failed: {}",
                key.figure,
                tier.name(),
                r.failure.unwrap_or_default()
            ),
        ));
    }
    read_summary(dir, key.figure)?.ok_or_else(|| {
        Error::new(
            ErrorKind::Io,
            format!(
                "{} wrote no summary.json into {}",
                key.figure,
                dir.display()
            ),
        )
    })
}

/// The cheapest measured configuration of each figure that resolves its
/// key (k SE <= scale / 2); where none does, the one whose extrapolated
/// [`Point::cpu_to_resolve`] is least, marked as extrapolated.
pub fn recommend(points: &[Point]) -> Vec<(String, String)> {
    // each figure once, in the order of first appearance (points read
    // with --from come after the measured ones)
    let mut figures: Vec<&str> = Vec::new();
    for p in points {
        if !figures.contains(&p.figure.as_str()) {
            figures.push(&p.figure);
        }
    }
    figures
        .into_iter()
        .map(|f| {
            let of: Vec<&Point> = points.iter().filter(|p| p.figure == f).collect();
            let resolved = of
                .iter()
                .filter(|p| p.resolution <= 0.5)
                .min_by(|a, b| a.cpu_seconds.total_cmp(&b.cpu_seconds));
            let text = match resolved {
                Some(p) => format!(
                    "tier {} with the {} engine resolves it: {:.4} +- {:.4} ({} runs) in {:.0} CPU-s",
                    p.tier, p.engine, p.measured, p.se, p.runs, p.cpu_seconds
                ),
                None => match of
                    .iter()
                    .filter(|p| p.cpu_to_resolve.is_finite())
                    .min_by(|a, b| a.cpu_to_resolve.total_cmp(&b.cpu_to_resolve))
                {
                    Some(p) => format!(
                        "no run resolves it; extrapolated: tier {} with the {} engine and {:.0}x the runs, about {:.0} CPU-s",
                        p.tier,
                        p.engine,
                        (p.cpu_to_resolve / p.cpu_seconds).ceil(),
                        p.cpu_to_resolve
                    ),
                    None => "no run resolves it, and none can be extrapolated".to_string(),
                },
            };
            (f.to_string(), text)
        })
        .collect()
}

/// Write `speed-accuracy.csv`, `summary.json` (the points and
/// [`recommend`]) and the log-log plot `speed-accuracy.png`
/// (k SE / scale against CPU-seconds, one series per figure and engine)
/// into `dir`.
pub fn write(dir: &Path, points: &[Point]) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| {
        Error::new(
            ErrorKind::Io,
            format!("cannot create {}: {e}", dir.display()),
        )
    })?;
    let mut csv = String::from(
        "figure,tier,engine,runs,cpu_seconds,wall_seconds,site_updates,measured,se,scale,k,k_se_over_scale,cpu_to_resolve\n",
    );
    for p in points {
        csv.push_str(&format!(
            "{},{},{},{},{:.2},{:.2},{:.4e},{},{},{},{:.4},{:.5},{:.1}\n",
            p.figure,
            p.tier,
            p.engine,
            p.runs,
            p.cpu_seconds,
            p.wall_seconds,
            p.site_updates,
            p.measured,
            p.se,
            p.scale,
            p.k,
            p.resolution,
            p.cpu_to_resolve
        ));
    }
    crate::run::write_atomic(&dir.join("speed-accuracy.csv"), csv.as_bytes())?;
    let summary = serde_json::json!({
        "figure": "speed-accuracy",
        "points": points,
        "recommendations": recommend(points)
            .into_iter()
            .map(|(f, r)| serde_json::json!({"figure": f, "recommendation": r}))
            .collect::<Vec<_>>(),
    });
    let text = serde_json::to_string_pretty(&summary)
        .map_err(|e| Error::new(ErrorKind::Io, format!("cannot serialise summary: {e}")))?;
    crate::run::write_atomic(&dir.join("summary.json"), text.as_bytes())?;
    // one colour per figure, the fast engine's points in a lighter shade
    let mut figures: Vec<&str> = Vec::new();
    let mut lines: Vec<Line> = Vec::new();
    for p in points {
        if !figures.contains(&p.figure.as_str()) {
            figures.push(&p.figure);
        }
        let base =
            PALETTE[figures.iter().position(|f| *f == p.figure).unwrap_or(0) % PALETTE.len()];
        let color = if p.engine.split('@').next() == Some("reference") {
            base
        } else {
            let light = |c: u8| ((c as u16 + 2 * 255) / 3) as u8;
            RGBColor(light(base.0), light(base.1), light(base.2))
        };
        let label = format!("{} ({})", p.figure, p.engine);
        match lines.iter_mut().find(|l| l.label == label) {
            Some(l) => l.points.push((p.cpu_seconds, p.resolution)),
            None => {
                lines.push(Line::new(&label, vec![(p.cpu_seconds, p.resolution)], color).markers())
            }
        }
    }
    let cpus: Vec<f64> = points.iter().map(|p| p.cpu_seconds).collect();
    let (lo, hi) = cpus
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), &c| (a.min(c), b.max(c)));
    let top = points.iter().map(|p| p.resolution).fold(0.0f64, f64::max);
    if lo.is_finite() && hi > 0.0 {
        lines.push(Line::new(
            "resolved below this line (k SE = scale / 2)",
            vec![(lo, 0.5), (hi, 0.5)],
            plotters::style::BLACK,
        ));
        // a guide of slope -1/2, above the points (it also leaves the
        // legend room above them)
        lines.push(Line::new(
            "slope of SE against CPU at a fixed set-up (CPU^-1/2)",
            vec![(lo, 8.0 * top), (hi, 8.0 * top * (lo / hi).sqrt())],
            RGBColor(150, 150, 150),
        ));
    }
    line_chart(
        &dir.join("speed-accuracy.png"),
        "granular-automata: error bar of each figure's key statistic against its CPU cost",
        "CPU seconds (all threads)",
        "k SE / scale (margin or threshold)",
        &lines,
        true,
        SeriesLabelPosition::UpperRight,
    )
}
