//! Rattle design charts (issue 39, item 2): where in (ω1, T2) and (ω1, a_k) the Liu gear pair is
//! free of rattle, rattles on one flank or on both.
//!
//! Each chart is a brute-force map (one settled long window per cell, [`liu2021::settled_window`])
//! with the boundaries located by shooting continuation drawn over it: the period-1 branch in
//! ω1 is continued at fixed values of the second parameter (the slices), from 100 rad/s up and
//! from 220 rad/s down ([`super::orbit_branch::speed_branch_at`]), and its special points on each
//! slice — the unilateral-onset grazing (drive flank), the grazing of the back flank, the folds
//! and the loss of stability of the bilateral orbits — are joined across the slices into curves.
//! A slice without a point leaves a gap in its curve and a named row in the `curves` table
//! (why: the branch stopped, or left the range before reaching it). The unilateral-onset
//! grazing of every slice is also continued in both parameters (codim-2, along the global
//! mesh-period maximum of the drive-flank event function, switching to another maximum at a
//! double grazing and ending where it meets one again), so the onset curve runs between and
//! past the slices where the continuation holds. Where the boundary runs almost along the ω1
//! axis into the chart's left edge (the (ω1, a_k) chart), one more onset curve starts from the
//! grazing on a branch in the second parameter at 100 rad/s and is traced in ω1
//! ([`Chart::edge`]). Between two slices whose interval of the
//! second parameter the codim-2 curves cover, the slices' onset grazings are not joined by a
//! straight piece: the continued curve is the boundary there, and a chord across a bending
//! boundary would be judged as a curve of its own (in the (ω1, T2) chart such a chord runs 3 to
//! 8 rad/s beside the continued curve). A straight piece stays where no continued curve spans
//! the interval.
//!
//! The folds and the loss of stability are drawn from the slices only, not continued in two
//! parameters: on these branches both are non-smooth. Measured on the slices with every special
//! point located (the charts locate only the grazings, [`tuning`]). Where the branches meet
//! contact changes, their steps move with changes of the model at rounding level (the folds
//! estimated from the tangent by up to 0.3 rad/s), so the figures below hold to about that:
//! * every fold lies at contact changes of the drive flank (a local mesh-period maximum
//!   touching it): T2 = 15 N·m, fold at 116.7878 rad/s, contact changes at 116.7875–116.7878;
//!   a_k = 0.2375, fold at 163.2977, contact changes at 163.2958–163.2975. From both the fold
//!   corrector's first Newton iterate leaves the domain ω1 > 0 (to −148 and −2455 in the
//!   scaled frequency); at a_k = 0.8 (a fold at 124.48 rad/s after six period doublings from
//!   119.26 up) neither the fold nor the doublings converge (residuals 0.013–2.6);
//! * the bilateral orbits lose stability across a contact change of the back flank, where
//!   the largest multiplier jumps (0.71 at 171.80 rad/s to 26.7 at 169.56, a_k = 0.2375; 0.29
//!   at 173.30 to 1.12 at 171.80, T2 = 30 N·m), with period doublings and contact changes
//!   alternating past it (sixteen between 169.16 and 169.56 rad/s at a_k = 0.2375); the
//!   period-doubling corrector converges from none of them (residuals 0.2–0.8).
//!
//! `orbit` continues a contact change as the grazing of its local extremum
//! ([`OrbitProblem::continue_codim2`]), but not here: at the chart's Newton tolerance (10⁻⁸)
//! the first point stalls at a residual of 2·10⁻⁶ (a_k = 0.2375); at 10⁻⁶ the nearest local
//! grazing converges at 168.29 rad/s, outside the branch's bracket of the change
//! ([169.56, 171.80]: another maximum of the cluster, refused), and from the T2 = 15 fold's
//! contact change the curve stops within 10⁻⁴ N·m (the corrector at a residual of 8·10⁻⁶).
//! Several mesh-period maxima lie at the flank together there, each a square-root
//! non-smoothness of the flow.
//!
//! The agreement rows hold the map and the curves against each other: every cell whose rattle
//! state differs from a 4-neighbour's (a boundary cell) must lie within one cell of a curve,
//! and every curve must separate cells of different states — or lie where the map names why
//! not (cells that are not period-1: a chaotic band, where no period-1 orbit is the attractor;
//! an unstable orbit, which no time integration reaches).

use models::liu2021::{self, LongWindowOptions, Model, Parameters};
use models::motion::Motion;
use models::response::{WindowDetail, window_motion};
use orbit::{
    Codim2ContinuationOptions, OrbitProblem, Parameter, ShootingOptions, ShootingPoint,
    SpecialKind, SpecialPoint,
};
use plot::{Curve, CurveStyle, HeatScale, Heatmap};

use super::orbit_branch::{
    BI, Branch, Liu, Tuning, UNI, named_branch_at, shooting, speed_branch_at, stop_label,
};
use super::{base, model, sig};
use crate::{
    Comparison, Cost, Error, Evidence, Paper, Reference, Study, StudyOutput, Table, Tolerance,
    ToleranceBand,
};

pub(super) fn study() -> Study {
    Study {
        id: "liu2021-design-charts",
        paper: Paper::Liu2021,
        source: "Fig. 11, 12–15; Sect. 3.3, 3.6, 3.7",
        title: "Rattle design charts in (ω1, T2) and (ω1, a_k): long-window map with the continued boundaries",
        description: "Two 40 × 40 maps of the settled long-window rattle state (time integration \
            from drive-flank contact at rtol 1e-6, 5 transient periods, a 20-period window, one more window \
            when the first still holds a transient; a cell that fails is a failed cell): ω1 = \
            100–220 rad/s against T2 = 0–60 N·m (a_k from Table 1) and against a_k = 0.05–0.8 \
            (T2 = 30 N·m). Over them the boundaries from shooting continuation of the period-1 \
            orbit in ω1 at fixed T2 or a_k (slices): the unilateral-onset grazing, the grazing \
            of the back flank, the folds and the loss of stability of the bilateral orbits (from \
            220 rad/s down), and the unilateral-onset grazing continued in both parameters \
            (codim-2, along the global mesh-period maximum) from each slice's grazing and, in \
            (ω1, a_k), from the grazing of a branch in a_k at 100 rad/s. Agreement rows: \
            each slice's grazing against the codim-2 curves from the other slices and the curves \
            against each other, every boundary cell of the map within one cell of \
            a curve or in a named region (cells not period-1: chaotic band), and every curve \
            point separating different states or in a named region (unstable orbit, chaotic \
            band). Consistency of two methods on one model, not a reproduction of the paper.",
        cost: Cost::Heavy,
        run,
    }
}

/// Cells per axis of each map.
const N: usize = 40;
/// The ω1 range of both maps (rad/s): below Liu's unilateral onset to well inside the bilateral
/// region (Fig. 11: onsets near 135 and 165 rad/s).
const OMEGA: [f64; 2] = [100.0, 220.0];
/// The width of a map cell in ω1 (rad/s).
const CELL_OMEGA: f64 = (OMEGA[1] - OMEGA[0]) / (N - 1) as f64;
/// Slices (fixed second-parameter values) at which the branch is continued in ω1.
const SLICES: usize = 5;

/// The branches of the curves: steps up to 3 rad/s (a map cell is 3.08 rad/s wide), special
/// points located to 1e-3 rad/s, at most [`MAX_POINTS`] points per branch (enough to pass the
/// unilateral grazing and the fold from 100 rad/s up; past them the branch enters the
/// non-smooth tangle near 169 rad/s, where `liu2021-orbit-branch`'s branch crawls by steps
/// below 0.01 rad/s until its stall stop). The branches from 220 rad/s down stop at their
/// first unstable point ([`down_tuning`]).
///
/// Only the grazings of the two flanks ([`UNI`], [`BI`]) are located: they are the only
/// special points the charts read ([`boundaries`], [`codim2_grazing`]); the folds are the
/// tangent's ([`folds_on`]) and the limit of stability the points' ([`stability_limit`]). The
/// period doublings and folds of the strongly modulated slices were located to no use: at
/// a_k = 0.6125 (from 220 rad/s down) and 0.8 (from 100 up) that took 22 of the chart's 77 CPU
/// s of branches (one thread, `docs/performance.md`). The outputs are the same, bit for bit, as
/// with every special point located: the model's speed is set from the value alone
/// ([`liu2021::Model::with_omega_c`]), so a location leaves nothing in the branch's model.
fn tuning() -> Tuning {
    Tuning {
        max_points: MAX_POINTS,
        max_step: 3.0,
        locate_tol: 1e-3,
        locate_samples: 4,
        stall: None,
        stop_at: vec![],
        stop_unstable: false,
        locate_only: Some(vec![UNI, BI]),
        max_iter: super::orbit_branch::CORRECTOR_MAX_ITER,
    }
}

