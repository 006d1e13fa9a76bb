//! Bifurcation diagrams: the stroboscopic Poincaré points of one coordinate against a swept
//! parameter, with the motion type of every point.
//!
//! For each parameter value `p` the user's closure builds the system and its forcing period
//! `T(p)`; from the initial state the transient is discarded (`transient_periods`), the section
//! `x_j(t_0 + kT)`, `k = 1..n_points` of coordinate `j` is kept, and [`classify_motion`] names
//! the motion (period-`n` by repetition of the section, otherwise quasi-periodic or chaotic by
//! the sign of the largest Lyapunov exponent).
//!
//! Two ways to start a point ([`Start`]):
//! * [`Start::Independent`]: every point from the same initial state, in parallel (rayon),
//!   results in input order — bit-identical for any thread count, since a point depends only on
//!   its own parameter;
//! * [`Start::ContinueUp`] / [`Start::ContinueDown`]: sequential continuation — each point
//!   starts from the last section state of its predecessor in the sweep direction, so that the
//!   diagram follows one attractor until it disappears; sweeping up and then down shows
//!   hysteresis (coexisting attractors). Deterministic (one thread, fixed order).
//!
//! A point that fails (the closure refuses the parameter, the integration stops early, a
//! non-finite state) is an `Err` in its slot; the sweep goes on, and a continuation restarts
//! the next point from the given initial state.

use crate::error::{Error, Result, check_finite_slice};
use crate::options::Options;
use crate::steady::{ClassifyOptions, Motion, classify_motion};
use crate::sweep::sweep;
use crate::system::OdeSystem;

/// How the initial state of each point of a bifurcation sweep is chosen.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum Start {
    /// Every point from the given initial state (parallel, bit-identical for any thread count).
    Independent,
    /// Points in input order, each from the last section state of the previous one.
    ContinueUp,
    /// Points in reverse input order, each from the last section state of the next one
    /// (results still in input order).
    ContinueDown,
}

/// Most section points per parameter value.
pub const MAX_SECTION_POINTS: usize = 100_000;
/// Most transient periods or Lyapunov renormalisations per parameter value.
pub const MAX_PERIODS: usize = 10_000_000;

/// Settings of [`bifurcation_sweep`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct BifurcationOptions {
    /// Index of the state component whose section values are kept (e.g. 0: displacement).
    pub coordinate: usize,
    /// The classification of every point ([`classify_motion`]): transient, section points
    /// (≤ [`MAX_SECTION_POINTS`]), period test, Lyapunov exponent, state scale.
    /// `classify.period` is not used: each point's period comes from the system builder.
    pub classify: ClassifyOptions,
    /// Independent points or sequential continuation.
    pub start: Start,
}

impl BifurcationOptions {
    /// Coordinate `coordinate`, the defaults of [`ClassifyOptions::new`] (200 transient
    /// periods, 64 section points, period ≤ 16, tol 1e-5, 300 Lyapunov intervals, threshold
    /// 0.01 per unit time, scale 1, λ only when not periodic), independent points.
    pub fn new(coordinate: usize) -> Self {
        Self {
            coordinate,
            classify: ClassifyOptions::new(1.0),
            start: Start::Independent,
        }
    }

