//! Studies and what they produce: comparisons, claims, tables, figures.

use serde::Serialize;

use crate::error::{Error, check_name};
use crate::figure::Figure;
use crate::format::half_last_digit;
use crate::heatmap::Heatmap;
use crate::published::{PublishedClaim, PublishedValue};
use crate::table::Table;

/// The source papers (and user studies, which belong to no paper).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[non_exhaustive]
pub enum Paper {
    /// Karpov, Nosko, Fil, Nosko, Olofsson 2017, *Prevention of resonance oscillations in gear
    /// mechanisms using non-circular gears*, Mech. Mach. Theory 114:1.
    Karpov2017,
    /// Liu, Lv, Zhao 2021, *Rattle dynamics of noncircular face gear under multifrequency
    /// parametric excitation*, Mech. Sci. 12:361.
    Liu2021,
    /// Yu, Sun, Li, Wu 2021, *Nonlinear response of gear system based on a novel backlash model
    /// with coupling dynamic change and surface topography* (preprint).
    Yu2021,
}

impl Paper {
    /// All papers, in report order.
    pub const ALL: [Paper; 3] = [Paper::Karpov2017, Paper::Liu2021, Paper::Yu2021];

    /// Directory name under `validation/` (`liu2021`, `karpov2017`, `yu2021`).
    pub fn dir(self) -> &'static str {
        match self {
            Paper::Liu2021 => "liu2021",
            Paper::Karpov2017 => "karpov2017",
            Paper::Yu2021 => "yu2021",
        }
    }

    /// Short citation for headings.
    pub fn citation(self) -> &'static str {
        match self {
            Paper::Liu2021 => {
                "Liu, Lv, Zhao 2021 — Rattle dynamics of noncircular face gear (Mech. Sci. 12:361)"
            }
            Paper::Karpov2017 => {
                "Karpov, Nosko, Fil, Nosko, Olofsson 2017 — Prevention of resonance oscillations \
                 using non-circular gears (MMT 114:1)"
            }
            Paper::Yu2021 => {
                "Yu, Sun, Li, Wu 2021 — Novel backlash model with coupling dynamic change and \
                 surface topography (preprint)"
            }
        }
    }
}

/// How expensive a study is; `cargo test -p validate` runs (and snapshot-tests) only
/// [`Cost::Fast`] studies, `cargo xtask validate` runs all.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[non_exhaustive]
pub enum Cost {
    /// Well under a second in a debug build (closed forms, geometry, small quadratures).
    Fast,
    /// Anything that integrates or continues a dynamic model.
    Heavy,
}

/// One published item (a table, a figure, an equation, a textual claim) and the code that holds a
/// model against it.
///
/// Studies are plain data plus a function pointer, so they are `Send + Sync` and cheap to list.
/// `id` must be unique, and is the file-name stem of every output (`a-z`, `0-9`, `-`, `_`, `.`);
/// by convention it starts with the paper, e.g. `karpov2017-fig4`, `liu2021-table2`.
#[derive(Debug, Clone, Copy)]
pub struct Study {
    /// Unique id and file-name stem, e.g. `liu2021-fig11-rsv-omega`.
    pub id: &'static str,
    /// The paper the study reproduces.
    pub paper: Paper,
    /// Where in the paper: `"Table 2, p. 12"`, `"Fig. 4, p. 6"`, `"Eq. (4), p. 3"`.
    pub source: &'static str,
    /// One-line title for the report.
    pub title: &'static str,
    /// What is compared and how the paper is read (Markdown, one paragraph).
    pub description: &'static str,
    /// Fast (run in unit tests) or heavy (only in `cargo xtask validate`).
    pub cost: Cost,
    /// The computation. Must be deterministic: same output bits for any rayon thread count
    /// (collect parallel sweeps in input order; no parallel float reductions).
    pub run: fn() -> Result<StudyOutput, Error>,
}

impl Study {
    /// Run the study, checking the output's names.
    pub fn execute(&self) -> Result<StudyOutput, Error> {
        check_name(self.id)?;
        let out = (self.run)()?;
        for t in &out.tables {
            check_name(&t.name)?;
        }
        for f in &out.figures {
            check_name(&f.name)?;
        }
        for m in &out.heatmaps {
            check_name(&m.name)?;
        }
        Ok(out)
    }
}

