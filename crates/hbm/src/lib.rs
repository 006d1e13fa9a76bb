//! # hbm — harmonic balance for periodic responses of nonlinear second-order systems
//!
//! `hbm` computes steady periodic responses of `n`-DOF systems
//!
//! ```text
//! M q''(t) + C q'(t) + K q(t) + g(t, q, q') = f(t),      g, f periodic with T = 2π/ω,
//! ```
//!
//! by the harmonic balance method (HBM) with the alternating frequency/time (AFT) scheme, the
//! approach of Liu, Lv & Zhao (2021, *Mech. Sci.* 12:361, Eq. 13–17) for gear rattle — but
//! generic: it knows nothing about gears. A model implements [`SecondOrderSystem`] (mass,
//! damping, optional stiffness, the nonlinear/time-varying force `g`, its Jacobians, the
//! forcing `f`).
//!
//! ## Method
//! * **Ansatz.** `q(t) = a_0 + Σ_{k∈B} a_k cos(kωt) + b_k sin(kωt)` over a [`Basis`] `B`:
//!   the full basis `1..H` ([`Basis::full`]), any set ([`Basis::from_harmonics`]), or Liu's
//!   sparse multifrequency basis of Eq. (13) ([`Basis::liu_multifrequency`]): with
//!   `ω = ω_c` and `ω_e = Z_2 ω_c`, the harmonics `ω_c, 2ω_c, rω_e ± {0,1,2}ω_c` (`r = 1..R`),
//!   i.e. `10R + 5` unknowns per DOF. A basis is a set of integers, so it can be used with any
//!   base frequency.
//! * **AFT** (Liu Eq. 15–17). Coefficients → `q, q'` on `N` samples (one inverse FFT per DOF,
//!   rustfft) → `h = g − f` → Fourier coefficients (forward FFT). The linear part is exact in
//!   the frequency domain. `N` defaults to the smallest power of two `> 4 k_max`, which keeps
//!   products up to cubic free of aliasing; raise it for non-smooth forces
//!   ([`HbmProblem::with_grid_size`]).
//! * **Jacobian** by the same route: the Fourier coefficients of `∂g/∂q(t)` and `∂g/∂q'(t)`
//!   (FFT) are convolved into the exact derivative of the discrete residual.
//! * **Solvers**: [`Newton`] with a backtracking line search (default) and [`Broyden`]
//!   (inverse update, Liu's choice), both argmin 0.11 `Solver`s run by argmin's `Executor`;
//!   non-convergence is returned in [`PeriodicSolution::converged`].
//! * **Dense linear solves**: each dense Newton step factors `P J = L U`, by nalgebra's LU or,
//!   from [`AUTO_BLOCKED_LU_UNKNOWNS`] unknowns, by [`BlockedLu`], a blocked right-looking LU
//!   whose trailing updates `A22 −= L21 U12` are matrix products (`gemm`); the choice is
//!   [`DenseLu`] ([`HbmProblem::set_dense_lu`], [`solve_equations_with`]). At 801 unknowns
//!   the blocked LU is about 4× faster than nalgebra's.
//! * **Large bases**: [`Method::NewtonKrylov`] never forms the Jacobian: each Newton step is a
//!   restarted GMRES solve of `J δ = −r` with products `J v` by AFT
//!   (`δh(t_m) = ∂g/∂q(t_m) δq(t_m) + ∂g/∂q'(t_m) δq'(t_m)`, exact for the discrete residual),
//!   right-preconditioned by the harmonic-diagonal Jacobian of the period-mean force Jacobians
//!   `J̄_q`, `J̄_v`: per harmonic `k` the block `[[D, kωC̄], [−kωC̄, D]]`, `D = K + J̄_q − (kω)²M`,
//!   `C̄ = C + J̄_v`. `O(N log N)` per product instead of `O(n_z³)` per step; bounded by
//!   [`KrylovOptions`], a missed linear tolerance is [`HbmError::KrylovNotConverged`].
//!   [`Method::Auto`] switches at [`AUTO_KRYLOV_UNKNOWNS`].
//! * **Continuation** is not here: the workspace's one continuation (natural and
//!   pseudo-arclength, step control, folds, the one branch type) is in the `geardyn-orbit`
//!   crate, whose `orbit::continue_hbm` uses this crate's residual, Jacobian and Newton
//!   ([`solve_equations`] on a bordered [`NonlinearEquations`]) as its corrector.
//! * **Stability** ([`HbmProblem::stability`]): Floquet multipliers of the variational
//!   equation (RK4 monodromy matrix).
//! * **Output**: coefficients, [`PeriodicSolution::time_series`], peak-to-peak values,
//!   [`PeriodicSolution::harmonic_amplitudes`], truncation indicators
//!   ([`PeriodicSolution::spectral_tail`], [`HbmProblem::truncation_estimate`]).
//! * **Accuracy of every solution**: [`PeriodicSolution::residual_norm`] `‖r‖₂` (how well the
//!   retained harmonics balance) and [`PeriodicSolution::truncation`] (how much of the force the
//!   basis discards), from the AFT spectrum `ĥ_{i,k}` of `h_i = g_i − f_i` at the solution:
//!
//!   ```text
//!   ε = sqrt( Σ_i Σ_{k∈T} |ĥ_{i,k}|² ) / sqrt( Σ_i Σ_{k∈B₀} |ĥ_{i,k}|² ),
//!   B₀ = {0} ∪ basis,   T = {1 ≤ k < N/2} \ B₀.
//!   ```
//!
//!   `ε = 0` for a linear system forced inside the basis; for `q = A cos θ` of a Duffing
//!   oscillator on `{0, 1}`, `ε = (γA³/4)/|¾γA³ − F|` (the cubed cosine's 3rd harmonic); `ε ~ 1`
//!   for an impact on a short basis. It is an indicator, not an error bound: what the response
//!   loses is `ε` filtered by the linear part (`|K − (kω)²M + ikωC|⁻¹` at the discarded `k`);
//!   [`HbmProblem::truncation_estimate`] measures the response change directly, at the cost of
//!   a solve in a larger basis.
//! * **Sweeps**: [`parallel_sweep`] (rayon), bit-identical for any thread count.
//!
//! ## Which method when
//! Newton is the robust default (quadratic convergence, a line search for large steps).
//! Broyden saves Jacobian evaluations when the Jacobian is expensive (many DOFs, finite-difference
//! Jacobians); it re-initialises from the exact Jacobian when a secant step fails. Use
//! continuation (not a sweep from a fixed guess) wherever the response may be multivalued.
//!
//! ## Limitations
//! * Non-smooth forces (dead zones, impacts) converge slowly in `H` (the response has a
//!   discontinuous higher derivative); AFT aliasing is then reduced, not removed, by a larger `N`.
//! * Quasi-periodic responses (incommensurate frequencies) are out of scope: all frequencies
//!   must be integer multiples of one base frequency.
//! * Stability uses fixed-step RK4: it must resolve the fastest linearised frequency.
//!
//! ## References
//! * Liu, Lv, Zhao (2021), *Rattle dynamics of noncircular face gear under multifrequency
//!   parametric excitation*, Mech. Sci. 12, 361–373 — Eq. (13) basis, Eq. (15)–(17) DFT, Broyden.
//! * Cameron & Griffin (1989), AFT; Krack & Gross (2019), *Harmonic Balance for Nonlinear
//!   Vibration Problems* (Springer) — residual, Jacobian, continuation.
//!
//! ## Example: a piecewise-linear (dead-zone) oscillator
//! `q'' + 2ζ q' + f(q) = F_0 + F cos ωt` with `f(q) = q − b` for `q > b`, `0` for `|q| ≤ b`,
//! `q + b` for `q < −b` (the 1-DOF backlash model).
//!
//! ```
//! use geardyn_hbm::{Basis, HbmProblem, SecondOrderSystem, SolverOptions};
//! use nalgebra::DMatrix;
//!
//! struct DeadZone { zeta: f64, b: f64, f0: f64, f1: f64, omega: f64 }
//!
//! impl SecondOrderSystem for DeadZone {
//!     fn n_dof(&self) -> usize { 1 }
//!     fn mass(&self) -> DMatrix<f64> { DMatrix::identity(1, 1) }
//!     fn damping(&self) -> DMatrix<f64> { DMatrix::from_element(1, 1, 2.0 * self.zeta) }
//!     fn nonlinear_force(&self, _t: f64, q: &[f64], _qd: &[f64], g: &mut [f64]) {
//!         g[0] = if q[0] > self.b { q[0] - self.b } else if q[0] < -self.b { q[0] + self.b } else { 0.0 };
//!     }
//!     fn force_jacobian(&self, _t: f64, q: &[f64], _qd: &[f64], dq: &mut [f64], dv: &mut [f64]) {
//!         dq[0] = if q[0].abs() > self.b { 1.0 } else { 0.0 };
//!         dv[0] = 0.0;
//!     }
//!     fn forcing(&self, t: f64, f: &mut [f64]) {
//!         f[0] = self.f0 + self.f1 * (self.omega * t).cos();
//!     }
//!     // the excitation follows the HBM base frequency (needed for frequency continuation)
//!     fn set_base_frequency(&mut self, omega: f64) -> Result<(), geardyn_hbm::SystemError> {
//!         self.omega = omega;
//!         Ok(())
//!     }
//! }
//!
//! let omega = 0.5;
//! let sys = DeadZone { zeta: 0.05, b: 0.1, f0: 0.2, f1: 0.1, omega };
//! let mut hb = HbmProblem::with_grid_size(sys, Basis::full(15)?, omega, 256)?;
//! let mut z0 = hb.zero_guess();
//! z0[0] = 0.3; // start in contact (mean deflection F_0 + b)
//! let sol = hb.solve(&z0, &SolverOptions::default())?;
//! assert!(sol.converged);
//! let ptp = sol.peak_to_peak(0).unwrap();
//! assert!(ptp > 0.0);
//! # Ok::<(), geardyn_hbm::HbmError>(())
//! ```
#![deny(missing_docs)]

