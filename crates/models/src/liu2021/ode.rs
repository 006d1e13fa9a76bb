//! Eq. (9) as a first-order system for the `timestep` engine, written lean.

use std::cell::Cell;

use super::model::Model;

/// Eq. (9) as the first-order system `y = [q, q']`,
///
/// ```text
/// q' = v,    v' = f_r(τ) − 2ζ v − F(τ) f(q; b̄(τ)),
/// ```
///
/// with the gap edges `q = ±b̄(τ)` as events (event 0: `q − b̄`, event 1: `q + b̄`).
///
/// The same numbers as the model's one system description integrated through
/// [`timestep::Mechanical`] (`M = 1`, `C = 2ζ`, `g = F f`, the forcing `f_r`), bit for bit
/// (tested), at a fraction of the cost:
///
/// * the time-only functions `F`, `b̄`, `f_r` come from [`Model::time_functions`] (every
///   `sin`/`cos` once), and
/// * they are kept for the last `τ` asked: the Dormand–Prince step evaluates its 7th stage at
///   the same `τ` as its 6th, and the event functions at the step end again, so two of every
///   seven evaluations of an accepted step reuse them.
///
/// The cache is a [`Cell`], so a `TimeSystem` is not `Sync`: build one per thread (it is
/// cheap, a copy of the model).
#[derive(Debug, Clone)]
pub struct TimeSystem {
    model: Model,
    /// The damping `C = 2ζ` (skipped when zero, as `Mechanical` skips a zero matrix).
    damping: f64,
    /// `[τ, F(τ), b̄(τ), f_r(τ)]` of the last evaluation (`τ` = NaN: empty).
    cache: Cell<[f64; 4]>,
}

impl TimeSystem {
    /// The system of `model`.
    pub fn new(model: Model) -> Self {
        Self {
            damping: 2.0 * model.zeta,
            model,
            cache: Cell::new([f64::NAN; 4]),
        }
    }

    /// The model.
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// `[F(τ), b̄(τ), f_r(τ)]`, from the cache when `τ` is the last one asked.
    #[inline]
    fn time_functions(&self, tau: f64) -> [f64; 3] {
        let c = self.cache.get();
        if c[0].to_bits() == tau.to_bits() {
            return [c[1], c[2], c[3]];
        }
        let f = self.model.time_functions(tau);
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
        let [stiffness, backlash, forcing] = self.time_functions(t);
        let (q, v) = (y[0], y[1]);
        // the order of `Mechanical`: a = f − C v − g
        let mut a = forcing;
        if self.damping != 0.0 {
            a -= self.damping * v;
        }
        a -= stiffness * backlash::dead_zone(q, backlash);
        dydt[0] = v;
        dydt[1] = a;
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
    use super::super::params::{BaseRadius, ErrorTerm, RigidAcceleration, RigidSeries, table1};
    use super::*;
    use timestep::OdeSystem;

    /// Every reading: the lean system gives the bits of `FirstOrder(Mechanical(model))`, for
    /// the right-hand side and the events, in and out of contact, with the cache hit and missed.
    #[test]
    fn lean_system_is_bit_identical_to_the_mechanical_adapter() {
        for ra in [RigidAcceleration::Derived, RigidAcceleration::PrintedEq20] {
            for rs in [RigidSeries::TwoTerms, RigidSeries::Exact] {
                for et in [ErrorTerm::Derived, ErrorTerm::Printed] {
                    for br in [BaseRadius::TimeVarying, BaseRadius::Mean] {
                        for zeta in [0.01, 0.0] {
                            let mut p = table1();
                            p.readings.rigid_acceleration = ra;
                            p.readings.rigid_series = rs;
                            p.readings.error_term = et;
                            p.readings.base_radius = br;
                            p.damping_ratio = zeta;
                            let m = p.model().unwrap();
                            let lean = TimeSystem::new(m);
                            let mech = timestep::FirstOrder(timestep::Mechanical::new(m).unwrap());
                            let b = m.backlash;
                            for i in 0..200 {
                                let t = 37.3 * f64::from(i) - 5.0;
                                for y in [[3.0 * b, 0.01], [0.2 * b, -0.3], [-2.0 * b, 1e-4]] {
                                    for _repeat in 0..2 {
                                        let (mut a, mut c) = ([0.0; 2], [0.0; 2]);
                                        lean.rhs(t, &y, &mut a);
                                        mech.rhs(t, &y, &mut c);
                                        assert_eq!(a.map(f64::to_bits), c.map(f64::to_bits));
                                        lean.events(t, &y, &mut a);
                                        mech.events(t, &y, &mut c);
                                        assert_eq!(a.map(f64::to_bits), c.map(f64::to_bits));
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
            }
        }
    }
}
