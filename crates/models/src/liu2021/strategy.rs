//! Solution strategy for sweeps of the Liu model: the time-integration reference with its motion
//! type and reproducibility, harmonic balance warm-started from the time response, sequential
//! continuation from converged neighbours, the stability policy and what happens on
//! non-convergence — in one call ([`solve_sweep`], [`solve_point`]).
//!
//! # Policy
//!
//! * **Reference** — time integration from the quasi-static contact position at rest
//!   ([`integrate`]). Its motion type comes from the stroboscopic Poincaré section (one point per
//!   excitation period `T = 2π/ω̄_c` after the transient): period-n if the section repeats with
//!   period `n ≤ 4` within [`SweepStrategy::poincare_tol`], else non-periodic. The run is repeated
//!   with the relative tolerance divided by [`SweepStrategy::refine_factor`] (100 by default); the
//!   metrics are *reproducible* when the rattle state is the same and ppv agrees within
//!   [`SweepStrategy::ppv_rel_tol`].
//! * **Harmonic balance** — three columns: the paper basis from a cold start, the paper basis
//!   warm-started from the harmonics of the time response (`HbmStart::FromTimeResponse`), and
//!   optionally a full basis warm-started the same way. A warm column that did not converge is
//!   retried from a converged neighbour along the sweep (`HbmStart::Given`), sweeping up and
//!   down, at most [`SweepStrategy::neighbour_passes`] passes (sequential, so bit-identical for
//!   any thread count).
//! * **Stability** — of every converged column, by the period map of the ODE at the HBM state ([`shooting_multipliers`](super::shooting_multipliers)):
//!   stable when the largest multiplier modulus is `≤ 1 + hbm::STABILITY_TOLERANCE`.
//! * **Non-convergence** — never an error: the point keeps `converged = false`, and
//!   [`HbmPoint::flag`] / [`TimeReference::flag`] say why a point cannot carry a verdict.
//!
//! # Example
//!
//! ```no_run
//! use geardyn_models::liu2021::{self, BaseRadius, SweepStrategy};
//! let params: Vec<_> = [140.0, 160.0, 180.0]
//!     .iter()
//!     .map(|&w| {
//!         let mut p = liu2021::table1();
//!         p.readings.base_radius = BaseRadius::Mean;
//!         p.omega1 = w;
//!         p
//!     })
//!     .collect();
//! let points = liu2021::solve_sweep(&params, &SweepStrategy::default())?;
//! for p in &points {
//!     println!("rsv {} ({:?}), flag {:?}", p.time.rattle.state.rsv(), p.time.motion, p.time.flag());
//! }
//! # Ok::<(), geardyn_models::Error>(())
//! ```

use serde::{Deserialize, Serialize};

use super::harmonic::{HbmOptions, HbmResponse, HbmStart, PreparedHbm, solve_hbm_with};
use super::integrate::{IntegrationOptions, TimeResponse, Transient, integrate, integrate_after};
use super::model::{Model, Rattle};
use super::params::Parameters;
use super::window::LongWindowOptions;
use crate::Error;
pub use crate::motion::{Motion, classify_section};
use crate::response::Robust;

