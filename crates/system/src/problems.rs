//! Shared reference problems of the workspace, written once against [`SecondOrderSystem`] so
//! that benches, examples and peer comparisons of different crates solve the same equations.

use nalgebra::DMatrix;

use crate::{SecondOrderSystem, SystemError};

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
        f[0] = 0.3 * (self.omega * t).cos();
    }
    fn set_base_frequency(&mut self, omega: f64) -> Result<(), SystemError> {
        self.omega = omega;
        Ok(())
    }
}
