//! The machine-readable verdict file `validation/verdicts.csv` and the verdict diff behind
//! `cargo xtask validate --diff [REV]` (issue 28).
//!
//! One line per comparison row, claim row and figure: the study, the row's key (quantity, claim
//! text or figure name, with its occurrence among rows of the same key), evidence class,
//! verdict, the paper value as printed, the model value as committed (rounded relative to the
//! row's band, [`crate::Comparison::committed_model`]), the band half-width, readings, flags and
//! cause. A figure's line carries the digest of its committed (drawing-precision) data.
//!
//! [`diff_verdicts`] compares two such files; [`VerdictDiff::to_markdown`] writes the summary a
//! reviewer reads first, most severe first: verdicts changed, evidence classes changed, rows
//! added or removed, model values moved by more than [`MOVE_FRACTION`] of their band, figures
//! whose curves moved beyond drawing precision.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use crate::error::Error;
use crate::format::{csv_field, fmt_sig};
use crate::precision::{MOVE_FRACTION, digest, drawn_figure};
use crate::render::StudyResult;

/// The committed verdict file, relative to `validation/`.
pub const VERDICTS_FILE: &str = "verdicts.csv";

/// Header of `validation/verdicts.csv`.
pub const VERDICTS_HEADER: &str =
    "study,kind,key,occurrence,evidence,verdict,paper,model,band,readings,flags,cause";

/// One line of `validation/verdicts.csv`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct VerdictRow {
    /// Study id.
    pub study: String,
    /// `comparison`, `claim` or `figure`.
    pub kind: String,
    /// Quantity (comparison), quoted text (claim) or figure name.
    pub key: String,
    /// 1-based occurrence among the study's rows of the same kind and key.
    pub occurrence: usize,
    /// Evidence class label.
    pub evidence: String,
    /// Verdict label (empty for a figure).
    pub verdict: String,
    /// Paper value as printed (comparison) or committed data file (figure).
    pub paper: String,
    /// Model value as committed (comparison) or data digest (figure).
    pub model: String,
    /// Band half-width (comparison), 3 significant digits.
    pub band: String,
    /// Reading ids, space separated.
    pub readings: String,
    /// Flags, `; ` separated.
    pub flags: String,
    /// Cause of a deviation or inconclusive verdict.
    pub cause: String,
}

impl VerdictRow {
    fn ident(&self) -> (String, String, String, usize) {
        (
            self.study.clone(),
            self.kind.clone(),
            self.key.clone(),
            self.occurrence,
        )
    }

    /// `study` · kind «key» (#n when repeated).
    fn name(&self) -> String {
        let key: String = self.key.chars().take(120).collect();
        let more = if self.key.chars().count() > 120 {
            "…"
        } else {
            ""
        };
        let occ = if self.occurrence > 1 {
            format!(" (#{})", self.occurrence)
        } else {
            String::new()
        };
        format!("`{}` · {} «{}{more}»{occ}", self.study, self.kind, md(&key))
    }

    /// Reading, flags and cause, for an entry.
    fn why(&self) -> String {
        let mut parts = Vec::new();
        if !self.readings.is_empty() {
            parts.push(format!("reading {}", self.readings));
        }
        if !self.flags.is_empty() {
            let f: String = self.flags.chars().take(200).collect();
            parts.push(format!("flags: {}", md(&f)));
        }
        if !self.cause.is_empty() {
            let c: String = self.cause.chars().take(200).collect();
            parts.push(format!("cause: {}", md(&c)));
        }
        if parts.is_empty() {
            "no reading or cause named".to_owned()
        } else {
            parts.join("; ")
        }
    }

    fn fields(&self) -> [String; 12] {
        [
            self.study.clone(),
            self.kind.clone(),
            self.key.clone(),
            self.occurrence.to_string(),
            self.evidence.clone(),
            self.verdict.clone(),
            self.paper.clone(),
            self.model.clone(),
            self.band.clone(),
            self.readings.clone(),
            self.flags.clone(),
            self.cause.clone(),
        ]
    }
}

fn md(s: &str) -> String {
    s.replace('|', "\\|").replace('\n', " ")
}

