//! The Karpov 2017 models of the [`REGISTRY`](crate::contract::REGISTRY): the non-circular
//! pair's kinematics (`karpov2017-kinematics`) and the oscillator with variable mesh frequency
//! (`karpov2017`).

use math::DetMath;
use std::collections::BTreeMap;

use crate::contract::{
    self, Adapter, Context, Job, Kind, MethodInfo, ModelInfo, ParamInfo, Point, PointError, Preset,
    Record, SettingDef, Settings, TOLERANCE_CHECK, Value, WithContext, api, apply_values,
    choice_info, outs, outs_stepped, params_of, reject_legacy, run_stepped, take_choice,
    wrong_method,
};
use crate::contract::{Method, no_initial};
use crate::karpov2017::Karpov2017;

// ---------------------------------------------------------------------------------------------
// karpov2017-kinematics

/// The kinematics of Karpov's slightly non-circular pair (`gear_geometry::KarpovPair`): speed
/// fluctuation and peak acceleration, exact and by the paper's approximations.
#[derive(Debug, Clone, Copy)]
pub struct Kinematics;

fn kinematics_unit(k: &str) -> &'static str {
    match k {
        "r" => "m",
        "omega1" => "rad/s",
        _ => "1",
    }
}

const KINEMATICS_OUT: &[(&str, &str)] = &[
    ("delta_exact", "1"),
    ("delta_eq4", "1"),
    ("emax_exact", "rad/s^2"),
    ("emax_eq6", "rad/s^2"),
    ("b_max_exact", "1"),
];

impl contract::Model for Kinematics {
    fn name(&self) -> &'static str {
        "karpov2017-kinematics"
    }

    fn description(&self) -> &'static str {
        "Karpov 2017 non-circular pair: speed fluctuation δ and peak acceleration ε_max"
    }

    fn unit_of(&self, parameter: &str) -> &'static str {
        kinematics_unit(parameter)
    }

    fn describe(&self) -> ModelInfo {
        let base = super::pair_params_table1();
        let mut parameters = params_of(&base, kinematics_unit);
        parameters.push(ParamInfo {
            name: "omega1".into(),
            unit: "rad/s".into(),
            default: "1".into(),
        });
        parameters.push(ParamInfo {
            name: "delta_max".into(),
            unit: "1".into(),
            default: "0.001".into(),
        });
        ModelInfo {
            parameters,
            choices: vec![choice_info(
                "centre_distance",
                base.centre_distance,
                "centre-distance closure (reading R-KARPOV-EQ1-CLOSURE)",
            )],
            methods: vec![MethodInfo {
                method: Method::Kinematics,
                settings: vec![],
                outputs: outs(KINEMATICS_OUT),
                initial: None,
            }],
        }
    }

    fn build(&self, ctx: &Context<'_>) -> Result<Adapter, PointError> {
        if ctx.solver.method != Method::Kinematics {
            return Err(wrong_method(
                "karpov2017-kinematics",
                ctx.solver.method,
                &[Method::Kinematics],
            ));
        }
        no_initial("karpov2017-kinematics", ctx)?;
        Settings::read(
            "karpov2017-kinematics",
            Method::Kinematics,
            &[],
            &ctx.solver.settings,
            &[],
        )?;
        Ok(Adapter {
            outputs: outs(KINEMATICS_OUT),
            prepare: Box::new(|p: &Point| {
                let mut fields = p.clone();
                let num = |f: &mut Point, k: &str, d: f64| match f.remove(k) {
                    None => Ok(d),
                    Some(Value::Num(x)) => Ok(x),
                    Some(v) => Err(PointError::Input(format!(
                        "`{k}` takes a number, got {}",
                        v.label()
                    ))),
                };
                let omega1 = num(&mut fields, "omega1", 1.0)?;
                let delta_max = num(&mut fields, "delta_max", 0.001)?;
                let base = super::pair_params_table1();
                // an unknown name lists the two point numbers taken above with the set's paths
                let params = apply_values(&base, &fields).map_err(|e| match e {
                    PointError::UnknownParameter { name, mut paths } => {
                        paths.extend(["delta_max".to_owned(), "omega1".to_owned()]);
                        paths.sort();
                        PointError::UnknownParameter { name, paths }
                    }
                    e => e,
                })?;
                if !(omega1.is_finite() && omega1 > 0.0) {
                    return Err(PointError::Compute(format!(
                        "omega1 must be finite and > 0, got {omega1}"
                    )));
                }
                if !(delta_max > 0.0 && delta_max < 1.0) {
                    return Err(PointError::Compute(format!(
                        "delta_max must be in (0, 1), got {delta_max}"
                    )));
                }
                let pair = gear_geometry::KarpovPair::new(params).context("Karpov pair")?;
                Ok(Box::new(move || {
                    let check = pair.design_check(delta_max).context("design check")?;
                    let mut r = Record::new();
                    r.push("delta_exact", "1", pair.speed_fluctuation())
                        .push("delta_eq4", "1", pair.speed_fluctuation_eq4())
                        .push("emax_exact", "rad/s^2", pair.max_acceleration(omega1))
                        .push("emax_eq6", "rad/s^2", pair.max_acceleration_eq6(omega1))
                        .push("b_max_exact", "1", check.b_max_exact);
                    Ok(r)
                }) as Job)
            }),
        })
    }
}

