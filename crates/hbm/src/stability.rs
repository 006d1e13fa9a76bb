//! Stability of periodic solutions by Floquet theory.

use crate::solution::eval_state;
use crate::{HbmError, HbmProblem, PeriodicSolution, SecondOrderSystem};
use nalgebra::DMatrix;

/// Floquet multipliers of a periodic solution (`2n` of them, `[Re μ, Im μ]`) and the verdict:
/// the workspace's one stability type, `system::Stability` (also `orbit::Stability`).
pub use system::Stability;

/// Tolerance on `|μ| − 1` below which a solution counts as stable: the workspace's one
/// threshold ([`system::STABILITY_TOLERANCE`]).
pub use system::STABILITY_TOLERANCE;

impl<S: SecondOrderSystem> HbmProblem<S> {
    /// Floquet stability of `solution` (which must belong to this problem's current parameters):
    /// the monodromy matrix of the variational equation
    /// `M δ'' + (C + ∂g/∂q') δ' + (K + ∂g/∂q) δ = 0` is integrated over one period with the
    /// workspace's classical RK4 (`geardyn_system::rk4`) (`steps` per period; `None` = `max(400, 32 k_max)`), and its eigenvalues are the
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
        // Φ' = A(t) Φ, one RK4 step of the workspace (`geardyn_system::rk4`) per `h` on Φ's
        // column-major entries. A(t) is evaluated once per distinct time: the stages at
        // `t + h/2` share it, and the end of one step is the start of the next.
        let mut phi = DMatrix::<f64>::identity(nn, nn);
        let mut a0 = a_at(0.0)?;
        let mut failure = None;
        let mut cached: Option<(u64, DMatrix<f64>)> = None;
        let (mut k2, mut k3, mut k4, mut stage) = (
            vec![0.0; nn * nn],
            vec![0.0; nn * nn],
            vec![0.0; nn * nn],
            vec![0.0; nn * nn],
        );
        let mut next = vec![0.0; nn * nn];
        for s in 0..steps {
            let t = s as f64 * h;
            let mut k1 = DMatrix::<f64>::zeros(nn, nn);
            system::numeric::product_into(&a0, &phi, &mut k1);
            let rhs = |t: f64, y: &[f64], d: &mut [f64]| {
                if cached.as_ref().is_none_or(|(bits, _)| *bits != t.to_bits()) {
                    match a_at(t) {
                        Ok(a) => cached = Some((t.to_bits(), a)),
                        Err(e) => {
                            failure.get_or_insert(e);
                            d.fill(f64::NAN);
                            return;
                        }
                    }
                }
                if let Some((_, a)) = &cached {
                    let product = a * DMatrix::from_column_slice(nn, nn, y);
                    d.copy_from_slice(product.as_slice());
                }
            };
            let stages = system::rk4::Rk4Stages {
                k1: k1.as_slice(),
                k2: &mut k2,
                k3: &mut k3,
                k4: &mut k4,
                stage: &mut stage,
            };
            system::rk4::rk4_step(rhs, t, h, phi.as_slice(), stages, &mut next);
            if let Some(e) = failure.take() {
                return Err(e);
            }
            phi.as_mut_slice().copy_from_slice(&next);
            if let Some((_, a1)) = cached.take() {
                a0 = a1;
            }
        }
        let mu = phi.complex_eigenvalues();
        let multipliers: Vec<[f64; 2]> = mu.iter().map(|z| [z.re, z.im]).collect();
        Ok(Stability::from_multipliers(multipliers))
    }
}