/// The verdict rows of every study result, in study and row order. Figures carry the digest
/// of their committed data CSV (`figure_csv(study, figure)` gives that text).
pub fn verdict_rows(results: &[StudyResult]) -> Vec<VerdictRow> {
    let mut rows = Vec::new();
    for r in results {
        let st = &r.study;
        let Ok(out) = &r.output else {
            rows.push(VerdictRow {
                study: st.id.to_owned(),
                kind: "study".to_owned(),
                key: "failed to run".to_owned(),
                occurrence: 1,
                evidence: String::new(),
                verdict: "error".to_owned(),
                paper: String::new(),
                model: String::new(),
                band: String::new(),
                readings: String::new(),
                flags: String::new(),
                cause: String::new(),
            });
            continue;
        };
        let mut seen: BTreeMap<(String, String), usize> = BTreeMap::new();
        let mut occ = |kind: &str, key: &str| {
            let n = seen.entry((kind.to_owned(), key.to_owned())).or_default();
            *n += 1;
            *n
        };
        for c in &out.comparisons {
            rows.push(VerdictRow {
                study: st.id.to_owned(),
                kind: "comparison".to_owned(),
                key: c.quantity.clone(),
                occurrence: occ("comparison", &c.quantity),
                evidence: c.evidence.label(),
                verdict: c.verdict().label().to_owned(),
                paper: c.reference.printed.clone(),
                model: c.committed_model(),
                band: fmt_sig(c.half_width(), 3),
                readings: c.readings.join(" "),
                flags: c.flags.join("; "),
                cause: c.cause.clone(),
            });
        }
        for c in &out.claims {
            rows.push(VerdictRow {
                study: st.id.to_owned(),
                kind: "claim".to_owned(),
                key: c.text.clone(),
                occurrence: occ("claim", &c.text),
                evidence: c.class.label(),
                verdict: c.verdict.label().to_owned(),
                paper: c.source.clone(),
                model: String::new(),
                band: String::new(),
                readings: c.readings.join(" "),
                flags: c.flags.join("; "),
                cause: c.cause.clone(),
            });
        }
        for f in &out.figures {
            if f.non_periodic {
                // not committed, not compared: its digest is part of stats-digest.txt
                continue;
            }
            let data = drawn_figure(f).to_table().to_csv();
            rows.push(VerdictRow {
                study: st.id.to_owned(),
                kind: "figure".to_owned(),
                key: f.name.clone(),
                occurrence: occ("figure", &f.name),
                evidence: String::new(),
                verdict: String::new(),
                paper: format!("{}/{}_{}.csv", st.paper.dir(), st.id, f.name),
                model: digest(data.as_bytes()),
                band: String::new(),
                readings: String::new(),
                flags: String::new(),
                cause: String::new(),
            });
        }
    }
    rows
}

/// The text of `validation/verdicts.csv`.
pub fn verdicts_csv(rows: &[VerdictRow]) -> String {
    let mut s = String::from(VERDICTS_HEADER);
    s.push('\n');
    for r in rows {
        let f: Vec<String> = r.fields().iter().map(|x| csv_field(x)).collect();
        s.push_str(&f.join(","));
        s.push('\n');
    }
    s
}

/// Parse RFC 4180 CSV (quoted fields with `""`, commas and newlines inside quotes).
fn parse_csv(text: &str) -> Vec<Vec<String>> {
    let mut rows = Vec::new();
    let mut row = Vec::new();
    let mut field = String::new();
    let mut quoted = false;
    let mut chars = text.chars().peekable();
    let mut any = false;
    while let Some(c) = chars.next() {
        any = true;
        if quoted {
            match c {
                '"' if chars.peek() == Some(&'"') => {
                    chars.next();
                    field.push('"');
                }
                '"' => quoted = false,
                _ => field.push(c),
            }
        } else {
            match c {
                '"' => quoted = true,
                ',' => row.push(std::mem::take(&mut field)),
                '\n' => {
                    row.push(std::mem::take(&mut field));
                    rows.push(std::mem::take(&mut row));
                    any = false;
                }
                '\r' => {}
                _ => field.push(c),
            }
        }
    }
    if any {
        row.push(field);
        rows.push(row);
    }
    rows
}

