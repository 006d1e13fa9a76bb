//! Fourier-series evaluation and fit: round trip, analytic rectangular-wave coefficients,
//! derivatives against finite differences, the NFG path to Liu's (k0, k_r, φ_m).

use approx::assert_relative_eq;
use geardyn_mesh_stiffness::{
    FourierFitter, FourierStiffness, NfgToothPairStiffness, SingleHarmonicStiffness,
    ToothPairStiffness, Waveform, fit_fourier, fit_single_harmonic,
};
use math::DetMath;
use proptest::prelude::*;

fn band_limited(h: usize) -> FourierStiffness {
    let cos: Vec<f64> = (1..=h).map(|n| 4.0e7 / n as f64).collect();
    let sin: Vec<f64> = (1..=h).map(|n| -1.5e7 / (n * n) as f64 + 1.0e6).collect();
    FourierStiffness::new(3.1e8, 2880.0, cos, sin).unwrap()
}

/// samples → series → samples is exact to rounding for a band-limited curve, for one and for
/// several periods, and the coefficients come back to rounding.
#[test]
fn round_trip_machine_precision() {
    for (h, periods, m) in [
        (1, 1, 8),
        (5, 1, 64),
        (10, 3, 1024),
        (7, 4, 60),
        (10, 1, 21),
    ] {
        let k = band_limited(h);
        let samples = k.sample(periods, m);
        let fit = fit_fourier(&samples, periods, h, k.omega_e()).unwrap();
        let scale = 3.1e8;
        assert!((fit.series.k0() - k.k0()).abs() < 1e-14 * scale * 4.0);
        for n in 0..h {
            assert!((fit.series.cos()[n] - k.cos()[n]).abs() < 1e-14 * scale * 4.0);
            assert!((fit.series.sin()[n] - k.sin()[n]).abs() < 1e-14 * scale * 4.0);
        }
        let back = fit.series.sample(periods, m);
        let err = samples
            .iter()
            .zip(&back)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(err < 1e-14 * scale * 4.0, "h={h} P={periods} M={m}: {err}");
        assert!(fit.residual_rms < 1e-14 * scale, "{}", fit.residual_rms);
        assert!(fit.aperiodic_rms < 1e-14 * scale);
    }
}

/// Fitting more harmonics than the curve has returns zeros for the extra ones.
#[test]
fn extra_harmonics_are_zero() {
    let k = band_limited(3);
    let fit = fit_fourier(&k.sample(1, 128), 1, 20, k.omega_e()).unwrap();
    for n in 4..=20 {
        assert!(
            fit.series.amplitude(n) < 1e-6,
            "{}",
            fit.series.amplitude(n)
        );
    }
}

/// The sampled DFT of a sharp rectangular wave (half values at the jumps) equals the analytic
/// Fourier coefficient times the trapezoidal factor (θ/2)cot(θ/2), θ = 2πn/M — an exact
/// discrete identity — and so converges to the analytic value as O((n/M)²).
#[test]
fn rectangular_wave_analytic_coefficients() {
    let wave = ToothPairStiffness::new(1.625, 2.0e8, 3.6e8, 0.0).unwrap();
    for (m, periods) in [(1024usize, 1usize), (4096, 1), (768, 3)] {
        // w M / periods must be an integer so that the jumps fall on samples (0.625 × 256 = 160),
        // and w exact in binary (1.625 − 1 = 0.625)
        let samples = wave.sample(m / periods, periods);
        let h = 12;
        let fit = fit_fourier(&samples, periods, h, 1.0).unwrap();
        let exact = wave.analytic_series(h, 1.0).unwrap();
        assert_relative_eq!(fit.series.k0(), exact.k0(), max_relative = 1e-14);
        let mp = (m / periods) as f64; // samples per period
        for n in 1..=h {
            let half = std::f64::consts::PI * n as f64 / mp;
            let factor = half / half.dtan();
            let (a, b) = (fit.series.cos()[n - 1], fit.series.sin()[n - 1]);
            let (ea, eb) = (exact.cos()[n - 1], exact.sin()[n - 1]);
            // exact identity, to rounding (1.6e8 is the jump)
            assert!(
                (a - ea * factor).abs() < 1e-13 * 1.6e8,
                "n={n} a={a} ea={ea}"
            );
            assert!(
                (b - eb * factor).abs() < 1e-13 * 1.6e8,
                "n={n} b={b} eb={eb}"
            );
            // and the convergence bound |fit − exact| ≤ (θ²/12)(1.01) |exact|
            let bound = (2.0 * half).powi(2) / 12.0 * 1.01;
            assert!((a - ea).abs() <= bound * ea.abs() + 1e-6);
            assert!((b - eb).abs() <= bound * eb.abs() + 1e-6);
        }
        assert!(fit.aperiodic_rms < 1e-6);
    }
}

