//! The Yu 2021 model of the [`REGISTRY`](crate::contract::REGISTRY) (`yu2021`): time stepping,
//! harmonic balance and shooting of the 6-DOF spur pair with dynamic backlash and its
//! reference variants.

use math::DetMath;
use std::collections::BTreeMap;
use std::sync::Arc;

use serde_json::{Value as J, json};

use crate::contract::lyapunov::{
    LYAPUNOV, LYAPUNOV_BATCHES, LYAPUNOV_EXPONENTS, LYAPUNOV_PERIODS, LYAPUNOV_RTOL,
    lyapunov_columns, lyapunov_plan, lyapunov_steps, push_lyapunov, tighter,
};
use crate::contract::shoot::{SHOOT_OUT, shoot_any, shoot_settings, shoot_transient};
use crate::contract::spur::{
    AFT_SAMPLES, RECORD_PERIODS, TRANSIENT_PERIODS, time_stepping_and_hbm,
};
use crate::contract::{
    self, Adapter, ChoiceInfo, Context, Job, Kind, Method, MethodInfo, ModelInfo, ParamInfo, Point,
    PointError, Preset, Record, SettingDef, Settings, TOLERANCE_CHECK, Value, WithContext, api,
    apply_values, choice_info, no_initial, outs, outs_stepped, params_of, run_stepped, take_choice,
    wrong_method,
};
use crate::yu2021;

/// Yu, Sun, Li, Wu 2021: the spur pair with dynamic backlash (6-DOF) and its Kahraman–Singh and
/// Chen references.
#[derive(Debug, Clone, Copy)]
pub struct Yu;

/// The unit of a parameter by its own name (the last segment of its dotted path).
fn yu_unit(k: &str) -> &'static str {
    match k.rsplit('.').next().unwrap_or(k) {
        "inertia_p" | "inertia_g" => "kg·m²",
        "mass_p" | "mass_g" => "kg",
        "radius_p" | "radius_g" | "ste_amplitude" | "nominal_length" | "chen_amplitude" | "b"
        | "b0" => "m",
        "pressure_angle" | "phase" => "rad",
        "torque" => "N·m",
        "mesh_stiffness" | "bearing_stiffness" => "N/m",
        _ => "1",
    }
}

const YU_VARIANTS: &[&str] = &["yu", "kahraman-singh", "chen", "yu-as-printed"];

const YU_TS: &[SettingDef] = &[
    SettingDef {
        name: "engine",
        kind: Kind::Name {
            options: &["rk4", "timestep"],
            default: "rk4",
        },
        doc: "rk4: the model's fixed-step RK4; timestep: Dormand–Prince 5(4) with the contact \
              switches located as events",
    },
    TRANSIENT_PERIODS,
    RECORD_PERIODS,
    SettingDef {
        name: "steps_per_period",
        kind: Kind::Int {
            lo: 8,
            hi: 100_000,
            default: Some(256),
        },
        doc: "RK4 steps (samples) per mesh period, raised so that Δτ ≤ 0.2/ω_max",
    },
    SettingDef {
        name: "rms_harmonics",
        kind: Kind::Int {
            lo: 1,
            hi: 100,
            default: Some(5),
        },
        doc: "n of Eq. (21)",
    },
    SettingDef {
        name: "rtol",
        kind: Kind::Num {
            lo: 1e-14,
            hi: 1e-2,
            default: 1e-8,
        },
        doc: "engine = \"timestep\": relative tolerance",
    },
    SettingDef {
        name: "atol",
        kind: Kind::Num {
            lo: 1e-16,
            hi: 1e-2,
            default: 1e-10,
        },
        doc: "engine = \"timestep\": absolute tolerance",
    },
    TOLERANCE_CHECK,
    LYAPUNOV,
    LYAPUNOV_PERIODS,
    LYAPUNOV_EXPONENTS,
    LYAPUNOV_RTOL,
    LYAPUNOV_BATCHES,
];

const YU_HBM: &[SettingDef] = &[
    SettingDef {
        name: "harmonics",
        kind: Kind::Int {
            lo: 1,
            hi: 64,
            default: None,
        },
        doc: "harmonics H of ω* (default of HbmSettings)",
    },
    AFT_SAMPLES,
    SettingDef {
        name: "tolerance",
        kind: Kind::Num {
            lo: 1e-14,
            hi: 1e-2,
            default: 1e-10,
        },
        doc: "residual-norm tolerance",
    },
    SettingDef {
        name: "max_iterations",
        kind: Kind::Int {
            lo: 1,
            hi: 10_000,
            default: None,
        },
        doc: "Newton iterations (default of HbmSettings)",
    },
];

