//! The Yu 2021 models on the `timestep` engine: the model's one system description
//! ([`Yu2021SixDof`], five coordinates, with the dead-zone switching surfaces `δ* = ±B` as
//! events) integrated through `timestep::Mechanical`, and [`Yu2021Model::simulate_with`] runs a steady-state response on the engine chosen by
//! [`Engine`], returning the same [`Response`] as the fixed-step RK4 of
//! [`Yu2021Model::simulate`].

use serde::{Deserialize, Serialize};

use crate::Error;

use super::hbm::Yu2021SixDof;
use super::model::{BacklashUpdate, Response, RunSettings, STATE_LEN, Yu2021Model};

/// Which engine integrates a [`RunSettings`] run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[non_exhaustive]
pub enum Engine {
    /// The model's own fixed-step RK4 ([`Yu2021Model::simulate`]): `RunSettings::steps_per_period`
    /// steps per mesh period (raised so that `Δτ ≤ 0.2/ω_max`), no event location, both
    /// backlash updates of Fig. 8 (the only engine for [`BacklashUpdate::PreviousStep`]).
    #[default]
    Rk4Fixed,
    /// The `timestep` crate ([`timestep::integrate`]) with the dead-zone edges `δ* = ±B` located
    /// as events (so no step straddles a contact switch). Only the state-dependent backlash
    /// ([`BacklashUpdate::InRhs`]); Fig. 8's previous-step update is a fixed-step algorithm.
    /// The response is sampled from the engine's dense output at the same instants as the RK4
    /// path (`steps_per_period` per period, raised as for RK4). The engine of the validation
    /// studies.
    Timestep {
        /// Integration method (e.g. [`timestep::Method::DormandPrince54`]).
        method: timestep::Method,
        /// Relative tolerance of the adaptive methods.
        rtol: f64,
        /// Absolute tolerance of the adaptive methods (units of `b_n`).
        atol: f64,
        /// Locate the switching surfaces `δ* = ±B` as events.
        events: bool,
    },
}

impl Engine {
    /// The `timestep` engine with Dormand–Prince 5(4), `rtol = 1e-8`, `atol = 1e-10`, events on.
    pub fn timestep() -> Self {
        Engine::Timestep {
            method: timestep::Method::DormandPrince54,
            rtol: 1e-8,
            atol: 1e-10,
            events: true,
        }
    }
}

/// The [`Yu2021Model::rhs`] state from an engine state of the same layout.
fn full_state(y: &[f64]) -> [f64; STATE_LEN] {
    let mut s = [0.0; STATE_LEN];
    for (a, b) in s.iter_mut().zip(y) {
        *a = *b;
    }
    s
}

fn engine_error(e: timestep::Error) -> Error {
    Error::timestep("yu2021 timestep engine: ")(e)
}

