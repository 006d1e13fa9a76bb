//! Set any field of a serde parameter struct by its name: the overrides of a point applied to a
//! model's base parameter set, and the study-file spelling of enum choices.

use std::collections::BTreeMap;

use serde::{Serialize, de::DeserializeOwned};

use super::{PointError, Value};

/// Apply `name = value` overrides to any serde parameter struct (through JSON), so that a user
/// can set any field by its Rust name: numbers into numeric fields (integers only into integer
/// fields), names into choice fields (kebab-case: `"printed-eq20"` for the variant
/// `PrintedEq20`), flags into `bool` fields, lists into array/tuple fields.
///
/// A field is addressed by its dotted path (`readings.rigid_acceleration`, the canonical form,
/// [`field_names`]); a bare name not found at the top level is accepted when exactly one nested
/// struct holds it (Liu's `rigid_acceleration`). Errors are typed: a bare name two nested
/// structs hold is [`PointError::AmbiguousParameter`] naming every dotted path, a name that
/// addresses nothing [`PointError::UnknownParameter`] listing the valid paths; a value of the
/// wrong kind names the field and what it takes.
pub fn apply_values<T: Serialize + DeserializeOwned>(
    base: &T,
    overrides: &BTreeMap<String, Value>,
) -> Result<T, PointError> {
    let mut v = serde_json::to_value(base).map_err(|e| PointError::Input(e.to_string()))?;
    if !v.is_object() {
        return Err(PointError::Input(
            "parameter set is not a struct".to_owned(),
        ));
    }
    for (k, x) in overrides {
        let slot = find_slot(&mut v, k)
            .map_err(|paths| PointError::AmbiguousParameter {
                name: k.clone(),
                paths,
            })?
            .ok_or_else(|| PointError::UnknownParameter {
                name: k.clone(),
                paths: field_names(base),
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
                return Err(PointError::Input(format!(
                    "parameter `{k}` = \"{}\" is not an option; options: \"{}\"",
                    x.label(),
                    expected_names(&e).join("\", \"")
                )));
            }
            return Err(PointError::Input(format!(
                "parameter `{k}` = {}: {e}",
                x.label()
            )));
        }
    }
    serde_json::from_value(v).map_err(|e| PointError::Input(e.to_string()))
}

/// [`apply_values`] with numbers only (the form of the paper studies).
pub fn apply_overrides<T: Serialize + DeserializeOwned>(
    base: &T,
    overrides: &BTreeMap<String, f64>,
) -> Result<T, PointError> {
    let o = overrides
        .iter()
        .map(|(k, v)| (k.clone(), Value::Num(*v)))
        .collect();
    apply_values(base, &o)
}

/// The field an override names: a dotted path (`readings.rigid_acceleration`) walks the
/// nested structs; a bare name is a top-level field, else the one nested field of that name at
/// any depth. A bare name that two nested structs hold is ambiguous: `Err` with the dotted paths.
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
    let Some(obj) = v.as_object() else {
        return Ok(None);
    };
    if obj.contains_key(k) {
        return Ok(v.get_mut(k));
    }
    let mut holders = Vec::new();
    nested_holders(obj, k, "", &mut holders);
    match holders.as_slice() {
        [] => Ok(None),
        [one] => {
            let path = one.clone();
            find_slot(v, &path)
        }
        _ => Err(holders),
    }
}

/// The dotted paths of the fields named `k` in the structs nested in `o` (at any depth).
fn nested_holders(
    o: &serde_json::Map<String, serde_json::Value>,
    k: &str,
    prefix: &str,
    out: &mut Vec<String>,
) {
    for (name, inner) in o {
        if let Some(io) = inner.as_object() {
            let path = if prefix.is_empty() {
                name.clone()
            } else {
                format!("{prefix}.{name}")
            };
            if io.contains_key(k) {
                out.push(format!("{path}.{k}"));
            }
            nested_holders(io, k, &path, out);
        }
    }
}

