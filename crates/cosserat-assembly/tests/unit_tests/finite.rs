//! The vectorised finiteness checks.

use cosserat_assembly::finite::{all_finite, first_non_finite};

#[test]
fn every_kind_of_non_finite_value_is_found_at_every_position() {
    for n in [1_usize, 7, 64, 729] {
        let clean: Vec<f64> = (0..n).map(|i| (i as f64 - 3.5) * 1e300).collect();
        assert!(all_finite(&clean));
        assert_eq!(first_non_finite(&clean), None);
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            for at in [0, n / 2, n - 1] {
                let mut v = clean.clone();
                v[at] = bad;
                assert!(!all_finite(&v), "{bad} at {at} of {n}");
                assert_eq!(first_non_finite(&v), Some(at), "{bad} at {at} of {n}");
                // With a second one after it, the first is reported.
                v[n - 1] = f64::NAN;
                assert_eq!(first_non_finite(&v), Some(at), "{bad} at {at} of {n}");
            }
        }
    }
    assert!(all_finite(&[]));
    assert!(all_finite(&[f64::MAX, f64::MIN, f64::MIN_POSITIVE, -0.0]));
}
