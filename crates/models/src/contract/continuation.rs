//! One-parameter continuation of periodic orbits and codim-2 curves of their special points,
//! for front ends (`[continuation]` in a study file, the CLI, Python): the request
//! ([`ContinuationRequest`]), the result in the model's units ([`ContinuationOutput`]) and the
//! one runner on the `orbit` crate ([`continue_on`]) that every model with a continuation uses.
//!
//! **Branch.** From the model's settled start (its shooting guess), the period-`T` orbit is
//! corrected by shooting and continued by pseudo-arclength in the parameter `λ` from its start
//! value towards `to` ([`orbit::OrbitProblem::continuation`]): every point with its Floquet
//! multipliers and stability; the special points located on the way — grazing (an extremum of
//! an event function through zero: a contact appears or vanishes), fold (a multiplier through
//! `+1`), period doubling (through `−1`), Neimark–Sacker, contact change (a local extremum).
//! The arclength weighs `λ` by `λ/(max_step/2)`, so that a step of the tracer's largest
//! arclength step (2) moves `λ` by at most `max_step`; the state is weighed by the model's
//! state scale.
//!
//! **Codim-2 curves.** From each located special point of a requested kind (at most
//! `max_curves`, in branch order), the augmented system — the shooting residual plus the
//! defining condition (`h(x(t_g)) = 0, ḣ = 0` for a grazing; `det(Φ ∓ I) = 0` by a bordered
//! system for a fold or a period doubling) — is continued in the second parameter `λ₂`, with
//! `λ` an unknown ([`orbit::OrbitProblem::continue_codim2`]), in both directions. Each curve
//! ends with a named reason (range left, point cap, a degenerate defining condition,
//! corrector failure), never silently.

use orbit::{Extremum, Parameter, SpecialKind, StopReason};
use system::SecondOrderSystem;

use super::{PointError, Settings, WithContext};

/// Which special points end a branch, or which start codim-2 curves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpecialFamily {
    /// Any grazing (every event function, maximum or minimum).
    Grazing,
    /// A fold.
    Fold,
    /// A period doubling.
    PeriodDoubling,
}

impl SpecialFamily {
    /// The name in a study file.
    pub fn name(self) -> &'static str {
        match self {
            Self::Grazing => "grazing",
            Self::Fold => "fold",
            Self::PeriodDoubling => "period-doubling",
        }
    }

    /// The family of a study-file name.
    ///
    /// # Errors
    /// An unknown name, with the known ones.
    pub fn parse(name: &str) -> Result<Self, PointError> {
        [Self::Grazing, Self::Fold, Self::PeriodDoubling]
            .into_iter()
            .find(|f| f.name() == name)
            .ok_or_else(|| {
                PointError::Input(format!(
                    "`{name}` is not a kind of special point; kinds: \"grazing\", \"fold\", \
                     \"period-doubling\""
                ))
            })
    }

    fn holds(self, kind: SpecialKind) -> bool {
        matches!(
            (self, kind),
            (Self::Grazing, SpecialKind::Grazing { .. })
                | (Self::Fold, SpecialKind::Fold)
                | (Self::PeriodDoubling, SpecialKind::PeriodDoubling)
        )
    }
}

/// A continuation asked by a front end: every number finite and checked by the front end
/// (the parameter names by the model).
#[derive(Debug, Clone, PartialEq)]
pub struct ContinuationRequest {
    /// The continued parameter (the model's names: [`Model::continuation_parameters`]).
    ///
    /// [`Model::continuation_parameters`]: super::Model::continuation_parameters
    pub parameter: String,
    /// The end of the branch's range (the start is the parameter's value in the point).
    pub to: f64,
    /// Largest change of the parameter per step (> 0, in its unit; `None`: a fiftieth of the
    /// range).
    pub max_step: Option<f64>,
    /// Most branch points.
    pub max_points: usize,
    /// End the branch after the first special point of one of these kinds.
    pub stop_at: Vec<SpecialFamily>,
    /// End the branch at its first unstable point after a stable one.
    pub stop_at_instability: bool,
    /// Report the contact changes (a local extremum of an event function through zero,
    /// detected between two branch points, not located) among the special points.
    pub contact_changes: bool,
    /// Codim-2 curves from the branch's special points.
    pub codim2: Option<Codim2Request>,
}

