//! Figures: series of curves, rendered as SVG with plotters.
//!
//! Drawing conventions (fit for a paper):
//! * colours from the Okabe–Ito palette ([`OKABE_ITO`]), distinguishable with the common forms
//!   of colour-vision deficiency; a series takes the next colour unless [`Series::colour`] pins
//!   one (the stable and unstable parts of one branch share a colour);
//! * discrete states (rattle state 0/1/2, …) as step plots ([`Style::Step`]): each sample's
//!   value holds up to the midpoint to its neighbours, never a ramp between levels;
//! * continuation branches ([`Figure::branch`]): stable parts solid, unstable parts dashed,
//!   folds marked with a cross;
//! * every axis carries a unit (`name [unit]`; `1` for dimensionless quantities);
//! * legends name what is drawn (model, reading, engine), never a code number.

use plotters::element::DashedPathElement;
use plotters::prelude::*;
use serde::Serialize;

use crate::error::Error;
use crate::table::{Cell, Table};

/// The Okabe–Ito colour-blind-safe palette (Okabe & Ito 2008, *Color Universal Design*), in
/// the order series take it: blue, vermillion, bluish green, reddish purple, orange, sky blue,
/// black, yellow (last: low contrast on white).
pub const OKABE_ITO: [(u8, u8, u8); 8] = [
    (0, 114, 178),
    (213, 94, 0),
    (0, 158, 115),
    (204, 121, 167),
    (230, 159, 0),
    (86, 180, 233),
    (0, 0, 0),
    (240, 228, 66),
];

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[non_exhaustive]
pub enum Style {
    /// A polyline through the points (non-finite points break the line).
    Line,
    /// A small circle per point (sweeps with jumps, Poincaré sections).
    Markers,
    /// A step plot for a discrete state: each value holds from the midpoint with the previous
    /// sample to the midpoint with the next (non-finite points break the line).
    Step,
    /// A dashed polyline (unstable branch parts; non-finite points break the line).
    Dashed,
    /// A cross per point (folds of a continuation branch).
    Folds,
}

/// One curve.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Series {
    /// Legend label, e.g. `B = 0.05`.
    pub label: String,
    /// The points (x, y).
    pub points: Vec<(f64, f64)>,
    /// Line, markers, step, dashed or folds.
    pub style: Style,
    /// Index into [`OKABE_ITO`] (modulo its length); `None` takes the next unpinned colour.
    pub colour: Option<usize>,
    /// Per point: the value does not settle under a solver retune ([`crate::Cell::Unsettled`]:
    /// a sample of a non-periodic orbit, a non-converged iterate, a solution seeded from one).
    /// Such points are drawn only in the uncommitted `validation/stats/` copy of the figure;
    /// the committed figure leaves them out. Empty: every point settles.
    pub unsettled: Vec<bool>,
}

impl Series {
    /// A series of any style.
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64)>, style: Style) -> Self {
        Series {
            label: label.into(),
            points,
            style,
            colour: None,
            unsettled: Vec::new(),
        }
    }

    /// A line series.
    pub fn line(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self::new(label, points, Style::Line)
    }

    /// A marker series.
    pub fn markers(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self::new(label, points, Style::Markers)
    }

    /// A step series, for discrete states (e.g. the rattle state over a speed sweep).
    pub fn step(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self::new(label, points, Style::Step)
    }

    /// A dashed line series.
    pub fn dashed(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self::new(label, points, Style::Dashed)
    }

    /// Pin the colour to `OKABE_ITO[index % 8]` (builder style).
    pub fn colour(mut self, index: usize) -> Self {
        self.colour = Some(index);
        self
    }

    /// Mark the points that do not settle under a solver retune (one flag per point, in order;
    /// missing flags count as settled): see [`Series::unsettled`].
    pub fn unsettled(mut self, flags: impl IntoIterator<Item = bool>) -> Self {
        self.unsettled = flags.into_iter().collect();
        self
    }

    /// Whether point `i` does not settle ([`Series::unsettled`]).
    pub fn is_unsettled(&self, i: usize) -> bool {
        self.unsettled.get(i).copied().unwrap_or(false)
    }
}

