//! The presets of Liu 2021: the Section 3.8 test rig ([`Rig`], Table 2, reading
//! `R-LIU-TABLE2`) and the model as the generic spur pair ([`crate::pair`]) in its circular
//! limit, [`PairParams::liu2021`]. The pair stands under the papers and knows none of them; each
//! paper's preset lives in its own folder. The Table 1 parameter set is [`super::table1`]
//! (its NFG geometry: `table1().pair()`).

use backlash::{Backlash, CentreDistanceForm, PressureAngleLaw};
use mesh_stiffness::Stiffness;

use crate::Error;
use crate::pair::{Dofs, PairParams};

/// The vibration test rig of Liu et al. 2021, Section 3.8: a variable-frequency motor drives the
/// pinion through a synchronous belt drive of ratio `belt_ratio` (motor speed / pinion speed).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Rig {
    /// Belt reduction ratio, motor speed / pinion speed (text: "1.3").
    pub belt_ratio: f64,
    /// Pinion teeth `Z1`.
    pub z1: u32,
    /// NFG teeth `Z2` (mesh periods per NFG revolution).
    pub z2: u32,
    /// Instantaneous-centre cycles per NFG revolution (1 for Eq. 18).
    pub lobes: u32,
}

/// Liu et al. 2021, Table 2 (p. 371), theoretical columns: motor speed `n` (rpm), `f_c` (Hz),
/// `f_e` (Hz), exactly as printed.
pub const TABLE2_THEORETICAL: [(f64, f64, f64); 9] = [
    (280.0, 1.0, 64.0),
    (392.0, 1.4, 89.6),
    (504.0, 1.8, 115.2),
    (616.0, 2.2, 140.8),
    (728.0, 2.6, 166.4),
    (840.0, 3.0, 192.0),
    (952.0, 3.4, 217.6),
    (1064.0, 3.8, 243.2),
    (1176.0, 4.2, 268.8),
];

impl Rig {
    /// Validated rig: `belt_ratio > 0` (finite), `z1, z2, lobes ≥ 1`; the error names the field.
    pub fn new(belt_ratio: f64, z1: u32, z2: u32, lobes: u32) -> Result<Self, Error> {
        if !(belt_ratio.is_finite() && belt_ratio > 0.0) {
            return Err(Error::invalid("liu2021.rig.belt_ratio", "> 0", belt_ratio));
        }
        for (name, v) in [
            ("liu2021.rig.z1", z1),
            ("liu2021.rig.z2", z2),
            ("liu2021.rig.lobes", lobes),
        ] {
            if v < 1 {
                return Err(Error::invalid(name, ">= 1", f64::from(v)));
            }
        }
        Ok(Self {
            belt_ratio,
            z1,
            z2,
            lobes,
        })
    }

    /// The constants that reproduce both theoretical columns of Table 2 exactly (reading
    /// `R-LIU-TABLE2`): belt ratio `21/16 = 1.3125` (printed "1.3"), `Z1 = 18`, `Z2 = 64`
    /// (`i_j = 32/9 ≈ 3.556`, printed "3.5"), one lobe. Then `f_e = 8n/35` and `f_c = n/280`
    /// Hz, exact decimals at every printed motor speed.
    pub fn table2() -> Self {
        Self {
            belt_ratio: 21.0 / 16.0,
            z1: 18,
            z2: 64,
            lobes: 1,
        }
    }

    /// The rig as the text states it: belt ratio 1.3, `Z1 = 18`, `Z2 = i_j Z1 = 63`. Does not
    /// reproduce Table 2 (its `f_e` at 280 rpm is 64.6 Hz, not 64.0).
    pub fn as_printed() -> Self {
        Self {
            belt_ratio: 1.3,
            z1: 18,
            z2: 63,
            lobes: 1,
        }
    }

    /// Pinion speed for motor speed `n` (rpm), rpm.
    pub fn pinion_rpm(&self, motor_rpm: f64) -> f64 {
        motor_rpm / self.belt_ratio
    }