/// Parse the text of a `verdicts.csv`.
pub fn parse_verdicts(text: &str) -> Result<Vec<VerdictRow>, Error> {
    let mut rows = parse_csv(text).into_iter();
    match rows.next() {
        Some(h) if h.join(",") == VERDICTS_HEADER => {}
        Some(h) => {
            return Err(Error::Study(format!(
                "verdicts.csv: unexpected header `{}`",
                h.join(",")
            )));
        }
        None => return Ok(Vec::new()),
    }
    rows.enumerate()
        .map(|(i, f)| {
            if f.len() != 12 {
                return Err(Error::Study(format!(
                    "verdicts.csv line {}: {} fields, expected 12",
                    i + 2,
                    f.len()
                )));
            }
            let mut it = f.into_iter();
            let mut next = || it.next().unwrap_or_default();
            Ok(VerdictRow {
                study: next(),
                kind: next(),
                key: next(),
                occurrence: next().parse().unwrap_or(1),
                evidence: next(),
                verdict: next(),
                paper: next(),
                model: next(),
                band: next(),
                readings: next(),
                flags: next(),
                cause: next(),
            })
        })
        .collect()
}

/// A model value that moved with its verdict kept.
#[derive(Debug, Clone, PartialEq)]
pub struct Moved {
    /// The row (new side).
    pub row: VerdictRow,
    /// The committed model value before.
    pub before: String,
    /// The largest move of the value (or of an interval bound), in units of the band
    /// half-width (infinite when the band is zero).
    pub bands: f64,
}

/// What changed between two verdict files.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct VerdictDiff {
    /// Rows whose verdict changed: (before, after).
    pub verdicts: Vec<(VerdictRow, VerdictRow)>,
    /// Rows whose evidence class changed (verdict kept): (before, after).
    pub classes: Vec<(VerdictRow, VerdictRow)>,
    /// Rows only in the new file.
    pub added: Vec<VerdictRow>,
    /// Rows only in the old file.
    pub removed: Vec<VerdictRow>,
    /// Model values that moved by more than [`MOVE_FRACTION`] of their band, largest first.
    pub moved: Vec<Moved>,
    /// Model values whose committed digits changed by at most [`MOVE_FRACTION`] of the band.
    pub small_moves: usize,
    /// Figures whose drawing-precision data changed: (before, after).
    pub figures: Vec<(VerdictRow, VerdictRow)>,
    /// Rows whose flags, readings or cause changed (verdict and class kept).
    pub annotations: Vec<(VerdictRow, VerdictRow)>,
    /// Rows compared.
    pub rows: usize,
}

/// The numbers of a committed model value: the value, then the interval bounds.
fn numbers(model: &str) -> Vec<f64> {
    model
        .split([' ', '[', ']', ','])
        .filter(|t| !t.is_empty())
        .map(|t| t.parse::<f64>().unwrap_or(f64::NAN))
        .collect()
}

/// Compare two verdict files (`old` at the base revision, `new` the working tree).
pub fn diff_verdicts(old: &[VerdictRow], new: &[VerdictRow]) -> VerdictDiff {
    let old_map: BTreeMap<_, &VerdictRow> = old.iter().map(|r| (r.ident(), r)).collect();
    let new_keys: std::collections::BTreeSet<_> = new.iter().map(VerdictRow::ident).collect();
    let mut d = VerdictDiff::default();
    for n in new {
        let Some(o) = old_map.get(&n.ident()) else {
            d.added.push(n.clone());
            continue;
        };
        d.rows += 1;
        if o.verdict != n.verdict {
            d.verdicts.push(((*o).clone(), n.clone()));
            continue;
        }
        if o.evidence != n.evidence {
            d.classes.push(((*o).clone(), n.clone()));
            continue;
        }
        if n.kind == "figure" {
            if o.model != n.model {
                d.figures.push(((*o).clone(), n.clone()));
            }
            continue;
        }
        if o.model != n.model {
            let (a, b) = (numbers(&o.model), numbers(&n.model));
            let band: f64 = n.band.parse().unwrap_or(f64::NAN);
            let shift = if a.len() == b.len() {
                a.iter()
                    .zip(&b)
                    .map(|(x, y)| {
                        if x.is_nan() && y.is_nan() {
                            0.0
                        } else {
                            (x - y).abs()
                        }
                    })
                    .fold(
                        0.0_f64,
                        |m, v| if v.is_nan() { f64::INFINITY } else { m.max(v) },
                    )
            } else {
                f64::INFINITY
            };
            let bands = if band > 0.0 {
                shift / band
            } else {
                f64::INFINITY
            };
            if bands > MOVE_FRACTION {
                d.moved.push(Moved {
                    row: n.clone(),
                    before: o.model.clone(),
                    bands,
                });
            } else {
                d.small_moves += 1;
            }
        }
        if o.flags != n.flags || o.readings != n.readings || o.cause != n.cause {
            d.annotations.push(((*o).clone(), n.clone()));
        }
    }
    for o in old {
        if !new_keys.contains(&o.ident()) {
            d.removed.push(o.clone());
        }
    }
    d.moved.sort_by(|a, b| b.bands.total_cmp(&a.bands));
    d
}

