//! Contact stiffness of the tooth pair: the fractal rough-surface stiffness of Yu 2021 Eq. (18)
//! and a Hertzian line contact of the same pair for comparison.

use math::DetMath;
use std::f64::consts::PI;

use crate::error::{Error, Result, positive};

/// Which form of Yu Eq. (18) to evaluate (reading R-YU-EQ18).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum FractalForm {
    /// Sign-consistent form (default): the printed factor `1/(1 − D)` is replaced by
    /// `1/(D − 1)`, and the removable singularity of `(l_a^e − l_s^e)/e` at
    /// `e = D − D² + 1 = 0` (D = golden ratio ≈ 1.618) is replaced by its limit `ln(l_a/l_s)`.
    /// Positive for every admissible input.
    #[default]
    Consistent,
    /// Eq. (18) exactly as printed: negative for every `D ∈ (1, 2)` (the ratio
    /// `(l_a^e − l_s^e)/e` is positive and `1 − D < 0`); at `e = 0` the limit is used as well.
    Printed,
}

/// The "coefficient of curved surfaces" `λ_c` of Yu Eq. (18).
///
/// Yu prints `λ_c = {(3FR/4E)^{1/3} / [2π(R₁ + R₂)]}^{2/R}`, whose exponent contains the
/// dimensional radius `R`; the number then depends on the length unit (reading R-YU-EQ18).
/// The default is an explicit `λ_c = 1` (no curvature correction).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum CurvatureCoefficient {
    /// An explicit value `λ_c > 0` \[-\]. `Value(1.0)` is the default.
    Value(f64),
    /// `base^p` with `base = (3FR/4E)^{1/3} / [2π(R₁ + R₂)]` and a user exponent `p` \[-\].
    FromLoad {
        /// Exponent `p`.
        exponent: f64,
    },
    /// The printed `base^{2/R}` with `R` in metres (evidence only; dimensionally meaningless).
    Printed,
}

impl Default for CurvatureCoefficient {
    fn default() -> Self {
        Self::Value(1.0)
    }
}

/// Inputs of the fractal contact stiffness, Yu et al. 2021 Eq. (18), all explicit (SI).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FractalContact {
    /// Fractal dimension `D` \[-\], in (1, 2) (Yu Eq. 2, 18).
    pub fractal_dimension: f64,
    /// Fractal roughness `G` \[m\], > 0 (Yu Eq. 2, 18).
    pub fractal_roughness: f64,
    /// Elastic modulus `E` \[Pa\] (Yu Eq. 18).
    pub elastic_modulus: f64,
    /// Hardness `H` \[Pa\]; `φ = H/E` (Yu Eq. 18).
    pub hardness: f64,
    /// Poisson's ratio `ν` \[-\], in [0, 0.5); `q = 0.454 + 0.41ν` (Yu Eq. 18).
    pub poisson_ratio: f64,
    /// Curvature radius of the pinion flank at the contact `R₁ = R_p` \[m\] (Yu Eq. 18 text).
    pub radius_pinion: f64,
    /// Curvature radius of the gear flank at the contact `R₂ = R_g` \[m\] (Yu Eq. 18 text).
    pub radius_gear: f64,
    /// Normal load `F` \[N\] (enters `λ_c`; Yu Eq. 18 text).
    pub load: f64,
    /// Largest asperity base diameter `l_a` \[m\] (Yu Eq. 2, 18).
    pub largest_asperity: f64,
    /// Smallest asperity base diameter `l_s` \[m\], `0 < l_s < l_a` (Yu Eq. 18).
    pub smallest_asperity: f64,
    /// Largest contact area of a single asperity `a_L` \[m²\] (Yu Eq. 18).
    pub largest_contact_area: f64,
    /// Coefficient of curved surfaces `λ_c` (Yu Eq. 18).
    pub curvature_coefficient: CurvatureCoefficient,
}

impl FractalContact {
    /// Check every input (ranges in the field docs). NaN is always an error.
    pub fn validate(&self) -> Result<()> {
        let d = self.fractal_dimension;
        if !(d > 1.0 && d < 2.0) {
            return Err(Error::InvalidParameter {
                name: "D",
                bound: "in (1, 2)",
                value: d,
            });
        }
        positive("G", self.fractal_roughness)?;
        positive("E", self.elastic_modulus)?;
        positive("H", self.hardness)?;
        let nu = self.poisson_ratio;
        if !(0.0..0.5).contains(&nu) {
            return Err(Error::InvalidParameter {
                name: "Poisson's ratio",
                bound: "in [0, 0.5)",
                value: nu,
            });
        }
        positive("R_p (pinion curvature radius)", self.radius_pinion)?;
        positive("R_g (gear curvature radius)", self.radius_gear)?;
        positive("F (load)", self.load)?;
        positive("l_a", self.largest_asperity)?;
        positive("l_s", self.smallest_asperity)?;
        if self.smallest_asperity >= self.largest_asperity {
            return Err(Error::InvalidParameter {
                name: "l_s",
                bound: "< l_a",
                value: self.smallest_asperity,
            });
        }
        positive("a_L", self.largest_contact_area)?;
        match self.curvature_coefficient {
            CurvatureCoefficient::Value(v) => {
                positive("lambda_c", v)?;
            }
            CurvatureCoefficient::FromLoad { exponent } => {
                crate::error::finite("lambda_c exponent", exponent)?;
            }
            CurvatureCoefficient::Printed => {}
        }
        Ok(())
    }