// ---------------------------------------------------------------------------------------------
// karpov2017

/// The oscillator excited at the variable mesh frequency (Eq. 9), by the exact Duhamel
/// quadrature or by time stepping.
#[derive(Debug, Clone, Copy)]
pub struct Karpov;

const KARPOV_TS: &[SettingDef] = &[
    SettingDef {
        name: "engine",
        kind: Kind::Name {
            options: &["duhamel", "timestep"],
            default: "duhamel",
        },
        doc: "duhamel: the model's exact Duhamel-integral quadrature (from rest); timestep: the \
              timestep crate's Dormand–Prince 5(4) (no `A` column)",
    },
    SettingDef {
        name: "rtol",
        kind: Kind::Num {
            lo: 1e-14,
            hi: 1e-2,
            default: 1e-9,
        },
        doc: "relative (and absolute) tolerance of the timestep engine",
    },
    TOLERANCE_CHECK,
];

const KARPOV_OUT: &[(&str, &str)] = &[("A", "1"), ("envelope", "1"), ("x_final", "1")];

/// The Duhamel engine's accuracy column: [`crate::karpov2017::KarpovResponse::error_estimate`].
const KARPOV_ERROR: (&str, &str) = ("error_estimate", "1");

/// The outputs of the Karpov oscillator on either engine.
fn karpov_outputs(duhamel: bool, check: bool) -> Vec<(String, String)> {
    if duhamel {
        let mut o = outs(KARPOV_OUT);
        o.extend(outs(&[KARPOV_ERROR]));
        o
    } else {
        // the timestep engine does not sample the last cycle: no `A` column
        outs_stepped(&KARPOV_OUT[1..], check)
    }
}