    /// Check every setting against its bound for a system of `dim` states.
    pub fn check(&self, dim: usize) -> Result<()> {
        let bad = |name: &'static str, bound: &'static str, value: f64| {
            Err(Error::InvalidParameter { name, bound, value })
        };
        let c = &self.classify;
        if self.coordinate >= dim {
            return Err(Error::DimensionMismatch {
                name: "coordinate index (bound: the state dimension)",
                expected: dim,
                got: self.coordinate,
            });
        }
        if !(2..=MAX_SECTION_POINTS).contains(&c.n_points) {
            return bad("n_points", "in [2, 100000]", c.n_points as f64);
        }
        if c.max_period == 0 || c.max_period >= c.n_points {
            return bad("max_period", ">= 1 and < n_points", c.max_period as f64);
        }
        if c.transient_periods > MAX_PERIODS {
            return bad(
                "transient_periods",
                "<= 10000000",
                c.transient_periods as f64,
            );
        }
        if !(1..=MAX_PERIODS).contains(&c.lyapunov_intervals) {
            return bad(
                "lyapunov_intervals",
                "in [1, 10000000]",
                c.lyapunov_intervals as f64,
            );
        }
        if !(c.tol.is_finite() && c.tol > 0.0) {
            return bad("tol", "finite and > 0", c.tol);
        }
        if !(c.scale.is_finite() && c.scale > 0.0) {
            return bad("scale", "finite and > 0", c.scale);
        }
        if !c.lyapunov_threshold.is_finite() {
            return bad("lyapunov_threshold", "finite", c.lyapunov_threshold);
        }
        Ok(())
    }
}

/// One point of a bifurcation diagram.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct BifurcationPoint {
    /// Motion type.
    pub motion: Motion,
    /// Largest Lyapunov exponent (per unit time); `None` at a periodic point unless
    /// [`ClassifyOptions::lyapunov_always`].
    pub lyapunov: Option<f64>,
    /// Forcing period `T` of this point.
    pub period: f64,
    /// Section values of the chosen coordinate, `n_points` of them, in time order.
    pub section: Vec<f64>,
    /// Full state at the last section point (time `(transient_periods + n_points − 1)·T`,
    /// forcing phase 0): where a continuation starts the next point.
    pub final_state: Vec<f64>,
}

/// One point of a bifurcation diagram: the section of `sys` (forcing period `period`) from
/// `y0` at `t = 0`, classified ([`classify_motion`]). What [`bifurcation_sweep`] does per
/// parameter value; a caller that distributes points itself (the study files' shards) calls
/// it directly.
pub fn bifurcation_point<S: OdeSystem + ?Sized>(
    sys: &S,
    period: f64,
    y0: &[f64],
    bo: &BifurcationOptions,
    opts: &Options,
) -> Result<BifurcationPoint> {
    bo.check(y0.len())?;
    check_finite_slice("initial state", y0)?;
    if sys.dim() != y0.len() {
        return Err(Error::DimensionMismatch {
            name: "initial state (bound: the system's dimension)",
            expected: sys.dim(),
            got: y0.len(),
        });
    }
    let co = ClassifyOptions {
        period,
        ..bo.classify
    };
    let c = classify_motion(sys, 0.0, y0, &co, opts)?;
    let dim = c.section.dim;
    let last = c.section.len() - 1;
    Ok(BifurcationPoint {
        motion: c.motion,
        lyapunov: c.lyapunov,
        period,
        section: c
            .section
            .points
            .iter()
            .skip(bo.coordinate)
            .step_by(dim)
            .copied()
            .collect(),
        final_state: c.section.point(last).to_vec(),
    })
}

fn point<S: OdeSystem>(
    built: Result<(S, f64)>,
    y0: &[f64],
    bo: &BifurcationOptions,
    opts: &Options,
) -> Result<BifurcationPoint> {
    let (sys, period) = built?;
    bifurcation_point(&sys, period, y0, bo, opts)
}

