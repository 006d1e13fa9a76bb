//! Running studies and turning their outputs into files: CSV, SVG, snapshots, `REPORT.md`.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

use crate::error::Error;
use crate::format::{csv_field, fmt6, md_cell};
use crate::study::{Paper, Study, StudyOutput};

/// The result of running one study.
#[derive(Debug)]
pub struct StudyResult {
    /// The study.
    pub study: Study,
    /// Its output, or why it failed.
    pub output: Result<StudyOutput, Error>,
    /// What it cost (never part of an output file but `validation/stats/cost.csv`).
    pub cost: StudyCost,
}

/// What one study cost: its work account ([`system::account`]) and its wall time.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StudyCost {
    /// Points, integrator steps, right-hand-side calls and exclusive CPU seconds.
    pub usage: system::account::Usage,
    /// Wall seconds from the study's start to its end (other studies run meanwhile).
    pub wall_seconds: f64,
}

/// Run studies in parallel (rayon), results in input order; `on_done` is called as each finishes
/// (e.g. to advance a progress bar). Deterministic: each study runs on one task and the results
/// are collected in order; each study's work is counted in its own [`system::account::Account`]
/// ([`StudyResult::cost`]).
pub fn run_studies(studies: &[Study], on_done: impl Fn(&Study) + Sync) -> Vec<StudyResult> {
    let accounts: Vec<_> = studies
        .iter()
        .map(|s| system::account::Account::new(s.id))
        .collect();
    run_studies_with(studies, &accounts, on_done)
}

/// As [`run_studies`], counting each study's work in the given accounts (one per study, in the
/// same order), which a caller may read while the run goes on (progress).
///
/// **Schedule: longest first.** The studies are started in the order of their expected CPU
/// time ([`crate::expected_cpu_seconds`], largest first; ties in input order) on a FIFO rayon
/// scope, so that the long studies (and their serial tails: neighbour continuation, threshold
/// bisection) start at once and the short ones fill the cores around them, instead of a long
/// study starting last and running alone. The schedule changes only when a study runs, never
/// what it computes: results are collected by index, in input order.
pub fn run_studies_with(
    studies: &[Study],
    accounts: &[std::sync::Arc<system::account::Account>],
    on_done: impl Fn(&Study) + Sync,
) -> Vec<StudyResult> {
    let slots: Vec<std::sync::Mutex<Option<StudyResult>>> = studies
        .iter()
        .map(|_| std::sync::Mutex::new(None))
        .collect();
    let run_one = |i: usize| {
        let s = &studies[i];
        let t0 = std::time::Instant::now();
        // a study that panics is one failed study, not a lost run
        let guarded = || {
            std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| s.execute())).unwrap_or_else(
                |p| {
                    let what = p
                        .downcast_ref::<&str>()
                        .map(|m| (*m).to_owned())
                        .or_else(|| p.downcast_ref::<String>().cloned())
                        .unwrap_or_default();
                    Err(Error::Study(format!("study {} panicked: {what}", s.id)))
                },
            )
        };
        let output = system::account::scope_opt(accounts.get(i), guarded);
        let wall_seconds = t0.elapsed().as_secs_f64();
        let usage = accounts.get(i).map(|a| a.usage()).unwrap_or_default();
        on_done(s);
        let r = StudyResult {
            study: *s,
            output,
            cost: StudyCost {
                usage,
                wall_seconds,
            },
        };
        if let Ok(mut slot) = slots[i].lock() {
            *slot = Some(r);
        }
    };
    let order = crate::longest_first(studies);
    rayon::scope_fifo(|scope| {
        for &i in &order {
            let run_one = &run_one;
            scope.spawn_fifo(move |_| run_one(i));
        }
    });
    slots
        .into_iter()
        .zip(studies)
        .map(|(slot, s)| {
            slot.into_inner()
                .ok()
                .flatten()
                .unwrap_or_else(|| StudyResult {
                    study: *s,
                    output: Err(Error::Study(format!("study {} did not finish", s.id))),
                    cost: StudyCost::default(),
                })
        })
        .collect()
}

