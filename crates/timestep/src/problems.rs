//! Reference problems with known answers, used by the tests and benches and available to
//! users for checking their own set-ups.

use crate::system::{Direction, EventAction, ExplicitSecondOrder, gap_edges};
use crate::{Event, FirstOrder};
use math::DetMath;

/// Linear oscillator `x'' + 2 ζ ω0 x' + ω0² x = F cos(Ω t)`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct LinearOscillator {
    /// Natural angular frequency ω0.
    pub omega0: f64,
    /// Damping ratio ζ.
    pub zeta: f64,
    /// Forcing amplitude F.
    pub force: f64,
    /// Forcing angular frequency Ω.
    pub omega: f64,
}

impl LinearOscillator {
    /// Exact free response of the undamped, unforced oscillator from `(x0, v0)` at time `t`.
    pub fn free_undamped(&self, x0: f64, v0: f64, t: f64) -> (f64, f64) {
        let w = self.omega0;
        let (s, c) = (w * t).dsin_cos();
        (x0 * c + v0 / w * s, -x0 * w * s + v0 * c)
    }

    /// As a first-order system `y = [x, x']`.
    pub fn first_order(self) -> FirstOrder<Self> {
        FirstOrder(self)
    }
}

impl ExplicitSecondOrder for LinearOscillator {
    fn ndof(&self) -> usize {
        1
    }
    fn acceleration(&self, t: f64, q: &[f64], v: &[f64], acc: &mut [f64]) {
        let w = self.omega0;
        acc[0] = self.force * (self.omega * t).dcos() - 2.0 * self.zeta * w * v[0] - w * w * q[0];
    }
}

/// Duffing oscillator `x'' + δ x' + α x + β x³ = γ cos(ω t)`.
///
/// With δ = 0.3, α = −1, β = 1, ω = 1.2 the response is period-1 at γ = 0.20, period-2 at
/// γ = 0.28 and chaotic at γ = 0.50 (the classic sequence of Holmes 1979 /
/// Guckenheimer & Holmes 1983, §2.2; also Jordan & Smith, *Nonlinear ODEs*, 4th ed., §13.3),
/// see [`Duffing::holmes`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Duffing {
    /// Damping δ.
    pub delta: f64,
    /// Linear stiffness α.
    pub alpha: f64,
    /// Cubic stiffness β.
    pub beta: f64,
    /// Forcing amplitude γ.
    pub gamma: f64,
    /// Forcing angular frequency ω.
    pub omega: f64,
}

impl Duffing {
    /// The double-well case δ = 0.3, α = −1, β = 1, ω = 1.2 with forcing amplitude `gamma`.
    pub fn holmes(gamma: f64) -> Self {
        Self {
            delta: 0.3,
            alpha: -1.0,
            beta: 1.0,
            gamma,
            omega: 1.2,
        }
    }
    /// Forcing period 2π/ω.
    pub fn period(&self) -> f64 {
        2.0 * std::f64::consts::PI / self.omega
    }
}

impl ExplicitSecondOrder for Duffing {
    fn ndof(&self) -> usize {
        1
    }
    fn acceleration(&self, t: f64, q: &[f64], v: &[f64], acc: &mut [f64]) {
        let x = q[0];
        acc[0] = self.gamma * (self.omega * t).dcos()
            - self.delta * v[0]
            - self.alpha * x
            - self.beta * x * x * x;
    }
}

/// Dead-zone (backlash) oscillator with parametric stiffness:
/// `x'' + 2ζ x' + (1 + κ cos Ω t) f(x) = F0 + F cos Ω t`, with the dead-zone function
/// `f(x) = x − b` for `x > b`, `0` for `|x| ≤ b`, `x + b` for `x < −b`.
///
/// This is the dimensionless 1-DOF gear-pair form (Liu et al. 2021, Eq. 9 and 12, with one
/// stiffness harmonic); its event functions are the gap edges `x = ±b` ([`gap_edges`]).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct DeadZoneOscillator {
    /// Damping ratio ζ.
    pub zeta: f64,
    /// Stiffness modulation κ.
    pub kappa: f64,
    /// Excitation frequency Ω.
    pub omega: f64,
    /// Mean force F0.
    pub f_mean: f64,
    /// Force amplitude F.
    pub f_amp: f64,
    /// Gap half-width b (> 0).
    pub b: f64,
}

