//! The `geardyn` command (install with `cargo install --path crates/cli`):
//!
//! * `geardyn study FILE [--out DIR]` — run a study file (format in `docs/studies.md`): CSV,
//!   one SVG per output and a JSON summary, written atomically into `DIR` (default: next to
//!   the file, in a directory named after the study);
//! * `geardyn models [NAME] [--json]` — every model with its parameters and units, choices and
//!   readings, solver methods with their settings and bounds, and outputs;
//! * `geardyn validate [--check]` — the validation of `cargo xtask validate` (same code).
//!
//! The commands are library functions here so that `cargo xtask` runs exactly the same code.
//! Progress goes to stderr: a progress bar on a terminal, plain lines otherwise.
//!
//! Exit status: 0 on success, 1 on an error (nothing computed or written, or a write failed),
//! 2 when every point of a study failed (the outputs are still written, with NaN rows).

#![deny(missing_docs)]

use std::io::IsTerminal;
use std::path::Path;
use std::sync::Mutex;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};

/// Exit status when every point of a study failed.
pub const EXIT_ALL_FAILED: u8 = 2;

/// Progress on stderr: an indicatif bar on a terminal, otherwise a plain line at most every
/// 10 % or 5 s (and at the end).
#[derive(Debug)]
pub struct StderrProgress {
    what: &'static str,
    bar: Option<ProgressBar>,
    last: Mutex<(Instant, usize)>,
}

impl StderrProgress {
    /// `what` names the items (`points`, `studies`).
    pub fn new(what: &'static str) -> Self {
        StderrProgress {
            what,
            bar: None,
            last: Mutex::new((Instant::now(), 0)),
        }
    }

    fn begin(&mut self, total: usize) {
        if std::io::stderr().is_terminal() {
            let pb = ProgressBar::new(total as u64);
            let template = format!(
                "{{elapsed_precise}} [{{bar:40}}] {{pos}}/{{len}} {} (eta {{eta}}) {{msg}}",
                self.what
            );
            if let Ok(style) = ProgressStyle::with_template(&template) {
                pb.set_style(style.progress_chars("=> "));
            }
            self.bar = Some(pb);
        } else {
            eprintln!("{total} {} to run", self.what);
        }
    }

    fn tick(&self, done: usize, total: usize, msg: &str) {
        if let Some(pb) = &self.bar {
            pb.set_message(msg.to_owned());
            pb.set_position(done as u64);
            return;
        }
        let Ok(mut last) = self.last.lock() else {
            return;
        };
        let step = (total / 10).max(1);
        if done == total || done >= last.1 + step || last.0.elapsed() >= Duration::from_secs(5) {
            *last = (Instant::now(), done);
            eprintln!(
                "{done}/{total} {} done ({}%) {msg}",
                self.what,
                (100 * done).checked_div(total).unwrap_or(100)
            );
        }
    }

    fn end(&self) {
        if let Some(pb) = &self.bar {
            pb.finish_and_clear();
        }
    }
}

/// The progress of `geardyn validate`: one bar over the whole run, in expected CPU seconds
/// ([`validate::RunProgress`]: finished studies plus the CPU time of the running ones),
/// with studies and points done and an ETA; on a non-terminal a plain line at most every 10 %
/// or 30 s, and at the end.
struct WorkProgress {
    bar: Option<ProgressBar>,
    start: Instant,
    last: Mutex<(Instant, f64)>,
}

/// Units of the bar per expected CPU second (the bar counts integers).
const WORK_UNITS: f64 = 100.0;

impl WorkProgress {
    fn new(studies: usize) -> Self {
        let bar = std::io::stderr().is_terminal().then(|| {
            let pb = ProgressBar::new(1);
            if let Ok(style) = ProgressStyle::with_template(
                "{elapsed_precise} [{bar:40}] {percent:>3}% (eta {eta}) {msg}",
            ) {
                pb.set_style(style.progress_chars("=> "));
            }
            pb
        });
        if bar.is_none() {
            eprintln!("{studies} studies to run");
        }
        WorkProgress {
            bar,
            start: Instant::now(),
            last: Mutex::new((Instant::now(), -1.0)),
        }
    }

