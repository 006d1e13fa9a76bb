//! The one continuation of the workspace: predictor, corrector interface, step control, fold
//! detection and the one branch type, shared by shooting
//! ([`OrbitProblem::continuation`](crate::OrbitProblem::continuation)), harmonic balance
//! ([`continue_hbm`](crate::continue_hbm))
//! and every model-specific use (the Liu speed continuation, the neighbour fill of a sweep).
//!
//! # Equations
//!
//! The unknowns are `y = (z, μ) ∈ ℝ^{N+1}` (the orbit's coordinates `z`, shooting state or
//! harmonic-balance coefficients, and the parameter `μ = λ/s_λ`), the branch is `F(y) = 0`,
//! `F: ℝ^{N+1} → ℝ^N`, and `J = [F_z | F_μ]` its `N × (N+1)` Jacobian.
//!
//! * **Tangent.** The unit null vector of `J`, oriented along the previous tangent `t_{i−1}`:
//!   the solution of the bordered system `[J; t_{i−1}ᵀ] v = e_{N+1}`, `t_i = v/‖v‖`
//!   ([`bordered_tangent`]); `t_{i−1}ᵀ t_i > 0` by construction. The first tangent is
//!   oriented along `±e_{N+1}` (the continuation direction).
//! * **Pseudo-arclength** ([`Predictor::Arclength`]): predictor `y_p = y_i + Δs t_i`,
//!   corrector Newton on `F(y) = 0, t_iᵀ (y − y_p) = 0` — the hyperplane through the
//!   predictor normal to the tangent, so the corrector goes round folds (`t_{i,μ} = 0`).
//! * **Natural** ([`Predictor::Natural`]): `Δμ = ±Δs` fixed, predictor along the tangent
//!   `y_p = y_i + (Δμ / t_{i,μ}) t_i`, corrector on `F(y) = 0, e_{N+1}ᵀ (y − y_p) = 0`
//!   (`μ` held). It cannot pass a fold: there the corrector fails, the step halves down to
//!   [`StepControl::min`] and the branch stops with [`StopReason::StepTooSmall`].
//! * **Step control** ([`StepControl`]): a rejected step (corrector failure, a correction
//!   longer than `max_correction·Δs`, a tangent turn with `cos < min_cos`) is halved; an
//!   accepted one grows by `grow` (optionally only after easy corrections) or shrinks after
//!   hard ones.
//! * **Stall** ([`Stall`], optional): a branch whose last `Stall::points` accepted steps are
//!   together shorter than `Stall::points · Stall::step` (their mean below `Stall::step`)
//!   crawls: in a non-smooth tangle, where the contact set changes at nearly every step, the
//!   corrector fails at most longer steps and the branch can spend hundreds of points within a
//!   tenth of a parameter unit. It stops there with [`StopReason::Stalled`] instead of at the
//!   cap or the minimum step. The mean, not every step, is compared: an occasional longer step
//!   through a tangle does not restart the count.
//! * **Folds** ([`Fold`]) where `t_μ` changes sign between `y_i` and `y_{i+1}`; with
//!   `σ = t_{i,μ} Δs/(t_{i,μ} − t_{i+1,μ})` (where the linear interpolant of `t_μ(s)` vanishes) the
//!   fold parameter is the quadratic estimate `μ_F = μ_i + ½ t_{i,μ} σ`. Shooting locates
//!   folds (and grazing, period doubling, Neimark–Sacker) further, on the corrector's test
//!   functions ([`SpecialPoint`]).
//!
//! The corrector (a shooting residual, a harmonic-balance residual, a model's own) is the
//! [`Corrector`] trait; [`trace`] is the one loop.

use std::ops::Deref;

use nalgebra::{DMatrix, DVector};
use system::Stability;

use crate::error::{OrbitError, check};
use crate::problem::Parameter;

/// How the next point is predicted and which constraint closes the corrector.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Predictor {
    /// Pseudo-arclength: tangent predictor, corrector on the hyperplane normal to the tangent
    /// (goes round folds).
    #[default]
    Arclength,
    /// Natural parameter: `μ` advances by the step, the corrector holds it (stops at folds).
    Natural,
}

/// The one options type of every continuation: the step bounds, the cap on points and the
/// predictor, shared by every corrector, and the corrector's own part `C`
/// ([`ShootingCorrection`](crate::ShootingCorrection) for
/// [`OrbitProblem::continuation`](crate::OrbitProblem::continuation),
/// [`HbmCorrection`](crate::HbmCorrection) for [`continue_hbm`](crate::continue_hbm)). The
/// corrector turns the step bounds into its [`StepControl`] (its growth and rejection rules)
/// and the cap and predictor into the [`Course`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ContinuationOptions<C> {
    /// First step `Δs` (in the corrector's variables: scaled shooting state and parameter,
    /// or the unscaled harmonic-balance coefficients and parameter).
    pub initial_step: f64,
    /// Smallest step: a rejection below it stops the branch
    /// ([`StopReason::StepTooSmall`]).
    pub min_step: f64,
    /// Largest step.
    pub max_step: f64,
    /// Cap on branch points (including the first).
    pub max_points: usize,
    /// Pseudo-arclength (default) or natural-parameter steps.
    #[cfg_attr(feature = "serde", serde(default))]
    pub predictor: Predictor,
    /// Stop a branch that crawls ([`StopReason::Stalled`]); `None` (default): no such stop.
    #[cfg_attr(feature = "serde", serde(default))]
    pub stall: Option<Stall>,
    /// The corrector's own settings.
    pub corrector: C,
}

/// When a branch crawls ([`ContinuationOptions::stall`]): its last `points` accepted steps are
/// together shorter than `points · step` (their mean below `step`; the corrector's scaled
/// variables, like the step bounds). A window of the mean rather than a count of short steps
/// in a row: in a tangle the corrector succeeds now and then at a longer step, and with a
/// count in a row those steps decided, at rounding level, whether a branch stopped after 15
/// points or crawled on for 150 (`liu2021-orbit-branch`, rounds 20–21).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Stall {
    /// The window: the last this many accepted steps (≥ 1).
    pub points: usize,
    /// The mean step length over the window below which the branch crawls (> 0 and finite).
    pub step: f64,
}

