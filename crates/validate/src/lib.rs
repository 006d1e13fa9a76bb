//! Validation harness of geardyn: every published table, figure, equation and claim of the three
//! source papers, held against the models, with the comparison written out and snapshot-tested.
//!
//! # What a study is
//!
//! A [`Study`] names one published item — `paper`, `source` (`"Table 2, p. 12"`), a title and a
//! one-paragraph description of how the paper is read — and a function `run` returning a
//! [`StudyOutput`]:
//!
//! * **comparisons** ([`Comparison`]): quantity, unit, the paper's value ([`Reference`], kept as
//!   printed), the model's value, deviation (absolute and relative), a [`Tolerance`] with its
//!   basis ([`ToleranceBasis`]) and the derivation of its size from the source (printed digits,
//!   round numbers, figure reading with the axis resolution, the one "about" band
//!   [`ABOUT_BAND`], experimental scatter, numerical), the [`Evidence`] class (reproduction,
//!   consistency, calibration, transcription, holds by construction), flags of the points the
//!   model value rests on, and the [`Verdict`] (pass if |model − paper| ≤ tolerance, else
//!   `DEVIATION`; `inconclusive` when flagged; `shown` when not judged or unable to fail);
//! * **claims** ([`Claim`]): a statement of the paper quoted with its page, the model's evidence
//!   (with numbers) and a verdict (pass / deviation / inconclusive);
//! * **tables** ([`Table`]): data written as CSV with `name [unit]` headers;
//! * **figures** ([`Figure`]): series of curves rendered to SVG with plotters (their data is also
//!   written as long-format CSV);
//! * **readings**: comparisons and claims carry reading ids (`R-LIU-EQ20`, `R-KARPOV-EQ8`, …) —
//!   headings `### R-… — title` in `docs/readings/*.md` — which the report links; use them to
//!   explain every deviation and every choice between a printed and a consistent form.
//!
//! # Rules for studies
//!
//! 1. The paper's numbers come from `validation/published/<paper>.toml` ([`Published`], loaded
//!    with [`published!`]), each with its source; never write a paper number into study code, and
//!    never invent digitised points (figures without printed numbers are checked through the
//!    text's claims and snapshotted).
//! 2. Set the tolerance from the printed precision ([`Comparison::published`] does it:
//!    half a unit in the last printed digit), the digitising uncertainty or the text's "about" —
//!    before looking at the model number. A deviation stays in, with its reading.
//! 3. Be deterministic: the same bits for any rayon thread count (parallel sweeps collect in
//!    input order, no parallel float reductions, fixed iteration counts). All numbers are written
//!    at [`SIGNIFICANT_DIGITS`] = 6 significant digits ([`fmt_sig`]).
//! 4. Mark anything that integrates or continues a dynamic model [`Cost::Heavy`]; `cargo test -p
//!    validate` runs only [`Cost::Fast`] studies. The whole `cargo xtask validate` should stay
//!    within a couple of minutes on 2 cores, so keep sweeps modest.
//! 5. Ids and table/figure names are file-name parts: `a-z 0-9 - _ .`, id prefixed by the paper
//!    (`liu2021-fig11-omega`).
//!
//! Study lists live in `src/studies/<file>.rs`, each exposing `pub fn studies() -> Vec<Study>`,
//! gathered by [`all_studies`].
//!
//! # Outputs (`cargo xtask validate`)
//!
//! [`run_studies`] runs the studies in parallel; [`render_all`] turns the results into the
//! committed files relative to `validation/`, at the precision a reviewer judges
//! ([`precision`]: model values rounded relative to their band, data at drawing precision):
//! `<paper>/<id>.csv` (comparison and claim rows), `<paper>/<id>_<table>.csv` (without solver
//! statistics and one-period samples of non-periodic orbits), `<paper>/<id>_<figure>.svg`
//! (+ `.csv`), `snapshots/<id>.snap` (insta format), `verdicts.csv` ([`verdicts`], read by
//! `cargo xtask validate --diff [REV]`), `stats-digest.txt` and `REPORT.md` (headline:
//! reproductions by paper; every comparison and claim with class, verdict and links to the
//! readings). [`render_stats`] gives the uncommitted `validation/stats/` (every column at 6
//! significant digits).
//! `cargo xtask validate --check` regenerates everything in memory and fails if any byte differs
//! from the committed files, or if [`audit()`] finds a deviation/inconclusive row without a reading
//! or cause, two outputs sharing a file name, or a verdict resting on a flagged point.
//!
//! # Example: a complete study
//!
//! ```
//! use geardyn_validate::{
//!     Claim, Comparison, Cost, Figure, Paper, Reference, Series, Study, StudyOutput, Table,
//!     Tolerance, Verdict,
//! };
//!
//! fn run() -> Result<StudyOutput, geardyn_validate::Error> {
//!     // In a real study: let paper = geardyn_validate::published!("karpov2017.toml")?;
//!     //                  out.compare(Comparison::published(paper.value("table1.delta")?, model)?);
//!     let exact = 2.0_f64.sqrt();
//!     let model = 1.414_213;
//!     let mut out = StudyOutput::new();
//!     out.compare(
//!         Comparison::new("√2", "1", Reference::computed(exact, "exact"), model,
//!             Tolerance::numerical(1e-6))
//!             .reading("R-KARPOV-EQ4"),
//!     );
//!     out.claim(Claim::new("√2 is irrational", "p. 1", "no counterexample found", Verdict::Pass));
//!     let mut t = Table::new("points", &[("x", "m"), ("y", "N")]);
//!     t.push_nums(&[1.0, 2.0])?;
//!     out.table(t);
//!     out.figure(
//!         Figure::new("curve", "y = x²", ("x", "m"), ("y", "m²"))
//!             .with(Series::line("model", (0..10).map(|i| (i as f64, (i * i) as f64)).collect())),
//!     );
//!     Ok(out)
//! }
//!
//! let study = Study {
//!     id: "example-sqrt2",
//!     paper: Paper::Karpov2017,
//!     source: "Eq. (0), p. 0",
//!     title: "An example",
//!     description: "Shows the harness.",
//!     cost: Cost::Fast,
//!     run,
//! };
//! let out = study.execute().unwrap();
//! assert_eq!(out.tally(), (2, 0, 0));
//! ```
//!
//! # User studies
//!
//! The `geardyn study` engine (study files, shards, merge, maps) is the `geardyn-study` crate;
//! the harness does not use it.
//!
//! # References
//!
//! Liu, Lv, Zhao 2021 (Mech. Sci. 12:361); Karpov et al. 2017 (Mech. Mach. Theory 114:1);
//! Yu, Sun, Li, Wu 2021 (preprint). See `docs/readings/` for every printed-vs-consistent choice.