/// The verdict on one comparison or claim.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[non_exhaustive]
pub enum Verdict {
    /// The model reproduces the paper within the tolerance (or the claim holds for the model).
    Pass,
    /// The model disagrees with the paper; the row should name a reading that explains why.
    Deviation,
    /// The row cannot be decided: the model value rests on a non-converged, unstable or
    /// non-reproducible point, or the claim is too vague; the row names why.
    Inconclusive,
    /// Shown beside the judged method but not judged (the paper's verdict rule picks the other
    /// method, see `validation/README.md`), or a row that cannot fail (holds by construction).
    Shown,
}

impl Verdict {
    /// `pass`, `DEVIATION`, `inconclusive` (upper case makes deviations stand out in tables).
    pub fn label(self) -> &'static str {
        match self {
            Verdict::Pass => "pass",
            Verdict::Deviation => "DEVIATION",
            Verdict::Inconclusive => "inconclusive",
            Verdict::Shown => "shown",
        }
    }

    /// [`Verdict::Pass`] if `holds`, else [`Verdict::Deviation`].
    pub fn from_bool(holds: bool) -> Self {
        if holds {
            Verdict::Pass
        } else {
            Verdict::Deviation
        }
    }
}

/// What kind of evidence a row is (issue: only reproductions count as evidence that a model
/// reproduces a paper).
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
pub enum Evidence {
    /// An independently computed model quantity against the paper.
    Reproduction,
    /// The paper against itself, or a formula against its exact form.
    Consistency,
    /// Constants fitted from this data (named): agreement follows from the fit.
    Calibration(String),
    /// A transcribed number read back (checks the transcription, not the model).
    Transcription,
    /// True for any parameters or returns an input: cannot fail, so not a check.
    ByConstruction,
    /// A check of a reading the project rejects or has not decided (named): it can fail, but it
    /// tests the reading, not the model's reproduction of the paper, so it is listed apart and
    /// never counted in the headline.
    ReadingVariant(String),
    /// Held against a number the seeds do not print (named): shown, not a check, never counted.
    NotCheckable(String),
}

impl Evidence {
    /// Short label for tables (`reproduction`, `calibration (k_b, c)`, …).
    pub fn label(&self) -> String {
        match self {
            Evidence::Reproduction => "reproduction".to_owned(),
            Evidence::Consistency => "consistency".to_owned(),
            Evidence::Calibration(what) => format!("calibration ({what})"),
            Evidence::Transcription => "transcription".to_owned(),
            Evidence::ByConstruction => "holds by construction".to_owned(),
            Evidence::ReadingVariant(what) => format!("reading variant ({what})"),
            Evidence::NotCheckable(what) => format!("not checkable ({what})"),
        }
    }

    /// Whether a row of this class is a check (can fail): all but
    /// [`Evidence::ByConstruction`] and [`Evidence::NotCheckable`].
    pub fn is_check(&self) -> bool {
        !matches!(self, Evidence::ByConstruction | Evidence::NotCheckable(_))
    }

    /// Whether a row of this class counts in the headline: only an independent
    /// [`Evidence::Reproduction`].
    pub fn is_reproduction(&self) -> bool {
        matches!(self, Evidence::Reproduction)
    }
}

/// Why a tolerance has the size it has. Chosen before looking at the model's number.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[non_exhaustive]
pub enum ToleranceBasis {
    /// Half a unit in the last digit the paper prints (`38.67` → ±0.005).
    PrintedPrecision,
    /// Uncertainty of reading a value off a published figure.
    Digitising,
    /// The text says "about"/"approximately"; the stated relative band.
    ApproximateText,
    /// Model against an exact or reference computation: numerical error only.
    Numerical,
    /// Anything else, explained in words.
    Stated(String),
}

impl ToleranceBasis {
    /// Short label for tables.
    pub fn label(&self) -> String {
        match self {
            ToleranceBasis::PrintedPrecision => "printed precision".to_owned(),
            ToleranceBasis::Digitising => "digitising".to_owned(),
            ToleranceBasis::ApproximateText => "\"about\" in text".to_owned(),
            ToleranceBasis::Numerical => "numerical".to_owned(),
            ToleranceBasis::Stated(s) => s.clone(),
        }
    }
}

/// Size of a tolerance band.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[non_exhaustive]
pub enum ToleranceBand {
    /// |model − paper| ≤ value (in the quantity's unit).
    Absolute(f64),
    /// |model − paper| ≤ value·|paper|.
    Relative(f64),
}