impl<C> ContinuationOptions<C> {
    /// The shared defaults with `corrector`: first step 0.01, steps in `[1e-6, 0.1]`, 500
    /// points, pseudo-arclength (each corrector's `Default` starts from these).
    pub fn with_corrector(corrector: C) -> Self {
        Self {
            initial_step: 0.01,
            min_step: 1e-6,
            max_step: 0.1,
            max_points: 500,
            predictor: Predictor::Arclength,
            stall: None,
            corrector,
        }
    }

    /// Checks the shared fields: `0 < min_step ≤ initial_step ≤ max_step`, all finite,
    /// `max_points ≥ 1`, and a [`Stall`] with `points ≥ 1` and a finite `step > 0` (the
    /// corrector's part is checked by its own `validate`).
    ///
    /// # Errors
    /// [`OrbitError::InvalidInput`] naming the field and its bound.
    pub fn validate_steps(&self) -> Result<(), OrbitError> {
        check(
            self.min_step.is_finite() && self.min_step > 0.0,
            "ContinuationOptions::min_step",
            "> 0 and finite",
            self.min_step,
        )?;
        check(
            self.max_step.is_finite() && self.max_step >= self.min_step,
            "ContinuationOptions::max_step",
            ">= min_step and finite",
            self.max_step,
        )?;
        check(
            self.initial_step >= self.min_step && self.initial_step <= self.max_step,
            "ContinuationOptions::initial_step",
            "in [min_step, max_step]",
            self.initial_step,
        )?;
        check(
            self.max_points >= 1,
            "ContinuationOptions::max_points",
            ">= 1",
            self.max_points as f64,
        )?;
        if let Some(stall) = self.stall {
            check(
                stall.points >= 1,
                "ContinuationOptions::stall.points",
                ">= 1",
                stall.points as f64,
            )?;
            check(
                stall.step.is_finite() && stall.step > 0.0,
                "ContinuationOptions::stall.step",
                "> 0 and finite",
                stall.step,
            )?;
        }
        Ok(())
    }

    /// The course of a branch over `range` in `direction` with this cap, predictor and stall.
    pub fn course(&self, range: [f64; 2], direction: f64) -> Course {
        Course {
            range,
            direction,
            max_points: self.max_points,
            predictor: self.predictor,
            stall: self.stall,
        }
    }
}

/// Step-size control of [`trace`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct StepControl {
    /// First step `Δs` (the corrector's scaled variables).
    pub initial: f64,
    /// Smallest step: a rejection below it stops the branch.
    pub min: f64,
    /// Largest step.
    pub max: f64,
    /// Factor after an accepted step.
    pub grow: f64,
    /// Grow only after a correction of at most this many iterations (`None`: always).
    pub grow_below: Option<u64>,
    /// After a correction of at least this many iterations the step is multiplied by
    /// [`StepControl::shrink`] instead (`None`: never).
    pub shrink_above: Option<u64>,
    /// Factor after a hard correction (see [`StepControl::shrink_above`]).
    pub shrink: f64,
    /// Factor after a rejected step.
    pub fail: f64,
    /// Reject a step whose tangent turned by more than `acos(min_cos)` (only while the step is
    /// above `2 min`); `None`: no check.
    pub min_cos: Option<f64>,
    /// Reject a corrected point farther than `max_correction · Δs` from its predictor (it
    /// jumped to another branch); `None`: no check.
    pub max_correction: Option<f64>,
}

impl StepControl {
    /// The shooting control: grow by 1.5 after every accepted step, halve on rejection, reject
    /// corrections longer than `max_correction · Δs`.
    pub fn shooting(initial: f64, min: f64, max: f64, max_correction: f64) -> Self {
        Self {
            initial,
            min,
            max,
            grow: 1.5,
            grow_below: None,
            shrink_above: None,
            shrink: 1.0,
            fail: 0.5,
            min_cos: None,
            max_correction: Some(max_correction),
        }
    }

    /// The harmonic-balance control: ×1.5 after easy corrections (≤ 3 iterations), ×0.7 after
    /// hard ones (≥ 7), ×0.5 after failures or tangent turns above ~25° (`cos < 0.9`).
    pub fn harmonic(initial: f64, min: f64, max: f64) -> Self {
        Self {
            initial: initial.min(max),
            min,
            max,
            grow: 1.5,
            grow_below: Some(3),
            shrink_above: Some(7),
            shrink: 0.7,
            fail: 0.5,
            min_cos: Some(0.9),
            max_correction: None,
        }
    }

    /// Checks every field.
    ///
    /// # Errors
    /// [`OrbitError::InvalidInput`] naming the field.
    pub fn validate(&self) -> crate::Result<()> {
        use crate::error::check;
        check(
            self.min.is_finite() && self.min > 0.0,
            "StepControl::min",
            "> 0 and finite",
            self.min,
        )?;
        check(
            self.max.is_finite() && self.max >= self.min,
            "StepControl::max",
            ">= min and finite",
            self.max,
        )?;
        check(
            self.initial.is_finite() && self.initial > 0.0,
            "StepControl::initial",
            "> 0 and finite",
            self.initial,
        )?;
        check(
            self.grow.is_finite() && self.grow >= 1.0,
            "StepControl::grow",
            ">= 1 and finite",
            self.grow,
        )?;
        check(
            self.shrink > 0.0 && self.shrink <= 1.0,
            "StepControl::shrink",
            "in (0, 1]",
            self.shrink,
        )?;
        check(
            self.fail > 0.0 && self.fail < 1.0,
            "StepControl::fail",
            "in (0, 1)",
            self.fail,
        )?;
        if let Some(c) = self.min_cos {
            check(
                (-1.0..=1.0).contains(&c),
                "StepControl::min_cos",
                "in [-1, 1]",
                c,
            )?;
        }
        if let Some(m) = self.max_correction {
            check(m > 0.0, "StepControl::max_correction", "> 0", m)?;
        }
        Ok(())
    }
}

