//! The dead-zone (backlash) function f(x; b) of Liu 2021 Eq. (12) / Yu 2021 Eq. (14).

use crate::error::{Error, finite, non_negative, positive};

/// Which side of the dead zone a relative displacement lies on.
///
/// Convention at the corners: `|x| = b` counts as [`ContactRegion::Separated`] (Liu Eq. 12
/// writes the zero branch on the closed interval `−b ≤ q ≤ b`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum ContactRegion {
    /// `x > b`: drive-side flanks in contact, `f = x − b`.
    DriveSide,
    /// `|x| ≤ b`: teeth separated (inside the gap), `f = 0`.
    Separated,
    /// `x < −b`: back-side flanks in contact, `f = x + b`.
    BackSide,
}

impl ContactRegion {
    /// `true` when the teeth touch (either flank).
    #[inline]
    pub fn in_contact(self) -> bool {
        !matches!(self, ContactRegion::Separated)
    }
}

/// Negative half-gaps are treated as zero by the unchecked hot-path functions.
#[inline(always)]
fn clamp_gap(b: f64) -> f64 {
    if b < 0.0 { 0.0 } else { b }
}

/// Dead-zone function f(x; b) (Liu Eq. 12, Yu Eq. 14):
///
/// ```text
///            ⎧ x − b   x >  b
/// f(x; b) =  ⎨ 0       −b ≤ x ≤ b
///            ⎩ x + b   x < −b
/// ```
///
/// `b` is the half gap (Liu: "half of tooth backlash"; Yu: `B(t)`), in the units of `x`.
/// Hot path: `#[inline]`, no allocation, no branch on errors. A negative `b` is treated as 0
/// (no preload model); for checked evaluation use [`try_dead_zone`] or [`DeadZone::new`].
///
/// ```
/// use geardyn_backlash::dead_zone;
/// assert_eq!(dead_zone(0.5, 1.0), 0.0);
/// assert_eq!(dead_zone(3.0, 1.0), 2.0);
/// assert_eq!(dead_zone(-3.0, 1.0), -2.0);
/// ```
#[inline]
pub fn dead_zone(x: f64, b: f64) -> f64 {
    let b = clamp_gap(b);
    if x > b {
        x - b
    } else if x < -b {
        x + b
    } else {
        0.0
    }
}

/// ∂f/∂x of the exact dead zone: 1 in contact, 0 inside the gap.
///
/// Corner convention: at `x = ±b` (with `b > 0`) the derivative is 0, the value of the closed
/// separated interval (Liu Eq. 12). For `b ≤ 0` the function is the identity and the derivative
/// is 1 everywhere, including `x = 0`.
#[inline]
pub fn dead_zone_dx(x: f64, b: f64) -> f64 {
    let b = clamp_gap(b);
    if b <= 0.0 || x > b || x < -b {
        1.0
    } else {
        0.0
    }
}

/// ∂f/∂b of the exact dead zone: −1 on the drive side, +1 on the back side, 0 inside the gap
/// (and 0 at the corners, same convention as [`dead_zone_dx`]). Needed when `b` depends on the
/// state (dynamic backlash, Yu Eq. 11): ∂f/∂q = f_x ∂x/∂q + f_b ∂b/∂q.
#[inline]
pub fn dead_zone_db(x: f64, b: f64) -> f64 {
    let b = clamp_gap(b);
    if x > b {
        -1.0
    } else if x < -b {
        1.0
    } else {
        0.0
    }
}

/// Region of `x` with respect to the gap `[−b, b]` (corners count as separated).
#[inline]
pub fn contact_region(x: f64, b: f64) -> ContactRegion {
    let b = clamp_gap(b);
    if x > b {
        ContactRegion::DriveSide
    } else if x < -b {
        ContactRegion::BackSide
    } else {
        ContactRegion::Separated
    }
}

/// Event functions for time steppers: `[x − b, x + b]`. A sign change of the first entry is a
/// drive-side impact/separation, of the second a back-side one.
#[inline]
pub fn switching_functions(x: f64, b: f64) -> [f64; 2] {
    let b = clamp_gap(b);
    [x - b, x + b]
}

