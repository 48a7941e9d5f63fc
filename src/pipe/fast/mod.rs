//! A fast, bit-sliced engine of the pipe lattice gas: the rules
//! of MODEL.md Part A on 64 sites at once, with the outcome probabilities of
//! the reference engine [`super::Pipe`] exactly (same thresholds), but not
//! its sequence of draws: a run of [`FastPipe`] is a different sample of the
//! same process, a pure function of (parameters, rules, seed).
//!
//! Layout ([`grid`]): for every column and channel one bit per row, so that
//! propagation is a shift along the column and every site rule is a few
//! Boolean operations on words. Random decisions ([`lanes`]) compare one
//! 32-bit uniform number per lane with the reference's threshold, drawing
//! its bits only as long as the comparison is undecided. The extra rest
//! particles of R4/R5 are relocated one by one by the scalar walk of the
//! reference (MODEL.md A4), on a neighbour table ([`walk`]). Every rule
//! reading of [`Rules`] is supported.
//!
//! The sub-steps repeat those of the reference engine
//! (`src/pipe/reference.rs`) on purpose: the reference must read like the
//! specification, and this engine is an independent implementation validated
//! against it (VALIDATION.md); code shared by the two would let one mistake
//! pass in both.
//!
//! ```
//! use granular_automata::pipe::engine::PipeEngine;
//! use granular_automata::pipe::fast::FastPipe;
//! use granular_automata::pipe::{Params, Rules};
//! let params = Params { length: 60, width: 5, ..Params::default() };
//! let mut pipe = FastPipe::new(params, Rules::default(), 7).unwrap();
//! let n0 = pipe.particle_count();
//! pipe.run(100).unwrap();
//! assert_eq!(pipe.particle_count(), n0); // the periodic pipe conserves mass
//! ```

pub mod grid;
pub mod lanes;
pub mod logic;
pub mod walk;

use super::collision::{bit, threshold, CollisionTable, Entry};
use super::engine::{forward_to_inherent, run_getters, EngineBuilder, PipeEngine};
use super::order::{self, SubSteps};
use super::relocation;
use super::{Boundary, Flux, GravityWording, Params, Rules};
use crate::error::{check_unit, Result};
use crate::lattice::neighbour;
use grid::{bit_range, site_totals, Grid, Word};
use logic::{Decisions, Moves};
use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

/// The thresholds of the collision draws, read from the reference's table
/// (MODEL.md A3), so that every outcome has its probability there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CollisionThresholds {
    /// R1: U below it takes {c+1, c+4} (1/2).
    pub r1: u64,
    /// R2: U below it dissipates (p; 0 when p = 0, 2^32 when p = 1).
    pub r2: u64,
    /// R3: the cumulative thresholds of the outcomes {0, c+j, c+j+3},
    /// j = 0, 1, 2 (p/3 each); U above the last one leaves the state.
    pub r3: [u64; 3],
}

/// The interval of uniform draws that picks `outcome` in `entry`, if any.
fn interval(entry: &Entry, outcome: u8) -> Option<(u64, u64)> {
    let j = entry.outcomes.iter().position(|o| o.state == outcome)?;
    let lo = if j == 0 { 0 } else { entry.cumulative[j - 1] };
    Some((lo, entry.cumulative[j]))
}

