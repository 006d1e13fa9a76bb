//! Dimensional parameters of the NFG pair (Liu et al. 2021, Table 1) and the readings.

use serde::{Deserialize, Serialize};

use gear_geometry::{NfgPair, NfgPairParams};

use crate::Error;

/// Which form of the rigid angular acceleration d²θ₂/dτ² (Eq. 20) drives the model:
/// `Derived` from Eq. (18) (default) or `PrintedEq20`. Shared with `gear_geometry`.
///
/// See `docs/readings/liu.md`, `R-LIU-EQ20`.
pub use gear_geometry::RigidAccelerationForm as RigidAcceleration;

/// How many Fourier terms of the rigid acceleration enter the forcing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum RigidSeries {
    /// The first two Fourier terms, `B₁ sin x + B₂ sin 2x`, as in Eq. (22) (the default).
    #[default]
    TwoTerms,
    /// The closed form, all harmonics of ω̄_c.
    Exact,
}

/// Sign and form of the transmission-error term `d²ē/dτ²` on the right of Eq. (9).
///
/// See `docs/readings/liu.md`, `R-LIU-EQ21`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum ErrorTerm {
    /// `+d²ē/dτ²` with `ē = e/r_b2` differentiated twice: for `e = e_r sin(ω̄_e τ)` the
    /// forcing is `−(e_r/r_b2) ω̄_e² sin(ω̄_e τ)` (the default).
    #[default]
    Derived,
    /// Eq. (21)–(22) as printed: `+B₃ sin(ω̄_e τ)` with `B₃ = e_r ω̄_e² / r_b2`.
    Printed,
}

/// Which base radius divides the backlash and the error in `b̄ = b/r_b2`, `ē = e/r_b2` (Eq. 11–12).
///
/// See `docs/readings/liu.md`, `R-LIU-EQ11`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum BaseRadius {
    /// The time-varying `r_b2(τ) = L[1 + β cos(ω̄_c τ)]` of Eq. (8): the exact substitution
    /// `q = q₂ + e/r_b2` (the default).
    #[default]
    TimeVarying,
    /// The mean `L`: constant `b̄ = b/L` and `B₃ = e_r ω̄_e²/L` (the paper treats b̄ and B₃ as
    /// constants).
    Mean,
}

/// The readings of the places where the paper is inconsistent. `Default` gives the consistent
/// forms; [`Readings::printed`] gives the forms as printed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(default)]
pub struct Readings {
    /// Form of d²θ₂/dτ² (Eq. 20).
    pub rigid_acceleration: RigidAcceleration,
    /// Fourier truncation of d²θ₂/dτ² (Eq. 22).
    pub rigid_series: RigidSeries,
    /// Sign/form of d²ē/dτ² (Eq. 21).
    pub error_term: ErrorTerm,
    /// Base radius in b̄ and ē (Eq. 11–12).
    pub base_radius: BaseRadius,
}

impl Readings {
    /// Every combination of the four readings (2⁴ = 16), for checks that must hold in each.
    pub fn all() -> [Self; 16] {
        std::array::from_fn(|i| Self {
            rigid_acceleration: [RigidAcceleration::Derived, RigidAcceleration::PrintedEq20][i & 1],
            rigid_series: [RigidSeries::TwoTerms, RigidSeries::Exact][(i >> 1) & 1],
            error_term: [ErrorTerm::Printed, ErrorTerm::Derived][(i >> 2) & 1],
            base_radius: [BaseRadius::TimeVarying, BaseRadius::Mean][(i >> 3) & 1],
        })
    }

    /// Every reading as printed in the paper (Eq. 20, 21, constant b̄ and B₃, two Fourier terms).
    pub fn printed() -> Self {
        Self {
            rigid_acceleration: RigidAcceleration::PrintedEq20,
            rigid_series: RigidSeries::TwoTerms,
            error_term: ErrorTerm::Printed,
            base_radius: BaseRadius::Mean,
        }
    }
}

