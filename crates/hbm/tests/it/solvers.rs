//! Newton and Broyden agree; sweeps are deterministic for any thread count.

use crate::common::TwoDof;
use geardyn_hbm::{Basis, HbmProblem, Method, SolverOptions, parallel_sweep};

#[test]
fn newton_and_broyden_reach_the_same_solution() {
    for basis in [
        Basis::full(5).unwrap(),
        Basis::liu_multifrequency(1, 6).unwrap(),
    ] {
        let omega = 0.9;
        let mut p = HbmProblem::new(
            TwoDof {
                omega,
                analytic: true,
            },
            basis,
            omega,
        )
        .unwrap();
        let z0 = p.zero_guess();
        let newton = p.solve(&z0, &SolverOptions::default()).unwrap();
        let broyden = p
            .solve(
                &z0,
                &SolverOptions {
                    method: Method::Broyden,
                    ..SolverOptions::default()
                },
            )
            .unwrap();
        assert!(newton.converged && broyden.converged);
        assert!(broyden.iterations >= newton.iterations);
        let diff = newton
            .coefficients
            .iter()
            .zip(&broyden.coefficients)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(diff < 1e-9, "max difference {diff}");
        // the time-varying stiffness makes the solution genuinely multi-harmonic
        assert!(
            newton
                .harmonic_amplitudes(0)
                .iter()
                .filter(|a| a.amplitude > 1e-4)
                .count()
                >= 3
        );
    }
}

#[test]
fn non_convergence_is_a_value() {
    let omega = 0.9;
    let mut p = HbmProblem::new(
        TwoDof {
            omega,
            analytic: true,
        },
        Basis::full(3).unwrap(),
        omega,
    )
    .unwrap();
    let opts = SolverOptions {
        max_iters: 1,
        tolerance: 1e-14,
        ..SolverOptions::default()
    };
    let sol = p.solve(&p.zero_guess(), &opts).unwrap();
    assert!(!sol.converged);
    assert_eq!(sol.iterations, 1);
    assert!(sol.residual_norm > 0.0);
}

#[test]
fn parallel_sweep_is_bit_identical_for_any_thread_count() {
    let values: Vec<f64> = (0..12).map(|i| 0.4 + 0.1 * i as f64).collect();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            parallel_sweep(
                &values,
                |w| {
                    HbmProblem::new(
                        TwoDof {
                            omega: w,
                            analytic: true,
                        },
                        Basis::full(4).unwrap(),
                        w,
                    )
                },
                |_, p| p.zero_guess(),
                &SolverOptions::default(),
            )
        })
    };
    let one = run(1);
    let three = run(3);
    assert_eq!(one.len(), values.len());
    for ((a, b), w) in one.iter().zip(&three).zip(&values) {
        let (a, b) = (a.as_ref().unwrap(), b.as_ref().unwrap());
        assert!(a.converged);
        assert!((a.omega - w).abs() < 1e-15);
        let bits = |s: &geardyn_hbm::PeriodicSolution| -> Vec<u64> {
            s.coefficients.iter().map(|x| x.to_bits()).collect()
        };
        assert_eq!(bits(a), bits(b));
    }
}

#[test]
fn both_solvers_stop_between_iterations_at_the_threads_deadline() {
    let omega = 0.9;
    for method in [Method::Newton, Method::Broyden] {
        let mut p = HbmProblem::new(
            TwoDof {
                omega,
                analytic: true,
            },
            Basis::full(5).unwrap(),
            omega,
        )
        .unwrap();
        let z0 = p.zero_guess();
        let options = SolverOptions {
            method,
            ..SolverOptions::default()
        };
        let stopped = system::deadline::scope(Some(std::time::Instant::now()), || {
            p.solve(&z0, &options).unwrap()
        });
        assert!(!stopped.converged, "{method:?}");
        assert_eq!(stopped.termination, system::deadline::REASON, "{method:?}");
        assert!(
            stopped.iterations <= 1,
            "{method:?}: {}",
            stopped.iterations
        );
        // the same solve without a deadline converges
        let free = p.solve(&z0, &options).unwrap();
        assert!(free.converged, "{method:?}: {}", free.termination);
    }
}
