//! Continuation studies (`[continuation]` in a study file): the periodic orbit of the study's
//! parameter set followed in one parameter by shooting, with its stability and special points
//! (grazing, fold, period doubling, …), and optionally the special points followed in two
//! parameters (codim-2 curves: a rattle boundary as a curve in the (speed, load) plane, for
//! instance). The model does the work ([`models::contract::Model::continuation`], one runner
//! for every model: [`models::contract::continuation::continue_on`]); this module reads the
//! table, checks it and renders the outputs.
//!
//! A continuation is one sequential computation (each point is predicted from the last), so a
//! continuation study has no sweep, does not shard, and its time limit
//! (`limits.max_seconds_per_point`) bounds the whole computation. If the start does not
//! converge, the study is one failed point with the message.
//!
//! **Outputs** (`<name>` the study's name):
//! * `<name>.csv` — one row per branch point in arclength order: the parameter, the orbit's
//!   state on the section (the model's coordinates), `max_multiplier`, `stable`,
//!   `events_per_period`, then `<event>_min`, `<event>_max` of every event function;
//! * `<name>_special.csv` — one row per special point: `kind`, the parameter, `located`
//!   (1: to the tolerance; 0: detected between two points), `precision` (the width of the
//!   last bracket), `stable`, the state;
//! * `<name>_curves.csv` (with `[continuation.codim2]`) — one row per curve point: `curve`
//!   (the index of its start in `<name>_special.csv`), `kind`, `direction` (of the second
//!   parameter from the start), `piece` (the smooth pieces of a grazing curve that switched
//!   between local extrema, from 0), the two parameters, `stable`;
//! * `<name>_branch_<coordinate>.svg` — the branch (dashed line in arclength order, stable
//!   and unstable points as markers) with its special points; `<name>_curves.svg` — the
//!   codim-2 curves in the two parameters;
//! * `<name>.json` — the summary, with `continuation`: the stop reason of the branch, the
//!   special points, every curve with its points and stop reason, and the starts that gave no
//!   curve with why.

use serde::{Deserialize, Serialize};

use crate::error::Error;
use models::contract::continuation::{
    Codim2Request, ContinuationOutput, ContinuationRequest, SpecialFamily,
};
use plot::{Cell, Figure, Series, Table};

/// Most branch points, and most points per direction of a codim-2 curve, in a study file.
pub const MAX_CONTINUATION_POINTS: i64 = 5000;
/// Most special points continued as codim-2 curves in a study file.
pub const MAX_CODIM2_CURVES: i64 = 16;
/// Most switches of a grazing curve between local extrema, per direction, in a study file.
pub const MAX_SWITCHES: i64 = 100;

fn default_points() -> i64 {
    200
}
fn default_curve_points() -> i64 {
    100
}
fn default_curves() -> i64 {
    4
}
fn default_switches() -> i64 {
    12
}
fn default_kinds() -> Vec<String> {
    vec!["grazing".into(), "fold".into(), "period-doubling".into()]
}

/// The `[continuation]` table of a study file; unknown keys are errors.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContinuationSpec {
    /// The continued parameter (the model's continuation parameters: `geardyn models`).
    pub parameter: String,
    /// The end of the range; the start is the parameter's value in `[overrides]` (or the
    /// model's default).
    pub to: f64,
    /// Largest change of the parameter per step (> 0; default a fiftieth of the range).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_step: Option<f64>,
    /// Most branch points (2 ..= [`MAX_CONTINUATION_POINTS`]; default 200).
    #[serde(default = "default_points")]
    pub max_points: i64,
    /// End the branch after its first special point of one of these kinds: `"grazing"`,
    /// `"fold"`, `"period-doubling"` (default none).
    #[serde(default)]
    pub stop_at: Vec<String>,
    /// End the branch at its first unstable point after a stable one (default false).
    #[serde(default)]
    pub stop_at_instability: bool,
    /// Report the contact changes among the special points (default false): a local extremum
    /// of an event function through zero (contacts appear or vanish inside the orbit),
    /// detected between two branch points and not located; on a rattling gear there can be
    /// dozens.
    #[serde(default)]
    pub contact_changes: bool,
    /// Codim-2 curves from the branch's special points.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub codim2: Option<Codim2Spec>,
}

