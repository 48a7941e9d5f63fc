//! Which collision rule stops the movers (a diagnostic of the reference
//! engine, MODEL.md A3; EXPERIMENTS.md "Which rule stops the movers").
//!
//! A mover is stopped when a collision turns it into a rest particle: R2 and
//! R3 do so with probability p (MODEL.md A3), R4 and R5 with certainty, and
//! only where a rest particle already sits. The count says whether the jams
//! of the lane grow by the p-rules or by the certain ones, the mechanism
//! argued for `v_const_p` (EXPERIMENTS.md "The mechanism each unreproduced
//! claim would need"). It also counts the holes of the lane (channel 4
//! empty) at the rest particles and elsewhere, before gravity and before the
//! collisions, since the rest particles' lifetime turned out to set the
//! p-dependence, and the holes above a rest particle and the
//! counts per column. It observes the run through
//! `super::order` and cannot change it.

use super::collision::{bit, Rule, MOVERS, REST_BIT};
use super::order::{step_observed, Stage};
use super::{Params, Pipe, Rules};
use crate::error::Result;
use serde::Serialize;

/// The rules counted, in the order of [`StopCounts::stopped`].
pub const COUNTED: [Rule; 5] = [Rule::R2, Rule::R3, Rule::R4, Rule::R5, Rule::R1];

/// Stopped movers and rule matches over the observed steps of one run.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct StopCounts {
    /// Steps observed.
    pub steps: u64,
    /// Movers stopped by each rule of [`COUNTED`] (movers before the
    /// collision minus movers after, at the site), `[nucleation, on_jam]`:
    /// on a jam when the site below held a rest particle before the
    /// collisions.
    pub stopped: [[u64; 2]; 5],
    /// Sites that matched each rule of [`COUNTED`], `[nucleation, on_jam]`
    /// (for R2 and R3 the stopped fraction is p).
    pub matched: [[u64; 2]; 5],
    /// Movers stopped at sites that matched no counted rule (0 when the
    /// table is R1-R5).
    pub stopped_elsewhere: u64,
    /// Rest particles just before the collisions, summed over the steps.
    pub rest_particles: u64,
    /// Of those, the ones whose site has channel 4 empty (free to fall by
    /// gravity, A5, at the next step's gravity sub-step if it stays so).
    pub rest_free_to_fall: u64,
    /// Sites (all, with or without a rest particle) whose channel 4 is empty
    /// just before the collisions, summed over the steps: the holes of the
    /// lane everywhere, to compare with [`StopCounts::rest_free_to_fall`].
    pub lane_holes: u64,
    /// Rest particles with another rest particle on the site just above (x,
    /// y + 1, wrapping), summed over the steps: the covered part of a stack.
    pub rest_covered: u64,
    /// Of those, the ones whose site has channel 4 empty.
    pub rest_covered_free: u64,
    /// Rest particles just before gravity (A5), summed over the steps.
    pub rest_before_gravity: u64,
    /// Of those, the ones whose site has channel 4 empty then.
    pub rest_holes_before_gravity: u64,
    /// Sites with channel 4 empty just before gravity (all sites).
    pub lane_holes_before_gravity: u64,
    /// The sites just above (x, y + 1, wrapping) a site that holds a rest
    /// particle after the collisions, `[rest below, no rest below]`, summed
    /// over the steps: their channel-4 mover is what propagation brings to
    /// the site below.
    pub above: [u64; 2],
    /// Of those, the ones whose channel 4 was empty before the collisions.
    pub above_holes_before: [u64; 2],
    /// `holes_up[d - 1]`: the sites d = 1..=[`UP`] rows above (wrapping)
    /// whose channel 4 is empty after the collisions, `[rest below, no rest
    /// below]` as [`StopCounts::above`]: how far up the lane stays full over
    /// a rest particle.
    pub holes_up: [[u64; 2]; UP],
    /// Per column x: rest particles just before the collisions, summed
    /// over the steps.
    pub rest_by_column: Vec<u64>,
    /// Per column x: sites with channel 4 empty just before the collisions.
    pub holes_by_column: Vec<u64>,
    /// Per column x: movers stopped by the counted rules (with
    /// [`StopCounts::rest_by_column`], a rest particle's lifetime there).
    pub stops_by_column: Vec<u64>,
}

