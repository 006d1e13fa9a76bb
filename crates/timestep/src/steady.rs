//! Steady state, Poincaré sections, largest Lyapunov exponent and motion classification.

use math::DetMath;
use std::cell::RefCell;

use crate::driver::integrate;
use crate::error::{Error, Result, check_finite_slice, check_positive};
use crate::options::{Options, Output};
use crate::solution::{Event, Stats, Status};
use crate::system::{Direction, EventAction, OdeSystem};

/// How transients are discarded before sampling.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum Transient {
    /// Integrate exactly this many forcing periods.
    Periods(usize),
    /// Integrate period by period until the stroboscopic state repeats after `m ≤ max_order`
    /// periods to `tol` (`|P_k − P_{k−m}|_∞ ≤ tol·(1 + |P_k|_∞)`), at least `min_periods` and
    /// at most `max_periods` periods. Not converging is reported, not an error.
    Converge {
        /// Relative tolerance of the period-to-period test.
        tol: f64,
        /// Minimum number of transient periods.
        min_periods: usize,
        /// Maximum number of transient periods.
        max_periods: usize,
        /// Largest subharmonic order accepted as converged (1 = period-1 only).
        max_order: usize,
    },
}

/// Settings of [`steady_state`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SteadyOptions {
    /// Forcing period `T` (> 0).
    pub period: f64,
    /// Transient handling.
    pub transient: Transient,
    /// Number of periods sampled after the transient (≥ 1).
    pub sample_periods: usize,
    /// Uniform samples per period (≥ 2); the window holds `sample_periods·samples_per_period`
    /// samples, end point excluded, so that harmonic `h` falls exactly in FFT bin
    /// `h·sample_periods`.
    pub samples_per_period: usize,
}

impl SteadyOptions {
    /// Period `T`, convergence to 1e-8 within 10..2000 periods (orders up to 8), then 8 periods
    /// of 128 samples.
    pub fn new(period: f64) -> Self {
        Self {
            period,
            transient: Transient::Converge {
                tol: 1e-8,
                min_periods: 10,
                max_periods: 2000,
                max_order: 8,
            },
            sample_periods: 8,
            samples_per_period: 128,
        }
    }
}

/// Result of [`steady_state`].
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SteadyState {
    /// Number of states.
    pub dim: usize,
    /// Whether the convergence test passed (always true for [`Transient::Periods`]).
    pub converged: bool,
    /// Subharmonic order found by the convergence test (`None` if not applicable).
    pub order: Option<usize>,
    /// Transient periods integrated.
    pub transient_periods: usize,
    /// Start of the sampled window.
    pub t0: f64,
    /// Sampling interval `T / samples_per_period`.
    pub dt: f64,
    /// Sample times.
    pub t: Vec<f64>,
    /// Samples, row-major (`dim` per sample).
    pub y: Vec<f64>,
    /// Status of the last integration segment.
    pub status: Status,
    /// Accumulated work counters.
    pub stats: Stats,
}

impl SteadyState {
    /// Time series of component `j`.
    pub fn component(&self, j: usize) -> Vec<f64> {
        if j >= self.dim {
            return Vec::new();
        }
        self.y.iter().skip(j).step_by(self.dim).copied().collect()
    }
    /// Stroboscopic points (state at the start of each sampled period), row-major.
    pub fn stroboscopic(&self, samples_per_period: usize) -> Vec<f64> {
        self.y
            .chunks(self.dim)
            .step_by(samples_per_period.max(1))
            .flatten()
            .copied()
            .collect()
    }
}

fn inf_norm_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

fn inf_norm(a: &[f64]) -> f64 {
    a.iter().map(|x| x.abs()).fold(0.0, f64::max)
}