/// The one band for numbers the text qualifies with "about", "approximately" or "almost":
/// ±10 % of the value (defined once here and in `validation/README.md`).
pub const ABOUT_BAND: f64 = 0.10;

/// A tolerance: its band, its basis and the derivation of its size from the source.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Tolerance {
    /// Size of the band.
    pub band: ToleranceBand,
    /// Why this size.
    pub basis: ToleranceBasis,
    /// How the size follows from the source (`½ unit of the last digit of "38.67"`), shown in
    /// the row.
    pub derivation: String,
}

impl Tolerance {
    /// Half a unit in the last printed digit of `printed` (`"38.67"` → ±0.005, `"150"` → ±0.5,
    /// `"1.5e-3"` → ±0.5e-4), basis [`ToleranceBasis::PrintedPrecision`].
    ///
    /// ```
    /// use geardyn_validate::{Tolerance, ToleranceBand};
    /// let t = Tolerance::printed("38.67").unwrap();
    /// assert_eq!(t.band, ToleranceBand::Absolute(0.005));
    /// ```
    pub fn printed(printed: &str) -> Result<Self, Error> {
        let half = half_last_digit(printed)?;
        Ok(Tolerance {
            band: ToleranceBand::Absolute(half),
            basis: ToleranceBasis::PrintedPrecision,
            derivation: format!(
                "½ unit of the last printed digit of \"{}\" = {}",
                printed.trim(),
                crate::fmt_sig(half, 3)
            ),
        })
    }

    /// A number the text gives as a round value (`"150 rad/s"` on a grid of `resolution`):
    /// half the resolution.
    pub fn round_number(printed: &str, resolution: f64, unit: &str) -> Self {
        Tolerance {
            band: ToleranceBand::Absolute(0.5 * resolution),
            basis: ToleranceBasis::PrintedPrecision,
            derivation: format!(
                "round number \"{}\" in the text: ½ of its {} {unit} resolution",
                printed.trim(),
                crate::fmt_sig(resolution, 3)
            ),
        }
    }

    /// An absolute band read off a figure: half the smallest distinguishable step of the axis,
    /// `axis` describing its resolution (`"y axis: ticks every 10 µm, 1 mm ≈ 2 µm"`).
    pub fn digitising(abs: f64, axis: &str) -> Self {
        Tolerance {
            band: ToleranceBand::Absolute(abs),
            basis: ToleranceBasis::Digitising,
            derivation: format!("figure reading: {axis}"),
        }
    }

    /// The one band [`ABOUT_BAND`] for numbers the text gives as "about …"/"almost …";
    /// `word` is the word the text uses.
    pub fn about(word: &str) -> Self {
        Tolerance {
            band: ToleranceBand::Relative(ABOUT_BAND),
            basis: ToleranceBasis::ApproximateText,
            derivation: format!(
                "the text says \"{word}\": the one band ±{} % (validation/README.md)",
                crate::fmt_sig(100.0 * ABOUT_BAND, 3)
            ),
        }
    }

    /// A band from the scatter of experimental values in the paper's own table.
    pub fn experimental_scatter(band: ToleranceBand, derivation: &str) -> Self {
        Tolerance {
            band,
            basis: ToleranceBasis::Stated("experimental scatter".to_owned()),
            derivation: derivation.to_owned(),
        }
    }

    /// A relative band for model-against-exact comparisons (numerical error only).
    pub fn numerical(rel: f64) -> Self {
        Tolerance {
            band: ToleranceBand::Relative(rel),
            basis: ToleranceBasis::Numerical,
            derivation: "numerical error of the computation".to_owned(),
        }
    }

    /// Any band with a basis explained in words.
    pub fn stated(band: ToleranceBand, why: &str) -> Self {
        Tolerance {
            band,
            basis: ToleranceBasis::Stated(why.to_owned()),
            derivation: why.to_owned(),
        }
    }

    /// The allowed absolute deviation around `reference`.
    pub fn allowed(&self, reference: f64) -> f64 {
        match self.band {
            ToleranceBand::Absolute(a) => a.abs(),
            ToleranceBand::Relative(r) => r.abs() * reference.abs(),
        }
    }

