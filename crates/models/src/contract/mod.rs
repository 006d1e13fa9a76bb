//! The model contract: what every model of geardyn offers its front ends (`geardyn study`,
//! `geardyn models`, the Python package), and the one [`REGISTRY`] that lists the models.
//!
//! A [`Model`] names itself, describes itself ([`ModelInfo`]: parameters with units and
//! defaults, choices and readings, methods with their settings, bounds and output columns) and
//! solves a [`Point`] by a [`Method`]: [`Model::build`] checks the method's settings once and
//! returns an [`Adapter`], whose `prepare` checks one point (the model's validating
//! constructor, every derived size against the [`Limits`]) and returns the [`Job`] that
//! computes its [`Record`]. A record carries each output with its name and unit, and the
//! front end checks it against the declared columns ([`Record::values_for`]).
//!
//! Shared by every model: the settings reader ([`Settings`]), the one accuracy check of the
//! time-stepping methods ([`run_stepped`]: repeat at a [`TIGHTER`] tolerance), the step
//! statistics, and the shooting solve on the `orbit` crate.
//!
//! Adding a model: a folder under `crates/models/src/` with a `registry.rs` that implements
//! [`Model`], and one line in [`REGISTRY`].

use std::collections::BTreeMap;

mod accuracy;
pub mod api;
pub mod continuation;
mod describe;
mod error;
pub(crate) mod lyapunov;
mod overrides;
mod record;
mod settings;
pub(crate) mod shoot;
pub(crate) mod spur;
mod value;

pub(crate) use accuracy::outs_stepped;
pub use accuracy::{
    CHANGE_COLUMN, STEP_STATISTICS, TIGHTER, TOLERANCE_CHECK, is_step_statistic, relative_change,
    run_stepped, step_statistics,
};
#[cfg(test)]
pub(crate) use describe::default_of;
pub use describe::{ChoiceInfo, Kind, MethodInfo, ModelInfo, ParamInfo, SettingDef};
pub(crate) use describe::{choice_info, outs, params_of};
pub use error::{PointError, WithContext};
pub use overrides::{
    apply_overrides, apply_values, camel_to_kebab, choice, display_name, field_names,
    kebab_to_camel, variant_names,
};
pub use record::{Output, Record};
pub use settings::Settings;
pub(crate) use settings::{no_initial, reject_legacy, take_choice, wrong_method};
pub use system::format::{fmt_sig, fmt6};
pub use value::{
    Limits, MAX_POINTS_BOUND, MAX_SECONDS_BOUND, MAX_STEPS_BOUND, Method, Point, Solver, Value,
};

/// The computation of one prepared point.
pub type Job = Box<dyn FnOnce() -> Result<Record, PointError> + Send>;

/// Checks one point and returns its computation.
pub type Preparer = Box<dyn Fn(&Point) -> Result<Job, PointError> + Sync>;

/// Output columns and the point preparer of a model under one solver.
pub struct Adapter {
    /// Output columns `(name, unit)`.
    pub outputs: Vec<(String, String)>,
    /// Check one point and return its computation.
    pub prepare: Preparer,
}

impl std::fmt::Debug for Adapter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Adapter")
            .field("outputs", &self.outputs)
            .finish_non_exhaustive()
    }
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

/// A named parameter set of a model (`geardyn.presets()` in Python).
#[derive(Debug, Clone, Copy)]
pub struct Preset {
    /// The set it belongs to: the model's name, or a part of it (`"liu2021-readings"`).
    pub set: &'static str,
    /// The preset's name (`"table1"`).
    pub name: &'static str,
    /// Its serde form.
    pub value: fn() -> serde_json::Value,
}

/// A model of geardyn, as its front ends see it.
pub trait Model: Sync {
    /// Name in a study file (`model = "liu2021"`).
    fn name(&self) -> &'static str;

    /// One line.
    fn description(&self) -> &'static str;

    /// Parameters, choices and readings, methods with settings and outputs.
    fn describe(&self) -> ModelInfo;