/// Discards the transient and samples an integer number of forcing periods.
pub fn steady_state<S: OdeSystem + ?Sized>(
    sys: &S,
    t0: f64,
    y0: &[f64],
    opts: &Options,
    ss: &SteadyOptions,
) -> Result<SteadyState> {
    check_positive("period", ss.period)?;
    if ss.sample_periods == 0 || ss.samples_per_period < 2 {
        return Err(Error::InvalidParameter {
            name: "sample_periods >= 1 and samples_per_period",
            bound: ">= 2",
            value: ss.samples_per_period as f64,
        });
    }
    let tp = ss.period;
    let mut o = opts.clone().with_output(Output::Final);
    let mut stats = Stats::default();
    let mut t = t0;
    let mut y = y0.to_vec();
    let mut history: Vec<Vec<f64>> = vec![y.clone()];
    let (mut converged, mut order, mut k_done) = (true, None, 0usize);
    let mut status = Status::Completed;
    match ss.transient {
        Transient::Periods(np) => {
            let t1 = t0 + np as f64 * tp;
            let s = integrate(sys, t, &y, t1, &o)?;
            stats.add(&s.stats);
            status = s.status;
            t = t1;
            y = s.y_final;
            k_done = np;
        }
        Transient::Converge {
            tol,
            min_periods,
            max_periods,
            max_order,
        } => {
            check_positive("convergence tol", tol)?;
            converged = false;
            for k in 1..=max_periods {
                let t1 = t0 + k as f64 * tp;
                let s = integrate(sys, t, &y, t1, &o)?;
                stats.add(&s.stats);
                status = s.status;
                if s.h_last.is_finite() && s.h_last > 0.0 {
                    o.h_init = Some(s.h_last);
                }
                t = t1;
                y = s.y_final;
                k_done = k;
                if !status.is_success() {
                    break;
                }
                history.push(y.clone());
                if history.len() > max_order.max(1) + 1 {
                    history.remove(0);
                }
                if k >= min_periods {
                    let last = history.len() - 1;
                    let scale = 1.0 + inf_norm(&y);
                    if let Some(m) = (1..=max_order.max(1)).find(|&m| {
                        m <= last
                            && inf_norm_diff(&history[last], &history[last - m]) <= tol * scale
                    }) {
                        converged = true;
                        order = Some(m);
                        break;
                    }
                }
            }
        }
    }
    let n = ss.sample_periods * ss.samples_per_period;
    let dt = tp / ss.samples_per_period as f64;
    let times: Vec<f64> = (0..n).map(|i| t + i as f64 * dt).collect();
    let t_end = t + ss.sample_periods as f64 * tp;
    let o = opts.clone().with_output(Output::Times(times));
    let s = integrate(sys, t, &y, t_end, &o)?;
    stats.add(&s.stats);
    if !s.status.is_success() {
        status = s.status;
    }
    Ok(SteadyState {
        dim: y0.len(),
        converged,
        order,
        transient_periods: k_done,
        t0: t,
        dt,
        t: s.t,
        y: s.y,
        status,
        stats,
    })
}

/// Points of a Poincaré section, row-major.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct PoincareSection {
    /// Number of states per point.
    pub dim: usize,
    /// Times of the points.
    pub t: Vec<f64>,
    /// Points (`dim` values each).
    pub points: Vec<f64>,
}

impl PoincareSection {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.t.len()
    }
    /// True if there are no points.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }
    /// Point `i`.
    pub fn point(&self, i: usize) -> &[f64] {
        &self.points[i * self.dim..(i + 1) * self.dim]
    }
}

/// Stroboscopic Poincaré section: the state at `t0 + k T` for `k = skip .. skip + n_points`.
pub fn poincare_stroboscopic<S: OdeSystem + ?Sized>(
    sys: &S,
    t0: f64,
    y0: &[f64],
    period: f64,
    skip: usize,
    n_points: usize,
    opts: &Options,
) -> Result<PoincareSection> {
    check_positive("period", period)?;
    let times: Vec<f64> = (skip..skip + n_points)
        .map(|k| t0 + k as f64 * period)
        .collect();
    let t_end = t0 + (skip + n_points.max(1) - 1) as f64 * period;
    let s = integrate(
        sys,
        t0,
        y0,
        t_end,
        &opts.clone().with_output(Output::Times(times)),
    )?;
    Ok(PoincareSection {
        dim: s.dim,
        t: s.t,
        points: s.y,
    })
}