    /// Human-readable band, e.g. `±0.005` or `±2%`.
    pub fn label(&self) -> String {
        match self.band {
            ToleranceBand::Absolute(a) => format!("±{}", crate::fmt_sig(a, 3)),
            ToleranceBand::Relative(r) => format!("±{}%", crate::fmt_sig(100.0 * r, 3)),
        }
    }
}

/// The reference side of a comparison: the paper's number (or an exact value) and where it is.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Reference {
    /// Value used for the deviation.
    pub value: f64,
    /// The number as printed (keeps the printed precision), or the value formatted.
    pub printed: String,
    /// Where it comes from: `"Table 2, p. 12"`, `"Eq. (4) evaluated"`, ….
    pub source: String,
}

impl Reference {
    /// A reference computed rather than printed (e.g. an exact formula), with its source.
    pub fn computed(value: f64, source: &str) -> Self {
        Reference {
            value,
            printed: crate::fmt6(value),
            source: source.to_owned(),
        }
    }
}

impl From<&PublishedValue> for Reference {
    fn from(p: &PublishedValue) -> Self {
        Reference {
            value: p.value,
            printed: p.printed.clone(),
            source: p.source.clone(),
        }
    }
}

/// One numeric comparison row: quantity, paper value, model value, deviation, tolerance, verdict.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Comparison {
    /// What is compared, e.g. `f_c at ω1 = 160 rad/s`.
    pub quantity: String,
    /// Unit (`rad/s`, `Hz`, `1` for dimensionless).
    pub unit: String,
    /// The paper's (or exact) value.
    pub reference: Reference,
    /// The model's value.
    pub model: f64,
    /// The tolerance (set from the paper's precision before looking at `model`).
    pub tolerance: Tolerance,
    /// Reading ids (`R-LIU-EQ20`, …; headings in `docs/readings/*.md`) explaining a deviation or
    /// the reading chosen.
    pub readings: Vec<String>,
    /// Free remark (Markdown, short).
    pub note: String,
    /// Evidence class of the row.
    pub evidence: Evidence,
    /// Cause of a deviation or of an inconclusive verdict, when no reading id explains it.
    pub cause: String,
    /// Why the model value rests on a point that cannot carry a verdict (non-converged,
    /// unstable, non-periodic, not reproducible); any flag makes the row inconclusive.
    pub flags: Vec<String>,
    /// False when the row is shown beside the judged method but not judged (verdict `shown`).
    pub judged: bool,
    /// The model's uncertainty interval `[lo, hi]` (a threshold located by bisection, with the
    /// spread over undecided readings and definitions); `None` for a point value. With an
    /// interval the verdict compares the interval with the band (validation/README.md).
    pub interval: Option<(f64, f64)>,
    /// The swept values the verdict rests on, exactly as swept; a flag (`at x: …`) must name one
    /// of them (`cargo xtask validate --check`). Empty: the row rests on no swept point.
    pub needs: Vec<f64>,
    /// The paper value is a threshold ([`PublishedValue::threshold`]): a judged reproduction
    /// must carry an [`Comparison::interval`] (`cargo xtask validate --check`).
    pub threshold: bool,
    /// The model value (and interval) does not settle under a solver retune: a statistic of a
    /// non-periodic orbit, whose value moves with every change of the integrator's step
    /// sequence while the verdict rests on the interval. Committed files write it as
    /// [`crate::precision::NOT_PERIODIC`] with the verdict; the value is in `validation/stats/`.
    pub unsettled: bool,
}

impl Comparison {
    /// Compare `model` against `reference` within `tolerance`.
    ///
    /// ```
    /// use geardyn_validate::{Comparison, Reference, Tolerance, Verdict};
    /// let c = Comparison::new("δ", "1", Reference::computed(0.1, "exact"), 0.1004,
    ///     Tolerance::numerical(1e-2));
    /// assert_eq!(c.verdict(), Verdict::Pass);
    /// ```
    pub fn new(
        quantity: &str,
        unit: &str,
        reference: impl Into<Reference>,
        model: f64,
        tolerance: Tolerance,
    ) -> Self {
        Comparison {
            quantity: quantity.to_owned(),
            unit: unit.to_owned(),
            reference: reference.into(),
            model,
            tolerance,
            readings: Vec::new(),
            note: String::new(),
            evidence: Evidence::Reproduction,
            cause: String::new(),
            flags: Vec::new(),
            judged: true,
            interval: None,
            needs: Vec::new(),
            threshold: false,
            unsettled: false,
        }
    }