const YU_TS_OUT: &[(&str, &str)] = &[
    ("df", "1"),
    ("rms", "1"),
    ("mean_dte", "1"),
    ("dte_peak_to_peak", "1"),
    ("mean_backlash", "1"),
];
const YU_HBM_OUT: &[(&str, &str)] = &[
    ("mean_dte", "1"),
    ("first_harmonic_amplitude", "1"),
    ("converged", "1"),
    ("residual_norm", "1"),
    ("truncation", "1"),
];

const YU_SHOOT_TRANSIENT: &str = "mesh periods of the model's fixed-step RK4 (256 steps per \
     period) from `initial` (or the static contact) whose end state is the shooting guess; \
     Yu's 6-DOF model with free centres only";

/// The shooting settings of Yu.
fn yu_shoot_settings() -> Vec<SettingDef> {
    shoot_settings(shoot_transient(200, YU_SHOOT_TRANSIENT))
}

/// Split a Yu point into ω*, the model options and the parameters.
fn yu_model(p: &Point) -> Result<(yu2021::Yu2021Model, f64), PointError> {
    use yu2021::{Options, Yu2021Model, Yu2021Params};
    let mut fields = p.clone();
    let omega = match fields.remove("omega") {
        Some(Value::Num(w)) => w,
        Some(v) => {
            return Err(PointError::Input(format!(
                "`omega` takes a number, got {}",
                v.label()
            )));
        }
        None => {
            return Err(PointError::Input(
                "yu2021 needs `omega` (ω*) in [overrides] or a sweep".to_owned(),
            ));
        }
    };
    let base = match take_choice(
        &mut fields,
        "table",
        Some("table = \"df-rig\" or table = \"rms-rig\""),
    )? {
        None => Yu2021Params::table1(),
        Some(Value::Text(s)) if s == "df-rig" => Yu2021Params::table1(),
        Some(Value::Text(s)) if s == "rms-rig" => Yu2021Params::table2(),
        Some(v) => {
            return Err(PointError::Input(format!(
                "`table` = {} is not an option; options: \"df-rig\", \"rms-rig\"",
                v.label()
            )));
        }
    };
    let legacy = "variant = \"yu\", \"kahraman-singh\", \"chen\" or \"yu-as-printed\"";
    let mut options = match take_choice(&mut fields, "variant", Some(legacy))? {
        None => Options::default(),
        Some(Value::Text(s)) => match s.as_str() {
            "yu" => Options::default(),
            "kahraman-singh" => Options::kahraman_singh(),
            "chen" => Options::chen(),
            "yu-as-printed" => Options::yu_as_printed(),
            other => {
                return Err(PointError::Input(format!(
                    "`variant` = \"{other}\" is not an option; write {legacy}"
                )));
            }
        },
        Some(v) => {
            return Err(PointError::Input(format!(
                "`variant` = {}: write {legacy}",
                v.label()
            )));
        }
    };
    // Individual choices on top of the preset.
    let mut opt_fields = BTreeMap::new();
    for (name, field) in [
        ("kind", "kind"),
        ("form", "form"),
        ("update", "update"),
        ("pressure_angle_law", "pressure_angle"),
        ("dynamic_backlash", "dynamic_backlash"),
        ("centre_distance", "centre_distance"),
        ("lock_centres", "lock_centres"),
    ] {
        if let Some(v) = fields.remove(name) {
            opt_fields.insert(field.to_owned(), v);
        }
    }
    if !opt_fields.is_empty() {
        options = apply_values(&options, &opt_fields)?;
    }
    let params = apply_values(&base, &fields)?;
    let model = Yu2021Model::new(&params, options).context("yu2021 parameters")?;
    Ok((model, omega))
}

/// A study's `initial` for Yu: the model state (`yu2021::STATE_LEN` numbers), or none.
fn yu_initial(ctx: &Context<'_>) -> Result<Option<[f64; yu2021::STATE_LEN]>, PointError> {
    ctx.initial
        .map(|v| {
            <[f64; yu2021::STATE_LEN]>::try_from(v).map_err(|_| {
                PointError::Input(format!(
                    "yu2021: `initial` must have {} numbers (the model state), got {}",
                    yu2021::STATE_LEN,
                    v.len()
                ))
            })
        })
        .transpose()
}