impl VerdictDiff {
    /// Whether any verdict or evidence class changed, or a row was added or removed.
    pub fn changes_meaning(&self) -> bool {
        !(self.verdicts.is_empty()
            && self.classes.is_empty()
            && self.added.is_empty()
            && self.removed.is_empty())
    }

    /// The markdown summary for a PR comment, most severe first. `figure_detail(before, after)`
    /// describes a changed figure (which series moved); `base` names the compared revision.
    pub fn to_markdown(
        &self,
        base: &str,
        figure_detail: &dyn Fn(&VerdictRow, &VerdictRow) -> String,
    ) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "## Validation diff against `{base}`\n");
        if self.verdicts.is_empty() {
            s.push_str("**No verdict changed.**");
        } else {
            let _ = write!(s, "**{} verdict(s) changed.**", self.verdicts.len());
        }
        let _ = writeln!(
            s,
            " {} evidence class(es) changed, {} row(s) added, {} removed; {} model value(s) moved by \
             more than {} of their band, {} by less; {} figure(s) moved beyond drawing precision \
             ({} rows compared).\n",
            self.classes.len(),
            self.added.len(),
            self.removed.len(),
            self.moved.len(),
            fraction(MOVE_FRACTION),
            self.small_moves,
            self.figures.len(),
            self.rows
        );
        if !self.verdicts.is_empty() {
            let _ = writeln!(s, "### Verdicts changed ({})\n", self.verdicts.len());
            for (o, n) in &self.verdicts {
                let model = if n.kind == "comparison" {
                    format!(
                        " (paper {}, model {} → {}, band ±{})",
                        o.paper, o.model, n.model, n.band
                    )
                } else {
                    String::new()
                };
                let _ = writeln!(
                    s,
                    "- **{} → {}** {}{model} — {}",
                    o.verdict,
                    n.verdict,
                    n.name(),
                    n.why()
                );
            }
            s.push('\n');
        }
        if !self.classes.is_empty() {
            let _ = writeln!(s, "### Evidence classes changed ({})\n", self.classes.len());
            for (o, n) in &self.classes {
                let _ = writeln!(
                    s,
                    "- {}: {} → {} (verdict {}) — {}",
                    n.name(),
                    o.evidence,
                    n.evidence,
                    n.verdict,
                    n.why()
                );
            }
            s.push('\n');
        }
        if !self.added.is_empty() || !self.removed.is_empty() {
            let _ = writeln!(
                s,
                "### Rows added ({}) or removed ({})\n",
                self.added.len(),
                self.removed.len()
            );
            for r in &self.added {
                let _ = writeln!(
                    s,
                    "- added {}: {} ({}) — {}",
                    r.name(),
                    r.verdict,
                    r.evidence,
                    r.why()
                );
            }
            for r in &self.removed {
                let _ = writeln!(
                    s,
                    "- removed {}: was {} ({})",
                    r.name(),
                    r.verdict,
                    r.evidence
                );
            }
            s.push('\n');
        }
        if !self.moved.is_empty() {
            let _ = writeln!(
                s,
                "### Model values moved by more than {} of their band, verdict kept ({})\n",
                fraction(MOVE_FRACTION),
                self.moved.len()
            );
            for m in &self.moved {
                let size = if m.bands.is_finite() {
                    format!("{} × band", fmt_sig(m.bands, 2))
                } else {
                    "band 0 or value not a number".to_owned()
                };
                let _ = writeln!(
                    s,
                    "- {}: {} → {} (paper {} ± {}; moved {size}; {}) — {}",
                    m.row.name(),
                    m.before,
                    m.row.model,
                    m.row.paper,
                    m.row.band,
                    m.row.verdict,
                    m.row.why()
                );
            }
            s.push('\n');
        }
        if !self.figures.is_empty() {
            let _ = writeln!(
                s,
                "### Figures whose curves moved beyond drawing precision ({})\n",
                self.figures.len()
            );
            for (o, n) in &self.figures {
                let _ = writeln!(
                    s,
                    "- {} (`validation/{}`): {}",
                    n.name(),
                    n.paper,
                    figure_detail(o, n)
                );
            }
            s.push('\n');
        }
        if !self.annotations.is_empty() {
            let _ = writeln!(
                s,
                "### Flags, readings or causes changed, verdict kept ({})\n",
                self.annotations.len()
            );
            for (o, n) in &self.annotations {
                let _ = writeln!(s, "- {}: {}", n.name(), annotation_change(o, n));
            }
            s.push('\n');
        }
        s
    }
}

