//! Studies of the Liu et al. 2021 NFG model (dynamics), one file per study.
//!
//! All use Table 1 with the constant-b̄ reading (`R-LIU-EQ11`, the one the paper's figures
//! follow) and the derived Eq. (20)/(21) (`R-LIU-EQ20`, `R-LIU-EQ21`). The numerical strategy
//! (time-integration reference with Poincaré motion type and a 100×-tighter repeat, HBM cold /
//! warm from the time response / from neighbours, period-map stability, flags on
//! non-convergence) is the library's `models::liu2021::solve_sweep`; these files only compare,
//! tabulate and plot.
//!
//! **Verdict rule (Liu):** rows are judged on converged, period-1, reproducible time
//! integration (the physics reference); the paper's own method, the 15-term HBM, is shown beside
//! it (verdict `shown`), as are the full-basis HBM columns. See `validation/README.md`.

use models::liu2021::{
    self, BaseRadius, HbmPoint, Model, Parameters, SweepStrategy, TimeReference,
};

use super::user_models::step_cells;
use crate::{
    Cell, Error, Figure, ResultExt, STEP_STATISTICS, Series, Study, StudyOutput, Table, Tolerance,
    fmt_sig,
};

mod continuation;
mod fig17;
mod load_sweep;
mod parameter_sweeps;
mod readings_thresholds;
mod responses;
mod speed_sweep;
mod table2;

/// The studies of the Liu paper, in report order.
pub fn studies() -> Vec<Study> {
    vec![
        table2::study(),
        fig17::study(),
        speed_sweep::study(),
        continuation::study(),
        responses::study(),
        load_sweep::study(),
        parameter_sweeps::study(),
        readings_thresholds::study(),
    ]
}

/// A number at 3 significant digits for claim evidence.
fn sig(x: f64) -> String {
    fmt_sig(x, 3)
}

/// Table 1 with the constant-b̄ reading.
fn base() -> Parameters {
    let mut p = liu2021::table1();
    p.readings.base_radius = BaseRadius::Mean;
    p
}

fn model(p: &Parameters) -> Result<Model, Error> {
    p.model().context("liu2021 model")
}

/// The strategy of every Liu sweep: the library default (paper basis cold/warm, full basis
/// K = Z2 + 2 warm, neighbour continuation, stability, Poincaré motion type, 100× refinement).
fn strategy() -> SweepStrategy {
    SweepStrategy::default()
}

/// One sweep point: the swept value, the time reference and the three HBM columns, with the
/// step statistics of the reference run and the accuracy of each HBM solution.
#[derive(Debug, Clone, Copy)]
struct Point {
    x: f64,
    time: TimeReference,
    cold: HbmPoint,
    warm: HbmPoint,
    full: HbmPoint,
    /// Work counters of the time reference's run at the study tolerance (transient included).
    stats: timestep::Stats,
    /// `(residual norm, truncation indicator)` of the cold, warm and full HBM solutions.
    accuracy: [(f64, f64); 3],
}

/// `(‖s‖₂, truncation indicator)` of a harmonic-balance solution.
fn accuracy(r: &liu2021::HbmResponse) -> (f64, f64) {
    (r.solution.residual_norm, r.solution.truncation)
}

/// The cost and accuracy columns of a row with one time run and one (paper-basis) HBM
/// solution, after the row's own columns: the run's step statistics, then the solution's
/// residual norm and truncation indicator (values: [`run_cells`]).
const RUN_COLUMNS: [(&str, &str); 6] = [
    STEP_STATISTICS[0],
    STEP_STATISTICS[1],
    STEP_STATISTICS[2],
    STEP_STATISTICS[3],
    ("residual_norm_hbm", "1"),
    ("truncation_hbm", "1"),
];

/// The values of [`RUN_COLUMNS`].
fn run_cells(stats: &timestep::Stats, (residual, truncation): (f64, f64)) -> Vec<Cell> {
    let mut v = step_cells(stats).to_vec();
    v.extend([Cell::Num(residual), Cell::Num(truncation)]);
    v
}

/// `own` columns followed by `more` (a table's column list from parts).
fn columns<'a>(own: &[(&'a str, &'a str)], more: &[(&'a str, &'a str)]) -> Vec<(&'a str, &'a str)> {
    own.iter().chain(more).copied().collect()
}

impl Point {
    fn rsv(&self) -> u8 {
        self.time.rattle.state.rsv()
    }
    fn ppv(&self) -> f64 {
        self.time.rattle.ppv
    }
    /// `at x: reason` when the time reference is flagged.
    fn flag(&self) -> Option<String> {
        self.time.flag().map(|f| format!("at {}: {f}", sig(self.x)))
    }
}

