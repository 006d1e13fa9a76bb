//! The Liu 2021 model of the [`REGISTRY`](crate::contract::REGISTRY) (`liu2021`): time
//! stepping (with the long-window statistics), harmonic balance, shooting and the bifurcation
//! study.

use std::collections::BTreeMap;
use std::sync::Arc;

use serde_json::{Value as J, json};

use crate::contract::lyapunov::{
    LYAPUNOV, LYAPUNOV_BATCHES, LYAPUNOV_EXPONENTS, LYAPUNOV_PERIODS, LYAPUNOV_RTOL,
    lyapunov_columns, lyapunov_plan, lyapunov_steps, push_lyapunov, run_lyapunov, tighter,
};
use crate::contract::shoot::shoot_on;
use crate::contract::{
    self, Adapter, ChoiceInfo, Context, Job, Kind, Method, MethodInfo, ModelInfo, Point,
    PointError, Preset, Record, SettingDef, Settings, TOLERANCE_CHECK, Value, WithContext, api,
    apply_values, bifurcation_outputs, bifurcation_record, choice_info, no_initial, outs,
    outs_stepped, params_of, reject_legacy, run_stepped, take_choice, wrong_method,
};
use crate::liu2021;

/// Liu, Lv, Zhao 2021: the non-circular face gear rattle model (Eq. 22).
#[derive(Debug, Clone, Copy)]
pub struct Liu;

fn liu_unit(k: &str) -> &'static str {
    match k {
        "module" | "e0" | "er" | "half_backlash" => "m",
        "pressure_angle" | "phase_stiffness" | "phase_error" => "rad",
        "load_torque" => "N·m",
        "inertia" => "kg·m²",
        "k0" | "kr" => "N/m",
        "omega1" => "rad/s",
        _ => "1",
    }
}

/// The Liu outputs: the first four on both methods; HBM adds convergence, the residual norm
/// `‖s‖₂` ([`hbm::PeriodicSolution::residual_norm`], units of the dimensionless forcing) and
/// the truncation indicator ([`hbm::PeriodicSolution::truncation`]).
const LIU_OUT: &[(&str, &str)] = &[
    ("rsv", "1"),
    ("ppv", "1"),
    ("q_min", "1"),
    ("q_max", "1"),
    ("converged", "1"),
    ("residual_norm", "1"),
    ("truncation", "1"),
];

/// Fewest samples of the recorded window (ppv, q_min, q_max are read from them).
const LIU_MIN_SAMPLES: f64 = 64.0;
/// Most samples of the recorded window.
const LIU_MAX_SAMPLES: f64 = 1e7;

/// The time-stepping settings (`max_step` and `rtol`, entries 3 and 4, are those of the
/// bifurcation study too).
pub(crate) const LIU_TS: &[SettingDef] = &[
    SettingDef {
        name: "transient_periods",
        kind: Kind::Num {
            lo: 0.0,
            hi: 1e4,
            default: USER_TRANSIENT,
        },
        doc: "periods T = 2π/ω̄_c integrated and discarded before the first window (and before \
              the one-period record)",
    },
    SettingDef {
        name: "record_periods",
        kind: Kind::Num {
            lo: 1e-3,
            hi: 1e3,
            default: 1.0,
        },
        doc: "periods of the one-period record (columns rsv_one_period, ppv_one_period); with \
              settle = \"fixed\" also the judged window (then a whole number ≥ 1, and one run \
              gives both unless lyapunov is on)",
    },
    SettingDef {
        name: "sample_step",
        kind: Kind::Num {
            lo: 1e-6,
            hi: 1e3,
            default: 0.1,
        },
        doc: "output sampling interval Δτ; the one-period record must hold 64 … 1e7 samples \
              (the windows sample at the largest Δτ ≤ sample_step that divides T)",
    },
    SettingDef {
        name: "max_step",
        kind: Kind::Num {
            lo: 1e-6,
            hi: 1e3,
            default: 0.5,
        },
        doc: "largest integrator step Δτ",
    },
    SettingDef {
        name: "rtol",
        kind: Kind::Num {
            lo: 1e-14,
            hi: 1e-2,
            default: 1e-8,
        },
        doc: "relative tolerance of Dormand–Prince 5(4)",
    },
    TOLERANCE_CHECK,
    SettingDef {
        name: "settle",
        kind: Kind::Name {
            options: &["section", "fixed"],
            default: "section",
        },
        doc: "\"section\": after transient_periods, windows of window_periods periods; a window \
              whose Poincaré section still holds a transient (repeats over its last half, not \
              the whole; or repeats nowhere while the next window repeats) is discarded until \
              max_transient_periods; the kept window gives rsv, ppv and the motion. \"fixed\": one window of record_periods after \
              transient_periods, nothing discarded (fewer than 20 periods: motion unsettled)",
    },
    SettingDef {
        name: "window_periods",
        kind: Kind::Int {
            lo: 20,
            hi: 10_000,
            default: Some(50),
        },
        doc: "periods of each window with settle = \"section\" (≥ 20: the section test and \
              the 0–1 test need them)",
    },
    SettingDef {
        name: "max_transient_periods",
        kind: Kind::Num {
            lo: 0.0,
            hi: 1e4,
            default: USER_MAX_TRANSIENT,
        },
        doc: "cap on the periods integrated before the kept window with settle = \"section\" \
              (whole windows: ⌊(cap − transient_periods)/window_periods⌋ may be discarded, none \
              when transient_periods ≥ cap)",
    },
    SettingDef {
        name: "robustness",
        kind: Kind::Name {
            options: &["off", "on"],
            default: "off",
        },
        doc: "\"on\": the spread over the validation's variants (rtol/100, a second window, a \
              second start; models::liu2021::robust_window, about 4× the work) in columns robust, \
              rsv_lo, rsv_hi, ppv_spread and the long-window columns (windows of ≥ 20 periods); \
              \"off\": those columns are absent and the study summary says so",
    },
    LYAPUNOV,
    LYAPUNOV_PERIODS,
    LYAPUNOV_EXPONENTS,
    LYAPUNOV_RTOL,
    LYAPUNOV_BATCHES,
];

/// Default cap on the periods integrated before the kept window (`max_transient_periods`): the
/// transients of Liu Fig. 11 near the bilateral onset last up to about 50 periods.
const USER_MAX_TRANSIENT: f64 = 200.0;

/// Default `transient_periods` of a time-stepping point: the validation's (10 periods: the free
/// transient decays by `e^{-17}` per period at Table 1 values).
const USER_TRANSIENT: f64 = 10.0;

/// The time-stepping outputs before the optional long-window columns: the kept window's rattle
/// state, ppv and extremes; its motion code and whether it settled
/// ([`crate::response::window_motion`]); the periods integrated before it; the one-period
/// figures. With `robustness = "on"`, [`LIU_TS_ROBUST_OUT`] and the long-window columns follow.
const LIU_TS_OUT: &[(&str, &str)] = &[
    ("rsv", "1"),
    ("ppv", "1"),
    ("q_min", "1"),
    ("q_max", "1"),
    ("motion", "1"),
    ("settled", "1"),
    ("transient_periods_used", "1"),
    ("rsv_one_period", "1"),
    ("ppv_one_period", "1"),
];