/// [`tuning`] for the branches from 220 rad/s down: they are wanted up to the loss of stability
/// of the bilateral orbits (the limit curve, [`stability_limit`]: located between the last
/// stable and the first unstable point), and end with their first unstable point. Past it they
/// went on into the tangle of contact changes and period doublings where the multipliers jump
/// (module docs),
/// locating a dozen or more special points that no curve uses: no fold and no back-flank
/// grazing of these branches lay past it.
fn down_tuning() -> Tuning {
    Tuning {
        stop_unstable: true,
        ..tuning()
    }
}

/// Most points of each branch of the curves ([`tuning`]).
const MAX_POINTS: usize = 32;

/// Map codes: the rattle state (0, 1, 2) of a period-1 window; 3 and 4 a unilateral or
/// bilateral window that is not period-1 (period-n, quasi-periodic or chaotic); 5 unsettled
/// (still a transient after the second window); NaN a failed cell.
const NOT_P1: f64 = 2.0;
const UNSETTLED: f64 = 5.0;

fn states() -> HeatScale {
    HeatScale::Categorical(vec![
        (0.0, "no rattle".to_owned()),
        (1.0, "unilateral, period-1".to_owned()),
        (2.0, "bilateral, period-1".to_owned()),
        (3.0, "unilateral, not period-1".to_owned()),
        (4.0, "bilateral, not period-1".to_owned()),
        (UNSETTLED, "unsettled".to_owned()),
    ])
}

/// The window of every map cell (module docs): short, but at least the 20 periods that the
/// section and 0–1 tests need; one window more when the first caught a transient. 5 transient
/// periods (the free transient decays by `e^{-17}` per period at Table 1 damping; a longer
/// nonlinear transient is caught by the second window) and rtol 1e-6 (the section tolerance
/// is 1e-4 of the ppv plus the gap, far above the integration error): about 40 ms a cell.
fn window_options() -> LongWindowOptions {
    LongWindowOptions {
        transient_periods: 5.0,
        periods: models::response::MIN_CLASSIFIED_PERIODS,
        settle_windows: 1,
        rtol: 1e-6,
        // a cell reads the state and the motion only
        detail: WindowDetail::Motion,
        ..LongWindowOptions::default()
    }
}

/// The map code of one cell (module docs); NaN when the cell fails.
fn cell(p: &Parameters) -> f64 {
    let Ok(m) = model(p) else { return f64::NAN };
    let Ok(w) = liu2021::settled_window(&m, &window_options(), None) else {
        return f64::NAN;
    };
    let rsv = f64::from(w.stats.state.rsv());
    match window_motion(&w.stats) {
        _ if rsv == 0.0 => 0.0,
        Some(Motion::Periodic(1)) => rsv,
        Some(_) => rsv + NOT_P1,
        None => UNSETTLED,
    }
}

/// The rattle state (0, 1, 2) of a map code; `None` for a failed cell.
fn rsv_of(code: f64) -> Option<u8> {
    if code.is_nan() {
        None
    } else if code >= UNSETTLED {
        Some(2)
    } else if code > NOT_P1 {
        Some((code - NOT_P1) as u8)
    } else {
        Some(code as u8)
    }
}

/// The code marks a cell whose window is not period-1 (or unsettled, or failed).
fn not_period_one(code: f64) -> bool {
    code.is_nan() || code > NOT_P1
}

/// One chart: its second parameter and range.
struct Chart {
    name: &'static str,
    y: (&'static str, &'static str),
    range: [f64; 2],
    set: fn(&mut Parameters, f64),
    /// The parameter's name for the orbit problem ([`Liu`]'s `set_parameter`).
    param: &'static str,
    /// Its arclength scale (1 ≈ 1 rad/s in ω1).
    scale: f64,
    /// The start of a branch in the second parameter at ω1 = 100 rad/s (the chart's left
    /// edge) and its direction, whose unilateral-onset grazing starts one more codim-2 onset
    /// curve ([`edge_grazing`]); `None`: no such branch.
    edge: Option<(f64, f64)>,
}

fn charts() -> [Chart; 2] {
    [
        Chart {
            name: "t2",
            y: ("T2", "N m"),
            range: [0.0, 60.0],
            set: |p, v| p.load_torque = v,
            param: "load_torque",
            scale: 1.0,
            // the onset curve from the T2 = 15 N·m slice reaches the left edge itself (it
            // leaves the ω1 range at T2 ≈ 10.9 N·m)
            edge: None,
        },
        Chart {
            name: "ak",
            y: ("a_k", "1"),
            range: [0.05, 0.8],
            set: |p, v| p.kr = v * p.k0,
            param: "ak",
            scale: 0.01,
            // the onset boundary meets the left edge at a shallow angle (a_k ≈ 0.46–0.48 over
            // ω1 = 100–125 rad/s), where several mesh-period maxima graze together: the
            // envelopes from the slices go round that cluster and end there
            // (`EnvelopeEnd::Cycle`), and a branch in a_k at 100 rad/s crosses the boundary
            // steeply
            edge: Some((0.05, 1.0)),
        },
    ]
}

fn axis(range: [f64; 2], n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| range[0] + (range[1] - range[0]) * i as f64 / (n - 1) as f64)
        .collect()
}

/// The special points of one slice: the branch from 100 rad/s up and from 220 rad/s down.
struct Slice {
    y: f64,
    up: Result<(Branch, f64), String>,
    down: Result<(Branch, f64), String>,
    /// The loss of stability of `down`, located ([`stability_limit`]).
    limit: Option<f64>,
}

/// A slice's branch job: the branch, and for a branch from 220 rad/s down its located
/// stability limit ([`stability_limit`]).
type SliceJob = (Result<(Branch, f64), String>, Option<f64>);

/// A curve of a chart: its name, style and one point per slice (NaN: none on that slice, with
/// the reason in `why`); `stable[k]`: the orbit at the point is stable; `breaks[k]`: no piece
/// is drawn from point `k` to point `k + 1` (missing entries: drawn).
struct Boundary {
    label: String,
    style: CurveStyle,
    colour: usize,
    points: Vec<(f64, f64)>,
    stable: Vec<bool>,
    why: Vec<String>,
    breaks: Vec<bool>,
}

impl Boundary {
    /// Whether a break follows point `k` (missing entries: none).
    fn broken(&self, k: usize) -> bool {
        self.breaks.get(k).copied().unwrap_or(false)
    }

    /// Whether the piece from point `k` to point `k + 1` is drawn.
    fn joined(&self, k: usize) -> bool {
        self.style != CurveStyle::Crosses && !self.broken(k)
    }

    /// The points as drawn: a non-finite point after each break (the plot's gap; crosses have
    /// no breaks).
    fn drawn_points(&self) -> Vec<(f64, f64)> {
        let mut out = Vec::with_capacity(self.points.len());
        for (k, &p) in self.points.iter().enumerate() {
            out.push(p);
            if k + 1 < self.points.len() && self.broken(k) {
                out.push((f64::NAN, f64::NAN));
            }
        }
        out
    }
}

/// Whether the intervals `ranges` (each `[lo, hi]`) together cover `[a, b]`.
fn covered(ranges: &[(f64, f64)], a: f64, b: f64) -> bool {
    let mut r: Vec<(f64, f64)> = ranges
        .iter()
        .copied()
        .filter(|&(lo, hi)| lo.is_finite() && hi.is_finite() && lo <= hi)
        .collect();
    r.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut reach = a;
    for (lo, hi) in r {
        if lo > reach {
            break;
        }
        reach = reach.max(hi);
    }
    reach >= b
}

/// The first special point of `kind` on a branch as `(ω1, stable)`.
fn special_on(b: &(Branch, f64), kind: SpecialKind) -> Option<(f64, bool)> {
    b.0.special
        .iter()
        .find(|s| s.kind == kind)
        .map(|s| (s.point.parameter / b.1, s.point.floquet.stable))
}

/// Every fold of a branch (rad/s).
fn folds_on(b: &(Branch, f64)) -> Vec<f64> {
    b.0.folds.iter().map(|f| f.parameter / b.1).collect()
}

/// Bisections of the bracket of the stability limit ([`stability_limit`]).
const LIMIT_BISECTIONS: usize = 6;

