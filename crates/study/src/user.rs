//! User studies: `geardyn study <file.toml>` / `cargo xtask study <file.toml>` (format in
//! `docs/studies.md`, limits and guarantees in `docs/reliability.md`).
//!
//! The flow is *check everything, then compute, then write*:
//!
//! 1. [`UserStudy::parse`] reads the file and checks every entry that does not depend on the
//!    model (names, finiteness, sweep sizes, limits);
//! 2. [`prepare`] builds the model adapter (every solver setting checked against its documented
//!    bounds) and prepares every point (the model's validating constructor, every derived size);
//!    a study-file error stops here, before any computation;
//! 3. [`run_user_study`] computes the points in parallel (collected in input order, so the
//!    output is identical for any thread count); a point whose preparation or computation
//!    fails — error, or a panic caught as a last resort — becomes a NaN row with its message;
//! 4. [`write_outputs`] writes the CSV, SVGs and JSON summary atomically (see there).
//!
//! [`run_study_from_str`] does 1–3 in one call (the entry point of the Python package).

use std::collections::BTreeMap;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::basin::{self, BasinSpec};
use crate::bifurcation::{self, BifurcationSpec};
use crate::continuation::{self, ContinuationSpec};

/// One `[overrides]` entry as TOML gives it: a value, or a table of entries (dotted keys).
#[derive(Deserialize)]
#[serde(untagged)]
enum OverrideEntry {
    Leaf(Value),
    Table(BTreeMap<String, OverrideEntry>),
}

/// `[overrides]` with its sub-tables flattened to dotted names (`a.b = 1` → `"a.b"`).
fn dotted_overrides<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> Result<BTreeMap<String, Value>, D::Error> {
    fn walk(prefix: &str, m: BTreeMap<String, OverrideEntry>, out: &mut BTreeMap<String, Value>) {
        for (k, e) in m {
            let name = if prefix.is_empty() {
                k
            } else {
                format!("{prefix}.{k}")
            };
            match e {
                OverrideEntry::Leaf(v) => {
                    out.insert(name, v);
                }
                OverrideEntry::Table(t) => walk(&name, t, out),
            }
        }
    }
    let raw = BTreeMap::<String, OverrideEntry>::deserialize(d)?;
    let mut out = BTreeMap::new();
    walk("", raw, &mut out);
    Ok(out)
}
use crate::error::{Error, check_name};
use crate::shard::{self, Journal, JournalHeader, PointRecord, ShardSpec};
use models::contract::{self as registry, Job, Model, is_step_statistic};
use plot::{Cell, Table};
use plot::{Figure, Series};
use plot::{HeatScale, Heatmap};

// The study-file vocabulary lives in `spec` (shared with the model registrations); its public
// items keep their `user::` paths.
pub use crate::spec::*;

/// A user study file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UserStudy {
    /// File-name stem of the outputs: `a-z 0-9 - _ .`, not starting with `.`, at most
    /// [`MAX_NAME_LEN`] bytes.
    pub name: String,
    /// Free description copied into the summary.
    #[serde(default)]
    pub description: String,
    /// Model: see [`model_names`] / `geardyn models`.
    pub model: String,
    /// Parameter overrides and choices `name = value` on top of the model's base set. A name
    /// is a field of the parameter struct, or a dotted path into its nested structs
    /// (`readings.rigid_acceleration`, written as a TOML dotted key or a sub-table); a bare name
    /// that two nested structs hold is an error that lists the dotted names.
    #[serde(default, deserialize_with = "dotted_overrides")]
    pub overrides: BTreeMap<String, Value>,
    /// Initial state of the time integration (model-specific length; see `geardyn models`);
    /// absent: the model's default start.
    pub initial: Option<Vec<f64>>,
    /// The first (x-axis) sweep; absent = a single point.
    pub sweep: Option<Sweep>,
    /// The optional second sweep (one curve per value).
    pub sweep2: Option<Sweep>,
    /// Solver.
    pub solver: Solver,
    /// Work limits.
    #[serde(default)]
    pub limits: Limits,
    /// A bifurcation study: Poincaré sections and motion types instead of the model's outputs
    /// (see [`crate::bifurcation`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bifurcation: Option<BifurcationSpec>,
    /// A basin-of-attraction study: a grid of initial states at fixed parameters, each cell's
    /// attractor named and clustered, with the basin fractions (see [`crate::basin`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub basin: Option<BasinSpec>,
    /// A continuation study: the periodic orbit followed in one parameter, its special points
    /// and optionally their codim-2 curves (see [`crate::continuation`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub continuation: Option<ContinuationSpec>,
}

impl UserStudy {
    /// Parse a study file and check every entry that does not need the model.
    pub fn parse(text: &str) -> Result<Self, Error> {
        let s: UserStudy = toml::from_str(text).map_err(|e| Error::StudyFile(e.to_string()))?;
        check_study_name(&s.name)?;
        for (k, v) in &s.overrides {
            v.check_finite(&format!("override `{k}`"))?;
        }
        for (k, v) in &s.solver.settings {
            v.check_finite(&format!("setting `{k}`"))?;
        }
        if let Some(v) = &s.initial {
            Value::List(v.clone()).check_finite("initial")?;
        }
        s.limits.check()?;
        if let (Some(a), Some(b)) = (&s.sweep, &s.sweep2)
            && a.parameter == b.parameter
        {
            return Err(Error::StudyFile(format!(
                "[sweep] and [sweep2] both sweep `{}`; sweep two different parameters",
                a.parameter
            )));
        }
        model_spec(&s.model)?;
        if let Some(b) = &s.bifurcation {
            b.options()?;
            if s.sweep2.is_some() {
                return Err(Error::StudyFile(
                    "a [bifurcation] study sweeps one parameter: remove [sweep2] (one study per \
                     value of the second parameter)"
                        .to_owned(),
                ));
            }
        }
        if let Some(c) = &s.continuation {
            c.request()?;
            if s.sweep.is_some()
                || s.sweep2.is_some()
                || s.bifurcation.is_some()
                || s.basin.is_some()
            {
                return Err(Error::StudyFile(
                    "a [continuation] study follows one orbit from the parameters of \
                     [overrides]: remove [sweep], [sweep2], [bifurcation] and [basin] (the \
                     continued parameters are continuation.parameter and \
                     continuation.codim2.parameter)"
                        .to_owned(),
                ));
            }
            return Ok(s);
        }
        if let Some(b) = &s.basin {
            let grid = b.grid()?;
            b.options()?;
            if s.sweep.is_some() || s.sweep2.is_some() || s.bifurcation.is_some() {
                return Err(Error::StudyFile(
                    "a [basin] study is at fixed parameters: remove [sweep], [sweep2] and \
                     [bifurcation] (set the parameters in [overrides])"
                        .to_owned(),
                ));
            }
            s.limits.check_points(grid.q.steps, grid.q_dot.steps)?;
            return Ok(s);
        }
        let n1 = s
            .sweep
            .as_ref()
            .map_or(Ok(1), |w| w.points().map(|p| p.len()))?;
        let n2 = s
            .sweep2
            .as_ref()
            .map_or(Ok(1), |w| w.points().map(|p| p.len()))?;
        s.limits.check_points(n1, n2)?;
        Ok(s)
    }
}

/// Check a study name: `a-z 0-9 - _ .`, not `.`/`..` nor starting with `.`, at most
/// [`MAX_NAME_LEN`] bytes.
pub fn check_study_name(name: &str) -> Result<(), Error> {
    check_name(name)?;
    if name.starts_with('.') || name.len() > MAX_NAME_LEN {
        return Err(Error::StudyFile(format!(
            "name `{name}` must not start with '.' and must be at most {MAX_NAME_LEN} characters"
        )));
    }
    Ok(())
}

