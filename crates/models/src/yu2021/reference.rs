//! The time-integration reference of one Yu run with its motion type and reproducibility
//! (issue "validation that counts only evidence": every time-stepping point carries its motion
//! type and whether its metrics hold when the tolerance is tightened 100×).
//!
//! [`Yu2021Model::reference_run`] runs [`Yu2021Model::simulate_with`] and then
//!
//! * classifies the recorded window by its stroboscopic Poincaré sections at every sampled phase
//!   ([`crate::motion::classify_record`] on the DTE `δ*` and the backlash `B`, both in units of
//!   `b_n`): period-n (`n ≤ 4`) when every section repeats after `n` mesh periods within
//!   [`ReferenceCheck::periodicity_tol`] of the response size `s = pp(δ*) + mean B`, else
//!   non-periodic;
//! * repeats the recorded window at a tolerance tightened by [`ReferenceCheck::refine_factor`]
//!   (`rtol`, `atol` divided by it for [`Engine::Timestep`]; the RK4 steps per period multiplied
//!   by its fourth root for [`Engine::Rk4Fixed`], whose error is `O(h⁴)`): the run continues
//!   from the state at the end of the record (an integer number of mesh periods, so the forcing
//!   phase is the same) for [`ReferenceCheck::refine_periods`] periods and records the same
//!   metrics. The refined window is the *next* one, so the check also fails when the response
//!   still drifts (an undecayed transient) — a stricter test than re-integrating the same window;
//! * compares the metrics ([`Metrics`]: DF, Eq. 20; RMS of the first `n` harmonics, Eq. 21;
//!   mean and peak-to-peak DTE; mean backlash): the largest change, relative to DF for DF and to
//!   `s` for the lengths, must stay within [`ReferenceCheck::metric_rel_tol`].
//!
//! [`ReferenceRun::flag`] says why a point cannot carry a verdict.

use math::DetMath;
use serde::{Deserialize, Serialize};

use crate::Error;
use crate::motion::{Motion, classify_record};

use super::engines::Engine;
use super::model::{EquationForm, ModelKind, Response, RunSettings, STATE_LEN, Yu2021Model};

/// Settings of [`Yu2021Model::reference_run`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ReferenceCheck {
    /// The repeat runs at the tolerance divided by this factor (> 1).
    pub refine_factor: f64,
    /// Mesh periods recorded by the repeat (≥ 1).
    pub refine_periods: usize,
    /// Relative distance (to `s = pp(δ*) + mean B`) below which two section points are equal.
    pub periodicity_tol: f64,
    /// Largest relative change of a metric under the refined tolerance for a reproducible point.
    pub metric_rel_tol: f64,
    /// Harmonics `n` of the RMS metric (Eq. 21).
    pub rms_harmonics: usize,
}

impl Default for ReferenceCheck {
    /// Factor 100, 20 refined periods, periodicity 1e-4, metrics 1e-3, RMS over 4 harmonics
    /// (the values of the Liu reference: `liu2021::SweepStrategy`'s `poincare_tol` and
    /// `ppv_rel_tol`; `n = 4` of R-YU-EQ21).
    fn default() -> Self {
        ReferenceCheck {
            refine_factor: crate::contract::TIGHTER,
            refine_periods: 20,
            periodicity_tol: 1e-4,
            metric_rel_tol: 1e-3,
            rms_harmonics: 4,
        }
    }
}

/// The metrics of a recorded window.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Metrics {
    /// Dynamic factor `max F_m / F_s` (Eq. 20).
    pub dynamic_factor: f64,
    /// RMS of the first `n` DTE harmonics (Eq. 21), units of `b_n`.
    pub rms: f64,
    /// Mean DTE `δ*`.
    pub mean_dte: f64,
    /// Peak-to-peak DTE.
    pub dte_peak_to_peak: f64,
    /// Mean backlash `B/b_n`.
    pub mean_backlash: f64,
}

impl Metrics {
    /// The metrics of a response (`n` harmonics for the RMS).
    pub fn of(r: &Response, n: usize) -> Self {
        Metrics {
            dynamic_factor: r.dynamic_factor(),
            rms: r.rms(n),
            mean_dte: r.mean_dte(),
            dte_peak_to_peak: r.dte_peak_to_peak(),
            mean_backlash: r.mean_backlash(),
        }
    }

    /// Response size `s = pp(δ*) + |mean B|`, the scale of the length metrics (at least the
    /// smallest positive normal number).
    pub fn scale(&self) -> f64 {
        (self.dte_peak_to_peak.abs() + self.mean_backlash.abs()).max(f64::MIN_POSITIVE)
    }

