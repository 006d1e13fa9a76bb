//! Benchmarks of the hot paths: k_m(t) evaluation (1 and 10 harmonics), the FFT fit of a
//! 1024-sample curve, and the fractal / Hertz contact stiffness.

// criterion_group! generates an undocumented public function
#![allow(missing_docs)]

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use geardyn_mesh_stiffness::{
    CurvatureCoefficient, FourierFitter, FourierStiffness, FractalContact, FractalForm,
    SingleHarmonicStiffness, ToothPairStiffness, Waveform, fit_fourier,
};

#[path = "../../crates/mesh-stiffness/tests/it/reference_contact.rs"]
mod reference_contact;
use reference_contact::reference_contact;

fn series(h: usize) -> FourierStiffness {
    let cos = (1..=h).map(|n| 4.0e7 / n as f64).collect();
    let sin = (1..=h).map(|n| -1.0e7 / n as f64).collect();
    FourierStiffness::new(3.1e8, 2880.0, cos, sin).unwrap()
}

fn eval(c: &mut Criterion) {
    // k0 = 3.1e8 N/m, k_r = 0.9e8 N/m, ω_e = 2880 rad/s, φ_m = π/2 (Liu 2021 Table 1 values)
    let single = SingleHarmonicStiffness::new(
        3.1e8,
        0.9e8,
        2880.0,
        std::f64::consts::FRAC_PI_2,
        Waveform::Sine,
    )
    .expect("valid stiffness");
    c.bench_function("single_harmonic_eval_with_derivative", |b| {
        let mut t = 0.0;
        b.iter(|| {
            t += 1.0e-6;
            black_box(single.eval_with_derivative(black_box(t)))
        })
    });
    for h in [1usize, 10] {
        let s = series(h);
        c.bench_function(&format!("series_eval_{h}_harmonics"), |b| {
            let mut t = 0.0;
            b.iter(|| {
                t += 1.0e-6;
                black_box(s.eval(black_box(t)))
            })
        });
        c.bench_function(&format!("series_eval_with_derivative_{h}_harmonics"), |b| {
            let mut t = 0.0;
            b.iter(|| {
                t += 1.0e-6;
                black_box(s.eval_with_derivative(black_box(t)))
            })
        });
    }
    let wave = ToothPairStiffness::new(1.6, 2.0e8, 3.6e8, 0.05).unwrap();
    c.bench_function("tooth_pair_value_at_phase", |b| {
        let mut u = 0.0;
        b.iter(|| {
            u += 1.0e-3;
            black_box(wave.value_at_phase(black_box(u)))
        })
    });
}

fn fit(c: &mut Criterion) {
    let wave = ToothPairStiffness::new(1.6, 2.0e8, 3.6e8, 0.05).unwrap();
    let samples = wave.sample(1024, 1);
    c.bench_function("fit_fourier_1024_samples_10_harmonics_with_plan", |b| {
        b.iter(|| black_box(fit_fourier(black_box(&samples), 1, 10, 2880.0).unwrap()))
    });
    let mut fitter = FourierFitter::new(1024).unwrap();
    c.bench_function("fitter_1024_samples_10_harmonics_reused_plan", |b| {
        b.iter(|| black_box(fitter.fit(black_box(&samples), 1, 10, 2880.0).unwrap()))
    });
}

fn contact(c: &mut Criterion) {
    let p = reference_contact();
    c.bench_function("fractal_contact_stiffness", |b| {
        b.iter(|| black_box(black_box(&p).stiffness(FractalForm::Consistent).unwrap()))
    });
    let h = p.hertz_line_contact(0.02).unwrap();
    c.bench_function("hertz_tangent_stiffness", |b| {
        b.iter(|| black_box(black_box(&h).tangent_stiffness(black_box(1146.8)).unwrap()))
    });
}

criterion_group!(benches, eval, fit, contact);
criterion_main!(benches);
