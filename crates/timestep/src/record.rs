//! Output recording and event monitoring shared by the integration drivers (`driver` and
//! `odesolvers`), kept apart so that neither driver imports the other's internals.

use crate::options::Output;
use crate::solution::{Event, Stats};
use crate::system::{Direction, OdeSystem};

/// A consumer of samples `(t, y)` in ascending `t` ([`crate::integrate_streamed`]).
pub(crate) type Sink<'a> = &'a mut dyn FnMut(f64, &[f64]);

/// Stores the requested samples, or hands each one to a sink.
pub(crate) struct Recorder<'a> {
    dim: usize,
    output: Output,
    t0: f64,
    t_end: f64,
    next: usize,
    pub(crate) t: Vec<f64>,
    pub(crate) y: Vec<f64>,
    /// Where the samples go instead of `t` and `y` (`None`: they are stored).
    sink: Option<Sink<'a>>,
}

impl<'a> Recorder<'a> {
    pub(crate) fn new(
        dim: usize,
        output: &Output,
        t0: f64,
        t_end: f64,
        sink: Option<Sink<'a>>,
    ) -> Self {
        Self {
            dim,
            output: output.clone(),
            t0,
            t_end,
            next: 0,
            t: Vec::new(),
            y: Vec::new(),
            sink,
        }
    }

    fn next_time(&self) -> Option<f64> {
        match &self.output {
            Output::Uniform { dt } => {
                let tg = Output::uniform_time(self.t0, self.next, *dt);
                Output::uniform_within(tg, self.t_end, *dt).then_some(tg)
            }
            Output::Times(ts) => {
                let mut i = self.next;
                while i < ts.len() && ts[i] < self.t0 {
                    i += 1;
                }
                ts.get(i).copied().filter(|&tg| tg <= self.t_end)
            }
            _ => None,
        }
    }

    fn skip_before_start(&mut self) {
        if let Output::Times(ts) = &self.output {
            while self.next < ts.len() && ts[self.next] < self.t0 {
                self.next += 1;
            }
        }
    }

    pub(crate) fn initial(&mut self, t0: f64, y0: &[f64]) {
        self.skip_before_start();
        match self.output {
            Output::Steps => self.push(t0, y0),
            Output::Uniform { .. } | Output::Times(_) => {
                while let Some(tg) = self.next_time() {
                    if tg > t0 {
                        break;
                    }
                    self.push(t0, y0);
                    self.next += 1;
                }
            }
            Output::Final => {}
        }
    }

    /// Whether [`Recorder::step`] for a step ending at `t_next` reads the dense output (a
    /// sample is due inside the step).
    pub(crate) fn wants_dense(&self, t_next: f64) -> bool {
        let slack = match self.output {
            Output::Uniform { dt } => 1e-9 * dt,
            Output::Times(_) => 0.0,
            Output::Steps | Output::Final => return false,
        };
        self.next_time().is_some_and(|tg| tg <= t_next + slack)
    }

    /// Records the samples of a step `[t, t + h]`; `dense(theta, out)` interpolates it.
    pub(crate) fn step(
        &mut self,
        t: f64,
        h: f64,
        y_end: &[f64],
        buf: &mut [f64],
        dense: &mut dyn FnMut(f64, &mut [f64]),
    ) {
        let t_next = t + h;
        match self.output {
            Output::Steps => self.push(t_next, y_end),
            Output::Final => {}
            Output::Uniform { .. } | Output::Times(_) => {
                let slack = match self.output {
                    Output::Uniform { dt } => 1e-9 * dt,
                    _ => 0.0,
                };
                while let Some(tg) = self.next_time() {
                    if tg > t_next + slack {
                        break;
                    }
                    let theta = if h > 0.0 {
                        ((tg - t) / h).clamp(0.0, 1.0 + 1e-9)
                    } else {
                        1.0
                    };
                    dense(theta, buf);
                    let dim = self.dim;
                    self.push(tg, &buf[..dim]);
                    self.next += 1;
                }
            }
        }
    }

    fn push(&mut self, t: f64, y: &[f64]) {
        match &mut self.sink {
            Some(sink) => sink(t, y),
            None => {
                self.t.push(t);
                self.y.extend_from_slice(y);
            }
        }
    }
}

/// Event bookkeeping shared by all methods.
pub(crate) struct EventMonitor {
    pub(crate) ne: usize,
    pub(crate) g_prev: Vec<f64>,
    pub(crate) g_new: Vec<f64>,
    gtmp: Vec<f64>,
    /// Sign of each event function on the current side (+1, -1, or 0 if unknown).
    side: Vec<f64>,
    /// Crossings of the last step: (index, theta, direction).
    crossings: Vec<(usize, f64, Direction)>,
    recorded: Vec<bool>,
    just_fired: Vec<bool>,
    /// Whether `recorded` or `just_fired` holds a `true` (set by [`EventMonitor::commit`]):
    /// the flags are cleared only then, not at every step (clearing and re-reading them
    /// at every step stalled on the store).
    flags_set: bool,
}

impl EventMonitor {
    pub(crate) fn new(ne: usize) -> Self {
        Self {
            ne,
            g_prev: vec![0.0; ne],
            g_new: vec![0.0; ne],
            gtmp: vec![0.0; ne],
            side: vec![0.0; ne],
            crossings: Vec::with_capacity(ne),
            recorded: vec![false; ne],
            just_fired: vec![false; ne],
            flags_set: false,
        }
    }

