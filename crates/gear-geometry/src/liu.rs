//! Noncircular face gear (NFG) pair of Liu, Lv, Zhao 2021 (Eq. 1, 8, 10, 18, 20, 22). The
//! paper's parameter sets and its test rig (Table 1, Section 3.8, Table 2) live with the model,
//! `geardyn_models::liu2021`.

use math::DetMath;
use std::f64::consts::{PI, TAU};

use crate::Error;
use crate::error::positive;

/// Unvalidated serde form of [`NfgPair`] (SI units).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct NfgPairParams {
    /// `m`, module of the pinion (Table 1), m.
    pub module: f64,
    /// `Z1`, teeth of the pinion (Table 1), `≥ 1`.
    pub z1: u32,
    /// `i_j`, mean reduction ratio (Eq. 18, Table 1 "reduction ratio"), `> 0`.
    pub ratio: f64,
    /// `ε`, eccentric ratio (Eq. 18), in `[0, 1)`.
    pub eccentricity: f64,
    /// `α`, pressure angle of the pinion (Fig. 4, Table 1), rad, in `(0, π/2)`.
    pub pressure_angle: f64,
}

/// Which expression of the NFG rigid-body angular acceleration `d²θ2/dτ²` to use
/// (reading `R-LIU-EQ20`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum RigidAccelerationForm {
    /// Differentiated from Eq. (18): `d²θ2/dτ² = 2ε(1 − ε²) ω̄c² sin θ/(1 + 2ε cos θ + ε²)²`,
    /// `θ = ω̄c τ`. Default.
    #[default]
    Derived,
    /// Eq. (20) exactly as printed: `2ω̄c ε(1 − ε²) sin θ/(1 + 2ε cos θ + ε²)` (one power of
    /// `ω̄c` and one power of the denominator short).
    PrintedEq20,
}

/// A validated NFG pair (pinion + noncircular face gear, orthogonal axes).
///
/// Transmission ratio (Eq. 18) with `θc = ωc t`, `ωc = ω1/i_j`:
/// `i12 = ω1/ω2 = i_j (1 + 2ε cos θc + ε²)/(1 − ε²)`, and `r2 = r1·i12` (Eq. 1),
/// `r_b2 = r2 cos α` (Section 2.3).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(try_from = "NfgPairParams", into = "NfgPairParams")
)]
pub struct NfgPair {
    p: NfgPairParams,
}

impl TryFrom<NfgPairParams> for NfgPair {
    type Error = Error;
    fn try_from(p: NfgPairParams) -> Result<Self, Error> {
        Self::new(p)
    }
}

impl From<NfgPair> for NfgPairParams {
    fn from(n: NfgPair) -> Self {
        n.p
    }
}

impl NfgPair {
    /// Validate and build: `module > 0`, `z1 ≥ 1`, `ratio > 0`, `0 ≤ ε < 1`, `0 < α < π/2`.
    pub fn new(p: NfgPairParams) -> Result<Self, Error> {
        positive("module", p.module)?;
        if p.z1 < 1 {
            return Err(Error::invalid("z1", ">= 1", f64::from(p.z1)));
        }
        positive("ratio", p.ratio)?;
        if !(p.eccentricity.is_finite() && (0.0..1.0).contains(&p.eccentricity)) {
            return Err(Error::invalid("eccentricity", "in [0, 1)", p.eccentricity));
        }
        if !(p.pressure_angle > 0.0 && p.pressure_angle < 0.5 * PI) {
            return Err(Error::invalid(
                "pressure_angle",
                "in (0, pi/2) rad",
                p.pressure_angle,
            ));
        }
        Ok(Self { p })
    }

    /// The parameters.
    pub fn params(&self) -> NfgPairParams {
        self.p
    }

    /// Same pair with another eccentricity (validated).
    pub fn with_eccentricity(&self, eccentricity: f64) -> Result<Self, Error> {
        Self::new(NfgPairParams {
            eccentricity,
            ..self.p
        })
    }