/// The cost table of a run (`validation/stats/cost.csv`): per study its points, integrator
/// steps (accepted, rejected), right-hand-side calls, integrations, exclusive CPU seconds and
/// wall seconds, then a `total` row (sums; the wall column of the total is `run_wall_seconds`,
/// the whole run's).
pub fn cost_csv(results: &[StudyResult], run_wall_seconds: f64) -> String {
    let mut s = String::from(
        "study,points,steps_accepted,steps_rejected,rhs_calls,integrations,cpu_seconds,wall_seconds\n",
    );
    let mut total = system::account::Usage::default();
    for r in results {
        let u = &r.cost.usage;
        s.push_str(&format!(
            "{},{},{},{},{},{},{:.3},{:.3}\n",
            r.study.id,
            u.points,
            u.steps_accepted,
            u.steps_rejected,
            u.rhs_calls,
            u.integrations,
            u.cpu_seconds,
            r.cost.wall_seconds
        ));
        total.points += u.points;
        total.steps_accepted += u.steps_accepted;
        total.steps_rejected += u.steps_rejected;
        total.rhs_calls += u.rhs_calls;
        total.integrations += u.integrations;
        total.cpu_seconds += u.cpu_seconds;
    }
    s.push_str(&format!(
        "total,{},{},{},{},{},{:.3},{:.3}\n",
        total.points,
        total.steps_accepted,
        total.steps_rejected,
        total.rhs_calls,
        total.integrations,
        total.cpu_seconds,
        run_wall_seconds
    ));
    s
}

/// The in-run memo's share of a run (`validation/stats/memo.csv`): per memoised function
/// ([`models::memo::MemoStats`]) its computed calls and their CPU seconds, the calls answered from
/// the memo and the CPU seconds they would have cost at the mean of the computed ones.
pub fn memo_csv(stats: &[models::memo::MemoStats]) -> String {
    let mut s = String::from("function,computed,cpu_seconds,saved,saved_cpu_seconds_estimate\n");
    for m in stats {
        s.push_str(&format!(
            "{},{},{:.3},{},{:.3}\n",
            m.name,
            m.misses,
            m.cpu_seconds,
            m.hits,
            m.saved_cpu_seconds()
        ));
    }
    s
}

/// The memo's lines under the cost table: per function what was computed and at what CPU, and
/// what the memo saved.
pub fn memo_text(stats: &[models::memo::MemoStats]) -> String {
    stats
        .iter()
        .map(|m| {
            format!(
                "memo {}: {} computed in {:.1} CPU s; {} computations saved (≈ {:.1} CPU s)\n",
                m.name,
                m.misses,
                m.cpu_seconds,
                m.hits,
                m.saved_cpu_seconds()
            )
        })
        .collect()
}

/// The cost table as aligned text for the terminal (most expensive study first by CPU).
pub fn cost_text(results: &[StudyResult], run_wall_seconds: f64) -> String {
    let mut rows: Vec<&StudyResult> = results.iter().collect();
    rows.sort_by(|a, b| {
        b.cost
            .usage
            .cpu_seconds
            .total_cmp(&a.cost.usage.cpu_seconds)
    });
    let w = rows
        .iter()
        .map(|r| r.study.id.len())
        .max()
        .unwrap_or(5)
        .max(5);
    let mut s = format!(
        "{:<w$} {:>8} {:>12} {:>10} {:>13} {:>9} {:>8}\n",
        "study", "points", "steps", "rejected", "rhs calls", "CPU s", "wall s"
    );
    let (mut cpu, mut steps, mut rej, mut rhs, mut pts) = (0.0, 0, 0, 0, 0);
    for r in rows {
        let u = &r.cost.usage;
        s.push_str(&format!(
            "{:<w$} {:>8} {:>12} {:>10} {:>13} {:>9.1} {:>8.1}\n",
            r.study.id,
            u.points,
            u.steps_accepted,
            u.steps_rejected,
            u.rhs_calls,
            u.cpu_seconds,
            r.cost.wall_seconds
        ));
        cpu += u.cpu_seconds;
        steps += u.steps_accepted;
        rej += u.steps_rejected;
        rhs += u.rhs_calls;
        pts += u.points;
    }
    s.push_str(&format!(
        "{:<w$} {:>8} {:>12} {:>10} {:>13} {:>9.1} {:>8.1}\n",
        "total", pts, steps, rej, rhs, cpu, run_wall_seconds
    ));
    s
}

/// Relative path (under `validation/`) of an output file of `study`.
fn out_path(study: &Study, suffix: &str) -> String {
    format!("{}/{}{}", study.paper.dir(), study.id, suffix)
}

