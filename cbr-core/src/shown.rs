//! Numbers as error messages show them: short, whatever their size. Rust prints an `f64`
//! in full (`1e300` as 301 digits, `1e-300` as 302), which buries the message; every
//! crate of the workspace shows an out-of-range number through [`shown`] or [`Shown`].

use std::fmt;

/// A number as messages show it: plainly (`0.25`, `5`, `3600`), or in scientific
/// notation when its plain form would be long (`1e300`, `-1e-300`, not hundreds of
/// digits). Infinities and NaN as Rust writes them (`inf`, `NaN`).
pub fn shown(x: f64) -> String {
    Shown(x).to_string()
}

/// A number that displays as [`shown`] writes it, for `format!` and error attributes
/// (`#[error("... got {}", Shown(*value))]`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shown(pub f64);

impl fmt::Display for Shown {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let x = self.0;
        if x.is_finite() && x != 0.0 && !(1e-4..1e16).contains(&x.abs()) {
            write!(f, "{x:e}")
        } else {
            write!(f, "{x}")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_numbers_are_shown_short_and_short_ones_plainly() {
        assert_eq!(shown(1e300), "1e300");
        assert_eq!(shown(-1e-300), "-1e-300");
        assert_eq!(shown(1.5e30), "1.5e30");
        assert_eq!(shown(0.25), "0.25");
        assert_eq!(shown(5.0), "5");
        assert_eq!(shown(3600.0), "3600");
        assert_eq!(shown(0.0), "0");
        assert_eq!(shown(f64::INFINITY), "inf");
        assert_eq!(shown(f64::NAN), "NaN");
        assert_eq!(format!("got {}", Shown(1e308)), "got 1e308");
    }
}