    /// Pinion pitch radius `r1 = m Z1/2`, m.
    pub fn pinion_pitch_radius(&self) -> f64 {
        0.5 * self.p.module * f64::from(self.p.z1)
    }

    /// Pinion base radius `r_b1 = r1 cos α`, m.
    pub fn pinion_base_radius(&self) -> f64 {
        self.pinion_pitch_radius() * self.p.pressure_angle.dcos()
    }

    /// Transmission ratio `i12(θc)` of Eq. (18), `θc = ωc t` (rad).
    #[inline]
    pub fn ratio(&self, theta_c: f64) -> f64 {
        let e = self.p.eccentricity;
        self.p.ratio * (1.0 + 2.0 * e * theta_c.dcos() + e * e) / (1.0 - e * e)
    }

    /// The same ratio as a function of the NFG polar angle `φ2` (Eq. 1, `r2(φ2)`), derived by
    /// integrating `dφ2/dθc = i_j/i12`: `i12(φ2) = i_j(1 − ε²)/(1 − 2ε cos φ2 + ε²)`.
    #[inline]
    pub fn ratio_at_nfg_angle(&self, phi2: f64) -> f64 {
        let e = self.p.eccentricity;
        self.p.ratio * (1.0 - e * e) / (1.0 - 2.0 * e * phi2.dcos() + e * e)
    }

    /// NFG rigid angle `φ2(θc) = 2 atan(((1 − ε)/(1 + ε)) tan(θc/2))`, continuous (one NFG
    /// revolution per period of `θc`).
    pub fn nfg_angle(&self, theta_c: f64) -> f64 {
        let e = self.p.eccentricity;
        let n = (theta_c / TAU).round();
        let t = theta_c - n * TAU;
        n * TAU + 2.0 * ((1.0 - e) / (1.0 + e) * (0.5 * t).dtan()).datan()
    }

    /// NFG pitch radius `r2 = r1 i12` (Eq. 1), m.
    #[inline]
    pub fn nfg_pitch_radius(&self, theta_c: f64) -> f64 {
        self.pinion_pitch_radius() * self.ratio(theta_c)
    }

    /// Equivalent base radius of the NFG, exact: `r_b2 = r2 cos α = r1 cos α · i12(θc)`, m.
    #[inline]
    pub fn base_radius(&self, theta_c: f64) -> f64 {
        self.pinion_base_radius() * self.ratio(theta_c)
    }

    /// `L` of Eq. (8): time mean of `r_b2`, `r1 cos α · i_j (1 + ε²)/(1 − ε²)`, m.
    pub fn base_radius_mean(&self) -> f64 {
        let e = self.p.eccentricity;
        self.pinion_base_radius() * self.p.ratio * (1.0 + e * e) / (1.0 - e * e)
    }

    /// `β` of Eq. (8): relative variation of `r_b2`, `2ε/(1 + ε²)`.
    pub fn base_radius_variation(&self) -> f64 {
        let e = self.p.eccentricity;
        2.0 * e / (1.0 + e * e)
    }

    /// Eq. (8), `r_b2 ≈ L(1 + β cos θc)`. With Eq. (18) in time this is not an approximation:
    /// it equals [`NfgPair::base_radius`] identically (tested).
    #[inline]
    pub fn base_radius_eq8(&self, theta_c: f64) -> f64 {
        self.base_radius_mean() * (1.0 + self.base_radius_variation() * theta_c.dcos())
    }

    /// Time mean of `r_b2²`, `L²(1 + β²/2)`, the factor in `ωn` of Eq. (10), m².
    pub fn base_radius_mean_square(&self) -> f64 {
        let l = self.base_radius_mean();
        let b = self.base_radius_variation();
        l * l * (1.0 + 0.5 * b * b)
    }