/// The registered model of that name ([`models::contract::REGISTRY`]).
pub fn model_spec(name: &str) -> Result<&'static dyn Model, Error> {
    Ok(registry::find(name)?)
}

/// Names of the models known to `geardyn study` (one line each in
/// [`models::contract::REGISTRY`]).
pub fn model_names() -> Vec<&'static str> {
    registry::names()
}

/// A study checked and ready to compute: every point prepared (or failed with its message).
pub struct Prepared {
    study: UserStudy,
    outputs: Vec<(String, String)>,
    xs: Vec<Value>,
    ys: Vec<Value>,
    jobs: Vec<Result<Job, Error>>,
}

impl std::fmt::Debug for Prepared {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Prepared")
            .field("study", &self.study.name)
            .field("points", &self.jobs.len())
            .finish()
    }
}

impl Prepared {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.jobs.len()
    }

    /// True if there is no point (never: a study has at least one).
    pub fn is_empty(&self) -> bool {
        self.jobs.is_empty()
    }

    /// Points that failed their preparation (index, message).
    pub fn failed_early(&self) -> Vec<(usize, String)> {
        self.jobs
            .iter()
            .enumerate()
            .filter_map(|(i, j)| j.as_ref().err().map(|e| (i, e.to_string())))
            .collect()
    }

    /// The study.
    pub fn study(&self) -> &UserStudy {
        &self.study
    }
}

/// Build the model adapter and prepare every point. Study-file errors (unknown or ill-typed
/// names, settings out of bounds, old spellings) are returned here, before any computation; a
/// point whose values the model rejects is kept as a failed point.
pub fn prepare(study: &UserStudy) -> Result<Prepared, Error> {
    let spec = model_spec(&study.model)?;
    if let Some(b) = &study.basin {
        return prepare_basin(study, spec, b);
    }
    if let Some(c) = &study.continuation {
        return prepare_continuation(study, spec, c);
    }
    let ctx = registry::Context {
        solver: &study.solver,
        initial: study.initial.as_deref(),
        limits: study.limits,
    };
    let adapter = match &study.bifurcation {
        None => spec.build(&ctx)?,
        Some(b) => {
            let coordinates = spec.bifurcation_coordinates().ok_or_else(|| {
                Error::StudyFile(format!(
                    "model `{}` has no [bifurcation] study; models with one: {}",
                    spec.name(),
                    registry::REGISTRY
                        .iter()
                        .filter(|m| m.bifurcation_coordinates().is_some())
                        .map(|m| m.name())
                        .collect::<Vec<_>>()
                        .join(", ")
                ))
            })?;
            let mut bo = b.options()?;
            bo.coordinate = b.coordinate_index(spec.name(), coordinates)?;
            spec.build_bifurcation(&ctx, &bo)?
        }
    };
    let xs = match &study.sweep {
        Some(s) => s.points()?,
        None => vec![Value::Num(f64::NAN)],
    };
    let ys = match &study.sweep2 {
        Some(s) => s.points()?,
        None => vec![Value::Num(f64::NAN)],
    };
    let mut jobs = Vec::with_capacity(xs.len().saturating_mul(ys.len()));
    for y in &ys {
        for x in &xs {
            let mut p = study.overrides.clone();
            if let Some(s) = &study.sweep {
                p.insert(s.parameter.clone(), x.clone());
            }
            if let Some(s) = &study.sweep2 {
                p.insert(s.parameter.clone(), y.clone());
            }
            let job = catch_unwind(AssertUnwindSafe(|| {
                (adapter.prepare)(&p).map_err(Error::from)
            }))
            .unwrap_or_else(|e| Err(Error::Study(panic_message(e.as_ref()))));
            match job {
                // A study-file error is the user's configuration, not a failed point.
                Err(Error::StudyFile(m)) => return Err(Error::StudyFile(m)),
                j => jobs.push(j),
            }
        }
    }
    Ok(Prepared {
        study: study.clone(),
        outputs: adapter.outputs,
        xs,
        ys,
        jobs,
    })
}

/// [`prepare`] for a basin study: one time-stepping point per cell, started at the cell's
/// initial state (the adapter is built per cell, so every initial state is checked by the
/// model as a study file's `initial` is).
fn prepare_basin(
    study: &UserStudy,
    spec: &'static dyn Model,
    b: &BasinSpec,
) -> Result<Prepared, Error> {
    let grid = b.grid()?;
    let mut outputs = None;
    let mut jobs = Vec::with_capacity(grid.len());
    for k in 0..grid.len() {
        let (q, v) = grid.cell(k);
        let initial = BasinSpec::initial(study.initial.as_deref(), q, v);
        let ctx = registry::Context {
            solver: &study.solver,
            initial: Some(&initial),
            limits: study.limits,
        };
        let adapter = spec.build(&ctx).map_err(|e| match Error::from(e) {
            Error::StudyFile(m) => Error::StudyFile(format!(
                "[basin] (every cell starts the time integration at its own initial state): {m}"
            )),
            e => e,
        })?;
        if outputs.is_none() {
            basin::check_outputs(spec.name(), &adapter.outputs)?;
            outputs = Some(adapter.outputs.clone());
        }
        let job = catch_unwind(AssertUnwindSafe(|| {
            (adapter.prepare)(&study.overrides).map_err(Error::from)
        }))
        .unwrap_or_else(|e| Err(Error::Study(panic_message(e.as_ref()))));
        match job {
            Err(Error::StudyFile(m)) => return Err(Error::StudyFile(m)),
            j => jobs.push(j),
        }
    }
    Ok(Prepared {
        study: study.clone(),
        outputs: outputs.unwrap_or_default(),
        xs: grid.q.values().into_iter().map(Value::Num).collect(),
        ys: grid.q_dot.values().into_iter().map(Value::Num).collect(),
        jobs,
    })
}

/// [`prepare`] for a continuation study: the model must have a continuation and know the
/// parameters, the solver must be shooting (its settings checked by the model's adapter);
/// no point jobs (the continuation is one computation, [`compute`]).
fn prepare_continuation(
    study: &UserStudy,
    spec: &'static dyn Model,
    c: &ContinuationSpec,
) -> Result<Prepared, Error> {
    let known = spec.continuation_parameters();
    if known.is_empty() {
        return Err(Error::StudyFile(format!(
            "model `{}` has no [continuation] study; models with one: {}",
            spec.name(),
            registry::REGISTRY
                .iter()
                .filter(|m| !m.continuation_parameters().is_empty())
                .map(|m| m.name())
                .collect::<Vec<_>>()
                .join(", ")
        )));
    }
    let names = || {
        known
            .iter()
            .map(|(n, _)| format!("\"{n}\""))
            .collect::<Vec<_>>()
            .join(", ")
    };
    for (key, name) in std::iter::once(("continuation.parameter", &c.parameter)).chain(
        c.codim2
            .iter()
            .map(|c2| ("continuation.codim2.parameter", &c2.parameter)),
    ) {
        if !known.iter().any(|(n, _)| n == name) {
            return Err(Error::StudyFile(format!(
                "{key} = \"{name}\" is not a continuation parameter of {}; parameters: {}",
                spec.name(),
                names()
            )));
        }
    }
    if study.solver.method != Method::Shooting {
        return Err(Error::StudyFile(
            "a [continuation] study corrects its orbits by shooting: set [solver] method = \
             \"shooting\" (its settings: rtol, tol, max_iter, flow_method, transient_periods)"
                .to_owned(),
        ));
    }
    let ctx = registry::Context {
        solver: &study.solver,
        initial: study.initial.as_deref(),
        limits: study.limits,
    };
    // the solver's settings and the initial state, checked as for a shooting study
    let adapter = spec.build(&ctx)?;
    Ok(Prepared {
        study: study.clone(),
        outputs: adapter.outputs,
        xs: vec![Value::Num(f64::NAN)],
        ys: vec![Value::Num(f64::NAN)],
        jobs: Vec::new(),
    })
}