/// The robustness columns (`robustness = "on"`): 1 when every variant agrees on the rattle state
/// and the window is periodic in every variant with its ppv reproducible to
/// [`crate::response::SETTLED`] ([`crate::response::window_unsettled`]), else 0; the rsv range and
/// the relative ppv spread over the variants.
const LIU_TS_ROBUST_OUT: &[(&str, &str)] = &[
    ("robust", "1"),
    ("rsv_lo", "1"),
    ("rsv_hi", "1"),
    ("ppv_spread", "1"),
];

pub(crate) const LIU_HBM: &[SettingDef] = &[
    SettingDef {
        name: "tol",
        kind: Kind::Num {
            lo: 1e-14,
            hi: 1e-2,
            default: 1e-9,
        },
        doc: "Newton residual tolerance",
    },
    SettingDef {
        name: "max_iter",
        kind: Kind::Int {
            lo: 1,
            hi: 10_000,
            default: Some(60),
        },
        doc: "Newton iterations",
    },
    SettingDef {
        name: "samples",
        kind: Kind::Int {
            lo: 8,
            hi: 65_536,
            default: None,
        },
        doc: "AFT samples per period (absent: smallest power of two ≥ 8 × harmonics)",
    },
    SettingDef {
        name: "full_r",
        kind: Kind::Int {
            lo: 1,
            hi: 8,
            default: None,
        },
        doc: "full basis with K = R·Z2 + 2 harmonics (absent: the paper's 15-unknown basis)",
    },
    SettingDef {
        name: "stability",
        kind: Kind::Name {
            options: &["on", "off"],
            default: "on",
        },
        doc: "\"on\": column stable, the Floquet verdict of the converged orbit (multipliers of \
              its event-located period map); \"off\": no column (the study summary says so)",
    },
    SettingDef {
        name: "confirm",
        kind: Kind::Name {
            options: &["off", "on"],
            default: "off",
        },
        doc: "\"on\": integrate from the converged orbit's state at τ = 0 (10 transient periods, \
              windows of 50, up to 200 periods settling: the time-stepping defaults) and set \
              confirmed_by_time_stepping = 1 when the settled window is periodic with the \
              orbit's rattle state (ppv_time_stepping: its ppv); \"off\": both columns absent \
              and the study summary says so",
    },
];

/// The HBM output after [`LIU_OUT`]: the orbit's stability from the Floquet multipliers of its
/// period map ([`liu2021::shooting_stability`]: 1 when converged and every multiplier modulus is
/// `≤ 1 + system::STABILITY_TOLERANCE`, 0 when unstable or not converged).
const LIU_HBM_OUT: &[(&str, &str)] = &[("stable", "1")];

/// The HBM outputs of `confirm = "on"`: 1 when time stepping from the orbit's state at `τ = 0`
/// settles on a periodic window with the orbit's rattle state (0 otherwise, or not converged),
/// and that window's ppv (the orbit's ppv when not converged: nothing was integrated).
const LIU_HBM_CONFIRM_OUT: &[(&str, &str)] = &[
    ("confirmed_by_time_stepping", "1"),
    ("ppv_time_stepping", "1"),
];

/// The Liu shooting outputs: the orbit's rattle state from its gap margins, the section state,
/// the multipliers and the test functions whose sign change between two rows marks a grazing
/// (`gap_max_drive`: unilateral onset; `gap_max_back`: bilateral onset) or a period doubling
/// (`det_phi_plus_i`).
const LIU_SHOOT_OUT: &[(&str, &str)] = &[
    ("rsv", "1"),
    ("q0", "1"),
    ("dq0", "1"),
    ("events_per_period", "1"),
    ("max_multiplier", "1"),
    ("mu1_re", "1"),
    ("mu1_im", "1"),
    ("mu2_re", "1"),
    ("mu2_im", "1"),
    ("stable", "1"),
    ("det_phi_plus_i", "1"),
    ("gap_max_drive", "1"),
    ("gap_max_back", "1"),
    ("newton_iterations", "1"),
    ("residual", "1"),
];

/// The shooting guess of Liu: dimensionless periods of its time integration.
const LIU_SHOOT_TRANSIENT: SettingDef = SettingDef {
    name: "transient_periods",
    kind: Kind::Num {
        lo: 0.0,
        hi: 1e4,
        default: 200.0,
    },
    doc: "periods of time integration from `initial` (or the quasi-static contact at rest) \
          whose end state is the shooting guess",
};

/// The shooting settings of Liu.
/// The settings of `method = "shooting"`, each checked against its bound.
fn liu_shoot_read(given: &BTreeMap<String, Value>) -> Result<Settings, PointError> {
    Settings::read(
        "liu2021",
        Method::Shooting,
        &liu_shoot_settings(),
        given,
        &[],
    )
}

fn liu_shoot_settings() -> Vec<SettingDef> {
    contract::shoot::shoot_settings(LIU_SHOOT_TRANSIENT)
}

/// The shooting guess of a Liu point: the state after `transient_periods` periods of time
/// integration from `initial` (default: quasi-static contact with the drive flank).
fn liu_guess(
    model: &liu2021::Model,
    s: &Settings,
    initial: Option<(f64, f64)>,
) -> Result<[f64; 2], PointError> {
    let b = model.backlash;
    let start = initial.unwrap_or((-b - model.b0, 0.0));
    let transient = s.f("transient_periods");
    let x0 = if transient > 0.0 {
        let r = liu2021::integrate(
            model,
            &liu2021::IntegrationOptions {
                transient_periods: (transient - 1.0).max(0.0),
                record_periods: transient.min(1.0),
                sample_step: model.period() / 8.0,
                initial: Some(start),
                ..liu2021::IntegrationOptions::default()
            },
        )
        .context("liu2021 shooting guess")?;
        let (Some(q), Some(v)) = (r.q.last(), r.v.last()) else {
            return Err(PointError::Compute(
                "liu2021 shooting guess: empty response".into(),
            ));
        };
        [*q, *v]
    } else {
        [start.0, start.1]
    };
    Ok(x0)
}

/// One Liu point by shooting: the guess from `transient_periods` of time integration, then
/// Newton on the event-located period map; the columns of [`LIU_SHOOT_OUT`].
fn liu_shoot(
    model: liu2021::Model,
    s: &Settings,
    initial: Option<(f64, f64)>,
) -> Result<Record, PointError> {
    let b = model.backlash;
    let x0 = liu_guess(&model, s, initial)?;
    let (p, o, shared) = shoot_on("liu2021", model, model.period(), &x0, s)?;
    let ext = p.event_extrema(&o.x0, 1).context("liu2021 gap extrema")?;
    // e0 = q − b̄ (back flank), e1 = q + b̄ (drive flank): contact while e1 < 0
    let (back, drive) = (ext[0][1] / b, ext[1][1] / b);
    let rsv = if back > 0.0 {
        2.0
    } else if drive > 0.0 {
        1.0
    } else {
        0.0
    };
    // LIU_SHOOT_OUT: the shared shooting columns with the section state and the gap margins
    let mut r = Record::new();
    r.push("rsv", "1", rsv)
        .push("q0", "1", o.x0[0])
        .push("dq0", "1", o.x0[1]);
    for c in shared.columns() {
        if c.name == "newton_iterations" {
            r.push("gap_max_drive", "1", drive)
                .push("gap_max_back", "1", back);
        }
        r.push(&c.name, &c.unit, c.value);
    }
    Ok(r)
}