    /// Equivalent curvature radius `R = R_p R_g / (R_p + R_g)` \[m\] (Yu Eq. 18 text).
    pub fn equivalent_radius(&self) -> f64 {
        self.radius_pinion * self.radius_gear / (self.radius_pinion + self.radius_gear)
    }

    /// `q = 0.454 + 0.41 ν` \[-\] (Yu Eq. 18 text).
    pub fn q(&self) -> f64 {
        0.454 + 0.41 * self.poisson_ratio
    }

    /// `φ = H/E` \[-\] (Yu Eq. 18 text).
    pub fn phi(&self) -> f64 {
        self.hardness / self.elastic_modulus
    }

    /// `λ_c` \[-\] as selected by [`FractalContact::curvature_coefficient`] (inputs validated).
    pub fn lambda_c(&self) -> Result<f64> {
        self.validate()?;
        let base = || {
            let r = self.equivalent_radius();
            (3.0 * self.load * r / (4.0 * self.elastic_modulus)).dcbrt()
                / (2.0 * PI * (self.radius_pinion + self.radius_gear))
        };
        let v = match self.curvature_coefficient {
            CurvatureCoefficient::Value(v) => v,
            CurvatureCoefficient::FromLoad { exponent } => base().dpowf(exponent),
            CurvatureCoefficient::Printed => base().dpowf(2.0 / self.equivalent_radius()),
        };
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(Error::InvalidParameter {
                name: "lambda_c (computed)",
                bound: "finite and > 0",
                value: v,
            })
        }
    }

    /// Fractal contact stiffness `k_c` of Yu Eq. (18), evaluated with SI inputs:
    ///
    /// `k_c = 2^D D G^{(D−1)²} / [e (1 − D)] · E λ_c a_L^{D/2} / [π^{(2−D)/2} (φq)^{D−1}]
    ///        · (l_a^e − l_s^e)`, `e = D − D² + 1`
    ///
    /// (`1 + D² − 2D = (D − 1)²`). [`FractalForm::Consistent`] uses `D − 1` for `1 − D`.
    /// Note (R-YU-EQ18): with a dimensionless `λ_c` the printed expression has the unit
    /// Pa·m^{(D−1)² + D + (D−D²+1)} = Pa·m² = N, not N/m. Its number does not depend on the
    /// length unit (a force), but it is not a stiffness; Yu uses it as `k_am` \[N/m\] all the
    /// same, and so does this function (value returned as is, read as N/m).
    pub fn stiffness(&self, form: FractalForm) -> Result<f64> {
        let lambda_c = self.lambda_c()?;
        let d = self.fractal_dimension;
        let e = d - d * d + 1.0;
        let (la, ls) = (self.largest_asperity, self.smallest_asperity);
        // (l_a^e − l_s^e)/e, stable through e = 0 where it tends to ln(l_a/l_s)
        let ln_r = (la / ls).dln();
        let scale_term = if e.abs() < 1e-12 {
            ln_r
        } else {
            ls.dpowf(e) * (e * ln_r).dexp_m1() / e
        };
        let sign = match form {
            FractalForm::Consistent => 1.0,
            FractalForm::Printed => -1.0,
        };
        let k = sign * 2f64.dpowf(d) * d * self.fractal_roughness.dpowf((d - 1.0).powi(2))
            / (d - 1.0)
            * self.elastic_modulus
            * lambda_c
            * self.largest_contact_area.dpowf(0.5 * d)
            / (PI.dpowf(0.5 * (2.0 - d)) * (self.phi() * self.q()).dpowf(d - 1.0))
            * scale_term;
        if k.is_finite() {
            Ok(k)
        } else {
            Err(Error::InvalidParameter {
                name: "k_c (computed; inputs overflow)",
                bound: "finite",
                value: k,
            })
        }
    }

    /// The Hertzian line contact of the same pair (same E, ν, radii) with face width `b` \[m\].
    pub fn hertz_line_contact(&self, face_width: f64) -> Result<HertzLineContact> {
        self.validate()?;
        HertzLineContact::same_material(
            self.elastic_modulus,
            self.poisson_ratio,
            self.radius_pinion,
            self.radius_gear,
            face_width,
        )
    }
}

