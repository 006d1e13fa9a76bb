//! Integrity rules of the validation outputs, enforced by `cargo xtask validate --check`.
//!
//! 1. A `DEVIATION` or `inconclusive` row — comparison or claim — names a reading id or a cause.
//! 2. No two outputs of a study share a file name (a table's CSV and a figure's data CSV would
//!    overwrite each other).
//! 3. No verdict rests on a flagged point: a row with flags (non-converged, unstable,
//!    non-periodic, not reproducible) is `inconclusive` or `shown`, never pass/deviation.
//! 4. Flags are claim-local: a flag that names a swept point (`at x: …`) names one of the
//!    points the row needs (`needs`); a row that names none has no such flag.
//! 5. A judged threshold reproduction (a published value marked `threshold`) carries an
//!    interval.
//! 6. Each check counts once: no two reproduction rows (in any studies) compare the same
//!    quantity and paper value with the same model value; a reading variant or a paper-vs-paper
//!    row must carry its own class ([`crate::Evidence::ReadingVariant`],
//!    [`crate::Evidence::Consistency`]), never `reproduction`.

use std::collections::BTreeMap;

use crate::render::StudyResult;
use crate::study::{Evidence, Study, StudyOutput, Verdict};

/// The swept value a flag names (`at 162.5: …`, `at 162.5 rad/s: …`), if any.
fn flag_point(flag: &str) -> Option<f64> {
    let rest = flag.strip_prefix("at ")?;
    let end = rest.find([' ', ':'])?;
    rest[..end].parse().ok()
}

/// Rule 4: the flags naming a point that is not among `needs`.
fn foreign_flags<'a>(flags: &'a [String], needs: &[f64]) -> Vec<&'a str> {
    flags
        .iter()
        .filter(|f| {
            flag_point(f).is_some_and(|x| !needs.iter().any(|n| n.to_bits() == x.to_bits()))
        })
        .map(String::as_str)
        .collect()
}

/// One broken rule: the study id and what is wrong.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Problem {
    /// Study id.
    pub study: String,
    /// What is wrong, naming the row or file.
    pub what: String,
}

impl std::fmt::Display for Problem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.study, self.what)
    }
}

/// File names (relative to `validation/`) a study's output is written to, in write order.
pub fn output_files(study: &Study, out: &StudyOutput) -> Vec<String> {
    let dir = study.paper.dir();
    let mut v = vec![format!("{dir}/{}.csv", study.id)];
    for t in &out.tables {
        v.push(format!("{dir}/{}_{}.csv", study.id, t.name));
    }
    for f in &out.figures {
        v.push(format!("{dir}/{}_{}.csv", study.id, f.name));
        v.push(format!("{dir}/{}_{}.svg", study.id, f.name));
    }
    for m in &out.heatmaps {
        v.push(format!("{dir}/{}_{}.csv", study.id, m.name));
        v.push(format!("{dir}/{}_{}.svg", study.id, m.name));
    }
    v
}

/// The problems of one study's output.
pub fn audit_output(study: &Study, out: &StudyOutput) -> Vec<Problem> {
    let mut p = Vec::new();
    let mut push = |what: String| {
        p.push(Problem {
            study: study.id.to_owned(),
            what,
        });
    };
    for (i, c) in out.comparisons.iter().enumerate() {
        let v = c.verdict();
        if matches!(v, Verdict::Deviation | Verdict::Inconclusive)
            && c.readings.is_empty()
            && c.cause.trim().is_empty()
            && c.flags.is_empty()
        {
            push(format!(
                "comparison #{} `{}` is {} but names no reading id or cause",
                i + 1,
                c.quantity,
                v.label()
            ));
        }
        if !c.flags.is_empty() && matches!(v, Verdict::Pass | Verdict::Deviation) {
            push(format!(
                "comparison #{} `{}` has verdict {} from a flagged point ({})",
                i + 1,
                c.quantity,
                v.label(),
                c.flags.join("; ")
            ));
        }
    }
    for (i, c) in out.comparisons.iter().enumerate() {
        let foreign = foreign_flags(&c.flags, &c.needs);
        if !foreign.is_empty() {
            push(format!(
                "comparison #{} `{}` rests on flags of points it does not need ({})",
                i + 1,
                c.quantity,
                foreign.join("; ")
            ));
        }
        if c.threshold && c.judged && c.evidence == Evidence::Reproduction && c.interval.is_none() {
            push(format!(
                "comparison #{} `{}` is a threshold without an interval",
                i + 1,
                c.quantity
            ));
        }
    }
    for c in &out.claims {
        let foreign = foreign_flags(&c.flags, &c.needs);
        if !foreign.is_empty() {
            push(format!(
                "claim `{}` rests on flags of points it does not need ({})",
                c.text,
                foreign.join("; ")
            ));
        }
        if matches!(c.verdict, Verdict::Deviation | Verdict::Inconclusive)
            && c.readings.is_empty()
            && c.cause.trim().is_empty()
            && c.flags.is_empty()
        {
            push(format!(
                "claim `{}` is {} but names no reading id or cause",
                c.text,
                c.verdict.label()
            ));
        }
        if !c.flags.is_empty() && matches!(c.verdict, Verdict::Pass | Verdict::Deviation) {
            push(format!(
                "claim `{}` has verdict {} from a flagged point ({})",
                c.text,
                c.verdict.label(),
                c.flags.join("; ")
            ));
        }
    }
    let mut seen: BTreeMap<String, usize> = BTreeMap::new();
    for f in output_files(study, out) {
        *seen.entry(f).or_default() += 1;
    }
    for (f, n) in seen {
        if n > 1 {
            push(format!("{n} outputs share the file name {f}"));
        }
    }
    p
}

