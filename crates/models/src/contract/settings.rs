//! Solver settings read against their definitions ([`SettingDef`]), and the checks of a point's
//! choices and initial state that every model shares.

use std::collections::BTreeMap;

use super::{Context, Kind, Method, Point, PointError, SettingDef, Value};

/// Settings read against their definitions: every given one checked (name, kind, bounds), the
/// defaults filled in.
#[derive(Debug, Clone)]
pub struct Settings(BTreeMap<&'static str, Value>);

impl Settings {
    /// Check every given setting against `defs` (unknown names, kind, bounds) and fill the
    /// defaults. `legacy` lists old spellings `(old, new)` refused with a pointer to the new one.
    pub fn read(
        model: &str,
        method: Method,
        defs: &[SettingDef],
        given: &BTreeMap<String, Value>,
        legacy: &[(&str, &str)],
    ) -> Result<Self, PointError> {
        let mut out = BTreeMap::new();
        for (k, v) in given {
            if let Some((_, new)) = legacy.iter().find(|(old, _)| *old == k) {
                return Err(PointError::Input(format!(
                    "setting `{k}` = {} is the old spelling; write {new}",
                    v.label()
                )));
            }
            let Some(d) = defs.iter().find(|d| d.name == k) else {
                return Err(PointError::Input(format!(
                    "unknown {model} {} setting `{k}`; settings: {}",
                    method.name(),
                    defs.iter().map(|d| d.name).collect::<Vec<_>>().join(", ")
                )));
            };
            let bad = |want: String| {
                PointError::Input(format!("setting `{k}` must be {want}, got {}", v.label()))
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

    /// A number setting (NaN if absent).
    pub fn f(&self, k: &str) -> f64 {
        self.0.get(k).and_then(Value::as_num).unwrap_or(f64::NAN)
    }

    /// An integer setting (`None` if absent).
    pub fn u(&self, k: &str) -> Option<u64> {
        self.0.get(k).and_then(Value::as_num).map(|x| x as u64)
    }

    /// A name setting (`""` if absent).
    pub fn name(&self, k: &str) -> &str {
        match self.0.get(k) {
            Some(Value::Text(s)) => s,
            _ => "",
        }
    }
}

/// The error of a method the model does not offer.
pub(crate) fn wrong_method(model: &str, m: Method, allowed: &[Method]) -> PointError {
    PointError::Input(format!(
        "{model} has no solver.method = \"{}\"; use {}",
        m.name(),
        allowed
            .iter()
            .map(|a| format!("\"{}\"", a.name()))
            .collect::<Vec<_>>()
            .join(" or ")
    ))
}

/// Remove the choices (names) from a point, checking old numeric spellings.
pub(crate) fn take_choice(
    p: &mut Point,
    name: &str,
    legacy: Option<&str>,
) -> Result<Option<Value>, PointError> {
    match p.remove(name) {
        Some(Value::Num(x)) => Err(PointError::Input(format!(
            "`{name}` = {x}: choices are names now; write {}",
            legacy.unwrap_or("a name (see `geardyn models`)")
        ))),
        v => Ok(v),
    }
}

/// Refuse the old spellings `(old, new)` of a point's names.
pub(crate) fn reject_legacy(p: &Point, legacy: &[(&str, &str)]) -> Result<(), PointError> {
    for (old, new) in legacy {
        if let Some(v) = p.get(*old) {
            return Err(PointError::Input(format!(
                "`{old}` = {} is the old spelling; write {new}",
                v.label()
            )));
        }
    }
    Ok(())
}

/// Refuse an `initial` state for a method that takes none.
pub(crate) fn no_initial(model: &str, ctx: &Context<'_>) -> Result<(), PointError> {
    if ctx.initial.is_some() {
        return Err(PointError::Input(format!(
            "{model} with solver.method = \"{}\" takes no `initial` state",
            ctx.solver.method.name()
        )));
    }
    Ok(())
}