/// Settings of [`solve_sweep`] / [`solve_point`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SweepStrategy {
    /// Time integration of the reference (and of the warm starts).
    pub integration: IntegrationOptions,
    /// Harmonic balance on the paper basis (the cold and warm columns).
    pub paper_hbm: HbmOptions,
    /// Highest harmonic multiple `R` of the full basis `K = R·Z₂ + 2` ([`HbmOptions::full`]);
    /// `None`: no full-basis column.
    pub full_basis: Option<usize>,
    /// Passes of neighbour continuation along the sweep (alternating up and down; stops early
    /// when nothing changes).
    pub neighbour_passes: usize,
    /// Compute the period-map stability of converged warm/full solutions.
    pub stability: bool,
    /// Periods recorded for the stroboscopic Poincaré section (≥ 4 + 1 to accept period 4:
    /// [`classify_section`] needs `n + 2` section points).
    pub poincare_periods: usize,
    /// Relative distance (to the section's spread plus the gap `b̄`) below which two section
    /// points are the same.
    pub poincare_tol: f64,
    /// The reference is repeated with `rtol / refine_factor`.
    pub refine_factor: f64,
    /// ppv of the refined run must agree within this relative tolerance.
    pub ppv_rel_tol: f64,
    /// Long-window statistics of every point with their spread ([`super::long_window`]);
    /// `None` (the default): not computed.
    #[serde(default)]
    pub long_window: Option<LongWindowOptions>,
    /// Settling of the time reference: while its Poincaré section does not repeat within
    /// `settle_margin` of the classification tolerance ([`TimeReference::section_margin`]),
    /// the transient is lengthened by `settle_periods`, at most `settle_rounds` times, and
    /// the reference (nominal, refined and section runs) is taken after the longer transient.
    /// Near a bifurcation the free transient decays slowly: at Liu Fig. 11, 170–237.5 rad/s,
    /// and Fig. 15, 0–22 N·m, the section after the 10-period transient repeated only just
    /// inside or outside the margin, so the reference (and the warm starts seeded from it)
    /// flipped between a confirmed and an unconfirmed periodic orbit under a retune of the
    /// step-size controller. A chaotic point never settles and costs the extra rounds.
    /// `settle_rounds = 0` switches it off. Each round integrates its transient from the
    /// start; the nominal run records after the last round's transient instead of
    /// integrating it again (the same start, length, tolerances and pair: the same steps).
    #[serde(default = "default_settle_rounds")]
    pub settle_rounds: usize,
    /// Periods added to the transient per settling round (see `settle_rounds`).
    #[serde(default = "default_settle_periods")]
    pub settle_periods: f64,
    /// Section margin below which the reference counts as settled (see `settle_rounds`): a
    /// settled periodic orbit repeats at the integrator's error, about 1e-5 to 1e-4 of the
    /// classification tolerance at rtol 1e-8 (Liu Fig. 11, 172.5–215 rad/s: 2e-5 to 1e-4
    /// after settling), so 1e-3 stops only a decade above it. With 1e-2 (round 10) a
    /// reference could stop at 8.7e-3 (215 rad/s), a transient still decaying, and the warm
    /// starts seeded from it moved with the retune of the step-size controller.
    #[serde(default = "default_settle_margin")]
    pub settle_margin: f64,
    /// Section margin up to which a warm start from the time response may seed its neighbours
    /// ([`SweepPoint::anchors`]): 1/100 of the classification tolerance, a decade above the
    /// settled orbits' 1e-5–1e-4 and five decades below the chaotic points' 10–10⁴ (Liu
    /// Fig. 11, 162.5–167.5 rad/s; Fig. 15 at 28 N·m).
    #[serde(default = "default_anchor_margin")]
    pub anchor_margin: f64,
}

fn default_anchor_margin() -> f64 {
    1e-2
}

fn default_settle_rounds() -> usize {
    2
}

fn default_settle_periods() -> f64 {
    40.0
}

fn default_settle_margin() -> f64 {
    1e-3
}

impl Default for SweepStrategy {
    fn default() -> Self {
        Self {
            integration: IntegrationOptions::default(),
            paper_hbm: HbmOptions::default(),
            full_basis: Some(1),
            neighbour_passes: 4,
            stability: true,
            poincare_periods: 6,
            poincare_tol: 1e-4,
            refine_factor: crate::contract::TIGHTER,
            ppv_rel_tol: 1e-3,
            long_window: None,
            settle_rounds: default_settle_rounds(),
            settle_periods: default_settle_periods(),
            settle_margin: default_settle_margin(),
            anchor_margin: default_anchor_margin(),
        }
    }
}

/// The time-integration reference of one point.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TimeReference {
    /// Rattle state and ppv over the recorded period.
    pub rattle: Rattle,
    /// Motion type from the Poincaré section.
    pub motion: Motion,
    /// Margin of [`TimeReference::motion`]: the section's repeat distance as a fraction of the
    /// classification tolerance ([`crate::motion::section_margin`]; ≤ 1 periodic, `+∞` when
    /// not known, e.g. read from data written before the field existed).
    #[serde(default = "infinite")]
    pub section_margin: f64,
    /// The same metrics with the tolerance divided by the refine factor.
    pub refined: Rattle,
    /// Rattle state equal and ppv within the strategy's tolerance under the refined tolerance.
    pub reproducible: bool,
    /// Work counters of the reference run ([`TimeResponse::stats`]: accepted and rejected
    /// steps, right-hand-side evaluations, events); the refined and Poincaré runs are not
    /// counted. Zero when read from data written before the field existed.
    #[serde(default)]
    pub stats: timestep::Stats,
}

fn infinite() -> f64 {
    f64::INFINITY
}

impl TimeReference {
    /// Why this point cannot carry a verdict, or `None` when it can: a non-periodic motion, a
    /// period-n motion with `n > 1` (the one-period metrics do not describe it), or metrics that
    /// change under the tightened tolerance.
    pub fn flag(&self) -> Option<String> {
        match self.motion {
            Motion::Periodic(n) if n > 1 => Some(format!(
                "time integration: period-{n} motion, one-period metrics do not describe it"
            )),
            // no sizes or states: they move with every retune of the integrator, and flags
            // are committed (the refined metrics carry them)
            Motion::Periodic(_) if !self.reproducible => {
                Some("time integration: metrics change under a tightened tolerance".to_owned())
            }
            Motion::Periodic(_) => None,
            other => Some(format!("time integration: {} motion", other.label())),
        }
    }
}