    /// Largest relative change from `self` to `other`: `|ΔDF|/|DF|`, and `|Δ|/s` for RMS, mean
    /// DTE, peak-to-peak DTE and mean backlash (`s` of `self`). NaN-safe: a non-finite metric
    /// gives infinity.
    pub fn max_change(&self, other: &Metrics) -> f64 {
        let s = self.scale();
        let df = (other.dynamic_factor - self.dynamic_factor).abs()
            / self.dynamic_factor.abs().max(f64::MIN_POSITIVE);
        let lengths = [
            (self.rms, other.rms),
            (self.mean_dte, other.mean_dte),
            (self.dte_peak_to_peak, other.dte_peak_to_peak),
            (self.mean_backlash, other.mean_backlash),
        ];
        let mut worst = df;
        for (a, b) in lengths {
            worst = worst.max((b - a).abs() / s);
        }
        if worst.is_finite() {
            worst
        } else {
            f64::INFINITY
        }
    }
}

/// One checked run: the response, its motion type and the refined metrics.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReferenceRun {
    /// The recorded response of the run.
    pub response: Response,
    /// Motion type of the recorded window.
    pub motion: Motion,
    /// Metrics of the recorded window.
    pub metrics: Metrics,
    /// The same metrics from the repeat at the tightened tolerance.
    pub refined: Metrics,
    /// [`Metrics::max_change`] from `metrics` to `refined`.
    pub max_change: f64,
    /// `max_change ≤ metric_rel_tol`.
    pub reproducible: bool,
}

impl ReferenceRun {
    /// Why this point cannot carry a verdict, or `None`: metrics that move beyond the tolerance
    /// under the tightened tolerance, or — when the verdict needs a periodic response
    /// (`periodic_needed`: harmonics, spectra, phase portraits) — a non-periodic motion.
    pub fn flag(&self, periodic_needed: bool) -> Option<String> {
        if !self.reproducible {
            // no size: the change itself moves with every retune of the integrator, and this
            // text is committed (validation/verdicts.csv); `max_change` carries it
            return Some(
                "time integration: metrics not reproducible under a 100× tighter tolerance"
                    .to_owned(),
            );
        }
        if periodic_needed && self.motion == Motion::NonPeriodic {
            return Some("time integration: non-periodic motion".to_owned());
        }
        None
    }
}

impl Yu2021Model {
    /// A steady-state run on `engine` with its motion type and the repeat at a tightened
    /// tolerance (see the module docs).
    ///
    /// Errors as [`Yu2021Model::simulate_with`], and on `refine_factor ≤ 1` or not finite,
    /// `refine_periods = 0`, or a tightened tolerance the engine refuses.
    pub fn reference_run(
        &self,
        settings: &RunSettings,
        engine: &Engine,
        check: &ReferenceCheck,
    ) -> Result<ReferenceRun, Error> {
        self.reference_run_from(settings, engine, check, self.static_state(settings.omega))
    }

    /// [`Yu2021Model::reference_run`] from the state `start` at `τ = 0` instead of the static
    /// state: the point of a continuation sweep (up- and down-sweeps start every point from the
    /// previous point's final state, so a coexisting response is followed), with the same
    /// motion type and repeat at the tightened tolerance.
    ///
    /// Errors as [`Yu2021Model::reference_run`], and on a non-finite `start` (the field and the
    /// index are named).
    pub fn reference_run_from(
        &self,
        settings: &RunSettings,
        engine: &Engine,
        check: &ReferenceCheck,
        start: [f64; STATE_LEN],
    ) -> Result<ReferenceRun, Error> {
        if let Some((i, v)) = start.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(Error::invalid(
                format!("yu2021.reference.start[{i}]"),
                "finite",
                *v,
            ));
        }
        let f = check.refine_factor;
        if !(f > 1.0 && f.is_finite()) {
            return Err(Error::invalid(
                "yu2021.reference.refine_factor",
                "> 1 and finite",
                f,
            ));
        }
        if check.refine_periods == 0 {
            return Err(Error::invalid(
                "yu2021.reference.refine_periods",
                ">= 1",
                0.0,
            ));
        }
        let response = self.simulate_with(settings, engine, Some(start))?;
        let (refined_settings, refined_engine) = match *engine {
            Engine::Timestep {
                method,
                rtol,
                atol,
                events,
            } => (
                *settings,
                Engine::Timestep {
                    method,
                    rtol: rtol / f,
                    atol: atol / f,
                    events,
                },
            ),
            // RK4's global error is O(h⁴): f× tighter needs f^{1/4}× the steps; the recorded
            // samples then differ, the metrics are compared, not the samples
            _ => (
                RunSettings {
                    steps_per_period: (response.steps_per_period as f64 * f.dpowf(0.25)).ceil()
                        as usize,
                    ..*settings
                },
                Engine::Rk4Fixed,
            ),
        };
        let repeat = RunSettings {
            transient_periods: 0,
            record_periods: check.refine_periods,
            ..refined_settings
        };
        let refined_response =
            self.simulate_with(&repeat, &refined_engine, Some(response.final_state))?;
        let metrics = Metrics::of(&response, check.rms_harmonics);
        let refined = Metrics::of(&refined_response, check.rms_harmonics);
        let max_change = metrics.max_change(&refined);
        let motion = classify_record(
            &[&response.dte, &response.backlash],
            response.steps_per_period,
            check.periodicity_tol,
            metrics.scale(),
        );
        Ok(ReferenceRun {
            response,
            motion,
            metrics,
            refined,
            max_change,
            reproducible: max_change <= check.metric_rel_tol,
        })
    }
}

