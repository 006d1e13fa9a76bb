//! The models of `geardyn study`: one [`ModelSpec`] registration each in [`REGISTRY`].
//!
//! A registration names the model, lists what `geardyn models` prints (parameters with units,
//! choices and readings with their options, solver settings with bounds, outputs), and builds
//! an [`Adapter`]: the output columns and a `prepare` function that checks one point (model
//! constructor, every derived size against [`Limits`](crate::Limits)) and returns the job that
//! computes it. Nothing else in the crate needs to change to add a model.

use std::collections::BTreeMap;

use models::{karpov2017, liu2021, pair, yu2021};
use serde::Serialize;

use crate::spec::{
    Limits, Method, Point, Solver, Value, apply_values, display_name, variant_names,
};
use crate::{Error, ResultExt};

/// The computation of one prepared point.
pub type Job = Box<dyn FnOnce() -> Result<Vec<f64>, Error> + Send>;

/// Checks one point and returns its computation.
pub type Preparer = Box<dyn Fn(&Point) -> Result<Job, Error> + Sync>;

/// Output columns and the point preparer of a model under one solver.
pub struct Adapter {
    /// Output columns `(name, unit)`.
    pub outputs: Vec<(String, String)>,
    /// Check one point and return its computation.
    pub prepare: Preparer,
}

/// What an adapter is built from.
#[derive(Debug, Clone, Copy)]
pub struct Context<'a> {
    /// The solver and its settings.
    pub solver: &'a Solver,
    /// The initial state, if given.
    pub initial: Option<&'a [f64]>,
    /// Work limits.
    pub limits: Limits,
}

/// One registered model.
#[derive(Debug, Clone, Copy)]
pub struct ModelSpec {
    /// Name in a study file.
    pub name: &'static str,
    /// One line.
    pub description: &'static str,
    /// Build the adapter for a solver (every setting checked).
    pub build: fn(&Context<'_>) -> Result<Adapter, Error>,
    /// What `geardyn models` prints.
    pub describe: fn() -> ModelInfo,
    /// Unit of a parameter (for CSV headers and axes; `""` if unknown).
    pub unit_of: fn(&str) -> &'static str,
}

/// A parameter (number) of a model.
#[derive(Debug, Clone, Serialize)]
pub struct ParamInfo {
    /// Name.
    pub name: String,
    /// Unit (`1`: dimensionless).
    pub unit: String,
    /// Default value.
    pub default: String,
}

/// A choice (model variant, reading) and its options.
#[derive(Debug, Clone, Serialize)]
pub struct ChoiceInfo {
    /// Name.
    pub name: String,
    /// Options (names).
    pub options: Vec<String>,
    /// Default option.
    pub default: String,
    /// What it selects.
    pub note: String,
}

/// The kind and bounds of a solver setting.
#[derive(Debug, Clone, Copy, Serialize)]
pub enum Kind {
    /// A number in `[lo, hi]`.
    Num {
        /// Lower bound.
        lo: f64,
        /// Upper bound.
        hi: f64,
        /// Default.
        default: f64,
    },
    /// An integer in `[lo, hi]`.
    Int {
        /// Lower bound.
        lo: u64,
        /// Upper bound.
        hi: u64,
        /// Default (`None`: absent unless given).
        default: Option<u64>,
    },
    /// A name.
    Name {
        /// Options.
        options: &'static [&'static str],
        /// Default.
        default: &'static str,
    },
}

/// A solver setting with its bounds.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct SettingDef {
    /// Name.
    pub name: &'static str,
    /// Kind, bounds and default.
    pub kind: Kind,
    /// What it does.
    pub doc: &'static str,
}

/// One solver method of a model.
#[derive(Debug, Clone, Serialize)]
pub struct MethodInfo {
    /// The method.
    pub method: Method,
    /// Its settings.
    pub settings: Vec<SettingDef>,
    /// Its outputs `(name, unit)`.
    pub outputs: Vec<(String, String)>,
    /// Meaning of `initial = [...]` for this method (`None`: not supported).
    pub initial: Option<&'static str>,
}

/// What `geardyn models` prints about a model.
#[derive(Debug, Clone, Serialize)]
pub struct ModelInfo {
    /// Numeric parameters.
    pub parameters: Vec<ParamInfo>,
    /// Choices and readings.
    pub choices: Vec<ChoiceInfo>,
    /// Methods with settings and outputs.
    pub methods: Vec<MethodInfo>,
}

/// Every model of `geardyn study`. Adding a model is one entry here.
pub const REGISTRY: [ModelSpec; 5] = [
    ModelSpec {
        name: "karpov2017-kinematics",
        description: "Karpov 2017 non-circular pair: speed fluctuation δ and peak acceleration ε_max",
        build: kinematics_build,
        describe: kinematics_describe,
        unit_of: kinematics_unit,
    },
    ModelSpec {
        name: "karpov2017",
        description: "Karpov 2017 oscillator with variable mesh frequency (Eq. 9)",
        build: karpov_build,
        describe: karpov_describe,
        unit_of: karpov_unit,
    },
    ModelSpec {
        name: "liu2021",
        description: "Liu 2021 non-circular face gear rattle model (Eq. 22)",
        build: liu_build,
        describe: liu_describe,
        unit_of: liu_unit,
    },
    ModelSpec {
        name: "yu2021",
        description: "Yu 2021 spur pair with dynamic backlash (6-DOF; Kahraman–Singh, Chen references)",
        build: yu_build,
        describe: yu_describe,
        unit_of: yu_unit,
    },
    ModelSpec {
        name: "generic-pair",
        description: "Generic spur pair from the leaves (tooth-pair stiffness, constant backlash; 1-DOF or 6-DOF)",
        build: pair_build,
        describe: pair_describe,
        unit_of: pair_unit,
    },
];