/// The comparisons and claims of a study as one CSV, as committed: model values and deviations
/// rounded relative to each row's band ([`crate::Comparison::committed_model`]).
pub fn comparisons_csv(out: &StudyOutput) -> String {
    comparisons_csv_with(out, true)
}

/// The comparisons and claims at 6 significant digits (`validation/stats/`, not committed).
pub fn comparisons_csv_full(out: &StudyOutput) -> String {
    comparisons_csv_with(out, false)
}

fn comparisons_csv_with(out: &StudyOutput, committed: bool) -> String {
    let mut s = String::from(
        "kind,quantity,unit,paper,model,deviation_abs,deviation_rel,tolerance,tolerance_basis,\
         verdict,source,readings,evidence,tolerance_derivation,flags,cause\n",
    );
    for c in &out.comparisons {
        let (model, dev, rel) = if committed {
            let (d, r) = c.committed_deviation();
            (c.committed_model(), d, r)
        } else {
            (
                c.model_label(),
                fmt6(c.deviation_abs()),
                fmt6(c.deviation_rel()),
            )
        };
        let row = [
            "comparison".to_owned(),
            c.quantity.clone(),
            c.unit.clone(),
            c.reference.printed.clone(),
            model,
            dev,
            rel,
            c.tolerance.label(),
            c.tolerance.basis.label(),
            c.verdict().label().to_owned(),
            c.reference.source.clone(),
            c.readings.join(" "),
            c.evidence.label(),
            c.tolerance.derivation.clone(),
            c.flags.join("; "),
            c.cause.clone(),
        ];
        let row: Vec<String> = row.iter().map(|f| csv_field(f)).collect();
        s.push_str(&row.join(","));
        s.push('\n');
    }
    for c in &out.claims {
        let row = [
            "claim".to_owned(),
            c.text.clone(),
            String::new(),
            String::new(),
            c.evidence.clone(),
            String::new(),
            String::new(),
            String::new(),
            String::new(),
            c.verdict.label().to_owned(),
            c.source.clone(),
            c.readings.join(" "),
            c.class.label(),
            String::new(),
            c.flags.join("; "),
            c.cause.clone(),
        ];
        let row: Vec<String> = row.iter().map(|f| csv_field(f)).collect();
        s.push_str(&row.join(","));
        s.push('\n');
    }
    s
}

/// The snapshot body of one study: what a reviewer judges, at the precision that matters
/// (what `validation/snapshots/<id>.snap` holds under insta's header). Per comparison: paper
/// value as printed, model value rounded relative to the row's band
/// ([`crate::Comparison::committed_model`]), band, verdict, class, flags; per claim: verdict,
/// class, the model's evidence and flags; per table and figure one line with the digest of its
/// committed data (tables without solver statistics or one-period samples of non-periodic
/// orbits; figures at drawing precision). Solver statistics are in `validation/stats/` only.
pub fn snapshot_body(study: &Study, output: &Result<StudyOutput, Error>) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "study: {}", study.id);
    let _ = writeln!(s, "source: {}", study.source);
    let _ = writeln!(
        s,
        "precision: model values to 1/{} of max(band, |model - paper|); data at 1/{} of range",
        crate::precision::BAND_FRACTION,
        crate::precision::DRAWING_STEPS
    );
    let out = match output {
        Ok(o) => o,
        Err(e) => {
            let _ = writeln!(s, "error: {e}");
            return s;
        }
    };
    if !out.comparisons.is_empty() {
        s.push_str("comparisons:\n");
        for c in &out.comparisons {
            let _ = writeln!(
                s,
                "  - {} [{}]: paper {} | model {} | tol {} | {} | {}",
                c.quantity,
                c.unit,
                c.reference.printed,
                c.committed_model(),
                c.tolerance.label(),
                c.verdict().label(),
                c.evidence.label()
            );
            if !c.flags.is_empty() {
                let _ = writeln!(s, "    flags: {}", c.flags.join("; "));
            }
        }
    }
    if !out.claims.is_empty() {
        s.push_str("claims:\n");
        for c in &out.claims {
            let _ = writeln!(
                s,
                "  - [{}] {} ({}) | {}",
                c.verdict.label(),
                c.text,
                c.source,
                c.class.label()
            );
            let _ = writeln!(s, "    evidence: {}", c.evidence);
            if !c.flags.is_empty() {
                let _ = writeln!(s, "    flags: {}", c.flags.join("; "));
            }
        }
    }
    for t in &out.tables {
        if t.non_periodic {
            // no row count: the record's length is part of what does not settle
            let _ = writeln!(
                s,
                "table {}: {} (validation/stats/ only)",
                t.name,
                t.record_reason
                    .as_deref()
                    .unwrap_or("record of a non-periodic orbit")
            );
            continue;
        }
        let csv = crate::precision::committed_table_csv(t);
        let _ = writeln!(
            s,
            "table {}: {} rows, data digest {}",
            t.name,
            t.rows.len(),
            crate::precision::digest(csv.as_bytes())
        );
    }
    for f in &out.figures {
        if f.non_periodic {
            let _ = writeln!(
                s,
                "figure {}: {} (validation/stats/ only)",
                f.name,
                f.record_reason
                    .as_deref()
                    .unwrap_or("record of a non-periodic orbit")
            );
            continue;
        }
        let csv = crate::precision::drawn_figure(f).to_table().to_csv();
        let _ = writeln!(
            s,
            "figure {}: {} series, data digest {}",
            f.name,
            f.series.len(),
            crate::precision::digest(csv.as_bytes())
        );
    }
    for m in &out.heatmaps {
        let csv = m.to_table().to_csv();
        let _ = writeln!(
            s,
            "heat map {}: {} cells, {} curves, data digest {}",
            m.name,
            m.grid().2.len(),
            m.curves().len(),
            crate::precision::digest(csv.as_bytes())
        );
    }
    s
}

