//! `cargo xtask validate [--check]`.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use std::time::Instant;

use indicatif::{ProgressBar, ProgressStyle};
use validate::{ReadingsIndex, Verdict};

/// Directories under `validation/` that are entirely generated (stale files there are removed).
fn generated_dirs() -> Vec<String> {
    let mut v: Vec<String> = validate::Paper::ALL
        .iter()
        .map(|p| p.dir().to_owned())
        .collect();
    v.push("snapshots".to_owned());
    v
}

const HINT: &str = "run `cargo xtask validate` locally and review/commit the diff \
                    (git diff validation/)";

pub fn run(root: &Path, check: bool, filter: Option<&str>) -> Result<(), String> {
    if check && filter.is_some() {
        return Err("--filter cannot be combined with --check".to_owned());
    }
    let t0 = Instant::now();
    let mut studies = validate::all_studies();
    if let Some(f) = filter {
        studies.retain(|s| s.id.contains(f));
    }
    let pb = ProgressBar::new(studies.len() as u64);
    pb.set_style(
        ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} {msg}")
            .map_err(|e| e.to_string())?
            .progress_chars("=> "),
    );
    let results = validate::run_studies(&studies, |s| {
        pb.set_message(s.id);
        pb.inc(1);
    });
    pb.finish_and_clear();
    let elapsed = t0.elapsed();

    let idx = ReadingsIndex::scan(root).map_err(|e| e.to_string())?;
    let files = validate::render_all(&results, &idx);

    // Console summary.
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
                    eprintln!(
                        "warning: {}: reading {id} not found in docs/readings",
                        r.study.id
                    );
                }
                let dev = o
                    .comparisons
                    .iter()
                    .filter(|c| c.verdict() == Verdict::Deviation && c.readings.is_empty())
                    .count();
                if dev > 0 {
                    eprintln!("note: {}: {dev} deviation(s) without a reading", r.study.id);
                }
            }
            Err(e) => eprintln!("warning: study {} failed: {e}", r.study.id),
        }
    }
    println!(
        "{} studies in {:.1} s: {p} pass, {d} deviation, {i} inconclusive",
        results.len(),
        elapsed.as_secs_f64()
    );

    // integrity rules (validate::audit): causes named, no shared file names, no verdict from a
    // flagged point; fatal under --check
    let problems = validate::audit(&results);
    for p in &problems {
        eprintln!("error: {p}");
    }
    if check && !problems.is_empty() {
        return Err(format!(
            "validate --check: {} integrity problem(s) (see above)",
            problems.len()
        ));
    }

    let vdir = root.join("validation");
    if check {
        check_files(&vdir, &files)
    } else {
        write_files(&vdir, &files, filter.is_none())
    }
}

/// Committed generated files: relative path → contents.
fn committed(vdir: &Path) -> Result<BTreeMap<String, Vec<u8>>, String> {
    let mut m = BTreeMap::new();
    for d in generated_dirs() {
        let dir = vdir.join(&d);
        if !dir.is_dir() {
            continue;
        }
        let rd = std::fs::read_dir(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        for e in rd {
            let e = e.map_err(|e| e.to_string())?;
            if e.path().is_file() {
                let name = format!("{d}/{}", e.file_name().to_string_lossy());
                let bytes = std::fs::read(e.path()).map_err(|e| e.to_string())?;
                m.insert(name, bytes);
            }
        }
    }
    let report = vdir.join("REPORT.md");
    if report.is_file() {
        m.insert(
            "REPORT.md".to_owned(),
            std::fs::read(&report).map_err(|e| e.to_string())?,
        );
    }
    Ok(m)
}

fn check_files(vdir: &Path, files: &BTreeMap<String, Vec<u8>>) -> Result<(), String> {
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
        println!(
            "validate --check: {} generated files match the committed ones",
            files.len()
        );
        Ok(())
    } else {
        for p in &problems {
            eprintln!("{p}");
        }
        Err(format!(
            "{} generated file(s) differ from the committed validation outputs/snapshots; {HINT}",
            problems.len()
        ))
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

fn write_files(vdir: &Path, files: &BTreeMap<String, Vec<u8>>, prune: bool) -> Result<(), String> {
    let old = committed(vdir)?;
    let mut changed = 0;
    for (k, v) in files {
        let path = vdir.join(k);
        if old.get(k) == Some(v) || (!prune && k == "REPORT.md") {
            // (a --filter run writes its studies' files but not a partial report)
            continue;
        }
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).map_err(|e| format!("{}: {e}", parent.display()))?;
        }
        std::fs::write(&path, v).map_err(|e| format!("{}: {e}", path.display()))?;
        changed += 1;
    }
    let mut removed = 0;
    if prune {
        for k in old.keys() {
            if !files.contains_key(k) {
                let path = vdir.join(k);
                std::fs::remove_file(&path).map_err(|e| format!("{}: {e}", path.display()))?;
                removed += 1;
            }
        }
    }
    println!(
        "wrote validation/: {} files ({changed} changed, {removed} removed); review with `git diff validation/`",
        files.len()
    );
    Ok(())
}
