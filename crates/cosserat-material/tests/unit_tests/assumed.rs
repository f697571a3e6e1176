//! The assumed-strain element kernel against an element energy composed directly (dual-number oracle,
//! with the tying maps applied to the strain tensors of the tying points) and against central
//! differences of its own gradient. The maps are random: the chain rule must hold for any linear map.

use super::common;
use super::coupled_element::{CoupledElement, check};
use cosserat_fem::quadrature::QuadratureRule;
use cosserat_geometry::Real;
use cosserat_material::assumed::{
    ElementTying, N_TIED, N_TYING, N_VALUES, TiedValues, TiedWeight, TyingMap, TyingTwins,
};
use cosserat_material::coupled::Coupling;
use nalgebra::SMatrix;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// Quadrature points; the tying points follow them.
const N_QUADRATURE: usize = 3;

/// The element energy with each quadrature point's strains replaced by its map of the tied values (of
/// the tying points' strains) and its own strains.
fn oracle<T: Real, const NU: usize, const NR: usize>(
    el: &CoupledElement<NU, NR>,
    values: &TiedValues,
    maps: &[TyingMap],
    u: &[T],
) -> T {
    let (strains, geoms) = el.oracle_strains(u);
    // The tied strains: entries 0–5 (column-major) of each tying point's Ê.
    let z: Vec<T> = (0..N_TIED)
        .map(|i| {
            let (e, _) = &strains[N_QUADRATURE + i / 6];
            let k = i % 6;
            e[(k % 3, k / 3)]
        })
        .collect();
    let mut y = [T::zero(); N_VALUES];
    for w in values.weights() {
        y[usize::from(w.value)] += z[usize::from(w.strain)] * T::from(w.weight);
    }
    let mut energy = T::zero();
    for (p, m) in maps.iter().enumerate() {
        let (own, g) = strains[p];
        let mut e = own;
        for k in 0..6 {
            let mut v = T::zero();
            for (j, yj) in y.iter().enumerate() {
                v += *yj * T::from(m.values[(k, j)]);
            }
            for j in 0..6 {
                v += own[(j % 3, j / 3)] * T::from(m.own[(k, j)]);
            }
            e[(k % 3, k / 3)] = v;
        }
        energy += el.oracle_density(&e, &g, &geoms[p]) * T::from(el.shapes[p].weight);
    }
    energy
}

/// The tying point that no random value reads: it must not be needed.
const UNREAD: usize = 6;

/// Gives the tying points of `el` no weight of their own and draws random tied values (three tied
/// strains each, of any tying point but [`UNREAD`]) and tying maps: the chain rule must hold for any
/// linear maps.
fn weightless_tying_points_and_random_maps<const NU: usize, const NR: usize>(
    el: &mut CoupledElement<NU, NR>,
    rng: &mut ChaCha8Rng,
) -> (TiedValues, Vec<TyingMap>) {
    for s in &mut el.shapes[N_QUADRATURE..] {
        s.weight = 0.0;
    }
    let mut weights = Vec::new();
    for value in 0..N_VALUES {
        for _ in 0..3 {
            let strain = loop {
                let strain = rng.random_range(0..N_TIED);
                if strain / 6 != UNREAD {
                    break strain;
                }
            };
            weights.push(TiedWeight {
                value: value as u8,
                strain: strain as u8,
                weight: rng.random_range(-1.0..1.0),
            });
        }
    }
    let maps = (0..N_QUADRATURE)
        .map(|_| TyingMap {
            values: SMatrix::from_fn(|_, _| rng.random_range(-0.3..0.3)),
            own: SMatrix::from_fn(|_, _| rng.random_range(-0.5..0.5)),
        })
        .collect();
    (TiedValues::from_weights(weights), maps)
}

fn check_assumed<const NU: usize, const NR: usize, const NL: usize, const NE: usize>(seed: u64, curved: bool) {
    let mut rng = common::rng(seed);
    let mut el = CoupledElement::<NU, NR>::random(&mut rng, N_QUADRATURE + N_TYING, curved);
    let (values, maps) = weightless_tying_points_and_random_maps(&mut el, &mut rng);
    // Linear rotations: no drilling hourglass term.
    let tying = ElementTying::new(&values, &maps, TyingTwins::NONE, false, std::iter::empty());
    check::<NU, NR, NL, NE>(&el, Coupling::Tying(tying), |u| oracle(&el, &values, &maps, u), seed);
}

/// Tying points on quadrature points (the twins of the paper's Tri6/Tri3 rule) are read at their
/// quadrature points instead of being evaluated: with the same position and rotation there, the kernel
/// must still match the oracle, which evaluates every tying point.
fn check_twins<const NU: usize, const NR: usize, const NL: usize, const NE: usize>(seed: u64, curved: bool) {
    let mut rng = common::rng(seed);
    let mut el = CoupledElement::<NU, NR>::random(&mut rng, N_QUADRATURE + N_TYING, curved);
    let rule = QuadratureRule::interior_p2();
    let twins = TyingTwins::of_rule(rule.points());
    let mut n_twins = 0;
    for t in 0..N_TYING {
        let source = twins.source(t, N_QUADRATURE);
        if source != N_QUADRATURE + t {
            n_twins += 1;
            el.shapes[N_QUADRATURE + t] = el.shapes[source];
            el.b_world[N_QUADRATURE + t] = el.b_world[source];
            el.offsets[N_QUADRATURE + t] = el.offsets[source];
            el.q_points[N_QUADRATURE + t] = el.q_points[source];
        }
    }
    assert_eq!(
        n_twins, 3,
        "the interior tying points are the interior degree-2 rule's points"
    );
    let (values, maps) = weightless_tying_points_and_random_maps(&mut el, &mut rng);
    // Linear rotations: no drilling hourglass term.
    let tying = ElementTying::new(&values, &maps, twins, false, std::iter::empty());
    check::<NU, NR, NL, NE>(&el, Coupling::Tying(tying), |u| oracle(&el, &values, &maps, u), seed);
}

#[test]
fn twin_tying_points_are_read_at_their_quadrature_points() {
    common::with_big_stack(|| {
        check_twins::<6, 3, 15, 27>(61, false);
        check_twins::<6, 3, 15, 27>(62, true);
    });
}

#[test]
fn assumed_element_matches_the_dual_oracle_and_central_differences() {
    common::with_big_stack(|| {
        check_assumed::<6, 3, 15, 27>(51, false);
        check_assumed::<6, 3, 15, 27>(52, true);
        check_assumed::<3, 3, 15, 18>(53, true);
    });
}
