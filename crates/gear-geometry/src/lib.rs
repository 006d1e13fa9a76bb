//! # gear-geometry
//!
//! Kinematics of the gear pairs of three papers, as cheap, allocation-free functions that a
//! time-stepping or harmonic-balance model can call inside its right-hand side.
//!
//! ## Karpov et al. 2017 — slightly non-circular pair ([`KarpovPair`], [`CentrodeDeviation`])
//!
//! Centrodes (Eq. 1), `θ = jφ1`:
//!
//! ```text
//! r1 = r (1 + g(θ)),   r2 = r (u − g(θ)),   g(θ) = B √(ξ²−1) sin θ / (ξ + cos θ)
//! ```
//!
//! `max g = B`, so `0 ≤ B < min(1, u)` keeps both radii positive; `ξ → ∞` gives the sinusoidal
//! centrodes of Section 4, `g = B sin θ` ([`CentrodeDeviation::sinusoidal`]).
//! Gear ratio (Eq. 2) `i = ω2/ω1 = r1/r2`, exact ([`KarpovPair::ratio`]) and
//! `≈ 1/u + (1+u)g/u²` ([`KarpovPair::ratio_eq2`]); output angle `φ2 = ∫ i dφ1` in closed form
//! ([`KarpovPair::output_angle`]), by adaptive Gauss–Legendre quadrature
//! ([`KarpovPair::output_angle_quadrature`]) and by the printed approximation
//! ([`KarpovPair::output_angle_approx`]). Speed fluctuation (Eq. 3, 4)
//! `δ = u(max i − min i) ≈ 2B(1+u)/u` (Eq. 4 prints `2B(1+u)/u²`, a factor `u` smaller:
//! reading `R-KARPOV-EQ4`, [`SpeedFluctuationForm`]); output acceleration (Eq. 5)
//! `ε2 = ω1² di/dφ1` and its maximum (Eq. 6 and numerically); mesh frequency (Eq. 7)
//! `ω_m = r1 z1 ω1/r` and its integral, the mesh phase `z1(φ1 + G(jφ1)/j)`,
//! `G(θ) = −B√(ξ²−1) ln((ξ + cos θ)/(ξ + 1))`. The dimensionless forms of Eq. (10) used by the
//! Karpov oscillator are [`CentrodeDeviation::dimensionless_mesh_frequency`] and
//! [`CentrodeDeviation::dimensionless_mesh_phase`]. The Section 4 design check
//! ([`KarpovPair::design_check`]) reports the largest admissible `B` for a `δ_max`.
//!
//! **Reading `R-KARPOV-EQ1-CLOSURE`**: with `a = r(1+u)` as printed, the output turns
//! `2π/u + O(B²)` per input revolution, not exactly `2π/u`; the default
//! [`CentreDistance::Closing`] moves the centre distance by `O(B²)` (3.5 µm for Table 1) so that
//! the centrodes close. [`CentreDistance::AsPrinted`] keeps Eq. (1) literally.
//!
//! ## Liu et al. 2021 — noncircular face gear pair ([`NfgPair`])
//!
//! Ratio (Eq. 1, 18) `i12 = ω1/ω2 = r2/r1 = i_j (1 + 2ε cos ωc t + ε²)/(1 − ε²)`, `ωc = ω1/i_j`,
//! pinion pitch radius `r1 = m Z1/2`, NFG pitch radius `r2 = r1 i12`, equivalent base radius
//! `r_b2 = r2 cos α = L(1 + β cos ωc t)` (Eq. 8) with `L = r1 cos α i_j (1+ε²)/(1−ε²)`,
//! `β = 2ε/(1+ε²)` — exact in time. Rigid acceleration `d²θ2/dτ²` derived from Eq. (18) or Eq.
//! (20) as printed ([`RigidAccelerationForm`], reading `R-LIU-EQ20`), with Fourier coefficients
//! `B1, B2` of Eq. (22) in closed form and by quadrature. Excitation frequencies
//! `f_c = ω1/(2π i_j)`, `f_e = Z1 ω1/(2π)`.
//!
//! ## Yu et al. 2021 — spur pair ([`SpurPair`])
//!
//! Reference radii, base radii `R cos α0`, nominal centre distance `a0 = Rp + Rg`, actual centre
//! distance (Eq. 8), roll angle `β = tan α`, involute arc length (Eq. 7), and the operating
//! pressure angle at centre distance `a`: Eq. (16) as printed, `arccos((Rp+Rg)/a)` (0° at
//! `a0`), or the involute `arccos(a0 cos α0/a)` (default; reading `R-YU-EQ16`). The law
//! ([`PressureAngleLaw`]) and the centre-distance form ([`CentreDistanceForm`]) are the
//! workspace's one definition in `geardyn-system`, shared with the backlash leaf.
//!
//! ## Paper parameter sets
//!
//! This crate holds the general types and their constructors only. The papers' parameter sets
//! and rigs live with their model in `geardyn-models`: `karpov2017::pair_table1()`,
//! `liu2021::table1().pair()` and the Section 3.8 test rig `liu2021::Rig` (Table 2, reading
//! `R-LIU-TABLE2`), `yu2021::Yu2021Params::table1().spur_pair()` / `table2()`.
//!
//! ## Which function when
//!
//! Inside an ODE right-hand side use the closed forms (`ratio`, `mesh_frequency`, `mesh_phase`,
//! `base_radius`, `rigid_acceleration`, `output_angle`): each is a handful of flops and one or two
//! transcendental calls (see `docs/performance/gear-geometry.md`). The `*_numeric` and
//! `*_quadrature` functions and `max_acceleration` are independent checks and design-time tools.
//!
//! ## Limitations
//!
//! Pitch-curve (centrode) kinematics only: no tooth profiles, contact ratio, undercut or
//! manufacturing geometry. Input speed is constant wherever an acceleration is computed.
//!
//! ## References
//!
//! * O. Karpov, P. Nosko, P. Fil, O. Nosko, U. Olofsson, *Prevention of resonance oscillations in
//!   gear mechanisms using non-circular gears*, Mech. Mach. Theory 114 (2017) 1–10.
//! * D. Liu, Z. Lv, G. Zhao, *Rattle dynamics of noncircular face gear under multifrequency
//!   parametric excitation*, Mech. Sci. 12 (2021) 361–373.
//! * Yu, Sun, Li, Wu, *Nonlinear response of gear system based on a novel backlash model with
//!   coupling dynamic change and surface topography* (2021, preprint).
//!
//! Readings (printed vs consistent forms): `docs/readings/geometry.md`.
//!
//! ## Example
//!
//! ```
//! use geardyn_gear_geometry::{
//!     CentreDistance, KarpovPair, KarpovPairParams, NfgPair, NfgPairParams, PressureAngleLaw,
//!     SpurPair,
//! };
//! use std::f64::consts::{PI, TAU};
//!
//! // a slightly non-circular pair: u = 2, r = 50 mm, B = 0.01, ξ = 2, j = 4, z1 = 32
//! let pair = KarpovPair::new(KarpovPairParams {
//!     r: 0.050, u: 2.0, b: 0.01, xi: 2.0, j: 4, z1: 32,
//!     centre_distance: CentreDistance::Closing,
//! })?;
//! // one input revolution turns the output by exactly 2π/u
//! assert!((pair.output_angle(TAU) - PI).abs() < 1e-13);
//! // speed fluctuation: exact, linearised, and Eq. (4) as printed (a factor u = 2 smaller)
//! let (d, dl, d4) =
//!     (pair.speed_fluctuation(), pair.speed_fluctuation_linear(), pair.speed_fluctuation_eq4());
//! assert!((d - 0.03).abs() < 1e-5 && (dl - 0.03).abs() < 1e-15 && (d4 - 0.015).abs() < 1e-15);
//! // largest B for δ_max = 0.02
//! let check = pair.design_check(0.02)?;
//! assert!(!check.admissible && check.b_max_exact < 0.01);
//!
//! // an NFG pair: m = 2.5 mm, Z1 = 18, i_j = 3.5, ε = 0.2, α = 20°
//! let nfg = NfgPair::new(NfgPairParams {
//!     module: 2.5e-3, z1: 18, ratio: 3.5, eccentricity: 0.2,
//!     pressure_angle: 20f64.to_radians(),
//! })?;
//! assert!((nfg.base_radius(0.3) - nfg.base_radius_eq8(0.3)).abs() < 1e-15);
//! // f_e = Z1 ω1/(2π): 18 mesh periods per pinion revolution
//! assert!((nfg.mesh_frequency(TAU) - 18.0).abs() < 1e-12);
//!
//! // a spur pair, module 3 mm, 50/50 teeth: 20° at the nominal centre distance
//! let spur = SpurPair::from_module(3e-3, 50, 50, 20f64.to_radians())?;
//! let a0 = spur.nominal_centre_distance();
//! let alpha = spur.operating_pressure_angle(a0, PressureAngleLaw::Involute)?;
//! assert!((alpha.to_degrees() - 20.0).abs() < 1e-12);
//! # Ok::<(), geardyn_gear_geometry::Error>(())
//! ```
#![deny(missing_docs)]

mod error;
mod karpov;
mod liu;
mod yu;

pub use error::Error;
pub use karpov::{
    CentreDistance, CentrodeDeviation, CentrodeDeviationParams, DesignCheck, KarpovPair,
    KarpovPairParams, SpeedFluctuationForm,
};
pub use liu::{NfgPair, NfgPairParams, RigidAccelerationForm, rigid_acceleration_coefficient};
pub use system::{CentreDistanceForm, PressureAngleLaw};
pub use yu::{SpurPair, SpurPairParams, involute_arc_length, roll_angle};

#[cfg(test)]
mod tests {
    /// Types used across rayon must be `Send + Sync`.
    #[test]
    fn send_sync() {
        fn check<T: Send + Sync + Clone>() {}
        check::<super::KarpovPair>();
        check::<super::CentrodeDeviation>();
        check::<super::NfgPair>();
        check::<super::SpurPair>();
        check::<super::Error>();
    }
}

/// The README's example, compiled and run as a doctest so that it cannot rot.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
