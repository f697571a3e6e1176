//! Reference solutions of the validation problems: the published tables of Sze, Liu and Lo (2004) and
//! closed forms (the inextensible elastica by elliptic integrals, the roll-up arc, Euler–Bernoulli and
//! thin-ring formulas).
//!
//! Tables are transcribed from `docs/references.md`, which names the publication and the public
//! transcription of every table. The closed forms are evaluated here; the tests check the elastica
//! against the independently computed table of that file (direct integration at 25 digits).

use std::f64::consts::PI;

/// Sze 3.1, cantilever under end shear (L = 10, EI = 100, P_max = 4): `(P/P_max, −U_tip, W_tip)`.
pub const SZE_END_SHEAR: [(f64, f64, f64); 20] = [
    (0.05, 0.026, 0.663),
    (0.10, 0.103, 1.309),
    (0.15, 0.224, 1.922),
    (0.20, 0.381, 2.493),
    (0.25, 0.563, 3.015),
    (0.30, 0.763, 3.488),
    (0.35, 0.971, 3.912),
    (0.40, 1.184, 4.292),
    (0.45, 1.396, 4.631),
    (0.50, 1.604, 4.933),
    (0.55, 1.807, 5.202),
    (0.60, 2.002, 5.444),
    (0.65, 2.190, 5.660),
    (0.70, 2.370, 5.855),
    (0.75, 2.541, 6.031),
    (0.80, 2.705, 6.190),
    (0.85, 2.861, 6.335),
    (0.90, 3.010, 6.467),
    (0.95, 3.151, 6.588),
    (1.00, 3.286, 6.698),
];

/// Sze 3.2, cantilever under end moment (L = 12, EI = 100, M_max = 2π EI/L), Sze's 16×1 FE result:
/// `(M/M_max, −U_tip, W_tip)`. The exact values are [`rollup_tip`].
pub const SZE_END_MOMENT_FE: [(f64, f64, f64); 20] = [
    (0.05, 0.196, 1.870),
    (0.10, 0.773, 3.648),
    (0.15, 1.698, 5.249),
    (0.20, 2.916, 6.600),
    (0.25, 4.357, 7.643),
    (0.30, 5.942, 8.338),
    (0.35, 7.582, 8.671),
    (0.40, 9.191, 8.646),
    (0.45, 10.687, 8.291),
    (0.50, 12.000, 7.652),
    (0.55, 13.075, 6.788),
    (0.60, 13.875, 5.772),
    (0.65, 14.384, 4.678),
    (0.70, 14.603, 3.583),
    (0.75, 14.556, 2.556),
    (0.80, 14.280, 1.656),
    (0.85, 13.826, 0.931),
    (0.90, 13.254, 0.407),
    (0.95, 12.625, 0.099),
    (1.00, 12.000, 0.000),
];

/// Sze 3.3, slit annular plate lifted by a line force (radii 6 and 10, h = 0.03, E = 21e6, ν = 0,
/// q_max = 0.8 per unit length), Sze's 10 × 80 FE result: `(P/P_max, W_A, W_B)`, the vertical
/// displacements of the loaded side at the inner (A) and the outer (B) edge.
pub const SZE_SLIT_ANNULAR: [(f64, f64, f64); 23] = [
    (0.025, 1.305, 1.789),
    (0.05, 2.455, 3.370),
    (0.075, 3.435, 4.720),
    (0.1, 4.277, 5.876),
    (0.125, 5.007, 6.872),
    (0.15, 5.649, 7.736),
    (0.2, 6.725, 9.160),
    (0.25, 7.602, 10.288),
    (0.3, 8.340, 11.213),
    (0.35, 8.974, 11.992),
    (0.4, 9.529, 12.661),
    (0.45, 10.023, 13.247),
    (0.5, 10.468, 13.768),
    (0.55, 10.876, 14.240),
    (0.6, 11.257, 14.674),
    (0.65, 11.620, 15.081),
    (0.7, 11.970, 15.469),
    (0.75, 12.310, 15.842),
    (0.8, 12.642, 16.202),
    (0.85, 12.966, 16.550),
    (0.9, 13.282, 16.886),
    (0.95, 13.590, 17.212),
    (1.0, 13.891, 17.528),
];

