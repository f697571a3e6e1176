//! The built-in colour map for scalar fields.
//!
//! A piecewise-linear version of matplotlib's *viridis* through its ten standard samples at
//! `t = 0, 1/9, ..., 1`. Viridis is perceptually uniform, readable in grey scale and by colour-blind
//! readers, and its darkest colour stays distinguishable from the light background of the renderer.

/// The ten samples of viridis, `t = k / 9`, as sRGB bytes.
const VIRIDIS: [[u8; 3]; 10] = [
    [0x44, 0x01, 0x54],
    [0x48, 0x28, 0x78],
    [0x3e, 0x4a, 0x89],
    [0x31, 0x68, 0x8e],
    [0x26, 0x82, 0x8e],
    [0x1f, 0x9e, 0x89],
    [0x35, 0xb7, 0x79],
    [0x6d, 0xcd, 0x59],
    [0xb4, 0xde, 0x2c],
    [0xfd, 0xe7, 0x25],
];

/// The colour of `t` in `[0, 1]` as channel values in `[0, 255]` (not rounded). `t` outside the
/// interval is clamped; NaN maps to the middle of the map.
pub(crate) fn viridis_channels(t: f64) -> [f64; 3] {
    let t = if t.is_nan() { 0.5 } else { t.clamp(0.0, 1.0) };
    let x = t * (VIRIDIS.len() - 1) as f64;
    // `x` lies in [0, 9], so the truncation picks a valid segment; the last sample closes the interval.
    let k = (x.floor() as usize).min(VIRIDIS.len() - 2);
    let s = x - k as f64;
    let (lo, hi) = (VIRIDIS[k], VIRIDIS[k + 1]);
    std::array::from_fn(|c| f64::from(lo[c]) * (1.0 - s) + f64::from(hi[c]) * s)
}

/// The colour of `t` in `[0, 1]` on the built-in map (viridis), as sRGB bytes. `t` outside the interval
/// is clamped; NaN maps to the middle of the map.
pub fn viridis(t: f64) -> [u8; 3] {
    viridis_channels(t).map(|c| c.round() as u8)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_are_hit_exactly() {
        for (k, sample) in VIRIDIS.iter().enumerate() {
            assert_eq!(viridis(k as f64 / 9.0), *sample, "sample {k}");
        }
    }

    #[test]
    fn out_of_range_values_are_clamped() {
        assert_eq!(viridis(-3.0), VIRIDIS[0]);
        assert_eq!(viridis(7.0), VIRIDIS[9]);
        assert_eq!(viridis(f64::NAN), viridis(0.5));
    }

    #[test]
    fn midpoints_interpolate_linearly() {
        let mid = viridis_channels(0.5 / 9.0);
        for c in 0..3 {
            let expected = 0.5 * (f64::from(VIRIDIS[0][c]) + f64::from(VIRIDIS[1][c]));
            assert!((mid[c] - expected).abs() < 1e-12);
        }
    }
}
