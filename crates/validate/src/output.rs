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
    run_validation_sharded(root, check, filter, None, progress)
}

/// One shard of `--check`: shard `index` of `count` (`1 ≤ index ≤ count`). The studies are
/// dealt to the shards by their expected CPU time ([`crate::expected_cpu_seconds`]): in the
/// order of [`crate::longest_first`], each to the shard with the least expected time so far
/// (ties: the lower shard), so that every study is in exactly one shard and the shards cost
/// about the same (the largest study alone sets the floor). Deterministic: the same shards on
/// every machine.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// 1-based index of the shard.
    pub index: usize,
    /// Number of shards.
    pub count: usize,
}

impl std::str::FromStr for Shard {
    type Err = Error;
    /// `I/N` with `1 ≤ I ≤ N ≤ 1000`.
    fn from_str(s: &str) -> Result<Shard, Error> {
        let bad = || {
            Error::Study(format!(
                "--shard {s:?}: expected I/N with 1 <= I <= N <= 1000"
            ))
        };
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let (index, count): (usize, usize) = (
            i.trim().parse().map_err(|_| bad())?,
            n.trim().parse().map_err(|_| bad())?,
        );
        if index == 0 || index > count || count > 1000 {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }
}

impl Shard {
    /// Which of `studies` are in this shard (one flag per study, in order).
    pub fn members(&self, studies: &[Study]) -> Vec<bool> {
        let mut load = vec![0.0_f64; self.count];
        let mut of = vec![0usize; studies.len()];
        for i in crate::longest_first(studies) {
            // the least-loaded shard (the first of equals)
            let mut best = 0;
            for k in 1..self.count {
                if load[k] < load[best] {
                    best = k;
                }
            }
            load[best] += crate::expected_cpu_seconds(studies[i].id);
            of[i] = best;
        }
        of.iter().map(|&k| k == self.index - 1).collect()
    }
}

/// [`run_validation`] restricted to one [`Shard`] (only with `check`): the shard's studies are
/// run, and their files, snapshots and rows of `verdicts.csv` are compared with the committed
/// ones; the other aggregates (`REPORT.md`, `stats-digest.txt`) and the rule that a study's
/// reproduction is counted once across studies need every study and are checked by the full
/// `--check`.
pub fn run_validation_sharded(
    root: &Path,
    check: bool,
    filter: Option<&str>,
    shard: Option<Shard>,
    progress: &(dyn Fn(&crate::RunProgress) + Sync),
) -> Result<ValidationSummary, Error> {
    if check && filter.is_some() {
        return Err(Error::Study(
            "--filter cannot be combined with --check".to_owned(),
        ));
    }
    if shard.is_some() && (!check || filter.is_some()) {
        return Err(Error::Study(
            "--shard needs --check and no --filter/--only".to_owned(),
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
    if let Some(sh) = shard {
        let members = sh.members(&studies);
        studies = studies
            .into_iter()
            .zip(members)
            .filter(|(_, m)| *m)
            .map(|(s, _)| s)
            .collect();
    }
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
    let whole = filter.is_none() && shard.is_none();
    write_stats(&vdir, &crate::render_stats(&results), whole)?;
    // the cost table: beside the statistics, outside their digest (timings differ run to run)
    let cost_path = vdir.join(STATS_DIR).join(COST_FILE);
    write_atomic(
        &cost_path,
        crate::cost_csv(&results, elapsed.as_secs_f64()).as_bytes(),
    )?;
    write_atomic(
        &vdir.join(STATS_DIR).join(MEMO_FILE),
        crate::memo_csv(&memo_stats).as_bytes(),
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
            crate::memo_text(&memo_stats)
        ),
    };
    summary.message = if let (true, Some(sh)) = (check, shard) {
        let ids: BTreeSet<&str> = studies.iter().map(|s| s.id).collect();
        check_shard_files(&vdir, &files, &ids, sh)?
    } else if check {
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

/// The in-run memo's computations, their CPU and what it saved, of the last run under
/// [`STATS_DIR`] ([`crate::memo_csv`]).
pub const MEMO_FILE: &str = "memo.csv";

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

/// `--check --shard`: the shard's generated files against the committed ones (no stale-file
/// check: the other shards' files are not generated here), and its studies' rows of
/// `verdicts.csv`; the other aggregates are skipped (see [`run_validation_sharded`]).
fn check_shard_files(
    vdir: &Path,
    files: &BTreeMap<String, Vec<u8>>,
    ids: &BTreeSet<&str>,
    shard: Shard,
) -> Result<String, Error> {
    let old = committed(vdir)?;
    let mut problems = Vec::new();
    let mut checked = 0;
    for (k, v) in files {
        if AGGREGATES.contains(&k.as_str()) {
            continue;
        }
        checked += 1;
        match old.get(k) {
            None => problems.push(format!("new file:  validation/{k}")),
            Some(o) if o != v => {
                problems.push(format!("changed:   validation/{k}{}", first_diff(o, v)))
            }
            Some(_) => {}
        }
    }
    // the shard's rows of verdicts.csv, in order (the first column is the study id)
    let rows = |bytes: Option<&Vec<u8>>| -> Vec<String> {
        bytes
            .map(|b| String::from_utf8_lossy(b).into_owned())
            .unwrap_or_default()
            .lines()
            .skip(1)
            .filter(|l| l.split(',').next().is_some_and(|id| ids.contains(id)))
            .map(str::to_owned)
            .collect()
    };
    let (o, n) = (
        rows(old.get(crate::VERDICTS_FILE)),
        rows(files.get(crate::VERDICTS_FILE)),
    );
    if o != n {
        let first = o
            .iter()
            .zip(&n)
            .find(|(a, b)| a != b)
            .map(|(a, b)| format!("\n  was: {a}\n  now: {b}"))
            .unwrap_or_else(|| format!(" ({} rows committed, {} generated)", o.len(), n.len()));
        problems.push(format!(
            "changed:   validation/{} (rows of this shard){first}",
            crate::VERDICTS_FILE
        ));
    }
    if problems.is_empty() {
        Ok(format!(
            "validate --check --shard {}/{}: {} studies, {checked} generated files and {} verdict \
             rows match the committed ones",
            shard.index,
            shard.count,
            ids.len(),
            n.len()
        ))
    } else {
        Err(Error::Study(format!(
            "validate --check --shard {}/{}: {} file(s) differ from the committed ones \
             (run `cargo xtask validate` and review `git diff validation/`):\n{}",
            shard.index,
            shard.count,
            problems.len(),
            problems.join("\n")
        )))
    }
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

    /// The integrations of [`costly`]: a damped oscillator at three forcing frequencies.
    fn oscillators() -> Vec<timestep::Solution> {
        let omegas = [0.5, 1.0, 1.5];
        timestep::sweep(
            &omegas,
            |&omega| {
                let sys = timestep::FirstOrder(timestep::LinearOscillator {
                    omega0: 1.0,
                    zeta: 0.1,
                    force: 1.0,
                    omega,
                });
                timestep::integrate(&sys, 0.0, &[1.0, 0.0], 30.0, &timestep::Options::default())
                    .expect("valid integration")
            },
            None,
        )
    }

    fn costly() -> Result<StudyOutput, Error> {
        assert_eq!(oscillators().len(), 3);
        Ok(StudyOutput::new())
    }

    fn idle() -> Result<StudyOutput, Error> {
        Ok(StudyOutput::new())
    }

    fn broken() -> Result<StudyOutput, Error> {
        panic!("a bug in a study")
    }

    fn synthetic(id: &'static str, run: fn() -> Result<StudyOutput, Error>) -> Study {
        Study {
            id,
            paper: Paper::Liu2021,
            source: "p. 1",
            title: "t",
            description: "",
            cost: Cost::Fast,
            run,
        }
    }

    /// The cost table agrees with the run: per study the points of its sweep, the steps and
    /// right-hand-side calls of its integrations (counted again here), nothing for a study
    /// that integrates nothing; the total row sums the rows; a panicking study is one failed
    /// study. And the progress reported during the run never decreases and ends at its total.
    #[test]
    fn cost_table_and_progress_agree_with_the_run() {
        let studies = [
            synthetic("liu2021-cost-idle", idle),
            synthetic("liu2021-cost-costly", costly),
            synthetic("liu2021-cost-broken", broken),
        ];
        let seen = std::sync::Mutex::new(Vec::<crate::RunProgress>::new());
        let record = |p: &crate::RunProgress| seen.lock().unwrap().push(p.clone());
        let results = run_with_progress(&studies, &record);
        // results in input order
        let ids: Vec<&str> = results.iter().map(|r| r.study.id).collect();
        assert_eq!(
            ids,
            [
                "liu2021-cost-idle",
                "liu2021-cost-costly",
                "liu2021-cost-broken"
            ]
        );
        assert!(results[0].output.is_ok() && results[1].output.is_ok());
        let err = results[2].output.as_ref().unwrap_err().to_string();
        assert!(
            err.contains("panicked") && err.contains("a bug in a study"),
            "{err}"
        );

        let want = oscillators();
        let u = results[1].cost.usage;
        assert_eq!(u.points, 3);
        assert_eq!(u.integrations, 3);
        assert_eq!(
            u.steps_accepted,
            want.iter().map(|s| s.stats.n_accepted).sum::<u64>()
        );
        assert_eq!(
            u.steps_rejected,
            want.iter().map(|s| s.stats.n_rejected).sum::<u64>()
        );
        assert_eq!(u.rhs_calls, want.iter().map(|s| s.stats.n_rhs).sum::<u64>());
        assert!(u.steps_accepted > 10 && u.cpu_seconds >= 0.0);
        let idle = results[0].cost.usage;
        assert_eq!(
            (idle.points, idle.steps_accepted, idle.rhs_calls),
            (0, 0, 0)
        );
        for r in &results {
            assert!(r.cost.wall_seconds >= 0.0);
        }

        let csv = crate::cost_csv(&results, 1.5);
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(lines.len(), 1 + 3 + 1);
        assert!(lines[2].starts_with(&format!(
            "liu2021-cost-costly,3,{},{},{},3,",
            u.steps_accepted, u.steps_rejected, u.rhs_calls
        )));
        assert!(lines[4].starts_with(&format!(
            "total,3,{},{},{},3,",
            u.steps_accepted, u.steps_rejected, u.rhs_calls
        )));
        assert!(lines[4].ends_with(",1.500"));
        let text = crate::cost_text(&results, 1.5);
        assert!(text.contains("liu2021-cost-costly") && text.contains("total"));

        let seen = seen.into_inner().unwrap();
        assert!(!seen.is_empty());
        for w in seen.windows(2) {
            assert!(w[1].work_done >= w[0].work_done);
        }
        let last = seen.last().unwrap();
        assert_eq!(last.studies_done, 3);
        assert_eq!(last.work_done.to_bits(), last.work_total.to_bits());
        assert!(last.work_total > 0.0);
    }

    /// The memo's table: per function what it computed at what CPU, and the hits' estimated
    /// CPU at the mean of the computed calls.
    #[test]
    fn memo_table_states_computed_and_saved_cpu() {
        let stats = [
            models::memo::MemoStats {
                name: "liu2021::long_window",
                hits: 2,
                misses: 4,
                cpu_seconds: 10.0,
            },
            models::memo::MemoStats {
                name: "never_computed",
                hits: 0,
                misses: 0,
                cpu_seconds: 0.0,
            },
        ];
        assert_eq!(
            crate::memo_csv(&stats),
            "function,computed,cpu_seconds,saved,saved_cpu_seconds_estimate\n\
             liu2021::long_window,4,10.000,2,5.000\n\
             never_computed,0,0.000,0,0.000\n"
        );
        let text = crate::memo_text(&stats);
        assert!(
            text.starts_with(
                "memo liu2021::long_window: 4 computed in 10.0 CPU s; 2 computations saved (≈ 5.0 CPU s)\n"
            ),
            "{text}"
        );
    }

    #[test]
    fn shards_partition_the_studies() {
        assert!("0/3".parse::<Shard>().is_err());
        assert!("4/3".parse::<Shard>().is_err());
        assert!("1/0".parse::<Shard>().is_err());
        assert!("x/2".parse::<Shard>().is_err());
        assert!("1-2".parse::<Shard>().is_err());
        let studies = crate::all_studies();
        for count in [1, 2, 4, 7] {
            let members: Vec<Vec<bool>> = (1..=count)
                .map(|i| {
                    format!("{i}/{count}")
                        .parse::<Shard>()
                        .unwrap()
                        .members(&studies)
                })
                .collect();
            for i in 0..studies.len() {
                assert_eq!(members.iter().filter(|m| m[i]).count(), 1);
            }
            // balanced: no shard expects more than the larger of the biggest study and twice
            // the mean
            let total: f64 = studies
                .iter()
                .map(|s| crate::expected_cpu_seconds(s.id))
                .sum();
            let biggest = studies
                .iter()
                .map(|s| crate::expected_cpu_seconds(s.id))
                .fold(0.0, f64::max);
            for m in &members {
                let load: f64 = studies
                    .iter()
                    .zip(m)
                    .filter(|(_, m)| **m)
                    .map(|(s, _)| crate::expected_cpu_seconds(s.id))
                    .sum();
                assert!(
                    load <= biggest.max(2.0 * total / count as f64) + 1e-9,
                    "{load}"
                );
            }
        }
    }

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