impl CollisionThresholds {
    /// The thresholds of `table`, from the states {1, 4} (R1), {1, 3} (R2:
    /// its outcome with a rest particle, in either notation of READINGS.md
    /// P1) and {1, 3, 5} (R3); every rotation of a rule has the same
    /// probabilities (checked state by state in the tests of [`logic`]).
    pub fn new(table: &CollisionTable) -> Self {
        let set = |cs: &[usize]| cs.iter().fold(0u8, |s, &c| s | bit(c));
        let first = |state: &[usize], out: u8| -> Option<u64> {
            let (lo, hi) = interval(&table.entries[set(state) as usize], out)?;
            assert_eq!(lo, 0, "the outcome is the table's first");
            Some(hi)
        };
        let r1 = first(&[1, 4], set(&[2, 5])).expect("R1 rotates");
        let e2 = &table.entries[set(&[1, 3]) as usize];
        let r2 = e2
            .outcomes
            .iter()
            .find(|o| o.state & bit(0) != 0)
            .and_then(|o| first(&[1, 3], o.state))
            .unwrap_or(0);
        let e3 = &table.entries[set(&[1, 3, 5]) as usize];
        let mut r3 = [0u64; 3];
        let mut below = 0;
        for (j, out) in [[0, 1, 4], [0, 2, 5], [0, 3, 6]].iter().enumerate() {
            if let Some((lo, hi)) = interval(e3, set(out)) {
                assert_eq!(lo, below, "R3 outcomes in order");
                below = hi;
            }
            r3[j] = below;
        }
        CollisionThresholds { r1, r2, r3 }
    }
}

/// The fast engine: the state as bit planes, the run's generator, counters.
#[derive(Debug, Clone)]
pub struct FastPipe<R = Xoshiro256PlusPlus> {
    params: Params,
    rules: Rules,
    rng: R,
    grid: Grid,
    next: Grid,
    collision: CollisionThresholds,
    g_t: u64,
    b_t: u64,
    /// The probability of `lane-collide` (p, or q of `lane-collide:q`) as a
    /// threshold (READINGS.md P23); 0 when the rule is off.
    lane_t: u64,
    inject_t: u64,
    /// Per column: the channels that leave the open pipe through the bottom
    /// from row 0, and through the top from row L-1 (MODEL.md A7).
    exits: Vec<(u8, u8)>,
    /// (bin, word, rows of the word in the bin), bin by bin (MODEL.md A9).
    segments: Vec<(usize, usize, u64)>,
    /// First segment of each bin, and one past the last.
    bin_start: Vec<usize>,
    /// Sites (y W + x) of the extra rest particles of this step.
    extras: Vec<u64>,
    /// `rest-ahead`: per word (as `grid.cells()`), the lanes whose mover 2,
    /// and whose mover 6, has a rest particle ahead at the start of gravity.
    ahead: Vec<(u64, u64)>,
    /// The neighbour table of relocation's walk, built at the first walk.
    walker: Option<walk::Walker>,
    time: u64,
    flux: Flux,
}

impl FastPipe {
    /// A new run: validates `params` as [`super::Pipe::new`] does, and draws
    /// the initial state of MODEL.md A8 (each moving channel occupied with
    /// probability rho/6, or with `wall-sites` each existing one with
    /// [`Rules::fill_probability`]; the open pipe starts empty).
    pub fn new(params: Params, rules: Rules, seed: u64) -> Result<Self> {
        params.validate()?;
        rules.validate_for(&params)?;
        let (w, l) = (params.width, params.length);
        let mut pipe = FastPipe {
            params,
            rules,
            rng: Xoshiro256PlusPlus::seed_from_u64(seed),
            grid: Grid::new(w, l),
            next: Grid::new(w, l),
            collision: CollisionThresholds::new(&CollisionTable::for_rules(params.p, rules)),
            g_t: threshold(params.g),
            b_t: threshold(params.b),
            lane_t: threshold(rules.lane_collide.probability(params.p)),
            inject_t: match params.boundary {
                Boundary::Open { inject } => threshold(inject),
                Boundary::Periodic => 0,
            },
            exits: (0..w).map(|x| exit_channels(x, w, l)).collect(),
            segments: Vec::new(),
            bin_start: Vec::new(),
            extras: Vec::new(),
            ahead: Vec::new(),
            walker: None,
            time: 0,
            flux: Flux::default(),
        };
        pipe.build_segments();
        if params.boundary == Boundary::Periodic {
            pipe.random_start();
        }
        Ok(pipe)
    }