/// The loss of stability of the branch from 220 rad/s down, located: the bracket of the last
/// stable and the first unstable continuation point (up to a step, 3 rad/s, apart: a map cell)
/// bisected [`LIMIT_BISECTIONS`] times in ω1 (to 1/64 of the step). At each midpoint the orbit
/// is shot at that speed ([`OrbitProblem::shoot`] with [`shooting`]'s options, 20 Newton
/// iterations) from the mean of the bracket's two orbit states, and its multipliers decide the
/// half.
/// The bisection ends early, at the bracket it has, where the shooting fails or its orbit lies
/// farther from the guess than the bracket's two orbits lie apart (another branch). The
/// midpoint of the final bracket is the limit. The midpoint of the continuation's own bracket
/// would move with the branch's steps: a change of the corrector's iteration limit moves it
/// at a_k = 0.05 from 168.8 to 169.9 rad/s, across a map cell. (The bracket's states are
/// carried into each guess, which [`system::numeric::bisect`], a scalar root finder, does
/// not.) Where stability changes more than once inside the bracket (contact changes and
/// period doublings alternate there, module docs) the bisection finds one of the changes, so
/// the limit holds to the width of that tangle: at a_k = 0.05, 169.6 rad/s with the corrector
/// at 10 iterations and 169.8 at 20 (other brackets). `p`: the slice's parameters.
fn stability_limit(p: &Parameters, b: &(Branch, f64)) -> Option<f64> {
    let pts = &b.0.points;
    let k = pts.iter().position(|q| !q.floquet.stable)?;
    if k == 0 {
        return None;
    }
    let (mut ws, mut xs) = (pts[k - 1].parameter / b.1, pts[k - 1].x0.clone());
    let (mut wu, mut xu) = (pts[k].parameter / b.1, pts[k].x0.clone());
    for _ in 0..LIMIT_BISECTIONS {
        let wm = 0.5 * (ws + wu);
        let guess: Vec<f64> = xs.iter().zip(&xu).map(|(a, c)| 0.5 * (a + c)).collect();
        let spread = xs
            .iter()
            .zip(&xu)
            .map(|(a, c)| (a - c).abs())
            .fold(0.0, f64::max);
        let mut q = *p;
        q.omega1 = wm;
        let Some(orbit) = model(&q)
            .ok()
            .and_then(|m| OrbitProblem::new(m, m.period()).ok())
            .and_then(|prob| prob.shoot(&guess, &shooting()).ok())
        else {
            break;
        };
        let off = orbit
            .x0
            .iter()
            .zip(&guess)
            .map(|(a, c)| (a - c).abs())
            .fold(0.0, f64::max);
        // (false for a NaN distance too)
        let same_branch = off <= spread;
        if !same_branch {
            break;
        }
        if orbit.floquet.stable {
            (ws, xs) = (wm, orbit.x0);
        } else {
            (wu, xu) = (wm, orbit.x0);
        }
    }
    Some(0.5 * (ws + wu))
}

fn missing(b: &Result<(Branch, f64), String>, what: &str) -> String {
    match b {
        Ok((br, conv)) => format!(
            "no {what} on the branch ({} points, stopped: {}, at ω1 = {} rad/s)",
            br.points.len(),
            stop_label(br),
            sig(br.points.last().map_or(f64::NAN, |p| p.parameter / conv))
        ),
        Err(e) => format!(
            "the branch failed: {}",
            system::format::round_numbers_in(e, 4)
        ),
    }
}

fn boundaries(slices: &[Slice]) -> Vec<Boundary> {
    let mut out = Vec::new();
    let from = |label: &str, style, colour, up: bool, kind: SpecialKind, what: &str| {
        let mut b = Boundary {
            label: label.to_owned(),
            style,
            colour,
            points: Vec::new(),
            stable: Vec::new(),
            why: Vec::new(),
            breaks: Vec::new(),
        };
        for s in slices {
            let branch = if up { &s.up } else { &s.down };
            match branch.as_ref().ok().and_then(|br| special_on(br, kind)) {
                Some((w, st)) => {
                    b.points.push((w, s.y));
                    b.stable.push(st);
                    b.why.push(String::new());
                }
                None => {
                    b.points.push((f64::NAN, s.y));
                    b.stable.push(false);
                    b.why.push(missing(branch, what));
                }
            }
        }
        b
    };
    out.push(from(
        "unilateral onset (grazing, drive flank) on the slices",
        CurveStyle::Dashed,
        0,
        true,
        UNI,
        "drive-flank grazing",
    ));
    out.push(from(
        "back-flank grazing, branch from 100 up",
        CurveStyle::Dashed,
        0,
        true,
        BI,
        "back-flank grazing",
    ));
    out.push(from(
        "back-flank grazing, branch from 220 down",
        CurveStyle::Dashed,
        2,
        false,
        BI,
        "back-flank grazing",
    ));
    let mut limit = Boundary {
        label: "limit of stable bilateral orbits (from 220 down)".to_owned(),
        style: CurveStyle::Solid,
        colour: 2,
        points: Vec::new(),
        stable: Vec::new(),
        why: Vec::new(),
        breaks: Vec::new(),
    };
    for s in slices {
        match s.limit {
            Some(w) => {
                limit.points.push((w, s.y));
                // the stable side of the limit is what the map sees
                limit.stable.push(true);
                limit.why.push(String::new());
            }
            None => {
                limit.points.push((f64::NAN, s.y));
                limit.stable.push(false);
                limit.why.push(missing(&s.down, "loss of stability"));
            }
        }
    }
    out.push(limit);
    let mut folds = Boundary {
        label: "folds (branches from 100 up and 220 down)".to_owned(),
        style: CurveStyle::Crosses,
        colour: 1,
        points: Vec::new(),
        stable: Vec::new(),
        why: Vec::new(),
        breaks: Vec::new(),
    };
    for s in slices {
        for br in [&s.up, &s.down].into_iter().flatten() {
            for w in folds_on(br) {
                folds.points.push((w, s.y));
                // at a fold a stable and an unstable orbit meet: the map sees the stable one
                folds.stable.push(true);
                folds.why.push(String::new());
            }
        }
    }
    out.push(folds);
    out
}

/// Grid index of `v` on a uniform axis (nearest cell), `None` outside it.
fn index(v: f64, ax: &[f64]) -> Option<usize> {
    let (a, b) = (ax[0], ax[ax.len() - 1]);
    let d = (b - a) / (ax.len() - 1) as f64;
    let k = ((v - a) / d).round();
    (k >= 0.0 && k < ax.len() as f64).then_some(k as usize)
}

/// The cells a curve passes through: each drawn piece sampled at 64 points per segment, each
/// isolated point (crosses, or a point between two gaps or breaks) its own cell; with the
/// stability of the orbit at the nearer end.
fn curve_cells(c: &Boundary, xs: &[f64], ys: &[f64]) -> Vec<(usize, usize, bool)> {
    let mut cells: Vec<(usize, usize, bool)> = Vec::new();
    let mut push = |x: f64, y: f64, st: bool| {
        if let (Some(i), Some(j)) = (index(x, xs), index(y, ys)) {
            if !cells.iter().any(|&(a, b, _)| a == i && b == j) {
                cells.push((i, j, st));
            }
        }
    };
    let ok = |p: &(f64, f64)| p.0.is_finite() && p.1.is_finite();
    for (k, p) in c.points.iter().enumerate() {
        if !ok(p) {
            continue;
        }
        push(p.0, p.1, c.stable[k]);
        if !c.joined(k) {
            continue;
        }
        if let Some(q) = c.points.get(k + 1).filter(|q| ok(q)) {
            for s in 1..64 {
                let t = f64::from(s) / 64.0;
                let st = if t < 0.5 {
                    c.stable[k]
                } else {
                    c.stable[k + 1]
                };
                push(p.0 + t * (q.0 - p.0), p.1 + t * (q.1 - p.1), st);
            }
        }
    }
    cells
}

/// Counts of the agreement of a map and its curves (module docs).
#[derive(Debug, Default)]
struct Agreement {
    boundary: usize,
    near_curve: usize,
    chaotic: usize,
    unexplained: Vec<(usize, usize)>,
    curve_cells: usize,
    separating: usize,
    curve_chaotic: usize,
    curve_unstable: usize,
    curve_unexplained: Vec<(usize, usize)>,
}

fn agreement(codes: &[f64], xs: &[f64], ys: &[f64], curves: &[Boundary]) -> Agreement {
    let (nx, ny) = (xs.len(), ys.len());
    let at = |i: usize, j: usize| codes[j * nx + i];
    let around = |i: usize, j: usize| {
        let (i0, i1) = (i.saturating_sub(1), (i + 1).min(nx - 1));
        let (j0, j1) = (j.saturating_sub(1), (j + 1).min(ny - 1));
        (j0..=j1).flat_map(move |b| (i0..=i1).map(move |a| (a, b)))
    };
    let hit: Vec<(usize, usize, bool)> =
        curves.iter().flat_map(|c| curve_cells(c, xs, ys)).collect();
    let mut near = vec![false; nx * ny];
    for &(i, j, _) in &hit {
        for (a, b) in around(i, j) {
            near[b * nx + a] = true;
        }
    }
    let mut g = Agreement::default();
    for j in 0..ny {
        for i in 0..nx {
            let Some(r) = rsv_of(at(i, j)) else { continue };
            let mut nb = Vec::new();
            if i > 0 {
                nb.push((i - 1, j));
            }
            if i + 1 < nx {
                nb.push((i + 1, j));
            }
            if j > 0 {
                nb.push((i, j - 1));
            }
            if j + 1 < ny {
                nb.push((i, j + 1));
            }
            let differs = nb
                .iter()
                .any(|&(a, b)| rsv_of(at(a, b)).is_some_and(|s| s != r));
            if !differs {
                continue;
            }
            g.boundary += 1;
            if near[j * nx + i] {
                g.near_curve += 1;
            } else if around(i, j).any(|(a, b)| not_period_one(at(a, b))) {
                g.chaotic += 1;
            } else {
                g.unexplained.push((i, j));
            }
        }
    }
    for c in curves {
        for (i, j, stable) in curve_cells(c, xs, ys) {
            g.curve_cells += 1;
            let mut seen: Vec<u8> = around(i, j).filter_map(|(a, b)| rsv_of(at(a, b))).collect();
            seen.sort_unstable();
            seen.dedup();
            if seen.len() > 1 {
                g.separating += 1;
            } else if around(i, j).any(|(a, b)| not_period_one(at(a, b))) {
                g.curve_chaotic += 1;
            } else if !stable {
                g.curve_unstable += 1;
            } else {
                g.curve_unexplained.push((i, j));
            }
        }
    }
    g
}

