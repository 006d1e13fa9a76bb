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
//! with `err_old = max(err, 10⁻⁴)` after each accepted step. Two `pow` calls per step cost
//! ~11 % of a Liu integration (profile of issue 38) and, through the C math library, made the
//! step sequence depend on the platform's `pow`. Here the same factor is computed as
//!
//! ```text
//! q = 2^(α·log₂ err − β·log₂ err_old)
//! ```
//!
//! with `log₂ err_old` kept from the last accepted step (one `log₂` and at most one `2^x` per
//! step), both by short polynomial kernels of IEEE `+`, `×`, `÷` and bit operations only:
//! deterministic on every platform, relative error of `q` below `10⁻⁸` (tested against `powf`),
//! monotone in `err`. Where the factor is clamped (`q/safe` outside `[1/10, 5]`), `2^x` is
//! skipped: the comparison is made on the exponent. The controller's guarantees are those of the
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
    /// Largest shrink of the next step after one step, `h/h_new ≤ max_shrink` (`1/fac1`).
    pub(crate) max_shrink: f64,
    /// Largest growth, `h_new/h ≤ max_growth` (`fac2`).
    pub(crate) max_growth: f64,
}

/// DOPRI5's controller (`dopri5.f` defaults: `β = 0.04`, `fac1 = 0.2`, `fac2 = 10`).
pub(crate) const DOPRI5_CONTROL: ControlParams = ControlParams {
    alpha: 1.0 / 5.0 - 0.75 * 0.04,
    beta: 0.04,
    max_shrink: 5.0,
    max_growth: 10.0,
};

/// DOP853's controller (`dop853.f` defaults: `β = 0`, `fac1 = 0.333`, `fac2 = 6`).
pub(crate) const DOP853_CONTROL: ControlParams = ControlParams {
    alpha: 1.0 / 8.0,
    beta: 0.0,
    max_shrink: 1.0 / 0.333,
    max_growth: 6.0,
};

/// Hairer's PI step-size controller (module docs), with the exponent arithmetic in `log₂`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PiController {
    p: ControlParams,
    /// `log₂ max(err_old, 10⁻⁴)`.
    log2_err_old: f64,
    /// `log₂(safe/max_growth)`: at or below it the factor clamps to the largest growth.
    lo: f64,
    /// `log₂(safe·max_shrink)`: at or above it the factor clamps to the largest shrink.
    hi: f64,
}

/// Safety factor.
const SAFE: f64 = 0.9;

impl PiController {
    /// A controller with the constants `p`.
    pub(crate) fn new(p: ControlParams) -> Self {
        PiController {
            p,
            log2_err_old: log2_pos(1e-4),
            // q/safe ≤ 1/max_growth ⟺ log₂ q ≤ log₂(safe/max_growth); q/safe ≥ max_shrink ⟺
            // log₂ q ≥ log₂(safe·max_shrink)
            lo: log2_pos(SAFE / p.max_growth),
            hi: log2_pos(SAFE * p.max_shrink),
        }
    }

    /// The factor `h/h_new` after a step with error norm `err` (finite, ≥ 0), and whether the
    /// step is accepted (`err ≤ 1`). On acceptance the controller remembers `err`.
    #[inline]
    pub(crate) fn step(&mut self, err: f64) -> (f64, bool) {
        let l = log2_pos(err);
        if err > 1.0 {
            // rejected: h /= min(max_shrink, err^α / safe); err^α > 1 here
            let la = self.p.alpha * l;
            let fac = if la >= self.hi {
                self.p.max_shrink
            } else {
                exp2(la) / SAFE
            };
            return (fac, false);
        }
        let lq = self.p.alpha * l - self.p.beta * self.log2_err_old;
        let fac = if lq <= self.lo {
            1.0 / self.p.max_growth
        } else if lq >= self.hi {
            self.p.max_shrink
        } else {
            exp2(lq) / SAFE
        };
        // err_old = max(err, 1e-4)
        self.log2_err_old = l.max(log2_pos(1e-4));
        (fac, true)
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
            let (got, ok) = c.step(err);
            assert_eq!(ok, accepted);
            assert!(
                (got / want - 1.0).abs() < 2e-8,
                "err {err}: {got} vs {want}"
            );
            assert!((0.1..=5.0).contains(&got));
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
            let (got, _) = c.step(err);
            assert!(
                (got / want - 1.0).abs() < 2e-8,
                "err {err}: {got} vs {want}"
            );
            err *= 1.0913;
        }
    }

    /// Monotone in `err` at a fixed history: a larger error never gives a longer step.
    #[test]
    fn factor_is_monotone() {
        // within each branch (accepted: err ≤ 1, rejected: err > 1; the exact controller also
        // jumps at err = 1, where the history term stops counting)
        for (from, to) in [(1e-20_f64, 1.0), (1.0 + 1e-12, 1e20)] {
            let mut prev = 0.0;
            let mut e = from;
            while e <= to {
                let mut c = PiController::new(DOPRI5_CONTROL);
                let (f, _) = c.step(e);
                assert!(f >= prev, "{e}: {f} < {prev}");
                prev = f;
                e *= 1.01;
            }
        }
    }
}
