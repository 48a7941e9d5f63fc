//! The readers of the external contract (VALIDATION.md): the NDJSON
//! samples of a pipe candidate, the end line of a hopper candidate, and the
//! hopper plan that `validate-example hopper --plan -` reads.

use super::mutate::mutate;
use super::{excerpt, Case, Rng, Verdict};
use crate::hopper::engine::{HopperBuilder, HopperEngine, Reference as HopperReference};
use crate::hopper::geometry::{Geometry, GeometryParams, SiteKind};
use crate::hopper::model::{is_grain, HopperParams, HOLE, WALL};
use crate::pipe::engine::Reference;
use crate::pipe::{Boundary, Params};
use crate::validate::candidate::{read_samples, Builtin, Candidate, RunPlan};
use crate::validate::external_hopper::HopperState;
use crate::validate::external_hopper::{act, load, read_end, EndLine, HopperAction, HopperPlan};
use rand::RngExt;

/// A few rule readings for the generated plans.
const READINGS: [&str; 5] = [
    "default",
    "ph94",
    "any-mover+rest-up",
    "rest-ahead+gravity-last+fhp-rest",
    "up-to-rest+wall-drag+lane-collide",
];

/// A small pipe run plan (periodic or open, some with site lists).
fn run_plan(rng: &mut Rng) -> RunPlan {
    let bin = rng.random_range(1..=3);
    let steps = rng.random_range(1..=12);
    let boundary = if rng.random_bool(0.5) {
        Boundary::Periodic
    } else {
        Boundary::Open {
            inject: rng.random_range(0.0..=1.0),
        }
    };
    RunPlan {
        params: Params {
            width: rng.random_range(1..=6),
            length: bin * rng.random_range(1..=6),
            rho: rng.random_range(0.2..2.0),
            p: rng.random_range(0.0..=1.0),
            g: rng.random_range(0.0..=1.0),
            b: rng.random_range(0.0..=1.0),
            bin,
            boundary,
        },
        rules: READINGS[rng.random_range(0..READINGS.len())].to_string(),
        seed: rng.random(),
        steps,
        every: rng.random_range(1..=steps),
        init: None,
        sites: rng.random_bool(0.3),
    }
}

/// The NDJSON samples of an external pipe candidate.
#[derive(Default)]
pub(crate) struct Samples {
    last: Vec<u8>,
}

impl Case for Samples {
    fn one(&mut self, rng: &mut Rng) -> Verdict {
        // a plan the reference runs through (a tiny pipe at a high p can
        // reach the model's validity limit, MODEL.md A4)
        let (plan, samples) = loop {
            let plan = run_plan(rng);
            if let Ok(samples) = Builtin(Reference).run(&plan) {
                break (plan, samples);
            }
        };
        let mut text = String::new();
        for s in &samples {
            text.push_str(&serde_json::to_string(s).expect("a sample serialises"));
            text.push('\n');
        }
        self.last = mutate(rng, text.as_bytes());
        // as `External::call` reads a program's output
        let read = String::from_utf8_lossy(&self.last);
        match read_samples(&plan, &read) {
            Err(_) => Verdict::Refused,
            Ok(v) => {
                let p = &plan.params;
                let want = plan.steps / plan.every;
                if v.len() as u64 != want {
                    return Verdict::Silent(format!("{} samples for {want}", v.len()));
                }
                for (i, s) in v.iter().enumerate() {
                    let sum: f64 = s.bins.iter().sum();
                    let ok = s.t == (i as u64 + 1) * plan.every
                        && s.bins.len() == p.bins()
                        && s.bins
                            .iter()
                            .all(|b| b.is_finite() && *b >= 0.0 && b.fract() == 0.0)
                        && sum == s.channels.iter().sum::<u64>() as f64
                        && s.sites.is_some() == plan.sites
                        && s.sites
                            .iter()
                            .flatten()
                            .all(|&(x, y, st)| x < p.width && y < p.length && st < 128);
                    if !ok {
                        return Verdict::Silent(format!("sample {i} breaks the contract: {s:?}"));
                    }
                }
                Verdict::Accepted
            }
        }
    }

    fn input(&self) -> String {
        excerpt(&self.last)
    }
}

/// A small hopper's parameters.
fn hopper_params(rng: &mut Rng) -> HopperParams {
    let width = rng.random_range(3..=14);
    let channel = rng.random_range(1..=3);
    let most = crate::hopper::geometry::max_outlet_width(width).max(1);
    let mut p = HopperParams::quick();
    p.geometry = GeometryParams {
        width,
        height: channel + 4 + rng.random_range(0..=8),
        outlet_width: rng.random_range(1..=most),
        channel_height: channel,
    };
    p.rain.sigma = 3.0;
    p
}

/// A hopper of `p` after some iterations of rain and outflow.
fn hopper_after(rng: &mut Rng, p: HopperParams) -> Box<dyn HopperEngine> {
    let mut h = HopperReference
        .build(p, rng.random())
        .expect("valid generated parameters");
    let n = rng.random_range(0..=20);
    let open_at = rng.random_range(0..=25);
    for it in 0..n {
        if it == open_at {
            h.open();
        }
        h.step(true);
    }
    h
}

