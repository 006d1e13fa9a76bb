//! # geardyn-orbit
//!
//! Periodic orbits of rattling and impacting systems: shooting on the event-located flow with
//! saltation matrices, Floquet multipliers with their conditioning, Lyapunov exponents of the
//! non-smooth flow, and pseudo-arclength continuation through grazing, period doubling and
//! folds, for any
//! [`SecondOrderSystem`](system::SecondOrderSystem) (every model of the registry).
//!
//! ## The flow and its variational equations
//!
//! With `x = (q, q')` the system `M q'' + C q' + K q + g(t, q, q') = f(t)` reads
//!
//! ```text
//! x' = F(t, x) = ( q',  M⁻¹ (f(t) − C q' − K q − g(t, q, q')) )
//! Φ' = A(t, x) Φ,   A = [[0, I], [−M⁻¹(K + ∂g/∂q), −M⁻¹(C + ∂g/∂q')]],   Φ(t₀) = I
//! ```
//!
//! integrated together by an adaptive Runge–Kutta pair, Dormand–Prince 5(4) by default or
//! Hairer's DOP853 ([`FlowMethod`], [`FlowOptions::method`]; error control on `x`; `Φ` rides
//! on the same stages, so it is the derivative of the discrete step). The zeros of the
//! event functions `h_i(t, q, q')` ([`events`](system::SecondOrderSystem::events), e.g. the gap
//! edges `q = ±b` where the backlash force kinks) are located in every step by Illinois on the
//! step fraction (re-stepping from the step's start); no step straddles a switch, and the
//! Jacobian of a step that ends on a switch is taken on its own side. An accepted step right
//! after a rejection does not grow; optionally a step rejected across a switch is retried to
//! just past the linearly estimated crossing ([`FlowOptions::crossing_retry`], off by default).
//!
//! ## Saltation matrices
//!
//! At an event at time `t_e` with reset `x⁺ = R(x⁻)` (identity unless an [`ImpactLaw`] says
//! otherwise) the Jacobian jumps by the saltation matrix (Müller 1995; Leine & Nijmeijer,
//! *Dynamics and Bifurcations of Non-smooth Mechanical Systems*, 2004, Sec. 7.2)
//!
//! ```text
//! Φ(t_e⁺) = S Φ(t_e⁻),   S = G + (f⁺ − G f⁻) ∇hᵀ / (∇hᵀ f⁻ + ∂h/∂t),   G = ∂R/∂x
//! ```
//!
//! with `f^∓` the vector field before and after the event. For a gear mesh whose force is
//! continuous and only kinks at the gap edges (dead zone), the state is continuous (`G = I`)
//! and `f⁺ = f⁻`, so **`S = I`**: the kinks enter the monodromy only through `A` changing
//! along the orbit. [`EventRecord::saltation_jump`] reports `‖S − G‖` (≈ 1e-12 at kinks,
//! tested). For an impact law with restitution `q'⁺ = −r q'⁻` ([`Restitution`]) on a stop
//! `h = q − σ`, `S = [[−r, 0], [(a⁺ + r a⁻)/v⁻, −r]]` (`a^∓` the accelerations), which the
//! tests check against the closed-form period-1 orbit of the impact oscillator.
//!
//! ## Shooting
//!
//! [`OrbitProblem::shoot`]: Newton on the matching conditions of `m` segments of the orbit
//! period `kT` (the forcing period `T` times `k`, period-`k` orbits), `τ = kT/m`,
//!
//! ```text
//! r_j = φ(t₀ + (j+1)τ; t₀ + jτ, x_j) − x_{j+1 mod m} = 0,   ∂r_j/∂x_j = Φ_j,  ∂r_j/∂x_{j+1} = −I
//! ```
//!
//! (`m = 1`: single shooting, `(Φ − I) δ = −r`), with a backtracking line search, an iteration
//! cap, and [`OrbitError::NotConverged`] when it fails. The monodromy is
//! `Φ = Φ_{m−1} ⋯ Φ_0`.
//!
//! ## Floquet multipliers
//!
//! [`floquet()`]: the eigenvalues `μ` of the monodromy (real Schur form), each with its
//! condition number `κ(μ) = ‖x‖‖y‖/|yᴴx|` (right and left eigenvectors by inverse iteration):
//! an error `E` in `Φ` moves `μ` by about `κ ‖E‖`. Stable if `max |μ| ≤ 1 + 10⁻⁶`. The test
//! functions `det(Φ + I)` (a real multiplier at `−1`), `det(Φ − I)` (at `+1`) and
//! `Π_{i<j}(μ_iμ_j − 1)` (a pair on the unit circle) change sign at period doubling, fold and
//! Neimark–Sacker points; [`classify_crossing`] names the crossing between two sets of
//! multipliers from the count outside the unit circle.
//!
//! ## Lyapunov exponents
//!
//! [`OrbitProblem::lyapunov`] runs the variational flow above over windows of length `τ`
//! (e.g. the forcing period), composed with the saltation matrix at every event. After each
//! window the tangent basis is re-orthonormalised by QR (Benettin, Galgani, Giorgilli &
//! Strelcyn 1980; Shimada & Nagashima 1979; Müller 1995 for the saltation matrices):
//!
//! ```text
//! Φ_j = Φ(t_j + τ ← t_e,m) S_m ⋯ S_1 Φ(t_e,1 ← t_j),     Φ_j Q_j = Q_{j+1} R_j
//! λ_i ≈ Λ_i(N) = (1 / Nτ) Σ_{j<N} ln R_j,ii,     Q_0 = [e_1 … e_k]
//! ```
//!
//! The QR is modified Gram–Schmidt with the columns in a fixed order. [`lyapunov_qr`] is the
//! one home of the renormalisation: it takes any window map, so a first-order system can use it
//! too (the Lorenz test). Optional warm-up windows ([`LyapunovOptions::warmup`]) align `Q`
//! before the sum starts. The result, [`LyapunovSpectrum`], holds the running estimate after
//! every window and its spread over the last `K` windows and over the last half. It is
//! converged when every spread is at most `rtol |Λ_i| + atol/τ`. Two exact statements are
//! tested:
//!
//! * **Volume.** `Σ_i Λ_i N τ = ln |det Π Φ_j|`, and `det Φ = exp(∫ tr A) Π det S`. With
//!   linear damping, `tr A = −tr(M⁻¹C)` whatever the stiffness does, and `det S = 1` at a kink.
//!   At a restitution impact, `det S = r²`. So `Σλ = −tr(M⁻¹C) + N_imp ln r² / (Nτ)`.
//! * **Periodic orbits.** With `τ = T` on a period-`T` orbit, the iteration is the orthogonal
//!   iteration on the monodromy, and `Λ_i → ln|μ_i|/T`.
//!
//! ## The one continuation
//!
//! Every branch of the workspace comes from one loop, [`path::trace`], generic over a
//! [`path::Corrector`]. With unknowns `y = (z, μ)`, the branch `F(y) = 0` (`F: ℝ^{N+1} → ℝ^N`)
//! and `J = [F_z | F_μ]`:
//!
//! ```text
//! tangent     [J(y_i); t_{i−1}ᵀ] v = e_{N+1},   t_i = v/‖v‖        (t_{i−1}ᵀ t_i > 0)
//! arclength   y_p = y_i + Δs t_i,                F(y) = 0,  t_iᵀ (y − y_p) = 0
//! natural     y_p = y_i + (±Δs / t_{i,μ}) t_i,   F(y) = 0,  e_{N+1}ᵀ (y − y_p) = 0
//! fold        t_{i,μ} t_{i+1,μ} < 0,   μ_F = μ_i + ½ t_{i,μ} σ,   σ = t_{i,μ} Δs/(t_{i,μ} − t_{i+1,μ})
//! ```
//!
//! ([`Predictor`]; the natural corrector holds `μ`, so it stops at a fold with
//! [`StopReason::StepTooSmall`], where pseudo-arclength goes round it). Step control
//! ([`StepControl`]): halve after a rejection (corrector failure, a correction longer than
//! `max_correction · Δs`, a tangent turn with `cos < min_cos`), grow after success (always, or
//! only after easy corrections), stop below the minimum. A branch that crawls — the mean of
//! its last [`Stall::points`] accepted steps below [`Stall::step`], as in a non-smooth tangle
//! where the contact set changes at nearly every step — stops with [`StopReason::Stalled`] when
//! [`ContinuationOptions::stall`] is set; a shooting branch stops after the first special point
//! of a kind in [`ShootingCorrection::stop_at`] ([`StopReason::SpecialPoint`], AUTO's `STOP`
//! list), or at its first unstable point after a stable one when
//! [`ShootingCorrection::stop_at_instability`] is set ([`StopReason::LostStability`]). Every
//! continuation takes the one
//! [`ContinuationOptions<C>`](ContinuationOptions) (step bounds, point cap, predictor, stall) with its
//! corrector's part `C` ([`ShootingCorrection`], [`HbmCorrection`]). The correctors: the shooting residual
//! below; the harmonic-balance residual of `hbm` ([`continue_hbm`]: Newton with line search on
//! `[r(z, λ); bᵀ(y − y_p)] = 0`, `∂r/∂λ` by central differences, Floquet stability by the RK4
//! monodromy of `hbm`); a model's own (the Liu speed continuation maps [`continue_hbm`] to
//! `ω₁`). Every branch is one type, [`Branch<P>`](Branch) of [`BranchPoint<P>`](BranchPoint)
//! `{ parameter, tangent_parameter, stability, orbit: P }` with the one
//! [`Stability`]; [`fill_from_neighbours`] is the sequential (zero-order
//! predictor) continuation of a fixed sweep grid.
//!
//! ## Pseudo-arclength continuation of shooting orbits
//!
//! [`OrbitProblem::continuation`] continues `z = (x₀/s_x, λ/s_λ)` along
//! `F(z) = φ_{kT}(x₀; λ) − x₀ = 0` in any [`Parameter`] (a named model parameter, or the base
//! frequency with `T = 2π/ω`):
//!
//! ```text
//! predictor  z_p = z_i + Δs t_i,             t_i the unit null vector of [(Φ − I) s_x | F_λ s_λ]
//! corrector  F(z) = 0,  t_iᵀ (z − z_p) = 0   (Newton, F_λ by central differences)
//! ```
//!
//! through [`path::trace`] ([`StepControl::shooting`]: halving on failure, growth by 1.5 after
//! success, corrections limited to `max_correction · Δs`). Between consecutive points the test
//! functions are checked: the minimum and maximum of every event (gap) function over the
//! orbit (**grazing**: the orbit touches a switching surface and contacts appear or vanish),
//! `det(Φ + I)` (**period doubling**), the `λ`-component of the tangent (**fold**), and the
//! unit-circle count (**Neimark–Sacker**). Each is located by Illinois on the arclength of
//! the step, re-correcting at every trial, with bisection on the sign as the fallback (a test
//! function that jumps at a contact change, a corrector that stalls next to a grazing); a
//! change of the crossing count of an event (a *local* extremum grazing,
//! [`SpecialKind::ContactChange`]) is located by bisection on the count when
//! [`ShootingCorrection::locate_contact_changes`] is set. Every special point carries its
//! parameter bracket ([`SpecialPoint::bracket`]). On non-smooth branches the multipliers jump
//! at contact changes and a test function can flip several times within one step;
//! [`ShootingCorrection::locate_samples`] samples the step first and locates the first flip.
//! Stable and unstable points are kept alike.
//! [`OrbitProblem::switch_at_period_doubling`] starts the period-`2k` branch from
//! `x_PD ± h v` (`v` the `−1` eigenvector), shooting over `2kT`.
//!
//! ## Codim-2 continuation
//!
//! [`OrbitProblem::continue_codim2`] continues a special point located on a one-parameter
//! shooting branch in `λ₁` ([`Codim2Correction::first`]) in a second parameter `λ₂`
//! ([`Codim2Correction::parameter`]), with `λ₁` among the unknowns, through the same
//! [`path::trace`] (step control [`StepControl::shooting`], [`StopReason`]s, the one
//! [`Branch`], here [`Codim2Branch`] of [`Codim2Point`]s). With the scaled unknowns
//! `ξ = x₀/s_x`, `μ_j = λ_j/s_j`:
//!
//! ```text
//! grazing of h_i   y = (ξ, θ, μ₁, μ₂),  t_g = t₀ + θ kT (θ mod 1)
//!                  φ_{kT}(x₀) − x₀ = 0
//!                  h_i(t_g, x(t_g)) = 0                     (touches the surface …
//!                  ḣ_i(t_g, x(t_g)) kT/2π = 0                … tangentially)
//! fold / PD        y = (ξ, μ₁, μ₂)
//!                  φ_{kT}(x₀) − x₀ = 0
//!                  g = 0,  [[Φ ∓ I, b], [cᵀ, 0]] [v; g] = [0; 1]   (minimally augmented)
//! ```
//!
//! The Jacobian: `[Φ − I]s_x` for the shooting rows; for the grazing rows
//! `∇h(x_g) Φ(t_g, t₀) s_x`, `∇ḣ(x_g) Φ(t_g, t₀) s_x` (the flow split at `t_g`,
//! `Φ = Φ(t₀ + kT, t_g) Φ(t_g, t₀)`), the `θ` column `(ḣ, ḧ kT/2π) kT`; `ḣ = ∂h/∂t + ∇h·f`
//! and `ḧ` by central differences along the vector field, `∇` by central differences in the
//! state; the state columns of `g` by central differences of the variational flow; both
//! parameter columns by central differences of the whole residual. The borders `b`, `c` start
//! as the left and right singular vectors of `Φ ∓ I` at the located point and follow the
//! bordered system's null vectors at every accepted point. A grazing of the maximum of `h`
//! needs `ḧ < 0` at `t_g`, of the minimum `ḧ > 0`.
//!
//! Along the curve every point carries its Floquet multipliers; the codim-2 points met are
//! listed in [`Branch::special`] (a sign change between two points, located by Illinois on
//! the arclength, re-correcting the augmented system at every trial; bracket in `λ₂`): on a
//! grazing curve a sign change of `det(Φ − I)` ([`SpecialKind::Fold`]: the grazing meets a
//! fold) or of `det(Φ + I)` ([`SpecialKind::PeriodDoubling`]), and another event function's
//! (or the other) extremum crossing zero ([`SpecialKind::Grazing`]: a second contact, the
//! grazing flank changes); on a fold or PD curve the grazings and the other test function.
//! A turn of the curve in `λ₂` (a cusp of two folds, a grazing curve's extremum in `λ₂`) is a
//! [`Fold`] of the curve. The curve **stops with a named reason** rather than continue
//! wrongly ([`StopReason::Degenerate`]): [`Degeneracy::GrazingCurvature`] where
//! `|ḧ|(kT/2π)² < curvature_tol · ½(max h − min h)` (the tangency is no longer quadratic),
//! [`Degeneracy::GrazingNotGlobal`] where the event function's global extremum passes the
//! tangency (the orbit crosses the surface elsewhere: the curve no longer bounds contact),
//! [`Degeneracy::SingularBordered`] where the bordered matrix is singular; and
//! [`StopReason::FirstLeftRange`] where `λ₁` leaves [`Codim2Correction::first_range`].
//!
//! A [`SpecialKind::ContactChange`] (a *local* extremum of `h_i` touching zero while the
//! global ones keep their sign) is continued as the grazing of that local extremum: the same
//! augmented system at its phase, without the global-extremum check. The start's orbit is
//! searched for the local extrema of `h_i` other than the global maximum and minimum,
//! nearest zero first; the first whose corrected point lies in the start's bracket (widened
//! for the lag of the count-located bracket) is continued, at most
//! [`CONTACT_CANDIDATES`] tried, else [`OrbitError::NotConverged`].
//!
//! The boundary of contact is the envelope of the grazing curves of the event function's local
//! extrema (for a gear, one per mesh period): [`OrbitProblem::continue_grazing_envelope`]
//! follows it, starting a new piece at each [`Degeneracy::GrazingNotGlobal`] stop on the
//! extremum that is global there. The double grazing is bisected in `λ₂` on the old piece
//! first; the new piece goes on forward (the two curves cross) or back from the bracket's
//! global end (the envelope has a corner and turns back in `λ₂`), and a restart whose first
//! point is again not global hops to the extremum global on its own orbit (several extrema
//! near the surface at once). [`EnvelopeEnd`] says how it ended. For
//! an impacting stop (an [`ImpactLaw`]) the flow is not `C¹` at a grazing (square-root
//! singularity): the grazing rows are then exact but Newton converges poorly; the tested
//! systems are piecewise-smooth with a continuous force (bilinear, dead zone).
//!
//! ## Accuracy and limits
//!
//! * The extrema of the gap functions are refined by golden-section search inside the steps
//!   around the sampled extremum; a gap function that leaves and re-enters its sign within one
//!   step is not seen (bounded by [`FlowOptions::max_step_fraction`]).
//! * Grazing of an impacting stop makes `S` singular (`v⁻ → 0`): the flow reports
//!   [`OrbitError::TangentialEvent`] only when `dh/dt` is exactly zero; near it, Newton may
//!   need small continuation steps.
//! * Continuation shoots singly (`segments = 1`); very unstable orbits (`|μ| ≫ 10⁸`) want
//!   multiple shooting ([`OrbitProblem::shoot`] with `segments > 1`).
//!
//! ## Example
//!
//! ```
//! use nalgebra::DMatrix;
//! use orbit::{OrbitProblem, ShootingOptions};
//! use system::SecondOrderSystem;
//!
//! /// q'' + 0.1 q' + dz(q, 0.2) = 0.5 + 0.3 cos(0.9 t): a loaded rattling mesh.
//! struct Mesh;
//! impl SecondOrderSystem for Mesh {
//!     fn n_dof(&self) -> usize { 1 }
//!     fn mass(&self) -> DMatrix<f64> { DMatrix::identity(1, 1) }
//!     fn damping(&self) -> DMatrix<f64> { DMatrix::from_element(1, 1, 0.1) }
//!     fn nonlinear_force(&self, _t: f64, q: &[f64], _v: &[f64], g: &mut [f64]) {
//!         let b = 0.2;
//!         g[0] = if q[0] > b { q[0] - b } else if q[0] < -b { q[0] + b } else { 0.0 };
//!     }
//!     fn forcing(&self, t: f64, f: &mut [f64]) { f[0] = 0.5 + 0.3 * (0.9 * t).cos(); }
//!     fn n_events(&self) -> usize { 2 }
//!     fn events(&self, _t: f64, q: &[f64], _v: &[f64], e: &mut [f64]) {
//!         system::gap_edges(q[0], 0.2, e);
//!     }
//! }
//!
//! let p = OrbitProblem::new(Mesh, 2.0 * std::f64::consts::PI / 0.9)?;
//! let o = p.shoot(&[0.7, 0.0], &ShootingOptions::default())?;
//! assert!(o.events.len() >= 2); // contact lost and regained once per period
//! assert!(o.events.iter().all(|e| e.saltation_jump < 1e-8)); // S = I at the kinks
//! assert!(o.floquet.stable);
//! # Ok::<(), orbit::OrbitError>(())
//! ```

