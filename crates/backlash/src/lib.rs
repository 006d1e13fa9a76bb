//! # backlash — gear backlash as a physics leaf
//!
//! Dead-zone function, Weierstrass–Mandelbrot (W-M) fractal backlash and dynamic backlash from
//! gear-centre motion, from Liu, Lv & Zhao (2021) *Mech. Sci.* 12:361 and Yu, Sun, Li & Wu (2021)
//! *Nonlinear response of gear system based on a novel backlash model with coupling dynamic
//! change and surface topography* (preprint). No solver and no gear model live here: models call
//! these functions in every right-hand side / at every harmonic-balance collocation point.
//!
//! ## Governing equations
//!
//! **Dead zone** (Liu Eq. 12, Yu Eq. 14), half gap `b ≥ 0`:
//!
//! ```text
//! f(x; b) = x − b  (x > b),   0  (−b ≤ x ≤ b),   x + b  (x < −b)
//! ```
//!
//! [`dead_zone`], [`dead_zone_dx`], [`dead_zone_db`], [`contact_region`],
//! [`switching_functions`]. Corner convention: at `x = ±b` the zero branch holds (Liu writes the
//! closed interval), so `∂f/∂x = ∂f/∂b = 0` there; for `b = 0`, `f(x) = x` and `∂f/∂x = 1`.
//! [`DeadZone`] adds an optional C^∞ [`Regularisation::Smooth`] (error ≤ ε/2) for Newton
//! iterations; [`Regularisation::Exact`] is the default. Time-dependent gaps go through the
//! [`HalfGap`] trait (`f64` or a closure in [`GapFn`]).
//!
//! **W-M profile** (Yu Eq. 2), fractal dimension `D ∈ (1, 2)`, roughness `G > 0` (m), `λ > 1`:
//!
//! ```text
//! z(l) = G^{D−1} Σ_{k=k_min}^{n_max} λ^{(D−2)k} cos(2π λ^k l),   λ^{k_min} ≈ 1/l_a,  λ^{n_max} ≤ 1/l_s
//! ```
//!
//! The infinite sum is truncated at the smallest resolvable wavelength `l_s`; the neglected tail
//! is bounded uniformly by `G^{D−1} λ^{(D−2)(n_max+1)}/(1 − λ^{D−2})`
//! ([`WmProfile::truncation_bound`]).
//!
//! **Chen's fractal backlash** (Yu Eq. 3): `z(t) = Σ_{k≥0} λ^{(D−2)k} sin(λ^k t)` ([`ChenFractal`],
//! with a tail bound and [`ChenFractal::for_tolerance`]).
//!
//! **Effective mean asperity height and constant part** (Yu Eq. 4–5):
//!
//! ```text
//! b_i = (1/L) ∫_0^L |z_i(l)| dl,      b_s = b_0 − b_p − b_g
//! ```
//!
//! computed by a composite midpoint rule with `points_per_wavelength` samples per smallest kept
//! wavelength; the result carries a quadrature error estimate (difference of the interleaved
//! half-rules) and the truncation bound ([`MeanHeight`]). With 8 points per wavelength the
//! estimate is below 1 % of b_i for D ≤ 1.6 (see `docs/performance/backlash.md` and the tests).
//! [`constant_part_grid`] returns b_s over a (D, G) grid (the form of Yu Fig. 4). The parameter
//! set chosen for Fig. 4 and the checks of the text's statements about it are Yu's, not the
//! law's: they live with the model (`geardyn_models::yu2021::{fig4_backlash_params, fig4,
//! fig4_claims}`).
//!
//! **Dynamic part** (Yu Eq. 6–11), centre displacements `(x_p, y_p, x_g, y_g)`:
//!
//! ```text
//! a  = √((a_0 + x_p − x_g)² + (y_p − y_g)²),   Δa = a − a_0                  (8), (9)
//! Δp = (R_pb/2)(β_c² − β_0²),  β = tan α                                      (7)
//! Δb = (Δa² − Δp²)^{1/2}                                                      (6), (10)
//! B  = b_s + b_dy,  b_dy = Δb                                                 (11)
//! ```
//!
//! [`DynamicBacklash::eval`] returns the half gap B, its parts and `∂B/∂(x_p, y_p, x_g, y_g)`.
//! Three forms ([`DynamicForm`]): the involute-geometry change of the half gap
//! `b_dy = (R_pb + R_gb)(inv α' − inv α_0) ≈ sin α_0 Δa` (default; half the change
//! `2 sin α_0 Δa` of the normal backlash), its line-of-action form `Δa sin α(a)`, and Yu's
//! Eq. (10) as printed. The sign of Eq. (8) ([`CentreDistanceForm`]), the pressure-angle law
//! ([`PressureAngleLaw`]) and β_0 of Eq. (7) ([`Beta0`]) are options.
//! A negative radicand in Eq. (6) is handled by a [`RadicandPolicy`] (default: clamp to 0);
//! no NaN leaves the crate for finite inputs.
//!
//! **Backlash laws** ([`BacklashLaw`]): every gap above as one trait, `half_gap(t, c)` with
//! `∂b/∂t` and `∂b/∂c`, plus the dead-zone corner treatment: `f64` (constant), [`ConstantPart`]
//! (Eq. 5), [`ChenBacklash`] (`b_s + a_z z(ωt)`), [`RadiusModulatedBacklash`] (Liu Eq. 11–12,
//! `b/(1 + β cos ωt)`), [`DynamicBacklash`], [`Smoothed`]; [`Backlash`] is their serde enum.
//!
//! ## Which method when
//!
//! * Time stepping: the exact [`dead_zone`] plus [`switching_functions`] for event location.
//! * Harmonic balance / Newton: exact, or [`Regularisation::Smooth`] with ε ≈ 1e-3·b if the
//!   Jacobian jump stalls convergence.
//! * State-dependent gap: evaluate [`DynamicBacklash::eval`] first, then [`DeadZone::eval`];
//!   chain `df_db · grad` into the Jacobian.
//! * b_s: compute once per parameter set (it costs N × n_terms cosines), not per step.
//!
//! ## Limitations and readings
//!
//! The paper prints no parameters for Fig. 4; ours are chosen and documented with the model
//! (`geardyn_models::yu2021::fig4_backlash_params`, reading R-YU-FIG4). Yu Eq. (16) (pressure angle) gives 0° at the
//! nominal centre distance, which makes the radicand of Eq. (6) negative at rest; Eq. (6) is
//! sign-blind; Eq. (11) drops the absolute value of Eq. (4). Each is a reading in
//! `docs/readings/backlash.md` (R-YU-EQ16, R-YU-EQ6, R-YU-EQ11-BS, R-YU-FIG4, R-LIU-EQ12).
//!
//! ## Example
//!
//! ```
//! use geardyn_backlash::{
//!     ConstantBacklashParams, ConstantPartForm, DeadZone, DynamicBacklash, CentreDisplacement,
//!     PairGeometry, Quadrature, SurfaceFractal, dead_zone,
//! };
//!
//! // constant part from the surface topography (Yu Eq. 5), coarse settings for the doc test:
//! // b0 = 30 µm, λ = 1.5, l_a = L = 1 mm, l_s = 10 µm
//! let p = ConstantBacklashParams {
//!     b0: 30e-6,
//!     gamma: 1.5,
//!     l_a: 1e-3,
//!     l_s: 1e-5,
//!     sampling_length: 1e-3,
//!     quadrature: Quadrature::default(),
//!     form: ConstantPartForm::AbsoluteMean,
//! };
//! let s = SurfaceFractal::new(1.4, 1e-11)?;
//! let cp = p.constant_part(s, s)?;
//! assert!(cp.b_s > 0.0 && cp.b_s < p.b0);
//!
//! // complete backlash for a centre displacement (Yu Eq. 11), involute form
//! let geometry = PairGeometry::new(0.094, 0.094, 20f64.to_radians())?; // R_p, R_g, α_0
//! let dynb = DynamicBacklash::involute(geometry, cp.b_s)?;
//! let e = dynb.eval(&CentreDisplacement::new(0.0, 0.0, 2e-6, 0.0))?;
//! assert!(e.b < cp.b_s); // x_g > 0: centres closer, less backlash
//!
//! // the dead zone with that gap, and its derivatives for a Jacobian
//! let f = DeadZone::EXACT.eval(1e-4, e.b);
//! assert!((f.f - dead_zone(1e-4, e.b)).abs() < 1e-18);
//! assert_eq!(f.df_dx, 1.0);
//! # Ok::<(), geardyn_backlash::Error>(())
//! ```
#![deny(missing_docs)]

