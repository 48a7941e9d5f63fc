//! Relocation of the extra rest particles of R4 and R5 (MODEL.md A4), one
//! function for both engines: the reference ([`super::Pipe`]) and the fast
//! engine ([`super::fast::FastPipe`]) differ in how they store the rest
//! channels ([`RestChannels`]) and draw their random numbers, not in the rule.

use super::{Boundary, Params, RestPlacement, Rules};
use crate::error::{Error, ErrorKind, Result};
use crate::lattice::neighbour_offset;

/// Whether an error means the model is undefined for this run (MODEL.md A4)
/// rather than a bug or bad input.
pub fn is_validity_limit(kind: ErrorKind) -> bool {
    matches!(
        kind,
        ErrorKind::RestExceedsSites | ErrorKind::RelocationStuck
    )
}

/// The rest channels of a lattice, as relocation reads and fills them.
pub trait RestChannels {
    /// Whether site (x, y) holds a rest particle.
    fn has_rest(&self, x: usize, y: usize) -> bool;
    /// Put a rest particle on site (x, y) (its rest channel is empty).
    fn put_rest(&mut self, x: usize, y: usize);
}

/// Place the extra rest particles created at `extras` (sites (x, y), one
/// entry per particle; reordered here) when the lattice already holds
/// `rest_now` rest particles, at step `time` (for the error messages).
///
/// First the validity check: more rest particles than sites make the model
/// undefined (`RestExceedsSites`). Then the sites in row-major order (row by
/// row from the bottom, left to right), one particle at a time: `rest-up`
/// (the nearest free site above in the column), else the random walk over
/// neighbouring sites, each hop to one of the `n` valid neighbours chosen by
/// `below(n)` (uniform in 0..n), until a free rest channel is found; a walk
/// longer than [`walk_bound`] hops is `RelocationStuck`.
#[allow(clippy::too_many_arguments)] // the lattice, its run and its draws
pub fn relocate(
    lattice: &mut impl RestChannels,
    below: &mut impl FnMut(u32) -> u32,
    params: &Params,
    rules: Rules,
    extras: &mut [(usize, usize)],
    rest_now: u64,
    time: u64,
) -> Result<()> {
    relocate_with(
        lattice,
        params,
        rules,
        extras,
        rest_now,
        time,
        |lat, x, y| random_walk(lat, below, params, rules, x, y, time),
    )
}

/// [`relocate`] with the random walk given as `walk(lattice, x, y)`, which
/// places one particle by the walk from (x, y). An engine may walk faster
/// than [`random_walk`] but not differently: the same hops from the same
/// draws (the fast engine's [`crate::pipe::fast::walk`], tested equal).
pub fn relocate_with<L: RestChannels>(
    lattice: &mut L,
    params: &Params,
    rules: Rules,
    extras: &mut [(usize, usize)],
    rest_now: u64,
    time: u64,
    mut walk: impl FnMut(&mut L, usize, usize) -> Result<()>,
) -> Result<()> {
    // the sites that can hold a rest particle (not the wall sites of
    // `wall-sites`, READINGS.md P12)
    let sites = (rules.inner_columns(params.width).len() * params.length) as u64;
    let total = rest_now + extras.len() as u64;
    if total > sites {
        let p = params;
        return Err(Error::new(
            ErrorKind::RestExceedsSites,
            format!(
                "at step {time}: {total} rest particles for {sites} sites (rho = {}, p = {}, g = {}, b = {}, W = {}, L = {}); \
                 the model is undefined here [PH95 G]: lower rho or p",
                p.rho, p.p, p.g, p.b, p.width, p.length
            ),
        ));
    }
    extras.sort_unstable_by_key(|&(x, y)| (y, x));
    for &(x, y) in extras.iter() {
        let placed = match rules.rest {
            RestPlacement::RestUp => place_above(lattice, params, x, y),
            RestPlacement::RandomWalk => false,
        };
        if !placed {
            walk(lattice, x, y)?;
        }
    }
    Ok(())
}

/// The longest walk: 1000 W L + 10^6 hops (then `RelocationStuck`).
pub fn walk_bound(params: &Params) -> u64 {
    1000 * params.sites() as u64 + 1_000_000
}