/// What changed in the flags, readings and cause of a row, and only that: the readings before
/// and after, the flags removed and added (a row's flags are `; `-separated items, one per
/// point, so a flag that appears at one swept point is named, not hidden 200 characters into
/// two identical-looking lists), and the cause from a little before its first difference.
fn annotation_change(o: &VerdictRow, n: &VerdictRow) -> String {
    const ITEM: usize = 160;
    const ITEMS: usize = 5;
    let clip = |t: &str| -> String {
        let c: String = t.chars().take(ITEM).collect();
        let more = if t.chars().count() > ITEM { "…" } else { "" };
        format!("«{}{more}»", md(&c))
    };
    let list = |items: &[&str]| -> String {
        let mut v: Vec<String> = items.iter().take(ITEMS).map(|t| clip(t)).collect();
        if items.len() > ITEMS {
            v.push(format!("and {} more", items.len() - ITEMS));
        }
        v.join(", ")
    };
    let mut parts = Vec::new();
    if o.readings != n.readings {
        parts.push(format!(
            "reading {} → {}",
            clip(&o.readings),
            clip(&n.readings)
        ));
    }
    if o.flags != n.flags {
        let split = |t: &str| -> Vec<String> {
            t.split("; ")
                .filter(|x| !x.is_empty())
                .map(str::to_owned)
                .collect()
        };
        let (a, b) = (split(&o.flags), split(&n.flags));
        let gone: Vec<&str> = a
            .iter()
            .filter(|x| !b.contains(x))
            .map(String::as_str)
            .collect();
        let new: Vec<&str> = b
            .iter()
            .filter(|x| !a.contains(x))
            .map(String::as_str)
            .collect();
        if !gone.is_empty() {
            parts.push(format!("flag removed: {}", list(&gone)));
        }
        if !new.is_empty() {
            parts.push(format!("flag added: {}", list(&new)));
        }
        if gone.is_empty() && new.is_empty() {
            parts.push("flags reordered".to_owned());
        }
    }
    if o.cause != n.cause {
        // from a little before the first differing character
        let common = o
            .cause
            .chars()
            .zip(n.cause.chars())
            .take_while(|(x, y)| x == y)
            .count();
        let from = common.saturating_sub(40);
        let tail = |t: &str| -> String {
            let rest: String = t.chars().skip(from).collect();
            let lead = if from > 0 { "…" } else { "" };
            format!("{lead}{}", clip(&rest))
        };
        parts.push(format!("cause {} → {}", tail(&o.cause), tail(&n.cause)));
    }
    parts.join("; ")
}

fn fraction(x: f64) -> String {
    if x > 0.0 && (1.0 / x).fract() == 0.0 {
        format!("1/{}", 1.0 / x)
    } else {
        fmt_sig(x, 3)
    }
}