/// Wrap a snapshot body in insta's `.snap` format, so `cargo insta` tools and the
/// `assert_snapshot!` test in this crate read the same file.
pub fn insta_snap(study: &Study, body: &str) -> String {
    format!(
        "---\nsource: xtask validate\nexpression: \"{} at the precision of each row\"\n---\n{}",
        study.id, body
    )
}

/// Where each reading id is documented: id → link relative to `validation/`.
#[derive(Debug, Clone, Default)]
pub struct ReadingsIndex {
    links: BTreeMap<String, String>,
}

impl ReadingsIndex {
    /// Scan `docs/readings.md` and `docs/readings/*.md` under the repository root for headings
    /// whose first word is a reading id (`### R-LIU-EQ20 — title`).
    pub fn scan(repo_root: &Path) -> Result<Self, Error> {
        let mut files = Vec::new();
        let single = repo_root.join("docs/readings.md");
        if single.is_file() {
            files.push(("../docs/readings.md".to_owned(), single));
        }
        let dir = repo_root.join("docs/readings");
        if dir.is_dir() {
            let rd = std::fs::read_dir(&dir).map_err(|e| Error::Io {
                path: dir.display().to_string(),
                source: e,
            })?;
            let mut names: Vec<String> = rd
                .filter_map(|e| e.ok())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .filter(|n| n.ends_with(".md"))
                .collect();
            names.sort();
            for n in names {
                files.push((format!("../docs/readings/{n}"), dir.join(&n)));
            }
        }
        let mut idx = ReadingsIndex::default();
        for (rel, path) in files {
            let text = std::fs::read_to_string(&path).map_err(|e| Error::Io {
                path: path.display().to_string(),
                source: e,
            })?;
            idx.add_markdown(&rel, &text);
        }
        Ok(idx)
    }

    /// Index the headings of one Markdown file, linked as `rel#anchor`.
    pub fn add_markdown(&mut self, rel: &str, text: &str) {
        for line in text.lines() {
            let Some(heading) = line.strip_prefix('#') else {
                continue;
            };
            let heading = heading.trim_start_matches('#').trim();
            let Some(first) = heading.split_whitespace().next() else {
                continue;
            };
            if first.starts_with("R-") && first.len() > 2 {
                self.links
                    .entry(first.to_owned())
                    .or_insert_with(|| format!("{rel}#{}", github_anchor(heading)));
            }
        }
    }

    /// Markdown link for a reading id (plain text marked `(undocumented)` if unknown).
    pub fn link(&self, id: &str) -> String {
        match self.links.get(id) {
            Some(l) => format!("[{id}]({l})"),
            None => format!("{id} (undocumented)"),
        }
    }