/// Hertzian contact of two parallel elastic cylinders along a line of length `b` (the tooth
/// pair's flanks at the contact point, radii = flank curvature radii).
///
/// - `E*`: `1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂`; `R = R₁R₂/(R₁ + R₂)`.
/// - Half-width of the contact strip (Johnson 1985, *Contact Mechanics*, Eq. 4.77 with load per
///   length `P = F/b`): `a = sqrt(4PR/(πE*))`.
/// - Approach of the cylinder axes (Johnson 1985, Eq. 5.36):
///   `δ = (P/π) Σ_i (1 − ν_i²)/E_i [2 ln(4R_i/a) − 1]`.
/// - Tangent stiffness `dF/dδ = b / (dδ/dP)` with
///   `dδ/dP = (1/π) Σ_i (1 − ν_i²)/E_i [2 ln(4R_i/a) − 2]` (since `a ∝ √P`).
/// - Load-independent estimate used in gear mesh-stiffness work (Yang & Lin 1987, ASME
///   J. Mech. Transm. Autom. Des. 109:189; Tian 2004): `k_h = π E* b / 2`, which is
///   `π E b / [4(1 − ν²)]` for two equal materials.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct HertzLineContact {
    /// Elastic modulus of body 1 `E₁` \[Pa\].
    pub elastic_modulus_1: f64,
    /// Poisson's ratio of body 1 `ν₁` \[-\].
    pub poisson_ratio_1: f64,
    /// Elastic modulus of body 2 `E₂` \[Pa\].
    pub elastic_modulus_2: f64,
    /// Poisson's ratio of body 2 `ν₂` \[-\].
    pub poisson_ratio_2: f64,
    /// Curvature radius of body 1 at the contact `R₁` \[m\].
    pub radius_1: f64,
    /// Curvature radius of body 2 at the contact `R₂` \[m\].
    pub radius_2: f64,
    /// Contact line length (face width) `b` \[m\].
    pub face_width: f64,
}

impl HertzLineContact {
    /// Validated constructor: moduli, radii, width > 0; Poisson's ratios in [0, 0.5).
    pub fn new(
        elastic_modulus_1: f64,
        poisson_ratio_1: f64,
        elastic_modulus_2: f64,
        poisson_ratio_2: f64,
        radius_1: f64,
        radius_2: f64,
        face_width: f64,
    ) -> Result<Self> {
        positive("E1", elastic_modulus_1)?;
        positive("E2", elastic_modulus_2)?;
        for (name, nu) in [
            ("Poisson's ratio 1", poisson_ratio_1),
            ("Poisson's ratio 2", poisson_ratio_2),
        ] {
            if !(0.0..0.5).contains(&nu) {
                return Err(Error::InvalidParameter {
                    name,
                    bound: "in [0, 0.5)",
                    value: nu,
                });
            }
        }
        positive("R1", radius_1)?;
        positive("R2", radius_2)?;
        positive("face width", face_width)?;
        Ok(Self {
            elastic_modulus_1,
            poisson_ratio_1,
            elastic_modulus_2,
            poisson_ratio_2,
            radius_1,
            radius_2,
            face_width,
        })
    }

    /// Two bodies of the same material.
    pub fn same_material(
        elastic_modulus: f64,
        poisson_ratio: f64,
        radius_1: f64,
        radius_2: f64,
        face_width: f64,
    ) -> Result<Self> {
        Self::new(
            elastic_modulus,
            poisson_ratio,
            elastic_modulus,
            poisson_ratio,
            radius_1,
            radius_2,
            face_width,
        )
    }

    fn compliances(&self) -> (f64, f64) {
        (
            (1.0 - self.poisson_ratio_1.powi(2)) / self.elastic_modulus_1,
            (1.0 - self.poisson_ratio_2.powi(2)) / self.elastic_modulus_2,
        )
    }

    /// Effective modulus `E*` \[Pa\].
    pub fn effective_modulus(&self) -> f64 {
        let (c1, c2) = self.compliances();
        1.0 / (c1 + c2)
    }

    /// Effective radius `R = R₁R₂/(R₁ + R₂)` \[m\].
    pub fn effective_radius(&self) -> f64 {
        self.radius_1 * self.radius_2 / (self.radius_1 + self.radius_2)
    }

    /// Load-independent line-contact stiffness `π E* b / 2` \[N/m\] (Yang & Lin 1987).
    pub fn stiffness_yang_lin(&self) -> f64 {
        0.5 * PI * self.effective_modulus() * self.face_width
    }

