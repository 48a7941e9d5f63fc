//! Rule variants of the pipe lattice gas: the readings of the papers' text
//! that MODEL.md names (A2, A4, A5, A6, A11). A variant is a value, not a fork
//! of the code: the engine builds its tables from it once.
//!
//! A rule set is written as names joined by `+`, e.g. `ph94+wall-drag` or
//! `any-mover+gravity-first`. `ph94` alone is the literal reading of
//! MODEL.md A2-A6 (the first default); `default` is the project's default,
//! the reading that reproduces the most published claims in the
//! reproduction matrix (MODEL.md A11, EXPERIMENTS.md "Reproducing Peng &
//! Herrmann: which reading"): `ph94+gravity-first+wall-move+inject-late`.
//! `inject-late` acts only in the open pipe, so in the periodic pipe the
//! default is the earlier default `ph94+gravity-first+wall-move`, step for
//! step.
//!
//! ```
//! use granular_automata::pipe::Rules;
//! let r: Rules = "any-mover+rest-up".parse().unwrap();
//! assert_eq!(r.to_string(), "any-mover+rest-up");
//! assert_eq!("default".parse::<Rules>().unwrap(), Rules::default());
//! assert_eq!(Rules::default().to_string(), "ph94+gravity-first+wall-move+inject-late");
//! assert_eq!(Rules::MODEL_MD.to_string(), "ph94");
//! assert!("ph96".parse::<Rules>().is_err());
//! ```

use super::{Boundary, Params};
use crate::error::{Error, ErrorKind};
use std::fmt;
use std::str::FromStr;

/// Which moving particles gravity acts on (MODEL.md A5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum GravityWording {
    /// \[PH94\]: a rest particle falls (0 -> 4); a mover is turned (2 -> 3,
    /// 6 -> 5) only at a site that holds a rest particle. The default.
    Ph94,
    /// \[PH95\]: every mover can be turned (2 -> 3, 6 -> 5), rest particles fall.
    AnyMover,
    /// `any-mover` plus an up-mover stopping (1 -> 0) when the rest channel is
    /// empty. (With the \[PH94\] condition 1 -> 0 could never happen, since the
    /// site must hold a rest particle, so this variant builds on `any-mover`.)
    UpToRest,
    /// `rest-ahead` (READINGS.md P7): \[PH94 (6)\]'s condition for turning a
    /// mover, its collision with a rest particle, read as a collision about
    /// to happen (in the next propagation): a
    /// mover is turned (2 -> 3, 6 -> 5, probability g, into an empty channel)
    /// only when its neighbour along its velocity before the turn (MODEL.md
    /// A1) holds a rest particle; rest particles fall (0 -> 4) as in every
    /// wording. The neighbours are read in the lattice state at the start of
    /// the gravity sub-step, before any of its moves (a rest particle that
    /// falls in this sub-step still counts as ahead). Beyond a wall or an
    /// open end there is no site, hence no rest particle.
    RestAhead,
}

/// Where an extra rest particle of R4/R5 goes (MODEL.md A4, A11).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RestPlacement {
    /// A random walk over neighbouring sites until a site with an empty rest
    /// channel is found (MODEL.md A4). The default.
    RandomWalk,
    /// `rest-up` (A11, "piling up"): the nearest site above in the same column
    /// whose rest channel is empty (wrapping in the periodic pipe; in the open
    /// pipe, or when the column is full, the random walk is used instead).
    RestUp,
}