/// One point of Yu's 6-DOF model by shooting for front ends without a study file (the Python
/// package): the settings checked by the study's definitions, the study's record of
/// `method = "shooting"`, computed by the same code.
///
/// # Errors
/// A bad setting (named with its bound), a model without a 6-DOF orbit, or a shooting failure.
pub fn shooting_point(
    model: yu2021::Yu2021Model,
    omega: f64,
    given: &BTreeMap<String, Value>,
) -> Result<Record, PointError> {
    let s = Settings::read("yu2021", Method::Shooting, &yu_shoot_settings(), given, &[])?;
    let settings = yu2021::RunSettings {
        omega,
        transient_periods: s.u("transient_periods").unwrap_or(200) as usize,
        record_periods: 1,
        steps_per_period: 256,
    };
    let sys = yu2021::Yu2021SixDof::new(&model, omega).context("yu2021 shooting")?;
    let r = model
        .simulate_with(&settings, &yu2021::Engine::Rk4Fixed, None)
        .context("yu2021 shooting guess")?;
    shoot_any(
        "yu2021",
        sys,
        std::f64::consts::TAU / omega,
        &r.final_state,
        &s,
    )
}

impl contract::Model for Yu {
    fn name(&self) -> &'static str {
        "yu2021"
    }

    fn description(&self) -> &'static str {
        "Yu 2021 spur pair with dynamic backlash (6-DOF; Kahraman–Singh, Chen references)"
    }

    fn unit_of(&self, parameter: &str) -> &'static str {
        yu_unit(parameter)
    }

    fn describe(&self) -> ModelInfo {
        let mut parameters = vec![ParamInfo {
            name: "omega".into(),
            unit: "1".into(),
            default: "(required) ω* = ω_h/ω_n".into(),
        }];
        parameters.extend(params_of(&yu2021::Yu2021Params::table1(), yu_unit));
        let o = yu2021::Options::default();
        ModelInfo {
            parameters,
            choices: vec![
                ChoiceInfo {
                    name: "variant".into(),
                    options: YU_VARIANTS.iter().map(|s| (*s).to_owned()).collect(),
                    default: "yu".into(),
                    note: "model preset: Yu 6-DOF consistent, Kahraman–Singh, Chen fractal, Yu as \
                           printed (the choices below refine it)"
                        .into(),
                },
                ChoiceInfo {
                    name: "table".into(),
                    options: vec!["df-rig".into(), "rms-rig".into()],
                    default: "df-rig".into(),
                    note: "base parameter set: Table 1 (DF rig) or Table 2 (RMS rig)".into(),
                },
                choice_info("kind", o.kind, "which model"),
                choice_info("form", o.form, "Eq. (19) consistent or as printed"),
                choice_info("update", o.update, "backlash update (Fig. 8)"),
                choice_info("pressure_angle_law", o.pressure_angle, "pressure-angle law"),
                choice_info(
                    "dynamic_backlash",
                    o.dynamic_backlash,
                    "dynamic-backlash law",
                ),
                choice_info(
                    "centre_distance",
                    o.centre_distance,
                    "sign convention of Eq. (8)",
                ),
                ChoiceInfo {
                    name: "lock_centres".into(),
                    options: vec!["true".into(), "false".into()],
                    default: "false".into(),
                    note: "infinitely stiff bearings (flag)".into(),
                },
            ],
            methods: {
                let mut m = time_stepping_and_hbm(
                    (YU_TS, YU_TS_OUT),
                    "the state vector of the model (yu2021::STATE_LEN numbers)",
                    (YU_HBM, YU_HBM_OUT),
                );
                m.push(MethodInfo {
                    method: Method::Shooting,
                    settings: yu_shoot_settings(),
                    outputs: outs(SHOOT_OUT),
                    initial: Some("the state vector where the guess's integration starts"),
                });
                m
            },
        }
    }

    fn build(&self, ctx: &Context<'_>) -> Result<Adapter, PointError> {
        match ctx.solver.method {
            Method::TimeStepping => time_stepping(ctx),
            Method::Hbm => harmonic_balance(ctx),
            Method::Shooting => shooting(ctx),
            m => Err(wrong_method(
                "yu2021",
                m,
                &[Method::TimeStepping, Method::Hbm, Method::Shooting],
            )),
        }
    }

    fn presets(&self) -> Vec<Preset> {
        vec![
            Preset {
                set: "yu2021",
                name: "table1",
                value: || serde_json::to_value(yu2021::Yu2021Params::table1()).unwrap_or_default(),
            },
            Preset {
                set: "yu2021",
                name: "table2",
                value: || serde_json::to_value(yu2021::Yu2021Params::table2()).unwrap_or_default(),
            },
            Preset {
                set: "yu2021-options",
                name: "yu",
                value: || serde_json::to_value(yu2021::Options::default()).unwrap_or_default(),
            },
            Preset {
                set: "yu2021-options",
                name: "chen",
                value: || serde_json::to_value(yu2021::Options::chen()).unwrap_or_default(),
            },
        ]
    }

    fn full_methods(&self) -> &'static [&'static str] {
        &["time-stepping", "rk4", "hbm", "shooting"]
    }

    fn solve_full(
        &self,
        params: &J,
        method: &str,
        mut s: BTreeMap<String, J>,
    ) -> Result<J, PointError> {
        let (p, o, omega) = yu_inputs(params, &mut s)?;
        match method {
            "time-stepping" | "rk4" => {
                let mut run = yu2021::RunSettings::new(omega);
                // the run sizes of `geardyn study` (same names, bounds, messages)
                let mut shared = serde_json::Map::new();
                for k in ["transient_periods", "record_periods"] {
                    if let Some(v) = s.remove(k) {
                        shared.insert(k.to_owned(), v);
                    }
                }
                api::no_leftovers(method, s)?;
                api::study_settings("yu2021", Method::TimeStepping, &shared)?;
                let num = |k: &str, d: f64| shared.get(k).and_then(J::as_f64).unwrap_or(d);
                run.transient_periods = num("transient_periods", 200.0) as usize;
                run.record_periods = num("record_periods", 20.0) as usize;
                let engine = if method == "rk4" {
                    yu2021::Engine::Rk4Fixed
                } else {
                    yu2021::Engine::timestep()
                };
                let m = yu2021::Yu2021Model::new(&p, o)?;
                let r = m.simulate_with(&run, &engine, None)?;
                let df = r.dynamic_factor();
                let mut v = api::to_json(&r)?;
                if let J::Object(obj) = &mut v {
                    obj.insert("dynamic_factor".into(), json!(df));
                    obj.insert("converged".into(), J::Bool(true));
                }
                Ok(v)
            }
            "hbm" => {
                let hs = api::with_overrides(
                    "yu2021 hbm settings",
                    &yu2021::HbmSettings::default(),
                    &s.remove("hbm").unwrap_or(J::Null),
                )?;
                api::no_leftovers(method, s)?;
                let m = yu2021::Yu2021Model::new(&p, o)?;
                let r = m.harmonic_balance(omega, &hs, None)?;
                api::to_json(&r)
            }
            "shooting" => {
                // the study's method "shooting" (Yu's 6-DOF model with free centres): settings
                // (transient_periods, rtol, tol, max_iter, segments) checked and computed by
                // the study code
                let map = api::study_values(s)?;
                let m = yu2021::Yu2021Model::new(&p, o)?;
                let r =
                    shooting_point(m, omega, &map).map_err(crate::liu2021::registry::as_input)?;
                Ok(api::shooting_json(&r))
            }
            _ => Err(PointError::Input(format!(
                "yu2021 has no full-result method `{method}`"
            ))),
        }
    }
}