/// The `[continuation.codim2]` table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Codim2Spec {
    /// The second parameter (another continuation parameter of the model).
    pub parameter: String,
    /// Its range `[lo, hi]`, `lo < hi`: the curves stop where they leave it.
    pub range: [f64; 2],
    /// Which special points start curves (default all: `"grazing"`, `"fold"`,
    /// `"period-doubling"`).
    #[serde(default = "default_kinds")]
    pub kinds: Vec<String>,
    /// Largest change of the second parameter per step (> 0; default a fiftieth of the range).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_step: Option<f64>,
    /// Most points per direction of a curve (2 ..= [`MAX_CONTINUATION_POINTS`]; default 100).
    #[serde(default = "default_curve_points")]
    pub max_points: i64,
    /// Most special points continued (1 ..= [`MAX_CODIM2_CURVES`]; default 4), in branch order.
    #[serde(default = "default_curves")]
    pub max_curves: i64,
    /// A grazing curve follows the global extremum of its event function; where another local
    /// extremum takes over (a double grazing: a kink of the boundary) it goes on along that
    /// one's grazing, at most this many times per direction (0 ..= [`MAX_SWITCHES`]; default
    /// 12).
    #[serde(default = "default_switches")]
    pub max_switches: i64,
}

fn bad(key: &str, bound: &str, got: impl std::fmt::Display) -> Error {
    Error::StudyFile(format!("continuation.{key} must be {bound}, got {got}"))
}

fn families(key: &str, names: &[String]) -> Result<Vec<SpecialFamily>, Error> {
    names
        .iter()
        .map(|n| {
            SpecialFamily::parse(n)
                .map_err(|e| Error::StudyFile(format!("continuation.{key}: {e}")))
        })
        .collect()
}

fn check_step(key: &str, step: Option<f64>) -> Result<(), Error> {
    match step {
        Some(s) if !(s.is_finite() && s > 0.0) => Err(bad(key, "finite and > 0", s)),
        _ => Ok(()),
    }
}

fn check_points(key: &str, n: i64) -> Result<usize, Error> {
    if (2..=MAX_CONTINUATION_POINTS).contains(&n) {
        Ok(n as usize)
    } else {
        Err(bad(key, &format!("in [2, {MAX_CONTINUATION_POINTS}]"), n))
    }
}

impl ContinuationSpec {
    /// The model's request, every entry that does not need the model checked (errors name the
    /// key and its bound).
    pub fn request(&self) -> Result<ContinuationRequest, Error> {
        if !self.to.is_finite() {
            return Err(bad("to", "finite", self.to));
        }
        check_step("max_step", self.max_step)?;
        let max_points = check_points("max_points", self.max_points)?;
        let stop_at = families("stop_at", &self.stop_at)?;
        let codim2 = match &self.codim2 {
            None => None,
            Some(c) => {
                if c.parameter == self.parameter {
                    return Err(bad(
                        "codim2.parameter",
                        "another parameter than continuation.parameter",
                        format!("`{}`", c.parameter),
                    ));
                }
                let [lo, hi] = c.range;
                if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                    return Err(bad(
                        "codim2.range",
                        "[lo, hi], finite, lo < hi",
                        format!("[{lo}, {hi}]"),
                    ));
                }
                check_step("codim2.max_step", c.max_step)?;
                if c.kinds.is_empty() {
                    return Err(bad("codim2.kinds", "a non-empty list", "[]"));
                }
                if !(1..=MAX_CODIM2_CURVES).contains(&c.max_curves) {
                    return Err(bad(
                        "codim2.max_curves",
                        &format!("in [1, {MAX_CODIM2_CURVES}]"),
                        c.max_curves,
                    ));
                }
                if !(0..=MAX_SWITCHES).contains(&c.max_switches) {
                    return Err(bad(
                        "codim2.max_switches",
                        &format!("in [0, {MAX_SWITCHES}]"),
                        c.max_switches,
                    ));
                }
                Some(Codim2Request {
                    parameter: c.parameter.clone(),
                    range: c.range,
                    kinds: families("codim2.kinds", &c.kinds)?,
                    max_step: c.max_step,
                    max_points: check_points("codim2.max_points", c.max_points)?,
                    max_curves: c.max_curves as usize,
                    max_switches: c.max_switches as usize,
                })
            }
        };
        Ok(ContinuationRequest {
            parameter: self.parameter.clone(),
            to: self.to,
            max_step: self.max_step,
            max_points,
            stop_at,
            stop_at_instability: self.stop_at_instability,
            contact_changes: self.contact_changes,
            codim2,
        })
    }
}

fn flag(b: bool) -> f64 {
    if b { 1.0 } else { 0.0 }
}