/// A complete reading of the pipe rules.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Rules {
    /// Which movers gravity turns (A5).
    pub gravity: GravityWording,
    /// `wall-drag` (A6 variant): in a wall column a particle moving along the
    /// wall (1 or 4) is bounced back (1 <-> 4) with probability b if the target
    /// channel is empty, just before propagation.
    pub wall_drag: bool,
    /// `gravity-first` (A2 variant): gravity acts before the collision step
    /// instead of after relocation.
    pub gravity_first: bool,
    /// `gravity-last` (A2 variant, READINGS.md P9): gravity acts after
    /// propagation, as the last sub-step of the step, instead of after
    /// relocation. \[PH94\] lists gravity as rule (6) beside the collisions
    /// and \[PH95 II\] after them, neither in a stated order with
    /// propagation. Under `ph94`, "a site holding a rest particle" is then the
    /// state after propagation. Excludes `gravity-first`.
    pub gravity_last: bool,
    /// Placement of extra rest particles (A4).
    pub rest: RestPlacement,
    /// `wall-move` (A6 variant): a particle heading into a wall is
    /// reflected (bounce-back with probability b, else specular) just before
    /// propagation and moves along its new velocity in the same step, when
    /// the reflected channels of its site are empty; otherwise it is
    /// reflected in place as in A6. Justification: MODEL.md A6 makes a wall
    /// reflection cost a whole step, so a diagonal mover crossing a pipe of
    /// width W falls (W - 1)/2 rows in W steps: at W = 11 it circles the
    /// periodic pipe at v = 5/11 = 0.4545, exactly the b = 0 peak the default
    /// reading shows, while \[PH95\] Fig. 7 has the peak at v = 1/2 "exactly".
    /// In the usual lattice-gas boundary (the wall acts on the link, as a
    /// collision at the wall site) the reflected particle loses no time and a
    /// diagonal mover falls 1/2 per step at every step. With W = 1 both
    /// walls act on the one column and the variant changes nothing.
    pub wall_move: bool,
    /// `rest-slide` (A5 variant): a rest particle whose fall
    /// channel 4 is occupied slides down a diagonal instead (0 -> 3 or
    /// 0 -> 5, one chosen at random among the empty ones) with probability g.
    /// Motivation: with A5 as written every reading ends with channel 4
    /// nearly full at rho >= 1 (a stream of down-movers through every site),
    /// so rest particles can never fall and stand as jams (MODEL.md A11,
    /// EXPERIMENTS.md on `rest-slide`); the diagonals are the only other downward
    /// channels, and they reach the rough walls.
    pub rest_slide: bool,
    /// `fhp-rest` (A3 variant, READINGS.md P4): a mover meeting a lone rest
    /// particle, a site holding exactly {0, c}, leaves as the pair
    /// {c-1, c+1} (FHP-II's rest-particle collision; mass and momentum
    /// conserved). \[PH94 (1)-(5)\] cover no state {0, c}, although a mover
    /// and a rest particle make a collision of two bodies; the probability is 1, as for the other
    /// collisions with a rest particle, (4) and (5), which happen with
    /// certainty. The inverse {c-1, c+1} is R2 of \[PH94 (2)\] and stays as it is.
    pub fhp_rest: bool,
    /// `inject-down` (A7 variant, READINGS.md P17): the open pipe's
    /// injection fills only channel 4, the one velocity straight down the
    /// pipe, instead of every velocity with a downward component (3, 4, 5).
    /// \[PH95 III I\] fills the empty states whose velocities point into the
    /// pipe; on the triangular lattice that can mean the three downward
    /// velocities or only the one along the pipe's axis.
    pub inject_down: bool,
    /// `inject-late` (A2/A7 variant, READINGS.md P18): the open pipe's
    /// injection comes after the collisions and gravity, just before the
    /// wall rules and propagation, so an injected particle leaves the top row
    /// in its first step without colliding there. \[PH95 III I\] does not
    /// place the injection in the step. (Injection after propagation is the
    /// default shifted by a whole step, the same dynamics; READINGS.md P18.)
    pub inject_late: bool,
    /// `lane-collide` (READINGS.md P23, a project extension beyond the
    /// text): two down-movers in contact along the pipe collide. After the
    /// collisions and relocation (A3, A4), a channel-4 mover whose neighbour
    /// below (along 4, MODEL.md A1) held a channel-4 mover at the start of
    /// this sub-step is deflected to 3 or 5 with probability p, or q with
    /// `lane-collide:q` (a fair coin when both are empty, the empty one
    /// otherwise, no move when neither is). Below row 0 of the open pipe there
    /// is no site; the periodic pipe wraps. The pair's downward momentum drops
    /// from 2 to 3/2, a dissipative collision, hence p; at probability 0 the
    /// rule does nothing.
    pub lane_collide: LaneCollide,
    /// `literal-labels` (READINGS.md P1): the indices of \[PH94 (1)-(5)\]
    /// read as velocities on both sides of each rule, instead of arrival
    /// bonds on the left and velocities on the right (MODEL.md A3). R1 and
    /// R4 are unchanged (a head-on pair is the same set either way); R2
    /// becomes {c, c+2} -> {0, c+4} (p) or {c+3, c+5} (1 - p), R5
    /// {0, c, c+2} -> {0, c+4} plus an extra rest particle, so both reverse
    /// the pair's momentum, against the statement that every collision
    /// conserves momentum (\[PH94\] before (1), \[PH95 II\]); R3's 1 - p
    /// outcome {c+1, c+3, c+5} is FHP's rotation of the triple.
    pub literal_labels: bool,
    /// `wall-sites` (READINGS.md P12): the outer columns 0 and W-1 are wall
    /// sites, read from \[PH94\] before (7) and \[PH95 II\] (a site at the
    /// wall has only two directions a particle can move in): they hold only
    /// the two inward diagonals (5 and 6 on the left, 2 and 3 on the right),
    /// never a rest particle or a vertical mover; no collision, gravity or
    /// relocation acts there. A particle arriving at a wall site is
    /// reflected there by the wall rule (A6: bounce-back with probability b,
    /// else specular) and moves back into the pipe in the next step. The
    /// initial fill (A8) occupies every moving state that exists with one
    /// probability, so that E\[N\] = rho W L. Needs W >= 3; `wall-move`
    /// has nothing to act on (no particle heads out of a wall site) and
    /// `wall-drag` is refused (a wall site holds no mover along the wall).
    pub wall_sites: bool,
}

