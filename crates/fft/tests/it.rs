//! The planners against a direct DFT (`X_k = Σ_j x_j e^{∓2πi jk/N}`, evaluated with the angle
//! reduced modulo N) on lengths that take every kind of rustfft plan: trivial (0, 1), butterflies
//! (2, 3, 16), mixed radix (12, 1000), powers of two (128, 1024) and primes (97: Rader or
//! Bluestein).

use geardyn_fft::{Complex, FftPlanner, RealFftPlanner};
use math::DetMath;
use std::f64::consts::PI;
use std::sync::Arc;

const LENGTHS: [usize; 9] = [0, 1, 2, 3, 12, 16, 97, 128, 1000];

/// A deterministic, non-symmetric test signal.
fn signal(n: usize) -> Vec<Complex<f64>> {
    (0..n)
        .map(|j| {
            let t = j as f64;
            Complex::new(
                (0.37 * t).dsin() + 0.1 * t / (n as f64),
                (1.3 * t).dcos() - 0.25,
            )
        })
        .collect()
}

/// Direct DFT with sign `s` (−1 forward, +1 inverse), unnormalised.
fn dft(x: &[Complex<f64>], s: f64) -> Vec<Complex<f64>> {
    let n = x.len();
    (0..n)
        .map(|k| {
            x.iter()
                .enumerate()
                .map(|(j, &xj)| {
                    let m = (j * k) % n;
                    xj * Complex::from_polar(1.0, s * 2.0 * PI * m as f64 / n as f64)
                })
                .sum()
        })
        .collect()
}

/// Largest difference, relative to `N · max|x|` (the size of the sums).
fn rel_err(a: &[Complex<f64>], b: &[Complex<f64>], x_max: f64) -> f64 {
    assert_eq!(a.len(), b.len());
    let scale = (a.len().max(1) as f64) * x_max.max(1e-300);
    a.iter()
        .zip(b)
        .map(|(p, q)| (p - q).norm() / scale)
        .fold(0.0, f64::max)
}

#[test]
fn complex_forward_and_inverse_match_the_direct_dft() {
    let mut planner = FftPlanner::new();
    for n in LENGTHS {
        let x = signal(n);
        let x_max = x.iter().map(|c| c.norm()).fold(0.0, f64::max);
        for (s, plan) in [
            (-1.0, planner.plan_forward(n)),
            (1.0, planner.plan_inverse(n)),
        ] {
            assert_eq!(plan.len(), n);
            let mut buf = x.clone();
            plan.process(&mut buf);
            let err = rel_err(&buf, &dft(&x, s), x_max);
            assert!(err < 1e-14, "n = {n}, sign {s}: relative error {err:e}");
        }
    }
}

#[test]
fn inverse_of_forward_is_n_times_the_signal() {
    let mut planner = FftPlanner::new();
    for n in LENGTHS {
        let x = signal(n);
        let mut buf = x.clone();
        let mut scratch =
            vec![Complex::default(); planner.plan_forward(n).get_inplace_scratch_len()];
        planner
            .plan_forward(n)
            .process_with_scratch(&mut buf, &mut scratch);
        planner.plan_inverse(n).process(&mut buf);
        let back: Vec<_> = buf.iter().map(|c| c / n as f64).collect();
        assert!(rel_err(&back, &x, 1.0) < 1e-14, "n = {n}");
    }
}

#[test]
fn real_forward_gives_the_first_half_of_the_complex_dft() {
    let mut planner = RealFftPlanner::new();
    for n in LENGTHS.into_iter().filter(|&n| n > 0) {
        let x: Vec<f64> = signal(n).iter().map(|c| c.re).collect();
        let x_max = x.iter().map(|v| v.abs()).fold(0.0, f64::max);
        let reference = dft(
            &x.iter().map(|&v| Complex::new(v, 0.0)).collect::<Vec<_>>(),
            -1.0,
        );
        let plan = planner.plan_forward(n);
        let (mut input, mut output) = (x.clone(), plan.make_output_vec());
        assert_eq!(output.len(), n / 2 + 1);
        plan.process(&mut input, &mut output)
            .expect("planned lengths");
        let err = rel_err(&output, &reference[..n / 2 + 1], x_max);
        assert!(err < 1e-14, "n = {n}: relative error {err:e}");

        // and the complex-to-real inverse takes it back (times n)
        let inv = planner.plan_inverse(n);
        let mut back = inv.make_output_vec();
        inv.process(&mut output, &mut back)
            .expect("planned lengths");
        let back: Vec<_> = back
            .iter()
            .map(|v| Complex::new(v / n as f64, 0.0))
            .collect();
        let x_c: Vec<_> = x.iter().map(|&v| Complex::new(v, 0.0)).collect();
        assert!(rel_err(&back, &x_c, x_max) < 1e-14, "n = {n}");
    }
}

#[test]
fn wrong_buffer_lengths_are_errors_of_the_real_transforms() {
    let plan = RealFftPlanner::new().plan_forward(16);
    let (mut input, mut output) = (vec![0.0; 15], plan.make_output_vec());
    assert!(plan.process(&mut input, &mut output).is_err());
}

#[test]
fn a_planner_returns_its_cached_plan() {
    let mut planner = FftPlanner::new();
    assert!(Arc::ptr_eq(
        &planner.plan_forward(64),
        &planner.plan_forward(64)
    ));
    let mut real = RealFftPlanner::new();
    assert!(Arc::ptr_eq(&real.plan_forward(64), &real.plan_forward(64)));
    assert_eq!(format!("{planner:?}"), "FftPlanner { .. }");
    assert_eq!(format!("{real:?}"), "RealFftPlanner { .. }");
}

/// One code path on every CPU: the planner's plans give the bits of rustfft's scalar planner
/// (rustfft is built without its `avx`, `sse` and `neon` features, so that its dispatching
/// planner has nothing else to choose).
#[test]
fn plans_are_rustffts_scalar_algorithms() {
    let mut ours = FftPlanner::new();
    let mut scalar = rustfft::FftPlannerScalar::<f64>::new();
    for n in [1, 2, 3, 8, 12, 64, 97, 120, 256, 1000, 4096] {
        let mut a = signal(n);
        let mut b = a.clone();
        ours.plan_forward(n).process(&mut a);
        scalar.plan_fft_forward(n).process(&mut b);
        let bits = |v: &[Complex<f64>]| -> Vec<(u64, u64)> {
            v.iter().map(|c| (c.re.to_bits(), c.im.to_bits())).collect()
        };
        assert_eq!(bits(&a), bits(&b), "n = {n}");
    }
}