/// The error of a walk that found no empty rest channel within
/// [`walk_bound`] hops, at step `time`.
pub fn stuck(params: &Params, time: u64) -> Error {
    Error::new(
        ErrorKind::RelocationStuck,
        format!(
            "at step {time}: an extra rest particle found no empty rest channel within {} hops \
             (W = {}, L = {}, rho = {}, p = {}); the lattice is (nearly) full of rest particles: lower rho or p",
            walk_bound(params), params.width, params.length, params.rho, params.p
        ),
    )
}

/// `rest-up`: the nearest site above (x, y) in its column with an empty rest
/// channel, wrapping in the periodic pipe; false if there is none.
fn place_above(lattice: &mut impl RestChannels, params: &Params, x: usize, y: usize) -> bool {
    let l = params.length;
    let periodic = params.boundary == Boundary::Periodic;
    for d in 1..l {
        let mut ny = y + d;
        if ny >= l {
            if !periodic {
                return false;
            }
            ny -= l;
        }
        if !lattice.has_rest(x, ny) {
            lattice.put_rest(x, ny);
            return true;
        }
    }
    false
}

/// `PICK[m][k]`: the position of the k-th set bit (from 0) of the 6-bit
/// mask `m`, so that hops enumerate the valid directions in order 1..=6.
const PICK: [[u8; 6]; 64] = {
    let mut t = [[0u8; 6]; 64];
    let mut m = 0;
    while m < 64 {
        let (mut i, mut k) = (0, 0);
        while i < 6 {
            if m >> i & 1 == 1 {
                t[m][k] = i as u8;
                k += 1;
            }
            i += 1;
        }
        m += 1;
    }
    t
};

/// The random walk from (x, y) over neighbouring sites (walls, the wall
/// sites of `wall-sites`, and rows beyond the open ends excluded) until a
/// site with an empty rest channel is reached.
pub fn random_walk(
    lattice: &mut impl RestChannels,
    below: &mut impl FnMut(u32) -> u32,
    params: &Params,
    rules: Rules,
    mut x: usize,
    mut y: usize,
    time: u64,
) -> Result<()> {
    let inner = rules.inner_columns(params.width);
    // the columns a walk may enter: x0 <= x < w
    let (x0_min, w) = (inner.start as i64, inner.end as i64);
    let l = params.length as i64;
    let periodic = params.boundary == Boundary::Periodic;
    let bound = walk_bound(params);
    // the six hops of an even and an odd column, in direction order 1..=6
    let hop =
        [0, 1].map(|parity| core::array::from_fn::<_, 6, _>(|k| neighbour_offset(k + 1, parity)));
    for _ in 0..bound {
        let (x0, y0) = (x as i64, y as i64);
        let steps = &hop[x % 2];
        let interior = x0 > x0_min && x0 < w - 1 && (periodic || (y0 >= 1 && y0 < l - 1));
        let (dx, dy) = if interior {
            // all six valid: direction below(6) + 1, as the enumeration gives
            steps[below(6) as usize]
        } else {
            // the valid directions as a mask (bit k: direction k + 1), computed
            // without branches; the hop is the below(n)-th of the n valid ones
            let mut valid = 0usize;
            for (k, &(dx, dy)) in steps.iter().enumerate() {
                let (nx, ny) = (x0 + dx, y0 + dy);
                let inside = (nx >= x0_min) & (nx < w) & (periodic | ((ny >= 0) & (ny < l)));
                valid |= (inside as usize) << k;
            }
            if valid == 0 {
                break;
            }
            steps[PICK[valid][below(valid.count_ones()) as usize] as usize]
        };
        x = (x0 + dx) as usize;
        // periodic: the row wraps by at most one length
        let ny = y0 + dy;
        y = (if ny < 0 {
            ny + l
        } else if ny >= l {
            ny - l
        } else {
            ny
        }) as usize;
        if !lattice.has_rest(x, y) {
            lattice.put_rest(x, y);
            return Ok(());
        }
    }
    Err(stuck(params, time))
}

#[cfg(test)]
mod tests {
    use super::PICK;

    #[test]
    fn pick_lists_the_set_bits_in_order() {
        assert_eq!(PICK[0b11_1111], [0, 1, 2, 3, 4, 5]);
        assert_eq!(PICK[0b10_1000][..2], [3, 5]);
        for (m, pick) in PICK.iter().enumerate() {
            let bits: Vec<u8> = (0..6).filter(|i| m >> i & 1 == 1).collect();
            assert_eq!(pick[..bits.len()], bits[..], "mask {m:06b}");
        }
    }
}