/// The polyline of a step plot through `points` (in x order as given): each value holds from
/// the midpoint with the previous sample to the midpoint with the next; the first and last
/// values hold to their own x. Non-finite points are kept as breaks.
pub fn step_path(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(3 * points.len());
    let finite = |p: &(f64, f64)| p.0.is_finite() && p.1.is_finite();
    for (i, p) in points.iter().enumerate() {
        if !finite(p) {
            out.push(*p);
            continue;
        }
        let prev = i
            .checked_sub(1)
            .and_then(|j| points.get(j))
            .filter(|q| finite(q));
        let next = points.get(i + 1).filter(|q| finite(q));
        let left = prev.map_or(p.0, |q| 0.5 * (q.0 + p.0));
        let right = next.map_or(p.0, |q| 0.5 * (p.0 + q.0));
        out.push((left, p.1));
        out.push((right, p.1));
    }
    out
}

/// A 2-D figure: axes with units and a set of series. Written to
/// `validation/<paper>/<study-id>_<name>.svg`, and its data to `<study-id>_<name>.csv`
/// (long format: `series, x, y`).
///
/// ```
/// use geardyn_plot::{Figure, Series};
/// let f = Figure::new("a-vs-omega", "Amplitude vs frequency", ("ω", "1"), ("A", "1"))
///     .with(Series::line("B = 0", vec![(0.0, 1.0), (1.0, 2.0)]));
/// let svg = f.to_svg().unwrap();
/// assert!(svg.starts_with("<svg"));
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Figure {
    /// File-name part (`a-z`, `0-9`, `-`, `_`, `.`).
    pub name: String,
    /// Caption.
    pub title: String,
    /// x label and unit.
    pub x: (String, String),
    /// y label and unit.
    pub y: (String, String),
    /// The curves.
    pub series: Vec<Series>,
    /// Fixed axis ranges (else from the data).
    pub x_range: Option<(f64, f64)>,
    /// Fixed y range (else from the data).
    pub y_range: Option<(f64, f64)>,
    /// The figure draws a record of a non-periodic (chaotic) orbit, not reproducible below its
    /// scatter: its data and SVG go to the uncommitted `validation/stats/` only
    /// ([`Figure::non_periodic_record`]).
    pub non_periodic: bool,
    /// Why the record is not committed, when it is not a non-periodic orbit
    /// ([`Figure::unsettled_record`]).
    pub record_reason: Option<String>,
    /// The ordinates are reproducible to this many significant digits only (the study's own
    /// accuracy check): committed at no more ([`Figure::reproducible_digits`]).
    pub digits: Option<i32>,
    /// The values are reproducible only to `10^-decades` of the largest magnitude (an absolute
    /// noise floor, e.g. the small lines of a spectrum): committed no finer
    /// ([`Figure::reproducible_decades`]).
    pub decades: Option<i32>,
}

impl Figure {
    /// An empty figure; `x`/`y` are `(label, unit)`.
    pub fn new(name: &str, title: &str, x: (&str, &str), y: (&str, &str)) -> Self {
        Figure {
            name: name.to_owned(),
            title: title.to_owned(),
            x: (x.0.to_owned(), x.1.to_owned()),
            y: (y.0.to_owned(), y.1.to_owned()),
            series: Vec::new(),
            x_range: None,
            y_range: None,
            non_periodic: false,
            record_reason: None,
            digits: None,
            decades: None,
        }
    }

    /// Mark the figure as a record that does not settle under a solver retune for the reason
    /// given: its data and SVG go to `validation/stats/` only, with the reason in the snapshot.
    pub fn unsettled_record(mut self, reason: &str) -> Self {
        self.non_periodic = true;
        self.record_reason = Some(reason.to_owned());
        self
    }

    /// Mark the figure (when `non_periodic`) as a record of a non-periodic orbit (a time series, phase portrait or
    /// one-record spectrum at a point whose motion is not periodic): written to
    /// `validation/stats/` only, with one line in the snapshot; a solver retune that reshuffles
    /// the chaotic record then changes no committed byte (issue 28).
    pub fn non_periodic_record(mut self, non_periodic: bool) -> Self {
        self.non_periodic = non_periodic;
        self
    }

    /// Add a series (builder style).
    pub fn with(mut self, s: Series) -> Self {
        self.series.push(s);
        self
    }

