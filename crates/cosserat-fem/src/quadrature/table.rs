//! Points and weights of the symmetric triangle rules, on the reference triangle of area 1/2.
//!
//! The digits were computed by `scripts/derive_quadrature.py`, which solves the symmetric moment
//! equations of each orbit structure to 40 digits with Newton's method, starting from the published
//! values (Strang & Fix 1973; Dunavant 1985, IJNME 21, 1129–1148), and are stored as the nearest
//! `f64`. They agree with the 15 published digits of those tables. Points are `(ξ₁, ξ₂)`; weights
//! already include the area factor ½.

pub(crate) const CENTROID_POINTS: [[f64; 2]; 1] = [[1.0 / 3.0, 1.0 / 3.0]];
pub(crate) const CENTROID_WEIGHTS: [f64; 1] = [0.5];

pub(crate) const INTERIOR_P2_POINTS: [[f64; 2]; 3] =
    [[1.0 / 6.0, 1.0 / 6.0], [1.0 / 6.0, 2.0 / 3.0], [2.0 / 3.0, 1.0 / 6.0]];
pub(crate) const INTERIOR_P2_WEIGHTS: [f64; 3] = [1.0 / 6.0; 3];

const P3_A: f64 = 0.10903900907287721;
const P3_B: f64 = 0.23193336855303057;
const P3_C: f64 = 0.6590276223740922;
pub(crate) const STRANG_FIX_P3_POINTS: [[f64; 2]; 6] = [
    [P3_A, P3_B],
    [P3_A, P3_C],
    [P3_B, P3_A],
    [P3_B, P3_C],
    [P3_C, P3_A],
    [P3_C, P3_B],
];
pub(crate) const STRANG_FIX_P3_WEIGHTS: [f64; 6] = [1.0 / 12.0; 6];

const P4_A1: f64 = 0.4459484909159649;
const P4_B1: f64 = 0.10810301816807023;
const P4_W1: f64 = 0.11169079483900574;
const P4_A2: f64 = 0.09157621350977074;
const P4_B2: f64 = 0.8168475729804585;
const P4_W2: f64 = 0.054975871827660935;
pub(crate) const DUNAVANT_P4_POINTS: [[f64; 2]; 6] = [
    [P4_A1, P4_B1],
    [P4_B1, P4_A1],
    [P4_A1, P4_A1],
    [P4_A2, P4_B2],
    [P4_B2, P4_A2],
    [P4_A2, P4_A2],
];
pub(crate) const DUNAVANT_P4_WEIGHTS: [f64; 6] = [P4_W1, P4_W1, P4_W1, P4_W2, P4_W2, P4_W2];

const P5_A1: f64 = 0.4701420641051151;
const P5_B1: f64 = 0.05971587178976982;
const P5_W1: f64 = 0.0661970763942531;
const P5_A2: f64 = 0.10128650732345634;
const P5_B2: f64 = 0.7974269853530873;
const P5_W2: f64 = 0.06296959027241357;
pub(crate) const DUNAVANT_P5_POINTS: [[f64; 2]; 7] = [
    [1.0 / 3.0, 1.0 / 3.0],
    [P5_A1, P5_B1],
    [P5_B1, P5_A1],
    [P5_A1, P5_A1],
    [P5_A2, P5_B2],
    [P5_B2, P5_A2],
    [P5_A2, P5_A2],
];
pub(crate) const DUNAVANT_P5_WEIGHTS: [f64; 7] = [0.1125, P5_W1, P5_W1, P5_W1, P5_W2, P5_W2, P5_W2];

const P6_A1: f64 = 0.24928674517091043;
const P6_B1: f64 = 0.5014265096581791;
const P6_W1: f64 = 0.058393137863189684;
const P6_A2: f64 = 0.06308901449150223;
const P6_B2: f64 = 0.8738219710169955;
const P6_W2: f64 = 0.02542245318510341;
const P6_A3: f64 = 0.053145049844816945;
const P6_B3: f64 = 0.3103524510337844;
const P6_C3: f64 = 0.6365024991213987;
const P6_W3: f64 = 0.041425537809186785;
pub(crate) const DUNAVANT_P6_POINTS: [[f64; 2]; 12] = [
    [P6_A1, P6_B1],
    [P6_B1, P6_A1],
    [P6_A1, P6_A1],
    [P6_A2, P6_B2],
    [P6_B2, P6_A2],
    [P6_A2, P6_A2],
    [P6_A3, P6_B3],
    [P6_A3, P6_C3],
    [P6_B3, P6_A3],
    [P6_B3, P6_C3],
    [P6_C3, P6_A3],
    [P6_C3, P6_B3],
];
pub(crate) const DUNAVANT_P6_WEIGHTS: [f64; 12] = [
    P6_W1, P6_W1, P6_W1, P6_W2, P6_W2, P6_W2, P6_W3, P6_W3, P6_W3, P6_W3, P6_W3, P6_W3,
];

const P8_W0: f64 = 0.07215780383889359;
const P8_A1: f64 = 0.4592925882927232;
const P8_B1: f64 = 0.0814148234145537;
const P8_W1: f64 = 0.04754581713364231;
const P8_A2: f64 = 0.1705693077517602;
const P8_B2: f64 = 0.6588613844964796;
const P8_W2: f64 = 0.05160868526735912;
const P8_A3: f64 = 0.05054722831703098;
const P8_B3: f64 = 0.8989055433659381;
const P8_W3: f64 = 0.01622924881159904;
const P8_A4: f64 = 0.008394777409957605;
const P8_B4: f64 = 0.2631128296346381;
const P8_C4: f64 = 0.7284923929554042;
const P8_W4: f64 = 0.013615157087217496;
pub(crate) const DUNAVANT_P8_POINTS: [[f64; 2]; 16] = [
    [1.0 / 3.0, 1.0 / 3.0],
    [P8_A1, P8_B1],
    [P8_B1, P8_A1],
    [P8_A1, P8_A1],
    [P8_A2, P8_B2],
    [P8_B2, P8_A2],
    [P8_A2, P8_A2],
    [P8_A3, P8_B3],
    [P8_B3, P8_A3],
    [P8_A3, P8_A3],
    [P8_A4, P8_B4],
    [P8_A4, P8_C4],
    [P8_B4, P8_A4],
    [P8_B4, P8_C4],
    [P8_C4, P8_A4],
    [P8_C4, P8_B4],
];
pub(crate) const DUNAVANT_P8_WEIGHTS: [f64; 16] = [
    P8_W0, P8_W1, P8_W1, P8_W1, P8_W2, P8_W2, P8_W2, P8_W3, P8_W3, P8_W3, P8_W4, P8_W4, P8_W4, P8_W4, P8_W4, P8_W4,
];