    /// First harmonic of `r_b2` over the NFG polar angle `φ2` (the pitch curve itself), `(L', β')`
    /// with `r_b2(φ2) = L'[1 + 2Σ εⁿ cos nφ2]`: `L' = r1 cos α · i_j`, `β' = 2ε`.
    pub fn base_radius_first_harmonic_in_nfg_angle(&self) -> (f64, f64) {
        (
            self.pinion_base_radius() * self.p.ratio,
            2.0 * self.p.eccentricity,
        )
    }

    /// Angular frequency of the instantaneous-centre excitation, `ωc = ω1/i_j` (rad/s), for pinion
    /// speed `ω1` (rad/s).
    pub fn centre_angular_frequency(&self, omega1: f64) -> f64 {
        omega1 / self.p.ratio
    }

    /// Angular mesh frequency `ωe = Z1 ω1` (rad/s).
    pub fn mesh_angular_frequency(&self, omega1: f64) -> f64 {
        f64::from(self.p.z1) * omega1
    }

    /// `f_c = ω1/(2π i_j)`, Hz (Section 2.2, `f1`).
    pub fn centre_frequency(&self, omega1: f64) -> f64 {
        self.centre_angular_frequency(omega1) / TAU
    }

    /// `f_e = ω1 Z1/(2π)`, Hz (Section 2.2, `f2`).
    pub fn mesh_frequency(&self, omega1: f64) -> f64 {
        self.mesh_angular_frequency(omega1) / TAU
    }

    /// Rigid-body angular acceleration of the NFG `d²θ2/dτ²` at dimensionless time `τ` for the
    /// dimensionless centre frequency `ω̄c = ωc/ωn` (Eq. 20 / derived, see
    /// [`RigidAccelerationForm`]).
    #[inline]
    pub fn rigid_acceleration(&self, form: RigidAccelerationForm, wc_bar: f64, tau: f64) -> f64 {
        let e = self.p.eccentricity;
        let (s, c) = (wc_bar * tau).dsin_cos();
        let den = 1.0 + 2.0 * e * c + e * e;
        match form {
            RigidAccelerationForm::Derived => {
                2.0 * e * (1.0 - e * e) * wc_bar * wc_bar * s / (den * den)
            }
            RigidAccelerationForm::PrintedEq20 => 2.0 * wc_bar * e * (1.0 - e * e) * s / den,
        }
    }

    /// Fourier sine coefficient `Bn` of `d²θ2/dτ² = Σ Bn sin(n ω̄c τ)` in closed form
    /// (`B1`, `B2` of Eq. 22 for `n = 1, 2`; the cosine coefficients vanish):
    /// derived `Bn = 2n(−1)ⁿ⁺¹ εⁿ ω̄c²`; printed Eq. (20) `Bn = 2(1 − ε²)(−1)ⁿ⁺¹ εⁿ ω̄c`.
    pub fn rigid_acceleration_coefficient(
        &self,
        form: RigidAccelerationForm,
        n: u32,
        wc_bar: f64,
    ) -> f64 {
        rigid_acceleration_coefficient(self.p.eccentricity, form, n, wc_bar)
    }

    /// The same coefficient computed numerically: trapezoidal rule with `samples` points over one
    /// period of the exact expression (spectrally accurate for this analytic periodic function;
    /// 64 samples reach ~1e-16 relative at `ε = 0.2`).
    pub fn rigid_acceleration_coefficient_numeric(
        &self,
        form: RigidAccelerationForm,
        n: u32,
        wc_bar: f64,
        samples: usize,
    ) -> f64 {
        let m = samples.max(4);
        let mut s = 0.0;
        for k in 0..m {
            let theta = TAU * k as f64 / m as f64;
            // τ with ω̄c τ = θ (ω̄c ≠ 0 assumed; for ω̄c = 0 the acceleration is 0 anyway).
            let v = if wc_bar == 0.0 {
                0.0
            } else {
                self.rigid_acceleration(form, wc_bar, theta / wc_bar)
            };
            s += v * (f64::from(n) * theta).dsin();
        }
        2.0 * s / m as f64
    }

