//! A model's self-description: parameters and outputs as quantities with units, choices and
//! readings with their options, methods with their settings and bounds. `geardyn models`, the
//! Python `describe()` and the model table of `docs/studies.md` are printed from it.

use serde::Serialize;

use super::Method;
use super::overrides::{display_name, variant_names};

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

/// What a model says about itself ([`Model::describe`](super::Model::describe)).
#[derive(Debug, Clone, Serialize)]
pub struct ModelInfo {
    /// Numeric parameters.
    pub parameters: Vec<ParamInfo>,
    /// Choices and readings.
    pub choices: Vec<ChoiceInfo>,
    /// Methods with settings and outputs.
    pub methods: Vec<MethodInfo>,
}

/// Output columns `(name, unit)` from a static table.
pub(crate) fn outs(v: &[(&str, &str)]) -> Vec<(String, String)> {
    v.iter()
        .map(|(a, b)| ((*a).to_owned(), (*b).to_owned()))
        .collect()
}

/// The numeric fields (numbers and number lists) of a serde parameter struct, at any depth,
/// named by the dotted path that a point's overrides accept ([`apply_values`](super::apply_values):
/// `geometry.rp`, `backlash.b`; a top-level field by its bare name), with their units from
/// `unit` (called with the last segment of the path, the field's own name) and their values as
/// defaults. Text fields (enum choices) are not parameters.
pub(crate) fn params_of<T: Serialize>(base: &T, unit: fn(&str) -> &'static str) -> Vec<ParamInfo> {
    fn walk(
        prefix: &str,
        o: serde_json::Map<String, serde_json::Value>,
        unit: fn(&str) -> &'static str,
        out: &mut Vec<ParamInfo>,
    ) {
        for (k, v) in o {
            let name = if prefix.is_empty() {
                k.clone()
            } else {
                format!("{prefix}.{k}")
            };
            match v {
                serde_json::Value::Number(n) => out.push(ParamInfo {
                    unit: unit(&k).to_owned(),
                    name,
                    default: n.to_string(),
                }),
                serde_json::Value::Array(a) if a.iter().all(|x| x.is_number()) => {
                    out.push(ParamInfo {
                        unit: unit(&k).to_owned(),
                        name,
                        default: serde_json::Value::Array(a).to_string(),
                    });
                }
                serde_json::Value::Object(inner) => walk(&name, inner, unit, out),
                _ => {}
            }
        }
    }
    let mut out = Vec::new();
    if let Ok(serde_json::Value::Object(o)) = serde_json::to_value(base) {
        walk("", o, unit, &mut out);
    }
    out
}

/// A choice over the variants of the enum `E`, with `default` as its default.
pub(crate) fn choice_info<E: serde::de::DeserializeOwned + Serialize>(
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

/// The default of setting `name` in `defs` as a number (tests of the documented defaults).
#[cfg(test)]
pub(crate) fn default_of(defs: &[SettingDef], name: &str) -> f64 {
    match defs.iter().find(|d| d.name == name).map(|d| d.kind) {
        Some(Kind::Num { default, .. }) => default,
        Some(Kind::Int {
            default: Some(d), ..
        }) => d as f64,
        other => panic!("{name}: {other:?}"),
    }
}
