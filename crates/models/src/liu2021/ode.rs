//! Eq. (9) as a first-order system for the `timestep` engine, written lean.

use math::DetMath;
use std::cell::Cell;

use serde::{Deserialize, Serialize};

use super::model::Model;

/// How [`TimeSystem`] evaluates the sines and cosines of its time functions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum Trig {
    /// The platform's `sin`/`cos` of every phase, as [`Model::stiffness`],
    /// [`Model::backlash_at`] and [`Model::forcing`] ([`Model::time_functions`]): the bits of
    /// the generic adapter `FirstOrder(Mechanical(model))`.
    Libm,
    /// Two short `sin_cos` (of `ω̄_c τ` and `ω̄_e τ`, Cody–Waite reduction and Taylor
    /// polynomials, within a few 10⁻¹⁶ of the platform's) and the addition theorems for
    /// `sin 2x` and the phases `φ_m`, `φ_e`: the same formulas, different at rounding level,
    /// about half the cost.
    Kernel,
    /// One period of the time functions tabulated as piecewise polynomials of degree 11 at
    /// round-off accuracy ([`super::TimeTable`]): one reduction and three polynomials per
    /// evaluation, different from the direct evaluation at rounding level. Built once per
    /// system (shared by the systems of one model, [`super::TimeTable::shared`]); where the
    /// table declines (`τ < 0`, a non-finite `τ`, `τ ≥ 2²⁰` periods) the evaluation is
    /// [`Trig::Kernel`]'s. The default.
    #[default]
    Table,
}

/// Eq. (9) as the first-order system `y = [q, q']`,
///
/// ```text
/// q' = v,    v' = f_r(τ) − 2ζ v − F(τ) f(q; b̄(τ)),
/// ```
///
/// with the gap edges `q = ±b̄(τ)` as events (event 0: `q − b̄`, event 1: `q + b̄`): the
/// model's one system description integrated through [`timestep::Mechanical`] (`M = 1`,
/// `C = 2ζ`, `g = F f`, the forcing `f_r`), written lean:
///
/// * the time-only functions `F`, `b̄`, `f_r` are computed together, every `sin`/`cos` once
///   ([`Trig::Libm`]: bit for bit the numbers of `FirstOrder(Mechanical(model))`, tested),
///   from two short `sin_cos` ([`Trig::Kernel`]: rounding-level different), or from one period
///   tabulated ([`Trig::Table`], the default: rounding-level different, the cheapest);
/// * they are kept for the last `τ` asked: the Dormand–Prince step evaluates its 7th stage at
///   the same `τ` as its 6th, and the event functions at the step end again, so two of every
///   seven evaluations of an accepted step reuse them.
///
/// The cache is a [`Cell`], so a `TimeSystem` is not `Sync`: build one per thread (it is
/// cheap: a copy of the model, and the model's shared table).
#[derive(Debug, Clone)]
pub struct TimeSystem {
    model: Model,
    trig: Trig,
    /// `[sin φ_m, cos φ_m, sin φ_e, cos φ_e]` of the phases ([`Trig::Kernel`]).
    phases: [f64; 4],
    /// `[τ, F(τ), b̄(τ), f_r(τ)]` of the last evaluation (`τ` = NaN: empty).
    cache: Cell<[f64; 4]>,
    /// The tabulated period ([`Trig::Table`]; `None` otherwise or where the model has none).
    table: Option<std::sync::Arc<super::TimeTable>>,
}

impl TimeSystem {
    /// The system of `model` with the default [`Trig::Table`].
    pub fn new(model: Model) -> Self {
        Self::with_trig(model, Trig::default())
    }

    /// The system of `model` with the given evaluation of the sines and cosines.
    pub fn with_trig(model: Model, trig: Trig) -> Self {
        let (spm, cpm) = model.phase_stiffness.dsin_cos();
        let (spe, cpe) = model.phase_error.dsin_cos();
        Self {
            model,
            trig,
            phases: [spm, cpm, spe, cpe],
            cache: Cell::new([f64::NAN; 4]),
            table: match trig {
                Trig::Table => super::TimeTable::shared(&model),
                _ => None,
            },
        }
    }

    /// The model.
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// The evaluation of the sines and cosines.
    pub fn trig(&self) -> Trig {
        self.trig
    }

    /// `[F(τ), b̄(τ), f_r(τ)]`, from the cache when `τ` is the last one asked.
    #[inline]
    fn time_functions(&self, tau: f64) -> [f64; 3] {
        let c = self.cache.get();
        if c[0].to_bits() == tau.to_bits() {
            return [c[1], c[2], c[3]];
        }
        let f = match self.trig {
            Trig::Libm => self.model.time_functions(tau),
            Trig::Table => match self.table.as_ref().and_then(|t| t.eval(tau)) {
                Some(f) => f,
                None => self.model.time_functions_kernel(tau, &self.phases),
            },
            Trig::Kernel => self.model.time_functions_kernel(tau, &self.phases),
        };
        self.cache.set([tau, f[0], f[1], f[2]]);
        f
    }
}