/// One Liu point by shooting for front ends without a study file (the Python package): the
/// settings are checked by the study's definitions and the result is the study's record of
/// `method = "shooting"`, computed by the same code.
///
/// # Errors
/// A bad setting (named with its bound), an invalid model, or a shooting failure.
pub fn shooting_point(
    model: liu2021::Model,
    given: &BTreeMap<String, Value>,
    initial: Option<(f64, f64)>,
) -> Result<Record, PointError> {
    let s = liu_shoot_read(given)?;
    liu_shoot(model, &s, initial)
}

fn liu_model(p: &Point) -> Result<liu2021::Model, PointError> {
    liu_params(p)?.model().context("liu2021 parameters")
}

/// The Liu parameter set of a point (overrides and the `readings` choice on Table 1).
fn liu_params(p: &Point) -> Result<liu2021::Parameters, PointError> {
    let mut fields = p.clone();
    reject_legacy(
        &fields,
        &[(
            "readings_printed",
            "readings = \"consistent\" or readings = \"printed\"",
        )],
    )?;
    let preset = take_choice(
        &mut fields,
        "readings",
        Some("readings = \"consistent\" or readings = \"printed\""),
    )?;
    let mut base = liu2021::table1();
    match preset {
        None => {}
        Some(Value::Text(s)) if s == "consistent" => base.readings = liu2021::Readings::default(),
        Some(Value::Text(s)) if s == "printed" => base.readings = liu2021::Readings::printed(),
        Some(v) => {
            return Err(PointError::Input(format!(
                "`readings` = {} is not an option; options: \"consistent\", \"printed\"",
                v.label()
            )));
        }
    }
    apply_values(&base, &fields)
}

fn liu_initial(ctx: &Context<'_>) -> Result<Option<(f64, f64)>, PointError> {
    match ctx.initial {
        None => Ok(None),
        Some([q, v]) => Ok(Some((*q, *v))),
        Some(v) => Err(PointError::Input(format!(
            "liu2021: `initial` must be [q, q'], got {} numbers",
            v.len()
        ))),
    }
}

const COORDINATES: &[(&str, &str)] = &[("q", "1"), ("q'", "1")];

/// The continuation parameters of liu2021: the pinion speed and the Table 1 entries of
/// [`liu2021::CONTINUATION_PARAMETERS`].
const CONTINUATION_PARAMETERS: [(&str, &str); 5] = [
    ("omega1", "rad/s"),
    liu2021::CONTINUATION_PARAMETERS[0],
    liu2021::CONTINUATION_PARAMETERS[1],
    liu2021::CONTINUATION_PARAMETERS[2],
    liu2021::CONTINUATION_PARAMETERS[3],
];

/// [`contract::Model::continuation`] of liu2021: the point's parameter set as a
/// [`liu2021::Parametric`] system, the shooting guess of `method = "shooting"`, the state
/// weighed by `0.1 b̄`; the work (guess, and every branch and curve point's Newton iterations)
/// bounded by `limits.max_steps`.
fn liu_continuation(
    point: &Point,
    ctx: &Context<'_>,
    request: &contract::continuation::ContinuationRequest,
) -> Result<contract::continuation::ContinuationOutput, PointError> {
    use contract::continuation::{Axis, Setup, continue_on};
    if ctx.solver.method != Method::Shooting {
        return Err(PointError::Input(
            "a [continuation] study corrects its orbits by shooting: set [solver] method = \"shooting\""
                .into(),
        ));
    }
    let s = liu_shoot_read(&ctx.solver.settings)?;
    let p = liu_params(point)?;
    let sys = liu2021::Parametric::new(p).context("liu2021 parameters")?;
    let m = *sys.model();
    let axis = |name: &str| -> Result<Axis, PointError> {
        let unit = CONTINUATION_PARAMETERS
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, u)| (*u).to_owned())
            .ok_or_else(|| {
                PointError::Input(format!(
                    "liu2021 cannot continue in `{name}`; parameters: {}",
                    CONTINUATION_PARAMETERS
                        .iter()
                        .map(|(n, _)| format!("\"{n}\""))
                        .collect::<Vec<_>>()
                        .join(", ")
                ))
            })?;
        Ok(if name == "omega1" {
            Axis {
                name: name.to_owned(),
                unit,
                parameter: orbit::Parameter::BaseFrequency,
                conv: m.omega_c / p.omega1,
                start: p.omega1,
            }
        } else {
            Axis {
                name: name.to_owned(),
                unit,
                parameter: orbit::Parameter::Named(name.to_owned()),
                conv: 1.0,
                start: system::SecondOrderSystem::parameter(&sys, name)
                    .context("liu2021 parameter")?,
            }
        })
    };
    let first = axis(&request.parameter)?;
    let second = match &request.codim2 {
        Some(c) if c.parameter == request.parameter => {
            return Err(PointError::Input(format!(
                "continuation.codim2.parameter must differ from continuation.parameter (both `{}`)",
                c.parameter
            )));
        }
        Some(c) => Some(axis(&c.parameter)?),
        None => None,
    };
    // the guess's integration, then every branch and curve point a few Newton iterations of
    // one period (the time stepper's ≈ 0.5 time units per step)
    let corrections = request.max_points as f64
        + request
            .codim2
            .as_ref()
            .map_or(0.0, |c| 2.0 * c.max_curves as f64 * c.max_points as f64);
    let steps =
        (s.f("transient_periods") + corrections * (s.f("max_iter") + 1.0)) * m.period() / 0.5;
    ctx.limits.need_steps("liu2021 continuation", steps)?;
    contract::continuation::check_request(&first, second.as_ref(), request)?;
    let guess = liu_guess(&m, &s, liu_initial(ctx)?)?;
    let setup = Setup {
        what: "liu2021",
        period: m.period(),
        guess: guess.to_vec(),
        state_scale: 0.1 * m.backlash,
        coordinates: COORDINATES
            .iter()
            .map(|(n, u)| ((*n).to_owned(), (*u).to_owned()))
            .collect(),
        // e0 = q − b̄ (back flank), e1 = q + b̄ (drive flank)
        events: vec!["back flank".to_owned(), "drive flank".to_owned()],
        axis: first,
        second,
    };
    continue_on(sys, &setup, request, &s)
}