/// Which series of a figure's committed data moved, from the two CSV texts
/// (`series,x,y` long format at drawing precision).
pub fn figure_change(old_csv: &str, new_csv: &str) -> String {
    let series = |t: &str| {
        let mut m: BTreeMap<String, Vec<(String, String)>> = BTreeMap::new();
        for f in parse_csv(t).into_iter().skip(1) {
            if f.len() >= 3 {
                m.entry(f[0].clone())
                    .or_default()
                    .push((f[1].clone(), f[2].clone()));
            }
        }
        m
    };
    let (a, b) = (series(old_csv), series(new_csv));
    let mut parts = Vec::new();
    for (name, pb) in &b {
        match a.get(name) {
            None => parts.push(format!("series «{name}» added")),
            Some(pa) if pa != pb => {
                // matched by abscissa (a point leaving or entering does not shift the others);
                // repeated abscissas (a hysteresis sweep, a phase portrait) pair in order
                let by_x = |v: &[(String, String)]| {
                    let mut m: BTreeMap<String, Vec<String>> = BTreeMap::new();
                    for (x, y) in v {
                        m.entry(x.clone()).or_default().push(y.clone());
                    }
                    m
                };
                let (xa, xb) = (by_x(pa), by_x(pb));
                let (mut moved, mut entered, mut left) = (0, 0, 0);
                for (x, ys) in &xb {
                    let old: &[String] = xa.get(x).map_or(&[], Vec::as_slice);
                    moved += ys.iter().zip(old).filter(|(p, q)| p != q).count();
                    entered += ys.len().saturating_sub(old.len());
                    left += old.len().saturating_sub(ys.len());
                }
                for (x, ys) in &xa {
                    if !xb.contains_key(x) {
                        left += ys.len();
                    }
                }
                let mut what = vec![format!("{moved} of {} points moved", pb.len())];
                if entered > 0 {
                    what.push(format!("{entered} entered"));
                }
                if left > 0 {
                    what.push(format!("{left} left"));
                }
                parts.push(format!("series «{name}»: {}", what.join(", ")));
            }
            Some(_) => {}
        }
    }
    for name in a.keys() {
        if !b.contains_key(name) {
            parts.push(format!("series «{name}» removed"));
        }
    }
    if parts.is_empty() {
        "data unchanged (style or labels only)".to_owned()
    } else {
        parts.join("; ")
    }
}

/// For `--check`: an error listing the verdict changes between the committed and the freshly
/// generated `verdicts.csv` (verdicts, classes, rows added or removed), `Ok` when none.
pub fn check_verdicts(committed: &str, fresh: &str) -> Result<(), String> {
    let old = parse_verdicts(committed).map_err(|e| e.to_string())?;
    let new = parse_verdicts(fresh).map_err(|e| e.to_string())?;
    let d = diff_verdicts(&old, &new);
    if d.changes_meaning() {
        Err(
            d.to_markdown("the committed validation/verdicts.csv", &|_, _| {
                String::new()
            }),
        )
    } else {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    /// Points are matched by abscissa: one point entering a series is one entry, not a shift
    /// of every later point.
    #[test]
    fn figure_change_matches_points_by_abscissa() {
        let old = "series,x,y\na,1,10\na,2,20\na,3,30\n";
        let new = "series,x,y\na,1,10\na,1.5,15\na,2,20\na,3,31\n";
        assert_eq!(
            super::figure_change(old, new),
            "series «a»: 1 of 4 points moved, 1 entered"
        );
        let fewer = "series,x,y\na,1,10\na,3,30\n";
        assert_eq!(
            super::figure_change(old, fewer),
            "series «a»: 0 of 2 points moved, 1 left"
        );
        assert_eq!(
            super::figure_change(old, old),
            "data unchanged (style or labels only)"
        );
    }

    /// A flag that appears at one point is named on its own, even when the lists agree on
    /// their first 200 characters (the round-10 `--diff` printed two identical-looking
    /// prefixes); an unchanged part is not repeated.
    #[test]
    fn annotation_change_names_only_what_changed() {
        let row = |flags: &str, cause: &str| super::VerdictRow {
            study: "s".into(),
            kind: "claim".into(),
            key: "k".into(),
            occurrence: 1,
            evidence: "reproduction".into(),
            verdict: "shown".into(),
            paper: String::new(),
            model: String::new(),
            band: String::new(),
            readings: "R-A".into(),
            flags: flags.into(),
            cause: cause.into(),
        };
        let long = "x".repeat(300);
        let a = row(&format!("{long}; at 1: f"), "same start, then one");
        let b = row(
            &format!("{long}; at 1: f; at 1.215: g"),
            "same start, then two",
        );
        let d = super::annotation_change(&a, &b);
        assert_eq!(
            d,
            "flag added: «at 1.215: g»; cause «same start, then one» → «same start, then two»"
        );
        assert_eq!(
            super::annotation_change(&b, &a),
            "flag removed: «at 1.215: g»; cause «same start, then two» → «same start, then one»"
        );
        let mut r = row("p; q", "");
        r.readings = "R-B".into();
        assert_eq!(
            super::annotation_change(&row("q; p", ""), &r),
            "reading «R-A» → «R-B»; flags reordered"
        );
    }
}
