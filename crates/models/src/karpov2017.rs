//! Karpov et al. 2017: a one-degree-of-freedom oscillator excited at the variable mesh frequency
//! of slightly non-circular gears (Eq. 7–10).
//!
//! ## Equations
//!
//! Dimensional (Eq. 8): `ẍ + ωn² x = f0 sin(·)` with mesh frequency `ωm = r1 z1 ω1/r` (Eq. 7).
//! With `τ = ωn t`, `X = x ωn²/f0`, `ω = z1 ω1/ωn`, `k = j/z1` (Eq. 9–10):
//!
//! ```text
//! X'' + X = sin Φ(τ),   ωe(τ) = ω (1 + g(kωτ)),   g(θ) = B√(ξ²−1) sin θ/(ξ + cos θ)
//! ```
//!
//! with zero initial conditions. Two readings of the phase `Φ` ([`Excitation`], reading
//! `R-KARPOV-EQ9`):
//!
//! * [`Excitation::AccumulatedPhase`] (default): `Φ = ∫₀^τ ωe dτ' = ωτ + G(kωτ)/k`,
//!   `G(θ) = −B√(ξ²−1) ln((ξ + cos θ)/(ξ + 1))` — the phase the mesh actually accumulates, whose
//!   instantaneous frequency is Eq. (7).
//! * [`Excitation::PrintedPhase`]: `Φ = ωe(τ)·τ`, Eq. (9) exactly as printed. Its instantaneous
//!   frequency `ωe + τ ωe'` grows without bound with `τ` (±173 at `τ = 10⁵` for Fig. 3's data).
//!
//! ## Final amplitude `A`
//!
//! [`AmplitudeMeasure::LastCycleMax`] (default): `A = max |X(τ)|` over the last cycle
//! `τ ∈ [τ_end − T, τ_end]`, `T = 2π·max(1, 1/ω)` (one period of both the free and the forced
//! motion), sampled every ≤ 0.01 (relative sampling error ≤ 1.3e-5).
//! [`AmplitudeMeasure::Envelope`]: `A = √(X² + X'²)` at `τ_end`, the amplitude of the free
//! oscillation the system would continue with.
//!
//! ## Methods
//!
//! The system is linear, so the response is the Duhamel integral
//! `X(τ) = sin τ·C(τ) − cos τ·S(τ)`, `X'(τ) = cos τ·C + sin τ·S`,
//! `C = ∫₀^τ cos s sin Φ(s) ds`, `S = ∫₀^τ sin s sin Φ(s) ds`, computed by 10-point
//! Gauss–Legendre panels whose length adapts to the local frequency (`≤ 2/(1 + |Φ'|)`):
//! [`Karpov2017::duhamel`] (fast path, ~10⁵ panels for `τ_end = 10⁵` in the accumulated
//! reading). The model also implements [`timestep::OdeSystem`] (states `[X, X']`) so the same
//! response can be integrated step by step; the two agree to ~1e-8 (tests).

use std::f64::consts::TAU;

use gear_geometry::{CentrodeDeviation, GaussLegendre, KarpovPair};
use serde::{Deserialize, Serialize};

use crate::Error;

/// How the excitation phase of Eq. (9) is read (reading `R-KARPOV-EQ9`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Excitation {
    /// `sin(∫₀^τ ωe dτ')`: the accumulated mesh phase of Eq. (7). Default.
    #[default]
    AccumulatedPhase,
    /// `sin(ωe(τ)·τ)`: Eq. (9)–(10) exactly as printed.
    PrintedPhase,
}

/// Definition of the final amplitude `A` (Section 3.3, "the amplitude that corresponds to the
/// final moment of simulation").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum AmplitudeMeasure {
    /// `max |X|` over the last cycle `[τ_end − 2π·max(1, 1/ω), τ_end]`. Default.
    #[default]
    LastCycleMax,
    /// `√(X² + X'²)` at `τ_end`.
    Envelope,
}

