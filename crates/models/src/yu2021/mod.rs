//! Yu, Sun, Li, Wu 2021: spur pair with fractal and dynamic backlash, and the two reference
//! models of the paper's comparison (Kahraman–Singh, Chen).
//!
//! # Governing equations (dimensional, Eq. 12–17)
//!
//! ```text
//! I_p θ̈_p + R_p F_m = T_p            m_p ẍ_p + c_px ẋ_p + k_px x_p + F_m sin α = 0
//! I_g θ̈_g − R_g F_m = −T_g           m_p ÿ_p + c_py ẏ_p + k_py y_p + F_m cos α = 0
//!                                    m_g ẍ_g + c_gx ẋ_g + k_gx x_g − F_m sin α = 0
//!                                    m_g ÿ_g + c_gy ẏ_g + k_gy y_g − F_m cos α = 0
//! F_m = c_m δ̇ + k_m(t) f(δ, B)                                   (13), f: dead zone (14)
//! δ = (x_p − x_g) sin α + (y_p − y_g) cos α + R_p θ_p − R_g θ_g − e(t)   (15)
//! k_m = k_am (1 + ε sin(ω_h t + φ_0)),  e = e_r cos(ω_h t + φ_0),  c_m = 2 ξ_c sqrt(k_am m_e)
//! B = b_s + b_dy,  b_dy = sqrt(Δa² − Δp²),  Δp = R_pb/2 (tan²α − tan²α_0)     (10)–(11)
//! ```
//!
//! # Dimensionless form (derived here, [`EquationForm::Consistent`])
//!
//! With `u = R_p θ_p − R_g θ_g`, `τ = ω_n t`, `ω_n² = k_am/m_e`, lengths over `b_n`, static
//! balance `T_p/R_p = T_g/R_g = F_s` and `F* = F_m/(k_am b_n)`:
//!
//! ```text
//! u''   = T* − F*,                         F* = (1 + ε sin(ω*τ + φ_0)) f(δ*, B*) + ζ δ*'
//! x_p'' = −ζ_px x_p' − κ_px x_p − μ_p F* sin α     (μ_p = m_e/m_p, and y_p with cos α)
//! x_g'' = −ζ_gx x_g' − κ_gx x_g + μ_g F* sin α     (μ_g = m_e/m_g, and y_g with cos α)
//! δ*  = (x_p − x_g) sin α + (y_p − y_g) cos α + u − ē cos(ω*τ + φ_0)
//! ```
//!
//! Written for `δ*` (constant `α`, `μ_i = m_e/m_i`) this is
//! `δ*'' = T* + ω*² ē cos(ω*τ + φ_0) − (1 + μ_p + μ_g) F* − sin α (ζ_px x_p' + κ_px x_p −
//! ζ_gx x_g' − κ_gx x_g) − cos α (…y…)`; Eq. (19) as printed keeps only
//! `δ*'' + ζ δ*' + k f = T* + T_ah` with `T_ah = e/b_n` ([`EquationForm::Printed`]).
//! See `docs/models/yu2021.md` for the derivation and `docs/readings/yu.md` for every
//! difference from the printed paper.
//!
//! # Which model, which option
//!
//! * [`Options::kahraman_singh`]: 1-DOF, constant backlash `b_s` (the paper's reference).
//! * [`Options::chen`]: 1-DOF, `B(t) = b_s + a_z z(ω_h t)` with Chen's `z` of Eq. (3).
//! * [`Options::default`]: Yu's 6-DOF model, consistent equations, state-dependent backlash
//!   evaluated inside the right-hand side, operating pressure angle, Eq. (10) dynamic part.
//! * [`Options::yu_as_printed`]: Eq. (19), (16), (8) as printed and Fig. 8's update of `B`
//!   from the previous step.
//! * `lock_centres: true` reduces the 6-DOF model to the torsional one (`B = b_s`).
//!
//! # Solvers (both engines)
//!
//! * Time integration, [`Yu2021Model::simulate_with`] with an [`Engine`]:
//!   [`Engine::Rk4Fixed`] (= [`Yu2021Model::simulate`], the model's own fixed-step RK4, both
//!   backlash updates of Fig. 8; needed for Fig. 8's previous-step update) or
//!   [`Engine::Timestep`] (used by the validation studies; the
//!   `timestep` crate through `timestep::Mechanical` on [`Yu2021SixDof`], adaptive Dormand–Prince by default, with the
//!   dead-zone edges `δ* = ±B` located as events; state-dependent backlash only). Both return
//!   the same [`Response`] sampled on the same grid.
//! * Harmonic balance, [`Yu2021Model::harmonic_balance`] / [`Yu2021Model::hbm_problem`]: the
//!   `hbm` engine through [`Yu2021Torsional`] (`system::SecondOrderSystem`, analytic dead-zone
//!   Jacobian, full basis `0..H` of `ω*`) for the periodic 1-DOF models (Kahraman–Singh, Yu
//!   with locked centres); [`Yu2021Model::hbm_problem_six_dof`] through [`Yu2021SixDof`]
//!   (five coordinates, state-dependent dynamic backlash, finite-difference Jacobian) for
//!   Yu's 6-DOF model. Chen's backlash is not periodic in the mesh period: time integration
//!   only.
//!
//! Outputs: DTE, mesh force, backlash, pressure angle, [`Response::dynamic_factor`] (Eq. 20)
//! and [`Response::rms`] (Eq. 21). Physics leaves: the dead zone, Chen's `z` and the W-M mean
//! height come from the `backlash` crate, the contact stiffness of Eq. (18) from
//! `mesh-stiffness`.
//!
//! # Limitations
//!
//! The fixed-step RK4 has no event location (the dead zone's kinks cost accuracy, about first
//! order in the step at the switching instants; the `timestep` engine removes that); the
//! harmonic balance is period-1 only and not available for Chen's model (its fractal backlash
//! is not periodic in the mesh period) or the 6-DOF model; the dynamic-backlash geometry of
//! Eq. (8)–(11), (16) is the `backlash` leaf's `DynamicBacklash`
//! ([`Yu2021Model::dynamic_backlash_law`] maps the options onto it); the parameter sets contain chosen values
//! (documented on [`Yu2021Params::table1`] and [`Yu2021Params::table2`]); no experimental
//! points of Fig. 13–14 exist in this repository.
//!
//! # Example
//!
//! ```
//! use geardyn_models::yu2021::{Engine, Options, RunSettings, Yu2021Model, Yu2021Params};
//!
//! let model = Yu2021Model::new(&Yu2021Params::table1(), Options::default())?;
//! let settings = RunSettings { omega: 0.9, transient_periods: 20, record_periods: 2, steps_per_period: 128 };
//! let response = model.simulate(&settings, None)?;
//! assert!(response.dynamic_factor() > 1.0);
//! assert!(response.mean_backlash() >= 1.0); // Eq. (10) never lowers the backlash
//!
//! // the same model on the `timestep` engine (adaptive, contact switches located as events)
//! let adaptive = model.simulate_with(&settings, &Engine::timestep(), None)?;
//! assert!((adaptive.dynamic_factor() - response.dynamic_factor()).abs() < 0.05);
//! # Ok::<(), geardyn_models::Error>(())
//! ```
//!
//! # Reference
//!
//! X. Yu, Y. Sun, H. Li, S. Wu, *Nonlinear response of gear system based on a novel backlash
//! model with coupling dynamic change and surface topography*, preprint (2021),
//! doi:10.21203/rs.3.rs-889901/v1.

mod engines;
mod fractal;
mod hbm;
mod model;
mod params;
mod presets;
mod reference;
pub mod registry;
mod stiffness;

pub use engines::Engine;
pub use fractal::{
    CurvatureCoefficient, FractalContact, FractalForm, FractalSurface, chen_z,
    fractal_contact_stiffness, fractal_mean_height,
};
pub use hbm::{HbmSettings, HbmSolution, Yu2021SixDof, Yu2021Torsional};
pub use model::{
    BacklashUpdate, CentreDistanceForm, DynamicBacklashLaw, EquationForm, MAX_RECORDED_SAMPLES,
    MAX_RUN_STEPS, MeshGeometry, ModelKind, Options, PressureAngleLaw, Response, RunSettings,
    STATE_LEN, Yu2021Dimensionless, Yu2021Model, dead_zone,
};
pub use params::{BacklashSpec, Yu2021Params};
pub use presets::{Fig4Claims, fig4, fig4_backlash_params, fig4_claims, fractal_contact_default};
pub use reference::{Metrics, ReferenceCheck, ReferenceRun};
pub use stiffness::{
    ContactAreaLaw, FractalMeshStiffness, majumdar_bhushan_area, majumdar_bhushan_load,
};
