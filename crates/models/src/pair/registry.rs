//! The generic spur pair of the [`REGISTRY`](crate::contract::REGISTRY) (`generic-pair`):
//! [`PairParams::example_spur`](crate::pair::PairParams::example_spur) in SI units, by time
//! stepping, harmonic balance or shooting.

use crate::contract::lyapunov::{
    LYAPUNOV, LYAPUNOV_BATCHES, LYAPUNOV_EXPONENTS, LYAPUNOV_PERIODS, LYAPUNOV_RTOL,
    lyapunov_columns, lyapunov_plan, lyapunov_steps, push_lyapunov, run_lyapunov, tighter,
};
use math::DetMath;
use std::sync::Arc;

use crate::contract::shoot::{SHOOT_OUT, shoot_any, shoot_settings, shoot_transient};
use crate::contract::spur::{
    AFT_SAMPLES, RECORD_PERIODS, TRANSIENT_PERIODS, time_stepping_and_hbm,
};
use crate::contract::{
    self, Adapter, ChoiceInfo, Context, Job, Kind, Method, MethodInfo, ModelInfo, Point,
    PointError, Record, SettingDef, Settings, TOLERANCE_CHECK, Value, WithContext, apply_values,
    no_initial, outs, outs_stepped, params_of, run_stepped, take_choice, wrong_method,
};
use crate::pair;

/// The generic spur pair from the leaves (tooth-pair stiffness, constant backlash; 1-DOF or
/// 6-DOF).
#[derive(Debug, Clone, Copy)]
pub struct Pair;

/// The unit of a parameter by its own name (the last segment of its dotted path).
fn pair_unit(k: &str) -> &'static str {
    match k.rsplit('.').next().unwrap_or(k) {
        "equivalent_mass" | "masses" => "kg",
        "rp" | "rg" | "ste_amplitude" | "b" => "m",
        "pressure_angle" | "ste_phase" => "rad",
        "bearing_stiffness" | "k_single" | "k_double" => "N/m",
        "bearing_damping" | "mesh_damping" => "N·s/m",
        "static_force" => "N",
        "mesh_frequency" => "rad/s",
        _ => "1",
    }
}

const PAIR_TS: &[SettingDef] = &[
    TRANSIENT_PERIODS,
    RECORD_PERIODS,
    SettingDef {
        name: "samples_per_period",
        kind: Kind::Int {
            lo: 4,
            hi: 100_000,
            default: Some(64),
        },
        doc: "samples per recorded mesh period",
    },
    SettingDef {
        name: "rtol",
        kind: Kind::Num {
            lo: 1e-14,
            hi: 1e-2,
            default: 1e-9,
        },
        doc: "relative tolerance (Dormand–Prince 5(4), gap edges as events)",
    },
    SettingDef {
        name: "atol",
        kind: Kind::Num {
            lo: 1e-20,
            hi: 1e-2,
            default: 1e-12,
        },
        doc: "absolute tolerance (units of the coordinates)",
    },
    TOLERANCE_CHECK,
    LYAPUNOV,
    LYAPUNOV_PERIODS,
    LYAPUNOV_EXPONENTS,
    LYAPUNOV_RTOL,
    LYAPUNOV_BATCHES,
];

const PAIR_HBM: &[SettingDef] = &[
    SettingDef {
        name: "harmonics",
        kind: Kind::Int {
            lo: 1,
            hi: 64,
            default: Some(16),
        },
        doc: "harmonics H of the mesh frequency",
    },
    AFT_SAMPLES,
    SettingDef {
        name: "tolerance",
        kind: Kind::Num {
            lo: 1e-14,
            hi: 1e3,
            default: 1e-6,
        },
        doc: "residual-norm tolerance (N)",
    },
];

const PAIR_TS_OUT: &[(&str, &str)] = &[("df", "1"), ("mean_dte", "m"), ("dte_peak_to_peak", "m")];
const PAIR_HBM_OUT: &[(&str, &str)] = &[
    ("mean_u", "m"),
    ("first_harmonic_amplitude", "m"),
    ("converged", "1"),
    ("residual_norm", "N"),
    ("truncation", "1"),
];

const PAIR_SHOOT_TRANSIENT: &str = "mesh periods of the model's time integration from \
     `initial` (or its static contact) whose end state is the shooting guess";

fn pair_shoot_settings() -> Vec<SettingDef> {
    shoot_settings(shoot_transient(200, PAIR_SHOOT_TRANSIENT))
}

/// A point of the generic pair: `dofs` (a choice) and the numbers of `PairParams`.
fn pair_model(p: &Point) -> Result<(pair::GearPair, f64), PointError> {
    let mut fields = p.clone();
    let dofs = match take_choice(&mut fields, "dofs", None)? {
        None => pair::Dofs::Torsional,
        Some(Value::Text(s)) if s == "torsional" => pair::Dofs::Torsional,
        Some(Value::Text(s)) if s == "transverse-torsional" => pair::Dofs::TransverseTorsional,
        Some(v) => {
            return Err(PointError::Input(format!(
                "`dofs` = {} is not an option; options: \"torsional\", \"transverse-torsional\"",
                v.label()
            )));
        }
    };
    let mut params = apply_values(&pair::PairParams::example_spur(), &fields)?;
    params.dofs = dofs;
    let model = pair::GearPair::from_params(&params).context("generic-pair parameters")?;
    Ok((model, params.static_force))
}