/// The codim-2 curves of a [`ContinuationRequest`].
#[derive(Debug, Clone, PartialEq)]
pub struct Codim2Request {
    /// The second parameter (a name of [`Model::continuation_parameters`] other than the
    /// branch's).
    ///
    /// [`Model::continuation_parameters`]: super::Model::continuation_parameters
    pub parameter: String,
    /// Its range `[lo, hi]` (the curve stops where it leaves it).
    pub range: [f64; 2],
    /// Which special points start curves.
    pub kinds: Vec<SpecialFamily>,
    /// Largest change of the second parameter per step (> 0; `None`: a fiftieth of the
    /// range).
    pub max_step: Option<f64>,
    /// Most points per direction of a curve.
    pub max_points: usize,
    /// Most special points continued.
    pub max_curves: usize,
    /// A grazing curve follows the global extremum of its event function: where another
    /// local extremum takes over (a double grazing), it goes on along that one's grazing, at
    /// most this many times per direction ([`orbit::OrbitProblem::continue_grazing_envelope`]).
    pub max_switches: usize,
}

/// One point of a branch, in the model's units.
#[derive(Debug, Clone, PartialEq)]
pub struct BranchRow {
    /// The parameter.
    pub value: f64,
    /// The orbit's state on the section (the model's coordinates).
    pub state: Vec<f64>,
    /// Largest Floquet multiplier modulus.
    pub max_multiplier: f64,
    /// Stable (every multiplier inside the unit circle).
    pub stable: bool,
    /// Located events per period.
    pub events: usize,
    /// `[min, max]` of every event function over the orbit (the model's event units).
    pub extrema: Vec<[f64; 2]>,
}

/// A special point of a branch, in the model's units.
#[derive(Debug, Clone, PartialEq)]
pub struct SpecialRow {
    /// What happens ([`ContinuationOutput::label`]).
    pub kind: String,
    /// The parameter.
    pub value: f64,
    /// Located to the tolerance (else only detected between two points).
    pub located: bool,
    /// Width of the last bracket: the precision of `value`.
    pub precision: f64,
    /// The orbit's state.
    pub state: Vec<f64>,
    /// Stability of the orbit there.
    pub stable: bool,
}

/// One codim-2 curve (one direction from its start).
#[derive(Debug, Clone, PartialEq)]
pub struct CurveRow {
    /// Index of its start in [`ContinuationOutput::special`].
    pub special: usize,
    /// The start's kind.
    pub kind: String,
    /// Initial direction of the second parameter (`+1`, `−1`).
    pub direction: f64,
    /// `(λ, λ₂, stable, piece)` in trace order, from the start: `piece` numbers the smooth
    /// pieces of a grazing envelope (a double grazing between two), 0 for other curves.
    pub points: Vec<(f64, f64, bool, usize)>,
    /// Why it stopped.
    pub stop: String,
}

/// A continuation's result.
#[derive(Debug, Clone, PartialEq)]
pub struct ContinuationOutput {
    /// The continued parameter and its unit.
    pub parameter: (String, String),
    /// The state coordinates and units.
    pub coordinates: Vec<(String, String)>,
    /// The event functions' names (index order).
    pub events: Vec<String>,
    /// The branch.
    pub points: Vec<BranchRow>,
    /// Its special points.
    pub special: Vec<SpecialRow>,
    /// Why the branch stopped.
    pub stop: String,
    /// The second parameter and its unit (codim-2).
    pub second: Option<(String, String)>,
    /// The codim-2 curves.
    pub curves: Vec<CurveRow>,
    /// Codim-2 starts that gave no curve, with the reason.
    pub curve_failures: Vec<String>,
}

