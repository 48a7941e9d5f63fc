//! The hopper behind the external-program contract (MODEL.md Part B;
//! VALIDATION.md, "The external contract: the hopper").
//!
//! `validate` starts `sh -c 'COMMAND "$@"' sh hopper --plan -` and writes
//! one [`HopperPlan`] on its stdin: the parameters, a seed, the state to
//! start from (every site value and spacing, and whether the plug is open;
//! `null`: a new, empty hopper) and one action: report the energies of some
//! grains, fill, or run some iterations. The program prints NDJSON lines
//! ([`EnergyLine`], [`StepLine`], [`EndLine`]) and exits 0.
//!
//! On this side, [`External`] is a [`HopperBuilder`] whose engine
//! ([`Proxy`]) keeps the state, and hands it to the program whenever the
//! engine is asked to compute: so both levels of the hopper part run
//! unchanged. Level 1 prepares states site by site and asks for energies
//! (one run of the program per question) or one iteration; level 2 fills
//! (one run) and empties (one run for all its iterations).

use super::candidate::External;
use crate::error::{Error, ErrorKind, Result};
use crate::hopper::engine::{HopperBuilder, HopperEngine};
use crate::hopper::geometry::{Geometry, SiteKind};
use crate::hopper::model::{is_grain, Hopper, HopperParams, StepReport, HOLE, WALL};
use crate::run::derive_seed;
use serde::{Deserialize, Serialize};
use std::cell::Cell;
use std::time::Duration;

/// One run of an external hopper program.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct HopperPlan {
    /// The hopper (MODEL.md Part B).
    pub params: HopperParams,
    /// The seed of this run.
    pub seed: u64,
    /// Where to start: `None` for a new hopper (empty, plug closed).
    pub state: Option<HopperState>,
    /// What to do.
    pub action: HopperAction,
}

/// A hopper's state, site by site (`y * width + x`, MODEL.md B2).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HopperState {
    /// Site values: 0 a hole, 255 a wall, 1..=21 a grain `1 + 7 O + v`.
    pub sites: Vec<u8>,
    /// Running mean spacing D_i of every site (read on grains only).
    pub spacing: Vec<f64>,
    /// Whether the plug is open.
    pub open: bool,
}

/// What a run does after setting up the state.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum HopperAction {
    /// Print one [`EnergyLine`] per site: E_i of every state the grain there
    /// may take (MODEL.md B3-B4), in the state as set up.
    Energies {
        /// Sites holding grains.
        sites: Vec<usize>,
    },
    /// Rain until `target` grains were added (grains of the state count as
    /// added) or `max_iterations` passed, then settle without rain until
    /// nothing moves, at most `max_settle` iterations (MODEL.md B5); print
    /// one [`EndLine`].
    Fill {
        /// Grains to add.
        target: u64,
        /// Most iterations of rain.
        max_iterations: u64,
        /// Most iterations of settling.
        max_settle: u64,
    },
    /// Run `n` iterations (rain on the top row if `rain`); print one
    /// [`StepLine`] per iteration, then one [`EndLine`].
    Steps {
        /// Iterations.
        n: u64,
        /// Rain during them.
        rain: bool,
    },
}

/// The energies of one grain (action `energies`).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct EnergyLine {
    /// The site.
    pub site: usize,
    /// (state 0..21, E) of every state the grain may take.
    pub energies: Vec<(usize, f64)>,
}

/// One iteration (action `steps`).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct StepLine {
    /// What it did.
    pub report: StepReport,
    /// Moving grains of orientation 0, 1, 2 after it.
    pub moving: [u64; 3],
}

/// The end of a `fill` or `steps` run.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct EndLine {
    /// The state reached.
    pub state: HopperState,
    /// Grains added by rain during the run.
    pub added: u64,
    /// Grains that left through the outlet during the run.
    pub removed: u64,
    /// Iterations done.
    pub iterations: u64,
    /// Work done (any measure; for the report only).
    #[serde(default)]
    pub site_updates: f64,
}

/// The external side for a Rust hopper engine: read a [`HopperPlan`] from
/// `input`, run it with `builder`, write its lines to `output` (what
/// `validate-example hopper --plan -` does with the reference).
pub fn serve(
    builder: &dyn HopperBuilder,
    input: &mut dyn std::io::Read,
    output: &mut dyn std::io::Write,
) -> Result<()> {
    let (plan, mut e) = load(builder, input)?;
    act(plan.action, e.as_mut(), output)
}