/// Checked dead zone: `x` finite, `b` finite and `≥ 0`.
pub fn try_dead_zone(x: f64, b: f64) -> Result<f64, Error> {
    finite("x", x)?;
    non_negative("b", b)?;
    Ok(dead_zone(x, b))
}

/// Smooth ramp s(u) = (u + √(u² + ε²))/2 and its derivative, evaluated without cancellation.
#[inline(always)]
fn smooth_ramp(u: f64, eps: f64) -> (f64, f64) {
    // sqrt instead of hypot: 5x faster; overflow only for |u| > 1e154
    let h = (u * u + eps * eps).sqrt();
    if u >= 0.0 {
        (0.5 * (u + h), 0.5 * (1.0 + u / h))
    } else {
        // u + h = ε² / (h − u), no cancellation for u ≪ 0.
        let d = h - u;
        (0.5 * eps * eps / d, 0.5 * eps * eps / (h * d))
    }
}

/// How the corners of the dead zone are treated.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum Regularisation {
    /// The piecewise-linear function of Liu Eq. (12) / Yu Eq. (14) (default).
    #[default]
    Exact,
    /// Hyperbolic smoothing f_ε(x; b) = s(x − b) − s(−x − b) with s(u) = (u + √(u² + ε²))/2.
    ///
    /// Odd in `x`, C^∞, f_ε(0) = 0, and |f_ε − f| ≤ ε/2 everywhere (the maximum is at the
    /// corners); the slope goes from 0 to 1 over a band of width ~ε around `±b`. Useful for
    /// Newton/Broyden in harmonic balance, where the Jacobian jump at the corners slows
    /// convergence. `eps` is in the units of `x` (choose ε ≪ b, e.g. 1e-3·b).
    Smooth {
        /// Smoothing width ε (> 0), same units as x.
        eps: f64,
    },
}

/// Value and partial derivatives of the dead zone at one point.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct DeadZoneEval {
    /// f(x; b).
    pub f: f64,
    /// ∂f/∂x.
    pub df_dx: f64,
    /// ∂f/∂b.
    pub df_db: f64,
}

/// A dead zone with a chosen [`Regularisation`]; evaluate with any [`HalfGap`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct DeadZone {
    regularisation: Regularisation,
}

impl DeadZone {
    /// The exact dead zone (Liu Eq. 12).
    pub const EXACT: DeadZone = DeadZone {
        regularisation: Regularisation::Exact,
    };

    /// A dead zone with the given regularisation; `Smooth { eps }` needs `eps > 0`.
    pub fn new(regularisation: Regularisation) -> Result<Self, Error> {
        if let Regularisation::Smooth { eps } = regularisation {
            positive("eps", eps)?;
        }
        Ok(Self { regularisation })
    }

    /// The regularisation in use.
    pub fn regularisation(&self) -> Regularisation {
        self.regularisation
    }

    /// f(x; b) and its partial derivatives (negative `b` treated as 0).
    #[inline]
    pub fn eval(&self, x: f64, b: f64) -> DeadZoneEval {
        match self.regularisation {
            Regularisation::Exact => DeadZoneEval {
                f: dead_zone(x, b),
                df_dx: dead_zone_dx(x, b),
                df_db: dead_zone_db(x, b),
            },
            Regularisation::Smooth { eps } => {
                let b = clamp_gap(b);
                let (sp, dsp) = smooth_ramp(x - b, eps);
                let (sm, dsm) = smooth_ramp(-x - b, eps);
                DeadZoneEval {
                    f: sp - sm,
                    df_dx: dsp + dsm,
                    df_db: -dsp + dsm,
                }
            }
        }
    }

    /// f(x; b).
    #[inline]
    pub fn value(&self, x: f64, b: f64) -> f64 {
        match self.regularisation {
            Regularisation::Exact => dead_zone(x, b),
            Regularisation::Smooth { .. } => self.eval(x, b).f,
        }
    }

