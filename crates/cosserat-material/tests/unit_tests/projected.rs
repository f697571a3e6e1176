//! The stabilised strain projection's element kernel against an element energy composed directly
//! (dual-number oracle, with the projection written on the strain tensors) and against central
//! differences of its own gradient.

use super::common;
use super::coupled_element::{CoupledElement, check};
use cosserat_geometry::Real;
use cosserat_geometry::rotation::RotationJet;
use cosserat_material::coupled::Coupling;
use cosserat_material::element::{f_hat, point_omega};
use cosserat_material::kernel::point_value;
use cosserat_material::{AxlVariant, StrainProjection};
use nalgebra::{Matrix3, Vector3};

/// The element energy with the projection applied to the points' strain tensors.
fn oracle<T: Real, const NU: usize, const NR: usize>(
    el: &CoupledElement<NU, NR>,
    projection: &StrainProjection,
    u: &[T],
) -> T {
    let (strains, geoms) = el.oracle_strains(u);
    let total: f64 = el.shapes.iter().map(|s| s.weight).sum();
    let mut mean = Matrix3::<T>::zeros();
    for ((e, _), s) in strains.iter().zip(&el.shapes) {
        mean += e * T::from(s.weight / total);
    }
    // The tangential block P E P splits into its symmetric (membrane) and skew (drilling) parts; the
    // normal row of the first two columns is the transverse shear; the rest is kept.
    let tangential = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, 0.0)).cast::<T>();
    let normal_row = Matrix3::from_fn(|r, c| if r == 2 && c < 2 { 1.0 } else { 0.0 });
    let removed = |m: &Matrix3<T>| {
        let t = tangential * m * tangential;
        let sym = (t + t.transpose()) * T::from(0.5);
        let skw = (t - t.transpose()) * T::from(0.5);
        let shear = m.component_mul(&normal_row.cast::<T>());
        sym * T::from(1.0 - projection.membrane)
            + skw * T::from(1.0 - projection.drilling)
            + shear * T::from(1.0 - projection.shear)
    };
    let mut energy = T::zero();
    for (((e, g), geom), s) in strains.iter().zip(&geoms).zip(&el.shapes) {
        let projected = e - removed(&(e - mean));
        energy += el.oracle_density(&projected, g, geom) * T::from(s.weight);
    }
    energy
}

/// An element of three points; with `shared_density`, one frame and curvature for all of them.
fn element<const NU: usize, const NR: usize>(seed: u64, curved: bool, shared_density: bool) -> CoupledElement<NU, NR> {
    let el = CoupledElement::random(&mut common::rng(seed), 3, curved);
    if shared_density { el.with_shared_density() } else { el }
}

fn check_projection<const NU: usize, const NR: usize, const NL: usize, const NE: usize>(
    seed: u64,
    curved: bool,
    shared_density: bool,
    projection: StrainProjection,
) {
    let el = element::<NU, NR>(seed, curved, shared_density);
    check::<NU, NR, NL, NE>(
        &el,
        Coupling::Projection(&projection),
        |u| oracle(&el, &projection, u),
        seed,
    );
}

#[test]
fn projected_element_matches_the_dual_oracle_and_central_differences() {
    // Equal membrane and drilling factors make `P` diagonal (the default constants: the point's strain
    // Jacobian is scaled); unequal ones couple the tangential pair (formed densities).
    let diagonal = StrainProjection {
        membrane: 0.3,
        drilling: 0.3,
        shear: 0.1,
    };
    let coupled = StrainProjection {
        drilling: 0.6,
        ..diagonal
    };
    common::with_big_stack(move || {
        // Flat (one shared density without coupling of `Ê` to `Γ`), curved with a density per point,
        // and curved with one shared density.
        for projection in [diagonal, coupled] {
            check_projection::<6, 3, 15, 27>(41, false, false, projection);
            check_projection::<6, 3, 15, 27>(42, true, false, projection);
            check_projection::<6, 3, 15, 27>(45, true, true, projection);
            check_projection::<3, 3, 15, 18>(43, true, false, projection);
        }
    });
}

/// With every factor 1 the projection is the identity: the paper's element.
#[test]
fn unit_factors_give_the_paper_energy() {
    let el = element::<6, 3>(44, true, false);
    let identity = StrainProjection {
        membrane: 1.0,
        drilling: 1.0,
        shear: 1.0,
    };
    let u = vec![0.1; 27];
    let (x, omega) = el.split(&u);
    let d = el.densities();
    let node_r: Vec<Matrix3<f64>> = (0..3)
        .map(|k| RotationJet::of_update(&el.q_nodes[k], &omega[k], el.dt).r)
        .collect();
    let paper: f64 = (0..el.shapes.len())
        .map(|p| {
            let shape = &el.shapes[p];
            let r = RotationJet::of_update(&el.q_points[p], &point_omega(shape, &omega), el.dt).r;
            shape.weight
                * point_value(
                    shape,
                    &f_hat(shape, &x),
                    &r,
                    std::array::from_fn(|k| &node_r[k]),
                    &el.offsets[p],
                    &d[p],
                    AxlVariant::SkewPart,
                )
        })
        .sum();
    assert!((el.fast_value(Coupling::Projection(&identity), &u) - paper).abs() <= 1e-14 * paper.abs());
}
