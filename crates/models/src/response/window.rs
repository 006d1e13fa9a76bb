//! Long-window rattle statistics of one record, and their spread over several records.

use math::DetMath;
use serde::{Deserialize, Serialize};

use super::metrics::RattleState;
use crate::Error;

/// A gear flank of the backlash coordinate `q` in the gap `−b(t) ≤ q ≤ b(t)`.
///
/// Convention (Liu et al. 2021, Sect. 3.2): the **drive** flank is in contact for `q < −b`
/// (normal loaded mesh, no rattle), the **back** flank for `q > b` (bilateral rattle).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Flank {
    /// `q = −b`: the loaded (drive) flank.
    Drive,
    /// `q = +b`: the back flank.
    Back,
}

/// A located crossing of a gap edge (from the integrator's event location), `entering`
/// when the motion enters contact on that flank (an impact).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Crossing {
    /// Time of the crossing.
    pub t: f64,
    /// The flank.
    pub flank: Flank,
    /// `true` when entering contact (`q` falls below `−b` or rises above `b`).
    pub entering: bool,
}

/// What a window measures ([`WindowOptions::detail`]).
///
/// The lines and the impact speeds cost work per sample: the line sums rotate two phases and
/// add two complex terms, and the speeds need the time and `q'` of every sample kept (16 bytes
/// each) until the window's crossings are known. A caller that reads only the motion (a map
/// cell, a basin cell) leaves both out.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum WindowDetail {
    /// Every statistic of [`WindowStats`].
    #[default]
    Full,
    /// The motion only. The rattle state, the fractions of periods per state, `q_min`,
    /// `q_max`, the ppv, the deepest separation, the impact counts and rates, the section tests
    /// (`period_multiple`, `tail_regular`, `chaos_k`) are bit for bit those of
    /// [`WindowDetail::Full`]. The lines and the impact speeds are NaN.
    Motion,
}

/// Settings of [`window_stats`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WindowOptions {
    /// The forcing period `T` (the stroboscopic period; `ppv`, states and lines refer to it).
    pub period: f64,
    /// Minimum separation depth, as a fraction of the local gap half-width `b`: a period is
    /// unilateral only when `q + b > min_depth · b` somewhere (a separation from the drive flank
    /// deeper than `min_depth·b`). In `[0, 1)`; `0` counts any separation.
    pub min_depth: f64,
    /// Harmonic numbers `k` of the phase-locked lines `k·2π/T` to measure (at most
    /// [`WindowOptions::MAX_LINES`]; `0` is the mean).
    pub lines: [u32; 2],
    /// What the window measures (default: everything).
    #[serde(default)]
    pub detail: WindowDetail,
}

impl WindowOptions {
    /// Number of lines measured.
    pub const MAX_LINES: usize = 2;

    /// Options with period `period`, any separation counted, lines `k = 1` and `k = 2`.
    pub fn new(period: f64) -> Self {
        Self {
            period,
            min_depth: 0.0,
            lines: [1, 2],
            detail: WindowDetail::Full,
        }
    }

    fn validate(&self) -> Result<(), Error> {
        if !(self.period > 0.0 && self.period.is_finite()) {
            return Err(Error::invalid("response.window.period", "> 0", self.period));
        }
        if !(self.min_depth >= 0.0 && self.min_depth < 1.0) {
            return Err(Error::invalid(
                "response.window.min_depth",
                "in [0, 1)",
                self.min_depth,
            ));
        }
        Ok(())
    }
}

/// Impacts on one flank over a window.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub struct FlankImpacts {
    /// Number of impacts (entries into contact) in the window.
    pub count: usize,
    /// Impacts per forcing period.
    pub rate: f64,
    /// Mean impact speed `|q'|` at entry (0 without impacts; NaN under
    /// [`WindowDetail::Motion`]).
    pub mean_speed: f64,
    /// Largest impact speed (0 without impacts; NaN under [`WindowDetail::Motion`]).
    pub max_speed: f64,
}

/// Long-window statistics of one record.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WindowStats {
    /// Whole forcing periods in the window.
    pub periods: usize,
    /// Rattle state over the window (the largest state of its periods).
    pub state: RattleState,
    /// Fraction of periods with no rattle, unilateral, bilateral (sums to 1).
    pub fraction: [f64; 3],
    /// `max q − min q` over the window (the long-window ppv).
    pub ppv: f64,
    /// Minimum of `q` over the window.
    pub q_min: f64,
    /// Maximum of `q` over the window.
    pub q_max: f64,
    /// Deepest separation from the drive flank, `max (q + b)/b` (negative: never separates).
    pub max_depth: f64,
    /// Impacts on the drive flank.
    pub drive: FlankImpacts,
    /// Impacts on the back flank.
    pub back: FlankImpacts,
    /// Coherent amplitude of each line: `|mean over periods of c_k|`, with
    /// `c_k = (2/T)∫ q e^{−ikΩt} dt` over one period (`c_0` the mean, factor 1); NaN under
    /// [`WindowDetail::Motion`].
    pub line_coherent: [f64; 2],
    /// Incoherent amplitude of each line: the mean over periods of `|c_k|`; NaN under
    /// [`WindowDetail::Motion`].
    pub line_incoherent: [f64; 2],
    /// 0–1 test `K` on the stroboscopic section (NaN below 20 periods).
    pub chaos_k: f64,
    /// The last half of the stroboscopic section repeats with a period `n ≤ 4` (the test of
    /// [`WindowStats::regular`] on periods `⌊P/2⌋ … P−1`; false below 20 periods). With
    /// [`WindowStats::regular`] false this marks a window that caught the end of a transient
    /// ([`WindowStats::transient`]).
    #[serde(default)]
    pub tail_regular: bool,
    /// The smallest `n ≤ 4` with which the whole window's stroboscopic section repeats (the
    /// test of [`WindowStats::regular`]); 0 when it does not repeat or the window holds fewer
    /// than 20 periods.
    #[serde(default)]
    pub period_multiple: usize,
}

impl WindowStats {
    /// The window's stroboscopic section repeats with a period `n ≤ 4` to within integration
    /// noise ([`WindowStats::chaos_k`] is then exactly 0, set by that test rather than computed
    /// by the 0–1 test). Over a long window this separates a settled periodic response from a
    /// chaotic one robustly: a 6-period sample of a chaotic orbit with laminar phases can repeat
    /// by chance (Liu Fig. 15 at T2 = 0 N·m: 2.8e-5 of the tolerance under one step-size
    /// controller, 4500× it under another), 50 periods of it do not.
    #[allow(clippy::float_cmp)] // exact: the value 0.0 is assigned, never computed
    pub fn regular(&self) -> bool {
        self.chaos_k == 0.0
    }

    /// The window holds the end of a transient: its section is not periodic over the whole
    /// window but is over its last half ([`WindowStats::tail_regular`]). A long-window record
    /// discards such a window and records the next one (`liu2021::LongWindowOptions::settle_windows`).
    pub fn transient(&self) -> bool {
        !self.regular() && self.tail_regular
    }

    /// Fraction of periods with back-flank contact.
    pub fn bilateral_fraction(&self) -> f64 {
        self.fraction[2]
    }
}

fn state_index(s: RattleState) -> usize {
    match s {
        RattleState::NoRattle => 0,
        RattleState::Unilateral | RattleState::NoContact => 1,
        RattleState::Bilateral => 2,
    }
}

fn state_of_index(i: usize) -> RattleState {
    match i {
        0 => RattleState::NoRattle,
        1 => RattleState::Unilateral,
        _ => RattleState::Bilateral,
    }
}

/// Long-window statistics of samples `(t[i], q[i], v[i])` (ascending `t`, at least two
/// samples per period and one whole period) in the gap `±gap(t)`, with the located gap-edge
/// crossings `crossings` of the same window (may be empty: impacts are then found between
/// samples by linear interpolation).
///
/// The window starts at `t[0]` and holds `P = ⌊(t_last − t_0)/T⌋` whole periods; later samples
/// are ignored. A period's state is the largest over its samples and the crossings in it (a
/// located back-flank entry makes it bilateral even when no sample lies beyond the edge). The
/// impact speed of a located crossing is `|q'|` interpolated linearly between the samples that
/// bracket it.
///
/// The samples are reduced one at a time by a [`WindowAccumulator`], which a long record can
/// feed while it integrates, without storing them (the same result, bit for bit).
///
/// # Errors
/// Invalid options, fewer than two samples, lengths that differ, non-finite or non-ascending
/// times, non-finite samples or gap, or a window shorter than one period.
pub fn window_stats(
    t: &[f64],
    q: &[f64],
    v: &[f64],
    gap: impl Fn(f64) -> f64,
    crossings: &[Crossing],
    options: &WindowOptions,
) -> Result<WindowStats, Error> {
    options.validate()?;
    let n = t.len();
    if n < 2 || q.len() != n || v.len() != n {
        return Err(Error::Solver(format!(
            "response window: need ≥ 2 samples of equal length, got t {n}, q {}, v {}",
            q.len(),
            v.len()
        )));
    }
    for i in 0..n {
        if !(t[i].is_finite() && q[i].is_finite() && v[i].is_finite()) {
            return Err(Error::invalid("response.window.sample", "finite", f64::NAN));
        }
        if i > 0 && t[i] <= t[i - 1] {
            return Err(Error::invalid(
                "response.window.t",
                "strictly ascending",
                t[i],
            ));
        }
    }
    let mut acc = WindowAccumulator::new(t[0], t[n - 1], gap, options)?;
    // the in-window samples are the first `n_in` of the slices: read there, not copied
    acc.store = false;
    acc.push_many(t, q, v);
    let n_in = acc.n_in;
    acc.finish_on(crossings, &t[..n_in], &v[..n_in])
}

