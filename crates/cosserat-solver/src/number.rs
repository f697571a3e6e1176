//! Numbers as messages show them.

use std::fmt;

/// A number as messages show it: plain where that stays short, scientific notation elsewhere, so
/// that a time step of `1e-8` or a load factor of `1e-300` is not written out in tens or hundreds of
/// digits (Rust's `Display` of `f64` never switches to an exponent). Both forms are the shortest text
/// that reads back as the same value, as with `Display`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Num(pub f64);

impl fmt::Display for Num {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let x = self.0;
        if x == 0.0 || !x.is_finite() || (1e-4..1e15).contains(&x.abs()) {
            write!(f, "{x}")
        } else {
            write!(f, "{x:e}")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Num;

    #[test]
    fn moderate_numbers_are_plain_and_extreme_ones_have_an_exponent() {
        assert_eq!(Num(0.0).to_string(), "0");
        assert_eq!(Num(0.25).to_string(), "0.25");
        assert_eq!(Num(-3.0).to_string(), "-3");
        assert_eq!(Num(1e-8).to_string(), "1e-8");
        assert_eq!(Num(5e-8).to_string(), "5e-8");
        assert_eq!(Num(1.5e300).to_string(), "1.5e300");
        assert_eq!(Num(f64::NAN).to_string(), "NaN");
        assert_eq!(Num(f64::NEG_INFINITY).to_string(), "-inf");
    }

    #[test]
    fn both_forms_read_back_as_the_same_value() {
        for x in [0.1 + 0.2, 1e-5 / 3.0, 1e20 / 7.0, f64::MIN_POSITIVE, -f64::MAX] {
            let back: f64 = Num(x).to_string().parse().expect("a number");
            assert_eq!(back.to_bits(), x.to_bits());
        }
    }
}
