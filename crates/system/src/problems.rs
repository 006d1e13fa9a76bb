//! Shared reference problems of the workspace, written once against [`SecondOrderSystem`] so
//! that benches, examples and peer comparisons of different crates solve the same equations.

use math::DetMath;
use nalgebra::DMatrix;

use crate::{SecondOrderSystem, SystemError};

/// The forced Duffing oscillator `q'' + 2ζ q' + q + γ q³ = F cos ωt` of the HBM and orbit
/// tests (one-harmonic frequency response with two folds, backbone, named-parameter
/// continuation in `"force"` and `"gamma"`), with the exact force Jacobian `∂g/∂q = 3γq²`.
///
/// ```
/// use geardyn_system::{SecondOrderSystem, problems::Duffing};
/// let mut d = Duffing { zeta: 0.05, gamma: 1.0, force: 0.3, omega: 1.2 };
/// d.set_parameter("gamma", 2.0)?;
/// assert_eq!(d.parameter("gamma")?, 2.0);
/// let mut g = [0.0];
/// d.nonlinear_force(0.0, &[2.0], &[0.0], &mut g);
/// assert_eq!(g[0], 16.0);
/// assert!(d.set_parameter("mass", 1.0).is_err());
/// # Ok::<(), geardyn_system::SystemError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Duffing {
    /// Damping ratio ζ.
    pub zeta: f64,
    /// Cubic stiffness γ.
    pub gamma: f64,
    /// Forcing amplitude F.
    pub force: f64,
    /// Forcing angular frequency ω (follows the base frequency).
    pub omega: f64,
}

impl Duffing {
    /// The hardening case of the HBM and orbit tests, `ζ = 0.05`, `γ = 1`, `F = 0.3`, at `ω`:
    /// its one-harmonic frequency response folds twice (near `ω ≈ 1.2` and `1.77`).
    pub const fn hardening(omega: f64) -> Self {
        Self {
            zeta: 0.05,
            gamma: 1.0,
            force: 0.3,
            omega,
        }
    }
}

impl SecondOrderSystem for Duffing {
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
    fn nonlinear_force(&self, _t: f64, q: &[f64], _qd: &[f64], g: &mut [f64]) {
        g[0] = self.gamma * q[0].powi(3);
    }
    fn force_jacobian(&self, _t: f64, q: &[f64], _qd: &[f64], a: &mut [f64], b: &mut [f64]) {
        a[0] = 3.0 * self.gamma * q[0] * q[0];
        b[0] = 0.0;
    }
    fn forcing(&self, t: f64, f: &mut [f64]) {
        f[0] = self.force * (self.omega * t).dcos();
    }
    fn set_base_frequency(&mut self, omega: f64) -> Result<(), SystemError> {
        self.omega = omega;
        Ok(())
    }
    fn set_parameter(&mut self, name: &str, value: f64) -> Result<(), SystemError> {
        match name {
            "force" => self.force = value,
            "gamma" => self.gamma = value,
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
            "force" => Ok(self.force),
            "gamma" => Ok(self.gamma),
            _ => Err(SystemError::UnknownParameter {
                name: name.to_string(),
            }),
        }
    }
}

/// The forced hardening Duffing oscillator of the HBM benches and peer comparisons,
/// `q'' + 0.1 q' + q + q³ = 0.3 cos ωt`, with the exact force Jacobian `∂g/∂q = 3q²`.
///
/// ```
/// use geardyn_system::{SecondOrderSystem, problems::BenchDuffing};
/// let d = BenchDuffing { omega: 1.2 };
/// let mut g = [0.0];
/// d.nonlinear_force(0.0, &[2.0], &[0.0], &mut g);
/// assert_eq!(g[0], 8.0);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BenchDuffing {
    /// Forcing angular frequency ω.
    pub omega: f64,
}

impl SecondOrderSystem for BenchDuffing {
    fn n_dof(&self) -> usize {
        1
    }
    fn mass(&self) -> DMatrix<f64> {
        DMatrix::identity(1, 1)
    }
    fn damping(&self) -> DMatrix<f64> {
        DMatrix::from_element(1, 1, 0.1)
    }
    fn stiffness(&self) -> DMatrix<f64> {
        DMatrix::identity(1, 1)
    }
    fn nonlinear_force(&self, _t: f64, q: &[f64], _qd: &[f64], g: &mut [f64]) {
        g[0] = q[0].powi(3);
    }
    fn force_jacobian(&self, _t: f64, q: &[f64], _qd: &[f64], a: &mut [f64], b: &mut [f64]) {
        a[0] = 3.0 * q[0] * q[0];
        b[0] = 0.0;
    }
    fn forcing(&self, t: f64, f: &mut [f64]) {
        f[0] = 0.3 * (self.omega * t).dcos();
    }
    fn set_base_frequency(&mut self, omega: f64) -> Result<(), SystemError> {
        self.omega = omega;
        Ok(())
    }
}