    fn update(&self, r: &validate::RunProgress) {
        let msg = format!(
            "{}/{} studies, {} points{}",
            r.studies_done,
            r.studies_total,
            r.points_done,
            r.last_finished
                .map(|s| format!(", last: {s}"))
                .unwrap_or_default()
        );
        if let Some(pb) = &self.bar {
            pb.set_length((r.work_total * WORK_UNITS).round().max(1.0) as u64);
            pb.set_position((r.work_done * WORK_UNITS).round() as u64);
            pb.set_message(msg);
            return;
        }
        let Ok(mut last) = self.last.lock() else {
            return;
        };
        let frac = if r.work_total > 0.0 {
            r.work_done / r.work_total
        } else {
            1.0
        };
        let end = r.studies_done == r.studies_total;
        if (end && last.1 < 1.0)
            || frac >= last.1 + 0.1
            || last.0.elapsed() >= Duration::from_secs(30)
        {
            *last = (Instant::now(), if end { 1.0 } else { frac });
            let spent = self.start.elapsed().as_secs_f64();
            let eta = if frac > 0.0 && !end {
                format!(", eta {:.0} s", spent * (1.0 - frac) / frac)
            } else {
                String::new()
            };
            eprintln!("{:3.0}% of the expected work{eta}: {msg}", 100.0 * frac);
        }
    }

    fn end(&self) {
        if let Some(pb) = &self.bar {
            pb.finish_and_clear();
        }
    }
}

/// [`study::Progress`] for study files.
struct StudyProgress(Mutex<StderrProgress>);

impl study::Progress for StudyProgress {
    fn start(&self, total: usize) {
        if let Ok(mut p) = self.0.lock() {
            p.begin(total);
        }
    }
    fn point(&self, done: usize, total: usize) {
        if let Ok(p) = self.0.lock() {
            p.tick(done, total, "");
        }
    }
    fn finish(&self) {
        if let Ok(p) = self.0.lock() {
            p.end();
        }
    }
}

/// An error of a command, with its exit status.
#[derive(Debug)]
pub struct Failure {
    /// The message (printed as `error: …`).
    pub message: String,
    /// Exit status.
    pub code: u8,
}

impl From<validate::Error> for Failure {
    fn from(e: validate::Error) -> Self {
        Failure {
            message: e.to_string(),
            code: 1,
        }
    }
}

impl From<study::Error> for Failure {
    fn from(e: study::Error) -> Self {
        Failure {
            message: e.to_string(),
            code: 1,
        }
    }
}

/// `geardyn study FILE [--out DIR]`: run, write, report. Returns an error with
/// [`EXIT_ALL_FAILED`] when every point failed (the files are written all the same).
pub fn study(file: &Path, out: Option<&Path>) -> Result<(), Failure> {
    let progress = StudyProgress(Mutex::new(StderrProgress::new("points")));
    let account = system::account::Account::new("study");
    let t0 = Instant::now();
    let (output, written) =
        system::account::scope(&account, || study::run_study_file(file, out, &progress))?;
    eprintln!(
        "{}",
        cost_line(&account.usage(), t0.elapsed().as_secs_f64())
    );
    for f in &written.files {
        println!("wrote {}", f.display());
    }
    print_reliability(&output);
    let failed = output.failed.len();
    for f in output.failed.iter().take(5) {
        let at: Vec<String> =
            f.at.iter()
                .map(|(k, v)| format!("{k} = {}", v.label()))
                .collect();
        eprintln!("failed point {} ({}): {}", f.index, at.join(", "), f.error);
    }
    if failed > 5 {
        eprintln!("… {} more failed point(s)", failed - 5);
    }
    if output.all_failed() {
        return Err(Failure {
            message: format!(
                "every point ({failed}) failed; see {}",
                written.dir.join(format!("{}.json", output.name)).display()
            ),
            code: EXIT_ALL_FAILED,
        });
    }
    if failed > 0 {
        eprintln!(
            "warning: {failed} of {} point(s) failed (NaN rows); see the JSON summary",
            output.points
        );
    }
    Ok(())
}

/// One line of what a run cost (its work account, [`system::account`]).
pub fn cost_line(u: &system::account::Usage, wall_seconds: f64) -> String {
    format!(
        "cost: {} points, {} integrator steps (+{} rejected), {} RHS calls, {:.2} CPU s, \
         {wall_seconds:.2} s wall",
        u.points, u.steps_accepted, u.steps_rejected, u.rhs_calls, u.cpu_seconds
    )
}

