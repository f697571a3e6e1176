//! The memory check: sizes, the estimate and the element budget.

use cosserat::memory::{BYTES_PER_UNKNOWN, MemoryEstimate, MemoryLimit, format_bytes, parse_size};
use cosserat::scene::spec::SceneSpec;
use std::path::Path;

#[test]
fn sizes_parse_in_binary_units() {
    assert_eq!(parse_size("3G"), Ok(3 << 30));
    assert_eq!(parse_size("512M"), Ok(512 << 20));
    assert_eq!(parse_size("1.5GiB"), Ok(3 << 29));
    assert_eq!(parse_size("2000000000"), Ok(2_000_000_000));
    assert_eq!(parse_size(" 64 kb "), Ok(64 << 10));
    for bad in ["", "G", "-1G", "3X", "0", "1e400"] {
        assert!(parse_size(bad).is_err(), "{bad:?} was accepted");
    }
    assert_eq!(format_bytes(512), "512 B");
    assert_eq!(format_bytes(3 << 29), "1.5 GiB");
}

/// A square of `nx` × `nx` quads; `elements` holds the mesh section's element keys.
fn strip(nx: usize, elements: &str) -> SceneSpec {
    let text = format!(
        "name = \"s\"\n[time]\ndt = 0.01\nend = 0.1\n[mesh]\ngenerator = \"rectangle\"\nlx = 1.0\nly = 1.0\nnx = {nx}\n\
         ny = {nx}\n{elements}\n[material]\nmodel = \"plate\"\nthickness = 1e-3\nyoungs_modulus = 1e6\n\
         poisson_ratio = 0.3\ndensity = 1000.0\nlength_scale = 1e-4\n"
    );
    SceneSpec::from_str(&text, "s.toml", Path::new("."), &[]).unwrap()
}

#[test]
fn the_estimate_counts_three_unknowns_per_node_of_each_field() {
    // 10 × 10 quads: 121 vertices, 441 Tri6 nodes; quadratic displacements come with quadratic
    // rotations unless the scene names linear ones.
    let tri6 = MemoryEstimate::of_scene(&strip(10, "element = \"tri6\""));
    assert_eq!(tri6.unknowns, 3 * (441 + 441));
    let paper = MemoryEstimate::of_scene(&strip(10, "element = \"tri6\"\nrotation_element = \"tri3\""));
    assert_eq!(paper.unknowns, 3 * (441 + 121));
    let tri3 = MemoryEstimate::of_scene(&strip(10, "element = \"tri3\""));
    assert_eq!(tri3.unknowns, 3 * (121 + 121));
    assert!(tri6.bytes > tri6.unknowns * BYTES_PER_UNKNOWN);
}

#[test]
fn a_limit_below_the_estimate_is_refused_and_names_its_source() {
    let estimate = MemoryEstimate::of_scene(&strip(10, "element = \"tri6\""));
    let limit = |bytes: u64| MemoryLimit {
        bytes,
        source: "--max-memory".into(),
    };
    estimate.check(&limit(estimate.bytes)).unwrap();
    let err = estimate.check(&limit(estimate.bytes - 1)).unwrap_err().to_string();
    assert!(
        err.starts_with("the scene has 2646 unknowns and needs at least") && err.contains("allowed by --max-memory"),
        "{err}"
    );
    // The element budget lets through only meshes whose own unknowns could fit.
    let budget = limit(estimate.bytes).element_budget();
    assert!(budget.max >= 200 && budget.max < 2 * 2646, "{budget:?}");
    assert!(budget.source.contains("--max-memory"), "{budget:?}");
}

#[test]
fn the_machine_limit_is_at_most_what_is_asked_for() {
    let limit = MemoryLimit::of_machine(Some(1 << 20)).unwrap();
    assert_eq!(limit.bytes, 1 << 20);
    assert_eq!(limit.source, "--max-memory");
    if let Some(machine) = MemoryLimit::of_machine(None) {
        assert!(machine.bytes > 0);
    }
}