struct Surface<'a, S: ?Sized, G> {
    inner: &'a S,
    g: G,
    direction: Direction,
    t_min: f64,
    hits: RefCell<(Vec<f64>, Vec<f64>)>,
}

impl<S: OdeSystem + ?Sized, G: Fn(f64, &[f64]) -> f64> OdeSystem for Surface<'_, S, G> {
    fn dim(&self) -> usize {
        self.inner.dim()
    }
    fn rhs(&self, t: f64, y: &[f64], dydt: &mut [f64]) {
        self.inner.rhs(t, y, dydt)
    }
    fn n_events(&self) -> usize {
        self.inner.n_events() + 1
    }
    fn events(&self, t: f64, y: &[f64], g: &mut [f64]) {
        let n = self.inner.n_events();
        self.inner.events(t, y, &mut g[..n]);
        g[n] = (self.g)(t, y);
    }
    fn event_direction(&self, index: usize) -> Direction {
        if index == self.inner.n_events() {
            self.direction
        } else {
            self.inner.event_direction(index)
        }
    }
    fn on_event(&self, event: &Event, y: &mut [f64]) -> EventAction {
        if event.index == self.inner.n_events() {
            if event.t >= self.t_min {
                let mut h = self.hits.borrow_mut();
                h.0.push(event.t);
                h.1.extend_from_slice(y);
            }
            EventAction::Continue
        } else {
            self.inner.on_event(event, y)
        }
    }
}

/// Poincaré section on a user surface `surface(t, y) = 0` crossed in `direction`, collected
/// for `t_transient ≤ t ≤ t_end`. The crossings are located events (see [`integrate`]).
pub fn poincare_surface<S, G>(
    sys: &S,
    t0: f64,
    y0: &[f64],
    t_transient: f64,
    t_end: f64,
    surface: G,
    direction: Direction,
    opts: &Options,
) -> Result<PoincareSection>
where
    S: OdeSystem + ?Sized,
    G: Fn(f64, &[f64]) -> f64,
{
    let w = Surface {
        inner: sys,
        g: surface,
        direction,
        t_min: t_transient,
        hits: RefCell::new((Vec::new(), Vec::new())),
    };
    integrate(
        &w,
        t0,
        y0,
        t_end,
        &opts.clone().with_output(Output::Final).with_events(true),
    )?;
    let (t, points) = w.hits.into_inner();
    Ok(PoincareSection {
        dim: sys.dim(),
        t,
        points,
    })
}

/// Smallest `n ≤ max_period` such that the section repeats after `n` points to `tol`
/// (`|P_{k+n} − P_k|_∞ ≤ tol·(1 + max|P|)` for all `k`), or `None`.
pub fn detect_period(section: &PoincareSection, max_period: usize, tol: f64) -> Option<usize> {
    detect_period_scaled(section, max_period, tol, 1.0)
}

/// As [`detect_period`] with the tolerance relative to `scale + max|P|` (`scale` = the state
/// magnitude of the problem; 1 in [`detect_period`]).
fn detect_period_scaled(
    section: &PoincareSection,
    max_period: usize,
    tol: f64,
    scale: f64,
) -> Option<usize> {
    let m = section.len();
    let scale = scale + inf_norm(&section.points);
    (1..=max_period).find(|&n| {
        n < m
            && (0..m - n)
                .all(|k| inf_norm_diff(section.point(k + n), section.point(k)) <= tol * scale)
    })
}

