//! Time integration of Eq. (9) through the `timestep` engine, and the steady-period metrics.

use serde::{Deserialize, Serialize};

use super::model::{Model, Rattle, RattleState};
use super::ode::TimeSystem;
use crate::Error;

/// Settings of the time integration.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct IntegrationOptions {
    /// Periods `T = 2π/ω̄_c` integrated and discarded as transient (`ζ = 0.01` decays by
    /// `e^{-ζT} ≈ e^{-17}` per period at Table 1 values).
    pub transient_periods: f64,
    /// Periods recorded after the transient (the steady response).
    pub record_periods: f64,
    /// Output sampling interval `Δτ` of the recorded window.
    pub sample_step: f64,
    /// Largest step of the integrator (bounds grazing contact excursions).
    pub max_step: f64,
    /// Relative tolerance of the adaptive method.
    pub rtol: f64,
    /// Start state `(q, q')`; `None`: the quasi-static contact position at rest.
    pub initial: Option<(f64, f64)>,
    /// The Runge–Kutta pair (default [`Stepping::Auto`]: the one that wins at `rtol`).
    #[serde(default)]
    pub method: Stepping,
    /// Relative tolerance of the discarded transient (`None`, the default: `rtol`). A damped
    /// transient reaches the same attractor at a looser tolerance in a fraction of the steps
    /// (DP5: `(rtol_t/rtol)^(1/5)`); the recorded window keeps `rtol` and its pair.
    #[serde(default)]
    pub transient_rtol: Option<f64>,
}

/// The Runge–Kutta pair that integrates Eq. (9).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Stepping {
    /// The pair that costs least at the tolerance asked for: Dormand–Prince 5(4) above
    /// [`AUTO_DOP853_RTOL`], DOP853 at or below it. The switch is where DOP853's work–precision
    /// curve on Eq. (9) crosses DP5's at the same `rtol` (`docs/performance/work-precision.md`,
    /// Liu 160 and 180 rad/s: DOP853 0.87× and 0.58× DP5's speed at 1e-6, 1.85× and 0.84× at
    /// 1e-8, 3.0× and 1.6× at 1e-10): the nominal runs (1e-8) stay on DP5, the 100×-tighter
    /// confirmations (1e-10) run on DOP853. The windows of a long-window run take DOP853 at
    /// 1e-8 too where the transient stayed on one flank ([`Stepping::long_window_method`]:
    /// there DOP853 is the cheaper pair, 1.85× at 160 rad/s).
    #[default]
    Auto,
    /// `timestep::Method::DormandPrince54` at every tolerance.
    DormandPrince54,
    /// `timestep::Method::Dop853` at every tolerance.
    Dop853,
}

/// The tolerance at and below which [`Stepping::Auto`] takes DOP853.
pub const AUTO_DOP853_RTOL: f64 = 1e-9;

/// The tolerance at and below which [`Stepping::Auto`] also takes DOP853 for the windows of a
/// long-window run whose transient crossed no back-flank edge ([`Stepping::long_window_method`]).
/// On one flank or none the response is smooth between few contact events and DOP853 is the
/// cheaper pair from 1e-7 down (`docs/performance/work-precision.md`, Liu 160 rad/s,
/// unilateral: DP5/DOP853 CPU 1.18 at 1e-7, 1.85 at 1e-8); in bilateral rattle DP5 stays
/// cheaper down to 1e-9 (180 rad/s: 0.76, 0.84), since DOP853 restarts at twice as many
/// events with twelve evaluations a step.
pub const AUTO_DOP853_ONE_FLANK_RTOL: f64 = 1e-8;

impl Stepping {
    /// The `timestep` method for `rtol`.
    pub fn method(self, rtol: f64) -> timestep::Method {
        match self {
            Stepping::Auto if rtol <= AUTO_DOP853_RTOL => timestep::Method::Dop853,
            Stepping::Auto | Stepping::DormandPrince54 => timestep::Method::DormandPrince54,
            Stepping::Dop853 => timestep::Method::Dop853,
        }
    }

    /// The `timestep` method for the windows of a long-window run at `rtol` whose transient
    /// crossed a back-flank edge (`back_flank`) or not: [`Stepping::Auto`] takes DOP853 at
    /// `rtol ≤` [`AUTO_DOP853_RTOL`], and without a back-flank crossing also at
    /// `rtol ≤` [`AUTO_DOP853_ONE_FLANK_RTOL`]; the fixed pairs are kept.
    pub fn long_window_method(self, rtol: f64, back_flank: bool) -> timestep::Method {
        match self {
            Stepping::Auto if !back_flank && rtol <= AUTO_DOP853_ONE_FLANK_RTOL => {
                timestep::Method::Dop853
            }
            _ => self.method(rtol),
        }
    }
}