impl ContinuationOutput {
    /// A special kind in words, with the event names.
    pub fn label(events: &[String], kind: SpecialKind) -> String {
        let event = |e: usize| {
            events
                .get(e)
                .cloned()
                .unwrap_or_else(|| format!("event {e}"))
        };
        match kind {
            SpecialKind::Grazing { event: e, extremum } => format!(
                "grazing {} ({})",
                event(e),
                match extremum {
                    Extremum::Max => "max",
                    Extremum::Min => "min",
                }
            ),
            SpecialKind::Fold => "fold".to_owned(),
            SpecialKind::PeriodDoubling => "period-doubling".to_owned(),
            SpecialKind::NeimarkSacker => "neimark-sacker".to_owned(),
            SpecialKind::ContactChange { event: e } => format!("contact-change {}", event(e)),
        }
    }
}

/// Why a branch or curve stopped, in words (parameter values in the model's units: `λ/conv`
/// of the continued parameter, `first_conv` of the first parameter of a codim-2 curve).
pub fn stop_text(events: &[String], stop: &StopReason, conv: f64, first_conv: f64) -> String {
    let v = |p: f64| super::fmt_sig(p / conv, 6);
    match stop {
        StopReason::ReachedEnd => "reached the end of the range".to_owned(),
        StopReason::LeftRange { parameter } => {
            format!("turned back and left the range at {}", v(*parameter))
        }
        StopReason::MaxPoints => "point cap reached".to_owned(),
        StopReason::StepTooSmall { parameter, cause } => format!(
            "corrector failed down to the smallest step at {}{}",
            v(*parameter),
            cause
                .as_ref()
                .map(|c| format!(" ({c})"))
                .unwrap_or_default()
        ),
        StopReason::SpecialPoint { parameter, kind } => format!(
            "stopped after its first {} at {}",
            ContinuationOutput::label(events, *kind),
            v(*parameter)
        ),
        StopReason::LostStability { parameter } => {
            format!("lost stability at {}", v(*parameter))
        }
        StopReason::Stalled { parameter, points } => {
            format!(
                "stalled at {} (its last {points} steps tiny)",
                v(*parameter)
            )
        }
        StopReason::InitialSolveFailed { residual_norm } => format!(
            "the start did not converge (residual {})",
            super::fmt_sig(*residual_norm, 6)
        ),
        StopReason::Degenerate {
            parameter,
            condition,
        } => format!(
            "the defining condition degenerates ({condition:?}) at {}",
            v(*parameter)
        ),
        StopReason::FirstLeftRange { parameter, first } => format!(
            "the first parameter left its range ({}) at {}",
            super::fmt_sig(*first / first_conv, 6),
            v(*parameter)
        ),
        other => format!("{other:?}"),
    }
}

/// A continuation parameter of a model: its name and unit, the `orbit` parameter it drives,
/// and `conv`, the `orbit` value per unit of the model's (the base frequency is
/// dimensionless, `ω̄_c = conv · ω₁`).
#[derive(Debug, Clone)]
pub struct Axis {
    /// Name (as in the study file).
    pub name: String,
    /// Unit.
    pub unit: String,
    /// The `orbit` parameter.
    pub parameter: Parameter,
    /// `orbit` value per model unit.
    pub conv: f64,
    /// The value at the start (model units).
    pub start: f64,
}

/// What a model gives [`continue_on`] besides the system.
#[derive(Debug, Clone)]
pub struct Setup {
    /// For messages (`"liu2021"`).
    pub what: &'static str,
    /// The orbit period at the start (the system's time units).
    pub period: f64,
    /// The shooting guess (the settled state).
    pub guess: Vec<f64>,
    /// The state's weight in the arclength (its typical size).
    pub state_scale: f64,
    /// State coordinates and units.
    pub coordinates: Vec<(String, String)>,
    /// Event names.
    pub events: Vec<String>,
    /// The continued parameter.
    pub axis: Axis,
    /// The second parameter of codim-2 curves.
    pub second: Option<Axis>,
}