/// Compute a continuation study (one computation under `limits.max_seconds_per_point`) and
/// render its outputs; a failure is the study's one failed point.
fn run_continuation(study: &UserStudy) -> UserStudyOutput {
    let owned = study.clone();
    let r = model_spec(&study.model)
        .map_err(|e| e.to_string())
        .and_then(|spec| {
            let request = study
                .continuation
                .as_ref()
                .ok_or_else(|| "no [continuation] table".to_owned())?
                .request()
                .map_err(|e| e.to_string())?;
            let seconds = study.limits.max_seconds_per_point;
            let job = move || {
                let ctx = registry::Context {
                    solver: &owned.solver,
                    initial: owned.initial.as_deref(),
                    limits: owned.limits,
                };
                spec.continuation(&owned.overrides, &ctx, &request)
                    .map_err(|e| Error::from(e).to_string())
            };
            // one point of the run's work account (the cost line counts it)
            timestep::sweep_owned(vec![job], |job| run_with_time_limit(seconds, job), None)
                .pop()
                .unwrap_or_else(|| Err("no result".to_owned()))
        });
    let (table, mut tables, figures, cont, failed) = match r {
        Ok(out) => {
            let (branch, special, curves) = continuation::tables(&study.name, &out);
            let mut tables = vec![special];
            tables.extend(curves);
            let figs = continuation::figures(&study.name, &out);
            (
                branch,
                tables,
                figs,
                continuation::summary(&out),
                Vec::new(),
            )
        }
        Err(e) => (
            Table::new(&study.name, &[]),
            Vec::new(),
            Vec::new(),
            serde_json::json!({ "error": e }),
            vec![FailedPoint {
                index: 0,
                at: BTreeMap::new(),
                error: e,
            }],
        ),
    };
    tables.retain(|t| !t.columns.is_empty());
    let stable = table.columns.iter().position(|c| c.name == "stable");
    let rows = table.rows.len();
    let unstable = stable.map(|j| {
        table
            .rows
            .iter()
            .filter(|r| r[j].number().is_some_and(|x| x.abs() < 0.5))
            .count()
    });
    let reliability = Reliability {
        points: rows.max(failed.len()),
        failed: failed.len(),
        unstable,
        notes: cont
            .get("stop")
            .and_then(|s| s.as_str())
            .map(|s| vec![format!("branch: {s}")])
            .unwrap_or_default(),
        ..Reliability::default()
    };
    let summary = serde_json::json!({
        "study": study,
        "points": reliability.points,
        "failed_points": failed,
        "reliability": reliability,
        "continuation": cont,
        "significant_digits": plot::SIGNIFICANT_DIGITS,
    });
    UserStudyOutput {
        name: study.name.clone(),
        outputs: Vec::new(),
        table,
        figures,
        maps: Vec::new(),
        failed,
        tables,
        basins: None,
        points: reliability.points,
        reliability,
        summary,
    }
}

/// Refuse to shard a continuation study (one sequential computation).
fn no_shards(study: &UserStudy) -> Result<(), Error> {
    if study.continuation.is_some() {
        return Err(Error::Shard(
            "a [continuation] study is one sequential computation (each point predicted from \
             the last): it does not shard; run it whole"
                .to_owned(),
        ));
    }
    Ok(())
}

pub(crate) fn panic_message(e: &(dyn std::any::Any + Send)) -> String {
    let m = e
        .downcast_ref::<&str>()
        .map(|s| (*s).to_owned())
        .or_else(|| e.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".to_owned());
    format!("internal error (panic caught): {m}")
}

/// One failed point of a study.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FailedPoint {
    /// Index of the point (row of the CSV, from 0).
    pub index: usize,
    /// The values of the swept parameters, `parameter = value`.
    pub at: BTreeMap<String, Value>,
    /// The message.
    pub error: String,
}

/// What a user study produced.
#[derive(Debug, Clone)]
pub struct UserStudyOutput {
    /// The study's name (file-name stem).
    pub name: String,
    /// Output columns `(name, unit)` of the model (after the swept parameters in the table).
    pub outputs: Vec<(String, String)>,
    /// One row per point: swept parameters then the model's outputs (`name [unit]` headers).
    pub table: Table,
    /// One figure per output quantity (x = first sweep, one curve per second-sweep value;
    /// none for the step statistics, [`crate::STEP_STATISTICS`]).
    pub figures: Vec<Figure>,
    /// For a two-parameter study with numeric sweeps: one heat map per output quantity but the
    /// step statistics (`<name>_<output>_map.svg`; the rattle state `rsv` with categorical
    /// colours).
    pub maps: Vec<Heatmap>,
    /// Points that failed (NaN rows in the table).
    pub failed: Vec<FailedPoint>,
    /// Further CSV tables written beside the main one (`<table name>.csv`): a basin study's
    /// fractions.
    pub tables: Vec<Table>,
    /// A basin study's attractors, fractions and labels ([`crate::basin`]).
    pub basins: Option<models::response::basin::Basins>,
    /// Number of points.
    pub points: usize,
    /// How many points can be trusted (settled, chaotic, failed, …): also in `summary`.
    pub reliability: Reliability,
    /// JSON summary: the study as read, the output ranges (numbers), failed points, the
    /// reliability counts and notes.
    pub summary: serde_json::Value,
}

impl UserStudyOutput {
    /// True when every point failed (the CLI then exits non-zero).
    pub fn all_failed(&self) -> bool {
        self.failed.len() == self.points
    }

    /// A numeric column of the table by name (without the unit).
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let i = self.table.columns.iter().position(|c| c.name == name)?;
        Some(
            self.table
                .rows
                .iter()
                .map(|r| r[i].number().unwrap_or(f64::NAN))
                .collect(),
        )
    }
}

/// Options of [`run_study_from_str`].
#[derive(Default)]
pub struct RunOptions<'a> {
    /// Called after each point with (points done, total); from several threads.
    pub progress: Option<&'a (dyn Fn(usize, usize) + Sync)>,
}

impl std::fmt::Debug for RunOptions<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RunOptions")
            .field("progress", &self.progress.is_some())
            .finish()
    }
}

/// Parse, check, prepare and compute a study given as TOML text; writes nothing. The entry
/// point for scripting front ends (the Python package).
pub fn run_study_from_str(toml: &str, options: &RunOptions<'_>) -> Result<UserStudyOutput, Error> {
    let study = UserStudy::parse(toml)?;
    let prepared = prepare(&study)?;
    Ok(compute(prepared, options.progress))
}

/// Run a user study (parse → [`prepare`] → compute): `on_point` is called after each point.
pub fn run_user_study(
    study: &UserStudy,
    on_point: impl Fn() + Sync,
) -> Result<UserStudyOutput, Error> {
    let prepared = prepare(study)?;
    let cb = move |_: usize, _: usize| on_point();
    Ok(compute(prepared, Some(&cb)))
}

/// Compute every prepared point (parallel, collected in input order) and assemble the outputs.
pub fn compute(
    prepared: Prepared,
    progress: Option<&(dyn Fn(usize, usize) + Sync)>,
) -> UserStudyOutput {
    if prepared.study.continuation.is_some() {
        let out = run_continuation(&prepared.study);
        if let Some(p) = progress {
            p(1, 1);
        }
        return out;
    }
    let (plan, records) = compute_records(prepared, ShardSpec::whole(), Vec::new(), None, progress);
    // The whole study was computed: every record is there, in order.
    let results = records.into_iter().map(record_result).collect();
    assemble(&plan.study, &plan.outputs, &plan.xs, &plan.ys, results)
}

