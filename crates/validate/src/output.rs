//! The validation run behind `cargo xtask validate [--check]` and `geardyn validate [--check]`:
//! run every study, render the files under `validation/`, then write them (pruning stale
//! generated files) or compare them byte for byte with the committed ones.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use std::time::Instant;

use crate::{Error, ReadingsIndex, Study, Verdict};

/// Directories under `validation/` that are entirely generated (stale files there are removed).
fn generated_dirs() -> Vec<String> {
    let mut v: Vec<String> = crate::Paper::ALL
        .iter()
        .map(|p| p.dir().to_owned())
        .collect();
    v.push("snapshots".to_owned());
    v
}

const HINT: &str = "run `cargo xtask validate` locally and review/commit the diff \
                    (git diff validation/)";

/// What a validation run did.
#[derive(Debug, Clone, Default)]
pub struct ValidationSummary {
    /// Studies run.
    pub studies: usize,
    /// Comparison/claim verdicts: pass, deviation, inconclusive.
    pub tally: (usize, usize, usize),
    /// Wall time of the studies (s).
    pub seconds: f64,
    /// Warnings (failed studies, undocumented readings, deviations without a reading).
    pub warnings: Vec<String>,
    /// What was written or checked, one line.
    pub message: String,
    /// The cost table of the run as aligned text ([`crate::cost_text`]; the same figures are
    /// in `validation/stats/cost.csv`).
    pub cost_table: String,
}

/// Whether a study id is selected by a filter: `=ID` selects exactly that study (`cargo xtask
/// validate --only ID`), any other text the studies whose id contains it (`--filter`).
///
/// ```
/// use geardyn_validate::study_selected;
/// assert!(study_selected("liu2021-fig11-speed-sweep", "fig11"));
/// assert!(study_selected("liu2021-fig11-speed-sweep", "=liu2021-fig11-speed-sweep"));
/// assert!(!study_selected("liu2021-fig11-speed-sweep", "=liu2021-fig11"));
/// ```
pub fn study_selected(id: &str, filter: &str) -> bool {
    match filter.strip_prefix('=') {
        Some(exact) => id == exact,
        None => id.contains(filter),
    }
}

/// Run every validation study (or those selected by `filter`, [`study_selected`]) under the repository
/// `root`, then write `validation/` (`check = false`) or compare with it (`check = true`:
/// an error lists every differing file). `progress(study, done, total)` is called after each
/// study.
pub fn run_validation(
    root: &Path,
    check: bool,
    filter: Option<&str>,
    progress: &(dyn Fn(&crate::RunProgress) + Sync),
) -> Result<ValidationSummary, Error> {
    if check && filter.is_some() {
        return Err(Error::Study(
            "--filter cannot be combined with --check".to_owned(),
        ));
    }
    let vdir = root.join("validation");
    if !vdir.is_dir() {
        return Err(Error::Study(format!(
            "{} is not a directory: run from the geardyn repository root (or pass --root)",
            vdir.display()
        )));
    }
    let t0 = Instant::now();
    let mut studies = crate::all_studies();
    if let Some(f) = filter {
        studies.retain(|s| study_selected(s.id, f));
        if studies.is_empty() {
            return Err(Error::Study(format!(
                "no study matches {f:?}; the studies are: {}",
                crate::all_studies()
                    .iter()
                    .map(|s| s.id)
                    .collect::<Vec<_>>()
                    .join(", ")
            )));
        }
    }
    // one in-run memo of the shared responses (models::memo): a study that needs a response
    // another study computed gets the same bits without recomputing them
    let memo = models::memo::Session::open(models::memo::DEFAULT_CAPACITY);
    let results = run_with_progress(&studies, progress);
    let memo_stats = models::memo::stats();
    drop(memo);
    let elapsed = t0.elapsed();

    let idx = ReadingsIndex::scan(root)?;
    let files = crate::render_all(&results, &idx);
    // solver statistics and full-precision data: written (also under --check, for inspection),
    // never compared byte for byte; their digest is in the committed stats-digest.txt
    write_stats(&vdir, &crate::render_stats(&results), filter.is_none())?;
    // the cost table: beside the statistics, outside their digest (timings differ run to run)
    let cost_path = vdir.join(STATS_DIR).join(COST_FILE);
    write_atomic(
        &cost_path,
        crate::cost_csv(&results, elapsed.as_secs_f64()).as_bytes(),
    )?;

    let mut warnings = Vec::new();
    let (mut p, mut d, mut i) = (0, 0, 0);
    for r in &results {
        match &r.output {
            Ok(o) => {
                let t = o.tally();
                p += t.0;
                d += t.1;
                i += t.2;
                let undocumented: BTreeSet<&String> = o
                    .comparisons
                    .iter()
                    .flat_map(|c| c.readings.iter())
                    .chain(o.claims.iter().flat_map(|c| c.readings.iter()))
                    .filter(|id| !idx.contains(id))
                    .collect();
                for id in undocumented {
                    warnings.push(format!(
                        "warning: {}: reading {id} not found in docs/readings",
                        r.study.id
                    ));
                }
                let dev = o
                    .comparisons
                    .iter()
                    .filter(|c| c.verdict() == Verdict::Deviation && c.readings.is_empty())
                    .count();
                if dev > 0 {
                    warnings.push(format!(
                        "note: {}: {dev} deviation(s) without a reading",
                        r.study.id
                    ));
                }
            }
            Err(e) => warnings.push(format!("warning: study {} failed: {e}", r.study.id)),
        }
    }
    // integrity rules (crate::audit): causes named, no shared file names, no verdict from a
    // flagged point; fatal under --check, warnings otherwise
    let problems = crate::audit(&results);
    if check && !problems.is_empty() {
        return Err(Error::Study(format!(
            "validate --check: {} integrity problem(s):\n{}",
            problems.len(),
            problems
                .iter()
                .map(|p| p.to_string())
                .collect::<Vec<_>>()
                .join("\n")
        )));
    }
    warnings.extend(problems.iter().map(|p| format!("error: {p}")));
    let mut summary = ValidationSummary {
        studies: results.len(),
        tally: (p, d, i),
        seconds: elapsed.as_secs_f64(),
        warnings,
        message: String::new(),
        cost_table: format!(
            "{}{}",
            crate::cost_text(&results, elapsed.as_secs_f64()),
            memo_stats
                .iter()
                .map(|(f, hits, misses)| format!(
                    "memo {f}: {hits} computations saved, {misses} computed\n"
                ))
                .collect::<String>()
        ),
    };
    summary.message = if check {
        check_files(&vdir, &files)?
    } else {
        write_files(&vdir, &files, filter.is_none())?
    };
    Ok(summary)
}