/// Which extremum of a gap (event) function touches zero at a grazing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Extremum {
    /// The minimum over the orbit.
    Min,
    /// The maximum over the orbit.
    Max,
}

/// The kind of a special point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum SpecialKind {
    /// The minimum or maximum of event function `event` over the orbit crosses zero: a contact
    /// (switching surface) is touched tangentially, and contacts appear or disappear.
    Grazing {
        /// Event index.
        event: usize,
        /// Which extremum.
        extremum: Extremum,
    },
    /// A multiplier crosses `−1`.
    PeriodDoubling,
    /// The branch turns back in `λ` (a multiplier crosses `+1`).
    Fold,
    /// A complex pair crosses the unit circle (detected, located like the others on
    /// `Π(μ_iμ_j − 1)`).
    NeimarkSacker,
    /// The number of crossings of event `event` per orbit changed between two points while
    /// neither global extremum of its function changed sign: a *local* extremum grazed the
    /// switching surface (a contact appeared or vanished inside the orbit). Located by
    /// bisection on the arclength with the crossing count as indicator.
    ContactChange {
        /// Event index.
        event: usize,
    },
}

/// A point of a branch: the parameter, the tangent's parameter component, the one
/// [`Stability`] (when computed) and the orbit `P` (a shooting state with its monodromy, a
/// harmonic-balance solution, a model's record). Dereferences to `P`.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct BranchPoint<P> {
    /// Parameter value `λ`.
    pub parameter: f64,
    /// `dμ/ds` of the unit tangent (the corrector's scaled variables); its sign change is a
    /// fold.
    pub tangent_parameter: f64,
    /// Multipliers and verdict; `None` when not computed.
    pub stability: Option<Stability>,
    /// The orbit.
    pub orbit: P,
}

impl<P> BranchPoint<P> {
    /// The stability verdict (`max |μ| ≤ 1 + STABILITY_TOLERANCE`), `None` when not computed.
    pub fn stable(&self) -> Option<bool> {
        self.stability.as_ref().map(|s| s.stable)
    }

    /// The largest multiplier modulus, `None` when not computed.
    pub fn max_multiplier(&self) -> Option<f64> {
        self.stability.as_ref().map(|s| s.max_modulus)
    }

    /// The same point with its orbit mapped (e.g. to a model's record).
    pub fn map<Q>(self, f: impl FnOnce(P) -> Q) -> BranchPoint<Q> {
        BranchPoint {
            parameter: self.parameter,
            tangent_parameter: self.tangent_parameter,
            stability: self.stability,
            orbit: f(self.orbit),
        }
    }
}

impl<P> Deref for BranchPoint<P> {
    type Target = P;
    fn deref(&self) -> &P {
        &self.orbit
    }
}

/// A fold (turning point, saddle-node) detected between two branch points.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Fold {
    /// The fold lies between points `after_index` and `after_index + 1`.
    pub after_index: usize,
    /// Parameter at the fold, from a quadratic fit of `λ(s)` using `dλ/ds` at both ends.
    pub parameter: f64,
}

/// A detected (and, where the corrector locates them, located) special point.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SpecialPoint<P> {
    /// What happens.
    pub kind: SpecialKind,
    /// The special point (located, or the first point past it).
    pub point: BranchPoint<P>,
    /// Index in [`Branch::points`] of the last point before it.
    pub after: usize,
    /// True if located to the corrector's tolerance; false if only detected.
    pub located: bool,
    /// `[λ_lo, λ_hi]`: the parameter at the two ends of the last arclength bracket that holds
    /// the special point (sorted; the two branch points around it when only detected). Its
    /// width is the precision of [`SpecialPoint::point`]'s parameter.
    pub bracket: [f64; 2],
}

impl<P> SpecialPoint<P> {
    /// Width of [`SpecialPoint::bracket`]: the precision of the located parameter.
    pub fn precision(&self) -> f64 {
        self.bracket[1] - self.bracket[0]
    }
}

/// Why a continuation stopped.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum StopReason {
    /// `λ` passed the end of the range in the continuation direction.
    ReachedEnd,
    /// The branch turned back and left the range on the side of the start.
    LeftRange {
        /// Parameter of the last point.
        parameter: f64,
    },
    /// The cap on branch points was reached.
    MaxPoints,
    /// The corrector failed down to the minimum step.
    StepTooSmall {
        /// Parameter of the last accepted point.
        parameter: f64,
        /// The last rejection.
        #[cfg_attr(feature = "serde", serde(skip))]
        cause: Option<OrbitError>,
    },
    /// The branch passed a special point of a kind it was asked to stop at
    /// ([`ShootingCorrection::stop_at`](crate::ShootingCorrection::stop_at)); it ends with the
    /// point after it.
    SpecialPoint {
        /// Parameter of the special point.
        parameter: f64,
        /// Its kind.
        kind: SpecialKind,
    },
    /// The branch lost stability
    /// ([`ShootingCorrection::stop_at_instability`](crate::ShootingCorrection::stop_at_instability)):
    /// its last point is the first unstable one after a stable one.
    LostStability {
        /// Parameter of the first unstable point (the branch's last).
        parameter: f64,
    },
    /// The branch crawled ([`ContinuationOptions::stall`]): the mean of its last `points`
    /// accepted steps was below the stall step.
    Stalled {
        /// Parameter of the last accepted point.
        parameter: f64,
        /// The window: accepted steps whose mean fell below the stall step.
        points: usize,
    },
    /// The first point did not converge.
    InitialSolveFailed {
        /// Residual norm reached.
        residual_norm: f64,
    },
    /// A codim-2 curve ([`OrbitProblem::continue_codim2`](crate::OrbitProblem::continue_codim2)):
    /// its defining condition degenerated at the last accepted point (named by `condition`);
    /// the curve is not continued past it rather than continued wrongly.
    Degenerate {
        /// Parameter (the continued, second parameter) of the last accepted point.
        parameter: f64,
        /// Which condition degenerated.
        condition: Degeneracy,
    },
    /// A codim-2 curve: the first parameter (the one of the branch the special point was
    /// found on) left its range [`Codim2Correction::first_range`](crate::Codim2Correction::first_range).
    FirstLeftRange {
        /// The continued (second) parameter of the last point.
        parameter: f64,
        /// The first parameter of the last point.
        first: f64,
    },
}