/// The Yu 2021 inputs of a full-result solve: parameters on top of Table 1, the model options
/// (`settings["options"]`) and `ω*` (a parameter, or `settings["omega"]` for older scripts).
fn yu_inputs(
    params: &J,
    s: &mut BTreeMap<String, J>,
) -> Result<(yu2021::Yu2021Params, yu2021::Options, f64), PointError> {
    let mut params = params.clone();
    let from_params = match &mut params {
        J::Object(o) => o.remove("omega"),
        _ => None,
    };
    let p = api::with_overrides("yu2021", &yu2021::Yu2021Params::table1(), &params)?;
    let o = api::with_overrides(
        "yu2021 options",
        &yu2021::Options::default(),
        &s.remove("options").unwrap_or(J::Null),
    )?;
    let from_settings = api::take_f64(s, "omega", f64::NAN)?;
    let omega = match from_params {
        Some(v) => v.as_f64().ok_or_else(|| {
            PointError::Input(format!("parameter `omega` takes a number, got {v}"))
        })?,
        None => from_settings,
    };
    if !(omega.is_finite() && omega > 0.0) {
        return Err(PointError::Input(format!(
            "yu2021.omega must be finite and > 0, got {omega} (set it as a parameter: \
             Yu2021().with_params(omega=0.5))"
        )));
    }
    Ok((p, o, omega))
}

