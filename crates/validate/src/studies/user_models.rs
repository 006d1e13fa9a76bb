//! User-study adapters of the dynamic models (see `docs/studies.md`).

use std::collections::BTreeMap;

use models::liu2021;

use super::Adapter;
use crate::user::{Method, Solver};
use crate::{Error, ResultExt, apply_overrides};

/// Split the solver settings into the ones named in `extra` and the rest.
fn take(
    settings: &BTreeMap<String, f64>,
    extra: &[&str],
) -> (BTreeMap<String, f64>, BTreeMap<String, f64>) {
    let mut a = BTreeMap::new();
    let mut b = BTreeMap::new();
    for (k, v) in settings {
        if extra.contains(&k.as_str()) {
            a.insert(k.clone(), *v);
        } else {
            b.insert(k.clone(), *v);
        }
    }
    (a, b)
}

/// Liu 2021: overrides are fields of `models::liu2021::Parameters` (SI) plus `readings_printed`
/// (1: every equation as printed, 0: consistent, default). Time stepping settings are the fields
/// of `IntegrationOptions`; HBM settings `tol`, `max_iter`, `samples` and `full_r` (full basis
/// with `K = R Z2 + 2`; absent: the paper's basis).
pub(super) fn liu2021(solver: &Solver) -> Result<Adapter, Error> {
    let outputs = vec![
        ("rsv", "1"),
        ("ppv", "1"),
        ("q_min", "1"),
        ("q_max", "1"),
        ("converged", "1"),
    ];
    match solver.method {
        Method::TimeStepping => {
            let opts = apply_overrides(&liu2021::IntegrationOptions::default(), &solver.settings)?;
            Ok((
                outputs,
                Box::new(move |p: &BTreeMap<String, f64>| {
                    let model = liu_model(p)?;
                    let r =
                        liu2021::integrate(&model, &opts).context("liu2021 time integration")?;
                    Ok(vec![
                        f64::from(r.rattle.state.rsv()),
                        r.rattle.ppv,
                        r.rattle.q_min,
                        r.rattle.q_max,
                        1.0,
                    ])
                }),
            ))
        }
        Method::Hbm => {
            let (extra, rest) = take(&solver.settings, &["full_r", "samples"]);
            let base = apply_overrides(&liu2021::HbmOptions::default(), &rest)?;
            let full_r = extra.get("full_r").copied();
            let samples = extra.get("samples").copied();
            for (k, v) in &extra {
                if v.fract() != 0.0 || *v < 1.0 {
                    return Err(Error::StudyFile(format!(
                        "setting `{k}` must be a positive integer, got {v}"
                    )));
                }
            }
            Ok((
                outputs,
                Box::new(move |p: &BTreeMap<String, f64>| {
                    let model = liu_model(p)?;
                    let mut opts = match full_r {
                        Some(r) => liu2021::HbmOptions {
                            tol: base.tol,
                            max_iter: base.max_iter,
                            ..liu2021::HbmOptions::full(&model, r as usize)
                        },
                        None => base,
                    };
                    if let Some(m) = samples {
                        opts.samples = Some(m as usize);
                    }
                    let r = liu2021::solve_hbm(&model, &opts, None)
                        .context("liu2021 harmonic balance")?;
                    Ok(vec![
                        f64::from(r.rattle.state.rsv()),
                        r.rattle.ppv,
                        r.rattle.q_min,
                        r.rattle.q_max,
                        if r.converged() { 1.0 } else { 0.0 },
                    ])
                }),
            ))
        }
        Method::Kinematics => Err(Error::StudyFile(
            "liu2021 needs solver.method = \"time-stepping\" or \"hbm\"".to_owned(),
        )),
    }
}

fn liu_model(p: &BTreeMap<String, f64>) -> Result<liu2021::Model, Error> {
    let mut fields = p.clone();
    let printed = fields.remove("readings_printed");
    let mut params = apply_overrides(&liu2021::table1(), &fields)?;
    match printed.map(f64::to_bits) {
        None => {}
        Some(b) if b == 0f64.to_bits() => params.readings = liu2021::Readings::default(),
        Some(b) if b == 1f64.to_bits() => params.readings = liu2021::Readings::printed(),
        Some(b) => {
            let x = f64::from_bits(b);
            return Err(Error::StudyFile(format!(
                "readings_printed must be 0 or 1, got {x}"
            )));
        }
    }
    params.model().context("liu2021 parameters")
}

