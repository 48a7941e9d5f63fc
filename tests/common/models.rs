//! Set-ups the model tests share: every rule reading of the pipe, and the
//! hopper's energy computed directly from MODEL.md B4.

use granular_automata::hopper::energy::{motion, orientation};
use granular_automata::hopper::model::{grain_state, is_grain};
use granular_automata::hopper::{Aligned, Hopper};
use granular_automata::lattice::velocity;
use granular_automata::pipe::{Boundary, GravityWording, Params, RestPlacement, Rules};

/// A pipe of L = `length` rows and W = `width` columns with `boundary`; p,
/// g, b, rho and the bins at their defaults (PH94 Fig. 2, [`Params::default`]).
pub fn pipe(length: usize, width: usize, boundary: Boundary) -> Params {
    Params {
        length,
        width,
        boundary,
        ..Params::default()
    }
}

/// Every rule reading (the 96 combinations of the rule switches).
pub fn all_rules() -> Vec<Rules> {
    let mut v = Vec::new();
    for gravity in [
        GravityWording::Ph94,
        GravityWording::AnyMover,
        GravityWording::UpToRest,
    ] {
        for wall_drag in [false, true] {
            for gravity_first in [false, true] {
                for rest in [RestPlacement::RandomWalk, RestPlacement::RestUp] {
                    for wall_move in [false, true] {
                        for rest_slide in [false, true] {
                            v.push(Rules {
                                gravity,
                                wall_drag,
                                gravity_first,
                                rest,
                                wall_move,
                                rest_slide,
                                ..Rules::MODEL_MD
                            });
                        }
                    }
                }
            }
        }
    }
    v
}

/// E_i of MODEL.md B4 computed directly from the vectors, powers and the
/// reading of "aligned" (slow, obvious reference).
pub fn reference_energy(h: &Hopper, i: usize, s: usize) -> f64 {
    let p = h.params().energy;
    let g = h.geometry();
    let sites = h.sites();
    let hole = |j: u32| j != u32::MAX && sites[j as usize] == 0;
    let nb = g.nbr[i];
    let below = hole(nb[2]) || hole(nb[3]) || hole(nb[4]);
    let v = motion(s);
    let mut e = if below && !(v == 3 || v == 4 || v == 5) {
        p.delta
    } else {
        0.0
    };
    for (k, &j) in nb.iter().enumerate() {
        if j == u32::MAX || !is_grain(sites[j as usize]) {
            continue;
        }
        let sn = grain_state(sites[j as usize]);
        let (a, b) = (velocity(v), velocity(motion(sn)));
        let shear = ((a.0 - b.0).powi(2) + (a.1 - b.1).powi(2)).sqrt() + 0.1;
        let same = orientation(s) == orientation(sn);
        // axis of orientation o: directions o + 1 and o + 4
        let along = |m: usize| m != 0 && (m - 1) % 3 == orientation(s);
        let aligned = match p.aligned {
            Aligned::SameOrientation => same,
            Aligned::AlongVelocity => same && (along(v) || along(motion(sn))),
            // the neighbour lies in direction k + 1, along axis k mod 3
            Aligned::AlongBond => same && k % 3 == orientation(s),
        };
        let orient = if aligned { p.s } else { 1.0 };
        let d = 0.5 * (h.spacing()[i] + h.spacing()[j as usize]);
        let dil = if d <= 1.0 / (1.0 - p.c) { 1.0 / d } else { 0.2 };
        e += shear.powf(p.alpha) * orient.powf(p.beta) * dil.powf(p.gamma);
    }
    e
}

/// Rain grains into `h` for the iterations before `rain_until`, open the
/// plug at `open_at`, run `iterations` in all, and every `every` iterations
/// assert that each grain's tabulated energies equal [`reference_energy`]
/// (`what` names the case in a failure); the number of energies compared.
pub fn check_energies(
    h: &mut Hopper,
    (iterations, rain_until, open_at, every): (u64, u64, u64, u64),
    what: &str,
) -> usize {
    let mut checked = 0;
    for it in 0..iterations {
        if it == open_at {
            h.open();
        }
        h.step(it < rain_until);
        if it % every != every - 1 {
            continue;
        }
        for i in 0..h.sites().len() {
            if !is_grain(h.sites()[i]) {
                continue;
            }
            for (s, got) in h.debug_energies(i) {
                let r = reference_energy(h, i, s);
                assert!(
                    (got - r).abs() <= 1e-9 * r.abs().max(1.0),
                    "{what}: site {i} state {s}: {got} vs {r}"
                );
                checked += 1;
            }
        }
    }
    checked
}