/// As [`detect_period`] on a two-coordinate section `(q_k, v_k)` with an absolute tolerance:
/// the smallest `n ≤ max_period` with `|q_{k+n} − q_k| ≤ tol` and `|v_{k+n} − v_k| ≤ tol` for
/// every `k`, accepted only with at least `n + 2` points (so that the repetition is seen
/// twice); else [`Motion::NonPeriodic`]. No Lyapunov exponent: a cheap test for sweeps whose
/// one-period metrics need period-1 motion.
pub fn detect_period_abs(q: &[f64], v: &[f64], max_period: usize, tol: f64) -> Motion {
    let len = q.len().min(v.len());
    for n in 1..=max_period {
        if len < n + 2 {
            break;
        }
        let repeats =
            (0..len - n).all(|k| (q[k + n] - q[k]).abs() <= tol && (v[k + n] - v[k]).abs() <= tol);
        if repeats {
            return Motion::Periodic(n);
        }
    }
    Motion::NonPeriodic
}

/// Largest repeat distance of a stroboscopic section at period `n`:
/// `max_k max(|q_{k+n} − q_k|, |v_{k+n} − v_k|)` over the section points, the quantity that
/// [`detect_period_abs`] compares with its tolerance. `+∞` when fewer than `n + 2` points are
/// given (the period cannot be accepted), when `n = 0`, or when a difference is not finite
/// (NaN never compares below a tolerance).
///
/// Its ratio to the tolerance is the margin of a classification: a section that repeats at
/// 1/100 of the tolerance is periodic under any retune of the integrator that moves the
/// points by less than that, one that repeats just inside it is not confirmed.
pub fn section_repeat_distance(q: &[f64], v: &[f64], n: usize) -> f64 {
    let len = q.len().min(v.len());
    if n == 0 || len < n + 2 {
        return f64::INFINITY;
    }
    let mut d = 0.0_f64;
    for k in 0..len - n {
        let (dq, dv) = ((q[k + n] - q[k]).abs(), (v[k + n] - v[k]).abs());
        // checked one by one: `f64::max` would drop a NaN
        if !(dq.is_finite() && dv.is_finite()) {
            return f64::INFINITY;
        }
        d = d.max(dq).max(dv);
    }
    d
}

/// Settings of [`largest_lyapunov`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct LyapunovOptions {
    /// Initial (and renormalised) separation `d0` (Euclidean norm of the state difference).
    pub d0: f64,
    /// Renormalisation interval τ (e.g. the forcing period).
    pub interval: f64,
    /// Number of renormalisations.
    pub n_intervals: usize,
}

/// Estimate of the largest Lyapunov exponent.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct LyapunovEstimate {
    /// `λ = Σ ln(d_k/d0) / (N τ)` (per unit time).
    pub value: f64,
    /// Running estimate after each interval.
    pub history: Vec<f64>,
}

/// Largest Lyapunov exponent by the two-trajectory renormalisation method (Benettin et al.
/// 1980; Wolf et al. 1985). Both trajectories are integrated with event location, so the
/// switching surfaces of a piecewise-smooth system (backlash) are handled exactly for each
/// trajectory and no linearisation across the switch (saltation matrix) is needed — this is
/// why the two-trajectory form is used rather than variational equations. Start `y0` on the
/// attractor (after the transient).
pub fn largest_lyapunov<S: OdeSystem + ?Sized>(
    sys: &S,
    t0: f64,
    y0: &[f64],
    lo: &LyapunovOptions,
    opts: &Options,
) -> Result<LyapunovEstimate> {
    check_positive("d0", lo.d0)?;
    check_positive("interval", lo.interval)?;
    if lo.n_intervals == 0 {
        return Err(Error::InvalidParameter {
            name: "n_intervals",
            bound: ">= 1",
            value: 0.0,
        });
    }
    let n = y0.len();
    let o = opts.clone().with_output(Output::Final);
    let mut yr = y0.to_vec();
    let e = 1.0 / (n as f64).sqrt();
    let mut yp: Vec<f64> = yr.iter().map(|v| v + lo.d0 * e).collect();
    let mut sum = 0.0;
    let mut history = Vec::with_capacity(lo.n_intervals);
    let mut t = t0;
    for k in 0..lo.n_intervals {
        let t1 = t0 + (k + 1) as f64 * lo.interval;
        let a = integrate(sys, t, &yr, t1, &o)?;
        let b = integrate(sys, t, &yp, t1, &o)?;
        yr = a.y_final;
        yp = b.y_final;
        t = t1;
        let d = yr
            .iter()
            .zip(&yp)
            .map(|(r, p)| (p - r) * (p - r))
            .sum::<f64>()
            .sqrt();
        if !(d.is_finite() && d > 0.0) {
            break;
        }
        sum += (d / lo.d0).dln();
        for (p, r) in yp.iter_mut().zip(&yr) {
            *p = r + (*p - r) * lo.d0 / d;
        }
        history.push(sum / ((k + 1) as f64 * lo.interval));
    }
    let value = history.last().copied().unwrap_or(f64::NAN);
    Ok(LyapunovEstimate { value, history })
}

