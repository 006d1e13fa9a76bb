//! The values of a point (numbers, names, flags, lists), the solver choice and the work limits:
//! the vocabulary shared by every [`Model`](super::Model) and its front ends.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use super::PointError;
use system::format::fmt6;

/// Hard upper bound of [`Limits::max_points`].
pub const MAX_POINTS_BOUND: usize = 1_000_000;
/// Hard upper bound of [`Limits::max_steps`].
pub const MAX_STEPS_BOUND: u64 = 10_000_000_000;
/// Hard upper bound of [`Limits::max_seconds_per_point`] (a week).
pub const MAX_SECONDS_BOUND: f64 = 604_800.0;

/// A value of a point: a number, a name (choices and readings), a flag or a list of numbers
/// (initial states).
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

    /// A short rendering for messages, labels and CSV cells (numbers at six significant
    /// digits, [`fmt6`]).
    pub fn label(&self) -> String {
        match self {
            Value::Bool(b) => b.to_string(),
            Value::Num(x) => fmt6(*x),
            Value::Text(s) => s.clone(),
            Value::List(v) => format!(
                "[{}]",
                v.iter().map(|x| fmt6(*x)).collect::<Vec<_>>().join(", ")
            ),
        }
    }

    /// Refuse a non-finite number (alone or in a list); the message names `what`.
    pub fn check_finite(&self, what: &str) -> Result<(), PointError> {
        let bad = |x: f64| PointError::Input(format!("{what} must be finite, got {x}"));
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

/// The inputs of one point: parameter and choice names with their values.
pub type Point = BTreeMap<String, Value>;

/// Which solver evaluates each point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[non_exhaustive]
pub enum Method {
    /// Time integration to steady state (`timestep` crate or a model's own engine; Karpov's
    /// Duhamel quadrature is an engine of this method).
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
    /// "time limit", and the study goes on.
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
    pub fn check(&self) -> Result<(), PointError> {
        if !(1..=MAX_POINTS_BOUND as i64).contains(&self.max_points) {
            return Err(PointError::Input(format!(
                "limits.max_points must be in [1, {MAX_POINTS_BOUND}], got {}",
                self.max_points
            )));
        }
        if !(self.max_steps >= 1.0 && self.max_steps <= MAX_STEPS_BOUND as f64) {
            return Err(PointError::Input(format!(
                "limits.max_steps must be in [1, {MAX_STEPS_BOUND:e}], got {}",
                self.max_steps
            )));
        }
        if let Some(t) = self.max_seconds_per_point {
            if !(t > 0.0 && t <= MAX_SECONDS_BOUND) {
                return Err(PointError::Input(format!(
                    "limits.max_seconds_per_point must be in (0, {MAX_SECONDS_BOUND}], got {t}"
                )));
            }
        }
        Ok(())
    }

    /// Check a study of `n1 × n2` points against [`Limits::max_points`] (saturating: any
    /// `usize` is accepted and compared, nothing is allocated). Returns the number of points.
    pub fn check_points(&self, n1: usize, n2: usize) -> Result<usize, PointError> {
        let n = n1.saturating_mul(n2);
        if n > self.max_points.max(0) as usize {
            return Err(PointError::Input(format!(
                "{n1} × {n2} = {n} points exceed limits.max_points = {}",
                self.max_points
            )));
        }
        Ok(n)
    }

    /// Refuse a point that needs about `steps` integration steps (or panels), over
    /// [`Limits::max_steps`]; the message names `what`.
    pub fn need_steps(&self, what: &str, steps: f64) -> Result<(), PointError> {
        if steps.is_finite() && steps <= self.max_steps {
            Ok(())
        } else {
            Err(PointError::Compute(format!(
                "{what}: about {steps:.3e} steps needed, over limits.max_steps = {:e}",
                self.max_steps
            )))
        }
    }
}