impl DeadZoneOscillator {
    /// Unforced, undamped case with gap `b` (unit contact stiffness).
    pub fn free(b: f64) -> Self {
        Self {
            zeta: 0.0,
            kappa: 0.0,
            omega: 1.0,
            f_mean: 0.0,
            f_amp: 0.0,
            b,
        }
    }

    /// Exact event times of [`DeadZoneOscillator::free`] started at `x = 0` with velocity
    /// `v0 > 0`, unit contact stiffness: the first `n` crossings of `x = ±b`.
    pub fn free_event_times(b: f64, v0: f64, n: usize) -> Vec<f64> {
        let pi = std::f64::consts::PI;
        let mut t = b / v0;
        let mut out = Vec::with_capacity(n);
        for k in 0..n {
            out.push(t);
            t += if k % 2 == 0 { pi } else { 2.0 * b / v0 };
        }
        out
    }

    /// The dead-zone function `f(x)`.
    pub fn dead_zone(&self, x: f64) -> f64 {
        if x > self.b {
            x - self.b
        } else if x < -self.b {
            x + self.b
        } else {
            0.0
        }
    }
}

impl ExplicitSecondOrder for DeadZoneOscillator {
    fn ndof(&self) -> usize {
        1
    }
    fn acceleration(&self, t: f64, q: &[f64], v: &[f64], acc: &mut [f64]) {
        let c = (self.omega * t).dcos();
        acc[0] = self.f_mean + self.f_amp * c
            - 2.0 * self.zeta * v[0]
            - (1.0 + self.kappa * c) * self.dead_zone(q[0]);
    }
    fn n_events(&self) -> usize {
        2
    }
    fn events(&self, _t: f64, q: &[f64], _v: &[f64], g: &mut [f64]) {
        gap_edges(q[0], self.b, g);
    }
}

/// Impact oscillator: a ball under gravity `g` bouncing on a rigid floor `x = 0` with
/// restitution coefficient `e` (the impact law `v → −e v` is applied by the event hook).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct BouncingBall {
    /// Gravity g (> 0).
    pub gravity: f64,
    /// Coefficient of restitution e in [0, 1].
    pub restitution: f64,
}

impl BouncingBall {
    /// Exact impact times when dropped from rest at height `h0`: the first `n` impacts.
    pub fn impact_times(&self, h0: f64, n: usize) -> Vec<f64> {
        let t1 = (2.0 * h0 / self.gravity).sqrt();
        let v1 = self.gravity * t1;
        let mut out = Vec::with_capacity(n);
        let mut t = t1;
        let mut v = v1;
        for _ in 0..n {
            out.push(t);
            v *= self.restitution;
            t += 2.0 * v / self.gravity;
        }
        out
    }
}

impl ExplicitSecondOrder for BouncingBall {
    fn ndof(&self) -> usize {
        1
    }
    fn acceleration(&self, _t: f64, _q: &[f64], _v: &[f64], acc: &mut [f64]) {
        acc[0] = -self.gravity;
    }
    fn n_events(&self) -> usize {
        1
    }
    fn events(&self, _t: f64, q: &[f64], _v: &[f64], g: &mut [f64]) {
        g[0] = q[0];
    }
    fn event_direction(&self, _index: usize) -> Direction {
        Direction::Falling
    }
    fn on_event(&self, _event: &Event, q: &mut [f64], v: &mut [f64]) -> EventAction {
        q[0] = 0.0;
        v[0] *= -self.restitution;
        EventAction::Continue
    }
}