/// What a study renders from its point records: the study, its output columns and its grid —
/// a [`Prepared`] study without its jobs (see [`crate::shard`]).
#[derive(Debug, Clone)]
pub struct StudyPlan {
    study: UserStudy,
    outputs: Vec<(String, String)>,
    xs: Vec<Value>,
    ys: Vec<Value>,
}

impl StudyPlan {
    /// Number of points (`len(sweep) · len(sweep2)`).
    pub fn len(&self) -> usize {
        self.xs.len() * self.ys.len()
    }

    /// True if there is no point (never: a study has at least one).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The study.
    pub fn study(&self) -> &UserStudy {
        &self.study
    }

    /// The fingerprint that ties partial results and journals to this study: FNV-1a of the
    /// study as parsed (canonical JSON: formatting and comments of the file do not count) and
    /// of the geardyn version.
    pub fn fingerprint(&self) -> String {
        let canonical = serde_json::to_string(&self.study).unwrap_or_default();
        shard::fingerprint(format!("{}\n{canonical}", env!("CARGO_PKG_VERSION")).as_bytes())
    }

    /// The header of a partial result (`Some(shard)`) or of a whole run's journal (`None`).
    pub fn header(&self, shard: Option<ShardSpec>) -> JournalHeader {
        JournalHeader::new(
            &self.study.name,
            self.fingerprint(),
            self.len(),
            self.outputs.iter().map(|(n, _)| n.clone()).collect(),
            shard,
        )
    }

    /// Render the outputs from the complete, ordered records (as [`shard::merge`] returns
    /// them): byte for byte what an unsharded run writes.
    pub fn render(&self, records: Vec<PointRecord>) -> Result<UserStudyOutput, Error> {
        if records.len() != self.len() || records.iter().enumerate().any(|(k, r)| r.index != k) {
            return Err(Error::Shard(format!(
                "{} records for a study of {} points, or out of order",
                records.len(),
                self.len()
            )));
        }
        if let Some(r) = records
            .iter()
            .find(|r| r.error.is_none() && r.values.len() != self.outputs.len())
        {
            return Err(Error::Shard(format!(
                "point {} has {} values for {} outputs",
                r.index,
                r.values.len(),
                self.outputs.len()
            )));
        }
        let results = records.into_iter().map(record_result).collect();
        Ok(assemble(
            &self.study,
            &self.outputs,
            &self.xs,
            &self.ys,
            results,
        ))
    }

    /// Check that partial results belong to this study (the fingerprint in their header).
    pub fn check_header(&self, header: &JournalHeader) -> Result<(), Error> {
        let mine = self.header(None);
        if header.fingerprint != mine.fingerprint
            || header.points != mine.points
            || header.outputs != mine.outputs
            || header.study != mine.study
        {
            return Err(Error::Shard(format!(
                "partial results of study `{}` ({} points, fingerprint {}) do not belong to \
                 this study file (`{}`, {} points, fingerprint {}): was the file changed?",
                header.study,
                header.points,
                header.fingerprint,
                mine.study,
                mine.points,
                mine.fingerprint
            )));
        }
        Ok(())
    }
}

fn record_result(r: PointRecord) -> Result<Vec<f64>, String> {
    match r.error {
        Some(e) => Err(e),
        None => Ok(r.values),
    }
}

/// Compute the points of one shard (`ShardSpec::whole()` for all) that are not in `done`, in
/// parallel; each finished point is appended to `journal` when one is given (so that a killed
/// run resumes from it). Returns the plan and the shard's records — `done` and the new ones —
/// in index order. A point's failure (error, non-finite output, panic) is its record's message.
pub fn compute_records(
    prepared: Prepared,
    shard: ShardSpec,
    done: Vec<PointRecord>,
    journal: Option<&Journal>,
    progress: Option<&(dyn Fn(usize, usize) + Sync)>,
) -> (StudyPlan, Vec<PointRecord>) {
    let Prepared {
        study,
        outputs,
        xs,
        ys,
        jobs,
    } = prepared;
    let mut have: BTreeMap<usize, PointRecord> = done
        .into_iter()
        .filter(|r| shard.owns(r.index) && r.index < jobs.len())
        .map(|r| (r.index, r))
        .collect();
    let todo: Vec<(usize, Result<Job, Error>)> = jobs
        .into_iter()
        .enumerate()
        .filter(|(k, _)| shard.owns(*k) && !have.contains_key(k))
        .collect();
    let seconds = study.limits.max_seconds_per_point;
    let journal_error = std::sync::Mutex::new(None::<String>);
    let new: Vec<PointRecord> = timestep::sweep_owned(
        todo,
        |(k, job)| {
            let r = match job {
                Ok(job) => match run_with_time_limit(seconds, move || {
                    catch_unwind(AssertUnwindSafe(job))
                        .map_err(|p| panic_message(p.as_ref()))?
                        .map_err(|e| Error::from(e).to_string())
                }) {
                    // The record's columns (name and unit) must be the declared ones.
                    Ok(rec) => match rec.values_for(&outputs) {
                        Ok(v) => match v.iter().position(|x| !x.is_finite()) {
                            // A success never carries a non-finite number.
                            Some(j) => {
                                Err(format!("non-finite output `{}` = {}", outputs[j].0, v[j]))
                            }
                            None => Ok(v),
                        },
                        Err(e) => Err(e),
                    },
                    Err(e) => Err(e),
                },
                Err(e) => Err(e.to_string()),
            };
            let rec = match r {
                Ok(v) => PointRecord::ok(k, v),
                Err(e) => PointRecord::failed(k, e),
            };
            if let Some(j) = journal {
                if let Err(e) = j.record(&rec) {
                    if let Ok(mut slot) = journal_error.lock() {
                        slot.get_or_insert(e.to_string());
                    }
                }
            }
            rec
        },
        progress,
    );
    if let Ok(Some(e)) = journal_error.into_inner() {
        // The journal only speeds up a restart: losing it costs recomputation, not results.
        eprintln!("warning: journal not written ({e}); an interrupted run would start afresh");
    }
    for r in new {
        have.insert(r.index, r);
    }
    (
        StudyPlan {
            study,
            outputs,
            xs,
            ys,
        },
        have.into_values().collect(),
    )
}

/// Compute shard `shard` of a study given as TOML text and return its partial result (the
/// text `geardyn study FILE --shard i/n` writes): a header line and one line per point. For
/// front ends that ship shards to workers (the Python package's Dask path).
pub fn run_shard_from_str(toml: &str, shard: ShardSpec) -> Result<String, Error> {
    let study = UserStudy::parse(toml)?;
    no_shards(&study)?;
    let prepared = prepare(&study)?;
    let (plan, records) = compute_records(prepared, shard, Vec::new(), None, None);
    let mut text = shard::header_line(&plan.header(Some(shard)));
    let fingerprint = plan.fingerprint();
    for r in &records {
        text.push_str(&shard::record_line(&fingerprint, r));
    }
    Ok(text)
}

/// Merge partial results (texts as [`run_shard_from_str`] returns them, or the contents of
/// `.part` files) of the study given as TOML text into its outputs.
pub fn merge_from_str(toml: &str, parts: &[String]) -> Result<UserStudyOutput, Error> {
    let study = UserStudy::parse(toml)?;
    no_shards(&study)?;
    let plan = plan_of(prepare(&study)?);
    let mut read = Vec::with_capacity(parts.len());
    for (k, text) in parts.iter().enumerate() {
        let name = format!("partial result {}", k + 1);
        let (h, recs) = shard::read_points(text, &name)?;
        plan.check_header(&h)?;
        read.push((name, h, recs));
    }
    let (_, records) = shard::merge(&read)?;
    plan.render(records)
}

fn plan_of(prepared: Prepared) -> StudyPlan {
    StudyPlan {
        study: prepared.study,
        outputs: prepared.outputs,
        xs: prepared.xs,
        ys: prepared.ys,
    }
}