/// Sze 3.8, hinged cylindrical roof, isotropic, h = 12.7 (P_max = 3000): `(P/P_max, −W_C)` along the
/// path, which has two limit points of the load.
pub const SZE_HINGED_ROOF: [(f64, f64); 36] = [
    (0.0877, 0.693),
    (0.1980, 1.638),
    (0.3473, 3.087),
    (0.4686, 4.477),
    (0.5647, 5.802),
    (0.6381, 7.057),
    (0.6908, 8.237),
    (0.7246, 9.339),
    (0.7412, 10.358),
    (0.7421, 11.293),
    (0.7286, 12.141),
    (0.7023, 12.903),
    (0.6649, 13.583),
    (0.6182, 14.188),
    (0.5643, 14.728),
    (0.5055, 15.217),
    (0.4442, 15.676),
    (0.3830, 16.125),
    (0.3245, 16.590),
    (0.2717, 17.094),
    (0.2272, 17.657),
    (0.1940, 18.299),
    (0.1750, 19.028),
    (0.1729, 19.852),
    (0.1905, 20.771),
    (0.2303, 21.780),
    (0.2950, 22.875),
    (0.3871, 24.049),
    (0.4443, 24.663),
    (0.5093, 25.293),
    (0.5826, 25.940),
    (0.6644, 26.601),
    (0.7551, 27.276),
    (0.8549, 27.964),
    (0.9643, 28.663),
    (1.0835, 29.374),
];

/// Sze 3.8, hinged cylindrical roof, isotropic, h = 6.35, normalised by the thicker roof's P_max = 3000:
/// `(P/P_max, −W_C)` along the path, which snaps back (the deflection falls between 17.0 and 14.5).
pub const SZE_HINGED_ROOF_THIN: [(f64, f64); 36] = [
    (0.0517, 1.846),
    (0.1182, 5.271),
    (0.1583, 8.257),
    (0.1837, 10.799),
    (0.1914, 11.904),
    (0.1953, 12.892),
    (0.1950, 13.752),
    (0.1901, 14.472),
    (0.1806, 15.050),
    (0.1671, 15.501),
    (0.1323, 16.145),
    (0.0923, 16.602),
    (0.0504, 16.915),
    (0.0083, 17.008),
    (-0.0312, 16.697),
    (-0.0622, 15.780),
    (-0.0739, 15.206),
    (-0.0861, 14.767),
    (-0.1001, 14.520),
    (-0.1142, 14.451),
    (-0.1247, 14.862),
    (-0.1288, 15.778),
    (-0.1271, 16.961),
    (-0.1196, 18.320),
    (-0.1055, 19.817),
    (-0.0825, 21.420),
    (-0.0484, 23.100),
    (-0.0006, 24.824),
    (0.0626, 26.565),
    (0.1427, 28.302),
    (0.2403, 30.023),
    (0.3559, 31.720),
    (0.4898, 33.388),
    (0.6417, 35.024),
    (0.8114, 36.626),
    (1.0313, 38.450),
];

/// Tip of a cantilever of length `length` rolled up by an end moment `λ · 2π EI/L` (pure bending, an
/// arc of curvature `2πλ/L`): `(−U, W)`, the axial shortening and the transverse displacement.
pub fn rollup_tip(lambda: f64, length: f64) -> (f64, f64) {
    let a = 2.0 * PI * lambda;
    if a.abs() < 1e-8 {
        return (0.0, 0.0);
    }
    (length * (1.0 - a.sin() / a), length * (1.0 - a.cos()) / a)
}

/// Carlson's symmetric elliptic integral `R_F(x, y, z)` (duplication algorithm, DLMF 19.36.1).
fn carlson_rf(x: f64, y: f64, z: f64) -> f64 {
    let (mut x, mut y, mut z) = (x, y, z);
    for _ in 0..100 {
        let (sx, sy, sz) = (x.sqrt(), y.sqrt(), z.sqrt());
        let lam = sx * (sy + sz) + sy * sz;
        x = 0.25 * (x + lam);
        y = 0.25 * (y + lam);
        z = 0.25 * (z + lam);
        let ave = (x + y + z) / 3.0;
        let (dx, dy, dz) = ((ave - x) / ave, (ave - y) / ave, (ave - z) / ave);
        if dx.abs().max(dy.abs()).max(dz.abs()) < 1e-4 {
            let e2 = dx * dy - dz * dz;
            let e3 = dx * dy * dz;
            return (1.0 + (e2 / 24.0 - 0.1 - 3.0 / 44.0 * e3) * e2 + e3 / 14.0) / ave.sqrt();
        }
    }
    f64::NAN
}

