//! # timestep — time integration with contact events, steady state and response metrics
//!
//! A generic engine (no gear knowledge) for the long, accurate time integrations that check
//! harmonic balance, reveal rattle and chaos, and give the resonance amplitudes of
//! Karpov et al. 2017. A model implements [`OdeSystem`] (or [`ExplicitSecondOrder`] wrapped in
//! [`FirstOrder`]), or — the way the geardyn models do it — the shared system description
//! `geardyn_system::SecondOrderSystem` (`M q'' + C q' + K q + g = f`, the trait the harmonic
//! balance engine solves too) wrapped in [`Mechanical`] and then [`FirstOrder`], and gets:
//!
//! * **Integration** of `y' = F(t, y)`, `y ∈ ℝⁿ` as slices (2 states for a 1-DOF pair, 12 for
//!   the 6-DOF model of Yu et al. 2021, Eq. 12–19; no allocation per step) by [`integrate`]
//!   with one of [`Method`]: this crate's Dormand–Prince 5(4) with 4th-order dense output
//!   (default, fastest), fixed-step RK4, or `ode_solvers` 0.6 `Dopri5` / `Dop853`.
//! * **Events**: event functions `g_i(t, y)` — e.g. the backlash switching surfaces
//!   `q = ±b` of the dead-zone function `f(q)` (Liu et al. 2021, Eq. 12; helper [`gap_edges`])
//!   or a user Poincaré surface. After each accepted step a sign change is located on the
//!   dense output (Illinois regula falsi, to [`Options::event_tol`] in time); the step is
//!   **recomputed** from its start so that it ends on the surface, re-located on the new clean
//!   dense output (repeat until the step end and the crossing agree), recorded as [`Event`]
//!   (time, index, direction), and [`OdeSystem::on_event`] may apply a jump (impact law) or
//!   stop. The right-hand side is thus never integrated across a kink inside one step.
//! * **Steady state** ([`steady_state`]): transient by a fixed number of forcing periods or a
//!   period-to-period test `|P_k − P_{k−m}|_∞ ≤ tol (1 + |P_k|_∞)`, `m ≤ max_order`; then an
//!   integer number of periods sampled uniformly (end point excluded) for exact-bin FFTs.
//! * **Poincaré sections** ([`poincare_stroboscopic`], [`poincare_surface`]) and **motion
//!   classification** ([`classify_motion`]): period-n by repetition of the stroboscopic
//!   points; otherwise quasi-periodic or chaotic from the largest Lyapunov exponent by
//!   two-trajectory renormalisation ([`largest_lyapunov`], Benettin et al. 1980), each
//!   trajectory integrated with event location — valid for piecewise-smooth systems without
//!   a saltation matrix.
//! * **Bifurcation diagrams** ([`bifurcation_sweep`]): for each parameter value the
//!   stroboscopic section `x_j(kT)` of one coordinate with its [`Motion`] (period-n,
//!   quasi-periodic, chaotic) and λ; independent points in parallel (bit-identical for any
//!   thread count) or sequential continuation up/down ([`Start`]) to show hysteresis; a failed
//!   point is an `Err` in its slot, not a lost sweep.
//! * **Spectra** ([`amplitude_spectrum`], rustfft): one-sided, a sine of amplitude `A` shows
//!   `A`; [`harmonic_amplitudes`] reads harmonic `h` from bin `h·n_periods`.
//! * **Signal metrics**: peak-to-peak ([`peak_to_peak`]), [`rms`], Fourier projection onto the
//!   harmonics of a frequency ([`fourier_projection`]). The gear metrics built on them (rattle
//!   state, dynamic factor, RMS over harmonics) are in `geardyn_models::response`: this crate
//!   knows no gears.
//! * **Sweeps** ([`sweep`], [`sweep_with_threads`]): rayon over a parameter list, results in
//!   input order, bit-identical for any thread count, progress callback.
//!
//! ## Which method when
//! * [`Method::DormandPrince54`] (default): everything, in particular backlash/impact models
//!   with events; ~60 ms for 20,000 time units of a 1-DOF backlash oscillator at rtol 1e-8
//!   (see `docs/performance/timestep.md`).
//! * [`Method::Rk4`]: reference fixed-step runs, order checks.
//! * [`Method::OdeSolversDopri5`] / [`Method::OdeSolversDop853`]: cross-checks against an
//!   independent implementation. Their output between steps and the event location use a
//!   cubic Hermite interpolant (O(h⁴)); they allocate per stage (`DVector`) and are 4–5× slower.
//!
//! ## Limitations
//! * Forward integration only (`t_end ≥ t0`).
//! * Two crossings of the same event function inside one accepted step (a grazing excursion
//!   shorter than a step) are not seen; bound the step with [`Options::h_max`] if that matters.
//! * Event times are as accurate as the integration itself (dense-output error ~ tolerance);
//!   `event_tol` is the root-finding tolerance on the interpolant, not a global accuracy.
//! * A right-hand side discontinuous *on* the surface is evaluated there from whichever side
//!   the state lies numerically; the backlash force `k f(q)` is continuous, so this does not
//!   arise for it.
//!
//! ## References
//! Hairer, Nørsett & Wanner, *Solving ODEs I*, 2nd ed., 1993 (DOPRI5, dense output, step
//! control); Benettin, Galgani, Giorgilli & Strelcyn, Meccanica 15 (1980) 9–30 (Lyapunov
//! exponents); Guckenheimer & Holmes 1983, §2.2 (Duffing reference cases); Liu, Lv & Zhao 2021,
//! Mech. Sci. 12:361 (rsv, ppv, Eq. 9, 12); Yu, Sun, Li & Wu 2021 (Eq. 20–21).
//!
//! ## Example
//! ```
//! use geardyn_timestep::*;
//! // free dead-zone oscillator, gap ±0.5: the first crossing of x = 0.5 is at t = 0.5
//! let sys = FirstOrder(DeadZoneOscillator::free(0.5));
//! let sol = integrate(&sys, 0.0, &[0.0, 1.0], 10.0, &Options::default())?;
//! assert_eq!(sol.status, Status::Completed);
//! assert!((sol.events[0].t - 0.5).abs() < 1e-9);
//! assert_eq!(sol.events[0].direction, Direction::Rising);
//! // steady forced response and its amplitude at the forcing frequency
//! let p = LinearOscillator { omega0: 1.0, zeta: 0.1, force: 1.0, omega: 0.5 };
//! let period = 2.0 * std::f64::consts::PI / p.omega;
//! let st = steady_state(&p.first_order(), 0.0, &[0.0, 0.0], &Options::default(),
//!                       &SteadyOptions::new(period))?;
//! let a1 = harmonic_amplitudes(&st.component(0), 8, 1)?[0];
//! let exact = 1.0 / ((1.0f64 - 0.25).powi(2) + (2.0f64 * 0.1 * 0.5).powi(2)).sqrt();
//! assert!((a1 - exact).abs() < 1e-5);
//! # Ok::<(), geardyn_timestep::Error>(())
//! ```
#![deny(missing_docs)]