#![deny(missing_docs)]

mod audit;
mod error;
mod output;
pub mod precision;
mod published;
mod render;
mod schedule;
mod studies;
mod study;
pub mod verdicts;

pub use audit::{Problem, audit, audit_output, output_files};
pub use error::{Error, ResultExt};
/// The step-statistic columns of a time-stepping record (from the model contract).
pub use models::contract::STEP_STATISTICS;
pub use output::{
    COST_FILE, MEMO_FILE, STATS_DIR, Shard, ValidationSummary, diff_against, run_validation,
    run_validation_sharded, study_selected,
};
pub use plot::{
    Cell, Column, Figure, OKABE_ITO, SIGNIFICANT_DIGITS, Series, Style, Table, committed_text,
    fmt_sig, fmt6, full_text, heatmap, step_path, unsettled,
};
// the output layer (tables, figures, heat maps, number formats) is the `plot` crate; its
// modules are in scope under their old names so that `crate::table::…` paths keep working
pub(crate) use plot::{figure, format, table};
pub use published::{Published, PublishedClaim, PublishedValue};
pub use render::{
    ReadingsIndex, STATS_DIGEST_FILE, StudyCost, StudyResult, comparisons_csv,
    comparisons_csv_full, cost_csv, cost_text, insta_snap, memo_csv, memo_text, render_all,
    render_stats, report, run_studies, run_studies_with, snapshot_body, stats_digest,
};
pub use schedule::{
    ProgressMeter, RunProgress, UNKNOWN_CPU_SECONDS, expected_cpu_seconds, longest_first,
};
pub use studies::all_studies;
pub use study::{
    ABOUT_BAND, Claim, Comparison, Cost, Evidence, Paper, Reference, Study, StudyOutput, Tolerance,
    ToleranceBand, ToleranceBasis, Verdict,
};
pub use verdicts::{VERDICTS_FILE, VerdictDiff, check_verdicts, diff_verdicts, parse_verdicts};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn study_ids_unique_and_valid() {
        let studies = all_studies();
        let mut ids: Vec<&str> = studies.iter().map(|s| s.id).collect();
        ids.sort_unstable();
        let n = ids.len();
        ids.dedup();
        assert_eq!(ids.len(), n, "duplicate study id");
        for s in &studies {
            assert!(
                s.id.starts_with(s.paper.dir()),
                "{} should start with {}",
                s.id,
                s.paper.dir()
            );
        }
    }

    #[test]
    fn send_sync() {
        fn check<T: Send + Sync>() {}
        check::<Study>();
        check::<StudyOutput>();
        check::<Error>();
    }
}

/// The README's example, compiled and run as a doctest so that it cannot rot.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
