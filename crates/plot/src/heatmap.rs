//! Heat maps of a quantity over a two-parameter grid: rattle-state maps over ω1 × T2, DF over
//! ω* × D, …, rendered to deterministic SVG.
//!
//! Each grid point is drawn as a cell reaching half-way to its neighbours, so non-uniform grids
//! are drawn faithfully. Two colour scales:
//!
//! * [`HeatScale::Continuous`] — a sequential scale (the viridis anchors, readable in grey and by
//!   the common colour-vision deficiencies) with a colour bar;
//! * [`HeatScale::Categorical`] — one colour per state from the Okabe–Ito palette, with a legend
//!   naming each state (e.g. no rattle / unilateral / bilateral).
//!
//! Failed points (NaN) are drawn in light grey and counted in the legend.
//!
//! Curves can be drawn over the cells ([`Heatmap::with_curve`], [`Curve`]): boundaries located
//! by continuation over a brute-force map (solid, dashed, or crosses at isolated points; in
//! black, dark grey or white so that they read over every state colour), named in the legend.
//!
//! Up to [`RASTER_CELLS`] cells each cell is an SVG rectangle. Above it the cells are one
//! embedded raster image (an indexed PNG, base64, at the plot area's pixel size: each pixel takes
//! the colour of the cell under its centre) while the axes, labels, colour bar and legend stay
//! vector: a 500 × 400 map is about 0.4 MB instead of 17 MB. The data are in the CSV either way.

use plotters::prelude::*;

use crate::error::Error;
use crate::format::fmt6;
use crate::table::Table;

/// Okabe–Ito colours (without black), in the order states are coloured.
const OKABE_ITO: [(u8, u8, u8); 7] = [
    (0x00, 0x72, 0xB2), // blue
    (0xE6, 0x9F, 0x00), // orange
    (0xD5, 0x5E, 0x00), // vermillion
    (0x00, 0x9E, 0x73), // bluish green
    (0xCC, 0x79, 0xA7), // reddish purple
    (0x56, 0xB4, 0xE9), // sky blue
    (0xF0, 0xE4, 0x42), // yellow
];

/// Anchors of the viridis scale at 0, 0.25, 0.5, 0.75, 1.
const VIRIDIS: [(u8, u8, u8); 5] = [
    (0x44, 0x01, 0x54),
    (0x3b, 0x52, 0x8b),
    (0x21, 0x91, 0x8c),
    (0x5e, 0xc9, 0x62),
    (0xfd, 0xe7, 0x25),
];

const FAILED: RGBColor = RGBColor(0xd9, 0xd9, 0xd9);

/// Cells above which a heat map's cells are drawn as one embedded raster image instead of one
/// SVG rectangle each (20 000 rectangles are about 1.7 MB of SVG; every map up to it renders as
/// before, byte for byte).
pub const RASTER_CELLS: usize = 20_000;

/// Levels of the continuous scale in a raster (the palette of an indexed PNG holds 256 colours:
/// these, the failed grey and spares).
const RASTER_LEVELS: usize = 254;

/// Colours of the curves over a map ([`Curve::colour`]): black, dark grey, white — none of them
/// a state colour, so a curve reads over every cell.
pub const CURVE_COLOURS: [(u8, u8, u8); 3] = [(0, 0, 0), (0x55, 0x55, 0x55), (0xff, 0xff, 0xff)];

/// How a curve over a map is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum CurveStyle {
    /// A solid polyline (non-finite points break it).
    Solid,
    /// A dashed polyline (non-finite points break it).
    Dashed,
    /// A cross at each point (isolated special points: folds, codim-2 points).
    Crosses,
}

/// A curve drawn over a heat map's cells, in data coordinates.
#[derive(Debug, Clone, PartialEq)]
pub struct Curve {
    /// Legend label (empty: not in the legend).
    pub label: String,
    /// The points `(x, y)`; a non-finite point breaks a polyline into pieces.
    pub points: Vec<(f64, f64)>,
    /// Solid, dashed or crosses.
    pub style: CurveStyle,
    /// Index into [`CURVE_COLOURS`] (modulo its length).
    pub colour: usize,
}

