//! The vocabulary of study files: values, sweeps, methods, solver settings and limits, and the
//! serde helpers that set any model parameter by its Rust name. Used by the study runner
//! (`user`) and by the model registrations (`studies::user_models`); it imports
//! neither, so the two do not import each other.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize, de::DeserializeOwned};

use crate::error::Error;

/// Longest study name (bytes).
pub const MAX_NAME_LEN: usize = 64;
/// Most values one sweep may have.
pub const MAX_SWEEP_VALUES: usize = 100_000;
/// Hard upper bound of [`Limits::max_points`].
pub const MAX_POINTS_BOUND: usize = 1_000_000;
/// Hard upper bound of [`Limits::max_steps`].
pub const MAX_STEPS_BOUND: u64 = 10_000_000_000;
/// Hard upper bound of [`Limits::max_seconds_per_point`] (a week).
pub const MAX_SECONDS_BOUND: f64 = 604_800.0;
/// The reason of a point stopped by [`Limits::max_seconds_per_point`] (the start of its message).
pub const TIME_LIMIT: &str = "time limit";

/// A value in a study file: a number, a name (choices and readings), a flag or a list of
/// numbers (initial states).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Value {
    /// `true` / `false`.
    Bool(bool),
    /// A number (TOML integers are read as numbers too).
    Num(f64),
    /// A name, e.g. `"kahraman-singh"`.
    Text(String),
    /// A list of numbers, e.g. an initial state.
    List(Vec<f64>),
}

impl Value {
    /// The number, if this is one.
    pub fn as_num(&self) -> Option<f64> {
        match self {
            Value::Num(x) => Some(*x),
            _ => None,
        }
    }

    /// A short rendering for messages, labels and CSV cells.
    pub fn label(&self) -> String {
        match self {
            Value::Bool(b) => b.to_string(),
            Value::Num(x) => crate::fmt6(*x),
            Value::Text(s) => s.clone(),
            Value::List(v) => format!(
                "[{}]",
                v.iter()
                    .map(|x| crate::fmt6(*x))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        }
    }

    pub(crate) fn check_finite(&self, what: &str) -> Result<(), Error> {
        let bad = |x: f64| Error::StudyFile(format!("{what} must be finite, got {x}"));
        match self {
            Value::Num(x) if !x.is_finite() => Err(bad(*x)),
            Value::List(v) => match v.iter().find(|x| !x.is_finite()) {
                Some(x) => Err(bad(*x)),
                None => Ok(()),
            },
            _ => Ok(()),
        }
    }
}

/// One swept parameter: a range (`from`, `to`, `steps`, linear) or explicit `values` (numbers,
/// or names for a choice such as `variant`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sweep {
    /// Parameter or choice name (see `geardyn models`).
    pub parameter: String,
    /// Start of a linear range.
    pub from: Option<f64>,
    /// End of a linear range (inclusive).
    pub to: Option<f64>,
    /// Number of points of the range (2 ..= [`MAX_SWEEP_VALUES`]).
    pub steps: Option<i64>,
    /// Explicit values (instead of a range).
    pub values: Option<Vec<Value>>,
}

impl Sweep {
    /// The swept values, in order. Errors name the sweep and the bound.
    pub fn points(&self) -> Result<Vec<Value>, Error> {
        let bad = |m: String| Error::StudyFile(format!("sweep of `{}`: {m}", self.parameter));
        let v = match (&self.values, self.from, self.to, self.steps) {
            (Some(v), None, None, None) => {
                if v.len() > MAX_SWEEP_VALUES {
                    return Err(bad(format!(
                        "{} values, at most {MAX_SWEEP_VALUES} allowed",
                        v.len()
                    )));
                }
                v.clone()
            }
            (None, Some(a), Some(b), Some(n)) => {
                if !(2..=MAX_SWEEP_VALUES as i64).contains(&n) {
                    return Err(bad(format!(
                        "steps must be in [2, {MAX_SWEEP_VALUES}], got {n}"
                    )));
                }
                if !(a.is_finite() && b.is_finite()) {
                    return Err(bad(format!("from and to must be finite, got {a} and {b}")));
                }
                // (b − a) may overflow for |a|, |b| near f64::MAX: interpolate without it.
                let n = n as usize;
                (0..n)
                    .map(|i| {
                        let t = i as f64 / (n - 1) as f64;
                        Value::Num(a * (1.0 - t) + b * t)
                    })
                    .collect()
            }
            _ => {
                return Err(bad(
                    "give either `values = [...]` or all of `from`, `to`, `steps`".to_owned(),
                ));
            }
        };
        if v.is_empty() {
            return Err(bad("no values".to_owned()));
        }
        for x in &v {
            x.check_finite(&format!("sweep of `{}`: every value", self.parameter))?;
        }
        Ok(v)
    }
}