/// Bifurcation diagram over `params`: for each parameter `system(p)` returns the system and
/// its forcing period `T(p)` (an `Err` becomes that point's failure); every point starts at
/// `t = 0` from `y0` ([`Start::Independent`]) or from its predecessor's last section state
/// (continuation). Returns one result per parameter, in input order; the outer `Err` only for
/// invalid options or a non-finite `y0`.
///
/// ```
/// use geardyn_timestep::*;
/// // Duffing, Holmes' double-well case, period-1 at γ = 0.20 and period-2 at γ = 0.28
/// let gammas = [0.20, 0.28];
/// let mut bo = BifurcationOptions::new(0);
/// bo.classify.transient_periods = 100;
/// bo.classify.n_points = 16;
/// bo.classify.max_period = 4;
/// let pts = bifurcation_sweep(
///     &gammas,
///     |&g| {
///         let d = Duffing::holmes(g);
///         Ok((FirstOrder(d), d.period()))
///     },
///     &[1.0, 0.0],
///     &bo,
///     &Options::default().with_tol(1e-9, 1e-11),
/// )?;
/// assert_eq!(pts[0].as_ref().unwrap().motion, Motion::Periodic(1));
/// assert_eq!(pts[1].as_ref().unwrap().motion, Motion::Periodic(2));
/// # Ok::<(), geardyn_timestep::Error>(())
/// ```
pub fn bifurcation_sweep<P, S, F>(
    params: &[P],
    system: F,
    y0: &[f64],
    bo: &BifurcationOptions,
    opts: &Options,
) -> Result<Vec<Result<BifurcationPoint>>>
where
    P: Sync,
    S: OdeSystem,
    F: Fn(&P) -> Result<(S, f64)> + Sync,
{
    bo.check(y0.len())?;
    check_finite_slice("initial state", y0)?;
    match bo.start {
        Start::Independent => Ok(sweep(params, |p| point(system(p), y0, bo, opts), None)),
        Start::ContinueUp | Start::ContinueDown => {
            let n = params.len();
            let order: Vec<usize> = if bo.start == Start::ContinueUp {
                (0..n).collect()
            } else {
                (0..n).rev().collect()
            };
            let mut out: Vec<Option<Result<BifurcationPoint>>> = vec![None; n];
            let mut start = y0.to_vec();
            for i in order {
                let r = point(system(&params[i]), &start, bo, opts);
                start = match &r {
                    Ok(p) if p.final_state.iter().all(|v| v.is_finite()) => p.final_state.clone(),
                    _ => y0.to_vec(),
                };
                out[i] = Some(r);
            }
            // every slot was visited once (order is a permutation of 0..n)
            Ok(out
                .into_iter()
                .map(|r| {
                    r.unwrap_or(Err(Error::TooFewSamples {
                        name: "bifurcation point",
                        needed: 1,
                        got: 0,
                    }))
                })
                .collect())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn options_are_checked() {
        let ok = BifurcationOptions::new(1);
        assert!(ok.check(2).is_ok());
        assert!(ok.check(1).is_err());
        for f in [
            |b: &mut BifurcationOptions| b.classify.n_points = 1,
            |b: &mut BifurcationOptions| b.classify.max_period = 0,
            |b: &mut BifurcationOptions| b.classify.max_period = 64,
            |b: &mut BifurcationOptions| b.classify.tol = f64::NAN,
            |b: &mut BifurcationOptions| b.classify.lyapunov_intervals = 0,
            |b: &mut BifurcationOptions| b.classify.scale = 0.0,
            |b: &mut BifurcationOptions| b.classify.lyapunov_threshold = f64::INFINITY,
            |b: &mut BifurcationOptions| b.classify.transient_periods = MAX_PERIODS + 1,
        ] {
            let mut b = ok;
            f(&mut b);
            assert!(b.check(2).is_err(), "{b:?}");
        }
    }

    #[test]
    fn motion_codes_round_trip() {
        for m in [
            Motion::Periodic(1),
            Motion::Periodic(7),
            Motion::QuasiPeriodic,
            Motion::Chaotic,
            Motion::NonPeriodic,
        ] {
            assert_eq!(Motion::from_code(m.code()), Some(m));
        }
        assert_eq!(Motion::from_code(0.5), None);
        assert_eq!(Motion::from_code(-3.0), None);
        assert_eq!(Motion::from_code(f64::NAN), None);
        assert_eq!(Motion::Periodic(3).label(), "period-3");
        assert_eq!(Motion::Chaotic.period_multiple(), 0);
    }
}