    /// Compare against a published value; quantity, unit and source come from it, the tolerance
    /// from its printed precision.
    pub fn published(p: &PublishedValue, model: f64) -> Result<Self, Error> {
        let tol = Tolerance::printed(&p.printed)?;
        let mut c = Comparison::new(&p.quantity, &p.unit, p, model, tol);
        c.threshold = p.threshold;
        Ok(c)
    }

    /// Add a reading id.
    pub fn reading(mut self, id: &str) -> Self {
        self.readings.push(id.to_owned());
        self
    }

    /// Set the note.
    pub fn note(mut self, note: &str) -> Self {
        self.note = note.to_owned();
        self
    }

    /// Set the evidence class (default [`Evidence::Reproduction`]).
    pub fn class(mut self, evidence: Evidence) -> Self {
        self.evidence = evidence;
        self
    }

    /// Name the cause of a deviation or an inconclusive verdict.
    pub fn cause(mut self, cause: &str) -> Self {
        self.cause = cause.to_owned();
        self
    }

    /// Mark that the model value rests on a point that cannot carry a verdict (the row becomes
    /// inconclusive; the reason is shown).
    pub fn flagged(mut self, reason: impl Into<String>) -> Self {
        self.flags.push(reason.into());
        self
    }

    /// Add every flag of `reasons`.
    pub fn flagged_all(mut self, reasons: impl IntoIterator<Item = String>) -> Self {
        self.flags.extend(reasons);
        self
    }

    /// Mark the model value as not settling under a solver retune when `unsettled` (see
    /// [`Comparison::unsettled`]).
    pub fn unsettled_if(mut self, unsettled: bool) -> Self {
        self.unsettled = unsettled;
        self
    }

    /// Show the row without judging it (the paper's verdict rule picks another method).
    pub fn shown_only(mut self) -> Self {
        self.judged = false;
        self
    }

    /// The model's interval `[lo, hi]` (the point value stays `model`): pass when the interval
    /// lies inside the band, deviation when it lies wholly outside, inconclusive when it
    /// straddles an edge.
    pub fn within(mut self, lo: f64, hi: f64) -> Self {
        // `f64::min` would drop a NaN bound: keep it, so that the verdict is a deviation
        self.interval = Some(if lo.is_nan() || hi.is_nan() {
            (f64::NAN, f64::NAN)
        } else {
            (lo.min(hi), lo.max(hi))
        });
        self
    }

    /// Name the swept values the verdict rests on (a flag must name one of them).
    pub fn needs(mut self, xs: impl IntoIterator<Item = f64>) -> Self {
        self.needs.extend(xs);
        self
    }

    /// Replace the tolerance.
    pub fn with_tolerance(mut self, tolerance: Tolerance) -> Self {
        self.tolerance = tolerance;
        self
    }

    /// model − paper.
    pub fn deviation_abs(&self) -> f64 {
        self.model - self.reference.value
    }

    /// (model − paper)/|paper| (NaN when the paper value is 0).
    pub fn deviation_rel(&self) -> f64 {
        if self.reference.value == 0.0 {
            f64::NAN
        } else {
            self.deviation_abs() / self.reference.value.abs()
        }
    }

    /// Pass when |model − paper| ≤ allowed (with a 1e-12 relative slack for the decimal
    /// representation of printed bounds); a non-finite model value is a deviation.
    ///
    /// A row that is not judged or cannot fail ([`Evidence::ByConstruction`]) is
    /// [`Verdict::Shown`]; a flagged row (or one whose model value is NaN because no point
    /// qualified and a flag says so) is [`Verdict::Inconclusive`].
    pub fn verdict(&self) -> Verdict {
        if !self.judged || !self.evidence.is_check() {
            return Verdict::Shown;
        }
        if !self.flags.is_empty() {
            return Verdict::Inconclusive;
        }
        let allowed = self.tolerance.allowed(self.reference.value);
        // a band that is not finite bounds nothing: no verdict from it
        if !allowed.is_finite() {
            return Verdict::Inconclusive;
        }
        let slack = 1e-12 * self.reference.value.abs().max(allowed);
        if let Some((lo, hi)) = self.interval {
            if !(lo.is_finite() && hi.is_finite()) {
                return Verdict::Deviation;
            }
            let (a, b) = (
                self.reference.value - allowed - slack,
                self.reference.value + allowed + slack,
            );
            return if lo >= a && hi <= b {
                Verdict::Pass
            } else if hi < a || lo > b {
                Verdict::Deviation
            } else {
                Verdict::Inconclusive
            };
        }
        Verdict::from_bool(self.model.is_finite() && self.deviation_abs().abs() <= allowed + slack)
    }