/// The unilateral-onset grazing curve by codim-2 continuation ([`OrbitProblem::continue_codim2`]:
/// the shooting residual plus the grazing condition of the drive flank, ω1 an unknown) from the
/// grazing located on the branch from 100 rad/s up at the slice `y0`, traced in the chart's
/// second parameter both ways to the ends of its range along the global maximum of the
/// drive-flank event function ([`OrbitProblem::continue_grazing_envelope`]: the Liu period
/// holds one local maximum per mesh period, and where another one reaches the flank first the
/// curve goes on along that one's grazing): `(ω1, y, stable, piece)` in trace order (from the
/// lower end of `y`), and the stop reasons of the two directions. Started on every slice with
/// a grazing, so that a curve stopped short is taken up by the one from the next slice, and
/// each slice's grazing is checked against the curves from the others.
fn codim2_grazing(chart: &Chart, y0: f64, up: &(Branch, f64)) -> Codim2Result {
    let start =
        up.0.special
            .iter()
            .find(|s| s.kind == UNI)
            .ok_or("no unilateral-onset grazing on the branch from 100 rad/s up")?;
    let mut p = base();
    p.omega1 = OMEGA[0];
    (chart.set)(&mut p, y0);
    both_ways(chart, p, start, up.1, false)
}

/// The unilateral-onset grazing curve by codim-2 continuation from the grazing located on the
/// branch in the chart's second parameter at ω1 = 100 rad/s from `chart.edge`
/// ([`named_branch_at`]), traced in ω1 both ways (the second parameter an unknown), as
/// [`codim2_grazing`]: where the boundary runs along the ω1 axis into the chart's left edge.
fn edge_grazing(chart: &Chart) -> Codim2Result {
    let (from, dir) = chart.edge.ok_or("no edge start")?;
    let mut p = base();
    p.omega1 = OMEGA[0];
    let branch = named_branch_at(
        p,
        chart.param,
        from,
        chart.range,
        dir,
        chart.scale,
        &tuning(),
    )
    .map_err(|e| e.to_string())?;
    let start = branch.special.iter().find(|s| s.kind == UNI).ok_or_else(|| {
        format!(
            "no unilateral-onset grazing on the branch in {} at {} rad/s ({} points, stopped: {})",
            chart.y.0,
            OMEGA[0],
            branch.points.len(),
            stop_label(&branch)
        )
    })?;
    (chart.set)(&mut p, from);
    let conv = model(&p).map_err(|e| e.to_string())?.omega_c / OMEGA[0];
    both_ways(chart, p, start, conv, true)
}

/// The grazing envelope from `start` (a unilateral-onset grazing on a branch of `p`) in both
/// directions, joined into one curve from its lower end (in ω1 when `along_omega`, else in the
/// chart's second parameter); the piece numbers ([`Codim2Curve`]): the first piece of each
/// direction is one piece through the start (0), the others alternate (down 1, 3, …; up 2,
/// 4, …).
fn both_ways(
    chart: &Chart,
    p: Parameters,
    start: &SpecialPoint<ShootingPoint>,
    conv: f64,
    along_omega: bool,
) -> Codim2Result {
    let m = model(&p).map_err(|e| e.to_string())?;
    let mut pieces: Vec<Codim2Curve> = Vec::new();
    let mut stops = [String::new(), String::new()];
    for (k, dir) in [-1.0, 1.0].into_iter().enumerate() {
        let sys = Liu::new(p).map_err(|e| e.to_string())?;
        let mut prob = OrbitProblem::new(sys, m.period()).map_err(|e| e.to_string())?;
        let o = envelope_options(chart, &m, conv, along_omega, dir);
        let env = prob
            .continue_grazing_envelope(start, &o, MAX_SWITCHES)
            .map_err(|e| format!("codim-2 continuation: {e}"))?;
        // the solver's values in the stop to 4 digits: a rounding-level change of the run is
        // no change of the note
        stops[k] = system::format::round_numbers_in(
            &format!(
                "{} piece(s), {} switch(es) of the mesh-period maximum, then {:?} ({:?})",
                env.pieces.len(),
                env.pieces.len() - 1,
                env.stop().cloned().unwrap_or(orbit::StopReason::MaxPoints),
                env.end
            ),
            4,
        );
        let id = |k: usize| match k {
            0 => 0,
            _ if dir < 0.0 => 2 * k - 1,
            _ => 2 * k,
        };
        let mut piece: Codim2Curve = env
            .points_by_piece()
            .into_iter()
            .map(|(k, q)| {
                let (w, y) = if along_omega {
                    (q.parameter / conv, q.first_parameter)
                } else {
                    (q.first_parameter / conv, q.parameter)
                };
                (w, y, q.floquet.stable, id(k))
            })
            .collect();
        if dir < 0.0 {
            piece.reverse();
            // the start is the first point of both directions
            piece.pop();
        }
        pieces.push(piece);
    }
    Ok((pieces.concat(), stops))
}

/// The codim-2 options of the onset envelopes ([`both_ways`]): ω1 (the base frequency, scaled
/// by `conv` = ω̄_c per rad/s) and the chart's second parameter, one of them an unknown and the
/// other traced in direction `dir` (ω1 traced when `along_omega`), within the chart's ranges
/// (ω1 one rad/s beyond).
fn envelope_options(
    chart: &Chart,
    m: &Model,
    conv: f64,
    along_omega: bool,
    dir: f64,
) -> Codim2ContinuationOptions {
    let omega = (
        Parameter::BaseFrequency,
        [(OMEGA[0] - 1.0) * conv, (OMEGA[1] + 1.0) * conv],
        conv,
    );
    let second = (
        Parameter::Named(chart.param.to_owned()),
        chart.range,
        chart.scale,
    );
    let (first, traced) = if along_omega {
        (second, omega)
    } else {
        (omega, second)
    };
    let mut o = Codim2ContinuationOptions::codim2(first.0, traced.0);
    o.initial_step = 0.5;
    o.max_step = 2.0;
    o.max_points = CODIM2_POINTS;
    o.corrector.first_range = first.1;
    o.corrector.first_scale = first.2;
    o.corrector.range = traced.1;
    o.corrector.direction = dir;
    o.corrector.parameter_scale = traced.2;
    o.corrector.state_scale = 0.1 * m.backlash;
    o.corrector.shooting = ShootingOptions {
        tol: 1e-8,
        max_iter: 20,
        ..ShootingOptions::default()
    };
    o.corrector.locate_tol = 1e-3;
    o
}

/// A codim-2 onset curve with the stop reasons of its two directions, or why there is none.
type Codim2Result = Result<(Codim2Curve, [String; 2]), String>;

/// A codim-2 curve as `(ω1, y, stable, piece)` points: `piece` numbers the smooth pieces of
/// a grazing envelope (a kink, the double grazing, lies between two).
type Codim2Curve = Vec<(f64, f64, bool, usize)>;

/// Points of each piece of the codim-2 curve at most.
const CODIM2_POINTS: usize = 60;

/// Switches of the grazing between local maxima of the drive-flank event function (one per
/// mesh period of the Liu period) per direction at most ([`OrbitProblem::continue_grazing_envelope`]).
/// Near T2 ≈ 24 and 36 N·m (ω1 ≈ 138 rad/s) and a_k ≈ 0.46 (ω1 ≈ 120–125 rad/s) the curves
/// turn among several maxima that lie close to the flank together, and the restarts go round
/// them; the envelope ends there at the first double grazing met again
/// ([`orbit::EnvelopeEnd::Cycle`], after 5–11 switches), so the cap only bounds an envelope
/// that keeps meeting new double grazings.
const MAX_SWITCHES: usize = 12;