/// Dimensionless parameters of Eq. (9)–(10) (serde form; validated by [`Karpov2017::new`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Karpov2017Params {
    /// `ω = z1 ω1/ωn`, dimensionless input gear velocity (Eq. 9), `> 0`.
    pub omega: f64,
    /// `B`, maximum relative centrode deviation (Eq. 1, 10), in `[0, 1)`.
    pub b: f64,
    /// `ξ`, smoothness coefficient (Eq. 1, 10), `> 1` (`+∞`: sinusoidal limit of Section 4).
    pub xi: f64,
    /// `k = j/z1` (Eq. 10), `> 0`.
    pub k: f64,
    /// `τ_end`, end of the simulation (paper: `10⁵`), `> 0`.
    pub tau_end: f64,
    /// Reading of the excitation phase.
    #[serde(default)]
    pub excitation: Excitation,
    /// Definition of `A`.
    #[serde(default)]
    pub measure: AmplitudeMeasure,
}

/// The Karpov 2017 oscillator (validated).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Karpov2017 {
    p: Karpov2017Params,
    dev: CentrodeDeviation,
}

/// Response at `τ_end` computed by the Duhamel integral.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct KarpovResponse {
    /// `X(τ_end)`.
    pub x: f64,
    /// `X'(τ_end)`.
    pub v: f64,
    /// `√(X² + X'²)` at `τ_end`.
    pub envelope: f64,
    /// `max |X|` over the last cycle.
    pub last_cycle_max: f64,
    /// The amplitude `A` by the chosen [`AmplitudeMeasure`].
    pub amplitude: f64,
    /// Quadrature panels used (work measure).
    pub panels: u64,
}

/// Panel-length factor: panels are `≤ PANEL/(1 + |Φ'|)` long.
const PANEL: f64 = 2.0;
/// Sampling step of `|X|` in the last cycle.
const SAMPLE: f64 = 0.01;
/// Panel factor of [`Karpov2017::duhamel`].
pub const DEFAULT_PANEL: f64 = PANEL;
/// Panel budget of [`Karpov2017::duhamel`] and [`Karpov2017::duhamel_with`]; beyond it the
/// response is NaN (use [`Karpov2017::try_duhamel_budget`] for the error).
pub const MAX_PANELS: u64 = 200_000_000;

