//! Helpers of the full-result solves ([`Model::solve_full`](super::Model::solve_full), the
//! Python package's `solve`): parameters as serde overrides of a base set, and settings taken
//! one by one with the study's names, bounds and messages.

use std::collections::BTreeMap;

use serde::Serialize;
use serde::de::DeserializeOwned;
use serde_json::Value as J;

use super::{Method, PointError, Value, check_settings};

/// Settings of a full-result solve by name.
pub type JsonSettings = BTreeMap<String, J>;

/// Overlay `over` on `base`, recursively for objects; every key of `over` must exist in `base`
/// (a typo is an error naming the known keys), except where `base` holds a non-object
/// (replaced whole, e.g. an enum).
pub fn merge(path: &str, base: &mut J, over: &J) -> Result<(), PointError> {
    match (base, over) {
        (J::Object(b), J::Object(o)) => {
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
                        return Err(PointError::Input(format!(
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

/// `base` with the JSON overrides `over` applied ([`merge`]), deserialised back into `T`.
pub fn with_overrides<T: Serialize + DeserializeOwned>(
    what: &str,
    base: &T,
    over: &J,
) -> Result<T, PointError> {
    let mut v = serde_json::to_value(base).map_err(|e| PointError::Input(e.to_string()))?;
    if !over.is_null() {
        merge("", &mut v, over)?;
    }
    serde_json::from_value(v).map_err(|e| PointError::Input(format!("{what}: {e}")))
}

/// A result as JSON.
pub fn to_json<T: Serialize>(x: &T) -> Result<J, PointError> {
    serde_json::to_value(x).map_err(|e| PointError::Unrepresentable(e.to_string()))
}

/// Remove the number setting `key` (`default` if absent).
pub fn take_f64(s: &mut JsonSettings, key: &str, default: f64) -> Result<f64, PointError> {
    match s.remove(key) {
        None => Ok(default),
        Some(v) => v
            .as_f64()
            .ok_or_else(|| PointError::Input(format!("setting `{key}` must be a number"))),
    }
}

/// Remove the flag setting `key` (`default` if absent).
pub fn take_bool(s: &mut JsonSettings, key: &str, default: bool) -> Result<bool, PointError> {
    match s.remove(key) {
        None => Ok(default),
        Some(v) => v
            .as_bool()
            .ok_or_else(|| PointError::Input(format!("setting `{key}` must be true or false"))),
    }
}

/// Refuse a setting no one took.
pub fn no_leftovers(method: &str, s: JsonSettings) -> Result<(), PointError> {
    match s.keys().next() {
        None => Ok(()),
        Some(k) => Err(PointError::Input(format!(
            "unknown setting `{k}` for method `{method}`"
        ))),
    }
}

/// Check settings through the study's definitions ([`check_settings`]): a bad one is the
/// study's message (name, kind, bound).
pub fn study_settings(
    model: &str,
    method: Method,
    given: &serde_json::Map<String, J>,
) -> Result<(), PointError> {
    let mut map = BTreeMap::new();
    for (k, v) in given {
        let value = match v {
            J::Number(n) => Value::Num(n.as_f64().unwrap_or(f64::NAN)),
            J::String(t) => Value::Text(t.clone()),
            J::Bool(b) => Value::Bool(*b),
            _ => {
                return Err(PointError::Input(format!(
                    "setting `{k}` must be a number, got {v}"
                )));
            }
        };
        map.insert(k.clone(), value);
    }
    check_settings(model, method, &map)
}

/// Settings (numbers, names) as study values, for the study code's checks.
pub fn study_values(s: JsonSettings) -> Result<BTreeMap<String, Value>, PointError> {
    let mut map = BTreeMap::new();
    for (k, v) in s {
        let value = match &v {
            J::Number(n) => Value::Num(n.as_f64().unwrap_or(f64::NAN)),
            J::String(t) => Value::Text(t.clone()),
            _ => {
                return Err(PointError::Input(format!(
                    "setting `{k}` must be a number, got {v}"
                )));
            }
        };
        map.insert(k, value);
    }
    Ok(map)
}

/// A shooting record as a result dict (a returned orbit converged).
pub fn shooting_json(r: &super::Record) -> J {
    let mut o: serde_json::Map<String, J> = r
        .columns()
        .iter()
        .map(|c| (c.name.clone(), serde_json::json!(c.value)))
        .collect();
    o.insert("converged".to_owned(), serde_json::json!(true));
    J::Object(o)
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn merge_rejects_unknown_keys_and_keeps_nested_ones() {
        let mut base = json!({"a": 1.0, "r": {"x": "derived", "y": "mean"}});
        merge("", &mut base, &json!({"r": {"x": "printed_eq20"}})).unwrap();
        assert_eq!(
            base,
            json!({"a": 1.0, "r": {"x": "printed_eq20", "y": "mean"}})
        );
        let e = merge("", &mut base, &json!({"b": 2.0})).unwrap_err();
        assert!(matches!(e, PointError::Input(_)));
        assert!(e.to_string().contains("`b`"));
    }
}