/// The codim-2 curve at `y` by linear interpolation between its two points around `y`, with an
/// estimate of the interpolation error (`|Δ²ω|/8` of the three points nearest, the bound
/// `h²|ω''|/8` of linear interpolation): every crossing of `y` in trace order (a curve that
/// turns in `y` crosses it more than once), empty outside the curve. The third point is the
/// nearest after the bracket on the smooth piece of its second point, else before it on the
/// piece of its first, whose `y` differs from both of the bracket's: a second difference
/// across a switch of the envelope (a double grazing, bracketed to `2⁻¹⁰` of a step) measures
/// the switch, not the curvature — where the envelope turns back in `y` there, it divides the
/// `ω1` between the two extrema's curves by the bracket's width and grows without bound as the
/// bracket shrinks. NaN where the piece has no such point.
fn crossings(curve: &[(f64, f64, bool, usize)], y: f64) -> Vec<(f64, f64)> {
    curve
        .windows(2)
        .enumerate()
        .filter(|(_, w)| (w[0].1 - y) * (w[1].1 - y) <= 0.0 && (w[1].1 - w[0].1).abs() > 0.0)
        .map(|(k, _)| {
            let (a, b) = (curve[k], curve[k + 1]);
            let w = a.0 + (b.0 - a.0) * (y - a.1) / (b.1 - a.1);
            let distinct =
                |c: &&(f64, f64, bool, usize)| (c.1 - a.1).abs() > 0.0 && (c.1 - b.1).abs() > 0.0;
            let c = curve[k + 2..]
                .iter()
                .take_while(|c| c.3 == b.3)
                .find(distinct)
                .or_else(|| {
                    curve[..k]
                        .iter()
                        .rev()
                        .take_while(|c| c.3 == a.3)
                        .find(distinct)
                })
                .copied();
            let err = c.map_or(f64::NAN, |c| {
                // second divided difference × the bracket's width squared / 8
                let (x0, x1, x2) = (a.1, b.1, c.1);
                let d1 = (b.0 - a.0) / (x1 - x0);
                let d2 = (c.0 - b.0) / (x2 - x1);
                let dd = (d2 - d1) / (x2 - x0);
                (dd * (x1 - x0) * (x1 - x0)).abs() / 4.0
            });
            (w, err)
        })
        .collect()
}

/// Whether the point `(ω1, y)` lies within the extent of the codim-2 curve in both ω1 and `y`,
/// widened by `margin` = (one map cell in ω1, one in `y`): a grazing or a curve point is
/// compared with a curve only there. The onset boundary can take one value of `y` at several
/// ω1 (the (ω1, a_k) chart's zigzag at a_k ≈ 0.46–0.48 over 100–125 rad/s), and a curve that
/// stops short of one of them has no counterpart there; a disagreement of up to a cell beside
/// the curve's extent is still compared.
fn spans_point(curve: &[(f64, f64, bool, usize)], w: f64, y: f64, margin: (f64, f64)) -> bool {
    let (mut w_lo, mut w_hi, mut y_lo, mut y_hi) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for p in curve {
        (w_lo, w_hi) = (w_lo.min(p.0), w_hi.max(p.0));
        (y_lo, y_hi) = (y_lo.min(p.1), y_hi.max(p.1));
    }
    (w_lo - margin.0..=w_hi + margin.0).contains(&w)
        && (y_lo - margin.1..=y_hi + margin.1).contains(&y)
}

/// The band of a comparison of a codim-1 grazing or a curve point with a codim-2 curve whose
/// linear interpolation there has the error estimate `err` ([`crossings`]): twice the estimate
/// plus the codim-1 location tolerance (1e-3 rad/s) twice.
fn band(err: f64) -> f64 {
    2.0 * err + 2e-3
}

/// Whether a comparison with the interpolation error `err` is judged: the error is known and
/// within one map cell in ω1 (where the curve turns in the second parameter, ω1 as a function
/// of it is steep and the estimate large: such a comparison resolves nothing at the chart's
/// resolution and is shown only).
fn judged(err: f64) -> bool {
    err.is_finite() && err <= CELL_OMEGA
}

/// The first crossing of `y` by the curve ([`crossings`]).
#[cfg(test)]
fn interpolate(curve: &[(f64, f64, bool, usize)], y: f64) -> Option<(f64, f64)> {
    crossings(curve, y).first().copied()
}

/// Cells as `(ω1, y)` text for a note (at most 8).
fn cells_text(cells: &[(usize, usize)], xs: &[f64], ys: &[f64]) -> String {
    let mut t: Vec<String> = cells
        .iter()
        .take(8)
        .map(|&(i, j)| format!("({}, {})", sig(xs[i]), sig(ys[j])))
        .collect();
    if cells.len() > 8 {
        t.push(format!("… {} more", cells.len() - 8));
    }
    t.join(", ")
}

/// CPU seconds charged so far to the account in force (NaN without one).
fn cpu_now() -> f64 {
    system::account::current().map_or(f64::NAN, |a| a.usage().cpu_seconds)
}

