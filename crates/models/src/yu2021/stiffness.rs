//! Mean mesh stiffness `k_am` from the fractal contact stiffness of Eq. (18), so that the
//! fractal dimension `D` and roughness `G` act on the stiffness of the dynamic model (Sec. 3:
//! "taking `k_c` as `k_am`, the meshing stiffness can be obtained by Eq. (17)").
//!
//! Eq. (18) is evaluated by the `mesh-stiffness` leaf ([`FractalContact::stiffness`],
//! [`FractalForm::Consistent`]: the printed expression is negative for every `1 < D < 2`,
//! reading R-YU-EQ18). Its number has the unit of a force (N), not N/m (length exponent 2 with a
//! dimensionless `λ_c`; `docs/readings/mesh-stiffness.md`), so it cannot be used as `k_am` as it
//! stands: the level is set by one reference stiffness at a reference surface, and Eq. (18)
//! supplies the dependence on `D` and `G`:
//!
//! ```text
//! k_am(D, G) = k_ref · k_c(D, G) / k_c(D_ref, G_ref)
//! ```
//!
//! with `(D_ref, G_ref)` the fractal parameters of [`FractalMeshStiffness::contact`] and every
//! other input of Eq. (18) (E, H, ν, radii, load, `l_a`, `l_s`, `a_L`, `λ_c`) held fixed.

use serde::{Deserialize, Serialize};

use crate::Error;

use super::fractal::{FractalContact, FractalForm, FractalSurface, fractal_contact_stiffness};
use super::params::{BacklashSpec, Yu2021Params};
use crate::error::check_pos;

/// Mean mesh stiffness from Eq. (18) with one calibrated level (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FractalMeshStiffness {
    /// Inputs of Eq. (18) at the reference surface: its `fractal_dimension` and
    /// `fractal_roughness` are `D_ref`, `G_ref`; the other fields stay fixed when `D`, `G` vary.
    pub contact: FractalContact,
    /// `k_am` (N/m) at the reference surface.
    pub reference_stiffness: f64,
}

impl FractalMeshStiffness {
    /// The reference used by the Yu dynamic studies on the Table 2 rig: the `mesh-stiffness`
    /// leaf's documented defaults ([`FractalContact::yu2021_default`]: `D_ref = 1.5`,
    /// `G_ref = 1e-11 m`, steel, `l_a = 1e-4 m`, `l_s = 1e-8 m`, `a_L = π l_a²/4`, `λ_c = 1`)
    /// with the Table 2 pair's flank radii (`0.075 sin 20°` m) and load (340 N·m / 0.075 m),
    /// and `k_ref` = the Table 2 parameter set's mean stiffness (4e8 N/m, ISO 6336-1 typical
    /// `c_γ = 20 N/(mm·µm)` times the 20 mm face width).
    pub fn table2() -> Self {
        let p = Yu2021Params::table2();
        let r = p.radius_p * p.pressure_angle.sin();
        FractalMeshStiffness {
            contact: FractalContact {
                radius_pinion: r,
                radius_gear: p.radius_g * p.pressure_angle.sin(),
                load: p.static_force(),
                ..FractalContact::yu2021_default()
            },
            reference_stiffness: p.mesh_stiffness,
        }
    }

    /// `k_am(D, G)` (N/m). Errors if `D ∉ (1, 2)`, `G ≤ 0`, the reference is invalid or the
    /// leaf cannot evaluate Eq. (18).
    pub fn stiffness(&self, dimension: f64, roughness: f64) -> Result<f64, Error> {
        check_pos(
            "yu2021.fractal_stiffness.reference_stiffness",
            self.reference_stiffness,
        )?;
        let reference = fractal_contact_stiffness(&self.contact, FractalForm::Consistent)?;
        let at = FractalContact {
            fractal_dimension: dimension,
            fractal_roughness: roughness,
            ..self.contact
        };
        let k = fractal_contact_stiffness(&at, FractalForm::Consistent)?;
        let v = self.reference_stiffness * k / reference;
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(Error::invalid(
                "yu2021.fractal_stiffness (k_am computed)",
                "> 0 and finite",
                v,
            ))
        }
    }

    /// `k_am` for a surface of the backlash model (its `D` and `G`).
    pub fn for_surface(&self, surface: &FractalSurface) -> Result<f64, Error> {
        self.stiffness(surface.dimension, surface.roughness)
    }
}

impl Yu2021Params {
    /// The same parameters with `mesh_stiffness = k_am(D, G)` of `law`, `D` and `G` taken from
    /// the fractal constant part of the backlash, so that one surface sets both the backlash
    /// (Eq. 4–5) and the stiffness (Eq. 17–18). Errors if the backlash is not
    /// [`BacklashSpec::Fractal`] or Eq. (18) cannot be evaluated.
    pub fn with_fractal_stiffness(&self, law: &FractalMeshStiffness) -> Result<Self, Error> {
        let BacklashSpec::Fractal { surface, .. } = self.backlash else {
            return Err(Error::invalid(
                "yu2021.backlash (for the Eq. 18 stiffness)",
                "a fractal surface (BacklashSpec::Fractal)",
                f64::NAN,
            ));
        };
        Ok(Yu2021Params {
            mesh_stiffness: law.for_surface(&surface)?,
            ..*self
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reference_surface_gives_reference_stiffness() {
        let law = FractalMeshStiffness::table2();
        let k = law.stiffness(1.5, 1e-11).unwrap();
        assert!((k / 4e8 - 1.0).abs() < 1e-14, "{k}");
    }

    #[test]
    fn ratio_is_the_ratio_of_eq18() {
        let law = FractalMeshStiffness::table2();
        let c = |d: f64| {
            let at = FractalContact {
                fractal_dimension: d,
                ..law.contact
            };
            fractal_contact_stiffness(&at, FractalForm::Consistent).unwrap()
        };
        let r = law.stiffness(1.2, 1e-11).unwrap() / law.stiffness(1.8, 1e-11).unwrap();
        assert!((r / (c(1.2) / c(1.8)) - 1.0).abs() < 1e-12);
        // with the leaf's defaults Eq. (18) falls with D (docs/readings/mesh-stiffness.md)
        assert!(r > 1.0, "{r}");
    }

    #[test]
    fn params_take_d_and_g_from_the_backlash_surface() {
        let mut p = Yu2021Params::table2();
        let surface = FractalSurface {
            dimension: 1.4,
            roughness: 1e-11,
            lambda: 1.5,
            l_max: 1e-3,
            l_min: 1e-6,
            length: 1e-3,
        };
        let law = FractalMeshStiffness::table2();
        assert!(p.with_fractal_stiffness(&law).is_err());
        p.backlash = BacklashSpec::Fractal { b0: 30e-6, surface };
        let q = p.with_fractal_stiffness(&law).unwrap();
        assert_eq!(
            q.mesh_stiffness.to_bits(),
            law.stiffness(1.4, 1e-11).unwrap().to_bits()
        );
        assert_eq!(q.torque.to_bits(), p.torque.to_bits());
    }

    #[test]
    fn invalid_inputs_are_errors() {
        let law = FractalMeshStiffness::table2();
        assert!(law.stiffness(2.2, 1e-11).is_err());
        assert!(law.stiffness(1.4, -1.0).is_err());
        let bad = FractalMeshStiffness {
            reference_stiffness: 0.0,
            ..law
        };
        let e = bad.stiffness(1.4, 1e-11).unwrap_err();
        assert!(e.to_string().contains("reference_stiffness"), "{e}");
    }
}