/// How the defining condition of a codim-2 curve degenerated ([`StopReason::Degenerate`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum Degeneracy {
    /// Grazing curve: the second time derivative of the event function at the grazing time
    /// vanished (`|ḧ| (kT/2π)² < curvature_tol · ½(max h − min h)`): the tangency is no
    /// longer quadratic (a cusp of the contact set), `(h, ḣ) = 0` no longer fixes `t_g`.
    GrazingCurvature,
    /// Grazing curve: the tangency at `t_g` is no longer the global extremum of the event
    /// function over the orbit (another local extremum crossed it): the orbit touches the
    /// surface at `t_g` but crosses it elsewhere, so the curve stopped bounding contact.
    GrazingNotGlobal,
    /// Fold or period-doubling curve: the bordered matrix `[[Φ ∓ I, b], [cᵀ, 0]]` is singular
    /// (a second multiplier reached `±1`, or the borders lost the null vectors).
    SingularBordered,
}

impl StopReason {
    /// The branch left its parameter range (at either end).
    pub fn left_range(&self) -> bool {
        matches!(self, Self::ReachedEnd | Self::LeftRange { .. })
    }

    /// The parameter where the branch stopped ([`LeftRange`](Self::LeftRange),
    /// [`StepTooSmall`](Self::StepTooSmall), [`Stalled`](Self::Stalled), the special point of
    /// [`SpecialPoint`](Self::SpecialPoint), the first unstable point of
    /// [`LostStability`](Self::LostStability), a codim-2 stop), if the reason carries one.
    pub fn parameter(&self) -> Option<f64> {
        match self {
            Self::LeftRange { parameter }
            | Self::StepTooSmall { parameter, .. }
            | Self::Stalled { parameter, .. }
            | Self::LostStability { parameter }
            | Self::SpecialPoint { parameter, .. } => Some(*parameter),
            Self::Degenerate { parameter, .. } | Self::FirstLeftRange { parameter, .. } => {
                Some(*parameter)
            }
            Self::ReachedEnd | Self::MaxPoints | Self::InitialSolveFailed { .. } => None,
        }
    }

    /// The same reason with its parameter mapped by `g` (a change of units).
    #[must_use]
    pub fn map_parameter(self, g: impl Fn(f64) -> f64) -> Self {
        match self {
            Self::LeftRange { parameter } => Self::LeftRange {
                parameter: g(parameter),
            },
            Self::StepTooSmall { parameter, cause } => Self::StepTooSmall {
                parameter: g(parameter),
                cause,
            },
            Self::Stalled { parameter, points } => Self::Stalled {
                parameter: g(parameter),
                points,
            },
            Self::SpecialPoint { parameter, kind } => Self::SpecialPoint {
                parameter: g(parameter),
                kind,
            },
            Self::Degenerate {
                parameter,
                condition,
            } => Self::Degenerate {
                parameter: g(parameter),
                condition,
            },
            Self::FirstLeftRange { parameter, first } => Self::FirstLeftRange {
                parameter: g(parameter),
                first,
            },
            other => other,
        }
    }
}

/// A continued branch of periodic orbits: the workspace's one branch type.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Branch<P> {
    /// The continued parameter.
    pub parameter: Parameter,
    /// Orbits of period `k T` (1 for harmonic balance).
    pub periods: usize,
    /// Points in arclength order; stable and unstable ones alike.
    pub points: Vec<BranchPoint<P>>,
    /// Folds found (sign changes of `dμ/ds`, quadratic estimate).
    pub folds: Vec<Fold>,
    /// Special points located by the corrector, in arclength order.
    pub special: Vec<SpecialPoint<P>>,
    /// Why it stopped.
    pub stop: StopReason,
}

impl<P> Branch<P> {
    /// An empty branch (stop reason [`StopReason::MaxPoints`] until [`trace`] says otherwise).
    pub fn new(parameter: Parameter, periods: usize) -> Self {
        Self {
            parameter,
            periods,
            points: Vec::new(),
            folds: Vec::new(),
            special: Vec::new(),
            stop: StopReason::MaxPoints,
        }
    }

    /// The same branch with every point mapped by `f` (which maps its parameter itself), the
    /// parameters of folds, special-point brackets and the stop reason by `g` (a change of
    /// the parameter's units, e.g. a model's physical speed for the corrector's base
    /// frequency).
    ///
    /// # Errors
    /// The first error of `f`.
    pub fn try_map<Q, E>(
        self,
        mut f: impl FnMut(&BranchPoint<P>) -> Result<BranchPoint<Q>, E>,
        g: impl Fn(f64) -> f64,
    ) -> Result<Branch<Q>, E> {
        let points = self.points.iter().map(&mut f).collect::<Result<_, E>>()?;
        let special = self
            .special
            .iter()
            .map(|s| {
                Ok(SpecialPoint {
                    kind: s.kind,
                    point: f(&s.point)?,
                    after: s.after,
                    located: s.located,
                    bracket: [g(s.bracket[0]), g(s.bracket[1])],
                })
            })
            .collect::<Result<_, E>>()?;
        Ok(Branch {
            parameter: self.parameter,
            periods: self.periods,
            points,
            folds: self
                .folds
                .iter()
                .map(|f| Fold {
                    after_index: f.after_index,
                    parameter: g(f.parameter),
                })
                .collect(),
            special,
            stop: self.stop.map_parameter(g),
        })
    }
}

/// A corrected point with what the next step needs: `y = (z, μ)`, the unit tangent there, the
/// corrector's iteration count and the point the corrector built.
#[derive(Debug, Clone)]
pub struct Node<R> {
    /// `(z, μ)` in the corrector's scaled variables.
    pub y: DVector<f64>,
    /// Unit tangent at `y`.
    pub tangent: DVector<f64>,
    /// Corrector iterations.
    pub iterations: u64,
    /// What the corrector returned (turned into a [`BranchPoint`] by [`Corrector::accept`]).
    pub raw: R,
}

