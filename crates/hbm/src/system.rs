//! The system trait: `M q'' + C q' + K q + g(t, q, q') = f(t)`.

use crate::HbmError;
use nalgebra::DMatrix;

/// An `n`-DOF second-order system `M q'' + C q' + K q + g(t, q, q') = f(t)`.
///
/// `M`, `C`, `K` are constant matrices; everything time-periodic (parametric stiffness,
/// transmission errors, …) and everything nonlinear lives in `g` and `f`, which must be periodic
/// in `t` with the period `2π/ω` of the harmonic balance base frequency `ω`.
///
/// Only [`n_dof`](Self::n_dof), [`mass`](Self::mass), [`damping`](Self::damping),
/// [`nonlinear_force`](Self::nonlinear_force) and [`forcing`](Self::forcing) are required.
/// [`force_jacobian`](Self::force_jacobian) defaults to central finite differences of
/// `nonlinear_force` (correct but slower and allocating; override it for speed and accuracy).
/// [`set_parameter`](Self::set_parameter) makes a named model parameter available to
/// continuation and sweeps.
pub trait SecondOrderSystem {
    /// Number of degrees of freedom `n`.
    fn n_dof(&self) -> usize;
    /// Mass matrix `M` (`n × n`, invertible).
    fn mass(&self) -> DMatrix<f64>;
    /// Damping matrix `C` (`n × n`).
    fn damping(&self) -> DMatrix<f64>;
    /// Linear stiffness matrix `K` (`n × n`); zero by default (put it in `g` or here).
    fn stiffness(&self) -> DMatrix<f64> {
        DMatrix::zeros(self.n_dof(), self.n_dof())
    }
    /// Nonlinear (and/or time-varying) force `g(t, q, q')`, written into `g` (length `n`).
    fn nonlinear_force(&self, t: f64, q: &[f64], qd: &[f64], g: &mut [f64]);
    /// External forcing `f(t)`, written into `f` (length `n`).
    fn forcing(&self, t: f64, f: &mut [f64]);
    /// Jacobians `∂g/∂q` and `∂g/∂q'`, row-major `n × n` (`dg_dq[i*n + j] = ∂g_i/∂q_j`).
    ///
    /// Default: central finite differences of [`nonlinear_force`](Self::nonlinear_force).
    fn force_jacobian(&self, t: f64, q: &[f64], qd: &[f64], dg_dq: &mut [f64], dg_dqd: &mut [f64]) {
        finite_difference_force_jacobian(self, t, q, qd, dg_dq, dg_dqd);
    }
    /// Told the harmonic balance base frequency `ω` whenever a [`HbmProblem`](crate::HbmProblem)
    /// is built or its `ω` changes (e.g. during frequency continuation). Systems whose
    /// excitation frequency is tied to `ω` store it here; the default ignores it (then `g` and
    /// `f` must already be `2π/ω`-periodic).
    ///
    /// # Errors
    /// Implementation-defined (e.g. an `ω` the model cannot take).
    fn set_base_frequency(&mut self, omega: f64) -> Result<(), HbmError> {
        let _ = omega;
        Ok(())
    }
    /// Length `L` of the per-sample table of time-only quantities (e.g. a time-varying
    /// stiffness and backlash) that [`nonlinear_force_tabulated`](Self::nonlinear_force_tabulated)
    /// and [`force_jacobian_tabulated`](Self::force_jacobian_tabulated) read. Default 0: no table.
    ///
    /// A [`HbmProblem`](crate::HbmProblem) fills the table once per problem and base frequency
    /// (at construction, [`set_base_frequency`](Self::set_base_frequency) and
    /// [`set_parameter`](Self::set_parameter)) instead of re-evaluating the time functions at
    /// every residual and Jacobian.
    fn time_table_len(&self) -> usize {
        0
    }
    /// Fill `row` (length [`time_table_len`](Self::time_table_len)) with the time-only
    /// quantities at time `t`. Default: nothing.
    fn fill_time_table(&self, t: f64, row: &mut [f64]) {
        let _ = (t, row);
    }
    /// [`nonlinear_force`](Self::nonlinear_force) with the row that
    /// [`fill_time_table`](Self::fill_time_table) wrote for the same `t`; must give the same
    /// result. Default: ignores the row.
    fn nonlinear_force_tabulated(&self, t: f64, row: &[f64], q: &[f64], qd: &[f64], g: &mut [f64]) {
        let _ = row;
        self.nonlinear_force(t, q, qd, g);
    }
    /// [`force_jacobian`](Self::force_jacobian) with the row of
    /// [`fill_time_table`](Self::fill_time_table) for the same `t`; must give the same result.
    /// Default: ignores the row.
    fn force_jacobian_tabulated(
        &self,
        t: f64,
        row: &[f64],
        q: &[f64],
        qd: &[f64],
        dg_dq: &mut [f64],
        dg_dqd: &mut [f64],
    ) {
        let _ = row;
        self.force_jacobian(t, q, qd, dg_dq, dg_dqd);
    }
    /// Set a named parameter (for continuation in a model parameter). Default: unknown.
    fn set_parameter(&mut self, name: &str, value: f64) -> Result<(), HbmError> {
        let _ = value;
        Err(HbmError::UnknownParameter {
            name: name.to_string(),
        })
    }
    /// Read a named parameter. Default: unknown.
    fn parameter(&self, name: &str) -> Result<f64, HbmError> {
        Err(HbmError::UnknownParameter {
            name: name.to_string(),
        })
    }
}

