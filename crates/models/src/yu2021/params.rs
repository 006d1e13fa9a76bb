//! Dimensional parameters of the Yu 2021 spur pair (SI units) and the paper's parameter sets.

use serde::{Deserialize, Serialize};

use crate::Error;
use crate::error::{check_nonneg, check_pos};

use super::fractal::{FractalSurface, fractal_mean_height};

/// How the constant part of the backlash `b_s` (Eq. 1, 5) is given.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
#[non_exhaustive]
pub enum BacklashSpec {
    /// A constant backlash: `b_s = b` (m). This is the threshold `B` of the dead zone of Eq. (14)
    /// (half the total circumferential play projected on the line of action, Kahraman–Singh
    /// convention).
    Constant {
        /// `b_s` (m), dead-zone half width of Eq. (14).
        b: f64,
    },
    /// Fractal constant part, Eq. (5): `b_s = b_0 − b_p − b_g` with `b_i` the effective mean
    /// asperity height of Eq. (4). Both flanks use the same surface (the paper's assumption in
    /// Sec. 4.2: `D = D_p = D_g`, `G = G_p = G_g`).
    Fractal {
        /// Initial (ideal, smooth-surface) backlash `b_0` (m), Eq. (5).
        b0: f64,
        /// Surface description of Eq. (2)/(4) shared by pinion and gear.
        surface: FractalSurface,
    },
}

impl BacklashSpec {
    /// The constant part `b_s` (m) of the backlash. Errors if it is not positive.
    pub fn constant_part(&self) -> Result<f64, Error> {
        let bs = match *self {
            BacklashSpec::Constant { b } => {
                check_pos("yu2021.backlash.b", b)?;
                b
            }
            BacklashSpec::Fractal { b0, surface } => {
                check_pos("yu2021.backlash.b0", b0)?;
                b0 - 2.0 * fractal_mean_height(&surface)?
            }
        };
        if bs.is_nan() || bs <= 0.0 {
            return Err(Error::invalid(
                "yu2021.backlash (b_s = b0 - 2 b_i)",
                "> 0",
                bs,
            ));
        }
        Ok(bs)
    }
}

/// Dimensional parameters of the spur pair of Yu et al. 2021, Eq. (12)–(17). SI units.
///
/// The same struct drives the three models of the paper's comparison (Kahraman–Singh
/// constant backlash, Chen's fractal backlash, Yu's 6-DOF dynamic backlash); fields that a
/// model does not use are ignored by it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Yu2021Params {
    /// Pinion polar moment of inertia `I_p` (kg·m²), Eq. (12).
    pub inertia_p: f64,
    /// Gear polar moment of inertia `I_g` (kg·m²), Eq. (12).
    pub inertia_g: f64,
    /// Pinion mass `m_p` (kg), Eq. (12), translational DOF.
    pub mass_p: f64,
    /// Gear mass `m_g` (kg), Eq. (12), translational DOF.
    pub mass_g: f64,
    /// Pinion radius `R_p` (m), Eq. (12), (15): the radius on which the mesh force acts.
    pub radius_p: f64,
    /// Gear radius `R_g` (m), Eq. (12), (15).
    pub radius_g: f64,
    /// Nominal pressure angle `α_0` (rad), Sec. 3 ("α_0 = 20").
    pub pressure_angle: f64,
    /// Input torque `T_p` (N·m), Eq. (12); the output torque is `T_g = T_p R_g/R_p` (static
    /// balance), and the static mesh force is `F_s = T_p/R_p` (Eq. 20).
    pub torque: f64,
    /// Mean mesh stiffness `k_am` (N/m), Eq. (17).
    pub mesh_stiffness: f64,
    /// Ratio of stiffness fluctuation to mean `ε` (–), Eq. (17).
    pub stiffness_ratio: f64,
    /// Mesh damping ratio `ξ_c` (–), Eq. (13): `c_m = 2 ξ_c sqrt(k_am m_e)`.
    pub mesh_damping_ratio: f64,
    /// Amplitude `e_r` (m) of the static transmission error `e(t) = e_r cos(ω_h t + φ_0)`,
    /// Eq. (15).
    pub ste_amplitude: f64,
    /// Initial phase `φ_0` (rad) of `e(t)` and `k_m(t)`, Eq. (15), (17).
    pub phase: f64,
    /// Bearing/shaft stiffnesses `[k_px, k_py, k_gx, k_gy]` (N/m), Eq. (12).
    pub bearing_stiffness: [f64; 4],
    /// Bearing damping ratio `ξ_b` (–): `c_ij = 2 ξ_b sqrt(k_ij m_i)`, Eq. (12) (not in the paper).
    pub bearing_damping_ratio: f64,
    /// Nominal length `b_n` (m) of the nondimensionalisation (Sec. 3).
    pub nominal_length: f64,
    /// Constant part of the backlash, Eq. (1), (5).
    pub backlash: BacklashSpec,
    /// Amplitude `a_z` (m) of the time-varying fractal backlash of Chen's model,
    /// `B(t) = b_s + a_z z(ω_h t)` with `z` of Eq. (3). Not in Yu's paper (chosen).
    pub chen_amplitude: f64,
    /// Fractal dimension `D` used in Chen's `z(t)`, Eq. (3).
    pub chen_dimension: f64,
}