/// The one-line reliability summary of a study (`name: N points, S settled, C chaotic, F
/// failed`, …) on stdout, and its notes (e.g. robustness not computed) on stderr.
fn print_reliability(output: &study::UserStudyOutput) {
    println!("{}: {}", output.name, output.reliability.line());
    for n in &output.reliability.notes {
        eprintln!("note: {n}");
    }
    if let Some(u) = output.reliability.unsettled.filter(|&u| u > 0) {
        eprintln!(
            "warning: {u} of {} point(s) did not settle (settled = 0, motion = −3): their rsv \
             and ppv are samples of a transient",
            output.points
        );
    }
    // a basin study: one line per attractor with its basin fraction
    if let Some(b) = &output.basins {
        for a in &b.attractors {
            println!(
                "  {}: {} cells, fraction {}",
                a.name(),
                a.cells,
                system::format::fmt6(a.fraction)
            );
        }
    }
}

/// `geardyn study FILE --shard i/n`: compute one shard and write its partial result (under
/// `<out>-shards/`); resumable; merge the shards with [`merge`].
pub fn study_shard(file: &Path, out: Option<&Path>, shard: &str) -> Result<(), Failure> {
    let shard: study::shard::ShardSpec = shard.parse()?;
    let progress = StudyProgress(Mutex::new(StderrProgress::new("points")));
    let path = study::run_study_shard_file(file, out, shard, &progress)?;
    println!("wrote {}", path.display());
    Ok(())
}

/// `geardyn study FILE --sbatch N`: print a Slurm job-array script that runs the study as
/// `N` shards (see `docs/scaling.md`).
pub fn study_sbatch(
    file: &Path,
    out: Option<&Path>,
    options: &study::shard::SlurmOptions,
) -> Result<(), Failure> {
    let text = std::fs::read_to_string(file).map_err(|e| Failure {
        message: format!("{}: {e}", file.display()),
        code: 2,
    })?;
    let study = study::UserStudy::parse(&text)?;
    let dir = out.map_or_else(|| study::default_out_dir(file, &study), Path::to_path_buf);
    print!(
        "{}",
        study::shard::sbatch_script(file, &dir, &study.name, options)?
    );
    Ok(())
}

/// `geardyn merge FILE --out DIR PART...`: merge shards' partial results into the outputs of
/// the whole study, identical to an unsharded run.
pub fn merge(file: &Path, out: Option<&Path>, parts: &[std::path::PathBuf]) -> Result<(), Failure> {
    let (output, written) = study::merge_study_files(file, out, parts)?;
    for f in &written.files {
        println!("wrote {}", f.display());
    }
    print_reliability(&output);
    if output.all_failed() {
        return Err(Failure {
            message: format!("every point ({}) failed", output.points),
            code: EXIT_ALL_FAILED,
        });
    }
    Ok(())
}

/// `geardyn validate [--check [--shard I/N]] [--filter F]` under the repository `root`.
pub fn validate(
    root: &Path,
    check: bool,
    filter: Option<&str>,
    shard: Option<&str>,
) -> Result<(), Failure> {
    let shard: Option<validate::Shard> = shard.map(str::parse).transpose()?;
    let total = if let Some(sh) = shard {
        sh.members(&validate::all_studies())
            .into_iter()
            .filter(|m| *m)
            .count()
    } else if let Some(f) = filter {
        validate::all_studies()
            .iter()
            .filter(|s| validate::study_selected(s.id, f))
            .count()
    } else {
        validate::all_studies().len()
    };
    let p = WorkProgress::new(total);
    let cb = |r: &validate::RunProgress| p.update(r);
    let result = validate::run_validation_sharded(root, check, filter, shard, &cb);
    p.end();
    let summary = result?;
    for w in &summary.warnings {
        eprintln!("{w}");
    }
    if sync_models_doc(root, check)? {
        println!("updated {MODELS_DOC} (model reference)");
    }
    let (pass, dev, inc) = summary.tally;
    println!(
        "{} studies in {:.1} s: {pass} pass, {dev} deviation, {inc} inconclusive",
        summary.studies, summary.seconds
    );
    println!("{}", summary.message);
    println!(
        "\ncost per study (validation/stats/{}; CPU s: exclusive thread CPU time):\n{}",
        validate::COST_FILE,
        summary.cost_table
    );
    Ok(())
}

/// The file that holds the generated model reference.
pub const MODELS_DOC: &str = "docs/studies.md";
const MODELS_BEGIN: &str = "<!-- BEGIN generated: model reference. `cargo xtask validate` writes \
it from the models' self-description (the source of `geardyn models`); `--check` fails when it is \
stale. Do not edit by hand. -->";
const MODELS_END: &str = "<!-- END generated: model reference -->";