    /// This run with its random words drawn from `rng` from now on: only
    /// for the mutant engines of `validate` (`crate::validate::mutants`).
    #[doc(hidden)]
    pub fn with_rng<S: Rng + Clone + Send>(self, rng: S) -> FastPipe<S> {
        FastPipe {
            params: self.params,
            rules: self.rules,
            rng,
            grid: self.grid,
            next: self.next,
            collision: self.collision,
            g_t: self.g_t,
            b_t: self.b_t,
            lane_t: self.lane_t,
            inject_t: self.inject_t,
            exits: self.exits,
            segments: self.segments,
            bin_start: self.bin_start,
            extras: self.extras,
            ahead: self.ahead,
            walker: self.walker,
            time: self.time,
            flux: self.flux,
        }
    }
}

impl<R: Rng + Clone + Send> FastPipe<R> {
    /// The random start of the periodic pipe (MODEL.md A8): each moving
    /// channel of each site occupied with probability rho/6; with
    /// `wall-sites` each moving channel that exists with rho W / (6 W - 8)
    /// (READINGS.md P12), the others empty.
    fn random_start(&mut self) {
        let t = threshold(self.rules.fill_probability(&self.params));
        let (w, words) = (self.params.width, self.grid.words());
        for i in 0..self.grid.cells().len() {
            let lanes = self.grid.lanes(i % words);
            let exists = self.rules.channels_of_column(i / words, w);
            for (c, plane) in self.grid.cells_mut()[i].iter_mut().enumerate().skip(1) {
                if exists & bit(c) != 0 {
                    *plane = lanes::bernoulli(&mut self.rng, t, lanes);
                }
            }
        }
    }

    /// The rows of each bin (MODEL.md A9) as (bin, word, mask) segments.
    fn build_segments(&mut self) {
        let bin = self.params.bin;
        for i in 0..self.params.bins() {
            self.bin_start.push(self.segments.len());
            let (lo, hi) = (i * bin, (i + 1) * bin);
            for k in lo / 64..hi.div_ceil(64) {
                let (a, b) = (lo.max(64 * k) - 64 * k, hi.min(64 * k + 64) - 64 * k);
                self.segments.push((i, k, bit_range(a, b)));
            }
        }
        self.bin_start.push(self.segments.len());
    }

    /// Empty every site (prepared states).
    pub fn clear(&mut self) {
        self.grid.clear();
    }

    run_getters!();

    /// Change the dissipation p mid-run (PH94 Fig. 1c); validated.
    pub fn set_p(&mut self, p: f64) -> Result<()> {
        check_unit("p", p)?;
        self.params.p = p;
        self.lane_t = threshold(self.rules.lane_collide.probability(p));
        self.collision = CollisionThresholds::new(&CollisionTable::for_rules(p, self.rules));
        Ok(())
    }

    fn check_site(&self, x: usize, y: usize) {
        assert!(
            x < self.params.width && y < self.params.length,
            "site ({x}, {y}) outside the pipe"
        );
    }

    /// The state byte of site (x, y) (bit c = channel c).
    pub fn site(&self, x: usize, y: usize) -> u8 {
        self.check_site(x, y);
        self.grid.site(x, y)
    }

    /// Set the state byte of site (x, y) (bits above 6 are ignored).
    pub fn set_site(&mut self, x: usize, y: usize, state: u8) {
        self.check_site(x, y);
        self.grid.set_site(x, y, state & 0x7f);
    }

    /// Advance `steps` steps.
    pub fn run(&mut self, steps: u64) -> Result<()> {
        for _ in 0..steps {
            self.step()?;
        }
        Ok(())
    }

    /// One time step in the order of MODEL.md A2, written once for both
    /// engines (`order::step`): injection (open pipe), collisions with
    /// relocation and gravity (gravity first with `gravity-first`),
    /// `wall-drag`, `wall-move`, propagation.
    pub fn step(&mut self) -> Result<()> {
        order::step(self)
    }
}

/// The sub-steps of one time step, in the order of MODEL.md A2.
impl<R: Rng + Clone + Send> SubSteps for FastPipe<R> {
    /// The parameters of the run.
    fn params(&self) -> &Params {
        &self.params
    }

