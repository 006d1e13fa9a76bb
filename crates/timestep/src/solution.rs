//! Integration results.

use crate::system::Direction;

/// A located event.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Event {
    /// Event time (located to `Options::event_tol`).
    pub t: f64,
    /// Index of the event function that crossed zero.
    pub index: usize,
    /// Crossing direction ([`Direction::Rising`] or [`Direction::Falling`]).
    pub direction: Direction,
}

/// How an integration ended.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum Status {
    /// Reached the end time.
    Completed,
    /// Stopped at an event whose hook returned [`crate::EventAction::Stop`].
    StoppedByEvent,
    /// The step limit `Options::max_steps` was reached at time `t`.
    MaxSteps {
        /// Time reached.
        t: f64,
    },
    /// The step size fell below round-off level at time `t`.
    StepSizeUnderflow {
        /// Time reached.
        t: f64,
    },
    /// The right-hand side returned NaN/inf that step-size reduction could not avoid.
    NonFinite {
        /// Time reached.
        t: f64,
    },
    /// The thread's wall-clock deadline ([`::system::deadline`]) passed; stopped at time `t`.
    TimeLimit {
        /// Time reached.
        t: f64,
    },
}

impl Status {
    /// True for [`Status::Completed`] and [`Status::StoppedByEvent`].
    pub fn is_success(&self) -> bool {
        matches!(self, Status::Completed | Status::StoppedByEvent)
    }
}

/// Work counters.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Stats {
    /// Right-hand-side evaluations.
    pub n_rhs: u64,
    /// Accepted steps (event restarts included).
    pub n_accepted: u64,
    /// Rejected steps.
    pub n_rejected: u64,
    /// Located events.
    pub n_events: u64,
    /// Root-finder iterations spent locating events (each costs one dense-output evaluation
    /// plus one call of the event functions).
    pub n_event_iterations: u64,
}

impl Stats {
    /// Adds the counters of `o` (the work of consecutive runs, e.g. a transient and a recorded
    /// window).
    pub fn add(&mut self, o: &Stats) {
        self.n_rhs += o.n_rhs;
        self.n_accepted += o.n_accepted;
        self.n_rejected += o.n_rejected;
        self.n_events += o.n_events;
        self.n_event_iterations += o.n_event_iterations;
    }
}

/// Result of [`crate::integrate`]: stored samples, events, final state and how it ended.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Solution {
    /// Number of states.
    pub dim: usize,
    /// Sample times.
    pub t: Vec<f64>,
    /// Samples, row-major: sample `i` is `y[i*dim .. (i+1)*dim]` (see [`Solution::state`]).
    pub y: Vec<f64>,
    /// Located events in time order.
    pub events: Vec<Event>,
    /// Time reached.
    pub t_final: f64,
    /// State reached.
    pub y_final: Vec<f64>,
    /// Last step size proposed by the controller (useful to continue an integration);
    /// NaN for the `ode_solvers` backends, which do not expose it.
    pub h_last: f64,
    /// How the integration ended.
    pub status: Status,
    /// Work counters.
    pub stats: Stats,
}

impl Solution {
    /// Number of stored samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }
    /// True if no samples are stored.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }
    /// Sample `i` (panics if `i >= len()`).
    pub fn state(&self, i: usize) -> &[f64] {
        &self.y[i * self.dim..(i + 1) * self.dim]
    }
    /// The time series of state component `j` (empty if `j >= dim`).
    pub fn component(&self, j: usize) -> Vec<f64> {
        if j >= self.dim {
            return Vec::new();
        }
        self.y.iter().skip(j).step_by(self.dim).copied().collect()
    }
}