impl contract::Model for Karpov {
    fn name(&self) -> &'static str {
        "karpov2017"
    }

    fn description(&self) -> &'static str {
        "Karpov 2017 oscillator with variable mesh frequency (Eq. 9)"
    }

    fn unit_of(&self, _parameter: &str) -> &'static str {
        "1"
    }

    fn describe(&self) -> ModelInfo {
        let p = Karpov2017::fig3().params();
        ModelInfo {
            parameters: params_of(&p, |_| "1"),
            choices: vec![
                choice_info(
                    "excitation",
                    p.excitation,
                    "excitation phase (reading R-KARPOV-EQ9): accumulated ∫ωe dτ or sin(ωe·τ) as printed",
                ),
                choice_info("measure", p.measure, "amplitude measure A"),
            ],
            methods: vec![MethodInfo {
                method: Method::TimeStepping,
                settings: KARPOV_TS.to_vec(),
                outputs: karpov_outputs(true, false),
                initial: Some("[X, X'] at τ = 0 (engine = \"timestep\" only)"),
            }],
        }
    }

    fn build(&self, ctx: &Context<'_>) -> Result<Adapter, PointError> {
        if ctx.solver.method != Method::TimeStepping {
            return Err(wrong_method(
                "karpov2017",
                ctx.solver.method,
                &[Method::TimeStepping],
            ));
        }
        let s = Settings::read(
            "karpov2017",
            Method::TimeStepping,
            KARPOV_TS,
            &ctx.solver.settings,
            &[("duhamel", "engine = \"duhamel\" or engine = \"timestep\"")],
        )?;
        let duhamel = s.name("engine") == "duhamel";
        let rtol = s.f("rtol");
        let check = s.name("tolerance_check") == "on";
        if check && duhamel {
            return Err(PointError::Input(
                "karpov2017: tolerance_check = \"on\" needs engine = \"timestep\" (the Duhamel \
                 quadrature states its own error estimate)"
                    .to_owned(),
            ));
        }
        let initial = match ctx.initial {
            None => [0.0, 0.0],
            Some(_) if duhamel => {
                return Err(PointError::Input(
                    "karpov2017: `initial` needs engine = \"timestep\" (the Duhamel path starts \
                     from rest)"
                        .to_owned(),
                ));
            }
            Some([x, v]) => [*x, *v],
            Some(v) => {
                return Err(PointError::Input(format!(
                    "karpov2017: `initial` must be [X, X'], got {} numbers",
                    v.len()
                )));
            }
        };
        let limits = ctx.limits;
        Ok(Adapter {
            outputs: karpov_outputs(duhamel, check),
            prepare: Box::new(move |p: &Point| {
                let mut fields = p.clone();
                reject_legacy(
                    &fields,
                    &[(
                        "printed_phase",
                        "excitation = \"accumulated-phase\" or excitation = \"printed-phase\"",
                    )],
                )?;
                for c in ["excitation", "measure"] {
                    if let Some(Value::Num(_)) = fields.get(c) {
                        take_choice(&mut fields, c, None)?;
                    }
                }
                let params = apply_values(&Karpov2017::fig3().params(), &fields)?;
                let m = Karpov2017::new(params).context("karpov2017 parameters")?;
                // Quadrature panels ≈ τ_end (1 + |Φ'|)/2 with |Φ'| ≥ ω(1 − B).
                let est = params.tau_end * (1.0 + params.omega * (1.0 - params.b)) / 2.0;
                limits.need_steps("karpov2017", est)?;
                let max_steps = limits.max_steps as u64;
                Ok(Box::new(move || {
                    if duhamel {
                        let r = m.duhamel().context("karpov2017 Duhamel quadrature")?;
                        let mut rec = Record::new();
                        rec.push("A", "1", r.amplitude)
                            .push("envelope", "1", r.envelope)
                            .push("x_final", "1", r.x)
                            .push(KARPOV_ERROR.0, KARPOV_ERROR.1, r.error_estimate);
                        Ok(rec)
                    } else {
                        let ode = m.time_stepping().context("karpov2017 system")?;
                        run_stepped(check, |factor| {
                            let opts = timestep::Options::default()
                                .with_tol(rtol / factor, rtol / factor)
                                .with_max_steps(max_steps)
                                .with_output(timestep::Output::Final);
                            let sol =
                                timestep::integrate(&ode, 0.0, &initial, params.tau_end, &opts)
                                    .context("karpov2017 time integration")?;
                            if !sol.status.is_success() {
                                return Err(PointError::Compute(format!(
                                    "time integration ended with {:?}",
                                    sol.status
                                )));
                            }
                            let (x, v) = (sol.y_final[0], sol.y_final[1]);
                            let mut rec = Record::new();
                            rec.push("envelope", "1", x.dhypot(v))
                                .push("x_final", "1", x);
                            Ok((rec, sol.stats))
                        })
                    }
                }) as Job)
            }),
        })
    }

    fn presets(&self) -> Vec<Preset> {
        vec![Preset {
            set: "karpov2017",
            name: "fig3",
            value: || serde_json::to_value(Karpov2017::fig3().params()).unwrap_or_default(),
        }]
    }

    fn full_methods(&self) -> &'static [&'static str] {
        &["duhamel", "time-stepping"]
    }

    fn solve_full(
        &self,
        params: &serde_json::Value,
        method: &str,
        s: BTreeMap<String, serde_json::Value>,
    ) -> Result<serde_json::Value, PointError> {
        let base = Karpov2017::fig3().params();
        let p: crate::karpov2017::Karpov2017Params =
            api::with_overrides("karpov2017", &base, params)?;
        api::no_leftovers(method, s)?;
        let m = Karpov2017::new(p)?;
        let r = m.duhamel()?;
        let mut v = api::to_json(&r)?;
        if let serde_json::Value::Object(o) = &mut v {
            o.insert("converged".into(), serde_json::Value::Bool(true));
        }
        Ok(v)
    }
}