impl Default for IntegrationOptions {
    fn default() -> Self {
        Self {
            transient_periods: 2.0,
            record_periods: 1.0,
            sample_step: 0.1,
            max_step: 0.5,
            rtol: 1e-8,
            initial: None,
            method: Stepping::Auto,
            transient_rtol: None,
        }
    }
}

/// The recorded window of a time integration.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TimeResponse {
    /// Dimensionless times of the samples.
    pub tau: Vec<f64>,
    /// Displacement `q`.
    pub q: Vec<f64>,
    /// Velocity `dq/dτ`.
    pub v: Vec<f64>,
    /// Rattle state (from the samples and the located gap-edge crossings) and ppv.
    pub rattle: Rattle,
    /// Gap-edge crossings located in the recorded window (`q = ±b̄`).
    pub contact_events: usize,
    /// Right-hand-side evaluations of the whole run.
    pub rhs_evaluations: u64,
    /// Work counters of the whole run (transient and recorded window): accepted and rejected
    /// steps, right-hand-side evaluations, located events (in the whole run, where
    /// `contact_events` counts the recorded window only). Zero when read from data written
    /// before the field existed.
    #[serde(default)]
    pub stats: timestep::Stats,
}

fn positive(name: &'static str, v: f64) -> Result<(), Error> {
    if v > 0.0 && v.is_finite() {
        Ok(())
    } else {
        Err(Error::invalid(
            format!("liu2021.integration.{name}"),
            "> 0",
            v,
        ))
    }
}

/// The first-order system of Eq. (9) (`y = [q, q']`, [`TimeSystem`]) and the integrator
/// settings of [`integrate`] (Dormand–Prince 5(4), `rtol`, `atol = 10⁻³·rtol·max(b̄, B₀)`,
/// steps ≤ `max_step`, events at `q = ±b̄(τ)`).
pub(super) fn system(
    model: &Model,
    options: &IntegrationOptions,
) -> Result<(TimeSystem, timestep::Options), Error> {
    positive("max_step", options.max_step)?;
    positive("rtol", options.rtol)?;
    let opts = timestep::Options::default()
        .with_tol(
            options.rtol,
            options.rtol * 1e-3 * model.backlash.max(model.b0),
        )
        .with_h_max(options.max_step)
        .with_method(options.method.method(options.rtol));
    Ok((TimeSystem::new(*model), opts))
}

/// One point of a bifurcation diagram of Eq. (9): the stroboscopic section (period
/// `T = 2π/ω̄_c`, [`Model::period`]) of coordinate `bifurcation.coordinate` (0: `q`, 1: `q'`)
/// after `bifurcation.classify.transient_periods`, with its motion type and Lyapunov exponent
/// ([`timestep::bifurcation_point`]); integrator settings `rtol` and `max_step` of `options`,
/// start `options.initial` (default: the quasi-static contact position at rest). The other
/// fields of `options` (transient, recorded window) are not used. The state scale of the
/// tolerances is the gap half-width `b̄` (`q` is of its order).
pub fn bifurcation_point(
    model: &Model,
    options: &IntegrationOptions,
    bifurcation: &timestep::BifurcationOptions,
) -> Result<timestep::BifurcationPoint, Error> {
    let (sys, opts) = system(model, options)?;
    let (q0, v0) = options.initial.unwrap_or((model.static_position(0.0), 0.0));
    let mut bo = *bifurcation;
    bo.classify.scale = model.backlash.abs().max(f64::MIN_POSITIVE);
    timestep::bifurcation_point(&sys, model.period(), &[q0, v0], &bo, &opts).map_err(Error::from)
}

pub(super) fn run(
    model: &Model,
    t0: f64,
    y0: &[f64],
    t1: f64,
    opts: timestep::Options,
) -> Result<timestep::Solution, Error> {
    run_to(model, t0, y0, t1, opts, None)
}

/// Where [`run_to`] hands its samples (`None`: they are stored).
pub(super) type Sink<'a> = Option<&'a mut dyn FnMut(f64, &[f64])>;

