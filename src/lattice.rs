//! The triangular lattice with a vertical axis and its six unit directions
//! (MODEL.md A1; the hopper of Part B uses the same lattice).
//!
//! Columns `x = 0..W` are horizontal, rows `y = 0..L` vertical with gravity
//! towards decreasing `y`. Odd columns are shifted up by half a spacing:
//! site `(x, y)` sits at `(x * sqrt(3)/2, y + (x mod 2)/2)`.
//!
//! Directions are numbered `1..=6` counter-clockwise starting straight up;
//! `0` is reserved for "rest" (no motion).
//!
//! ```
//! use granular_automata::lattice::{neighbour_offset, opposite, DOWN, UP};
//! assert_eq!(opposite(UP), DOWN);
//! // the up-left neighbour of an odd column is one row higher
//! assert_eq!(neighbour_offset(2, 3), (-1, 1));
//! assert_eq!(neighbour_offset(2, 4), (-1, 0));
//! ```

/// Rest (no velocity); channel 0 of the pipe gas.
pub const REST: usize = 0;
/// Straight up, angle 90 degrees, e = (0, 1).
pub const UP: usize = 1;
/// Up-left, 150 degrees.
pub const UP_LEFT: usize = 2;
/// Down-left, 210 degrees.
pub const DOWN_LEFT: usize = 3;
/// Straight down, 270 degrees: the direction of gravity.
pub const DOWN: usize = 4;
/// Down-right, 330 degrees.
pub const DOWN_RIGHT: usize = 5;
/// Up-right, 30 degrees.
pub const UP_RIGHT: usize = 6;

/// The six moving directions in order.
pub const DIRECTIONS: [usize; 6] = [UP, UP_LEFT, DOWN_LEFT, DOWN, DOWN_RIGHT, UP_RIGHT];

/// Short names of the channels 0..=6, for tables and printouts.
pub const CHANNEL_NAMES: [&str; 7] = [
    "rest",
    "up",
    "up-left",
    "down-left",
    "down",
    "down-right",
    "up-right",
];

const S3_2: f64 = 0.866_025_403_784_438_6;

/// Unit velocity `e_c` of direction `c` (MODEL.md A1); `e_0 = (0, 0)`.
pub fn velocity(c: usize) -> (f64, f64) {
    match c {
        0 => (0.0, 0.0),
        1 => (0.0, 1.0),
        2 => (-S3_2, 0.5),
        3 => (-S3_2, -0.5),
        4 => (0.0, -1.0),
        5 => (S3_2, -0.5),
        6 => (S3_2, 0.5),
        _ => panic!("direction {c} is not in 0..=6"),
    }
}

/// Integer velocity components `(2*vx/sqrt(3), 2*vy)`, exact for momentum
/// bookkeeping: `e_c` in units where both components are integers.
pub fn velocity_int(c: usize) -> (i32, i32) {
    match c {
        0 => (0, 0),
        1 => (0, 2),
        2 => (-1, 1),
        3 => (-1, -1),
        4 => (0, -2),
        5 => (1, -1),
        6 => (1, 1),
        _ => panic!("direction {c} is not in 0..=6"),
    }
}

/// Direction `c + k`, wrapping within `1..=6` (`c` must be a moving direction).
pub fn rotate(c: usize, k: usize) -> usize {
    debug_assert!((1..=6).contains(&c));
    (c - 1 + k) % 6 + 1
}

/// The opposite direction, `e_{c+3} = -e_c`.
pub fn opposite(c: usize) -> usize {
    rotate(c, 3)
}

/// Offset `(dx, dy)` from site `(x, y)` to its neighbour in direction `c`,
/// for a site in column `x` (the offset depends on the parity of `x`).
pub fn neighbour_offset(c: usize, x: usize) -> (i64, i64) {
    let odd = x % 2 == 1;
    match c {
        1 => (0, 1),
        4 => (0, -1),
        2 => (-1, if odd { 1 } else { 0 }),
        3 => (-1, if odd { 0 } else { -1 }),
        6 => (1, if odd { 1 } else { 0 }),
        5 => (1, if odd { 0 } else { -1 }),
        _ => panic!("direction {c} is not in 1..=6"),
    }
}

/// Neighbour of `(x, y)` in direction `c` as signed coordinates (may lie
/// outside the lattice; the caller applies walls or periodicity).
pub fn neighbour(x: usize, y: usize, c: usize) -> (i64, i64) {
    let (dx, dy) = neighbour_offset(c, x);
    (x as i64 + dx, y as i64 + dy)
}

/// Position of site `(x, y)` in the plane (unit lattice spacing).
pub fn position(x: usize, y: usize) -> (f64, f64) {
    (x as f64 * S3_2, y as f64 + (x % 2) as f64 * 0.5)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identities_of_the_unit_vectors() {
        for c in 1..=6 {
            let (a, b) = velocity_int(c);
            let (o1, o2) = velocity_int(opposite(c));
            assert_eq!((a + o1, b + o2), (0, 0));
            // e_c + e_{c+2} = e_{c+1}
            let (p, q) = velocity_int(rotate(c, 2));
            assert_eq!((a + p, b + q), velocity_int(rotate(c, 1)));
            // integer and float forms agree
            let (fx, fy) = velocity(c);
            assert!((fx - a as f64 * S3_2).abs() < 1e-12);
            assert!((fy - b as f64 * 0.5).abs() < 1e-12);
        }
    }

    #[test]
    fn neighbours_lie_at_unit_distance_in_their_direction() {
        for x in 2..4 {
            for c in 1..=6 {
                let (nx, ny) = neighbour(x, 5, c);
                let (px, py) = position(x, 5);
                let (qx, qy) = position(nx as usize, ny as usize);
                let (ex, ey) = velocity(c);
                assert!((qx - px - ex).abs() < 1e-12, "x={x} c={c}");
                assert!((qy - py - ey).abs() < 1e-12, "x={x} c={c}");
                // going back returns home
                let (bx, by) = neighbour(nx as usize, ny as usize, opposite(c));
                assert_eq!((bx, by), (x as i64, 5));
            }
        }
    }
}