    /// The rule reading of the run.
    fn rules(&self) -> Rules {
        self.rules
    }

    /// Injection (MODEL.md A7): each empty channel 3, 4, 5 of the top row
    /// (channel 4 alone with `inject-down`, READINGS.md P17) is filled with
    /// probability I, at a wall site of `wall-sites` only the channel that
    /// exists there; the columns are taken 64 at a time.
    fn inject(&mut self) {
        let (w, l) = (self.params.width, self.params.length);
        let (k, j) = ((l - 1) / 64, (l - 1) % 64);
        let words = self.grid.words();
        let channels: &[usize] = if self.rules.inject_down {
            &[4]
        } else {
            &[3, 4, 5]
        };
        for first in (0..w).step_by(64) {
            let n = (w - first).min(64);
            for &c in channels {
                let cells = self.grid.cells_mut();
                let site = |x: usize| (first + x) * words + k;
                let rules = self.rules;
                let exists = |x: usize| u64::from(rules.channels_of_column(first + x, w) >> c & 1);
                let empty = (0..n).fold(0u64, |m, x| {
                    m | (!cells[site(x)][c] >> j & 1 & exists(x)) << x
                });
                let fill = lanes::bernoulli(&mut self.rng, self.inject_t, empty);
                for x in 0..n {
                    cells[site(x)][c] |= (fill >> x & 1) << j;
                }
                self.flux.injected += fill.count_ones() as u64;
            }
        }
    }

    /// Collision step (MODEL.md A3) on every word: classify, draw the
    /// decisions the classes need, apply; then relocation (A4).
    fn collide(&mut self) -> Result<()> {
        self.extras.clear();
        let (w, words) = (self.params.width as u64, self.grid.words());
        let (t, fhp_rest) = (self.collision, self.rules.fhp_rest);
        let literal = self.rules.literal_labels;
        let inner = self.rules.inner_columns(self.params.width);
        for (i, s) in self.grid.cells_mut().iter_mut().enumerate() {
            if !inner.contains(&(i / words)) {
                continue; // a wall site of `wall-sites`: no collision
            }
            let k = logic::classify(s, fhp_rest);
            if k.any() == 0 {
                continue;
            }
            // the classes are disjoint: one uniform per lane serves them all
            let r3 = k.any_r3();
            let [r1, r2, a, b, c] = lanes::below_each(
                &mut self.rng,
                [t.r1, t.r2, t.r3[0], t.r3[1], t.r3[2]],
                [k.r1, k.r2, r3, r3, r3],
            );
            let d = Decisions {
                r1,
                r2,
                r3: [a, b, c],
            };
            let out = if literal {
                logic::collide_literal(s, &k, &d)
            } else {
                logic::collide(s, &k, &d)
            };
            *s = out.state;
            if out.one_extra | out.two_extras != 0 {
                let (x, y0) = ((i / words) as u64, 64 * (i % words) as u64);
                push_extras(&mut self.extras, &out, |j| (y0 + j) * w + x);
            }
        }
        if !self.extras.is_empty() {
            self.relocate()?;
        }
        if self.rules.lane_collide.is_on() {
            self.lane_collide();
        }
        Ok(())
    }

