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
//! * [`solve_hbm`] — harmonic balance with AFT (Eq. 13–17) through the `hbm` engine, on the
//!   paper's sparse basis ([`Basis::PAPER`], 15 unknowns) or a full basis ([`Basis::Full`],
//!   [`HbmOptions::full`]); Newton with the exact AFT Jacobian instead of the paper's Broyden.
//!   [`solve_hbm_from_time_response`] starts it on the branch a time integration found.
//! * [`integrate`] — the `timestep` engine (adaptive Dormand–Prince with the gap edges
//!   `q = ±b̄` as located events) over whole periods `T = 2π/ω̄_c`.
//!
//! Both give a [`Rattle`] (rsv, ppv). Which when: time integration is the reference for the
//! rattle state (≈ 30–80 ms per point in release); HBM is fast (≈ 3 ms on the paper basis) and
//! gives spectra, agrees with time integration without rattle, but from a cold start it stays
//! on the unilateral branch where time integration finds bilateral rattle, and on bilateral
//! branches Newton often stalls above tolerance (`converged() == false`, ppv still within
//! ≈ 10 %).
//!
//! # Limitations
//!
//! * Constant damping ratio (the paper's assumption); `φ₂ ≈ ω_c t` in Eq. (18).
//! * With the default time-varying `b̄(τ)` the paper's 15-term basis cannot represent the
//!   quasi-static `1/r_b2(τ)` shape and misreports rattle; use a full basis, or the constant-b̄
//!   reading the paper's figures follow (`BaseRadius::Mean`).
//! * Several periodic responses coexist near the onset of bilateral rattle; a sweep from rest
//!   is not a continuation.
//!
//! # References
//!
//! Liu, Lv, Zhao (2021), Mech. Sci. 12, 361–373, Eq. (1)–(23), Table 1–2. Theory as
//! implemented: `docs/models/liu2021.md`; performance: `docs/performance/models-liu.md`.
//!
//! # Example
//!
//! ```
//! use models::liu2021::{self, BaseRadius, HbmOptions};
//! let mut p = liu2021::table1();
//! p.omega1 = 120.0; // below the unilateral-rattle threshold
//! p.readings.base_radius = BaseRadius::Mean; // constant b̄, as the paper's figures (R-LIU-EQ11)
//! let model = p.model()?;
//! let sol = liu2021::solve_hbm(&model, &HbmOptions::default(), None)?;
//! assert!(sol.converged());
//! assert_eq!(sol.rattle.state.rsv(), 0);
//! # Ok::<(), models::Error>(())
//! ```

mod harmonic;
mod integrate;
mod model;
mod params;

pub use harmonic::{
    Basis, HbmOptions, HbmResponse, coefficients_from_time_response, solve_hbm,
    solve_hbm_from_time_response,
};
pub use integrate::{IntegrationOptions, TimeResponse, integrate};
pub use model::{Model, Rattle, RattleState};
pub use params::{
    BaseRadius, ErrorTerm, Parameters, Readings, RigidAcceleration, RigidSeries, table1,
};