/// Run the studies ([`crate::run_studies_with`]) while a meter thread reports the progress every
/// half second (and once at the end, at the total) through `progress`. The meter thread ends
/// when the studies have (a flag set by a guard, also if a study panics).
fn run_with_progress(
    studies: &[Study],
    progress: &(dyn Fn(&crate::RunProgress) + Sync),
) -> Vec<crate::StudyResult> {
    use std::sync::atomic::{AtomicBool, Ordering};
    let accounts: Vec<_> = studies
        .iter()
        .map(|s| system::account::Account::new(s.id))
        .collect();
    let meter = std::sync::Mutex::new(crate::ProgressMeter::new(studies));
    let stop = AtomicBool::new(false);
    let report = || {
        if let Ok(mut m) = meter.lock() {
            progress(&m.read(&accounts));
        }
    };
    struct Stop<'a>(&'a AtomicBool);
    impl Drop for Stop<'_> {
        fn drop(&mut self) {
            self.0.store(true, Ordering::Relaxed);
        }
    }
    let results = std::thread::scope(|sc| {
        sc.spawn(|| {
            while !stop.load(Ordering::Relaxed) {
                report();
                std::thread::sleep(std::time::Duration::from_millis(500));
            }
        });
        let _stop = Stop(&stop);
        crate::run_studies_with(studies, &accounts, |s| {
            if let (Ok(mut m), Some(i)) = (meter.lock(), studies.iter().position(|x| x.id == s.id))
            {
                m.finished(i, s.id);
            }
        })
    });
    report();
    results
}

/// Committed generated files: relative path → contents.
fn committed(vdir: &Path) -> Result<BTreeMap<String, Vec<u8>>, Error> {
    let mut m = BTreeMap::new();
    for d in generated_dirs() {
        let dir = vdir.join(&d);
        if !dir.is_dir() {
            continue;
        }
        let rd = std::fs::read_dir(&dir).map_err(io(&dir))?;
        for e in rd {
            let e = e.map_err(io(&dir))?;
            if e.path().is_file() {
                let name = format!("{d}/{}", e.file_name().to_string_lossy());
                let path = e.path();
                let bytes = std::fs::read(&path).map_err(io(&path))?;
                m.insert(name, bytes);
            }
        }
    }
    for name in AGGREGATES {
        let path = vdir.join(name);
        if path.is_file() {
            m.insert((*name).to_owned(), std::fs::read(&path).map_err(io(&path))?);
        }
    }
    Ok(m)
}

/// Generated files at the top of `validation/` that sum up every study (not written by a
/// `--filter` run).
const AGGREGATES: &[&str] = &["REPORT.md", crate::VERDICTS_FILE, crate::STATS_DIGEST_FILE];

/// The uncommitted statistics directory, relative to `validation/` (gitignored).
pub const STATS_DIR: &str = "stats";