/// Yu 2021: overrides are fields of `models::yu2021::Yu2021Params` (SI) on top of its
/// `table1()` (DF rig) or, with `table = 2`, `table2()` (RMS rig); `omega` is the dimensionless
/// mesh frequency ω* (required); `variant` selects the model: 0 Yu 6-DOF consistent (default),
/// 1 Kahraman–Singh, 2 Chen fractal, 3 Yu as printed. Time stepping settings: `transient_periods`,
/// `record_periods`, `steps_per_period`, `rms_harmonics` (default 5); HBM settings: fields of
/// `HbmSettings` (`harmonics`, `samples`, `tolerance`, `max_iterations`), torsional models only.
pub(super) fn yu2021(solver: &Solver) -> Result<Adapter, Error> {
    use models::yu2021::{HbmSettings, RunSettings};
    match solver.method {
        Method::TimeStepping => {
            let (extra, rest) = take(
                &solver.settings,
                &["rms_harmonics", "engine", "rtol", "atol"],
            );
            let n_rms = extra.get("rms_harmonics").copied().unwrap_or(5.0);
            if n_rms.fract() != 0.0 || n_rms < 1.0 {
                return Err(Error::StudyFile(format!(
                    "rms_harmonics must be a positive integer, got {n_rms}"
                )));
            }
            let engine = yu_engine(&extra)?;
            let base = apply_overrides(&RunSettings::new(1.0), &rest)?;
            Ok((
                vec![
                    ("df", "1"),
                    ("rms", "1"),
                    ("mean_dte", "1"),
                    ("dte_peak_to_peak", "1"),
                    ("mean_backlash", "1"),
                ],
                Box::new(move |p: &BTreeMap<String, f64>| {
                    let (model, omega) = yu_model(p)?;
                    let settings = RunSettings { omega, ..base };
                    let r = model
                        .simulate_with(&settings, &engine, None)
                        .context("yu2021 time integration")?;
                    Ok(vec![
                        r.dynamic_factor(),
                        r.rms(n_rms as usize),
                        r.mean_dte(),
                        r.dte_peak_to_peak(),
                        r.mean_backlash(),
                    ])
                }),
            ))
        }
        Method::Hbm => {
            let settings = apply_overrides(&HbmSettings::default(), &solver.settings)?;
            Ok((
                vec![
                    ("mean_dte", "1"),
                    ("first_harmonic_amplitude", "1"),
                    ("converged", "1"),
                    ("residual_norm", "1"),
                ],
                Box::new(move |p: &BTreeMap<String, f64>| {
                    let (model, omega) = yu_model(p)?;
                    let s = model
                        .harmonic_balance(omega, &settings, None)
                        .context("yu2021 harmonic balance")?;
                    let c = &s.coefficients;
                    let a1 = if c.len() >= 3 {
                        c[1].hypot(c[2])
                    } else {
                        f64::NAN
                    };
                    Ok(vec![
                        c.first().copied().unwrap_or(f64::NAN),
                        a1,
                        if s.converged { 1.0 } else { 0.0 },
                        s.residual_norm,
                    ])
                }),
            ))
        }
        Method::Kinematics => Err(Error::StudyFile(
            "yu2021 needs solver.method = \"time-stepping\" or \"hbm\"".to_owned(),
        )),
    }
}

/// `engine` 0 (default): the model's fixed-step RK4; 1: the `timestep` crate (Dormand–Prince
/// 5(4) with the contact switches located as events), tolerances `rtol` (default 1e-8) and
/// `atol` (default 1e-10).
fn yu_engine(extra: &BTreeMap<String, f64>) -> Result<models::yu2021::Engine, Error> {
    use models::yu2021::Engine;
    let rtol = extra.get("rtol").copied().unwrap_or(1e-8);
    let atol = extra.get("atol").copied().unwrap_or(1e-10);
    for (name, v) in [("rtol", rtol), ("atol", atol)] {
        if !(v.is_finite() && v > 0.0) {
            return Err(Error::StudyFile(format!(
                "{name} must be finite and > 0, got {v}"
            )));
        }
    }
    match extra.get("engine").copied().unwrap_or(0.0) {
        e if e.abs() < f64::EPSILON => Ok(Engine::Rk4Fixed),
        e if (e - 1.0).abs() < f64::EPSILON => Ok(Engine::Timestep {
            method: timestep::Method::DormandPrince54,
            rtol,
            atol,
            events: true,
        }),
        e => Err(Error::StudyFile(format!(
            "engine must be 0 (fixed-step RK4) or 1 (timestep Dormand-Prince with events), got {e}"
        ))),
    }
}

