//! Python bindings of geardyn (module `geardyn._geardyn`; the public API is the pure-Python
//! package `geardyn` around it).
//!
//! Every function takes and returns JSON text: parameter sets and results are the models'
//! serde forms, so each field keeps its Rust name and SI unit, and the Python layer turns
//! number lists into numpy arrays. A failure returns `{"error": {"kind", "message", "chain"}}`,
//! which the Python layer raises as the typed exception named by `kind` (`ParameterError`,
//! `SolverError`, `StudyError`); `chain` lists the messages of the Rust `source()` chain.
//! The heavy work runs with the GIL released.

use std::collections::BTreeMap;

use models::{karpov2017, liu2021, yu2021};
use pyo3::prelude::*;
use rayon::prelude::*;
use serde::Serialize;
use serde::de::DeserializeOwned;
use serde_json::{Value, json};

/// The kind of Python exception an error maps to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    /// Bad input: unknown name, out-of-range parameter, unsupported reading.
    Parameter,
    /// An engine failed (a non-converged solve is a result, not an error).
    Solver,
    /// A study file could not be read or run.
    Study,
}

/// An error on its way to Python.
#[derive(Debug)]
struct Failure {
    kind: Kind,
    message: String,
    chain: Vec<String>,
}

impl Failure {
    fn parameter(message: impl Into<String>) -> Self {
        Failure {
            kind: Kind::Parameter,
            message: message.into(),
            chain: Vec::new(),
        }
    }

    fn to_json(&self) -> Value {
        let kind = match self.kind {
            Kind::Parameter => "ParameterError",
            Kind::Solver => "SolverError",
            Kind::Study => "StudyError",
        };
        json!({"error": {"kind": kind, "message": self.message, "chain": self.chain}})
    }
}

/// The messages of `e.source()`, `e.source().source()`, … (not `e` itself).
fn source_chain(e: &dyn std::error::Error) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur = e.source();
    while let Some(s) = cur {
        out.push(s.to_string());
        cur = s.source();
    }
    out
}

impl From<models::Error> for Failure {
    fn from(e: models::Error) -> Self {
        use models::Error as E;
        let kind = match &e {
            E::InvalidParameter { .. }
            | E::UnsupportedReading { .. }
            | E::Geometry(_)
            | E::Stiffness { .. }
            | E::Backlash { .. } => Kind::Parameter,
            _ => Kind::Solver,
        };
        Failure {
            kind,
            message: e.to_string(),
            chain: source_chain(&e),
        }
    }
}

impl From<validate::Error> for Failure {
    fn from(e: validate::Error) -> Self {
        Failure {
            kind: Kind::Study,
            message: e.to_string(),
            chain: source_chain(&e),
        }
    }
}

type Res<T> = Result<T, Failure>;

fn parse_json(what: &str, text: &str) -> Res<Value> {
    serde_json::from_str(text).map_err(|e| Failure::parameter(format!("{what}: invalid JSON: {e}")))
}

/// Overlay `over` on `base`, recursively for objects; every key of `over` must exist in `base`
/// (a typo is an error naming the known keys), except where `base` holds `null` (an optional
/// field) or a non-object (replaced whole, e.g. an enum).
fn merge(path: &str, base: &mut Value, over: &Value) -> Res<()> {
    match (base, over) {
        (Value::Object(b), Value::Object(o)) => {
            for (k, v) in o {
                let p = if path.is_empty() {
                    k.clone()
                } else {
                    format!("{path}.{k}")
                };
                match b.get_mut(k) {
                    Some(slot) if slot.is_object() && v.is_object() => merge(&p, slot, v)?,
                    Some(slot) => *slot = v.clone(),
                    None => {
                        let known: Vec<&String> = b.keys().collect();
                        return Err(Failure::parameter(format!(
                            "unknown parameter `{p}`; known: {known:?}"
                        )));
                    }
                }
            }
            Ok(())
        }
        (b, o) => {
            *b = o.clone();
            Ok(())
        }
    }
}