/// [`run`], with the samples handed to `sink(t, [q, q'])` instead of stored
/// (`timestep::integrate_streamed`).
pub(super) fn run_to(
    model: &Model,
    t0: f64,
    y0: &[f64],
    t1: f64,
    opts: timestep::Options,
    sink: Sink<'_>,
) -> Result<timestep::Solution, Error> {
    // the model's system description made explicit, lean (`TimeSystem`; with `Trig::Libm` bit
    // for bit as `FirstOrder(Mechanical(model))`)
    let sys = TimeSystem::new(*model);
    let sol = match sink {
        Some(sink) => timestep::integrate_streamed(&sys, t0, y0, t1, &opts, sink),
        None => timestep::integrate(&sys, t0, y0, t1, &opts),
    }
    .map_err(Error::from)?;
    if !sol.status.is_success() {
        return Err(Error::Solver(format!(
            "liu2021 integration ended with {:?}",
            sol.status
        )));
    }
    Ok(sol)
}

/// Integrate Eq. (9) with the `timestep` engine (adaptive Dormand–Prince 5(4), steps restarted
/// at every gap-edge crossing `q = ±b̄(τ)`), discard `transient_periods` and return the
/// recorded window with its rattle state and ppv.
pub fn integrate(model: &Model, options: &IntegrationOptions) -> Result<TimeResponse, Error> {
    integrate_after(model, options, None).map(|(response, _)| response)
}

/// The discarded transient of one [`integrate`] run: the run from the start over
/// `transient_periods` (its final state and work counters), with the inputs it depends on.
/// Two runs whose model, start, transient length, tolerances, step bound and pair agree bit
/// for bit integrate the same transient step for step; [`integrate_after`] records after a
/// kept transient instead of integrating it again when they do, and integrates it afresh
/// when they do not.
#[derive(Debug, Clone)]
pub(super) struct Transient {
    /// The `Debug` text of the model (its period follows from its fields) and the bits of the other
    /// inputs of the transient run.
    key: (String, [u64; 5], timestep::Method),
    run: timestep::Solution,
}

impl Transient {
    fn key(model: &Model, options: &IntegrationOptions) -> (String, [u64; 5], timestep::Method) {
        let (q0, v0) = options.initial.unwrap_or((model.static_position(0.0), 0.0));
        let rtol = options.transient_rtol.unwrap_or(options.rtol);
        (
            format!("{model:?}"),
            [
                q0.to_bits(),
                v0.to_bits(),
                options.transient_periods.to_bits(),
                rtol.to_bits(),
                options.max_step.to_bits(),
            ],
            options.method.method(rtol),
        )
    }
}

/// [`integrate`], recording after `kept` where it is the transient of these inputs
/// ([`Transient`]); returns the response and its own transient, for a later run to share.
/// Bit for bit [`integrate`]'s response either way, work counters included (they count the
/// transient the response stands on, also when it was integrated once for two runs).
pub(super) fn integrate_after(
    model: &Model,
    options: &IntegrationOptions,
    kept: Option<Transient>,
) -> Result<(TimeResponse, Transient), Error> {
    positive("record_periods", options.record_periods)?;
    positive("sample_step", options.sample_step)?;
    if !(options.transient_periods >= 0.0 && options.transient_periods.is_finite()) {
        return Err(Error::invalid(
            "liu2021.integration.transient_periods",
            ">= 0",
            options.transient_periods,
        ));
    }
    let period = model.period();
    let (_, base) = system(model, options)?;
    let (q0, v0) = options.initial.unwrap_or((model.static_position(0.0), 0.0));
    let t_rec = options.transient_periods * period;
    let key = Transient::key(model, options);
    let warm = match kept {
        Some(t) if t.key == key => t,
        _ => {
            let warm_opts = match options.transient_rtol {
                Some(rtol) => {
                    positive("transient_rtol", rtol)?;
                    system(model, &IntegrationOptions { rtol, ..*options })?.1
                }
                None => base.clone(),
            };
            let run = run(
                model,
                0.0,
                &[q0, v0],
                t_rec,
                warm_opts.with_output(timestep::Output::Final),
            )?;
            Transient { key, run }
        }
    };
    let t_end = t_rec + options.record_periods * period;
    let rec = run(
        model,
        t_rec,
        &warm.run.y_final,
        t_end,
        base.with_output(timestep::Output::Uniform {
            dt: options.sample_step,
        }),
    )?;
    let q = rec.component(0);
    let v = rec.component(1);
    let mut rattle = model.rattle(rec.t.iter().copied().zip(q.iter().copied()));
    // crossings between samples: event 0 is q = +b̄ (back flank), event 1 is q = −b̄
    for e in &rec.events {
        let s = if e.index == 0 {
            RattleState::Bilateral
        } else {
            RattleState::Unilateral
        };
        rattle.state = rattle.state.max(s);
    }
    let stats = crate::error::total_stats(&[&warm.run, &rec]);
    let rhs_evaluations = warm.run.stats.n_rhs + rec.stats.n_rhs;
    Ok((
        TimeResponse {
            tau: rec.t,
            q,
            v,
            rattle,
            contact_events: rec.events.len(),
            rhs_evaluations,
            stats,
        },
        warm,
    ))
}