/// Read a [`HopperPlan`] from `input`, check it, build its hopper with
/// `builder` and set up its state: the plan and the hopper, or a typed
/// error naming what is wrong.
pub fn load(
    builder: &dyn HopperBuilder,
    input: &mut dyn std::io::Read,
) -> Result<(HopperPlan, Box<dyn HopperEngine>)> {
    let plan: HopperPlan = super::candidate::read_plan(input, "HopperPlan")?;
    check_plan(&plan)?;
    let mut e = builder.build(plan.params, plan.seed)?;
    if let Some(st) = &plan.state {
        set_up(e.as_mut(), st)?;
    }
    Ok((plan, e))
}

/// Do `action` on the hopper `e` set up by [`load`], writing its lines to
/// `output`.
pub fn act(
    action: HopperAction,
    e: &mut dyn HopperEngine,
    output: &mut dyn std::io::Write,
) -> Result<()> {
    let (added, removed, it) = (e.added(), e.removed(), e.iteration());
    let mut line = |v: &dyn erased::Line| -> Result<()> {
        writeln!(output, "{}", v.json())?;
        Ok(())
    };
    match action {
        HopperAction::Energies { sites } => {
            for site in sites {
                let energies = e.energies(site)?;
                line(&EnergyLine { site, energies })?;
            }
            return Ok(());
        }
        HopperAction::Fill {
            target,
            max_iterations,
            max_settle,
        } => {
            e.fill(target, max_iterations, max_settle);
        }
        HopperAction::Steps { n, rain } => {
            // one line per step as it is taken (as `empty_steps` does, streamed)
            for _ in 0..n {
                let report = e.step(rain);
                let moving = crate::hopper::engine::moving_by_orientation(e.sites());
                line(&StepLine { report, moving })?;
            }
        }
    }
    line(&EndLine {
        state: HopperState {
            sites: e.sites().to_vec(),
            spacing: e.spacing().to_vec(),
            open: e.is_open(),
        },
        added: e.added() - added,
        removed: e.removed() - removed,
        iterations: e.iteration() - it,
        site_updates: e.site_updates(),
    })
}

/// Most iterations one hopper plan may ask for (a hopper empties in some
/// thousands; the cap stops a plan that would run without end).
pub const MAX_ITERATIONS: u64 = 10_000_000;

/// Check a hopper plan's iteration counts against [`MAX_ITERATIONS`].
fn check_plan(plan: &HopperPlan) -> Result<()> {
    let counts: Vec<(&str, u64)> = match &plan.action {
        HopperAction::Energies { .. } => vec![],
        HopperAction::Fill {
            max_iterations,
            max_settle,
            ..
        } => vec![
            ("max_iterations", *max_iterations),
            ("max_settle", *max_settle),
        ],
        HopperAction::Steps { n, .. } => vec![("n", *n)],
    };
    for (name, v) in counts {
        if v > MAX_ITERATIONS {
            return Err(Error::out_of_range(
                name,
                v,
                &format!("[0, {MAX_ITERATIONS}]"),
            ));
        }
    }
    Ok(())
}

/// One printable line (a tiny object-safe wrapper of serde's Serialize).
mod erased {
    pub trait Line {
        fn json(&self) -> String;
    }
    impl<T: serde::Serialize> Line for T {
        fn json(&self) -> String {
            serde_json::to_string(self).expect("a line serialises")
        }
    }
}

/// Set up `e` (a new hopper) in state `st`: every inside site's value,
/// every grain's spacing, and the plug.
pub fn set_up(e: &mut dyn HopperEngine, st: &HopperState) -> Result<()> {
    let n = e.sites().len();
    if let Some(why) = state_fault(e.geometry(), st, false) {
        return Err(Error::new(
            ErrorKind::InvalidParameter,
            format!("the plan's state {why}"),
        ));
    }
    if st.open {
        e.open();
    }
    let inside: Vec<usize> = (0..n)
        .filter(|&i| e.geometry().kind[i] == SiteKind::Inside)
        .collect();
    for &i in &inside {
        if e.sites()[i] != st.sites[i] {
            e.set_site(i, st.sites[i])?;
        }
    }
    for &i in &inside {
        if is_grain(st.sites[i]) {
            e.set_spacing(i, st.spacing[i])?;
        }
    }
    Ok(())
}