/// Carlson's elliptic integral `R_D(x, y, z)` (duplication algorithm, DLMF 19.36.2).
fn carlson_rd(x: f64, y: f64, z: f64) -> f64 {
    let (c1, c2, c3, c4) = (3.0 / 14.0, 1.0 / 6.0, 9.0 / 22.0, 3.0 / 26.0);
    let (c5, c6) = (0.25 * c3, 1.5 * c4);
    let (mut x, mut y, mut z) = (x, y, z);
    let (mut sum, mut fac) = (0.0, 1.0);
    for _ in 0..100 {
        let (sx, sy, sz) = (x.sqrt(), y.sqrt(), z.sqrt());
        let lam = sx * (sy + sz) + sy * sz;
        sum += fac / (sz * (z + lam));
        fac *= 0.25;
        x = 0.25 * (x + lam);
        y = 0.25 * (y + lam);
        z = 0.25 * (z + lam);
        let ave = 0.2 * (x + y + 3.0 * z);
        let (dx, dy, dz) = ((ave - x) / ave, (ave - y) / ave, (ave - z) / ave);
        if dx.abs().max(dy.abs()).max(dz.abs()) < 1e-4 {
            let ea = dx * dy;
            let eb = dz * dz;
            let ec = ea - eb;
            let ed = ea - 6.0 * eb;
            let ee = ed + ec + ec;
            return 3.0 * sum
                + fac * (1.0 + ed * (-c1 + c5 * ed - c6 * dz * ee) + dz * (c2 * ee + dz * (-c3 * ec + dz * c4 * ea)))
                    / (ave * ave.sqrt());
        }
    }
    f64::NAN
}

/// Incomplete elliptic integrals of the first and second kind, `(F(φ | m), E(φ | m))`, parameter
/// `m = k²`, for `0 ≤ φ ≤ π/2`.
fn elliptic_fe(phi: f64, m: f64) -> (f64, f64) {
    let (s, c) = phi.sin_cos();
    let y = 1.0 - m * s * s;
    let rf = carlson_rf(c * c, y, 1.0);
    let rd = carlson_rd(c * c, y, 1.0);
    (s * rf, s * rf - m / 3.0 * s * s * s * rd)
}

/// The tip of the inextensible, unshearable elastica of a cantilever under a dead transverse end load
/// with `α = P L²/EI`: `(w/L, u/L, θ)`, the transverse deflection, the axial shortening and the tip
/// rotation \[rad\].
///
/// With `k² = (1 + sin θ)/2` and `φ₁ = asin(1/(√2 k))`, the tip rotation solves
/// `K(k) − F(φ₁, k) = √α`; then `u/L = 1 − √(2 sin θ/α)` and
/// `w/L = 1 − 2 (E(k) − E(φ₁, k))/√α` (Mattiasson 1981; the residual form of
/// docs/references.md). Returns zeros for `α ≤ 0`.
pub fn elastica_tip(alpha: f64) -> (f64, f64, f64) {
    if alpha <= 0.0 {
        return (0.0, 0.0, 0.0);
    }
    let residual = |theta: f64| {
        let m = 0.5 * (1.0 + theta.sin());
        let phi1 = (1.0 / (2.0 * m).sqrt()).min(1.0).asin();
        let (k_full, _) = elliptic_fe(0.5 * PI, m);
        let (f1, _) = elliptic_fe(phi1, m);
        k_full - f1 - alpha.sqrt()
    };
    // The residual grows monotonically from −√α at θ = 0 to +∞ as θ → π/2.
    let (mut lo, mut hi) = (0.0, 0.5 * PI - 1e-15);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if residual(mid) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let theta = 0.5 * (lo + hi);
    let m = 0.5 * (1.0 + theta.sin());
    let phi1 = (1.0 / (2.0 * m).sqrt()).min(1.0).asin();
    let (_, e_full) = elliptic_fe(0.5 * PI, m);
    let (_, e1) = elliptic_fe(phi1, m);
    let w = 1.0 - 2.0 * (e_full - e1) / alpha.sqrt();
    let u = 1.0 - (2.0 * theta.sin() / alpha).sqrt();
    (w, u, theta)
}

/// Tip deflection of a straight cantilever under a small transverse end force `force`: Euler–Bernoulli
/// bending `P L³/(3B)` plus the transverse-shear term `P L/S` (Timoshenko), with the bending stiffness
/// `B` \[N·m²\] and the shear stiffness `S` \[N\] of the cross-section.
pub fn cantilever_tip_deflection(force: f64, length: f64, bending_stiffness: f64, shear_stiffness: f64) -> f64 {
    force * length.powi(3) / (3.0 * bending_stiffness) + force * length / shear_stiffness
}

/// Thin ring of radius `radius` and bending stiffness `EI` under two opposite diametral forces `P`
/// (inextensible curved beam; Roark's ring case 1): `(δ_V, δ_H)`, the shortening of the loaded
/// diameter and the lengthening of the perpendicular one.
pub fn ring_diametral(force: f64, radius: f64, bending_stiffness: f64) -> (f64, f64) {
    let s = force * radius.powi(3) / bending_stiffness;
    ((PI / 4.0 - 2.0 / PI) * s, (2.0 / PI - 0.5) * s)
}