    /// Contact half-width `a` \[m\] under normal load `F` \[N\] (Johnson Eq. 4.77).
    pub fn half_width(&self, load: f64) -> Result<f64> {
        positive("F (load)", load)?;
        let p = load / self.face_width;
        Ok((4.0 * p * self.effective_radius() / (PI * self.effective_modulus())).sqrt())
    }

    /// Approach `δ` \[m\] of the two cylinder axes under load `F` \[N\] (Johnson Eq. 5.36).
    pub fn approach(&self, load: f64) -> Result<f64> {
        let a = self.half_width(load)?;
        let p = load / self.face_width;
        let (c1, c2) = self.compliances();
        Ok(p / PI
            * (c1 * (2.0 * (4.0 * self.radius_1 / a).dln() - 1.0)
                + c2 * (2.0 * (4.0 * self.radius_2 / a).dln() - 1.0)))
    }

    /// Tangent stiffness `dF/dδ` \[N/m\] at load `F` \[N\] (from Johnson Eq. 5.36). Errors if the
    /// load is so large that `a > 4R_i/e` (the formula's compliance turns non-positive).
    pub fn tangent_stiffness(&self, load: f64) -> Result<f64> {
        let a = self.half_width(load)?;
        let (c1, c2) = self.compliances();
        let dd = (c1 * (2.0 * (4.0 * self.radius_1 / a).dln() - 2.0)
            + c2 * (2.0 * (4.0 * self.radius_2 / a).dln() - 2.0))
            / PI;
        if dd > 0.0 && dd.is_finite() {
            Ok(self.face_width / dd)
        } else {
            Err(Error::InvalidParameter {
                name: "F (load; contact wider than the Johnson Eq. 5.36 range)",
                bound: "small enough that a < 4R/e",
                value: load,
            })
        }
    }
}

#[cfg(test)]
#[path = "../tests/it/reference_contact.rs"]
mod reference_contact;

#[cfg(test)]
mod tests {
    use super::reference_contact::reference_contact;
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn printed_is_negative_consistent_is_positive() {
        let p = reference_contact();
        let c = p.stiffness(FractalForm::Consistent).unwrap();
        let pr = p.stiffness(FractalForm::Printed).unwrap();
        assert!(c > 0.0);
        assert_relative_eq!(pr, -c, max_relative = 1e-15);
    }

    #[test]
    fn golden_ratio_limit_is_continuous() {
        let golden = 0.5 * (1.0 + 5f64.sqrt());
        let mut p = reference_contact();
        p.fractal_dimension = golden;
        let k0 = p.stiffness(FractalForm::Consistent).unwrap();
        for h in [1e-6, -1e-6] {
            p.fractal_dimension = golden + h;
            let k = p.stiffness(FractalForm::Consistent).unwrap();
            assert_relative_eq!(k, k0, max_relative = 1e-4);
        }
    }

    #[test]
    fn validation_messages() {
        let mut p = reference_contact();
        p.fractal_dimension = 2.3;
        assert_eq!(
            p.stiffness(FractalForm::Consistent)
                .unwrap_err()
                .to_string(),
            "D must be in (1, 2), got 2.3"
        );
        let base = reference_contact();
        type Edit = Box<dyn Fn(&mut FractalContact)>;
        let cases: Vec<Edit> = vec![
            Box::new(|p| p.fractal_dimension = 1.0),
            Box::new(|p| p.fractal_dimension = f64::NAN),
            Box::new(|p| p.fractal_roughness = 0.0),
            Box::new(|p| p.elastic_modulus = -1.0),
            Box::new(|p| p.hardness = 0.0),
            Box::new(|p| p.poisson_ratio = 0.5),
            Box::new(|p| p.radius_pinion = 0.0),
            Box::new(|p| p.radius_gear = f64::INFINITY),
            Box::new(|p| p.load = -5.0),
            Box::new(|p| p.smallest_asperity = p.largest_asperity),
            Box::new(|p| p.largest_contact_area = f64::NAN),
            Box::new(|p| p.curvature_coefficient = CurvatureCoefficient::Value(0.0)),
        ];
        for f in cases {
            let mut p = base;
            f(&mut p);
            assert!(p.stiffness(FractalForm::Consistent).is_err(), "{p:?}");
        }
    }

    #[test]
    fn printed_lambda_is_unit_dependent_and_tiny() {
        let mut p = reference_contact();
        p.curvature_coefficient = CurvatureCoefficient::Printed;
        // exponent 2/R ≈ 124 for R ≈ 0.016 m: λ_c underflows towards 0 -> error, never NaN
        let r = p.lambda_c();
        assert!(r.is_err() || r.unwrap() < 1e-100);
        p.curvature_coefficient = CurvatureCoefficient::FromLoad { exponent: 0.0 };
        assert_relative_eq!(p.lambda_c().unwrap(), 1.0);
    }
}
