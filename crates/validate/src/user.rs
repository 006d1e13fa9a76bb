//! User studies: `cargo xtask study <file.toml>` (format documented in `docs/studies.md`).

use std::collections::BTreeMap;

use rayon::prelude::*;
use serde::{Deserialize, Serialize, de::DeserializeOwned};

use crate::error::{Error, check_name};
use crate::figure::{Figure, Series};
use crate::table::{Cell, Table};

/// One swept parameter: a range (`from`, `to`, `steps`, linear) or explicit `values`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sweep {
    /// Parameter name (a field of the model's parameter struct, or a solver input such as the
    /// excitation frequency; see `docs/studies.md`).
    pub parameter: String,
    /// Start of a linear range.
    pub from: Option<f64>,
    /// End of a linear range (inclusive).
    pub to: Option<f64>,
    /// Number of points of the range (≥ 2).
    pub steps: Option<usize>,
    /// Explicit values (instead of a range).
    pub values: Option<Vec<f64>>,
}

impl Sweep {
    /// The swept values, in order.
    pub fn points(&self) -> Result<Vec<f64>, Error> {
        let bad = |m: String| Error::StudyFile(format!("sweep of `{}`: {m}", self.parameter));
        let v = match (&self.values, self.from, self.to, self.steps) {
            (Some(v), None, None, None) => v.clone(),
            (None, Some(a), Some(b), Some(n)) => {
                if n < 2 {
                    return Err(bad(format!("steps must be >= 2, got {n}")));
                }
                (0..n)
                    .map(|i| a + (b - a) * i as f64 / (n - 1) as f64)
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
        if let Some(x) = v.iter().find(|x| !x.is_finite()) {
            return Err(bad(format!("values must be finite, got {x}")));
        }
        Ok(v)
    }
}

/// Which solver evaluates each point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[non_exhaustive]
pub enum Method {
    /// Time integration to steady state (`timestep` crate).
    TimeStepping,
    /// Harmonic balance (`hbm` crate).
    Hbm,
    /// Closed-form kinematics/geometry (no dynamics).
    Kinematics,
}

/// Solver choice and settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Solver {
    /// `time-stepping`, `hbm` or `kinematics`.
    pub method: Method,
    /// Method settings by name (e.g. `periods`, `transient_periods`, `harmonics`, `tolerance`);
    /// unknown names are an error of the model adapter.
    #[serde(default)]
    pub settings: BTreeMap<String, f64>,
}

/// A user study file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UserStudy {
    /// File-name stem of the outputs (`a-z 0-9 - _ .`).
    pub name: String,
    /// Free description copied into the summary.
    #[serde(default)]
    pub description: String,
    /// Model: see [`MODELS`].
    pub model: String,
    /// Parameter overrides `name = value`, applied on top of the paper's parameter set.
    #[serde(default)]
    pub overrides: BTreeMap<String, f64>,
    /// The first (x-axis) sweep; absent = a single point.
    pub sweep: Option<Sweep>,
    /// The optional second sweep (one curve per value).
    pub sweep2: Option<Sweep>,
    /// Solver.
    pub solver: Solver,
}

impl UserStudy {
    /// Parse a study file.
    pub fn parse(text: &str) -> Result<Self, Error> {
        let s: UserStudy = toml::from_str(text).map_err(|e| Error::StudyFile(e.to_string()))?;
        check_name(&s.name)?;
        if let Some((k, v)) = s.overrides.iter().find(|(_, v)| !v.is_finite()) {
            return Err(Error::StudyFile(format!(
                "override `{k}` must be finite, got {v}"
            )));
        }
        if let Some((k, v)) = s.solver.settings.iter().find(|(_, v)| !v.is_finite()) {
            return Err(Error::StudyFile(format!(
                "setting `{k}` must be finite, got {v}"
            )));
        }
        if !MODELS.iter().any(|(m, _)| *m == s.model) {
            return Err(Error::StudyFile(format!(
                "unknown model `{}`; known: {}",
                s.model,
                MODELS
                    .iter()
                    .map(|(m, _)| *m)
                    .collect::<Vec<_>>()
                    .join(", ")
            )));
        }
        Ok(s)
    }
}

