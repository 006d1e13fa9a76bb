//! The Liu 2021 model of the [`REGISTRY`](crate::contract::REGISTRY) (`liu2021`): time
//! stepping (with the long-window statistics), harmonic balance, shooting and the bifurcation
//! study.

use std::collections::BTreeMap;
use std::sync::Arc;

use serde_json::{Value as J, json};

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
            default: 2.0,
        },
        doc: "periods T = 2π/ω̄_c integrated and discarded",
    },
    SettingDef {
        name: "record_periods",
        kind: Kind::Num {
            lo: 1e-3,
            hi: 1e3,
            default: 1.0,
        },
        doc: "periods recorded (the steady response)",
    },
    SettingDef {
        name: "sample_step",
        kind: Kind::Num {
            lo: 1e-6,
            hi: 1e3,
            default: 0.1,
        },
        doc: "output sampling interval Δτ; the recorded window must hold 64 … 1e7 samples",
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
        name: "long_window_periods",
        kind: Kind::Num {
            lo: 0.0,
            hi: 1e4,
            default: 0.0,
        },
        doc: "0: off; n ≥ 1: add the long-window rattle statistics over windows of n periods \
              with their range over two tolerances, two windows and two starts \
              (models::liu2021::long_window; the issue's long window is n = 50)",
    },
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
fn liu_shoot_settings() -> Vec<SettingDef> {
    contract::shoot::shoot_settings(LIU_SHOOT_TRANSIENT)
}

/// One Liu point by shooting: the guess from `transient_periods` of time integration, then
/// Newton on the event-located period map; the columns of [`LIU_SHOOT_OUT`].
fn liu_shoot(
    model: liu2021::Model,
    s: &Settings,
    initial: Option<(f64, f64)>,
) -> Result<Record, PointError> {
    let b = model.backlash;
    let start = initial.unwrap_or((-b - model.b0, 0.0));
    let transient = s.f("transient_periods");
    let x0 = if transient > 0.0 {
        let r = liu2021::integrate(
            &model,
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
    let s = Settings::read(
        "liu2021",
        Method::Shooting,
        &liu_shoot_settings(),
        given,
        &[],
    )?;
    liu_shoot(model, &s, initial)
}

fn liu_model(p: &Point) -> Result<liu2021::Model, PointError> {
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
    let params = apply_values(&base, &fields)?;
    params.model().context("liu2021 parameters")
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
                    outputs: outs_stepped(&LIU_OUT[..4], false),
                    initial: Some("[q, q'] at τ = 0 (default: the quasi-static contact at rest)"),
                },
                MethodInfo {
                    method: Method::Hbm,
                    settings: LIU_HBM.to_vec(),
                    outputs: outs(LIU_OUT),
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

fn time_stepping(ctx: &Context<'_>) -> Result<Adapter, PointError> {
    let limits = ctx.limits;
    let s = Settings::read(
        "liu2021",
        Method::TimeStepping,
        LIU_TS,
        &ctx.solver.settings,
        &[],
    )?;
    let initial = liu_initial(ctx)?;
    let opts = liu2021::IntegrationOptions {
        transient_periods: s.f("transient_periods"),
        record_periods: s.f("record_periods"),
        sample_step: s.f("sample_step"),
        max_step: s.f("max_step"),
        rtol: s.f("rtol"),
        initial,
    };
    let check = s.name("tolerance_check") == "on";
    let lw_periods = s.f("long_window_periods");
    if lw_periods.fract() != 0.0 {
        return Err(PointError::Input(format!(
            "liu2021: long_window_periods must be a whole number (0: off), got {lw_periods}"
        )));
    }
    let window = (lw_periods >= 1.0).then(|| liu2021::LongWindowOptions {
        transient_periods: opts.transient_periods,
        periods: lw_periods as usize,
        sample_step: opts.sample_step,
        max_step: opts.max_step,
        rtol: opts.rtol,
        ..liu2021::LongWindowOptions::default()
    });
    let mut names: Vec<(&str, &str)> = LIU_OUT[..4].to_vec();
    if window.is_some() {
        names.extend(crate::response::Robust::COLUMNS);
    }
    Ok(Adapter {
        outputs: outs_stepped(&names, check),
        prepare: Box::new(move |p: &Point| {
            let model = liu_model(p)?;
            if let Some(w) = &window {
                // three runs of (transient + window), the nominal one with two windows, each
                // run discarding at most `settle_windows` windows that hold a transient
                let windows = 4.0 + 3.0 * w.settle_windows as f64;
                let steps = (3.0 * w.transient_periods + windows * w.periods as f64)
                    * model.period()
                    / w.max_step;
                limits.need_steps("liu2021 long window", steps)?;
            }
            let period = model.period();
            let samples = opts.record_periods * period / opts.sample_step;
            if !(LIU_MIN_SAMPLES..=LIU_MAX_SAMPLES).contains(&samples) {
                return Err(PointError::Input(format!(
                    "liu2021: the recorded window holds {samples:.3e} samples \
                     (record_periods·T/sample_step, T = {period:.4}); it must hold \
                     {LIU_MIN_SAMPLES} … {LIU_MAX_SAMPLES:e}: change sample_step or \
                     record_periods"
                )));
            }
            let steps = (opts.transient_periods + opts.record_periods) * period / opts.max_step;
            limits.need_steps("liu2021", steps)?;
            Ok(Box::new(move || {
                run_stepped(check, |factor| {
                    let o = liu2021::IntegrationOptions {
                        rtol: opts.rtol / factor,
                        ..opts
                    };
                    let r = liu2021::integrate(&model, &o).context("liu2021 time integration")?;
                    let mut rec = Record::new();
                    rec.push("rsv", "1", f64::from(r.rattle.state.rsv()))
                        .push("ppv", "1", r.rattle.ppv)
                        .push("q_min", "1", r.rattle.q_min)
                        .push("q_max", "1", r.rattle.q_max);
                    if let Some(w) = &window {
                        let wo = liu2021::LongWindowOptions {
                            rtol: w.rtol / factor,
                            ..*w
                        };
                        let lw =
                            liu2021::long_window(&model, &wo).context("liu2021 long window")?;
                        for ((name, unit), v) in
                            crate::response::Robust::COLUMNS.iter().zip(lw.values())
                        {
                            rec.push(name, unit, v);
                        }
                    }
                    Ok((rec, r.stats))
                })
            }) as Job)
        }),
    })
}

fn harmonic_balance(ctx: &Context<'_>) -> Result<Adapter, PointError> {
    no_initial("liu2021", ctx)?;
    let s = Settings::read("liu2021", Method::Hbm, LIU_HBM, &ctx.solver.settings, &[])?;
    let (tol, max_iter) = (s.f("tol"), s.u("max_iter").unwrap_or(60));
    let (full_r, samples) = (s.u("full_r"), s.u("samples"));
    Ok(Adapter {
        outputs: outs(LIU_OUT),
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
                Ok(rec)
            }) as Job)
        }),
    })
}