impl contract::Model for Pair {
    fn name(&self) -> &'static str {
        "generic-pair"
    }

    fn description(&self) -> &'static str {
        "Generic spur pair from the leaves (tooth-pair stiffness, constant backlash; 1-DOF or 6-DOF)"
    }

    fn unit_of(&self, parameter: &str) -> &'static str {
        pair_unit(parameter)
    }

    fn describe(&self) -> ModelInfo {
        ModelInfo {
            // every number of `PairParams` by the dotted path a point's overrides accept
            // (`geometry.rp`, `backlash.b`, `stiffness.curve.k_single`), except the stiffness
            // law's own mesh frequency, which `mesh_frequency` replaces
            parameters: params_of(&pair::PairParams::example_spur(), pair_unit)
                .into_iter()
                .filter(|p| p.name != "stiffness.omega_e")
                .collect(),
            choices: vec![ChoiceInfo {
                name: "dofs".into(),
                options: vec!["torsional".into(), "transverse-torsional".into()],
                default: "torsional".into(),
                note: "1-DOF torsional or 6-DOF transverse-torsional".into(),
            }],
            methods: {
                let mut m = time_stepping_and_hbm(
                    (PAIR_TS, PAIR_TS_OUT),
                    "[q, q'] (2 × number of DOFs)",
                    (PAIR_HBM, PAIR_HBM_OUT),
                );
                m.push(MethodInfo {
                    method: Method::Shooting,
                    settings: pair_shoot_settings(),
                    outputs: outs(SHOOT_OUT),
                    initial: Some("[q, q'] where the guess's integration starts"),
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
                "generic-pair",
                m,
                &[Method::TimeStepping, Method::Hbm, Method::Shooting],
            )),
        }
    }
}

fn time_stepping(ctx: &Context<'_>) -> Result<Adapter, PointError> {
    let limits = ctx.limits;
    let s = Settings::read(
        "generic-pair",
        Method::TimeStepping,
        PAIR_TS,
        &ctx.solver.settings,
        &[],
    )?;
    let settings = pair::TimeSettings {
        transient_periods: s.u("transient_periods").unwrap_or(200) as usize,
        record_periods: s.u("record_periods").unwrap_or(20) as usize,
        samples_per_period: s.u("samples_per_period").unwrap_or(64) as usize,
        rtol: s.f("rtol"),
        atol: s.f("atol"),
    };
    let initial = ctx.initial.map(<[f64]>::to_vec);
    let check = s.name("tolerance_check") == "on";
    let lyapunov = lyapunov_plan(&s);
    let mut names = PAIR_TS_OUT.to_vec();
    if let Some(l) = &lyapunov {
        names.extend(lyapunov_columns(l.window.exponents, "1/s"));
    }
    Ok(Adapter {
        outputs: outs_stepped(&names, check),
        prepare: Box::new(move |p: &Point| {
            let (model, f_s) = pair_model(p)?;
            if let Some(l) = &lyapunov {
                let dim = 2 * system::SecondOrderSystem::n_dof(&model);
                if l.window.exponents > dim {
                    return Err(PointError::Input(format!(
                        "setting `lyapunov_exponents` must be at most the state dimension \
                         {dim} of this generic-pair, got {}",
                        l.window.exponents
                    )));
                }
            }
            // adaptive steps: at least 8 per mesh period (h_max = T/8)
            let periods = settings.transient_periods + settings.record_periods;
            let steps = 8.0 * periods as f64 + lyapunov.as_ref().map_or(0.0, lyapunov_steps);
            limits.need_steps("generic-pair", steps)?;
            let initial = initial.clone();
            Ok(Box::new(move || {
                run_stepped(check, |factor| {
                    let st = pair::TimeSettings {
                        rtol: settings.rtol / factor,
                        atol: settings.atol / factor,
                        ..settings
                    };
                    let r = model
                        .time_response(&st, initial.as_deref())
                        .context("generic-pair time integration")?;
                    let n = r.delta.len().max(1) as f64;
                    let max = r.delta.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                    let min = r.delta.iter().copied().fold(f64::INFINITY, f64::min);
                    let mut rec = Record::new();
                    rec.push("df", "1", r.dynamic_factor(f_s))
                        .push("mean_dte", "m", r.delta.iter().sum::<f64>() / n)
                        .push("dte_peak_to_peak", "m", max - min);
                    if let Some(l) = &lyapunov {
                        // from the end state of the run, at its time
                        let period = std::f64::consts::TAU / r.omega;
                        let periods = (st.transient_periods + st.record_periods) as f64;
                        let s = run_lyapunov(
                            "generic-pair",
                            model.clone(),
                            period,
                            (periods * period, &r.final_state),
                            &tighter(l, factor),
                        )?;
                        push_lyapunov(&mut rec, &s, period, "1/s");
                    }
                    Ok((rec, r.stats))
                })
            }) as Job)
        }),
    })
}

