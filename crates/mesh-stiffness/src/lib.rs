//! # mesh-stiffness
//!
//! Time-varying gear mesh stiffness and tooth contact stiffness: a physics leaf with no solver
//! and no gear model inside.
//!
//! ## Governing equations
//!
//! **Fourier-series mesh stiffness** (Liu, Lv & Zhao 2021, Eq. 6), [`FourierStiffness`]:
//!
//! ```text
//! k_m(t) = k0 + Σ_{n=1}^{N} [ k_{2n−1} cos(n ω_e t) + k_{2n} sin(n ω_e t) ]
//! dk_m/dt = ω_e Σ_{n=1}^{N} n [ k_{2n} cos(n ω_e t) − k_{2n−1} sin(n ω_e t) ]
//! ```
//!
//! **Single harmonic with phase** (Liu Eq. 19; Yu et al. 2021 Eq. 17), [`SingleHarmonicStiffness`]:
//!
//! ```text
//! k_m(t) = k0 + k_r sin(ω_e t + φ_m)            (Liu; φ_m = π/2 in the paper)
//! k_m(t) = k_am [1 + ε sin(ω_h t + φ0)]         (Yu: k0 = k_am, k_r = ε k_am)
//! ```
//!
//! Both papers print the sine form ([`Waveform::Sine`], the default); [`Waveform::Cosine`]
//! gives `k0 + k_r cos(ω_e t + φ_m)`. For the fundamental `a cos θ + b sin θ`:
//! `k_r = √(a² + b²)`, `φ_m = atan2(a, b)` (sine form) or `atan2(−b, a)` (cosine form).
//!
//! **Fit from samples** ([`fit_fourier`], [`FourierFitter`], [`fit_single_harmonic`]):
//! `M` samples uniform over `P` whole mesh periods, end point excluded
//! (`t_j = j P T_e / M`); forward DFT `X_m = Σ_j k_j e^{−2πi jm/M}` (rustfft); harmonic n sits
//! in bin `nP`:
//!
//! ```text
//! k0 = X_0 / M,   k_{2n−1} = 2 Re X_{nP} / M,   k_{2n} = −2 Im X_{nP} / M,   N P < M/2
//! ```
//!
//! This is Liu's "k0 and k_r can be calculated by a discrete Fourier transformation of the
//! synthesizing meshing stiffness in Fig. 7": curve → DFT → `(k0, k_r, φ_m)`.
//!
//! **Tooth-pair stiffness** ([`ToothPairStiffness`]): per mesh period, `k_double` for the
//! double-contact fraction `w = ε_α − 1`, `k_single` for the rest (Liu Sect. 3.1, Fig. 7),
//! optionally with raised-sine transitions, and its exact Fourier coefficients
//! `a_n = Δ sin(2πnw)/(πn) H_n`, `b_n = Δ (1 − cos 2πnw)/(πn) H_n`, `k0 = k_single + Δ w`.
//! **NFG variant** ([`NfgToothPairStiffness`]): contact ratio and pair stiffness modulated with
//! the pitch radius of Liu Eq. (18) at each mesh period's instantaneous-centre angle.
//!
//! **Fractal contact stiffness** (Yu et al. 2021 Eq. 18), [`FractalContact`]:
//!
//! ```text
//! k_c = 2^D D G^{(D−1)²} / [(D − D² + 1)(1 − D)] · E λ_c a_L^{D/2} / [π^{(2−D)/2} (φq)^{D−1}]
//!       · (l_a^{D−D²+1} − l_s^{D−D²+1}),      φ = H/E,  q = 0.454 + 0.41ν
//! ```
//!
//! and the **Hertzian line contact** of the same pair ([`HertzLineContact`]; Johnson 1985
//! Eq. 5.36, Yang & Lin 1987).
//!
//! ## Which method when
//!
//! - In an ODE right-hand side: [`FourierStiffness::eval_with_derivative`] or
//!   [`SingleHarmonicStiffness::eval_with_derivative`] (one `sin_cos`, no allocation).
//! - From an FE or measured curve: [`fit_fourier`] (one curve) or [`FourierFitter`] (many curves
//!   of one length), then [`FourierFit::fundamental`] for Liu's `(k0, k_r, φ_m)`.
//! - Without FE data: [`ToothPairStiffness`] (circular gears) or [`NfgToothPairStiffness`].
//! - Absolute contact stiffness: [`HertzLineContact`]; [`FractalContact`] for the D/G trends of
//!   Yu's model (see limitations).
//!
//! ## Limitations (see `docs/readings/mesh-stiffness.md`)
//!
//! - R-YU-EQ18: Eq. (18) as printed is negative for every `D ∈ (1, 2)`, singular at
//!   `D = (1+√5)/2`, its `λ_c` exponent `2/R` is dimensional, and the whole expression has the
//!   unit Pa·m² = N instead of N/m. [`FractalForm::Consistent`] (default) fixes sign and
//!   singularity; the missing 1/length cannot be restored without Yu's Ref. \[26\]. With the
//!   documented defaults it gives ~1e4 against ~6e8 N/m for Hertz, and it *falls* with D and
//!   *rises* with G (Yu's text says smoother surfaces are stiffer). Use it for what Eq. 18
//!   says, and calibrate absolute levels elsewhere.
//! - R-LIU-FIG7: Liu gives the NFG per-period curves only as an FE figure; the modulation model
//!   of [`NfgToothPairStiffness`] is this crate's choice.
//! - Stiffness positivity is not enforced for Fourier series (a truncated series of a positive
//!   curve may dip); check `k0 > Σ amplitudes` if it matters.
//!
//! ## Example
//!
//! ```
//! use geardyn_mesh_stiffness::{fit_fourier, ToothPairStiffness, Waveform};
//!
//! // Rectangular single/double-pair wave: contact ratio 1.625, pair stiffness 2e8 N/m.
//! let wave = ToothPairStiffness::from_pair_stiffness(1.625, 2.0e8, 0.0)?;
//! let omega_e = 2880.0; // rad/s, Liu Table 1: ω_1 Z_1 = 160 × 18
//! let samples = wave.sample(1024, 1);
//! let fit = fit_fourier(&samples, 1, 10, omega_e)?;
//! let single = fit.fundamental(Waveform::Sine); // Liu Eq. 19: (k0, k_r, φ_m)
//! assert!((single.k0 - wave.mean()).abs() < 1e-6 * wave.mean());
//! let (k, dk) = fit.series.eval_with_derivative(1.0e-4);
//! assert!(k > 0.0 && dk.is_finite());
//! # Ok::<(), geardyn_mesh_stiffness::Error>(())
//! ```
//!
//! ## References
//!
//! - Liu, Lv, Zhao (2021), *Rattle dynamics of noncircular face gear under multifrequency
//!   parametric excitation*, Mech. Sci. 12:361 — Eq. 6, 8, 18, 19, Fig. 7, Table 1.
//! - Yu, Sun, Li, Wu (2021), *Nonlinear response of gear system based on a novel backlash model
//!   with coupling dynamic change and surface topography* (preprint) — Eq. 17, 18.
//! - K. L. Johnson (1985), *Contact Mechanics*, CUP — Eq. 4.77, 5.36.
//! - Yang & Lin (1987), ASME J. Mech. Transm. Autom. Des. 109:189 — line-contact stiffness.

#![deny(missing_docs)]

mod contact;
mod error;
mod fit;
mod law;
mod series;
mod tooth_pair;

pub use contact::{CurvatureCoefficient, FractalContact, FractalForm, HertzLineContact};
pub use error::{Error, Result};
pub use fit::{FourierFit, FourierFitter, fit_fourier, fit_single_harmonic};
pub use law::{MeshTimed, PhaseCurve, Stiffness, StiffnessLaw};
pub use series::{FourierStiffness, FourierStiffnessData, SingleHarmonicStiffness, Waveform};
pub use tooth_pair::{NfgToothPairStiffness, ToothPairStiffness};

/// The README's example, compiled and run as a doctest so that it cannot rot.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
