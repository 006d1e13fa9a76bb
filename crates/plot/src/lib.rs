//! The output layer of geardyn: tables, figures, heat maps and the number format, knowing no
//! model and no study.
//!
//! * [`Table`]: named columns with units ([`Column`]) and rows of [`Cell`]s, written as CSV with
//!   `name [unit]` headers ([`Table::to_csv`]), every number at [`SIGNIFICANT_DIGITS`] = 6
//!   significant digits ([`fmt_sig`], the workspace's one formatter from `system::format`);
//! * [`Figure`]: series of curves ([`Series`], [`Style`], colours from [`OKABE_ITO`]) rendered to
//!   SVG with plotters ([`Figure::to_svg`]); its data is also a long-format table;
//! * [`heatmap::Heatmap`]: a quantity `z(x, y)` on a rectangular grid, continuous (viridis, with
//!   a colour bar) or categorical (one colour per state), drawn cell by cell so that non-uniform
//!   grids are drawn faithfully, and above [`RASTER_CELLS`] cells as one embedded PNG with vector
//!   axes and labels, with curves over the cells ([`Curve`]: boundaries located by continuation);
//! * text helpers for CSV and Markdown ([`csv_field`], [`md_cell`]), values that do not settle
//!   under a solver retune ([`unsettled`], [`committed_text`], [`NOT_PERIODIC`]) and the
//!   tolerance of a printed number ([`half_last_digit`]).
//!
//! Output is deterministic: the same input gives the same bytes on every platform, so that
//! generated files can be committed and compared byte for byte.
//!
//! ```
//! use geardyn_plot::{Figure, Series, Table};
//!
//! let mut t = Table::new("points", &[("x", "m"), ("y", "N")]);
//! t.push_nums(&[1.0, 2.0]).unwrap();
//! assert_eq!(t.to_csv(), "x [m],y [N]\n1,2\n");
//! let f = Figure::new("curve", "y = x²", ("x", "m"), ("y", "m²"))
//!     .with(Series::line("model", (0..10).map(|i| (i as f64, (i * i) as f64)).collect()));
//! assert!(f.to_svg().unwrap().starts_with("<svg"));
//! ```

#![deny(missing_docs)]

mod error;
pub mod figure;
pub mod format;
pub mod heatmap;
mod raster;
pub mod table;

pub use error::{Error, check_name};
pub use figure::{Figure, OKABE_ITO, Series, Style, step_path};
pub use format::{
    NOT_PERIODIC, SIGNIFICANT_DIGITS, UNSETTLED_CLOSE, UNSETTLED_OPEN, committed_text, csv_field,
    fmt_sig, fmt6, full_text, half_last_digit, md_cell, unsettled,
};
pub use heatmap::{CURVE_COLOURS, Curve, CurveStyle, HeatScale, Heatmap, RASTER_CELLS};
pub use table::{Cell, Column, Table};