    /// Add a series.
    pub fn push(&mut self, s: Series) {
        self.series.push(s);
    }

    /// Add a continuation branch: the segments between two points that are both stable drawn
    /// solid (`"<label>, stable"`), every other segment dashed (`"<label>, unstable"` — a
    /// segment touching a point of unknown stability counts as not stable), the folds as
    /// crosses (`"<label>, folds"`), all in colour `colour`. `points` are `(x, y, stable)` in
    /// arclength order.
    pub fn branch(
        mut self,
        label: &str,
        colour: usize,
        points: &[(f64, f64, Option<bool>)],
        folds: Vec<(f64, f64)>,
    ) -> Self {
        let (mut solid, mut dashed) = (Vec::new(), Vec::new());
        for w in points.windows(2) {
            let (a, b) = (w[0], w[1]);
            let target = if a.2 == Some(true) && b.2 == Some(true) {
                &mut solid
            } else {
                &mut dashed
            };
            // continue the polyline if it ends at `a`, else start a new piece
            if target.last() != Some(&(a.0, a.1)) {
                if !target.is_empty() {
                    target.push((f64::NAN, f64::NAN));
                }
                target.push((a.0, a.1));
            }
            target.push((b.0, b.1));
        }
        if points.len() == 1 {
            let p = points[0];
            let target = if p.2 == Some(true) {
                &mut solid
            } else {
                &mut dashed
            };
            target.push((p.0, p.1));
        }
        if !solid.is_empty() {
            self.push(Series::line(format!("{label}, stable"), solid).colour(colour));
        }
        if !dashed.is_empty() {
            self.push(Series::dashed(format!("{label}, unstable"), dashed).colour(colour));
        }
        if !folds.is_empty() {
            self.push(Series::new(format!("{label}, folds"), folds, Style::Folds).colour(colour));
        }
        self
    }

    /// Commit no finer than `10^-decades` of the largest magnitude (at least 1 decade): the
    /// study's own check shows an absolute noise floor there. The stats copy keeps every digit.
    pub fn reproducible_decades(mut self, decades: i32) -> Self {
        self.decades = Some(decades.max(1));
        self
    }

    /// Commit the ordinates at no more than `digits` significant digits (at least 1; the
    /// default is 3, `FIGURE_DIGITS` of the validation harness): the study's own accuracy check
    /// reproduces them only to that precision. The stats copy keeps every digit.
    pub fn reproducible_digits(mut self, digits: i32) -> Self {
        self.digits = Some(digits.max(1));
        self
    }

    /// Fix the axis ranges.
    pub fn ranges(mut self, x: Option<(f64, f64)>, y: Option<(f64, f64)>) -> Self {
        self.x_range = x;
        self.y_range = y;
        self
    }

    /// The figure's data as a long-format table (`series`, x, y).
    pub fn to_table(&self) -> Table {
        let mut t = Table::new(
            &self.name,
            &[
                ("series", ""),
                (self.x.0.as_str(), self.x.1.as_str()),
                (self.y.0.as_str(), self.y.1.as_str()),
            ],
        );
        for s in &self.series {
            for &(x, y) in &s.points {
                t.rows.push(vec![
                    Cell::Text(s.label.clone()),
                    Cell::Num(x),
                    Cell::Num(y),
                ]);
            }
        }
        t
    }

    /// The drawn range of one coordinate (`pick`) over every finite point, with a 3 % margin
    /// (5 % of the value, or ±1 at zero, when all are equal); `(0, 1)` without finite points.
    pub fn data_range(&self, pick: impl Fn(&(f64, f64)) -> f64) -> (f64, f64) {
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for p in self.series.iter().flat_map(|s| s.points.iter()) {
            let v = pick(p);
            if p.0.is_finite() && p.1.is_finite() {
                lo = lo.min(v);
                hi = hi.max(v);
            }
        }
        if !lo.is_finite() || !hi.is_finite() {
            return (0.0, 1.0);
        }
        if hi - lo <= 1e-300 + 1e-12 * hi.abs().max(lo.abs()) {
            let pad = if lo == 0.0 { 1.0 } else { 0.05 * lo.abs() };
            return (lo - pad, hi + pad);
        }
        let pad = 0.03 * (hi - lo);
        (lo - pad, hi + pad)
    }