/// A file-name and column part of a coordinate or event name: `a-z 0-9 _`, a prime as `p`
/// (`q'` → `qp`, `back flank` → `back_flank`).
fn file_part(s: &str) -> String {
    s.chars()
        .map(|c| match c {
            'a'..='z' | 'A'..='Z' | '0'..='9' => c.to_ascii_lowercase(),
            '\'' => 'p',
            _ => '_',
        })
        .collect()
}

/// The tables of a continuation: the branch, its special points and (codim-2) the curves.
pub fn tables(name: &str, out: &ContinuationOutput) -> (Table, Table, Option<Table>) {
    let (pn, pu) = (&out.parameter.0, &out.parameter.1);
    let mut cols: Vec<(String, String)> = vec![(pn.clone(), pu.clone())];
    cols.extend(out.coordinates.iter().cloned());
    for c in ["max_multiplier", "stable", "events_per_period"] {
        cols.push((c.to_owned(), "1".to_owned()));
    }
    for e in &out.events {
        for m in ["min", "max"] {
            cols.push((format!("{}_{m}", file_part(e)), "1".to_owned()));
        }
    }
    let refs: Vec<(&str, &str)> = cols.iter().map(|(n, u)| (n.as_str(), u.as_str())).collect();
    let mut branch = Table::new(name, &refs);
    for p in &out.points {
        let mut row = vec![Cell::Num(p.value)];
        row.extend(p.state.iter().map(|&x| Cell::Num(x)));
        row.push(Cell::Num(p.max_multiplier));
        row.push(Cell::Num(flag(p.stable)));
        row.push(Cell::Count(p.events as u64));
        for e in 0..out.events.len() {
            let [lo, hi] = p.extrema.get(e).copied().unwrap_or([f64::NAN; 2]);
            row.push(Cell::Num(lo));
            row.push(Cell::Num(hi));
        }
        branch.rows.push(row);
    }
    let mut scols: Vec<(String, String)> = vec![
        ("kind".to_owned(), String::new()),
        (pn.clone(), pu.clone()),
        ("located".to_owned(), "1".to_owned()),
        ("precision".to_owned(), pu.clone()),
        ("stable".to_owned(), "1".to_owned()),
    ];
    scols.extend(out.coordinates.iter().cloned());
    let refs: Vec<(&str, &str)> = scols
        .iter()
        .map(|(n, u)| (n.as_str(), u.as_str()))
        .collect();
    let mut special = Table::new(&format!("{name}_special"), &refs);
    for s in &out.special {
        let mut row = vec![
            Cell::Text(s.kind.clone()),
            Cell::Num(s.value),
            Cell::Num(flag(s.located)),
            Cell::Num(s.precision),
            Cell::Num(flag(s.stable)),
        ];
        row.extend(s.state.iter().map(|&x| Cell::Num(x)));
        special.rows.push(row);
    }
    let curves = out.second.as_ref().map(|(qn, qu)| {
        let mut t = Table::new(
            &format!("{name}_curves"),
            &[
                ("curve", "1"),
                ("kind", ""),
                ("direction", "1"),
                ("piece", "1"),
                (pn, pu),
                (qn, qu),
                ("stable", "1"),
            ],
        );
        for c in &out.curves {
            for &(a, b, st, piece) in &c.points {
                t.rows.push(vec![
                    Cell::Count(c.special as u64),
                    Cell::Text(c.kind.clone()),
                    Cell::Num(c.direction),
                    Cell::Count(piece as u64),
                    Cell::Num(a),
                    Cell::Num(b),
                    Cell::Num(flag(st)),
                ]);
            }
        }
        t
    });
    (branch, special, curves)
}