/// A model with a bifurcation study (`[bifurcation]`, see [`crate::bifurcation`]).
#[derive(Debug, Clone, Copy)]
pub struct BifurcationModel {
    /// The model's name in [`REGISTRY`].
    pub name: &'static str,
    /// The state coordinates a section can show: `(name, unit)`, in state order.
    pub coordinates: &'static [(&'static str, &'static str)],
    /// Build the adapter (outputs [`crate::bifurcation::outputs`], one job per parameter
    /// value) for the checked engine options (coordinate index set).
    pub build: fn(&Context<'_>, &timestep::BifurcationOptions) -> Result<Adapter, Error>,
}

/// The models that have a bifurcation study (a second, optional registration).
pub const BIFURCATION: [BifurcationModel; 1] = [BifurcationModel {
    name: "liu2021",
    coordinates: &[("q", "1"), ("q'", "1")],
    build: liu_bifurcation_build,
}];

// ---------------------------------------------------------------------------------------------
// Shared helpers.

fn outs(v: &[(&str, &str)]) -> Vec<(String, String)> {
    v.iter()
        .map(|(a, b)| ((*a).to_owned(), (*b).to_owned()))
        .collect()
}

/// Study setting `tolerance_check` (time stepping): `"on"` repeats every point at a 100×
/// tighter tolerance and adds the column [`CHANGE_COLUMN`].
const TOLERANCE_CHECK: SettingDef = SettingDef {
    name: "tolerance_check",
    kind: Kind::Name {
        options: &["off", "on"],
        default: "off",
    },
    doc: "on: repeat every point at a 100× tighter integrator tolerance and add the column \
          `change_100x_tighter`, the largest relative change of the point's outputs",
};

/// The column of [`TOLERANCE_CHECK`].
const CHANGE_COLUMN: (&str, &str) = ("change_100x_tighter", "1");

/// Largest relative change `|a_i − b_i| / max(|a_i|, |b_i|)` over the outputs (0 where both are
/// equal, including both zero).
fn relative_change(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| {
            let d = (x - y).abs();
            if d == 0.0 {
                0.0
            } else {
                d / x.abs().max(y.abs())
            }
        })
        .fold(0.0, f64::max)
}

/// The step statistics of every time-stepping point, the last columns of its row (always on):
/// accepted and rejected steps, right-hand-side evaluations and located events of the whole
/// run (transient included) at the study's tolerance ([`timestep::Stats`]).
pub const STEP_STATISTICS: [(&str, &str); 4] = [
    ("steps_accepted", "1"),
    ("steps_rejected", "1"),
    ("rhs_calls", "1"),
    ("events", "1"),
];

/// True for a column that describes the computation rather than the model (the
/// [`STEP_STATISTICS`]): in the CSV and the JSON ranges, without a figure or heat map.
pub fn is_step_statistic(column: &str) -> bool {
    STEP_STATISTICS.iter().any(|(n, _)| *n == column)
}

/// The values of the [`STEP_STATISTICS`] columns (exact: counts below 2⁵³).
pub fn step_statistics(s: &timestep::Stats) -> [f64; 4] {
    [s.n_accepted, s.n_rejected, s.n_rhs, s.n_events].map(|n| n as f64)
}

/// The [`STEP_STATISTICS`] as table cells (written in full), for the validation studies.
pub(crate) fn step_cells(s: &timestep::Stats) -> [crate::Cell; 4] {
    [s.n_accepted, s.n_rejected, s.n_rhs, s.n_events].map(crate::Cell::Count)
}

/// The outputs of a time-stepping method: the model's, the [`CHANGE_COLUMN`] when the check is
/// on, then the [`STEP_STATISTICS`].
fn outs_stepped(v: &[(&str, &str)], check: bool) -> Vec<(String, String)> {
    let mut o = outs(v);
    if check {
        o.push((CHANGE_COLUMN.0.to_owned(), CHANGE_COLUMN.1.to_owned()));
    }
    o.extend(outs(&STEP_STATISTICS));
    o
}

/// Run `job(1)` and, when `check`, `job(100)` (tolerance divided by 100), appending the
/// relative change of the outputs, then the step statistics of the run at the study's
/// tolerance (the columns of [`outs_stepped`]). `job` returns the outputs and the statistics.
fn run_stepped_job(
    check: bool,
    job: impl Fn(f64) -> Result<(Vec<f64>, timestep::Stats), Error>,
) -> Result<Vec<f64>, Error> {
    let (mut v, stats) = job(1.0)?;
    if check {
        let (tight, _) = job(100.0)?;
        let c = relative_change(&v, &tight);
        v.push(c);
    }
    v.extend(step_statistics(&stats));
    Ok(v)
}

fn params_of<T: Serialize>(base: &T, unit: fn(&str) -> &'static str) -> Vec<ParamInfo> {
    let mut out = Vec::new();
    if let Ok(serde_json::Value::Object(o)) = serde_json::to_value(base) {
        for (k, v) in o {
            match v {
                serde_json::Value::Number(n) => out.push(ParamInfo {
                    unit: unit(&k).to_owned(),
                    name: k,
                    default: n.to_string(),
                }),
                serde_json::Value::Array(a) if a.iter().all(|x| x.is_number()) => {
                    out.push(ParamInfo {
                        unit: unit(&k).to_owned(),
                        name: k,
                        default: serde_json::Value::Array(a).to_string(),
                    })
                }
                _ => {}
            }
        }
    }
    out
}

fn choice_info<E: serde::de::DeserializeOwned + Serialize>(
    name: &str,
    default: E,
    note: &str,
) -> ChoiceInfo {
    let d = serde_json::to_value(default)
        .ok()
        .and_then(|v| v.as_str().map(display_name))
        .unwrap_or_default();
    ChoiceInfo {
        name: name.to_owned(),
        options: variant_names::<E>(),
        default: d,
        note: note.to_owned(),
    }
}

/// The two methods of the spur-pair models: time stepping (with an initial state) and HBM.
fn time_stepping_and_hbm(
    ts: (&[SettingDef], &[(&str, &str)]),
    initial: &'static str,
    hbm: (&[SettingDef], &[(&str, &str)]),
) -> Vec<MethodInfo> {
    vec![
        MethodInfo {
            method: Method::TimeStepping,
            settings: ts.0.to_vec(),
            outputs: outs_stepped(ts.1, false),
            initial: Some(initial),
        },
        MethodInfo {
            method: Method::Hbm,
            settings: hbm.0.to_vec(),
            outputs: outs(hbm.1),
            initial: None,
        },
    ]
}

