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
    self, BaseRadius, ErrorTerm, HbmPoint, LongWindowOptions, Model, Parameters, SweepStrategy,
    TimeReference,
};
use models::response::Robust;

use super::step_cells;
use crate::{
    Cell, Error, Figure, ResultExt, STEP_STATISTICS, Series, Study, StudyOutput, Table, Tolerance,
    fmt_sig,
};

mod basins;
mod continuation;
mod design_charts;
mod fig17;
mod load_sweep;
mod orbit_branch;
mod parameter_sweeps;
mod readings_thresholds;
mod responses;
mod speed_sweep;
mod table2;
pub(in crate::studies) use table2::fitted_slope;

/// The studies of the Liu paper, in report order.
pub fn studies() -> Vec<Study> {
    vec![
        table2::study(),
        fig17::study(),
        speed_sweep::study(),
        continuation::study(),
        orbit_branch::study(),
        responses::study(),
        load_sweep::study(),
        parameter_sweeps::study(),
        basins::study(),
        readings_thresholds::study(),
        design_charts::study(),
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
/// K = Z2 + 2 warm, neighbour continuation, stability, Poincaré motion type, 100× refinement)
/// plus the long-window statistics that judge every point ([`LongWindowOptions::default`]:
/// two windows of 50 periods, `rtol/100`, a second start).
fn strategy() -> SweepStrategy {
    SweepStrategy {
        long_window: Some(LongWindowOptions::default()),
        ..SweepStrategy::default()
    }
}

/// The swept value exactly as swept (shortest round-trip form: `162.5`, `0.000011`), so that
/// flags and evidence never make two points read the same.
fn at(x: f64) -> String {
    format!("{x}")
}

/// One sweep point: the swept value, the time reference and the three HBM columns, with the
/// step statistics of the reference run and the accuracy of each HBM solution.
#[derive(Debug, Clone)]
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
    /// Long-window statistics with their spread (the judged metrics).
    window: Option<Robust>,
    /// Per column of [`HBM_KINDS`]: the start of the column's solution is not a result
    /// ([`seed_chains`]): the warm start that anchors it — its own, or that of the point its
    /// neighbour continuation started from, followed back — was seeded from a motion not
    /// confirmed periodic or is not reproducible ([`HbmPoint::seed_reproducible`]).
    seed_unsettled: [bool; 3],
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

/// Relative spread over the long-window variants below which a window statistic is committed
/// ([`models::response::SETTLED`], the one definition shared with the user studies).
pub(super) use models::response::SETTLED;

/// Margin below which a periodic one-period classification is confirmed
/// ([`models::response::CONFIRMED`]; [`liu2021::TimeReference::section_margin`]).
pub(super) use models::response::CONFIRMED;

/// The ppv axis of the committed sweep figures: fixed, so that leaving out a point that does not
/// settle does not re-scale the drawing. It covers every computed ppv of the sweeps (largest
/// 2.9e-3, Fig. 12–14 a_k = 1.60).
const PPV_AXIS: (f64, f64) = (0.0, 3.0e-3);

/// The rsv axis (states 0, 1, 2) of the committed sweep figures, with a 3 % margin.
const RSV_AXIS: (f64, f64) = (-0.06, 2.06);

/// The one-period time reference is a sample of a non-periodic orbit, or its periodicity is not
/// confirmed with margin ([`CONFIRMED`]): its one-period values (ppv, spectrum) are samples.
fn unconfirmed(time: &liu2021::TimeReference) -> bool {
    !models::response::section_confirmed(time.motion, time.section_margin, CONFIRMED)
}

impl Point {
    /// The one-period time reference is a sample of a non-periodic orbit, or its periodicity
    /// is not confirmed with margin ([`CONFIRMED`]).
    fn time_unsettled(&self) -> bool {
        unconfirmed(&self.time)
    }
    /// The long-window statistics are samples: the window is not periodic in every variant, or
    /// its state or ppv moves over the variants by more than [`SETTLED`]
    /// ([`Robust::reproducible`]; without long windows: the one-period reference is
    /// unsettled).
    fn window_unsettled(&self) -> bool {
        self.window.as_ref().map_or(self.time_unsettled(), |w| {
            models::response::window_unsettled(w, SETTLED)
        })
    }
    /// The point's motion is not confirmed periodic: without a long window, the one-period
    /// reference is not confirmed periodic with margin; with one, in addition the window's
    /// section does not repeat in every variant or its state or ppv does not settle. The
    /// one-period classification columns (motion period, reproducibility, flag) and the warm
    /// starts seeded from the time response are committed only for a confirmed point: near a
    /// bifurcation the classification of the one-period sample flips under a solver retune.
    fn motion_unsettled(&self) -> bool {
        match &self.window {
            // both must hold: the one-period sample, which seeds the warm starts, is confirmed
            // periodic (its 6-period section can repeat by chance in a laminar phase of a
            // chaotic orbit, so it is not enough alone), and the 50-period window is periodic
            // in every variant (it is not enough alone either: near a bifurcation the 10-period
            // transient of the one-period sample has not decayed — Fig. 11, 170–237.5 rad/s;
            // Fig. 15, 4–21 N·m, where the long window settles only after discarding a window —
            // and a warm start from that sample reached the unilateral or the bilateral branch
            // depending on the step-size controller). A finer statistic (an impact speed) that
            // does not settle is withheld on its own and says nothing about which orbit a warm
            // start reaches.
            Some(w) => !w.regular() || self.window_unsettled() || self.time_unsettled(),
            None => self.time_unsettled(),
        }
    }
    /// An HBM column's values do not settle: the solver did not converge, or a warm start was
    /// seeded from the harmonics of a time response whose motion is not confirmed periodic, or
    /// the same warm start from the refined reference reaches another solution
    /// ([`HbmPoint::seed_reproducible`]): which of the coexisting solutions it reaches depends
    /// on that sample.
    /// A neighbour continuation inherits this from the warm start it was continued from
    /// ([`seed_chains`]). `col` indexes [`HBM_KINDS`].
    fn hbm_unsettled(&self, col: usize) -> bool {
        !(HBM_KINDS[col].1)(self).converged || self.seed_unsettled[col]
    }
    /// The judgement of this point's own sample as a seed of the warm column `h`: the motion
    /// that seeds it is not confirmed periodic, or the warm start from the refined reference
    /// has another outcome.
    fn own_seed_unsettled(&self, h: &HbmPoint) -> bool {
        self.motion_unsettled() || h.seed_reproducible == Some(false)
    }
    /// The judged rattle state: over the long window (all periods), else the one-period one.
    fn rsv(&self) -> u8 {
        self.window
            .as_ref()
            .map_or(self.time.rattle.state.rsv(), |w| w.nominal.state.rsv())
    }
    /// `[lo, hi]` of the rsv over the long-window variants.
    fn rsv_range(&self) -> (u8, u8) {
        self.window
            .as_ref()
            .map_or((self.rsv(), self.rsv()), Robust::rsv_interval)
    }
    /// The judged ppv for evidence text: [`sig`], as an unsettled span when it does not
    /// settle over the variants ([`Point::window_unsettled`]).
    fn ppv_text(&self) -> String {
        sig_u(self.ppv(), self.window_unsettled())
    }
    /// The judged ppv: over the long window, else over the one recorded period.
    fn ppv(&self) -> f64 {
        self.window
            .as_ref()
            .map_or(self.time.rattle.ppv, |w| w.nominal.ppv)
    }
    /// `[lo, hi]` of the long-window ppv over the variants.
    fn ppv_range(&self) -> (f64, f64) {
        self.window
            .as_ref()
            .map_or((self.ppv(), self.ppv()), |w| w.interval(|s| s.ppv))
    }
    /// `at x: reason` when the point cannot carry a rattle-state verdict: the long-window state
    /// differs between the variants (two tolerances, two windows, two starts). Without long
    /// windows: the one-period time reference's flag.
    fn flag(&self) -> Option<String> {
        match &self.window {
            None => self.time.flag().map(|f| format!("at {}: {f}", at(self.x))),
            Some(w) if w.state().is_none() => {
                let (lo, hi) = w.rsv_interval();
                Some(format!(
                    "at {}: long-window rattle state not robust (rsv {lo}–{hi} over the variants; fractions in validation/stats/)",
                    at(self.x),
                ))
            }
            Some(_) => None,
        }
    }
    /// `at x: reason` when the long-window ppv moves over the variants by more than `margin`
    /// (relative): the claim's own margin decides whether the spread matters.
    fn ppv_flag(&self, margin: f64) -> Option<String> {
        let w = self.window.as_ref()?;
        (w.ppv_spread() > margin).then(|| {
            format!(
                "at {}: long-window ppv moves by {} over the variants, more than the claim's margin {}",
                at(self.x),
                crate::unsettled(format!(
                    "order {}",
                    models::response::order_of_magnitude(w.ppv_spread())
                )),
                sig(margin)
            )
        })
    }
}

/// `sig(x)` for evidence text, as an unsettled span ([`crate::unsettled`]) when it is computed
/// from a value that does not settle: written in full to validation/stats/, not committed.
fn sig_u(x: f64, unsettled: bool) -> String {
    if unsettled {
        crate::unsettled(sig(x))
    } else {
        sig(x)
    }
}

/// Some point of `pts` has a judged ppv that does not settle ([`Point::window_unsettled`]).
fn any_unsettled<'a>(pts: impl IntoIterator<Item = &'a Point>) -> bool {
    pts.into_iter().any(Point::window_unsettled)
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
    Ok(seed_chains(
        xs.iter()
            .zip(sol)
            .map(|(&x, s)| Point {
                x,
                window: s.window.clone(),
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
                seed_unsettled: [false; 3],
            })
            .collect(),
    ))
}

/// Fill [`Point::seed_unsettled`]: for each warm column, follow every point's neighbour
/// continuation back to the warm start that anchors it ([`HbmPoint::neighbour`]) and judge
/// that anchor's sample ([`Point::own_seed_unsettled`]). A chain is anchored at one point and
/// carries its solution along the sweep: seeded from a chaotic sample, it moves under any
/// solver retune at every point it reaches, although each of those points is itself
/// confirmed periodic. The walk is bounded by the number of points (a chain never revisits a
/// point; a longer walk or a missing index counts as unsettled).
fn seed_chains(mut pts: Vec<Point>) -> Vec<Point> {
    let flags: Vec<[bool; 3]> = (0..pts.len())
        .map(|i| {
            let mut f = [false; 3];
            for (col, flag) in f.iter_mut().enumerate().skip(1) {
                *flag = anchor(&pts, i, col)
                    .is_none_or(|k| pts[k].own_seed_unsettled(&(HBM_KINDS[col].1)(&pts[k])));
            }
            f
        })
        .collect();
    for (p, f) in pts.iter_mut().zip(flags) {
        p.seed_unsettled = f;
    }
    pts
}

/// The index of the point whose own start anchors the solution of column `col` at point `i`
/// (the neighbour continuation followed back, [`HbmPoint::neighbour`]); `None` for a broken
/// chain (a missing or out-of-range index, or a walk longer than the sweep: a chain never
/// revisits a point, so the walk ends).
fn anchor(pts: &[Point], i: usize, col: usize) -> Option<usize> {
    let kind = HBM_KINDS[col].1;
    let n = pts.len();
    let mut k = i;
    for _ in 0..=n {
        let h = kind(&pts[k]);
        match (h.origin, h.neighbour) {
            (liu2021::HbmOrigin::Neighbour, Some(j)) if j < n => k = j,
            (liu2021::HbmOrigin::Neighbour, _) => return None,
            _ => return Some(k),
        }
    }
    None
}

/// Table `<name>_seeds`: for each warm column, where its solution started (its own time
/// response or a neighbour), whether the start is reproducible, the swept value of the point
/// whose sample anchors the chain and that sample's section margin and judgement. Diagnostics
/// of [`Point::seed_unsettled`], written to `validation/stats/` only: they name why a warm
/// column is or is not committed.
fn seeds_table(name: &str, x: (&str, &str), pts: &[Point]) -> Result<Table, Error> {
    let mut cols = vec![x];
    let names: [[&str; 6]; 2] = [
        [
            "warm_from_neighbour",
            "warm_converged",
            "warm_seed_reproducible",
            "warm_anchor",
            "warm_anchor_section_margin",
            "warm_unsettled",
        ],
        [
            "full_from_neighbour",
            "full_converged",
            "full_seed_reproducible",
            "full_anchor",
            "full_anchor_section_margin",
            "full_unsettled",
        ],
    ];
    for c in names.iter().flatten() {
        cols.push((c, "1"));
    }
    let mut t = Table::new(&format!("{name}_seeds"), &cols);
    for (i, p) in pts.iter().enumerate() {
        let mut row: Vec<Cell> = vec![p.x.into()];
        for col in 1..3 {
            let h = (HBM_KINDS[col].1)(p);
            let a = anchor(pts, i, col);
            row.extend([
                flag01(h.origin == liu2021::HbmOrigin::Neighbour).into(),
                flag01(h.converged).into(),
                h.seed_reproducible.map_or(f64::NAN, flag01).into(),
                a.map_or(f64::NAN, |k| pts[k].x).into(),
                a.map_or(f64::NAN, |k| pts[k].time.section_margin).into(),
                flag01(p.seed_unsettled[col]).into(),
            ]);
        }
        t.push(row)?;
    }
    Ok(t.unsettled_record(
        "diagnostics of the warm starts (origin, reproducibility, the anchoring sample of each neighbour chain)",
    ))
}

/// A threshold on a swept parameter: the first grid point that meets the condition, the
/// interval that contains the onset (bisected below the grid step, widened over the readings
/// and definitions that evidence has not decided), the swept points it rests on and the flags
/// of those points only (claim-local).
struct Threshold {
    /// The first grid point that meets the condition (NaN if none).
    x: f64,
    /// The onset interval `[lo, hi]` (NaN if no onset in the sweep).
    lo: f64,
    hi: f64,
    /// The swept values the threshold rests on: the last grid point before the onset and the
    /// first at it.
    needs: Vec<f64>,
    /// Flags of the needed points.
    flags: Vec<String>,
    /// How the interval was found (bisection steps, variants, reasons for its width).
    note: String,
    /// The interval rests on a state that is not robust over the variants (a bisection stopped
    /// at one, or no robust bracket was found): which midpoints are robust can change under a
    /// solver retune, so `[lo, hi]` is committed as unsettled.
    unsettled: bool,
}

/// First grid point whose judged (long-window) rsv satisfies `cond`; the grid bracket
/// `[x_{i−1}, x_i]` is the interval until [`refine`] narrows it. Only the two bracketing points
/// are needed, so only their flags count.
fn first_time(pts: &[Point], cond: impl Fn(&Point) -> bool) -> Threshold {
    match pts.iter().position(&cond) {
        // no onset: a robust absence is a result (deviation); only the points whose state is
        // not robust could hide one, so only their flags count
        None => Threshold {
            x: f64::NAN,
            lo: f64::NAN,
            hi: f64::NAN,
            needs: pts.iter().map(|p| p.x).collect(),
            flags: flags_of(pts),
            note: "no onset in the sweep".to_owned(),
            unsettled: false,
        },
        Some(i) => {
            let from = i.saturating_sub(1);
            let used = &pts[from..=i];
            Threshold {
                x: pts[i].x,
                lo: pts[from].x,
                hi: pts[i].x,
                needs: used.iter().map(|p| p.x).collect(),
                flags: flags_of(used),
                note: format!(
                    "grid bracket [{}, {}]",
                    crate::fmt_sig(pts[from].x, 6),
                    crate::fmt_sig(pts[i].x, 6)
                ),
                unsettled: false,
            }
        }
    }
}

fn first_at_least(pts: &[Point], rsv: u8) -> Threshold {
    first_time(pts, |p| p.rsv() >= rsv)
}

/// Minimum separation depth of the second rattle definition: a separation from the drive flank
/// deeper than 1 % of b̄ (the model's 135 rad/s onset rests on 0.11 % of b̄; 1 % is about the
/// line width of the paper's time-series figures, whose q axis spans several b̄).
const MIN_DEPTH: f64 = 0.01;

/// Bisection steps below the grid: each halves the bracket (2 steps: a 2.5 rad/s grid gives
/// 0.625 rad/s, below the 10 rad/s resolution of the text's round numbers).
const BISECTION_STEPS: usize = 2;

/// Grid steps a variant's bracket may move out of the nominal one before the search gives up.
const WIDEN_STEPS: usize = 4;

/// Whether the long-window rsv range `(lo, hi)` meets a condition on rsv: `Some(true)` when
/// both ends do, `Some(false)` when neither does, `None` when the variants disagree.
fn meets(range: (u8, u8), cond: fn(u8) -> bool) -> Option<bool> {
    match (cond(range.0), cond(range.1)) {
        (true, true) => Some(true),
        (false, false) => Some(false),
        _ => None,
    }
}

/// Narrow a grid threshold by bisection on the long-window rattle state and widen it over the
/// undecided readings: the error-term sign of Eq. (21) (R-LIU-EQ21) and, when `depth_matters`,
/// the rattle definition (any separation, or deeper than [`MIN_DEPTH`]·b̄). `set` applies the
/// swept value, `step` is the grid step, `cond` the condition on rsv.
fn refine(
    th: Threshold,
    set: &dyn Fn(&mut Parameters, f64),
    step: f64,
    cond: fn(u8) -> bool,
    depth_matters: bool,
) -> Result<Threshold, Error> {
    if !(th.lo.is_finite() && th.hi.is_finite()) || th.lo >= th.hi {
        return Ok(th);
    }
    let mut variants = vec![
        (
            "error term as derived, any separation",
            ErrorTerm::Derived,
            0.0,
        ),
        ("printed Eq. (21) sign", ErrorTerm::Printed, 0.0),
    ];
    if depth_matters {
        variants.push((
            "separation deeper than 1 % of b̄",
            ErrorTerm::Derived,
            MIN_DEPTH,
        ));
    }
    let mut lo_all = f64::INFINITY;
    let mut hi_all = f64::NEG_INFINITY;
    let mut notes = Vec::new();
    let mut unsettled = false;
    for (label, error_term, min_depth) in variants {
        let eval = |x: f64| -> Result<Option<bool>, Error> {
            let mut p = base();
            set(&mut p, x);
            p.readings.error_term = error_term;
            let m = model(&p)?;
            let o = LongWindowOptions {
                min_depth,
                ..LongWindowOptions::default()
            };
            let r = liu2021::long_window(&m, &o).context("liu2021 long window")?;
            Ok(meets(r.rsv_interval(), cond))
        };
        // bracket: condition false (robustly) at a, true at b
        let (mut a, mut b) = (th.lo, th.hi);
        let mut ok = true;
        let mut widened = 0;
        while eval(a)? != Some(false) {
            if widened == WIDEN_STEPS {
                ok = false;
                break;
            }
            a -= step;
            widened += 1;
        }
        let mut widened = 0;
        while ok && eval(b)? != Some(true) {
            if widened == WIDEN_STEPS {
                ok = false;
                break;
            }
            b += step;
            widened += 1;
        }
        if !ok {
            unsettled = true;
            notes.push(format!(
                "{label}: no robust bracket within {WIDEN_STEPS} grid steps, interval [{}, {}]",
                crate::fmt_sig(a, 6),
                crate::fmt_sig(b, 6)
            ));
            lo_all = lo_all.min(a);
            hi_all = hi_all.max(b);
            continue;
        }
        let mut stop = None;
        for _ in 0..BISECTION_STEPS {
            let mid = 0.5 * (a + b);
            match eval(mid)? {
                Some(true) => b = mid,
                Some(false) => a = mid,
                None => {
                    stop = Some(mid);
                    break;
                }
            }
        }
        unsettled |= stop.is_some();
        notes.push(match stop {
            Some(m) => format!(
                "{label}: [{}, {}] (state not robust at {})",
                crate::fmt_sig(a, 6),
                crate::fmt_sig(b, 6),
                crate::fmt_sig(m, 6)
            ),
            None => format!(
                "{label}: [{}, {}]",
                crate::fmt_sig(a, 6),
                crate::fmt_sig(b, 6)
            ),
        });
        lo_all = lo_all.min(a);
        hi_all = hi_all.max(b);
    }
    Ok(Threshold {
        lo: lo_all,
        hi: hi_all,
        note: format!(
            "{}; bisected on the long-window rattle state ({} steps) under each variant: {}",
            th.note,
            BISECTION_STEPS,
            // the per-variant intervals move with the robustness of the midpoints
            if unsettled {
                crate::unsettled(notes.join("; "))
            } else {
                notes.join("; ")
            }
        ),
        unsettled,
        ..th
    })
}

/// First x where the HBM column of `kind` is usable (converged, stable) and meets `cond`.
/// The first swept value whose usable HBM solution of column `i` of [`HBM_KINDS`] meets
/// `cond` (NaN: none), and whether it is unsettled: a point up to it does not settle
/// ([`Point::hbm_unsettled`]), so which point comes first can change under a solver retune.
fn first_hbm(pts: &[Point], i: usize, cond: impl Fn(&HbmPoint) -> bool) -> (f64, bool) {
    let kind = HBM_KINDS[i].1;
    let found = pts
        .iter()
        .position(|p| kind(p).flag().is_none() && cond(&kind(p)));
    let upto = found.map_or(pts.len(), |j| j + 1);
    let unsettled = pts[..upto].iter().any(|p| p.hbm_unsettled(i));
    (found.map_or(f64::NAN, |j| pts[j].x), unsettled)
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
    // the counts move with the warm starts near bifurcations: full text in validation/stats/
    format!(
        "{}; only converged stable points used",
        crate::unsettled(format!(
            "{n}/{} converged, {m} of them via a neighbour, {u} unstable",
            pts.len()
        ))
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
    let mut cols = columns(&own, &Robust::COLUMNS);
    cols.extend(RUN_COLUMNS);
    cols.extend([
        ("residual_norm_hbm_warm", "1"),
        ("truncation_hbm_warm", "1"),
        ("residual_norm_hbm_full", "1"),
        ("truncation_hbm_full", "1"),
        ("section_margin_time", "1"),
    ]);
    let mut t = Table::new(name, &cols);
    for p in pts {
        let tu = p.time_unsettled();
        let (cu, wu, fu) = (p.hbm_unsettled(0), p.hbm_unsettled(1), p.hbm_unsettled(2));
        let cell = Cell::settled_if;
        // the one-period classification (motion period, reproducibility, flag) is a diagnostic
        // of the one-period reference where a long window judges the point: its period
        // detector flips under a solver retune even where the long window agrees to 6 digits
        // (docs/examples/validate-diff.md, round 8), so it is committed only without a window
        let mu = p.motion_unsettled() || p.window.is_some();
        let flag = p.time.flag().unwrap_or_default();
        let mut row: Vec<Cell> = vec![
            p.x.into(),
            cell(f64::from(p.rsv()), p.window.is_none() && tu),
            cell(p.ppv(), p.window_unsettled()),
            cell(f64::from(p.time.motion.period_multiple()), mu),
            cell(flag01(p.time.reproducible), mu),
            // an empty flag is as unsettled as a text: it flips with the classification
            if mu { crate::unsettled(flag) } else { flag }.into(),
            cell(f64::from(p.cold.rattle.state.rsv()), cu),
            cell(p.cold.rattle.ppv, cu),
            flag01(p.cold.converged).into(),
            cell(f64::from(p.warm.rattle.state.rsv()), wu),
            cell(p.warm.rattle.ppv, wu),
            // whether a start seeded from an unconfirmed sample converges depends on the sample
            cell(flag01(p.warm.converged), p.seed_unsettled[1]),
            cell(p.warm.stable().map_or(f64::NAN, flag01), wu),
            cell(f64::from(p.full.rattle.state.rsv()), fu),
            cell(p.full.rattle.ppv, fu),
            cell(flag01(p.full.converged), p.seed_unsettled[2]),
            cell(p.full.stable().map_or(f64::NAN, flag01), fu),
        ];
        let window = p
            .window
            .as_ref()
            .map_or([f64::NAN; Robust::COLUMNS.len()], Robust::values);
        // each window column only when it settles over the variants (the state columns when
        // every variant agrees on the state)
        let settled = p
            .window
            .as_ref()
            .map_or([false; Robust::COLUMNS.len()], |w| {
                w.settled_columns(SETTLED)
            });
        row.extend(
            window
                .iter()
                .zip(settled)
                .map(|(&x, s)| cell(x, !s && x.is_finite())),
        );
        row.extend(run_cells(&p.stats, p.accuracy[0]));
        row.extend(
            p.accuracy[1..]
                .iter()
                .flat_map(|&(r, tr)| [Cell::Num(r), Cell::Num(tr)]),
        );
        row.push(Cell::Num(p.time.section_margin));
        t.push(row)?;
    }
    Ok(t)
}

/// Figures `<name>_rsv` and `<name>_ppv` (names distinct from the tables' names).
fn sweep_figures(out: &mut StudyOutput, name: &str, x: (&str, &str), pts: &[Point]) {
    let s = |f: &dyn Fn(&Point) -> f64| pts.iter().map(|p| (p.x, f(p))).collect::<Vec<_>>();
    let u = |f: &dyn Fn(&Point) -> bool| pts.iter().map(f).collect::<Vec<_>>();
    let robust = |p: &Point| p.window.as_ref().map(|w| w.state().is_some());
    // fixed axes: the swept range (inputs) and the fixed rsv/ppv axes, so that the committed
    // drawing does not re-scale when a point leaves it
    let (x0, x1) = pts
        .iter()
        .map(|p| p.x)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    let pad = 0.03 * (x1 - x0);
    let xr = (x0 < x1).then_some((x0 - pad, x1 + pad));
    let mut rsv = Figure::new(&format!("{name}_rsv"), "Rattle state", x, ("rsv", "1"))
        .ranges(xr, Some(RSV_AXIS))
        .with(
            Series::step("time integration", s(&|p| f64::from(p.rsv())))
                .unsettled(u(&|p| robust(p).map_or(p.time_unsettled(), |r| !r))),
        );
    let mut ppv = Figure::new(
        &format!("{name}_ppv"),
        "Peak-to-peak value of q",
        x,
        ("ppv", "1"),
    )
    .ranges(xr, Some(PPV_AXIS))
    .with(Series::line("time integration", s(&|p| p.ppv())).unsettled(u(&Point::window_unsettled)));
    for (i, (label, kind)) in HBM_KINDS.into_iter().enumerate() {
        let unsettled = u(&|p| p.hbm_unsettled(i));
        rsv = rsv.with(
            Series::markers(label, s(&|p| f64::from(kind(p).rattle.state.rsv())))
                .unsettled(unsettled.clone()),
        );
        ppv = ppv.with(Series::markers(label, s(&|p| kind(p).rattle.ppv)).unsettled(unsettled));
    }
    out.figure(rsv);
    out.figure(ppv);
}

/// Least-squares slope of the judged ppv against the swept value, and its standard error:
/// the residual scatter plus the ppv spread of each point over its long-window variants
/// (half the range, as a measurement error of each point) propagated into the slope.
/// `None` with fewer than three points or a degenerate abscissa.
fn ppv_slope(pts: &[Point]) -> Option<(f64, f64)> {
    ppv_slope_by(pts, &Point::ppv)
}

/// [`ppv_slope`] of the ppv that `ppv` reads from each point (a variant's, [`ppv_of`]); the
/// measurement term is the points' spread over all variants either way.
fn ppv_slope_by(pts: &[Point], ppv: &dyn Fn(&Point) -> f64) -> Option<(f64, f64)> {
    let n = pts.len();
    if n < 3 {
        return None;
    }
    let nf = n as f64;
    let mx = pts.iter().map(|p| p.x).sum::<f64>() / nf;
    let my = pts.iter().map(ppv).sum::<f64>() / nf;
    let sxx: f64 = pts.iter().map(|p| (p.x - mx).powi(2)).sum();
    if sxx <= 0.0 || !sxx.is_finite() {
        return None;
    }
    let sxy: f64 = pts.iter().map(|p| (p.x - mx) * (ppv(p) - my)).sum();
    let slope = sxy / sxx;
    let rss: f64 = pts
        .iter()
        .map(|p| (ppv(p) - my - slope * (p.x - mx)).powi(2))
        .sum();
    let measurement: f64 = pts
        .iter()
        .map(|p| {
            let (lo, hi) = p.ppv_range();
            (p.x - mx).powi(2) * (0.5 * (hi - lo)).powi(2)
        })
        .sum::<f64>()
        / (sxx * sxx);
    let se = (rss / (nf - 2.0) / sxx + measurement).sqrt();
    Some((slope, se))
}

/// Smallest rise over a regime that a "grows" claim can mean: 5 % of the regime's mean ppv,
/// about the line width of the paper's ppv figures (Fig. 11b–15b span several times the ppv of a
/// regime), fixed before looking at the model's slopes.
const MIN_RISE: f64 = 0.05;

/// Trend of ppv over `pts` judged by the fitted slope against its standard error:
/// `Some(true)` for a rise (slope ≥ 2 SE), `Some(false)` when even the slope plus 2 SE gives a
/// rise over the regime below [`MIN_RISE`] of its mean ppv (robustly no visible growth, or a
/// fall), `None` in between or with fewer than three points.
fn ppv_rises(pts: &[Point]) -> Option<bool> {
    ppv_rises_by(pts, &Point::ppv)
}

/// [`ppv_rises`] of the ppv that `ppv` reads from each point.
fn ppv_rises_by(pts: &[Point], ppv: &dyn Fn(&Point) -> f64) -> Option<bool> {
    let (slope, se) = ppv_slope_by(pts, ppv)?;
    let (first, last) = (pts.first()?.x, pts.last()?.x);
    let span = (last - first).abs();
    let mean = pts.iter().map(ppv).sum::<f64>() / pts.len() as f64;
    if slope >= 2.0 * se && slope > 0.0 {
        Some(true)
    } else if (slope + 2.0 * se) * span < MIN_RISE * mean.abs() {
        Some(false)
    } else {
        None
    }
}

/// The long-window ppv of `p` in variant `k` (0: the nominal window; `k ≥ 1`: the `k`-th
/// variant, or the nominal where the point has fewer); without a long window, the time
/// reference's for every `k`.
fn ppv_of(p: &Point, k: usize) -> f64 {
    match &p.window {
        None => p.time.rattle.ppv,
        Some(w) if k == 0 => w.nominal.ppv,
        Some(w) => w.variants.get(k - 1).map_or(w.nominal.ppv, |(_, s)| s.ppv),
    }
}

/// [`ppv_rises`] on the nominal windows, kept only where every long-window variant's series
/// (each point's ppv under the same variant: the second window, rtol/100, the other start)
/// gives the same trend; `(trend, split)` with `split` true when some variant gives another
/// (the trend is then `None`: a solver retune could move the verdict).
fn ppv_rises_robust(pts: &[Point]) -> (Option<bool>, bool) {
    let t = ppv_rises(pts);
    let variants = pts
        .iter()
        .filter_map(|p| p.window.as_ref().map(|w| w.variants.len()))
        .max()
        .unwrap_or(0);
    let split = (1..=variants).any(|k| ppv_rises_by(pts, &|p| ppv_of(p, k)) != t);
    (if split { None } else { t }, split)
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
            at(a.x),
            at(b.x),
            a.ppv_text(),
            b.ppv_text(),
            pts.len()
        ),
        _ => "no points".to_owned(),
    }
}