/// How values map to colours.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum HeatScale {
    /// A sequential colour scale from the smallest to the largest finite value, with a colour bar.
    Continuous,
    /// Discrete states: each `(value, label)` gets its own colour; a value not listed is an error.
    Categorical(Vec<(f64, String)>),
}

/// A quantity `z(x, y)` on a rectangular grid.
#[derive(Debug, Clone, PartialEq)]
pub struct Heatmap {
    /// File-name stem of the SVG (`a-z 0-9 - _ .`).
    pub name: String,
    /// Title drawn above the map.
    pub title: String,
    /// x axis: name and unit.
    pub x: (String, String),
    /// y axis: name and unit.
    pub y: (String, String),
    /// The mapped quantity: name and unit.
    pub z: (String, String),
    xs: Vec<f64>,
    ys: Vec<f64>,
    values: Vec<f64>,
    scale: HeatScale,
    curves: Vec<Curve>,
}

fn axis_label((n, u): &(String, String)) -> String {
    if u.is_empty() || u == "1" {
        n.clone()
    } else {
        format!("{n} [{u}]")
    }
}

fn strictly_monotone(v: &[f64]) -> bool {
    v.windows(2).all(|w| w[1] > w[0]) || v.windows(2).all(|w| w[1] < w[0])
}

impl Heatmap {
    /// A map of `values` (row-major: `values[j * xs.len() + i] = z(xs[i], ys[j])`).
    ///
    /// Errors: an empty or non-finite axis, an axis that is not strictly monotone, a value count
    /// that is not `xs.len() · ys.len()`, an infinite value, or (categorical) a finite value that
    /// is not one of the listed states.
    pub fn new(
        name: &str,
        title: &str,
        axes: [(&str, &str); 3],
        xs: Vec<f64>,
        ys: Vec<f64>,
        values: Vec<f64>,
        scale: HeatScale,
    ) -> Result<Self, Error> {
        crate::error::check_name(name)?;
        let bad = |reason: String| Error::Plot {
            figure: name.to_owned(),
            reason,
        };
        for (axis, v) in [("x", &xs), ("y", &ys)] {
            if v.is_empty() {
                return Err(bad(format!("{axis} axis has no values")));
            }
            if let Some(x) = v.iter().find(|x| !x.is_finite()) {
                return Err(bad(format!("{axis} axis value {x} is not finite")));
            }
            if !strictly_monotone(v) {
                return Err(bad(format!("{axis} axis values must be strictly monotone")));
            }
        }
        let n = xs.len().saturating_mul(ys.len());
        if values.len() != n {
            return Err(bad(format!(
                "{} values for a {}×{} grid",
                values.len(),
                xs.len(),
                ys.len()
            )));
        }
        if let Some(z) = values.iter().find(|z| z.is_infinite()) {
            return Err(bad(format!("value {z} is infinite")));
        }
        if let HeatScale::Categorical(states) = &scale {
            if states.is_empty() || states.len() > OKABE_ITO.len() {
                return Err(bad(format!(
                    "a categorical map needs 1 to {} states, got {}",
                    OKABE_ITO.len(),
                    states.len()
                )));
            }
            if let Some(z) = values
                .iter()
                .find(|z| z.is_finite() && !states.iter().any(|(s, _)| s.to_bits() == z.to_bits()))
            {
                return Err(bad(format!("value {z} is not one of the listed states")));
            }
        }
        let [x, y, z] = axes.map(|(a, b)| (a.to_owned(), b.to_owned()));
        Ok(Self {
            name: name.to_owned(),
            title: title.to_owned(),
            x,
            y,
            z,
            xs,
            ys,
            values,
            scale,
            curves: Vec::new(),
        })
    }

    /// Draw `curve` over the cells (builder style). Points outside the grid's area are clipped
    /// to it; a map without curves renders exactly as before.
    ///
    /// Errors: an infinite coordinate (NaN is a break, infinity is a mistake).
    pub fn with_curve(mut self, curve: Curve) -> Result<Self, Error> {
        if let Some(p) = curve
            .points
            .iter()
            .find(|p| p.0.is_infinite() || p.1.is_infinite())
        {
            return Err(Error::Plot {
                figure: self.name.clone(),
                reason: format!("curve '{}' has an infinite point {p:?}", curve.label),
            });
        }
        self.curves.push(curve);
        Ok(self)
    }