impl timestep::OdeSystem for TimeSystem {
    fn dim(&self) -> usize {
        2
    }

    #[inline]
    fn rhs(&self, t: f64, y: &[f64], dydt: &mut [f64]) {
        let (q, v) = (y[0], y[1]);
        dydt[0] = v;
        dydt[1] = self.model.acceleration_of(self.time_functions(t), q, v);
    }

    fn n_events(&self) -> usize {
        2
    }

    #[inline]
    fn events(&self, t: f64, y: &[f64], g: &mut [f64]) {
        let [_, backlash, _] = self.time_functions(t);
        system::gap_edges(y[0], backlash, g);
    }
}

#[cfg(test)]
mod tests {
    use super::super::params::{BaseRadius, Readings, RigidSeries, table1};
    use super::*;
    use timestep::OdeSystem;

    /// Every reading: the lean system gives the values of `FirstOrder(Mechanical(model))`, for
    /// the right-hand side and the events, in and out of contact, with the cache hit and missed:
    /// to rounding, since the adapter reads the model's time functions from three short
    /// `sin_cos` (`Model::time_functions_short`) and `Trig::Libm` from `geardyn-math`
    /// (bound: `10⁻¹³` of the terms' scale, far below any physical difference, far above the
    /// ~`10⁻¹⁵` of the two evaluations, see `kernel_time_functions_are_the_direct_ones_to_rounding`).
    #[test]
    fn lean_system_is_the_mechanical_adapter_to_rounding() {
        for readings in Readings::all() {
            for zeta in [0.01, 0.0] {
                let mut p = table1();
                p.readings = readings;
                p.damping_ratio = zeta;
                let m = p.model().unwrap();
                let lean = TimeSystem::with_trig(m, Trig::Libm);
                let mech = timestep::FirstOrder(timestep::Mechanical::new(m).unwrap());
                let b = m.backlash;
                let scale = 1.0 + 3.0 * b + m.b0 + m.b1.abs() + m.b2.abs() + m.b3.abs();
                for i in 0..200 {
                    let t = 37.3 * f64::from(i) - 5.0;
                    for y in [[3.0 * b, 0.01], [0.2 * b, -0.3], [-2.0 * b, 1e-4]] {
                        for _repeat in 0..2 {
                            let (mut a, mut c) = ([0.0; 2], [0.0; 2]);
                            lean.rhs(t, &y, &mut a);
                            mech.rhs(t, &y, &mut c);
                            assert_eq!(a[0].to_bits(), c[0].to_bits());
                            assert!((a[1] - c[1]).abs() <= 1e-13 * scale, "{t}: {a:?} {c:?}");
                            lean.events(t, &y, &mut a);
                            mech.events(t, &y, &mut c);
                            for k in 0..2 {
                                assert!((a[k] - c[k]).abs() <= 1e-13 * b, "{t}: {a:?} {c:?}");
                            }
                        }
                    }
                }
                assert_eq!(lean.n_events(), mech.n_events());
                assert_eq!(lean.dim(), mech.dim());
                for k in 0..2 {
                    assert_eq!(lean.event_direction(k), mech.event_direction(k));
                }
            }
        }
    }

    /// The default system reads the table ([`Trig::Table`]): its right-hand side and events
    /// are those of [`Trig::Libm`] to rounding (the table's own bound: `2·10⁻¹⁵` of the scale
    /// plus the phase rounding `4ε ω̄_e τ`), and below `τ = 0`, where the table declines, they
    /// are [`Trig::Kernel`]'s bit for bit.
    #[test]
    fn the_default_system_reads_the_table() {
        let m = table1().model().unwrap();
        let table = TimeSystem::new(m);
        assert_eq!(table.trig(), Trig::Table);
        let libm = TimeSystem::with_trig(m, Trig::Libm);
        let kernel = TimeSystem::with_trig(m, Trig::Kernel);
        let scale = 1.0 + 3.0 * m.backlash + m.b0 + m.b1.abs() + m.b2.abs() + m.b3.abs();
        let y = [0.5 * m.backlash, 0.01];
        for i in 0..500 {
            let t = 91.7 * f64::from(i);
            let bound = (2e-15 + 4.0 * f64::EPSILON * m.omega_e * t) * scale;
            let (mut a, mut b) = ([0.0; 2], [0.0; 2]);
            table.rhs(t, &y, &mut a);
            libm.rhs(t, &y, &mut b);
            assert!((a[1] - b[1]).abs() <= bound, "{t}: {a:?} {b:?}");
            table.events(t, &y, &mut a);
            libm.events(t, &y, &mut b);
            assert!((a[0] - b[0]).abs() <= bound * m.backlash, "{t}");
        }
        for t in [-1e-3, -10.0, -1e4] {
            let (mut a, mut b) = ([0.0; 2], [0.0; 2]);
            table.rhs(t, &y, &mut a);
            kernel.rhs(t, &y, &mut b);
            assert_eq!(a[1].to_bits(), b[1].to_bits());
        }
    }