#[cfg(test)]
mod tests {
    use super::super::ode::Trig;
    use super::super::params::{BaseRadius, table1};
    use super::*;

    /// The pair of a long window: `Auto` takes DOP853 at `rtol ≤ 1e-9`, and at `rtol ≤ 1e-8`
    /// only without a back-flank crossing; the fixed pairs ignore the transient.
    #[test]
    fn long_window_pair_follows_tolerance_and_flank() {
        use timestep::Method::{Dop853, DormandPrince54};
        let a = Stepping::Auto;
        assert_eq!(a.long_window_method(1e-8, false), Dop853);
        assert_eq!(a.long_window_method(1e-8, true), DormandPrince54);
        assert_eq!(a.long_window_method(1e-10, true), Dop853);
        assert_eq!(a.long_window_method(1e-6, false), DormandPrince54);
        assert_eq!(a.long_window_method(2e-8, false), DormandPrince54);
        for back in [false, true] {
            assert_eq!(
                Stepping::DormandPrince54.long_window_method(1e-10, back),
                DormandPrince54
            );
            assert_eq!(Stepping::Dop853.long_window_method(1e-6, back), Dop853);
        }
    }

    /// The response carries the counters of both runs; the lean system with [`Trig::Libm`]
    /// samples on the grid of the generic adapter `FirstOrder(Mechanical(model))`, and with
    /// the default [`Trig::Table`] (what `integrate` uses) reaches the same metrics within 10⁻⁶ of
    /// ppv and the same samples within the change a 100× tighter tolerance makes (bilateral
    /// rattle at 220 rad/s and unilateral at 160 rad/s: events, restarts and dense samples all
    /// exercised).
    #[test]
    fn response_counts_the_work_and_matches_the_generic_adapter() {
        for omega1 in [220.0, 160.0] {
            let mut p = table1();
            p.omega1 = omega1;
            p.readings.base_radius = BaseRadius::Mean;
            let m = p.model().unwrap();
            let o = IntegrationOptions {
                transient_periods: 0.5,
                record_periods: 0.25,
                sample_step: 0.5,
                ..IntegrationOptions::default()
            };
            let r = integrate(&m, &o).unwrap();
            assert_eq!(r.stats.n_rhs, r.rhs_evaluations);
            assert!(r.stats.n_accepted > 100 && r.stats.n_rejected > 0);
            assert!(r.stats.n_events >= r.contact_events as u64 && r.contact_events > 0);
            let (_, opts) = system(&m, &o).unwrap();
            let y0 = [m.static_position(0.0), 0.0];
            let t_rec = o.transient_periods * m.period();
            let t_end = t_rec + o.record_periods * m.period();
            let out = timestep::Output::Uniform { dt: o.sample_step };
            let two_runs = |sys: &dyn timestep::OdeSystem, opts: &timestep::Options| {
                let warm = timestep::integrate(sys, 0.0, &y0, t_rec, opts).unwrap();
                let rec_opts = opts.clone().with_output(out.clone());
                let rec = timestep::integrate(sys, t_rec, &warm.y_final, t_end, &rec_opts);
                (warm, rec.unwrap())
            };
            let mech = timestep::FirstOrder(timestep::Mechanical::new(m).unwrap());
            let (_, mr) = two_runs(&mech, &opts);
            // the lean system's structure (cache, events, restarts) against the adapter's on
            // the same rounding-level footing: both read the time functions through short
            // `sin_cos` kernels (`Trig::Kernel`'s addition theorems, the adapter's three
            // direct `sin_cos`), so they agree as the kernel and the adapter do below
            let (_, lr) = two_runs(&TimeSystem::with_trig(m, Trig::Libm), &opts);
            assert_eq!(lr.y.len(), mr.y.len());

            // the kernel's rounding-level change of the right-hand side, through an impacting
            // orbit (measured: ppv within 1e-8 of itself, samples within 1/20 to 1/100 of the
            // change a 100x tighter tolerance makes)
            let q = mr.component(0);
            let direct = m.rattle(mr.t.iter().copied().zip(q.iter().copied()));
            assert_eq!(r.rattle.state, direct.state);
            let ppv = direct.ppv;
            for (a, b) in [
                (r.rattle.ppv, ppv),
                (r.rattle.q_min, direct.q_min),
                (r.rattle.q_max, direct.q_max),
            ] {
                assert!((a - b).abs() <= 1e-6 * ppv, "{omega1}: {a:e} vs {b:e}");
            }
            let tight = timestep::Options {
                rtol: opts.rtol / crate::contract::TIGHTER,
                atol: opts.atol / crate::contract::TIGHTER,
                ..opts.clone()
            };
            let (_, tr) = two_runs(&mech, &tight);
            let max_diff = |a: &[f64], b: &[f64]| {
                a.iter()
                    .zip(b)
                    .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
            };
            let d_kernel = max_diff(&r.q, &q);
            let d_tol = max_diff(&tr.component(0), &q);
            eprintln!(
                "{omega1}: max |dq|/ppv kernel {:e}, 100x tighter {:e}; ppv change {:e}",
                d_kernel / ppv,
                d_tol / ppv,
                (r.rattle.ppv - ppv) / ppv
            );
            assert!(d_kernel <= d_tol, "{omega1}: {d_kernel:e} vs {d_tol:e}");
            let d_libm = max_diff(&lr.component(0), &q);
            assert!(d_libm <= d_tol, "{omega1}: libm {d_libm:e} vs {d_tol:e}");
        }
    }