/// Central finite-difference Jacobians of `g` (the default of
/// [`SecondOrderSystem::force_jacobian`]); step `6e-6 (1 + |x|)`.
pub fn finite_difference_force_jacobian<S: SecondOrderSystem + ?Sized>(
    system: &S,
    t: f64,
    q: &[f64],
    qd: &[f64],
    dg_dq: &mut [f64],
    dg_dqd: &mut [f64],
) {
    let n = q.len();
    let mut x = q.to_vec();
    let mut v = qd.to_vec();
    let mut gp = vec![0.0; n];
    let mut gm = vec![0.0; n];
    for j in 0..n {
        let h = 6e-6 * (1.0 + q[j].abs());
        x[j] = q[j] + h;
        system.nonlinear_force(t, &x, qd, &mut gp);
        x[j] = q[j] - h;
        system.nonlinear_force(t, &x, qd, &mut gm);
        x[j] = q[j];
        for i in 0..n {
            dg_dq[i * n + j] = (gp[i] - gm[i]) / (2.0 * h);
        }
        let h = 6e-6 * (1.0 + qd[j].abs());
        v[j] = qd[j] + h;
        system.nonlinear_force(t, q, &v, &mut gp);
        v[j] = qd[j] - h;
        system.nonlinear_force(t, q, &v, &mut gm);
        v[j] = qd[j];
        for i in 0..n {
            dg_dqd[i * n + j] = (gp[i] - gm[i]) / (2.0 * h);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Cubic;
    impl SecondOrderSystem for Cubic {
        fn n_dof(&self) -> usize {
            1
        }
        fn mass(&self) -> DMatrix<f64> {
            DMatrix::identity(1, 1)
        }
        fn damping(&self) -> DMatrix<f64> {
            DMatrix::zeros(1, 1)
        }
        fn nonlinear_force(&self, _t: f64, q: &[f64], qd: &[f64], g: &mut [f64]) {
            g[0] = q[0].powi(3) + q[0] * qd[0];
        }
        fn forcing(&self, _t: f64, f: &mut [f64]) {
            f[0] = 0.0;
        }
    }

    #[test]
    fn default_jacobian_is_finite_differences() {
        let (mut a, mut b) = ([0.0], [0.0]);
        Cubic.force_jacobian(0.0, &[2.0], &[3.0], &mut a, &mut b);
        assert!((a[0] - (12.0 + 3.0)).abs() < 1e-6);
        assert!((b[0] - 2.0).abs() < 1e-6);
        assert!(Cubic.parameter("x").is_err());
        assert!(Cubic.set_parameter("x", 1.0).is_err());
    }
}