mod bifurcation;
mod dop853;
mod driver;
mod error;
mod metrics;
mod odesolvers;
mod options;
mod problems;
mod record;
mod solution;
mod spectrum;
mod steady;
mod stepper;
mod sweep;
mod system;

pub use bifurcation::{
    BifurcationOptions, BifurcationPoint, MAX_PERIODS, MAX_SECTION_POINTS, Start,
    bifurcation_point, bifurcation_sweep,
};
pub use driver::integrate;
pub use error::{Error, Result};
pub use metrics::{
    fourier_projection, fourier_projection_at, harmonic_amplitudes_of_projection, peak_to_peak, rms,
};
pub use options::{Method, Options, Output};
pub use problems::{BouncingBall, DeadZoneOscillator, Duffing, LinearOscillator};
pub use solution::{Event, Solution, Stats, Status};
pub use spectrum::{Spectrum, amplitude_spectrum, harmonic_amplitudes};
pub use steady::{
    Classification, ClassifyOptions, LyapunovEstimate, LyapunovOptions, Motion, PoincareSection,
    SteadyOptions, SteadyState, Transient, classify_motion, detect_period, detect_period_abs,
    largest_lyapunov, poincare_stroboscopic, poincare_surface, section_repeat_distance,
    steady_state,
};
#[cfg(feature = "parallel")]
pub use sweep::sweep_with_threads;
pub use sweep::{sweep, sweep_owned};
pub use system::{
    Direction, EventAction, ExplicitSecondOrder, FirstOrder, FnSystem, Mechanical, OdeSystem,
    gap_edges,
};

/// The README's example, compiled and run as a doctest so that it cannot rot.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