    /// The curves drawn over the cells.
    pub fn curves(&self) -> &[Curve] {
        &self.curves
    }

    /// The grid: `(xs, ys, values)` with `values[j * xs.len() + i] = z(xs[i], ys[j])`.
    pub fn grid(&self) -> (&[f64], &[f64], &[f64]) {
        (&self.xs, &self.ys, &self.values)
    }

    /// The data in long format (`x, y, z`), for the CSV written beside the SVG.
    pub fn to_table(&self) -> Table {
        let cols = [
            (self.x.0.as_str(), self.x.1.as_str()),
            (self.y.0.as_str(), self.y.1.as_str()),
            (self.z.0.as_str(), self.z.1.as_str()),
        ];
        let mut t = Table::new(&self.name, &cols);
        for (j, &y) in self.ys.iter().enumerate() {
            for (i, &x) in self.xs.iter().enumerate() {
                // three cells for three columns: cannot fail
                let _ = t.push_nums(&[x, y, self.values[j * self.xs.len() + i]]);
            }
        }
        t
    }

    /// Cell edges: half-way between neighbours, the outer cells as wide as their inner halves.
    fn edges(v: &[f64]) -> Vec<f64> {
        if v.len() == 1 {
            let w = if v[0] == 0.0 { 0.5 } else { 0.05 * v[0].abs() };
            return vec![v[0] - w, v[0] + w];
        }
        let mut e = Vec::with_capacity(v.len() + 1);
        e.push(v[0] - 0.5 * (v[1] - v[0]));
        for w in v.windows(2) {
            e.push(0.5 * (w[0] + w[1]));
        }
        let n = v.len();
        e.push(v[n - 1] + 0.5 * (v[n - 1] - v[n - 2]));
        e
    }

    fn finite_range(&self) -> (f64, f64) {
        let (lo, hi) = self
            .values
            .iter()
            .filter(|z| z.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &z| {
                (a.min(z), b.max(z))
            });
        if !lo.is_finite() {
            (0.0, 1.0)
        } else if hi - lo <= 1e-12 * hi.abs().max(lo.abs()).max(1e-300) {
            (lo - 0.5, hi + 0.5)
        } else {
            (lo, hi)
        }
    }

    fn colour(&self, z: f64, range: (f64, f64)) -> RGBColor {
        if !z.is_finite() {
            return FAILED;
        }
        match &self.scale {
            HeatScale::Continuous => viridis((z - range.0) / (range.1 - range.0)),
            HeatScale::Categorical(states) => {
                let k = states
                    .iter()
                    .position(|(s, _)| s.to_bits() == z.to_bits())
                    .unwrap_or(0);
                let (r, g, b) = OKABE_ITO[k % OKABE_ITO.len()];
                RGBColor(r, g, b)
            }
        }
    }