mod deadzone;
mod dynamic;
mod error;
mod fractal;
mod law;

pub use deadzone::{
    ContactRegion, DeadZone, DeadZoneEval, GapFn, HalfGap, Regularisation, contact_region,
    dead_zone, dead_zone_db, dead_zone_dx, switching_functions, try_dead_zone,
};
pub use dynamic::{
    BacklashEval, Beta0, CentreDisplacement, CentreDistanceForm, DynamicBacklash, DynamicForm,
    PairGeometry, PressureAngleLaw, RadicandPolicy,
};
pub use error::Error;
pub use fractal::{
    CHEN_MAX_TERMS, ChenFractal, ConstantBacklashParams, ConstantPart, ConstantPartForm,
    ConstantPartGrid, MeanHeight, Quadrature, SurfaceFractal, WmProfile, constant_part_grid,
    mean_asperity_height,
};
pub use law::{
    Backlash, BacklashLaw, ChenBacklash, ContactEval, GapEval, RadiusModulatedBacklash, Smoothed,
};

#[cfg(test)]
mod tests {
    use super::*;

    fn assert_send_sync<T: Send + Sync + Clone>() {}

    #[test]
    fn types_are_send_sync() {
        assert_send_sync::<DeadZone>();
        assert_send_sync::<DynamicBacklash>();
        assert_send_sync::<ConstantBacklashParams>();
        assert_send_sync::<WmProfile>();
        assert_send_sync::<ConstantPartGrid>();
        assert_send_sync::<Error>();
    }
}

/// The README's example, compiled and run as a doctest so that it cannot rot.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