/// The in-window sample whose line term waits for the next sample's time (the trapezoid
/// weight reads it): its time, `q`, and the step from the sample before it.
#[derive(Debug, Clone, Copy)]
struct Pending {
    t: f64,
    q: f64,
    step: f64,
}

/// Samples pushed one at a time, on their way to [`WindowAccumulator::push_many`]'s loop.
#[derive(Debug)]
struct Queue {
    t: [f64; Queue::LEN],
    q: [f64; Queue::LEN],
    v: [f64; Queue::LEN],
    len: usize,
}

impl Default for Queue {
    fn default() -> Self {
        Self {
            t: [0.0; Queue::LEN],
            q: [0.0; Queue::LEN],
            v: [0.0; Queue::LEN],
            len: 0,
        }
    }
}

impl Queue {
    /// Samples reduced at a time.
    const LEN: usize = 256;

    /// Adds a sample; true when the queue is full.
    #[inline]
    fn add(&mut self, t: f64, q: f64, v: f64) -> bool {
        self.t[self.len] = t;
        self.q[self.len] = q;
        self.v[self.len] = v;
        self.len += 1;
        self.len == Self::LEN
    }
}

/// The phase `e^{−ikΩ(t−t0)}` of the two lines at the latest in-window sample: it advances by
/// a rotation, recomputed exactly at every period start and whenever the sample step changes,
/// so no rounding accumulates beyond one period.
#[derive(Debug, Clone, Copy)]
struct Phase {
    t0: f64,
    t_end: f64,
    period: f64,
    omega: f64,
    ks: [f64; 2],
    lines: [u32; 2],
    rot: [(f64, f64); 2],
    cur: [(f64, f64); 2],
    last_dt: f64,
    last_period: usize,
}

impl Phase {
    /// Adds the line term of the in-window sample `s` of period `p` to that period's sums
    /// `re`, `im`, with the time of the sample after it (`next`; NaN: none, the weight is 0).
    #[inline(always)]
    fn term(&mut self, s: Pending, next: f64, p: usize, re: &mut [f64; 2], im: &mut [f64; 2]) {
        let dt = if next.is_nan() {
            0.0
        } else {
            (next.min(self.t_end) - s.t).max(0.0)
        };
        // a uniform grid's steps differ in their last bits: reuse the rotation when the
        // step agrees to 1e-9 (phase error ≤ 2πk·1e-9 over a period, reset every period)
        let same_step = (s.step - self.last_dt).abs() <= 1e-9 * self.last_dt.abs();
        let exact = p != self.last_period || !same_step;
        // the trapezoid weight of a line k ≠ 0 (factor 2; `(2·dt)/T` as written per line
        // before, one division per sample instead of two)
        let w_two = 2.0 * dt / self.period;
        for j in 0..2 {
            if exact {
                let (sn, cs) = (self.ks[j] * self.omega * (s.t - self.t0)).dsin_cos();
                self.cur[j] = (cs, -sn);
                let (rs, rc) = (self.ks[j] * self.omega * s.step).dsin_cos();
                self.rot[j] = (rc, -rs);
            } else {
                let (a, b2) = self.cur[j];
                let (c, d) = self.rot[j];
                self.cur[j] = (a * c - b2 * d, a * d + b2 * c);
            }
            let w = if self.lines[j] == 0 {
                1.0 * dt / self.period
            } else {
                w_two
            };
            re[j] += w * s.q * self.cur[j].0;
            im[j] += w * s.q * self.cur[j].1;
        }
        self.last_period = p;
        self.last_dt = s.step;
    }
}

/// [`window_stats`] fed one sample at a time: announce the window by its first and last
/// sample times ([`WindowAccumulator::new`]), [`WindowAccumulator::push`] every sample in
/// ascending time (or [`WindowAccumulator::push_many`] slices of them; either way they are reduced in
/// batches, with the per-sample state in registers), then [`WindowAccumulator::finish`] with
/// the located crossings. The result
/// is [`window_stats`] of the same samples, bit for bit (that function is this one fed from
/// slices); what it keeps is `t` and `q'` of the samples inside the window (the speeds at the
/// located crossings interpolate them) and a few numbers per period, not the samples.
///
/// This is how a long record reduces its samples while it integrates
/// (`timestep::integrate_streamed`): a 50-period Liu window at `Δτ = 0.1` has 971 000
/// samples, which stored as `t`, `y` and the copies of `q` and `q'` took 39 MB.
///
/// An invalid sample (non-finite, not after the one before, a non-finite or negative gap at
/// it) is remembered and reported by [`WindowAccumulator::finish`]; the samples after it are
/// not read.
#[derive(Debug)]
pub struct WindowAccumulator<G: Fn(f64) -> f64> {
    gap: G,
    period: f64,
    min_depth: f64,
    t0: f64,
    t_last: f64,
    periods: usize,
    t_end: f64,
    t_stop: f64,
    t_last_line: f64,
    /// The phase of the lines (kept in registers while [`WindowAccumulator::push_many`] runs).
    phase: Phase,
    state: Vec<usize>,
    q_min: f64,
    q_max: f64,
    max_depth: f64,
    /// `(q, b)` of the sample that set `max_depth` (NaN before one did).
    deepest: (f64, f64),
    line_re: Vec<[f64; 2]>,
    line_im: Vec<[f64; 2]>,
    /// The period of the latest in-window sample, and the start of the next one.
    p: usize,
    next_start: f64,
    /// Samples pushed, and the time of the latest.
    n: usize,
    t_prev: f64,
    pending: Option<Pending>,
    /// A sample past the window's end was pushed: later ones are only checked.
    closed: bool,
    /// `t` and `q'` of the samples in the window (kept when `store`; [`window_stats`] reads
    /// them from its slices instead), and how many samples lie in the window.
    ts: Vec<f64>,
    vs: Vec<f64>,
    store: bool,
    /// [`WindowDetail::Full`]: the lines summed and the impact speeds measured.
    full: bool,
    n_in: usize,
    /// The latest in-window sample `(t, q, q', b)`, for the impacts found between samples.
    last_in: Option<(f64, f64, f64, f64)>,
    drive_scan: Vec<(f64, f64)>,
    back_scan: Vec<(f64, f64)>,
    section: Vec<f64>,
    next_section: usize,
    error: Option<Error>,
    /// Pushed samples not yet reduced (`None` only while they are).
    queue: Option<Box<Queue>>,
}

impl<G: Fn(f64) -> f64> WindowAccumulator<G> {
    /// A window whose samples run from `t_first` to `t_last` (the times of the first and the
    /// last sample that will be pushed; [`WindowAccumulator::finish`] checks both), in the gap
    /// `±gap(t)`.
    ///
    /// # Errors
    /// Invalid options, or a window shorter than one period or longer than 10⁹ of them.
    pub fn new(t_first: f64, t_last: f64, gap: G, options: &WindowOptions) -> Result<Self, Error> {
        options.validate()?;
        let period = options.period;
        let t0 = t_first;
        let span = (t_last - t0) / period;
        // a sample grid that ends a rounding error short of a whole period still counts it
        let periods = (span + 1e-9).floor();
        if !(1.0..=1e9).contains(&periods) {
            return Err(Error::invalid(
                "response.window.periods",
                "in [1, 1e9] whole periods",
                span,
            ));
        }
        let periods = periods as usize;
        let t_end = t0 + periods as f64 * period;
        Ok(Self {
            gap,
            period,
            min_depth: options.min_depth,
            t0,
            t_last,
            periods,
            t_end,
            t_stop: t_end + 1e-9 * period,
            t_last_line: t_end - 1e-9 * period,
            phase: Phase {
                t0,
                t_end,
                period,
                omega: std::f64::consts::TAU / period,
                ks: options.lines.map(f64::from),
                lines: options.lines,
                rot: [(1.0f64, 0.0f64); 2],
                cur: [(1.0f64, 0.0f64); 2],
                last_dt: f64::NAN,
                last_period: usize::MAX,
            },
            state: vec![0usize; periods],
            q_min: f64::INFINITY,
            q_max: f64::NEG_INFINITY,
            max_depth: f64::MIN,
            deepest: (f64::NAN, f64::NAN),
            // per period: complex amplitudes of the lines (trapezoid weights on the sample
            // grid); the phase e^{−ikΩ(t−t0)} advances by a rotation, recomputed exactly at
            // every period start and whenever the sample step changes, so no rounding
            // accumulates beyond one period
            line_re: vec![[0.0f64; 2]; periods],
            line_im: vec![[0.0f64; 2]; periods],
            p: 0,
            next_start: t0 + period,
            n: 0,
            t_prev: f64::NAN,
            pending: None,
            closed: false,
            ts: Vec::new(),
            vs: Vec::new(),
            store: options.detail == WindowDetail::Full,
            full: options.detail == WindowDetail::Full,
            n_in: 0,
            last_in: None,
            drive_scan: Vec::new(),
            back_scan: Vec::new(),
            section: Vec::with_capacity(periods),
            next_section: 0,
            error: None,
            queue: Some(Box::default()),
        })
    }