    pub(crate) fn start<S: OdeSystem + ?Sized>(&mut self, sys: &S, t: f64, y: &[f64]) {
        if self.ne == 0 {
            return;
        }
        sys.events(t, y, &mut self.g_prev);
        for i in 0..self.ne {
            self.side[i] = sgn(self.g_prev[i]);
        }
    }

    /// Re-evaluates the event functions after a state reset at `t`. The side of each function
    /// is taken from a probe `delta` ahead along the new motion (`y + delta·F(t, y)`), so that a
    /// reset on the surface (impact law) is followed by the right crossing and not its echo.
    pub(crate) fn refresh<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &S,
        t: f64,
        y: &[f64],
        delta: f64,
        work: &mut [f64],
        fbuf: &mut [f64],
    ) {
        if self.ne == 0 {
            return;
        }
        sys.events(t, y, &mut self.g_prev);
        sys.rhs(t, y, fbuf);
        for i in 0..y.len() {
            work[i] = y[i] + delta * fbuf[i];
        }
        sys.events(t + delta, work, &mut self.gtmp);
        for i in 0..self.ne {
            let s = sgn(self.gtmp[i]);
            if s != 0.0 {
                self.side[i] = s;
            }
        }
    }

    /// Whether some event function has left its side at the end of the step (`g_new`): the
    /// only case in which [`EventMonitor::locate`] finds a crossing.
    pub(crate) fn may_cross(&self) -> bool {
        self.side
            .iter()
            .zip(&self.g_new)
            .any(|(&s, &gb)| !(s == 0.0 || gb * s > 0.0 || gb.is_nan()))
    }

    /// With `g_new` evaluated at the end of a step `[t, t+h]`, finds and locates accepted
    /// crossings. Returns the earliest `theta` (post-crossing end of the final bracket).
    pub(crate) fn locate<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &S,
        t: f64,
        h: f64,
        tol: f64,
        ybuf: &mut [f64],
        dense: &mut dyn FnMut(f64, &mut [f64]),
        stats: &mut Stats,
    ) -> Option<f64> {
        self.crossings.clear();
        let mut best: Option<f64> = None;
        for i in 0..self.ne {
            let s = self.side[i];
            let gb = self.g_new[i];
            if s == 0.0 || gb * s > 0.0 || gb.is_nan() {
                continue;
            }
            let dir = if s > 0.0 {
                Direction::Falling
            } else {
                Direction::Rising
            };
            if !sys.event_direction(i).accepts(dir) {
                continue;
            }
            // bracket [a, b] in theta; fa has sign s, fb has sign -s or is zero
            let mut a = 0.0;
            let mut fa = if self.g_prev[i] * s > 0.0 {
                self.g_prev[i]
            } else {
                s * f64::MIN_POSITIVE
            };
            let mut b = 1.0;
            let mut fb = gb;
            let mut retained = 0i8;
            let mut iter = 0;
            while (b - a) * h > tol && fb != 0.0 && iter < 200 {
                iter += 1;
                let mut c = (a * fb - b * fa) / (fb - fa);
                if !(c > a && c < b) {
                    c = 0.5 * (a + b);
                }
                dense(c, ybuf);
                sys.events(t + c * h, ybuf, &mut self.gtmp);
                let fc = self.gtmp[i];
                if fc.is_nan() {
                    break;
                }
                if fc * s > 0.0 {
                    a = c;
                    fa = fc;
                    if retained == 1 {
                        fb *= 0.5;
                    }
                    retained = 1;
                } else {
                    b = c;
                    fb = fc;
                    if retained == -1 {
                        fa *= 0.5;
                    }
                    retained = -1;
                }
            }
            stats.n_event_iterations += iter;
            // the echo of the event just handled at the step start (restart point on the
            // surface to round-off, trajectory grazing back) is not a new event
            if self.just_fired[i] && b * h <= tol {
                continue;
            }
            self.crossings.push((i, b, dir));
            best = Some(best.map_or(b, |x: f64| x.min(b)));
        }
        best
    }

    /// After the (possibly restarted) step ending at `t_new` with `g_new` evaluated there:
    /// records events whose crossing lies within `tol` of the restart point and updates sides.
    pub(crate) fn commit(
        &mut self,
        h_orig: f64,
        theta_star: Option<f64>,
        t_new: f64,
        tol: f64,
        events: &mut Vec<Event>,
        first_new: &mut usize,
    ) {
        *first_new = events.len();
        if self.flags_set {
            self.recorded.iter_mut().for_each(|r| *r = false);
            self.just_fired.iter_mut().for_each(|r| *r = false);
            self.flags_set = false;
        }
        if let Some(th) = theta_star {
            for &(i, theta, dir) in &self.crossings {
                if (theta - th) * h_orig.abs() <= tol {
                    events.push(Event {
                        t: t_new,
                        index: i,
                        direction: dir,
                    });
                    self.side[i] = if dir == Direction::Rising { 1.0 } else { -1.0 };
                    self.recorded[i] = true;
                    self.just_fired[i] = true;
                    self.flags_set = true;
                }
            }
        }
        for i in 0..self.ne {
            if !self.recorded[i] && self.g_new[i] != 0.0 && !self.g_new[i].is_nan() {
                self.side[i] = sgn(self.g_new[i]);
            }
        }
        std::mem::swap(&mut self.g_prev, &mut self.g_new);
    }
}

fn sgn(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}