fn yu_model(p: &BTreeMap<String, f64>) -> Result<(models::yu2021::Yu2021Model, f64), Error> {
    use models::yu2021::{Options, Yu2021Model, Yu2021Params};
    let mut fields = p.clone();
    let omega = fields.remove("omega").ok_or_else(|| {
        Error::StudyFile("yu2021 needs `omega` (ω*) in [overrides] or a sweep".to_owned())
    })?;
    let base = match fields.remove("table") {
        None => Yu2021Params::table1(),
        Some(t) if (t - 1.0).abs() < f64::EPSILON => Yu2021Params::table1(),
        Some(t) if (t - 2.0).abs() < f64::EPSILON => Yu2021Params::table2(),
        Some(t) => return Err(Error::StudyFile(format!("table must be 1 or 2, got {t}"))),
    };
    let options = match fields.remove("variant").map(|v| v.to_bits()) {
        None => Options::default(),
        Some(b) if b == 0f64.to_bits() => Options::default(),
        Some(b) if b == 1f64.to_bits() => Options::kahraman_singh(),
        Some(b) if b == 2f64.to_bits() => Options::chen(),
        Some(b) if b == 3f64.to_bits() => Options::yu_as_printed(),
        Some(b) => {
            return Err(Error::StudyFile(format!(
                "variant must be 0 (Yu), 1 (Kahraman–Singh), 2 (Chen) or 3 (Yu as printed), got {}",
                f64::from_bits(b)
            )));
        }
    };
    let params = apply_overrides(&base, &fields)?;
    let model = Yu2021Model::new(&params, options).context("yu2021 parameters")?;
    Ok((model, omega))
}

/// Karpov 2017 oscillator: overrides are fields of `models::karpov2017::Karpov2017Params`
/// (`omega`, `b`, `xi`, `k`, `tau_end`; default: the Fig. 3 point) plus `printed_phase`
/// (0: accumulated phase, default; 1: `sin(ωe·τ)` as printed). Method `time-stepping`;
/// settings: `duhamel` (1: the model's Duhamel-integral fast path, default; 0: the timestep
/// crate's Dormand–Prince 5(4)), `rtol` (for `duhamel = 0`, default 1e-9).
pub(super) fn karpov2017(solver: &Solver) -> Result<Adapter, Error> {
    use models::karpov2017::{Excitation, Karpov2017};
    if solver.method != Method::TimeStepping {
        return Err(Error::StudyFile(
            "karpov2017 needs solver.method = \"time-stepping\"".to_owned(),
        ));
    }
    let (extra, rest) = take(&solver.settings, &["duhamel", "rtol"]);
    if let Some(k) = rest.keys().next() {
        return Err(Error::StudyFile(format!(
            "unknown karpov2017 setting `{k}` (known: duhamel, rtol)"
        )));
    }
    let duhamel = extra.get("duhamel").copied().unwrap_or(1.0) != 0.0;
    let rtol = extra.get("rtol").copied().unwrap_or(1e-9);
    Ok((
        vec![("A", "1"), ("envelope", "1"), ("x_final", "1")],
        Box::new(move |p: &BTreeMap<String, f64>| {
            let mut fields = p.clone();
            let printed = fields.remove("printed_phase").unwrap_or(0.0) != 0.0;
            let mut params = apply_overrides(&Karpov2017::fig3().params(), &fields)?;
            params.excitation = if printed {
                Excitation::PrintedPhase
            } else {
                Excitation::AccumulatedPhase
            };
            let m = Karpov2017::new(params).context("karpov2017 parameters")?;
            if duhamel {
                let r = m.duhamel().context("karpov2017 Duhamel quadrature")?;
                Ok(vec![r.amplitude, r.envelope, r.x])
            } else {
                let opts = timestep::Options::default()
                    .with_tol(rtol, rtol)
                    .with_max_steps(500_000_000)
                    .with_output(timestep::Output::Final);
                let ode = m.time_stepping().context("karpov2017 system")?;
                let sol = timestep::integrate(&ode, 0.0, &[0.0, 0.0], params.tau_end, &opts)
                    .context("karpov2017 time integration")?;
                if !sol.status.is_success() {
                    return Err(Error::Study(format!(
                        "time integration ended with {:?}",
                        sol.status
                    )));
                }
                let (x, v) = (sol.y_final[0], sol.y_final[1]);
                Ok(vec![f64::NAN, x.hypot(v), x])
            }
        }),
    ))
}