    /// Whether the id is documented.
    pub fn contains(&self, id: &str) -> bool {
        self.links.contains_key(id)
    }
}

/// GitHub's heading anchor: lower case, spaces to `-`, punctuation other than `-`/`_` dropped.
fn github_anchor(heading: &str) -> String {
    heading
        .chars()
        .filter_map(|c| {
            if c == ' ' {
                Some('-')
            } else if c.is_alphanumeric() || c == '-' || c == '_' {
                Some(c.to_lowercase().next().unwrap_or(c))
            } else {
                None
            }
        })
        .collect()
}

/// The verdict, bold unless pass/shown; an inconclusive row lists its flags (at most 3).
fn verdict_cell(v: crate::Verdict, flags: &[String]) -> String {
    let label = match v {
        crate::Verdict::Pass | crate::Verdict::Shown => v.label().to_owned(),
        _ => format!("**{}**", v.label()),
    };
    if flags.is_empty() {
        return label;
    }
    let more = if flags.len() > 3 {
        format!(" (+{} more)", flags.len() - 3)
    } else {
        String::new()
    };
    format!(
        "{label}: {}{more}",
        md_cell(&flags.iter().take(3).cloned().collect::<Vec<_>>().join("; "))
    )
}

/// Reading links, then the cause.
fn cause_cell(ids: &[String], cause: &str, idx: &ReadingsIndex) -> String {
    let r = readings_cell(ids, idx);
    match (r.is_empty(), cause.is_empty()) {
        (_, true) => r,
        (true, false) => md_cell(cause),
        (false, false) => format!("{r}; {}", md_cell(cause)),
    }
}

fn readings_cell(ids: &[String], idx: &ReadingsIndex) -> String {
    ids.iter()
        .map(|r| idx.link(r))
        .collect::<Vec<_>>()
        .join(", ")
}