/// Whether and how often two down-movers in contact collide (`lane-collide`,
/// READINGS.md P23).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LaneCollide {
    /// No such collision (the text's rules, the default).
    Off,
    /// `lane-collide`: with probability p, the papers' probability of a
    /// dissipative collision \[PH94 (2); PH95 II\].
    AtP,
    /// `lane-collide:q`: with a probability q of its own, independent of p
    /// (READINGS.md P23, the one-knob bridge between the lane and the gas).
    At(Probability),
}

impl LaneCollide {
    /// Whether the rule acts at all.
    pub fn is_on(self) -> bool {
        self != LaneCollide::Off
    }

    /// Its probability at dissipation `p`: p for `lane-collide`, q for
    /// `lane-collide:q`, 0 when off.
    pub fn probability(self, p: f64) -> f64 {
        match self {
            LaneCollide::Off => 0.0,
            LaneCollide::AtP => p,
            LaneCollide::At(q) => q.get(),
        }
    }
}

/// A probability in \[0, 1\] written in a reading's name (`lane-collide:0.1`);
/// compared and hashed by its bits, which is exact since it is never NaN.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Probability(f64);

impl Probability {
    /// `q`, or a typed error naming it and the allowed range.
    pub fn new(q: f64) -> Result<Self, Error> {
        if q.is_finite() && (0.0..=1.0).contains(&q) {
            Ok(Probability(q + 0.0)) // -0 is written as 0
        } else {
            Err(Error::new(
                ErrorKind::InvalidParameter,
                format!(
                    "rules: lane-collide probability q = {} is outside [0, 1]",
                    crate::error::num(q)
                ),
            ))
        }
    }

    /// The value.
    pub fn get(self) -> f64 {
        self.0
    }
}

impl Eq for Probability {}

impl std::hash::Hash for Probability {
    fn hash<H: std::hash::Hasher>(&self, h: &mut H) {
        self.0.to_bits().hash(h);
    }
}

impl Rules {
    /// The literal reading of MODEL.md A2-A6 (`ph94`): \[PH94\] gravity, no wall drag,
    /// collision before gravity, random-walk relocation, A6 walls.
    pub const MODEL_MD: Rules = Rules {
        gravity: GravityWording::Ph94,
        wall_drag: false,
        gravity_first: false,
        rest: RestPlacement::RandomWalk,
        wall_move: false,
        rest_slide: false,
        gravity_last: false,
        fhp_rest: false,
        inject_down: false,
        inject_late: false,
        lane_collide: LaneCollide::Off,
        literal_labels: false,
        wall_sites: false,
    };
}