    /// Unit of a parameter (for CSV headers and axes; `"1"` if dimensionless or unknown).
    fn unit_of(&self, parameter: &str) -> &'static str;

    /// Check the solver's settings (every one against its bounds) and the initial state, and
    /// return the output columns and the point preparer.
    fn build(&self, ctx: &Context<'_>) -> Result<Adapter, PointError>;

    /// Solve one point by the solver of `ctx`: [`Model::build`], prepare, compute.
    fn solve(&self, point: &Point, ctx: &Context<'_>) -> Result<Record, PointError> {
        let adapter = self.build(ctx)?;
        let job = (adapter.prepare)(point)?;
        job()
    }

    /// The state coordinates a bifurcation section can show, `(name, unit)` in state order;
    /// `None`: the model has no bifurcation study.
    fn bifurcation_coordinates(&self) -> Option<&'static [(&'static str, &'static str)]> {
        None
    }

    /// Build the adapter of a bifurcation study (outputs [`bifurcation_outputs`], one job per
    /// parameter value) for the checked engine options (coordinate index set).
    fn build_bifurcation(
        &self,
        ctx: &Context<'_>,
        options: &timestep::BifurcationOptions,
    ) -> Result<Adapter, PointError> {
        let _ = (ctx, options);
        Err(PointError::Input(format!(
            "model `{}` has no [bifurcation] study",
            self.name()
        )))
    }

    /// The parameters a continuation ([`Model::continuation`]) can change, `(name, unit)`;
    /// empty: the model has no continuation.
    fn continuation_parameters(&self) -> &'static [(&'static str, &'static str)] {
        &[]
    }

    /// Continue the periodic orbit of `point` in a parameter (and codim-2 curves of its
    /// special points) as `request` asks, with the shooting settings of `ctx`'s solver
    /// ([`continuation::continue_on`]).
    fn continuation(
        &self,
        point: &Point,
        ctx: &Context<'_>,
        request: &continuation::ContinuationRequest,
    ) -> Result<continuation::ContinuationOutput, PointError> {
        let _ = (point, ctx, request);
        Err(PointError::Input(format!(
            "model `{}` has no [continuation] study",
            self.name()
        )))
    }

    /// The model's named parameter sets.
    fn presets(&self) -> Vec<Preset> {
        Vec::new()
    }

    /// The methods of [`Model::solve_full`] (names as the Python `solve` takes them).
    fn full_methods(&self) -> &'static [&'static str] {
        &[]
    }

    /// One point with the full result as JSON (time series, coefficients): the Python
    /// package's `solve`. `params` are serde overrides of the base parameter set; `settings`
    /// the method's settings by name (every one must be used).
    fn solve_full(
        &self,
        params: &serde_json::Value,
        method: &str,
        settings: BTreeMap<String, serde_json::Value>,
    ) -> Result<serde_json::Value, PointError> {
        let _ = (params, settings);
        Err(PointError::Input(format!(
            "{} has no full-result method `{method}`",
            self.name()
        )))
    }
}

impl std::fmt::Debug for dyn Model {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_tuple("Model").field(&self.name()).finish()
    }
}

/// Every model of geardyn. Adding a model is one line here.
pub static REGISTRY: &[&dyn Model] = &[
    &crate::karpov2017::registry::Kinematics,
    &crate::karpov2017::registry::Karpov,
    &crate::liu2021::registry::Liu,
    &crate::yu2021::registry::Yu,
    &crate::pair::registry::Pair,
];

/// The names of the registered models, in [`REGISTRY`] order.
pub fn names() -> Vec<&'static str> {
    REGISTRY.iter().map(|m| m.name()).collect()
}

/// The registered model of that name; the error lists the known names.
pub fn find(name: &str) -> Result<&'static dyn Model, PointError> {
    REGISTRY
        .iter()
        .copied()
        .find(|m| m.name() == name)
        .ok_or_else(|| {
            PointError::Input(format!(
                "unknown model `{name}`; known: {}",
                names().join(", ")
            ))
        })
}