#![deny(missing_docs)]

mod codim2;
mod continuation;
mod error;
mod floquet;
mod flow;
mod harmonic;
mod impact;
mod lyapunov;
pub mod path;
mod problem;
mod shooting;

pub use codim2::{
    CONTACT_CANDIDATES, Codim2Branch, Codim2BranchPoint, Codim2ContinuationOptions,
    Codim2Correction, Codim2Point, EnvelopeEnd, GrazingEnvelope, MAX_ENVELOPE_SWITCHES,
};
pub use continuation::{
    ShootingBranch, ShootingBranchPoint, ShootingContinuationOptions, ShootingCorrection,
    ShootingPoint,
};
pub use error::{OrbitError, Result};
pub use floquet::{
    Crossing, Floquet, OutsideCount, STABILITY_TOLERANCE, Stability, classify_crossing, floquet,
    real_eigenvector,
};
pub use flow::{EventRecord, Flow, FlowMethod, FlowOptions};
pub use harmonic::{HbmContinuationOptions, HbmCorrection, continue_hbm};
pub use impact::{ImpactLaw, Restitution};
pub use lyapunov::{
    LyapunovOptions, LyapunovSpectrum, MAX_LYAPUNOV_WINDOWS, WindowMap, lyapunov_qr,
};
pub use path::{
    Branch, BranchPoint, ContinuationOptions, Degeneracy, Extremum, Fold, Predictor, SpecialKind,
    SpecialPoint, Stall, StepControl, StopReason, fill_from_neighbours,
};
pub use problem::{OrbitProblem, Parameter};
pub use shooting::{PeriodicOrbit, ShootingOptions};

/// The README's example, compiled and run as a doctest so that it cannot rot.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctest;