fn axis_unit(study: &UserStudy, parameter: &str) -> String {
    model_spec(&study.model)
        .map(|m| m.unit_of(parameter).to_owned())
        .unwrap_or_default()
}

fn assemble(
    study: &UserStudy,
    outputs: &[(String, String)],
    xs: &[Value],
    ys: &[Value],
    results: Vec<Result<Vec<f64>, String>>,
) -> UserStudyOutput {
    let cell = |v: &Value| match v {
        Value::Num(x) => Cell::Num(*x),
        other => Cell::Text(other.label()),
    };
    let bif = study.bifurcation.is_some();
    // a basin study: its attractors from the complete, ordered records (a study whose records
    // cannot be clustered keeps its rows and says why in the summary)
    let basins = study
        .basin
        .as_ref()
        .map(|b| basin::basins_of(b, outputs, &results));
    let mut cols: Vec<(String, String)> = Vec::new();
    for s in [&study.sweep, &study.sweep2].into_iter().flatten() {
        cols.push((s.parameter.clone(), axis_unit(study, &s.parameter)));
    }
    if study.basin.is_some() {
        cols.push(("q".to_owned(), String::new()));
        cols.push(("q_dot".to_owned(), String::new()));
    }
    cols.extend(outputs.iter().cloned());
    if let Some(Ok(_)) = &basins {
        cols.push((basin::COLUMN.to_owned(), String::new()));
    }
    let col_refs: Vec<(&str, &str)> = cols.iter().map(|(a, b)| (a.as_str(), b.as_str())).collect();
    let mut table = Table::new(&study.name, &col_refs);
    let mut failed = Vec::new();
    let mut k = 0;
    for y in ys {
        for x in xs {
            let mut row: Vec<Cell> = Vec::new();
            let mut at = BTreeMap::new();
            if let Some(s) = &study.sweep {
                row.push(cell(x));
                at.insert(s.parameter.clone(), x.clone());
            }
            if let Some(s) = &study.sweep2 {
                row.push(cell(y));
                at.insert(s.parameter.clone(), y.clone());
            }
            if study.basin.is_some() {
                row.push(cell(x));
                row.push(cell(y));
                at.insert("q".to_owned(), x.clone());
                at.insert("q_dot".to_owned(), y.clone());
            }
            match &results[k] {
                Ok(v) if bif => {
                    row.extend(v.iter().enumerate().map(|(j, &z)| bifurcation::cell(j, z)))
                }
                Ok(v) => row.extend(v.iter().zip(outputs).map(|(&z, (name, _))| {
                    if is_step_statistic(name) {
                        Cell::count(z)
                    } else {
                        Cell::Num(z)
                    }
                })),
                Err(e) => {
                    failed.push(FailedPoint {
                        index: k,
                        at,
                        error: e.clone(),
                    });
                    row.extend(outputs.iter().map(|_| Cell::Num(f64::NAN)));
                }
            }
            if let Some(Ok(b)) = &basins {
                row.push(basin::label_cell(b, k));
            }
            // Row length always matches the header (same column list).
            let _ = table.push(row);
            k += 1;
        }
    }

    // The x axis: numbers as they are; names at their index 0, 1, 2, …
    let x_num: Vec<f64> = xs
        .iter()
        .enumerate()
        .map(|(i, v)| v.as_num().unwrap_or(i as f64))
        .collect();
    let mut figures = Vec::new();
    let mut ranges = serde_json::Map::new();
    for (j, (name, unit)) in outputs.iter().enumerate() {
        let vals: Vec<f64> = results
            .iter()
            .filter_map(|r| r.as_ref().ok().map(|v| v[j]))
            .filter(|v| v.is_finite())
            .collect();
        let lo = vals.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = vals.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        ranges.insert(
            name.clone(),
            serde_json::json!({"unit": unit, "min": json_num(lo), "max": json_num(hi)}),
        );
        // the step statistics describe the computation: CSV and ranges, no figure
        if is_step_statistic(name) {
            continue;
        }
        if let (Some(s), false) = (&study.sweep, bif) {
            let fname = format!("{}_{}", study.name, sanitize(name));
            let x_unit = axis_unit(study, &s.parameter);
            // a second sweep of many values: a few chosen curves (the CSV and the heat map
            // hold every one)
            let shown = chosen_curves(ys.len());
            let title = if shown.len() < ys.len() {
                format!(
                    "{}: {name} ({} of {} curves; all in the CSV and the map)",
                    study.name,
                    shown.len(),
                    ys.len()
                )
            } else {
                format!("{}: {name}", study.name)
            };
            let mut fig = Figure::new(&fname, &title, (&s.parameter, &x_unit), (name, unit));
            for (iy, y) in shown.iter().map(|&iy| (iy, &ys[iy])) {
                let pts: Vec<(f64, f64)> = x_num
                    .iter()
                    .enumerate()
                    .map(|(ix, &x)| {
                        let r = &results[iy * xs.len() + ix];
                        (x, r.as_ref().map_or(f64::NAN, |v| v[j]))
                    })
                    .collect();
                let label = match &study.sweep2 {
                    Some(s2) => {
                        let u = axis_unit(study, &s2.parameter);
                        if u.is_empty() || u == "1" {
                            format!("{} = {}", s2.parameter, y.label())
                        } else {
                            format!("{} = {} {u}", s2.parameter, y.label())
                        }
                    }
                    None => name.clone(),
                };
                fig.push(Series::line(label, pts));
            }
            figures.push(fig);
        }
    }
    if let (Some(s), true) = (&study.sweep, bif) {
        // the section columns share the coordinate's name (`q_1`, `q_2`, …) and unit
        let (cname, cunit) = outputs
            .get(bifurcation::LEADING)
            .map(|(n, u)| (n.trim_end_matches("_1"), u.as_str()))
            .unwrap_or(("section", ""));
        figures.push(bifurcation::figure(
            &format!("{}_bifurcation", study.name),
            &format!("{}: bifurcation diagram", study.name),
            (&s.parameter, &axis_unit(study, &s.parameter)),
            (&format!("{cname}(kT)"), cunit),
            &x_num,
            &results,
        ));
    }
    let mut maps = heat_maps(study, outputs, xs, ys, &results);
    let points = results.len();
    let reliability = Reliability::of(outputs, &results);
    let mut summary = serde_json::json!({
        "study": study,
        "points": points,
        "failed_points": failed,
        "outputs": ranges,
        "reliability": reliability,
        "significant_digits": plot::SIGNIFICANT_DIGITS,
    });
    let mut tables = Vec::new();
    let basins = match basins {
        Some(Ok(b)) => {
            tables.push(basin::fractions_table(&study.name, &b));
            maps.extend(basin::heat_map(&study.name, &b));
            if let Some(o) = summary.as_object_mut() {
                o.insert("basin".to_owned(), basin::summary(&b));
            }
            Some(b)
        }
        Some(Err(e)) => {
            if let Some(o) = summary.as_object_mut() {
                o.insert(
                    "basin".to_owned(),
                    serde_json::json!({ "error": e.to_string() }),
                );
            }
            None
        }
        None => None,
    };
    UserStudyOutput {
        name: study.name.clone(),
        outputs: outputs.to_vec(),
        table,
        figures,
        maps,
        failed,
        tables,
        basins,
        points,
        reliability,
        summary,
    }
}

/// Most curves of a line figure: a second sweep of more values is drawn as [`SHOWN_CURVES`]
/// chosen curves (a figure of 400 curves is unreadable and tens of MB; the heat map shows all).
pub const MAX_CURVES: usize = 12;

/// Curves drawn when a second sweep has more than [`MAX_CURVES`] values: the first, the last
/// and evenly spaced ones between.
pub const SHOWN_CURVES: usize = 6;