/// The state of a hopper, as the contract lists it.
fn state_of(h: &dyn HopperEngine) -> HopperState {
    HopperState {
        sites: h.sites().to_vec(),
        spacing: h.spacing().to_vec(),
        open: h.is_open(),
    }
}

/// Whether `st` is a valid state of a hopper of geometry `g`: walls where
/// walls are, the plug closed (a wall) or open (a hole), holes or grains
/// 1..=21 inside, grains' spacings in [1, 1e6]; what is wrong otherwise.
fn state_fault(g: &Geometry, st: &HopperState) -> Option<String> {
    let n = g.kind.len();
    if st.sites.len() != n || st.spacing.len() != n {
        return Some(format!("{} sites for {n}", st.sites.len()));
    }
    for i in 0..n {
        let (v, d) = (st.sites[i], st.spacing[i]);
        let grain = is_grain(v) && v <= 21;
        let ok = match g.kind[i] {
            SiteKind::Wall => v == WALL,
            SiteKind::Plug => v == if st.open { HOLE } else { WALL } || (st.open && grain),
            SiteKind::Inside => v == HOLE || grain,
        };
        if !ok || (is_grain(v) && !(d.is_finite() && (1.0..=1e6).contains(&d))) {
            return Some(format!("site {i} ({:?}) = {v}, spacing {d}", g.kind[i]));
        }
    }
    None
}

/// The end line of an external hopper candidate.
#[derive(Default)]
pub(crate) struct HopperEnd {
    last: Vec<u8>,
}

impl Case for HopperEnd {
    fn one(&mut self, rng: &mut Rng) -> Verdict {
        let p = hopper_params(rng);
        let h = hopper_after(rng, p);
        let end = EndLine {
            state: state_of(h.as_ref()),
            added: h.added(),
            removed: h.removed(),
            iterations: h.iteration(),
            site_updates: h.site_updates(),
        };
        let line = serde_json::to_string(&end).expect("an end line serialises");
        self.last = mutate(rng, line.as_bytes());
        match read_end(h.geometry(), &String::from_utf8_lossy(&self.last)) {
            Err(_) => Verdict::Refused,
            Ok(e) => match state_fault(h.geometry(), &e.state) {
                Some(why) => Verdict::Silent(why),
                None => Verdict::Accepted,
            },
        }
    }

    fn input(&self) -> String {
        excerpt(&self.last)
    }
}

/// The hopper plan of `validate-example hopper --plan -`.
#[derive(Default)]
pub(crate) struct HopperPlanCase {
    last: Vec<u8>,
}

impl Case for HopperPlanCase {
    fn one(&mut self, rng: &mut Rng) -> Verdict {
        let params = hopper_params(rng);
        let h = hopper_after(rng, params);
        let grains: Vec<usize> = (0..h.sites().len())
            .filter(|&i| is_grain(h.sites()[i]))
            .collect();
        let action = match rng.random_range(0..3) {
            0 => HopperAction::Energies {
                sites: grains
                    .iter()
                    .copied()
                    .take(rng.random_range(0..=4))
                    .collect(),
            },
            1 => HopperAction::Steps {
                n: rng.random_range(0..=4),
                rain: rng.random_bool(0.5),
            },
            _ => HopperAction::Fill {
                target: rng.random_range(0..=30),
                max_iterations: rng.random_range(0..=20),
                max_settle: rng.random_range(0..=20),
            },
        };
        let plan = HopperPlan {
            params,
            seed: rng.random(),
            state: rng.random_bool(0.7).then(|| state_of(h.as_ref())),
            action,
        };
        let json = serde_json::to_string(&plan).expect("a plan serialises");
        self.last = mutate(rng, json.as_bytes());
        let Ok((plan, mut e)) = load(&HopperReference, &mut self.last.as_slice()) else {
            return Verdict::Refused;
        };
        // the hopper holds the state of the plan, site by site
        if let Some(st) = &plan.state {
            if let Some(why) = state_fault(e.geometry(), st) {
                return Verdict::Silent(format!("a plan's state was taken: {why}"));
            }
            let differs = (0..st.sites.len()).find(|&i| {
                e.sites()[i] != st.sites[i]
                    || (is_grain(st.sites[i]) && e.spacing()[i] != st.spacing[i])
            });
            if let Some(i) = differs.or((e.is_open() != st.open).then_some(0)) {
                return Verdict::Silent(format!(
                    "the hopper holds site {i} = {} (spacing {}), the plan {} (spacing {})",
                    e.sites()[i],
                    e.spacing()[i],
                    st.sites[i],
                    st.spacing[i]
                ));
            }
        }
        // its action, when it is small
        let work = match &plan.action {
            HopperAction::Energies { sites } => sites.len() as u64,
            HopperAction::Steps { n, .. } => *n,
            HopperAction::Fill {
                max_iterations,
                max_settle,
                ..
            } => max_iterations.saturating_add(*max_settle),
        };
        if work.saturating_mul(e.sites().len() as u64) > 200_000 {
            return Verdict::Accepted;
        }
        let mut out = Vec::new();
        match act(plan.action, e.as_mut(), &mut out) {
            Ok(()) => Verdict::Accepted,
            Err(_) => Verdict::Refused,
        }
    }

    fn input(&self) -> String {
        excerpt(&self.last)
    }
}