impl Yu2021Model {
    /// A steady-state response on the chosen [`Engine`] (same [`Response`] for both).
    ///
    /// Errors as [`Yu2021Model::simulate`]; with [`Engine::Timestep`] also for
    /// [`BacklashUpdate::PreviousStep`], invalid tolerances, and an integration that does
    /// not complete (step-size underflow, step limit, non-finite state: [`Error::Solver`]).
    pub fn simulate_with(
        &self,
        settings: &RunSettings,
        engine: &Engine,
        initial: Option<[f64; STATE_LEN]>,
    ) -> Result<Response, Error> {
        let Engine::Timestep {
            method,
            rtol,
            atol,
            events,
        } = *engine
        else {
            return self.simulate(settings, initial);
        };
        let w = settings.omega;
        let n = self.samples_per_period(settings)?;
        if self.options.update == BacklashUpdate::PreviousStep {
            return Err(Error::Solver(
                "yu2021: Fig. 8's previous-step backlash update needs Engine::Rk4Fixed".into(),
            ));
        }
        let period = std::f64::consts::TAU / w;
        let opts = timestep::Options::default()
            .with_method(method)
            .with_tol(rtol, atol)
            .with_events(events)
            .with_h_max(period / 4.0)
            .with_output(timestep::Output::Final);
        // the model's one system description, made explicit for the engine: the state is
        // `[q, x_p, y_p, x_g, y_g, q', …]` as in `Yu2021Model::rhs`
        let sys = timestep::FirstOrder(
            timestep::Mechanical::new(Yu2021SixDof::for_time_stepping(self, w))
                .map_err(engine_error)?,
        );
        let y0 = initial.unwrap_or_else(|| self.initial_state());
        let h = period / n as f64;
        // the RK4 grid: sample k at τ = k h, k = transient·n … (transient + record)·n − 1
        let start = settings.transient_periods * n;
        let t_rec = start as f64 * h;
        let check = |s: &timestep::Solution| crate::error::completed(s, "yu2021");
        let tr = timestep::integrate(&sys, 0.0, &y0, t_rec, &opts).map_err(engine_error)?;
        check(&tr)?;
        let m = settings.record_periods * n;
        let times: Vec<f64> = (start..start + m).map(|k| k as f64 * h).collect();
        let t_end = (start + m) as f64 * h;
        let rec = timestep::integrate(
            &sys,
            t_rec,
            &tr.y_final,
            t_end,
            &opts.with_output(timestep::Output::Times(times)),
        )
        .map_err(engine_error)?;
        check(&rec)?;
        let mut out = Response {
            omega: w,
            steps_per_period: n,
            load: self.params.load,
            tau: Vec::with_capacity(m),
            dte: Vec::with_capacity(m),
            force: Vec::with_capacity(m),
            backlash: Vec::with_capacity(m),
            alpha: Vec::with_capacity(m),
            final_state: full_state(&rec.y_final),
            stats: crate::error::total_stats(&[&tr, &rec]),
        };
        for i in 0..rec.len() {
            let tau = rec.t[i];
            let s = full_state(rec.state(i));
            let g = self.geometry(w, tau, &s);
            let (delta, _, force) = self.mesh(w, tau, &s, &g, g.backlash);
            out.tau.push(tau);
            out.dte.push(delta);
            out.force.push(force);
            out.backlash.push(g.backlash);
            out.alpha.push(g.alpha);
        }
        if out.final_state.iter().any(|v| !v.is_finite()) {
            return Err(Error::Solver(
                "yu2021 timestep engine: non-finite state".into(),
            ));
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::yu2021::{Options, Yu2021Params};
    use timestep::OdeSystem;

    #[test]
    fn ode_rhs_is_the_model_rhs_and_events_are_gap_edges() {
        let m = Yu2021Model::new(&Yu2021Params::table1(), Options::default()).unwrap();
        let sys = timestep::FirstOrder(
            timestep::Mechanical::new(Yu2021SixDof::for_time_stepping(&m, 0.9)).unwrap(),
        );
        let mut y = m.initial_state();
        y[1] = 0.01;
        y[6] = -0.02;
        let mut d = [0.0; STATE_LEN];
        sys.rhs(0.3, &y, &mut d);
        let want = m.rhs(0.9, 0.3, &y, None);
        for (a, b) in d.iter().zip(want) {
            assert!((a - b).abs() <= 1e-15 * (1.0 + b.abs()));
        }
        let mut g = [0.0; 2];
        sys.events(0.3, &y, &mut g);
        let geo = m.geometry(0.9, 0.3, &y);
        assert!((g[0] - g[1] + 2.0 * geo.backlash).abs() < 1e-12);
        assert_eq!(sys.n_events(), 2);
    }

    #[test]
    fn previous_step_update_is_refused_by_the_timestep_engine() {
        let o = Options {
            update: BacklashUpdate::PreviousStep,
            ..Options::default()
        };
        let m = Yu2021Model::new(&Yu2021Params::table1(), o).unwrap();
        let r = m.simulate_with(&RunSettings::new(0.9), &Engine::timestep(), None);
        assert!(matches!(r, Err(Error::Solver(_))));
    }
}