/// The claim that ppv rises over `pts` (a contiguous run of one rattle regime), judged by the
/// fitted slope against its standard error ([`ppv_rises`]), and only where every long-window
/// variant's ppv gives the same reading ([`ppv_rises_robust`]); every point of the run is
/// needed.
fn rise_claim(text: &str, source: &str, what: &str, pts: &[Point]) -> crate::Claim {
    // only robust points enter the fit (state the same under every variant, ppv within 50 %)
    let (robust, dropped): (Vec<Point>, Vec<Point>) = pts
        .iter()
        .cloned()
        .partition(|p| p.flag().is_none() && p.ppv_flag(0.5).is_none());
    let (t, split) = ppv_rises_robust(&robust);
    // the fitted numbers move with any point whose ppv does not settle
    let u = any_unsettled(&robust);
    let mut fit = ppv_slope(&robust).map_or(
        "no fit (fewer than three robust points)".to_owned(),
        |(b, se)| format!("fitted slope {} ± {} (1 SE)", sig_u(b, u), sig_u(se, u)),
    );
    if !dropped.is_empty() {
        fit.push_str(&format!(
            " over the robust points; not robust, left out: {}",
            dropped
                .iter()
                .map(|p| at(p.x))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    crate::Claim::new(
        text,
        source,
        format!(
            "{what}, long-window ppv {}; {fit}; 'grows' read as a slope of at least 2 SE, 'no growth' as a rise (slope + 2 SE) over the regime below {} % of its mean ppv",
            span(pts),
            sig(100.0 * MIN_RISE)
        ),
        trend_verdict(t),
    )
    .cause(if split {
        "the trend differs between the long-window variants (second window, rtol/100, other start): fitted over one variant's ppv the slope gives another reading than over the nominal's, so a solver retune could move the verdict"
    } else if t.is_none() {
        "the fitted ppv slope is within 2 standard errors of zero while a visible rise cannot be excluded, or the regime has fewer than three robust points"
    } else {
        "fitted ppv slope of the long-window statistics over the robust points of the regime"
    })
    .needs(pts.iter().map(|p| p.x))
}

/// An "always" / "throughout" claim on the rattle state over `pts`: `(holds, flags)`. A robust
/// counterexample (a point whose long-window state is the same under every variant and fails
/// `want`) refutes it without flags; otherwise the non-robust points whose variants could
/// fail `want` are the flags (inconclusive), and the claim holds when there are none.
fn always(pts: &[Point], want: impl Fn(u8) -> bool) -> (bool, Vec<String>) {
    if pts.iter().any(|p| p.flag().is_none() && !want(p.rsv())) {
        return (false, Vec::new());
    }
    let flags = pts
        .iter()
        .filter(|p| {
            let (lo, hi) = p.rsv_range();
            !(want(lo) && want(hi))
        })
        .filter_map(Point::flag)
        .collect();
    (true, flags)
}

#[cfg(test)]
mod tests {
    use super::*;
    use models::liu2021::{HbmOrigin, Motion, Rattle, RattleState};

    fn point(motion: Motion, section_margin: f64) -> Point {
        let r = Rattle {
            state: RattleState::Bilateral,
            ppv: 2e-3,
            q_min: -1e-3,
            q_max: 1e-3,
        };
        let h = HbmPoint {
            rattle: r,
            converged: true,
            origin: HbmOrigin::TimeResponse,
            max_multiplier: Some(0.5),
            seed_reproducible: Some(true),
            neighbour: None,
        };
        Point {
            x: 200.0,
            time: TimeReference {
                rattle: r,
                motion,
                section_margin,
                refined: r,
                reproducible: true,
                stats: timestep::Stats::default(),
            },
            cold: h,
            warm: h,
            full: h,
            stats: timestep::Stats::default(),
            accuracy: [(0.0, 0.0); 3],
            window: None,
            seed_unsettled: [false; 3],
        }
    }

    /// Points at x = 0, 1, …, 4 whose long windows have the nominal ppv `nominal[i]` and three
    /// variants with `variant(k, i)`.
    fn windowed(nominal: [f64; 5], variant: impl Fn(usize, usize) -> f64) -> Vec<Point> {
        use math::DetMath;
        use models::response::{WindowOptions, window_stats};
        let t: Vec<f64> = (0..=400).map(|i| f64::from(i) * 0.05).collect();
        let q: Vec<f64> = t.iter().map(|&t| -2.0 + 0.1 * t.dsin()).collect();
        let v: Vec<f64> = t.iter().map(|&t| 0.1 * t.dcos()).collect();
        let o = WindowOptions::new(std::f64::consts::TAU);
        let base = window_stats(&t, &q, &v, |_| 1.0, &[], &o).unwrap();
        let with = |ppv: f64| models::response::WindowStats { ppv, ..base };
        (0..5)
            .map(|i| {
                let mut p = point(Motion::Periodic(1), 0.0);
                p.x = i as f64;
                p.window = Some(models::response::Robust {
                    nominal: with(nominal[i]),
                    variants: (1..=3)
                        .map(|k| (format!("variant {k}"), with(variant(k, i))))
                        .collect(),
                });
                p
            })
            .collect()
    }

    /// A ppv trend is read only where every long-window variant reads it: a clear rise in the
    /// nominal windows and every variant passes; one variant whose series is flat splits it
    /// (no reading, flagged as split), and the claim is inconclusive.
    #[test]
    fn a_trend_is_read_only_where_every_variant_reads_it() {
        let rise = [1.0, 1.2, 1.4, 1.6, 1.8];
        let pts = windowed(rise, |_, i| rise[i]);
        assert_eq!(ppv_rises(&pts), Some(true));
        assert_eq!(ppv_rises_robust(&pts), (Some(true), false));
        // variant 2 nearly flat (1.000 → 1.004): over it the slope reads no rise
        let pts = windowed(rise, |k, i| {
            if k == 2 {
                1.0 + 0.001 * i as f64
            } else {
                rise[i]
            }
        });
        let (t, split) = ppv_rises_robust(&pts);
        assert_ne!(ppv_rises_by(&pts, &|p| ppv_of(p, 2)), ppv_rises(&pts));
        assert_eq!((t, split), (None, true));
        let c = rise_claim("ppv rises", "test", "x", &pts);
        assert_eq!(c.verdict, crate::Verdict::Inconclusive);
        // no windows: the time reference's ppv for every variant, never split
        let mut bare = windowed(rise, |_, i| rise[i]);
        for p in &mut bare {
            p.window = None;
        }
        assert!(!ppv_rises_robust(&bare).1);
    }

    /// [`point`] with its seed judged ([`seed_chains`]).
    fn judged(motion: Motion, section_margin: f64) -> Point {
        seed_chains(vec![point(motion, section_margin)]).remove(0)
    }

    /// A period-1 classification is confirmed only with margin: at 1/100 of the tolerance and
    /// below it settles, just inside the tolerance (where a retune flipped it) it does not, and
    /// the warm starts seeded from it are withheld with it.
    #[test]
    fn periodicity_is_confirmed_only_with_margin() {
        let clear = judged(Motion::Periodic(1), 1e-4);
        assert!(!clear.time_unsettled() && !clear.motion_unsettled());
        assert!(!clear.hbm_unsettled(1));
        let edge = judged(Motion::Periodic(1), CONFIRMED);
        assert!(!edge.time_unsettled());
        let marginal = judged(Motion::Periodic(1), 0.3);
        assert!(marginal.time_unsettled() && marginal.motion_unsettled());
        assert!(marginal.hbm_unsettled(1) && marginal.hbm_unsettled(2));
        // the cold start does not depend on the sample
        assert!(!marginal.hbm_unsettled(0));
        // a confirmed sample whose refined twin leads the warm start elsewhere
        let mut split = point(Motion::Periodic(1), 1e-4);
        split.warm.seed_reproducible = Some(false);
        let split = seed_chains(vec![split]).remove(0);
        assert!(split.hbm_unsettled(1) && split.seed_unsettled[1]);
        assert!(!split.hbm_unsettled(2) && !split.seed_unsettled[2]);
        assert!(point(Motion::NonPeriodic, 1e-6).time_unsettled());
        // not known (older data): not confirmed
        assert!(point(Motion::Periodic(1), f64::INFINITY).time_unsettled());
        assert!(point(Motion::Periodic(1), f64::NAN).time_unsettled());
    }

    /// A neighbour continuation is as settled as the warm start that anchors it (Liu Fig. 11,
    /// 172.5–185 rad/s under a retune: a chain from a chaotic sample at 167.5 rad/s carried
    /// whichever solution that sample reached to confirmed periodic points): every point of a
    /// chain from an unconfirmed anchor is withheld, a chain from a confirmed one is not, and
    /// a broken index (older data) counts as unsettled.
    #[test]
    fn neighbour_chains_inherit_the_judgement_of_their_anchor() {
        let chain = |anchor_margin: f64| {
            let mut pts: Vec<Point> = (0..4).map(|_| point(Motion::Periodic(1), 1e-4)).collect();
            pts[0] = point(Motion::Periodic(1), anchor_margin);
            for i in 1..3 {
                pts[i].warm.origin = HbmOrigin::Neighbour;
                pts[i].warm.neighbour = Some(i - 1);
            }
            // the last point continued from an index that does not exist
            pts[3].warm.origin = HbmOrigin::Neighbour;
            pts[3].warm.neighbour = Some(7);
            seed_chains(pts)
        };
        let bad = chain(0.3);
        assert!(bad.iter().all(|p| p.hbm_unsettled(1)));
        // the full column has no chain here: only the anchor's own sample is unsettled
        assert!(bad[0].hbm_unsettled(2) && !bad[1].hbm_unsettled(2));
        let good = chain(1e-4);
        assert!(good[..3].iter().all(|p| !p.hbm_unsettled(1)));
        assert!(good[3].hbm_unsettled(1));
        // a cycle (impossible from the continuation, possible in hand-made data) ends
        let mut cyc: Vec<Point> = (0..2).map(|_| point(Motion::Periodic(1), 1e-4)).collect();
        for (i, p) in cyc.iter_mut().enumerate() {
            p.warm.origin = HbmOrigin::Neighbour;
            p.warm.neighbour = Some(1 - i);
        }
        assert!(seed_chains(cyc).iter().all(|p| p.hbm_unsettled(1)));
    }

    /// Evidence numbers from unsettled values are committed as `n/p` and kept in full in
    /// validation/stats/.
    #[test]
    fn unsettled_evidence_numbers_commit_as_not_periodic() {
        assert_eq!(sig_u(11.43, false), sig(11.43));
        let u = sig_u(11.43, true);
        assert_eq!(crate::committed_text(&u), crate::format::NOT_PERIODIC);
        assert_eq!(crate::full_text(&u), sig(11.43));
        // without a long window the judged ppv of an unconfirmed sample is unsettled
        let p = point(Motion::Periodic(1), 0.5);
        assert_eq!(
            crate::committed_text(&p.ppv_text()),
            crate::format::NOT_PERIODIC
        );
        let q = point(Motion::Periodic(1), 1e-5);
        assert_eq!(q.ppv_text(), sig(2e-3));
        assert!(any_unsettled([&q, &p]) && !any_unsettled([&q]));
    }
}