mod band;
mod basis;
mod error;
mod krylov;
pub mod lu;
mod plans;
mod problem;
mod solution;
mod solve;
mod stability;
mod sweep;
mod system;

/// The argmin this crate's solvers are built on ([`Newton`] and [`Broyden`] are
/// `argmin::core::Solver`s, [`SolverState`] an argmin state), re-exported for the same reason.
pub use argmin;
/// The nalgebra this crate's API uses ([`SecondOrderSystem`] returns `DMatrix<f64>`), re-exported
/// so that users implement the trait against the same version.
pub use nalgebra;

pub use basis::{Basis, CoefficientKind};
pub use error::HbmError;
pub use krylov::{KrylovOptions, MAX_BAND_HARMONICS, Preconditioner};
pub use lu::{AUTO_BLOCKED_LU_UNKNOWNS, BlockedLu, DEFAULT_LU_BLOCK, DenseLu};
pub use problem::{Counters, HbmProblem};
pub use solution::{HarmonicAmplitude, PeriodicSolution, TimeSeries, TruncationEstimate};
pub use solve::{
    AUTO_KRYLOV_UNKNOWNS, Broyden, Method, Newton, NonlinearEquations, SolveReport, SolverOptions,
    SolverState, solve_equations, solve_equations_with,
};
pub use stability::{STABILITY_TOLERANCE, Stability};
pub use sweep::parallel_sweep;
pub use system::{SecondOrderSystem, SystemError, finite_difference_force_jacobian};

#[cfg(test)]
mod tests {
    use super::*;

    fn is_send_sync<T: Send + Sync>() {}

    #[test]
    fn public_types_are_send_sync() {
        is_send_sync::<Basis>();
        is_send_sync::<PeriodicSolution>();
        is_send_sync::<HbmError>();
        is_send_sync::<HbmProblem<()>>();
        is_send_sync::<Newton>();
        is_send_sync::<Broyden>();
    }
}

/// The README's example, compiled and run as a doctest so that it cannot rot.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