/// The cost table of the last run under [`STATS_DIR`] ([`crate::cost_csv`]).
pub const COST_FILE: &str = "cost.csv";

fn write_stats(vdir: &Path, stats: &BTreeMap<String, Vec<u8>>, prune: bool) -> Result<(), Error> {
    let dir = vdir.join(STATS_DIR);
    if prune && dir.is_dir() {
        std::fs::remove_dir_all(&dir).map_err(io(&dir))?;
    }
    for (k, v) in stats {
        write_atomic(&dir.join(k), v)?;
    }
    Ok(())
}

fn check_files(vdir: &Path, files: &BTreeMap<String, Vec<u8>>) -> Result<String, Error> {
    let old = committed(vdir)?;
    let mut problems = Vec::new();
    for (k, v) in files {
        match old.get(k) {
            None => problems.push(format!("new file:  validation/{k}")),
            Some(o) if o != v => {
                problems.push(format!("changed:   validation/{k}{}", first_diff(o, v)))
            }
            Some(_) => {}
        }
    }
    for k in old.keys() {
        if !files.contains_key(k) {
            problems.push(format!("stale:     validation/{k} (no longer generated)"));
        }
    }
    if problems.is_empty() {
        Ok(format!(
            "validate --check: {} generated files match the committed ones",
            files.len()
        ))
    } else {
        // the meaning first: verdicts, classes, rows added or removed
        let verdicts = match (
            old.get(crate::VERDICTS_FILE),
            files.get(crate::VERDICTS_FILE),
        ) {
            (Some(o), Some(n)) => {
                crate::check_verdicts(&String::from_utf8_lossy(o), &String::from_utf8_lossy(n))
                    .err()
                    .map(|m| format!("VERDICTS DIFFER from the committed ones:\n{m}\n"))
                    .unwrap_or_default()
            }
            _ => String::new(),
        };
        let digest = if old.get(crate::STATS_DIGEST_FILE) != files.get(crate::STATS_DIGEST_FILE) {
            "validation/stats/ digest differs: a solver statistic or full-precision value \
             changed (regenerate and commit) or is not deterministic (compare validation/stats/ \
             of two runs with different RAYON_NUM_THREADS)\n"
        } else {
            ""
        };
        Err(Error::Study(format!(
            "{verdicts}{digest}{}\n{} generated file(s) differ from the committed validation outputs/snapshots; {HINT}",
            problems
                .iter()
                .map(|p| p.to_string())
                .collect::<Vec<_>>()
                .join("\n"),
            problems.len()
        )))
    }
}

/// The first differing line, for the CI log.
fn first_diff(old: &[u8], new: &[u8]) -> String {
    let o = String::from_utf8_lossy(old);
    let n = String::from_utf8_lossy(new);
    for (i, (a, b)) in o.lines().zip(n.lines()).enumerate() {
        if a != b {
            let cut = |s: &str| s.chars().take(160).collect::<String>();
            return format!("\n    line {}:\n    - {}\n    + {}", i + 1, cut(a), cut(b));
        }
    }
    format!(" ({} vs {} lines)", o.lines().count(), n.lines().count())
}

fn write_files(
    vdir: &Path,
    files: &BTreeMap<String, Vec<u8>>,
    prune: bool,
) -> Result<String, Error> {
    let old = committed(vdir)?;
    let mut changed = 0;
    for (k, v) in files {
        let path = vdir.join(k);
        if old.get(k) == Some(v) || (!prune && AGGREGATES.contains(&k.as_str())) {
            // (a --filter run writes its studies' files but not a partial report)
            continue;
        }
        write_atomic(&path, v)?;
        changed += 1;
    }
    let mut removed = 0;
    if prune {
        for k in old.keys() {
            if !files.contains_key(k) {
                let path = vdir.join(k);
                std::fs::remove_file(&path).map_err(io(&path))?;
                removed += 1;
            }
        }
    }
    Ok(format!(
        "wrote validation/: {} files ({changed} changed, {removed} removed); review with `git diff validation/`",
        files.len()
    ))
}

/// Write `bytes` to `path` atomically: into a temporary file beside it, then renamed over it
/// (a reader, or a run killed half-way, never sees a half-written file); the parent directory
/// is created when missing.
pub(crate) fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent).map_err(io(parent))?;
    }
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    let tmp = std::path::PathBuf::from(tmp);
    std::fs::write(&tmp, bytes).map_err(io(&tmp))?;
    std::fs::rename(&tmp, path).map_err(io(path))
}

fn io(path: &Path) -> impl Fn(std::io::Error) -> Error + '_ {
    move |source| Error::Io {
        path: path.display().to_string(),
        source,
    }
}

