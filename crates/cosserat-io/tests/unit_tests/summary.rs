//! `summary.json`: serde round trip, every contract key present, non-finite numbers refused.

use cosserat_io::{
    BoundingBox, ContactRecord, ConvergenceRecord, EnergyHistory, FactorRecord, LinearSolverRecord, ModelRecord,
    OutputError, RunStatus, RunSummary, ToleranceMode, read_summary, write_summary,
};

use super::{entries, test_dir};

fn sample_summary() -> RunSummary {
    RunSummary {
        scene: "cantilever".to_owned(),
        status: RunStatus::Ok,
        reason: None,
        stopped_at: Some(1.0),
        failed_step: None,
        resumed_from: None,
        model: ModelRecord::KirchhoffLove { law: "stvk".into() },
        displacement_element: "tri6".to_owned(),
        rotation_element: "tri3".to_owned(),
        strain_interpolation: "paper".to_owned(),
        quadrature_points: "3".to_owned(),
        n_shells: 1,
        n_cells: 128,
        n_displacement_dofs: 867,
        n_rotation_dofs: 243,
        n_curved_points: 0,
        active_terms: vec!["membrane".to_owned(), "bending".to_owned(), "inertia".to_owned()],
        hessian_nnz: 12_345,
        dt: 1e-3,
        n_steps: 1000,
        n_frames: 31,
        avg_newton_iterations: 3.25,
        max_newton_iterations: 7,
        wasted_newton_iterations: 4,
        n_step_reductions: 2,
        n_intermediate_levels: 3,
        wall_seconds: 12.75,
        avg_step_ms: 12.5,
        assembly_share: 0.625,
        linear_solve_share: 0.25,
        peak_memory_mb: Some(42.5),
        linear_solver: LinearSolverRecord {
            factorisations: 3250,
            factor: Some(FactorRecord {
                nnz: 40_000,
                flops: 2.5e6,
                domains: 1,
                seconds: 1.5,
                gflops_per_s: Some(5.4),
            }),
            cg_iterations: None,
            cg_iterations_per_newton: None,
        },
        min_area_ratio: Some(0.875),
        contact: Some(ContactRecord {
            min_gap: Some(1e-4),
            ..ContactRecord::default()
        }),
        warnings: vec!["shell `s`: elements lock".into()],
        energy: EnergyHistory {
            t: vec![0.0, 0.5],
            kinetic: vec![0.0, 0.25],
            elastic: vec![0.0, 1.5],
        },
        rest_bbox: BoundingBox {
            min: [0.0, -0.5, 0.0],
            max: [10.0, 0.5, 1e-17],
        },
        convergence: Some(ConvergenceRecord {
            tolerance_mode: ToleranceMode::Relative,
            tolerance: 1e-6,
            max_step_tolerance: 2.5e-6,
            max_residual: 1.25e-6,
            max_relative_residual: 5e-7,
            stagnated_steps: 0,
            shifted_iterations: 3,
            rejected_iterates: 4,
            retracted_guesses: 1,
            free_retries: 0,
        }),
    }
}

/// The keys of the output contract, with the JSON names used for them.
const CONTRACT_KEYS: [&str; 37] = [
    "scene",
    "status",
    "reason",
    "stopped_at",
    "failed_step",
    "model",
    "displacement_element",
    "rotation_element",
    "strain_interpolation",
    "quadrature_points",
    "n_shells",
    "n_cells",
    "n_displacement_dofs",
    "n_rotation_dofs",
    "n_curved_points",
    "active_terms",
    "hessian_nnz",
    "dt",
    "n_steps",
    "n_frames",
    "avg_newton_iterations",
    "max_newton_iterations",
    "wasted_newton_iterations",
    "n_step_reductions",
    "n_intermediate_levels",
    "wall_seconds",
    "avg_step_ms",
    "assembly_share",
    "linear_solve_share",
    "peak_memory_mb",
    "linear_solver",
    "min_area_ratio",
    "contact",
    "warnings",
    "energy",
    "rest_bbox",
    "convergence",
];

#[test]
fn summary_round_trips_through_the_file() {
    let dir = test_dir("summary_round_trip");
    let path = dir.join("summary.json");
    let summary = sample_summary();
    write_summary(&path, &summary).expect("write");
    assert_eq!(read_summary(&path).expect("read"), summary);
    assert_eq!(entries(&dir), vec!["summary.json".to_owned()]);
}

