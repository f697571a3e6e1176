//! Scatter with absent slots: present blocks land in the global upper triangle, absent ones nowhere; a
//! block named in two slots receives both orders of their coupling.

use super::common::rng;
use cosserat_assembly::SparsityPattern;
use cosserat_assembly::scatter::GroupScatter;
use nalgebra::{DMatrix, SMatrix, SVector};
use rand::Rng;

#[test]
fn absent_slots_are_skipped_and_present_blocks_are_scattered_symmetrically() {
    let mut r = rng(51);
    // Two groups over 4 blocks; the first has slot 1 absent and its blocks in descending order.
    let groups = vec![[Some(3), None, Some(1)], [Some(0), Some(1), Some(2)]];
    let present: Vec<Vec<usize>> = groups.iter().map(|g| g.iter().flatten().copied().collect()).collect();
    let pattern = SparsityPattern::from_groups(4, present.iter().map(|g| g.as_slice()));
    let scatter = GroupScatter::<3>::new(&pattern, groups.clone());
    assert_eq!(scatter.len(), 2);
    assert!(!scatter.is_empty());
    let mut grad = vec![0.0; 12];
    let mut values = vec![0.0; pattern.nnz()];
    let mut expected_g = SVector::<f64, 12>::zeros();
    let mut expected_h = DMatrix::<f64>::zeros(12, 12);
    for (e, group) in groups.iter().enumerate() {
        let a = SMatrix::<f64, 9, 9>::from_fn(|_, _| r.random_range(-1.0..1.0));
        let h = a + a.transpose();
        let g = SVector::<f64, 9>::from_fn(|_, _| r.random_range(-1.0..1.0));
        scatter.add_gradient(e, &g, &mut grad);
        scatter.add_hessian(e, &h, &pattern, &mut values);
        for (i, bi) in group.iter().enumerate() {
            let Some(bi) = bi else { continue };
            for c in 0..3 {
                expected_g[3 * bi + c] += g[3 * i + c];
            }
            for (j, bj) in group.iter().enumerate() {
                let Some(bj) = bj else { continue };
                for c in 0..3 {
                    for d in 0..3 {
                        expected_h[(3 * bi + c, 3 * bj + d)] += h[(3 * i + c, 3 * j + d)];
                    }
                }
            }
        }
    }
    assert_eq!(grad.as_slice(), expected_g.as_slice());
    for i in 0..12 {
        for j in i..12 {
            let got = pattern.entry(i, j).map_or(0.0, |k| values[k]);
            assert!(
                (got - expected_h[(i, j)]).abs() < 1e-14,
                "({i}, {j}): {got} vs {}",
                expected_h[(i, j)]
            );
        }
    }
}

#[test]
fn a_block_in_two_slots_gets_both_orders_of_their_coupling() {
    // Where a vertex has valence 3, the faces across two edges share their third vertex: a stencil then
    // names it twice. The scattered Hessian must be that of the energy of the distinct blocks.
    let mut r = rng(52);
    let groups = vec![[Some(2), Some(0), Some(2)], [Some(1), Some(1), None]];
    let present: Vec<Vec<usize>> = groups.iter().map(|g| g.iter().flatten().copied().collect()).collect();
    let pattern = SparsityPattern::from_groups(3, present.iter().map(|g| g.as_slice()));
    let scatter = GroupScatter::<3>::new(&pattern, groups.clone());
    let mut grad = vec![0.0; 9];
    let mut values = vec![0.0; pattern.nnz()];
    let mut expected_g = SVector::<f64, 9>::zeros();
    let mut expected_h = DMatrix::<f64>::zeros(9, 9);
    for (e, group) in groups.iter().enumerate() {
        let a = SMatrix::<f64, 9, 9>::from_fn(|_, _| r.random_range(-1.0..1.0));
        let h = a + a.transpose();
        let g = SVector::<f64, 9>::from_fn(|_, _| r.random_range(-1.0..1.0));
        scatter.add_gradient(e, &g, &mut grad);
        scatter.add_hessian(e, &h, &pattern, &mut values);
        // The chain rule for x_slot = x_block: sum over all slot pairs.
        for (i, bi) in group.iter().enumerate() {
            let Some(bi) = bi else { continue };
            for c in 0..3 {
                expected_g[3 * bi + c] += g[3 * i + c];
            }
            for (j, bj) in group.iter().enumerate() {
                let Some(bj) = bj else { continue };
                for c in 0..3 {
                    for d in 0..3 {
                        expected_h[(3 * bi + c, 3 * bj + d)] += h[(3 * i + c, 3 * j + d)];
                    }
                }
            }
        }
    }
    assert_eq!(grad.as_slice(), expected_g.as_slice());
    for i in 0..9 {
        for j in i..9 {
            let got = pattern.entry(i, j).map_or(0.0, |k| values[k]);
            assert!(
                (got - expected_h[(i, j)]).abs() < 1e-14,
                "({i}, {j}): {got} vs {}",
                expected_h[(i, j)]
            );
        }
    }
}