/// The smoothed wave's fit converges to the analytic coefficients with the cos(πns)/(1−(2ns)²)
/// multiplier (including the removable point 2ns = 1 at n = 5, s = 0.1).
#[test]
fn smoothed_wave_analytic_coefficients() {
    let wave = ToothPairStiffness::new(1.6, 2.0e8, 3.6e8, 0.1).unwrap();
    let samples = wave.sample(4096, 1);
    let fit = fit_fourier(&samples, 1, 12, 1.0).unwrap();
    let exact = wave.analytic_series(12, 1.0).unwrap();
    assert_relative_eq!(fit.series.k0(), exact.k0(), max_relative = 1e-10);
    for n in 0..12 {
        assert!((fit.series.cos()[n] - exact.cos()[n]).abs() < 1e-5 * 1.6e8);
        assert!((fit.series.sin()[n] - exact.sin()[n]).abs() < 1e-5 * 1.6e8);
    }
    // smoothing lowers the high harmonics relative to the sharp wave
    let sharp = ToothPairStiffness::new(1.6, 2.0e8, 3.6e8, 0.0)
        .unwrap()
        .analytic_series(12, 1.0)
        .unwrap();
    assert!(exact.amplitude(7) < sharp.amplitude(7));
}

/// Liu's path: curve → DFT → (k0, k_r, φ_m); for the rectangular wave the fundamental is
/// k_r = 2Δ|sin(πw)|/π.
#[test]
fn curve_to_liu_eq19() {
    let wave = ToothPairStiffness::new(1.625, 2.0e8, 3.6e8, 0.0).unwrap();
    let samples = wave.sample(2048, 2);
    let sh = fit_single_harmonic(&samples, 2, 2880.0, Waveform::Sine).unwrap();
    let d = 1.6e8;
    let kr = 2.0 * d * (std::f64::consts::PI * 0.625).dsin() / std::f64::consts::PI;
    assert_relative_eq!(sh.k0, 2.0e8 + 0.625 * d, max_relative = 1e-13);
    assert_relative_eq!(sh.k_r, kr, max_relative = 1e-5);
    // φ = atan2(a, b) with a ∝ sin 2πw, b ∝ 1 − cos 2πw: φ = π/2 − πw
    assert_relative_eq!(
        sh.phi_m,
        std::f64::consts::FRAC_PI_2 - std::f64::consts::PI * 0.625,
        epsilon = 1e-12
    );
}

/// The NFG curve: the fit over one revolution (Z₂ periods) gives the mesh harmonics and a
/// non-zero aperiodic (sideband) part that grows with the eccentricity.
#[test]
fn nfg_revolution_fit() {
    let base = ToothPairStiffness::new(1.6, 2.0e8, 3.6e8, 0.05).unwrap();
    let z2 = 63;
    let mut last = -1.0;
    for e in [0.0, 0.1, 0.2, 0.3] {
        let nfg = NfgToothPairStiffness::new(base, z2, e, 0.3, 0.2).unwrap();
        let s = nfg.sample_revolution(64);
        let fit = fit_fourier(&s, z2, 8, 2880.0).unwrap();
        assert!(fit.aperiodic_rms > last);
        last = fit.aperiodic_rms;
        // the mean over the revolution is close to the circular mean (ρ averages to 1 over
        // the centre angles to first order)
        assert_relative_eq!(fit.series.k0(), base.mean(), max_relative = 0.02);
        // every period differs from the next when e > 0
        if e > 0.0 {
            let c0 = nfg.period_curve(0).unwrap();
            let c1 = nfg.period_curve(z2 / 2).unwrap();
            assert!(c0.contact_ratio > c1.contact_ratio);
        }
    }
}

#[test]
fn fitter_reuse_matches_free_function() {
    let k = band_limited(4);
    let mut f = FourierFitter::new(256).unwrap();
    for p in 1..4 {
        let s = k.sample(p, 256);
        let a = f.fit(&s, p, 4, k.omega_e()).unwrap();
        let b = fit_fourier(&s, p, 4, k.omega_e()).unwrap();
        assert_eq!(a, b);
    }
}

#[test]
fn types_are_send_sync() {
    fn check<T: Send + Sync + Clone>() {}
    check::<FourierStiffness>();
    check::<SingleHarmonicStiffness>();
    check::<ToothPairStiffness>();
    check::<NfgToothPairStiffness>();
    fn check_send<T: Send>() {}
    check_send::<FourierFitter>();
}

