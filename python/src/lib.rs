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

use models::contract::{self, PointError, REGISTRY};
use pyo3::prelude::*;
use rayon::prelude::*;
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

impl From<PointError> for Failure {
    fn from(e: PointError) -> Self {
        match e {
            PointError::Model(e) => Failure::from(e),
            PointError::Unrepresentable(_) => Failure {
                kind: Kind::Solver,
                message: e.to_string(),
                chain: Vec::new(),
            },
            // a study-code error: its message without the "study file: " prefix (a Python call
            // has no study file)
            e => Failure::parameter(e.to_string()),
        }
    }
}

impl From<study::Error> for Failure {
    fn from(e: study::Error) -> Self {
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

/// Every `(set, preset)` pair of the registered models ([`contract::Model::presets`]).
fn presets() -> Vec<contract::Preset> {
    REGISTRY.iter().flat_map(|m| m.presets()).collect()
}

/// The named parameter sets (`preset(model, name)`).
fn preset_value(model: &str, name: &str) -> Res<Value> {
    let all = presets();
    match all.iter().find(|p| p.set == model && p.name == name) {
        Some(p) => Ok((p.value)()),
        None => Err(Failure::parameter(format!(
            "unknown preset `{name}` of `{model}`; known: {}",
            all.iter()
                .map(|p| format!("{}:{}", p.set, p.name))
                .collect::<Vec<_>>()
                .join(", ")
        ))),
    }
}

fn settings_map(settings: &Value) -> Res<BTreeMap<String, Value>> {
    match settings {
        Value::Null => Ok(BTreeMap::new()),
        Value::Object(m) => Ok(m.iter().map(|(k, v)| (k.clone(), v.clone())).collect()),
        _ => Err(Failure::parameter("settings must be a mapping")),
    }
}

/// Solve one point of a model by one method: the model's full-result solve
/// ([`contract::Model::solve_full`]).
fn solve_value(model: &str, params: &Value, method: &str, settings: &Value) -> Res<Value> {
    let s = settings_map(settings)?;
    let Some(m) = REGISTRY
        .iter()
        .find(|m| m.name() == model && m.full_methods().contains(&method))
    else {
        let known: Vec<String> = REGISTRY
            .iter()
            .filter(|m| !m.full_methods().is_empty())
            .map(|m| format!("{} ({})", m.name(), m.full_methods().join(", ")))
            .collect();
        return Err(Failure::parameter(format!(
            "unknown model/method `{model}`/`{method}`; known: {}",
            known.join(", ")
        )));
    };
    Ok(m.solve_full(params, method, s)?)
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
            return Ok(contract::describe_all());
        }
        let m = contract::find(model)?;
        Ok(contract::describe_json(m))
    })())
}

/// `preset(model, name)` → JSON of the named parameter set (see the Python `geardyn.presets`).
#[pyfunction]
fn preset(model: &str, name: &str) -> String {
    envelope(preset_value(model, name))
}

/// The limits of a Python call (`limits_json`: `null` or `{"max_points", "max_steps",
/// "max_seconds_per_point"}`), checked by the study code ([`study::Limits::check`]); a bad
/// one is a `ParameterError` naming the entry and the bound.
fn parse_limits(text: &str) -> Res<study::Limits> {
    let v = parse_json("limits", text)?;
    let limits: study::Limits = if v.is_null() {
        study::Limits::default()
    } else {
        serde_json::from_value(v).map_err(|e| Failure::parameter(format!("limits: {e}")))?
    };
    limits.check()?;
    Ok(limits)
}