fn wrong_method(model: &str, m: Method, allowed: &[Method]) -> Error {
    Error::StudyFile(format!(
        "{model} has no solver.method = \"{}\"; use {}",
        m.name(),
        allowed
            .iter()
            .map(|a| format!("\"{}\"", a.name()))
            .collect::<Vec<_>>()
            .join(" or ")
    ))
}

/// Settings read against their definitions.
struct Settings(BTreeMap<&'static str, Value>);

impl Settings {
    /// Check every given setting against `defs` (unknown names, kind, bounds) and fill the
    /// defaults.
    fn read(
        model: &str,
        method: Method,
        defs: &[SettingDef],
        given: &BTreeMap<String, Value>,
        legacy: &[(&str, &str)],
    ) -> Result<Self, Error> {
        let mut out = BTreeMap::new();
        for (k, v) in given {
            if let Some((_, new)) = legacy.iter().find(|(old, _)| *old == k) {
                return Err(Error::StudyFile(format!(
                    "setting `{k}` = {} is the old spelling; write {new}",
                    v.label()
                )));
            }
            let Some(d) = defs.iter().find(|d| d.name == k) else {
                return Err(Error::StudyFile(format!(
                    "unknown {model} {} setting `{k}`; settings: {}",
                    method.name(),
                    defs.iter().map(|d| d.name).collect::<Vec<_>>().join(", ")
                )));
            };
            let bad = |want: String| {
                Error::StudyFile(format!("setting `{k}` must be {want}, got {}", v.label()))
            };
            match (d.kind, v) {
                (Kind::Num { lo, hi, .. }, Value::Num(x)) => {
                    if !(*x >= lo && *x <= hi) {
                        return Err(bad(format!("in [{lo:e}, {hi:e}]")));
                    }
                }
                (Kind::Int { lo, hi, .. }, Value::Num(x)) => {
                    if x.fract() != 0.0 || !(*x >= lo as f64 && *x <= hi as f64) {
                        return Err(bad(format!("an integer in [{lo}, {hi}]")));
                    }
                }
                (Kind::Name { options, .. }, Value::Text(s)) => {
                    if !options.contains(&s.as_str()) {
                        return Err(bad(format!("one of \"{}\"", options.join("\", \""))));
                    }
                }
                (Kind::Name { options, .. }, _) => {
                    return Err(bad(format!(
                        "a name: one of \"{}\" (e.g. {k} = \"{}\")",
                        options.join("\", \""),
                        options[0]
                    )));
                }
                (_, _) => return Err(bad("a number".to_owned())),
            }
            out.insert(d.name, v.clone());
        }
        for d in defs {
            if !out.contains_key(d.name) {
                match d.kind {
                    Kind::Num { default, .. } => {
                        out.insert(d.name, Value::Num(default));
                    }
                    Kind::Int {
                        default: Some(x), ..
                    } => {
                        out.insert(d.name, Value::Num(x as f64));
                    }
                    Kind::Int { default: None, .. } => {}
                    Kind::Name { default, .. } => {
                        out.insert(d.name, Value::Text(default.to_owned()));
                    }
                }
            }
        }
        Ok(Settings(out))
    }

    fn f(&self, k: &str) -> f64 {
        self.0.get(k).and_then(Value::as_num).unwrap_or(f64::NAN)
    }

    fn u(&self, k: &str) -> Option<u64> {
        self.0.get(k).and_then(Value::as_num).map(|x| x as u64)
    }

    fn name(&self, k: &str) -> &str {
        match self.0.get(k) {
            Some(Value::Text(s)) => s,
            _ => "",
        }
    }
}

/// Check solver settings of `model` under `method` against the definitions `geardyn models`
/// prints — the code, bounds and messages of a study file's `[solver.settings]` — for front
/// ends that take settings by other routes (the Python package).
pub fn check_settings(
    model: &str,
    method: Method,
    given: &BTreeMap<String, Value>,
) -> Result<(), Error> {
    let spec = REGISTRY
        .iter()
        .find(|m| m.name == model)
        .ok_or_else(|| Error::StudyFile(format!("unknown model `{model}`")))?;
    let info = (spec.describe)();
    let m = info
        .methods
        .iter()
        .find(|m| m.method == method)
        .ok_or_else(|| wrong_method(model, method, &[]))?;
    Settings::read(model, method, &m.settings, given, &[]).map(|_| ())
}

/// One Liu point by shooting for front ends without a study file (the Python package): the
/// settings are checked by the study's definitions and the result is the study's columns
/// `(name, value)` of `method = "shooting"`, computed by the same code.
///
/// # Errors
/// A bad setting (named with its bound), an invalid model, or a shooting failure.
pub fn liu_shooting_point(
    model: liu2021::Model,
    given: &BTreeMap<String, Value>,
    initial: Option<(f64, f64)>,
) -> Result<Vec<(&'static str, f64)>, Error> {
    let s = Settings::read("liu2021", Method::Shooting, LIU_SHOOT, given, &[])?;
    let v = liu_shoot(model, &s, initial)?;
    Ok(LIU_SHOOT_OUT.iter().map(|(n, _)| *n).zip(v).collect())
}

/// One point of Yu's 6-DOF model by shooting for front ends without a study file (the Python
/// package): the settings checked by the study's definitions, the study's columns
/// `(name, value)` of `method = "shooting"`, computed by the same code.
///
/// # Errors
/// A bad setting (named with its bound), a model without a 6-DOF orbit, or a shooting failure.
pub fn yu_shooting_point(
    model: yu2021::Yu2021Model,
    omega: f64,
    given: &BTreeMap<String, Value>,
) -> Result<Vec<(&'static str, f64)>, Error> {
    let defs = shoot_settings(shoot_transient(200.0, YU_SHOOT_TRANSIENT));
    let s = Settings::read("yu2021", Method::Shooting, &defs, given, &[])?;
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
    let v = shoot_any(
        "yu2021",
        sys,
        std::f64::consts::TAU / omega,
        &r.final_state,
        &s,
    )?;
    Ok(SHOOT_OUT.iter().map(|(n, _)| *n).zip(v).collect())
}

/// Remove the choices (names) from a point, checking old numeric spellings.
fn take_choice(p: &mut Point, name: &str, legacy: Option<&str>) -> Result<Option<Value>, Error> {
    match p.remove(name) {
        Some(Value::Num(x)) => Err(Error::StudyFile(format!(
            "`{name}` = {x}: choices are names now; write {}",
            legacy.unwrap_or("a name (see `geardyn models`)")
        ))),
        v => Ok(v),
    }
}

fn reject_legacy(p: &Point, legacy: &[(&str, &str)]) -> Result<(), Error> {
    for (old, new) in legacy {
        if let Some(v) = p.get(*old) {
            return Err(Error::StudyFile(format!(
                "`{old}` = {} is the old spelling; write {new}",
                v.label()
            )));
        }
    }
    Ok(())
}

fn need_steps(what: &str, steps: f64, limits: &Limits) -> Result<(), Error> {
    if steps.is_finite() && steps <= limits.max_steps {
        Ok(())
    } else {
        Err(Error::Study(format!(
            "{what}: about {steps:.3e} steps needed, over limits.max_steps = {:e}",
            limits.max_steps
        )))
    }
}

fn no_initial(model: &str, ctx: &Context<'_>) -> Result<(), Error> {
    if ctx.initial.is_some() {
        return Err(Error::StudyFile(format!(
            "{model} with solver.method = \"{}\" takes no `initial` state",
            ctx.solver.method.name()
        )));
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// karpov2017-kinematics

fn kinematics_unit(k: &str) -> &'static str {
    match k {
        "r" => "m",
        "omega1" => "rad/s",
        _ => "1",
    }
}

fn kinematics_describe() -> ModelInfo {
    let base = gear_geometry::KarpovPair::karpov2017_table1().params();
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

const KINEMATICS_OUT: &[(&str, &str)] = &[
    ("delta_exact", "1"),
    ("delta_eq4", "1"),
    ("emax_exact", "rad/s^2"),
    ("emax_eq6", "rad/s^2"),
    ("b_max_exact", "1"),
];

fn kinematics_build(ctx: &Context<'_>) -> Result<Adapter, Error> {
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
                Some(v) => Err(Error::StudyFile(format!(
                    "`{k}` takes a number, got {}",
                    v.label()
                ))),
            };
            let omega1 = num(&mut fields, "omega1", 1.0)?;
            let delta_max = num(&mut fields, "delta_max", 0.001)?;
            let base = gear_geometry::KarpovPair::karpov2017_table1().params();
            let params = apply_values(&base, &fields)?;
            if !(omega1.is_finite() && omega1 > 0.0) {
                return Err(Error::Study(format!(
                    "omega1 must be finite and > 0, got {omega1}"
                )));
            }
            if !(delta_max > 0.0 && delta_max < 1.0) {
                return Err(Error::Study(format!(
                    "delta_max must be in (0, 1), got {delta_max}"
                )));
            }
            let pair = gear_geometry::KarpovPair::new(params).context("Karpov pair")?;
            Ok(Box::new(move || {
                let check = pair.design_check(delta_max).context("design check")?;
                Ok(vec![
                    pair.speed_fluctuation(),
                    pair.speed_fluctuation_eq4(),
                    pair.max_acceleration(omega1),
                    pair.max_acceleration_eq6(omega1),
                    check.b_max_exact,
                ])
            }) as Job)
        }),
    })
}

