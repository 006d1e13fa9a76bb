//! Test systems with reference data, and a small RK4 integrator for long time integration.
#![allow(dead_code)]

use math::DetMath;
pub mod random_matrix;

use geardyn_hbm::SecondOrderSystem;
use nalgebra::DMatrix;

/// Linear oscillator `m q'' + c q' + k q = f0 + f1 cos ωt + f2 sin 2ωt` (K given as stiffness).
#[derive(Debug, Clone)]
pub struct Linear {
    pub m: f64,
    pub c: f64,
    pub k: f64,
    pub f0: f64,
    pub f1: f64,
    pub f2: f64,
    pub omega: f64,
}

impl SecondOrderSystem for Linear {
    fn set_base_frequency(&mut self, omega: f64) -> Result<(), geardyn_hbm::SystemError> {
        self.omega = omega;
        Ok(())
    }
    fn n_dof(&self) -> usize {
        1
    }
    fn mass(&self) -> DMatrix<f64> {
        DMatrix::from_element(1, 1, self.m)
    }
    fn damping(&self) -> DMatrix<f64> {
        DMatrix::from_element(1, 1, self.c)
    }
    fn stiffness(&self) -> DMatrix<f64> {
        DMatrix::from_element(1, 1, self.k)
    }
    fn nonlinear_force(&self, _t: f64, _q: &[f64], _qd: &[f64], g: &mut [f64]) {
        g[0] = 0.0;
    }
    fn force_jacobian(&self, _t: f64, _q: &[f64], _qd: &[f64], a: &mut [f64], b: &mut [f64]) {
        a[0] = 0.0;
        b[0] = 0.0;
    }
    fn forcing(&self, t: f64, f: &mut [f64]) {
        f[0] =
            self.f0 + self.f1 * (self.omega * t).dcos() + self.f2 * (2.0 * self.omega * t).dsin();
    }
}

/// Duffing `q'' + 2ζ q' + q + γ q³ = F cos ωt`: the workspace's reference problem.
pub use system::problems::Duffing;

/// Dead-zone (backlash) oscillator `q'' + 2ζ q' + f(q) = F0 + F cos ωt`.
#[derive(Debug, Clone)]
pub struct DeadZone {
    pub zeta: f64,
    pub b: f64,
    pub f0: f64,
    pub f1: f64,
    pub omega: f64,
}

impl DeadZone {
    pub fn f(&self, q: f64) -> f64 {
        if q > self.b {
            q - self.b
        } else if q < -self.b {
            q + self.b
        } else {
            0.0
        }
    }
}

impl SecondOrderSystem for DeadZone {
    fn set_base_frequency(&mut self, omega: f64) -> Result<(), geardyn_hbm::SystemError> {
        self.omega = omega;
        Ok(())
    }
    fn n_dof(&self) -> usize {
        1
    }
    fn mass(&self) -> DMatrix<f64> {
        DMatrix::identity(1, 1)
    }
    fn damping(&self) -> DMatrix<f64> {
        DMatrix::from_element(1, 1, 2.0 * self.zeta)
    }
    fn nonlinear_force(&self, _t: f64, q: &[f64], _qd: &[f64], g: &mut [f64]) {
        g[0] = self.f(q[0]);
    }
    fn force_jacobian(&self, _t: f64, q: &[f64], _qd: &[f64], a: &mut [f64], b: &mut [f64]) {
        a[0] = if q[0].abs() > self.b { 1.0 } else { 0.0 };
        b[0] = 0.0;
    }
    fn forcing(&self, t: f64, f: &mut [f64]) {
        f[0] = self.f0 + self.f1 * (self.omega * t).dcos();
    }
}

/// A smooth 2-DOF system with parametric stiffness, cubic coupling and a velocity nonlinearity
/// (no analytic Jacobian: exercises the finite-difference default when `analytic == false`).
#[derive(Debug, Clone)]
pub struct TwoDof {
    pub omega: f64,
    pub analytic: bool,
}

