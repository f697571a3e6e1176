//! Measures the dense GEMM rate of faer on this machine (scratch).
use faer::Mat;
use std::time::Instant;
fn main() {
    for &n in &[1000usize, 2000, 4000] {
        let a = Mat::<f64>::from_fn(n, n, |i, j| ((i * 7 + j * 13) % 17) as f64 * 0.1);
        let b = Mat::<f64>::from_fn(n, n, |i, j| ((i * 3 + j * 5) % 11) as f64 * 0.1);
        for par in [faer::Par::Seq, faer::Par::rayon(2)] {
            let mut c = Mat::<f64>::zeros(n, n);
            let t = Instant::now();
            let reps = if n <= 1000 { 10 } else { 2 };
            for _ in 0..reps {
                faer::linalg::matmul::matmul(c.as_mut(), faer::Accum::Replace, a.as_ref(), b.as_ref(), 1.0, par);
            }
            let s = t.elapsed().as_secs_f64() / reps as f64;
            println!("n {n} {:?}: {:.1} GFLOP/s", par, 2.0 * (n as f64).powi(3) / s / 1e9);
        }
    }
}