/// The corrector of [`trace`]: solves `F(y) = 0` bordered by one linear constraint, and turns
/// accepted solutions into branch points.
pub trait Corrector {
    /// What a correction returns.
    type Raw: Clone;
    /// The orbit of a branch point.
    type Point: Clone;
    /// Fatal errors (abort the continuation).
    type Error;

    /// Solve `F(y) = 0`, `borderᵀ (y − pred) = 0` from `pred`; the tangent at the solution is
    /// oriented along `reference`. `Ok(Err(e))`: the step is rejected (and retried smaller);
    /// `Err`: the continuation aborts.
    ///
    /// # Errors
    /// Fatal failures of the problem.
    #[allow(clippy::type_complexity)]
    fn correct(
        &mut self,
        pred: &DVector<f64>,
        border: &DVector<f64>,
        reference: &DVector<f64>,
    ) -> Result<Result<Node<Self::Raw>, OrbitError>, Self::Error>;

    /// Turn an accepted correction into a branch point (stability, records).
    ///
    /// # Errors
    /// Fatal failures.
    fn accept(&mut self, node: &Node<Self::Raw>) -> Result<BranchPoint<Self::Point>, Self::Error>;

    /// `λ = s_λ μ`: the parameter scale.
    fn parameter_scale(&self) -> f64 {
        1.0
    }

    /// Called with every accepted step from `a` to `b` (step `ds`) before `b` is pushed:
    /// detection and location of special points.
    ///
    /// # Errors
    /// Fatal failures.
    fn on_step(
        &mut self,
        _a: &Node<Self::Raw>,
        _b: &Node<Self::Raw>,
        _ds: f64,
        _branch: &mut Branch<Self::Point>,
    ) -> Result<(), Self::Error> {
        Ok(())
    }

    /// Leave the problem at `y` (called when the branch stops on a rejection).
    ///
    /// # Errors
    /// Fatal failures.
    fn leave_at(&mut self, _y: &DVector<f64>) -> Result<(), Self::Error> {
        Ok(())
    }

    /// Called after the point of `node` was pushed: `Some(reason)` stops the branch there
    /// (a codim-2 curve whose defining condition degenerated, a second parameter out of its
    /// range). Default: never.
    fn stop_after(&mut self, _node: &Node<Self::Raw>) -> Option<StopReason> {
        None
    }
}

/// Unit null vector of `jac` (`N × (N+1)`), oriented along `reference`: the solution `v` of
/// `[J; referenceᵀ] v = e_{N+1}`, normalised. `None` when the bordered matrix is singular or
/// the result is not finite.
pub fn bordered_tangent(jac: &DMatrix<f64>, reference: &DVector<f64>) -> Option<DVector<f64>> {
    let nn = jac.nrows();
    if jac.ncols() != nn + 1 || reference.len() != nn + 1 {
        return None;
    }
    let mut a = DMatrix::zeros(nn + 1, nn + 1);
    a.view_mut((0, 0), (nn, nn + 1)).copy_from(jac);
    a.row_mut(nn).copy_from(&reference.transpose());
    let mut rhs = DVector::zeros(nn + 1);
    rhs[nn] = 1.0;
    if !a.lu().solve_mut(&mut rhs) {
        return None;
    }
    let norm = rhs.norm();
    if !norm.is_finite() || norm == 0.0 {
        return None;
    }
    Some(rhs / norm)
}

/// Where the continuation runs: the parameter range, the direction and the cap on points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Course {
    /// The branch stops when `λ` leaves `[range[0], range[1]]`.
    pub range: [f64; 2],
    /// `+1` (increasing `λ`) or `−1`.
    pub direction: f64,
    /// Cap on branch points (including the first).
    pub max_points: usize,
    /// Predictor and constraint.
    pub predictor: Predictor,
    /// Stop a crawling branch ([`StopReason::Stalled`]); `None`: never.
    pub stall: Option<Stall>,
}