/// The rows above a site that [`StopCounts::holes_up`] looks at.
pub const UP: usize = 16;

impl StopCounts {
    /// All movers stopped by the counted rules, `[nucleation, on_jam]`.
    pub fn total(&self) -> [u64; 2] {
        let mut t = [0; 2];
        for k in self.stopped {
            t[0] += k[0];
            t[1] += k[1];
        }
        t
    }

    /// The share of the stops (all, or only those on a jam) made by the
    /// p-rules R2 and R3; 0 when there is none.
    pub fn p_rule_share(&self, on_jam_only: bool) -> f64 {
        let pick = |k: [u64; 2]| if on_jam_only { k[1] } else { k[0] + k[1] };
        let all = pick(self.total());
        let p = pick(self.stopped[0]) + pick(self.stopped[1]);
        if all == 0 {
            0.0
        } else {
            p as f64 / all as f64
        }
    }

    /// The counts as text, per step over the counted steps (`explore
    /// --stops`): each counted rule's stops at the nucleation of a jam and on
    /// a jam, the shares by R2/R3, the lane's holes at and above rest
    /// particles, by column, and how far up. "n/a" where there is nothing to
    /// divide by, never a 0 that looks measured.
    pub fn describe(&self, params: &Params) -> String {
        let per = |k: usize, j: usize| self.stopped[k][j] as f64 / self.steps as f64;
        let mut line = String::new();
        for (k, r) in COUNTED.iter().enumerate() {
            line.push_str(&format!(" {r:?} [{:.3}, {:.3}]", per(k, 0), per(k, 1)));
        }
        let [nucleation, on_jam] = self.total();
        line.push_str(&format!(
        "; elsewhere {}; all stops per step {:.3}, on a jam {:.3} of them; share by R2/R3 {:.3} (on jams {:.3}); rest particles {:.1}, {:.3} of them with channel 4 empty",
        self.stopped_elsewhere,
        (nucleation + on_jam) as f64 / self.steps as f64,
        on_jam as f64 / (nucleation + on_jam).max(1) as f64,
        self.p_rule_share(false),
        self.p_rule_share(true),
        self.rest_particles as f64 / self.steps as f64,
        self.rest_free_to_fall as f64 / self.rest_particles.max(1) as f64,
    ));
        // the lane's holes at the sites without a rest particle
        let others = (params.sites() as u64 * self.steps).saturating_sub(self.rest_particles);
        line.push_str(&format!(
            "; sites without one: {:.4} with channel 4 empty",
            (self.lane_holes - self.rest_free_to_fall) as f64 / others.max(1) as f64
        ));
        // a stack: rest particles with a rest particle just above, and the others
        let top = self.rest_particles - self.rest_covered;
        line.push_str(&format!(
        "; rest particles under a rest particle {:.1} ({:.4} with channel 4 empty), the others {:.4}",
        self.rest_covered as f64 / self.steps as f64,
        self.rest_covered_free as f64 / self.rest_covered.max(1) as f64,
        (self.rest_free_to_fall - self.rest_covered_free) as f64 / top.max(1) as f64
    ));
        // the same just before gravity
        let others = (params.sites() as u64 * self.steps).saturating_sub(self.rest_before_gravity);
        line.push_str(&format!(
        "; before gravity: rest particles {:.1}, {:.4} of them with channel 4 empty, the other sites {:.4}",
        self.rest_before_gravity as f64 / self.steps as f64,
        self.rest_holes_before_gravity as f64 / self.rest_before_gravity.max(1) as f64,
        (self.lane_holes_before_gravity - self.rest_holes_before_gravity) as f64 / others.max(1) as f64
    ));
        // the site above: its channel 4 before and after its collisions,
        // above a site that holds a rest particle after them, and elsewhere
        // "n/a" where there is nothing to divide by (no rest particle, or
        // no hole elsewhere), never a 0 that looks measured
        let frac =
            |h: [u64; 2], k: usize| (self.above[k] > 0).then(|| h[k] as f64 / self.above[k] as f64);
        let show =
            |v: Option<f64>, digits: usize| v.map_or("n/a".into(), |v| format!("{v:.digits$}"));
        line.push_str(&format!(
        "; site above a rest particle: channel 4 empty {} before its collisions, {} after; above the other sites {}, {}",
        show(frac(self.above_holes_before, 0), 4),
        show(frac(self.holes_up[0], 0), 4),
        show(frac(self.above_holes_before, 1), 4),
        show(frac(self.holes_up[0], 1), 4)
    ));
        // by column: rest particles per step, and the lane's holes
        line.push_str("; by column x = 0..W-1: rest particles per step");
        for r in &self.rest_by_column {
            line.push_str(&format!(" {:.1}", *r as f64 / self.steps as f64));
        }
        line.push_str(", channel 4 empty");
        for h in &self.holes_by_column {
            line.push_str(&format!(
                " {:.3}",
                *h as f64 / (self.steps * params.length as u64) as f64
            ));
        }
        line.push_str(", stops per step");
        for k in &self.stops_by_column {
            line.push_str(&format!(" {:.3}", *k as f64 / self.steps as f64));
        }
        // how far up: the ratio of the two, d rows above
        line.push_str("; ratio d rows above (d = 1..16):");
        for h in self.holes_up {
            let ratio = frac(h, 0).zip(frac(h, 1).filter(|&e| e > 0.0));
            line.push_str(&format!(" {}", show(ratio.map(|(a, b)| a / b), 3)));
        }
        line
    }
}

