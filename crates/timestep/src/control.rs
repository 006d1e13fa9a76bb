//! The step-size controller of the adaptive methods, without `pow`.
//!
//! Hairer's PI controller (DOPRI5, Hairer & Wanner, Solving ODEs I, §II.4, and the `dopri5.f`
//! defaults) computes, from the scaled error norm `err` of a step and the norm `err_old` of the
//! last accepted step,
//!
//! ```text
//! q   = err^α / err_old^β            (α = 1/5 − 0.75 β, β = 0.04)
//! fac = clamp(q / safe, 1/10, 5)     (safe = 0.9)
//! h_new = h / fac                    (accepted: err ≤ 1)
//! h_new = h / min(5, err^α / safe)   (rejected: err > 1)
//! ```
//!
//! (`1/10` and `5` are `1/fac2` and `1/fac1` of `dopri5.f`.)
//!
//! with `err_old = max(err, 10⁻⁴)` after each accepted step. Two `pow` calls per step cost
//! ~11 % of a Liu integration (profile of issue 38) and, through the C math library, made the
//! step sequence depend on the platform's `pow`. Here the same factor is computed as
//!
//! ```text
//! q = 2^(α·log₂ err − β·log₂ err_old)
//! ```
//!
//! with `log₂ err_old` kept from the last accepted step (one `log₂` and at most one `2^x` per
//! step), both by short polynomial kernels of IEEE `+`, `×` and bit operations only
//! (`system::numeric::log2_approx`, `exp2_approx`): deterministic on every platform, relative
//! error of `q` below `10⁻⁸` (tested against `powf`), monotone in `err`. Where the factor is
//! clamped (`q/safe` outside `[1/10, 5]`), `2^x` is skipped: the comparison is made on the
//! exponent.
//!
//! Every step waits on this computation (the next step's stage times depend on `h_new`), so
//! its chain of dependent operations is kept short and free of divisions: `log₂` by a table and
//! a degree-4 polynomial, and the controller returns the *ratio* `h_new/h = 1/fac` directly,
//!
//! ```text
//! h_new/h = 2^(log₂ safe − log₂ q),   clamped to [fac1, fac2] = [1/5, 10]
//! ```
//!
//! so that `/ safe` and `h / fac` become one `2^x` and one product. The controller's guarantees are those of the
//! exact form: the factor stays within `[1/10, 5]`, a rejected step shrinks by at least
//! `safe⁻¹·err^α > 1` (capped at 5), and the step after a rejection does not grow.

use system::numeric::{exp2_approx as exp2, log2_approx as log2_pos};

/// The constants of a controller (Hairer's `beta`, `fac1`, `fac2` of DOPRI5/DOP853).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ControlParams {
    /// `α`, the exponent of the current error: `1/q − 0.75 β` for an error estimate of order `q`
    /// (DOPRI5: `1/5 − 0.75·0.04`; DOP853: `1/8`).
    pub(crate) alpha: f64,
    /// `β`, the exponent of the last accepted error (0: a pure I controller, as DOP853's).
    pub(crate) beta: f64,
    /// Smallest ratio of the next step to this one, `h_new/h ≥ fac1`.
    pub(crate) fac1: f64,
    /// Largest ratio, `h_new/h ≤ fac2`.
    pub(crate) fac2: f64,
}

/// DOPRI5's controller (`dopri5.f` defaults: `β = 0.04`, `fac1 = 0.2`, `fac2 = 10`).
pub(crate) const DOPRI5_CONTROL: ControlParams = ControlParams {
    alpha: 1.0 / 5.0 - 0.75 * 0.04,
    beta: 0.04,
    fac1: 0.2,
    fac2: 10.0,
};

/// DOP853's controller (`dop853.f` defaults: `β = 0`, `fac1 = 0.333`, `fac2 = 6`).
pub(crate) const DOP853_CONTROL: ControlParams = ControlParams {
    alpha: 1.0 / 8.0,
    beta: 0.0,
    fac1: 0.333,
    fac2: 6.0,
};

/// Hairer's PI step-size controller (module docs), with the exponent arithmetic in `log₂`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PiController {
    p: ControlParams,
    /// `log₂ max(err_old, 10⁻⁴)`.
    log2_err_old: f64,
    /// `log₂(safe/fac2)`: at or below it (`log₂ q`) the ratio clamps to `fac2`.
    lo: f64,
    /// `log₂(safe/fac1)`: at or above it the ratio clamps to `fac1`.
    hi: f64,
    /// `log₂ safe`.
    log2_safe: f64,
    /// `log₂ 10⁻⁴`, the floor of `log₂ err_old`.
    log2_floor: f64,
    /// `α/2`: the exponent applied to `log₂ err²`.
    half_alpha: f64,
}