// ---------------------------------------------------------------------------------------------
// karpov2017

fn karpov_unit(_: &str) -> &'static str {
    "1"
}

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

/// The Duhamel engine's accuracy column: [`karpov2017::KarpovResponse::error_estimate`].
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

fn karpov_describe() -> ModelInfo {
    let p = karpov2017::Karpov2017::fig3().params();
    ModelInfo {
        parameters: params_of(&p, karpov_unit),
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

fn karpov_build(ctx: &Context<'_>) -> Result<Adapter, Error> {
    use karpov2017::Karpov2017;
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
        return Err(Error::StudyFile(
            "karpov2017: tolerance_check = \"on\" needs engine = \"timestep\" (the Duhamel \
             quadrature states its own error estimate)"
                .to_owned(),
        ));
    }
    let initial = match ctx.initial {
        None => [0.0, 0.0],
        Some(_) if duhamel => {
            return Err(Error::StudyFile(
                "karpov2017: `initial` needs engine = \"timestep\" (the Duhamel path starts \
                 from rest)"
                    .to_owned(),
            ));
        }
        Some([x, v]) => [*x, *v],
        Some(v) => {
            return Err(Error::StudyFile(format!(
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
            need_steps("karpov2017", est, &limits)?;
            let max_steps = limits.max_steps as u64;
            Ok(Box::new(move || {
                if duhamel {
                    let r = m.duhamel().context("karpov2017 Duhamel quadrature")?;
                    Ok(vec![r.amplitude, r.envelope, r.x, r.error_estimate])
                } else {
                    let ode = m.time_stepping().context("karpov2017 system")?;
                    run_stepped_job(check, |factor| {
                        let opts = timestep::Options::default()
                            .with_tol(rtol / factor, rtol / factor)
                            .with_max_steps(max_steps)
                            .with_output(timestep::Output::Final);
                        let sol = timestep::integrate(&ode, 0.0, &initial, params.tau_end, &opts)
                            .context("karpov2017 time integration")?;
                        if !sol.status.is_success() {
                            return Err(Error::Study(format!(
                                "time integration ended with {:?}",
                                sol.status
                            )));
                        }
                        let (x, v) = (sol.y_final[0], sol.y_final[1]);
                        Ok((vec![x.hypot(v), x], sol.stats))
                    })
                }
            }) as Job)
        }),
    })
}

// ---------------------------------------------------------------------------------------------
// liu2021

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

const LIU_TS: &[SettingDef] = &[
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

/// The long-window outputs of the Liu time stepping (`long_window_periods` ≥ 1):
/// [`models::response::Robust::COLUMNS`] (the lines are f_c and f_e).
const LIU_WINDOW_OUT: &[(&str, &str)] = &models::response::Robust::COLUMNS;

const LIU_HBM: &[SettingDef] = &[
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

const LIU_SHOOT: &[SettingDef] = &[
    SettingDef {
        name: "transient_periods",
        kind: Kind::Num {
            lo: 0.0,
            hi: 1e4,
            default: 200.0,
        },
        doc: "periods of time integration from `initial` (or the quasi-static contact at rest) \
              whose end state is the shooting guess",
    },
    SettingDef {
        name: "rtol",
        kind: Kind::Num {
            lo: 1e-14,
            hi: 1e-4,
            default: 1e-10,
        },
        doc: "relative tolerance of the event-located flow and its variational equations",
    },
    SettingDef {
        name: "tol",
        kind: Kind::Num {
            lo: 1e-14,
            hi: 1e-3,
            default: 1e-8,
        },
        doc: "Newton tolerance on the periodicity residual",
    },
    SettingDef {
        name: "max_iter",
        kind: Kind::Int {
            lo: 1,
            hi: 1000,
            default: Some(20),
        },
        doc: "Newton iterations",
    },
    SettingDef {
        name: "segments",
        kind: Kind::Int {
            lo: 1,
            hi: 64,
            default: Some(1),
        },
        doc: "shooting segments per period (1: single shooting)",
    },
];

/// The shooting settings of the Yu and generic-pair models: the guess from
/// `transient_periods` of the model's own time integration, then the solver settings of
/// [`LIU_SHOOT`] (one definition: the tail of that table).
fn shoot_settings(transient: SettingDef) -> Vec<SettingDef> {
    std::iter::once(transient)
        .chain(LIU_SHOOT.iter().skip(1).cloned())
        .collect()
}

/// The shooting outputs of any model (Yu, generic pair): events per period, the multipliers
/// (largest two by modulus), stability and the period-doubling test function, the Newton work.
const SHOOT_OUT: &[(&str, &str)] = &[
    ("events_per_period", "1"),
    ("max_multiplier", "1"),
    ("mu1_re", "1"),
    ("mu1_im", "1"),
    ("mu2_re", "1"),
    ("mu2_im", "1"),
    ("stable", "1"),
    ("det_phi_plus_i", "1"),
    ("newton_iterations", "1"),
    ("residual", "1"),
];

/// Shoot the periodic orbit of `sys` (period `period`) from `guess` with the settings of
/// [`shoot_settings`]: the problem, the orbit and the values of [`SHOOT_OUT`] (every model's
/// shooting columns; Liu adds its own around them).
fn shoot_on<S: system::SecondOrderSystem>(
    what: &'static str,
    sys: S,
    period: f64,
    guess: &[f64],
    s: &Settings,
) -> Result<(orbit::OrbitProblem<S>, orbit::PeriodicOrbit, Vec<f64>), Error> {
    let flow = orbit::FlowOptions {
        rtol: s.f("rtol"),
        ..orbit::FlowOptions::default()
    };
    let p = orbit::OrbitProblem::new(sys, period)
        .and_then(|p| p.with_flow_options(flow))
        .map_err(|e| Error::Study(format!("{what} orbit problem: {e}")))?;
    let opts = orbit::ShootingOptions {
        tol: s.f("tol"),
        max_iter: s.u("max_iter").unwrap_or(20) as usize,
        segments: s.u("segments").unwrap_or(1) as usize,
        ..orbit::ShootingOptions::default()
    };
    let o = p
        .shoot(guess, &opts)
        .map_err(|e| Error::Study(format!("{what} shooting: {e}")))?;
    let mut mu = o.floquet.multipliers.clone();
    mu.sort_by(|x, y| y[0].hypot(y[1]).total_cmp(&x[0].hypot(x[1])));
    let m = |i: usize, j: usize| mu.get(i).map_or(f64::NAN, |c| c[j]);
    let v = vec![
        o.events.len() as f64,
        o.floquet.max_modulus,
        m(0, 0),
        m(0, 1),
        m(1, 0),
        m(1, 1),
        if o.floquet.stable { 1.0 } else { 0.0 },
        o.floquet.test_period_doubling,
        o.iterations as f64,
        o.residual,
    ];
    Ok((p, o, v))
}

/// [`shoot_on`], the values only.
fn shoot_any<S: system::SecondOrderSystem>(
    what: &'static str,
    sys: S,
    period: f64,
    guess: &[f64],
    s: &Settings,
) -> Result<Vec<f64>, Error> {
    shoot_on(what, sys, period, guess, s).map(|(_, _, v)| v)
}

/// The transient setting of the Yu and pair shooting guesses.
fn shoot_transient(default: f64, doc: &'static str) -> SettingDef {
    SettingDef {
        name: "transient_periods",
        kind: Kind::Int {
            lo: 0,
            hi: 100_000,
            default: Some(default as u64),
        },
        doc,
    }
}

const YU_SHOOT_TRANSIENT: &str = "mesh periods of the model's fixed-step RK4 (256 steps per \
     period) from `initial` (or the static contact) whose end state is the shooting guess; \
     Yu's 6-DOF model with free centres only";
const PAIR_SHOOT_TRANSIENT: &str = "mesh periods of the model's time integration from \
     `initial` (or its static contact) whose end state is the shooting guess";

fn liu_describe() -> ModelInfo {
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
                settings: LIU_SHOOT.to_vec(),
                outputs: outs(LIU_SHOOT_OUT),
                initial: Some(
                    "[q, q'] at τ = 0 where the guess's integration starts (default: the quasi-static contact at rest)",
                ),
            },
        ],
    }
}

/// One Liu point by shooting: the guess from `transient_periods` of time integration, then
/// Newton on the event-located period map; the values of [`LIU_SHOOT_OUT`].
fn liu_shoot(
    model: liu2021::Model,
    s: &Settings,
    initial: Option<(f64, f64)>,
) -> Result<Vec<f64>, Error> {
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
            return Err(Error::Study(
                "liu2021 shooting guess: empty response".into(),
            ));
        };
        [*q, *v]
    } else {
        [start.0, start.1]
    };
    let (p, o, v) = shoot_on("liu2021", model, model.period(), &x0, s)?;
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
    // LIU_SHOOT_OUT: the shared SHOOT_OUT columns with the section state and the gap margins
    let mut out = vec![rsv, o.x0[0], o.x0[1]];
    out.extend_from_slice(&v[..8]);
    out.extend_from_slice(&[drive, back]);
    out.extend_from_slice(&v[8..]);
    Ok(out)
}