/// The figures: the branch against each state coordinate, and the codim-2 curves.
pub fn figures(name: &str, out: &ContinuationOutput) -> Vec<Figure> {
    let (pn, pu) = (&out.parameter.0, &out.parameter.1);
    let mut figs = Vec::new();
    for (j, (cn, cu)) in out.coordinates.iter().enumerate() {
        let mut f = Figure::new(
            &format!("{name}_branch_{}", file_part(cn)),
            &format!("{name}: periodic orbit continued in {pn}"),
            (pn, pu),
            (&format!("{cn}(t0)"), cu),
        );
        let at = |p: &[f64]| p.get(j).copied().unwrap_or(f64::NAN);
        f.push(
            Series::dashed(
                "branch",
                out.points.iter().map(|p| (p.value, at(&p.state))).collect(),
            )
            .colour(7),
        );
        for (label, stable, colour) in [("stable", true, 0), ("unstable", false, 1)] {
            let pts: Vec<(f64, f64)> = out
                .points
                .iter()
                .filter(|p| p.stable == stable)
                .map(|p| (p.value, at(&p.state)))
                .collect();
            if !pts.is_empty() {
                f.push(Series::markers(label, pts).colour(colour));
            }
        }
        let mut kinds: Vec<&str> = out.special.iter().map(|s| s.kind.as_str()).collect();
        kinds.sort_unstable();
        kinds.dedup();
        for (k, kind) in kinds.into_iter().enumerate() {
            let pts = out
                .special
                .iter()
                .filter(|s| s.kind == kind)
                .map(|s| (s.value, at(&s.state)))
                .collect();
            f.push(Series::markers(kind, pts).colour(2 + k % 5));
        }
        figs.push(f);
    }
    if let Some((qn, qu)) = &out.second {
        let mut f = Figure::new(
            &format!("{name}_curves"),
            &format!("{name}: special points continued in ({pn}, {qn})"),
            (pn, pu),
            (qn, qu),
        );
        // one line per start: the −1 direction reversed, then the +1 direction
        let mut starts: Vec<usize> = out.curves.iter().map(|c| c.special).collect();
        starts.dedup();
        for (k, s) in starts.into_iter().enumerate() {
            let mut pts: Vec<(f64, f64)> = Vec::new();
            let mut label = String::new();
            for c in out.curves.iter().filter(|c| c.special == s) {
                label.clone_from(&c.kind);
                let mut piece: Vec<(f64, f64)> =
                    c.points.iter().map(|&(a, b, _, _)| (a, b)).collect();
                if c.direction < 0.0 {
                    piece.reverse();
                } else if !pts.is_empty() && !piece.is_empty() {
                    // the start is the first point of both directions
                    piece.remove(0);
                }
                pts.extend(piece);
            }
            f.push(Series::line(format!("{label} (start {s})"), pts).colour(k % 8));
        }
        figs.push(f);
    }
    figs
}

