//! Prints the curvature refinement study of `docs/curvature-convergence.md` as Markdown tables.
//!
//! Run with `cargo run --release -p cosserat-fem --example curvature_convergence`.

#[path = "../tests/convergence_tests/study.rs"]
mod study;

use study::{Discretisation, Shape, fitted_order, measure};

fn main() {
    let levels = 4;
    for shape in [Shape::Sphere, Shape::Cylinder, Shape::JitteredTorus] {
        println!("## {shape:?}\n");
        for d in Discretisation::ALL {
            println!("### {}\n", d.label());
            println!("| h | max err abs(H) | RMS err abs(H) | max err K | RMS err K |");
            println!("|---|---|---|---|---|");
            let errors: Vec<_> = (0..levels).map(|l| measure(shape, l, d)).collect();
            for e in &errors {
                println!(
                    "| {:.4} | {:.3e} | {:.3e} | {:.3e} | {:.3e} |",
                    e.h, e.max_h, e.rms_h, e.max_k, e.rms_k
                );
            }
            let h: Vec<f64> = errors.iter().map(|e| e.h).collect();
            let order = |f: fn(&study::Errors) -> f64| {
                let v: Vec<f64> = errors.iter().map(f).collect();
                if v.iter().all(|&x| x > 0.0) {
                    format!("{:.2}", fitted_order(&h, &v))
                } else {
                    "n/a".into()
                }
            };
            println!(
                "| order | {} | {} | {} | {} |\n",
                order(|e| e.max_h),
                order(|e| e.rms_h),
                order(|e| e.max_k),
                order(|e| e.rms_k)
            );
        }
    }
}