fn liu_model(p: &Point) -> Result<liu2021::Model, Error> {
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
            return Err(Error::StudyFile(format!(
                "`readings` = {} is not an option; options: \"consistent\", \"printed\"",
                v.label()
            )));
        }
    }
    let params = apply_values(&base, &fields)?;
    params.model().context("liu2021 parameters")
}

fn liu_initial(ctx: &Context<'_>) -> Result<Option<(f64, f64)>, Error> {
    match ctx.initial {
        None => Ok(None),
        Some([q, v]) => Ok(Some((*q, *v))),
        Some(v) => Err(Error::StudyFile(format!(
            "liu2021: `initial` must be [q, q'], got {} numbers",
            v.len()
        ))),
    }
}

/// A bifurcation study of the Liu model: time stepping with the integrator settings `max_step`
/// and `rtol` (the transient and section sizes come from `[bifurcation]`).
fn liu_bifurcation_build(
    ctx: &Context<'_>,
    bo: &timestep::BifurcationOptions,
) -> Result<Adapter, Error> {
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
    let coordinate = BIFURCATION[0].coordinates[bo.coordinate];
    let (bo, limits) = (*bo, ctx.limits);
    Ok(Adapter {
        outputs: crate::bifurcation::outputs(coordinate, "1", bo.classify.n_points),
        prepare: Box::new(move |p: &Point| {
            let model = liu_model(p)?;
            // periods integrated: transient and section, twice the Lyapunov intervals
            let c = bo.classify;
            let periods = (c.transient_periods + c.n_points + 2 * c.lyapunov_intervals) as f64;
            need_steps(
                "liu2021 bifurcation",
                periods * model.period() / opts.max_step,
                &limits,
            )?;
            Ok(Box::new(move || {
                let pt = liu2021::bifurcation_point(&model, &opts, &bo)
                    .context("liu2021 bifurcation point")?;
                Ok(crate::bifurcation::row(&pt))
            }) as Job)
        }),
    })
}