/// One model's self-description as JSON: `{name, description, info}`.
pub fn describe_json(m: &dyn Model) -> serde_json::Value {
    serde_json::json!({
        "name": m.name(),
        "description": m.description(),
        "info": m.describe(),
        "continuation_parameters": m
            .continuation_parameters()
            .iter()
            .map(|(n, u)| serde_json::json!({"name": n, "unit": u}))
            .collect::<Vec<_>>(),
    })
}

/// Every registered model's self-description as JSON (`geardyn models --json`).
pub fn describe_all() -> serde_json::Value {
    serde_json::Value::Array(REGISTRY.iter().map(|m| describe_json(*m)).collect())
}

/// Check solver settings of `model` under `method` against the definitions `geardyn models`
/// prints — the code, bounds and messages of a study file's `[solver.settings]` — for front
/// ends that take settings by other routes (the Python package).
pub fn check_settings(
    model: &str,
    method: Method,
    given: &BTreeMap<String, Value>,
) -> Result<(), PointError> {
    let m = REGISTRY
        .iter()
        .find(|m| m.name() == model)
        .ok_or_else(|| PointError::Input(format!("unknown model `{model}`")))?;
    let info = m.describe();
    let d = info
        .methods
        .iter()
        .find(|d| d.method == method)
        .ok_or_else(|| wrong_method(model, method, &[]))?;
    Settings::read(model, method, &d.settings, given, &[]).map(|_| ())
}

/// The output columns of a bifurcation study: `motion`, `period`, `lambda` (unit
/// `lambda_unit`), then `<coordinate>_1 … <coordinate>_N` (unit of the coordinate).
pub fn bifurcation_outputs(
    coordinate: (&str, &str),
    lambda_unit: &str,
    points: usize,
) -> Vec<(String, String)> {
    let mut v = vec![
        ("motion".to_owned(), String::new()),
        ("period".to_owned(), "1".to_owned()),
        ("lambda".to_owned(), lambda_unit.to_owned()),
    ];
    v.extend((1..=points).map(|k| (format!("{}_{k}", coordinate.0), coordinate.1.to_owned())));
    v
}