/// Dimensional parameters of the NFG pair, SI units (Liu et al. 2021, Table 1, Eq. 1–8, 18–19).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Parameters {
    /// Module of the pinion `m` \[m\] (Table 1: 2.5 mm).
    pub module: f64,
    /// Number of teeth of the pinion `Z₁` (Table 1: 18).
    pub z1: u32,
    /// Mean reduction ratio `i_j = Z₂/Z₁` (Table 1: 3.5; `i_j Z₁` must be an integer).
    pub ratio: f64,
    /// Eccentric ratio `ε` of the transmission ratio, Eq. (18) \[-\] (Table 1: 0.2), in `[0, 1)`.
    pub eccentricity: f64,
    /// Pressure angle `α` \[rad\] (Table 1: 20°).
    pub pressure_angle: f64,
    /// Load torque on the NFG `T₂` \[N·m\] (Table 1: 30).
    pub load_torque: f64,
    /// Moment of inertia of the NFG `I₂` \[kg·m²\] (Table 1: 0.014).
    pub inertia: f64,
    /// Mean mesh stiffness `k₀` \[N/m\], Eq. (19) (Table 1: 3.1e8).
    pub k0: f64,
    /// Amplitude of the mesh-stiffness fundamental `k_r` \[N/m\], Eq. (19) (Table 1: 0.9e8).
    pub kr: f64,
    /// Mesh damping ratio `ζ` \[-\], Eq. (9) (Table 1 calls it ξ: 0.01).
    pub damping_ratio: f64,
    /// Mean static transmission error `e₀` \[m\], Eq. (19) (Table 1: 0). A constant error only
    /// shifts `q`; it does not enter Eq. (22).
    pub e0: f64,
    /// Amplitude of the static transmission error `e_r` \[m\], Eq. (19) (Table 1: 1e-5).
    pub er: f64,
    /// Half of the tooth backlash `b` \[m\], Eq. (12) (Table 1: 5e-5).
    pub half_backlash: f64,
    /// Rotational velocity of the pinion `ω₁` \[rad/s\] (Table 1: 160).
    pub omega1: f64,
    /// Phase of the mesh stiffness `φ_m` \[rad\], Eq. (19) (paper: π/2).
    pub phase_stiffness: f64,
    /// Phase of the transmission error `φ_e` \[rad\], Eq. (19) (paper: 0).
    pub phase_error: f64,
    /// Readings of the inconsistent equations.
    #[serde(default)]
    pub readings: Readings,
}

/// The parameter set of Liu et al. 2021, Table 1 (with `φ_m = π/2`, `φ_e = 0` from Sect. 3.1).
pub fn table1() -> Parameters {
    Parameters {
        module: 2.5e-3,
        z1: 18,
        ratio: 3.5,
        eccentricity: 0.2,
        pressure_angle: 20f64.to_radians(),
        load_torque: 30.0,
        inertia: 0.014,
        k0: 3.1e8,
        kr: 0.9e8,
        damping_ratio: 0.01,
        e0: 0.0,
        er: 1e-5,
        half_backlash: 5e-5,
        omega1: 160.0,
        phase_stiffness: std::f64::consts::FRAC_PI_2,
        phase_error: 0.0,
        readings: Readings::default(),
    }
}

fn check(field: &'static str, value: f64, ok: bool, bound: &'static str) -> Result<(), Error> {
    if value.is_finite() && ok {
        Ok(())
    } else {
        Err(Error::invalid(format!("liu2021.{field}"), bound, value))
    }
}

impl Parameters {
    /// Check every field; the error names the first offending field and its bound.
    pub fn validate(&self) -> Result<(), Error> {
        check("module", self.module, self.module > 0.0, "> 0")?;
        check("z1", f64::from(self.z1), self.z1 >= 1, ">= 1")?;
        check("ratio", self.ratio, self.ratio > 0.0, "> 0")?;
        let z2 = self.ratio * f64::from(self.z1);
        check(
            "ratio",
            self.ratio,
            (z2 - z2.round()).abs() < 1e-9 && z2.round() >= 3.0,
            "such that ratio * z1 is an integer >= 3",
        )?;
        check(
            "eccentricity",
            self.eccentricity,
            (0.0..1.0).contains(&self.eccentricity),
            "in [0, 1)",
        )?;
        check(
            "pressure_angle",
            self.pressure_angle,
            self.pressure_angle > 0.0 && self.pressure_angle < std::f64::consts::FRAC_PI_2,
            "in (0, pi/2)",
        )?;
        check("load_torque", self.load_torque, true, "finite")?;
        check("inertia", self.inertia, self.inertia > 0.0, "> 0")?;
        check("k0", self.k0, self.k0 > 0.0, "> 0")?;
        check(
            "kr",
            self.kr,
            self.kr >= 0.0 && self.kr < self.k0,
            "in [0, k0)",
        )?;
        check(
            "damping_ratio",
            self.damping_ratio,
            self.damping_ratio >= 0.0,
            ">= 0",
        )?;
        check("e0", self.e0, true, "finite")?;
        check("er", self.er, self.er >= 0.0, ">= 0")?;
        check(
            "half_backlash",
            self.half_backlash,
            self.half_backlash >= 0.0,
            ">= 0",
        )?;
        check("omega1", self.omega1, self.omega1 > 0.0, "> 0")?;
        check("phase_stiffness", self.phase_stiffness, true, "finite")?;
        check("phase_error", self.phase_error, true, "finite")?;
        Ok(())
    }

