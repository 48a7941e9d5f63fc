//! The margins Delta of the pipe's published claims that the reproduction
//! matrix ([`crate::drivers::claims`]), the sweeps ([`crate::drivers::sweep`]) and the figure
//! binaries share, each fixed before measuring. They live below all of
//! them, so none imports another for a constant. The margins of
//! the acceptance tier, with their derivations, are in
//! [`crate::drivers::acceptance::MARGINS`].

/// Agreement margin Delta of the alpha claims ("alpha near 4/3", "white
/// noise, alpha about 0"): |alpha - target| <= 0.1, a third of the way from
/// 4/3 to 1/f noise (alpha = 1). Fixed 2026-11-25, before grading the new
/// readings; see `equivalent`.
pub const ALPHA_MARGIN: f64 = 0.1;

/// Agreement margin Delta of the wave speed v = 0.40 of PH94 Fig. 2 (quoted
/// to two decimals: rounding +-0.005, doubled).
pub const V_MARGIN: f64 = 0.01;

/// Margin Delta of "the wave speed does not change with p" (PH95 Fig.
/// 8b, "within the error bars"): the published error bar of the wave speed,
/// 0.05 (PH95 Fig. 5).
pub const V_SAME_MARGIN: f64 = crate::pipe::overlap::SPEED_MARGIN;