/// A setting's kind, range and default in words (`quote` around names: "`" in Markdown).
fn setting_bound(kind: &study::Kind, quote: &str) -> String {
    match *kind {
        study::Kind::Num { lo, hi, default } => {
            format!("number in [{lo:e}, {hi:e}], default {default:e}")
        }
        study::Kind::Int { lo, hi, default } => format!(
            "integer in [{lo}, {hi}], default {}",
            default.map_or("the model's".to_owned(), |d| d.to_string())
        ),
        study::Kind::Name { options, default } => format!(
            "{quote}\"{}\"{quote}, default {quote}\"{default}\"{quote}",
            options.join("\" | \"")
        ),
    }
}

/// Escape a table cell.
fn cell(s: &str) -> String {
    s.replace('|', "\\|").replace('\n', " ")
}

/// The model reference of [`MODELS_DOC`], in Markdown, from the registry's self-description
/// (the same source as [`models_text`]): per model its parameters with units and defaults, its
/// choices and readings, and per method its settings with bounds and its output columns.
pub fn models_markdown() -> String {
    use std::fmt::Write;
    let mut s = String::new();
    for m in study::REGISTRY.iter() {
        let info = m.describe();
        let _ = writeln!(s, "### `{}`\n\n{}\n", m.name(), cell(m.description()));
        let methods: Vec<String> = info
            .methods
            .iter()
            .map(|x| format!("`{}`", x.method.name()))
            .collect();
        let _ = writeln!(s, "Methods: {}.\n", methods.join(", "));
        let cont = m.continuation_parameters();
        if !cont.is_empty() {
            let names: Vec<String> = cont
                .iter()
                .map(|(n, u)| format!("`{n}` ({})", cell(u)))
                .collect();
            let _ = writeln!(
                s,
                "`[continuation]` parameters (with `method = \"shooting\"`): {}.\n",
                names.join(", ")
            );
        }
        let _ = writeln!(s, "| parameter | unit | default |\n| --- | --- | --- |");
        for p in &info.parameters {
            let _ = writeln!(
                s,
                "| `{}` | {} | {} |",
                p.name,
                cell(&p.unit),
                cell(&p.default)
            );
        }
        s.push('\n');
        if !info.choices.is_empty() {
            let _ = writeln!(
                s,
                "| choice or reading | options (default first) | note |\n| --- | --- | --- |"
            );
            for c in &info.choices {
                let mut opts = vec![c.default.clone()];
                opts.extend(c.options.iter().filter(|o| **o != c.default).cloned());
                let opts: Vec<String> = opts.iter().map(|o| format!("`\"{o}\"`")).collect();
                let _ = writeln!(
                    s,
                    "| `{}` | {} | {} |",
                    c.name,
                    cell(&opts.join(" | ")),
                    cell(&c.note)
                );
            }
            s.push('\n');
        }
        for meth in &info.methods {
            let _ = writeln!(s, "`solver.method = \"{}\"`", meth.method.name());
            s.push('\n');
            if meth.settings.is_empty() {
                let _ = writeln!(s, "Settings: none.\n");
            } else {
                let _ = writeln!(
                    s,
                    "| setting | range, default | meaning |\n| --- | --- | --- |"
                );
                for d in &meth.settings {
                    let bound = setting_bound(&d.kind, "`");
                    let _ = writeln!(s, "| `{}` | {} | {} |", d.name, cell(&bound), cell(d.doc));
                }
                s.push('\n');
            }
            let outs: Vec<String> = meth
                .outputs
                .iter()
                .map(|(n, u)| format!("`{n}` [{u}]"))
                .collect();
            let _ = writeln!(s, "Outputs: {}.", cell(&outs.join(", ")));
            if let Some(i) = meth.initial {
                let _ = writeln!(s, "Initial state: `initial = {i}`.");
            }
            s.push('\n');
        }
    }
    s
}