/// Accessor of one HBM column of a [`Point`].
type HbKind = fn(&Point) -> HbmPoint;

const HBM_KINDS: [(&str, HbKind); 3] = [
    ("HBM paper basis, cold start", |p| p.cold),
    ("HBM paper basis, warm start", |p| p.warm),
    ("HBM full basis K=65, warm start", |p| p.full),
];

/// Solve a sweep with the library strategy.
fn sweep(xs: &[f64], set: impl Fn(&mut Parameters, f64)) -> Result<Vec<Point>, Error> {
    let params: Vec<Parameters> = xs
        .iter()
        .map(|&x| {
            let mut p = base();
            set(&mut p, x);
            p
        })
        .collect();
    let sol = liu2021::solve_sweep(&params, &strategy()).context("liu2021 sweep")?;
    Ok(xs
        .iter()
        .zip(sol)
        .map(|(&x, s)| Point {
            x,
            time: s.time,
            cold: s.cold,
            warm: s.warm,
            full: s.full.unwrap_or(s.warm),
            stats: s.response.stats,
            accuracy: [
                accuracy(&s.cold_solution),
                accuracy(&s.warm_solution),
                accuracy(s.full_solution.as_ref().unwrap_or(&s.warm_solution)),
            ],
        })
        .collect())
}

/// A threshold read from the time-integration points, with the flags of the points it rests
/// on (every point up to and including the first one that meets the condition).
struct Threshold {
    x: f64,
    flags: Vec<String>,
}

/// First x where the time-integration rsv satisfies `cond`; NaN if none (then every point's
/// flag counts).
fn first_time(pts: &[Point], cond: impl Fn(&Point) -> bool) -> Threshold {
    let idx = pts.iter().position(&cond);
    let upto = idx.map_or(pts.len(), |i| i + 1);
    Threshold {
        x: idx.map_or(f64::NAN, |i| pts[i].x),
        flags: pts[..upto].iter().filter_map(Point::flag).collect(),
    }
}

fn first_at_least(pts: &[Point], rsv: u8) -> Threshold {
    first_time(pts, |p| p.rsv() >= rsv)
}

/// First x where the HBM column of `kind` is usable (converged, stable) and meets `cond`.
fn first_hbm(pts: &[Point], kind: HbKind, cond: impl Fn(&HbmPoint) -> bool) -> f64 {
    pts.iter()
        .find(|p| kind(p).flag().is_none() && cond(&kind(p)))
        .map_or(f64::NAN, |p| p.x)
}

/// "n/N converged (m via a neighbour), u unstable".
fn converged_note(pts: &[Point], kind: HbKind) -> String {
    let n = pts.iter().filter(|p| kind(p).converged).count();
    let m = pts
        .iter()
        .filter(|p| kind(p).origin == liu2021::HbmOrigin::Neighbour)
        .count();
    let u = pts
        .iter()
        .filter(|p| kind(p).stable() == Some(false))
        .count();
    format!(
        "{n}/{} converged, {m} of them via a neighbour, {u} unstable; only converged stable points used",
        pts.len()
    )
}

/// Flags of the points, each `at x: reason`.
fn flags_of<'a>(pts: impl IntoIterator<Item = &'a Point>) -> Vec<String> {
    pts.into_iter().filter_map(Point::flag).collect()
}

/// The ±5 rad/s of the speed thresholds: the text's round numbers (150, 170) on a 10 rad/s
/// resolution.
fn speed_tolerance(printed: &str) -> Tolerance {
    Tolerance::round_number(printed, 10.0, "rad/s")
}

fn flag01(b: bool) -> f64 {
    if b { 1.0 } else { 0.0 }
}