fn time_stepping(ctx: &Context<'_>) -> Result<Adapter, PointError> {
    use yu2021::{Engine, RunSettings};
    let limits = ctx.limits;
    let s = Settings::read(
        "yu2021",
        Method::TimeStepping,
        YU_TS,
        &ctx.solver.settings,
        &[],
    )?;
    let check = s.name("tolerance_check") == "on";
    let timestep_engine = s.name("engine") == "timestep";
    if check && !timestep_engine {
        return Err(PointError::Input(
            "yu2021: tolerance_check = \"on\" needs engine = \"timestep\" (the \
             fixed-step RK4 has no tolerance)"
                .to_owned(),
        ));
    }
    let (rtol, atol) = (s.f("rtol"), s.f("atol"));
    let engine_at = move |factor: f64| {
        if timestep_engine {
            Engine::Timestep {
                method: timestep::Method::DormandPrince54,
                rtol: rtol / factor,
                atol: atol / factor,
                events: true,
            }
        } else {
            Engine::Rk4Fixed
        }
    };
    let initial = yu_initial(ctx)?;
    let n_rms = s.u("rms_harmonics").unwrap_or(5) as usize;
    let base = RunSettings {
        omega: 1.0,
        transient_periods: s.u("transient_periods").unwrap_or(200) as usize,
        record_periods: s.u("record_periods").unwrap_or(20) as usize,
        steps_per_period: s.u("steps_per_period").unwrap_or(256) as usize,
    };
    let lyapunov = lyapunov_plan(&s);
    if let Some(l) = lyapunov
        && l.window.exponents > 10
    {
        return Err(PointError::Input(format!(
            "setting `lyapunov_exponents` must be at most 10 for yu2021 (state dimension 10), \
             got {}",
            l.window.exponents
        )));
    }
    let mut names = YU_TS_OUT.to_vec();
    if let Some(l) = &lyapunov {
        names.extend(lyapunov_columns(l.window.exponents, "1"));
    }
    Ok(Adapter {
        outputs: outs_stepped(&names, check),
        prepare: Box::new(move |p: &Point| {
            let (model, omega) = yu_model(p)?;
            let settings = RunSettings { omega, ..base };
            if lyapunov.is_some() && model.options.update == yu2021::BacklashUpdate::PreviousStep {
                return Err(PointError::Input(
                    "yu2021: lyapunov = \"on\" needs the state-dependent backlash update \
                     (Fig. 8's previous-step update is not a function of the state)"
                        .to_owned(),
                ));
            }
            let steps = model.run_steps(&settings).context("yu2021 run size")?;
            let steps = steps as f64 + lyapunov.as_ref().map_or(0.0, lyapunov_steps);
            limits.need_steps("yu2021", steps)?;
            Ok(Box::new(move || {
                run_stepped(check, |factor| {
                    let r = model
                        .simulate_with(&settings, &engine_at(factor), initial)
                        .context("yu2021 time integration")?;
                    let mut rec = Record::new();
                    rec.push("df", "1", r.dynamic_factor())
                        .push("rms", "1", r.rms(n_rms))
                        .push("mean_dte", "1", r.mean_dte())
                        .push("dte_peak_to_peak", "1", r.dte_peak_to_peak())
                        .push("mean_backlash", "1", r.mean_backlash());
                    if let Some(l) = &lyapunov {
                        // from the end state of the run, at its time (Chen's fractal backlash
                        // is not periodic in time)
                        let t = tighter(l, factor);
                        let s = model
                            .lyapunov_batches(&settings, &r.final_state, &t.window, t.batches)
                            .context("yu2021")?;
                        push_lyapunov(&mut rec, &s, std::f64::consts::TAU / omega, "1");
                    }
                    Ok((rec, r.stats))
                })
            }) as Job)
        }),
    })
}