    /// Number of teeth of the NFG, `Z₂ = i_j Z₁` (Sect. 2.4); call after [`Parameters::validate`].
    pub fn z2(&self) -> u32 {
        // validated: ratio*z1 is a positive integer
        (self.ratio * f64::from(self.z1)).round() as u32
    }

    /// The NFG pair geometry (Eq. 1, 8, 18) as a validated `gear_geometry::NfgPair`.
    pub fn pair(&self) -> Result<NfgPair, Error> {
        NfgPair::new(NfgPairParams {
            module: self.module,
            z1: self.z1,
            ratio: self.ratio,
            eccentricity: self.eccentricity,
            pressure_angle: self.pressure_angle,
        })
        .map_err(Error::from)
    }

    /// Mean equivalent base radius `L` \[m\] of Eq. (8), from Eq. (1) and (18):
    /// `r_b2 = r₁ i₁₂ cos α = L[1 + β cos(ω_c t)]`, `L = r₁ i_j cos α (1+ε²)/(1−ε²)`.
    pub fn mean_base_radius(&self) -> Result<f64, Error> {
        Ok(self.pair()?.base_radius_mean())
    }

    /// Change rate `β = 2ε/(1+ε²)` of the base radius, Eq. (8) from Eq. (18).
    pub fn base_radius_rate(&self) -> Result<f64, Error> {
        Ok(self.pair()?.base_radius_variation())
    }

    /// Angular frequency of the instantaneous-centre excitation `ω_c = ω₁/i_j` \[rad/s\]
    /// (Sect. 2.2: `f₁ = ω₁/(2π i_j)`; also the mean NFG speed, exactly, for Eq. 18).
    pub fn omega_c(&self) -> f64 {
        self.omega1 / self.ratio
    }

    /// Angular frequency of the mesh excitation `ω_e = ω₁ Z₁` \[rad/s\] (Sect. 2.2).
    pub fn omega_e(&self) -> f64 {
        self.omega1 * f64::from(self.z1)
    }

    /// Natural frequency `ω_n = sqrt(k₀ L² (1 + β²/2) / I₂)` \[rad/s\], Eq. (10).
    pub fn omega_n(&self) -> Result<f64, Error> {
        Ok((self.k0 * self.pair()?.base_radius_mean_square() / self.inertia).sqrt())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use math::DetMath;

    #[test]
    fn all_readings_are_distinct() {
        let all = Readings::all();
        for (i, a) in all.iter().enumerate() {
            assert!(all[..i].iter().all(|b| b != a), "{a:?} twice");
        }
    }

    #[test]
    fn table1_is_valid() {
        let p = table1();
        p.validate().unwrap();
        assert_eq!(p.z2(), 63);
    }

    #[test]
    fn omega_n_eq10() {
        let p = table1();
        let l = p.mean_base_radius().unwrap();
        let beta = p.base_radius_rate().unwrap();
        let wn = (p.k0 * l * l * (1.0 + 0.5 * beta * beta) / p.inertia).sqrt();
        assert!((p.omega_n().unwrap() / wn - 1.0).abs() < 1e-12);
        // L = r1 i_j cos(alpha) (1+e^2)/(1-e^2) = 0.0225 * 3.5 * cos 20deg * 1.04/0.96
        let l_ref = 0.0225 * 3.5 * 20f64.to_radians().dcos() * 1.04 / 0.96;
        assert!((l / l_ref - 1.0).abs() < 1e-12);
    }
}