    /// Room for `additional` more samples (an allocation up front instead of regrowth; none
    /// under [`WindowDetail::Motion`], which keeps no samples).
    pub fn reserve(&mut self, additional: usize) {
        if self.store {
            self.ts.reserve(additional);
            self.vs.reserve(additional);
        }
    }

    /// The next sample, at a time after the one before. It is queued and reduced with the
    /// queued ones before it, 256 at a time ([`WindowAccumulator::push_many`]).
    #[inline]
    pub fn push(&mut self, t: f64, q: f64, v: f64) {
        if let Some(queue) = self.queue.as_mut()
            && queue.add(t, q, v)
        {
            self.flush();
        }
    }

    /// The next samples `(ts[i], qs[i], vs[i])`, in ascending time after the ones before: the
    /// same as [`WindowAccumulator::push`] of each in turn, bit for bit. Slices of different
    /// lengths are an invalid sample.
    pub fn push_many(&mut self, ts: &[f64], qs: &[f64], vs: &[f64]) {
        self.flush();
        self.reduce(ts, qs, vs);
    }

    /// Reduces the queued samples.
    fn flush(&mut self) {
        if let Some(mut queue) = self.queue.take() {
            let n = queue.len;
            if n > 0 {
                self.reduce(&queue.t[..n], &queue.q[..n], &queue.v[..n]);
                queue.len = 0;
            }
            self.queue = Some(queue);
        }
    }

    /// The samples reduced, with the running state held in locals over the batch (the lines'
    /// phase rotation and sums are a chain of dependent operations per sample that otherwise
    /// goes through memory).
    fn reduce(&mut self, ts: &[f64], qs: &[f64], vs: &[f64]) {
        if self.error.is_some() {
            return;
        }
        if qs.len() != ts.len() || vs.len() != ts.len() {
            self.error = Some(Error::invalid(
                "response.window.sample",
                format!("q and q' as many as t ({})", ts.len()),
                qs.len().max(vs.len()) as f64,
            ));
            return;
        }
        let mut phase = self.phase;
        // the line sums of one period (`line_period`), written back when another is summed
        let mut line_period = usize::MAX;
        let (mut re, mut im) = ([0.0f64; 2], [0.0f64; 2]);
        let (mut n, mut t_prev, mut closed) = (self.n, self.t_prev, self.closed);
        let (mut p, mut next_start) = (self.p, self.next_start);
        let (mut q_min, mut q_max, mut max_depth) = (self.q_min, self.q_max, self.max_depth);
        let mut deepest = self.deepest;
        let (mut pending, mut last_in, mut n_in) = (self.pending, self.last_in, self.n_in);
        let mut next_section = self.next_section;
        let periods = self.periods;
        // stroboscopic section: the first sample at or after each period start (to 1e-9 T; one
        // point per period, so that a sample a rounding error short of a period start is not
        // taken twice); a period start that a sampling interval longer than the period skips
        // has none
        let start = |k: usize| self.t0 + k as f64 * self.period - 1e-9 * self.period;
        let mut section_at = start(next_section);
        let mut error = None;
        for ((&t, &q), &v) in ts.iter().zip(qs).zip(vs) {
            n += 1;
            if !(t.is_finite() && q.is_finite() && v.is_finite()) {
                error = Some(Error::invalid("response.window.sample", "finite", f64::NAN));
                break;
            }
            if n == 1 && t.to_bits() != self.t0.to_bits() {
                error = Some(Error::invalid(
                    "response.window.t",
                    "the first sample at the announced start",
                    t,
                ));
                break;
            }
            if n > 1 && t <= t_prev {
                error = Some(Error::invalid("response.window.t", "strictly ascending", t));
                break;
            }
            t_prev = t;
            if closed {
                continue;
            }
            // (never set under `WindowDetail::Motion`)
            if let Some(s) = pending.take() {
                if p != line_period {
                    if line_period != usize::MAX {
                        self.line_re[line_period] = re;
                        self.line_im[line_period] = im;
                    }
                    line_period = p;
                    re = self.line_re[p];
                    im = self.line_im[p];
                }
                phase.term(s, t, p, &mut re, &mut im);
            }
            if t > self.t_stop {
                closed = true;
                continue;
            }
            let b = (self.gap)(t);
            if !b.is_finite() || b < 0.0 {
                error = Some(Error::invalid("response.window.gap", ">= 0 and finite", b));
                break;
            }
            // the period index advances with the (ascending) samples: no division per sample
            while p + 1 < periods && t >= next_start {
                p += 1;
                next_start = self.t0 + (p + 1) as f64 * self.period;
            }
            q_min = q_min.min(q);
            q_max = q_max.max(q);
            // `(q + b)/b` is monotone in `q` at one `b` (rounded addition and division are):
            // a sample below the deepest one at the same `b` cannot raise the maximum
            if !(b.to_bits() == deepest.1.to_bits() && q <= deepest.0) {
                let depth = if b > 0.0 { (q + b) / b } else { f64::INFINITY };
                if depth > max_depth {
                    deepest = (q, b);
                }
                max_depth = max_depth.max(depth);
            }
            let s = if q > b {
                2
            } else if q + b > self.min_depth * b {
                1
            } else {
                0
            };
            self.state[p] = self.state[p].max(s);
            // impacts between samples (used when no crossing is located): sign changes of the
            // distances to the edges
            if let Some((ta, qa, va, ba)) = last_in {
                // drive flank entry: q + b goes from ≥ 0 to < 0
                let (da, db) = (qa + ba, q + b);
                if da >= 0.0 && db < 0.0 {
                    let a = da / (da - db);
                    self.drive_scan
                        .push((ta + a * (t - ta), (va + a * (v - va)).abs()));
                }
                let (ea, eb) = (qa - ba, q - b);
                if ea <= 0.0 && eb > 0.0 {
                    let a = ea / (ea - eb);
                    self.back_scan
                        .push((ta + a * (t - ta), (va + a * (v - va)).abs()));
                }
            }
            if next_section < periods && t >= section_at {
                self.section.push(q);
                next_section += 1;
                section_at = start(next_section);
                while next_section < periods && t >= section_at {
                    next_section += 1;
                    section_at = start(next_section);
                }
            }
            if self.full && t < self.t_last_line {
                let step = last_in.map_or(f64::NAN, |(ta, ..)| t - ta);
                pending = Some(Pending { t, q, step });
            }
            last_in = Some((t, q, v, b));
            n_in += 1;
            if self.store {
                self.ts.push(t);
                self.vs.push(v);
            }
        }
        if line_period != usize::MAX {
            self.line_re[line_period] = re;
            self.line_im[line_period] = im;
        }
        self.phase = phase;
        (self.n, self.t_prev, self.closed) = (n, t_prev, closed);
        (self.p, self.next_start) = (p, next_start);
        (self.q_min, self.q_max, self.max_depth) = (q_min, q_max, max_depth);
        self.deepest = deepest;
        (self.pending, self.last_in, self.n_in) = (pending, last_in, n_in);
        self.next_section = next_section;
        self.error = error;
    }

    /// The statistics of the pushed samples with the located gap-edge crossings `crossings` of
    /// the same window (may be empty: impacts are then found between samples by linear
    /// interpolation).
    ///
    /// # Errors
    /// An invalid sample ([`WindowAccumulator`]), fewer than two samples, a last sample not at
    /// the announced time, or a non-finite crossing time.
    pub fn finish(mut self, crossings: &[Crossing]) -> Result<WindowStats, Error> {
        self.flush();
        let (ts, vs) = (std::mem::take(&mut self.ts), std::mem::take(&mut self.vs));
        self.finish_on(crossings, &ts, &vs)
    }