/// Solve one point under the wall-clock limit of `limits` (see
/// [`study::run_with_time_limit`]): over it, a `SolverError` whose message starts with
/// "time limit".
fn solve_limited(
    model: &str,
    params: &Value,
    method: &str,
    settings: &Value,
    limits: &study::Limits,
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
    let r = study::run_with_time_limit(Some(seconds), move || {
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
/// ([`study::Limits::check_points`]); called before the values are converted.
#[pyfunction]
fn check_points(n: usize, limits: &str) -> String {
    envelope((|| {
        let l = parse_limits(limits)?;
        l.check_points(n, 1)?;
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
            l.check_points(values.len(), 1)?;
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

/// A table row as JSON values (numbers, counts, labels; NaN as null by serde_json).
fn cells(r: &[study::Cell]) -> Vec<Value> {
    r.iter()
        .map(|c| match c {
            study::Cell::Num(x) | study::Cell::Unsettled(x) => json!(x),
            study::Cell::Text(t) => json!(t),
            study::Cell::Count(n) => json!(n),
            _ => Value::Null,
        })
        .collect()
}

/// `run_study(toml_text)` → JSON `{name, columns: [{name, unit}], rows, summary, unsettled,
/// tables}` (`tables`: the further tables `[{name, columns, rows}]`);
/// `unsettled` lists the `[row, column]` of every cell the table marks as not settled
/// (`Cell::Unsettled`: written as a number, judged as not periodic).
#[pyfunction]
fn run_study(py: Python<'_>, text: &str) -> String {
    py.detach(|| {
        envelope((|| {
            let study = study::UserStudy::parse(text)?;
            let out = study::run_user_study(&study, || {})?;
            // the cells the table marks as not settled (`Cell::Unsettled`), as [row, column]
            let unsettled: Vec<[usize; 2]> = out
                .table
                .rows
                .iter()
                .enumerate()
                .flat_map(|(i, r)| {
                    r.iter()
                        .enumerate()
                        .filter(|(_, c)| matches!(c, study::Cell::Unsettled(_)))
                        .map(move |(j, _)| [i, j])
                })
                .collect();
            let rows: Vec<Vec<Value>> = out.table.rows.iter().map(|r| cells(r)).collect();
            // the further tables (a basin study's fractions, a continuation's special points
            // and codim-2 curves), by name
            let tables: Vec<Value> = out
                .tables
                .iter()
                .map(|t| {
                    json!({
                        "name": t.name,
                        "columns": t.columns,
                        "rows": t.rows.iter().map(|r| cells(r)).collect::<Vec<_>>(),
                    })
                })
                .collect();
            Ok(json!({
                "name": study.name,
                "columns": out.table.columns,
                "rows": rows,
                "summary": out.summary,
                "unsettled": unsettled,
                "tables": tables,
            }))
        })())
    })
}

/// Write a computed study's outputs into `out_dir` (checked and locked first): the files of
/// `geardyn study`. Returns the JSON summary with the run id.
fn write_into(out: &study::UserStudyOutput, out_dir: &str) -> Res<Value> {
    let lock = study::lock_output_dir(std::path::Path::new(out_dir))?;
    let written = study::write_outputs(out, &lock)?;
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
            let out = study::run_study_from_str(text, &study::RunOptions::default())?;
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
            let shard = study::shard::ShardSpec::new(index, count)?;
            Ok(json!(study::run_shard_from_str(text, shard)?))
        })())
    })
}

/// `merge_study(toml_text, parts, out_dir)` → JSON summary; merges the partial results and
/// writes the outputs to `out_dir`, byte-identical to `write_study` in one process.
#[pyfunction]
fn merge_study(py: Python<'_>, text: &str, parts: Vec<String>, out_dir: &str) -> String {
    py.detach(|| {
        envelope((|| {
            let out = study::merge_from_str(text, &parts)?;
            write_into(&out, out_dir)
        })())
    })
}

/// The Rust side of the `geardyn` Python package.
#[pymodule]
fn _geardyn(m: &Bound<'_, PyModule>) -> PyResult<()> {
    // keep geardyn-math's C math symbols in the link
    math::c_symbols::link();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add(
        "PRESETS",
        presets()
            .iter()
            .map(|p| (p.set.to_owned(), p.name.to_owned()))
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
    fn every_preset_and_full_method_is_reachable() {
        assert!(!presets().is_empty());
        for p in presets() {
            assert!(preset_value(p.set, p.name).is_ok(), "{}:{}", p.set, p.name);
        }
        let e = solve_value("nope", &Value::Null, "hbm", &Value::Null).unwrap_err();
        assert_eq!(e.kind, Kind::Parameter);
        assert!(e.message.contains("liu2021 ("), "{}", e.message);
    }
}