impl Karpov2017 {
    /// Validate and build. Errors name the field (`karpov2017.omega`, …).
    pub fn new(p: Karpov2017Params) -> Result<Self, Error> {
        let pos = |name: &str, v: f64| -> Result<(), Error> {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(Error::invalid(name, "finite and > 0", v))
            }
        };
        pos("karpov2017.omega", p.omega)?;
        pos("karpov2017.k", p.k)?;
        pos("karpov2017.tau_end", p.tau_end)?;
        if !(p.b.is_finite() && (0.0..1.0).contains(&p.b)) {
            return Err(Error::invalid("karpov2017.b", "in [0, 1)", p.b));
        }
        if p.xi.is_nan() || p.xi <= 1.0 {
            return Err(Error::invalid("karpov2017.xi", "> 1 (or +inf)", p.xi));
        }
        let dev = CentrodeDeviation::new(p.b, p.xi).map_err(|e| Error::Geometry(e.to_string()))?;
        Ok(Self { p, dev })
    }

    /// Fig. 3 of the paper: `ω = 1`, `B = 0.01`, `ξ = 2`, `k = 1/10`, `τ_end = 10⁵`, with the
    /// default (accumulated-phase) reading.
    pub fn fig3() -> Self {
        Self::new(Karpov2017Params {
            omega: 1.0,
            b: 0.01,
            xi: 2.0,
            k: 0.1,
            tau_end: 1e5,
            excitation: Excitation::AccumulatedPhase,
            measure: AmplitudeMeasure::LastCycleMax,
        })
        .expect("Fig. 3 parameters are valid")
    }

    /// From a gear pair and the dimensional speeds: `ω = z1 ω1/ωn`, `k = j/z1`, `B`, `ξ` of the
    /// pair. `ω1`, `ωn` in rad/s.
    pub fn from_pair(
        pair: &KarpovPair,
        omega1: f64,
        omega_n: f64,
        tau_end: f64,
    ) -> Result<Self, Error> {
        if !(omega_n.is_finite() && omega_n > 0.0) {
            return Err(Error::invalid(
                "karpov2017.omega_n",
                "finite and > 0",
                omega_n,
            ));
        }
        if !(omega1.is_finite() && omega1 > 0.0) {
            return Err(Error::invalid(
                "karpov2017.omega1",
                "finite and > 0",
                omega1,
            ));
        }
        let omega = f64::from(pair.z1()) * omega1 / omega_n;
        if !omega.is_finite() {
            return Err(Error::invalid(
                "karpov2017.omega1",
                "such that z1·omega1/omega_n is finite",
                omega1,
            ));
        }
        Self::new(Karpov2017Params {
            omega: f64::from(pair.z1()) * omega1 / omega_n,
            b: pair.b(),
            xi: pair.xi(),
            k: pair.k(),
            tau_end,
            excitation: Excitation::default(),
            measure: AmplitudeMeasure::default(),
        })
    }

    /// The parameters.
    pub fn params(&self) -> Karpov2017Params {
        self.p
    }

    /// Same model with other parameters changed through a closure (validated).
    pub fn with(&self, f: impl FnOnce(&mut Karpov2017Params)) -> Result<Self, Error> {
        let mut p = self.p;
        f(&mut p);
        Self::new(p)
    }

    /// Dimensionless excitation frequency `ωe(τ)` of Eq. (10).
    #[inline]
    pub fn excitation_frequency(&self, tau: f64) -> f64 {
        self.dev
            .dimensionless_mesh_frequency(tau, self.p.omega, self.p.k)
    }

    /// Excitation phase `Φ(τ)` in the chosen reading.
    #[inline]
    pub fn phase(&self, tau: f64) -> f64 {
        match self.p.excitation {
            Excitation::AccumulatedPhase => {
                self.dev
                    .dimensionless_mesh_phase(tau, self.p.omega, self.p.k)
            }
            Excitation::PrintedPhase => self.excitation_frequency(tau) * tau,
        }
    }

    /// Instantaneous frequency `Φ'(τ)` of the excitation in the chosen reading
    /// (`ωe` for the accumulated phase, `ωe + τ ωe'` for the printed one).
    #[inline]
    pub fn phase_rate(&self, tau: f64) -> f64 {
        let (w, k) = (self.p.omega, self.p.k);
        match self.p.excitation {
            Excitation::AccumulatedPhase => self.excitation_frequency(tau),
            Excitation::PrintedPhase => {
                let th = k * w * tau;
                w * (1.0 + self.dev.value(th)) + tau * w * k * w * self.dev.derivative(th)
            }
        }
    }

    /// Right-hand side forcing `sin Φ(τ)`.
    #[inline]
    pub fn forcing(&self, tau: f64) -> f64 {
        self.phase(tau).sin()
    }

    /// Length of the last cycle over which [`AmplitudeMeasure::LastCycleMax`] looks.
    pub fn last_cycle(&self) -> f64 {
        TAU * (1.0f64).max(1.0 / self.p.omega)
    }

    /// Response at `τ_end` by the Duhamel integral (the fast path; no time stepping).
    pub fn duhamel(&self) -> KarpovResponse {
        self.duhamel_with(PANEL)
    }

    /// [`Karpov2017::duhamel`] with panel factor `panel` (panels `≤ panel/(1 + |Φ'|)`); for
    /// convergence checks.
    ///
    /// Within [`MAX_PANELS`] panels; a response that would need more (or a non-positive
    /// `panel`) is all NaN — [`Karpov2017::try_duhamel_budget`] reports why.
    pub fn duhamel_with(&self, panel: f64) -> KarpovResponse {
        self.try_duhamel_budget(panel, MAX_PANELS)
            .unwrap_or(KarpovResponse {
                x: f64::NAN,
                v: f64::NAN,
                envelope: f64::NAN,
                last_cycle_max: f64::NAN,
                amplitude: f64::NAN,
                panels: 0,
            })
    }

    /// [`Karpov2017::duhamel_with`] with a panel budget: errors (naming the bound) if `panel`
    /// is not finite and > 0, if the estimated panel count `τ_end (1 + ω(1 − B))/panel`
    /// exceeds `max_panels`, if the quadrature takes more than `max_panels` panels, if a
    /// panel no longer advances `τ` (`τ + h == τ`), or if the response is not finite (e.g.
    /// an overflowing phase for extreme `k`, `ω`). Every loop therefore ends.
    pub fn try_duhamel_budget(&self, panel: f64, max_panels: u64) -> Result<KarpovResponse, Error> {
        if !(panel.is_finite() && panel > 0.0) {
            return Err(Error::invalid("karpov2017.panel", "finite and > 0", panel));
        }
        let estimate = self.p.tau_end * (1.0 + self.p.omega * (1.0 - self.p.b)) / panel;
        if estimate.is_nan() || estimate > max_panels as f64 {
            return Err(Error::Solver(format!(
                "karpov2017: about {estimate:.3e} quadrature panels needed for tau_end = {} and \
                 omega = {}, over the budget of {max_panels}",
                self.p.tau_end, self.p.omega
            )));
        }
        let over = |panels: u64, t: f64, h: f64| -> Result<(), Error> {
            if panels >= max_panels {
                Err(Error::Solver(format!(
                    "karpov2017: quadrature budget of {max_panels} panels spent at tau = {t}"
                )))
            } else if t + h <= t {
                Err(Error::Solver(format!(
                    "karpov2017: quadrature step {h:e} no longer advances tau = {t}"
                )))
            } else {
                Ok(())
            }
        };
        let g = GaussLegendre::<10>::new();
        let tau_end = self.p.tau_end;
        let t_w = (tau_end - self.last_cycle()).max(0.0);
        let mut c = Sum::default();
        let mut s = Sum::default();
        let mut t = 0.0;
        let mut panels = 0u64;
        let step = |t: f64, h: f64, c: &mut Sum, s: &mut Sum| {
            let (half, mid) = (0.5 * h, t + 0.5 * h);
            let (mut pc, mut ps) = (0.0, 0.0);
            for i in 0..10 {
                let x = mid + half * g.nodes[i];
                let f = g.weights[i] * self.forcing(x);
                let (sx, cx) = x.sin_cos();
                pc += f * cx;
                ps += f * sx;
            }
            c.add(pc * half);
            s.add(ps * half);
        };
        while t < t_w {
            let h = (panel / (1.0 + self.phase_rate(t).abs())).min(t_w - t);
            over(panels, t, h)?;
            step(t, h, &mut c, &mut s);
            t += h;
            panels += 1;
        }
        let x_at = |t: f64, c: f64, s: f64| {
            let (st, ct) = t.sin_cos();
            (st * c - ct * s, ct * c + st * s)
        };
        let mut max_abs = x_at(t, c.value(), s.value()).0.abs();
        while t < tau_end {
            let h = (panel / (1.0 + self.phase_rate(t).abs()))
                .min(SAMPLE)
                .min(tau_end - t);
            over(panels, t, h)?;
            step(t, h, &mut c, &mut s);
            t += h;
            panels += 1;
            max_abs = max_abs.max(x_at(t, c.value(), s.value()).0.abs());
        }
        let (x, v) = x_at(tau_end, c.value(), s.value());
        let envelope = x.hypot(v);
        let amplitude = match self.p.measure {
            AmplitudeMeasure::LastCycleMax => max_abs,
            AmplitudeMeasure::Envelope => envelope,
        };
        if !(x.is_finite() && v.is_finite() && max_abs.is_finite()) {
            return Err(Error::Solver(format!(
                "karpov2017: non-finite response (X = {x}, X' = {v}) for {:?}",
                self.p
            )));
        }
        Ok(KarpovResponse {
            x,
            v,
            envelope,
            last_cycle_max: max_abs,
            amplitude,
            panels,
        })
    }

    /// Final amplitude `A` (fast path).
    pub fn amplitude(&self) -> f64 {
        self.duhamel().amplitude
    }

    /// Secular growth rate `dA/dτ` of the accumulated-phase response at `ω = 1`.
    ///
    /// The excitation `sin(τ + G(kτ)/k)` is a phase-modulated carrier whose mean frequency is
    /// exactly 1, so its spectrum keeps a line at the natural frequency with complex amplitude
    /// `c0 = (1/2π)∫₀^{2π} exp(i G(θ)/k) dθ`; that line grows the response like `|c0|·τ/2`
    /// (the sidebands at `1 + nk` stay bounded). Trapezoidal rule, 512 points (spectrally
    /// accurate). Returns `|c0|/2` (`1/2` for `B = 0`).
    pub fn accumulated_resonance_growth_rate(&self) -> f64 {
        let n = 512;
        let (mut re, mut im) = (0.0, 0.0);
        for i in 0..n {
            let th = TAU * i as f64 / n as f64;
            let (s, c) = (self.dev.integral(th) / self.p.k).sin_cos();
            re += c;
            im += s;
        }
        0.5 * re.hypot(im) / n as f64
    }

    /// Classical resonance (`B = 0`, `ω = 1`) exact solution `X = (sin τ − τ cos τ)/2`,
    /// `X' = τ sin τ/2`: amplitude grows like `τ/2`.
    pub fn resonance_solution(tau: f64) -> (f64, f64) {
        let (s, c) = tau.sin_cos();
        (0.5 * (s - tau * c), 0.5 * tau * s)
    }
}