    /// Render to an SVG string (860×560 px; deterministic).
    pub fn to_svg(&self) -> Result<String, Error> {
        let err = |e: String| Error::Plot {
            figure: self.name.clone(),
            reason: e,
        };
        let ex = Self::edges(&self.xs);
        let ey = Self::edges(&self.ys);
        let (x0, x1) = (ex[0].min(ex[ex.len() - 1]), ex[0].max(ex[ex.len() - 1]));
        let (y0, y1) = (ey[0].min(ey[ey.len() - 1]), ey[0].max(ey[ey.len() - 1]));
        if ![x0, x1, y0, y1].iter().all(|v| v.is_finite()) || x1 <= x0 || y1 <= y0 {
            return Err(err("the grid spans no finite area".to_owned()));
        }
        let range = self.finite_range();
        let failed = self.values.iter().filter(|z| z.is_nan()).count();
        let mut svg = String::new();
        // above RASTER_CELLS: the plot area's pixel ranges and data bounds of the raster
        let mut raster_at = None;
        {
            let root = SVGBackend::with_string(&mut svg, (860, 560)).into_drawing_area();
            root.fill(&WHITE).map_err(|e| err(e.to_string()))?;
            let (left, right) = root.split_horizontally(690);
            let mut chart = ChartBuilder::on(&left)
                .caption(&self.title, ("sans-serif", 20))
                .margin(12)
                .x_label_area_size(45)
                .y_label_area_size(70)
                .build_cartesian_2d(x0..x1, y0..y1)
                .map_err(|e| err(e.to_string()))?;
            chart
                .configure_mesh()
                .disable_mesh()
                .x_desc(axis_label(&self.x))
                .y_desc(axis_label(&self.y))
                .label_style(("sans-serif", 15))
                .axis_desc_style(("sans-serif", 17))
                .draw()
                .map_err(|e| err(e.to_string()))?;
            let nx = self.xs.len();
            if self.values.len() > RASTER_CELLS {
                let (px, py) = chart.plotting_area().get_pixel_range();
                raster_at = Some((px, py, [x0, x1, y0, y1]));
            } else {
                let cells = (0..self.ys.len()).flat_map(|j| {
                    let (ex, ey) = (&ex, &ey);
                    (0..nx).map(move |i| (i, j, [(ex[i], ey[j]), (ex[i + 1], ey[j + 1])]))
                });
                chart
                    .draw_series(cells.map(|(i, j, r)| {
                        Rectangle::new(r, self.colour(self.values[j * nx + i], range).filled())
                    }))
                    .map_err(|e| err(e.to_string()))?;
            }

            self.draw_curves(&mut chart, [x0, x1, y0, y1])
                .map_err(err)?;
            match &self.scale {
                HeatScale::Continuous => {
                    let mut bar = ChartBuilder::on(&right)
                        .margin_top(48)
                        .margin_bottom(57)
                        .margin_right(10)
                        .y_label_area_size(90)
                        .caption(axis_label(&self.z), ("sans-serif", 15))
                        .build_cartesian_2d(0.0..1.0, range.0..range.1)
                        .map_err(|e| err(e.to_string()))?;
                    bar.configure_mesh()
                        .disable_mesh()
                        .disable_x_axis()
                        .y_label_formatter(&|v| fmt6(*v))
                        .label_style(("sans-serif", 13))
                        .draw()
                        .map_err(|e| err(e.to_string()))?;
                    let n = 96;
                    let h = (range.1 - range.0) / n as f64;
                    bar.draw_series((0..n).map(|k| {
                        let a = range.0 + k as f64 * h;
                        Rectangle::new(
                            [(0.0, a), (1.0, a + h)],
                            viridis((k as f64 + 0.5) / n as f64).filled(),
                        )
                    }))
                    .map_err(|e| err(e.to_string()))?;
                }
                HeatScale::Categorical(states) => {
                    right
                        .draw_text(
                            &axis_label(&self.z),
                            &("sans-serif", 15).into_text_style(&right),
                            (8, 48),
                        )
                        .map_err(|e| err(e.to_string()))?;
                    for (k, (_, label)) in states.iter().enumerate() {
                        let y = 78 + 26 * k as i32;
                        let (r, g, b) = OKABE_ITO[k];
                        right
                            .draw(&Rectangle::new(
                                [(8, y), (26, y + 18)],
                                RGBColor(r, g, b).filled(),
                            ))
                            .map_err(|e| err(e.to_string()))?;
                        right
                            .draw_text(
                                label,
                                &("sans-serif", 14).into_text_style(&right),
                                (32, y + 2),
                            )
                            .map_err(|e| err(e.to_string()))?;
                    }
                }
            }
            // the curves' legend under the states' (categorical) or under the colour bar's
            // caption area (continuous: at the bottom, above the failed count)
            let first = match &self.scale {
                HeatScale::Categorical(states) => 78 + 26 * states.len() as i32 + 14,
                HeatScale::Continuous => 500 - 26 * self.curves.len() as i32,
            };
            for (k, c) in self
                .curves
                .iter()
                .filter(|c| !c.label.is_empty())
                .enumerate()
            {
                let y = first + 26 * k as i32;
                let (r, g, b) = CURVE_COLOURS[c.colour % CURVE_COLOURS.len()];
                let colour = RGBColor(r, g, b);
                // a white curve's key on a grey swatch
                right
                    .draw(&Rectangle::new([(6, y - 2), (28, y + 20)], FAILED.filled()))
                    .map_err(|e| err(e.to_string()))?;
                match c.style {
                    CurveStyle::Solid => right.draw(&PathElement::new(
                        vec![(8, y + 9), (26, y + 9)],
                        colour.stroke_width(2),
                    )),
                    CurveStyle::Dashed => right
                        .draw(&PathElement::new(
                            vec![(8, y + 9), (14, y + 9)],
                            colour.stroke_width(2),
                        ))
                        .and_then(|()| {
                            right.draw(&PathElement::new(
                                vec![(20, y + 9), (26, y + 9)],
                                colour.stroke_width(2),
                            ))
                        }),
                    CurveStyle::Crosses => {
                        right.draw(&Cross::new((17, y + 9), 5, colour.stroke_width(2)))
                    }
                }
                .map_err(|e| err(e.to_string()))?;
                right
                    .draw_text(
                        &c.label,
                        &("sans-serif", 13).into_text_style(&right),
                        (32, y + 2),
                    )
                    .map_err(|e| err(e.to_string()))?;
            }
            if failed > 0 {
                let y = 500;
                right
                    .draw(&Rectangle::new([(8, y), (26, y + 18)], FAILED.filled()))
                    .map_err(|e| err(e.to_string()))?;
                right
                    .draw_text(
                        &format!("failed ({failed})"),
                        &("sans-serif", 14).into_text_style(&right),
                        (32, y + 2),
                    )
                    .map_err(|e| err(e.to_string()))?;
            }
            root.present().map_err(|e| err(e.to_string()))?;
        }
        if let Some((px, py, bounds)) = raster_at {
            let image = self
                .raster_image(px, py, bounds, &ex, &ey, range)
                .ok_or_else(|| err("the raster of the cells could not be encoded".to_owned()))?;
            // right after the background rectangle: below the axes, labels and legend
            let at = svg
                .find("<rect")
                .and_then(|r| svg[r..].find("/>").map(|e| r + e + 2))
                .unwrap_or(0);
            svg.insert_str(at, &format!("\n{image}"));
        }
        Ok(svg)
    }

