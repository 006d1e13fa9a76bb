//! Liu 2021 as the generic spur pair ([`crate::pair`]), in its circular limit: the preset
//! [`PairParams::liu2021`]. The pair stands under the papers and knows none of them; each
//! paper's preset lives in its own folder.

use backlash::{Backlash, CentreDistanceForm, PressureAngleLaw};
use mesh_stiffness::Stiffness;

use crate::Error;
use crate::pair::{Dofs, PairParams};

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
    use crate::pair::test_support::{accel, close};
    use crate::pair::{GearPair, PairParams};

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
            let e = er * (w * tau + phi).cos();
            let e_rate = -er * w * (w * tau + phi).sin();
            let u_dd = accel(&pair, tau, &[q + e], &[v + e_rate])[0];
            let got = u_dd + w * w * e;
            let want = m.acceleration(tau, q, v);
            assert!(close(got, want, m.b0), "{tau}: {got} vs {want}");
        }
        let m = crate::liu2021::table1().model().unwrap();
        assert!(PairParams::liu2021(&m).is_err());
    }
}
