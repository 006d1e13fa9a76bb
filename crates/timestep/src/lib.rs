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
//!   (default), this crate's DOP853 (order 8, 7th-order dense output; fastest at tight
//!   tolerances), fixed-step RK4, or `ode_solvers` 0.6 `Dopri5` / `Dop853`. DP5 and DOP853
//!   share one driver (step control, event location, restarts, output, deadline, statistics);
//!   they differ only in the stepper and its controller constants. [`integrate_streamed`]
//!   hands each sample of the [`Output`] grid to a closure as it is computed instead of storing
//!   it (the same samples, events and final state, bit for bit), for consumers that reduce a
//!   long record as it comes; [`Output::last_sample`] gives the time of the last sample before
//!   the run.
//! * **Events**: event functions `g_i(t, y)` — e.g. the backlash switching surfaces
//!   `q = ±b` of the dead-zone function `f(q)` (Liu et al. 2021, Eq. 12; helper [`gap_edges`])
//!   or a user Poincaré surface. After each accepted step a sign change is located on the
//!   dense output (Illinois regula falsi, to [`Options::event_tol`] in time); the step is
//!   **recomputed** from its start so that it ends on the surface, re-located on the new clean
//!   dense output (repeat until the step end and the crossing agree), recorded as [`Event`]
//!   (time, index, direction), and [`OdeSystem::on_event`] may apply a jump (impact law) or
//!   stop. The right-hand side is thus never integrated across a kink inside one step.
//! * **Steps across a switching surface.** A trial step that straddles a surface carries the
//!   kink in its error estimate and is usually rejected; the controller's shrink factor alone
//!   then takes several rejections to step off it (about 7 per event for DP5 and 13 for
//!   DOP853 on Liu's bilateral rattle). On a rejection whose end state lies across a surface,
//!   the crossing is located on the rejected step's own dense output (the same Illinois
//!   iteration as an accepted step's, to the event tolerance), and the retry ends just past
//!   it, at `max(θ + 10⁻⁴, 10⁻³) h`; the event is then located on that accepted step as usual.
//!   The dense output of a rejected step is polluted by the kink, but far less than a linear
//!   interpolation of the event functions is wrong on a curved approach (the estimate before).
//!   The margin `10⁻⁴ h` is a compromise: the last stage of an embedded pair sits at the step
//!   end, past the kink, so a straddle `δ` enters the error estimate linearly (with `10⁻³ h`
//!   about half the retries were rejected again), while below `10⁻⁴ h` the retry sometimes
//!   ends short of the surface and the step sequence then jumps with the start (forward
//!   differences of a period map lose their error bound). The retry is used only where it
//!   shortens the step by 10 % or more (every rejection still shrinks the step), never below
//!   `10⁻³` of it, and at most four times between located events (an estimate that keeps
//!   falling short, near a grazing, goes back to the plain controller; four retries shrink the
//!   step by at most `10⁻¹²`). Measured on Liu 2021 (one settled 50-period window at
//!   200 rad/s): rejections per event 4.6 → 2.9 (DP5, rtol 1e-8) and 8.7 → 5.8 (DOP853,
//!   1e-10); right-hand sides −11 % and −12 % against the linear estimate.
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
//! * **Sweeps** ([`sweep()`], [`sweep_with_threads`]): rayon over a parameter list, results in
//!   input order, bit-identical for any thread count, progress callback.
//!
//! ## Which method when
//! * [`Method::DormandPrince54`] (default): everything, in particular backlash/impact models
//!   with events; ~60 ms for 20,000 time units of a 1-DOF backlash oscillator at rtol 1e-8
//!   (see `docs/performance/timestep.md`).
//! * [`Method::Dop853`]: tight tolerances and smooth stretches between events. Hairer's
//!   8(5,3) pair: 12 evaluations per step (3 more where the dense output is read) against
//!   DP5's 6, with far fewer steps as the tolerance shrinks. Measured (one round on a loaded
//!   2-core machine, on-CPU times; `docs/performance/work-precision.md`, generated by
//!   `docs/peers/work_precision.py`): on Liu 2021 at 160 rad/s it is 4.6–5.9× faster than
//!   DP5 at equal error at every rtol from 1e-6 to 1e-12, and at the same rtol 1.85× (1e-8)
//!   to 4.7× (1e-12) cheaper with a smaller error (there `h_max = 0.5` bounds its steps at
//!   rtol ≥ 1e-9); on Yu 2021 it wins from rtol 1e-9 down (1.5–1.8× at equal error) and
//!   loses at 1e-6 … 1e-8 (0.8–0.9×); at Liu 180 rad/s the end state is ill-conditioned
//!   (reference spread ≈ 1e-6), and at the same rtol DOP853 costs 1.2× DP5's at 1e-8 and
//!   1.6–2.7× less at 1e-10 … 1e-12. Under callgrind the Liu 160 rad/s run at rtol 1e-10 without
//!   events takes 76.8 M instructions for 17,919 steps and 215,031 right-hand sides (357
//!   instructions per evaluation, stepping included). Its step control is Hairer's `dop853`: error norm
//!   from the 5th- and 3rd-order estimates, `h_new = h · clamp(0.9/err^(1/8), 0.333, 6)`,
//!   with `err^(1/8)` from the shared controller's `log₂`/`2^x` kernels (no libm `pow`, no
//!   division or square root on the step's critical path; relative error below `10⁻⁸`).
//!   It is an own stepper rather than the `ode_solvers` backend brought up to it because that
//!   backend has no access to its stages: its dense output is a cubic Hermite, events need a
//!   solver restart per crossing and it allocates per stage. Measured on
//!   the same Liu 160 rad/s run at rtol 1e-8 (in one process, interleaved, on a loaded
//!   2-core machine), the `ode_solvers` backend takes ≈ 6.5 M steps and ≈ 14.6 s of CPU,
//!   the own DOP853 ≈ 12.5 k steps and ≈ 6 ms, at a 10⁵× smaller error.
//! * [`Method::Rk4`]: reference fixed-step runs, order checks.
//! * [`Method::OdeSolversDopri5`] / [`Method::OdeSolversDop853`]: cross-checks against an
//!   independent implementation. Their output between steps and the event location use a
//!   cubic Hermite interpolant (O(h⁴)); they allocate per stage (`DVector`) and are 4–5× slower
//!   on the benches' dead-zone oscillator, and 10³× slower on Liu 2021, whose many events
//!   each restart the solver.
//!
//! ## Limitations
//! * Forward integration only (`t_end ≥ t0`).
//! * A stored uniform output holds at most [`MAX_STORED_VALUES`] values (2 GiB); a finer grid
//!   is an error naming `output dt`. Stream it ([`integrate_streamed`]) instead.
//! * Two crossings of the same event function inside one accepted step (a grazing excursion
//!   shorter than a step) are not seen; bound the step with [`Options::h_max`] if that matters.
//! * Event times are as accurate as the integration itself (dense-output error ~ tolerance);
//!   `event_tol` is the root-finding tolerance on the interpolant, not a global accuracy.
//! * A right-hand side discontinuous *on* the surface is evaluated there from whichever side
//!   the state lies numerically; the backlash force `k f(q)` is continuous, so this does not
//!   arise for it.
//!
//! ## References
//! Hairer, Nørsett & Wanner, *Solving ODEs I*, 2nd ed., 1993 (DOPRI5, DOP853 §II.10, dense
//! output §II.6, step control); Benettin, Galgani, Giorgilli & Strelcyn, Meccanica 15 (1980) 9–30 (Lyapunov
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
mod control;
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
pub use driver::{MAX_STORED_VALUES, integrate, integrate_streamed};
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
