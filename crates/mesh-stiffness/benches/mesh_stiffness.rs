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

/// The contact of reading R-YU-EQ18 (`docs/readings/mesh-stiffness.md`; Yu's set, kept by the
/// model as `geardyn_models::yu2021::fractal_contact_default`), written out so that the law's
/// tests stand without the model: D = 1.5, G = 1e-11 m, E = 2.06e11 Pa, H = 2.2e9 Pa, ν = 0.3,
/// R₁ = R₂ = 0.094 sin 20° m, F = 107.8/0.094 N, l_a = 1e-4 m, l_s = 1e-8 m, a_L = π l_a²/4,
/// λ_c = 1.
fn reference_contact() -> FractalContact {
    let r = 0.094 * 20f64.to_radians().sin();
    let la = 1e-4;
    FractalContact {
        fractal_dimension: 1.5,
        fractal_roughness: 1e-11,
        elastic_modulus: 2.06e11,
        hardness: 2.2e9,
        poisson_ratio: 0.3,
        radius_pinion: r,
        radius_gear: r,
        load: 107.8 / 0.094,
        largest_asperity: la,
        smallest_asperity: 1e-8,
        largest_contact_area: std::f64::consts::PI * la * la / 4.0,
        curvature_coefficient: CurvatureCoefficient::Value(1.0),
    }
}
