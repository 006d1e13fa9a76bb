//! Linear forced oscillators: HBM is exact.

use crate::common::Linear;
use geardyn_hbm::{Basis, HbmProblem, Method, SolverOptions};
use num_complex::Complex;

#[test]
fn linear_oscillator_is_exact() {
    let sys = Linear {
        m: 2.0,
        c: 0.3,
        k: 5.0,
        f0: 0.7,
        f1: 1.3,
        f2: -0.4,
        omega: 1.7,
    };
    let w = sys.omega;
    let mut p = HbmProblem::new(sys.clone(), Basis::full(4).unwrap(), w).unwrap();
    for method in [Method::Newton, Method::Broyden] {
        let opts = SolverOptions {
            method,
            ..SolverOptions::default()
        };
        let sol = p.solve(&p.zero_guess(), &opts).unwrap();
        assert!(sol.converged, "{method:?}: {}", sol.termination);
        // exact: X_k = F_k / (k − m (kω)² + i c kω), with a = Re X, b = −Im X
        let x1 = Complex::new(sys.f1, 0.0) / Complex::new(sys.k - sys.m * w * w, sys.c * w);
        let x2 =
            Complex::new(0.0, -sys.f2) / Complex::new(sys.k - 4.0 * sys.m * w * w, 2.0 * sys.c * w);
        let z = &sol.coefficients;
        let exact = [
            sys.f0 / sys.k,
            x1.re,
            -x1.im,
            x2.re,
            -x2.im,
            0.0,
            0.0,
            0.0,
            0.0,
        ];
        for (i, (a, b)) in z.iter().zip(exact).enumerate() {
            assert!(
                (a - b).abs() < 1e-12,
                "{method:?} coefficient {i}: {a} vs {b}"
            );
        }
        // Newton on a linear problem: one step
        if method == Method::Newton {
            assert_eq!(sol.iterations, 1);
        }
        // time series and amplitudes agree with the coefficients
        let amps = sol.harmonic_amplitudes(0);
        assert!((amps[1].amplitude - x1.norm()).abs() < 1e-12);
        assert!((amps[2].frequency - 2.0 * w).abs() < 1e-12);
        let ts = sol.time_series(64);
        let t = ts.time[5];
        let q = sys.f0 / sys.k
            + (x1 * Complex::new(0.0, w * t).exp()).re
            + (x2 * Complex::new(0.0, 2.0 * w * t).exp()).re;
        assert!((ts.displacement[0][5] - q).abs() < 1e-12);
        assert!(sol.spectral_tail(0) < 1e-12);
    }
}

#[test]
fn rejects_bad_input() {
    let sys = Linear {
        m: 1.0,
        c: 0.1,
        k: 1.0,
        f0: 0.0,
        f1: 1.0,
        f2: 0.0,
        omega: 1.0,
    };
    assert!(HbmProblem::new(sys.clone(), Basis::full(3).unwrap(), f64::NAN).is_err());
    assert!(HbmProblem::new(sys.clone(), Basis::full(3).unwrap(), -1.0).is_err());
    assert!(HbmProblem::with_grid_size(sys.clone(), Basis::full(8).unwrap(), 1.0, 16).is_err());
    let mut p = HbmProblem::new(sys, Basis::full(3).unwrap(), 1.0).unwrap();
    assert!(p.solve(&[0.0; 3], &SolverOptions::default()).is_err());
    let bad = SolverOptions {
        tolerance: f64::NAN,
        ..SolverOptions::default()
    };
    assert!(p.solve(&p.zero_guess(), &bad).is_err());
    let mut z = p.zero_guess();
    z[1] = f64::NAN;
    let mut r = vec![0.0; z.len()];
    assert!(p.residual(&z, &mut r).is_err());
    assert!(p.set_omega(0.0).is_err());
    assert!(p.set_parameter("nope", 1.0).is_err());
}