/// The indices of the curves of a line figure over `n` second-sweep values: all up to
/// [`MAX_CURVES`], else [`SHOWN_CURVES`] evenly spaced from the first to the last.
pub fn chosen_curves(n: usize) -> Vec<usize> {
    if n <= MAX_CURVES {
        return (0..n).collect();
    }
    (0..SHOWN_CURVES)
        .map(|k| k * (n - 1) / (SHOWN_CURVES - 1))
        .collect()
}

/// How many points of a study can be trusted: the counts behind the CLI's one-line summary and
/// the `reliability` object of the JSON summary. A count is `None` when the model has no such
/// column (e.g. `settled` for harmonic balance).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Reliability {
    /// Points of the study.
    pub points: usize,
    /// Points that failed (an error: NaN row).
    pub failed: usize,
    /// Points with `settled = 1` (time stepping: the kept window is classified).
    pub settled: Option<usize>,
    /// Points with `settled = 0`.
    pub unsettled: Option<usize>,
    /// Points with `motion = −1` (chaotic).
    pub chaotic: Option<usize>,
    /// Points with `converged = 0` (harmonic balance).
    pub not_converged: Option<usize>,
    /// Points with `stable = 0` (harmonic balance: Floquet).
    pub unstable: Option<usize>,
    /// Points with `robust = 0` (the spread over the variants exceeds the settled tolerance).
    pub not_robust: Option<usize>,
    /// What the output says about its own reliability where it cannot show it: e.g. that the
    /// robustness spread was not computed (`robustness = "off"`: the columns `robust`,
    /// `rsv_lo`, `rsv_hi`, `ppv_spread` are NaN).
    pub notes: Vec<String>,
}

impl Reliability {
    /// The counts over the rows `results` of the columns `outputs`.
    pub fn of(outputs: &[(String, String)], results: &[Result<Vec<f64>, String>]) -> Self {
        let ok: Vec<&Vec<f64>> = results.iter().filter_map(|r| r.as_ref().ok()).collect();
        let count = |name: &str, want: f64| {
            let j = outputs.iter().position(|(n, _)| n == name)?;
            #[allow(clippy::float_cmp)] // exact: flags and codes are small integers
            let n = ok.iter().filter(|r| r.get(j) == Some(&want)).count();
            Some(n)
        };
        let has = |name: &str| outputs.iter().any(|(n, _)| n == name);
        let mut notes = Vec::new();
        if has("settled") && !has("robust") {
            notes.push(
                "robustness spread not computed (robustness = \"off\"): no columns robust, \
                 rsv_lo, rsv_hi, ppv_spread; set robustness = \"on\" for the spread over \
                 rtol/100, a second window and a second start"
                    .to_owned(),
            );
        }
        if has("converged") && has("residual_norm") && !has("stable") {
            notes.push(
                "Floquet stability not computed (stability = \"off\"): no column stable".to_owned(),
            );
        }
        if has("stable") && has("converged") && !has("confirmed_by_time_stepping") {
            notes.push(
                "time-stepping confirmation not computed (confirm = \"off\"): no column \
                 confirmed_by_time_stepping"
                    .to_owned(),
            );
        }
        Reliability {
            points: results.len(),
            failed: results.len() - ok.len(),
            settled: count("settled", 1.0),
            unsettled: count("settled", 0.0),
            chaotic: count("motion", -1.0),
            not_converged: count("converged", 0.0),
            unstable: count("stable", 0.0),
            not_robust: count("robust", 0.0),
            notes,
        }
    }

    /// The one-line summary of a study: `points, settled, chaotic, failed`, then the other
    /// counts that apply (`not converged`, `unstable`, `not robust`).
    pub fn line(&self) -> String {
        let mut parts = vec![format!("{} points", self.points)];
        let opt = |n: Option<usize>, what: &str| n.map(|n| format!("{n} {what}"));
        parts.extend(opt(self.settled, "settled"));
        parts.extend(opt(self.chaotic, "chaotic"));
        parts.push(format!("{} failed", self.failed));
        parts.extend(opt(self.not_converged, "not converged"));
        parts.extend(opt(self.unstable, "unstable"));
        parts.extend(opt(self.not_robust, "not robust"));
        parts.join(", ")
    }
}

/// The rattle-state labels of the categorical maps (`rsv`: 0, 1, 2).
const RATTLE_STATES: [&str; 3] = ["no rattle", "unilateral", "bilateral"];

/// Heat maps of a two-parameter study: one per output, over (first sweep × second sweep), when
/// both sweeps are numeric and strictly monotone; otherwise none (the line figures remain).
fn heat_maps(
    study: &UserStudy,
    outputs: &[(String, String)],
    xs: &[Value],
    ys: &[Value],
    results: &[Result<Vec<f64>, String>],
) -> Vec<Heatmap> {
    let (Some(s1), Some(s2)) = (&study.sweep, &study.sweep2) else {
        return Vec::new();
    };
    let nums = |v: &[Value]| v.iter().map(Value::as_num).collect::<Option<Vec<f64>>>();
    let (Some(x), Some(y)) = (nums(xs), nums(ys)) else {
        return Vec::new();
    };
    let (ux, uy) = (
        axis_unit(study, &s1.parameter),
        axis_unit(study, &s2.parameter),
    );
    let mut maps = Vec::new();
    for (j, (name, unit)) in outputs.iter().enumerate() {
        if is_step_statistic(name) {
            continue;
        }
        let z: Vec<f64> = results
            .iter()
            .map(|r| r.as_ref().map_or(f64::NAN, |v| v[j]))
            .collect();
        let scale = if name == "rsv" {
            HeatScale::Categorical(
                RATTLE_STATES
                    .iter()
                    .enumerate()
                    .map(|(k, l)| (k as f64, (*l).to_owned()))
                    .collect(),
            )
        } else {
            HeatScale::Continuous
        };
        let title = format!("{}: {name}", study.name);
        // A map that cannot be built (non-monotone sweep values, an unknown state) is left
        // out; the CSV and the line figures carry the data.
        if let Ok(m) = Heatmap::new(
            &format!("{}_{}_map", study.name, sanitize(name)),
            &title,
            [
                (s1.parameter.as_str(), ux.as_str()),
                (s2.parameter.as_str(), uy.as_str()),
                (name.as_str(), unit.as_str()),
            ],
            x.clone(),
            y.clone(),
            z,
            scale,
        ) {
            maps.push(m);
        }
    }
    maps
}

/// A number at 6 significant digits as a JSON number (`null` if not finite).
fn json_num(x: f64) -> serde_json::Value {
    if x.is_finite() {
        let r: f64 = plot::fmt6(x).parse().unwrap_or(x);
        serde_json::json!(r)
    } else {
        serde_json::Value::Null
    }
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

// ---------------------------------------------------------------------------------------------
// Writing the outputs.

/// What [`write_outputs`] wrote.
#[derive(Debug, Clone)]
pub struct Written {
    /// The output directory.
    pub dir: PathBuf,
    /// The files, in write order (JSON summary last).
    pub files: Vec<PathBuf>,
    /// The run id recorded in the JSON summary.
    pub run_id: String,
}

/// Marker file that identifies a directory as a study output (so that it may be replaced).
const MARKER: &str = ".geardyn-study";

/// A lock on an output directory: an OS advisory lock on `.<dir>.lock` beside it, released
/// when this value is dropped or the process ends, however it ends ([`shard::FileLock`]).
#[derive(Debug)]
pub struct OutputLock {
    _lock: shard::FileLock,
    dir: PathBuf,
}

impl OutputLock {
    /// The locked output directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }
}

fn io(path: &Path) -> impl Fn(std::io::Error) -> Error + '_ {
    move |source| Error::Io {
        path: path.display().to_string(),
        source,
    }
}

