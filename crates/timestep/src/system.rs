//! The problem traits: first-order systems with event functions, and second-order systems.

/// Direction of a zero crossing of an event function `g(t, y)`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Direction {
    /// `g` goes from negative to positive.
    Rising,
    /// `g` goes from positive to negative.
    Falling,
    /// Either direction (used as a filter only).
    Both,
}

impl Direction {
    /// True if a crossing in direction `actual` passes this filter.
    pub fn accepts(self, actual: Direction) -> bool {
        matches!(self, Direction::Both) || self == actual
    }
}

/// What the integrator does after an event has been located and the step restarted there.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum EventAction {
    /// Record the event and continue from the event point (switching surface).
    Continue,
    /// Record the event and stop the integration at the event point.
    Stop,
}

/// A first-order system `y' = F(t, y)` with optional event functions `g_i(t, y)`.
///
/// State vectors are plain slices of length [`OdeSystem::dim`], so that the same code serves a
/// 2-state 1-DOF oscillator and a 12-state 6-DOF model without generic dimension parameters and
/// without allocation per step.
///
/// Event functions (switching surfaces such as the backlash gap edges `x = ±b`, or Poincaré
/// surfaces) are located on the integrator's dense output whenever one changes sign in an
/// accepted step; the step is then restarted so that it ends on the surface (see
/// [`crate::integrate`]).
pub trait OdeSystem {
    /// Number of states.
    fn dim(&self) -> usize;

    /// Right-hand side: writes `F(t, y)` into `dydt` (both of length `dim`).
    fn rhs(&self, t: f64, y: &[f64], dydt: &mut [f64]);

    /// Number of event functions (default 0).
    fn n_events(&self) -> usize {
        0
    }

    /// Event functions: writes `g_i(t, y)` into `g` (length [`OdeSystem::n_events`]).
    /// Each must be continuous along a trajectory; its zeros are the events.
    fn events(&self, _t: f64, _y: &[f64], _g: &mut [f64]) {}

    /// Which crossings of event function `index` are located and reported (default both).
    /// Crossings filtered out here do not restart the step.
    fn event_direction(&self, _index: usize) -> Direction {
        Direction::Both
    }

    /// Called once per located event, at the event point. May modify the state (an impact
    /// law such as `v -> -e v`); returns whether to continue. Default: continue, no change.
    fn on_event(&self, _event: &crate::Event, _y: &mut [f64]) -> EventAction {
        EventAction::Continue
    }
}

impl<S: OdeSystem + ?Sized> OdeSystem for &S {
    fn dim(&self) -> usize {
        (**self).dim()
    }
    fn rhs(&self, t: f64, y: &[f64], dydt: &mut [f64]) {
        (**self).rhs(t, y, dydt)
    }
    fn n_events(&self) -> usize {
        (**self).n_events()
    }
    fn events(&self, t: f64, y: &[f64], g: &mut [f64]) {
        (**self).events(t, y, g)
    }
    fn event_direction(&self, index: usize) -> Direction {
        (**self).event_direction(index)
    }
    fn on_event(&self, event: &crate::Event, y: &mut [f64]) -> EventAction {
        (**self).on_event(event, y)
    }
}

/// A second-order system `q'' = a(t, q, q')` with `n` degrees of freedom.
///
/// Wrap it in [`FirstOrder`] to integrate it; the first-order state is `y = [q; q']`
/// (positions first, then velocities).
pub trait SecondOrderSystem {
    /// Number of degrees of freedom `n` (the first-order state has `2n` entries).
    fn ndof(&self) -> usize;

    /// Accelerations: writes `a(t, q, v)` into `acc` (all slices of length `n`).
    fn acceleration(&self, t: f64, q: &[f64], v: &[f64], acc: &mut [f64]);

    /// Number of event functions (default 0).
    fn n_events(&self) -> usize {
        0
    }

    /// Event functions `g_i(t, q, v)`.
    fn events(&self, _t: f64, _q: &[f64], _v: &[f64], _g: &mut [f64]) {}

    /// Direction filter of event `index` (default both).
    fn event_direction(&self, _index: usize) -> Direction {
        Direction::Both
    }

    /// Event hook; may change positions and velocities (impact laws).
    fn on_event(&self, _event: &crate::Event, _q: &mut [f64], _v: &mut [f64]) -> EventAction {
        EventAction::Continue
    }
}

/// Adapter that turns a [`SecondOrderSystem`] into an [`OdeSystem`] with `y = [q; q']`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FirstOrder<S>(pub S);

impl<S: SecondOrderSystem> OdeSystem for FirstOrder<S> {
    fn dim(&self) -> usize {
        2 * self.0.ndof()
    }
    fn rhs(&self, t: f64, y: &[f64], dydt: &mut [f64]) {
        let n = self.0.ndof();
        let (q, v) = y.split_at(n);
        let (dq, dv) = dydt.split_at_mut(n);
        dq.copy_from_slice(v);
        self.0.acceleration(t, q, v, dv);
    }
    fn n_events(&self) -> usize {
        self.0.n_events()
    }
    fn events(&self, t: f64, y: &[f64], g: &mut [f64]) {
        let n = self.0.ndof();
        let (q, v) = y.split_at(n);
        self.0.events(t, q, v, g)
    }
    fn event_direction(&self, index: usize) -> Direction {
        self.0.event_direction(index)
    }
    fn on_event(&self, event: &crate::Event, y: &mut [f64]) -> EventAction {
        let n = self.0.ndof();
        let (q, v) = y.split_at_mut(n);
        self.0.on_event(event, q, v)
    }
}

/// Event functions of a symmetric gap (backlash, dead zone) of half-width `b` in the
/// coordinate `x`: `g[0] = x - b` (upper edge) and `g[1] = x + b` (lower edge).
///
/// A model with a backlash coordinate calls this from [`OdeSystem::events`] so that the
/// switching surfaces `x = ±b` of the dead-zone function are located exactly.
pub fn gap_edges(x: f64, b: f64, g: &mut [f64]) {
    g[0] = x - b;
    g[1] = x + b;
}

/// A closure-based [`OdeSystem`] without events: `FnSystem::new(dim, |t, y, dy| ...)`.
#[derive(Debug, Clone, Copy)]
pub struct FnSystem<F> {
    dim: usize,
    f: F,
}

impl<F: Fn(f64, &[f64], &mut [f64])> FnSystem<F> {
    /// Wraps `f(t, y, dydt)` as a system with `dim` states.
    pub fn new(dim: usize, f: F) -> Self {
        Self { dim, f }
    }
}

impl<F: Fn(f64, &[f64], &mut [f64])> OdeSystem for FnSystem<F> {
    fn dim(&self) -> usize {
        self.dim
    }
    fn rhs(&self, t: f64, y: &[f64], dydt: &mut [f64]) {
        (self.f)(t, y, dydt)
    }
}