impl contract::Model for Liu {
    fn name(&self) -> &'static str {
        "liu2021"
    }

    fn description(&self) -> &'static str {
        "Liu 2021 non-circular face gear rattle model (Eq. 22)"
    }

    fn unit_of(&self, parameter: &str) -> &'static str {
        liu_unit(parameter)
    }

    fn describe(&self) -> ModelInfo {
        let p = liu2021::table1();
        let mut choices = vec![ChoiceInfo {
            name: "readings".into(),
            options: vec!["consistent".into(), "printed".into()],
            default: "consistent".into(),
            note: "every reading at once: the consistent equations, or every equation as printed"
                .into(),
        }];
        choices.push(choice_info(
            "rigid_acceleration",
            p.readings.rigid_acceleration,
            "d²θ₂/dτ², Eq. (20)",
        ));
        choices.push(choice_info(
            "rigid_series",
            p.readings.rigid_series,
            "Fourier truncation, Eq. (22)",
        ));
        choices.push(choice_info(
            "error_term",
            p.readings.error_term,
            "d²ē/dτ², Eq. (21)",
        ));
        choices.push(choice_info(
            "base_radius",
            p.readings.base_radius,
            "base radius in b̄ and ē, Eq. (11)–(12)",
        ));
        ModelInfo {
            parameters: params_of(&p, liu_unit),
            choices,
            methods: vec![
                MethodInfo {
                    method: Method::TimeStepping,
                    settings: LIU_TS.to_vec(),
                    outputs: outs_stepped(LIU_TS_OUT, false),
                    initial: Some("[q, q'] at τ = 0 (default: the quasi-static contact at rest)"),
                },
                MethodInfo {
                    method: Method::Hbm,
                    settings: LIU_HBM.to_vec(),
                    outputs: outs(&hbm_outputs(true, false)),
                    initial: None,
                },
                MethodInfo {
                    method: Method::Shooting,
                    settings: liu_shoot_settings(),
                    outputs: outs(LIU_SHOOT_OUT),
                    initial: Some(
                        "[q, q'] at τ = 0 where the guess's integration starts (default: the quasi-static contact at rest)",
                    ),
                },
            ],
        }
    }

    fn build(&self, ctx: &Context<'_>) -> Result<Adapter, PointError> {
        match ctx.solver.method {
            Method::TimeStepping => time_stepping(ctx),
            Method::Hbm => harmonic_balance(ctx),
            Method::Shooting => shooting(ctx),
            m => Err(wrong_method(
                "liu2021",
                m,
                &[Method::TimeStepping, Method::Hbm, Method::Shooting],
            )),
        }
    }

    fn bifurcation_coordinates(&self) -> Option<&'static [(&'static str, &'static str)]> {
        Some(COORDINATES)
    }

    /// Time stepping with the integrator settings `max_step` and `rtol` (the transient and
    /// section sizes come from `[bifurcation]`).
    fn build_bifurcation(
        &self,
        ctx: &Context<'_>,
        bo: &timestep::BifurcationOptions,
    ) -> Result<Adapter, PointError> {
        if ctx.solver.method != Method::TimeStepping {
            return Err(wrong_method(
                "liu2021 [bifurcation]",
                ctx.solver.method,
                &[Method::TimeStepping],
            ));
        }
        let integrator = &LIU_TS[3..5];
        let s = Settings::read(
            "liu2021 [bifurcation]",
            Method::TimeStepping,
            integrator,
            &ctx.solver.settings,
            &[],
        )?;
        let opts = liu2021::IntegrationOptions {
            max_step: s.f("max_step"),
            rtol: s.f("rtol"),
            initial: liu_initial(ctx)?,
            ..liu2021::IntegrationOptions::default()
        };
        let coordinate = COORDINATES
            .get(bo.coordinate)
            .copied()
            .ok_or_else(|| PointError::Input(format!("no coordinate {}", bo.coordinate)))?;
        let (bo, limits) = (*bo, ctx.limits);
        Ok(Adapter {
            outputs: bifurcation_outputs(coordinate, "1", bo.classify.n_points),
            prepare: Box::new(move |p: &Point| {
                let model = liu_model(p)?;
                // periods integrated: transient and section, twice the Lyapunov intervals
                let c = bo.classify;
                let periods = (c.transient_periods + c.n_points + 2 * c.lyapunov_intervals) as f64;
                limits.need_steps(
                    "liu2021 bifurcation",
                    periods * model.period() / opts.max_step,
                )?;
                Ok(Box::new(move || {
                    let pt = liu2021::bifurcation_point(&model, &opts, &bo)
                        .context("liu2021 bifurcation point")?;
                    Ok(bifurcation_record(&pt, coordinate, "1"))
                }) as Job)
            }),
        })
    }

    fn presets(&self) -> Vec<Preset> {
        vec![
            Preset {
                set: "liu2021",
                name: "table1",
                value: || serde_json::to_value(liu2021::table1()).unwrap_or_default(),
            },
            Preset {
                set: "liu2021-readings",
                name: "consistent",
                value: || serde_json::to_value(liu2021::Readings::default()).unwrap_or_default(),
            },
            Preset {
                set: "liu2021-readings",
                name: "printed",
                value: || serde_json::to_value(liu2021::Readings::printed()).unwrap_or_default(),
            },
        ]
    }

    fn full_methods(&self) -> &'static [&'static str] {
        &["hbm", "time-stepping", "shooting"]
    }

    fn continuation_parameters(&self) -> &'static [(&'static str, &'static str)] {
        &CONTINUATION_PARAMETERS
    }

    /// Shooting continuation of the period-1 orbit ([`contract::continuation::continue_on`]
    /// on [`liu2021::Parametric`]): in `omega1` (the base frequency `ω̄_c`) or a Table 1 entry
    /// of [`liu2021::CONTINUATION_PARAMETERS`], from the shooting guess of the point.
    fn continuation(
        &self,
        point: &Point,
        ctx: &Context<'_>,
        request: &contract::continuation::ContinuationRequest,
    ) -> Result<contract::continuation::ContinuationOutput, PointError> {
        liu_continuation(point, ctx, request)
    }

    fn solve_full(
        &self,
        params: &J,
        method: &str,
        s: BTreeMap<String, J>,
    ) -> Result<J, PointError> {
        let p: liu2021::Parameters = api::with_overrides("liu2021", &liu2021::table1(), params)?;
        match method {
            "time-stepping" => full_time_stepping(p, method, s),
            "hbm" => full_hbm(p, s),
            "shooting" => full_shooting(p, s),
            _ => Err(PointError::Input(format!(
                "liu2021 has no full-result method `{method}`"
            ))),
        }
    }
}

/// The time-stepping plan of one study: the one-period run and the window settings.
#[derive(Debug, Clone, Copy)]
struct TsPlan {
    one_period: liu2021::IntegrationOptions,
    window: liu2021::LongWindowOptions,
    robust: bool,
    /// The Lyapunov run (`lyapunov = "on"`).
    lyapunov: Option<crate::contract::lyapunov::LyapunovPlan>,
    /// `settle = "fixed"`: the judged window is the one-period record (the same start,
    /// transient and periods).
    fixed: bool,
}

impl TsPlan {
    /// The one-period columns are the judged window's, from its run: `settle = "fixed"` (the
    /// window is the record; with `robustness = "on"` its nominal run), without a Lyapunov run
    /// (which starts from the end of the one-period run).
    fn window_is_record(&self) -> bool {
        self.fixed && self.lyapunov.is_none()
    }
}