    /// Render to an SVG string (800×560 px; deterministic).
    pub fn to_svg(&self) -> Result<String, Error> {
        let err = |e: String| Error::Plot {
            figure: self.name.clone(),
            reason: e,
        };
        let (x0, x1) = self.x_range.unwrap_or_else(|| self.data_range(|p| p.0));
        let (y0, y1) = self.y_range.unwrap_or_else(|| self.data_range(|p| p.1));
        // Non-finite, reversed or overflowing ranges would make the axis key points loop.
        for (axis, a, b) in [("x", x0, x1), ("y", y0, y1)] {
            if !(a.is_finite() && b.is_finite() && a < b && (b - a).is_finite()) {
                return Err(err(format!(
                    "{axis} range [{a}, {b}] must be finite, increasing and of finite width"
                )));
            }
        }
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, (800, 560)).into_drawing_area();
            root.fill(&WHITE).map_err(|e| err(e.to_string()))?;
            let mut chart = ChartBuilder::on(&root)
                .caption(&self.title, ("sans-serif", 22))
                .margin(12)
                .x_label_area_size(45)
                .y_label_area_size(70)
                .build_cartesian_2d(x0..x1, y0..y1)
                .map_err(|e| err(e.to_string()))?;
            let label = |(n, u): &(String, String)| {
                if u.is_empty() {
                    n.clone()
                } else {
                    format!("{n} [{u}]")
                }
            };
            chart
                .configure_mesh()
                .x_desc(label(&self.x))
                .y_desc(label(&self.y))
                .label_style(("sans-serif", 15))
                .axis_desc_style(("sans-serif", 17))
                .light_line_style(WHITE.mix(0.0))
                .draw()
                .map_err(|e| err(e.to_string()))?;
            let inside = |p: &(f64, f64)| {
                p.0.is_finite()
                    && p.1.is_finite()
                    && p.0 >= x0
                    && p.0 <= x1
                    && p.1 >= y0
                    && p.1 <= y1
            };
            let mut next_colour = 0;
            for s in &self.series {
                let index = s.colour.unwrap_or_else(|| {
                    next_colour += 1;
                    next_colour - 1
                });
                let (r, g, b) = OKABE_ITO[index % OKABE_ITO.len()];
                let color = RGBColor(r, g, b).to_rgba();
                match s.style {
                    Style::Line | Style::Step | Style::Dashed => {
                        let path = if s.style == Style::Step {
                            step_path(&s.points)
                        } else {
                            s.points.clone()
                        };
                        let dashed = s.style == Style::Dashed;
                        // Split at non-finite points.
                        let mut segments: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
                        for p in &path {
                            if p.0.is_finite() && p.1.is_finite() {
                                if let Some(seg) = segments.last_mut() {
                                    seg.push((p.0.clamp(x0, x1), p.1.clamp(y0, y1)));
                                }
                            } else {
                                segments.push(Vec::new());
                            }
                        }
                        let mut first = true;
                        for seg in segments.into_iter().filter(|s| !s.is_empty()) {
                            let anno = if dashed {
                                chart.draw_series(DashedLineSeries::new(
                                    seg,
                                    8,
                                    5,
                                    color.stroke_width(2),
                                ))
                            } else {
                                chart.draw_series(LineSeries::new(seg, color.stroke_width(2)))
                            }
                            .map_err(|e| err(e.to_string()))?;
                            if first && !s.label.is_empty() {
                                if dashed {
                                    anno.label(s.label.as_str()).legend(move |(x, y)| {
                                        DashedPathElement::new(
                                            vec![(x, y), (x + 20, y)],
                                            6,
                                            4,
                                            color.stroke_width(2),
                                        )
                                    });
                                } else {
                                    anno.label(s.label.as_str()).legend(move |(x, y)| {
                                        PathElement::new(
                                            vec![(x, y), (x + 20, y)],
                                            color.stroke_width(2),
                                        )
                                    });
                                }
                            }
                            first = false;
                        }
                    }
                    Style::Folds => {
                        let pts: Vec<(f64, f64)> =
                            s.points.iter().copied().filter(inside).collect();
                        let anno = chart
                            .draw_series(
                                pts.into_iter()
                                    .map(|p| Cross::new(p, 6, color.stroke_width(2))),
                            )
                            .map_err(|e| err(e.to_string()))?;
                        if !s.label.is_empty() {
                            anno.label(s.label.as_str()).legend(move |(x, y)| {
                                Cross::new((x + 10, y), 5, color.stroke_width(2))
                            });
                        }
                    }
                    Style::Markers => {
                        let pts: Vec<(f64, f64)> =
                            s.points.iter().copied().filter(inside).collect();
                        let anno = chart
                            .draw_series(pts.into_iter().map(|p| Circle::new(p, 2, color.filled())))
                            .map_err(|e| err(e.to_string()))?;
                        if !s.label.is_empty() {
                            anno.label(s.label.as_str())
                                .legend(move |(x, y)| Circle::new((x + 10, y), 3, color.filled()));
                        }
                    }
                }
            }
            if self.series.iter().any(|s| !s.label.is_empty()) {
                chart
                    .configure_series_labels()
                    .label_font(("sans-serif", 15))
                    .background_style(WHITE.mix(0.85))
                    .border_style(BLACK)
                    .draw()
                    .map_err(|e| err(e.to_string()))?;
            }
            root.present().map_err(|e| err(e.to_string()))?;
        }
        Ok(svg)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn step_path_holds_values_to_the_midpoints() {
        let p = step_path(&[(0.0, 0.0), (1.0, 2.0), (f64::NAN, f64::NAN), (3.0, 1.0)]);
        assert_eq!(&p[..4], &[(0.0, 0.0), (0.5, 0.0), (0.5, 2.0), (1.0, 2.0)]);
        assert!(p[4].0.is_nan());
        assert_eq!(&p[5..], &[(3.0, 1.0), (3.0, 1.0)]);
        // never a ramp: every vertical jump is at one x
        let q = step_path(&[(0.0, 0.0), (1.0, 1.0), (2.0, 2.0)]);
        // exact: the path only copies input coordinates and their midpoints
        #[allow(clippy::float_cmp)]
        let no_ramp = q.windows(2).all(|w| w[0].0 == w[1].0 || w[0].1 == w[1].1);
        assert!(no_ramp);
    }

    #[test]
    fn branch_splits_stable_and_unstable_and_marks_folds() {
        let pts = [
            (0.0, 0.0, Some(true)),
            (1.0, 1.0, Some(true)),
            (2.0, 2.0, Some(false)),
            (1.5, 3.0, Some(false)),
            (2.5, 4.0, Some(true)),
            (3.0, 5.0, Some(true)),
        ];
        let f = Figure::new("b", "t", ("x", "1"), ("y", "1")).branch(
            "model",
            2,
            &pts,
            vec![(2.1, 2.5)],
        );
        let styles: Vec<Style> = f.series.iter().map(|s| s.style).collect();
        assert_eq!(styles, [Style::Line, Style::Dashed, Style::Folds]);
        assert!(f.series.iter().all(|s| s.colour == Some(2)));
        assert_eq!(f.series[0].label, "model, stable");
        // stable: (0,0)-(1,1), break, (2.5,4)-(3,5); unstable: (1,1)-(2,2)-(1.5,3)-(2.5,4)
        assert_eq!(f.series[0].points.len(), 5);
        assert!(f.series[0].points[2].0.is_nan());
        assert_eq!(
            f.series[1].points,
            vec![(1.0, 1.0), (2.0, 2.0), (1.5, 3.0), (2.5, 4.0)]
        );
        let svg = f.to_svg().unwrap();
        assert!(svg.contains("stroke-dasharray") || svg.matches("<line").count() > 0);
        assert_eq!(svg, f.to_svg().unwrap(), "deterministic");
    }

    #[test]
    fn palette_is_okabe_ito() {
        let f = Figure::new("p", "t", ("x", "1"), ("y", "1"))
            .with(Series::line("a", vec![(0.0, 0.0), (1.0, 1.0)]));
        let svg = f.to_svg().unwrap();
        assert!(svg.contains("#0072B2"), "first series in Okabe–Ito blue");
    }
}