/// Check and lock an output directory **before computing**: its parent must exist or be
/// creatable and writable; the directory must be absent, empty, or a previous study output
/// (holding the `.geardyn-study` marker) — never an unrelated directory, which would be
/// replaced; and no other live run may hold it (an OS advisory lock on `.<dir>.lock` beside
/// it, [`shard::FileLock`]: a killed run's lock is released by the OS, so its restart is not
/// refused).
pub fn lock_output_dir(dir: &Path) -> Result<OutputLock, Error> {
    let name = dir
        .file_name()
        .and_then(|n| n.to_str())
        .filter(|n| *n != "." && *n != "..")
        .ok_or_else(|| {
            Error::StudyFile(format!(
                "output directory `{}` must end in a plain directory name",
                dir.display()
            ))
        })?;
    let parent = match dir.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    std::fs::create_dir_all(&parent).map_err(io(&parent))?;
    if dir.exists() {
        if !dir.is_dir() {
            return Err(Error::StudyFile(format!(
                "output `{}` exists and is not a directory",
                dir.display()
            )));
        }
        let mut entries = std::fs::read_dir(dir).map_err(io(dir))?;
        let empty = entries.next().is_none();
        if !empty && !dir.join(MARKER).is_file() {
            return Err(Error::StudyFile(format!(
                "output directory `{}` is not empty and holds no previous study output; \
                 refusing to replace it (choose another --out)",
                dir.display()
            )));
        }
    }
    let lock_path = parent.join(format!(".{name}.lock"));
    let lock = match shard::FileLock::acquire(&lock_path) {
        Ok(l) => l,
        Err(shard::LockRefused::Held(holder)) => {
            return Err(Error::StudyFile(format!(
                "output directory `{}` is locked by a running study ({}, lock {}); wait for \
                 it to finish or choose another --out",
                dir.display(),
                if holder.is_empty() {
                    "pid unknown"
                } else {
                    holder.as_str()
                },
                lock_path.display()
            )));
        }
        Err(shard::LockRefused::Io(e)) => return Err(e),
    };
    // Probe writability now rather than after the computation.
    let probe = parent.join(format!(".{name}.probe-{}", std::process::id()));
    std::fs::write(&probe, b"").map_err(io(&probe))?;
    let _ = std::fs::remove_file(&probe);
    Ok(OutputLock {
        _lock: lock,
        dir: dir.to_path_buf(),
    })
}

/// A run id: seconds since the Unix epoch, nanoseconds and the process id.
pub fn new_run_id() -> String {
    let t = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap_or_default();
    format!(
        "{}-{:09}-{}",
        t.as_secs(),
        t.subsec_nanos(),
        std::process::id()
    )
}

/// Write a study's outputs atomically into the locked directory: every file goes into a fresh
/// temporary directory beside it (CSV, SVGs, then the JSON summary with the run id last), which
/// then replaces the output directory by renames; files of an earlier run are therefore never
/// mixed with new ones (stale files disappear with the old directory). A killed run leaves at
/// most a `.<name>.tmp-<run id>` directory beside the output, never a mixed output.
pub fn write_outputs(out: &UserStudyOutput, lock: &OutputLock) -> Result<Written, Error> {
    let dir = lock.dir();
    // Render everything first: the run id is the fingerprint of the files it stands for, so
    // that the same study gives the same bytes however it was computed (whole, sharded and
    // merged, resumed), and the JSON names exactly the set of files written with it.
    let mut rendered: Vec<(String, Vec<u8>)> = Vec::new();
    rendered.push((format!("{}.csv", out.name), out.table.to_csv().into_bytes()));
    for t in &out.tables {
        rendered.push((format!("{}.csv", t.name), t.to_csv().into_bytes()));
    }
    // A figure that cannot be drawn (e.g. a data range wider than f64) is reported in the
    // summary; its data is in the CSV.
    let mut not_drawn = Vec::new();
    for f in &out.figures {
        match f.to_svg() {
            Ok(svg) => rendered.push((format!("{}.svg", f.name), svg.into_bytes())),
            Err(e) => not_drawn.push(e.to_string()),
        }
    }
    for m in &out.maps {
        match m.to_svg() {
            Ok(svg) => rendered.push((format!("{}.svg", m.name), svg.into_bytes())),
            Err(e) => not_drawn.push(e.to_string()),
        }
    }
    let mut all = Vec::new();
    for (n, b) in &rendered {
        all.extend_from_slice(n.as_bytes());
        all.push(0);
        all.extend_from_slice(b);
    }
    let run_id = format!("content-{}", crate::shard::fingerprint(&all));
    let name = dir
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or("study")
        .to_owned();
    let parent = match dir.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let unique = new_run_id();
    let tmp = parent.join(format!(".{name}.tmp-{unique}"));
    std::fs::create_dir(&tmp).map_err(io(&tmp))?;
    let result = (|| {
        let mut files = Vec::new();
        let mut put = |file: &str, bytes: &[u8]| -> Result<(), Error> {
            let p = tmp.join(file);
            std::fs::write(&p, bytes).map_err(io(&p))?;
            files.push(dir.join(file));
            Ok(())
        };
        for (n, b) in &rendered {
            put(n, b)?;
        }
        let mut summary = out.summary.clone();
        if let Some(o) = summary.as_object_mut() {
            o.insert("figures_not_drawn".to_owned(), serde_json::json!(not_drawn));
            o.insert("run_id".to_owned(), serde_json::json!(run_id));
        }
        let json =
            serde_json::to_string_pretty(&summary).map_err(|e| Error::Study(e.to_string()))?;
        put(
            &format!("{}.json", out.name),
            format!("{json}\n").as_bytes(),
        )?;
        put(MARKER, format!("{run_id}\n").as_bytes())?;
        Ok(files)
    })();
    let files = match result {
        Ok(f) => f,
        Err(e) => {
            let _ = std::fs::remove_dir_all(&tmp);
            return Err(e);
        }
    };
    let old = parent.join(format!(".{name}.old-{unique}"));
    if dir.exists() {
        std::fs::rename(dir, &old).map_err(io(dir))?;
    }
    std::fs::rename(&tmp, dir).map_err(io(dir))?;
    if old.exists() {
        std::fs::remove_dir_all(&old).map_err(io(&old))?;
    }
    let files = files
        .into_iter()
        .filter(|p| p.file_name().and_then(|n| n.to_str()) != Some(MARKER))
        .collect();
    Ok(Written {
        dir: dir.to_path_buf(),
        files,
        run_id,
    })
}

/// The default output directory of a study file: `<directory of the file>/<name>/`.
pub fn default_out_dir(file: &Path, study: &UserStudy) -> PathBuf {
    file.parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
        .join(&study.name)
}

/// Progress of a study file run, for front ends.
pub trait Progress: Sync {
    /// The points are about to be computed.
    fn start(&self, total: usize);
    /// A point finished (`done` of `total`).
    fn point(&self, done: usize, total: usize);
    /// Computation finished.
    fn finish(&self);
}

/// Run a study file end to end: read and check it, check and lock the output directory
/// (`out`, default [`default_out_dir`]), prepare every point, compute, write atomically.
pub fn run_study_file(
    file: &Path,
    out: Option<&Path>,
    progress: &dyn Progress,
) -> Result<(UserStudyOutput, Written), Error> {
    let study = read_study(file)?;
    let dir = out.map_or_else(|| default_out_dir(file, &study), Path::to_path_buf);
    let lock = lock_output_dir(&dir)?;
    let prepared = prepare(&study)?;
    if study.continuation.is_some() {
        // one computation: no journal to resume from
        progress.start(1);
        let output = compute(prepared, None);
        progress.point(1, 1);
        progress.finish();
        let written = write_outputs(&output, &lock)?;
        return Ok((output, written));
    }
    // The journal lives beside the output directory (which is replaced atomically at the end)
    // and under the same lock: a run stopped by SIGINT/SIGKILL resumes from it.
    let journal_path = sibling(&dir, "journal");
    let (journal, done) = Journal::open(&journal_path, &plan_ref(&prepared).header(None))?;
    if !done.is_empty() {
        eprintln!(
            "resuming {}: {} of {} points taken from {}",
            study.name,
            done.len(),
            prepared.len(),
            journal_path.display()
        );
    }
    progress.start(prepared.len() - done.len().min(prepared.len()));
    let cb = |d: usize, t: usize| progress.point(d, t);
    let (plan, records) = compute_records(
        prepared,
        ShardSpec::whole(),
        done,
        Some(&journal),
        Some(&cb),
    );
    progress.finish();
    let output = plan.render(records)?;
    let written = write_outputs(&output, &lock)?;
    journal.finish()?;
    Ok((output, written))
}