/// Which solver evaluates each point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[non_exhaustive]
pub enum Method {
    /// Time integration to steady state (`timestep` crate or a model's own engine).
    TimeStepping,
    /// Harmonic balance (`hbm` crate).
    Hbm,
    /// Closed-form kinematics/geometry (no dynamics).
    Kinematics,
    /// Periodic orbit by shooting on the event-located flow (`orbit` crate): the orbit through
    /// a time-integration guess, its Floquet multipliers and the grazing / period-doubling
    /// test functions.
    Shooting,
}

impl Method {
    /// The name in a study file.
    pub fn name(self) -> &'static str {
        match self {
            Method::TimeStepping => "time-stepping",
            Method::Hbm => "hbm",
            Method::Kinematics => "kinematics",
            Method::Shooting => "shooting",
        }
    }
}

/// Solver choice and settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Solver {
    /// `time-stepping`, `hbm`, `kinematics` or `shooting`.
    pub method: Method,
    /// Method settings by name (see `geardyn models`); unknown names are an error.
    #[serde(default)]
    pub settings: BTreeMap<String, Value>,
}

/// Work limits of a study (`[limits]`), checked before anything runs.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Limits {
    /// Most points (sweep × sweep2); default 10 000, at most [`MAX_POINTS_BOUND`].
    pub max_points: i64,
    /// Most integration steps (or quadrature panels) one point may take, estimated before it
    /// runs from its settings and enforced by the engines' step budgets; default 2·10⁸, at most
    /// [`MAX_STEPS_BOUND`]. A point over the budget fails with a message (a NaN row).
    pub max_steps: f64,
    /// Wall-clock seconds one point may take (absent: no limit; at most
    /// [`MAX_SECONDS_BOUND`]). A point over it becomes a failed row whose message starts with
    /// [`TIME_LIMIT`], and the study goes on ([`run_with_time_limit`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_seconds_per_point: Option<f64>,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            max_points: 10_000,
            max_steps: 2e8,
            max_seconds_per_point: None,
        }
    }
}

impl Limits {
    /// Check every limit against its bounds; the message names the entry and the bound.
    pub fn check(&self) -> Result<(), Error> {
        if !(1..=MAX_POINTS_BOUND as i64).contains(&self.max_points) {
            return Err(Error::StudyFile(format!(
                "limits.max_points must be in [1, {MAX_POINTS_BOUND}], got {}",
                self.max_points
            )));
        }
        if !(self.max_steps >= 1.0 && self.max_steps <= MAX_STEPS_BOUND as f64) {
            return Err(Error::StudyFile(format!(
                "limits.max_steps must be in [1, {MAX_STEPS_BOUND:e}], got {}",
                self.max_steps
            )));
        }
        if let Some(t) = self.max_seconds_per_point {
            if !(t > 0.0 && t <= MAX_SECONDS_BOUND) {
                return Err(Error::StudyFile(format!(
                    "limits.max_seconds_per_point must be in (0, {MAX_SECONDS_BOUND}], got {t}"
                )));
            }
        }
        Ok(())
    }

    /// Check a study of `n1 × n2` points against [`Limits::max_points`] (saturating: any
    /// `usize` is accepted and compared, nothing is allocated). Returns the number of points.
    pub fn check_points(&self, n1: usize, n2: usize) -> Result<usize, Error> {
        let n = n1.saturating_mul(n2);
        if n > self.max_points.max(0) as usize {
            return Err(Error::StudyFile(format!(
                "{n1} × {n2} = {n} points exceed limits.max_points = {}",
                self.max_points
            )));
        }
        Ok(n)
    }
}

