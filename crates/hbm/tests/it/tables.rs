//! Cached time functions and FFT time series: the fast paths give the results of the direct ones.

use geardyn_hbm::{Basis, HbmProblem, SecondOrderSystem, SolverOptions};
use math::DetMath;
use nalgebra::DMatrix;

/// Parametric oscillator with a dead zone: `q'' + 0.1 q' + k(t) f(q; b(t)) = cos(ωt)`,
/// `k(t) = 1 + 0.3 sin ωt`, `b(t) = 0.2 + 0.05 cos 2ωt`; `tabulate` switches the time table on.
#[derive(Clone)]
struct Parametric {
    omega: f64,
    tabulate: bool,
}

impl Parametric {
    fn k(&self, t: f64) -> f64 {
        1.0 + 0.3 * (self.omega * t).dsin()
    }
    fn b(&self, t: f64) -> f64 {
        0.2 + 0.05 * (2.0 * self.omega * t).dcos()
    }
}

fn dead(q: f64, b: f64) -> (f64, f64) {
    if q > b {
        (q - b, 1.0)
    } else if q < -b {
        (q + b, 1.0)
    } else {
        (0.0, 0.0)
    }
}

impl SecondOrderSystem for Parametric {
    fn n_dof(&self) -> usize {
        1
    }
    fn mass(&self) -> DMatrix<f64> {
        DMatrix::identity(1, 1)
    }
    fn damping(&self) -> DMatrix<f64> {
        DMatrix::from_element(1, 1, 0.1)
    }
    fn nonlinear_force(&self, t: f64, q: &[f64], _qd: &[f64], g: &mut [f64]) {
        g[0] = self.k(t) * dead(q[0], self.b(t)).0;
    }
    fn forcing(&self, t: f64, f: &mut [f64]) {
        f[0] = (self.omega * t).dcos();
    }
    fn force_jacobian(&self, t: f64, q: &[f64], _qd: &[f64], a: &mut [f64], b: &mut [f64]) {
        a[0] = self.k(t) * dead(q[0], self.b(t)).1;
        b[0] = 0.0;
    }
    fn set_base_frequency(&mut self, omega: f64) -> Result<(), geardyn_hbm::SystemError> {
        self.omega = omega;
        Ok(())
    }
    fn time_table_len(&self) -> usize {
        if self.tabulate { 2 } else { 0 }
    }
    fn fill_time_table(&self, t: f64, row: &mut [f64]) {
        row[0] = self.k(t);
        row[1] = self.b(t);
    }
    fn nonlinear_force_tabulated(&self, t: f64, row: &[f64], q: &[f64], qd: &[f64], g: &mut [f64]) {
        if self.tabulate {
            g[0] = row[0] * dead(q[0], row[1]).0;
        } else {
            self.nonlinear_force(t, q, qd, g);
        }
    }
    fn force_jacobian_tabulated(
        &self,
        t: f64,
        row: &[f64],
        q: &[f64],
        qd: &[f64],
        a: &mut [f64],
        b: &mut [f64],
    ) {
        if self.tabulate {
            a[0] = row[0] * dead(q[0], row[1]).1;
            b[0] = 0.0;
        } else {
            self.force_jacobian(t, q, qd, a, b);
        }
    }
}

#[test]
fn tabulated_residual_and_jacobian_are_bit_identical_and_follow_omega() {
    let basis = Basis::full(6).unwrap();
    let mut z = vec![0.0; basis.n_coefficients()];
    for (i, v) in z.iter_mut().enumerate() {
        *v = 0.3 * ((i as f64) * 1.7).dsin();
    }
    for omega in [0.7, 1.3] {
        let mk = |tabulate| {
            let mut p = HbmProblem::new(
                Parametric {
                    omega: 0.5,
                    tabulate,
                },
                basis.clone(),
                0.5,
            )
            .unwrap();
            // the tables must follow a change of ω
            p.set_omega(omega).unwrap();
            p
        };
        let (mut a, mut b) = (mk(false), mk(true));
        let nz = a.n_unknowns();
        let (mut ra, mut rb) = (vec![0.0; nz], vec![0.0; nz]);
        let (mut ja, mut jb) = (DMatrix::zeros(nz, nz), DMatrix::zeros(nz, nz));
        a.residual_and_jacobian(&z, &mut ra, &mut ja).unwrap();
        b.residual_and_jacobian(&z, &mut rb, &mut jb).unwrap();
        for (x, y) in ra.iter().zip(&rb).chain(ja.iter().zip(jb.iter())) {
            assert_eq!(x.to_bits(), y.to_bits());
        }
        // a clone carries the tables
        let mut c = b.clone();
        let mut rc = vec![0.0; nz];
        c.residual(&z, &mut rc).unwrap();
        assert_eq!(rb, rc);
    }
}

#[test]
fn fft_time_series_matches_direct_summation() {
    let mut p = HbmProblem::new(
        Parametric {
            omega: 1.1,
            tabulate: true,
        },
        Basis::full(9).unwrap(),
        1.1,
    )
    .unwrap();
    // convergence does not matter here: any coefficients will do
    let mut sol = p.solve(&p.zero_guess(), &SolverOptions::default()).unwrap();
    for (i, c) in sol.coefficients.iter_mut().enumerate() {
        *c = 1.0 / (1.0 + i as f64) * (0.9 * i as f64).dcos();
    }
    for n_points in [19, 20, 64, 1000] {
        let ts = sol.time_series(n_points);
        assert_eq!(ts.time.len(), n_points);
        let scale = sol.coefficients.iter().map(|c| c.abs()).sum::<f64>();
        for (m, &t) in ts.time.iter().enumerate() {
            let (q, qd) = sol.state_at(t);
            assert!((ts.displacement[0][m] - q[0]).abs() < 1e-13 * scale);
            assert!((ts.velocity[0][m] - qd[0]).abs() < 1e-12 * scale);
        }
    }
}

/// `set_system` (a prepared problem re-used for another system, e.g. a sweep point) gives the
/// solution of a freshly built problem bit for bit, with the time tables re-read; a system
/// with another number of degrees of freedom is refused.
#[test]
fn set_system_equals_a_fresh_problem() {
    let basis = Basis::full(5).unwrap();
    let so = SolverOptions::default();
    let first = Parametric {
        omega: 1.1,
        tabulate: true,
    };
    let mut prepared = HbmProblem::with_grid_size(first, basis.clone(), 1.1, 64).unwrap();
    // start in contact (the dead zone's slope vanishes at rest)
    let mut z0 = prepared.zero_guess();
    z0[0] = 0.6;
    for omega in [1.3, 0.9, 1.3] {
        let sys = Parametric {
            omega,
            tabulate: true,
        };
        let mut fresh = HbmProblem::with_grid_size(sys.clone(), basis.clone(), omega, 64).unwrap();
        let a = fresh.solve(&z0, &so).unwrap();
        prepared.set_system(sys, omega).unwrap();
        let b = prepared.solve(&z0, &so).unwrap();
        assert!(a.converged);
        assert_eq!(a.coefficients.len(), b.coefficients.len());
        for (x, y) in a.coefficients.iter().zip(&b.coefficients) {
            assert_eq!(x.to_bits(), y.to_bits(), "omega = {omega}");
        }
        assert_eq!(prepared.omega().to_bits(), omega.to_bits());
    }
    let sys = Parametric {
        omega: 1.0,
        tabulate: true,
    };
    assert!(prepared.set_system(sys.clone(), f64::NAN).is_err());
    assert!(prepared.set_system(sys, -1.0).is_err());
}