/// How an HBM column's solution was obtained.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum HbmOrigin {
    /// From the quasi-static contact position.
    Cold,
    /// From the harmonics of the time-integrated period.
    TimeResponse,
    /// From a converged neighbouring sweep point.
    Neighbour,
}

/// One harmonic-balance column of a sweep point.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct HbmPoint {
    /// Rattle state and ppv of the (last) iterate.
    pub rattle: Rattle,
    /// Whether Newton converged.
    pub converged: bool,
    /// Where the converged solution started from.
    pub origin: HbmOrigin,
    /// Largest period-map multiplier modulus; `None` when not computed or not converged.
    pub max_multiplier: Option<f64>,
    /// Whether the warm start is reproducible: the same solve started from the harmonics of
    /// the refined reference (the run at `rtol / refine_factor`, [`TimeReference::refined`])
    /// reaches the same outcome — both converge to the same rattle state with ppv within
    /// [`SweepStrategy::ppv_rel_tol`], or neither converges. `Some(false)`: whether and where
    /// the warm start converges depends on the integrator's error in the sample that seeds it,
    /// so its values are not results, and it does not seed the neighbour continuation
    /// ([`SweepPoint::anchors`]). A neighbour continuation inherits the check of the point it
    /// started from. `None`: a cold start, or not checked (data written before the field
    /// existed).
    #[serde(default)]
    pub seed_reproducible: Option<bool>,
    /// For [`HbmOrigin::Neighbour`]: the index (in the sweep) of the point whose solution
    /// started this one. Following it back ends at the warm start from a time response that
    /// anchors the chain; a judgement of that sample (e.g. a motion not confirmed periodic)
    /// holds for every point continued from it.
    #[serde(default)]
    pub neighbour: Option<usize>,
}

impl HbmPoint {
    fn of(r: &HbmResponse, origin: HbmOrigin) -> Self {
        Self {
            rattle: r.rattle,
            converged: r.converged(),
            origin,
            max_multiplier: None,
            seed_reproducible: None,
            neighbour: None,
        }
    }

    /// [`HbmPoint::of`] a warm start, checked against the warm start from the refined
    /// reference (see [`HbmPoint::seed_reproducible`]).
    fn checked(r: &HbmResponse, refined: &HbmResponse, ppv_rel_tol: f64, backlash: f64) -> Self {
        let same = match (r.converged(), refined.converged()) {
            (true, true) => {
                r.rattle.state == refined.rattle.state
                    && (r.rattle.ppv - refined.rattle.ppv).abs()
                        <= ppv_rel_tol * refined.rattle.ppv.abs().max(backlash.abs())
            }
            (false, false) => true,
            _ => false,
        };
        Self {
            seed_reproducible: Some(same),
            ..Self::of(r, HbmOrigin::TimeResponse)
        }
    }

    /// Stability by the policy (`max |μ| ≤ 1 + hbm::STABILITY_TOLERANCE`); `None` when not
    /// computed.
    pub fn stable(&self) -> Option<bool> {
        self.max_multiplier.map(is_stable_multiplier)
    }

    /// Why this column cannot carry a verdict (not converged, a warm start that another sample
    /// of the same orbit leads elsewhere, unstable, stability unknown), or `None`.
    pub fn flag(&self) -> Option<String> {
        if !self.converged {
            return Some("HBM not converged".to_owned());
        }
        if self.seed_reproducible == Some(false) {
            return Some(
                "HBM warm start not reproducible: started from the refined reference it reaches another solution"
                    .to_owned(),
            );
        }
        match self.max_multiplier {
            None => Some("HBM stability not computed".to_owned()),
            Some(m) if !is_stable_multiplier(m) => Some(format!("HBM unstable (max |μ| = {m:.4})")),
            Some(_) => None,
        }
    }
}

/// The stability threshold: a multiplier modulus `≤ 1 + STABILITY_TOLERANCE` is stable (the
/// workspace's one verdict, [`system::is_stable_multiplier`]).
pub use system::is_stable_multiplier;

/// Largest period-map multiplier modulus at a converged HBM state.
pub fn max_multiplier(model: &Model, response: &HbmResponse) -> Result<f64, Error> {
    Ok(super::shooting_stability(model, response)?.max_modulus)
}