    /// [`WindowAccumulator::finish`] with `t` and `q'` of the in-window samples from `ts`, `vs`.
    fn finish_on(
        mut self,
        crossings: &[Crossing],
        ts: &[f64],
        vs: &[f64],
    ) -> Result<WindowStats, Error> {
        if let Some(e) = self.error.take() {
            return Err(e);
        }
        if self.n < 2 {
            return Err(Error::Solver(format!(
                "response window: need ≥ 2 samples, got {}",
                self.n
            )));
        }
        if self.t_prev.to_bits() != self.t_last.to_bits() {
            return Err(Error::Solver(format!(
                "response window: the last sample is at {}, the window was announced to end at {}",
                self.t_prev, self.t_last
            )));
        }
        if let Some(pending) = self.pending.take() {
            let p = self.p;
            let (mut re, mut im) = (self.line_re[p], self.line_im[p]);
            self.phase.term(pending, f64::NAN, p, &mut re, &mut im);
            (self.line_re[p], self.line_im[p]) = (re, im);
        }
        let (t0, period, periods) = (self.t0, self.period, self.periods);
        let period_of = |tt: f64| (((tt - t0) / period).floor().max(0.0) as usize).min(periods - 1);
        // the kept samples give the impact speeds (`WindowDetail::Full` only)
        if self.n_in == 0 || (self.full && (ts.len() != self.n_in || vs.len() != self.n_in)) {
            return Err(Error::Solver(format!(
                "response window: {} samples in the window, {} times and {} speeds kept",
                self.n_in,
                ts.len(),
                vs.len()
            )));
        }
        let last = ts.len().saturating_sub(1);
        // the first sample after `tc`, searched from the one found for the crossing before
        // (the crossings come in time order, a few hundred samples apart: a gallop from there
        // reads the samples near it instead of jumping across all of them; any order is
        // still right, through the bisection of the whole when `tc` lies before the hint)
        let mut hint = 0usize;
        let mut first_after = |tc: f64| -> usize {
            let n = ts.len();
            if hint > 0 && ts[hint - 1] > tc {
                hint = ts.partition_point(|&x| x <= tc);
                return hint;
            }
            let mut step = 1usize;
            while hint + step < n && ts[hint + step] <= tc {
                step *= 2;
            }
            let lo = hint + step / 2;
            let hi = (hint + step).min(n);
            hint = lo + ts[lo..hi].partition_point(|&x| x <= tc);
            hint
        };
        let mut speed_at = |tc: f64| -> f64 {
            let j = first_after(tc);
            if j == 0 {
                vs[0].abs()
            } else if j > last {
                vs[last].abs()
            } else {
                let (ta, tb) = (ts[j - 1], ts[j]);
                let a = (tc - ta) / (tb - ta);
                (vs[j - 1] + a * (vs[j] - vs[j - 1])).abs()
            }
        };
        // impacts: located crossings when given, else sign changes between samples
        let (drive, back) = if crossings.is_empty() {
            (
                std::mem::take(&mut self.drive_scan),
                std::mem::take(&mut self.back_scan),
            )
        } else {
            let (mut drive, mut back) = (Vec::new(), Vec::new());
            for c in crossings {
                if !c.t.is_finite() {
                    return Err(Error::invalid("response.window.crossing.t", "finite", c.t));
                }
                if c.t < t0 || c.t > self.t_end || !c.entering {
                    continue;
                }
                let sp = if self.full { speed_at(c.t) } else { f64::NAN };
                match c.flank {
                    Flank::Drive => drive.push((c.t, sp)),
                    Flank::Back => back.push((c.t, sp)),
                }
            }
            (drive, back)
        };
        let mut state = std::mem::take(&mut self.state);
        for &(tc, _) in &back {
            let p = period_of(tc);
            state[p] = 2;
        }
        let full = self.full;
        let impacts = |list: &[(f64, f64)]| {
            let count = list.len();
            let (sum, max) = list
                .iter()
                .fold((0.0, 0.0f64), |(s, m), &(_, sp)| (s + sp, m.max(sp)));
            let (mean_speed, max_speed) = match (full, count) {
                (false, _) => (f64::NAN, f64::NAN),
                (true, 0) => (0.0, max),
                (true, _) => (sum / count as f64, max),
            };
            FlankImpacts {
                count,
                rate: count as f64 / periods as f64,
                mean_speed,
                max_speed,
            }
        };
        let mut counts = [0usize; 3];
        for &s in &state {
            counts[s] += 1;
        }
        let fraction = counts.map(|c| c as f64 / periods as f64);
        let mut line_coherent = [0.0; 2];
        let mut line_incoherent = [0.0; 2];
        for j in 0..2 {
            if !full {
                (line_coherent[j], line_incoherent[j]) = (f64::NAN, f64::NAN);
                continue;
            }
            let (mut re, mut im, mut inc) = (0.0, 0.0, 0.0);
            for p in 0..periods {
                re += self.line_re[p][j];
                im += self.line_im[p][j];
                inc += self.line_re[p][j].dhypot(self.line_im[p][j]);
            }
            line_coherent[j] = re.dhypot(im) / periods as f64;
            line_incoherent[j] = inc / periods as f64;
        }
        let section = &self.section;
        let (q_min, q_max) = (self.q_min, self.q_max);
        let section_tol = SECTION_TOL * (q_max - q_min + (self.gap)(t0).abs());
        let tail_regular =
            section.len() >= 20 && repeats(&section[section.len() / 2..], section_tol);
        let period_multiple = if section.len() < 20 {
            0
        } else {
            repeat_period(section, section_tol).unwrap_or(0)
        };
        let chaos_k = if section.len() < 20 {
            f64::NAN
        } else if period_multiple > 0 {
            // period n ≤ 4 to within integration noise: regular by definition (the 0–1 test
            // would read the rounding-level noise of a repeating section as diffusion)
            0.0
        } else {
            zero_one_test(section)
        };
        Ok(WindowStats {
            periods,
            state: state_of_index(state.iter().copied().max().unwrap_or(0)),
            fraction,
            ppv: q_max - q_min,
            q_min,
            q_max,
            max_depth: self.max_depth,
            drive: impacts(&drive),
            back: impacts(&back),
            line_coherent,
            line_incoherent,
            chaos_k,
            tail_regular,
            period_multiple,
        })
    }
}

/// Relative distance (to the window's ppv plus the gap half-width) under which two section
/// points are the same: the Poincaré tolerance of the Liu sweep strategy
/// (`SweepStrategy::poincare_tol`).
const SECTION_TOL: f64 = 1e-4;

/// Whether the section repeats with some period `n ≤ 4` to within `tol`.
fn repeats(section: &[f64], tol: f64) -> bool {
    repeat_period(section, tol).is_some()
}

/// The smallest period `n ≤ 4` with which the section repeats to within `tol`.
fn repeat_period(section: &[f64], tol: f64) -> Option<usize> {
    (1..=4).find(|&n| {
        section.len() > n
            && section
                .iter()
                .zip(&section[n..])
                .all(|(a, b)| (a - b).abs() <= tol)
    })
}

/// The 0–1 test for chaos (Gottwald & Melbourne 2009, the correlation method with the
/// regularised mean-square displacement) of a scalar series `phi`: the median over 20 fixed
/// frequencies `c ∈ [π/5, 4π/5]` of the correlation `K_c` between `n` and the mean-square
/// displacement `D_c(n)`, `n ≤ N/10`. About 0 for regular (periodic, quasi-periodic) series,
/// about 1 for chaotic ones. NaN for fewer than 20 values or a constant series.
///
/// The frequencies are deterministic (not random as in the paper) so that the result is
/// reproducible bit for bit.
pub fn zero_one_test(phi: &[f64]) -> f64 {
    let n = phi.len();
    if n < 20 || phi.iter().any(|x| !x.is_finite()) {
        return f64::NAN;
    }
    let mean = phi.iter().sum::<f64>() / n as f64;
    let var = phi.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n as f64;
    if var <= 1e-30 * (1.0 + mean * mean) {
        return 0.0;
    }
    let ncut = (n / 10).max(2);
    let mut ks = Vec::with_capacity(20);
    for j in 0..20 {
        let c = std::f64::consts::PI * (0.2 + 0.6 * (j as f64 + 0.5) / 20.0);
        let (mut p, mut qq) = (Vec::with_capacity(n), Vec::with_capacity(n));
        let (mut ps, mut qs) = (0.0, 0.0);
        for (i, &x) in phi.iter().enumerate() {
            let a = c * (i + 1) as f64;
            ps += (x - mean) * a.dcos();
            qs += (x - mean) * a.dsin();
            p.push(ps);
            qq.push(qs);
        }
        let dn: Vec<f64> = (1..=ncut)
            .map(|k| {
                let m = n - k;
                let msd = (0..m)
                    .map(|i| (p[i + k] - p[i]).powi(2) + (qq[i + k] - qq[i]).powi(2))
                    .sum::<f64>()
                    / m as f64;
                // regularised: subtract the oscillatory term of a regular series
                msd - var * (1.0 - (k as f64 * c).dcos()) / (1.0 - c.dcos())
            })
            .collect();
        let xs: Vec<f64> = (1..=ncut).map(|k| k as f64).collect();
        ks.push(correlation(&xs, &dn));
    }
    ks.retain(|k| k.is_finite());
    if ks.is_empty() {
        return f64::NAN;
    }
    ks.sort_by(f64::total_cmp);
    let m = ks.len();
    if m % 2 == 1 {
        ks[m / 2]
    } else {
        0.5 * (ks[m / 2 - 1] + ks[m / 2])
    }
}