impl Yu2021Model {
    /// The static-contact state at `τ = 0` with the gear centres at their static deflection:
    /// bearing forces balancing the static mesh force `T*` along the line of action
    /// (`κ_ij x_ij = ∓μ_i T* (sin α, cos α)`), the pressure angle and backlash of those centres,
    /// and `δ* = B + T*/(1 + ε sin φ_0)` (contact at the mesh stiffness of `τ = 0`), at rest.
    /// Starting there instead of at [`Yu2021Model::initial_state`] (centres at the origin,
    /// ≈ 5 `b_n` from their static position on the Fig. 10 rig) removes the slowly decaying
    /// bearing transient (damping ratio 0.02) that a fixed number of transient periods leaves
    /// at high `ω*`. Torsional models and locked centres: [`Yu2021Model::initial_state`].
    /// A few fixed-point passes (α depends on the centres); a non-finite result falls back to
    /// [`Yu2021Model::initial_state`].
    pub fn static_state(&self, omega: f64) -> [f64; STATE_LEN] {
        let base = self.initial_state();
        if self.options.kind != ModelKind::Yu || self.options.lock_centres {
            return base;
        }
        let p = &self.params;
        let mut s = base;
        let mut alpha = p.alpha0;
        let k0 = 1.0 + p.epsilon * p.phase.dsin();
        for _ in 0..6 {
            let (sa, ca) = alpha.dsin_cos();
            let dirs = [sa, ca, -sa, -ca];
            for i in 0..4 {
                let mu = p.mass_ratio[i / 2];
                s[1 + i] = -mu * p.load * dirs[i] / p.kappa[i];
            }
            let g = self.geometry(omega, 0.0, &s);
            alpha = g.alpha;
            let delta = g.backlash + p.load / k0;
            s[0] = if self.options.form == EquationForm::Consistent {
                let (sa, ca) = alpha.dsin_cos();
                let (dx, dy) = (s[1] - s[3], s[2] - s[4]);
                delta - dx * sa - dy * ca + p.ste * p.phase.dcos()
            } else {
                delta
            };
        }
        if s.iter().all(|v| v.is_finite()) {
            s
        } else {
            base
        }
    }
}