/// `validation/REPORT.md`.
pub fn report(results: &[StudyResult], idx: &ReadingsIndex) -> String {
    let mut s = String::new();
    s.push_str("# geardyn validation report\n\n");
    s.push_str(
        "Generated by `cargo xtask validate` — do not edit. Every row carries an evidence class: \
         *reproduction* (an independently computed model quantity against the paper), \
         *consistency* (the paper against itself, or a formula against its exact form), \
         *calibration* (constants fitted from this data, named), *transcription*, *holds by \
         construction* (cannot fail: shown, not a check), *reading variant* (a reading the \
         evidence rejects or has not selected: listed apart) and *not checkable* (against \
         numbers the seeds do not print: shown). Only independent reproductions count as \
         evidence that a model reproduces a paper, each check once. Rows judged by the other \
         method of a paper's verdict rule (`validation/README.md`) are `shown`. A row is \
         judged on the points it needs, with long-window statistics where rattle is concerned; \
         it is `inconclusive` only when those points' statistics are not robust (over two \
         tolerances, two windows, two starts) or a solver did not converge, and lists the flag. \
         Thresholds are intervals: pass inside the band, deviation outside, inconclusive when \
         they straddle an edge. Every tolerance shows its derivation (CSV column \
         `tolerance_derivation`). Paper values as printed; each model value rounded to a power of ten \
         at most 1/20 of the larger of its band half-width and its distance to the paper value, \
         so that a move well inside the band changes no digit (solver statistics and full \
         precision: `validation/stats/`, not committed).\n\n",
    );
    let mut errs = 0;
    // (paper, class label) -> (pass, deviation, inconclusive, shown)
    let mut by: BTreeMap<(Paper, String), [usize; 4]> = BTreeMap::new();
    for r in results {
        let Ok(o) = &r.output else {
            errs += 1;
            continue;
        };
        let rows = o
            .comparisons
            .iter()
            .map(|c| (c.evidence.clone(), c.verdict()))
            .chain(o.claims.iter().map(|c| (c.class.clone(), c.verdict)));
        for (class, v) in rows {
            let key = match class {
                crate::Evidence::Calibration(_) => "calibration".to_owned(),
                crate::Evidence::ReadingVariant(_) => "reading variant".to_owned(),
                crate::Evidence::NotCheckable(_) => "not checkable".to_owned(),
                other => other.label(),
            };
            let e = by.entry((r.study.paper, key)).or_default();
            e[match v {
                crate::Verdict::Pass => 0,
                crate::Verdict::Deviation => 1,
                crate::Verdict::Inconclusive => 2,
                crate::Verdict::Shown => 3,
            }] += 1;
        }
    }
    s.push_str("## Independent reproductions by paper\n\n");
    s.push_str("| paper | reproductions judged | pass | deviation | inconclusive | shown (other method) |\n");
    s.push_str("| --- | ---: | ---: | ---: | ---: | ---: |\n");
    for paper in Paper::ALL {
        let z = by
            .get(&(paper, "reproduction".to_owned()))
            .copied()
            .unwrap_or_default();
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} |",
            paper.citation(),
            z[0] + z[1] + z[2],
            z[0],
            z[1],
            z[2],
            z[3]
        );
    }
    let _ = writeln!(
        s,
        "\n{} studies; {errs} failed to run.\n\n### Other evidence classes (not counted above)\n",
        results.len()
    );
    s.push_str("| paper | class | pass | deviation | inconclusive | shown |\n");
    s.push_str("| --- | --- | ---: | ---: | ---: | ---: |\n");
    for ((paper, class), z) in &by {
        if class == "reproduction" {
            continue;
        }
        let _ = writeln!(
            s,
            "| {} | {class} | {} | {} | {} | {} |",
            paper.citation(),
            z[0],
            z[1],
            z[2],
            z[3]
        );
    }
    s.push_str("\n## Studies\n\n");
    s.push_str("| study | source | title | pass | deviation | inconclusive |\n");
    s.push_str("| --- | --- | --- | ---: | ---: | ---: |\n");
    for r in results {
        let (a, b, c) = match &r.output {
            Ok(o) => {
                let t = o.tally();
                (t.0.to_string(), t.1.to_string(), t.2.to_string())
            }
            Err(_) => ("error".to_owned(), String::new(), String::new()),
        };
        let _ = writeln!(
            s,
            "| [{id}](#{anchor}) | {} | {} | {a} | {b} | {c} |",
            md_cell(r.study.source),
            md_cell(r.study.title),
            id = r.study.id,
            anchor = github_anchor(r.study.id),
        );
    }
    for paper in Paper::ALL {
        let of_paper: Vec<&StudyResult> =
            results.iter().filter(|r| r.study.paper == paper).collect();
        if of_paper.is_empty() {
            continue;
        }
        let _ = writeln!(s, "\n## {}\n", paper.citation());
        for r in of_paper {
            study_section(&mut s, r, idx);
        }
    }
    s
}

