//! Integration options.

use crate::error::{Error, Result, check_positive};

/// Integration method.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum Method {
    /// This crate's own embedded Dormand–Prince 5(4) with 4th-order dense output (Hairer,
    /// Nørsett & Wanner 1993, §II.5/II.6). Adaptive, allocation-free per step; events are
    /// located on its dense output and the step is recomputed to end on the surface.
    /// The default; the fastest at loose and moderate tolerances ([`Method::Dop853`] wins at
    /// tight ones).
    DormandPrince54,
    /// This crate's own DOP853: Hairer's explicit Runge–Kutta pair of order 8 with error
    /// estimators of orders 5 and 3 and a 7th-order dense output (Hairer, Nørsett & Wanner
    /// 1993, §II.10). Everything [`Method::DormandPrince54`] has (events located on its dense
    /// output with step restarts, the same output modes, statistics and deadline), through
    /// the same driver; step control as in Hairer's `dop853` (`err^(1/8)`, factor clamps
    /// 1/6 … 3, safety 0.9). Fewer, longer steps than DP5 at tight tolerances (12 evaluations
    /// per step instead of 6; 3 more where the dense output is read). See the crate docs for
    /// where it wins.
    Dop853,
    /// Classical fixed-step Runge–Kutta 4 with step `h` (the last step is shortened to hit
    /// the end time). Dense output: cubic Hermite. Events as for the adaptive methods.
    Rk4 {
        /// Step size (same unit as `t`).
        h: f64,
    },
    /// `ode_solvers::Dopri5` (adaptive 5(4)). Events: detected per accepted step, located on a
    /// cubic Hermite interpolant of the step, the step re-integrated up to the event.
    OdeSolversDopri5,
    /// `ode_solvers::Dop853` (adaptive 8(5,3)); events as for [`Method::OdeSolversDopri5`].
    /// An independent cross-check of [`Method::Dop853`].
    OdeSolversDop853,
}

/// Which states are stored in the [`crate::Solution`].
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum Output {
    /// Only the final state (always available as `Solution::y_final`).
    Final,
    /// The initial state and every accepted step (event points included).
    Steps,
    /// Uniform samples `t0 + k dt`, `k = 0, 1, ...` up to the end, from dense output.
    Uniform {
        /// Sampling interval (> 0).
        dt: f64,
    },
    /// Samples at the given times (ascending, within the integration interval), from dense output.
    Times(Vec<f64>),
}

impl Output {
    /// Sample `k` of [`Output::Uniform`] from `t0`: `t0 + k·dt` (the recorder's formula).
    pub(crate) fn uniform_time(t0: f64, k: usize, dt: f64) -> f64 {
        t0 + k as f64 * dt
    }

    /// Whether a uniform sample time `tg` lies in a run that ends at `t_end` (to `10⁻⁹ dt`).
    pub(crate) fn uniform_within(tg: f64, t_end: f64, dt: f64) -> bool {
        tg <= t_end + 1e-9 * dt
    }

    /// The time of the last sample a completed run from `t0` to `t_end` (`t0 ≤ t_end`) records:
    /// for [`Output::Uniform`] the last `t0 + k·dt` within `t_end + 10⁻⁹ dt`, for
    /// [`Output::Times`] the last listed time in `[t0, t_end]`, for [`Output::Steps`] `t_end`;
    /// `None` for [`Output::Final`], an invalid `dt`, non-finite or reversed ends, no listed
    /// time in the interval, or a grid of more than 2⁵² samples. A consumer of
    /// [`crate::integrate_streamed`] that must know a window's end before its samples arrive
    /// reads it here.
    pub fn last_sample(&self, t0: f64, t_end: f64) -> Option<f64> {
        if !(t0.is_finite() && t_end.is_finite() && t0 <= t_end) {
            return None;
        }
        match self {
            Output::Uniform { dt } => {
                let dt = *dt;
                let span = (t_end - t0) / dt;
                if !(dt > 0.0 && span.is_finite() && span < 4.5e15) {
                    return None;
                }
                // the grid is monotone in k: start above the last sample, step down to it
                let mut k = span.ceil() as usize + 2;
                while k > 0 && !Self::uniform_within(Self::uniform_time(t0, k, dt), t_end, dt) {
                    k -= 1;
                }
                Some(Self::uniform_time(t0, k, dt))
            }
            Output::Times(ts) => ts.iter().rev().copied().find(|&t| t >= t0 && t <= t_end),
            Output::Steps => Some(t_end),
            Output::Final => None,
        }
    }
}

/// Options of [`crate::integrate`]. Build with [`Options::default`] and the `with_*` setters.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Options {
    /// Method (default [`Method::DormandPrince54`]).
    pub method: Method,
    /// Relative tolerance of the adaptive methods (default 1e-8).
    pub rtol: f64,
    /// Absolute tolerance of the adaptive methods (default 1e-10).
    pub atol: f64,
    /// Maximum step size (default: infinity, i.e. the whole interval).
    pub h_max: f64,
    /// Initial step size; `None` selects it automatically (Hairer's `hinit`).
    pub h_init: Option<f64>,
    /// Maximum number of accepted plus rejected steps (default 10,000,000).
    pub max_steps: u64,
    /// Absolute time tolerance to which events are located (default 1e-12).
    pub event_tol: f64,
    /// Whether event functions are monitored at all (default true).
    pub events: bool,
    /// What to store (default [`Output::Steps`]).
    pub output: Output,
    /// Whether a rejected step whose end lies across a switching surface is retried to just
    /// past the crossing located on its own dense output (default true; crate docs, "Steps
    /// across a switching surface"). Off: the controller's shrink factor alone, as in Hairer's
    /// codes.
    #[cfg_attr(feature = "serde", serde(default = "default_crossing_retry"))]
    pub crossing_retry: bool,
}