    /// The kernel evaluations (`Trig::Kernel`'s addition theorems and the three `sin_cos` of
    /// the model as a `SecondOrderSystem`) differ from the direct one at rounding level only: every time
    /// function within `2·10⁻¹⁵ + 4ε·ω̄_e τ` of its scale (`F ≈ 1`, `b̄`, and `f_r` against the
    /// sum of the amplitudes `B₀ + |B₁| + |B₂| + |B₃|`). The second term is the rounding of the
    /// phase argument itself (`ω̄_e τ + φ` and `ω̄_e τ` are rounded to their own last place),
    /// which no evaluation avoids; `τ` runs to 2.7·10⁷ (past the kernel's range, fallback).
    #[test]
    fn kernel_time_functions_are_the_direct_ones_to_rounding() {
        for br in [BaseRadius::TimeVarying, BaseRadius::Mean] {
            for rs in [RigidSeries::TwoTerms, RigidSeries::Exact] {
                let mut p = table1();
                p.readings.base_radius = br;
                p.readings.rigid_series = rs;
                p.phase_error = 0.4;
                let m = p.model().unwrap();
                let sys = TimeSystem::new(m);
                let scale = [1.0, m.backlash, m.b0 + m.b1.abs() + m.b2.abs() + m.b3];
                let mut worst = [0.0f64; 3];
                for i in 0..20_000 {
                    let tau = 1.37 * f64::from(i) * f64::from(i) / 20.0;
                    let a = m.time_functions(tau);
                    let b = m.time_functions_kernel(tau, &sys.phases);
                    let c = m.time_functions_short(tau);
                    let bound = 2e-15 + 4.0 * f64::EPSILON * m.omega_e * tau;
                    for k in 0..3 {
                        worst[k] = worst[k].max((a[k] - b[k]).abs() / scale[k] / bound);
                        worst[k] = worst[k].max((a[k] - c[k]).abs() / scale[k] / bound);
                    }
                }
                assert!(worst.iter().all(|&w| w <= 1.0), "{br:?} {rs:?}: {worst:?}");
            }
        }
    }

    /// The peer-comparison run (`peer_bench liu`: 160 rad/s, mean base radius, three periods,
    /// DP5(4) rtol 1e-8 with the gap events, `Trig::Kernel`) ends on the bits recorded at
    /// round 22 (steps, events, work counters and final state; the controller's arithmetic
    /// moved them: round 14 without `pow`, round 15 its shorter polynomials and the retry of a
    /// rejected step at an estimated crossing, `timestep::Options::crossing_retry`, round 21
    /// its division-free chain, a table-driven `log₂` of the squared error norm and the step
    /// ratio from one `2^x`, `timestep::control`, round 22 the retry's crossing located on the
    /// rejected step's dense output; the numba peer computes the same and ends on the same
    /// bits): a speed-up of the driver, the stepper or this system must move no
    /// floating-point operation of this run. The kernel trig is the crate's own polynomial and
    /// everything else is `geardyn-math`, so the bits do not depend on the platform's libm.
    #[test]
    fn peer_run_ends_on_the_recorded_bits() {
        use super::super::params::BaseRadius;
        let mut p = table1();
        p.omega1 = 160.0;
        p.readings.base_radius = BaseRadius::Mean;
        let m = p.model().unwrap();
        let y0 = [m.static_position(0.0), 0.0];
        let opts = timestep::Options::default()
            .with_tol(1e-8, 1e-8 * 1e-3 * m.backlash.max(m.b0))
            .with_h_max(0.5)
            .with_events(true)
            .with_output(timestep::Output::Final);
        let sys = TimeSystem::with_trig(m, Trig::Kernel);
        let s = timestep::integrate(&sys, 0.0, &y0, 3.0 * m.period(), &opts).unwrap();
        assert_eq!(
            (s.stats.n_accepted, s.stats.n_rejected, s.stats.n_events),
            (40163, 1714, 138)
        );
        assert_eq!((s.stats.n_rhs, s.stats.n_event_iterations), (252_297, 2641));
        let expect = [-0.0006296649513583953, -9.766886649416716e-7];
        assert_eq!(
            s.y_final.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
            expect.map(f64::to_bits)
        );
    }
}