/// Check `request` against the start values of its parameters (cheap: a model calls it
/// before its start's time integration; [`continue_on`] calls it again): the branch's range
/// must hold more than its start, and a codim-2 range must hold the second parameter's start.
///
/// # Errors
/// [`PointError::Input`] naming the key, its bound and the start value.
pub fn check_request(
    axis: &Axis,
    second: Option<&Axis>,
    request: &ContinuationRequest,
) -> Result<(), PointError> {
    let width = (request.to - axis.start).abs();
    if width == 0.0 || !width.is_finite() {
        return Err(PointError::Input(format!(
            "continuation.to = {} must differ from the start value {} of `{}`",
            request.to, axis.start, axis.name
        )));
    }
    if let (Some(c2), Some(ax2)) = (&request.codim2, second) {
        let [lo, hi] = c2.range;
        if !(lo <= ax2.start && ax2.start <= hi) {
            return Err(PointError::Input(format!(
                "continuation.codim2.range = [{lo}, {hi}] must contain the start value {} of \
                 `{}` (its value in [overrides], or the model's default)",
                ax2.start, ax2.name
            )));
        }
    }
    Ok(())
}

/// Continue the orbit of `sys` as `request` asks, with the shooting settings `s` (`rtol`,
/// `tol`, `max_iter`, `segments`, `flow_method`).
///
/// # Errors
/// A bad request (a range that holds no step, codim-2 with multiple shooting), the orbit
/// problem's or the start's failure. A branch or curve that stops early is a result with its
/// reason, not an error.
pub fn continue_on<S: SecondOrderSystem + Clone>(
    sys: S,
    setup: &Setup,
    request: &ContinuationRequest,
    s: &Settings,
) -> Result<ContinuationOutput, PointError> {
    let what = setup.what;
    let ax = &setup.axis;
    check_request(ax, setup.second.as_ref(), request)?;
    let width = (request.to - ax.start).abs();
    let shooting = super::shoot::shooting_options(s);
    if request.codim2.is_some() && shooting.segments != 1 {
        return Err(PointError::Input(format!(
            "codim-2 curves use single shooting: set segments = 1 (got {})",
            shooting.segments
        )));
    }
    let flow = super::shoot::flow_options(s);
    let problem = |sys: S| {
        orbit::OrbitProblem::new(sys, setup.period)
            .and_then(|p| p.with_flow_options(flow))
            .context(&format!("{what} orbit problem"))
    };
    let events = &setup.events;
    let n_events = sys.n_events();
    let mut stop_at = Vec::new();
    for f in &request.stop_at {
        match f {
            SpecialFamily::Fold => stop_at.push(SpecialKind::Fold),
            SpecialFamily::PeriodDoubling => stop_at.push(SpecialKind::PeriodDoubling),
            SpecialFamily::Grazing => {
                for event in 0..n_events {
                    for extremum in [Extremum::Max, Extremum::Min] {
                        stop_at.push(SpecialKind::Grazing { event, extremum });
                    }
                }
            }
        }
    }
    let (lo, hi) = (ax.start.min(request.to), ax.start.max(request.to));
    let scale = 0.5 * request.max_step.unwrap_or(width / 50.0) * ax.conv;
    let opts = orbit::ContinuationOptions {
        initial_step: 1.0,
        max_step: 2.0,
        min_step: 1e-6,
        max_points: request.max_points,
        corrector: orbit::ShootingCorrection {
            parameter: ax.parameter.clone(),
            range: [lo * ax.conv, hi * ax.conv],
            direction: (request.to - ax.start).signum(),
            parameter_scale: scale,
            state_scale: setup.state_scale,
            locate_tol: 1e-6,
            locate_samples: 4,
            shooting,
            stop_at,
            stop_at_instability: request.stop_at_instability,
            ..orbit::ShootingCorrection::default()
        },
        ..orbit::ContinuationOptions::default()
    };
    let mut prob = problem(sys.clone())?;
    let branch = prob
        .continuation(&setup.guess, ax.start * ax.conv, &opts)
        .context(&format!("{what} continuation in {}", ax.name))?;
    // the special points reported (and started from): contact changes only when asked
    let shown: Vec<&orbit::SpecialPoint<orbit::ShootingPoint>> = branch
        .special
        .iter()
        .filter(|sp| {
            request.contact_changes || !matches!(sp.kind, SpecialKind::ContactChange { .. })
        })
        .collect();
    let row = |p: &orbit::ShootingBranchPoint| BranchRow {
        value: p.parameter / ax.conv,
        state: p.x0.clone(),
        max_multiplier: p.floquet.max_modulus,
        stable: p.floquet.stable,
        events: p.events,
        extrema: p.extrema.clone(),
    };
    let mut out = ContinuationOutput {
        parameter: (ax.name.clone(), ax.unit.clone()),
        coordinates: setup.coordinates.clone(),
        events: events.clone(),
        points: branch.points.iter().map(row).collect(),
        special: shown
            .iter()
            .map(|sp| SpecialRow {
                kind: ContinuationOutput::label(events, sp.kind),
                value: sp.point.parameter / ax.conv,
                located: sp.located,
                precision: sp.precision() / ax.conv,
                state: sp.point.x0.clone(),
                stable: sp.point.floquet.stable,
            })
            .collect(),
        stop: stop_text(events, &branch.stop, ax.conv, ax.conv),
        second: None,
        curves: Vec::new(),
        curve_failures: Vec::new(),
    };
    let Some(c2) = &request.codim2 else {
        return Ok(out);
    };
    let Some(ax2) = &setup.second else {
        return Err(PointError::Input(
            "codim-2 curves need a second parameter".into(),
        ));
    };
    out.second = Some((ax2.name.clone(), ax2.unit.clone()));
    let starts = shown
        .iter()
        .enumerate()
        .filter(|(_, sp)| sp.located && c2.kinds.iter().any(|f| f.holds(sp.kind)))
        .take(c2.max_curves);
    for (k, sp) in starts {
        for dir in [-1.0, 1.0] {
            let mut o = orbit::Codim2ContinuationOptions::codim2(
                ax.parameter.clone(),
                ax2.parameter.clone(),
            );
            o.initial_step = 0.5;
            o.max_step = 2.0;
            o.max_points = c2.max_points;
            o.corrector.first_range = [lo * ax.conv, hi * ax.conv];
            o.corrector.first_scale = scale;
            o.corrector.range = [c2.range[0] * ax2.conv, c2.range[1] * ax2.conv];
            o.corrector.direction = dir;
            let step2 = c2.max_step.unwrap_or((c2.range[1] - c2.range[0]) / 50.0);
            o.corrector.parameter_scale = 0.5 * step2 * ax2.conv;
            o.corrector.state_scale = setup.state_scale;
            o.corrector.shooting = shooting;
            o.corrector.locate_tol = 1e-3;
            let label = ContinuationOutput::label(events, sp.kind);
            let point = |(k, q): (usize, &orbit::Codim2BranchPoint)| {
                (
                    q.first_parameter / ax.conv,
                    q.parameter / ax2.conv,
                    q.floquet.stable,
                    k,
                )
            };
            let curve = problem(sys.clone()).and_then(|mut p| {
                if matches!(sp.kind, SpecialKind::Grazing { .. }) {
                    let env = p
                        .continue_grazing_envelope(sp, &o, c2.max_switches)
                        .context(&format!("{what} codim-2 curve"))?;
                    let stop = env.stop().map_or_else(
                        || "no piece".to_owned(),
                        |st| stop_text(events, st, ax2.conv, ax.conv),
                    );
                    Ok((
                        env.points_by_piece().into_iter().map(point).collect(),
                        format!(
                            "{stop}; {} piece(s), {} switch(es) of the extremum, envelope end {:?}",
                            env.pieces.len(),
                            env.pieces.len().saturating_sub(1),
                            env.end
                        ),
                    ))
                } else {
                    let c = p
                        .continue_codim2(sp, &o)
                        .context(&format!("{what} codim-2 curve"))?;
                    Ok((
                        c.points.iter().map(|q| point((0, q))).collect(),
                        stop_text(events, &c.stop, ax2.conv, ax.conv),
                    ))
                }
            });
            match curve {
                Ok((points, stop)) => out.curves.push(CurveRow {
                    special: k,
                    kind: label,
                    direction: dir,
                    points,
                    stop,
                }),
                Err(e) => out.curve_failures.push(format!(
                    "{label} at {} {} (direction {dir:+}): {e}",
                    super::fmt_sig(sp.point.parameter / ax.conv, 6),
                    ax.unit
                )),
            }
        }
    }
    Ok(out)
}
