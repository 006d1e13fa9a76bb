//! `geardyn`: run gear-dynamics studies, list the models, run the validation.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "geardyn",
    version,
    about = "Nonlinear gear dynamics: studies, models, validation"
)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Run a study file (TOML, see docs/studies.md); writes CSV, SVG and a JSON summary.
    Study {
        /// The study file.
        file: PathBuf,
        /// Output directory (default: next to the study file, `<name>/`).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Compute only shard `i/n` (1-based) and write its partial result to
        /// `<out>-shards/`; merge the shards with `geardyn merge`.
        #[arg(long, value_name = "I/N", conflicts_with = "sbatch")]
        shard: Option<String>,
        /// Print a Slurm job-array script that runs the study as N shards (docs/scaling.md).
        #[arg(long, value_name = "N")]
        sbatch: Option<usize>,
        /// Slurm: time limit per task (HH:MM:SS).
        #[arg(long, default_value = "01:00:00", requires = "sbatch")]
        sbatch_time: String,
        /// Slurm: memory per task.
        #[arg(long, default_value = "2G", requires = "sbatch")]
        sbatch_mem: String,
        /// Slurm: cores per task.
        #[arg(long, default_value_t = 1, requires = "sbatch")]
        sbatch_cpus: usize,
        /// Slurm: partition.
        #[arg(long, requires = "sbatch")]
        sbatch_partition: Option<String>,
    },
    /// Merge shards' partial results into the outputs of the whole study (byte-identical to an
    /// unsharded run).
    Merge {
        /// The study file the shards were computed from.
        file: PathBuf,
        /// Output directory (default: next to the study file, `<name>/`).
        #[arg(long)]
        out: Option<PathBuf>,
        /// The partial results (`<out>-shards/*.part`).
        #[arg(required = true)]
        parts: Vec<PathBuf>,
    },
    /// List every model: parameters and units, choices and readings, methods, settings, outputs.
    Models {
        /// Only this model.
        name: Option<String>,
        /// Machine-readable JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Run the validation studies and write validation/ (same code as `cargo xtask validate`).
    Validate {
        /// Do not write: fail if any generated file differs from the committed one.
        #[arg(long)]
        check: bool,
        /// Only studies whose id contains this text (never with --check).
        #[arg(long)]
        filter: Option<String>,
        /// With --check: only shard I of N (each study in exactly one shard; the CI splits the
        /// check this way). The cross-study aggregates are left to the full --check.
        #[arg(long, value_name = "I/N", requires = "check")]
        shard: Option<String>,
        /// Do not run: print the verdict diff (markdown) between validation/verdicts.csv at REV
        /// (default: the merge base with `main`) and the working tree.
        #[arg(long, value_name = "REV", num_args = 0..=1, default_missing_value = "",
              conflicts_with_all = ["check", "filter"])]
        diff: Option<String>,
        /// Repository root holding `validation/` and `docs/` (default: current directory).
        #[arg(long, default_value = ".")]
        root: PathBuf,
    },
}

fn main() -> ExitCode {
    // keep geardyn-math's C math symbols in the link (deterministic sin, pow, … for the
    // dependencies too)
    math::c_symbols::link();
    let cli = Cli::parse();
    let result = match cli.cmd {
        Cmd::Study {
            file,
            out,
            shard,
            sbatch,
            sbatch_time,
            sbatch_mem,
            sbatch_cpus,
            sbatch_partition,
        } => match (shard, sbatch) {
            (Some(s), _) => geardyn_cli::study_shard(&file, out.as_deref(), &s),
            (None, Some(n)) => geardyn_cli::study_sbatch(
                &file,
                out.as_deref(),
                &study::shard::SlurmOptions {
                    shards: n,
                    time: sbatch_time,
                    memory: sbatch_mem,
                    cpus: sbatch_cpus,
                    partition: sbatch_partition,
                    ..study::shard::SlurmOptions::default()
                },
            ),
            (None, None) => geardyn_cli::study(&file, out.as_deref()),
        },
        Cmd::Merge { file, out, parts } => geardyn_cli::merge(&file, out.as_deref(), &parts),
        Cmd::Models { name, json } => {
            if json {
                let v = match name {
                    Some(n) => validate_json(&n),
                    None => Ok(study::describe_all()),
                };
                v.map(|v| println!("{}", serde_json::to_string_pretty(&v).unwrap_or_default()))
            } else {
                geardyn_cli::models_text(name.as_deref()).map(|t| print!("{t}"))
            }
        }
        Cmd::Validate {
            diff: Some(rev),
            root,
            ..
        } => geardyn_cli::validate_diff(&root, Some(rev.as_str()).filter(|r| !r.is_empty())),
        Cmd::Validate {
            check,
            filter,
            shard,
            root,
            ..
        } => geardyn_cli::validate(&root, check, filter.as_deref(), shard.as_deref()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => {
            eprintln!("error: {}", f.message);
            ExitCode::from(f.code)
        }
    }
}

fn validate_json(name: &str) -> Result<serde_json::Value, geardyn_cli::Failure> {
    Ok(study::describe_json(study::model_spec(name)?))
}
