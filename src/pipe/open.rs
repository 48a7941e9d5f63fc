//! The open pipe (MODEL.md A7, PH95 Figs. 11-12): runs from an empty pipe
//! with injection at the top, the recorded bin densities and particle number,
//! the exact mass bookkeeping, and the two-point correlation C(R, T) of
//! MODEL.md A9 with its peak.

use super::{Boundary, Params, Pipe, Rules};
use crate::error::{Error, ErrorKind, Result};
use serde::{Deserialize, Serialize};

/// What one open-pipe run records.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct OpenRecord {
    /// Steps between samples.
    pub every: u64,
    /// Bin counts n_i(t), one vector per sample (sample s at step (s+1) * every).
    pub n: Vec<Vec<f64>>,
    /// Particle number N(t) at each sample.
    pub total: Vec<f64>,
    /// Samples at which injected - out_bottom - out_top differed from N(t)
    /// (MODEL.md A7: must be 0).
    pub bookkeeping_errors: u64,
    /// Particles injected over the run.
    pub injected: u64,
    /// Particles that left at the bottom.
    pub out_bottom: u64,
    /// Particles that left at the top.
    pub out_top: u64,
    /// When the run left the model's validity (MODEL.md A4: the pipe filled
    /// with rest particles, a clog): the step and the message. The record
    /// holds the samples before it.
    pub stopped: Option<(u64, String)>,
}

/// The injection rate of an open pipe, or an error naming the boundary.
pub fn inject_of(params: &Params) -> Result<f64> {
    match params.boundary {
        Boundary::Open { inject } => Ok(inject),
        Boundary::Periodic => Err(Error::new(
            ErrorKind::InvalidParameter,
            "an open-pipe run needs boundary = Open { inject }, got Periodic; set Params::boundary",
        )),
    }
}

/// Run an open pipe from empty for `steps` steps, sampling every `every`
/// steps (bin counts only when `bins` is true) and checking the bookkeeping
/// injected - out_bottom - out_top = N(t) - N(0) at every sample.
pub fn open_run(
    params: Params,
    rules: Rules,
    seed: u64,
    steps: u64,
    every: u64,
    bins: bool,
    tick: &(dyn Fn(u64) + Sync),
) -> Result<OpenRecord> {
    inject_of(&params)?;
    if every == 0 {
        return Err(Error::out_of_range("sampling interval", 0, "[1, inf)"));
    }
    let mut pipe = Pipe::new(params, rules, seed)?;
    let n0 = pipe.particle_count() as i64;
    let mut rec = OpenRecord {
        every,
        n: Vec::new(),
        total: Vec::new(),
        bookkeeping_errors: 0,
        injected: 0,
        out_bottom: 0,
        out_top: 0,
        stopped: None,
    };
    for _ in 0..steps / every {
        if let Err(e) = pipe.run(every) {
            if crate::pipe::sweep::is_validity_limit(e.kind) {
                rec.stopped = Some((pipe.time(), e.message));
                break;
            }
            return Err(e);
        }
        tick(every);
        let f = pipe.flux();
        let n = pipe.particle_count() as i64;
        if f.injected as i64 - f.out_bottom as i64 - f.out_top as i64 != n - n0 {
            rec.bookkeeping_errors += 1;
        }
        rec.total.push(n as f64);
        if bins {
            rec.n.push(pipe.bin_counts());
        }
    }
    let f = pipe.flux();
    rec.injected = f.injected;
    rec.out_bottom = f.out_bottom;
    rec.out_top = f.out_top;
    Ok(rec)
}

/// Two-point correlation of MODEL.md A9 (PH95 eq. 2),
/// C(R, T) = <dn_i(t) dn_{i+R}(t+T)> averaged over all i, t with both bins
/// inside the pipe (no wrap) and both times inside the record, for
/// T = 0..=t_max samples. dn_i = n_i - (time mean of n_i): the constant
/// background <n_i><n_{i+R}> of eq. 2 is removed (it does not move the peak
/// for a stationary record). R may be negative (bin i+R below bin i).
pub fn correlation(n: &[Vec<f64>], r: isize, t_max: usize) -> Result<Vec<f64>> {
    let s = n.len();
    let k = n.first().map_or(0, |v| v.len());
    if s <= t_max + 1 || k as isize <= r.abs() {
        return Err(Error::new(
            ErrorKind::BadSeries,
            format!(
                "correlation needs more than t_max + 1 = {} samples and more than |R| = {} bins; got {s} samples of {k} bins; record longer or lower R",
                t_max + 1,
                r.abs()
            ),
        ));
    }
    let mean: Vec<f64> = (0..k)
        .map(|i| n.iter().map(|v| v[i]).sum::<f64>() / s as f64)
        .collect();
    let d: Vec<Vec<f64>> = n
        .iter()
        .map(|v| v.iter().zip(&mean).map(|(x, m)| x - m).collect())
        .collect();
    let (i0, i1) = if r >= 0 {
        (0, k - r as usize)
    } else {
        ((-r) as usize, k)
    };
    Ok((0..=t_max)
        .map(|t| {
            let mut sum = 0.0;
            for tt in 0..s - t {
                let (a, b) = (&d[tt], &d[tt + t]);
                for i in i0..i1 {
                    sum += a[i] * b[(i as isize + r) as usize];
                }
            }
            sum / ((s - t) * (i1 - i0)) as f64
        })
        .collect())
}

/// Index of the largest value of `c` with index >= `from` (the peak T_c).
pub fn peak_index(c: &[f64], from: usize) -> Option<usize> {
    (from..c.len())
        .filter(|&t| c[t].is_finite())
        .max_by(|&a, &b| c[a].total_cmp(&c[b]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn correlation_finds_a_moving_pulse() {
        // a pulse moving up one bin every 3 samples: C(R = 4, T) peaks at T = 12
        let k = 20;
        let n: Vec<Vec<f64>> = (0..300)
            .map(|t| {
                let pos = (t / 3) % k;
                (0..k).map(|i| if i == pos { 5.0 } else { 1.0 }).collect()
            })
            .collect();
        let c = correlation(&n, 4, 30).unwrap();
        assert_eq!(peak_index(&c, 1), Some(12));
        // the reverse direction does not peak at 12
        let c = correlation(&n, -4, 30).unwrap();
        assert_ne!(peak_index(&c, 1), Some(12));
        assert!(correlation(&n, 25, 30).is_err());
    }

    #[test]
    fn open_run_keeps_the_books() {
        let params = Params {
            length: 100,
            width: 5,
            p: 0.5,
            b: 0.5,
            g: 0.2,
            boundary: Boundary::Open { inject: 0.2 },
            ..Params::default()
        };
        let rec = open_run(params, Rules::default(), 3, 2000, 10, true, &|_| {}).unwrap();
        assert_eq!(rec.bookkeeping_errors, 0);
        assert!(rec.stopped.is_none());
        assert!(rec.injected > 0 && rec.out_bottom > 0);
        assert_eq!(
            rec.injected - rec.out_bottom - rec.out_top,
            *rec.total.last().unwrap() as u64
        );
        // I = 0.5 fills this pipe with rest particles: recorded, not fatal
        let clog = Params {
            boundary: Boundary::Open { inject: 0.5 },
            ..params
        };
        let rec = open_run(clog, Rules::default(), 3, 2000, 10, true, &|_| {}).unwrap();
        assert!(rec.stopped.is_some() && rec.bookkeeping_errors == 0);
        assert!(open_run(
            Params::default(),
            Rules::default(),
            3,
            10,
            10,
            false,
            &|_| {}
        )
        .is_err());
    }
}