/// The settable fields of a parameter struct by their canonical address: a top-level field by
/// its name, a field of a nested struct by its dotted path (`readings.rigid_acceleration`), at
/// any depth. A bare nested name is accepted by [`apply_values`] only when exactly one nested
/// struct holds it; the dotted path always works.
pub fn field_names<T: Serialize>(base: &T) -> Vec<String> {
    fn walk(prefix: &str, o: serde_json::Map<String, serde_json::Value>, out: &mut Vec<String>) {
        for (k, v) in o {
            let path = if prefix.is_empty() {
                k
            } else {
                format!("{prefix}.{k}")
            };
            match v {
                serde_json::Value::Object(inner) => walk(&path, inner, out),
                _ => out.push(path),
            }
        }
    }
    let mut names = Vec::new();
    if let Ok(serde_json::Value::Object(o)) = serde_json::to_value(base) {
        walk("", o, &mut names);
    }
    names
}

fn to_json(k: &str, x: &Value, old: &serde_json::Value) -> Result<serde_json::Value, PointError> {
    use serde_json::Value as J;
    let wrong = |takes: &str| {
        PointError::Input(format!("parameter `{k}` takes {takes}, got {}", x.label()))
    };
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
pub fn choice<E: DeserializeOwned>(field: &str, v: &Value) -> Result<E, PointError> {
    let opts = || variant_names::<E>().join("\", \"");
    match v {
        Value::Text(s) => [kebab_to_camel(s), s.replace('-', "_"), s.clone()]
            .into_iter()
            .find_map(|c| serde_json::from_value(serde_json::Value::String(c)).ok())
            .ok_or_else(|| {
                PointError::Input(format!(
                    "`{field}` = \"{s}\" is not an option; options: \"{}\"",
                    opts()
                ))
            }),
        other => Err(PointError::Input(format!(
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

    fn set(name: &str, v: f64) -> Result<Outer, PointError> {
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
        let e = set("k", 5.0).unwrap_err();
        assert!(
            e.to_string()
                .contains("parameter `k` is ambiguous: write one of a.k, b.k"),
            "{e}"
        );
        match e {
            PointError::AmbiguousParameter { name, paths } => {
                assert_eq!(name, "k");
                assert_eq!(paths, ["a.k", "b.k"]);
            }
            e => panic!("expected AmbiguousParameter, got {e:?}"),
        }
    }

    #[test]
    fn an_unknown_path_lists_the_valid_dotted_paths() {
        let all = ["a.k", "a.only_a", "b.k", "b.only_a", "top"];
        assert_eq!(field_names(&base()), all);
        for bad in ["a.nonesuch", "nonesuch", "c.k", "a.k.deeper", "top.k"] {
            match set(bad, 5.0).unwrap_err() {
                PointError::UnknownParameter { name, paths } => {
                    assert_eq!(name, bad);
                    assert_eq!(paths, all);
                }
                e => panic!("{bad}: expected UnknownParameter, got {e:?}"),
            }
        }
        let e = set("a.nonesuch", 5.0).unwrap_err().to_string();
        assert_eq!(
            e,
            "unknown parameter `a.nonesuch`; parameters: a.k, a.only_a, b.k, b.only_a, top"
        );
    }

    #[test]
    fn a_bare_name_one_struct_holds_is_accepted() {
        #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
        struct One {
            top: f64,
            a: Inner,
        }
        let base = One {
            top: 0.0,
            a: Inner {
                k: 1.0,
                only_a: 2.0,
            },
        };
        let o: BTreeMap<String, Value> = [("k".to_owned(), Value::Num(4.0))].into();
        assert_eq!(apply_values(&base, &o).unwrap().a.k, 4.0);
        // at any depth: `deep` is held only by `outer.a`
        #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
        struct Two {
            outer: One,
        }
        let two = Two { outer: base };
        let o: BTreeMap<String, Value> = [("only_a".to_owned(), Value::Num(9.0))].into();
        assert_eq!(apply_values(&two, &o).unwrap().outer.a.only_a, 9.0);
        assert_eq!(
            field_names(&two),
            ["outer.a.k", "outer.a.only_a", "outer.top"]
        );
    }
}
