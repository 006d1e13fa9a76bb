//! Integrity rules of the validation outputs, enforced by `cargo xtask validate --check`.
//!
//! 1. A `DEVIATION` or `inconclusive` row — comparison or claim — names a reading id or a cause.
//! 2. No two outputs of a study share a file name (a table's CSV and a figure's data CSV would
//!    overwrite each other).
//! 3. No verdict rests on a flagged point: a row with flags (non-converged, unstable,
//!    non-periodic, not reproducible) is `inconclusive` or `shown`, never pass/deviation.

use std::collections::BTreeMap;

use crate::render::StudyResult;
use crate::study::{Study, StudyOutput, Verdict};

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
    for c in &out.claims {
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
}