/// The closed-form path of a shallow sinusoidal arch under a sinusoidal load (docs/references.md):
/// the load `q(W)` at the crown deflection `W` for the rise `e = ê r`, in units of `EI k⁴ r`, with
/// `W` in units of the radius of gyration `r`.
pub fn shallow_arch_load(rise: f64, deflection: f64) -> f64 {
    let c = rise - deflection;
    (rise - c) + c * (rise * rise - c * c) / 4.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shallow_arch_path_has_its_limit_points_where_the_closed_form_puts_them() {
        // ê = 4: maximum 8 at W = 2, zero at W = 6, 8 again at W = 8; the slope vanishes at both
        // extremes (central differences).
        let q = |w: f64| shallow_arch_load(4.0, w);
        assert!((q(2.0) - 8.0).abs() < 1e-12 && q(6.0).abs() < 1e-12 && (q(8.0) - 8.0).abs() < 1e-12);
        for w in [2.0, 6.0] {
            assert!((q(w + 1e-5) - q(w - 1e-5)).abs() < 1e-8, "slope at {w}");
        }
        assert!(q(1.9) < 8.0 && q(2.1) < 8.0 && q(5.9) > 0.0 && q(6.1) > 0.0);
    }

    #[test]
    fn elliptic_integrals_match_known_values() {
        // K(m = 1/2) = 1.854074677301372 and E(m = 1/2) = 1.350643881047675 (DLMF Table 19.2.1 values;
        // also Γ(1/4)²/(4√π) for K).
        let (k, e) = elliptic_fe(0.5 * PI, 0.5);
        assert!((k - 1.854_074_677_301_372).abs() < 1e-14, "K = {k}");
        assert!((e - 1.350_643_881_047_675).abs() < 1e-14, "E = {e}");
        // m = 0: F(φ) = E(φ) = φ.
        let (f, e0) = elliptic_fe(0.7, 0.0);
        assert!((f - 0.7).abs() < 1e-15 && (e0 - 0.7).abs() < 1e-15);
    }

    #[test]
    fn elastica_reproduces_the_independently_computed_table() {
        // (α, w/L, u/L, θ) computed with mpmath by direct integration (the elastica table of docs/references.md), 5 digits.
        let table = [
            (0.2, 0.06636, 0.00265, 0.09964),
            (1.0, 0.30172, 0.05643, 0.46135),
            (2.0, 0.49346, 0.16064, 0.78175),
            (4.0, 0.66996, 0.32894, 1.12124),
            (7.0, 0.76737, 0.47293, 1.33496),
            (10.0, 0.81061, 0.55500, 1.43029),
        ];
        for (alpha, w, u, theta) in table {
            let (w_c, u_c, t_c) = elastica_tip(alpha);
            assert!((w_c - w).abs() < 6e-6, "α = {alpha}: w/L {w_c} vs {w}");
            assert!((u_c - u).abs() < 6e-6, "α = {alpha}: u/L {u_c} vs {u}");
            assert!((t_c - theta).abs() < 6e-6, "α = {alpha}: θ {t_c} vs {theta}");
        }
    }

    #[test]
    fn elastica_tends_to_the_linear_cantilever_for_small_loads() {
        let alpha = 1e-4;
        let (w, u, theta) = elastica_tip(alpha);
        assert!((w - alpha / 3.0).abs() < 1e-10, "w/L = {w}");
        assert!((theta - alpha / 2.0).abs() < 1e-10, "θ = {theta}");
        assert!(u.abs() < 1e-8, "u/L = {u}");
    }

    #[test]
    fn rollup_reproduces_the_exact_columns_of_sze_3_2() {
        // "exact" columns of Sze 3.2 in docs/references.md at λ = 0.25, 0.5, 0.75 (3 decimals).
        for (lambda, u, w) in [(0.25, 4.361, 7.639), (0.5, 12.0, 7.639), (0.75, 14.546, 2.546)] {
            let (u_c, w_c) = rollup_tip(lambda, 12.0);
            assert!(
                (u_c - u).abs() < 6e-4 && (w_c - w).abs() < 6e-4,
                "λ = {lambda}: {u_c}, {w_c}"
            );
        }
        let (u1, w1) = rollup_tip(1.0, 12.0);
        assert!((u1 - 12.0).abs() < 1e-12 && w1.abs() < 1e-12);
    }

    #[test]
    fn sze_end_shear_table_ends_near_the_elastica() {
        // The published 16×1 FE values agree with the inextensible elastica at α = 4 to 1e-3 of L.
        let (w, u, _) = elastica_tip(4.0);
        let (_, su, sw) = SZE_END_SHEAR[19];
        assert!((10.0 * w - sw).abs() < 1e-2 && (10.0 * u - su).abs() < 1e-2);
    }
}