impl Response {
    /// The DTE rate `dδ*/dτ` at the recorded samples by second-order central differences
    /// (one-sided at the ends), for phase portraits: the DTE is continuously differentiable
    /// (only its second derivative jumps at contact switches), so the error is `O(h²)` with
    /// `h` the sample spacing. Empty for fewer than 2 samples.
    pub fn dte_rate(&self) -> Vec<f64> {
        let (x, t) = (&self.dte, &self.tau);
        let n = x.len().min(t.len());
        if n < 2 {
            return Vec::new();
        }
        (0..n)
            .map(|i| {
                let (a, b) = if i == 0 {
                    (0, 1)
                } else if i == n - 1 {
                    (n - 2, n - 1)
                } else {
                    (i - 1, i + 1)
                };
                (x[b] - x[a]) / (t[b] - t[a])
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::yu2021::{Options, Yu2021Params};

    fn short(omega: f64) -> RunSettings {
        RunSettings {
            omega,
            transient_periods: 60,
            record_periods: 8,
            steps_per_period: 64,
        }
    }

    #[test]
    fn loaded_torsional_point_is_period_one_and_reproducible() {
        // Kahraman–Singh on Table 2 at ω* = 0.3: loaded, no impact, periodic
        let m = Yu2021Model::new(&Yu2021Params::table2(), Options::kahraman_singh()).unwrap();
        let r = m
            .reference_run(&short(0.3), &Engine::timestep(), &ReferenceCheck::default())
            .unwrap();
        assert_eq!(r.motion, Motion::Periodic(1));
        assert!(r.reproducible, "{}", r.max_change);
        assert!(r.flag(true).is_none());
        assert_eq!(r.metrics, Metrics::of(&r.response, 4));
    }

    #[test]
    fn undecayed_transient_is_flagged() {
        // too short a transient for the lightly damped bearings: the next window differs
        let m = Yu2021Model::new(&Yu2021Params::table2(), Options::default()).unwrap();
        let s = RunSettings {
            transient_periods: 1,
            ..short(1.2)
        };
        let r = m
            .reference_run(&s, &Engine::timestep(), &ReferenceCheck::default())
            .unwrap();
        assert!(r.flag(true).is_some());
        assert_eq!(r.motion, Motion::NonPeriodic);
    }

    #[test]
    fn static_state_is_an_equilibrium_of_the_unforced_pair() {
        // no stiffness variation, no STE: the static state must be a rest point of the rhs
        let mut p = Yu2021Params::table2();
        p.stiffness_ratio = 0.0;
        p.ste_amplitude = 0.0;
        let m = Yu2021Model::new(&p, Options::default()).unwrap();
        let s = m.static_state(0.5);
        let d = m.rhs(0.5, 0.0, &s, None);
        for (i, v) in d.iter().enumerate() {
            assert!(v.abs() < 1e-9, "{i}: {v}");
        }
        assert!(s[1].abs() > 1.0, "the centres are deflected: {}", s[1]);
        let t = Yu2021Model::new(&p, Options::kahraman_singh()).unwrap();
        assert_eq!(
            t.static_state(0.5).map(f64::to_bits),
            t.initial_state().map(f64::to_bits)
        );
    }

    #[test]
    fn invalid_check_settings_are_errors() {
        let m = Yu2021Model::new(&Yu2021Params::table2(), Options::kahraman_singh()).unwrap();
        let bad = ReferenceCheck {
            refine_factor: 1.0,
            ..ReferenceCheck::default()
        };
        let e = m
            .reference_run(&short(0.3), &Engine::timestep(), &bad)
            .unwrap_err();
        assert!(e.to_string().contains("refine_factor"), "{e}");
        let bad = ReferenceCheck {
            refine_periods: 0,
            ..ReferenceCheck::default()
        };
        assert!(
            m.reference_run(&short(0.3), &Engine::timestep(), &bad)
                .is_err()
        );
    }

    #[test]
    fn reference_run_from_the_static_state_is_reference_run() {
        let m = Yu2021Model::new(&Yu2021Params::table2(), Options::default()).unwrap();
        let check = ReferenceCheck::default();
        let a = m
            .reference_run(&short(0.3), &Engine::timestep(), &check)
            .unwrap();
        let b = m
            .reference_run_from(
                &short(0.3),
                &Engine::timestep(),
                &check,
                m.static_state(0.3),
            )
            .unwrap();
        assert_eq!(a, b);
    }

    #[test]
    fn reference_run_from_refuses_a_non_finite_start() {
        let m = Yu2021Model::new(&Yu2021Params::table2(), Options::kahraman_singh()).unwrap();
        let mut s = m.initial_state();
        s[3] = f64::NAN;
        let e = m
            .reference_run_from(
                &short(0.3),
                &Engine::timestep(),
                &ReferenceCheck::default(),
                s,
            )
            .unwrap_err();
        assert!(e.to_string().contains("start[3]"), "{e}");
    }

    #[test]
    fn rk4_reference_refines_the_step() {
        let m = Yu2021Model::new(&Yu2021Params::table2(), Options::kahraman_singh()).unwrap();
        let r = m
            .reference_run(&short(0.3), &Engine::Rk4Fixed, &ReferenceCheck::default())
            .unwrap();
        assert!(r.reproducible, "{}", r.max_change);
    }

    #[test]
    fn dte_rate_of_a_sine_is_its_cosine() {
        let n = 400;
        let tau: Vec<f64> = (0..n).map(|i| i as f64 * 0.01).collect();
        let r = Response {
            omega: 1.0,
            steps_per_period: 628,
            load: 1.0,
            dte: tau.iter().map(|t| t.dsin()).collect(),
            force: vec![0.0; n],
            backlash: vec![0.0; n],
            alpha: vec![0.0; n],
            tau: tau.clone(),
            final_state: [0.0; crate::yu2021::STATE_LEN],
            stats: timestep::Stats::default(),
        };
        let v = r.dte_rate();
        for i in 1..n - 1 {
            assert!((v[i] - tau[i].dcos()).abs() < 2e-5, "{i}");
        }
        assert!((v[0] - 1.0).abs() < 1e-2);
    }
}