fn run() -> Result<StudyOutput, Error> {
    let mut out = StudyOutput::new();
    let xs = axis(OMEGA, N);
    let mut curves_t = Table::new(
        "curves",
        &[
            ("chart", "-"),
            ("curve", "-"),
            ("slice", "N m | 1"),
            ("omega1", "rad/s"),
            ("stable", "1"),
            ("note", "-"),
        ],
    );
    let mut cost_t = Table::new(
        "cost",
        &[
            ("chart", "-"),
            ("part", "-"),
            ("cells_or_branches", "1"),
            ("branch_points", "1"),
        ],
    );
    for chart in charts() {
        let ys = axis(chart.range, N);
        let params: Vec<Parameters> = ys
            .iter()
            .flat_map(|&y| {
                xs.iter().map(move |&x| {
                    let mut p = base();
                    p.omega1 = x;
                    (chart.set)(&mut p, y);
                    p
                })
            })
            .collect();
        let t0 = cpu_now();
        let codes: Vec<f64> = system::sweep::sweep(&params, cell, None);
        let t_map = cpu_now() - t0;
        let slice_ys = axis(chart.range, SLICES);
        let jobs: Vec<(f64, bool)> = slice_ys
            .iter()
            .flat_map(|&y| [(y, true), (y, false)])
            .collect();
        let t1 = cpu_now();
        // each job: the branch, and for a branch from 220 down its located stability limit
        let branches: Vec<SliceJob> = system::sweep::sweep(
            &jobs,
            |&(y, up)| {
                let mut p = base();
                (chart.set)(&mut p, y);
                let (w, dir) = if up {
                    (OMEGA[0], 1.0)
                } else {
                    (OMEGA[1], -1.0)
                };
                let t = if up { tuning() } else { down_tuning() };
                let b = speed_branch_at(p, w, dir, [OMEGA[0] - 1.0, OMEGA[1] + 1.0], &t)
                    .map_err(|e| e.to_string());
                let limit = if up {
                    None
                } else {
                    b.as_ref().ok().and_then(|b| stability_limit(&p, b))
                };
                (b, limit)
            },
            None,
        );
        let t_curves = cpu_now() - t1;
        let mut it = branches.into_iter();
        let no_job = || (Err("no job".to_owned()), None);
        let slices: Vec<Slice> = slice_ys
            .iter()
            .map(|&y| {
                let (up, _) = it.next().unwrap_or_else(no_job);
                let (down, limit) = it.next().unwrap_or_else(no_job);
                Slice { y, up, down, limit }
            })
            .collect();
        let mut curves = boundaries(&slices);
        // the unilateral-onset grazing curve by codim-2 continuation from the grazing of every
        // slice (each curve checked against the grazings of the other slices it reaches)
        let t2 = cpu_now();
        // job `slices.len()`: the curve from the chart's left edge ([`edge_grazing`])
        let jobs: Vec<usize> = (0..=slices.len()).collect();
        let mut results: Vec<Codim2Result> = system::sweep::sweep(
            &jobs,
            |&k| match slices.get(k).map(|s| &s.up) {
                Some(Ok(up)) => codim2_grazing(&chart, slices[k].y, up),
                Some(Err(e)) => Err(format!(
                    "no branch on the slice: {}",
                    system::format::round_numbers_in(e, 4)
                )),
                None => edge_grazing(&chart),
            },
            None,
        );
        let t_codim2 = cpu_now() - t2;
        let edge = results.pop().filter(|_| chart.edge.is_some());
        // every codim-2 curve with where it starts and the slice it started on
        let codim2: Vec<(String, Option<usize>, &Codim2Result)> = results
            .iter()
            .enumerate()
            .map(|(k, c)| (format!("{} = {}", chart.y.0, sig(slices[k].y)), Some(k), c))
            .chain(
                edge.iter()
                    .map(|c| (format!("ω1 = {} rad/s", sig(OMEGA[0])), None, c)),
            )
            .collect();
        // the slices' onset grazings: no chord between two slices whose interval the codim-2
        // curves cover (module docs)
        let spans: Vec<(f64, f64)> = codim2
            .iter()
            .filter_map(|c| c.2.as_ref().ok())
            .filter(|(c2, _)| !c2.is_empty())
            .map(|(c2, _)| {
                c2.iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                        (lo.min(p.1), hi.max(p.1))
                    })
            })
            .collect();
        let onset = &mut curves[0];
        onset.breaks = (0..onset.points.len())
            .map(|k| {
                let p = onset.points[k];
                onset.points.get(k + 1).is_some_and(|q| {
                    p.0.is_finite()
                        && q.0.is_finite()
                        && covered(&spans, p.1.min(q.1), p.1.max(q.1))
                })
            })
            .collect();
        for (k, &b) in onset.breaks.iter().enumerate() {
            if b {
                onset.why[k] =
                    "not joined to the next slice: the codim-2 curves cover the interval"
                        .to_owned();
            }
        }
        let points: usize = slices
            .iter()
            .flat_map(|s| [&s.up, &s.down])
            .flatten()
            .map(|b| b.0.points.len())
            .sum();
        cost_t.push(vec![
            chart.name.into(),
            "map".into(),
            crate::Cell::count((N * N) as f64),
            crate::Cell::count(0.0),
        ])?;
        cost_t.push(vec![
            chart.name.into(),
            "curves".into(),
            crate::Cell::count((2 * SLICES) as f64),
            crate::Cell::count(points as f64),
        ])?;
        for c in &curves {
            for (k, p) in c.points.iter().enumerate() {
                curves_t.push(vec![
                    chart.name.into(),
                    c.label.as_str().into(),
                    p.1.into(),
                    p.0.into(),
                    crate::Cell::count(if c.stable[k] { 1.0 } else { 0.0 }),
                    c.why[k].as_str().into(),
                ])?;
            }
        }
        // codim-1 grazings on the slices against the codim-2 curves started on the other slices
        let y = chart.y.0;
        let quantity = format!(
            "(ω1, {y}) unilateral-onset grazing: largest |ω1| difference between the codim-1 grazing on each slice and the codim-2 curves started on the other slices, and between those curves where they overlap"
        );
        // one map cell in ω1 and in y ([`spans_point`])
        let cell = (
            CELL_OMEGA,
            (chart.range[1] - chart.range[0]) / (N - 1) as f64,
        );
        // every comparison as (|Δω1|, interpolation error, text); each is judged against its
        // own band, 2 err + 2e-3 ([`band`])
        let mut all: Vec<(f64, f64, String)> = Vec::new();
        for (k, s) in slices.iter().enumerate() {
            let w1 = curves[0].points[k].0;
            if !w1.is_finite() {
                continue;
            }
            // the crossing of y = y_k nearest the slice's grazing, over the other slices' curves
            let nearest = codim2
                .iter()
                .filter(|c| c.1 != Some(k))
                .filter_map(|c| c.2.as_ref().ok().map(|r| (&c.0, r)))
                .filter(|(_, (c2, _))| spans_point(c2, w1, s.y, cell))
                .flat_map(|(from, (c2, _))| {
                    crossings(c2, s.y)
                        .into_iter()
                        .map(move |(w2, err)| (from, w2, err))
                })
                .min_by(|a, b| (a.1 - w1).abs().total_cmp(&(b.1 - w1).abs()));
            if let Some((from, w2, err)) = nearest {
                all.push((
                    (w1 - w2).abs(),
                    err,
                    format!(
                        "{y} = {}: {} vs {} (curve from {from})",
                        sig(s.y),
                        sig(w1),
                        sig(w2)
                    ),
                ));
            }
        }
        // and the curves against each other where they overlap (one envelope from two
        // starts): every point of one inside the other's extent against the nearest crossing
        // of the other, the point farthest outside its band (or least inside) for the pair
        for (i, (from_i, _, ci)) in codim2.iter().enumerate() {
            for (j, (from_j, _, cj)) in codim2.iter().enumerate() {
                let (Ok((ci, _)), Ok((cj, _))) = (ci, cj) else {
                    continue;
                };
                if i == j {
                    continue;
                }
                let points: Vec<(f64, f64, f64)> = ci
                    .iter()
                    .filter(|p| spans_point(cj, p.0, p.1, cell))
                    .filter_map(|p| {
                        crossings(cj, p.1)
                            .into_iter()
                            .min_by(|a, b| (a.0 - p.0).abs().total_cmp(&(b.0 - p.0).abs()))
                            .map(|(w2, err)| ((p.0 - w2).abs(), err, p.1))
                    })
                    .collect();
                // a pair with no judged point is shown by its largest difference
                let pair = points
                    .iter()
                    .filter(|&&(_, err, _)| judged(err))
                    .max_by(|a, b| (a.0 / band(a.1)).total_cmp(&(b.0 / band(b.1))))
                    .or_else(|| points.iter().max_by(|a, b| a.0.total_cmp(&b.0)))
                    .copied();
                if let Some((d, err, at)) = pair {
                    all.push((
                        d,
                        err,
                        format!(
                            "curves from {from_i} and {from_j}: {} rad/s at {y} = {} (band ±{})",
                            sig(d),
                            sig(at),
                            sig(band(err))
                        ),
                    ));
                }
            }
        }
        let compared = all.iter().filter(|c| judged(c.1)).count();
        let unjudged = all.len() - compared;
        // the comparison farthest outside its own band (or least inside)
        let worst = all
            .iter()
            .filter(|c| judged(c.1))
            .max_by(|a, b| (a.0 / band(a.1)).total_cmp(&(b.0 / band(b.1))));
        let (worst, tol) = worst.map_or((f64::NAN, 2e-3), |c| (c.0, band(c.1)));
        let rows: Vec<&str> = all.iter().map(|c| c.2.as_str()).collect();
        let extents: Vec<String> = codim2
            .iter()
            .map(|(from, _, c)| match c {
                Ok((c2, stops)) => format!(
                    "from {from}: {} points over {y} = {} … {}, stops: {} / {}",
                    c2.len(),
                    sig(c2.iter().map(|p| p.1).fold(f64::INFINITY, f64::min)),
                    sig(c2.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max)),
                    stops[0],
                    stops[1]
                ),
                Err(e) => format!("from {from}: none ({e})"),
            })
            .collect();
        out.compare(
            Comparison::new(
                &quantity,
                "rad/s",
                Reference::computed(0.0, "the two continuations locate one curve"),
                worst,
                Tolerance::stated(
                    ToleranceBand::Absolute(tol),
                    "the comparison farthest outside its own band: twice the linear-interpolation error of the codim-2 curve at the compared point (|Δ²ω|/8 of the three nearest on its smooth piece) plus the codim-1 location tolerance (1e-3 rad/s) twice; comparisons where that error is unknown or above one map cell are shown, not judged",
                ),
            )
            .class(Evidence::Consistency)
            .cause(if compared > 0 && worst <= tol {
                ""
            } else if compared == 0 {
                "no judged comparison: no codim-2 curve reaches another slice with a grazing or overlaps another curve, or each comparison lies where a curve's interpolation error exceeds a map cell (their extents, stop reasons and comparisons in the note and the `curves` table)"
            } else {
                "the codim-2 curves miss grazings on the other slices or each other (listed in the note): where the curves from two slices meet, several mesh-period maxima of the drive-flank gap graze within about a rad/s of each other, the envelopes from the two sides stop there (a cycle, the switch cap, no progress or a failed restart: stops in the note) and end on different local-maximum curves"
            })
            .note(&format!(
                "{compared} comparisons judged, {unjudged} shown only ({}); codim-2 curves {}",
                rows.join("; "),
                extents.join("; ")
            )),
        );
        let mut c2_points = 0;
        for (from, _, c) in &codim2 {
            let Ok((c2, stops)) = c else { continue };
            c2_points += c2.len();
            let label = format!("unilateral onset, codim-2 curve from {from}");
            for p in c2 {
                curves_t.push(vec![
                    chart.name.into(),
                    label.as_str().into(),
                    p.1.into(),
                    p.0.into(),
                    crate::Cell::count(if p.2 { 1.0 } else { 0.0 }),
                    format!("stops: {} / {}", stops[0], stops[1])
                        .as_str()
                        .into(),
                ])?;
            }
            curves.push(Boundary {
                label,
                style: CurveStyle::Solid,
                colour: 1,
                points: c2.iter().map(|p| (p.0, p.1)).collect(),
                stable: c2.iter().map(|p| p.2).collect(),
                why: vec![String::new(); c2.len()],
                breaks: Vec::new(),
            });
        }
        cost_t.push(vec![
            chart.name.into(),
            "codim-2 grazing curves".into(),
            crate::Cell::count(codim2.iter().filter(|c| c.2.is_ok()).count() as f64),
            crate::Cell::count(c2_points as f64),
        ])?;
        let g = agreement(&codes, &xs, &ys, &curves);
        let failed = codes.iter().filter(|c| c.is_nan()).count();
        let not_p1 = codes.iter().filter(|&&c| not_period_one(c)).count() - failed;
        let mut map = Heatmap::new(
            &format!("map_{}", chart.name),
            &format!(
                "Liu rattle design chart: ω1 × {} (long-window state, curves by continuation)",
                chart.y.0
            ),
            [("omega1", "rad/s"), chart.y, ("state", "-")],
            xs.clone(),
            ys.clone(),
            codes,
            states(),
        )?;
        for c in &curves {
            map = map.with_curve(Curve {
                label: c.label.clone(),
                points: c.drawn_points(),
                style: c.style,
                colour: c.colour,
            })?;
        }
        out.heatmap(map);
        out.compare(
            Comparison::new(
                &format!(
                    "(ω1, {y}) map: boundary cells neither within one cell of a curve nor beside a cell that is not period-1"
                ),
                "1",
                Reference::computed(0.0, "every boundary explained (issue 39)"),
                g.unexplained.len() as f64,
                Tolerance::stated(
                    ToleranceBand::Absolute(0.0),
                    "none may be left: a boundary the continuation misses is a deviation",
                ),
            )
            .class(Evidence::Consistency)
            .cause(if g.unexplained.is_empty() {
                ""
            } else {
                "boundary cells that no curve and no chaotic band explain (listed in the note): the slices are a fifth of the range apart, so a boundary that bends between two slices leaves the straight piece drawn between them, and a state change that no special point of the period-1 branch marks (another attractor reached from the map's single start: coexistence) has no curve"
            })
            .note(&format!(
                "{} boundary cells (rattle state differs from a 4-neighbour's): {} within one cell of a curve, {} beside a cell that is not period-1 (chaotic band / period-n: no period-1 orbit is the attractor there), {} unexplained{}; {failed} failed cells, {not_p1} cells not period-1",
                g.boundary,
                g.near_curve,
                g.chaotic,
                g.unexplained.len(),
                if g.unexplained.is_empty() {
                    String::new()
                } else {
                    format!(" at (ω1, {y}) = {}", cells_text(&g.unexplained, &xs, &ys))
                }
            )),
        );
        out.compare(
            Comparison::new(
                &format!(
                    "(ω1, {y}) map: curve cells that separate no two states and lie in no named region"
                ),
                "1",
                Reference::computed(0.0, "every curve separates states (issue 39)"),
                g.curve_unexplained.len() as f64,
                Tolerance::stated(
                    ToleranceBand::Absolute(0.0),
                    "none may be left: a curve inside one state is a deviation unless named",
                ),
            )
            .class(Evidence::Consistency)
            .cause(if g.curve_unexplained.is_empty() {
                ""
            } else {
                "curve cells inside one state on a stable orbit (listed in the note): the straight piece between two slices leaves a bending boundary, or the map's single start reaches another attractor than the continued orbit (coexistence)"
            })
            .note(&format!(
                "{} cells on the curves: {} separate two states (within one cell), {} beside a cell that is not period-1 (chaotic band), {} on an unstable orbit (no time integration reaches it: coexistence with the attractor the map shows), {} unexplained{}",
                g.curve_cells,
                g.separating,
                g.curve_chaotic,
                g.curve_unstable,
                g.curve_unexplained.len(),
                if g.curve_unexplained.is_empty() {
                    String::new()
                } else {
                    format!(
                        " at (ω1, {y}) = {}",
                        cells_text(&g.curve_unexplained, &xs, &ys)
                    )
                }
            )),
        );
        // the CPU seconds of map and curves vary run to run: they go to the run's cost table
        // (validation/stats/cost.csv, outside the stats digest) and to stderr, never into a
        // committed or digested output
        eprintln!(
            "liu2021-design-charts (ω1, {y}): map {t_map:.1} CPU s, curves {t_curves:.1} CPU s, codim-2 grazing curves {t_codim2:.1} CPU s"
        );
        out.note(format!(
            "(ω1, {y}) chart: map of {} cells, curves from {} slices ({} branches, {points} branch points) and a codim-2 grazing curve from each slice's grazing (the CPU seconds of each part: docs/performance.md)",
            N * N,
            SLICES,
            2 * SLICES,
        ));
        for (k, s) in slices.iter().enumerate() {
            for (b, dir) in [(&s.up, "up"), (&s.down, "down")] {
                if let Err(e) = b {
                    out.note(format!(
                        "(ω1, {y}) slice {k} ({y} = {}), branch {dir}: {e}",
                        sig(s.y)
                    ));
                }
            }
        }
    }
    out.table(curves_t);
    out.table(cost_t.unsettled_record(
        "the work of the map and the curves (their CPU seconds: stderr and the run's cost table)",
    ));
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn boundary(points: Vec<(f64, f64)>, stable: bool) -> Boundary {
        let n = points.len();
        Boundary {
            label: "c".to_owned(),
            style: CurveStyle::Solid,
            colour: 0,
            points,
            stable: vec![stable; n],
            why: vec![String::new(); n],
            breaks: Vec::new(),
        }
    }

    /// Interval cover: overlapping and touching intervals join, a gap anywhere fails, and
    /// unordered or non-finite intervals count for nothing.
    #[test]
    fn intervals_cover_only_without_gaps() {
        assert!(covered(&[(0.0, 2.0), (1.5, 4.0)], 0.5, 3.5));
        assert!(covered(&[(1.5, 4.0), (0.0, 1.5)], 0.0, 4.0));
        assert!(!covered(&[(0.0, 1.0), (1.1, 4.0)], 0.5, 3.5));
        assert!(!covered(&[(0.0, 3.0)], 0.5, 3.5));
        assert!(!covered(&[(0.2, 4.0)], 0.0, 1.0));
        assert!(!covered(&[(f64::NAN, 5.0), (3.0, 1.0)], 1.5, 2.0));
        assert!(!covered(&[], 0.0, 1.0));
    }

    /// A broken piece is neither sampled into curve cells nor drawn: its two ends are isolated
    /// points, and the plot gets a gap between them.
    #[test]
    fn a_broken_piece_has_no_cells_and_a_gap() {
        let xs: Vec<f64> = (0..10).map(f64::from).collect();
        let ys = xs.clone();
        let mut c = boundary(vec![(1.0, 1.0), (8.0, 8.0), (8.0, 9.0)], true);
        let joined = curve_cells(&c, &xs, &ys).len();
        assert_eq!(joined, 9); // the diagonal 1..=8 and (8, 9)
        c.breaks = vec![true, false, false];
        let cells: Vec<(usize, usize)> = curve_cells(&c, &xs, &ys)
            .iter()
            .map(|&(i, j, _)| (i, j))
            .collect();
        assert_eq!(cells, vec![(1, 1), (8, 8), (8, 9)]);
        let drawn = c.drawn_points();
        assert_eq!(drawn.len(), 4);
        assert!(drawn[1].0.is_nan() && drawn[1].1.is_nan());
        assert_eq!((drawn[2], drawn[3]), ((8.0, 8.0), (8.0, 9.0)));
        // crosses are never joined, and get no gap markers
        c.style = CurveStyle::Crosses;
        c.breaks.clear();
        assert_eq!(c.drawn_points().len(), 3);
        assert_eq!(curve_cells(&c, &xs, &ys).len(), 3);
    }

    /// A 6 × 4 map split at x = 2.5 by a vertical curve: every boundary cell is near it and
    /// every curve cell separates; a second curve inside one state is unexplained when its
    /// orbit is stable and named (unstable orbit) when not; a non-period-1 cell names the
    /// boundary beside it.
    #[test]
    fn agreement_counts_boundaries_and_curves() {
        let xs: Vec<f64> = (0..6).map(f64::from).collect();
        let ys: Vec<f64> = (0..4).map(f64::from).collect();
        let codes: Vec<f64> = (0..24).map(|k| if k % 6 < 3 { 0.0 } else { 1.0 }).collect();
        let split = boundary(vec![(2.5, 0.0), (2.5, 3.0)], true);
        let g = agreement(&codes, &xs, &ys, std::slice::from_ref(&split));
        assert_eq!(g.boundary, 8);
        assert_eq!(g.near_curve, 8);
        assert!(g.unexplained.is_empty());
        assert_eq!(g.curve_cells, g.separating);
        let inside = boundary(vec![(0.0, 0.0), (0.0, 3.0)], true);
        let g = agreement(&codes, &xs, &ys, &[split, inside]);
        assert_eq!(g.curve_unexplained.len(), 4);
        let unstable = boundary(vec![(0.0, 0.0), (0.0, 3.0)], false);
        let g = agreement(&codes, &xs, &ys, &[unstable]);
        assert_eq!((g.curve_unstable, g.near_curve), (4, 0));
        assert_eq!(g.unexplained.len(), 8, "no curve near the boundary");
        let mut chaotic = codes.clone();
        chaotic[3] = 4.0; // bilateral, not period-1, at (3, 0)
        let g = agreement(&chaotic, &xs, &ys, &[]);
        assert!(g.chaotic > 0 && g.chaotic + g.unexplained.len() == g.boundary);
    }

    /// Linear interpolation of a curve in `y` with its error estimate: exact on a line (error
    /// 0), the `h²|ω''|/8` bound on a parabola (ω = y², h = 1: 1/4 · 1/… ≥ the true error).
    #[test]
    fn curve_interpolation_and_its_error() {
        let line: Codim2Curve = (0..5)
            .map(|i| (2.0 * f64::from(i) + 1.0, f64::from(i), true, 0))
            .collect();
        let (w, e) = interpolate(&line, 2.5).unwrap();
        assert!((w - 6.0).abs() < 1e-12 && e.abs() < 1e-12);
        assert!(interpolate(&line, 7.0).is_none());
        let parabola: Codim2Curve = (0..5)
            .map(|i| (f64::from(i * i), f64::from(i), true, 0))
            .collect();
        let (w, e) = interpolate(&parabola, 1.5).unwrap();
        let truth = 1.5 * 1.5;
        assert!((w - 2.5).abs() < 1e-12);
        assert!(
            (w - truth).abs() <= e + 1e-12,
            "estimate {e} bounds the error {}",
            w - truth
        );
        // a repeated y after the bracket is passed over for the third point: the estimate
        // stays finite, and equals the one from the next distinct point
        let mut repeated = parabola.clone();
        repeated.insert(3, repeated[2]);
        let (wr, er) = interpolate(&repeated, 1.5).unwrap();
        assert!(
            wr.to_bits() == w.to_bits() && er.is_finite() && er.to_bits() == e.to_bits(),
            "{wr} {er} vs {w} {e}"
        );
        // decreasing y (a curve traced downwards) works too
        let rev: Codim2Curve = parabola.iter().rev().copied().collect();
        assert!((interpolate(&rev, 1.5).unwrap().0 - 2.5).abs() < 1e-12);
        // a curve that turns in y crosses it twice, in trace order
        let turn = [
            (0.0, 0.0, true, 0),
            (1.0, 1.0, true, 0),
            (2.0, 0.0, true, 0),
        ];
        let c = crossings(&turn, 0.5);
        assert_eq!(c.len(), 2);
        assert!((c[0].0 - 0.5).abs() < 1e-12 && (c[1].0 - 1.5).abs() < 1e-12);
        assert!(crossings(&turn, 1.5).is_empty());
        // the extent of a curve in both coordinates
        let none = (0.0, 0.0);
        assert!(spans_point(&turn, 1.5, 0.5, none) && spans_point(&turn, 0.0, 1.0, none));
        assert!(!spans_point(&turn, 2.5, 0.5, none) && !spans_point(&turn, 1.0, 1.5, none));
        // widened by a margin
        assert!(spans_point(&turn, 2.5, 0.5, (0.5, 0.0)));
        assert!(spans_point(&turn, 1.0, 1.5, (0.0, 0.5)));
    }

    /// An envelope with a corner: ω = y on piece 0 up to the double grazing at y = 2, where it
    /// turns back in y along ω = 2 + (2 − y)·1.5 + 0.5 on piece 1 (the restart 10⁻⁶ before
    /// the corner, on the other extremum's curve half a rad/s away, as the back restart leaves
    /// it). The estimate takes its third point on the bracket's own piece: exact (0) on the
    /// lines. Across the corner the second difference would divide the half rad/s by the
    /// 10⁻⁶ of y between the two sides: about 10⁵ here, and without bound as the bracket of
    /// the double grazing shrinks.
    #[test]
    fn curve_error_stays_on_the_smooth_piece() {
        let back = |y: f64| 2.5 + 1.5 * (2.0 - y);
        let mut cornered: Codim2Curve = vec![
            (0.0, 0.0, true, 0),
            (1.0, 1.0, true, 0),
            (2.0, 2.0, true, 0),
            (back(2.0 - 1e-6), 2.0 - 1e-6, true, 1),
        ];
        cornered.extend([1.0, 0.0].map(|y| (back(y), y, true, 1)));
        let c = crossings(&cornered, 1.5);
        assert_eq!(c.len(), 2);
        assert!(
            (c[0].0 - 1.5).abs() < 1e-12 && c[0].1.abs() < 1e-12,
            "{c:?}"
        );
        assert!(
            (c[1].0 - back(1.5)).abs() < 1e-12 && c[1].1.abs() < 1e-9,
            "{c:?}"
        );
        // one piece throughout: the corner enters the estimate
        let one: Codim2Curve = cornered.iter().map(|p| (p.0, p.1, p.2, 0)).collect();
        let e = crossings(&one, 1.5)[0].1;
        assert!(e > 1e4, "{e}");
    }

    /// The (ω1, a_k) onset envelope from the a_k = 0.425 slice, traced up: near a_k ≈ 0.46,
    /// ω1 ≈ 120–125 rad/s several mesh-period maxima lie close to the flank together, and
    /// the restarts go round them. The envelope ends at the first double grazing met again
    /// ([`orbit::EnvelopeEnd::Cycle`]) with every switch point its own; before that check, the
    /// twelve switches went round one loop of six points four times (88 points).
    #[test]
    #[ignore = "heavy: run optimised by `cargo xtask heavy-tests` (.ci/run)"]
    fn onset_envelope_ends_where_it_goes_round() {
        let chart = charts().into_iter().nth(1).unwrap();
        assert_eq!(chart.name, "ak");
        let y0 = 0.425;
        let mut p = base();
        (chart.set)(&mut p, y0);
        let up = speed_branch_at(
            p,
            OMEGA[0],
            1.0,
            [OMEGA[0] - 1.0, OMEGA[1] + 1.0],
            &tuning(),
        )
        .unwrap();
        let start = up.0.special.iter().find(|s| s.kind == UNI).unwrap();
        let mut p = base();
        p.omega1 = OMEGA[0];
        (chart.set)(&mut p, y0);
        let m = model(&p).unwrap();
        let mut prob = OrbitProblem::new(Liu::new(p).unwrap(), m.period()).unwrap();
        let o = envelope_options(&chart, &m, up.1, false, 1.0);
        let env = prob
            .continue_grazing_envelope(start, &o, MAX_SWITCHES)
            .unwrap();
        assert_eq!(env.end, orbit::EnvelopeEnd::Cycle, "{:?}", env.stop());
        assert!(env.pieces.len() < MAX_SWITCHES, "{}", env.pieces.len());
        let conv = up.1;
        let sw = env.switches();
        for (i, a) in sw.iter().enumerate() {
            for b in &sw[..i] {
                let dw = (a.first_parameter - b.first_parameter).abs() / conv;
                let dy = (a.parameter - b.parameter).abs() / chart.scale;
                assert!(dw > 1e-3 || dy > 1e-3, "switch {i} repeats one before");
            }
        }
        // the envelope runs from the slice's grazing up to the cluster
        let pts = env.points();
        let last = pts.last().unwrap();
        assert!(
            (0.45..0.48).contains(&last.parameter),
            "ends at a_k = {}",
            last.parameter
        );
    }

    /// The onset envelopes' options: on the slices ω1 is the unknown and the second parameter
    /// is traced; for the edge curve the roles swap, each parameter keeping its range and
    /// arclength scale.
    #[test]
    fn envelope_options_swap_the_parameters() {
        let chart = charts().into_iter().nth(1).unwrap();
        let mut p = base();
        p.omega1 = OMEGA[0];
        let m = model(&p).unwrap();
        let conv = m.omega_c / OMEGA[0];
        let omega_range = [(OMEGA[0] - 1.0) * conv, (OMEGA[1] + 1.0) * conv];
        let ak = Parameter::Named("ak".to_owned());
        let bits = |a: [f64; 2]| a.map(f64::to_bits);
        let slice = envelope_options(&chart, &m, conv, false, 1.0).corrector;
        assert_eq!(slice.first, Parameter::BaseFrequency);
        assert_eq!(slice.parameter, ak);
        assert_eq!(bits(slice.first_range), bits(omega_range));
        assert_eq!(bits(slice.range), bits(chart.range));
        assert_eq!(
            [slice.first_scale, slice.parameter_scale, slice.direction].map(f64::to_bits),
            [conv, chart.scale, 1.0].map(f64::to_bits)
        );
        let edge = envelope_options(&chart, &m, conv, true, -1.0).corrector;
        assert_eq!(edge.first, ak);
        assert_eq!(edge.parameter, Parameter::BaseFrequency);
        assert_eq!(bits(edge.first_range), bits(chart.range));
        assert_eq!(bits(edge.range), bits(omega_range));
        assert_eq!(
            [edge.first_scale, edge.parameter_scale, edge.direction].map(f64::to_bits),
            [chart.scale, conv, -1.0].map(f64::to_bits)
        );
    }

    #[test]
    fn codes_map_to_states() {
        assert_eq!(rsv_of(0.0), Some(0));
        assert_eq!(rsv_of(2.0), Some(2));
        assert_eq!(rsv_of(3.0), Some(1));
        assert_eq!(rsv_of(4.0), Some(2));
        assert_eq!(rsv_of(f64::NAN), None);
        assert!(not_period_one(3.0) && not_period_one(f64::NAN) && !not_period_one(2.0));
        assert_eq!(index(2.6, &[0.0, 1.0, 2.0, 3.0]), Some(3));
        assert_eq!(index(3.6, &[0.0, 1.0, 2.0, 3.0]), None);
    }
}
