//! Steady state, spectra, Poincaré classification and sweeps.

use geardyn_timestep::*;
use std::sync::atomic::{AtomicUsize, Ordering};

#[test]
fn steady_forced_linear_oscillator_has_exact_amplitude() {
    let p = LinearOscillator {
        omega0: 1.0,
        zeta: 0.05,
        force: 0.3,
        omega: 0.8,
    };
    let period = 2.0 * std::f64::consts::PI / p.omega;
    let sys = p.first_order();
    let opts = Options::default().with_tol(1e-10, 1e-12);
    let ss = SteadyOptions {
        sample_periods: 4,
        samples_per_period: 64,
        ..SteadyOptions::new(period)
    };
    let st = steady_state(&sys, 0.0, &[0.0, 0.0], &opts, &ss).unwrap();
    assert!(st.converged);
    assert_eq!(st.order, Some(1));
    assert_eq!(st.t.len(), 256);
    let x = st.component(0);
    // exact steady amplitude F / sqrt((w0² − Ω²)² + (2 ζ w0 Ω)²)
    let a_exact = 0.3 / ((1.0f64 - 0.64).powi(2) + (2.0f64 * 0.05 * 0.8).powi(2)).sqrt();
    let h = harmonic_amplitudes(&x, 4, 3).unwrap();
    assert!(
        (h[0] - a_exact).abs() < 1e-6 * a_exact,
        "{} vs {a_exact}",
        h[0]
    );
    assert!(h[1] < 1e-6 && h[2] < 1e-6);
    let sp = amplitude_spectrum(&x, st.dt).unwrap();
    let (f, a) = sp.amplitude_at(0.8 / (2.0 * std::f64::consts::PI)).unwrap();
    assert!((f - 1.0 / period).abs() < 1e-12 && (a - a_exact).abs() < 1e-6 * a_exact);
    assert!((peak_to_peak(&x).unwrap() - 2.0 * a_exact).abs() < 1e-3 * a_exact);
}

fn classify(sys: &dyn OdeSystem, period: f64, y0: &[f64]) -> Classification {
    let mut co = ClassifyOptions::new(period);
    co.transient_periods = 100;
    co.n_points = 32;
    co.lyapunov_intervals = 100;
    classify_motion(sys, 0.0, y0, &co, &Options::default().with_tol(1e-9, 1e-11)).unwrap()
}

/// Duffing δ = 0.3, α = −1, β = 1, ω = 1.2 from (1, 0): period-1 at γ = 0.20, period-2 at
/// 0.28, period-4 at 0.29, period-5 at 0.37, chaos at 0.50 (Holmes 1979; Guckenheimer &
/// Holmes 1983 §2.2; Jordan & Smith, Nonlinear ODEs, 4th ed.).
#[test]
fn duffing_reference_classification() {
    for (gamma, expected) in [
        (0.20, Motion::Periodic(1)),
        (0.28, Motion::Periodic(2)),
        (0.29, Motion::Periodic(4)),
        (0.37, Motion::Periodic(5)),
        (0.50, Motion::Chaotic),
    ] {
        let d = Duffing::holmes(gamma);
        let c = classify(&FirstOrder(d), d.period(), &[1.0, 0.0]);
        assert_eq!(c.motion, expected, "gamma = {gamma}");
        if expected == Motion::Chaotic {
            let l = c.lyapunov.unwrap();
            assert!(l > 0.05 && l < 0.3, "lambda = {l}");
        }
    }
}

#[test]
fn incommensurate_forcing_is_quasi_periodic() {
    // x'' + x = cos(√2 t): free oscillation at 1 plus forced at √2, invariant circle in the
    // stroboscopic section, zero Lyapunov exponent
    let q = LinearOscillator {
        omega0: 1.0,
        zeta: 0.0,
        force: 1.0,
        omega: 2f64.sqrt(),
    };
    let c = classify(
        &q.first_order(),
        2.0 * std::f64::consts::PI / q.omega,
        &[1.0, 0.0],
    );
    assert_eq!(c.motion, Motion::QuasiPeriodic);
    assert!(c.lyapunov.unwrap().abs() < 1e-3);
}

#[test]
fn user_surface_section_of_harmonic_oscillator() {
    let sys = LinearOscillator {
        omega0: 1.0,
        zeta: 0.0,
        force: 0.0,
        omega: 1.0,
    }
    .first_order();
    // x = cos t crosses x = 0 upwards at t = 3π/2 + 2πk
    let sec = poincare_surface(
        &sys,
        0.0,
        &[1.0, 0.0],
        0.0,
        30.0,
        |_t, y: &[f64]| y[0],
        Direction::Rising,
        &Options::default().with_tol(1e-11, 1e-13),
    )
    .unwrap();
    assert_eq!(sec.len(), 5);
    for k in 0..5 {
        let te = 1.5 * std::f64::consts::PI + 2.0 * std::f64::consts::PI * k as f64;
        assert!((sec.t[k] - te).abs() < 1e-9);
        assert!((sec.point(k)[1] - 1.0).abs() < 1e-8);
    }
    assert_eq!(detect_period(&sec, 3, 1e-6), Some(1));
}

#[test]
fn sweep_is_ordered_and_thread_count_independent() {
    let gammas: Vec<f64> = (0..6).map(|i| 0.2 + 0.06 * i as f64).collect();
    let f = |g: &f64| {
        let d = Duffing::holmes(*g);
        let o = Options::default().with_output(Output::Final);
        integrate(&FirstOrder(d), 0.0, &[1.0, 0.0], 60.0, &o)
            .unwrap()
            .y_final
    };
    let count = AtomicUsize::new(0);
    let cb = |_done: usize, total: usize| {
        assert_eq!(total, 6);
        count.fetch_add(1, Ordering::Relaxed);
    };
    let one = sweep_with_threads(1, &gammas, f, Some(&cb)).unwrap();
    let two = sweep_with_threads(2, &gammas, f, None).unwrap();
    let serial: Vec<Vec<f64>> = gammas.iter().map(f).collect();
    assert_eq!(count.load(Ordering::Relaxed), 6);
    // bit-identical, in input order
    for ((a, b), c) in one.iter().zip(&two).zip(&serial) {
        assert!(
            a.iter()
                .zip(b)
                .zip(c)
                .all(|((x, y), z)| x.to_bits() == y.to_bits() && x.to_bits() == z.to_bits())
        );
    }
}
