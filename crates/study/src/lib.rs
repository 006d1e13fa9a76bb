//! The `geardyn study` engine: study files over any model of the registry, computed in
//! parallel, sharded, merged and written atomically. It knows no model by name: everything it
//! says about a model comes from the model's self-description ([`Model::describe`] through
//! [`REGISTRY`]).
//!
//! # A study file
//!
//! [`UserStudy`] reads the TOML study files of `geardyn study <file.toml>` (format in
//! `docs/studies.md`, limits in `docs/reliability.md`): any model of [`REGISTRY`], parameter
//! overrides and choices, a sweep over one or two parameters ([`Sweep`]), solver and settings,
//! the initial state, limits ([`Limits`]) and an optional bifurcation diagram
//! ([`BifurcationSpec`]), basin-of-attraction grid ([`BasinSpec`], [`basin`]) or continuation
//! of a periodic orbit with codim-2 curves of its special points ([`ContinuationSpec`],
//! [`continuation`]).
//!
//! The flow is *check everything, then compute, then write*: [`UserStudy::parse`] checks every
//! entry that does not depend on the model; [`prepare`] builds every point through the model's
//! validating constructor (a study-file error stops here, before any computation);
//! [`run_user_study`] computes the points in parallel, collected in input order, so the output
//! is identical for any thread count; [`write_outputs`] writes CSV, SVG (figures and heat maps
//! from `geardyn-plot`) and a JSON summary atomically under an [`OutputLock`].
//!
//! [`run_study_from_str`] parses, checks and computes a study without writing;
//! [`run_study_file`] is the whole command (output directory checked and locked first, atomic
//! writes). The [`shard`] module splits a study into shards with journals (resumable), merges
//! them and writes Slurm array scripts.
//!
//! ```
//! let toml = r#"
//! name = "delta-vs-b"
//! model = "karpov2017-kinematics"
//! [sweep]
//! parameter = "b"
//! values = [0.001, 0.01]
//! [solver]
//! method = "kinematics"
//! "#;
//! let out = geardyn_study::run_study_from_str(toml, &Default::default()).unwrap();
//! assert_eq!(out.table.rows.len(), 2);
//! ```

#![deny(missing_docs)]

pub mod basin;
pub mod bifurcation;
pub mod continuation;
mod error;
pub mod shard;
mod spec;
mod user;

pub use basin::BasinSpec;
pub use bifurcation::{BifurcationSpec, MAX_BIFURCATION_PERIODS, MAX_BIFURCATION_POINTS};
pub use continuation::{
    Codim2Spec, ContinuationSpec, MAX_CODIM2_CURVES, MAX_CONTINUATION_POINTS, MAX_SWITCHES,
};
pub use error::Error;
// the output table of a study is a `plot` table
pub use models::contract::{
    Adapter, ChoiceInfo, Context, Job, Kind, MethodInfo, Model, ModelInfo, ParamInfo, Preparer,
    REGISTRY, Record, STEP_STATISTICS, SettingDef, check_settings, describe_all, describe_json,
    is_step_statistic, step_statistics,
};
pub use plot::{Cell, Table};
pub use user::{
    FailedPoint, Limits, MAX_CURVES, MAX_NAME_LEN, MAX_POINTS_BOUND, MAX_SECONDS_BOUND,
    MAX_STEPS_BOUND, MAX_SWEEP_VALUES, Method, OutputLock, Point, Prepared, Progress, Reliability,
    RunOptions, SHOWN_CURVES, Solver, StudyPlan, Sweep, TIME_LIMIT, UserStudy, UserStudyOutput,
    Value, Written, apply_overrides, apply_values, camel_to_kebab, check_study_name, choice,
    chosen_curves, compute, compute_records, default_out_dir, display_name, field_names,
    kebab_to_camel, lock_output_dir, merge_from_str, merge_study_files, model_names, model_spec,
    new_run_id, prepare, run_shard_from_str, run_study_file, run_study_from_str,
    run_study_shard_file, run_user_study, run_with_time_limit, shard_path, variant_names,
    write_outputs,
};
