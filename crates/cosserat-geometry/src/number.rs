//! Numbers as the project writes them in text: messages, CSV and PVD files.

use std::fmt;

/// A number as text: plain where that stays short (magnitudes in `[1e-4, 1e15)` and zero), scientific
/// notation elsewhere, so that a time step of `1e-8` or a value of `1e300` is not written out in tens or
/// hundreds of digits (Rust's `Display` of `f64` never switches to an exponent). Both forms are the
/// shortest text that reads back as the same value, so written numbers round-trip bit-exactly.
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
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn moderate_numbers_are_plain_and_extreme_ones_have_an_exponent() {
        assert_eq!(Num(0.0).to_string(), "0");
        assert_eq!(Num(0.1).to_string(), "0.1");
        assert_eq!(Num(0.25).to_string(), "0.25");
        assert_eq!(Num(-2.5).to_string(), "-2.5");
        assert_eq!(Num(-3.0).to_string(), "-3");
        assert_eq!(Num(0.00001).to_string(), "1e-5");
        assert_eq!(Num(1e-8).to_string(), "1e-8");
        assert_eq!(Num(5e-8).to_string(), "5e-8");
        assert_eq!(Num(1e-300).to_string(), "1e-300");
        assert_eq!(Num(1.5e300).to_string(), "1.5e300");
        assert_eq!(Num(f64::NAN).to_string(), "NaN");
        assert_eq!(Num(f64::NEG_INFINITY).to_string(), "-inf");
    }

    #[test]
    fn random_bit_patterns_read_back_as_the_same_value() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let mut checked = 0;
        while checked < 20_000 {
            let x = f64::from_bits(rng.random::<u64>());
            if !x.is_finite() {
                continue;
            }
            let parsed: f64 = Num(x).to_string().parse().expect("formatted numbers parse");
            assert_eq!(parsed.to_bits(), x.to_bits(), "{x:e} did not round-trip");
            checked += 1;
        }
        for x in [0.1 + 0.2, 1e-5 / 3.0, 1e20 / 7.0, f64::MIN_POSITIVE, -f64::MAX] {
            let back: f64 = Num(x).to_string().parse().expect("a number");
            assert_eq!(back.to_bits(), x.to_bits());
        }
    }

    #[test]
    fn negative_zero_keeps_its_sign() {
        let parsed: f64 = Num(-0.0).to_string().parse().expect("parses");
        assert_eq!(parsed.to_bits(), (-0.0f64).to_bits());
    }
}