/// Rule 6 over all results: a reproduction counted twice (same quantity, paper value and model
/// value in two rows).
pub fn audit_counted_once(results: &[StudyResult]) -> Vec<Problem> {
    let mut seen: BTreeMap<(String, String, u64), String> = BTreeMap::new();
    let mut v = Vec::new();
    for r in results {
        let Ok(o) = &r.output else { continue };
        for c in &o.comparisons {
            if !(c.judged && c.evidence == Evidence::Reproduction) {
                continue;
            }
            let key = (
                c.quantity.clone(),
                c.reference.printed.clone(),
                c.model.to_bits(),
            );
            if let Some(first) = seen.get(&key) {
                v.push(Problem {
                    study: r.study.id.to_owned(),
                    what: format!(
                        "reproduction `{}` (paper {}) repeats a row of {first}: count each check once (class it as a reading variant or consistency)",
                        c.quantity, c.reference.printed
                    ),
                });
            } else {
                seen.insert(key, r.study.id.to_owned());
            }
        }
    }
    v
}

/// The problems of all results (a study that failed to run is a problem too).
pub fn audit(results: &[StudyResult]) -> Vec<Problem> {
    let mut v = Vec::new();
    for r in results {
        match &r.output {
            Ok(o) => v.extend(audit_output(&r.study, o)),
            Err(e) => v.push(Problem {
                study: r.study.id.to_owned(),
                what: format!("failed to run: {e}"),
            }),
        }
    }
    v.extend(audit_counted_once(results));
    v
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Claim, Comparison, Cost, Figure, Paper, Reference, Table, Tolerance};

    fn study() -> Study {
        Study {
            id: "karpov2017-audit-test",
            paper: Paper::Karpov2017,
            source: "test",
            title: "test",
            description: "",
            cost: Cost::Fast,
            run: || Ok(StudyOutput::new()),
        }
    }

    fn deviating() -> Comparison {
        Comparison::new(
            "x",
            "1",
            Reference::computed(1.0, "exact"),
            2.0,
            Tolerance::numerical(1e-3),
        )
    }

    #[test]
    fn deviation_without_reading_or_cause_fails() {
        let mut out = StudyOutput::new();
        out.compare(deviating());
        assert_eq!(audit_output(&study(), &out).len(), 1);
        let mut out = StudyOutput::new();
        out.compare(deviating().cause("known: printed value is a typo"));
        out.compare(deviating().reading("R-X"));
        assert!(audit_output(&study(), &out).is_empty());
    }

    #[test]
    fn claim_deviation_or_inconclusive_without_cause_fails() {
        let mut out = StudyOutput::new();
        out.claim(Claim::new("c", "p. 1", "e", Verdict::Deviation));
        out.claim(Claim::new("d", "p. 1", "e", Verdict::Inconclusive));
        assert_eq!(audit_output(&study(), &out).len(), 2);
        let mut out = StudyOutput::new();
        out.claim(Claim::new("c", "p. 1", "e", Verdict::Deviation).cause("why"));
        out.claim(Claim::new("d", "p. 1", "e", Verdict::Pass));
        assert!(audit_output(&study(), &out).is_empty());
    }

    #[test]
    fn verdict_from_flagged_point_fails() {
        // a claim whose verdict is set after flagging (bypassing `flagged_all`)
        let mut c =
            Claim::new("c", "p. 1", "e", Verdict::Pass).flagged_all(["HBM unstable".into()]);
        assert_eq!(c.verdict, Verdict::Inconclusive);
        let mut out = StudyOutput::new();
        out.claim(c.clone());
        assert!(audit_output(&study(), &out).is_empty());
        c.verdict = Verdict::Pass;
        let mut out = StudyOutput::new();
        out.claim(c);
        let p = audit_output(&study(), &out);
        assert_eq!(p.len(), 1);
        assert!(p[0].what.contains("flagged"));
        // a flagged comparison is inconclusive (and carries its reason, so it passes rule 1)
        let f = deviating().flagged("HBM not converged");
        assert_eq!(f.verdict(), Verdict::Inconclusive);
        let mut out = StudyOutput::new();
        out.compare(f);
        assert!(audit_output(&study(), &out).is_empty());
    }

    #[test]
    fn shared_file_name_fails() {
        let mut out = StudyOutput::new();
        out.table(Table::new("dte", &[("x", "1")]));
        out.figure(Figure::new("dte", "t", ("x", "1"), ("y", "1")));
        let p = audit_output(&study(), &out);
        assert_eq!(p.len(), 1);
        assert!(p[0].what.contains("share the file name"));
        let mut out = StudyOutput::new();
        out.table(Table::new("dte", &[("x", "1")]));
        out.figure(Figure::new("dte_series", "t", ("x", "1"), ("y", "1")));
        assert!(audit_output(&study(), &out).is_empty());
    }

    /// Rule 4: a verdict resting on the flag of a point the row does not need fails; the flag of
    /// a needed point (named exactly as swept) does not.
    #[test]
    fn flags_of_points_not_needed_fail() {
        let flag = "at 180: long-window rattle state not robust".to_owned();
        let mut out = StudyOutput::new();
        out.claim(
            Claim::new("c", "p. 1", "e", Verdict::Pass)
                .needs([140.0, 160.0])
                .flagged_all([flag.clone()]),
        );
        let p = audit_output(&study(), &out);
        assert_eq!(p.len(), 1, "{p:?}");
        assert!(p[0].what.contains("does not need"));
        let mut out = StudyOutput::new();
        out.claim(
            Claim::new("c", "p. 1", "e", Verdict::Pass)
                .needs([160.0, 180.0])
                .flagged_all([flag]),
        );
        assert!(audit_output(&study(), &out).is_empty());
        // 162.5 is not 162 (exact swept values)
        let mut out = StudyOutput::new();
        out.compare(
            deviating()
                .needs([162.0])
                .flagged("at 162.5 rad/s: not robust"),
        );
        assert_eq!(audit_output(&study(), &out).len(), 1);
        assert_eq!(flag_point("at 162.5 rad/s: x"), Some(162.5));
        assert_eq!(flag_point("HBM unstable"), None);
    }

    /// Rule 5: a judged threshold reproduction without an interval fails; with one, or as a
    /// reading variant, it does not.
    #[test]
    fn threshold_without_interval_fails() {
        let mut c = deviating().cause("c");
        c.threshold = true;
        let mut out = StudyOutput::new();
        out.compare(c.clone());
        let p = audit_output(&study(), &out);
        assert_eq!(p.len(), 1);
        assert!(p[0].what.contains("without an interval"));
        let mut out = StudyOutput::new();
        out.compare(c.clone().within(1.5, 2.5));
        out.compare(c.class(Evidence::ReadingVariant("R-X".into())));
        assert!(audit_output(&study(), &out).is_empty());
    }

    /// Rule 6: the same reproduction in two studies is counted twice and fails; classed as a
    /// reading variant it does not.
    #[test]
    fn reproduction_counted_twice_fails() {
        let result = |out: StudyOutput| StudyResult {
            study: study(),
            output: Ok(out),
            cost: Default::default(),
        };
        let mut a = StudyOutput::new();
        a.compare(deviating().cause("c"));
        let b = a.clone();
        let p = audit(&[result(a.clone()), result(b)]);
        assert_eq!(p.len(), 1, "{p:?}");
        assert!(p[0].what.contains("count each check once"));
        let mut c = StudyOutput::new();
        c.compare(
            deviating()
                .cause("c")
                .class(Evidence::ReadingVariant("R-X".into())),
        );
        assert!(audit(&[result(a), result(c)]).is_empty());
    }
}
