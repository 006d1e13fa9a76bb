//! Liu, Lv, Zhao 2021 — rattle of a noncircular face gear (NFG) under multifrequency parametric
//! excitation (Mech. Sci. 12:361).
//!
//! # Model
//!
//! A pinion driven at constant `ω₁` meshes with an NFG whose equivalent base radius follows the
//! instantaneous centre, `r_b2 = L[1 + β cos(ω_c t)]` (Eq. 8, from the ratio of Eq. 18 with
//! `L = r₁ i_j cos α (1+ε²)/(1−ε²)`, `β = 2ε/(1+ε²)`). With `q = q₂ + e/r_b2` and
//! `τ = ω_n t`, `ω_n = sqrt(k₀L²(1+β²/2)/I₂)` (Eq. 10), the NFG's elastic angle obeys (Eq. 9)
//!
//! ```text
//! q'' + 2ζ q' + F(τ) f(q; b̄) = −B₀ − d²θ₂/dτ² + d²ē/dτ²                      (9), (22)
//! F(τ) = [1 + a_k sin(ω̄_e τ + φ_m)] (1 + β cos ω̄_c τ)² / (1 + β²/2)
//! ```
//!
//! with the dead zone `f` of Eq. (12), `B₀ = T₂/(I₂ω_n²)`, `ω̄_c = ω₁/(i_j ω_n)`,
//! `ω̄_e = Z₂ ω̄_c`. Dimensional parameters: [`Parameters`] ([`table1`] is the paper's set);
//! [`Parameters::model`] builds the dimensionless [`Model`] (the only conversion point).
//!
//! # Readings
//!
//! The printed Eq. (20) (rigid acceleration), Eq. (21) (sign of the error term) and the
//! constant-vs-varying `r_b2` in `b̄`, `ē` are selectable through [`Readings`]; the default is
//! the consistent derivation, [`Readings::printed`] the paper as printed. See
//! `docs/readings/liu.md` (`R-LIU-EQ20`, `R-LIU-EQ21`, `R-LIU-EQ11`) for the evidence.
//!
//! # Solvers
//!
//! * [`solve_hbm_with`] — harmonic balance with AFT (Eq. 13–17) through the `hbm` engine, on the
//!   paper's sparse basis ([`Basis::PAPER`], 15 unknowns) or a full basis ([`Basis::Full`],
//!   [`HbmOptions::full`]); Newton with the exact AFT Jacobian instead of the paper's Broyden.
//!   The [`HbmStart`] picks the branch: [`HbmStart::Cold`] (quasi-static contact position, the
//!   no-rattle/unilateral branch), [`HbmStart::FromTimeResponse`] (warm start: the harmonics of
//!   a time-integrated period, [`coefficients_from_time_response`]) or [`HbmStart::Given`]
//!   (a neighbouring solution: sequential continuation). [`solve_hbm`] and
//!   [`solve_hbm_from_time_response`] are shorthands; [`PreparedHbm`] is the sweep form (the
//!   problem, FFT plans and buffers built once, re-solved at each speed or load).
//! * [`continue_in_speed`] — pseudo-arclength continuation in `ω₁` (the engine's frequency
//!   continuation with [`Model::with_omega_c`]), reporting folds (the jumps) and stability
//!   ([`BranchStability`], by default the period map of the ODE: [`shooting_multipliers`],
//!   the shooting monodromy of `orbit` at the harmonic-balance state).
//! * [`integrate()`] — the `timestep` engine (adaptive Dormand–Prince with the gap edges
//!   `q = ±b̄` as located events) over whole periods `T = 2π/ω̄_c`, on [`TimeSystem`] (Eq. 9
//!   written lean; [`Trig`] chooses the platform's `sin`/`cos`, bit-identical to the generic
//!   adapter, or the default short kernel, rounding-level different and about twice as fast).
//!
//! * [`solve_sweep`] / [`solve_point`] — the solution strategy in one call: time-integration
//!   reference with its Poincaré motion type and a 100×-tighter-tolerance repeat, HBM cold, warm
//!   from the time response and from converged neighbours, period-map stability, and flags
//!   ([`HbmPoint::flag`], [`TimeReference::flag`]) instead of errors on non-convergence
//!   ([`SweepStrategy`]).
//!
//! All give a [`Rattle`] (rsv, ppv). Which when: time integration is the reference for the
//! rattle state from rest (≈ 20 ms per point in release); HBM is fast (≈ 3 ms on the paper
//! basis, ≈ 20 ms on K = 65) and gives spectra and branches. From a cold start it stays on the
//! unilateral branch; warm-started from the time response it converges on bilateral branches
//! where that response is T-periodic (ω₁ sweep: 61/61 points with neighbour starts, against
//! 35/61 cold); continuation shows the hysteresis (unilateral-branch fold at 178.8 rad/s,
//! K = 65, 185.5 on the paper basis) behind the ppv jump.
//!
//! # Limitations
//!
//! * Constant damping ratio (the paper's assumption); `φ₂ ≈ ω_c t` in Eq. (18).
//! * With the default time-varying `b̄(τ)` the paper's 15-term basis cannot represent the
//!   quasi-static `1/r_b2(τ)` shape and misreports rattle; use a full basis, or the constant-b̄
//!   reading the paper's figures follow (`BaseRadius::Mean`).
//! * Several periodic responses coexist near the onset of bilateral rattle; a sweep from rest
//!   is not a continuation. Where the time response is not T-periodic no stable HBM solution
//!   exists.
//! * The engine's Floquet multipliers are meaningless along truncated impacting orbits
//!   (`R-LIU-STABILITY`); use [`BranchStability::Shooting`].
//!
//! # References
//!
//! Liu, Lv, Zhao (2021), Mech. Sci. 12, 361–373, Eq. (1)–(23), Table 1–2. Theory as
//! implemented: `docs/models/liu2021.md`; performance: `docs/performance/models-liu.md`.
//!
//! # Example
//!
//! ```
//! use geardyn_models::liu2021::{self, BaseRadius, HbmOptions};
//! let mut p = liu2021::table1();
//! p.omega1 = 120.0; // below the unilateral-rattle threshold
//! p.readings.base_radius = BaseRadius::Mean; // constant b̄, as the paper's figures (R-LIU-EQ11)
//! let model = p.model()?;
//! let sol = liu2021::solve_hbm(&model, &HbmOptions::default(), None)?;
//! assert!(sol.converged());
//! assert_eq!(sol.rattle.state.rsv(), 0);
//!
//! // bilateral rattle at 220 rad/s: warm-start HBM from a period of the settled response
//! // (after the default 2 periods the response is still a transient whose harmonics may not
//! // lead Newton to the orbit)
//! p.omega1 = 220.0;
//! let model = p.model()?;
//! let settled = liu2021::IntegrationOptions {
//!     transient_periods: 12.0,
//!     ..liu2021::IntegrationOptions::default()
//! };
//! let ti = liu2021::integrate(&model, &settled)?;
//! let warm = liu2021::solve_hbm_with(
//!     &model,
//!     &HbmOptions::default(),
//!     liu2021::HbmStart::FromTimeResponse(&ti),
//! )?;
//! assert!(warm.converged());
//! assert_eq!(warm.rattle.state.rsv(), 2);
//! # Ok::<(), geardyn_models::Error>(())
//! ```