/// What a user study produced.
#[derive(Debug, Clone)]
pub struct UserStudyOutput {
    /// One row per point: swept parameters then the model's outputs.
    pub table: Table,
    /// One figure per output quantity (x = first sweep, one curve per second-sweep value).
    pub figures: Vec<Figure>,
    /// JSON summary: the study as read, the output ranges, failed points.
    pub summary: serde_json::Value,
}

/// Models known to `cargo xtask study`, with whether they are wired to a solver yet.
pub const MODELS: [(&str, &str); 4] = [
    (
        "karpov2017-kinematics",
        "Karpov 2017 centrodes: δ, ε_max (method = kinematics)",
    ),
    (
        "karpov2017",
        "Karpov 2017 oscillator with variable mesh frequency",
    ),
    ("liu2021", "Liu 2021 NFG rattle model"),
    ("yu2021", "Yu 2021 6-DOF spur pair with dynamic backlash"),
];

/// Apply `name = value` overrides to any serde parameter struct (through JSON), so that a user
/// can set any numeric field by its Rust name; unknown names are an error listing the fields.
pub fn apply_overrides<T: Serialize + DeserializeOwned>(
    base: &T,
    overrides: &BTreeMap<String, f64>,
) -> Result<T, Error> {
    let mut v = serde_json::to_value(base).map_err(|e| Error::StudyFile(e.to_string()))?;
    let obj = v
        .as_object_mut()
        .ok_or_else(|| Error::StudyFile("parameter set is not a struct".to_owned()))?;
    for (k, x) in overrides {
        match obj.get_mut(k) {
            Some(slot) if slot.is_u64() || slot.is_i64() => {
                // Integer fields (teeth numbers, j, …) take integral values only.
                if x.fract() != 0.0 || x.abs() > 9.0e15 {
                    return Err(Error::StudyFile(format!(
                        "parameter `{k}` is an integer, got {x}"
                    )));
                }
                *slot = if *x >= 0.0 {
                    serde_json::Value::from(*x as u64)
                } else {
                    serde_json::Value::from(*x as i64)
                };
            }
            Some(slot) if slot.is_number() => {
                *slot = serde_json::Value::from(*x);
            }
            _ => {
                let names: Vec<&String> = obj
                    .iter()
                    .filter(|(_, v)| v.is_number())
                    .map(|(k, _)| k)
                    .collect();
                return Err(Error::StudyFile(format!(
                    "unknown numeric parameter `{k}`; numeric fields: {names:?}"
                )));
            }
        }
    }
    serde_json::from_value(v).map_err(|e| Error::StudyFile(e.to_string()))
}