/// Run `job` under a wall-clock limit of `seconds` (`None`: on the calling thread, no limit).
///
/// Two layers stop a point that runs too long:
///
/// 1. **Cooperative.** The job runs with a [`system::deadline`] in force on its thread, so the
///    engines stop themselves at the limit: the integrators between steps, the harmonic balance
///    solvers between iterations, shooting between flow steps. A job that ends after the
///    limit, however it ends, becomes `Err` with a message starting with [`TIME_LIMIT`] and
///    naming what the engine reported.
/// 2. **Watchdog.** The job runs on a thread of its own and the caller waits at most
///    `seconds × 1.1 + 1 s` for it, for work the deadline does not reach (a model that hands
///    work to other threads). Over that, `Err` with [`TIME_LIMIT`] and the caller goes on; the
///    abandoned job ends by itself (every engine has a step budget, [`Limits::max_steps`]) and
///    its result is dropped.
///
/// A panic in the job becomes an `Err` with the panic's message.
pub fn run_with_time_limit<T: Send + 'static>(
    seconds: Option<f64>,
    job: impl FnOnce() -> Result<T, String> + Send + 'static,
) -> Result<T, String> {
    let Some(limit) = seconds else {
        return job();
    };
    let budget =
        std::time::Duration::try_from_secs_f64(limit.max(0.0)).unwrap_or(std::time::Duration::MAX);
    let (tx, rx) = std::sync::mpsc::sync_channel(1);
    let spawned = std::thread::Builder::new()
        .name("geardyn-point".to_owned())
        .spawn(move || {
            let start = std::time::Instant::now();
            let deadline = start.checked_add(budget);
            let r = system::deadline::scope(deadline, || {
                std::panic::catch_unwind(std::panic::AssertUnwindSafe(job))
                    .unwrap_or_else(|p| Err(crate::user::panic_message(p.as_ref())))
            });
            let r = if start.elapsed() >= budget {
                Err(match r {
                    Err(e) => format!(
                        "{TIME_LIMIT}: the point ran longer than limits.max_seconds_per_point = \
                         {limit} s and was stopped by its solver ({e})"
                    ),
                    Ok(_) => format!(
                        "{TIME_LIMIT}: the point ran longer than limits.max_seconds_per_point = \
                         {limit} s"
                    ),
                })
            } else {
                r
            };
            // The receiver may have given up (watchdog): nothing to do then.
            let _ = tx.send(r);
        });
    if let Err(e) = spawned {
        return Err(format!("{TIME_LIMIT}: no thread for the point ({e})"));
    }
    let grace = budget
        .checked_mul(11)
        .map(|d| d / 10)
        .and_then(|d| d.checked_add(std::time::Duration::from_secs(1)))
        .unwrap_or(std::time::Duration::MAX);
    match rx.recv_timeout(grace) {
        Ok(r) => r,
        Err(std::sync::mpsc::RecvTimeoutError::Timeout) => Err(format!(
            "{TIME_LIMIT}: the point ran longer than limits.max_seconds_per_point = {limit} s \
             and was abandoned (its solver did not stop at the deadline)"
        )),
        Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => {
            Err("internal error: the point's thread ended without a result".to_owned())
        }
    }
}

/// The inputs of one point: overrides with the swept values on top.
pub type Point = BTreeMap<String, Value>;

/// Apply `name = value` overrides to any serde parameter struct (through JSON), so that a user
/// can set any field by its Rust name: numbers into numeric fields (integers only into integer
/// fields), names into choice fields (kebab-case: `"printed-eq20"` for the variant
/// `PrintedEq20`), flags into `bool` fields, lists into array/tuple fields. A name not found at
/// the top level is looked up one level down (e.g. Liu's `readings.rigid_acceleration` as
/// `rigid_acceleration`). Errors name the field and what it takes.
pub fn apply_values<T: Serialize + DeserializeOwned>(
    base: &T,
    overrides: &BTreeMap<String, Value>,
) -> Result<T, Error> {
    let mut v = serde_json::to_value(base).map_err(|e| Error::StudyFile(e.to_string()))?;
    if !v.is_object() {
        return Err(Error::StudyFile("parameter set is not a struct".to_owned()));
    }
    for (k, x) in overrides {
        let slot = find_slot(&mut v, k)
            .map_err(|names| {
                Error::StudyFile(format!(
                    "parameter `{k}` is ambiguous: write one of {}",
                    names.join(", ")
                ))
            })?
            .ok_or_else(|| {
                Error::StudyFile(format!(
                    "unknown parameter `{k}`; parameters: {}",
                    field_names(base).join(", ")
                ))
            })?;
        let old = slot.clone();
        let candidates: Vec<serde_json::Value> = match (x, &old) {
            // A name: try the serde spellings of a variant (CamelCase, snake_case, as given).
            (Value::Text(t), serde_json::Value::String(_)) => {
                [kebab_to_camel(t), t.replace('-', "_"), t.clone()]
                    .into_iter()
                    .map(serde_json::Value::String)
                    .collect()
            }
            _ => vec![to_json(k, x, &old)?],
        };
        // Deserialise after each field so that an out-of-type value names its field.
        let mut last = None;
        for c in candidates {
            if let Ok(Some(slot)) = find_slot(&mut v, k) {
                *slot = c;
            }
            match serde_json::from_value::<T>(v.clone()) {
                Ok(_) => {
                    last = None;
                    break;
                }
                Err(e) => last = Some(e.to_string()),
            }
        }
        if let Some(e) = last {
            if e.contains("unknown variant") {
                return Err(Error::StudyFile(format!(
                    "parameter `{k}` = \"{}\" is not an option; options: \"{}\"",
                    x.label(),
                    expected_names(&e).join("\", \"")
                )));
            }
            return Err(Error::StudyFile(format!(
                "parameter `{k}` = {}: {e}",
                x.label()
            )));
        }
    }
    serde_json::from_value(v).map_err(|e| Error::StudyFile(e.to_string()))
}

