//! Reference systems of the integration tests.
#![allow(dead_code)]

use math::DetMath;
use nalgebra::DMatrix;
use system::{Direction, SecondOrderSystem, SystemError};

/// `q'' + 2ζ q' + k(q) = F0 + F cos ωt`, `k(q) = q` for `q < d`, `d + κ (q − d)` for `q ≥ d`:
/// a bilinear (piecewise-linear) oscillator with one kink at `q = d`.
#[derive(Debug, Clone, Copy)]
pub struct Bilinear {
    pub zeta: f64,
    pub kappa: f64,
    pub d: f64,
    pub f0: f64,
    pub f: f64,
    pub omega: f64,
}

impl SecondOrderSystem for Bilinear {
    fn n_dof(&self) -> usize {
        1
    }
    fn mass(&self) -> DMatrix<f64> {
        DMatrix::identity(1, 1)
    }
    fn damping(&self) -> DMatrix<f64> {
        DMatrix::from_element(1, 1, 2.0 * self.zeta)
    }
    fn nonlinear_force(&self, _t: f64, q: &[f64], _v: &[f64], g: &mut [f64]) {
        g[0] = if q[0] < self.d {
            q[0]
        } else {
            self.d + self.kappa * (q[0] - self.d)
        };
    }
    fn force_jacobian(&self, _t: f64, q: &[f64], _v: &[f64], dq: &mut [f64], dv: &mut [f64]) {
        dq[0] = if q[0] < self.d { 1.0 } else { self.kappa };
        dv[0] = 0.0;
    }
    fn forcing(&self, t: f64, f: &mut [f64]) {
        f[0] = self.f0 + self.f * (self.omega * t).dcos();
    }
    fn n_events(&self) -> usize {
        1
    }
    fn events(&self, _t: f64, q: &[f64], _v: &[f64], e: &mut [f64]) {
        e[0] = q[0] - self.d;
    }
    fn set_base_frequency(&mut self, omega: f64) -> Result<(), SystemError> {
        self.omega = omega;
        Ok(())
    }
    fn set_parameter(&mut self, name: &str, value: f64) -> Result<(), SystemError> {
        match name {
            "f" => self.f = value,
            "kappa" => self.kappa = value,
            _ => {
                return Err(SystemError::UnknownParameter {
                    name: name.to_string(),
                });
            }
        }
        Ok(())
    }
    fn parameter(&self, name: &str) -> Result<f64, SystemError> {
        match name {
            "f" => Ok(self.f),
            "kappa" => Ok(self.kappa),
            _ => Err(SystemError::UnknownParameter {
                name: name.to_string(),
            }),
        }
    }
}

/// `q'' + 2ζ q' + q = cos ωt`, a rigid stop at `q = σ` (event `q − σ`, rising only).
#[derive(Debug, Clone, Copy)]
pub struct ImpactOscillator {
    pub zeta: f64,
    pub sigma: f64,
    pub omega: f64,
}

impl SecondOrderSystem for ImpactOscillator {
    fn n_dof(&self) -> usize {
        1
    }
    fn mass(&self) -> DMatrix<f64> {
        DMatrix::identity(1, 1)
    }
    fn damping(&self) -> DMatrix<f64> {
        DMatrix::from_element(1, 1, 2.0 * self.zeta)
    }
    fn stiffness(&self) -> DMatrix<f64> {
        DMatrix::identity(1, 1)
    }
    fn nonlinear_force(&self, _t: f64, _q: &[f64], _v: &[f64], g: &mut [f64]) {
        g[0] = 0.0;
    }
    fn force_jacobian(&self, _t: f64, _q: &[f64], _v: &[f64], dq: &mut [f64], dv: &mut [f64]) {
        dq[0] = 0.0;
        dv[0] = 0.0;
    }
    fn forcing(&self, t: f64, f: &mut [f64]) {
        f[0] = (self.omega * t).dcos();
    }
    fn n_events(&self) -> usize {
        1
    }
    fn events(&self, _t: f64, q: &[f64], _v: &[f64], e: &mut [f64]) {
        e[0] = q[0] - self.sigma;
    }
    fn event_direction(&self, _index: usize) -> Direction {
        Direction::Rising
    }
    fn set_base_frequency(&mut self, omega: f64) -> Result<(), SystemError> {
        self.omega = omega;
        Ok(())
    }
    fn set_parameter(&mut self, name: &str, value: f64) -> Result<(), SystemError> {
        match name {
            "zeta" => self.zeta = value,
            _ => {
                return Err(SystemError::UnknownParameter {
                    name: name.to_string(),
                });
            }
        }
        Ok(())
    }
    fn parameter(&self, name: &str) -> Result<f64, SystemError> {
        match name {
            "zeta" => Ok(self.zeta),
            _ => Err(SystemError::UnknownParameter {
                name: name.to_string(),
            }),
        }
    }
}