    /// Gravity step (MODEL.md A5): the moves possible before gravity, each
    /// made with probability g (an independent draw per particle), then
    /// `rest-slide` if named. With `rest-ahead` a mover turns only where
    /// its neighbour ahead holds a rest particle before the sub-step. No
    /// gravity at the wall sites of `wall-sites`.
    fn gravity(&mut self) {
        if self.g_t == 0 {
            return;
        }
        let (g, wording, slide) = (self.g_t, self.rules.gravity, self.rules.rest_slide);
        let ahead_only = wording == GravityWording::RestAhead;
        if ahead_only {
            self.find_rest_ahead();
        }
        let (inner, words) = (
            self.rules.inner_columns(self.params.width),
            self.grid.words(),
        );
        for (i, s) in self.grid.cells_mut().iter_mut().enumerate() {
            if !inner.contains(&(i / words)) {
                continue;
            }
            let mut m = logic::gravity_moves(s, wording);
            if ahead_only {
                m.turn2 &= self.ahead[i].0;
                m.turn6 &= self.ahead[i].1;
            }
            // 0 -> 4 needs a rest particle, 1 -> 0 its absence: one draw
            let falls = lanes::bernoulli(&mut self.rng, g, m.fall | m.stop);
            let (turn2, turn6) = lanes::bernoulli_pair(&mut self.rng, g, m.turn2, m.turn6);
            let made = Moves {
                fall: falls & m.fall,
                turn2,
                turn6,
                stop: falls & m.stop,
            };
            let after = logic::apply_moves(s, &made);
            *s = if slide {
                Self::rest_slide(&mut self.rng, g, s, &after)
            } else {
                after
            };
        }
    }

    /// `wall-drag` (MODEL.md A6 variant): in a wall column a lone mover
    /// along the wall (1 or 4) is reversed with probability b.
    fn wall_drag(&mut self) {
        for x in self.wall_columns() {
            for k in 0..self.grid.words() {
                let s = &mut self.grid.column_mut(x)[k];
                let flip = lanes::bernoulli(&mut self.rng, self.b_t, s[1] ^ s[4]);
                s[1] ^= flip;
                s[4] ^= flip;
            }
        }
    }

    /// `wall-move` (MODEL.md A6, the default): particles heading into a wall
    /// are reflected before propagation (same draws as A6), where the
    /// reflected channels are empty, so that they move this step.
    fn wall_move(&mut self) {
        let w = self.params.width;
        if w == 1 {
            return;
        }
        // (column, the channels into the wall, the reflected channels)
        for (x, into, out) in [(0, [2, 3], [5, 6]), (w - 1, [6, 5], [3, 2])] {
            for k in 0..self.grid.words() {
                let s = &mut self.grid.column_mut(x)[k];
                let (a, b) = (s[into[0]], s[into[1]]);
                let bounce = lanes::bernoulli(&mut self.rng, self.b_t, a ^ b);
                let (ra, rb) = logic::reflect(a, b, bounce);
                let free = (a | b) & !(s[out[0]] & ra) & !(s[out[1]] & rb);
                s[into[0]] &= !free;
                s[into[1]] &= !free;
                s[out[0]] |= ra & free;
                s[out[1]] |= rb & free;
            }
        }
    }

    /// Propagation (MODEL.md A2 step 4) with the walls of A6 and the ends
    /// of A7: count what leaves the open pipe, stream, reflect at the walls.
    fn propagate(&mut self) {
        let periodic = self.params.boundary == Boundary::Periodic;
        if !periodic {
            self.count_exits();
        }
        self.grid.stream_into(&mut self.next, periodic);
        if self.rules.wall_sites {
            self.reflect_on_arrival();
        } else {
            self.reflect_at_walls();
        }
        std::mem::swap(&mut self.grid, &mut self.next);
    }

    /// One step done.
    fn tick(&mut self) {
        self.time += 1;
    }
}

/// The parts of the sub-steps, and what a run measures.
impl<R: Rng + Clone + Send> FastPipe<R> {
    /// Relocation of the extra rest particles (MODEL.md A4), by the rule the
    /// reference uses ([`relocation::relocate`]), its walk on a neighbour
    /// table ([`walk::Walker`]: the same hops from the same draws).
    fn relocate(&mut self) -> Result<()> {
        let rest_now = self.rest_count();
        let w = self.params.width as u64;
        let mut extras: Vec<(usize, usize)> = self
            .extras
            .iter()
            .map(|&site| ((site % w) as usize, (site / w) as usize))
            .collect();
        let (params, rules, time, words) = (&self.params, self.rules, self.time, self.grid.words());
        let walker = self
            .walker
            .get_or_insert_with(|| walk::Walker::new(params, rules, words));
        let rng = &mut self.rng;
        relocation::relocate_with(
            &mut self.grid,
            params,
            self.rules,
            &mut extras,
            rest_now,
            time,
            |grid, x, y| walker.walk(grid, rng, params, (x, y), time),
        )
    }