/// The two-sided 95 % quantile `t₀.₉₇₅` of Student's t distribution with `dof` degrees of
/// freedom (tabulated for 1–30, from the standard table to 3 decimals; above 30 the value at
/// 30, which is larger than every quantile beyond it, so the interval errs wide). `dof = 0`
/// gives infinity.
pub fn student_t_975(dof: usize) -> f64 {
    const T: [f64; 30] = [
        12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179, 2.160,
        2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064, 2.060, 2.056,
        2.052, 2.048, 2.045, 2.042,
    ];
    match dof {
        0 => f64::INFINITY,
        d => T[d.min(30) - 1],
    }
}

fn correlation(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len() as f64;
    let mx = x.iter().sum::<f64>() / n;
    let my = y.iter().sum::<f64>() / n;
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for (a, b) in x.iter().zip(y) {
        sxy += (a - mx) * (b - my);
        sxx += (a - mx).powi(2);
        syy += (b - my).powi(2);
    }
    if sxx <= 0.0 || syy <= 0.0 {
        return 0.0;
    }
    sxy / (sxx * syy).sqrt()
}

/// The statistics of one point under several variants (two tolerances, two windows, two
/// initial states): the nominal values, the spread, and the intervals a verdict compares.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Robust {
    /// The nominal record's statistics.
    pub nominal: WindowStats,
    /// Every variant: a label (`window B`, `rtol/100`, `other start`) and its statistics.
    pub variants: Vec<(String, WindowStats)>,
}

impl Robust {
    /// Every window (nominal and variants) is [`WindowStats::regular`]: the response is
    /// periodic under every tolerance, window and start of the variants.
    pub fn regular(&self) -> bool {
        self.all().all(WindowStats::regular)
    }

    fn all(&self) -> impl Iterator<Item = &WindowStats> {
        std::iter::once(&self.nominal).chain(self.variants.iter().map(|(_, s)| s))
    }

    /// `[min, max]` of a statistic over the nominal record and the variants.
    pub fn interval(&self, f: impl Fn(&WindowStats) -> f64) -> (f64, f64) {
        self.all()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), s| {
                let x = f(s);
                (lo.min(x), hi.max(x))
            })
    }

    /// A 95 % prediction interval for the statistic `f` of one more window: the nominal record
    /// and the variants are taken as `n` samples of the statistic (windows of a non-periodic
    /// orbit after different transients, starts and tolerances), and the interval is
    /// `x̄ ± t₀.₉₇₅,ₙ₋₁ · s · √(1 + 1/n)` (Student t, sample standard deviation `s`), widened to
    /// contain `[min, max]` ([`Robust::interval`]).
    ///
    /// `[min, max]` of four samples misses the next sample with probability 2/5; the paper's
    /// own value, read off one window of the same orbit, is such a next sample. For a periodic
    /// orbit (`s = 0`) the interval is the point.
    ///
    /// The samples are treated as independent; windows of one trajectory that decorrelates
    /// slowly make `s` an underestimate (documented in validation/README.md).
    pub fn prediction_interval(&self, f: impl Fn(&WindowStats) -> f64) -> (f64, f64) {
        let xs: Vec<f64> = self.all().map(&f).collect();
        let (lo, hi) = self.interval(&f);
        let n = xs.len();
        if n < 2 || xs.iter().any(|x| !x.is_finite()) {
            return (lo, hi);
        }
        let nf = n as f64;
        let mean = xs.iter().sum::<f64>() / nf;
        let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (nf - 1.0);
        let half = student_t_975(n - 1) * var.sqrt() * (1.0 + 1.0 / nf).sqrt();
        ((mean - half).min(lo), (mean + half).max(hi))
    }

    /// True when the statistic `f` agrees over the nominal record and every variant within
    /// `rel` (relative to the largest magnitude): the value is reproducible at that precision.
    pub fn settled(&self, f: impl Fn(&WindowStats) -> f64, rel: f64) -> bool {
        let (lo, hi) = self.interval(&f);
        let mag = lo.abs().max(hi.abs());
        lo.is_finite() && hi.is_finite() && (hi - lo) <= rel * mag
    }

    /// The statistic `f` is a reproducible value of the point: the response is periodic in every
    /// variant ([`Robust::regular`]) and `f` agrees over them within `rel`
    /// ([`Robust::settled`]). A statistic of a non-periodic window is a sample of the orbit,
    /// not a value: its agreement over four variants is chance (Liu Fig. 11 at 165–190 rad/s,
    /// 0–1 test K ≈ 0.9: the long-window ppv agreed to 1e-5 under one step-size controller
    /// setting and spread by 5e-4 under another), so it never counts as reproducible. The two
    /// classes are far apart: a periodic window repeats on its section to about 1e-5 of the
    /// section tolerance, a non-periodic one misses it by 10³.
    pub fn reproducible(&self, f: impl Fn(&WindowStats) -> f64, rel: f64) -> bool {
        self.regular() && self.settled(f, rel)
    }

    /// The window state when every variant agrees on it, else `None` (not robust).
    pub fn state(&self) -> Option<RattleState> {
        let s = state_index(self.nominal.state);
        self.all()
            .all(|w| state_index(w.state) == s)
            .then_some(self.nominal.state)
    }

    /// `[min, max]` of the rsv (0, 1, 2) over the variants.
    pub fn rsv_interval(&self) -> (u8, u8) {
        let (lo, hi) = self.interval(|w| f64::from(w.state.rsv()));
        (lo as u8, hi as u8)
    }

    /// Relative spread of the long-window ppv, `(max − min)/nominal`.
    pub fn ppv_spread(&self) -> f64 {
        let (lo, hi) = self.interval(|w| w.ppv);
        (hi - lo) / self.nominal.ppv.abs().max(f64::MIN_POSITIVE)
    }

    /// Spread (max − min) of the fraction of bilateral periods.
    pub fn bilateral_fraction_spread(&self) -> f64 {
        let (lo, hi) = self.interval(WindowStats::bilateral_fraction);
        hi - lo
    }

    /// Names and units of [`Robust::values`]: the columns a study file or a table gets for a
    /// point's long-window statistics (one definition for the library, the CLI and Python).
    pub const COLUMNS: [(&'static str, &'static str); 19] = [
        ("rsv_window", "1"),
        ("window_state_robust", "1"),
        ("no_rattle_fraction", "1"),
        ("unilateral_fraction", "1"),
        ("bilateral_fraction", "1"),
        ("bilateral_fraction_lo", "1"),
        ("bilateral_fraction_hi", "1"),
        ("ppv_window", "1"),
        ("ppv_window_lo", "1"),
        ("ppv_window_hi", "1"),
        ("back_impacts_per_period", "1"),
        ("back_impact_speed_mean", "1"),
        ("back_impact_speed_max", "1"),
        ("drive_impacts_per_period", "1"),
        ("drive_impact_speed_mean", "1"),
        ("drive_impact_speed_max", "1"),
        ("line_1", "1"),
        ("line_2", "1"),
        ("chaos_k_01", "1"),
    ];

    /// The values of [`Robust::COLUMNS`]: the nominal window's state (rsv), whether every
    /// variant agrees on it (1/0), the fractions of periods per state, the bilateral fraction's
    /// range over the variants, the long-window ppv with its range, the impact rates and speeds
    /// per flank, the incoherent amplitudes of the two lines ([`WindowOptions::lines`]) and the
    /// 0–1 test.
    pub fn values(&self) -> [f64; 19] {
        let w = &self.nominal;
        let (fl, fh) = self.interval(WindowStats::bilateral_fraction);
        let (pl, ph) = self.interval(|s| s.ppv);
        [
            f64::from(w.state.rsv()),
            if self.state().is_some() { 1.0 } else { 0.0 },
            w.fraction[0],
            w.fraction[1],
            w.fraction[2],
            fl,
            fh,
            w.ppv,
            pl,
            ph,
            w.back.rate,
            w.back.mean_speed,
            w.back.max_speed,
            w.drive.rate,
            w.drive.mean_speed,
            w.drive.max_speed,
            w.line_incoherent[0],
            w.line_incoherent[1],
            w.chaos_k,
        ]
    }

    /// Per column of [`Robust::COLUMNS`]: the value settles, i.e. every variant agrees on the
    /// rattle state and the column's own statistic is reproducible ([`Robust::reproducible`]:
    /// periodic in every variant and agreeing within `rel`; the state columns need only the
    /// agreement on the state). A column that does not settle is a sample of the point's
    /// statistic, not a reproducible value (issue 28: it is committed as `n/p`). A statistic
    /// that is NaN in every variant (no impacts on a flank) of a periodic point settles.
    pub fn settled_columns(&self, rel: f64) -> [bool; 19] {
        let robust = self.state().is_some();
        let regular = self.regular();
        // a statistic that does not exist in any variant (NaN: no impacts on a flank) settles
        let s = |f: &dyn Fn(&WindowStats) -> f64| {
            robust && regular && (self.all().all(|w| f(w).is_nan()) || self.settled(f, rel))
        };
        let bilateral = s(&WindowStats::bilateral_fraction);
        let ppv = s(&|w| w.ppv);
        [
            robust,
            robust,
            s(&|w| w.fraction[0]),
            s(&|w| w.fraction[1]),
            s(&|w| w.fraction[2]),
            bilateral,
            bilateral,
            ppv,
            ppv,
            ppv,
            s(&|w| w.back.rate),
            s(&|w| w.back.mean_speed),
            s(&|w| w.back.max_speed),
            s(&|w| w.drive.rate),
            s(&|w| w.drive.mean_speed),
            s(&|w| w.drive.max_speed),
            s(&|w| w.line_incoherent[0]),
            s(&|w| w.line_incoherent[1]),
            s(&|w| w.chaos_k),
        ]
    }

    /// A one-line description of the spread: `rsv 2 (all), P_bi 0.41–0.47, ppv 1.62–1.70`.
    pub fn describe(&self) -> String {
        self.describe_marked(0.0, |s| s)
    }

    /// [`Robust::describe`] with each statistic (bilateral fraction, ppv, 0–1 test K) passed
    /// through `mark` when it does not settle over the variants to `rel`
    /// ([`Robust::settled_columns`]), e.g. to mark it as not committed.
    pub fn describe_marked(&self, rel: f64, mark: impl Fn(String) -> String) -> String {
        let (rl, rh) = self.rsv_interval();
        let (fl, fh) = self.interval(WindowStats::bilateral_fraction);
        let (pl, ph) = self.interval(|w| w.ppv);
        let rsv = if rl == rh {
            format!("rsv {rl} in all {} variants", self.variants.len() + 1)
        } else {
            format!("rsv {rl}–{rh} over {} variants", self.variants.len() + 1)
        };
        let settled = self.settled_columns(rel);
        let column = |name: &str| {
            Self::COLUMNS
                .iter()
                .position(|c| c.0 == name)
                .is_some_and(|i| settled[i])
        };
        let span = |x: String, name: &str| if column(name) { x } else { mark(x) };
        format!(
            "{rsv}, bilateral periods {}, long-window ppv {}, 0–1 test K {}",
            span(format!("{fl:.3}–{fh:.3}"), "bilateral_fraction"),
            span(format!("{pl:.4}–{ph:.4}"), "ppv_window"),
            span(format!("{:.2}", self.nominal.chaos_k), "chaos_k_01"),
        )
    }
}

