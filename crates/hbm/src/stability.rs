//! Stability of periodic solutions by Floquet theory.

use crate::solution::eval_state;
use crate::{HbmError, HbmProblem, PeriodicSolution, SecondOrderSystem};
use nalgebra::DMatrix;

/// Floquet multipliers of a periodic solution and the verdict.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Stability {
    /// Floquet multipliers `μ` as `[Re μ, Im μ]`, `2n` of them.
    pub multipliers: Vec<[f64; 2]>,
    /// `max |μ|`.
    pub max_modulus: f64,
    /// `max |μ| ≤ 1 + tolerance`.
    pub stable: bool,
    /// RK4 steps per period used for the monodromy matrix.
    pub steps: usize,
}

/// Tolerance on `|μ| − 1` below which a solution counts as stable.
pub const STABILITY_TOLERANCE: f64 = 1e-6;

impl<S: SecondOrderSystem> HbmProblem<S> {
    /// Floquet stability of `solution` (which must belong to this problem's current parameters):
    /// the monodromy matrix of the variational equation
    /// `M δ'' + (C + ∂g/∂q') δ' + (K + ∂g/∂q) δ = 0` is integrated over one period with classical
    /// RK4 (`steps` per period; `None` = `max(400, 32 k_max)`), and its eigenvalues are the
    /// multipliers.
    ///
    /// Chosen over Hill's method because it works for any (sparse) basis and needs no sorting of
    /// Hill eigenvalues; RK4 must resolve the fastest linearised frequency (raise `steps` for
    /// stiff contacts).
    ///
    /// # Errors
    /// Singular mass matrix, mismatched solution, non-finite Jacobians.
    pub fn stability(
        &self,
        solution: &PeriodicSolution,
        steps: Option<usize>,
    ) -> Result<Stability, HbmError> {
        let n = self.n_dof();
        if solution.n_dof != n || solution.coefficients.len() != self.n_unknowns() {
            return Err(HbmError::DimensionMismatch {
                what: "solution coefficients",
                expected: self.n_unknowns(),
                got: solution.coefficients.len(),
            });
        }
        let steps = steps
            .unwrap_or((32 * solution.basis.max_harmonic()).max(400))
            .max(4);
        let (m, c, k) = self.matrices();
        let minv = m.clone().lu().try_inverse().ok_or(HbmError::Singular {
            what: "mass matrix",
        })?;
        let nn = 2 * n;
        let period = solution.period();
        let h = period / steps as f64;
        let (mut q, mut qd) = (vec![0.0; n], vec![0.0; n]);
        let (mut jq, mut jv) = (vec![0.0; n * n], vec![0.0; n * n]);
        let mut a_at = |t: f64| -> Result<DMatrix<f64>, HbmError> {
            eval_state(
                &solution.basis,
                n,
                solution.omega,
                &solution.coefficients,
                t,
                &mut q,
                &mut qd,
            );
            self.system().force_jacobian(t, &q, &qd, &mut jq, &mut jv);
            if jq.iter().chain(jv.iter()).any(|x| !x.is_finite()) {
                return Err(HbmError::NonFinite {
                    what: "force Jacobian",
                    time: t,
                });
            }
            let kt = DMatrix::from_fn(n, n, |i, j| k[(i, j)] + jq[i * n + j]);
            let ct = DMatrix::from_fn(n, n, |i, j| c[(i, j)] + jv[i * n + j]);
            let lower_k = -(&minv * kt);
            let lower_c = -(&minv * ct);
            let mut a = DMatrix::zeros(nn, nn);
            for i in 0..n {
                a[(i, n + i)] = 1.0;
                for j in 0..n {
                    a[(n + i, j)] = lower_k[(i, j)];
                    a[(n + i, n + j)] = lower_c[(i, j)];
                }
            }
            Ok(a)
        };
        let mut phi = DMatrix::<f64>::identity(nn, nn);
        let mut a0 = a_at(0.0)?;
        for s in 0..steps {
            let t = s as f64 * h;
            let am = a_at(t + 0.5 * h)?;
            let a1 = a_at(t + h)?;
            let k1 = &a0 * &phi;
            let k2 = &am * (&phi + &k1 * (0.5 * h));
            let k3 = &am * (&phi + &k2 * (0.5 * h));
            let k4 = &a1 * (&phi + &k3 * h);
            phi += (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0);
            a0 = a1;
        }
        let mu = phi.complex_eigenvalues();
        let multipliers: Vec<[f64; 2]> = mu.iter().map(|z| [z.re, z.im]).collect();
        let max_modulus = mu.iter().map(|z| z.norm()).fold(0.0, f64::max);
        Ok(Stability {
            multipliers,
            max_modulus,
            stable: max_modulus <= 1.0 + STABILITY_TOLERANCE,
            steps,
        })
    }
}