/// Kind of steady motion, from the stroboscopic Poincaré section (one point per forcing
/// period) and, when it does not repeat, the largest Lyapunov exponent.
///
/// The one motion type of the workspace: [`classify_motion`] gives all but
/// [`Motion::NonPeriodic`]; a section test without a Lyapunov exponent
/// ([`detect_period_abs`], used by the Liu 2021 model's sweep strategy) gives `Periodic(n)` or
/// `NonPeriodic`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum Motion {
    /// Period-`n` response (the stroboscopic section has `n` points).
    Periodic(usize),
    /// Not periodic up to the tested order, largest Lyapunov exponent ≤ threshold.
    QuasiPeriodic,
    /// Largest Lyapunov exponent > threshold.
    Chaotic,
    /// Not periodic up to the tested order, not classified further (no Lyapunov exponent).
    NonPeriodic,
}

impl Motion {
    /// `period-1`, `period-2`, …, `quasi-periodic`, `chaotic`, `non-periodic` (the labels of
    /// the validation tables and study outputs).
    pub fn label(self) -> String {
        match self {
            Motion::Periodic(n) => format!("period-{n}"),
            Motion::QuasiPeriodic => "quasi-periodic".to_owned(),
            Motion::Chaotic => "chaotic".to_owned(),
            Motion::NonPeriodic => "non-periodic".to_owned(),
        }
    }

    /// Period multiple `n`, 0 when not periodic (for tables).
    pub fn period_multiple(self) -> u32 {
        match self {
            Motion::Periodic(n) => u32::try_from(n).unwrap_or(u32::MAX),
            _ => 0,
        }
    }

    /// A number for a table cell: `n ≥ 1` for period-`n`, 0 quasi-periodic, −1 chaotic, −2
    /// non-periodic (inverse: [`Motion::from_code`]).
    pub fn code(self) -> f64 {
        match self {
            Motion::Periodic(n) => n as f64,
            Motion::QuasiPeriodic => 0.0,
            Motion::Chaotic => -1.0,
            Motion::NonPeriodic => -2.0,
        }
    }

    /// The motion of a [`Motion::code`]; `None` for a number that is no code.
    pub fn from_code(code: f64) -> Option<Self> {
        if !(code.is_finite() && code.fract() == 0.0) {
            return None;
        }
        if (1.0..=f64::from(u32::MAX)).contains(&code) {
            return Some(Motion::Periodic(code as usize));
        }
        // an integral value in [-2, 0]: exactly one of the three codes
        match code as i64 {
            0 => Some(Motion::QuasiPeriodic),
            -1 => Some(Motion::Chaotic),
            -2 => Some(Motion::NonPeriodic),
            _ => None,
        }
    }
}