    /// The model value as shown: `165` or `165 [163.1, 166.9]` with an interval.
    pub fn model_label(&self) -> String {
        match self.interval {
            Some((lo, hi)) => format!(
                "{} [{}, {}]",
                crate::fmt6(self.model),
                crate::fmt6(lo),
                crate::fmt6(hi)
            ),
            None => crate::fmt6(self.model),
        }
    }
}

/// A textual claim of the paper held against the model.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Claim {
    /// The claim, quoted (or closely paraphrased, then say so).
    pub text: String,
    /// Where: `"Sect. 3.3, p. 9"`.
    pub source: String,
    /// What the model shows (numbers!).
    pub evidence: String,
    /// The verdict.
    pub verdict: Verdict,
    /// Reading ids explaining a deviation.
    pub readings: Vec<String>,
    /// Evidence class of the row.
    pub class: Evidence,
    /// Cause of a deviation or of an inconclusive verdict, when no reading id explains it.
    pub cause: String,
    /// Why the evidence rests on points that cannot carry a verdict; a flagged claim must be
    /// inconclusive (`cargo xtask validate --check` fails otherwise).
    pub flags: Vec<String>,
    /// The swept values the verdict rests on, exactly as swept (see [`Comparison::needs`]).
    pub needs: Vec<f64>,
}

impl Claim {
    /// A claim with its quote, source, the model's evidence and the verdict.
    pub fn new(text: &str, source: &str, evidence: impl Into<String>, verdict: Verdict) -> Self {
        Claim {
            text: text.to_owned(),
            source: source.to_owned(),
            evidence: evidence.into(),
            verdict,
            readings: Vec::new(),
            class: Evidence::Reproduction,
            cause: String::new(),
            flags: Vec::new(),
            needs: Vec::new(),
        }
    }

    /// Name the swept values the verdict rests on (a flag must name one of them).
    pub fn needs(mut self, xs: impl IntoIterator<Item = f64>) -> Self {
        self.needs.extend(xs);
        self
    }

    /// A claim from the published data file (text and source transcribed there).
    pub fn published(p: &PublishedClaim, evidence: impl Into<String>, verdict: Verdict) -> Self {
        Claim::new(&p.text, &p.source, evidence, verdict)
    }

    /// Add a reading id.
    pub fn reading(mut self, id: &str) -> Self {
        self.readings.push(id.to_owned());
        self
    }

    /// Set the evidence class (default [`Evidence::Reproduction`]); a
    /// [`Evidence::ByConstruction`] claim is shown, not judged.
    pub fn class(mut self, evidence: Evidence) -> Self {
        if !evidence.is_check() {
            self.verdict = Verdict::Shown;
        }
        self.class = evidence;
        self
    }

    /// Name the cause of a deviation or an inconclusive verdict.
    pub fn cause(mut self, cause: &str) -> Self {
        self.cause = cause.to_owned();
        self
    }

    /// Mark flagged evidence: the verdict becomes [`Verdict::Inconclusive`] and the reasons
    /// are listed.
    pub fn flagged_all(mut self, reasons: impl IntoIterator<Item = String>) -> Self {
        let before = self.flags.len();
        self.flags.extend(reasons);
        if self.flags.len() > before && self.verdict != Verdict::Shown {
            self.verdict = Verdict::Inconclusive;
        }
        self
    }
}

/// Everything a study produces. Build it with the chaining methods.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct StudyOutput {
    /// Numeric comparisons (written to `<id>.csv` and the report).
    pub comparisons: Vec<Comparison>,
    /// Claims (report and snapshot).
    pub claims: Vec<Claim>,
    /// Data tables (each written to `<id>_<table>.csv`).
    pub tables: Vec<Table>,
    /// Figures (each written to `<id>_<figure>.svg` and, as data, `<id>_<figure>.csv`).
    pub figures: Vec<Figure>,
    /// Remarks shown under the study in the report (Markdown).
    pub notes: Vec<String>,
    /// Heat maps (each written to `<id>_<map>.svg` and, as data, `<id>_<map>.csv`; their
    /// curves are drawn in the SVG, their data belong in a table of the study).
    #[serde(skip)]
    pub heatmaps: Vec<Heatmap>,
}