/// The statistics that [`WindowDetail::Motion`] keeps, as bits and counts (for the tests that
/// compare it with [`WindowDetail::Full`]).
#[cfg(test)]
pub(crate) fn motion_fields(x: &WindowStats) -> (Vec<u64>, RattleState, [usize; 4], bool) {
    let mut v = vec![x.ppv, x.q_min, x.q_max, x.max_depth, x.chaos_k];
    v.extend([x.drive.rate, x.back.rate]);
    v.extend(x.fraction);
    (
        v.into_iter().map(f64::to_bits).collect(),
        x.state,
        [x.periods, x.period_multiple, x.drive.count, x.back.count],
        x.tail_regular,
    )
}

/// The lines and impact speeds of `x` are NaN (what [`WindowDetail::Motion`] leaves out).
#[cfg(test)]
pub(crate) fn assert_motion_only(x: &WindowStats) {
    let lines = x.line_coherent.iter().chain(&x.line_incoherent);
    assert!(lines.into_iter().all(|v| v.is_nan()), "lines of {x:?}");
    let speeds = [x.drive, x.back].map(|i| [i.mean_speed, i.max_speed]);
    assert!(
        speeds.as_flattened().iter().all(|v| v.is_nan()),
        "speeds of {x:?}"
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Four samples 1, 2, 3, 4 of a statistic: mean 2.5, s² = 5/3, t₀.₉₇₅,₃ = 3.182, so the
    /// prediction half-width is 3.182 · √(5/3) · √(5/4) (hand-computed); equal samples give
    /// the point, and `settled` follows the relative spread.
    #[test]
    fn prediction_interval_of_four_samples() {
        let period = 2.0;
        let om = std::f64::consts::TAU / period;
        // 20 periods: enough for the section test, so that the equal samples are periodic
        let t = grid(20, 40, period);
        let stats = |a: f64| {
            let q: Vec<f64> = t.iter().map(|&x| a * (om * x).dsin()).collect();
            let v: Vec<f64> = t.iter().map(|&x| a * om * (om * x).dcos()).collect();
            window_stats(&t, &q, &v, |_| 10.0, &[], &WindowOptions::new(period)).unwrap()
        };
        let r = Robust {
            nominal: stats(1.0),
            variants: vec![
                ("b".into(), stats(2.0)),
                ("c".into(), stats(3.0)),
                ("d".into(), stats(4.0)),
            ],
        };
        let amp = |w: &WindowStats| w.line_incoherent[0];
        let (lo, hi) = r.prediction_interval(amp);
        let half = 3.182 * (5.0f64 / 3.0).sqrt() * (1.25f64).sqrt();
        assert!((lo - (2.5 - half)).abs() < 1e-6, "{lo}");
        assert!((hi - (2.5 + half)).abs() < 1e-6, "{hi}");
        assert!(!r.settled(amp, 1e-3));
        let same = Robust {
            nominal: stats(1.0),
            variants: vec![("b".into(), stats(1.0))],
        };
        let (lo, hi) = same.prediction_interval(amp);
        assert!((hi - lo).abs() < 1e-12 && (lo - 1.0).abs() < 1e-6);
        assert!(same.settled(amp, 1e-3));
        assert!(same.regular() && same.reproducible(amp, 1e-3));
        // the same equal samples over 4 periods: too short for the section test (K is NaN), so
        // not known to be periodic: settled, but not a reproducible value, and no column commits
        let short = {
            let t = grid(4, 40, period);
            let q: Vec<f64> = t.iter().map(|&x| (om * x).dsin()).collect();
            let v: Vec<f64> = t.iter().map(|&x| om * (om * x).dcos()).collect();
            window_stats(&t, &q, &v, |_| 10.0, &[], &WindowOptions::new(period)).unwrap()
        };
        let unknown = Robust {
            nominal: short,
            variants: vec![("b".into(), short)],
        };
        assert!(unknown.settled(amp, 1e-3) && !unknown.reproducible(amp, 1e-3));
        assert_eq!(unknown.settled_columns(1e-3)[7..], [false; 12]);
        // per column: identical variants settle everywhere; amplitudes 1..4 move the ppv and
        // line columns (7–9, 16) but no state or fraction column (0–6)
        assert!(same.settled_columns(1e-5).iter().all(|&s| s));
        let cols = r.settled_columns(1e-5);
        assert!(cols[..7].iter().all(|&s| s), "{cols:?}");
        assert!(!cols[7] && !cols[8] && !cols[9] && !cols[16], "{cols:?}");
        // the marked description marks the moving ppv and nothing of the identical variants
        let mark = |s: String| format!("<{s}>");
        assert_eq!(same.describe_marked(1e-5, mark), same.describe());
        let d = r.describe_marked(1e-5, mark);
        assert!(
            d.contains("long-window ppv <") && d.contains("bilateral periods 0"),
            "{d}"
        );
        assert!(student_t_975(0).is_infinite());
        assert_eq!(student_t_975(3).to_bits(), 3.182f64.to_bits());
        assert_eq!(student_t_975(500).to_bits(), 2.042f64.to_bits());
    }

    fn grid(periods: usize, per: usize, period: f64) -> Vec<f64> {
        (0..=periods * per)
            .map(|i| i as f64 * period / per as f64)
            .collect()
    }

    /// The section holds one point per period even where the sample at a period start lies a
    /// rounding error before it (`t = k·(T/n)` against `k·T`): a periodic response with fast
    /// content (a 63rd harmonic, as the Liu mesh) then repeats on it exactly ([`WindowStats::regular`]).
    /// A window whose first periods still decay repeats over its last half only
    /// ([`WindowStats::transient`]); a chaotic amplitude sequence repeats over neither.
    #[test]
    fn section_one_point_per_period_and_transient() {
        let period = std::f64::consts::TAU / 3.7;
        let om = std::f64::consts::TAU / period;
        let per = 97;
        let dt = period / per as f64;
        let t: Vec<f64> = (0..=50 * per).map(|i| i as f64 * dt).collect();
        // the test is meaningful only if some period-start sample falls short of k·T
        assert!((1..50).any(|k| t[k * per] < k as f64 * period));
        let run = |amp: &dyn Fn(f64) -> f64| {
            let q: Vec<f64> = t
                .iter()
                .map(|&x| amp(x) * (om * x).dcos() + 0.1 * (63.0 * om * x).dsin())
                .collect();
            // q' is not used by the section; the impact speeds need only be finite here
            let v = vec![0.0; t.len()];
            window_stats(&t, &q, &v, |_| 2.0, &[], &WindowOptions::new(period)).unwrap()
        };
        let periodic = run(&|_| 0.5);
        assert_eq!(periodic.periods, 50);
        assert!(periodic.regular() && periodic.tail_regular && !periodic.transient());
        // decay over 3 periods: 0.2·e^{-25/3} ≈ 5e-5 at mid-window, inside the section
        // tolerance (1e-4 of ppv + gap ≈ 3e-4); 0.2 at the start, far outside it
        let decaying = run(&|x| 0.5 + 0.2 * (-x / (3.0 * period)).dexp());
        assert!(!decaying.regular() && decaying.tail_regular && decaying.transient());
        // amplitude from the logistic map, one value per period: no repeat anywhere
        let mut a = vec![0.3f64];
        for _ in 0..60 {
            let x = *a.last().unwrap_or(&0.3);
            a.push(3.9 * x * (1.0 - x));
        }
        let chaotic = run(&|x| 0.2 + 0.5 * a[((x / period).floor() as usize).min(59)]);
        assert!(!chaotic.regular() && !chaotic.tail_regular && !chaotic.transient());
    }

    /// A pure sinusoid `q = a sin(Ωt) + m` in a gap `±b`: exact state, fractions, ppv, lines
    /// and impact speeds (`|q'| = aΩ|cos|` at the crossing).
    #[test]
    fn sinusoid_exact_statistics() {
        let period = 2.0;
        let om = std::f64::consts::TAU / period;
        let t = grid(60, 400, period);
        let (a, m, b) = (1.5, -0.2, 1.0);
        let q: Vec<f64> = t.iter().map(|&x| m + a * (om * x).dsin()).collect();
        let v: Vec<f64> = t.iter().map(|&x| a * om * (om * x).dcos()).collect();
        let w = window_stats(&t, &q, &v, |_| b, &[], &WindowOptions::new(period)).unwrap();
        assert_eq!(w.periods, 60);
        assert_eq!(w.state, RattleState::Bilateral);
        assert_eq!(
            w.fraction.map(f64::to_bits),
            [0.0, 0.0, 1.0f64].map(f64::to_bits)
        );
        assert!((w.ppv - 2.0 * a).abs() < 1e-3);
        assert!(
            (w.line_coherent[0] - a).abs() < 1e-9,
            "{:?}",
            w.line_coherent
        );
        assert!((w.line_incoherent[0] - a).abs() < 1e-9);
        assert!(w.line_coherent[1].abs() < 1e-9);
        assert_eq!((w.back.count, w.drive.count), (60, 60));
        // back-flank entry at sin = (b − m)/a, speed aΩ cos
        let s = (b - m) / a;
        let exact = a * om * (1.0 - s * s).sqrt();
        assert!((w.back.mean_speed - exact).abs() < 1e-3 * exact);
        let s = (-b - m) / a;
        let exact = a * om * (1.0 - s * s).sqrt();
        assert!((w.drive.max_speed - exact).abs() < 1e-3 * exact);
        assert!(w.chaos_k.abs() < 0.3, "periodic: K = {}", w.chaos_k);
    }

    /// Intermittent back-flank contact: every third period reaches the back flank, so the
    /// bilateral fraction is 1/3 while the window state is bilateral; the minimum depth turns
    /// shallow separations into no rattle.
    #[test]
    fn fractions_and_min_depth() {
        let period = 1.0;
        let om = std::f64::consts::TAU;
        let t = grid(30, 200, period);
        let b = 1.0;
        // q oscillates in [−1.5, −1.5 + 2A] with A = 1.4 every third period, else A = 0.26
        let amp = |x: f64| {
            if (x / period).floor() as i64 % 3 == 0 {
                1.4
            } else {
                0.26
            }
        };
        let q: Vec<f64> = t
            .iter()
            .map(|&x| -1.5 + amp(x) * (1.0 - (om * x).dcos()))
            .collect();
        let v = vec![0.0; t.len()];
        let w = window_stats(&t, &q, &v, |_| b, &[], &WindowOptions::new(period)).unwrap();
        assert_eq!(w.state, RattleState::Bilateral);
        assert!((w.fraction[2] - 1.0 / 3.0).abs() < 1e-12);
        assert!(
            (w.fraction[1] - 2.0 / 3.0).abs() < 1e-12,
            "{:?}",
            w.fraction
        );
        // separations of depth 0.02·b are not counted with a 5 % minimum depth
        let o = WindowOptions {
            min_depth: 0.05,
            ..WindowOptions::new(period)
        };
        let w = window_stats(&t, &q, &v, |_| b, &[], &o).unwrap();
        assert!(
            (w.fraction[0] - 2.0 / 3.0).abs() < 1e-12,
            "{:?}",
            w.fraction
        );
        assert!((w.max_depth - 2.3).abs() < 1e-6, "{}", w.max_depth);
    }

    /// The 0–1 test separates the logistic map at r = 4 (chaotic) from a period-3 sequence
    /// and a quasi-periodic one (Gottwald & Melbourne 2009 report K ≈ 1 and K ≈ 0).
    #[test]
    fn zero_one_test_separates_chaos() {
        let mut x = 0.3;
        let chaotic: Vec<f64> = (0..2000)
            .map(|_| {
                x = 4.0 * x * (1.0 - x);
                x
            })
            .collect();
        let k = zero_one_test(&chaotic);
        assert!(k > 0.8, "logistic r = 4: K = {k}");
        let periodic: Vec<f64> = (0..2000).map(|i| [0.1, 0.5, 0.9][i % 3]).collect();
        let k = zero_one_test(&periodic);
        assert!(k < 0.2, "period 3: K = {k}");
        let quasi: Vec<f64> = (0..2000)
            .map(|i| (i as f64 * 0.7).dsin() + (i as f64 * 0.7 * 2f64.sqrt()).dcos())
            .collect();
        let k = zero_one_test(&quasi);
        assert!(k < 0.3, "quasi-periodic: K = {k}");
        assert!(zero_one_test(&chaotic[..10]).is_nan());
    }

    #[test]
    fn hostile_inputs_are_errors() {
        let t = [0.0, 0.5, 1.0, 1.5];
        let q = [0.0; 4];
        let o = WindowOptions::new(1.0);
        assert!(window_stats(&t, &q, &q, |_| 1.0, &[], &o).is_ok());
        let bad = |o: WindowOptions| window_stats(&t, &q, &q, |_| 1.0, &[], &o).is_err();
        assert!(bad(WindowOptions::new(f64::NAN)));
        assert!(bad(WindowOptions::new(-1.0)));
        assert!(bad(WindowOptions::new(10.0)), "shorter than one period");
        assert!(bad(WindowOptions {
            min_depth: 1.0,
            ..o
        }));
        assert!(window_stats(&t, &[0.0, f64::NAN, 0.0, 0.0], &q, |_| 1.0, &[], &o).is_err());
        assert!(window_stats(&[0.0, 0.0, 1.0, 2.0], &q, &q, |_| 1.0, &[], &o).is_err());
        assert!(window_stats(&t, &q[..3], &q, |_| 1.0, &[], &o).is_err());
        assert!(window_stats(&t, &q, &q, |_| f64::NAN, &[], &o).is_err());
    }

    /// The accumulator's own checks, for a caller that streams samples: a first or last
    /// sample away from the announced ends, a sample not after the one before, a non-finite
    /// sample or gap, fewer than two samples, and a window shorter than a period are errors
    /// naming the field; samples past the window's end are checked and otherwise ignored.
    #[test]
    fn accumulator_checks_what_it_is_fed() {
        let o = WindowOptions::new(1.0);
        let feed = |t_last: f64, samples: &[(f64, f64)], gap: f64| {
            let mut acc = WindowAccumulator::new(0.0, t_last, |_| gap, &o)?;
            for &(t, q) in samples {
                acc.push(t, q, 0.0);
            }
            acc.finish(&[])
        };
        let good = [(0.0, 0.0), (0.5, 0.1), (1.0, 0.0), (1.5, 0.1)];
        let w = feed(1.5, &good, 1.0).unwrap();
        assert_eq!(w.periods, 1);
        let field = |r: Result<WindowStats, Error>| match r {
            Err(Error::InvalidParameter { field, .. }) => field,
            other => panic!("expected an invalid parameter, got {other:?}"),
        };
        assert_eq!(field(feed(1.5, &good[1..], 1.0)), "response.window.t");
        assert!(matches!(feed(2.0, &good, 1.0), Err(Error::Solver(m)) if m.contains("announced")));
        let mut back = good;
        back[2].0 = 0.5;
        assert_eq!(field(feed(1.5, &back, 1.0)), "response.window.t");
        let mut nan = good;
        nan[1].1 = f64::NAN;
        assert_eq!(field(feed(1.5, &nan, 1.0)), "response.window.sample");
        assert_eq!(field(feed(1.5, &good, -1.0)), "response.window.gap");
        assert!(matches!(feed(1.5, &good[..1], 1.0), Err(Error::Solver(_))));
        assert_eq!(field(feed(0.5, &good[..2], 1.0)), "response.window.periods");
        // a NaN past the window's end is still an error; a valid sample there changes only
        // the trapezoid weight of the last sample in the window (here: none, q there is 0)
        let mut tail = good.to_vec();
        tail.push((3.0, 0.0));
        let w3 = feed(3.0, &tail, 1.0).unwrap();
        assert_eq!(w3.periods, 3);
        let ok = WindowAccumulator::new(0.0, 1.0, |_| 1.0, &o).unwrap();
        let mut acc = ok;
        for (t, q) in [(0.0, 0.0), (0.5, 0.1), (1.0, 0.0)] {
            acc.push(t, q, 0.0);
        }
        acc.push(1.2, f64::NAN, 0.0);
        assert!(acc.finish(&[]).is_err());
    }

    /// `push_many` is `push` of each sample, bit for bit, wherever the batches break: the
    /// state it holds in locals (the lines' phase and the sums of the period being summed,
    /// the deepest sample, the section time) is written back between batches. A rattle with
    /// both flanks, a period-varying gap, a sampling step that changes mid-window and
    /// samples past the end; batches of 1, 2, 7, 64 and 1000 samples, and a batch that
    /// breaks at each period start. A mismatch of the slices' lengths is an invalid sample.
    #[test]
    fn batches_are_single_pushes_bit_for_bit() {
        let period = 2.0;
        let o = WindowOptions {
            lines: [1, 3],
            ..WindowOptions::new(period)
        };
        let gap = |t: f64| 0.5 + 0.1 * (std::f64::consts::TAU * t / period).dcos();
        // 6 periods at step 0.01, then 0.013 to past the end
        let mut t: Vec<f64> = (0..=600).map(|k| k as f64 * 0.01).collect();
        t.extend((1..=40).map(|k| 6.0 + k as f64 * 0.013));
        let q: Vec<f64> = t
            .iter()
            .map(|&x| 0.8 * (3.1 * x).dsin() - 0.2 + 0.05 * (17.0 * x).dcos())
            .collect();
        let v: Vec<f64> = t
            .iter()
            .map(|&x| 0.8 * 3.1 * (3.1 * x).dcos() - 0.85 * (17.0 * x).dsin())
            .collect();
        let t_last = *t.last().unwrap();
        let stats = |cuts: &[usize]| {
            let mut acc = WindowAccumulator::new(0.0, t_last, gap, &o).unwrap();
            let mut from = 0;
            for &c in cuts.iter().chain(std::iter::once(&t.len())) {
                let c = c.min(t.len());
                acc.push_many(&t[from..c], &q[from..c], &v[from..c]);
                from = c.max(from);
            }
            acc.finish(&[]).unwrap()
        };
        let run = |cuts: &[usize]| format!("{:?}", stats(cuts));
        let single: Vec<usize> = (1..t.len()).collect();
        let w1 = stats(&single);
        // both flanks are reached (the scans between samples run) in every period
        assert_eq!(w1.periods, 3);
        assert!(w1.drive.count >= 3 && w1.back.count >= 3, "{w1:?}");
        assert_eq!(w1.state, RattleState::Bilateral);
        let reference = format!("{w1:?}");
        for size in [2, 7, 64, 1000] {
            let cuts: Vec<usize> = (1..=t.len() / size).map(|k| k * size).collect();
            assert_eq!(run(&cuts), reference, "batches of {size}");
        }
        let at_starts: Vec<usize> = (1..6).map(|k| k * 200).collect();
        assert_eq!(run(&at_starts), reference);
        // the slice path is the same accumulator
        let w = window_stats(&t, &q, &v, gap, &[], &o).unwrap();
        assert_eq!(format!("{w:?}"), reference);
        let mut acc = WindowAccumulator::new(0.0, t_last, gap, &o).unwrap();
        acc.push_many(&t[..3], &q[..2], &v[..3]);
        assert!(matches!(
            acc.finish(&[]),
            Err(Error::InvalidParameter { field, .. }) if field == "response.window.sample"
        ));
    }

    /// Located crossings decide the period state and the impact count, with the speed
    /// interpolated from the samples.
    #[test]
    fn located_crossings_count() {
        let t = grid(4, 10, 1.0);
        let q = vec![0.0; t.len()];
        let v: Vec<f64> = t.iter().map(|&x| 2.0 * x).collect();
        let cs = [
            Crossing {
                t: 1.25,
                flank: Flank::Back,
                entering: true,
            },
            Crossing {
                t: 1.3,
                flank: Flank::Back,
                entering: false,
            },
            Crossing {
                t: 3.55,
                flank: Flank::Drive,
                entering: true,
            },
        ];
        let w = window_stats(&t, &q, &v, |_| 1.0, &cs, &WindowOptions::new(1.0)).unwrap();
        assert_eq!(w.back.count, 1);
        assert!((w.back.max_speed - 2.5).abs() < 1e-12);
        assert_eq!(w.drive.count, 1);
        assert_eq!(
            w.fraction.map(f64::to_bits),
            [0.0, 0.75, 0.25f64].map(f64::to_bits)
        );
        assert_eq!(w.state, RattleState::Bilateral);
        // the crossings in any order give the same speeds (the search from the previous
        // crossing's sample falls back to a bisection of the whole)
        let mut reversed = cs;
        reversed.reverse();
        let r = window_stats(&t, &q, &v, |_| 1.0, &reversed, &WindowOptions::new(1.0)).unwrap();
        assert_eq!(r.back.max_speed.to_bits(), w.back.max_speed.to_bits());
        assert_eq!(r.drive.max_speed.to_bits(), w.drive.max_speed.to_bits());
        // a crossing before the first sample and one at the last take the end samples' speeds
        let ends = [
            Crossing {
                t: 0.0,
                flank: Flank::Back,
                entering: true,
            },
            Crossing {
                t: 4.0,
                flank: Flank::Drive,
                entering: true,
            },
        ];
        let e = window_stats(&t, &q, &v, |_| 1.0, &ends, &WindowOptions::new(1.0)).unwrap();
        assert_eq!(e.back.max_speed.to_bits(), 0.0f64.to_bits());
        assert_eq!(e.drive.max_speed.to_bits(), 8.0f64.to_bits());
    }

    /// [`WindowDetail::Motion`] gives every statistic but the lines and the impact speeds bit
    /// for bit, with located crossings and with the impacts found between samples (whose
    /// interpolated times may fall in the period before the sample that shows the contact), on
    /// the stored path and through the accumulator; the lines and speeds are NaN.
    #[test]
    fn motion_detail_keeps_the_motion_and_drops_lines_and_speeds() {
        // a rattle across both edges (|q| up to 1.3, gap ±1) with a slowly drifting amplitude,
        // 24 periods of 2π, sampled at 0.05
        let t = grid(24, 126, std::f64::consts::TAU);
        let q: Vec<f64> = t
            .iter()
            .map(|&x| (1.0 + 0.3 * (0.05 * x).dsin()) * x.dsin() - 0.2)
            .collect();
        let v: Vec<f64> = t.iter().map(|&x| x.dcos()).collect();
        let crossings: Vec<Crossing> = t
            .windows(2)
            .zip(q.windows(2))
            .filter(|(_, qq)| {
                (qq[0] - 1.0) * (qq[1] - 1.0) < 0.0 || (qq[0] + 1.0) * (qq[1] + 1.0) < 0.0
            })
            .map(|(tt, qq)| Crossing {
                t: 0.5 * (tt[0] + tt[1]),
                flank: if qq[0].max(qq[1]) > 1.0 {
                    Flank::Back
                } else {
                    Flank::Drive
                },
                entering: qq[1].abs() > 1.0,
            })
            .collect();
        let full = WindowOptions::new(std::f64::consts::TAU);
        let motion = WindowOptions {
            detail: WindowDetail::Motion,
            ..full
        };
        for cs in [&crossings[..], &[]] {
            let f = window_stats(&t, &q, &v, |_| 1.0, cs, &full).unwrap();
            let w = window_stats(&t, &q, &v, |_| 1.0, cs, &motion).unwrap();
            let mut acc = WindowAccumulator::new(t[0], t[t.len() - 1], |_| 1.0, &motion).unwrap();
            acc.reserve(t.len());
            acc.push_many(&t, &q, &v);
            let a = acc.finish(cs).unwrap();
            assert!(
                f.back.count > 0 && f.drive.count > 0,
                "both flanks exercised"
            );
            assert!(f.line_incoherent.iter().all(|x| x.is_finite()));
            for m in [&w, &a] {
                assert_eq!(motion_fields(&f), motion_fields(m));
                assert_motion_only(m);
            }
        }
    }
}