    /// Draw the curves over the cells of `chart` (data bounds `[x0, x1, y0, y1]`: polylines
    /// clamped to them, crosses outside them left out).
    fn draw_curves<DB: DrawingBackend>(
        &self,
        chart: &mut ChartContext<
            '_,
            DB,
            Cartesian2d<
                plotters::coord::types::RangedCoordf64,
                plotters::coord::types::RangedCoordf64,
            >,
        >,
        [x0, x1, y0, y1]: [f64; 4],
    ) -> Result<(), String> {
        for c in &self.curves {
            let (r, g, b) = CURVE_COLOURS[c.colour % CURVE_COLOURS.len()];
            let colour = RGBColor(r, g, b);
            match c.style {
                CurveStyle::Solid | CurveStyle::Dashed => {
                    let mut segments: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
                    for p in &c.points {
                        if p.0.is_finite() && p.1.is_finite() {
                            if let Some(seg) = segments.last_mut() {
                                seg.push((p.0.clamp(x0, x1), p.1.clamp(y0, y1)));
                            }
                        } else {
                            segments.push(Vec::new());
                        }
                    }
                    for seg in segments.into_iter().filter(|s| !s.is_empty()) {
                        if c.style == CurveStyle::Dashed {
                            chart
                                .draw_series(DashedLineSeries::new(
                                    seg,
                                    8,
                                    5,
                                    colour.stroke_width(2),
                                ))
                                .map_err(|e| e.to_string())?;
                        } else {
                            chart
                                .draw_series(LineSeries::new(seg, colour.stroke_width(2)))
                                .map_err(|e| e.to_string())?;
                        }
                    }
                }
                CurveStyle::Crosses => {
                    let inside = |p: &&(f64, f64)| p.0 >= x0 && p.0 <= x1 && p.1 >= y0 && p.1 <= y1;
                    chart
                        .draw_series(
                            c.points
                                .iter()
                                .filter(inside)
                                .map(|&p| Cross::new(p, 6, colour.stroke_width(2))),
                        )
                        .map_err(|e| e.to_string())?;
                }
            }
        }
        Ok(())
    }