/// One solved sweep point.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepPoint {
    /// Time-integration reference.
    pub time: TimeReference,
    /// Paper basis, cold start.
    pub cold: HbmPoint,
    /// Paper basis, warm start (or neighbour).
    pub warm: HbmPoint,
    /// Full basis, warm start (or neighbour); `None` if the strategy has no full basis.
    pub full: Option<HbmPoint>,
    /// The recorded time response of the reference (for spectra and plots).
    pub response: TimeResponse,
    /// The cold paper-basis solution.
    pub cold_solution: HbmResponse,
    /// The warm paper-basis solution.
    pub warm_solution: HbmResponse,
    /// The full-basis solution.
    pub full_solution: Option<HbmResponse>,
    /// Long-window statistics with their spread, when the strategy asks for them.
    pub window: Option<Robust>,
}

impl SweepPoint {
    /// Whether the converged HBM column `h` of this point may seed the neighbour continuation
    /// ([`solve_sweep`]): a cold start or a neighbour continuation always; a warm start from
    /// the time response only when that response is a confirmed periodic orbit — period 1,
    /// reproducible under the refined tolerance, its section repeating within
    /// [`SweepStrategy::anchor_margin`] of the tolerance — and the warm start from the refined
    /// sample reaches the same solution ([`HbmPoint::seed_reproducible`]). A warm start from a
    /// chaotic sample converges to whichever solution that sample is near; as a source it
    /// carried that arbitrary choice along the sweep (Liu Fig. 11: from 165 rad/s to
    /// 195 rad/s in one run, from 162.5 to 185 rad/s under a retune of the step-size
    /// controller). Such a point is re-solved from a confirmed neighbour instead and keeps its
    /// own solution only when that fails.
    pub fn anchors(&self, h: &HbmPoint, strategy: &SweepStrategy) -> bool {
        h.converged
            && match h.origin {
                HbmOrigin::Cold | HbmOrigin::Neighbour => true,
                HbmOrigin::TimeResponse => {
                    self.time.flag().is_none()
                        && self.time.section_margin <= strategy.anchor_margin
                        && h.seed_reproducible != Some(false)
                }
            }
    }
}

/// The time-integration reference of a model: metrics, Poincaré motion type and the refined run.
pub fn time_reference(
    model: &Model,
    strategy: &SweepStrategy,
) -> Result<(TimeReference, TimeResponse), Error> {
    time_reference_runs(model, strategy).map(|(t, nominal, _)| (t, nominal))
}

/// The fields of a [`SweepStrategy`] that the time reference reads, and all that its
/// computation is given: so its memo key holds every input and nothing else. A study without
/// long windows (or with other harmonic-balance settings) shares the references of a study
/// with them (`liu2021-readings-speed-thresholds`' constant-b̄ row and the speed sweep).
#[derive(Debug, Clone, Copy, PartialEq)]
struct ReferenceSettings {
    integration: IntegrationOptions,
    poincare_periods: usize,
    poincare_tol: f64,
    refine_factor: f64,
    ppv_rel_tol: f64,
    settle_rounds: usize,
    settle_periods: f64,
    settle_margin: f64,
}

impl ReferenceSettings {
    fn of(s: &SweepStrategy) -> Self {
        Self {
            integration: s.integration,
            poincare_periods: s.poincare_periods,
            poincare_tol: s.poincare_tol,
            refine_factor: s.refine_factor,
            ppv_rel_tol: s.ppv_rel_tol,
            settle_rounds: s.settle_rounds,
            settle_periods: s.settle_periods,
            settle_margin: s.settle_margin,
        }
    }

    /// The memo key of the reference of `model` under these settings.
    fn key(&self, model: &Model) -> String {
        format!("{model:?}|{self:?}")
    }
}

/// [`time_reference`] with the recorded response of the refined run as well. Memoised while a
/// [`crate::memo::Session`] is open (key: the model and the strategy's fields that the
/// reference reads, [`ReferenceSettings`]).
fn time_reference_runs(
    model: &Model,
    strategy: &SweepStrategy,
) -> Result<(TimeReference, TimeResponse, TimeResponse), Error> {
    let settings = ReferenceSettings::of(strategy);
    crate::memo::cached(
        "liu2021::time_reference",
        || settings.key(model),
        || time_reference_runs_uncached(model, &settings),
    )
}