/// Read the time-stepping settings (bounds checked by [`Settings::read`]; the relations between
/// them here, each error naming the settings and the bound).
fn ts_plan(s: &Settings, initial: Option<(f64, f64)>) -> Result<TsPlan, PointError> {
    let one_period = liu2021::IntegrationOptions {
        transient_periods: s.f("transient_periods"),
        record_periods: s.f("record_periods"),
        sample_step: s.f("sample_step"),
        max_step: s.f("max_step"),
        rtol: s.f("rtol"),
        initial,
        method: liu2021::Stepping::Auto,
        transient_rtol: None,
    };
    let fixed = s.name("settle") == "fixed";
    let transient = one_period.transient_periods;
    let (periods, settle_windows) = if fixed {
        let r = one_period.record_periods;
        if r.fract() != 0.0 || r < 1.0 {
            return Err(PointError::Input(format!(
                "setting `record_periods` must be a whole number ≥ 1 with settle = \"fixed\" \
                 (it is the judged window), got {r}"
            )));
        }
        (r as usize, 0)
    } else {
        let w = s.u("window_periods").unwrap_or(50) as usize;
        // whole windows between the transient and the cap (none when the transient reaches it)
        let cap = s.f("max_transient_periods");
        (w, ((cap - transient).max(0.0) / w as f64).floor() as usize)
    };
    let robust = s.name("robustness") == "on";
    if robust && periods < crate::response::MIN_CLASSIFIED_PERIODS {
        return Err(PointError::Input(format!(
            "robustness = \"on\" needs windows of ≥ {} periods (the 0–1 test); \
             settle = \"fixed\" has record_periods = {periods}",
            crate::response::MIN_CLASSIFIED_PERIODS
        )));
    }
    let lyapunov = lyapunov_plan(s);
    if let Some(l) = lyapunov
        && l.window.exponents > 2
    {
        return Err(PointError::Input(format!(
            "setting `lyapunov_exponents` must be at most 2 for liu2021 (one degree of \
             freedom: state dimension 2), got {}",
            l.window.exponents
        )));
    }
    Ok(TsPlan {
        lyapunov,
        fixed,
        one_period,
        window: liu2021::LongWindowOptions {
            transient_periods: transient,
            periods,
            sample_step: one_period.sample_step,
            max_step: one_period.max_step,
            rtol: one_period.rtol,
            settle_windows,
            ..liu2021::LongWindowOptions::default()
        },
        robust,
    })
}

/// One time-stepping point of [`ts_plan`] at `rtol / factor`: the columns of [`LIU_TS_OUT`]
/// (plus [`crate::response::Robust::COLUMNS`] when robust) and the work of every run. Where
/// the judged window is the one-period record ([`TsPlan::window_is_record`]), its run gives
/// both: `rsv_one_period` and `ppv_one_period` repeat `rsv` and `ppv`, and the one-period run
/// is not repeated.
fn ts_point(
    model: &liu2021::Model,
    plan: &TsPlan,
    factor: f64,
) -> Result<(Record, timestep::Stats), PointError> {
    ts_point_with(model, plan, factor, !plan.window_is_record()).map(|(r, w, _)| (r, w))
}

/// [`ts_point`] with the one-period response (its samples for a full-result solve).
fn ts_point_full(
    model: &liu2021::Model,
    plan: &TsPlan,
    factor: f64,
) -> Result<(Record, timestep::Stats, liu2021::TimeResponse), PointError> {
    let (rec, work, one) = ts_point_with(model, plan, factor, true)?;
    let one = one.ok_or_else(|| PointError::Compute("liu2021: no one-period run".into()))?;
    Ok((rec, work, one))
}

/// [`ts_point`], with the one-period run (`with_one`, which the Lyapunov run needs: it starts
/// from its end) or with the one-period columns from the judged window.
fn ts_point_with(
    model: &liu2021::Model,
    plan: &TsPlan,
    factor: f64,
    with_one: bool,
) -> Result<(Record, timestep::Stats, Option<liu2021::TimeResponse>), PointError> {
    use crate::response::{Robust, SETTLED, motion_code, window_motion, window_unsettled};
    let o = liu2021::IntegrationOptions {
        rtol: plan.one_period.rtol / factor,
        ..plan.one_period
    };
    let one = if with_one {
        Some(liu2021::integrate(model, &o).context("liu2021 time integration")?)
    } else {
        None
    };
    let wo = liu2021::LongWindowOptions {
        rtol: plan.window.rtol / factor,
        ..plan.window
    };
    let (robust, kept) = if plan.robust {
        let (r, k) = liu2021::robust_window(model, &wo, o.initial).context("liu2021 window")?;
        (Some(r), k)
    } else {
        let k = liu2021::settled_window(model, &wo, o.initial).context("liu2021 window")?;
        (None, k)
    };
    let w = &kept.stats;
    let flag = |b: bool| if b { 1.0 } else { 0.0 };
    let (rsv_one, ppv_one) = match &one {
        Some(one) => (one.rattle.state.rsv(), one.rattle.ppv),
        None => (w.state.rsv(), w.ppv),
    };
    let mut rec = Record::new();
    rec.push("rsv", "1", f64::from(w.state.rsv()))
        .push("ppv", "1", w.ppv)
        .push("q_min", "1", w.q_min)
        .push("q_max", "1", w.q_max)
        .push("motion", "1", motion_code(w))
        .push("settled", "1", flag(window_motion(w).is_some()))
        .push("transient_periods_used", "1", kept.transient_periods)
        .push("rsv_one_period", "1", f64::from(rsv_one))
        .push("ppv_one_period", "1", ppv_one);
    // the columns of LIU_TS_ROBUST_OUT, then the long-window columns
    if let Some(r) = &robust {
        let (lo, hi) = r.rsv_interval();
        rec.push("robust", "1", flag(!window_unsettled(r, SETTLED)))
            .push("rsv_lo", "1", f64::from(lo))
            .push("rsv_hi", "1", f64::from(hi))
            .push("ppv_spread", "1", r.ppv_spread());
        for ((name, unit), v) in Robust::COLUMNS.iter().zip(r.values()) {
            rec.push(name, unit, v);
        }
    }
    if let Some(l) = &plan.lyapunov {
        // from the end of the settled one-period run (the forcing phase of its last sample)
        let (Some(t0), Some(q), Some(v)) = one.as_ref().map_or((None, None, None), |one| {
            (one.tau.last(), one.q.last(), one.v.last())
        }) else {
            return Err(PointError::Compute(
                "liu2021 Lyapunov run: empty response".into(),
            ));
        };
        let s = run_lyapunov(
            "liu2021",
            *model,
            model.period(),
            (*t0, &[*q, *v]),
            &tighter(l, factor),
        )?;
        push_lyapunov(&mut rec, &s, model.period(), "1");
    }
    let mut work = kept.work;
    if let Some(one) = &one {
        work = one.stats;
        work.add(&kept.work);
    }
    Ok((rec, work, one))
}