    /// The SVG `<image>` of the cells over the plot area `px × py` (pixels) spanning the data
    /// bounds `[x0, x1, y0, y1]`: each pixel the colour of the cell under its centre, found on
    /// the cell edges `ex`, `ey` (ascending or descending).
    fn raster_image(
        &self,
        px: std::ops::Range<i32>,
        py: std::ops::Range<i32>,
        [x0, x1, y0, y1]: [f64; 4],
        ex: &[f64],
        ey: &[f64],
        range: (f64, f64),
    ) -> Option<String> {
        let (w, h) = (
            usize::try_from(px.end - px.start).ok()?,
            usize::try_from(py.end - py.start).ok()?,
        );
        // the palette: the categorical colours, or the continuous scale in RASTER_LEVELS levels;
        // then the failed grey
        let mut palette: Vec<(u8, u8, u8)> = match &self.scale {
            HeatScale::Categorical(states) => OKABE_ITO[..states.len()].to_vec(),
            HeatScale::Continuous => (0..RASTER_LEVELS)
                .map(|k| {
                    let c = viridis(k as f64 / (RASTER_LEVELS - 1) as f64);
                    (c.0, c.1, c.2)
                })
                .collect(),
        };
        let failed = palette.len() as u8;
        palette.push((FAILED.0, FAILED.1, FAILED.2));
        let index = |z: f64| -> u8 {
            if !z.is_finite() {
                return failed;
            }
            match &self.scale {
                HeatScale::Categorical(states) => states
                    .iter()
                    .position(|(s, _)| s.to_bits() == z.to_bits())
                    .map_or(failed, |k| k as u8),
                HeatScale::Continuous => {
                    let t = ((z - range.0) / (range.1 - range.0)).clamp(0.0, 1.0);
                    (t * (RASTER_LEVELS - 1) as f64).round() as u8
                }
            }
        };
        // the cell holding a coordinate: edges are monotone, cells between consecutive edges
        let cell = |e: &[f64], v: f64| -> usize {
            let n = e.len() - 1;
            let k = if e[n] >= e[0] {
                e.partition_point(|&a| a <= v)
            } else {
                e.partition_point(|&a| a >= v)
            };
            k.clamp(1, n) - 1
        };
        let cols: Vec<usize> = (0..w)
            .map(|i| cell(ex, x0 + (i as f64 + 0.5) / w as f64 * (x1 - x0)))
            .collect();
        let nx = self.xs.len();
        let mut pixels = Vec::with_capacity(w * h);
        for j in 0..h {
            // pixel rows run downwards, y upwards
            let row = cell(ey, y1 - (j as f64 + 0.5) / h as f64 * (y1 - y0));
            pixels.extend(cols.iter().map(|&c| index(self.values[row * nx + c])));
        }
        let png = crate::raster::png_indexed(w, h, &pixels, &palette)?;
        Some(format!(
            "<image x=\"{}\" y=\"{}\" width=\"{w}\" height=\"{h}\" \
             preserveAspectRatio=\"none\" style=\"image-rendering:pixelated\" \
             href=\"data:image/png;base64,{}\"/>",
            px.start,
            py.start,
            crate::raster::base64(&png)
        ))
    }
}