impl Rules {
    /// Checks a reading built as a value (names parsed by [`Rules::from_str`]
    /// are checked there): `gravity-first` and `gravity-last` exclude each
    /// other, since gravity acts once per step.
    pub fn validate(&self) -> Result<(), Error> {
        if self.gravity_first && self.gravity_last {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                format!("rules: '{self}' names both gravity-first and gravity-last; gravity acts once per step, name at most one of them"),
            ));
        }
        if self.wall_sites && self.wall_drag {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                format!("rules: '{self}' names both wall-sites and wall-drag; a wall site holds only the two inward diagonals, so there is no mover along the wall to drag: name at most one of them"),
            ));
        }
        Ok(())
    }

    /// Checks this reading against the pipe it runs on: `wall-sites` needs
    /// a column between the two walls (W >= 3), and its initial occupation
    /// rho W / (6 W - 8) of every existing moving state (A8, READINGS.md
    /// P12) must lie below 1, i.e. rho < 6 - 8/W in the periodic pipe.
    pub fn validate_for(&self, params: &Params) -> Result<(), Error> {
        self.validate()?;
        if !self.wall_sites {
            return Ok(());
        }
        let w = params.width;
        if w < 3 {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                format!("rules: wall-sites makes columns 0 and W-1 wall sites and needs W >= 3 (a column between them); W = {w}"),
            ));
        }
        if params.boundary == Boundary::Periodic {
            let hi = 6.0 - 8.0 / w as f64;
            if params.rho >= hi {
                return Err(Error::new(
                    ErrorKind::InvalidParameter,
                    format!(
                        "rho = {} is outside the allowed range (0, {hi}) of wall-sites at W = {w}: the {} moving states per row (6 per inner site, 2 per wall site) hold rho W = {} particles per row on average; choose rho < {hi}",
                        params.rho,
                        6 * w - 8,
                        params.rho * w as f64
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The probability with which each existing moving state is occupied
    /// at the start of the periodic pipe (MODEL.md A8): rho/6 (six moving
    /// states per site); with `wall-sites` (READINGS.md P12) rho W / (6 W -
    /// 8), since a row then holds 6 (W - 2) + 2 + 2 moving states, so that
    /// E\[N\] = rho W L in both.
    pub fn fill_probability(&self, params: &Params) -> f64 {
        if self.wall_sites {
            let w = params.width as f64;
            params.rho * w / (6.0 * w - 8.0)
        } else {
            params.rho / 6.0
        }
    }

    /// The channels site column `x` of a pipe `width` wide can hold, as a
    /// mask: all seven, or with `wall-sites` the two inward diagonals of a
    /// wall site (column 0: 5 and 6; column W-1: 2 and 3).
    pub fn channels_of_column(&self, x: usize, width: usize) -> u8 {
        if self.wall_sites && x == 0 {
            0b0110_0000
        } else if self.wall_sites && x + 1 == width {
            0b0000_1100
        } else {
            0b0111_1111
        }
    }

    /// The columns where particles collide, feel gravity and take rest
    /// particles (the inner columns): 0..W, or 1..W-1 with `wall-sites`.
    pub fn inner_columns(&self, width: usize) -> std::ops::Range<usize> {
        if self.wall_sites {
            1..width.saturating_sub(1)
        } else {
            0..width
        }
    }
}

impl Default for Rules {
    /// The project's default (`default`): `ph94+gravity-first+wall-move`
    /// (chosen by the paper-tier reproduction matrix, MODEL.md A11: PH94
    /// Fig. 1, alpha of PH94 Fig. 2, the b = 0 peak at v = 1/2 of PH95 Fig. 7)
    /// with `inject-late` (the open pipe's injection after collisions and
    /// gravity; 14 of the matrix's 28 claims at the standard tier against 12
    /// without it, EXPERIMENTS.md "the injection axes"). In the periodic pipe
    /// `inject-late` changes nothing.
    fn default() -> Self {
        Rules {
            gravity_first: true,
            wall_move: true,
            inject_late: true,
            ..Rules::MODEL_MD
        }
    }
}

/// Every name understood by [`Rules::from_str`], with its meaning.
pub const RULE_NAMES: [(&str, &str); 17] = [
    (
        "default",
        "the project's default reading, ph94+gravity-first+wall-move+inject-late",
    ),
    (
        "ph94",
        "gravity turns movers only at sites holding a rest particle [PH94]",
    ),
    ("any-mover", "gravity turns every mover [PH95]"),
    ("up-to-rest", "any-mover plus up-movers stopping (1 -> 0)"),
    (
        "rest-ahead",
        "gravity turns only movers whose next site holds a rest particle",
    ),
    (
        "wall-drag",
        "movers along a wall are bounced back (1 <-> 4) with probability b",
    ),
    ("gravity-first", "gravity before the collision step"),
    (
        "gravity-last",
        "gravity after propagation, the last sub-step",
    ),
    (
        "rest-up",
        "extra rest particles pile up on the nearest free site above",
    ),
    (
        "wall-move",
        "a particle reflected by a wall moves along its new velocity in the same step",
    ),
    (
        "rest-slide",
        "a rest particle whose fall channel is occupied slides down a diagonal",
    ),
    (
        "fhp-rest",
        "a mover meeting a lone rest particle, {0, c}, leaves as {c-1, c+1}",
    ),
    (
        "inject-down",
        "the open pipe injects only into channel 4 (straight down)",
    ),
    (
        "inject-late",
        "the open pipe injects just before the wall rules and propagation",
    ),
    (
        "lane-collide",
        "a down-mover above another is deflected to 3 or 5 with probability p (an extension); lane-collide:q with a probability q in [0, 1] of its own",
    ),
    (
        "literal-labels",
        "the collision rules' indices read as velocities on both sides (R2 and R5 reverse the pair's momentum, R3's 1 - p branch rotates the triple)",
    ),
    (
        "wall-sites",
        "columns 0 and W-1 are wall sites holding only the two inward diagonals (no rest particle, collision or gravity there)",
    ),
];

impl GravityWording {
    /// Every wording (a reading names at most one).
    const ALL: [GravityWording; 4] = [
        GravityWording::Ph94,
        GravityWording::AnyMover,
        GravityWording::UpToRest,
        GravityWording::RestAhead,
    ];

    /// The wording's name in a reading.
    fn name(self) -> &'static str {
        match self {
            GravityWording::Ph94 => "ph94",
            GravityWording::AnyMover => "any-mover",
            GravityWording::UpToRest => "up-to-rest",
            GravityWording::RestAhead => "rest-ahead",
        }
    }
}

/// A switch of a reading beside its gravity wording: its name, whether a
/// reading has it on, and how to turn it on.
type Switch = (&'static str, fn(&Rules) -> bool, fn(&mut Rules));

/// Every switch, in the order a reading's name lists them
/// (`ph94+wall-drag+gravity-first`, never the other way round).
const SWITCHES: [Switch; 12] = [
    ("wall-drag", |r| r.wall_drag, |r| r.wall_drag = true),
    (
        "gravity-first",
        |r| r.gravity_first,
        |r| r.gravity_first = true,
    ),
    (
        "rest-up",
        |r| r.rest == RestPlacement::RestUp,
        |r| r.rest = RestPlacement::RestUp,
    ),
    ("wall-move", |r| r.wall_move, |r| r.wall_move = true),
    ("rest-slide", |r| r.rest_slide, |r| r.rest_slide = true),
    (
        "gravity-last",
        |r| r.gravity_last,
        |r| r.gravity_last = true,
    ),
    ("fhp-rest", |r| r.fhp_rest, |r| r.fhp_rest = true),
    ("inject-down", |r| r.inject_down, |r| r.inject_down = true),
    ("inject-late", |r| r.inject_late, |r| r.inject_late = true),
    (
        "lane-collide",
        |r| r.lane_collide == LaneCollide::AtP,
        |r| r.lane_collide = LaneCollide::AtP,
    ),
    (
        "literal-labels",
        |r| r.literal_labels,
        |r| r.literal_labels = true,
    ),
    ("wall-sites", |r| r.wall_sites, |r| r.wall_sites = true),
];

impl fmt::Display for Rules {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut parts = vec![self.gravity.name()];
        parts.extend(SWITCHES.iter().filter(|s| (s.1)(self)).map(|s| s.0));
        let q = match self.lane_collide {
            LaneCollide::At(q) => format!("+lane-collide:{}", crate::error::num(q.get())),
            _ => String::new(),
        };
        write!(f, "{}{q}", parts.join("+"))
    }
}

impl FromStr for Rules {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self, Error> {
        let mut r = Rules::MODEL_MD;
        let mut gravity_named = false;
        let parts: Vec<&str> = s.split('+').map(str::trim).collect();
        crate::error::reject_duplicates("rules", &parts)?;
        for part in parts {
            let g = if part == "default" {
                let d = Rules::default();
                r.gravity_first |= d.gravity_first;
                r.wall_move |= d.wall_move;
                r.inject_late |= d.inject_late;
                Some(d.gravity)
            } else if let Some(&g) = GravityWording::ALL.iter().find(|g| g.name() == part) {
                Some(g)
            } else if let Some(switch) = SWITCHES.iter().find(|sw| sw.0 == part) {
                if part == "lane-collide" && r.lane_collide.is_on() {
                    return Err(Error::new(
                        ErrorKind::InvalidParameter,
                        format!("rules: '{s}' names lane-collide twice; name it once, with or without :q"),
                    ));
                }
                (switch.2)(&mut r);
                None
            } else if let Some(q) = part.strip_prefix("lane-collide:") {
                let q: f64 = q.parse().map_err(|_| {
                    Error::new(
                        ErrorKind::InvalidParameter,
                        format!("rules: '{part}' in '{s}' needs a number q in [0, 1] after 'lane-collide:'"),
                    )
                })?;
                if r.lane_collide.is_on() {
                    return Err(Error::new(
                        ErrorKind::InvalidParameter,
                        format!("rules: '{s}' names lane-collide twice; name it once, with or without :q"),
                    ));
                }
                r.lane_collide = LaneCollide::At(Probability::new(q)?);
                None
            } else {
                let known: Vec<&str> = RULE_NAMES.iter().map(|n| n.0).collect();
                return Err(Error::new(
                    ErrorKind::InvalidParameter,
                    format!(
                        "rules: unknown name '{part}' in '{s}'; use names from {{{}}} joined by '+'",
                        known.join(", ")
                    ),
                ));
            };
            if let Some(g) = g {
                if gravity_named && g != r.gravity {
                    return Err(Error::new(
                        ErrorKind::InvalidParameter,
                        format!("rules: '{s}' names two gravity wordings; name at most one of ph94, any-mover, up-to-rest, rest-ahead"),
                    ));
                }
                gravity_named = true;
                r.gravity = g;
            }
        }
        r.validate()?;
        Ok(r)
    }
}

impl serde::Serialize for Rules {
    /// Serialised as its name, e.g. `"ph94+wall-drag"`.
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&self.to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_combination_round_trips() {
        let single = SWITCHES.iter().map(|s| format!("+{}", s.0));
        let combined = [
            "+fhp-rest+inject-late+lane-collide",
            "+wall-drag+gravity-first+rest-up+wall-move+rest-slide+fhp-rest+inject-down",
            "+wall-drag+rest-up+wall-move+rest-slide+gravity-last+fhp-rest+inject-late",
            "+gravity-first+inject-down+inject-late",
            "+gravity-first+wall-move+inject-late+literal-labels+wall-sites",
        ];
        let extras: Vec<String> = std::iter::once(String::new())
            .chain(single)
            .chain(combined.map(String::from))
            .collect();
        assert_eq!(extras.len(), 18);
        for g in GravityWording::ALL.map(GravityWording::name) {
            for extra in &extras {
                let s = format!("{g}{extra}");
                let r: Rules = s.parse().unwrap();
                assert_eq!(r.to_string(), s);
            }
        }
        assert!("ph94+any-mover".parse::<Rules>().is_err());
        let e = "wall".parse::<Rules>().unwrap_err();
        assert!(e.message.contains("'wall'") && e.message.contains("wall-drag"));
        // every listed name parses, and the listed names are all the names
        for (name, _) in RULE_NAMES {
            assert!(name.parse::<Rules>().is_ok(), "{name}");
        }
        assert_eq!(
            RULE_NAMES.len(),
            1 + GravityWording::ALL.len() + SWITCHES.len()
        );
    }

    #[test]
    fn lane_collide_takes_a_probability_of_its_own() {
        let r: Rules = "default+lane-collide:0.05".parse().unwrap();
        assert_eq!(r.lane_collide.probability(0.5), 0.05);
        assert_eq!(
            r.to_string(),
            "ph94+gravity-first+wall-move+inject-late+lane-collide:0.05"
        );
        assert_eq!(r.to_string().parse::<Rules>().unwrap(), r);
        let at_p: Rules = "default+lane-collide".parse().unwrap();
        assert_eq!(at_p.lane_collide.probability(0.3), 0.3);
        assert_eq!(Rules::default().lane_collide.probability(0.3), 0.0);
        assert_ne!(r, at_p);
        for bad in ["1.5", "-0.1", "NaN", "inf", "", "p"] {
            let e = format!("default+lane-collide:{bad}")
                .parse::<Rules>()
                .unwrap_err();
            assert!(e.message.contains("[0, 1]"), "{bad}: {}", e.message);
        }
        for twice in [
            "default+lane-collide+lane-collide:0.1",
            "default+lane-collide:0.1+lane-collide",
            "default+lane-collide:0.1+lane-collide:0.2",
        ] {
            let e = twice.parse::<Rules>().unwrap_err();
            assert!(e.message.contains("twice"), "{twice}: {}", e.message);
        }
        let zero: Rules = "default+lane-collide:-0".parse().unwrap();
        assert_eq!(
            zero.to_string(),
            "ph94+gravity-first+wall-move+inject-late+lane-collide:0"
        );
    }

    #[test]
    fn literal_labels_and_wall_sites_are_named_parts() {
        let r: Rules = "default+literal-labels".parse().unwrap();
        assert!(r.literal_labels && !r.wall_sites);
        assert_eq!(
            r.to_string(),
            "ph94+gravity-first+wall-move+inject-late+literal-labels"
        );
        let r: Rules = "wall-sites+any-mover+literal-labels".parse().unwrap();
        assert_eq!(r.to_string(), "any-mover+literal-labels+wall-sites");
        assert!(!Rules::default().literal_labels && !Rules::default().wall_sites);
        // wall-drag has no mover along the wall to act on
        let e = "default+wall-sites+wall-drag".parse::<Rules>().unwrap_err();
        assert!(
            e.message.contains("wall-sites") && e.message.contains("wall-drag"),
            "{}",
            e.message
        );
    }

    /// `wall-sites` needs W >= 3 and, in the periodic pipe, rho below
    /// 6 - 8/W (every existing moving state filled with rho W / (6 W - 8) <
    /// 1); the open pipe starts empty and needs only W.
    #[test]
    fn wall_sites_checks_the_pipe_it_runs_on() {
        let ws: Rules = "default+wall-sites".parse().unwrap();
        let p = Params::default();
        assert!(ws.validate_for(&p).is_ok());
        let e = ws.validate_for(&Params { width: 2, ..p }).unwrap_err();
        assert!(
            e.message.contains("W = 2") && e.message.contains("W >= 3"),
            "{}",
            e.message
        );
        let e = ws.validate_for(&Params { rho: 5.5, ..p }).unwrap_err();
        assert!(e.message.contains("rho = 5.5"), "{}", e.message);
        let open = Params {
            rho: 5.5,
            boundary: Boundary::Open { inject: 0.5 },
            ..p
        };
        assert!(ws.validate_for(&open).is_ok());
        assert!(Rules::default()
            .validate_for(&Params { width: 1, ..p })
            .is_ok());
        // E[N] = rho W L: the probability times the moving states per row
        let q = ws.fill_probability(&p);
        assert!((q * (6.0 * 11.0 - 8.0) - 11.0).abs() < 1e-12);
        assert_eq!(Rules::default().fill_probability(&p), 1.0 / 6.0);
        assert_eq!(ws.channels_of_column(0, 11), 0b0110_0000);
        assert_eq!(ws.channels_of_column(10, 11), 0b0000_1100);
        assert_eq!(ws.channels_of_column(5, 11), 0x7f);
        assert_eq!(ws.inner_columns(11), 1..10);
        assert_eq!(Rules::default().inner_columns(11), 0..11);
    }

    #[test]
    fn gravity_first_and_gravity_last_exclude_each_other() {
        for s in ["ph94+gravity-first+gravity-last", "default+gravity-last"] {
            let e = s.parse::<Rules>().unwrap_err();
            assert!(
                e.message.contains("gravity-first") && e.message.contains("gravity-last"),
                "{}",
                e.message
            );
        }
        let r: Rules = "gravity-last+wall-move+fhp-rest+rest-ahead"
            .parse()
            .unwrap();
        assert_eq!(r.to_string(), "rest-ahead+wall-move+gravity-last+fhp-rest");
        assert!("rest-ahead+ph94".parse::<Rules>().is_err());
    }
}