#[test]
fn json_holds_every_contract_key() {
    let dir = test_dir("summary_keys");
    let path = dir.join("summary.json");
    write_summary(&path, &sample_summary()).expect("write");
    let value: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).expect("read")).expect("valid JSON");
    let object = value.as_object().expect("a JSON object");
    for key in CONTRACT_KEYS {
        assert!(object.contains_key(key), "missing key {key}");
    }
    assert_eq!(
        object.len(),
        CONTRACT_KEYS.len(),
        "unexpected keys: {:?}",
        object.keys()
    );
    assert_eq!(object["status"], "ok");
    assert_eq!(object["reason"], serde_json::Value::Null);
    assert_eq!(object["rest_bbox"]["min"], serde_json::json!([0.0, -0.5, 0.0]));
    assert_eq!(object["rest_bbox"]["max"].as_array().map(Vec::len), Some(3));
    assert_eq!(
        object["active_terms"],
        serde_json::json!(["membrane", "bending", "inertia"])
    );
    assert_eq!(
        object["model"],
        serde_json::json!({ "kind": "kirchhoff_love", "law": "stvk" })
    );
    assert_eq!(object["linear_solver"]["factor"]["nnz"], 40_000);
    assert_eq!(object["contact"]["min_gap"].as_f64(), Some(1e-4));
    assert_eq!(object["convergence"]["tolerance_mode"], "relative");
}

#[test]
fn statuses_are_lower_case_strings() {
    for (status, text) in [
        (RunStatus::Ok, "ok"),
        (RunStatus::Error, "error"),
        (RunStatus::Interrupted, "interrupted"),
    ] {
        assert_eq!(
            serde_json::to_value(status).expect("serialise"),
            serde_json::json!(text)
        );
        assert_eq!(
            serde_json::from_value::<RunStatus>(serde_json::json!(text)).expect("parse"),
            status
        );
    }
}

#[test]
fn non_finite_numbers_are_refused_and_nothing_is_written() {
    let dir = test_dir("summary_non_finite");
    let path = dir.join("summary.json");
    type Poison = fn(&mut RunSummary);
    let cases: [(&str, Poison); 14] = [
        ("dt", |s| s.dt = f64::NAN),
        ("avg_newton_iterations", |s| s.avg_newton_iterations = f64::INFINITY),
        ("wall_seconds", |s| s.wall_seconds = f64::NAN),
        ("avg_step_ms", |s| s.avg_step_ms = f64::NEG_INFINITY),
        ("assembly_share", |s| s.assembly_share = f64::NAN),
        ("linear_solve_share", |s| s.linear_solve_share = f64::NAN),
        ("rest_bbox.min[1]", |s| s.rest_bbox.min[1] = f64::NAN),
        ("rest_bbox.max[2]", |s| s.rest_bbox.max[2] = f64::INFINITY),
        ("stopped_at", |s| s.stopped_at = Some(f64::NAN)),
        ("min_area_ratio", |s| s.min_area_ratio = Some(f64::NAN)),
        ("linear_solver.factor.flops", |s| {
            s.linear_solver.factor.as_mut().unwrap().flops = f64::INFINITY
        }),
        ("contact.min_gap", |s| {
            s.contact.as_mut().unwrap().min_gap = Some(f64::NAN)
        }),
        ("energy.kinetic[1]", |s| s.energy.kinetic[1] = f64::NAN),
        ("convergence.max_relative_residual", |s| {
            if let Some(c) = &mut s.convergence {
                c.max_relative_residual = f64::INFINITY;
            }
        }),
    ];
    for (field, poison) in cases {
        let mut summary = sample_summary();
        poison(&mut summary);
        match write_summary(&path, &summary) {
            Err(OutputError::NonFiniteSummary { field: reported, .. }) => assert_eq!(reported, field),
            other => panic!("{field}: expected a non-finite error, got {other:?}"),
        }
        assert!(entries(&dir).is_empty(), "{field}: a file was written");
    }
}

#[test]
fn failed_summary_carries_status_and_reason() {
    let summary = RunSummary::failed("plate", RunStatus::Error, "Newton diverged at t = 0.5 with dt = 1e-6");
    summary.validate().expect("a failure summary is valid");
    let value = serde_json::to_value(&summary).expect("serialise");
    assert_eq!(value["status"], "error");
    assert_eq!(value["reason"], "Newton diverged at t = 0.5 with dt = 1e-6");
    assert_eq!(value["scene"], "plate");
}

#[test]
fn bounding_box_of_points() {
    let bbox = BoundingBox::of_points(&[[1.0, -2.0, 3.0], [-1.0, 5.0, 0.0], [0.0, 0.0, 4.0]]).expect("points");
    assert_eq!(
        bbox,
        BoundingBox {
            min: [-1.0, -2.0, 0.0],
            max: [1.0, 5.0, 4.0]
        }
    );
    assert_eq!(BoundingBox::of_points(&[]), None);
}