/// The viridis colour at `t ∈ [0, 1]` (clamped), linear between the five anchors.
fn viridis(t: f64) -> RGBColor {
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let s = t * (VIRIDIS.len() - 1) as f64;
    let k = (s.floor() as usize).min(VIRIDIS.len() - 2);
    let f = s - k as f64;
    let lerp = |a: u8, b: u8| (f64::from(a) + f * (f64::from(b) - f64::from(a))).round() as u8;
    let (a, b) = (VIRIDIS[k], VIRIDIS[k + 1]);
    RGBColor(lerp(a.0, b.0), lerp(a.1, b.1), lerp(a.2, b.2))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn map(values: Vec<f64>, scale: HeatScale) -> Result<Heatmap, Error> {
        Heatmap::new(
            "m",
            "t",
            [("omega1", "rad/s"), ("T2", "N·m"), ("rsv", "1")],
            vec![100.0, 150.0, 200.0],
            vec![5.0, 10.0],
            values,
            scale,
        )
    }

    fn states() -> HeatScale {
        HeatScale::Categorical(vec![
            (0.0, "no rattle".into()),
            (1.0, "unilateral".into()),
            (2.0, "bilateral".into()),
        ])
    }

    #[test]
    fn categorical_map_renders_every_state_and_failed_cells() {
        let m = map(vec![0.0, 1.0, 2.0, 2.0, f64::NAN, 0.0], states()).unwrap();
        let svg = m.to_svg().unwrap();
        for label in [
            "no rattle",
            "unilateral",
            "bilateral",
            "failed (1)",
            "omega1 [rad/s]",
        ] {
            assert!(svg.contains(label), "{label} missing");
        }
        // Okabe–Ito blue, orange and vermillion cells
        for c in ["#0072B2", "#E69F00", "#D55E00"] {
            assert!(svg.to_uppercase().contains(c), "{c} missing");
        }
        assert_eq!(svg, m.to_svg().unwrap(), "deterministic");
        assert_eq!(m.to_table().rows.len(), 6);
    }

    #[test]
    fn continuous_map_has_a_colour_bar_with_the_range() {
        let m = map(vec![0.5, 1.0, 1.5, 2.0, 2.5, 3.0], HeatScale::Continuous).unwrap();
        let svg = m.to_svg().unwrap();
        assert!(svg.contains("rsv"));
        // colour-bar ticks (fmt6) inside the range and the bar's end colours
        assert!(svg.contains("0.5") && svg.contains("2.5"));
        assert!(svg.to_uppercase().contains("#FDE725") || svg.to_uppercase().contains("#FCE625"));
    }

    #[test]
    fn bad_grids_are_refused() {
        assert!(map(vec![0.0; 5], states()).is_err(), "count");
        assert!(
            map(vec![0.0, 1.0, 2.0, 3.0, 0.0, 0.0], states()).is_err(),
            "unknown state"
        );
        assert!(map(vec![f64::INFINITY; 6], HeatScale::Continuous).is_err());
        let e = Heatmap::new(
            "m",
            "t",
            [("x", ""), ("y", ""), ("z", "")],
            vec![-1e308, 1e308],
            vec![1.0],
            vec![0.0, 1.0],
            HeatScale::Continuous,
        )
        .and_then(|m| m.to_svg());
        assert!(
            e.is_err(),
            "a grid spanning more than f64 can hold is refused, not drawn"
        );
        assert!(
            Heatmap::new(
                "m",
                "t",
                [("x", ""), ("y", ""), ("z", "")],
                vec![2.0, 1.0, 3.0],
                vec![1.0],
                vec![0.0; 3],
                HeatScale::Continuous,
            )
            .is_err()
        );
    }

    #[test]
    fn single_point_and_constant_maps_render() {
        let m = Heatmap::new(
            "m",
            "t",
            [("x", ""), ("y", ""), ("z", "")],
            vec![0.0],
            vec![3.0],
            vec![7.0],
            HeatScale::Continuous,
        )
        .unwrap();
        assert!(m.to_svg().is_ok());
    }

    /// FNV-1a (64 bit) of a text: a fixed fingerprint of a rendering.
    fn fnv(s: &str) -> u64 {
        s.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
            (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
        })
    }

    /// Below RASTER_CELLS a map renders exactly as before the raster existed (the fingerprints
    /// of the two small test maps were taken from the renderer without the raster path), so
    /// the committed validation maps do not move.
    #[test]
    fn small_maps_render_as_before() {
        let a = map(vec![0.0, 1.0, 2.0, 2.0, f64::NAN, 0.0], states()).unwrap();
        let b = map(vec![0.5, 1.0, 1.5, 2.0, 2.5, 3.0], HeatScale::Continuous).unwrap();
        let (sa, sb) = (a.to_svg().unwrap(), b.to_svg().unwrap());
        assert!(!sa.contains("<image") && !sb.contains("<image"));
        assert_eq!((fnv(&sa), fnv(&sb)), SMALL_MAP_FINGERPRINTS);
    }

    const SMALL_MAP_FINGERPRINTS: (u64, u64) = (0xbbde_a449_5ee0_38e5, 0x7d00_2b9d_5b5f_ab65);

    /// A 500 × 400 map (200 000 cells, non-uniform x) is one embedded PNG under 2 MB with its
    /// axes, colour bar and labels as vector text; each pixel of the raster takes the colour of
    /// the cell under it; a categorical map of the same size too.
    #[test]
    fn a_large_map_is_a_raster_under_two_megabytes() {
        let xs: Vec<f64> = (0..500)
            .map(|i| 100.0 + f64::from(i) + 1e-3 * f64::from(i * i))
            .collect();
        let ys: Vec<f64> = (0..400).map(|j| 5.0 + 0.1 * f64::from(j)).collect();
        let values: Vec<f64> = (0..400)
            .flat_map(|j| (0..500).map(move |i| f64::from(i) * 1e-3 + f64::from(j) * 1e-4))
            .collect();
        let m = Heatmap::new(
            "big",
            "a 500 × 400 map",
            [("omega1", "rad/s"), ("T2", "N·m"), ("ppv", "1")],
            xs.clone(),
            ys.clone(),
            values,
            HeatScale::Continuous,
        )
        .unwrap();
        let svg = m.to_svg().unwrap();
        eprintln!("500 x 400 continuous map: {} bytes", svg.len());
        assert!(svg.len() < 2_000_000, "{}", svg.len());
        assert_eq!(svg.matches("<image").count(), 1);
        assert!(svg.contains("data:image/png;base64,iVBORw0KGgo"));
        assert!(svg.contains("omega1 [rad/s]") && svg.contains("T2 [N·m]"));
        // the colour bar stays vector (96 rectangles) and no cell is a rectangle
        assert!(
            svg.matches("<rect").count() < 200,
            "{}",
            svg.matches("<rect").count()
        );
        let cats: Vec<f64> = (0..200_000).map(|k| f64::from(k % 3)).collect();
        let c = Heatmap::new(
            "cat",
            "t",
            [("x", ""), ("y", ""), ("rsv", "1")],
            xs,
            ys,
            cats,
            states(),
        )
        .unwrap();
        let svg = c.to_svg().unwrap();
        assert!(svg.len() < 2_000_000 && svg.contains("bilateral"));
    }

    /// Curves over a map: drawn (a polyline per unbroken piece, crosses inside the area),
    /// named in the legend, clipped; an infinite point is refused; no curve renders as before.
    #[test]
    fn curves_are_drawn_over_the_cells_and_named() {
        let m = map(vec![0.0, 1.0, 2.0, 2.0, f64::NAN, 0.0], states()).unwrap();
        let plain = m.to_svg().unwrap();
        let m = m
            .with_curve(Curve {
                label: "grazing".into(),
                points: vec![
                    (110.0, 5.0),
                    (140.0, 8.0),
                    (f64::NAN, f64::NAN),
                    (160.0, 6.0),
                    (190.0, 50.0),
                ],
                style: CurveStyle::Solid,
                colour: 0,
            })
            .unwrap()
            .with_curve(Curve {
                label: "fold".into(),
                points: vec![(150.0, 7.0), (1e4, 7.0)],
                style: CurveStyle::Crosses,
                colour: 2,
            })
            .unwrap();
        let svg = m.to_svg().unwrap();
        assert!(svg.contains("grazing") && svg.contains("fold"));
        let more = |tag: &str| svg.matches(tag).count() - plain.matches(tag).count();
        assert_eq!(more("<polyline"), 3, "two pieces and the legend key");
        // the cross inside the area and the legend's (two strokes each); the one outside left out
        assert_eq!(more("<line"), 4);
        assert_eq!(m.curves().len(), 2);
        assert_eq!(svg, m.to_svg().unwrap(), "deterministic");
        let bad = map(vec![0.0; 6], states()).unwrap().with_curve(Curve {
            label: "x".into(),
            points: vec![(f64::INFINITY, 1.0)],
            style: CurveStyle::Dashed,
            colour: 1,
        });
        assert!(bad.is_err());
    }

    #[test]
    fn viridis_ends_are_the_anchors() {
        assert_eq!(viridis(0.0), RGBColor(0x44, 0x01, 0x54));
        assert_eq!(viridis(1.0), RGBColor(0xfd, 0xe7, 0x25));
        assert_eq!(viridis(f64::NAN), viridis(0.0));
    }
}