fn time_stepping(ctx: &Context<'_>) -> Result<Adapter, PointError> {
    let limits = ctx.limits;
    let s = Settings::read(
        "liu2021",
        Method::TimeStepping,
        LIU_TS,
        &ctx.solver.settings,
        &[(
            "long_window_periods",
            "robustness = \"on\" (with window_periods = n; the settled window is the default)",
        )],
    )?;
    let plan = ts_plan(&s, liu_initial(ctx)?)?;
    let check = s.name("tolerance_check") == "on";
    let mut names: Vec<(&str, &str)> = LIU_TS_OUT.to_vec();
    if plan.robust {
        names.extend(LIU_TS_ROBUST_OUT);
        names.extend(crate::response::Robust::COLUMNS);
    }
    if let Some(l) = &plan.lyapunov {
        names.extend(lyapunov_columns(l.window.exponents, "1"));
    }
    Ok(Adapter {
        outputs: outs_stepped(&names, check),
        prepare: Box::new(move |p: &Point| {
            let model = liu_model(p)?;
            let period = model.period();
            let opts = &plan.one_period;
            let samples = opts.record_periods * period / opts.sample_step;
            if !(LIU_MIN_SAMPLES..=LIU_MAX_SAMPLES).contains(&samples) {
                return Err(PointError::Input(format!(
                    "liu2021: the recorded window holds {samples:.3e} samples \
                     (record_periods·T/sample_step, T = {period:.4}); it must hold \
                     {LIU_MIN_SAMPLES} … {LIU_MAX_SAMPLES:e}: change sample_step or \
                     record_periods"
                )));
            }
            // the one-period run, then the window run(s): the nominal one with every window it
            // may discard (robust: two kept windows, and two more runs of one)
            let w = &plan.window;
            let nominal = w.transient_periods + (w.settle_windows + 1) as f64 * w.periods as f64;
            let runs = if plan.robust {
                3.0 * nominal + (1 + 2 * w.settle_windows) as f64 * w.periods as f64
            } else {
                nominal
            };
            // the one-period run, unless the judged window is the record
            let one = if plan.window_is_record() {
                0.0
            } else {
                opts.transient_periods + opts.record_periods
            };
            let steps = (one + runs) * period / w.max_step;
            let steps = steps + plan.lyapunov.as_ref().map_or(0.0, lyapunov_steps);
            limits.need_steps("liu2021", steps)?;
            Ok(
                Box::new(move || run_stepped(check, |factor| ts_point(&model, &plan, factor)))
                    as Job,
            )
        }),
    })
}

fn harmonic_balance(ctx: &Context<'_>) -> Result<Adapter, PointError> {
    no_initial("liu2021", ctx)?;
    let s = Settings::read("liu2021", Method::Hbm, LIU_HBM, &ctx.solver.settings, &[])?;
    let (tol, max_iter) = (s.f("tol"), s.u("max_iter").unwrap_or(60));
    let (full_r, samples) = (s.u("full_r"), s.u("samples"));
    let confirm = s.name("confirm") == "on";
    let stability = s.name("stability") == "on";
    Ok(Adapter {
        outputs: outs(&hbm_outputs(stability, confirm)),
        prepare: Box::new(move |p: &Point| {
            let model = liu_model(p)?;
            let mut opts = match full_r {
                Some(r) => liu2021::HbmOptions::full(&model, r as usize),
                None => liu2021::HbmOptions::default(),
            };
            opts.tol = tol;
            opts.max_iter = max_iter;
            opts.samples = samples.map(|m| m as usize);
            Ok(Box::new(move || {
                let r =
                    liu2021::solve_hbm(&model, &opts, None).context("liu2021 harmonic balance")?;
                let mut rec = Record::new();
                rec.push("rsv", "1", f64::from(r.rattle.state.rsv()))
                    .push("ppv", "1", r.rattle.ppv)
                    .push("q_min", "1", r.rattle.q_min)
                    .push("q_max", "1", r.rattle.q_max)
                    .push("converged", "1", if r.converged() { 1.0 } else { 0.0 })
                    .push("residual_norm", "1", r.solution.residual_norm)
                    .push("truncation", "1", r.solution.truncation);
                rec.append(hbm_reliability(&model, &r, stability, confirm)?);
                Ok(rec)
            }) as Job)
        }),
    })
}

/// The HBM columns: [`LIU_OUT`], [`LIU_HBM_OUT`] when `stability`, then
/// [`LIU_HBM_CONFIRM_OUT`] when `confirm`.
fn hbm_outputs(stability: bool, confirm: bool) -> Vec<(&'static str, &'static str)> {
    let st: &[(&str, &str)] = if stability { LIU_HBM_OUT } else { &[] };
    let more: &[(&str, &str)] = if confirm { LIU_HBM_CONFIRM_OUT } else { &[] };
    LIU_OUT.iter().chain(st).chain(more).copied().collect()
}

/// The columns of [`LIU_HBM_OUT`] (when `stability`) and [`LIU_HBM_CONFIRM_OUT`] (when
/// `confirm`) for a harmonic-balance response.
fn hbm_reliability(
    model: &liu2021::Model,
    r: &liu2021::HbmResponse,
    stability: bool,
    confirm: bool,
) -> Result<Record, PointError> {
    let mut rec = Record::new();
    let flag = |b: bool| if b { 1.0 } else { 0.0 };
    if !r.converged() {
        if stability {
            rec.push("stable", "1", 0.0);
        }
        if confirm {
            rec.push("confirmed_by_time_stepping", "1", 0.0).push(
                "ppv_time_stepping",
                "1",
                r.rattle.ppv,
            );
        }
        return Ok(rec);
    }
    if stability {
        let st = liu2021::shooting_stability(model, r).context("liu2021 Floquet stability")?;
        rec.push("stable", "1", flag(st.stable));
    }
    if confirm {
        let (q, v) = r.solution.state_at(0.0);
        let o = liu2021::LongWindowOptions {
            transient_periods: USER_TRANSIENT,
            settle_windows: ((USER_MAX_TRANSIENT - USER_TRANSIENT) / 50.0).floor() as usize,
            // the confirmation reads the motion, the state and the ppv only
            detail: crate::response::WindowDetail::Motion,
            ..liu2021::LongWindowOptions::default()
        };
        let w = liu2021::settled_window(model, &o, Some((q[0], v[0])))
            .context("liu2021 time-stepping confirmation")?;
        let periodic =
            crate::response::window_motion(&w.stats).is_some_and(|m| m.period_multiple() >= 1);
        let same = w.stats.state.rsv() == r.rattle.state.rsv();
        rec.push("confirmed_by_time_stepping", "1", flag(periodic && same))
            .push("ppv_time_stepping", "1", w.stats.ppv);
    }
    Ok(rec)
}

fn shooting(ctx: &Context<'_>) -> Result<Adapter, PointError> {
    let limits = ctx.limits;
    let s = liu_shoot_read(&ctx.solver.settings)?;
    let initial = liu_initial(ctx)?;
    let s = Arc::new(s);
    Ok(Adapter {
        outputs: outs(LIU_SHOOT_OUT),
        prepare: Box::new(move |p: &Point| {
            let model = liu_model(p)?;
            // the guess's integration plus a few Newton iterations of one period each
            let steps = (s.f("transient_periods") + 2.0 * s.f("max_iter")) * model.period() / 0.5;
            limits.need_steps("liu2021 shooting", steps)?;
            let s = Arc::clone(&s);
            Ok(Box::new(move || liu_shoot(model, &s, initial)) as Job)
        }),
    })
}

// ---------------------------------------------------------------------------------------------
// Full-result solves (the Python package's `solve`).