/// `cargo xtask validate --diff [REV]`: the markdown summary of what changed in meaning between
/// `validation/verdicts.csv` at `rev` (default: the merge base of `HEAD` with `main`, else
/// `origin/main`) and the working tree's file as it is (run `cargo xtask validate` first, or
/// rely on CI's `--check`, which guarantees the committed file is fresh). Figures whose data
/// digest changed are compared series by series from their committed CSVs.
pub fn diff_against(root: &Path, rev: Option<&str>) -> Result<String, Error> {
    let git = |args: &[&str]| -> Result<String, Error> {
        let out = std::process::Command::new("git")
            .arg("-C")
            .arg(root)
            .args(args)
            .output()
            .map_err(|e| Error::Study(format!("git {}: {e}", args.join(" "))))?;
        if out.status.success() {
            Ok(String::from_utf8_lossy(&out.stdout).into_owned())
        } else {
            Err(Error::Study(format!(
                "git {}: {}",
                args.join(" "),
                String::from_utf8_lossy(&out.stderr).trim()
            )))
        }
    };
    let base = match rev {
        Some(r) if !r.is_empty() => r.to_owned(),
        _ => git(&["merge-base", "HEAD", "main"])
            .or_else(|_| git(&["merge-base", "HEAD", "origin/main"]))?
            .trim()
            .to_owned(),
    };
    let label = git(&["rev-parse", "--short", &base])
        .map(|s| format!("{} ({})", base, s.trim()))
        .unwrap_or_else(|_| base.clone());
    let vpath = |p: &str| format!("{base}:validation/{p}");
    let old_text = git(&["show", &vpath(crate::VERDICTS_FILE)]).unwrap_or_default();
    let new_path = root.join("validation").join(crate::VERDICTS_FILE);
    let new_text = std::fs::read_to_string(&new_path).map_err(io(&new_path))?;
    let old = crate::parse_verdicts(&old_text)?;
    let new = crate::parse_verdicts(&new_text)?;
    let d = crate::diff_verdicts(&old, &new);
    let detail = |o: &crate::verdicts::VerdictRow, n: &crate::verdicts::VerdictRow| {
        let before = git(&["show", &vpath(&o.paper)]).unwrap_or_default();
        let after =
            std::fs::read_to_string(root.join("validation").join(&n.paper)).unwrap_or_default();
        crate::verdicts::figure_change(&before, &after)
    };
    let md = d.to_markdown(&label, &detail);
    if old_text.is_empty() {
        // say so before the list of added rows
        let (head, rest) = md.split_once("\n\n").unwrap_or((md.as_str(), ""));
        return Ok(format!(
            "{head}\n\n_The base revision has no `validation/verdicts.csv`: every row is listed as \
             added._\n\n{rest}"
        ));
    }
    Ok(md)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Comparison, Cost, Paper, Reference, StudyOutput, StudyResult, Tolerance};

    fn run_with(model: f64) -> Vec<StudyResult> {
        fn pass() -> Result<StudyOutput, Error> {
            Ok(StudyOutput::new())
        }
        let study = Study {
            id: "liu2021-check",
            paper: Paper::Liu2021,
            source: "p. 1",
            title: "t",
            description: "",
            cost: Cost::Fast,
            run: pass,
        };
        let mut out = StudyOutput::new();
        out.compare(Comparison::new(
            "f_c",
            "Hz",
            Reference::computed(38.67, "Table 2"),
            model,
            Tolerance::printed("38.67").unwrap(),
        ));
        vec![StudyResult {
            study,
            output: Ok(out),
            cost: Default::default(),
        }]
    }

    /// `--check` against committed files: passes on identical outputs, fails on a flipped
    /// verdict and names it first; a move inside the band fails too (a byte changed) but
    /// without a verdict section.
    #[test]
    fn check_names_a_flipped_verdict_first() {
        let dir = std::env::temp_dir().join(format!("geardyn-check-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let idx = ReadingsIndex::default();
        let base = crate::render_all(&run_with(38.6712), &idx);
        write_files(&dir, &base, true).unwrap();
        assert!(check_files(&dir, &base).is_ok());

        let flipped = crate::render_all(&run_with(38.69), &idx);
        let err = check_files(&dir, &flipped).unwrap_err().to_string();
        assert!(
            err.starts_with("validation study error: VERDICTS DIFFER")
                || err.contains("VERDICTS DIFFER"),
            "{err}"
        );
        let first = err
            .find("pass → DEVIATION")
            .expect("the flipped row is named");
        assert!(first < err.find("changed:").unwrap(), "{err}");

        let moved = crate::render_all(&run_with(38.6741), &idx);
        let err = check_files(&dir, &moved).unwrap_err().to_string();
        assert!(!err.contains("VERDICTS DIFFER"), "{err}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
