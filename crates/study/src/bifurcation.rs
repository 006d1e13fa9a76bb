//! Bifurcation studies (`[bifurcation]` in a study file): for every value of the swept
//! parameter, the stroboscopic Poincaré section of one state coordinate after the transient,
//! with the motion type (period-n, quasi-periodic, chaotic) and the largest Lyapunov exponent
//! ([`timestep::bifurcation_point`]).
//!
//! **CSV shape** (one row per parameter value, so that shards, journals and merges work as for
//! every study): the swept parameter, then `motion` (text: `period-1`, `period-2`, …,
//! `quasi-periodic`, `chaotic`), `period` (n, 0 when not periodic), `lambda` (λ per unit time
//! of the model, computed at every point: negative at a stable periodic point), then the
//! section values `<coordinate>_1 … <coordinate>_N` in time order. A failed point is a row of
//! NaN (`motion` empty) with its message in the JSON summary.
//!
//! **Figure** `<name>_bifurcation.svg`: the section values against the parameter, one marker
//! per section point, coloured by motion type with fixed Okabe–Ito colours (period-1 blue,
//! period-2 vermillion, period-3 bluish green, period-4 reddish purple, period ≥ 5 orange,
//! quasi-periodic sky blue, chaotic black), with a legend.
//!
//! Points are independent (each from the model's initial state), so they run in parallel and
//! shard; sequential continuation (sweep up/down for hysteresis) is in the library
//! ([`timestep::bifurcation_sweep`] with [`timestep::Start`]).

use serde::{Deserialize, Serialize};

use crate::error::Error;
use plot::Cell;
use plot::{Figure, Series};

/// Most section points per parameter value (CSV columns) in a study file.
pub const MAX_BIFURCATION_POINTS: i64 = 1000;
/// Most transient periods or Lyapunov intervals per parameter value in a study file.
pub const MAX_BIFURCATION_PERIODS: i64 = 1_000_000;

/// The `[bifurcation]` table of a study file; every key optional, unknown keys are errors.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct BifurcationSpec {
    /// State coordinate of the section, by name (per model; absent: the model's first,
    /// e.g. `q`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub coordinate: Option<String>,
    /// Section points per parameter value (2 ..= [`MAX_BIFURCATION_POINTS`]; default 32).
    pub points: i64,
    /// Forcing periods discarded before the section (0 ..= [`MAX_BIFURCATION_PERIODS`];
    /// default 200).
    pub transient_periods: i64,
    /// Largest period-n tested (1 ..< `points`; default 8).
    pub max_period: i64,
    /// Relative tolerance of the periodicity test, in (0, 0.1] (default 1e-5).
    pub tol: f64,
    /// Lyapunov renormalisation intervals of one forcing period (1 ..=
    /// [`MAX_BIFURCATION_PERIODS`]; default 100).
    pub lyapunov_intervals: i64,
    /// λ above which a non-periodic motion is chaotic (finite; default 0.01 per unit time).
    pub lyapunov_threshold: f64,
}

impl Default for BifurcationSpec {
    fn default() -> Self {
        BifurcationSpec {
            coordinate: None,
            points: 32,
            transient_periods: 200,
            max_period: 8,
            tol: 1e-5,
            lyapunov_intervals: 100,
            lyapunov_threshold: 0.01,
        }
    }
}

impl BifurcationSpec {
    /// The engine's options (coordinate 0: the adapter sets it from the name); errors name the
    /// key and its bound.
    pub fn options(&self) -> Result<timestep::BifurcationOptions, Error> {
        let bad = |key: &str, bound: String, got: String| {
            Err(Error::StudyFile(format!(
                "bifurcation.{key} must be {bound}, got {got}"
            )))
        };
        if !(2..=MAX_BIFURCATION_POINTS).contains(&self.points) {
            return bad(
                "points",
                format!("in [2, {MAX_BIFURCATION_POINTS}]"),
                self.points.to_string(),
            );
        }
        if !(0..=MAX_BIFURCATION_PERIODS).contains(&self.transient_periods) {
            return bad(
                "transient_periods",
                format!("in [0, {MAX_BIFURCATION_PERIODS}]"),
                self.transient_periods.to_string(),
            );
        }
        if !(1..self.points).contains(&self.max_period) {
            return bad(
                "max_period",
                format!("in [1, points − 1 = {}]", self.points - 1),
                self.max_period.to_string(),
            );
        }
        if !(self.tol > 0.0 && self.tol <= 0.1) {
            return bad("tol", "in (0, 0.1]".into(), self.tol.to_string());
        }
        if !(1..=MAX_BIFURCATION_PERIODS).contains(&self.lyapunov_intervals) {
            return bad(
                "lyapunov_intervals",
                format!("in [1, {MAX_BIFURCATION_PERIODS}]"),
                self.lyapunov_intervals.to_string(),
            );
        }
        if !self.lyapunov_threshold.is_finite() {
            return bad(
                "lyapunov_threshold",
                "finite".into(),
                self.lyapunov_threshold.to_string(),
            );
        }
        let mut o = timestep::BifurcationOptions::new(0);
        // the ranges above are inside the engine's (usize, ≤ MAX_PERIODS)
        o.classify.n_points = self.points as usize;
        o.classify.transient_periods = self.transient_periods as usize;
        o.classify.max_period = self.max_period as usize;
        o.classify.tol = self.tol;
        o.classify.lyapunov_intervals = self.lyapunov_intervals as usize;
        o.classify.lyapunov_threshold = self.lyapunov_threshold;
        // λ at every point, so that the `lambda` column is a number in every successful row
        o.classify.lyapunov_always = true;
        Ok(o)
    }

