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
        /// Repository root holding `validation/` and `docs/` (default: current directory).
        #[arg(long, default_value = ".")]
        root: PathBuf,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.cmd {
        Cmd::Study { file, out } => geardyn_cli::study(&file, out.as_deref()),
        Cmd::Models { name, json } => {
            if json {
                let v = match name {
                    Some(n) => validate_json(&n),
                    None => Ok(validate::describe_all()),
                };
                v.map(|v| println!("{}", serde_json::to_string_pretty(&v).unwrap_or_default()))
            } else {
                geardyn_cli::models_text(name.as_deref()).map(|t| print!("{t}"))
            }
        }
        Cmd::Validate {
            check,
            filter,
            root,
        } => geardyn_cli::validate(&root, check, filter.as_deref()),
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
    let m = validate::model_spec(name)?;
    Ok(serde_json::json!({
        "name": m.name,
        "description": m.description,
        "info": (m.describe)(),
    }))
}