fn liu_build(ctx: &Context<'_>) -> Result<Adapter, Error> {
    let limits = ctx.limits;
    match ctx.solver.method {
        Method::TimeStepping => {
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
                return Err(Error::StudyFile(format!(
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
                names.extend(LIU_WINDOW_OUT);
            }
            Ok(Adapter {
                outputs: outs_stepped(&names, check),
                prepare: Box::new(move |p: &Point| {
                    let model = liu_model(p)?;
                    if let Some(w) = &window {
                        // three runs of (transient + window), the nominal one with two windows
                        let steps = (3.0 * w.transient_periods + 4.0 * w.periods as f64)
                            * model.period()
                            / w.max_step;
                        need_steps("liu2021 long window", steps, &limits)?;
                    }
                    let period = model.period();
                    let samples = opts.record_periods * period / opts.sample_step;
                    if !(LIU_MIN_SAMPLES..=LIU_MAX_SAMPLES).contains(&samples) {
                        return Err(Error::StudyFile(format!(
                            "liu2021: the recorded window holds {samples:.3e} samples \
                             (record_periods·T/sample_step, T = {period:.4}); it must hold \
                             {LIU_MIN_SAMPLES} … {LIU_MAX_SAMPLES:e}: change sample_step or \
                             record_periods"
                        )));
                    }
                    let steps =
                        (opts.transient_periods + opts.record_periods) * period / opts.max_step;
                    need_steps("liu2021", steps, &limits)?;
                    Ok(Box::new(move || {
                        run_stepped_job(check, |factor| {
                            let o = liu2021::IntegrationOptions {
                                rtol: opts.rtol / factor,
                                ..opts
                            };
                            let r = liu2021::integrate(&model, &o)
                                .context("liu2021 time integration")?;
                            let mut v = vec![
                                f64::from(r.rattle.state.rsv()),
                                r.rattle.ppv,
                                r.rattle.q_min,
                                r.rattle.q_max,
                            ];
                            if let Some(w) = &window {
                                let wo = liu2021::LongWindowOptions {
                                    rtol: w.rtol / factor,
                                    ..*w
                                };
                                let lw = liu2021::long_window(&model, &wo)
                                    .context("liu2021 long window")?;
                                v.extend(lw.values());
                            }
                            Ok((v, r.stats))
                        })
                    }) as Job)
                }),
            })
        }
        Method::Hbm => {
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
                        let r = liu2021::solve_hbm(&model, &opts, None)
                            .context("liu2021 harmonic balance")?;
                        Ok(vec![
                            f64::from(r.rattle.state.rsv()),
                            r.rattle.ppv,
                            r.rattle.q_min,
                            r.rattle.q_max,
                            if r.converged() { 1.0 } else { 0.0 },
                            r.solution.residual_norm,
                            r.solution.truncation,
                        ])
                    }) as Job)
                }),
            })
        }
        Method::Shooting => {
            let s = Settings::read(
                "liu2021",
                Method::Shooting,
                LIU_SHOOT,
                &ctx.solver.settings,
                &[],
            )?;
            let initial = liu_initial(ctx)?;
            let s = std::sync::Arc::new(s);
            Ok(Adapter {
                outputs: outs(LIU_SHOOT_OUT),
                prepare: Box::new(move |p: &Point| {
                    let model = liu_model(p)?;
                    // the guess's integration plus a few Newton iterations of one period each
                    let steps =
                        (s.f("transient_periods") + 2.0 * s.f("max_iter")) * model.period() / 0.5;
                    need_steps("liu2021 shooting", steps, &limits)?;
                    let s = std::sync::Arc::clone(&s);
                    Ok(Box::new(move || liu_shoot(model, &s, initial)) as Job)
                }),
            })
        }
        m => Err(wrong_method(
            "liu2021",
            m,
            &[Method::TimeStepping, Method::Hbm, Method::Shooting],
        )),
    }
}