/// Bring the generated model reference of `root/`[`MODELS_DOC`] up to date (between its
/// markers); with `check`, fail instead when it is stale. Returns whether the file changed.
///
/// # Errors
/// The file or its markers missing, unwritable, or (with `check`) stale.
pub fn sync_models_doc(root: &Path, check: bool) -> Result<bool, Failure> {
    let path = root.join(MODELS_DOC);
    let fail = |message: String| Failure { message, code: 1 };
    let text =
        std::fs::read_to_string(&path).map_err(|e| fail(format!("{}: {e}", path.display())))?;
    let (Some(a), Some(b)) = (text.find(MODELS_BEGIN), text.find(MODELS_END)) else {
        return Err(fail(format!(
            "{}: the markers of the generated model reference are missing",
            path.display()
        )));
    };
    if b < a {
        return Err(fail(format!(
            "{}: the model reference markers are out of order",
            path.display()
        )));
    }
    let start = a + MODELS_BEGIN.len();
    let fresh = format!("\n\n{}", models_markdown());
    if text[start..b] == fresh {
        return Ok(false);
    }
    if check {
        return Err(fail(format!(
            "{MODELS_DOC}: the model reference is stale (a model's parameters, settings or \
             outputs changed); run `cargo xtask validate` to regenerate it"
        )));
    }
    let new = format!("{}{}{}", &text[..start], fresh, &text[b..]);
    let tmp = path.with_extension("md.tmp");
    std::fs::write(&tmp, new)
        .and_then(|()| std::fs::rename(&tmp, &path))
        .map_err(|e| fail(format!("{}: {e}", path.display())))?;
    Ok(true)
}

/// `cargo xtask validate --diff [REV]`: print the markdown summary of what changed in meaning
/// (verdicts, evidence classes, rows, model values against their band, figures) between
/// `validation/verdicts.csv` at `REV` (default: the merge base with `main`) and the working
/// tree. Exit status 0 whatever changed (`--check` is the gate).
pub fn validate_diff(root: &Path, rev: Option<&str>) -> Result<(), Failure> {
    use std::io::Write as _;
    let md = validate::diff_against(root, rev)?;
    // a closed pipe (`| head`) is not an error of the diff
    let _ = std::io::stdout().lock().write_all(md.as_bytes());
    Ok(())
}

/// The text of `geardyn models [NAME]`.
pub fn models_text(name: Option<&str>) -> Result<String, Failure> {
    use std::fmt::Write;
    let specs: Vec<&dyn study::Model> = match name {
        Some(n) => vec![study::model_spec(n)?],
        None => study::REGISTRY.to_vec(),
    };
    let mut s = String::new();
    for m in specs {
        let info = m.describe();
        let _ = writeln!(s, "{} — {}", m.name(), m.description());
        let _ = writeln!(
            s,
            "  parameters ([overrides] or a sweep; name [unit] = default):"
        );
        for p in &info.parameters {
            let _ = writeln!(s, "    {} [{}] = {}", p.name, p.unit, p.default);
        }
        if !info.choices.is_empty() {
            let _ = writeln!(s, "  choices and readings (names; default first):");
            for c in &info.choices {
                let mut opts = vec![c.default.clone()];
                opts.extend(c.options.iter().filter(|o| **o != c.default).cloned());
                let _ = writeln!(
                    s,
                    "    {} = \"{}\"  — {}",
                    c.name,
                    opts.join("\" | \""),
                    c.note
                );
            }
        }
        for meth in &info.methods {
            let _ = writeln!(s, "  solver.method = \"{}\":", meth.method.name());
            if meth.settings.is_empty() {
                let _ = writeln!(s, "    settings: none");
            }
            for d in &meth.settings {
                let bound = setting_bound(&d.kind, "");
                let _ = writeln!(s, "    {}: {bound} — {}", d.name, d.doc);
            }
            let outs: Vec<String> = meth
                .outputs
                .iter()
                .map(|(n, u)| format!("{n} [{u}]"))
                .collect();
            let _ = writeln!(s, "    outputs: {}", outs.join(", "));
            if let Some(i) = meth.initial {
                let _ = writeln!(s, "    initial = {i}");
            }
        }
        let cont = m.continuation_parameters();
        if !cont.is_empty() {
            let names: Vec<String> = cont.iter().map(|(n, u)| format!("{n} [{u}]")).collect();
            let _ = writeln!(
                s,
                "  [continuation] (method \"shooting\") parameters: {}",
                names.join(", ")
            );
        }
        s.push('\n');
    }
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn models_lists_every_model_with_units_and_outputs() {
        let t = models_text(None).unwrap();
        for m in study::model_names() {
            assert!(t.contains(m), "{m} missing");
        }
        assert!(t.contains("omega1 [rad/s]"), "{t}");
        assert!(t.contains("kahraman-singh"), "{t}");
        assert!(t.contains("printed-phase"), "{t}");
        assert!(t.contains("outputs: df [1]"), "{t}");
        assert!(models_text(Some("nope")).is_err());
    }
}
