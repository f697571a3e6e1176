//! Unit tests mirroring `src/`.

mod element;
mod mesh;
mod quadrature;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A seeded generator, so every run sees the same points.
pub fn rng(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

/// A uniformly distributed point of the reference triangle.
pub fn random_reference_point(rng: &mut impl Rng) -> [f64; 2] {
    let (mut a, mut b): (f64, f64) = (rng.random(), rng.random());
    if a + b > 1.0 {
        (a, b) = (1.0 - a, 1.0 - b);
    }
    [a, b]
}