#[cfg(feature = "serde")]
fn default_crossing_retry() -> bool {
    true
}

impl Default for Options {
    fn default() -> Self {
        Self {
            method: Method::DormandPrince54,
            rtol: 1e-8,
            atol: 1e-10,
            h_max: f64::INFINITY,
            h_init: None,
            max_steps: 10_000_000,
            event_tol: 1e-12,
            events: true,
            output: Output::Steps,
            crossing_retry: true,
        }
    }
}

impl Options {
    /// Sets the method.
    pub fn with_method(mut self, method: Method) -> Self {
        self.method = method;
        self
    }
    /// Sets relative and absolute tolerances.
    pub fn with_tol(mut self, rtol: f64, atol: f64) -> Self {
        self.rtol = rtol;
        self.atol = atol;
        self
    }
    /// Sets the output mode.
    pub fn with_output(mut self, output: Output) -> Self {
        self.output = output;
        self
    }
    /// Enables or disables event location.
    pub fn with_events(mut self, on: bool) -> Self {
        self.events = on;
        self
    }
    /// Enables or disables the retry of a rejected step at an estimated crossing
    /// ([`Options::crossing_retry`]).
    pub fn with_crossing_retry(mut self, on: bool) -> Self {
        self.crossing_retry = on;
        self
    }
    /// Sets the maximum step size.
    pub fn with_h_max(mut self, h_max: f64) -> Self {
        self.h_max = h_max;
        self
    }
    /// Sets the initial step size.
    pub fn with_h_init(mut self, h: f64) -> Self {
        self.h_init = Some(h);
        self
    }
    /// Sets the step limit.
    pub fn with_max_steps(mut self, n: u64) -> Self {
        self.max_steps = n;
        self
    }

    /// Checks all values; called by [`crate::integrate`].
    pub fn validate(&self) -> Result<()> {
        check_positive("rtol", self.rtol)?;
        check_positive("atol", self.atol)?;
        check_positive("event_tol", self.event_tol)?;
        if self.h_max.is_nan() || self.h_max <= 0.0 {
            return Err(Error::InvalidParameter {
                name: "h_max",
                bound: "> 0",
                value: self.h_max,
            });
        }
        if let Some(h) = self.h_init {
            check_positive("h_init", h)?;
        }
        if let Method::Rk4 { h } = self.method {
            check_positive("Rk4 step h", h)?;
        }
        match &self.output {
            Output::Uniform { dt } => check_positive("output dt", *dt)?,
            Output::Times(ts) => {
                crate::error::check_finite_slice("output times", ts)?;
                if let Some(i) = ts.windows(2).position(|w| w[1] < w[0]) {
                    return Err(Error::InvalidParameter {
                        name: "output times (must be ascending)",
                        bound: ">= previous time",
                        value: ts[i + 1],
                    });
                }
            }
            _ => {}
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`Output::last_sample`] against the recorder's own enumeration (`t0 + k·dt` for
    /// `k = 0, 1, …` while within `t_end + 10⁻⁹ dt`), on grids that end exactly on, a rounding
    /// error short of, and between samples past `t_end`, including the Liu windows' grids
    /// (`dt = T/⌈T/0.1⌉`, windows of 20 and 50 periods after 5 and 10); degenerate inputs give
    /// `None`.
    #[test]
    fn last_sample_is_the_recorders_last() {
        let period = std::f64::consts::TAU / 0.003_235_4;
        let liu_dt = period / (period / 0.1f64).ceil();
        let mut cases = vec![
            (0.0, 1.0, 0.1),
            (0.0, 1.0, 0.3),
            (2.5, 2.5, 0.1),
            (-3.0, 7.0, 1e-3),
        ];
        for (before, window) in [(5.0, 20.0), (10.0, 50.0), (60.0, 50.0)] {
            let t0 = before * period;
            cases.push((t0, t0 + window * period, liu_dt));
        }
        for (t0, t_end, dt) in cases {
            let within =
                |k: usize| Output::uniform_within(Output::uniform_time(t0, k, dt), t_end, dt);
            let mut k = 0;
            while within(k + 1) {
                k += 1;
            }
            let expected = Output::uniform_time(t0, k, dt);
            let got = Output::Uniform { dt }.last_sample(t0, t_end);
            assert_eq!(
                got.map(f64::to_bits),
                Some(expected.to_bits()),
                "{t0} {t_end} {dt}"
            );
        }
        let times = Output::Times(vec![0.5, 1.0, 2.0]);
        assert_eq!(times.last_sample(0.0, 1.5), Some(1.0));
        assert_eq!(times.last_sample(3.0, 4.0), None);
        assert_eq!(Output::Steps.last_sample(0.0, 2.0), Some(2.0));
        assert_eq!(Output::Final.last_sample(0.0, 2.0), None);
        for (t0, t_end, dt) in [
            (0.0, 1.0, 0.0),
            (0.0, 1.0, -0.1),
            (0.0, 1.0, f64::NAN),
            (1.0, 0.0, 0.1),
            (0.0, f64::INFINITY, 0.1),
            (0.0, 1e300, 1e-300),
        ] {
            assert_eq!(
                Output::Uniform { dt }.last_sample(t0, t_end),
                None,
                "{t0} {t_end} {dt}"
            );
        }
    }
}