    /// f(x; b(t)) for a constant, time- or state-dependent half gap.
    #[inline]
    pub fn eval_at<G: HalfGap + ?Sized>(&self, x: f64, t: f64, gap: &G) -> DeadZoneEval {
        self.eval(x, gap.half_gap(t))
    }
}

/// A half gap b(t) for the dead zone: a constant (`f64`), a closure wrapped in [`GapFn`], or
/// anything else a model implements (e.g. a dynamic backlash evaluated from the current state).
///
/// State-dependent gaps: evaluate `b` from the state yourself (e.g.
/// [`DynamicBacklash::eval`](crate::DynamicBacklash::eval)) and call [`DeadZone::eval`];
/// use `df_db` with the gap's gradient for a Jacobian.
pub trait HalfGap {
    /// Half gap at time `t` (same units as the displacement passed to the dead zone).
    fn half_gap(&self, t: f64) -> f64;
}

impl HalfGap for f64 {
    #[inline(always)]
    fn half_gap(&self, _t: f64) -> f64 {
        *self
    }
}

/// Wraps a closure `t ↦ b(t)` as a [`HalfGap`].
#[derive(Debug, Clone, Copy)]
pub struct GapFn<F>(pub F);

impl<F: Fn(f64) -> f64> HalfGap for GapFn<F> {
    #[inline(always)]
    fn half_gap(&self, t: f64) -> f64 {
        (self.0)(t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use math::DetMath;

    #[test]
    #[allow(clippy::float_cmp)] // exact arithmetic on small integers is the point
    fn corners_and_degenerate_gap() {
        assert_eq!(dead_zone(1.0, 1.0), 0.0);
        assert_eq!(dead_zone_dx(1.0, 1.0), 0.0);
        assert_eq!(dead_zone_dx(-1.0, 1.0), 0.0);
        assert_eq!(dead_zone_db(1.0, 1.0), 0.0);
        assert_eq!(dead_zone_dx(0.0, 0.0), 1.0);
        assert_eq!(dead_zone(2.0, -1.0), 2.0);
        assert_eq!(contact_region(1.0, 1.0), ContactRegion::Separated);
        assert_eq!(contact_region(1.5, 1.0), ContactRegion::DriveSide);
        assert_eq!(contact_region(-1.5, 1.0), ContactRegion::BackSide);
        assert!(contact_region(-1.5, 1.0).in_contact());
        assert_eq!(switching_functions(0.25, 1.0), [-0.75, 1.25]);
    }

    #[test]
    fn smooth_is_close_odd_and_stable() {
        let dz = DeadZone::new(Regularisation::Smooth { eps: 1e-3 }).unwrap();
        for i in -400..=400 {
            let x = f64::from(i) * 0.01;
            let e = dz.eval(x, 1.0);
            assert!((e.f - dead_zone(x, 1.0)).abs() <= 0.5e-3 + 1e-15);
            assert!((e.f + dz.eval(-x, 1.0).f).abs() < 1e-15);
            assert!((0.0..=1.0).contains(&e.df_dx));
        }
        // far from the corners: no cancellation, exact to rounding
        let far = dz.eval(-1e6, 1.0);
        assert!(far.f.is_finite() && (far.f - (-1e6 + 1.0)).abs() < 1e-6);
        assert!(DeadZone::new(Regularisation::Smooth { eps: 0.0 }).is_err());
        assert!(DeadZone::new(Regularisation::Smooth { eps: f64::NAN }).is_err());
    }

    #[test]
    fn checked_and_gap_forms() {
        assert!(try_dead_zone(f64::NAN, 1.0).is_err());
        assert!(try_dead_zone(1.0, -1e-5).is_err());
        let g = GapFn(|t: f64| 1.0 + 0.5 * t.dsin());
        let e = DeadZone::EXACT.eval_at(2.0, 0.0, &g);
        assert!((e.f - 1.0).abs() < 1e-15);
        let c = DeadZone::default().eval_at(2.0, 5.0, &0.5_f64);
        assert!((c.f - 1.5).abs() < 1e-15);
    }
}
