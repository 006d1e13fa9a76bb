//! Figures: series of curves, rendered as SVG with plotters.

use plotters::prelude::*;
use serde::Serialize;

use crate::error::Error;
use crate::table::{Cell, Table};

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Style {
    /// A polyline through the points (non-finite points break the line).
    Line,
    /// A small circle per point (sweeps with jumps, Poincaré sections).
    Markers,
}

/// One curve.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Series {
    /// Legend label, e.g. `B = 0.05`.
    pub label: String,
    /// The points (x, y).
    pub points: Vec<(f64, f64)>,
    /// Line or markers.
    pub style: Style,
}

impl Series {
    /// A line series.
    pub fn line(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Series {
            label: label.into(),
            points,
            style: Style::Line,
        }
    }

    /// A marker series.
    pub fn markers(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Series {
            label: label.into(),
            points,
            style: Style::Markers,
        }
    }
}

/// A 2-D figure: axes with units and a set of series. Written to
/// `validation/<paper>/<study-id>_<name>.svg`, and its data to `<study-id>_<name>.csv`
/// (long format: `series, x, y`).
///
/// ```
/// use geardyn_validate::{Figure, Series};
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
        }
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

    fn data_range(&self, pick: impl Fn(&(f64, f64)) -> f64) -> (f64, f64) {
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
            for (i, s) in self.series.iter().enumerate() {
                let color = Palette99::pick(i).to_rgba();
                match s.style {
                    Style::Line => {
                        // Split at non-finite points.
                        let mut segments: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
                        for p in &s.points {
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
                            let anno = chart
                                .draw_series(LineSeries::new(seg, color.stroke_width(2)))
                                .map_err(|e| err(e.to_string()))?;
                            if first && !s.label.is_empty() {
                                anno.label(s.label.as_str()).legend(move |(x, y)| {
                                    PathElement::new(
                                        vec![(x, y), (x + 20, y)],
                                        color.stroke_width(2),
                                    )
                                });
                            }
                            first = false;
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