/// The one continuation loop: from `first` (already the first point of `branch`) predict,
/// correct, check, accept, detect folds, grow or shrink the step, until the range is left,
/// the cap is reached, the step falls below [`StepControl::min`] or the branch stalls
/// ([`Course::stall`]). Every pass either accepts a point (at most `max_points`) or halves
/// the step (at most `log₂(max/min)` times in a row), so the loop ends.
///
/// # Errors
/// Fatal errors of the corrector.
pub fn trace<C: Corrector>(
    corrector: &mut C,
    first: Node<C::Raw>,
    control: &StepControl,
    course: &Course,
    branch: &mut Branch<C::Point>,
) -> Result<(), C::Error> {
    let mut cur = first;
    let n = cur.y.len() - 1;
    let mut s = control.initial;
    let scale = corrector.parameter_scale();
    let [lo, hi] = course.range;
    let mut e_mu = DVector::zeros(n + 1);
    e_mu[n] = 1.0;
    // the last `stall.points` accepted step lengths (a window of at most that many)
    let mut recent: std::collections::VecDeque<f64> = std::collections::VecDeque::new();
    while branch.points.len() < course.max_points {
        let (pred, border) = match course.predictor {
            Predictor::Arclength => (&cur.y + &cur.tangent * s, cur.tangent.clone()),
            Predictor::Natural => {
                let tm = cur.tangent[n];
                if tm.abs() < 1e-12 {
                    (cur.y.clone(), e_mu.clone())
                } else {
                    (
                        &cur.y + &cur.tangent * (course.direction * s / tm),
                        e_mu.clone(),
                    )
                }
            }
        };
        let natural_stalled =
            course.predictor == Predictor::Natural && cur.tangent[n].abs() < 1e-12;
        let attempt = if natural_stalled {
            Err(OrbitError::Singular {
                what: "natural continuation at a fold (dλ/ds = 0)",
            })
        } else {
            corrector.correct(&pred, &border, &cur.tangent)?
        };
        let checked = attempt.and_then(|next| {
            if let Some(m) = control.max_correction {
                let dist = (&next.y - &pred).norm();
                if dist > m * s {
                    return Err(OrbitError::NotConverged {
                        what: "continuation corrector (moved farther than max_correction·Δs)",
                        iterations: 0,
                        residual: dist,
                    });
                }
            }
            if let Some(c) = control.min_cos {
                let cos = next.tangent.dot(&cur.tangent);
                if cos < c && s > 2.0 * control.min {
                    return Err(OrbitError::NotConverged {
                        what: "continuation step (tangent turned too far)",
                        iterations: usize::try_from(next.iterations).unwrap_or(usize::MAX),
                        residual: cos,
                    });
                }
            }
            Ok(next)
        });
        let next = match checked {
            Ok(next) => next,
            Err(e) => {
                s *= control.fail;
                if s < control.min {
                    corrector.leave_at(&cur.y)?;
                    branch.stop = StopReason::StepTooSmall {
                        parameter: cur.y[n] * scale,
                        cause: Some(e),
                    };
                    return Ok(());
                }
                continue;
            }
        };
        let point = corrector.accept(&next)?;
        let (ta, tb) = (cur.tangent[n], next.tangent[n]);
        if ta * tb < 0.0 {
            let sigma = ta * s / (ta - tb);
            branch.folds.push(Fold {
                after_index: branch.points.len() - 1,
                parameter: (cur.y[n] + 0.5 * ta * sigma) * scale,
            });
        }
        corrector.on_step(&cur, &next, s, branch)?;
        branch.points.push(point);
        if let Some(reason) = corrector.stop_after(&next) {
            branch.stop = reason;
            return Ok(());
        }
        let accepted_step = s;
        if control.grow_below.is_none_or(|k| next.iterations <= k) {
            s = (s * control.grow).min(control.max);
        } else if control.shrink_above.is_some_and(|k| next.iterations >= k) {
            s = (s * control.shrink).max(control.min);
        }
        cur = next;
        let lam = cur.y[n] * scale;
        if lam > hi || lam < lo {
            let past_end = if course.direction > 0.0 {
                lam > hi
            } else {
                lam < lo
            };
            branch.stop = if past_end {
                StopReason::ReachedEnd
            } else {
                StopReason::LeftRange { parameter: lam }
            };
            return Ok(());
        }
        if let Some(stall) = course.stall {
            if recent.len() == stall.points {
                recent.pop_front();
            }
            recent.push_back(accepted_step);
            // summed in one order every time (no running sum to drift)
            let sum: f64 = recent.iter().sum();
            if recent.len() == stall.points && sum < stall.points as f64 * stall.step {
                branch.stop = StopReason::Stalled {
                    parameter: lam,
                    points: stall.points,
                };
                return Ok(());
            }
        }
    }
    branch.stop = StopReason::MaxPoints;
    Ok(())
}