/// The record of one bifurcation point in the columns of [`bifurcation_outputs`] (the motion
/// as its [`timestep::Motion::code`]).
pub fn bifurcation_record(
    p: &timestep::BifurcationPoint,
    coordinate: (&str, &str),
    lambda_unit: &str,
) -> Record {
    let mut r = Record::new();
    r.push("motion", "", p.motion.code())
        .push("period", "1", f64::from(p.motion.period_multiple()))
        .push("lambda", lambda_unit, p.lyapunov.unwrap_or(f64::NAN));
    for (k, x) in p.section.iter().enumerate() {
        r.push(&format!("{}_{}", coordinate.0, k + 1), coordinate.1, *x);
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_model_describes_itself() {
        let mut seen = Vec::new();
        for m in REGISTRY {
            assert!(!seen.contains(&m.name()), "{} twice", m.name());
            seen.push(m.name());
            let info = m.describe();
            assert!(!info.parameters.is_empty(), "{}", m.name());
            assert!(!info.methods.is_empty(), "{}", m.name());
            for c in &info.choices {
                assert!(c.options.contains(&c.default), "{}: {c:?}", m.name());
            }
        }
        assert!(find("nope").unwrap_err().to_string().contains("known: "));
    }

    /// Every parameter a model describes is accepted as a point override under its described
    /// name (the dotted path of a nested field: `geometry.rp`, `backlash.b`) with its described
    /// default, by every method the model offers; a name the model does not hold is the typed
    /// [`PointError::UnknownParameter`] listing the valid paths, among them every described one.
    #[test]
    fn every_described_parameter_is_an_accepted_override() {
        let limits = Limits {
            max_steps: MAX_STEPS_BOUND as f64,
            ..Limits::default()
        };
        for m in REGISTRY {
            let info = m.describe();
            // a required number without a default (Yu's ω*)
            let mut base = Point::new();
            for p in &info.parameters {
                if p.default.starts_with("(required)") {
                    base.insert(p.name.clone(), Value::Num(1.0));
                }
            }
            let mut tried = 0;
            for d in &info.methods {
                let solver = Solver {
                    method: d.method,
                    settings: BTreeMap::new(),
                };
                let ctx = Context {
                    solver: &solver,
                    initial: None,
                    limits,
                };
                let adapter = m
                    .build(&ctx)
                    .unwrap_or_else(|e| panic!("{} {:?}: {e}", m.name(), d.method));
                for p in &info.parameters {
                    let value = match serde_json::from_str::<serde_json::Value>(&p.default) {
                        Ok(serde_json::Value::Number(n)) => Value::Num(n.as_f64().unwrap()),
                        Ok(serde_json::Value::Array(a)) => {
                            Value::List(a.iter().filter_map(serde_json::Value::as_f64).collect())
                        }
                        _ => {
                            assert!(base.contains_key(&p.name), "{}: {p:?}", m.name());
                            continue;
                        }
                    };
                    let mut point = base.clone();
                    point.insert(p.name.clone(), value);
                    if let Err(e) = (adapter.prepare)(&point) {
                        panic!("{} {:?}: `{}` refused: {e}", m.name(), d.method, p.name);
                    }
                    tried += 1;
                }
                let mut point = base.clone();
                point.insert("no_such_parameter".into(), Value::Num(1.0));
                match (adapter.prepare)(&point) {
                    Err(PointError::UnknownParameter { name, paths }) => {
                        assert_eq!(name, "no_such_parameter");
                        for p in &info.parameters {
                            assert!(
                                base.contains_key(&p.name) || paths.contains(&p.name),
                                "{}: `{}` not among {paths:?}",
                                m.name(),
                                p.name
                            );
                        }
                    }
                    Err(e) => panic!(
                        "{} {:?}: expected UnknownParameter, got {e:?}",
                        m.name(),
                        d.method
                    ),
                    Ok(_) => panic!(
                        "{} {:?}: an unknown parameter was accepted",
                        m.name(),
                        d.method
                    ),
                }
            }
            assert!(tried > 0, "{}", m.name());
        }
    }

    /// The generic pair's geometry and backlash are nested: described by their dotted paths,
    /// and `pressure_angle` (the law, a name) is not the geometry's angle `geometry.pressure_angle`.
    #[test]
    fn the_generic_pair_describes_nested_fields_by_dotted_path() {
        let info = find("generic-pair").unwrap().describe();
        let names: Vec<&str> = info.parameters.iter().map(|p| p.name.as_str()).collect();
        for want in [
            "geometry.rp",
            "geometry.rg",
            "geometry.pressure_angle",
            "backlash.b",
            "stiffness.curve.k_single",
            "mesh_frequency",
        ] {
            assert!(names.contains(&want), "{want} not in {names:?}");
        }
        for bare in ["rp", "rg", "b", "pressure_angle", "stiffness.omega_e"] {
            assert!(!names.contains(&bare), "{bare} in {names:?}");
        }
        let unit = |n: &str| {
            info.parameters
                .iter()
                .find(|p| p.name == n)
                .map(|p| p.unit.clone())
        };
        assert_eq!(unit("backlash.b").as_deref(), Some("m"));
        assert_eq!(unit("geometry.pressure_angle").as_deref(), Some("rad"));
        assert_eq!(unit("stiffness.curve.k_single").as_deref(), Some("N/m"));
        // Yu's constant backlash is a length too (Table 1: 1 mm)
        let yu = find("yu2021").unwrap().describe();
        let b = yu
            .parameters
            .iter()
            .find(|p| p.name == "backlash.b")
            .unwrap();
        assert_eq!(b.unit, "m");
    }
}