/// Read and check a study file; study-file errors name the file.
fn read_study(file: &Path) -> Result<UserStudy, Error> {
    let text = std::fs::read_to_string(file).map_err(io(file))?;
    UserStudy::parse(&text).map_err(|e| match e {
        Error::StudyFile(m) => Error::StudyFile(format!("{}: {m}", file.display())),
        e => e,
    })
}

/// `<parent>/.<name>.<what>` for an output directory `<parent>/<name>`.
fn sibling(dir: &Path, what: &str) -> PathBuf {
    let name = dir.file_name().and_then(|n| n.to_str()).unwrap_or("study");
    let parent = match dir.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    parent.join(format!(".{name}.{what}"))
}

fn plan_ref(p: &Prepared) -> StudyPlan {
    StudyPlan {
        study: p.study.clone(),
        outputs: p.outputs.clone(),
        xs: p.xs.clone(),
        ys: p.ys.clone(),
    }
}

/// The partial-result file of shard `shard` of the study whose outputs go to `out`:
/// `<out>-shards/<name>.shard-<i>-of-<n>.part`, beside the output directory (which a merge
/// replaces atomically, so the parts cannot live inside it).
pub fn shard_path(out: &Path, study: &UserStudy, shard: ShardSpec) -> PathBuf {
    let mut dir = out.as_os_str().to_owned();
    dir.push("-shards");
    PathBuf::from(dir).join(format!(
        "{}.shard-{}-of-{}.part",
        study.name,
        shard.index(),
        shard.count()
    ))
}

/// Run shard `shard` of a study file: its partial result is written point by point to
/// [`shard_path`] (so a task that is stopped resumes where it was when it is run again) and
/// the path is returned. Merge the shards with [`merge_study_files`].
pub fn run_study_shard_file(
    file: &Path,
    out: Option<&Path>,
    shard: ShardSpec,
    progress: &dyn Progress,
) -> Result<PathBuf, Error> {
    let study = read_study(file)?;
    no_shards(&study)?;
    let dir = out.map_or_else(|| default_out_dir(file, &study), Path::to_path_buf);
    let path = shard_path(&dir, &study, shard);
    if let Some(p) = path.parent() {
        std::fs::create_dir_all(p).map_err(io(p))?;
    }
    // One task per shard file: a second copy of the same task (a resubmitted array task while
    // the first still runs) is refused; a killed task's lock is released by the OS.
    let mut lock_path = path.as_os_str().to_owned();
    lock_path.push(".lock");
    let lock_path = PathBuf::from(lock_path);
    let _lock = match shard::FileLock::acquire(&lock_path) {
        Ok(l) => l,
        Err(shard::LockRefused::Held(holder)) => {
            return Err(Error::Shard(format!(
                "shard {shard} is being computed by another run ({}, lock {})",
                if holder.is_empty() {
                    "pid unknown"
                } else {
                    holder.as_str()
                },
                lock_path.display()
            )));
        }
        Err(shard::LockRefused::Io(e)) => return Err(e),
    };
    let prepared = prepare(&study)?;
    let (journal, done) = Journal::open(&path, &plan_ref(&prepared).header(Some(shard)))?;
    let owned = shard.points(prepared.len()).count();
    progress.start(owned - done.len().min(owned));
    let cb = |d: usize, t: usize| progress.point(d, t);
    let _ = compute_records(prepared, shard, done, Some(&journal), Some(&cb));
    progress.finish();
    Ok(path)
}

/// Merge the partial results `parts` of the study file `file` and write its outputs to `out`
/// (default [`default_out_dir`]) exactly as an unsharded run would.
pub fn merge_study_files(
    file: &Path,
    out: Option<&Path>,
    parts: &[PathBuf],
) -> Result<(UserStudyOutput, Written), Error> {
    let study = read_study(file)?;
    no_shards(&study)?;
    let dir = out.map_or_else(|| default_out_dir(file, &study), Path::to_path_buf);
    let plan = plan_of(prepare(&study)?);
    let mut read = Vec::with_capacity(parts.len());
    for p in parts {
        // Bytes, not text: a flipped bit that breaks UTF-8 is then a checksum error naming the
        // line, like any other damage.
        let bytes = std::fs::read(p).map_err(io(p))?;
        let t = String::from_utf8_lossy(&bytes);
        let name = p.display().to_string();
        let (h, recs) = shard::read_points(&t, &name)?;
        if h.shard.is_none() {
            return Err(Error::Shard(format!(
                "{name} is the journal of an unfinished whole run, not a shard's partial result"
            )));
        }
        plan.check_header(&h)?;
        read.push((name, h, recs));
    }
    let (_, records) = shard::merge(&read)?;
    let output = plan.render(records)?;
    let lock = lock_output_dir(&dir)?;
    let written = write_outputs(&output, &lock)?;
    Ok((output, written))
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
        o.insert("n".to_owned(), -3.0);
        let e = apply_overrides(&Q { n: 1 }, &o).unwrap_err().to_string();
        assert!(e.contains("`n`"), "{e}");
        let mut o = BTreeMap::new();
        o.insert("name".to_owned(), 1.0);
        assert!(apply_overrides(&p, &o).is_err());
    }

    #[test]
    fn names_round_trip() {
        assert_eq!(camel_to_kebab("PrintedEq20"), "printed-eq20");
        assert_eq!(kebab_to_camel("printed-eq20"), "PrintedEq20");
        assert_eq!(kebab_to_camel("kahraman-singh"), "KahramanSingh");
        let v = variant_names::<Method>();
        // Method is kebab-case in serde: the names come back as they are.
        assert_eq!(
            v,
            ["time-stepping", "hbm", "kinematics", "shooting"],
            "{v:?}"
        );
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
            steps: Some(i64::MAX),
            ..s
        };
        assert!(s.points().is_err());
        let s = Sweep {
            parameter: "x".into(),
            from: Some(-1e308),
            to: Some(1e308),
            steps: Some(3),
            values: None,
        };
        let p = s.points().unwrap();
        assert!(p.iter().all(|v| v.as_num().is_some_and(f64::is_finite)));
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
    fn parse_rejects_bad_files() {
        let t = "name = \"a\"\nmodel = \"nope\"\n[solver]\nmethod = \"hbm\"\n";
        assert!(UserStudy::parse(t).is_err());
        for name in ["..", ".", "a/b", ".hidden", &"x".repeat(65)] {
            let t = format!("name = \"{name}\"\nmodel = \"liu2021\"\n[solver]\nmethod = \"hbm\"\n");
            assert!(UserStudy::parse(&t).is_err(), "{name}");
        }
        let t = "name = \"a\"\nmodel = \"liu2021\"\n[sweep]\nparameter = \"kr\"\nvalues = [1]\n\
                 [sweep2]\nparameter = \"kr\"\nvalues = [2]\n[solver]\nmethod = \"hbm\"\n";
        let e = UserStudy::parse(t).unwrap_err().to_string();
        assert!(e.contains("kr"), "{e}");
    }
}