/// [`apply_values`] with numbers only (the form of the paper studies).
pub fn apply_overrides<T: Serialize + DeserializeOwned>(
    base: &T,
    overrides: &BTreeMap<String, f64>,
) -> Result<T, Error> {
    let o = overrides
        .iter()
        .map(|(k, v)| (k.clone(), Value::Num(*v)))
        .collect();
    apply_values(base, &o)
}

/// The field an override names: a dotted path (`readings.rigid_acceleration`) walks the
/// nested structs; a bare name is a top-level field, else the one nested field of that name.
/// A bare name that two nested structs hold is ambiguous: `Err` with the dotted names.
fn find_slot<'a>(
    v: &'a mut serde_json::Value,
    k: &str,
) -> Result<Option<&'a mut serde_json::Value>, Vec<String>> {
    if k.contains('.') {
        let mut cur = v;
        for seg in k.split('.') {
            match cur.as_object_mut().and_then(|o| o.get_mut(seg)) {
                Some(next) => cur = next,
                None => return Ok(None),
            }
        }
        return Ok(Some(cur));
    }
    let Some(obj) = v.as_object_mut() else {
        return Ok(None);
    };
    if obj.contains_key(k) {
        return Ok(obj.get_mut(k));
    }
    let holders: Vec<String> = obj
        .iter()
        .filter(|(_, inner)| inner.as_object().is_some_and(|o| o.contains_key(k)))
        .map(|(name, _)| name.clone())
        .collect();
    match holders.as_slice() {
        [] => Ok(None),
        [one] => Ok(obj
            .get_mut(one)
            .and_then(|o| o.as_object_mut())
            .and_then(|o| o.get_mut(k))),
        many => Err(many.iter().map(|h| format!("{h}.{k}")).collect()),
    }
}

/// The settable fields of a parameter struct (top level and one level down).
pub fn field_names<T: Serialize>(base: &T) -> Vec<String> {
    let mut names = Vec::new();
    if let Ok(serde_json::Value::Object(o)) = serde_json::to_value(base) {
        for (k, v) in o {
            match v {
                serde_json::Value::Object(inner) => names.extend(inner.keys().cloned()),
                _ => names.push(k),
            }
        }
    }
    names
}

fn to_json(k: &str, x: &Value, old: &serde_json::Value) -> Result<serde_json::Value, Error> {
    use serde_json::Value as J;
    let wrong =
        |takes: &str| Error::StudyFile(format!("parameter `{k}` takes {takes}, got {}", x.label()));
    Ok(match (old, x) {
        (J::Number(n), Value::Num(f)) if n.is_u64() || n.is_i64() => {
            if f.fract() != 0.0 || f.abs() > 9.0e15 {
                return Err(wrong("an integer"));
            }
            if *f >= 0.0 {
                J::from(*f as u64)
            } else {
                J::from(*f as i64)
            }
        }
        (J::Number(_), Value::Num(f)) => J::from(*f),
        (J::Number(_), _) => return Err(wrong("a number")),
        (J::Bool(_), Value::Bool(b)) => J::Bool(*b),
        (J::Bool(_), _) => return Err(wrong("true or false")),
        (J::String(_), Value::Text(s)) => J::String(kebab_to_camel(s)),
        (J::String(cur), _) => {
            return Err(wrong(&format!(
                "a name (e.g. `{k} = \"{}\"`)",
                display_name(cur)
            )));
        }
        (J::Array(_) | J::Null, Value::List(v)) => J::from(v.clone()),
        (J::Array(a), _) => return Err(wrong(&format!("a list of {} numbers", a.len()))),
        _ => return Err(wrong("a value of another kind")),
    })
}