fn shooting(ctx: &Context<'_>) -> Result<Adapter, PointError> {
    let limits = ctx.limits;
    let s = Settings::read(
        "liu2021",
        Method::Shooting,
        &liu_shoot_settings(),
        &ctx.solver.settings,
        &[],
    )?;
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
    api::no_leftovers(method, s)?;
    // the integration options share their names, bounds and messages with the study
    // setting of `geardyn study` (all but `initial`, a state)
    if let J::Object(o) = &opts_over {
        let shared: serde_json::Map<String, J> = o
            .iter()
            .filter(|(k, _)| k.as_str() != "initial")
            .map(|(k, v)| (k.clone(), v.clone()))
            .collect();
        api::study_settings("liu2021", Method::TimeStepping, &shared)?;
    }
    let opts = api::with_overrides(
        "liu2021 integration options",
        &liu2021::IntegrationOptions::default(),
        &opts_over,
    )?;
    let model = p.model()?;
    let r = liu2021::integrate(&model, &opts)?;
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
    Ok(json!({
        "tau": r.tau, "q": r.q, "v": r.v,
        "rsv": r.rattle.state.rsv(), "ppv": r.rattle.ppv,
        "converged": true, "contact_events": r.contact_events,
        "window": window,
    }))
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
        assert_eq!(default_of(LIU_TS, "transient_periods"), o.transient_periods);
        assert_eq!(default_of(LIU_TS, "record_periods"), o.record_periods);
        assert_eq!(default_of(LIU_TS, "sample_step"), o.sample_step);
        assert_eq!(default_of(LIU_TS, "max_step"), o.max_step);
        assert_eq!(default_of(LIU_TS, "rtol"), o.rtol);
        let h = liu2021::HbmOptions::default();
        assert_eq!(default_of(LIU_HBM, "tol"), h.tol);
        assert_eq!(default_of(LIU_HBM, "max_iter"), h.max_iter as f64);
    }
}