fn harmonic_balance(ctx: &Context<'_>) -> Result<Adapter, PointError> {
    no_initial("yu2021", ctx)?;
    let s = Settings::read("yu2021", Method::Hbm, YU_HBM, &ctx.solver.settings, &[])?;
    let mut settings = yu2021::HbmSettings::default();
    if let Some(h) = s.u("harmonics") {
        settings.harmonics = h as usize;
    }
    if let Some(m) = s.u("samples") {
        settings.samples = m as usize;
    }
    if let Some(m) = s.u("max_iterations") {
        settings.max_iterations = m as usize;
    }
    settings.tolerance = s.f("tolerance");
    if settings.samples < 4 * settings.harmonics + 2 {
        return Err(PointError::Input(format!(
            "yu2021 hbm: samples = {} must be >= 4·harmonics + 2 = {}",
            settings.samples,
            4 * settings.harmonics + 2
        )));
    }
    Ok(Adapter {
        outputs: outs(YU_HBM_OUT),
        prepare: Box::new(move |p: &Point| {
            let (model, omega) = yu_model(p)?;
            if !(omega.is_finite() && omega > 0.0) {
                return Err(PointError::Compute(format!(
                    "yu2021.omega must be finite and > 0, got {omega}"
                )));
            }
            Ok(Box::new(move || {
                let s = model
                    .harmonic_balance(omega, &settings, None)
                    .context("yu2021 harmonic balance")?;
                let c = &s.coefficients;
                let a1 = if c.len() >= 3 {
                    c[1].dhypot(c[2])
                } else {
                    f64::NAN
                };
                let mut rec = Record::new();
                rec.push("mean_dte", "1", c.first().copied().unwrap_or(f64::NAN))
                    .push("first_harmonic_amplitude", "1", a1)
                    .push("converged", "1", if s.converged { 1.0 } else { 0.0 })
                    .push("residual_norm", "1", s.residual_norm)
                    .push("truncation", "1", s.truncation);
                Ok(rec)
            }) as Job)
        }),
    })
}

fn shooting(ctx: &Context<'_>) -> Result<Adapter, PointError> {
    let limits = ctx.limits;
    let s = Settings::read(
        "yu2021",
        Method::Shooting,
        &yu_shoot_settings(),
        &ctx.solver.settings,
        &[],
    )?;
    let initial = yu_initial(ctx)?;
    let transient = s.u("transient_periods").unwrap_or(200) as usize;
    let s = Arc::new(s);
    Ok(Adapter {
        outputs: outs(SHOOT_OUT),
        prepare: Box::new(move |p: &Point| {
            let (model, omega) = yu_model(p)?;
            let settings = yu2021::RunSettings {
                omega,
                transient_periods: transient,
                record_periods: 1,
                steps_per_period: 256,
            };
            let steps = model.run_steps(&settings).context("yu2021 run size")?;
            limits.need_steps("yu2021 shooting", steps as f64)?;
            let s = Arc::clone(&s);
            Ok(Box::new(move || {
                let sys = yu2021::Yu2021SixDof::new(&model, omega).context("yu2021 shooting")?;
                let r = model
                    .simulate_with(&settings, &yu2021::Engine::Rk4Fixed, initial)
                    .context("yu2021 shooting guess")?;
                let period = std::f64::consts::TAU / omega;
                shoot_any("yu2021", sys, period, &r.final_state, &s)
            }) as Job)
        }),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contract::default_of;

    /// The documented defaults are the library's defaults (the same literals: exact).
    #[test]
    #[allow(clippy::float_cmp)]
    fn setting_defaults_match_the_library() {
        let r = yu2021::RunSettings::new(1.0);
        assert_eq!(
            default_of(YU_TS, "transient_periods"),
            r.transient_periods as f64
        );
        assert_eq!(default_of(YU_TS, "record_periods"), r.record_periods as f64);
        assert_eq!(
            default_of(YU_TS, "steps_per_period"),
            r.steps_per_period as f64
        );
        assert_eq!(
            default_of(YU_HBM, "tolerance"),
            yu2021::HbmSettings::default().tolerance
        );
    }
}