fn time_reference_runs_uncached(
    model: &Model,
    settings: &ReferenceSettings,
) -> Result<(TimeReference, TimeResponse, TimeResponse), Error> {
    if settings.settle_rounds > 100 {
        return Err(Error::invalid(
            "liu2021.strategy.settle_rounds",
            "at most 100",
            settings.settle_rounds as f64,
        ));
    }
    if !(settings.settle_periods >= 0.0 && settings.settle_periods <= 1e5) {
        return Err(Error::invalid(
            "liu2021.strategy.settle_periods",
            "in [0, 1e5]",
            settings.settle_periods,
        ));
    }
    if !(settings.settle_margin > 0.0 && settings.settle_margin.is_finite()) {
        return Err(Error::invalid(
            "liu2021.strategy.settle_margin",
            "> 0 and finite",
            settings.settle_margin,
        ));
    }
    let mut opts = settings.integration;
    // the section after the transient; lengthened while it does not repeat with margin
    // (`settle_rounds`: a bounded loop). The transient of the last section is the transient
    // of the nominal run below (the same start, length and tolerances): integrated once.
    let section = |opts: &IntegrationOptions| -> Result<(Motion, f64, Transient), Error> {
        let (strobe, transient) = integrate_after(
            model,
            &IntegrationOptions {
                record_periods: settings.poincare_periods as f64,
                sample_step: model.period(),
                ..*opts
            },
            None,
        )?;
        let scale = (strobe.rattle.ppv + model.backlash.abs()).max(f64::MIN_POSITIVE);
        let motion = classify_section(&strobe.q, &strobe.v, settings.poincare_tol, scale);
        let margin = crate::motion::section_margin(
            &strobe.q,
            &strobe.v,
            motion,
            settings.poincare_tol,
            scale,
        );
        Ok((motion, margin, transient))
    };
    let (mut motion, mut section_margin, mut transient) = section(&opts)?;
    for _ in 0..settings.settle_rounds {
        // a NaN margin is not settled: it goes on to the next round
        if section_margin <= settings.settle_margin {
            break;
        }
        opts.transient_periods += settings.settle_periods;
        (motion, section_margin, transient) = section(&opts)?;
    }
    let (ti, _) = integrate_after(model, &opts, Some(transient))?;
    let refined_opts = IntegrationOptions {
        rtol: opts.rtol / settings.refine_factor,
        ..opts
    };
    let refined_run = integrate(model, &refined_opts)?;
    let refined = refined_run.rattle;
    let reproducible = refined.state == ti.rattle.state
        && (refined.ppv - ti.rattle.ppv).abs()
            <= settings.ppv_rel_tol * refined.ppv.abs().max(model.backlash.abs());
    Ok((
        TimeReference {
            rattle: ti.rattle,
            motion,
            section_margin,
            refined,
            reproducible,
            stats: ti.stats,
        },
        ti,
        refined_run,
    ))
}

/// Solve one point without neighbours: reference, cold, warm and full columns, stability.
pub fn solve_point(params: &Parameters, strategy: &SweepStrategy) -> Result<SweepPoint, Error> {
    let m = params.model()?;
    let (time, ti, refined) = time_reference_runs(&m, strategy)?;
    let mut paper = PreparedHbm::per_thread(&m, &strategy.paper_hbm)?;
    let cold = paper.solve(&m, HbmStart::Cold)?;
    // every warm start twice: from the nominal and from the refined sample of the reference
    // (HbmPoint::seed_reproducible)
    let warm = paper.solve(&m, HbmStart::FromTimeResponse(&ti))?;
    let warm_check = paper.solve(&m, HbmStart::FromTimeResponse(&refined))?;
    let check = |a: &HbmResponse, b: &HbmResponse| {
        HbmPoint::checked(a, b, strategy.ppv_rel_tol, m.backlash)
    };
    let full = match strategy.full_basis {
        Some(r) => {
            let o = HbmOptions::full(&m, r);
            let f = solve_hbm_with(&m, &o, HbmStart::FromTimeResponse(&ti))?;
            let f_check = solve_hbm_with(&m, &o, HbmStart::FromTimeResponse(&refined))?;
            Some((f, f_check))
        }
        None => None,
    };
    let mut point = SweepPoint {
        time,
        cold: HbmPoint::of(&cold, HbmOrigin::Cold),
        warm: check(&warm, &warm_check),
        full: full.as_ref().map(|(f, c)| check(f, c)),
        response: ti,
        cold_solution: cold,
        warm_solution: warm,
        full_solution: full.map(|(f, _)| f),
        window: match &strategy.long_window {
            Some(o) => Some(super::long_window(&m, o)?),
            None => None,
        },
    };
    if strategy.stability {
        add_stability(&m, &mut point)?;
    }
    Ok(point)
}

fn add_stability(m: &Model, p: &mut SweepPoint) -> Result<(), Error> {
    if p.cold.converged {
        p.cold.max_multiplier = Some(max_multiplier(m, &p.cold_solution)?);
    }
    if p.warm.converged {
        p.warm.max_multiplier = Some(max_multiplier(m, &p.warm_solution)?);
    }
    if let (Some(f), Some(s)) = (p.full.as_mut(), p.full_solution.as_ref())
        && f.converged
    {
        f.max_multiplier = Some(max_multiplier(m, s)?);
    }
    Ok(())
}