/// The end line of a run on a hopper of `geometry`, from the `line` its
/// program printed: the state checked (same size, walls and plug where they
/// are, valid grains, finite spacings); otherwise what is wrong.
pub fn read_end(geometry: &Geometry, line: &str) -> std::result::Result<EndLine, String> {
    let end: EndLine = serde_json::from_str(line).map_err(|e| {
        let head: String = line.chars().take(200).collect();
        format!("printed a line that is not an end line {{\"state\": ..}}: {e}; it reads: {head:?}")
    })?;
    match state_fault(geometry, &end.state, true) {
        Some(why) => Err(format!("ended with a state that {why}")),
        None => Ok(end),
    }
}

/// Why `st` is no state of a hopper of `geometry`, or `None`: the same
/// number of sites; walls (255) where the walls are; the plug a wall when
/// closed, a hole when open (or a grain, if `plug_grains`); every inside
/// site a hole (0) or a grain 1..=21 ([`crate::hopper::engine::check_value`]);
/// every grain's spacing D finite in [1, 1e6] (a mean of ray lengths of at
/// least 1, as `set_spacing` takes it). Spacings of other sites are not read.
pub fn state_fault(geometry: &Geometry, st: &HopperState, plug_grains: bool) -> Option<String> {
    let n = geometry.kind.len();
    if st.sites.len() != n || st.spacing.len() != n {
        return Some(format!(
            "has {} site values and {} spacings; the hopper has {n} sites",
            st.sites.len(),
            st.spacing.len()
        ));
    }
    for (i, (&v, &d)) in st.sites.iter().zip(&st.spacing).enumerate() {
        let kind = geometry.kind[i];
        let grain = crate::hopper::engine::check_value(v).is_ok() && v != HOLE;
        let ok = match kind {
            SiteKind::Wall => v == WALL,
            SiteKind::Plug if st.open => v == HOLE || (plug_grains && grain),
            SiteKind::Plug => v == WALL,
            SiteKind::Inside => v == HOLE || grain,
        };
        let spaced = !is_grain(v) || (d.is_finite() && (1.0..=1e6).contains(&d));
        if !ok || !spaced {
            return Some(format!(
                "has site {i} ({kind:?}) = {v}, spacing {d}: not a valid value there \
                 (0 a hole, 1..=21 a grain with spacing in [1, 1e6], 255 a wall)"
            ));
        }
    }
    None
}

impl HopperBuilder for External {
    fn name(&self) -> String {
        format!("cmd:{}", self.command)
    }

    fn build(&self, params: HopperParams, seed: u64) -> Result<Box<dyn HopperEngine>> {
        Ok(Box::new(Proxy::new(self.clone(), params, seed)?))
    }
}

/// The engine of an external hopper program: the state is kept here and
/// handed to the program for every computation (module doc).
pub struct Proxy {
    ext: External,
    params: HopperParams,
    seed: u64,
    geometry: Geometry,
    state: HopperState,
    added: u64,
    removed: u64,
    iteration: u64,
    work: f64,
    /// Runs of the program so far (each run's seed derives from it).
    calls: Cell<u64>,
    /// The first error of a method that cannot return one.
    error: Option<Error>,
}

impl Proxy {
    /// A new, empty hopper: the reference draws the container (the
    /// parameters are checked as the reference checks them).
    fn new(ext: External, params: HopperParams, seed: u64) -> Result<Self> {
        let h = Hopper::new(params, seed)?;
        Ok(Proxy {
            ext,
            params,
            seed,
            geometry: h.geometry().clone(),
            state: HopperState {
                sites: h.sites().to_vec(),
                spacing: h.spacing().to_vec(),
                open: false,
            },
            added: 0,
            removed: 0,
            iteration: 0,
            work: 0.0,
            calls: Cell::new(0),
            error: None,
        })
    }