/// `steps` steps of the reference engine from `seed`, counting from step
/// `skip` on.
pub fn count_stops(
    params: Params,
    rules: Rules,
    seed: u64,
    skip: u64,
    steps: u64,
) -> Result<StopCounts> {
    let mut pipe = Pipe::new(params, rules, seed)?;
    for _ in 0..skip {
        pipe.step()?;
    }
    let (w, l) = (params.width, params.length);
    let mut before = vec![0u8; w * l];
    let mut counts = StopCounts {
        steps,
        rest_by_column: vec![0; w],
        holes_by_column: vec![0; w],
        stops_by_column: vec![0; w],
        ..StopCounts::default()
    };
    for _ in 0..steps {
        step_observed(&mut pipe, &mut |stage, p: &Pipe| match stage {
            Stage::BeforeGravity => {
                for x in 0..w {
                    for y in 0..l {
                        let v = p.site(x, y);
                        let hole = v & bit(4) == 0;
                        counts.rest_before_gravity += (v & REST_BIT) as u64;
                        counts.rest_holes_before_gravity += (hole && v & REST_BIT != 0) as u64;
                        counts.lane_holes_before_gravity += hole as u64;
                    }
                }
            }
            Stage::BeforeCollide => {
                for x in 0..w {
                    for y in 0..l {
                        let v = p.site(x, y);
                        before[x * l + y] = v;
                        let free = v & (REST_BIT | bit(4)) == REST_BIT;
                        counts.rest_particles += (v & REST_BIT) as u64;
                        counts.rest_free_to_fall += free as u64;
                        counts.lane_holes += (v & bit(4) == 0) as u64;
                        counts.rest_by_column[x] += (v & REST_BIT) as u64;
                        counts.holes_by_column[x] += (v & bit(4) == 0) as u64;
                        let covered = v & REST_BIT != 0 && p.site(x, (y + 1) % l) & REST_BIT != 0;
                        counts.rest_covered += covered as u64;
                        counts.rest_covered_free += (covered && free) as u64;
                    }
                }
            }
            Stage::AfterCollide => {
                let table = p.collision_table();
                for x in 0..w {
                    for y in 0..l {
                        let s = before[x * l + y];
                        let below = before[x * l + (y + l - 1) % l];
                        let jam = (below & REST_BIT != 0) as usize;
                        let movers = |v: u8| (v & MOVERS).count_ones() as u64;
                        let stopped = movers(s).saturating_sub(movers(p.site(x, y)));
                        // the site just above, seen from a site that now
                        // holds a rest particle (0) or not (1)
                        let up = (y + 1) % l;
                        let side = (p.site(x, y) & REST_BIT == 0) as usize;
                        counts.above[side] += 1;
                        counts.above_holes_before[side] +=
                            (before[x * l + up] & bit(4) == 0) as u64;
                        for (d, h) in counts.holes_up.iter_mut().enumerate() {
                            h[side] += (p.site(x, (y + 1 + d) % l) & bit(4) == 0) as u64;
                        }
                        match COUNTED
                            .iter()
                            .position(|&r| r == table.entries[s as usize].rule)
                        {
                            Some(k) => {
                                counts.matched[k][jam] += 1;
                                counts.stopped[k][jam] += stopped;
                                counts.stops_by_column[x] += stopped;
                            }
                            None => counts.stopped_elsewhere += stopped,
                        }
                    }
                }
            }
        })?;
    }
    Ok(counts)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// R2 and R3 stop a mover in a fraction p of their matches, R1 never,
    /// the lane's holes are counted within bounds, and the diagnostic
    /// leaves the run as it was.
    #[test]
    fn p_rules_stop_in_a_fraction_p_and_the_run_is_unchanged() {
        let params = Params {
            length: 40,
            width: 5,
            p: 0.3,
            ..Params::default()
        };
        let rules = Rules::default();
        let c = count_stops(params, rules, 7, 50, 4000).unwrap();
        assert_eq!(c.stopped_elsewhere, 0);
        assert_eq!(c.stopped[4], [0, 0], "R1 conserves the movers");
        // the lane's holes include those at rest particles, and fit the pipe
        assert!(c.rest_free_to_fall <= c.lane_holes && c.lane_holes <= 200 * 4000);
        assert!(c.lane_holes > c.rest_free_to_fall, "a lane with no hole");
        assert!(c.rest_covered <= c.rest_particles);
        assert!(c.rest_holes_before_gravity <= c.rest_before_gravity);
        assert!(c.rest_holes_before_gravity < c.lane_holes_before_gravity);
        assert!(c.rest_covered_free <= c.rest_covered.min(c.rest_free_to_fall));
        assert_eq!(
            c.above[0] + c.above[1],
            200 * 4000,
            "every site has one above"
        );
        assert_eq!(c.rest_by_column.iter().sum::<u64>(), c.rest_particles);
        assert_eq!(c.holes_by_column.iter().sum::<u64>(), c.lane_holes);
        let [a, b] = c.total();
        assert_eq!(c.stops_by_column.iter().sum::<u64>(), a + b);
        for k in 0..2 {
            assert!(c.above_holes_before[k] <= c.above[k] && c.holes_up[0][k] <= c.above[k]);
        }
        for (k, rule) in COUNTED.iter().enumerate().take(2) {
            let (m, s) = (
                (c.matched[k][0] + c.matched[k][1]) as f64,
                (c.stopped[k][0] + c.stopped[k][1]) as f64,
            );
            assert!(m > 40.0, "{rule:?} matched {m}");
            let se = (0.3 * 0.7 / m).sqrt();
            assert!((s / m - 0.3).abs() < 4.0 * se, "{rule:?}: {s} of {m}");
        }
        // observed and plain runs end in the same state
        let mut plain = Pipe::new(params, rules, 7).unwrap();
        plain.run(450).unwrap();
        let mut seen = Pipe::new(params, rules, 7).unwrap();
        for _ in 0..450 {
            step_observed(&mut seen, &mut |_, _: &Pipe| {}).unwrap();
        }
        for x in 0..5 {
            assert_eq!(plain.column(x), seen.column(x));
        }
    }
}
