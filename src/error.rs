//! The one error type of the library: every failure names the offending
//! value, the allowed range and what to do about it.

use std::fmt;

/// What kind of failure an [`Error`] is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorKind {
    /// A parameter lies outside its allowed range (or breaks a constraint
    /// between parameters, such as L being a multiple of the bin size).
    InvalidParameter,
    /// The model is undefined for this state: more rest particles than sites
    /// (MODEL.md A4, \[PH95 G\]); lower rho or p.
    RestExceedsSites,
    /// A relocation walk of an extra rest particle did not find an empty rest
    /// channel within its step bound (MODEL.md A4).
    RelocationStuck,
    /// A time series cannot be analysed (too short, constant, non-finite).
    BadSeries,
    /// Reading or writing an output file failed.
    Io,
    /// The caller stopped the work (Ctrl-C in the Python module).
    Interrupted,
}

/// A failure with a message that names the value, the allowed range and the fix.
/// (`Debug` prints the kind and the message, so `main` returning this error
/// shows a readable line.)
#[derive(Clone, PartialEq)]
pub struct Error {
    /// What kind of failure this is.
    pub kind: ErrorKind,
    /// Human-readable explanation (value, allowed range, fix).
    pub message: String,
}

impl Error {
    /// A new error of `kind` with `message`.
    pub fn new(kind: ErrorKind, message: impl Into<String>) -> Self {
        Error {
            kind,
            message: message.into(),
        }
    }

    /// A parameter `name = value` outside `allowed`; a number written with
    /// hundreds of digits (1e300, 1e-320) is shown as [`num`] writes it.
    pub fn out_of_range(name: &str, value: impl fmt::Display, allowed: &str) -> Self {
        let value = tidy(value.to_string());
        Error::new(
            ErrorKind::InvalidParameter,
            format!("{name} = {value} is outside the allowed range {allowed}; choose {name} in {allowed}"),
        )
    }
}

/// `x` as the shortest text that reads back as `x`, in exponent notation
/// outside 1e-4 <= |x| < 1e16 (Rust's `{}` writes 1e300 with 301 digits and
/// 1e-320 with 320): `0.001`, `1e-320`, `1e300`.
pub fn num(x: f64) -> String {
    if x != 0.0 && x.is_finite() && !(1e-4..1e16).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// A value's text, with a long number (more than 24 characters, e.g. a
/// float written in full) rewritten by [`num`].
fn tidy(text: String) -> String {
    match text.parse::<f64>() {
        Ok(x) if text.len() > 24 => num(x),
        _ => text,
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.message)
    }
}

impl fmt::Debug for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:?}: {}", self.kind, self.message)
    }
}

impl std::error::Error for Error {}

impl From<std::io::Error> for Error {
    fn from(e: std::io::Error) -> Self {
        Error::new(ErrorKind::Io, format!("i/o error: {e}"))
    }
}

/// Result alias of the library.
pub type Result<T> = std::result::Result<T, Error>;

/// Check that a probability-like `value` lies in `[0, 1]` (and is finite).
pub fn check_unit(name: &str, value: f64) -> Result<()> {
    check_range(name, value, 0.0, 1.0)
}

/// Check that `value` lies in the closed interval `[lo, hi]` (and is finite).
pub fn check_range(name: &str, value: f64, lo: f64, hi: f64) -> Result<()> {
    if value.is_finite() && value >= lo && value <= hi {
        Ok(())
    } else {
        Err(Error::out_of_range(name, value, &format!("[{lo}, {hi}]")))
    }
}

/// Check that an integer `value` is at least `min`.
pub fn check_min(name: &str, value: usize, min: usize) -> Result<()> {
    if value >= min {
        Ok(())
    } else {
        Err(Error::out_of_range(name, value, &format!("[{min}, inf)")))
    }
}

/// Parse an option value of the form `a<sep>b`, two whole numbers with
/// `ok(a, b)`, e.g. a shard `2/8` or a pipe size `220x11`. Otherwise an
/// [`ErrorKind::InvalidParameter`] error "`{name} {s:?} is not of the form
/// {form}`" (`form` ends with the fix).
pub fn parse_pair(
    s: &str,
    sep: char,
    name: &str,
    form: &str,
    ok: impl Fn(usize, usize) -> bool,
) -> Result<(usize, usize)> {
    let pair = s.split_once(sep).and_then(|(a, b)| {
        let (a, b) = (a.trim().parse().ok()?, b.trim().parse().ok()?);
        ok(a, b).then_some((a, b))
    });
    pair.ok_or_else(|| {
        Error::new(
            ErrorKind::InvalidParameter,
            format!("{name} {s:?} is not of the form {form}"),
        )
    })
}

/// Reject a list option whose entries repeat (e.g. `--lengths 128,128`,
/// which would run and report the same set-up twice): an
/// [`ErrorKind::InvalidParameter`] error naming the option and the
/// repeated value.
pub fn reject_duplicates<T: PartialEq + std::fmt::Display>(
    option: &str,
    values: &[T],
) -> Result<()> {
    for (i, v) in values.iter().enumerate() {
        if values[..i].contains(v) {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                format!("{option}: {v} is given more than once; give each value once"),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_value_and_range() {
        let e = check_unit("p", 1.5).unwrap_err();
        assert_eq!(e.kind, ErrorKind::InvalidParameter);
        assert!(e.message.contains("p = 1.5"), "{}", e.message);
        assert!(e.message.contains("[0, 1]"), "{}", e.message);
        assert!(check_unit("g", f64::NAN).is_err());
        assert!(check_unit("g", 0.0).is_ok() && check_unit("g", 1.0).is_ok());
        assert!(check_min("W", 0, 1).is_err() && check_min("W", 1, 1).is_ok());
    }
}