    /// `rest-ahead` (READINGS.md P7): for every word, from the state before
    /// any gravity move, the lanes whose up-movers 2 and 6 have a rest
    /// particle on their next site ([`Grid::rest_ahead`]).
    fn find_rest_ahead(&mut self) {
        let periodic = self.params.boundary == Boundary::Periodic;
        let words = self.grid.words();
        self.ahead.clear();
        for x in 0..self.params.width {
            for k in 0..words {
                self.ahead.push(self.grid.rest_ahead(x, k, periodic));
            }
        }
    }

    /// `lane-collide` (READINGS.md P23, a project extension): a channel-4
    /// mover whose neighbour below held a channel-4 mover at the start of
    /// this sub-step is deflected to 3 or 5 with probability p (a fair coin
    /// when both are free), as the reference does.
    fn lane_collide(&mut self) {
        if self.lane_t == 0 {
            return;
        }
        let periodic = self.params.boundary == Boundary::Periodic;
        let words = self.grid.words();
        for x in 0..self.params.width {
            let below: Vec<u64> = (0..words)
                .map(|k| self.grid.from_below(x, 4, k, periodic))
                .collect();
            for (k, &under) in below.iter().enumerate() {
                let s = &mut self.grid.column_mut(x)[k];
                let (free3, free5) = (!s[3], !s[5]);
                let hit =
                    lanes::bernoulli(&mut self.rng, self.lane_t, s[4] & under & (free3 | free5));
                let coin = lanes::coins(&mut self.rng, hit & free3 & free5);
                let to5 = hit & free5 & (!free3 | coin);
                let to3 = hit & !to5;
                s[4] &= !hit;
                s[3] |= to3;
                s[5] |= to5;
            }
        }
    }

    /// `rest-slide` (MODEL.md A5): a rest particle blocked by an occupied
    /// channel 4 slides down a free diagonal with probability g (a fair coin
    /// when both are free).
    fn rest_slide(rng: &mut R, g: u64, before: &Word, after: &Word) -> Word {
        let slid = lanes::bernoulli(rng, g, logic::slide_candidates(before, after));
        let coin = lanes::coins(rng, logic::slide_choices(after, slid));
        logic::apply_slide(after, slid, coin)
    }

    /// The wall columns: 0 and W-1, the one column when W = 1 (MODEL.md A6).
    fn wall_columns(&self) -> Vec<usize> {
        let w = self.params.width;
        if w == 1 {
            vec![0]
        } else {
            vec![0, w - 1]
        }
    }

    /// Particles that propagation moves out through the ends of the open
    /// pipe (MODEL.md A7): below row 0 (out_bottom), above row L-1 (out_top);
    /// those heading into a wall are reflected instead.
    fn count_exits(&mut self) {
        let l = self.params.length;
        for (x, &(down, up)) in self.exits.iter().enumerate() {
            self.flux.out_bottom += (self.grid.site(x, 0) & down).count_ones() as u64;
            self.flux.out_top += (self.grid.site(x, l - 1) & up).count_ones() as u64;
        }
    }

    /// The wall rule of MODEL.md A6 in place: particles of the wall columns
    /// heading into a wall stay and are bounced back (probability b) or
    /// mirrored; their reflected channels have no other source.
    fn reflect_at_walls(&mut self) {
        let last = self.params.width - 1;
        // (column, the channels into the wall, the reflected channels)
        for (x, into, out) in [(0, [2, 3], [5, 6]), (last, [6, 5], [3, 2])] {
            for k in 0..self.grid.words() {
                let s = &self.grid.column(x)[k];
                let (a, b) = (s[into[0]], s[into[1]]);
                let bounce = lanes::bernoulli(&mut self.rng, self.b_t, a ^ b);
                let (ra, rb) = logic::reflect(a, b, bounce);
                let n = &mut self.next.column_mut(x)[k];
                n[out[0]] |= ra;
                n[out[1]] |= rb;
            }
        }
    }