fn harmonic_balance(ctx: &Context<'_>) -> Result<Adapter, PointError> {
    no_initial("generic-pair", ctx)?;
    let s = Settings::read(
        "generic-pair",
        Method::Hbm,
        PAIR_HBM,
        &ctx.solver.settings,
        &[],
    )?;
    let h = s.u("harmonics").unwrap_or(16) as usize;
    let samples = s.u("samples").unwrap_or(256) as usize;
    if samples < 4 * h + 2 {
        return Err(PointError::Input(format!(
            "generic-pair hbm: samples = {samples} must be >= 4·harmonics + 2 = {}",
            4 * h + 2
        )));
    }
    let options = hbm::SolverOptions {
        tolerance: s.f("tolerance"),
        ..hbm::SolverOptions::default()
    };
    Ok(Adapter {
        outputs: outs(PAIR_HBM_OUT),
        prepare: Box::new(move |p: &Point| {
            let (model, _) = pair_model(p)?;
            Ok(Box::new(move || {
                let n = model.dofs().n();
                let mut z0 = vec![0.0; n * (2 * h + 1)];
                z0[..n].copy_from_slice(&model.static_state());
                let mut problem = model
                    .hbm_problem(h, samples)
                    .context("generic-pair harmonic balance")?;
                let sol = problem
                    .solve(&z0, &options)
                    .map_err(crate::Error::from)
                    .context("generic-pair harmonic balance")?;
                let c = &sol.coefficients;
                let mut rec = Record::new();
                rec.push("mean_u", "m", c[0])
                    .push("first_harmonic_amplitude", "m", c[n].dhypot(c[2 * n]))
                    .push("converged", "1", if sol.converged { 1.0 } else { 0.0 })
                    .push("residual_norm", "N", sol.residual_norm)
                    .push("truncation", "1", sol.truncation);
                Ok(rec)
            }) as Job)
        }),
    })
}

fn shooting(ctx: &Context<'_>) -> Result<Adapter, PointError> {
    let limits = ctx.limits;
    let s = Settings::read(
        "generic-pair",
        Method::Shooting,
        &pair_shoot_settings(),
        &ctx.solver.settings,
        &[],
    )?;
    let initial = ctx.initial.map(<[f64]>::to_vec);
    let settings = pair::TimeSettings {
        transient_periods: s.u("transient_periods").unwrap_or(200) as usize,
        record_periods: 1,
        samples_per_period: 4,
        ..pair::TimeSettings::default()
    };
    let s = Arc::new(s);
    Ok(Adapter {
        outputs: outs(SHOOT_OUT),
        prepare: Box::new(move |p: &Point| {
            let (model, _) = pair_model(p)?;
            let periods = settings.transient_periods + settings.record_periods;
            limits.need_steps("generic-pair shooting", 8.0 * periods as f64)?;
            let (s, initial) = (Arc::clone(&s), initial.clone());
            Ok(Box::new(move || {
                let r = model
                    .time_response(&settings, initial.as_deref())
                    .context("generic-pair shooting guess")?;
                let period = std::f64::consts::TAU / model.mesh_frequency();
                shoot_any("generic-pair", model, period, &r.final_state, &s)
            }) as Job)
        }),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;

    /// `lyapunov = "on"` reaches the generic pair: the columns in `1/s`, a full spectrum whose
    /// sum is the run's `lambda_sum`, and the exponent bound named.
    #[test]
    fn lyapunov_columns_reach_the_generic_pair() {
        let solve = |extra: &[(&str, Value)]| {
            let mut settings: BTreeMap<String, Value> = [
                ("transient_periods", Value::Num(5.0)),
                ("record_periods", Value::Num(2.0)),
                ("lyapunov", Value::Text("on".into())),
                ("lyapunov_periods", Value::Num(5.0)),
            ]
            .into_iter()
            .map(|(k, v)| (k.to_owned(), v))
            .collect();
            for (k, v) in extra {
                settings.insert((*k).to_owned(), v.clone());
            }
            let solver = contract::Solver {
                method: Method::TimeStepping,
                settings,
            };
            let ctx = Context {
                solver: &solver,
                initial: None,
                limits: contract::Limits::default(),
            };
            contract::Model::solve(&Pair, &Point::new(), &ctx)
        };
        let r = solve(&[("lyapunov_exponents", Value::Num(2.0))]).unwrap();
        let (l1, l2) = (r.get("lambda1").unwrap(), r.get("lambda2").unwrap());
        assert!(l1.is_finite() && l2.is_finite());
        assert!((l1 + l2 - r.get("lambda_sum").unwrap()).abs() <= 1e-12 * l1.abs().max(1.0));
        let unit = |n: &str| {
            r.columns()
                .iter()
                .find(|c| c.name == n)
                .map(|c| c.unit.clone())
        };
        assert_eq!(unit("lambda1").as_deref(), Some("1/s"));
        let e = solve(&[("lyapunov_exponents", Value::Num(5.0))])
            .unwrap_err()
            .to_string();
        assert!(e.contains("lyapunov_exponents"), "{e}");
    }
}