fn study_section(s: &mut String, r: &StudyResult, idx: &ReadingsIndex) {
    let st = &r.study;
    let _ = writeln!(s, "### {}\n", st.id);
    let _ = writeln!(s, "**{}** — {}\n", md_cell(st.title), st.source);
    if !st.description.is_empty() {
        let _ = writeln!(s, "{}\n", st.description.trim());
    }
    let out = match &r.output {
        Ok(o) => o,
        Err(e) => {
            let _ = writeln!(
                s,
                "**The study failed to run:** {}\n",
                md_cell(&e.to_string())
            );
            return;
        }
    };
    let mut files = vec![format!("[{0}.csv]({1})", st.id, out_path(st, ".csv"))];
    // records of non-periodic orbits live in the uncommitted stats/ (written by every run)
    let at = |non_periodic: bool, suffix: String| {
        if non_periodic {
            format!("stats/{}", out_path(st, &suffix))
        } else {
            out_path(st, &suffix)
        }
    };
    for t in &out.tables {
        files.push(format!(
            "[{n}.csv]({p})",
            n = t.name,
            p = at(t.non_periodic, format!("_{}.csv", t.name))
        ));
    }
    for f in &out.figures {
        files.push(format!(
            "[{n}.svg]({p})",
            n = f.name,
            p = at(f.non_periodic, format!("_{}.svg", f.name))
        ));
    }
    for m in &out.heatmaps {
        files.push(format!(
            "[{n}.svg]({p})",
            n = m.name,
            p = out_path(st, &format!("_{}.svg", m.name))
        ));
    }
    let _ = writeln!(s, "Outputs: {}\n", files.join(", "));
    if !out.comparisons.is_empty() {
        s.push_str("| # | quantity | unit | paper | model | deviation (abs / rel) | tolerance (derivation) | class | verdict | readings / cause |\n");
        s.push_str("| ---: | --- | --- | ---: | ---: | ---: | --- | --- | --- | --- |\n");
        for (i, c) in out.comparisons.iter().enumerate() {
            let (dev, rel) = c.committed_deviation();
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} / {} | {} ({}) | {} | {} | {} |",
                i + 1,
                md_cell(&c.quantity),
                md_cell(&c.unit),
                md_cell(&c.reference.printed),
                c.committed_model(),
                dev,
                rel,
                c.tolerance.label(),
                md_cell(&c.tolerance.derivation),
                md_cell(&c.evidence.label()),
                verdict_cell(c.verdict(), &c.flags),
                cause_cell(&c.readings, &c.cause, idx),
            );
        }
        s.push('\n');
        let notes: Vec<String> = out
            .comparisons
            .iter()
            .enumerate()
            .filter(|(_, c)| !c.note.is_empty())
            .map(|(i, c)| format!("- #{} *{}*: {}", i + 1, md_cell(&c.quantity), c.note))
            .collect();
        if !notes.is_empty() {
            s.push_str(&notes.join("\n"));
            s.push_str("\n\n");
        }
    }
    if !out.claims.is_empty() {
        s.push_str(
            "| claim (quoted) | source | model evidence | class | verdict | readings / cause |\n",
        );
        s.push_str("| --- | --- | --- | --- | --- | --- |\n");
        for c in &out.claims {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} |",
                md_cell(&c.text),
                md_cell(&c.source),
                md_cell(&c.evidence),
                md_cell(&c.class.label()),
                verdict_cell(c.verdict, &c.flags),
                cause_cell(&c.readings, &c.cause, idx),
            );
        }
        s.push('\n');
    }
    for n in &out.notes {
        let _ = writeln!(s, "> {}\n", n.trim().replace('\n', "\n> "));
    }
}

/// Every committed generated file, path relative to `validation/` → contents. Deterministic.
///
/// Layout: `<paper>/<id>.csv` (comparisons and claims, model values rounded relative to their
/// band), `<paper>/<id>_<table>.csv` (no solver statistics, no one-period samples of
/// non-periodic orbits, numbers at drawing precision), `<paper>/<id>_<figure>.svg` and `.csv`
/// (drawing precision), `snapshots/<id>.snap`, `verdicts.csv` (one line per row and figure, read
/// by `--diff`), `stats-digest.txt` (digest of [`render_stats`]) and `REPORT.md`.
/// A figure that fails to render is reported as an error in the study's snapshot.
pub fn render_all(results: &[StudyResult], idx: &ReadingsIndex) -> BTreeMap<String, Vec<u8>> {
    let mut files = BTreeMap::new();
    for r in results {
        let st = &r.study;
        let mut body = snapshot_body(st, &r.output);
        if let Ok(out) = &r.output {
            files.insert(out_path(st, ".csv"), comparisons_csv(out).into_bytes());
            for t in out.tables.iter().filter(|t| !t.non_periodic) {
                files.insert(
                    out_path(st, &format!("_{}.csv", t.name)),
                    crate::precision::committed_table_csv(t).into_bytes(),
                );
            }
            for f in out.figures.iter().filter(|f| !f.non_periodic) {
                let drawn = crate::precision::drawn_figure(f);
                files.insert(
                    out_path(st, &format!("_{}.csv", f.name)),
                    drawn.to_table().to_csv().into_bytes(),
                );
                match drawn.to_svg() {
                    Ok(svg) => {
                        files.insert(out_path(st, &format!("_{}.svg", f.name)), svg.into_bytes());
                    }
                    Err(e) => {
                        let _ = writeln!(body, "render error: {e}");
                    }
                }
            }
            for m in &out.heatmaps {
                files.insert(
                    out_path(st, &format!("_{}.csv", m.name)),
                    m.to_table().to_csv().into_bytes(),
                );
                match m.to_svg() {
                    Ok(svg) => {
                        files.insert(out_path(st, &format!("_{}.svg", m.name)), svg.into_bytes());
                    }
                    Err(e) => {
                        let _ = writeln!(body, "render error: {e}");
                    }
                }
            }
        }
        files.insert(
            format!("snapshots/{}.snap", st.id),
            insta_snap(st, &body).into_bytes(),
        );
    }
    files.insert(
        crate::verdicts::VERDICTS_FILE.to_owned(),
        crate::verdicts::verdicts_csv(&crate::verdicts::verdict_rows(results)).into_bytes(),
    );
    files.insert(
        STATS_DIGEST_FILE.to_owned(),
        stats_digest(&render_stats(results)).into_bytes(),
    );
    files.insert("REPORT.md".to_owned(), report(results, idx).into_bytes());
    // spans that do not settle under a solver retune (claims' evidence, flags, notes) are
    // committed as n/p; the text files are UTF-8 by construction
    for v in files.values_mut() {
        if let Ok(text) = std::str::from_utf8(v) {
            if text.contains(crate::format::UNSETTLED_OPEN) {
                *v = crate::format::committed_text(text).into_bytes();
            }
        }
    }
    files
}