/// Solve a sweep (points in order along the swept parameter): every point in parallel
/// ([`solve_point`] without stability), then neighbour continuation of the warm and full
/// columns, then stability of the converged solutions. Deterministic for any thread count.
pub fn solve_sweep(
    params: &[Parameters],
    strategy: &SweepStrategy,
) -> Result<Vec<SweepPoint>, Error> {
    if strategy.anchor_margin.is_nan() || strategy.anchor_margin < 0.0 {
        return Err(Error::invalid(
            "liu2021.strategy.anchor_margin",
            ">= 0 (+inf: any periodic sample seeds)",
            strategy.anchor_margin,
        ));
    }
    let no_stab = SweepStrategy {
        stability: false,
        ..*strategy
    };
    let mut pts: Vec<SweepPoint> = timestep::sweep(params, |p| solve_point(p, &no_stab), None)
        .into_iter()
        .collect::<Result<_, Error>>()?;
    let models: Vec<Model> = params
        .iter()
        .map(Parameters::model)
        .collect::<Result<_, Error>>()?;
    fill_from_neighbours(&models, &mut pts, strategy, false)?;
    if strategy.full_basis.is_some() {
        fill_from_neighbours(&models, &mut pts, strategy, true)?;
    }
    if strategy.stability {
        let pairs: Vec<(SweepPoint, &Model)> = pts.into_iter().zip(&models).collect();
        pts = timestep::sweep_owned(
            pairs,
            |(mut p, m)| add_stability(m, &mut p).map(|()| p),
            None,
        )
        .into_iter()
        .collect::<Result<_, Error>>()?;
    }
    Ok(pts)
}

