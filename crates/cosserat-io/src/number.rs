//! Text formatting of floating-point numbers for the text outputs (CSV, PVD).
//!
//! Rust's `Display` and `LowerExp` without a precision print the shortest decimal string that parses back
//! to the same `f64`, so written numbers round-trip bit-exactly. Plain notation is used for magnitudes
//! where it stays short and scientific notation elsewhere, so that neither `1e-300` nor `1e300` turns
//! into hundreds of digits.

/// The shortest text that parses back to exactly `x` (the caller guarantees `x` is finite).
pub(crate) fn format_f64(x: f64) -> String {
    let magnitude = x.abs();
    if x == 0.0 || (1e-4..1e15).contains(&magnitude) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

#[cfg(test)]
mod tests {
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::*;

    #[test]
    fn formats_are_short_and_readable() {
        assert_eq!(format_f64(0.0), "0");
        assert_eq!(format_f64(0.1), "0.1");
        assert_eq!(format_f64(-2.5), "-2.5");
        assert_eq!(format_f64(1e-300), "1e-300");
        assert_eq!(format_f64(1.5e300), "1.5e300");
        assert_eq!(format_f64(0.00001), "1e-5");
    }

    #[test]
    fn random_bit_patterns_round_trip() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let mut checked = 0;
        while checked < 20_000 {
            let x = f64::from_bits(rng.random::<u64>());
            if !x.is_finite() {
                continue;
            }
            let parsed: f64 = format_f64(x).parse().expect("formatted numbers parse");
            assert_eq!(parsed.to_bits(), x.to_bits(), "{x:e} did not round-trip");
            checked += 1;
        }
    }

    #[test]
    fn negative_zero_keeps_its_sign() {
        let parsed: f64 = format_f64(-0.0).parse().expect("parses");
        assert_eq!(parsed.to_bits(), (-0.0f64).to_bits());
    }
}