/// Duffing `q'' + 2ζ q' + q + γ q³ = F cos ωt`: the workspace's reference problem.
pub use system::problems::Duffing;

/// One-DOF rattle: `q'' + 2ζ q' + dz(q, b) = F0 + F cos ωt` (dead zone of half-width `b`),
/// gap edges as events.
#[derive(Debug, Clone, Copy)]
pub struct Rattle {
    pub zeta: f64,
    pub b: f64,
    pub f0: f64,
    pub f: f64,
    pub omega: f64,
}

impl SecondOrderSystem for Rattle {
    fn n_dof(&self) -> usize {
        1
    }
    fn mass(&self) -> DMatrix<f64> {
        DMatrix::identity(1, 1)
    }
    fn damping(&self) -> DMatrix<f64> {
        DMatrix::from_element(1, 1, 2.0 * self.zeta)
    }
    fn nonlinear_force(&self, _t: f64, q: &[f64], _v: &[f64], g: &mut [f64]) {
        let x = q[0];
        g[0] = if x > self.b {
            x - self.b
        } else if x < -self.b {
            x + self.b
        } else {
            0.0
        };
    }
    fn force_jacobian(&self, _t: f64, q: &[f64], _v: &[f64], dq: &mut [f64], dv: &mut [f64]) {
        dq[0] = if q[0].abs() > self.b { 1.0 } else { 0.0 };
        dv[0] = 0.0;
    }
    fn forcing(&self, t: f64, f: &mut [f64]) {
        f[0] = self.f0 + self.f * (self.omega * t).dcos();
    }
    fn n_events(&self) -> usize {
        2
    }
    fn events(&self, _t: f64, q: &[f64], _v: &[f64], e: &mut [f64]) {
        system::gap_edges(q[0], self.b, e);
    }
    fn set_base_frequency(&mut self, omega: f64) -> Result<(), SystemError> {
        self.omega = omega;
        Ok(())
    }
}

/// `exp(A t)` of `A = [[0, 1], [−k, −c]]`, closed form (underdamped, overdamped or critical).
pub fn exp_oscillator(k: f64, c: f64, t: f64) -> DMatrix<f64> {
    // eigenvalues of A: λ = −c/2 ± sqrt(c²/4 − k)
    let a = -0.5 * c;
    let disc = 0.25 * c * c - k;
    // exp(At) = e^{at} [ (cosh/cos)(wt) I + (sinh/sin)(wt)/w (A − a I) ]
    let (ch, shw) = if disc > 0.0 {
        let w = disc.sqrt();
        ((w * t).dcosh(), (w * t).dsinh() / w)
    } else if disc < 0.0 {
        let w = (-disc).sqrt();
        ((w * t).dcos(), (w * t).dsin() / w)
    } else {
        (1.0, t)
    };
    let e = (a * t).dexp();
    let am = DMatrix::from_row_slice(2, 2, &[-a, 1.0, -k, -c - a]);
    (DMatrix::identity(2, 2) * ch + am * shw) * e
}