    /// `wall-sites` (READINGS.md P12): the wall rule of MODEL.md A6 at the
    /// wall sites, on the particles that have just arrived there (heading
    /// into the wall), as the reference does: each leaves in its reflected
    /// channel, one of the two inward diagonals.
    fn reflect_on_arrival(&mut self) {
        let last = self.params.width - 1;
        for (x, into, out) in [(0, [2, 3], [5, 6]), (last, [6, 5], [3, 2])] {
            for k in 0..self.next.words() {
                let n = &mut self.next.column_mut(x)[k];
                let (a, b) = (n[into[0]], n[into[1]]);
                let bounce = lanes::bernoulli(&mut self.rng, self.b_t, a ^ b);
                let (ra, rb) = logic::reflect(a, b, bounce);
                n[into[0]] = 0;
                n[into[1]] = 0;
                n[out[0]] |= ra;
                n[out[1]] |= rb;
            }
        }
    }

    /// Number of particles in each channel 0..=6.
    pub fn channel_counts(&self) -> [u64; 7] {
        self.grid.channel_counts()
    }

    fn count(&self, channels: std::ops::Range<usize>) -> u64 {
        self.grid
            .cells()
            .iter()
            .map(|w| {
                w[channels.clone()]
                    .iter()
                    .map(|p| p.count_ones() as u64)
                    .sum::<u64>()
            })
            .sum()
    }

    /// Total number of particles N.
    pub fn particle_count(&self) -> u64 {
        self.count(0..7)
    }

    /// Kinetic energy E = number of moving particles.
    pub fn moving_count(&self) -> u64 {
        self.count(1..7)
    }

    /// Number of rest particles.
    pub fn rest_count(&self) -> u64 {
        self.count(0..1)
    }

    /// Bin densities n_i (MODEL.md A9) into `out` (length K): per word the
    /// particle numbers of its sites as three bit planes, then masked
    /// population counts of the rows of each bin.
    pub fn fill_bin_counts(&self, out: &mut [f64]) {
        out.iter_mut().for_each(|v| *v = 0.0);
        for x in 0..self.params.width {
            let col = self.grid.column(x);
            let mut current = (usize::MAX, [0u64; 3]);
            for &(i, k, mask) in &self.segments {
                if current.0 != k {
                    current = (k, site_totals(&col[k]));
                }
                let [a, b, c] = current.1;
                out[i] += ((a & mask).count_ones()
                    + 2 * (b & mask).count_ones()
                    + 4 * (c & mask).count_ones()) as f64;
            }
        }
    }

    /// Particle count of bin `i` alone (MODEL.md A9).
    pub fn bin_count(&self, i: usize) -> u32 {
        let segments = &self.segments[self.bin_start[i]..self.bin_start[i + 1]];
        (0..self.params.width)
            .map(|x| {
                let col = self.grid.column(x);
                segments
                    .iter()
                    .map(|&(_, k, mask)| {
                        col[k].iter().map(|p| (p & mask).count_ones()).sum::<u32>()
                    })
                    .sum::<u32>()
            })
            .sum()
    }
}

/// The sites (by `site` of the lane) of the extra rest particles of one
/// word (MODEL.md A4), once per particle: two at an R4 lane, one at R5.
fn push_extras(extras: &mut Vec<u64>, out: &logic::Collided, site: impl Fn(u64) -> u64) {
    let mut m = out.one_extra | out.two_extras;
    while m != 0 {
        let j = m.trailing_zeros() as u64;
        extras.push(site(j));
        if out.two_extras >> j & 1 == 1 {
            extras.push(site(j));
        }
        m &= m - 1;
    }
}