/// `PrintedEq20` → `printed-eq20`.
pub fn camel_to_kebab(s: &str) -> String {
    let mut out = String::new();
    for (i, c) in s.chars().enumerate() {
        if c.is_ascii_uppercase() {
            if i > 0 {
                out.push('-');
            }
            out.push(c.to_ascii_lowercase());
        } else {
            out.push(c);
        }
    }
    out
}

/// `printed-eq20` → `PrintedEq20`.
pub fn kebab_to_camel(s: &str) -> String {
    s.split('-')
        .map(|w| {
            let mut c = w.chars();
            match c.next() {
                Some(f) => f.to_ascii_uppercase().to_string() + c.as_str(),
                None => String::new(),
            }
        })
        .collect()
}

/// The study-file spelling of a serde variant name: `PrintedEq20` → `printed-eq20`,
/// `two_terms` → `two-terms`.
pub fn display_name(raw: &str) -> String {
    if raw.contains('_') || raw.chars().all(|c| !c.is_ascii_uppercase()) {
        raw.replace('_', "-").to_ascii_lowercase()
    } else {
        camel_to_kebab(raw)
    }
}

/// The names listed after "expected" in a serde unknown-variant message.
fn expected_names(message: &str) -> Vec<String> {
    let tail = message.split_once("expected").map_or("", |(_, t)| t);
    tail.split('`')
        .skip(1)
        .step_by(2)
        .map(display_name)
        .collect()
}

/// The names of a unit-variant enum in study-file spelling, read from serde's error for an
/// unknown variant.
pub fn variant_names<T: DeserializeOwned>() -> Vec<String> {
    match serde_json::from_value::<T>(serde_json::Value::String("\u{1}".to_owned())) {
        Ok(_) => Vec::new(),
        Err(e) => expected_names(&e.to_string()),
    }
}

/// A choice by name into an enum `E` (study-file spelling); errors list the options.
pub fn choice<E: DeserializeOwned>(field: &str, v: &Value) -> Result<E, Error> {
    let opts = || variant_names::<E>().join("\", \"");
    match v {
        Value::Text(s) => [kebab_to_camel(s), s.replace('-', "_"), s.clone()]
            .into_iter()
            .find_map(|c| serde_json::from_value(serde_json::Value::String(c)).ok())
            .ok_or_else(|| {
                Error::StudyFile(format!(
                    "`{field}` = \"{s}\" is not an option; options: \"{}\"",
                    opts()
                ))
            }),
        other => Err(Error::StudyFile(format!(
            "`{field}` takes a name, got {}; options: \"{}\"",
            other.label(),
            opts()
        ))),
    }
}

#[cfg(test)]
#[allow(clippy::float_cmp)] // exact: values are copied, not computed
mod dotted_tests {
    use super::*;
    use serde::Deserialize;

    #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
    struct Inner {
        k: f64,
        only_a: f64,
    }
    #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
    struct Outer {
        top: f64,
        a: Inner,
        b: Inner,
    }

    fn base() -> Outer {
        let i = Inner {
            k: 1.0,
            only_a: 2.0,
        };
        Outer {
            top: 0.0,
            a: i.clone(),
            b: i,
        }
    }

    fn set(name: &str, v: f64) -> Result<Outer, Error> {
        let o: BTreeMap<String, Value> = [(name.to_owned(), Value::Num(v))].into();
        apply_values(&base(), &o)
    }

    #[test]
    fn dotted_paths_address_nested_fields() {
        assert_eq!(set("a.k", 5.0).unwrap().a.k, 5.0);
        assert_eq!(set("b.k", 6.0).unwrap().b.k, 6.0);
        assert_eq!(set("b.k", 6.0).unwrap().a.k, 1.0);
        assert_eq!(set("top", 3.0).unwrap().top, 3.0);
        // both nested structs hold `only_a` too: the bare name is refused, not the first holder
        let o = set("only_a", 7.0).unwrap_err().to_string();
        assert!(o.contains("ambiguous"), "{o}");
        assert_eq!(set("a.only_a", 7.0).unwrap().a.only_a, 7.0);
    }

    #[test]
    fn a_bare_name_two_structs_hold_is_ambiguous() {
        let e = set("k", 5.0).unwrap_err().to_string();
        assert!(
            e.contains("parameter `k` is ambiguous: write one of a.k, b.k"),
            "{e}"
        );
        let e = set("a.nonesuch", 5.0).unwrap_err().to_string();
        assert!(e.contains("unknown parameter `a.nonesuch`"), "{e}");
    }
}
