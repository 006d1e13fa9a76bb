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

/// The bilinear oscillator of the non-smooth tests: one excursion past its kink `q = 0.5` per
/// period on its period-1 orbit.
pub fn bilinear() -> Bilinear {
    Bilinear {
        zeta: 0.05,
        kappa: 4.0,
        d: 0.5,
        f0: 0.0,
        f: 1.0,
        omega: 1.5,
    }
}

/// The two-sided rattle of the flow tests: four contact events a period on its period-1 orbit.
pub fn two_sided_rattle() -> Rattle {
    Rattle {
        zeta: 0.05,
        b: 0.5,
        f0: 0.1,
        f: 1.2,
        omega: 1.2,
    }
}

/// The bilinear oscillator far below its kink, `q'' + 2ζq' + q = F cos ωt` (ζ = 0.05,
/// F = 0.3, ω = 1.3), and its periodic orbit `q = a cos ωt + b sin ωt` on the section `t = 0`.
pub fn linear_oscillator() -> (Bilinear, [f64; 2]) {
    let s = Bilinear {
        zeta: 0.05,
        kappa: 10.0,
        d: 100.0,
        f0: 0.0,
        f: 0.3,
        omega: 1.3,
    };
    let (w, z) = (s.omega, s.zeta);
    let den = (1.0 - w * w).powi(2) + (2.0 * z * w).powi(2);
    let (a, b) = (s.f * (1.0 - w * w) / den, s.f * 2.0 * z * w / den);
    (s, [a, b * w])
}

/// The bilinear oscillator's monodromy over `[0, t]` from the located kinks alone: between
/// events the variational equation is linear with constant coefficients, so
/// `Φ = e^{A_m Δt_m} ⋯ e^{A_1 Δt_1}` (`S = I` at the kinks of the continuous force), with
/// stiffness `κ` beyond `q = d` and 1 below, starting on the side of `x0`.
pub fn bilinear_monodromy(
    s: &Bilinear,
    x0: &[f64],
    events: &[orbit::EventRecord],
    t: f64,
) -> DMatrix<f64> {
    let mut phi = DMatrix::identity(2, 2);
    let mut t_prev = 0.0;
    let mut beyond = x0[0] >= s.d;
    for e in events {
        let k = if beyond { s.kappa } else { 1.0 };
        phi = exp_oscillator(k, 2.0 * s.zeta, e.time - t_prev) * phi;
        t_prev = e.time;
        beyond = !beyond;
    }
    let k = if beyond { s.kappa } else { 1.0 };
    exp_oscillator(k, 2.0 * s.zeta, t - t_prev) * phi
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