impl StudyOutput {
    /// An empty output.
    pub fn new() -> Self {
        Self::default()
    }

    /// Add a comparison.
    pub fn compare(&mut self, c: Comparison) -> &mut Self {
        self.comparisons.push(c);
        self
    }

    /// Add a claim.
    pub fn claim(&mut self, c: Claim) -> &mut Self {
        self.claims.push(c);
        self
    }

    /// Add a data table.
    pub fn table(&mut self, t: Table) -> &mut Self {
        self.tables.push(t);
        self
    }

    /// Add a figure.
    pub fn figure(&mut self, f: Figure) -> &mut Self {
        self.figures.push(f);
        self
    }

    /// Add a heat map.
    pub fn heatmap(&mut self, m: Heatmap) -> &mut Self {
        self.heatmaps.push(m);
        self
    }

    /// Add a remark.
    pub fn note(&mut self, n: impl Into<String>) -> &mut Self {
        self.notes.push(n.into());
        self
    }

    /// Count of (pass, deviation, inconclusive) over comparisons and claims (rows shown but not
    /// judged are not counted).
    pub fn tally(&self) -> (usize, usize, usize) {
        let mut t = (0, 0, 0);
        let verdicts = self
            .comparisons
            .iter()
            .map(Comparison::verdict)
            .chain(self.claims.iter().map(|c| c.verdict));
        for v in verdicts {
            match v {
                Verdict::Pass => t.0 += 1,
                Verdict::Deviation => t.1 += 1,
                Verdict::Inconclusive => t.2 += 1,
                Verdict::Shown => {}
            }
        }
        t
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn printed_precision() {
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-15 * b.abs();
        assert!(close(half_last_digit("38.67").unwrap(), 0.005));
        assert!(close(half_last_digit("150").unwrap(), 0.5));
        assert!(close(half_last_digit("-0.0125").unwrap(), 0.00005));
        assert!(close(half_last_digit("1.5e-3").unwrap(), 0.5e-4));
        assert!(half_last_digit("abc").is_err());
        assert!(half_last_digit("1.2.3").is_err());
        assert!(half_last_digit("").is_err());
    }

    #[test]
    fn verdicts() {
        let r = Reference::computed(38.67, "t");
        let tol = Tolerance::printed("38.67").unwrap();
        let c = Comparison::new("f", "Hz", r.clone(), 38.675, tol.clone());
        assert_eq!(c.verdict(), Verdict::Pass, "boundary is inclusive");
        let c = Comparison::new("f", "Hz", r.clone(), 38.676, tol.clone());
        assert_eq!(c.verdict(), Verdict::Deviation);
        let c = Comparison::new("f", "Hz", r.clone(), f64::NAN, tol);
        assert_eq!(c.verdict(), Verdict::Deviation);
        // an unbounded or undefined band judges nothing
        for band in [f64::INFINITY, f64::NAN] {
            let wide = Tolerance::stated(ToleranceBand::Absolute(band), "t");
            let c = Comparison::new("f", "Hz", r.clone(), 38.67, wide);
            assert_eq!(c.verdict(), Verdict::Inconclusive, "{band}");
        }
    }

    /// An interval inside the band passes, one outside is a deviation, one across an edge is
    /// inconclusive; a NaN bound is a deviation (no threshold found).
    #[test]
    fn interval_verdicts() {
        let r = Reference::computed(150.0, "text");
        let tol = Tolerance::round_number("150", 10.0, "rad/s");
        let c = |lo: f64, hi: f64| {
            Comparison::new("w", "rad/s", r.clone(), 0.5 * (lo + hi), tol.clone()).within(lo, hi)
        };
        assert_eq!(c(146.0, 154.0).verdict(), Verdict::Pass);
        assert_eq!(c(145.0, 155.0).verdict(), Verdict::Pass, "edges inclusive");
        assert_eq!(c(133.0, 137.0).verdict(), Verdict::Deviation);
        assert_eq!(c(156.0, 160.0).verdict(), Verdict::Deviation);
        assert_eq!(c(143.0, 147.0).verdict(), Verdict::Inconclusive);
        assert_eq!(c(f64::NAN, 147.0).verdict(), Verdict::Deviation);
        assert_eq!(c(146.0, 154.0).model_label(), "150 [146, 154]");
    }
}
