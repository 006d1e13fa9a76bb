//! The workspace's one classical fourth-order Runge–Kutta step.
//!
//! For a first-order system `y' = F(t, y)` and a step `h` from `(t, y)`:
//!
//! ```text
//! k₁ = F(t, y)
//! k₂ = F(t + h/2, y + (h/2) k₁)
//! k₃ = F(t + h/2, y + (h/2) k₂)
//! k₄ = F(t + h,   y + h k₃)
//! y(t + h) ≈ y + (h/6) (k₁ + 2 k₂ + 2 k₃ + k₄)
//! ```
//!
//! with a local error `O(h⁵)` and a global error `O(h⁴)`. The first stage `k₁` is passed in by
//! the caller, so that a stepper may reuse a derivative it already has (the end-point derivative
//! of the previous step for a dense-output interpolant, a cached linear operator for a
//! variational equation). The arithmetic, in this order, is the one every engine uses: the
//! time stepper's fixed-step method (`geardyn-timestep`), the fixed-step models and the
//! monodromy matrix of the harmonic-balance stability (`geardyn-hbm`).
//!
//! ```
//! use geardyn_system::rk4::{rk4_step, Rk4Stages};
//!
//! // y' = -y from y(0) = 1: one step of h = 0.1 against e^{-0.1}
//! let rhs = |_t: f64, y: &[f64], d: &mut [f64]| d[0] = -y[0];
//! let (y, k1) = ([1.0], [-1.0]);
//! let (mut k2, mut k3, mut k4, mut stage, mut y1) = ([0.0], [0.0], [0.0], [0.0], [0.0]);
//! let stages = Rk4Stages { k1: &k1, k2: &mut k2, k3: &mut k3, k4: &mut k4, stage: &mut stage };
//! rk4_step(rhs, 0.0, 0.1, &y, stages, &mut y1);
//! assert!((y1[0] - (-0.1f64).exp()).abs() < 1e-7);
//! ```

/// The stage buffers of one [`rk4_step`], each of the state's length: `k1 = F(t, y)` (given),
/// `k2`, `k3`, `k4` (written) and the stage state (work).
#[derive(Debug)]
pub struct Rk4Stages<'a> {
    /// `F(t, y)`, supplied by the caller.
    pub k1: &'a [f64],
    /// Second stage derivative (output).
    pub k2: &'a mut [f64],
    /// Third stage derivative (output).
    pub k3: &'a mut [f64],
    /// Fourth stage derivative (output).
    pub k4: &'a mut [f64],
    /// Stage state (work buffer).
    pub stage: &'a mut [f64],
}

/// One classical RK4 step of `y' = rhs(t, y)` from `(t, y)` with step `h`; writes
/// `y(t + h)` to `y_new` and the stage derivatives to `stages` (see the module docs for the
/// scheme). `rhs(t, y, dy)` writes `F(t, y)` to `dy`. Every slice has the length of `y`; only
/// the first `y.len()` entries of longer buffers are used. Non-finite values propagate (the
/// caller checks the result).
pub fn rk4_step<F>(mut rhs: F, t: f64, h: f64, y: &[f64], stages: Rk4Stages<'_>, y_new: &mut [f64])
where
    F: FnMut(f64, &[f64], &mut [f64]),
{
    let n = y.len();
    let Rk4Stages {
        k1,
        k2,
        k3,
        k4,
        stage,
    } = stages;
    let (k1, k2, k3, k4) = (&k1[..n], &mut k2[..n], &mut k3[..n], &mut k4[..n]);
    let (stage, y_new) = (&mut stage[..n], &mut y_new[..n]);
    let half = 0.5 * h;
    for i in 0..n {
        stage[i] = y[i] + half * k1[i];
    }
    rhs(t + half, stage, k2);
    for i in 0..n {
        stage[i] = y[i] + half * k2[i];
    }
    rhs(t + half, stage, k3);
    for i in 0..n {
        stage[i] = y[i] + h * k3[i];
    }
    rhs(t + h, stage, k4);
    let sixth = h / 6.0;
    for i in 0..n {
        y_new[i] = y[i] + sixth * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn step(rhs: impl FnMut(f64, &[f64], &mut [f64]), t: f64, h: f64, y: &[f64]) -> Vec<f64> {
        let n = y.len();
        let mut rhs = rhs;
        let mut k1 = vec![0.0; n];
        rhs(t, y, &mut k1);
        let (mut k2, mut k3, mut k4, mut st, mut out) = (
            vec![0.0; n],
            vec![0.0; n],
            vec![0.0; n],
            vec![0.0; n],
            vec![0.0; n],
        );
        let stages = Rk4Stages {
            k1: &k1,
            k2: &mut k2,
            k3: &mut k3,
            k4: &mut k4,
            stage: &mut st,
        };
        rk4_step(&mut rhs, t, h, y, stages, &mut out);
        out
    }

    /// RK4 integrates a cubic in `t` exactly (it is exact for quadrature of polynomials of
    /// degree ≤ 3, Simpson's rule).
    #[test]
    fn exact_for_cubic_quadrature() {
        let f = |t: f64, _y: &[f64], d: &mut [f64]| d[0] = 3.0 * t * t - 2.0 * t + 1.0 + t * t * t;
        let (t, h) = (0.5, 0.25);
        let y1 = step(f, t, h, &[2.0]);
        let anti = |t: f64| t * t * t - t * t + t + 0.25 * t.powi(4);
        let exact = 2.0 + anti(t + h) - anti(t);
        assert!((y1[0] - exact).abs() < 1e-14, "{} vs {exact}", y1[0]);
    }

    /// Global error of the harmonic oscillator over one period falls as `h⁴` (order 4): halving
    /// `h` divides the error by 16 within 10 %.
    #[test]
    fn fourth_order_on_the_harmonic_oscillator() {
        let err = |steps: usize| {
            let h = std::f64::consts::TAU / steps as f64;
            let mut y = vec![1.0, 0.0];
            for s in 0..steps {
                y = step(
                    |_t, y: &[f64], d: &mut [f64]| {
                        d[0] = y[1];
                        d[1] = -y[0];
                    },
                    s as f64 * h,
                    h,
                    &y,
                );
            }
            ((y[0] - 1.0).powi(2) + y[1].powi(2)).sqrt()
        };
        let ratio = err(64) / err(128);
        assert!((ratio / 16.0 - 1.0).abs() < 0.1, "ratio {ratio}");
    }

    /// Stage times: `t + h/2` twice, then `t + h`.
    #[test]
    fn stage_times() {
        let mut seen = Vec::new();
        let _ = step(
            |t, _y: &[f64], d: &mut [f64]| {
                seen.push(t);
                d[0] = 0.0;
            },
            1.0,
            0.5,
            &[0.0],
        );
        assert_eq!(seen, vec![1.0, 1.25, 1.25, 1.5]);
    }
}