/// Run a user study: every point (in parallel, collected in order) — `on_point` is called after
/// each point (progress bar). A point whose model or solver fails is recorded (NaN outputs and
/// the message in the summary), it does not abort the study.
pub fn run_user_study(
    study: &UserStudy,
    on_point: impl Fn() + Sync,
) -> Result<UserStudyOutput, Error> {
    let (outputs, eval) = crate::studies::user_adapter(&study.model, &study.solver)?;
    let xs = match &study.sweep {
        Some(s) => s.points()?,
        None => vec![f64::NAN],
    };
    let ys = match &study.sweep2 {
        Some(s) => s.points()?,
        None => vec![f64::NAN],
    };
    let mut grid = Vec::with_capacity(xs.len() * ys.len());
    for &y in &ys {
        for &x in &xs {
            grid.push((x, y));
        }
    }
    let results: Vec<Result<Vec<f64>, Error>> = grid
        .par_iter()
        .map(|&(x, y)| {
            let mut params = study.overrides.clone();
            if let Some(s) = &study.sweep {
                params.insert(s.parameter.clone(), x);
            }
            if let Some(s) = &study.sweep2 {
                params.insert(s.parameter.clone(), y);
            }
            let r = eval(&params);
            on_point();
            r
        })
        .collect();

    // A study-file error (unknown or ill-typed parameter) is the user's configuration, not a
    // failed point: report it once.
    for r in &results {
        if let Err(Error::StudyFile(m)) = r {
            return Err(Error::StudyFile(m.clone()));
        }
    }
    let mut cols: Vec<(&str, &str)> = Vec::new();
    if let Some(s) = &study.sweep {
        cols.push((s.parameter.as_str(), ""));
    }
    if let Some(s) = &study.sweep2 {
        cols.push((s.parameter.as_str(), ""));
    }
    cols.extend(outputs.iter().copied());
    let mut table = Table::new(&study.name, &cols);
    let mut failures = Vec::new();
    for (&(x, y), r) in grid.iter().zip(&results) {
        let mut row: Vec<Cell> = Vec::new();
        if study.sweep.is_some() {
            row.push(Cell::Num(x));
        }
        if study.sweep2.is_some() {
            row.push(Cell::Num(y));
        }
        match r {
            Ok(v) => row.extend(v.iter().map(|&z| Cell::Num(z))),
            Err(e) => {
                failures.push(serde_json::json!({"x": x, "y": y, "error": e.to_string()}));
                row.extend(outputs.iter().map(|_| Cell::Num(f64::NAN)));
            }
        }
        table.push(row)?;
    }

    let mut figures = Vec::new();
    let mut ranges = serde_json::Map::new();
    for (k, (name, unit)) in outputs.iter().enumerate() {
        let vals: Vec<f64> = results
            .iter()
            .filter_map(|r| r.as_ref().ok().map(|v| v[k]))
            .filter(|v| v.is_finite())
            .collect();
        let (lo, hi) = vals
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            });
        ranges.insert(
            (*name).to_owned(),
            serde_json::json!({"unit": unit, "min": crate::fmt6(lo), "max": crate::fmt6(hi)}),
        );
        if let Some(s) = &study.sweep {
            let fname = format!("{}_{}", study.name, sanitize(name));
            let mut fig = Figure::new(
                &fname,
                &format!("{}: {name}", study.name),
                (&s.parameter, ""),
                (name, unit),
            );
            for (j, &y) in ys.iter().enumerate() {
                let pts: Vec<(f64, f64)> = xs
                    .iter()
                    .enumerate()
                    .map(|(i, &x)| {
                        let r = &results[j * xs.len() + i];
                        (x, r.as_ref().map_or(f64::NAN, |v| v[k]))
                    })
                    .collect();
                let label = match &study.sweep2 {
                    Some(s2) => format!("{} = {}", s2.parameter, crate::fmt6(y)),
                    None => (*name).to_owned(),
                };
                fig.push(Series::line(label, pts));
            }
            figures.push(fig);
        }
    }
    let summary = serde_json::json!({
        "study": study,
        "points": grid.len(),
        "failed_points": failures,
        "outputs": ranges,
        "significant_digits": crate::SIGNIFICANT_DIGITS,
    });
    Ok(UserStudyOutput {
        table,
        figures,
        summary,
    })
}

fn sanitize(s: &str) -> String {
    s.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '-'
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, Serialize, Deserialize, PartialEq)]
    struct P {
        a: f64,
        b: f64,
        name: String,
    }

    #[test]
    fn overrides_by_name() {
        let p = P {
            a: 1.0,
            b: 2.0,
            name: "x".into(),
        };
        let mut o = BTreeMap::new();
        o.insert("b".to_owned(), 5.0);
        let q = apply_overrides(&p, &o).unwrap();
        assert_eq!(
            q,
            P {
                a: 1.0,
                b: 5.0,
                name: "x".into()
            }
        );
        o.insert("c".to_owned(), 1.0);
        assert!(apply_overrides(&p, &o).is_err());
        #[derive(Debug, Serialize, Deserialize, PartialEq)]
        struct Q {
            n: u32,
        }
        let mut o = BTreeMap::new();
        o.insert("n".to_owned(), 3.0);
        assert_eq!(apply_overrides(&Q { n: 1 }, &o).unwrap(), Q { n: 3 });
        o.insert("n".to_owned(), 2.5);
        assert!(apply_overrides(&Q { n: 1 }, &o).is_err());
        let mut o = BTreeMap::new();
        o.insert("name".to_owned(), 1.0);
        assert!(apply_overrides(&p, &o).is_err());
    }

    #[test]
    fn sweeps() {
        let s = Sweep {
            parameter: "x".into(),
            from: Some(0.0),
            to: Some(1.0),
            steps: Some(3),
            values: None,
        };
        assert_eq!(s.points().unwrap().len(), 3);
        let s = Sweep {
            parameter: "x".into(),
            from: Some(0.0),
            to: None,
            steps: Some(3),
            values: None,
        };
        assert!(s.points().is_err());
    }

    #[test]
    fn parse_rejects_unknown_model() {
        let t = "name = \"a\"\nmodel = \"nope\"\n[solver]\nmethod = \"hbm\"\n";
        assert!(UserStudy::parse(t).is_err());
    }
}