/// The `continuation` object of the JSON summary.
pub fn summary(out: &ContinuationOutput) -> serde_json::Value {
    let num = |x: f64| {
        if x.is_finite() {
            serde_json::json!(x)
        } else {
            serde_json::Value::Null
        }
    };
    serde_json::json!({
        "parameter": out.parameter.0,
        "unit": out.parameter.1,
        "branch_points": out.points.len(),
        "stop": out.stop,
        "special": out.special.iter().map(|s| serde_json::json!({
            "kind": s.kind,
            "value": num(s.value),
            "located": s.located,
            "precision": num(s.precision),
            "stable": s.stable,
            "state": s.state.iter().map(|&x| num(x)).collect::<Vec<_>>(),
        })).collect::<Vec<_>>(),
        "second": out.second.as_ref().map(|s| s.0.clone()),
        "second_unit": out.second.as_ref().map(|s| s.1.clone()),
        "curves": out.curves.iter().map(|c| serde_json::json!({
            "special": c.special,
            "kind": c.kind,
            "direction": c.direction,
            "points": c.points.iter().map(|&(a, b, st, piece)| serde_json::json!([num(a), num(b), st, piece])).collect::<Vec<_>>(),
            "stop": c.stop,
        })).collect::<Vec<_>>(),
        "curve_failures": out.curve_failures,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(text: &str) -> Result<ContinuationRequest, Error> {
        let s: ContinuationSpec =
            toml::from_str(text).map_err(|e| Error::StudyFile(e.to_string()))?;
        s.request()
    }

    #[test]
    fn keys_are_checked_with_their_bounds() {
        let r = spec("parameter = \"omega1\"\nto = 220.0").unwrap();
        assert_eq!((r.max_points, r.max_step, r.codim2), (200, None, None));
        let r = spec(
            "parameter = \"omega1\"\nto = 220.0\nstop_at = [\"fold\"]\n\
             [codim2]\nparameter = \"load_torque\"\nrange = [0.0, 60.0]",
        )
        .unwrap();
        assert_eq!(r.stop_at, [SpecialFamily::Fold]);
        let c = r.codim2.unwrap();
        assert_eq!((c.max_points, c.max_curves, c.kinds.len()), (100, 4, 3));
        for (bad, key) in [
            ("parameter = \"omega1\"\nto = nan", "continuation.to"),
            (
                "parameter = \"omega1\"\nto = 1.0\nmax_step = 0.0",
                "max_step",
            ),
            (
                "parameter = \"omega1\"\nto = 1.0\nmax_points = 1",
                "max_points",
            ),
            (
                "parameter = \"omega1\"\nto = 1.0\nmax_points = 5001",
                "max_points",
            ),
            (
                "parameter = \"omega1\"\nto = 1.0\nstop_at = [\"hopf\"]",
                "stop_at",
            ),
            ("parameter = \"omega1\"\nto = 1.0\ntypo = 1", "typo"),
            (
                "parameter = \"omega1\"\nto = 1.0\n[codim2]\nparameter = \"omega1\"\nrange = [0.0, 1.0]",
                "codim2.parameter",
            ),
            (
                "parameter = \"omega1\"\nto = 1.0\n[codim2]\nparameter = \"ak\"\nrange = [1.0, 0.0]",
                "codim2.range",
            ),
            (
                "parameter = \"omega1\"\nto = 1.0\n[codim2]\nparameter = \"ak\"\nrange = [0.0, 1.0]\nmax_curves = 17",
                "codim2.max_curves",
            ),
            (
                "parameter = \"omega1\"\nto = 1.0\n[codim2]\nparameter = \"ak\"\nrange = [0.0, 1.0]\nkinds = []",
                "codim2.kinds",
            ),
        ] {
            let e = spec(bad).unwrap_err().to_string();
            assert!(e.contains(key), "{bad}: {e}");
        }
    }

    /// Tables and figures of a synthetic result, with the edge cases a run can give: a curve
    /// with no point, a start with one direction only, a point without event extrema.
    #[test]
    fn tables_and_figures_take_every_shape() {
        use models::contract::continuation::{BranchRow, CurveRow, SpecialRow};
        let row = |v: f64, stable: bool| BranchRow {
            value: v,
            state: vec![v, -v],
            max_multiplier: 0.5,
            stable,
            events: 2,
            extrema: vec![[-1.0, 0.5]],
        };
        let curve =
            |special: usize, direction: f64, points: Vec<(f64, f64, bool, usize)>| CurveRow {
                special,
                kind: "fold".into(),
                direction,
                points,
                stop: "point cap reached".into(),
            };
        let out = ContinuationOutput {
            parameter: ("w".into(), "rad/s".into()),
            coordinates: vec![("q".into(), "1".into()), ("q'".into(), "1".into())],
            events: vec!["back flank".into(), "drive flank".into()],
            points: vec![row(1.0, true), row(2.0, false)],
            special: vec![SpecialRow {
                kind: "fold".into(),
                value: 1.5,
                located: true,
                precision: 1e-6,
                state: vec![1.5, -1.5],
                stable: false,
            }],
            stop: "reached the end of the range".into(),
            second: Some(("t".into(), "N·m".into())),
            curves: vec![
                curve(0, -1.0, vec![(1.5, 30.0, true, 0), (1.4, 29.0, true, 0)]),
                curve(0, 1.0, vec![]),
                curve(1, 1.0, vec![(1.0, 30.0, false, 0), (1.1, 31.0, false, 1)]),
            ],
            curve_failures: vec!["fold at 2 rad/s (direction -1): no".into()],
        };
        let (branch, special, curves) = tables("n", &out);
        let names: Vec<&str> = branch.columns.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(
            names,
            [
                "w",
                "q",
                "q'",
                "max_multiplier",
                "stable",
                "events_per_period",
                "back_flank_min",
                "back_flank_max",
                "drive_flank_min",
                "drive_flank_max"
            ]
        );
        // the missing extrema of the second event are NaN cells, not a short row
        assert!(branch.rows.iter().all(|r| r.len() == names.len()));
        assert_eq!(special.rows.len(), 1);
        assert_eq!(curves.unwrap().rows.len(), 4);
        let figs = figures("n", &out);
        let names: Vec<&str> = figs.iter().map(|f| f.name.as_str()).collect();
        assert_eq!(names, ["n_branch_q", "n_branch_qp", "n_curves"]);
        // one line per start, the −1 direction reversed
        assert_eq!(figs[2].series.len(), 2);
        assert_eq!(figs[2].series[0].points, [(1.4, 29.0), (1.5, 30.0)]);
        for f in &figs {
            f.to_svg().unwrap();
        }
        let j = summary(&out);
        assert_eq!(
            j["curves"][2]["points"][1],
            serde_json::json!([1.1, 31.0, false, 1])
        );
        assert_eq!(j["curve_failures"].as_array().unwrap().len(), 1);
    }
}