impl Yu2021Params {
    /// Yu Table 1 (the DF rig of Kahraman & Singh 1991, ref. \[10\]) with every unstated value
    /// chosen; see `docs/models/yu2021.md`, section "Parameter sets".
    ///
    /// Stated: 25/25 teeth, `I = 1.15e-3 kg·m²`, "equivalent mass" 0.23 kg, `R_p = R_g = 0.094 m`,
    /// `k_m = 3e8 N/m`, `T = 107.8 N·m`, `b_h = 1e-3 m`, `ξ = 0.1`, `T_dh = 0.019`.
    /// Read as: 0.23 kg = mass of each gear (`I/(2R²) = 0.065 kg` is the equivalent mass of
    /// the stated inertias and radii, reading R-YU-T1-ME); `b_h` = backlash `b_s` and `b_n`;
    /// `T_dh` = `e_r/b_n` (reading R-YU-T1-TDH).
    /// Chosen: `α_0 = 20°`, `ε = 0.2`, bearings `1e8 N/m` with `ξ_b = 0.02`, `φ_0 = 0`,
    /// Chen amplitude `0.05 b_h`, `D = 1.5`.
    pub fn table1() -> Self {
        Yu2021Params {
            inertia_p: 1.15e-3,
            inertia_g: 1.15e-3,
            mass_p: 0.23,
            mass_g: 0.23,
            radius_p: 0.094,
            radius_g: 0.094,
            pressure_angle: 20f64.to_radians(),
            torque: 107.8,
            mesh_stiffness: 3e8,
            stiffness_ratio: 0.2,
            mesh_damping_ratio: 0.1,
            ste_amplitude: 0.019 * 1e-3,
            phase: 0.0,
            bearing_stiffness: [1e8; 4],
            bearing_damping_ratio: 0.02,
            nominal_length: 1e-3,
            backlash: BacklashSpec::Constant { b: 1e-3 },
            chen_amplitude: 0.05e-3,
            chen_dimension: 1.5,
        }
    }