/// Settings of [`classify_motion`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ClassifyOptions {
    /// Forcing period (stroboscopic section and Lyapunov renormalisation interval).
    pub period: f64,
    /// Transient periods discarded.
    pub transient_periods: usize,
    /// Section points examined.
    pub n_points: usize,
    /// Largest period-n tested.
    pub max_period: usize,
    /// Relative tolerance of the periodicity test.
    pub tol: f64,
    /// Renormalisations for the Lyapunov exponent.
    pub lyapunov_intervals: usize,
    /// λ above which the motion is chaotic (per unit time).
    pub lyapunov_threshold: f64,
    /// State magnitude `s` of the problem (> 0): the periodicity test is
    /// `|P_{k+n} − P_k|_∞ ≤ tol·(s + max|P|)` and the Lyapunov separation `d0 = 10⁻⁷·(s + |y|)`;
    /// 1 for states of order one, the gap half-width for a backlash coordinate in metres.
    pub scale: f64,
    /// Compute λ for periodic motions too (then negative for a stable cycle: its decay rate);
    /// otherwise only when the section does not repeat.
    pub lyapunov_always: bool,
}

impl ClassifyOptions {
    /// Defaults for forcing period `period`: 200 transient periods, 64 points, period ≤ 16,
    /// tol 1e-5, 300 Lyapunov intervals, threshold 0.01 per unit time, λ only when not
    /// periodic.
    pub fn new(period: f64) -> Self {
        Self {
            period,
            transient_periods: 200,
            n_points: 64,
            max_period: 16,
            tol: 1e-5,
            lyapunov_intervals: 300,
            lyapunov_threshold: 0.01,
            scale: 1.0,
            lyapunov_always: false,
        }
    }
}

/// Classification of a steady motion.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Classification {
    /// Kind of motion.
    pub motion: Motion,
    /// Largest Lyapunov exponent (computed only when the section is not periodic).
    pub lyapunov: Option<f64>,
    /// The stroboscopic section used.
    pub section: PoincareSection,
}

/// Classifies the steady motion from `(t0, y0)`: stroboscopic section after the transient,
/// period-n test, and if not periodic the largest Lyapunov exponent (two-trajectory method)
/// against a threshold.
pub fn classify_motion<S: OdeSystem + ?Sized>(
    sys: &S,
    t0: f64,
    y0: &[f64],
    co: &ClassifyOptions,
    opts: &Options,
) -> Result<Classification> {
    let section = poincare_stroboscopic(
        sys,
        t0,
        y0,
        co.period,
        co.transient_periods,
        co.n_points,
        opts,
    )?;
    // an integration that stopped early (step limit, non-finite state) leaves a short section
    if section.is_empty() || section.len() < co.n_points {
        return Err(Error::TooFewSamples {
            name: "Poincaré section (integration stopped early?)",
            needed: co.n_points.max(2),
            got: section.len(),
        });
    }
    check_finite_slice("Poincaré section", &section.points)?;
    check_positive("scale", co.scale)?;
    let periodic = detect_period_scaled(&section, co.max_period, co.tol, co.scale);
    if let (Some(p), false) = (periodic, co.lyapunov_always) {
        return Ok(Classification {
            motion: Motion::Periodic(p),
            lyapunov: None,
            section,
        });
    }
    let ts = section.t[0];
    let ys = section.point(0).to_vec();
    let scale = co.scale + inf_norm(&ys);
    let lo = LyapunovOptions {
        d0: 1e-7 * scale,
        interval: co.period,
        n_intervals: co.lyapunov_intervals,
    };
    let ly = largest_lyapunov(sys, ts, &ys, &lo, opts)?;
    let motion = if let Some(p) = periodic {
        Motion::Periodic(p)
    } else if ly.value > co.lyapunov_threshold {
        Motion::Chaotic
    } else {
        Motion::QuasiPeriodic
    };
    Ok(Classification {
        motion,
        lyapunov: Some(ly.value),
        section,
    })
}