/// Sequential continuation along the sweep for the points whose warm start did not converge:
/// start from a converged neighbour, sweeping up and down until nothing changes (the one
/// neighbour continuation, [`orbit::fill_from_neighbours`], with the Liu harmonic-balance
/// solve as corrector).
fn fill_from_neighbours(
    models: &[Model],
    pts: &mut [SweepPoint],
    strategy: &SweepStrategy,
    full: bool,
) -> Result<(), Error> {
    // a point counts as solved (a source, never re-solved) only when its solution may seed
    // its neighbours: an unconfirmed warm start is re-solved from a confirmed neighbour
    let converged = |p: &SweepPoint| {
        if full {
            p.full.is_some_and(|f| p.anchors(&f, strategy))
        } else {
            p.anchors(&p.warm, strategy)
        }
    };
    orbit::fill_from_neighbours(
        pts,
        strategy.neighbour_passes,
        converged,
        |i, j, target, from| {
            let m = &models[i];
            let (opts, start) = if full {
                let Some(s) = from.full_solution.clone() else {
                    return Ok(false);
                };
                (HbmOptions::full(m, strategy.full_basis.unwrap_or(1)), s)
            } else {
                (strategy.paper_hbm, from.warm_solution.clone())
            };
            let r = solve_hbm_with(m, &opts, HbmStart::Given(&start))?;
            if !r.converged() {
                return Ok(false);
            }
            // the neighbour's own seed check carries over: a start from a solution that another
            // sample would not have reached is as arbitrary as that solution
            let hp = HbmPoint {
                seed_reproducible: if full {
                    from.full.and_then(|f| f.seed_reproducible)
                } else {
                    from.warm.seed_reproducible
                },
                neighbour: Some(j),
                ..HbmPoint::of(&r, HbmOrigin::Neighbour)
            };
            if full {
                target.full = Some(hp);
                target.full_solution = Some(r);
            } else {
                target.warm = hp;
                target.warm_solution = r;
            }
            Ok(true)
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The time reference's memo key: the same for strategies that differ only in what the
    /// reference does not read (long windows, harmonic balance, continuation, stability,
    /// anchors), different when any field it reads changes.
    #[test]
    fn time_reference_key_holds_exactly_the_fields_it_reads() {
        let m = super::super::table1().model().unwrap();
        let base = SweepStrategy::default();
        let key = |s: &SweepStrategy| ReferenceSettings::of(s).key(&m);
        let changed = |change: fn(&mut SweepStrategy)| {
            let mut s = base;
            change(&mut s);
            key(&s)
        };
        let same: [fn(&mut SweepStrategy); 6] = [
            |s| s.long_window = Some(LongWindowOptions::default()),
            |s| s.full_basis = None,
            |s| s.neighbour_passes = 1,
            |s| s.stability = false,
            |s| s.anchor_margin = 0.5,
            |s| s.paper_hbm.max_iter += 1,
        ];
        for (i, change) in same.into_iter().enumerate() {
            assert_eq!(changed(change), key(&base), "unread field {i}");
        }
        let other: [fn(&mut SweepStrategy); 8] = [
            |s| s.integration.rtol /= 2.0,
            |s| s.poincare_periods += 1,
            |s| s.poincare_tol *= 2.0,
            |s| s.refine_factor *= 2.0,
            |s| s.ppv_rel_tol *= 2.0,
            |s| s.settle_rounds += 1,
            |s| s.settle_periods += 1.0,
            |s| s.settle_margin *= 2.0,
        ];
        for (i, change) in other.into_iter().enumerate() {
            assert_ne!(changed(change), key(&base), "read field {i}");
        }
        // another model, another key
        let mut p = super::super::table1();
        p.omega1 += 1.0;
        assert_ne!(
            ReferenceSettings::of(&base).key(&p.model().unwrap()),
            key(&base)
        );
    }

    /// Liu Fig. 11 at 180 rad/s (Table 1, constant b̄): after the 10-period transient the
    /// 6-period section is still far from repeating (the free transient near the bilateral
    /// onset decays slowly); the settling rounds lengthen the transient until it repeats at the
    /// integrator's error, two decades inside the margin. A bad setting is an error naming the
    /// field.
    #[test]
    fn time_reference_settles_the_transient() {
        let mut p = super::super::table1();
        p.omega1 = 180.0;
        p.readings.base_radius = super::super::BaseRadius::Mean;
        let m = p.model().unwrap();
        let bare = SweepStrategy {
            settle_rounds: 0,
            ..SweepStrategy::default()
        };
        let (t0, _) = time_reference(&m, &bare).unwrap();
        let (t1, r1) = time_reference(&m, &SweepStrategy::default()).unwrap();
        assert!(t0.section_margin > 1e-2, "{}", t0.section_margin);
        assert!(t1.section_margin <= 1e-4, "{}", t1.section_margin);
        assert_eq!(t1.motion, Motion::Periodic(1));
        assert!(r1.rattle.state == super::super::RattleState::Bilateral);
        for (s, field) in [
            (
                SweepStrategy {
                    settle_rounds: 101,
                    ..SweepStrategy::default()
                },
                "settle_rounds",
            ),
            (
                SweepStrategy {
                    settle_periods: f64::NAN,
                    ..SweepStrategy::default()
                },
                "settle_periods",
            ),
            (
                SweepStrategy {
                    settle_margin: 0.0,
                    ..SweepStrategy::default()
                },
                "settle_margin",
            ),
        ] {
            let e = time_reference(&m, &s).unwrap_err().to_string();
            assert!(e.contains(field), "{e}");
        }
        let bad = SweepStrategy {
            anchor_margin: f64::NAN,
            ..SweepStrategy::default()
        };
        let e = solve_sweep(&[p], &bad).unwrap_err().to_string();
        assert!(e.contains("anchor_margin"), "{e}");
    }

    /// Only a confirmed warm start seeds its neighbours: a chaotic reference (section margin far
    /// above the tolerance), one that is not reproducible, or a warm start that the refined
    /// sample leads elsewhere does not; a cold start and a neighbour continuation do; an
    /// unconverged column never.
    #[test]
    fn only_confirmed_warm_starts_anchor_neighbour_chains() {
        let r = Rattle {
            state: super::super::RattleState::Unilateral,
            ppv: 1.0,
            q_min: 0.0,
            q_max: 1.0,
        };
        let h = HbmPoint {
            rattle: r,
            converged: true,
            origin: HbmOrigin::TimeResponse,
            max_multiplier: None,
            seed_reproducible: Some(true),
            neighbour: None,
        };
        let mut p = super::super::table1();
        p.omega1 = 140.0;
        let s = SweepStrategy {
            stability: false,
            full_basis: None,
            ..SweepStrategy::default()
        };
        let mut pt = solve_point(&p, &s).unwrap();
        pt.time.section_margin = 1e-4;
        assert!(pt.time.flag().is_none());
        assert!(pt.anchors(&h, &s));
        pt.time.section_margin = 2e3;
        assert!(!pt.anchors(&h, &s));
        pt.time.section_margin = 1e-4;
        assert!(!pt.anchors(
            &HbmPoint {
                seed_reproducible: Some(false),
                ..h
            },
            &s
        ));
        assert!(!pt.anchors(
            &HbmPoint {
                converged: false,
                ..h
            },
            &s
        ));
        for origin in [HbmOrigin::Cold, HbmOrigin::Neighbour] {
            let chaotic = SweepPoint {
                time: TimeReference {
                    section_margin: 2e3,
                    motion: Motion::NonPeriodic,
                    ..pt.time
                },
                ..pt.clone()
            };
            assert!(chaotic.anchors(&HbmPoint { origin, ..h }, &s));
        }
        pt.time.reproducible = false;
        assert!(!pt.anchors(&h, &s));
    }

    /// Every warm start is solved twice, from the nominal and from the refined sample of the
    /// reference: at 140 rad/s (Table 1, a confirmed periodic orbit; both converge to the same
    /// solution) the check holds for the paper and the full basis, and the cold start carries
    /// none.
    #[test]
    fn warm_starts_are_checked_against_the_refined_reference() {
        let mut p = super::super::table1();
        p.omega1 = 140.0;
        p.readings.base_radius = super::super::BaseRadius::Mean;
        let s = SweepStrategy {
            stability: false,
            ..SweepStrategy::default()
        };
        let pt = solve_point(&p, &s).unwrap();
        assert!(pt.warm.converged);
        assert_eq!(pt.warm.seed_reproducible, Some(true));
        assert_eq!(pt.full.unwrap().seed_reproducible, Some(true));
        assert_eq!(pt.cold.seed_reproducible, None);
        assert_eq!(pt.warm.neighbour, None);
        // the check itself: another state, a ppv outside the tolerance, one side not converged
        let a = pt.warm_solution.clone();
        let mut b = a.clone();
        let same = |a: &HbmResponse, b: &HbmResponse| {
            HbmPoint::checked(a, b, s.ppv_rel_tol, 0.0).seed_reproducible
        };
        assert_eq!(same(&a, &b), Some(true));
        b.rattle.ppv *= 1.0 + 2.0 * s.ppv_rel_tol;
        assert_eq!(same(&a, &b), Some(false));
        b = a.clone();
        b.rattle.state = super::super::RattleState::Bilateral;
        assert_ne!(a.rattle.state, b.rattle.state);
        assert_eq!(same(&a, &b), Some(false));
        b = a.clone();
        b.solution.converged = false;
        assert_eq!(same(&a, &b), Some(false));
        let mut c = b.clone();
        c.rattle.ppv *= 3.0;
        // neither converges: reproducibly not converged, whatever the iterates
        assert_eq!(same(&c, &b), Some(true));
    }

    #[test]
    fn section_classification() {
        let q1 = [1.0; 6];
        assert_eq!(classify_section(&q1, &q1, 1e-6, 1.0), Motion::Periodic(1));
        let q2 = [1.0, -1.0, 1.0, -1.0, 1.0, -1.0];
        let v0 = [0.0; 6];
        assert_eq!(classify_section(&q2, &v0, 1e-6, 1.0), Motion::Periodic(2));
        let qn = [0.1, 0.5, 0.9, 0.3, 0.7, 0.2, 0.8];
        assert_eq!(classify_section(&qn, &v0, 1e-6, 1.0), Motion::NonPeriodic);
        // too short to accept period 4
        let q4 = [1.0, 2.0, 3.0, 4.0, 1.0];
        assert_eq!(
            classify_section(&q4, &v0[..5], 1e-6, 1.0),
            Motion::NonPeriodic
        );
    }

    #[test]
    fn flags() {
        let r = Rattle {
            state: super::super::RattleState::NoRattle,
            ppv: 1.0,
            q_min: 0.0,
            q_max: 1.0,
        };
        let mut h = HbmPoint {
            rattle: r,
            converged: false,
            origin: HbmOrigin::Cold,
            max_multiplier: None,
            seed_reproducible: None,
            neighbour: None,
        };
        assert!(h.flag().unwrap().contains("not converged"));
        h.converged = true;
        assert!(h.flag().unwrap().contains("not computed"));
        h.max_multiplier = Some(1.5);
        assert!(h.flag().unwrap().contains("unstable"));
        h.max_multiplier = Some(0.9);
        assert!(h.flag().is_none());
        h.seed_reproducible = Some(true);
        assert!(h.flag().is_none());
        h.seed_reproducible = Some(false);
        assert!(h.flag().unwrap().contains("not reproducible"));
        let mut t = TimeReference {
            rattle: r,
            motion: Motion::Periodic(1),
            section_margin: 1e-3,
            refined: r,
            reproducible: true,
            stats: timestep::Stats::default(),
        };
        assert!(t.flag().is_none());
        t.motion = Motion::Periodic(2);
        assert!(t.flag().unwrap().contains("period-2"));
        t.motion = Motion::NonPeriodic;
        assert!(t.flag().unwrap().contains("non-periodic"));
        t.motion = Motion::Periodic(1);
        t.reproducible = false;
        assert!(t.flag().unwrap().contains("tightened"));
    }

    #[test]
    fn one_point_below_threshold_is_clean() {
        let mut p = super::super::table1();
        p.readings.base_radius = super::super::BaseRadius::Mean;
        p.omega1 = 120.0;
        let s = SweepStrategy {
            full_basis: None,
            poincare_periods: 4,
            ..SweepStrategy::default()
        };
        let pt = solve_point(&p, &s).unwrap();
        assert_eq!(pt.time.motion, Motion::Periodic(1));
        assert!(pt.time.flag().is_none(), "{:?}", pt.time.flag());
        assert_eq!(pt.time.rattle.state.rsv(), 0);
        assert!(pt.warm.converged && pt.warm.flag().is_none());
    }
}