fn sweep_table(name: &str, x: (&str, &str), pts: &[Point]) -> Result<Table, Error> {
    let own = [
        x,
        ("rsv_time", "1"),
        ("ppv_time", "1"),
        ("time_motion_period", "1"),
        ("time_reproducible_100x", "1"),
        ("time_flag", "-"),
        ("rsv_hbm", "1"),
        ("ppv_hbm", "1"),
        ("hbm_converged", "1"),
        ("rsv_hbm_warm", "1"),
        ("ppv_hbm_warm", "1"),
        ("hbm_warm_converged", "1"),
        ("hbm_warm_stable", "1"),
        ("rsv_hbm_full", "1"),
        ("ppv_hbm_full", "1"),
        ("hbm_full_converged", "1"),
        ("hbm_full_stable", "1"),
    ];
    let mut cols = columns(&own, &RUN_COLUMNS);
    cols.extend([
        ("residual_norm_hbm_warm", "1"),
        ("truncation_hbm_warm", "1"),
        ("residual_norm_hbm_full", "1"),
        ("truncation_hbm_full", "1"),
    ]);
    let mut t = Table::new(name, &cols);
    for p in pts {
        let mut row: Vec<Cell> = vec![
            p.x.into(),
            f64::from(p.rsv()).into(),
            p.ppv().into(),
            f64::from(p.time.motion.period_multiple()).into(),
            flag01(p.time.reproducible).into(),
            p.time.flag().unwrap_or_default().into(),
            f64::from(p.cold.rattle.state.rsv()).into(),
            p.cold.rattle.ppv.into(),
            flag01(p.cold.converged).into(),
            f64::from(p.warm.rattle.state.rsv()).into(),
            p.warm.rattle.ppv.into(),
            flag01(p.warm.converged).into(),
            p.warm.stable().map_or(f64::NAN, flag01).into(),
            f64::from(p.full.rattle.state.rsv()).into(),
            p.full.rattle.ppv.into(),
            flag01(p.full.converged).into(),
            p.full.stable().map_or(f64::NAN, flag01).into(),
        ];
        row.extend(run_cells(&p.stats, p.accuracy[0]));
        row.extend(
            p.accuracy[1..]
                .iter()
                .flat_map(|&(r, tr)| [Cell::Num(r), Cell::Num(tr)]),
        );
        t.push(row)?;
    }
    Ok(t)
}

/// Figures `<name>_rsv` and `<name>_ppv` (names distinct from the tables' names).
fn sweep_figures(out: &mut StudyOutput, name: &str, x: (&str, &str), pts: &[Point]) {
    let s = |f: &dyn Fn(&Point) -> f64| pts.iter().map(|p| (p.x, f(p))).collect::<Vec<_>>();
    let mut rsv = Figure::new(&format!("{name}_rsv"), "Rattle state", x, ("rsv", "1"))
        .with(Series::step("time integration", s(&|p| f64::from(p.rsv()))));
    let mut ppv = Figure::new(
        &format!("{name}_ppv"),
        "Peak-to-peak value of q",
        x,
        ("ppv", "1"),
    )
    .with(Series::line("time integration", s(&|p| p.ppv())));
    for (label, kind) in HBM_KINDS {
        rsv = rsv.with(Series::markers(
            label,
            s(&|p| f64::from(kind(p).rattle.state.rsv())),
        ));
        ppv = ppv.with(Series::markers(label, s(&|p| kind(p).rattle.ppv)));
    }
    out.figure(rsv);
    out.figure(ppv);
}

/// Relative ppv change below which a step is undecided: the ppv tolerance of the 100×
/// refinement (`SweepStrategy::ppv_rel_tol`), so round-off never settles a trend.
const PPV_STEP: f64 = 1e-3;

/// Trend of ppv over consecutive points: `Some(true)` if every step rises by more than
/// [`PPV_STEP`] relative, `Some(false)` if some step falls by more than that, `None` if a step
/// is within it (undecided) or there are fewer than two points.
fn ppv_rises(pts: &[Point]) -> Option<bool> {
    if pts.len() < 2 {
        return None;
    }
    let mut all_up = true;
    for w in pts.windows(2) {
        let d = w[1].ppv() - w[0].ppv();
        let scale = PPV_STEP * w[0].ppv().abs().max(w[1].ppv().abs());
        if d.abs() <= scale {
            return None;
        }
        all_up &= d > 0.0;
    }
    Some(all_up)
}

/// Verdict of a trend: pass/deviation, or inconclusive when undecided.
fn trend_verdict(t: Option<bool>) -> crate::Verdict {
    t.map_or(crate::Verdict::Inconclusive, crate::Verdict::from_bool)
}

/// "x₀…x₁: ppv a → b" for evidence.
fn span(pts: &[Point]) -> String {
    match (pts.first(), pts.last()) {
        (Some(a), Some(b)) => format!(
            "{}…{}: ppv {} → {} over {} points",
            sig(a.x),
            sig(b.x),
            sig(a.ppv()),
            sig(b.ppv()),
            pts.len()
        ),
        _ => "no points".to_owned(),
    }
}

/// The claim that ppv rises over `pts` (a contiguous run of one rattle regime).
fn rise_claim(text: &str, source: &str, what: &str, pts: &[Point]) -> crate::Claim {
    let t = ppv_rises(pts);
    crate::Claim::new(
        text,
        source,
        format!(
            "{what}, time integration {}; 'grows' read as every step rising by more than {} relative",
            span(pts),
            PPV_STEP
        ),
        trend_verdict(t),
    )
    .cause(if t.is_none() {
        "a step is within the 1e-3 ppv reproducibility, or the regime has fewer than two points"
    } else {
        "ppv trend of the time-integration reference over the regime"
    })
    .flagged_all(flags_of(pts))
}