/// `base` with the JSON overrides `over` applied, deserialised back into `T`.
fn with_overrides<T: Serialize + DeserializeOwned>(what: &str, base: &T, over: &Value) -> Res<T> {
    let mut v = serde_json::to_value(base).map_err(|e| Failure::parameter(e.to_string()))?;
    if !over.is_null() {
        merge("", &mut v, over)?;
    }
    serde_json::from_value(v).map_err(|e| Failure::parameter(format!("{what}: {e}")))
}

fn to_json<T: Serialize>(x: &T) -> Res<Value> {
    serde_json::to_value(x).map_err(|e| Failure {
        kind: Kind::Solver,
        message: format!("result not representable: {e}"),
        chain: Vec::new(),
    })
}

/// The named parameter sets (`preset(model, name)`).
fn preset_value(model: &str, name: &str) -> Res<Value> {
    let v = match (model, name) {
        ("liu2021", "table1") => to_json(&liu2021::table1())?,
        ("liu2021-readings", "consistent") => to_json(&liu2021::Readings::default())?,
        ("liu2021-readings", "printed") => to_json(&liu2021::Readings::printed())?,
        ("karpov2017", "fig3") => to_json(&karpov2017::Karpov2017::fig3().params())?,
        ("yu2021", "table1") => to_json(&yu2021::Yu2021Params::table1())?,
        ("yu2021", "table2") => to_json(&yu2021::Yu2021Params::table2())?,
        ("yu2021-options", "yu") => to_json(&yu2021::Options::default())?,
        ("yu2021-options", "chen") => to_json(&yu2021::Options::chen())?,
        _ => {
            return Err(Failure::parameter(format!(
                "unknown preset `{name}` of `{model}`; known: {}",
                PRESETS
                    .iter()
                    .map(|(m, n)| format!("{m}:{n}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            )));
        }
    };
    Ok(v)
}

/// Every `(model, preset)` pair.
const PRESETS: [(&str, &str); 8] = [
    ("liu2021", "table1"),
    ("liu2021-readings", "consistent"),
    ("liu2021-readings", "printed"),
    ("karpov2017", "fig3"),
    ("yu2021", "table1"),
    ("yu2021", "table2"),
    ("yu2021-options", "yu"),
    ("yu2021-options", "chen"),
];

fn settings_map(settings: &Value) -> Res<BTreeMap<String, Value>> {
    match settings {
        Value::Null => Ok(BTreeMap::new()),
        Value::Object(m) => Ok(m.iter().map(|(k, v)| (k.clone(), v.clone())).collect()),
        _ => Err(Failure::parameter("settings must be a mapping")),
    }
}

fn take_f64(s: &mut BTreeMap<String, Value>, key: &str, default: f64) -> Res<f64> {
    match s.remove(key) {
        None => Ok(default),
        Some(v) => v
            .as_f64()
            .ok_or_else(|| Failure::parameter(format!("setting `{key}` must be a number"))),
    }
}

fn take_bool(s: &mut BTreeMap<String, Value>, key: &str, default: bool) -> Res<bool> {
    match s.remove(key) {
        None => Ok(default),
        Some(v) => v
            .as_bool()
            .ok_or_else(|| Failure::parameter(format!("setting `{key}` must be true or false"))),
    }
}

fn no_leftovers(method: &str, s: BTreeMap<String, Value>) -> Res<()> {
    match s.keys().next() {
        None => Ok(()),
        Some(k) => Err(Failure::parameter(format!(
            "unknown setting `{k}` for method `{method}`"
        ))),
    }
}

/// A study-code error as a `ParameterError`: its message without the "study file: " prefix (a
/// Python call has no study file).
fn parameter_error(e: validate::Error) -> Failure {
    match e {
        validate::Error::StudyFile(m) => Failure::parameter(m),
        e => Failure::parameter(e.to_string()),
    }
}

/// Check settings through `geardyn study`'s definitions ([`validate::check_settings`]): a
/// bad one is a `ParameterError` with the study's message (name, kind, bound).
fn study_settings(
    model: &str,
    method: validate::Method,
    given: &serde_json::Map<String, Value>,
) -> Res<()> {
    let mut map = BTreeMap::new();
    for (k, v) in given {
        let value = match v {
            Value::Number(n) => validate::Value::Num(n.as_f64().unwrap_or(f64::NAN)),
            Value::String(t) => validate::Value::Text(t.clone()),
            Value::Bool(b) => validate::Value::Bool(*b),
            _ => {
                return Err(Failure::parameter(format!(
                    "setting `{k}` must be a number, got {v}"
                )));
            }
        };
        map.insert(k.clone(), value);
    }
    validate::check_settings(model, method, &map).map_err(parameter_error)
}

/// Solve one point of a model by one method.
/// The Yu 2021 inputs shared by both methods: parameters on top of Table 1, the model
/// options (`settings["options"]`) and `ω*` (`settings["omega"]`, required: NaN is refused by
/// the model).
fn yu_inputs(
    params: &Value,
    s: &mut BTreeMap<String, Value>,
) -> Res<(yu2021::Yu2021Params, yu2021::Options, f64)> {
    // `omega` (ω*) is a parameter, as in a study file; a setting too (older scripts)
    let mut params = params.clone();
    let from_params = match &mut params {
        Value::Object(o) => o.remove("omega"),
        _ => None,
    };
    let p = with_overrides("yu2021", &yu2021::Yu2021Params::table1(), &params)?;
    let o = with_overrides(
        "yu2021 options",
        &yu2021::Options::default(),
        &s.remove("options").unwrap_or(Value::Null),
    )?;
    let from_settings = take_f64(s, "omega", f64::NAN)?;
    let omega = match from_params {
        Some(v) => v.as_f64().ok_or_else(|| {
            Failure::parameter(format!("parameter `omega` takes a number, got {v}"))
        })?,
        None => from_settings,
    };
    if !(omega.is_finite() && omega > 0.0) {
        return Err(Failure::parameter(format!(
            "yu2021.omega must be finite and > 0, got {omega} (set it as a parameter: \
             Yu2021().with_params(omega=0.5))"
        )));
    }
    Ok((p, o, omega))
}

/// The columns of a study's `shooting` point as a result dict (a returned orbit converged).
fn shooting_json(cols: Vec<(&'static str, f64)>) -> Value {
    let mut o: serde_json::Map<String, Value> = cols
        .into_iter()
        .map(|(k, v)| (k.to_owned(), json!(v)))
        .collect();
    o.insert("converged".to_owned(), json!(true));
    Value::Object(o)
}

/// Python settings (numbers, names) as study-file values, for the study code's checks.
fn study_values(s: BTreeMap<String, Value>) -> Res<BTreeMap<String, validate::Value>> {
    let mut map = BTreeMap::new();
    for (k, v) in s {
        let value = match &v {
            Value::Number(n) => validate::Value::Num(n.as_f64().unwrap_or(f64::NAN)),
            Value::String(t) => validate::Value::Text(t.clone()),
            _ => {
                return Err(Failure::parameter(format!(
                    "setting `{k}` must be a number, got {v}"
                )));
            }
        };
        map.insert(k, value);
    }
    Ok(map)
}

fn solve_value(model: &str, params: &Value, method: &str, settings: &Value) -> Res<Value> {
    let mut s = settings_map(settings)?;
    match (model, method) {
        ("liu2021", "time-stepping") => {
            let p: liu2021::Parameters = with_overrides("liu2021", &liu2021::table1(), params)?;
            let mut opts_over = s.remove("options").unwrap_or(Value::Null);
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
                        opts_over = Value::Object(serde_json::Map::new());
                    }
                    let Value::Object(o) = &mut opts_over else {
                        return Err(Failure::parameter(format!(
                            "setting `options` must be a mapping, got {opts_over}"
                        )));
                    };
                    if o.contains_key(k) {
                        return Err(Failure::parameter(format!(
                            "setting `{k}` given twice (top level and in `options`)"
                        )));
                    }
                    o.insert(k.to_owned(), v);
                }
            }
            // long-window rattle statistics (issue 22): windows of n periods, 0 = off
            let lw_periods = take_f64(&mut s, "long_window_periods", 0.0)?;
            if !((0.0..=1e4).contains(&lw_periods) && lw_periods.fract() == 0.0) {
                return Err(Failure::parameter(format!(
                    "setting `long_window_periods` must be an integer in [0, 10000], got {lw_periods}"
                )));
            }
            no_leftovers(method, s)?;
            // the integration options share their names, bounds and messages with the study
            // setting of `geardyn study` (all but `initial`, a state)
            if let Value::Object(o) = &opts_over {
                let shared: serde_json::Map<String, Value> = o
                    .iter()
                    .filter(|(k, _)| k.as_str() != "initial")
                    .map(|(k, v)| (k.clone(), v.clone()))
                    .collect();
                study_settings("liu2021", validate::Method::TimeStepping, &shared)?;
            }
            let opts = with_overrides(
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
                let mut m: serde_json::Map<String, Value> = models::response::Robust::COLUMNS
                    .iter()
                    .zip(lw.values())
                    .map(|((name, _), v)| ((*name).to_owned(), json!(v)))
                    .collect();
                m.insert("spread".to_owned(), json!(lw.describe()));
                Value::Object(m)
            } else {
                Value::Null
            };
            Ok(json!({
                "tau": r.tau, "q": r.q, "v": r.v,
                "rsv": r.rattle.state.rsv(), "ppv": r.rattle.ppv,
                "converged": true, "contact_events": r.contact_events,
                "window": window,
            }))
        }
        ("liu2021", "hbm") => {
            let p: liu2021::Parameters = with_overrides("liu2021", &liu2021::table1(), params)?;
            let warm = take_bool(&mut s, "warm_start", false)?;
            let output_samples = take_f64(&mut s, "output_samples", 512.0)?;
            if !((8.0..=65_536.0).contains(&output_samples) && output_samples.fract() == 0.0) {
                return Err(Failure::parameter(format!(
                    "setting `output_samples` must be an integer in [8, 65536], got {output_samples}"
                )));
            }
            // tol, max_iter, samples, full_r: the settings of `geardyn study` (same names,
            // bounds and messages; checked by the same code)
            let shared: serde_json::Map<String, Value> =
                std::mem::take(&mut s).into_iter().collect();
            study_settings("liu2021", validate::Method::Hbm, &shared)?;
            let num = |k: &str| shared.get(k).and_then(Value::as_f64);
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
        ("liu2021", "shooting") => {
            // the study's method "shooting": settings (transient_periods, rtol, tol, max_iter,
            // segments) checked and computed by the study code; `initial` = [q, q'] where the
            // guess's integration starts
            let p: liu2021::Parameters = with_overrides("liu2021", &liu2021::table1(), params)?;
            let initial = match s.remove("initial") {
                None | Some(Value::Null) => None,
                Some(Value::Array(a)) if a.len() == 2 => match (a[0].as_f64(), a[1].as_f64()) {
                    (Some(q), Some(v)) => Some((q, v)),
                    _ => {
                        return Err(Failure::parameter(
                            "setting `initial` must be [q, q'] (two numbers)".to_owned(),
                        ));
                    }
                },
                Some(v) => {
                    return Err(Failure::parameter(format!(
                        "setting `initial` must be [q, q'] (two numbers), got {v}"
                    )));
                }
            };
            let map = study_values(std::mem::take(&mut s))?;
            let m = p.model()?;
            let cols = validate::liu_shooting_point(m, &map, initial).map_err(parameter_error)?;
            Ok(shooting_json(cols))
        }
        ("yu2021", "shooting") => {
            // the study's method "shooting" (Yu's 6-DOF model with free centres): settings
            // (transient_periods, rtol, tol, max_iter, segments) checked and computed by the
            // study code
            let (p, o, omega) = yu_inputs(params, &mut s)?;
            let map = study_values(std::mem::take(&mut s))?;
            let m = yu2021::Yu2021Model::new(&p, o)?;
            let cols = validate::yu_shooting_point(m, omega, &map).map_err(parameter_error)?;
            Ok(shooting_json(cols))
        }
        ("karpov2017", "duhamel") | ("karpov2017", "time-stepping") => {
            let base = karpov2017::Karpov2017::fig3().params();
            let p: karpov2017::Karpov2017Params = with_overrides("karpov2017", &base, params)?;
            no_leftovers(method, s)?;
            let m = karpov2017::Karpov2017::new(p)?;
            let r = m.duhamel()?;
            let mut v = to_json(&r)?;
            if let Value::Object(o) = &mut v {
                o.insert("converged".into(), Value::Bool(true));
            }
            Ok(v)
        }
        ("yu2021", "time-stepping") | ("yu2021", "rk4") => {
            let (p, o, omega) = yu_inputs(params, &mut s)?;
            let mut run = yu2021::RunSettings::new(omega);
            // the run sizes of `geardyn study` (same names, bounds, messages)
            let mut shared = serde_json::Map::new();
            for k in ["transient_periods", "record_periods"] {
                if let Some(v) = s.remove(k) {
                    shared.insert(k.to_owned(), v);
                }
            }
            no_leftovers(method, s)?;
            study_settings("yu2021", validate::Method::TimeStepping, &shared)?;
            let num = |k: &str, d: f64| shared.get(k).and_then(Value::as_f64).unwrap_or(d);
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
            let mut v = to_json(&r)?;
            if let Value::Object(obj) = &mut v {
                obj.insert("dynamic_factor".into(), json!(df));
                obj.insert("converged".into(), Value::Bool(true));
            }
            Ok(v)
        }
        ("yu2021", "hbm") => {
            let (p, o, omega) = yu_inputs(params, &mut s)?;
            let hs = with_overrides(
                "yu2021 hbm settings",
                &yu2021::HbmSettings::default(),
                &s.remove("hbm").unwrap_or(Value::Null),
            )?;
            no_leftovers(method, s)?;
            let m = yu2021::Yu2021Model::new(&p, o)?;
            let r = m.harmonic_balance(omega, &hs, None)?;
            to_json(&r)
        }
        _ => Err(Failure::parameter(format!(
            "unknown model/method `{model}`/`{method}`; known: liu2021 (hbm, time-stepping, shooting), \
             karpov2017 (duhamel), yu2021 (time-stepping, rk4, hbm, shooting)"
        ))),
    }
}

fn envelope(r: Res<Value>) -> String {
    match r {
        Ok(v) => json!({ "ok": v }).to_string(),
        Err(f) => f.to_json().to_string(),
    }
}

/// `describe(model)` → JSON of the model's self-description (parameters with units and
/// defaults, choices and readings, methods with their settings, bounds and outputs): the
/// registry's, the same as `geardyn models --json` and the generated table of docs/studies.md.
/// An empty name: every model.
#[pyfunction]
fn describe(model: &str) -> String {
    envelope((|| {
        if model.is_empty() {
            return Ok(validate::describe_all());
        }
        let m = validate::model_spec(model).map_err(parameter_error)?;
        Ok(json!({
            "name": m.name,
            "description": m.description,
            "info": (m.describe)(),
        }))
    })())
}

/// `preset(model, name)` → JSON of the named parameter set (see the Python `geardyn.presets`).
#[pyfunction]
fn preset(model: &str, name: &str) -> String {
    envelope(preset_value(model, name))
}

/// The limits of a Python call (`limits_json`: `null` or `{"max_points", "max_steps",
/// "max_seconds_per_point"}`), checked by the study code ([`validate::Limits::check`]); a bad
/// one is a `ParameterError` naming the entry and the bound.
fn parse_limits(text: &str) -> Res<validate::Limits> {
    let v = parse_json("limits", text)?;
    let limits: validate::Limits = if v.is_null() {
        validate::Limits::default()
    } else {
        serde_json::from_value(v).map_err(|e| Failure::parameter(format!("limits: {e}")))?
    };
    limits.check().map_err(parameter_error)?;
    Ok(limits)
}

/// Solve one point under the wall-clock limit of `limits` (see
/// [`validate::run_with_time_limit`]): over it, a `SolverError` whose message starts with
/// "time limit".
fn solve_limited(
    model: &str,
    params: &Value,
    method: &str,
    settings: &Value,
    limits: &validate::Limits,
) -> Res<Value> {
    let Some(seconds) = limits.max_seconds_per_point else {
        return solve_value(model, params, method, settings);
    };
    let (model, params, method, settings) = (
        model.to_owned(),
        params.clone(),
        method.to_owned(),
        settings.clone(),
    );
    let r = validate::run_with_time_limit(Some(seconds), move || {
        Ok(solve_value(&model, &params, &method, &settings))
    });
    match r {
        Ok(inner) => inner,
        Err(message) => Err(Failure {
            kind: Kind::Solver,
            message,
            chain: Vec::new(),
        }),
    }
}

/// `solve(model, params_json, method, settings_json, limits_json)` → JSON result of one point.
#[pyfunction]
fn solve(
    py: Python<'_>,
    model: &str,
    params: &str,
    method: &str,
    settings: &str,
    limits: &str,
) -> String {
    py.detach(|| {
        envelope((|| {
            let p = parse_json("params", params)?;
            let s = parse_json("settings", settings)?;
            let l = parse_limits(limits)?;
            solve_limited(model, &p, method, &s, &l)
        })())
    })
}

/// `check_points(n, limits_json)`: `None`, or a `ParameterError` when a sweep of `n` points
/// exceeds `limits.max_points` — the check and message of a study file
/// ([`validate::Limits::check_points`]); called before the values are converted.
#[pyfunction]
fn check_points(n: usize, limits: &str) -> String {
    envelope((|| {
        let l = parse_limits(limits)?;
        l.check_points(n, 1).map_err(parameter_error)?;
        Ok(Value::Null)
    })())
}

/// `sweep(model, params_json, parameter, values, method, settings_json, limits_json)` → JSON
/// list, one result (or error) per value, solved in parallel and returned in input order (each
/// point is independent, so the results do not depend on the number of threads). The number
/// of values is checked against `limits.max_points` first; a non-finite value is a failed point
/// with its reason; a point over `limits.max_seconds_per_point` fails with "time limit".
// The arguments of the Python call, one by one (JSON texts and a float list).
#[allow(clippy::too_many_arguments)]
#[pyfunction]
fn sweep(
    py: Python<'_>,
    model: &str,
    params: &str,
    parameter: &str,
    values: Vec<f64>,
    method: &str,
    settings: &str,
    limits: &str,
) -> String {
    py.detach(|| {
        envelope((|| {
            let l = parse_limits(limits)?;
            l.check_points(values.len(), 1).map_err(parameter_error)?;
            let p = parse_json("params", params)?;
            let s = parse_json("settings", settings)?;
            let points: Vec<Value> = values
                .par_iter()
                .map(|&x| {
                    let mut pp = p.clone();
                    if pp.is_null() {
                        pp = json!({});
                    }
                    let r = if !x.is_finite() {
                        // the message of a study file's sweep value
                        Err(Failure::parameter(format!(
                            "sweep of `{parameter}`: every value must be finite, got {x}"
                        )))
                    } else {
                        match &mut pp {
                            Value::Object(o) => {
                                o.insert(parameter.to_owned(), json!(x));
                                solve_limited(model, &pp, method, &s, &l)
                            }
                            _ => Err(Failure::parameter("params must be a mapping")),
                        }
                    };
                    match r {
                        Ok(v) => json!({ "ok": v }),
                        Err(f) => f.to_json(),
                    }
                })
                .collect();
            Ok(Value::Array(points))
        })())
    })
}

/// `run_study(toml_text)` → JSON `{name, columns: [{name, unit}], rows, summary}`.
#[pyfunction]
fn run_study(py: Python<'_>, text: &str) -> String {
    py.detach(|| {
        envelope((|| {
            let study = validate::UserStudy::parse(text)?;
            let out = validate::run_user_study(&study, || {})?;
            let rows: Vec<Vec<Value>> = out
                .table
                .rows
                .iter()
                .map(|r| {
                    r.iter()
                        .map(|c| match c {
                            validate::Cell::Num(x) | validate::Cell::Unsettled(x) => json!(x),
                            validate::Cell::Text(t) => json!(t),
                            validate::Cell::Count(n) => json!(n),
                            _ => Value::Null,
                        })
                        .collect()
                })
                .collect();
            Ok(json!({
                "name": study.name,
                "columns": out.table.columns,
                "rows": rows,
                "summary": out.summary,
            }))
        })())
    })
}

/// Write a computed study's outputs into `out_dir` (checked and locked first): the files of
/// `geardyn study`. Returns the JSON summary with the run id.
fn write_into(out: &validate::UserStudyOutput, out_dir: &str) -> Res<Value> {
    let lock = validate::lock_output_dir(std::path::Path::new(out_dir))?;
    let written = validate::write_outputs(out, &lock)?;
    let mut summary = out.summary.clone();
    if let Some(o) = summary.as_object_mut() {
        o.insert("run_id".to_owned(), json!(written.run_id));
    }
    Ok(summary)
}

/// `write_study(toml_text, out_dir)` → JSON summary; computes the study in this process and
/// writes its CSV, SVG and JSON files to `out_dir`, as `geardyn study` does.
#[pyfunction]
fn write_study(py: Python<'_>, text: &str, out_dir: &str) -> String {
    py.detach(|| {
        envelope((|| {
            let out = validate::run_study_from_str(text, &validate::RunOptions::default())?;
            write_into(&out, out_dir)
        })())
    })
}

/// `run_study_shard(toml_text, index, count)` → the shard's partial result (text), as
/// `geardyn study FILE --shard index/count` writes it.
#[pyfunction]
fn run_study_shard(py: Python<'_>, text: &str, index: usize, count: usize) -> String {
    py.detach(|| {
        envelope((|| {
            let shard = validate::shard::ShardSpec::new(index, count)?;
            Ok(json!(validate::run_shard_from_str(text, shard)?))
        })())
    })
}

/// `merge_study(toml_text, parts, out_dir)` → JSON summary; merges the partial results and
/// writes the outputs to `out_dir`, byte-identical to `write_study` in one process.
#[pyfunction]
fn merge_study(py: Python<'_>, text: &str, parts: Vec<String>, out_dir: &str) -> String {
    py.detach(|| {
        envelope((|| {
            let out = validate::merge_from_str(text, &parts)?;
            write_into(&out, out_dir)
        })())
    })
}

/// The Rust side of the `geardyn` Python package.
#[pymodule]
fn _geardyn(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add(
        "PRESETS",
        PRESETS
            .iter()
            .map(|(a, b)| (a.to_string(), b.to_string()))
            .collect::<Vec<_>>(),
    )?;
    m.add_function(wrap_pyfunction!(describe, m)?)?;
    m.add_function(wrap_pyfunction!(preset, m)?)?;
    m.add_function(wrap_pyfunction!(solve, m)?)?;
    m.add_function(wrap_pyfunction!(sweep, m)?)?;
    m.add_function(wrap_pyfunction!(check_points, m)?)?;
    m.add_function(wrap_pyfunction!(run_study, m)?)?;
    m.add_function(wrap_pyfunction!(write_study, m)?)?;
    m.add_function(wrap_pyfunction!(run_study_shard, m)?)?;
    m.add_function(wrap_pyfunction!(merge_study, m)?)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn merge_rejects_unknown_keys_and_keeps_nested_ones() {
        let mut base = json!({"a": 1.0, "r": {"x": "derived", "y": "mean"}});
        merge("", &mut base, &json!({"r": {"x": "printed_eq20"}})).unwrap();
        assert_eq!(
            base,
            json!({"a": 1.0, "r": {"x": "printed_eq20", "y": "mean"}})
        );
        let e = merge("", &mut base, &json!({"b": 2.0})).unwrap_err();
        assert_eq!(e.kind, Kind::Parameter);
        assert!(e.message.contains("`b`"));
    }
}