/// The channels by which a particle of column `x` leaves the open pipe
/// through the bottom from row 0 and through the top from row L-1: those
/// whose neighbour (MODEL.md A1) lies beyond the end and inside the walls.
fn exit_channels(x: usize, w: usize, l: usize) -> (u8, u8) {
    let mut bottom = 0u8;
    let mut top = 0u8;
    for c in 1..=6 {
        let inside = |nx: i64| nx >= 0 && nx < w as i64;
        let (nx, ny) = neighbour(x, 0, c);
        if inside(nx) && ny < 0 {
            bottom |= bit(c);
        }
        let (nx, ny) = neighbour(x, l - 1, c);
        if inside(nx) && ny >= l as i64 {
            top |= bit(c);
        }
    }
    (bottom, top)
}

impl<R: Rng + Clone + Send> PipeEngine for FastPipe<R> {
    forward_to_inherent!(FastPipe);
    fn run(&mut self, steps: u64) -> Result<()> {
        FastPipe::run(self, steps)
    }
}

/// Builds [`FastPipe`] runs: the engine `fast` of `validate` and the figures.
/// Every rule reading of [`Rules`] is supported (all four gravity
/// wordings, `wall-drag`, `gravity-first`, `gravity-last`, `rest-up`,
/// `wall-move`, `rest-slide`, `fhp-rest`, `literal-labels`, `wall-sites`),
/// so `build` fails only on invalid parameters or an invalid reading.
#[derive(Debug, Clone, Copy, Default)]
pub struct Fast;

impl EngineBuilder for Fast {
    fn name(&self) -> String {
        "fast".into()
    }
    fn build(&self, params: Params, rules: Rules, seed: u64) -> Result<Box<dyn PipeEngine>> {
        Ok(Box::new(FastPipe::new(params, rules, seed)?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thresholds_follow_p() {
        let t = CollisionThresholds::new(&CollisionTable::new(0.0));
        assert_eq!((t.r1, t.r2, t.r3), (1 << 31, 0, [0, 0, 0]));
        let t = CollisionThresholds::new(&CollisionTable::new(1.0));
        assert_eq!((t.r2, t.r3[2]), (1 << 32, 1 << 32));
        let t = CollisionThresholds::new(&CollisionTable::new(0.5));
        assert_eq!(t.r2, 1 << 31);
        assert_eq!(t.r3, [threshold(0.5 / 3.0), threshold(1.0 / 3.0), 1 << 31]);
    }

    #[test]
    fn bins_cover_every_row_once() {
        for (l, bin) in [(220, 10), (130, 65), (128, 64), (7, 7), (10, 1), (2200, 10)] {
            let p = Params {
                width: 3,
                length: l,
                bin,
                ..Params::default()
            };
            let pipe = FastPipe::new(p, Rules::default(), 1).unwrap();
            let mut n = vec![0.0; p.bins()];
            pipe.fill_bin_counts(&mut n);
            assert_eq!(n.iter().sum::<f64>(), pipe.particle_count() as f64);
            for (i, &v) in n.iter().enumerate() {
                assert_eq!(pipe.bin_count(i) as f64, v);
                let direct: u32 = (0..3)
                    .flat_map(|x| (i * bin..(i + 1) * bin).map(move |y| (x, y)))
                    .map(|(x, y)| pipe.site(x, y).count_ones())
                    .sum();
                assert_eq!(direct as f64, v, "L {l} bin {bin} i {i}");
            }
        }
    }

    #[test]
    fn the_start_has_density_rho() {
        let p = Params {
            length: 2200,
            rho: 1.5,
            ..Params::default()
        };
        let pipe = FastPipe::new(p, Rules::default(), 3).unwrap();
        let n = pipe.moving_count() as f64;
        let mean = 1.5 * p.sites() as f64;
        assert!(
            (n - mean).abs() < 5.0 * (mean * 0.75).sqrt(),
            "{n} vs {mean}"
        );
        assert_eq!(pipe.rest_count(), 0);
        let open = Params {
            boundary: Boundary::Open { inject: 0.5 },
            ..p
        };
        assert_eq!(
            FastPipe::new(open, Rules::default(), 3)
                .unwrap()
                .particle_count(),
            0
        );
    }
}