    /// The index of the section coordinate among the model's `coordinates` (name, unit).
    pub fn coordinate_index(
        &self,
        model: &str,
        coordinates: &[(&str, &str)],
    ) -> Result<usize, Error> {
        match &self.coordinate {
            None => Ok(0),
            Some(c) => coordinates.iter().position(|(n, _)| n == c).ok_or_else(|| {
                Error::StudyFile(format!(
                    "bifurcation.coordinate = \"{c}\" is not a coordinate of {model}; \
                     coordinates: {}",
                    coordinates
                        .iter()
                        .map(|(n, _)| format!("\"{n}\""))
                        .collect::<Vec<_>>()
                        .join(", ")
                ))
            }),
        }
    }
}

/// Number of leading non-section columns of [`models::contract::bifurcation_outputs`].
pub const LEADING: usize = 3;

/// A CSV cell of output column `j` of a successful point (the motion as its label).
pub fn cell(j: usize, value: f64) -> Cell {
    if j == 0 {
        Cell::Text(
            timestep::Motion::from_code(value)
                .map(|m| m.label())
                .unwrap_or_default(),
        )
    } else {
        Cell::Num(value)
    }
}

/// The motion classes of the figure: (label, Okabe–Ito colour index), in legend order.
fn class_of(m: timestep::Motion) -> usize {
    match m {
        timestep::Motion::Periodic(n) => n.clamp(1, 5) - 1,
        timestep::Motion::QuasiPeriodic => 5,
        timestep::Motion::Chaotic => 6,
        _ => 7,
    }
}

const CLASSES: [&str; 8] = [
    "period-1",
    "period-2",
    "period-3",
    "period-4",
    "period ≥ 5",
    "quasi-periodic",
    "chaotic",
    "non-periodic",
];

/// The bifurcation diagram: section values against the parameter `x`, coloured by motion type
/// (only the classes that occur, in a fixed order and fixed colours). `records[i]` is point
/// `i`'s record ([`models::contract::bifurcation_record`]) or its failure (not drawn).
pub fn figure(
    name: &str,
    title: &str,
    x_axis: (&str, &str),
    coordinate: (&str, &str),
    x: &[f64],
    records: &[Result<Vec<f64>, String>],
) -> Figure {
    let mut classes: Vec<Vec<(f64, f64)>> = vec![Vec::new(); CLASSES.len()];
    for (xi, r) in x.iter().zip(records) {
        let Ok(v) = r else { continue };
        let Some(m) = v.first().and_then(|&c| timestep::Motion::from_code(c)) else {
            continue;
        };
        let pts = &mut classes[class_of(m)];
        pts.extend(
            v.iter()
                .skip(LEADING)
                .filter(|y| y.is_finite())
                .map(|&y| (*xi, y)),
        );
    }
    let mut fig = Figure::new(name, title, x_axis, coordinate);
    for (k, pts) in classes.into_iter().enumerate() {
        if !pts.is_empty() {
            fig.push(Series::markers(CLASSES[k], pts).colour(k));
        }
    }
    fig
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(text: &str) -> Result<timestep::BifurcationOptions, Error> {
        let s: BifurcationSpec =
            toml::from_str(text).map_err(|e| Error::StudyFile(e.to_string()))?;
        s.options()
    }

    #[test]
    fn keys_are_checked() {
        let o = spec("").unwrap();
        assert_eq!(
            (
                o.classify.n_points,
                o.classify.max_period,
                o.classify.transient_periods
            ),
            (32, 8, 200)
        );
        assert!(o.classify.lyapunov_always);
        for bad in [
            "points = 1",
            "points = 1001",
            "max_period = 32",
            "max_period = 0",
            "tol = 0.0",
            "tol = nan",
            "lyapunov_intervals = 0",
            "transient_periods = -1",
            "lyapunov_threshold = inf",
            "typo = 3",
        ] {
            assert!(spec(bad).is_err(), "{bad}");
        }
        let s: BifurcationSpec = toml::from_str("coordinate = \"v\"").unwrap();
        assert!(s.coordinate_index("m", &[("q", "1"), ("q'", "1")]).is_err());
        let s: BifurcationSpec = toml::from_str("coordinate = \"q'\"").unwrap();
        assert_eq!(
            s.coordinate_index("m", &[("q", "1"), ("q'", "1")]).unwrap(),
            1
        );
    }

    #[test]
    fn figure_colours_by_motion() {
        let rec = |m: timestep::Motion, ys: &[f64]| {
            let mut v = vec![m.code(), 0.0, 0.0];
            v.extend_from_slice(ys);
            Ok(v)
        };
        let records = vec![
            rec(timestep::Motion::Periodic(1), &[1.0, 1.0]),
            rec(timestep::Motion::Periodic(2), &[1.0, 2.0]),
            Err("failed".to_owned()),
            rec(timestep::Motion::Chaotic, &[0.3, 0.7]),
        ];
        let f = figure(
            "b",
            "t",
            ("w", "rad/s"),
            ("q", "1"),
            &[1.0, 2.0, 3.0, 4.0],
            &records,
        );
        let labels: Vec<&str> = f.series.iter().map(|s| s.label.as_str()).collect();
        assert_eq!(labels, ["period-1", "period-2", "chaotic"]);
        assert_eq!(f.series[2].colour, Some(6));
        assert_eq!(f.series[1].points, [(2.0, 1.0), (2.0, 2.0)]);
        let svg = f.to_svg().unwrap();
        assert!(svg.contains("chaotic"));
        assert_eq!(cell(0, 2.0), Cell::Text("period-2".into()));
        assert_eq!(cell(0, -1.0), Cell::Text("chaotic".into()));
    }
}