    /// Yu Table 2 (the RMS rig of Kahraman & Blankenship 1997, ref. \[28\]) with every unstated
    /// value chosen; see `docs/models/yu2021.md`.
    ///
    /// Stated: module 3 mm, 50/50 teeth (so `R = 75 mm`), `I = 9e-3 kg·m²`, mass 6.57 kg, face
    /// width 20 mm, `α_0 = 20°`, `E = 2.06e5 N/mm²`, load 340 N·m.
    /// Chosen: `k_am = c_γ·w` with `c_γ = 20 N/(mm·µm)` (ISO 6336-1 typical mesh stiffness per
    /// unit face width) giving `4e8 N/m`; `ε = 0.2`; `ξ_c = 0.05`; backlash and `b_n` = 10 µm
    /// (half play of a precision pair); `e_r = 5 µm`; bearings `1e8 N/m`, `ξ_b = 0.02`.
    pub fn table2() -> Self {
        Yu2021Params {
            inertia_p: 9e-3,
            inertia_g: 9e-3,
            mass_p: 6.57,
            mass_g: 6.57,
            radius_p: 0.075,
            radius_g: 0.075,
            pressure_angle: 20f64.to_radians(),
            torque: 340.0,
            mesh_stiffness: 20e9 * 0.02,
            stiffness_ratio: 0.2,
            mesh_damping_ratio: 0.05,
            ste_amplitude: 5e-6,
            phase: 0.0,
            bearing_stiffness: [1e8; 4],
            bearing_damping_ratio: 0.02,
            nominal_length: 10e-6,
            backlash: BacklashSpec::Constant { b: 10e-6 },
            chen_amplitude: 0.5e-6,
            chen_dimension: 1.5,
        }
    }

    /// Check every field; the error names the field and the bound.
    pub fn validate(&self) -> Result<(), Error> {
        check_pos("yu2021.inertia_p", self.inertia_p)?;
        check_pos("yu2021.inertia_g", self.inertia_g)?;
        check_pos("yu2021.mass_p", self.mass_p)?;
        check_pos("yu2021.mass_g", self.mass_g)?;
        check_pos("yu2021.radius_p", self.radius_p)?;
        check_pos("yu2021.radius_g", self.radius_g)?;
        let a = self.pressure_angle;
        if !(a > 0.0 && a < std::f64::consts::FRAC_PI_2) {
            return Err(Error::invalid(
                "yu2021.pressure_angle",
                "in (0, pi/2) rad",
                a,
            ));
        }
        check_pos("yu2021.torque", self.torque)?;
        check_pos("yu2021.mesh_stiffness", self.mesh_stiffness)?;
        let e = self.stiffness_ratio;
        if !(0.0..1.0).contains(&e) {
            return Err(Error::invalid("yu2021.stiffness_ratio", "in [0, 1)", e));
        }
        check_nonneg("yu2021.mesh_damping_ratio", self.mesh_damping_ratio)?;
        check_nonneg("yu2021.ste_amplitude", self.ste_amplitude)?;
        if !self.phase.is_finite() {
            return Err(Error::invalid("yu2021.phase", "finite", self.phase));
        }
        const NAMES: [&str; 4] = [
            "yu2021.bearing_stiffness[0] (k_px)",
            "yu2021.bearing_stiffness[1] (k_py)",
            "yu2021.bearing_stiffness[2] (k_gx)",
            "yu2021.bearing_stiffness[3] (k_gy)",
        ];
        for (name, k) in NAMES.iter().zip(self.bearing_stiffness) {
            check_pos(name, k)?;
        }
        check_nonneg("yu2021.bearing_damping_ratio", self.bearing_damping_ratio)?;
        check_pos("yu2021.nominal_length", self.nominal_length)?;
        self.backlash.constant_part()?;
        check_nonneg("yu2021.chen_amplitude", self.chen_amplitude)?;
        let d = self.chen_dimension;
        if !(d > 1.0 && d < 2.0) {
            return Err(Error::invalid("yu2021.chen_dimension", "in (1, 2)", d));
        }
        Ok(())
    }

    /// Equivalent mass `m_e = (R_p²/I_p + R_g²/I_g)^{-1}` (kg), Sec. 3.
    pub fn equivalent_mass(&self) -> f64 {
        1.0 / (self.radius_p.powi(2) / self.inertia_p + self.radius_g.powi(2) / self.inertia_g)
    }

    /// Natural frequency `ω_n = sqrt(k_am/m_e)` (rad/s), Sec. 3.
    pub fn natural_frequency(&self) -> f64 {
        (self.mesh_stiffness / self.equivalent_mass()).sqrt()
    }

    /// Static mesh force `F_s = T_p/R_p` (N), Eq. (20).
    pub fn static_force(&self) -> f64 {
        self.torque / self.radius_p
    }
}