/// Sequential continuation along a fixed grid of points (a sweep) with a zero-order
/// predictor: every item `i` that is not `converged` is re-solved from a converged neighbour
/// `j = i ∓ 1` (`solve(i, j, &mut items[i], &items[j])` returns whether that worked; `j` lets
/// the caller record where a solution came from), in passes
/// alternating up (`j = i − 1`) and down (`j = i + 1`), at most `passes` passes, stopping
/// early when a pass changes nothing. Sequential, so bit-identical for any thread count.
///
/// # Errors
/// The first error of `solve`.
pub fn fill_from_neighbours<T, E>(
    items: &mut [T],
    passes: usize,
    converged: impl Fn(&T) -> bool,
    mut solve: impl FnMut(usize, usize, &mut T, &T) -> Result<bool, E>,
) -> Result<(), E> {
    let n = items.len();
    for pass in 0..passes {
        let mut changed = false;
        let order: Vec<usize> = if pass % 2 == 0 {
            (1..n).collect()
        } else {
            (0..n.saturating_sub(1)).rev().collect()
        };
        for i in order {
            let j = if pass % 2 == 0 { i - 1 } else { i + 1 };
            if converged(&items[i]) || !converged(&items[j]) {
                continue;
            }
            let (target, from) = if j < i {
                let (lo, hi) = items.split_at_mut(i);
                (&mut hi[0], &lo[j])
            } else {
                let (lo, hi) = items.split_at_mut(j);
                (&mut lo[i], &hi[0])
            };
            if solve(i, j, target, from)? {
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use math::DetMath;

    /// The unit circle `F(z, μ) = z² + μ² − 1 = 0`: folds at `μ = ±1` (where `z = 0`), exact
    /// Newton on the bordered system.
    struct Circle {
        corrections: usize,
        /// `Some(μ_r)`: a rough stretch above `μ_r` where every correction farther than
        /// [`ROUGH_REACH`] from the last accepted point fails (a tangle in miniature).
        rough_above: Option<f64>,
        /// `k > 0`: on the rough stretch every `k`-th correction reaches 4 · [`ROUGH_REACH`]
        /// (a tangle where a longer step succeeds now and then).
        lucky_every: usize,
        last: Option<DVector<f64>>,
    }

    /// The longest correction that succeeds on the rough stretch of [`Circle`].
    const ROUGH_REACH: f64 = 0.004;

    impl Corrector for Circle {
        type Raw = ();
        type Point = f64;
        type Error = OrbitError;

        fn correct(
            &mut self,
            pred: &DVector<f64>,
            border: &DVector<f64>,
            reference: &DVector<f64>,
        ) -> Result<Result<Node<()>, OrbitError>, OrbitError> {
            self.corrections += 1;
            if let (Some(mu), Some(last)) = (self.rough_above, &self.last) {
                let lucky = self.lucky_every > 0 && self.corrections % self.lucky_every == 0;
                let reach = if lucky {
                    4.0 * ROUGH_REACH
                } else {
                    ROUGH_REACH
                };
                if pred[1] > mu && (pred - last).norm() > reach {
                    return Ok(Err(OrbitError::Singular { what: "rough" }));
                }
            }
            let mut y = pred.clone();
            for it in 0..20 {
                let r = DVector::from_vec(vec![
                    y[0] * y[0] + y[1] * y[1] - 1.0,
                    border.dot(&(&y - pred)),
                ]);
                let jac = DMatrix::from_row_slice(1, 2, &[2.0 * y[0], 2.0 * y[1]]);
                if r.amax() < 1e-13 {
                    let Some(tangent) = bordered_tangent(&jac, reference) else {
                        return Ok(Err(OrbitError::Singular { what: "circle" }));
                    };
                    return Ok(Ok(Node {
                        y,
                        tangent,
                        iterations: it,
                        raw: (),
                    }));
                }
                let m =
                    DMatrix::from_row_slice(2, 2, &[2.0 * y[0], 2.0 * y[1], border[0], border[1]]);
                let Some(d) = m.lu().solve(&(-r)) else {
                    return Ok(Err(OrbitError::Singular { what: "circle" }));
                };
                y += d;
            }
            Ok(Err(OrbitError::NotConverged {
                what: "circle",
                iterations: 20,
                residual: f64::NAN,
            }))
        }

        fn accept(&mut self, node: &Node<()>) -> Result<BranchPoint<f64>, OrbitError> {
            self.last = Some(node.y.clone());
            Ok(BranchPoint {
                parameter: node.y[1],
                tangent_parameter: node.tangent[1],
                stability: None,
                orbit: node.y[0],
            })
        }
    }

    fn run(predictor: Predictor, max: f64) -> Branch<f64> {
        run_rough(predictor, max, None, None)
    }

    fn run_rough(
        predictor: Predictor,
        max: f64,
        rough_above: Option<f64>,
        stall: Option<Stall>,
    ) -> Branch<f64> {
        run_lucky(predictor, max, rough_above, 0, stall)
    }

    fn run_lucky(
        predictor: Predictor,
        max: f64,
        rough_above: Option<f64>,
        lucky_every: usize,
        stall: Option<Stall>,
    ) -> Branch<f64> {
        let mut c = Circle {
            corrections: 0,
            rough_above,
            lucky_every,
            last: None,
        };
        let y = DVector::from_vec(vec![(1.0_f64 - 0.25).sqrt(), -0.5]);
        let jac = DMatrix::from_row_slice(1, 2, &[2.0 * y[0], 2.0 * y[1]]);
        let tangent = bordered_tangent(&jac, &DVector::from_vec(vec![0.0, 1.0])).unwrap();
        let first = Node {
            y,
            tangent,
            iterations: 0,
            raw: (),
        };
        let mut branch = Branch::new(Parameter::Named("mu".into()), 1);
        branch.points.push(c.accept(&first).unwrap());
        let control = StepControl::shooting(0.05, 1e-9, max, 2.0);
        let course = Course {
            range: [-0.9, 2.0],
            direction: 1.0,
            max_points: 500,
            predictor,
            stall,
        };
        trace(&mut c, first, &control, &course, &mut branch).unwrap();
        branch
    }

    #[test]
    fn a_crawling_branch_stops_as_stalled_and_only_then() {
        let stall = Stall {
            points: 10,
            step: 0.01,
        };
        // smooth: the stall never fires, the branch goes round the fold as without it
        let smooth = run_rough(Predictor::Arclength, 0.2, None, Some(stall));
        assert_eq!(smooth, run(Predictor::Arclength, 0.2));
        // rough above μ = 0.3: steps fall to ≤ ROUGH_REACH, and once the last 10 steps
        // average below 0.01 the branch stops there instead of crawling on to the cap
        let b = run_rough(Predictor::Arclength, 0.2, Some(0.3), Some(stall));
        let StopReason::Stalled { parameter, points } = b.stop else {
            panic!("{:?}", b.stop);
        };
        assert_eq!(points, 10);
        assert_eq!(
            parameter.to_bits(),
            b.points.last().unwrap().parameter.to_bits()
        );
        // at most 10 crawling steps: μ advances by at most 10 · ROUGH_REACH past the edge
        assert!(
            parameter > 0.3 && parameter < 0.3 + 11.0 * ROUGH_REACH,
            "stopped at {parameter}"
        );
        let n = b.points.len();
        let mean = b.points[n - 11..]
            .windows(2)
            .map(|w| (w[1].parameter - w[0].parameter).dhypot(w[1].orbit - w[0].orbit))
            .sum::<f64>()
            / 10.0;
        assert!(mean < stall.step, "stopped at a mean step of {mean}");
        // without the stall the same branch crawls on to the cap
        let crawl = run_rough(Predictor::Arclength, 0.2, Some(0.3), None);
        assert_eq!(crawl.stop, StopReason::MaxPoints);
        assert_eq!(crawl.points[..n], b.points[..]);
    }

    /// A tangle where a longer step succeeds now and then: a count of short steps in a row
    /// would restart at each of them, the mean over the window still stops the branch, and
    /// only then (the window before the stop averaged at least the stall step).
    #[test]
    fn a_crawl_with_occasional_longer_steps_stops_on_the_mean() {
        let stall = Stall {
            points: 10,
            step: 0.01,
        };
        let b = run_lucky(Predictor::Arclength, 0.2, Some(0.3), 3, Some(stall));
        let StopReason::Stalled { parameter, .. } = b.stop else {
            panic!("{:?}", b.stop);
        };
        let steps: Vec<f64> = b
            .points
            .windows(2)
            .map(|w| (w[1].parameter - w[0].parameter).dhypot(w[1].orbit - w[0].orbit))
            .collect();
        let n = steps.len();
        let last: f64 = steps[n - 10..].iter().sum();
        assert!(last < 10.0 * stall.step, "{last}");
        // the lucky steps: some of the last ten were longer than the stall step, so ten short
        // steps in a row never happened
        assert!(
            steps[n - 10..].iter().any(|&d| d >= stall.step),
            "{:?}",
            &steps[n - 10..]
        );
        // the window one step earlier did not yet average below the stall step
        let before: f64 = steps[n - 11..n - 1].iter().sum();
        assert!(before >= 10.0 * stall.step, "{before}");
        assert!(parameter > 0.3, "stopped at {parameter}");
        // without the stall the same branch crawls on to the cap
        let crawl = run_lucky(Predictor::Arclength, 0.2, Some(0.3), 3, None);
        assert_eq!(crawl.stop, StopReason::MaxPoints);
    }

    #[test]
    fn a_stall_with_no_points_or_no_step_is_an_error_naming_the_field() {
        let ok = ContinuationOptions::with_corrector(());
        for (stall, field) in [
            (
                Stall {
                    points: 0,
                    step: 0.1,
                },
                "stall.points",
            ),
            (
                Stall {
                    points: 3,
                    step: 0.0,
                },
                "stall.step",
            ),
            (
                Stall {
                    points: 3,
                    step: f64::NAN,
                },
                "stall.step",
            ),
        ] {
            let e = ContinuationOptions {
                stall: Some(stall),
                ..ok
            }
            .validate_steps()
            .unwrap_err();
            assert!(e.to_string().contains(field), "{e}");
        }
        ContinuationOptions {
            stall: Some(Stall {
                points: 1,
                step: 1e-3,
            }),
            ..ok
        }
        .validate_steps()
        .unwrap();
    }

    #[test]
    fn arclength_goes_round_the_fold_of_a_circle_and_locates_it() {
        let b = run(Predictor::Arclength, 0.2);
        // up to μ = 1, round the fold, back down past μ = −0.9 on the other half (z < 0)
        assert_eq!(
            b.stop,
            StopReason::LeftRange {
                parameter: b.points.last().unwrap().parameter
            }
        );
        assert_eq!(b.folds.len(), 1);
        let f = b.folds[0];
        assert!((f.parameter - 1.0).abs() < 1e-3, "fold at {}", f.parameter);
        let (a, c) = (&b.points[f.after_index], &b.points[f.after_index + 1]);
        assert!(a.orbit > 0.0 && c.orbit < 0.0);
        for p in &b.points {
            assert!((p.orbit * p.orbit + p.parameter * p.parameter - 1.0).abs() < 1e-12);
        }
        assert!(b.points.last().unwrap().orbit < 0.0);
    }

    #[test]
    fn natural_stops_at_the_fold_of_a_circle() {
        let b = run(Predictor::Natural, 0.2);
        let StopReason::StepTooSmall { parameter, .. } = b.stop else {
            panic!("{:?}", b.stop);
        };
        assert!(b.folds.is_empty());
        assert!(
            parameter < 1.0 && 1.0 - parameter < 1e-6,
            "stopped at {parameter}"
        );
        assert!(b.points.windows(2).all(|w| w[1].parameter > w[0].parameter));
        assert!(b.points.iter().all(|p| p.orbit > 0.0));
    }

    #[test]
    fn step_control_grows_to_its_cap_and_counts_points() {
        let b = run(Predictor::Arclength, 0.05);
        // constant step Δs = 0.05 (initial = max) on the unit circle: each step advances the
        // angle by exactly asin(Δs) (predictor along the tangent, corrector normal to it), from
        // θ = acos(−0.5) (μ = −0.5, z > 0) round the fold to the first point past μ = −0.9
        // (θ = −acos(−0.9)).
        let arc = (-0.5_f64).dacos() + (-0.9_f64).dacos();
        let dtheta = 0.05_f64.dasin();
        let steps = (b.points.len() - 1) as f64;
        assert!(
            steps * dtheta >= arc && steps * dtheta < arc + dtheta,
            "{steps} steps of {dtheta} for the arc {arc}"
        );
    }

    #[test]
    fn neighbour_fill_alternates_and_stops_when_nothing_changes() {
        // converged only at index 2; a solve from a converged neighbour always works
        let mut items = vec![false, false, true, false, false];
        let mut calls = vec![];
        fill_from_neighbours::<bool, ()>(
            &mut items,
            4,
            |c| *c,
            |i, j, t, f| {
                calls.push(i);
                assert_eq!(i.abs_diff(j), 1);
                assert!(*f);
                *t = true;
                Ok(true)
            },
        )
        .unwrap();
        assert!(items.iter().all(|c| *c));
        // pass 1 (up): 3, 4; pass 2 (down): 1, 0; pass 3 changes nothing
        assert_eq!(calls, vec![3, 4, 1, 0]);
        let mut none = vec![false, false];
        fill_from_neighbours::<bool, ()>(&mut none, 4, |c| *c, |_, _, _, _| Ok(true)).unwrap();
        assert_eq!(none, vec![false, false]);
        let mut err = vec![true, false];
        assert_eq!(
            fill_from_neighbours(&mut err, 1, |c| *c, |_, _, _, _| Err("e")),
            Err("e")
        );
    }

    #[test]
    fn step_control_rejects_bad_fields() {
        let ok = StepControl::harmonic(0.01, 1e-6, 0.1);
        assert!(ok.validate().is_ok());
        assert_eq!(ok.initial.to_bits(), 0.01_f64.to_bits());
        assert_eq!(
            StepControl::harmonic(1.0, 1e-6, 0.1).initial.to_bits(),
            0.1_f64.to_bits()
        );
        for bad in [
            StepControl { min: 0.0, ..ok },
            StepControl { max: 1e-9, ..ok },
            StepControl {
                initial: f64::NAN,
                ..ok
            },
            StepControl { grow: 0.5, ..ok },
            StepControl { fail: 1.0, ..ok },
            StepControl { shrink: 0.0, ..ok },
            StepControl {
                min_cos: Some(2.0),
                ..ok
            },
            StepControl {
                max_correction: Some(0.0),
                ..ok
            },
        ] {
            assert!(bad.validate().is_err(), "{bad:?}");
        }
    }

    #[test]
    fn bordered_tangent_is_the_unit_null_vector_oriented_by_the_reference() {
        let jac = DMatrix::from_row_slice(1, 2, &[2.0, 0.0]);
        let t = bordered_tangent(&jac, &DVector::from_vec(vec![0.3, -1.0])).unwrap();
        assert!((t[0]).abs() < 1e-15 && (t[1] + 1.0).abs() < 1e-15);
        // singular bordered matrix and wrong shapes
        assert!(bordered_tangent(&jac, &DVector::from_vec(vec![1.0, 0.0])).is_none());
        assert!(bordered_tangent(&jac, &DVector::from_vec(vec![1.0])).is_none());
    }
}