// ---------------------------------------------------------------------------------------------
// yu2021

fn yu_unit(k: &str) -> &'static str {
    match k {
        "inertia_p" | "inertia_g" => "kg·m²",
        "mass_p" | "mass_g" => "kg",
        "radius_p" | "radius_g" | "ste_amplitude" | "nominal_length" | "chen_amplitude" => "m",
        "pressure_angle" | "phase" => "rad",
        "torque" => "N·m",
        "mesh_stiffness" | "bearing_stiffness" => "N/m",
        _ => "1",
    }
}

/// Mesh periods discarded (time stepping of the spur-pair models).
const TRANSIENT_PERIODS: SettingDef = SettingDef {
    name: "transient_periods",
    kind: Kind::Int {
        lo: 0,
        hi: 100_000,
        default: Some(200),
    },
    doc: "mesh periods discarded",
};

/// Mesh periods recorded (time stepping of the spur-pair models).
const RECORD_PERIODS: SettingDef = SettingDef {
    name: "record_periods",
    kind: Kind::Int {
        lo: 1,
        hi: 10_000,
        default: Some(20),
    },
    doc: "mesh periods recorded",
};

/// AFT samples per period (harmonic balance of the spur-pair models; default: the model's).
const AFT_SAMPLES: SettingDef = SettingDef {
    name: "samples",
    kind: Kind::Int {
        lo: 6,
        hi: 65_536,
        default: None,
    },
    doc: "AFT samples per period (≥ 4H + 2)",
};

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

fn yu_describe() -> ModelInfo {
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
                settings: shoot_settings(shoot_transient(200.0, YU_SHOOT_TRANSIENT)),
                outputs: outs(SHOOT_OUT),
                initial: Some("the state vector where the guess's integration starts"),
            });
            m
        },
    }
}

