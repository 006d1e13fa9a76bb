//! geardyn project automation.
//!
//! * `cargo xtask validate` — run every validation study, write `validation/` (CSV, SVG,
//!   snapshots, `REPORT.md`).
//! * `cargo xtask validate --only STUDY` — run one study (exact id) and write its outputs.
//! * `cargo xtask validate --check` — regenerate in memory and fail if any committed output or
//!   snapshot would change (CI); a changed verdict is listed first. `--check --shard I/N`: only
//!   the studies of shard I of N (the parallel CI jobs).
//! * `cargo xtask validate --diff [REV]` — markdown summary of what changed in meaning between
//!   `validation/verdicts.csv` at REV (default: merge base with `main`) and the working tree.
//! * `cargo xtask study <file.toml>` — run a user study (format in `docs/studies.md`).
//! * `cargo xtask heavy-tests` — the heavy numerical tests (`#[ignore = "heavy: …"]` in
//!   `geardyn-models`, `geardyn-orbit`, `geardyn-study` and `geardyn-validate`), optimised:
//!   `cargo test --profile validate` with `--ignored`. `cargo test --workspace` skips them so
//!   that the contributor loop stays short (issue 26); `.ci/run` runs both.
//!
//! Both run the code of the `geardyn` command (`cli::validate`, `cli::study`).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(name = "xtask", about = "geardyn project automation")]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Run every validation study and write validation/ (CSV, SVG, snapshots, REPORT.md).
    Validate {
        /// Do not write: fail if any generated file differs from the committed one.
        #[arg(long)]
        check: bool,
        /// Only studies whose id contains this text (never with --check).
        #[arg(long)]
        filter: Option<String>,
        /// With --check: only shard I of N (each study in exactly one shard; the CI splits the
        /// check this way). The cross-study aggregates are left to the full --check.
        #[arg(long, value_name = "I/N", requires = "check", conflicts_with_all = ["filter", "only"])]
        shard: Option<String>,
        /// Only the study with exactly this id (never with --check); an unknown id lists the
        /// studies. The fast loop for one study: `cargo xtask validate --only liu2021-table2-amplitude-ratio`.
        #[arg(long, value_name = "STUDY", conflicts_with_all = ["check", "filter"])]
        only: Option<String>,
        /// Do not run: print the verdict diff (markdown) between validation/verdicts.csv at REV
        /// (default: the merge base with `main`) and the working tree.
        #[arg(long, value_name = "REV", num_args = 0..=1, default_missing_value = "",
              conflicts_with_all = ["check", "filter", "only"])]
        diff: Option<String>,
    },
    /// Run a user study file (see docs/studies.md); writes CSV, SVG and a JSON summary.
    Study {
        /// The study file (TOML).
        file: PathBuf,
        /// Output directory (default: next to the study file, `<name>/`).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Compute only shard `i/n` and write its partial result (see docs/scaling.md).
        #[arg(long, value_name = "I/N")]
        shard: Option<String>,
    },
    /// Run the heavy numerical tests (ignored by `cargo test --workspace`) in the optimised
    /// `validate` profile: `cargo test --profile validate -p geardyn-models -p geardyn-orbit
    /// -p geardyn-study -p geardyn-validate --lib --tests -- --ignored --skip fuzz::`, then ARGS
    /// (e.g. a test-name filter).
    HeavyTests {
        /// Passed to the test binaries after `--ignored` (filters, `--nocapture`, ...).
        #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
        args: Vec<String>,
    },
    /// Merge shards' partial results into the outputs of the whole study.
    Merge {
        /// The study file the shards were computed from.
        file: PathBuf,
        /// Output directory (default: next to the study file, `<name>/`).
        #[arg(long)]
        out: Option<PathBuf>,
        /// The partial results.
        #[arg(required = true)]
        parts: Vec<PathBuf>,
    },
}

/// The repository root (parent of `xtask/`).
fn repo_root() -> PathBuf {
    let manifest = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    manifest.parent().map(PathBuf::from).unwrap_or(manifest)
}

/// The printing helpers among the ignored tests of `geardyn-models` (tables for the docs, not
/// checks); `heavy-tests` skips them.
const PRINTING_HELPERS: [&str; 2] = ["paper_values", "karpov_levin_figures"];

/// `cargo xtask heavy-tests`: run cargo (the one that runs this xtask, `$CARGO`) on the heavy
/// tests and return its exit status.
fn heavy_tests(args: &[String]) -> ExitCode {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let mut cmd = std::process::Command::new(cargo);
    cmd.current_dir(repo_root()).args([
        "test",
        "--profile",
        "validate",
        "-p",
        "geardyn-models",
        "-p",
        "geardyn-orbit",
        "-p",
        "geardyn-study",
        "-p",
        "geardyn-validate",
        "--lib",
        "--tests",
        "--",
        "--ignored",
        // the study crate's fuzzer is ignored too; `.ci/run` runs it on its own, with a budget
        "--skip",
        "fuzz::",
    ]);
    for helper in PRINTING_HELPERS {
        cmd.args(["--skip", helper]);
    }
    cmd.args(args);
    match cmd.status() {
        Ok(status) if status.success() => ExitCode::SUCCESS,
        Ok(status) => {
            eprintln!("error: the heavy tests failed ({status})");
            ExitCode::FAILURE
        }
        Err(e) => {
            eprintln!("error: could not run cargo: {e}");
            ExitCode::FAILURE
        }
    }
}

fn main() -> ExitCode {
    // keep geardyn-math's C math symbols in the link (deterministic sin, pow, … for the
    // dependencies too)
    math::c_symbols::link();
    let cli = Cli::parse();
    let result = match cli.cmd {
        Cmd::Validate {
            diff: Some(rev), ..
        } => cli::validate_diff(&repo_root(), Some(rev.as_str()).filter(|r| !r.is_empty())),
        Cmd::Validate {
            check,
            filter,
            only,
            shard,
            ..
        } => {
            let filter = only.map(|id| format!("={id}")).or(filter);
            cli::validate(&repo_root(), check, filter.as_deref(), shard.as_deref())
        }
        Cmd::Study { file, out, shard } => match shard {
            Some(s) => cli::study_shard(&file, out.as_deref(), &s),
            None => cli::study(&file, out.as_deref()),
        },
        Cmd::Merge { file, out, parts } => cli::merge(&file, out.as_deref(), &parts),
        Cmd::HeavyTests { args } => return heavy_tests(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => {
            eprintln!("error: {}", f.message);
            ExitCode::from(f.code)
        }
    }
}