    /// A run that records after a kept transient is the run that integrates it, bit for bit
    /// (samples, rattle, work counters); a transient of other inputs (another length, start,
    /// tolerance, step bound, pair or model) is not used but integrated afresh.
    #[test]
    fn a_kept_transient_gives_the_same_run_bit_for_bit() {
        let bits = |r: &TimeResponse| {
            let mut b: Vec<u64> = [&r.tau, &r.q, &r.v]
                .iter()
                .flat_map(|x| x.iter().map(|v| v.to_bits()))
                .collect();
            b.extend([r.rattle.ppv, r.rattle.q_min, r.rattle.q_max].map(f64::to_bits));
            b.extend([
                r.stats.n_accepted,
                r.stats.n_rejected,
                r.stats.n_rhs,
                r.stats.n_events,
            ]);
            b.extend([r.rhs_evaluations, r.contact_events as u64]);
            b
        };
        let mut p = table1();
        p.omega1 = 180.0;
        let m = p.model().unwrap();
        p.omega1 = 181.0;
        let other_model = p.model().unwrap();
        let o = IntegrationOptions {
            transient_periods: 0.5,
            record_periods: 0.25,
            sample_step: 0.5,
            ..IntegrationOptions::default()
        };
        // the section's run: another window and sampling over the same transient
        let section = IntegrationOptions {
            record_periods: 0.5,
            sample_step: 7.0,
            ..o
        };
        let (_, kept) = integrate_after(&m, &section, None).unwrap();
        let direct = integrate(&m, &o).unwrap();
        let (shared, _) = integrate_after(&m, &o, Some(kept.clone())).unwrap();
        assert_eq!(bits(&shared), bits(&direct));
        assert!(direct.stats.n_accepted > 100 && direct.contact_events > 0);

        // other inputs: the kept transient is not theirs, so each run is its own direct run
        let others = [
            IntegrationOptions {
                transient_periods: 0.4,
                ..o
            },
            IntegrationOptions {
                initial: Some((0.0, 0.0)),
                ..o
            },
            IntegrationOptions { rtol: 1e-7, ..o },
            IntegrationOptions {
                transient_rtol: Some(1e-6),
                ..o
            },
            IntegrationOptions {
                max_step: 0.25,
                ..o
            },
            IntegrationOptions {
                method: Stepping::Dop853,
                ..o
            },
        ];
        for other in &others {
            let (r, _) = integrate_after(&m, other, Some(kept.clone())).unwrap();
            assert_eq!(bits(&r), bits(&integrate(&m, other).unwrap()), "{other:?}");
            assert_ne!(bits(&r), bits(&direct), "{other:?}");
        }
        let (r, _) = integrate_after(&other_model, &o, Some(kept)).unwrap();
        assert_eq!(bits(&r), bits(&integrate(&other_model, &o).unwrap()));
    }
}
