//! Impact laws: state resets `x⁺ = R(t, x⁻)` applied at located events.

use crate::error::{Result, check};
use nalgebra::DMatrix;

/// A reset map applied at some events (an impact law with restitution, a velocity jump).
///
/// The state is `x = (q, q')` (length `2n`). At a located crossing of an event `i` with
/// [`is_impact`](Self::is_impact)`(i)`, the flow continues from `x⁺ = R(t, x⁻)`
/// ([`reset`](Self::reset)), and the monodromy is composed with the saltation matrix
///
/// ```text
/// S = G + (f⁺ − G f⁻) ∇hᵀ / (∇hᵀ f⁻ + ∂h/∂t),   G = ∂R/∂x,  f⁻ = f(t, x⁻),  f⁺ = f(t, x⁺)
/// ```
///
/// (Müller 1995; Leine & Nijmeijer 2004, Sec. 7.2). Events that are not impacts only switch the
/// force law (`G = I`).
pub trait ImpactLaw {
    /// True if event `index` resets the state.
    fn is_impact(&self, index: usize) -> bool;
    /// Writes `x⁺ = R(t, x⁻)` into `out` (both of length `2n`).
    fn reset(&self, index: usize, t: f64, x: &[f64], out: &mut [f64]);
    /// `G = ∂R/∂x` (`2n × 2n`). Default: central finite differences of [`reset`](Self::reset).
    fn reset_jacobian(&self, index: usize, t: f64, x: &[f64], jac: &mut DMatrix<f64>) {
        let m = x.len();
        let mut xp = x.to_vec();
        let (mut rp, mut rm) = (vec![0.0; m], vec![0.0; m]);
        for j in 0..m {
            let h = 1e-7 * (1.0 + x[j].abs());
            xp[j] = x[j] + h;
            self.reset(index, t, &xp, &mut rp);
            xp[j] = x[j] - h;
            self.reset(index, t, &xp, &mut rm);
            xp[j] = x[j];
            for i in 0..m {
                jac[(i, j)] = (rp[i] - rm[i]) / (2.0 * h);
            }
        }
    }
}

/// Newton's impact law on one coordinate: `q'_c⁺ = −r q'_c⁻` at the listed events (a rigid
/// stop; `r ∈ [0, 1]` the coefficient of restitution). `G = diag(1, …, −r, …, 1)`.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Restitution {
    coordinate: usize,
    coefficient: f64,
    events: Vec<usize>,
}

impl Restitution {
    /// Restitution `r` on coordinate `coordinate` at the events `events`.
    ///
    /// # Errors
    /// `r` outside `[0, 1]` or not finite.
    pub fn new(coordinate: usize, r: f64, events: Vec<usize>) -> Result<Self> {
        check(
            r.is_finite() && (0.0..=1.0).contains(&r),
            "restitution coefficient",
            "in [0, 1]",
            r,
        )?;
        Ok(Self {
            coordinate,
            coefficient: r,
            events,
        })
    }
    /// The coefficient of restitution.
    pub fn coefficient(&self) -> f64 {
        self.coefficient
    }
}

impl ImpactLaw for Restitution {
    fn is_impact(&self, index: usize) -> bool {
        self.events.contains(&index)
    }
    fn reset(&self, _index: usize, _t: f64, x: &[f64], out: &mut [f64]) {
        out.copy_from_slice(x);
        let n = x.len() / 2;
        if let Some(v) = out.get_mut(n + self.coordinate) {
            *v *= -self.coefficient;
        }
    }
    fn reset_jacobian(&self, _index: usize, _t: f64, x: &[f64], jac: &mut DMatrix<f64>) {
        jac.fill_with_identity();
        let n = x.len() / 2;
        if n + self.coordinate < x.len() {
            jac[(n + self.coordinate, n + self.coordinate)] = -self.coefficient;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn restitution_reset_and_jacobian() {
        let law = Restitution::new(1, 0.7, vec![2]).unwrap();
        assert!(law.is_impact(2) && !law.is_impact(0));
        let x = [0.1, 0.2, 3.0, -4.0];
        let mut out = [0.0; 4];
        law.reset(2, 0.0, &x, &mut out);
        assert_eq!(out[..3], [0.1, 0.2, 3.0]);
        assert!((out[3] - 2.8).abs() < 1e-15);
        let mut g = DMatrix::zeros(4, 4);
        law.reset_jacobian(2, 0.0, &x, &mut g);
        // the finite-difference default agrees with the exact Jacobian
        struct Fd(Restitution);
        impl ImpactLaw for Fd {
            fn is_impact(&self, i: usize) -> bool {
                self.0.is_impact(i)
            }
            fn reset(&self, i: usize, t: f64, x: &[f64], out: &mut [f64]) {
                self.0.reset(i, t, x, out)
            }
        }
        let mut gfd = DMatrix::zeros(4, 4);
        Fd(law.clone()).reset_jacobian(2, 0.0, &x, &mut gfd);
        assert!((&g - &gfd).amax() < 1e-8);
        assert!((g[(3, 3)] + 0.7).abs() < 1e-15);
        assert!((law.coefficient() - 0.7).abs() < 1e-15);
    }
}