fn full_time_stepping(
    p: liu2021::Parameters,
    method: &str,
    mut s: BTreeMap<String, J>,
) -> Result<J, PointError> {
    let mut opts_over = s.remove("options").unwrap_or(J::Null);
    // The study-file names work here too, at the top level as in `geardyn study`
    // (`transient_periods=…`), or inside `options={…}`; not both for one name.
    for k in [
        "transient_periods",
        "record_periods",
        "sample_step",
        "max_step",
        "rtol",
    ] {
        if let Some(v) = s.remove(k) {
            if opts_over.is_null() {
                opts_over = J::Object(serde_json::Map::new());
            }
            let J::Object(o) = &mut opts_over else {
                return Err(PointError::Input(format!(
                    "setting `options` must be a mapping, got {opts_over}"
                )));
            };
            if o.contains_key(k) {
                return Err(PointError::Input(format!(
                    "setting `{k}` given twice (top level and in `options`)"
                )));
            }
            o.insert(k.to_owned(), v);
        }
    }
    // long-window rattle statistics (issue 22): windows of n periods, 0 = off
    let lw_periods = api::take_f64(&mut s, "long_window_periods", 0.0)?;
    if !((0.0..=1e4).contains(&lw_periods) && lw_periods.fract() == 0.0) {
        return Err(PointError::Input(format!(
            "setting `long_window_periods` must be an integer in [0, 10000], got {lw_periods}"
        )));
    }
    // the settle settings of `geardyn study` (same names, bounds, defaults and messages)
    let mut settle = serde_json::Map::new();
    for k in [
        "settle",
        "window_periods",
        "max_transient_periods",
        "robustness",
    ] {
        if let Some(v) = s.remove(k) {
            settle.insert(k.to_owned(), v);
        }
    }
    api::no_leftovers(method, s)?;
    // the integration options share their names, bounds and messages with the study
    // setting of `geardyn study` (all but `initial`, a state)
    let mut shared = settle.clone();
    if let J::Object(o) = &opts_over {
        for (k, v) in o {
            if k.as_str() != "initial" {
                shared.insert(k.clone(), v.clone());
            }
        }
    }
    api::study_settings("liu2021", Method::TimeStepping, &shared)?;
    let base = liu2021::IntegrationOptions {
        transient_periods: USER_TRANSIENT,
        ..liu2021::IntegrationOptions::default()
    };
    let opts = api::with_overrides("liu2021 integration options", &base, &opts_over)?;
    let settings = Settings::read(
        "liu2021",
        Method::TimeStepping,
        LIU_TS,
        &api::study_values(
            [
                ("transient_periods", opts.transient_periods),
                ("record_periods", opts.record_periods),
                ("sample_step", opts.sample_step),
                ("max_step", opts.max_step),
                ("rtol", opts.rtol),
            ]
            .into_iter()
            .map(|(k, v)| (k.to_owned(), json!(v)))
            .chain(settle)
            .collect(),
        )?,
        &[],
    )?;
    let plan = ts_plan(&settings, opts.initial)?;
    let model = p.model()?;
    let (rec, _, r) = ts_point_full(&model, &plan, 1.0)?;
    let window = if lw_periods >= 1.0 {
        let o = liu2021::LongWindowOptions {
            periods: lw_periods as usize,
            rtol: opts.rtol,
            max_step: opts.max_step,
            sample_step: opts.sample_step,
            ..liu2021::LongWindowOptions::default()
        };
        let lw = liu2021::long_window(&model, &o)?;
        // the columns of `geardyn study` (one definition: Robust::COLUMNS)
        let mut m: serde_json::Map<String, J> = crate::response::Robust::COLUMNS
            .iter()
            .zip(lw.values())
            .map(|((name, _), v)| ((*name).to_owned(), json!(v)))
            .collect();
        m.insert("spread".to_owned(), json!(lw.describe()));
        J::Object(m)
    } else {
        J::Null
    };
    // the study's columns (rsv, ppv, motion, settled, the one-period figures, the spread), the
    // one-period samples, the motion's label
    let mut out: serde_json::Map<String, J> = rec
        .columns()
        .iter()
        .map(|c| (c.name.clone(), json!(c.value)))
        .collect();
    let label = rec
        .get("motion")
        .and_then(crate::response::motion_label)
        .unwrap_or_default();
    out.insert("motion_label".to_owned(), json!(label));
    out.insert("robustness".to_owned(), json!(settings.name("robustness")));
    for (k, v) in [
        ("tau", json!(r.tau)),
        ("q", json!(r.q)),
        ("v", json!(r.v)),
        ("converged", json!(true)),
        ("contact_events", json!(r.contact_events)),
        ("window", window),
    ] {
        out.insert(k.to_owned(), v);
    }
    Ok(J::Object(out))
}

fn full_hbm(p: liu2021::Parameters, mut s: BTreeMap<String, J>) -> Result<J, PointError> {
    let warm = api::take_bool(&mut s, "warm_start", false)?;
    let output_samples = api::take_f64(&mut s, "output_samples", 512.0)?;
    if !((8.0..=65_536.0).contains(&output_samples) && output_samples.fract() == 0.0) {
        return Err(PointError::Input(format!(
            "setting `output_samples` must be an integer in [8, 65536], got {output_samples}"
        )));
    }
    // tol, max_iter, samples, full_r: the settings of `geardyn study` (same names,
    // bounds and messages; checked by the same code)
    let shared: serde_json::Map<String, J> = s.into_iter().collect();
    api::study_settings("liu2021", Method::Hbm, &shared)?;
    let num = |k: &str| shared.get(k).and_then(J::as_f64);
    let tol = num("tol").unwrap_or(1e-9);
    let max_iter = num("max_iter").unwrap_or(60.0);
    let full_r = num("full_r").unwrap_or(0.0);
    let aft_samples = num("samples").map(|x| x as usize);
    let m = p.model()?;
    let mut opts = if full_r > 0.0 {
        liu2021::HbmOptions::full(&m, full_r as usize)
    } else {
        liu2021::HbmOptions::default()
    };
    opts.tol = tol;
    opts.max_iter = max_iter as u64;
    opts.samples = aft_samples;
    let r = if warm {
        let ti = liu2021::integrate(&m, &liu2021::IntegrationOptions::default())?;
        liu2021::solve_hbm_from_time_response(&m, &opts, &ti)?
    } else {
        liu2021::solve_hbm(&m, &opts, None)?
    };
    let n = output_samples as usize;
    let period = m.period();
    let tau: Vec<f64> = (0..n).map(|i| period * i as f64 / n as f64).collect();
    let q: Vec<f64> = tau.iter().map(|&t| r.eval(t)).collect();
    Ok(json!({
        "tau": tau, "q": q,
        "rsv": r.rattle.state.rsv(), "ppv": r.rattle.ppv,
        "converged": r.converged(),
        "coefficients": r.solution.coefficients,
    }))
}