impl timestep::OdeSystem for Karpov2017 {
    fn dim(&self) -> usize {
        2
    }

    fn rhs(&self, t: f64, y: &[f64], dydt: &mut [f64]) {
        dydt[0] = y[1];
        dydt[1] = self.forcing(t) - y[0];
    }
}

/// Neumaier-compensated sum.
#[derive(Default, Clone, Copy)]
struct Sum {
    s: f64,
    c: f64,
}

impl Sum {
    fn add(&mut self, x: f64) {
        let t = self.s + x;
        if self.s.abs() >= x.abs() {
            self.c += (self.s - t) + x;
        } else {
            self.c += (x - t) + self.s;
        }
        self.s = t;
    }
    fn value(&self) -> f64 {
        self.s + self.c
    }
}

#[cfg(test)]
mod tests {

    /// Inputs that used to hang return at once: NaN from `duhamel*`, an error naming the
    /// budget from `try_duhamel_budget`.
    #[test]
    fn loops_end_on_extreme_inputs() {
        let m = Karpov2017::fig3().with(|p| p.omega = 1e17).unwrap();
        assert!(m.duhamel().x.is_nan());
        let e = m.try_duhamel_budget(DEFAULT_PANEL, MAX_PANELS).unwrap_err();
        assert!(e.to_string().contains("panels"), "{e}");
        let m = Karpov2017::fig3().with(|p| p.tau_end = 1e12).unwrap();
        assert!(m.duhamel().x.is_nan());
        let m = Karpov2017::fig3();
        assert!(m.duhamel_with(0.0).x.is_nan());
        assert!(m.duhamel_with(f64::NAN).x.is_nan());
        assert!(m.try_duhamel_budget(-1.0, 10).is_err());
        // a small budget is honoured
        assert!(m.try_duhamel_budget(DEFAULT_PANEL, 10).is_err());
        assert!(m.try_duhamel_budget(DEFAULT_PANEL, MAX_PANELS).is_ok());
    }