mod continuation;
mod harmonic;
mod integrate;
mod model;
mod ode;
mod parametric;
mod params;
mod presets;
pub mod registry;
mod strategy;
mod table;
mod window;

pub use continuation::{
    BranchStability, SpeedBranch, SpeedBranchPoint, SpeedContinuationOptions, SpeedPoint,
    add_branch_stability, continue_in_speed, shooting_multipliers, shooting_period_map,
    shooting_stability,
};
pub use harmonic::{
    Basis, HbmOptions, HbmResponse, HbmStart, PerThreadHbm, PreparedHbm,
    coefficients_from_time_response, solve_hbm, solve_hbm_from_time_response, solve_hbm_with,
};
pub use integrate::{
    AUTO_DOP853_ONE_FLANK_RTOL, AUTO_DOP853_RTOL, IntegrationOptions, Stepping, TimeResponse,
    bifurcation_point, integrate,
};
pub use model::{Model, Rattle, RattleState};
pub use ode::{TimeSystem, Trig};
pub use parametric::{PARAMETERS as CONTINUATION_PARAMETERS, Parametric};
pub use params::{
    BaseRadius, ErrorTerm, Parameters, Readings, RigidAcceleration, RigidSeries, table1,
};
pub use presets::{Rig, TABLE2_THEORETICAL};
pub use strategy::{
    HbmOrigin, HbmPoint, Motion, SweepPoint, SweepStrategy, TimeReference, classify_section,
    is_stable_multiplier, max_multiplier, solve_point, solve_sweep, time_reference,
};
pub use table::TimeTable;
pub use window::{
    LongWindowOptions, MAX_WINDOW_SAMPLES, SettledWindow, long_window, robust_window,
    settled_window,
};
