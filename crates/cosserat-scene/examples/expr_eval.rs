//! Measures the cost of evaluating compiled scene expressions, next to the same formula written as a
//! Rust closure. Run with `cargo run --release -p cosserat-scene --example expr_eval`.
//!
//! The simulator evaluates rest fields at every quadrature point every step, so this is the number to
//! watch: nanoseconds per evaluation for formulas of the paper's scenes.

use cosserat_scene::expr::ExprContext;
use nalgebra::Vector3;
use std::hint::black_box;
use std::time::Instant;

/// Nanoseconds per call of `f` over `n` calls (after a warm-up of `n / 10`).
fn ns_per_call(n: usize, mut f: impl FnMut(usize) -> f64) -> f64 {
    let mut sink = 0.0;
    for i in 0..n / 10 {
        sink += f(i);
    }
    let start = Instant::now();
    for i in 0..n {
        sink += f(i);
    }
    let elapsed = start.elapsed().as_secs_f64();
    black_box(sink);
    elapsed * 1e9 / n as f64
}

fn main() {
    let mut ctx = ExprContext::new();
    ctx.define(
        "p",
        &["u".into()],
        "-0.2314286 + 10.89881*u - 14.28571*u^2 + 4.427083*u^3",
    )
    .unwrap();
    ctx.define("sigma", &["t".into()], "min(t/6 + 1, 1.8)").unwrap();
    ctx.define("alpha", &["t".into()], "10*ramp(t, 0, 6)").unwrap();
    ctx.define("rho", &["x".into(), "y".into()], "sqrt(x^2 + y^2)").unwrap();
    let p = |u: f64| -0.2314286 + 10.89881 * u - 14.28571 * u * u + 4.427083 * u * u * u;
    let ramp = |t: f64, t0: f64, t1: f64| ((t - t0) / (t1 - t0)).clamp(0.0, 1.0);
    type Native = Box<dyn Fn(&Vector3<f64>, f64) -> f64>;
    let cases: Vec<(&str, &str, Native)> = vec![
        (
            "cylinder coiling Γ_21",
            "4*pi*ramp(t, 0, 2.5)",
            Box::new(move |_, t| 4.0 * std::f64::consts::PI * ramp(t, 0.0, 2.5)),
        ),
        (
            "curvature modes",
            "3*2*pi*ramp(t, 0, 2.5)*sgn(x)",
            Box::new(move |x, t| 6.0 * std::f64::consts::PI * ramp(t, 0.0, 2.5) * if x.x > 0.0 { 1.0 } else { -1.0 }),
        ),
        (
            "lotus Γ_21",
            "-alpha(t) * 0.35 * p(sigma(t)*abs(x)/0.5)",
            Box::new(move |x, t| -10.0 * ramp(t, 0.0, 6.0) * 0.35 * p((t / 6.0 + 1.0).min(1.8) * x.x.abs() / 0.5)),
        ),
        (
            "buckling growth (inner)",
            "0.15*ramp(t, 1, 5)*max(0, 1 - min(rho(x, y), 0.9*0.025)/(0.9*0.025))",
            Box::new(move |x, t| {
                let rho = (x.x * x.x + x.y * x.y).sqrt();
                0.15 * ramp(t, 1.0, 5.0) * (1.0 - rho.min(0.0225) / 0.0225).max(0.0)
            }),
        ),
    ];
    let n = 2_000_000;
    println!("{:<26} {:>12} {:>12}", "expression", "compiled ns", "closure ns");
    for (name, text, native) in &cases {
        let f = ctx.field_function(text).unwrap();
        let point = |i: usize| Vector3::new((i % 1000) as f64 * 1e-3 - 0.5, 0.013, 0.0);
        let time = |i: usize| (i % 997) as f64 * 0.01;
        // Both must agree before their speed is worth comparing.
        for i in (0..10_000).step_by(37) {
            let (a, b) = (f.eval(&point(i), time(i)), native(&point(i), time(i)));
            assert!((a - b).abs() <= 1e-12 * (1.0 + b.abs()), "{name}: {a} vs {b}");
        }
        let compiled = ns_per_call(n, |i| f.eval(black_box(&point(i)), black_box(time(i))));
        let closure = ns_per_call(n, |i| native(black_box(&point(i)), black_box(time(i))));
        println!("{name:<26} {compiled:>12.1} {closure:>12.1}");
    }
}