/// Split a Yu point into ω*, the model options and the parameters.
fn yu_model(p: &Point) -> Result<(yu2021::Yu2021Model, f64), Error> {
    use yu2021::{Options, Yu2021Model, Yu2021Params};
    let mut fields = p.clone();
    let omega = match fields.remove("omega") {
        Some(Value::Num(w)) => w,
        Some(v) => {
            return Err(Error::StudyFile(format!(
                "`omega` takes a number, got {}",
                v.label()
            )));
        }
        None => {
            return Err(Error::StudyFile(
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
            return Err(Error::StudyFile(format!(
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
                return Err(Error::StudyFile(format!(
                    "`variant` = \"{other}\" is not an option; write {legacy}"
                )));
            }
        },
        Some(v) => {
            return Err(Error::StudyFile(format!(
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
fn yu_initial(ctx: &Context<'_>) -> Result<Option<[f64; yu2021::STATE_LEN]>, Error> {
    ctx.initial
        .map(|v| {
            <[f64; yu2021::STATE_LEN]>::try_from(v).map_err(|_| {
                Error::StudyFile(format!(
                    "yu2021: `initial` must have {} numbers (the model state), got {}",
                    yu2021::STATE_LEN,
                    v.len()
                ))
            })
        })
        .transpose()
}

fn yu_build(ctx: &Context<'_>) -> Result<Adapter, Error> {
    use yu2021::{Engine, HbmSettings, RunSettings};
    let limits = ctx.limits;
    match ctx.solver.method {
        Method::TimeStepping => {
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
                return Err(Error::StudyFile(
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
            Ok(Adapter {
                outputs: outs_stepped(YU_TS_OUT, check),
                prepare: Box::new(move |p: &Point| {
                    let (model, omega) = yu_model(p)?;
                    let settings = RunSettings { omega, ..base };
                    let steps = model.run_steps(&settings).context("yu2021 run size")?;
                    need_steps("yu2021", steps as f64, &limits)?;
                    Ok(Box::new(move || {
                        run_stepped_job(check, |factor| {
                            let r = model
                                .simulate_with(&settings, &engine_at(factor), initial)
                                .context("yu2021 time integration")?;
                            let v = vec![
                                r.dynamic_factor(),
                                r.rms(n_rms),
                                r.mean_dte(),
                                r.dte_peak_to_peak(),
                                r.mean_backlash(),
                            ];
                            Ok((v, r.stats))
                        })
                    }) as Job)
                }),
            })
        }
        Method::Hbm => {
            no_initial("yu2021", ctx)?;
            let s = Settings::read("yu2021", Method::Hbm, YU_HBM, &ctx.solver.settings, &[])?;
            let mut settings = HbmSettings::default();
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
                return Err(Error::StudyFile(format!(
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
                        return Err(Error::Study(format!(
                            "yu2021.omega must be finite and > 0, got {omega}"
                        )));
                    }
                    Ok(Box::new(move || {
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
                            s.truncation,
                        ])
                    }) as Job)
                }),
            })
        }
        Method::Shooting => {
            let defs = shoot_settings(shoot_transient(200.0, YU_SHOOT_TRANSIENT));
            let s = Settings::read("yu2021", Method::Shooting, &defs, &ctx.solver.settings, &[])?;
            let initial = yu_initial(ctx)?;
            let transient = s.u("transient_periods").unwrap_or(200) as usize;
            let s = std::sync::Arc::new(s);
            Ok(Adapter {
                outputs: outs(SHOOT_OUT),
                prepare: Box::new(move |p: &Point| {
                    let (model, omega) = yu_model(p)?;
                    let settings = RunSettings {
                        omega,
                        transient_periods: transient,
                        record_periods: 1,
                        steps_per_period: 256,
                    };
                    let steps = model.run_steps(&settings).context("yu2021 run size")?;
                    need_steps("yu2021 shooting", steps as f64, &limits)?;
                    let s = std::sync::Arc::clone(&s);
                    Ok(Box::new(move || {
                        let sys =
                            yu2021::Yu2021SixDof::new(&model, omega).context("yu2021 shooting")?;
                        let r = model
                            .simulate_with(&settings, &Engine::Rk4Fixed, initial)
                            .context("yu2021 shooting guess")?;
                        let period = std::f64::consts::TAU / omega;
                        shoot_any("yu2021", sys, period, &r.final_state, &s)
                    }) as Job)
                }),
            })
        }
        m => Err(wrong_method(
            "yu2021",
            m,
            &[Method::TimeStepping, Method::Hbm, Method::Shooting],
        )),
    }
}

// ---------------------------------------------------------------------------------------------
// generic-pair (models::pair, preset PairParams::example_spur, SI units)

fn pair_unit(k: &str) -> &'static str {
    match k {
        "equivalent_mass" | "masses" => "kg",
        "rp" | "rg" | "ste_amplitude" | "b" => "m",
        "pressure_angle" | "ste_phase" => "rad",
        "bearing_stiffness" => "N/m",
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

fn pair_describe() -> ModelInfo {
    ModelInfo {
        parameters: {
            // the top-level numbers, the geometry and the constant half gap `b`
            let p = pair::PairParams::example_spur();
            let mut v = params_of(&p, pair_unit);
            v.extend(params_of(&p.geometry, pair_unit));
            v.push(ParamInfo {
                name: "b".into(),
                unit: "m".into(),
                default: "5e-5 (half gap of the constant backlash law)".into(),
            });
            v
        },
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
                settings: shoot_settings(shoot_transient(200.0, PAIR_SHOOT_TRANSIENT)),
                outputs: outs(SHOOT_OUT),
                initial: Some("[q, q'] where the guess's integration starts"),
            });
            m
        },
    }
}

/// A point of the generic pair: `dofs` (a choice) and the numbers of `PairParams`.
fn pair_model(p: &Point) -> Result<(pair::GearPair, f64), Error> {
    let mut fields = p.clone();
    let dofs = match take_choice(&mut fields, "dofs", None)? {
        None => pair::Dofs::Torsional,
        Some(Value::Text(s)) if s == "torsional" => pair::Dofs::Torsional,
        Some(Value::Text(s)) if s == "transverse-torsional" => pair::Dofs::TransverseTorsional,
        Some(v) => {
            return Err(Error::StudyFile(format!(
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

fn pair_build(ctx: &Context<'_>) -> Result<Adapter, Error> {
    let limits = ctx.limits;
    match ctx.solver.method {
        Method::TimeStepping => {
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
            Ok(Adapter {
                outputs: outs_stepped(PAIR_TS_OUT, check),
                prepare: Box::new(move |p: &Point| {
                    let (model, f_s) = pair_model(p)?;
                    // adaptive steps: at least 8 per mesh period (h_max = T/8)
                    let periods = settings.transient_periods + settings.record_periods;
                    need_steps("generic-pair", 8.0 * periods as f64, &limits)?;
                    let initial = initial.clone();
                    Ok(Box::new(move || {
                        run_stepped_job(check, |factor| {
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
                            let v = vec![
                                r.dynamic_factor(f_s),
                                r.delta.iter().sum::<f64>() / n,
                                max - min,
                            ];
                            Ok((v, r.stats))
                        })
                    }) as Job)
                }),
            })
        }
        Method::Hbm => {
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
                return Err(Error::StudyFile(format!(
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
                            .map_err(models::Error::from)
                            .context("generic-pair harmonic balance")?;
                        let c = &sol.coefficients;
                        Ok(vec![
                            c[0],
                            c[n].hypot(c[2 * n]),
                            if sol.converged { 1.0 } else { 0.0 },
                            sol.residual_norm,
                            sol.truncation,
                        ])
                    }) as Job)
                }),
            })
        }
        Method::Shooting => {
            let defs = shoot_settings(shoot_transient(200.0, PAIR_SHOOT_TRANSIENT));
            let s = Settings::read(
                "generic-pair",
                Method::Shooting,
                &defs,
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
            let s = std::sync::Arc::new(s);
            Ok(Adapter {
                outputs: outs(SHOOT_OUT),
                prepare: Box::new(move |p: &Point| {
                    let (model, _) = pair_model(p)?;
                    let periods = settings.transient_periods + settings.record_periods;
                    need_steps("generic-pair shooting", 8.0 * periods as f64, &limits)?;
                    let (s, initial) = (std::sync::Arc::clone(&s), initial.clone());
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
        m => Err(wrong_method(
            "generic-pair",
            m,
            &[Method::TimeStepping, Method::Hbm, Method::Shooting],
        )),
    }
}

/// Describe every registered model as JSON (for `geardyn models --json`).
pub fn describe_all() -> serde_json::Value {
    let v: Vec<serde_json::Value> = REGISTRY
        .iter()
        .map(|m| {
            serde_json::json!({
                "name": m.name,
                "description": m.description,
                "info": (m.describe)(),
            })
        })
        .collect();
    serde_json::Value::Array(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn default_of(defs: &[SettingDef], name: &str) -> f64 {
        match defs.iter().find(|d| d.name == name).map(|d| d.kind) {
            Some(Kind::Num { default, .. }) => default,
            Some(Kind::Int {
                default: Some(d), ..
            }) => d as f64,
            other => panic!("{name}: {other:?}"),
        }
    }

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

    #[test]
    fn every_model_describes_itself() {
        for m in &REGISTRY {
            let info = (m.describe)();
            assert!(!info.parameters.is_empty(), "{}", m.name);
            assert!(!info.methods.is_empty(), "{}", m.name);
            for c in &info.choices {
                assert!(c.options.contains(&c.default), "{}: {c:?}", m.name);
            }
        }
    }
}