fn series_strategy() -> impl Strategy<Value = FourierStiffness> {
    (
        1.0e8..5.0e8f64,
        10.0..5000.0f64,
        prop::collection::vec((-5.0e7..5.0e7f64, -5.0e7..5.0e7f64), 1..=10),
    )
        .prop_map(|(k0, w, ab)| {
            let (cos, sin) = ab.into_iter().unzip();
            FourierStiffness::new(k0, w, cos, sin).unwrap()
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// dk/dt of the series against a central difference (step 1e-5 of a period).
    #[test]
    fn series_derivative_matches_finite_difference(k in series_strategy(), x in 0.0..3.0f64) {
        let t = x * k.period();
        let h = 1e-5 * k.period();
        let fd = (k.eval(t + h) - k.eval(t - h)) / (2.0 * h);
        let (_, dk) = k.eval_with_derivative(t);
        // scale: ω_e Σ n |c_n|; truncation error of the central difference ~ (nωh)²/6
        let scale = k.omega_e() * (1..=k.harmonics()).map(|n| n as f64 * k.amplitude(n)).sum::<f64>();
        prop_assert!((fd - dk).abs() <= 1e-6 * scale + 1e-3, "fd={fd} dk={dk} scale={scale}");
        // same code path: bit-identical
        prop_assert_eq!(k.derivative(t).to_bits(), dk.to_bits());
    }

    /// Same for the single-harmonic forms.
    #[test]
    fn single_harmonic_derivative(k0 in 1.0e8..5.0e8f64, kr in 0.0..1.0e8f64, w in 1.0..5000.0f64,
                                  phi in -3.0..3.0f64, cosine in any::<bool>(), x in 0.0..2.0f64) {
        let wf = if cosine { Waveform::Cosine } else { Waveform::Sine };
        let k = SingleHarmonicStiffness::new(k0, kr, w, phi, wf).unwrap();
        let period = std::f64::consts::TAU / w;
        let t = x * period;
        let h = 1e-5 * period;
        let fd = (k.eval(t + h) - k.eval(t - h)) / (2.0 * h);
        prop_assert!((fd - k.derivative(t)).abs() <= 1e-6 * kr * w + 1e-3);
        // and it equals its one-harmonic series
        let s = k.to_series().unwrap();
        prop_assert!((s.eval(t) - k.eval(t)).abs() <= 1e-14 * (k0 + kr) * 4.0);
    }

    /// Round trip on random band-limited series and random (valid) sample layouts.
    #[test]
    fn random_round_trip(k in series_strategy(), periods in 1usize..4, extra in 1usize..40) {
        let m = 2 * k.harmonics() * periods + extra;
        let s = k.sample(periods, m);
        let fit = fit_fourier(&s, periods, k.harmonics(), k.omega_e()).unwrap();
        let back = fit.series.sample(periods, m);
        for (a, b) in s.iter().zip(&back) {
            prop_assert!((a - b).abs() < 1e-13 * 5.0e8);
        }
    }
}

/// Liu Table 1 (k0 = 3.1e8 N/m, k_r = 0.9e8 N/m, a_k = 0.29) is what a rectangular
/// single/double-pair wave of two identical pairs gives for ε_α = 1.7143 and
/// k_pair = 1.8083e8 N/m (solved offline by bisection of 2 sin(πw)/(π(1+w)) = 0.9/3.1; the other
/// root is ε_α = 1.1810). Reading R-LIU-EQ19 in docs/readings/mesh-stiffness.md.
#[test]
fn liu_table1_from_rectangular_wave() {
    let wave = ToothPairStiffness::from_pair_stiffness(
        1.714_307_523_072_680_3,
        1.808_310_328_384_746_6e8,
        0.0,
    )
    .unwrap();
    let exact = wave.analytic_series(1, 2880.0).unwrap();
    assert_relative_eq!(exact.k0(), 3.1e8, max_relative = 1e-12);
    assert_relative_eq!(exact.amplitude(1), 0.9e8, max_relative = 1e-12);
    // and the DFT of the sampled curve gets there as O(1/M) (jump between samples)
    let sh = fit_single_harmonic(&wave.sample(8192, 1), 1, 2880.0, Waveform::Sine).unwrap();
    assert_relative_eq!(sh.k0, 3.1e8, max_relative = 1e-4);
    assert_relative_eq!(sh.k_r, 0.9e8, max_relative = 1e-4);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// The (smoothed) rectangular wave stays within [k_single, k_double], and its sampled mean
    /// converges to k0 = k_single + Δ(ε_α − 1) (O(1/M) when a jump falls between samples).
    #[test]
    fn tooth_pair_bounds_and_mean(cr in 1.01..1.99f64, ks in 1.0e8..3.0e8f64, kd in 1.0e8..5.0e8f64,
                                  sf in 0.0..1.0f64, u in -5.0..5.0f64) {
        let w = cr - 1.0;
        let s = sf * w.min(1.0 - w);
        let wave = ToothPairStiffness::new(cr, ks, kd, s).unwrap();
        let v = wave.value_at_phase(u);
        prop_assert!(v >= ks.min(kd) * (1.0 - 1e-15) && v <= ks.max(kd) * (1.0 + 1e-15));
        let m = 4096;
        let samples = wave.sample(m, 1);
        let mean = samples.iter().sum::<f64>() / m as f64;
        prop_assert!((mean - wave.mean()).abs() <= 2.0 * (kd - ks).abs() / m as f64 + 1e-6);
    }

    /// `eval_into` equals pointwise `eval`.
    #[test]
    fn eval_into_matches_eval(k in series_strategy(), ts in prop::collection::vec(-1.0..1.0f64, 1..20)) {
        let mut out = vec![0.0; ts.len()];
        k.eval_into(&ts, &mut out);
        for (o, t) in out.iter().zip(&ts) {
            prop_assert_eq!(o.to_bits(), k.eval(*t).to_bits());
        }
    }
}