    /// Run the program on `action` from the current state: its lines.
    fn call(&self, action: HopperAction, iterations: u64) -> Result<Vec<String>> {
        let k = self.calls.get();
        self.calls.set(k + 1);
        let plan = HopperPlan {
            params: self.params,
            seed: derive_seed(self.seed, k),
            state: Some(self.state.clone()),
            action,
        };
        let json = serde_json::to_string(&plan).expect("a plan serialises");
        let sites = self.state.sites.len() as f64;
        let limit = self
            .ext
            .time_limit
            .unwrap_or_else(|| Duration::from_secs_f64(60.0 + 1e-5 * iterations as f64 * sites));
        let what = || {
            format!(
                "hopper plan seed {}, {iterations} iterations of a {} x {} hopper",
                plan.seed,
                self.geometry.width(),
                self.geometry.height()
            )
        };
        // a line per iteration; the end line lists the state, site by site
        let max_line = 4096 + 64 * self.state.sites.len();
        let text = self
            .ext
            .call("hopper", json, limit, &what, (max_line, iterations + 2))?;
        Ok(text
            .lines()
            .filter(|l| !l.trim().is_empty())
            .map(str::to_string)
            .collect())
    }

    fn bad(&self, why: String) -> Error {
        Error::new(
            ErrorKind::Io,
            format!(
                "external candidate `{}` {why} (see VALIDATION.md for the hopper contract)",
                self.ext.command
            ),
        )
    }

    fn parse<T: serde::de::DeserializeOwned>(&self, line: &str, what: &str) -> Result<T> {
        serde_json::from_str(line).map_err(|e| {
            let head: String = line.chars().take(200).collect();
            self.bad(format!(
                "printed a line that is not {what}: {e}; it reads: {head:?}"
            ))
        })
    }

    /// Take the end of a run: the state (checked: same size, walls and plug
    /// where they were, valid grains, finite spacings) and the counters.
    /// The run asked for `iterations` iterations: exactly so many (a
    /// `steps` run) or at most so many (a `fill`, `exact` false); the
    /// counters must fit what so many iterations can do, and the totals
    /// must not overflow.
    fn end(&mut self, line: &str, iterations: u64, exact: bool) -> Result<()> {
        let end = read_end(&self.geometry, line).map_err(|why| self.bad(why))?;
        let asked = if exact { "exactly" } else { "at most" };
        if (exact && end.iterations != iterations) || end.iterations > iterations {
            return Err(self.bad(format!(
                "printed an end line with iterations = {}, where its plan asks for {asked} {iterations}",
                end.iterations
            )));
        }
        // each iteration adds at most a row of grains and lets out at most
        // the outlet's: never more than the sites
        let most = (self.state.sites.len() as u64).saturating_mul(end.iterations.saturating_add(1));
        for (name, v) in [("added", end.added), ("removed", end.removed)] {
            if v > most {
                return Err(self.bad(format!(
                    "printed an end line with {name} = {v}, more than {most} (the sites times the iterations + 1) can be"
                )));
            }
        }
        let sum = |a: u64, b: u64, name: &str| {
            a.checked_add(b).ok_or_else(|| {
                self.bad(format!(
                    "printed counts whose total {name} overflows 64 bits"
                ))
            })
        };
        let (added, removed, iteration) = (
            sum(self.added, end.added, "added")?,
            sum(self.removed, end.removed, "removed")?,
            sum(self.iteration, end.iterations, "iterations")?,
        );
        self.state = end.state;
        (self.added, self.removed, self.iteration) = (added, removed, iteration);
        self.work += end.site_updates;
        Ok(())
    }

    /// `n` iterations as one run: the step lines.
    fn steps(&mut self, n: u64, rain: bool) -> Result<Vec<(StepReport, [u64; 3])>> {
        let lines = self.call(HopperAction::Steps { n, rain }, n)?;
        if lines.len() as u64 != n + 1 {
            return Err(self.bad(format!(
                "printed {} lines for {n} iterations; the contract asks for {n} step lines and an end line",
                lines.len()
            )));
        }
        let out = lines[..n as usize]
            .iter()
            .map(|l| {
                let s: StepLine = self.parse(l, "a step line {\"report\": .., \"moving\": ..}")?;
                Ok((s.report, s.moving))
            })
            .collect::<Result<Vec<_>>>()?;
        self.end(&lines[n as usize], n, true)?;
        Ok(out)
    }