impl SecondOrderSystem for TwoDof {
    fn set_base_frequency(&mut self, omega: f64) -> Result<(), geardyn_hbm::SystemError> {
        self.omega = omega;
        Ok(())
    }
    fn n_dof(&self) -> usize {
        2
    }
    fn mass(&self) -> DMatrix<f64> {
        DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, 2.0])
    }
    fn damping(&self) -> DMatrix<f64> {
        DMatrix::from_row_slice(2, 2, &[0.1, -0.02, -0.02, 0.05])
    }
    fn stiffness(&self) -> DMatrix<f64> {
        DMatrix::from_row_slice(2, 2, &[2.0, -1.0, -1.0, 1.5])
    }
    fn nonlinear_force(&self, t: f64, q: &[f64], qd: &[f64], g: &mut [f64]) {
        let kt = 0.3 * (self.omega * t).dcos() + 0.1 * (3.0 * self.omega * t).dsin();
        let d = q[0] - q[1];
        g[0] = kt * q[0] + 0.5 * d.powi(3) + 0.2 * q[0] * q[0] * qd[0];
        g[1] = -0.5 * d.powi(3) + 0.1 * qd[1].powi(3);
    }
    fn force_jacobian(&self, t: f64, q: &[f64], qd: &[f64], a: &mut [f64], b: &mut [f64]) {
        if !self.analytic {
            geardyn_hbm::finite_difference_force_jacobian(self, t, q, qd, a, b);
            return;
        }
        let kt = 0.3 * (self.omega * t).dcos() + 0.1 * (3.0 * self.omega * t).dsin();
        let d = q[0] - q[1];
        let c = 1.5 * d * d;
        a.copy_from_slice(&[kt + c + 0.4 * q[0] * qd[0], -c, -c, c]);
        b.copy_from_slice(&[0.2 * q[0] * q[0], 0.0, 0.0, 0.3 * qd[1] * qd[1]]);
    }
    fn forcing(&self, t: f64, f: &mut [f64]) {
        f[0] = 0.2 * (self.omega * t).dcos();
        f[1] = 0.05;
    }
}

/// Classical RK4 of `M q'' + C q' + K q + g = f` (1-DOF or n-DOF with diagonal mass) from
/// `(q0, v0)` over `[0, t_end]` with step `h`; returns the final state and calls `observe(t, q,
/// v)` after each step.
pub fn rk4<S: SecondOrderSystem>(
    sys: &S,
    q0: &[f64],
    v0: &[f64],
    t_end: f64,
    h: f64,
    mut observe: impl FnMut(f64, &[f64], &[f64]),
) -> (Vec<f64>, Vec<f64>) {
    let n = sys.n_dof();
    let m = sys.mass();
    let c = sys.damping();
    let k = sys.stiffness();
    let accel = |t: f64, q: &[f64], v: &[f64]| -> Vec<f64> {
        let mut g = vec![0.0; n];
        let mut f = vec![0.0; n];
        sys.nonlinear_force(t, q, v, &mut g);
        sys.forcing(t, &mut f);
        (0..n)
            .map(|i| {
                let mut s = f[i] - g[i];
                for j in 0..n {
                    s -= c[(i, j)] * v[j] + k[(i, j)] * q[j];
                }
                s / m[(i, i)]
            })
            .collect()
    };
    let steps = (t_end / h).round() as usize;
    let (mut q, mut v) = (q0.to_vec(), v0.to_vec());
    for s in 0..steps {
        let t = s as f64 * h;
        let a1 = accel(t, &q, &v);
        let q2: Vec<f64> = (0..n).map(|i| q[i] + 0.5 * h * v[i]).collect();
        let v2: Vec<f64> = (0..n).map(|i| v[i] + 0.5 * h * a1[i]).collect();
        let a2 = accel(t + 0.5 * h, &q2, &v2);
        let q3: Vec<f64> = (0..n).map(|i| q[i] + 0.5 * h * v2[i]).collect();
        let v3: Vec<f64> = (0..n).map(|i| v[i] + 0.5 * h * a2[i]).collect();
        let a3 = accel(t + 0.5 * h, &q3, &v3);
        let q4: Vec<f64> = (0..n).map(|i| q[i] + h * v3[i]).collect();
        let v4: Vec<f64> = (0..n).map(|i| v[i] + h * a3[i]).collect();
        let a4 = accel(t + h, &q4, &v4);
        for i in 0..n {
            q[i] += h / 6.0 * (v[i] + 2.0 * v2[i] + 2.0 * v3[i] + v4[i]);
            v[i] += h / 6.0 * (a1[i] + 2.0 * a2[i] + 2.0 * a3[i] + a4[i]);
        }
        observe(t + h, &q, &v);
    }
    (q, v)
}

/// Peak-to-peak of `q[dof]` over the last `periods` periods after a long transient.
pub fn steady_ptp<S: SecondOrderSystem>(
    sys: &S,
    q0: &[f64],
    v0: &[f64],
    omega: f64,
    transient_periods: usize,
    periods: usize,
    steps_per_period: usize,
) -> f64 {
    let t = 2.0 * std::f64::consts::PI / omega;
    let h = t / steps_per_period as f64;
    let (q, v) = rk4(sys, q0, v0, transient_periods as f64 * t, h, |_, _, _| {});
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    rk4(sys, &q, &v, periods as f64 * t, h, |_, q, _| {
        lo = lo.min(q[0]);
        hi = hi.max(q[0]);
    });
    hi - lo
}