/// The committed file holding the digest of the uncommitted `validation/stats/`.
pub const STATS_DIGEST_FILE: &str = "stats-digest.txt";

/// The uncommitted files of `validation/stats/` (path relative to it → contents): every study's
/// comparisons and tables at 6 significant digits with every column (solver statistics,
/// one-period samples), and its figures' data at 6 significant digits. Written by every run,
/// never snapshot-tested; `--check` compares their digest ([`stats_digest`]).
pub fn render_stats(results: &[StudyResult]) -> BTreeMap<String, Vec<u8>> {
    let mut files = BTreeMap::new();
    for r in results {
        let st = &r.study;
        if let Ok(out) = &r.output {
            files.insert(out_path(st, ".csv"), comparisons_csv_full(out).into_bytes());
            for t in &out.tables {
                files.insert(
                    out_path(st, &format!("_{}.csv", t.name)),
                    t.to_csv().into_bytes(),
                );
            }
            for f in &out.figures {
                files.insert(
                    out_path(st, &format!("_{}.csv", f.name)),
                    f.to_table().to_csv().into_bytes(),
                );
                // a non-periodic record is drawn here only (its committed SVG does not exist);
                // a figure with unsettled points is drawn here in full
                if f.non_periodic || f.series.iter().any(|s| s.unsettled.contains(&true)) {
                    if let Ok(svg) = f.to_svg() {
                        files.insert(out_path(st, &format!("_{}.svg", f.name)), svg.into_bytes());
                    }
                }
            }
        }
    }
    for v in files.values_mut() {
        if let Ok(text) = std::str::from_utf8(v) {
            if text.contains(crate::format::UNSETTLED_OPEN) {
                *v = crate::format::full_text(text).into_bytes();
            }
        }
    }
    files
}

/// The text of `validation/stats-digest.txt`: one digest over every stats file (path and
/// contents, in path order), so that a retune changes one committed line while `--check`
/// still catches a non-deterministic statistic (the same digest for any thread count).
pub fn stats_digest(stats: &BTreeMap<String, Vec<u8>>) -> String {
    let mut all = Vec::new();
    for (k, v) in stats {
        all.extend_from_slice(k.as_bytes());
        all.push(0);
        all.extend_from_slice(v);
        all.push(0);
    }
    format!(
        "# FNV-1a 64 digest of validation/stats/ (solver statistics and full-precision data;\n\
         # gitignored, written by every `cargo xtask validate`). The same for any thread count:\n\
         # `--check` fails when it differs. See validation/README.md, \"Reviewing a PR\".\n\
         stats: {} files, digest {}\n",
        stats.len(),
        crate::precision::digest(&all)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn anchors_match_github() {
        assert_eq!(
            github_anchor("R-LIU-EQ20 — Eq. 20 as printed"),
            "r-liu-eq20--eq-20-as-printed"
        );
        assert_eq!(github_anchor("karpov2017-fig4"), "karpov2017-fig4");
    }

    #[test]
    fn readings_index() {
        let mut idx = ReadingsIndex::default();
        idx.add_markdown(
            "../docs/readings/x.md",
            "# Title\n\n### R-YU-EQ16 — pressure angle\ntext\n",
        );
        assert!(idx.contains("R-YU-EQ16"));
        assert_eq!(
            idx.link("R-YU-EQ16"),
            "[R-YU-EQ16](../docs/readings/x.md#r-yu-eq16--pressure-angle)"
        );
        assert_eq!(idx.link("R-X"), "R-X (undocumented)");
    }
}