/// Safety factor.
const SAFE: f64 = 0.9;

impl PiController {
    /// A controller with the constants `p`.
    pub(crate) fn new(p: ControlParams) -> Self {
        PiController {
            p,
            log2_err_old: log2_pos(1e-4),
            // safe/q ≥ fac2 ⟺ log₂ q ≤ log₂(safe/fac2); safe/q ≤ fac1 ⟺ log₂ q ≥ log₂(safe/fac1)
            lo: log2_pos(SAFE / p.fac2),
            hi: log2_pos(SAFE / p.fac1),
            log2_safe: log2_pos(SAFE),
            log2_floor: log2_pos(1e-4),
            half_alpha: 0.5 * p.alpha,
        }
    }

    /// The ratio `h_new/h` after a step whose error norm squared is `err2` (finite, ≥ 0: the
    /// steppers return `err²`), and whether the step is accepted (`err ≤ 1`). On acceptance the
    /// controller remembers `err`.
    #[inline]
    pub(crate) fn step(&mut self, err2: f64) -> (f64, bool) {
        // α log₂ err = (α/2) log₂ err²: the halving folded into the constant
        let l2 = log2_pos(err2);
        if err2 > 1.0 {
            // rejected: h_new/h = max(fac1, safe/err^α); err^α > 1 here
            let la = self.half_alpha * l2;
            let ratio = if la >= self.hi {
                self.p.fac1
            } else {
                exp2(self.log2_safe - la)
            };
            return (ratio, false);
        }
        let lq = self.half_alpha * l2 - self.p.beta * self.log2_err_old;
        let ratio = if lq <= self.lo {
            self.p.fac2
        } else if lq >= self.hi {
            self.p.fac1
        } else {
            exp2(self.log2_safe - lq)
        };
        // err_old = max(err, 1e-4)
        self.log2_err_old = (0.5 * l2).max(self.log2_floor);
        (ratio, true)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use math::DetMath;

    /// The factor against the exact `pow` form of DOPRI5's controller over a run of errors.
    #[test]
    fn factor_matches_the_pow_form() {
        let (beta, safe) = (0.04, 0.9);
        let expo1 = 0.2 - 0.75 * beta;
        let mut c = PiController::new(DOPRI5_CONTROL);
        let mut facold: f64 = 1e-4;
        let mut err = 1e-12_f64;
        let mut n = 0;
        while err < 1e3 {
            let fac11 = err.dpowf(expo1);
            let (want, accepted) = if err > 1.0 {
                (5.0_f64.min(fac11 / safe), false)
            } else {
                let f = 0.1_f64.max(5.0_f64.min(fac11 / facold.dpowf(beta) / safe));
                facold = err.max(1e-4);
                (f, true)
            };
            let (ratio, ok) = c.step(err * err);
            let got = 1.0 / ratio;
            assert_eq!(ok, accepted);
            assert!(
                (got / want - 1.0).abs() < 2e-8,
                "err {err}: {got} vs {want}"
            );
            assert!((0.2..=10.0).contains(&ratio));
            err *= 1.0913;
            n += 1;
        }
        assert!(n > 300);
    }

    /// DOP853's pure I controller against `err^(1/8)`.
    #[test]
    fn dop853_factor_matches_the_eighth_root() {
        let mut c = PiController::new(DOP853_CONTROL);
        let mut err = 1e-12_f64;
        while err < 1e3 {
            let fac11 = err.sqrt().sqrt().sqrt();
            let want = if err > 1.0 {
                (1.0_f64 / 0.333).min(fac11 / 0.9)
            } else {
                (1.0_f64 / 6.0).max((1.0_f64 / 0.333).min(fac11 / 0.9))
            };
            let (ratio, _) = c.step(err * err);
            let got = 1.0 / ratio;
            assert!(
                (got / want - 1.0).abs() < 2e-8,
                "err {err}: {got} vs {want}"
            );
            err *= 1.0913;
        }
    }

    /// Monotone in `err` at a fixed history: a larger error never gives a longer step (a
    /// smaller ratio `h_new/h`).
    #[test]
    fn factor_is_monotone() {
        // within each branch (accepted: err ≤ 1, rejected: err > 1; the exact controller also
        // jumps at err = 1, where the history term stops counting)
        for (from, to) in [(1e-20_f64, 1.0), (1.0 + 1e-12, 1e20)] {
            let mut prev = f64::INFINITY;
            let mut e = from;
            while e <= to {
                let mut c = PiController::new(DOPRI5_CONTROL);
                let (f, _) = c.step(e * e);
                assert!(f <= prev, "{e}: {f} > {prev}");
                prev = f;
                e *= 1.01;
            }
        }
    }
}
