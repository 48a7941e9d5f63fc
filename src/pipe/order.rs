//! The order of one time step (MODEL.md A2), written once for every engine:
//! an engine implements the sub-steps ([`SubSteps`]), [`step`] runs them.

use super::{Boundary, Params, Rules};
use crate::error::Result;

/// The sub-steps of one time step of the pipe (MODEL.md A2), each over the
/// whole lattice, as one engine implements them.
pub(crate) trait SubSteps {
    /// The parameters of the run.
    fn params(&self) -> &Params;
    /// The rule reading of the run.
    fn rules(&self) -> Rules;
    /// Injection at the top row of the open pipe (A7): channels 3, 4, 5, or
    /// channel 4 alone with `inject-down` (READINGS.md P17).
    fn inject(&mut self);
    /// Collisions (A3), then the relocation of extra rest particles (A4).
    fn collide(&mut self) -> Result<()>;
    /// Gravity (A5), with `rest-slide` if named.
    fn gravity(&mut self);
    /// `wall-drag` (A6 variant).
    fn wall_drag(&mut self);
    /// `wall-move` (A6): the wall rule before propagation.
    fn wall_move(&mut self);
    /// Propagation (A2 step 5) with the walls (A6) and the ends (A7).
    fn propagate(&mut self);
    /// Count the step done (the clock the runs report as `time`).
    fn tick(&mut self);
}

/// One time step (MODEL.md A2): injection (open pipe only; with
/// `inject-late` it comes after gravity instead, READINGS.md P18); gravity
/// then collisions with `gravity-first`, collisions alone with
/// `gravity-last`, else collisions then gravity; `wall-drag` and `wall-move`
/// if named; propagation; gravity with `gravity-last` (READINGS.md P9).
pub(crate) fn step(engine: &mut impl SubSteps) -> Result<()> {
    step_observed(engine, &mut |_, _| {})
}

/// Where in a step an observer of [`step_observed`] looks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Stage {
    /// Just before gravity (A5), wherever the reading puts it.
    BeforeGravity,
    /// Just before the collisions (after gravity with `gravity-first`).
    BeforeCollide,
    /// Just after the collisions and the relocation of their extra rest
    /// particles.
    AfterCollide,
}

/// [`step`], with `observe` called on the engine around the collisions (a
/// diagnostic, e.g. [`crate::pipe::stops`]); it cannot change the run.
pub(crate) fn step_observed<E: SubSteps>(
    engine: &mut E,
    observe: &mut impl FnMut(Stage, &E),
) -> Result<()> {
    let rules = engine.rules();
    let open = matches!(engine.params().boundary, Boundary::Open { .. });
    if open && !rules.inject_late {
        engine.inject();
    }
    if rules.gravity_first {
        observe(Stage::BeforeGravity, engine);
        engine.gravity();
        collide(engine, observe)?;
    } else {
        collide(engine, observe)?;
        if !rules.gravity_last {
            observe(Stage::BeforeGravity, engine);
            engine.gravity();
        }
    }
    if open && rules.inject_late {
        engine.inject();
    }
    if rules.wall_drag {
        engine.wall_drag();
    }
    // with `wall-sites` no particle heads out of a wall site: nothing to move
    if rules.wall_move && !rules.wall_sites {
        engine.wall_move();
    }
    engine.propagate();
    if rules.gravity_last {
        observe(Stage::BeforeGravity, engine);
        engine.gravity();
    }
    engine.tick();
    Ok(())
}

/// Collisions and relocation (A3, A4), observed before and after.
fn collide<E: SubSteps>(engine: &mut E, observe: &mut impl FnMut(Stage, &E)) -> Result<()> {
    observe(Stage::BeforeCollide, engine);
    engine.collide()?;
    observe(Stage::AfterCollide, engine);
    Ok(())
}