    /// `B1` from the first-harmonic route: Eq. (8) linearised, `ω2 ≈ (ω1 r_b1/L)(1 − β cos θ)`,
    /// gives `B1 ≈ ω̄c² β (1 − ε²)/(1 + ε²) = 2ε(1 − ε²)ω̄c²/(1 + ε²)²` and `B2 = 0`
    /// (relative error `O(ε²)` against the exact `2εω̄c²`).
    pub fn rigid_acceleration_b1_first_harmonic(&self, wc_bar: f64) -> f64 {
        let e = self.p.eccentricity;
        self.base_radius_variation() * (1.0 - e * e) / (1.0 + e * e) * wc_bar * wc_bar
    }
}

/// [`NfgPair::rigid_acceleration_coefficient`] of a pair with eccentric ratio `eccentricity`
/// (the coefficient reads nothing else of the pair): `Bn = 2n(−1)ⁿ⁺¹ εⁿ ω̄c²` derived,
/// `Bn = 2(1 − ε²)(−1)ⁿ⁺¹ εⁿ ω̄c` printed Eq. (20); `0` for `n = 0`. A model that changes its
/// speed recomputes its amplitudes with it, bit for bit those of a model built at that speed.
pub fn rigid_acceleration_coefficient(
    eccentricity: f64,
    form: RigidAccelerationForm,
    n: u32,
    wc_bar: f64,
) -> f64 {
    if n == 0 {
        return 0.0;
    }
    let e = eccentricity;
    let sign = if n % 2 == 1 { 1.0 } else { -1.0 };
    let en = e.powi(n as i32);
    match form {
        RigidAccelerationForm::Derived => 2.0 * f64::from(n) * sign * en * wc_bar * wc_bar,
        RigidAccelerationForm::PrintedEq20 => 2.0 * (1.0 - e * e) * sign * en * wc_bar,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An NFG pair with literal inputs (`m = 3 mm`, `Z1 = 20`, `i_j = 3`, `ε = 0.3`, `α = 25°`).
    fn nfg() -> NfgPair {
        let p = NfgPairParams {
            module: 3e-3,
            z1: 20,
            ratio: 3.0,
            eccentricity: 0.3,
            pressure_angle: 25f64.to_radians(),
        };
        NfgPair::new(p).unwrap()
    }

    #[test]
    fn validation() {
        let ok = nfg().params();
        let e = |p| NfgPair::new(p).unwrap_err().to_string();
        assert!(
            e(NfgPairParams {
                eccentricity: 1.0,
                ..ok
            })
            .starts_with("eccentricity")
        );
        assert!(
            e(NfgPairParams {
                eccentricity: f64::NAN,
                ..ok
            })
            .starts_with("eccentricity")
        );
        assert!(e(NfgPairParams { module: 0.0, ..ok }).starts_with("module"));
        assert!(e(NfgPairParams { z1: 0, ..ok }).starts_with("z1"));
        assert!(
            e(NfgPairParams {
                pressure_angle: 2.0,
                ..ok
            })
            .starts_with("pressure_angle")
        );
    }

    #[test]
    fn nfg_angle_closes_and_matches_ratio() {
        let p = nfg();
        assert!((p.nfg_angle(TAU) - TAU).abs() < 1e-14);
        // dφ2/dθc = i_j/i12(θc)
        let h = 1e-5;
        for t in [0.3, 2.0, 4.0] {
            let d = (p.nfg_angle(t + h) - p.nfg_angle(t - h)) / (2.0 * h);
            assert!((d - p.params().ratio / p.ratio(t)).abs() < 1e-9);
            // the two parametrisations of the same ratio agree
            assert!((p.ratio_at_nfg_angle(p.nfg_angle(t)) - p.ratio(t)).abs() < 1e-12);
        }
    }
}