fn full_shooting(p: liu2021::Parameters, mut s: BTreeMap<String, J>) -> Result<J, PointError> {
    // the study's method "shooting": settings (transient_periods, rtol, tol, max_iter,
    // segments) checked and computed by the study code; `initial` = [q, q'] where the
    // guess's integration starts
    let initial = match s.remove("initial") {
        None | Some(J::Null) => None,
        Some(J::Array(a)) if a.len() == 2 => match (a[0].as_f64(), a[1].as_f64()) {
            (Some(q), Some(v)) => Some((q, v)),
            _ => {
                return Err(PointError::Input(
                    "setting `initial` must be [q, q'] (two numbers)".to_owned(),
                ));
            }
        },
        Some(v) => {
            return Err(PointError::Input(format!(
                "setting `initial` must be [q, q'] (two numbers), got {v}"
            )));
        }
    };
    let map = api::study_values(s)?;
    let m = p.model()?;
    let r = shooting_point(m, &map, initial).map_err(as_input)?;
    Ok(api::shooting_json(&r))
}

/// A study-code error of a full-result solve reported as a bad input (the message of
/// `geardyn study`, without a study file).
pub(crate) fn as_input(e: PointError) -> PointError {
    match e {
        PointError::Input(m) | PointError::Compute(m) => PointError::Input(m),
        e => PointError::Input(e.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contract::default_of;

    /// The documented defaults are the library's defaults (the same literals: exact).
    #[test]
    #[allow(clippy::float_cmp)]
    fn setting_defaults_match_the_library() {
        let o = liu2021::IntegrationOptions::default();
        // the user default is the validation's transient (the library's one-period run keeps 2)
        assert_eq!(
            default_of(LIU_TS, "transient_periods"),
            liu2021::LongWindowOptions::default().transient_periods
        );
        assert_eq!(default_of(LIU_TS, "window_periods"), 50.0);
        assert_eq!(default_of(LIU_TS, "record_periods"), o.record_periods);
        assert_eq!(default_of(LIU_TS, "sample_step"), o.sample_step);
        assert_eq!(default_of(LIU_TS, "max_step"), o.max_step);
        assert_eq!(default_of(LIU_TS, "rtol"), o.rtol);
        let h = liu2021::HbmOptions::default();
        assert_eq!(default_of(LIU_HBM, "tol"), h.tol);
        assert_eq!(default_of(LIU_HBM, "max_iter"), h.max_iter as f64);
        assert_eq!(default_of(LIU_TS, "lyapunov_periods"), 200.0);
        assert_eq!(
            default_of(LIU_TS, "lyapunov_rtol"),
            crate::response::LyapunovWindowOptions::default().rtol
        );
    }

    fn ts_solve(settings: &[(&str, Value)], omega1: f64) -> Result<Record, PointError> {
        let solver = contract::Solver {
            method: Method::TimeStepping,
            settings: settings
                .iter()
                .map(|(k, v)| ((*k).to_owned(), v.clone()))
                .collect(),
        };
        let ctx = Context {
            solver: &solver,
            initial: None,
            limits: contract::Limits::default(),
        };
        let mut p = Point::new();
        p.insert("omega1".into(), Value::Num(omega1));
        contract::Model::solve(&Liu, &p, &ctx)
    }

    /// `lyapunov = "on"` adds the Lyapunov columns (off by default: absent); on a settled
    /// periodic point the full spectrum (k = 2) sums to the mean divergence `−c` of the linear
    /// damping (the mesh force only kinks: `S = I`), to the flow's accuracy, and both
    /// exponents are negative (a short run: 3 transient periods, 6 of exponents; the
    /// convergence flag is 0 or 1).
    #[test]
    fn lyapunov_columns_are_opt_in_and_obey_the_volume_law() {
        let fixed = [
            ("settle", Value::Text("fixed".into())),
            ("record_periods", Value::Num(1.0)),
            ("transient_periods", Value::Num(3.0)),
        ];
        let off = ts_solve(&fixed, 100.0).unwrap();
        assert!(off.get("lambda1").is_none());
        let mut on = fixed.to_vec();
        on.extend([
            ("lyapunov", Value::Text("on".into())),
            ("lyapunov_periods", Value::Num(6.0)),
            ("lyapunov_exponents", Value::Num(2.0)),
        ]);
        let r = ts_solve(&on, 100.0).unwrap();
        let (l1, l2, sum) = (
            r.get("lambda1").unwrap(),
            r.get("lambda2").unwrap(),
            r.get("lambda_sum").unwrap(),
        );
        let mut p = Point::new();
        p.insert("omega1".into(), Value::Num(100.0));
        let m = liu_model(&p).unwrap();
        let c = system::SecondOrderSystem::damping(&m)[(0, 0)];
        // the integrator's floor: over a Liu period (≈ 6400 flow steps at ω1 = 100 rad/s) the
        // determinant of the discrete variational map loses ≈ 5.6e-4 of the dissipation −c,
        // nearly independent of rtol (1e-9: 5.6e-4, 1e-11: 5.3e-4): a floor of ≈ 1e-5 per unit
        // τ on every exponent (measured; the validation quotes Σλ + c beside λ1)
        assert!((sum + c).abs() < 1e-3 * c, "Σλ = {sum}, −c = {}", -c);
        assert!((l1 + l2 - sum).abs() < 1e-15);
        // both negative (here a complex pair of multipliers: λ1 ≈ λ2 ≈ −c/2, in either order)
        assert!(l1 < 0.0 && l2 < 0.0, "{l1} {l2}");
        let flag = r.get("lambda_converged").unwrap();
        assert!(flag.to_bits() == 0.0_f64.to_bits() || flag.to_bits() == 1.0_f64.to_bits());
        assert!(r.get("lyapunov_events_per_period").unwrap() >= 0.0);
        // batches: one is the default bit for bit; two are the mean of two consecutive runs,
        // their spread at least the first run's own, the volume law still held
        let with = |extra: (&'static str, Value)| {
            let mut v = on.clone();
            v.push(extra);
            v
        };
        let one = ts_solve(&with(("lyapunov_batches", Value::Num(1.0))), 100.0).unwrap();
        for c in ["lambda1", "lambda2", "lambda1_spread", "lambda_sum"] {
            assert_eq!(
                one.get(c).unwrap().to_bits(),
                r.get(c).unwrap().to_bits(),
                "{c}"
            );
        }
        let two = ts_solve(&with(("lyapunov_batches", Value::Num(2.0))), 100.0).unwrap();
        let (m1, m2, s2) = (
            two.get("lambda1").unwrap(),
            two.get("lambda2").unwrap(),
            two.get("lambda1_spread").unwrap(),
        );
        assert!(m1 < 0.0 && m2 < 0.0, "{m1} {m2}");
        assert!((two.get("lambda_sum").unwrap() + c).abs() < 1e-3 * c);
        assert!(s2 >= 0.0 && s2.is_finite());
        assert!(two.get("lyapunov_events_per_period").unwrap() >= 0.0);
        for bad in [0.0, 17.0] {
            let e = ts_solve(&with(("lyapunov_batches", Value::Num(bad))), 100.0)
                .unwrap_err()
                .to_string();
            assert!(e.contains("lyapunov_batches"), "{e}");
        }
        // the bound of the 1-DOF model, named
        on.push(("lyapunov_exponents", Value::Num(3.0)));
        let e = ts_solve(&on, 100.0).unwrap_err().to_string();
        assert!(e.contains("lyapunov_exponents"), "{e}");
    }
}