    use super::*;
    use timestep::{Method, Options, Output};

    fn model(b: f64, omega: f64, tau_end: f64, ex: Excitation) -> Karpov2017 {
        Karpov2017::new(Karpov2017Params {
            omega,
            b,
            xi: 2.0,
            k: 0.1,
            tau_end,
            excitation: ex,
            measure: AmplitudeMeasure::LastCycleMax,
        })
        .unwrap()
    }

    /// Independent check without the `timestep` crate: classical RK4 with a small fixed step.
    fn rk4(m: &Karpov2017, tau_end: f64, h: f64) -> (f64, f64) {
        let f = |t: f64, x: f64, v: f64| (v, m.forcing(t) - x);
        let n = (tau_end / h).ceil() as usize;
        let h = tau_end / n as f64;
        let (mut x, mut v) = (0.0, 0.0);
        for i in 0..n {
            let t = i as f64 * h;
            let (a1, b1) = f(t, x, v);
            let (a2, b2) = f(t + 0.5 * h, x + 0.5 * h * a1, v + 0.5 * h * b1);
            let (a3, b3) = f(t + 0.5 * h, x + 0.5 * h * a2, v + 0.5 * h * b2);
            let (a4, b4) = f(t + h, x + h * a3, v + h * b3);
            x += h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4);
            v += h / 6.0 * (b1 + 2.0 * b2 + 2.0 * b3 + b4);
        }
        (x, v)
    }

    #[test]
    fn validation_names_fields() {
        let p = Karpov2017::fig3().params();
        let e = |q: Karpov2017Params| Karpov2017::new(q).unwrap_err().to_string();
        assert!(e(Karpov2017Params { omega: 0.0, ..p }).starts_with("karpov2017.omega"));
        assert!(e(Karpov2017Params { b: 1.0, ..p }).starts_with("karpov2017.b"));
        assert!(e(Karpov2017Params { b: f64::NAN, ..p }).starts_with("karpov2017.b"));
        assert!(e(Karpov2017Params { xi: 0.5, ..p }).starts_with("karpov2017.xi"));
        assert!(e(Karpov2017Params { k: -1.0, ..p }).starts_with("karpov2017.k"));
        assert!(
            e(Karpov2017Params {
                tau_end: f64::INFINITY,
                ..p
            })
            .starts_with("karpov2017.tau_end")
        );
        let json = serde_json::to_string(&p).unwrap();
        let back: Karpov2017Params = serde_json::from_str(&json).unwrap();
        assert_eq!(back, p);
    }

    #[test]
    fn b_zero_is_classical_resonance() {
        // X'' + X = sin τ, X(0) = X'(0) = 0: X = (sin τ − τ cos τ)/2, amplitude → τ/2.
        for ex in [Excitation::AccumulatedPhase, Excitation::PrintedPhase] {
            let m = model(0.0, 1.0, 2000.0, ex);
            let r = m.duhamel();
            let (x, v) = Karpov2017::resonance_solution(2000.0);
            assert!(
                (r.x - x).abs() < 1e-9 && (r.v - v).abs() < 1e-9,
                "{r:?} vs {x} {v}"
            );
            assert!((r.amplitude / 1000.0 - 1.0).abs() < 2e-3, "{}", r.amplitude);
            assert!((r.envelope - 0.5 * (2000f64 * 2000.0 + 1.0).sqrt()).abs() < 0.5);
        }
    }

    #[test]
    fn duhamel_matches_timestep_and_rk4() {
        for ex in [Excitation::AccumulatedPhase, Excitation::PrintedPhase] {
            let tau_end = 300.0;
            let m = model(0.05, 1.0, tau_end, ex);
            let r = m.duhamel();
            // panel refinement changes nothing at the 1e-10 level
            let r2 = m.duhamel_with(1.0);
            assert!((r.x - r2.x).abs() < 1e-10 && (r.v - r2.v).abs() < 1e-10);
            let (x, v) = rk4(&m, tau_end, 0.01);
            // RK4 (h = 0.01) global error ~1e-8 relative over 300 time units
            let tol = 1e-7 * r.envelope;
            assert!(
                (r.x - x).abs() < tol && (r.v - v).abs() < tol,
                "{ex:?}: {r:?} vs {x} {v}"
            );
            let opts = Options::default()
                .with_method(Method::DormandPrince54)
                .with_tol(1e-11, 1e-12)
                .with_output(Output::Final);
            let sol = timestep::integrate(&m, 0.0, &[0.0, 0.0], tau_end, &opts).unwrap();
            let y = sol.y_final.clone();
            let tol = 1e-6 * r.envelope;
            assert!(
                (r.x - y[0]).abs() < tol && (r.v - y[1]).abs() < tol,
                "{ex:?}: {r:?} vs {y:?}"
            );
        }
    }

    #[test]
    fn accumulated_reading_keeps_resonant_growth() {
        // R-KARPOV-EQ9: with the accumulated phase the response at ω = 1 still grows linearly,
        // at the rate |c0|/2 of the carrier line; the printed reading stays bounded.
        for (b, k) in [(0.01, 0.1), (0.02, 0.01), (0.05, 0.05)] {
            let m = Karpov2017::fig3()
                .with(|p| {
                    p.b = b;
                    p.k = k;
                    p.tau_end = 20_000.0;
                })
                .unwrap();
            let rate = m.accumulated_resonance_growth_rate();
            let a = m.duhamel().envelope;
            assert!(
                (a / 20_000.0 / rate - 1.0).abs() < 0.01,
                "B={b} k={k}: A={a}, rate={rate}"
            );
        }
        let zero = Karpov2017::fig3().with(|p| p.b = 0.0).unwrap();
        assert!((zero.accumulated_resonance_growth_rate() - 0.5).abs() < 1e-15);
        let printed = Karpov2017::fig3()
            .with(|p| {
                p.tau_end = 5000.0;
                p.excitation = Excitation::PrintedPhase;
            })
            .unwrap();
        assert!(printed.amplitude() < 200.0, "{}", printed.amplitude());
    }

    #[test]
    fn accumulated_phase_matches_quadrature_of_frequency() {
        let m = model(0.3, 1.3, 10.0, Excitation::AccumulatedPhase);
        // Φ(τ) = ∫ ωe: Simpson on a fine grid
        let n = 20_000;
        let h = 7.0 / n as f64;
        let mut s = 0.0;
        for i in 0..=n {
            let w = if i == 0 || i == n {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            s += w * m.excitation_frequency(i as f64 * h);
        }
        s *= h / 3.0;
        assert!((s - m.phase(7.0)).abs() < 1e-10);
        // the printed phase's rate is the derivative of ωe·τ
        let p = model(0.3, 1.3, 10.0, Excitation::PrintedPhase);
        let d = 1e-5;
        let fd = (p.phase(6.0 + d) - p.phase(6.0 - d)) / (2.0 * d);
        assert!((fd - p.phase_rate(6.0)).abs() < 1e-7);
    }

    /// Values for `docs/readings/karpov.md` (release: `cargo test -p models --release karpov
    /// -- --ignored --nocapture`).
    #[test]
    #[ignore = "several seconds in release; prints the A tables of the readings"]
    fn paper_values() {
        let base = Karpov2017::fig3();
        let a = |ex: Excitation, f: &dyn Fn(&mut Karpov2017Params)| {
            base.with(|p| {
                p.excitation = ex;
                f(p)
            })
            .unwrap()
            .duhamel()
        };
        // A over `values` of one parameter (set by `set`), the others changed by `fixed`.
        let row = |ex: Excitation,
                   values: &[f64],
                   fixed: &dyn Fn(&mut Karpov2017Params),
                   set: &dyn Fn(&mut Karpov2017Params, f64)| {
            values
                .iter()
                .map(|&v| {
                    format!(
                        "{:.3}",
                        a(ex, &|p| {
                            fixed(p);
                            set(p, v)
                        })
                        .amplitude
                    )
                })
                .collect::<Vec<String>>()
                .join(" ")
        };
        for ex in [Excitation::PrintedPhase, Excitation::AccumulatedPhase] {
            println!("== {ex:?}");
            let t0 = std::time::Instant::now();
            let r = a(ex, &|_| {});
            println!("fig3 duhamel wall time {:?}", t0.elapsed());
            println!(
                "fig3 A={:.4} env={:.4} panels={}",
                r.amplitude, r.envelope, r.panels
            );
            println!(
                "fig3 growth-rate*tau = {:.3}",
                1e5 * base.accumulated_resonance_growth_rate()
            );
            for t in [2.5e4, 5e4, 2e5] {
                println!(
                    "fig3 tau_end={t}: A={:.3}",
                    a(ex, &|p| p.tau_end = t).amplitude
                );
            }
            for b in [0.0, 0.001, 0.002, 0.005, 0.01, 0.02] {
                let ks = row(ex, &[0.01, 0.05, 0.1, 0.2], &|p| p.b = b, &|p, k| p.k = k);
                println!("fig5 B={b} k=[.01,.05,.1,.2]: {ks}");
            }
            for xi in [1.1, 2.0, 5.0, 10.0, f64::INFINITY] {
                let bs = row(ex, &[0.001, 0.005, 0.01], &|p| p.xi = xi, &|p, b| p.b = b);
                println!("fig6 xi={xi} B=[.001,.005,.01]: {bs}");
            }
            for w in [0.8, 0.9, 0.95, 0.99, 1.0, 1.01, 1.05, 1.1, 1.2] {
                let bs = row(ex, &[0.001, 0.01], &|p| p.omega = w, &|p, b| p.b = b);
                println!(
                    "fig4 w={w} B=[.001,.01]: {bs}  (1/|1-w^2| = {:.3})",
                    1.0 / (1.0 - w * w).abs()
                );
            }
        }
    }
}