    /// Site `i` is an inside site (as the reference checks it).
    fn inside(&self, i: usize) -> Result<()> {
        let n = self.state.sites.len();
        if i >= n || self.geometry.kind[i] != SiteKind::Inside {
            return Err(Error::out_of_range(
                "site index",
                i,
                &format!("an inside site of the {n}-site hopper"),
            ));
        }
        Ok(())
    }

    fn keep<T: Default>(&mut self, r: Result<T>) -> T {
        r.unwrap_or_else(|e| {
            self.error.get_or_insert(e);
            T::default()
        })
    }
}

impl HopperEngine for Proxy {
    fn params(&self) -> &HopperParams {
        &self.params
    }
    fn geometry(&self) -> &Geometry {
        &self.geometry
    }
    fn step(&mut self, rain: bool) -> StepReport {
        if self.error.is_some() {
            return StepReport::default();
        }
        let r = self.steps(1, rain).map(|v| v[0].0);
        self.keep(r)
    }
    fn empty_steps(&mut self, n: u64) -> Vec<(StepReport, [u64; 3])> {
        if self.error.is_some() {
            return Vec::new();
        }
        let r = self.steps(n, false);
        self.keep(r)
    }
    fn fill(&mut self, target: u64, max_iterations: u64, max_settle: u64) -> u64 {
        if self.error.is_some() {
            return 0;
        }
        let action = HopperAction::Fill {
            // the program counts the grains of the state as added
            target: target.saturating_sub(self.removed),
            max_iterations,
            max_settle,
        };
        let r = self
            .call(action, max_iterations + max_settle)
            .and_then(|lines| match lines.as_slice() {
                [end] => {
                    let before = self.iteration;
                    self.end(end, max_iterations + max_settle, false)?;
                    Ok(self.iteration - before)
                }
                _ => Err(self.bad(format!(
                    "printed {} lines for a fill; the contract asks for one end line",
                    lines.len()
                ))),
            });
        self.keep(r)
    }
    fn open(&mut self) {
        self.state.open = true;
        for (i, k) in self.geometry.kind.iter().enumerate() {
            if *k == SiteKind::Plug {
                self.state.sites[i] = HOLE;
            }
        }
    }
    fn is_open(&self) -> bool {
        self.state.open
    }
    fn sites(&self) -> &[u8] {
        &self.state.sites
    }
    fn spacing(&self) -> &[f64] {
        &self.state.spacing
    }
    fn added(&self) -> u64 {
        self.added
    }
    fn removed(&self) -> u64 {
        self.removed
    }
    fn iteration(&self) -> u64 {
        self.iteration
    }
    fn set_site(&mut self, i: usize, value: u8) -> Result<()> {
        self.inside(i)?;
        crate::hopper::engine::check_value(value)?;
        // as the reference: a grain set counts as added, one removed as not
        if is_grain(self.state.sites[i]) {
            self.added = self.added.saturating_sub(1);
        }
        if is_grain(value) {
            self.added += 1;
            self.state.spacing[i] = 1.0;
        }
        self.state.sites[i] = value;
        Ok(())
    }
    fn set_spacing(&mut self, i: usize, d: f64) -> Result<()> {
        self.inside(i)?;
        crate::error::check_range("spacing D", d, 1.0, 1e6)?;
        self.state.spacing[i] = d;
        Ok(())
    }
    fn energies(&self, i: usize) -> Result<Vec<(usize, f64)>> {
        if i >= self.state.sites.len() || !is_grain(self.state.sites[i]) {
            return Err(Error::out_of_range(
                "site index",
                i,
                "a site holding a grain (energies are those of a grain)",
            ));
        }
        let lines = self.call(HopperAction::Energies { sites: vec![i] }, 1)?;
        let [line] = lines.as_slice() else {
            return Err(self.bad(format!(
                "printed {} lines for the energies of one grain; the contract asks for one",
                lines.len()
            )));
        };
        let e: EnergyLine = self.parse(line, "an energy line {\"site\": .., \"energies\": ..}")?;
        if e.site != i {
            return Err(self.bad(format!(
                "printed the energies of site {} when asked for site {i}",
                e.site
            )));
        }
        Ok(e.energies)
    }
    fn site_updates(&self) -> f64 {
        self.work
    }
    fn error(&self) -> Result<()> {
        match &self.error {
            Some(e) => Err(e.clone()),
            None => Ok(()),
        }
    }
}