    /// Pinion angular speed `ω1` for motor speed `n` (rpm), rad/s.
    pub fn pinion_angular_speed(&self, motor_rpm: f64) -> f64 {
        self.pinion_rpm(motor_rpm) * std::f64::consts::TAU / 60.0
    }

    /// Mesh excitation frequency `f_e = Z1 · n_pinion/60`, Hz.
    pub fn mesh_frequency(&self, motor_rpm: f64) -> f64 {
        f64::from(self.z1) * self.pinion_rpm(motor_rpm) / 60.0
    }

    /// Instantaneous-centre frequency `f_c = lobes · f_e/Z2`, Hz.
    pub fn centre_frequency(&self, motor_rpm: f64) -> f64 {
        f64::from(self.lobes) * self.mesh_frequency(motor_rpm) / f64::from(self.z2)
    }
}

impl PairParams {
    /// The Liu 2021 model in its circular limit (`ε = 0`, see the module docs) as the 1-DOF
    /// pair, in Liu's dimensionless units. Errors for `ε ≠ 0` and for the readings that are
    /// no spur-pair physics (printed Eq. 21 error term).
    pub fn liu2021(model: &super::Model) -> Result<Self, Error> {
        use super::ErrorTerm;
        if model.beta != 0.0 || model.eccentricity != 0.0 {
            return Err(Error::invalid(
                "pair.liu2021 eccentricity (NFG: no spur-pair preset)",
                "= 0",
                model.eccentricity,
            ));
        }
        if model.readings.error_term != ErrorTerm::Derived {
            return Err(Error::UnsupportedReading {
                field: "pair.liu2021.readings.error_term",
                reading: format!("{:?}", model.readings.error_term),
            });
        }
        Ok(Self {
            // geometry enters only through α_0 (1-DOF); unit radii in units of L
            geometry: gear_geometry::SpurPairParams {
                rp: 1.0,
                rg: 1.0,
                pressure_angle: 20f64.to_radians(),
            },
            dofs: Dofs::Torsional,
            equivalent_mass: 1.0,
            masses: [1.0, 1.0],
            bearing_stiffness: [0.0; 4],
            bearing_damping: [0.0; 4],
            mesh_damping: 2.0 * model.zeta,
            static_force: -model.b0,
            // e = −ē = −(e_r/L) sin(ω̄_e τ + φ_e) = (e_r/L) cos(ω̄_e τ + φ_e + π/2)
            ste_amplitude: model.error,
            ste_phase: model.phase_error + std::f64::consts::FRAC_PI_2,
            mesh_frequency: model.omega_e,
            stiffness: Stiffness::SingleHarmonic(model.mesh_stiffness_law()),
            backlash: Backlash::RadiusModulated(model.backlash_law()),
            pressure_angle: PressureAngleLaw::Constant,
            centre_distance: CentreDistanceForm::Consistent,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::{Rig, TABLE2_THEORETICAL};
    use crate::pair::test_support::{accel, close};
    use crate::pair::{GearPair, PairParams};
    use math::DetMath;

    /// Format to one decimal the way the paper prints it.
    fn one_decimal(x: f64) -> String {
        format!("{x:.1}")
    }

    #[test]
    fn table2_theoretical_frequencies_to_every_printed_digit() {
        // Liu et al. 2021, Table 2 (p. 371), columns n, f_c/Hz and f_e/Hz of "Theoretical results".
        let rig = Rig::table2();
        for (n, fc, fe) in TABLE2_THEORETICAL {
            let (c, e) = (rig.centre_frequency(n), rig.mesh_frequency(n));
            assert_eq!(one_decimal(c), one_decimal(fc), "f_c at {n} rpm: {c}");
            assert_eq!(one_decimal(e), one_decimal(fe), "f_e at {n} rpm: {e}");
            // and the values are exact decimals: f_e = 8n/35, f_c = n/280
            assert!((e - 8.0 * n / 35.0).abs() < 1e-12 && (c - n / 280.0).abs() < 1e-13);
        }
        // 840 rpm: 192 Hz and 3 Hz; ω1 = 2π·640/60 rad/s
        assert!((rig.mesh_frequency(840.0) - 192.0).abs() < 1e-12);
        assert!((rig.centre_frequency(840.0) - 3.0).abs() < 1e-12);
        let w = rig.pinion_angular_speed(840.0);
        assert!((w - std::f64::consts::TAU * 640.0 / 60.0).abs() < 1e-12);
    }

    #[test]
    fn table2_is_not_reproduced_by_the_rounded_text_constants() {
        // Belt ratio 1.3 and Z2 = i_j·Z1 = 63 (Section 3.8, Table 1) miss the f_e column.
        let rig = Rig::as_printed();
        let misses = TABLE2_THEORETICAL
            .iter()
            .filter(|(n, _, fe)| one_decimal(rig.mesh_frequency(*n)) != one_decimal(*fe))
            .count();
        assert_eq!(misses, 9);
        // Z2 = 63 with the exact belt ratio gets f_e right but f_c only when truncating:
        // at 952 rpm f_c = 217.6/63 = 3.454 → "3.5" rounded, Table 2 prints 3.4.
        let r63 = Rig::new(21.0 / 16.0, 18, 63, 1).unwrap();
        assert_eq!(one_decimal(r63.centre_frequency(952.0)), "3.5");
        // Fig. 17's "864 rpm" gives 197.5 Hz, not the 192 Hz it quotes (which is the 840 rpm row).
        assert!((Rig::table2().mesh_frequency(864.0) - 197.485_714).abs() < 1e-5);
    }

    #[test]
    fn rig_validation_names_the_field() {
        let e = |r: Result<Rig, crate::Error>| r.unwrap_err().to_string();
        assert!(e(Rig::new(0.0, 18, 64, 1)).contains("belt_ratio"));
        assert!(e(Rig::new(f64::NAN, 18, 64, 1)).contains("belt_ratio"));
        assert!(e(Rig::new(1.3, 18, 0, 1)).contains("z2"));
        assert!(e(Rig::new(1.3, 0, 64, 1)).contains("z1"));
        assert!(e(Rig::new(1.3, 18, 64, 0)).contains("lobes"));
    }

    /// The Table 1 NFG geometry comes from the parameter set: `r1 = 22.5 mm`, `L = 80.168 mm`,
    /// `β = 0.3846` (Eq. 8).
    #[test]
    fn table1_nfg_geometry() {
        let p = crate::liu2021::table1().pair().unwrap();
        assert!((p.pinion_pitch_radius() - 0.0225).abs() < 1e-16);
        assert!((p.base_radius_mean() - 0.080_167_53).abs() < 1e-8);
        assert!((p.base_radius_variation() - 0.384_615_38).abs() < 1e-8);
    }

    /// Liu's model in its circular limit (ε = 0) is the torsional pair with `δ = q`.
    #[test]
    fn liu_circular_limit_is_the_torsional_pair() {
        let mut p = crate::liu2021::table1();
        p.eccentricity = 0.0;
        let m = p.model().unwrap();
        let pre = PairParams::liu2021(&m).unwrap();
        let pair = GearPair::from_params(&pre).unwrap();
        let (er, phi, w) = (pre.ste_amplitude, pre.ste_phase, pre.mesh_frequency);
        for (tau, q, v) in [
            (0.3, -0.002, 0.01),
            (7.7, 0.0001, -0.02),
            (40.0, 0.003, 0.0),
        ] {
            let e = er * (w * tau + phi).dcos();
            let e_rate = -er * w * (w * tau + phi).dsin();
            let u_dd = accel(&pair, tau, &[q + e], &[v + e_rate])[0];
            let got = u_dd + w * w * e;
            let want = m.acceleration(tau, q, v);
            assert!(close(got, want, m.b0), "{tau}: {got} vs {want}");
        }
        let m = crate::liu2021::table1().model().unwrap();
        assert!(PairParams::liu2021(&m).is_err());
    }
}
