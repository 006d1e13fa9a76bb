//! Spur pair geometry of Yu, Sun, Li, Wu 2021 (Section 2.2, Eq. 7–9, 16). The paper's pairs
//! (Tables 1–2) live with the model, `geardyn_models::yu2021`.

use math::DetMath;
use system::{
    CentreDisplacement, CentreDistanceForm, GeometryField, PairGeometry, PressureAngleLaw,
};

use crate::Error;
use crate::error::positive;

/// Unvalidated serde form of [`SpurPair`] (SI units).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SpurPairParams {
    /// `R_p`, reference (pitch) radius of the pinion (Eq. 8, Table 1), m.
    pub rp: f64,
    /// `R_g`, reference radius of the gear, m.
    pub rg: f64,
    /// `α0`, standard pressure angle (Section 3, "ideal meshing angle α0 = 20"), rad.
    pub pressure_angle: f64,
}

/// A validated involute spur pair, built on the workspace's one spur-pair geometry
/// ([`system::PairGeometry`], which the backlash leaf uses too): this type adds the
/// construction from module and teeth and the serde form [`SpurPairParams`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(try_from = "SpurPairParams", into = "SpurPairParams")
)]
pub struct SpurPair {
    g: PairGeometry,
}

impl TryFrom<SpurPairParams> for SpurPair {
    type Error = Error;
    fn try_from(p: SpurPairParams) -> Result<Self, Error> {
        Self::new(p)
    }
}

impl From<SpurPair> for SpurPairParams {
    fn from(s: SpurPair) -> Self {
        s.params()
    }
}

impl SpurPair {
    /// Validate: radii finite and `> 0`, `0 < α0 < π/2` ([`PairGeometry::new`]); the error
    /// names the field (`rp`, `rg`, `pressure_angle`).
    pub fn new(p: SpurPairParams) -> Result<Self, Error> {
        let g = PairGeometry::new(p.rp, p.rg, p.pressure_angle).map_err(|e| match e.field {
            GeometryField::PinionRadius => Error::invalid("rp", "finite and > 0", e.value),
            GeometryField::GearRadius => Error::invalid("rg", "finite and > 0", e.value),
            GeometryField::PressureAngle => {
                Error::invalid("pressure_angle", "in (0, pi/2) rad", e.value)
            }
        })?;
        Ok(Self { g })
    }

    /// From module `m` (m) and teeth: `R = m z/2`.
    pub fn from_module(module: f64, zp: u32, zg: u32, pressure_angle: f64) -> Result<Self, Error> {
        positive("module", module)?;
        if zp < 1 {
            return Err(Error::invalid("zp", ">= 1", f64::from(zp)));
        }
        if zg < 1 {
            return Err(Error::invalid("zg", ">= 1", f64::from(zg)));
        }
        Self::new(SpurPairParams {
            rp: 0.5 * module * f64::from(zp),
            rg: 0.5 * module * f64::from(zg),
            pressure_angle,
        })
    }

    /// The parameters.
    pub fn params(&self) -> SpurPairParams {
        SpurPairParams {
            rp: self.g.r_p,
            rg: self.g.r_g,
            pressure_angle: self.g.alpha0,
        }
    }

    /// The pair's geometry, the workspace's one [`PairGeometry`] (as the backlash leaf takes it).
    pub fn geometry(&self) -> PairGeometry {
        self.g
    }

    /// Reference radii `(R_p, R_g)`, m.
    pub fn reference_radii(&self) -> (f64, f64) {
        (self.g.r_p, self.g.r_g)
    }

    /// Base radii `(R_p cos α0, R_g cos α0)`, m (`R_pb` of Eq. 7).
    pub fn base_radii(&self) -> (f64, f64) {
        self.g.base_radii()
    }

    /// Nominal centre distance `a0 = R_p + R_g` (Section 2.2), m.
    pub fn nominal_centre_distance(&self) -> f64 {
        self.g.a0()
    }

    /// Standard pressure angle `α0`, rad.
    pub fn pressure_angle(&self) -> f64 {
        self.g.alpha0
    }

    /// Operating pressure angle at centre distance `a` (m), rad, under the workspace's one
    /// pressure-angle law (`system::PressureAngleLaw`, reading `R-YU-EQ16`):
    /// `cos α = a0 cos α0/a` ([`PressureAngleLaw::Involute`], base radii fixed),
    /// `cos α = (Rp + Rg)/a` (Eq. 16 as printed) or `α0` ([`PressureAngleLaw::Constant`]).
    ///
    /// The involute law needs `a ≥ a0 cos α0` (base circles apart); the printed Eq. (16) needs
    /// `a ≥ a0`. Outside, or for NaN, an error naming `a` (the backlash leaf clamps instead).
    #[inline]
    pub fn operating_pressure_angle(&self, a: f64, law: PressureAngleLaw) -> Result<f64, Error> {
        let (a0, alpha0) = (self.g.a0(), self.g.alpha0);
        let bound = match law {
            PressureAngleLaw::PrintedEq16 => ">= Rp + Rg (Eq. 16 as printed)",
            _ => ">= a0 cos(alpha0) (base circles must not overlap)",
        };
        if !(a.is_finite() && a >= law.cosine_numerator(a0, alpha0)) {
            return Err(Error::invalid("a", bound, a));
        }
        Ok(self.g.pressure_angle(a, law).0)
    }

    /// Actual centre distance of Eq. (8) as printed, `a = √((a0 + x_p − x_g)² + (y_p − y_g)²)`,
    /// for centre displacements (m) (`system::CentreDistanceForm::PrintedEq8`).
    #[inline]
    pub fn centre_distance(&self, xp: f64, yp: f64, xg: f64, yg: f64) -> f64 {
        self.centre_distance_with(xp, yp, xg, yg, CentreDistanceForm::PrintedEq8)
    }

    /// Actual centre distance in either frame of Eq. (8) ([`CentreDistanceForm`], reading
    /// `R-YU-EQ8`), m.
    #[inline]
    pub fn centre_distance_with(
        &self,
        xp: f64,
        yp: f64,
        xg: f64,
        yg: f64,
        form: CentreDistanceForm,
    ) -> f64 {
        self.g
            .centre_distance_with(&CentreDisplacement::new(xp, yp, xg, yg), form)
            .0
    }
}

/// Roll angle of an involute point with pressure angle `α`: `β = tan α = inv α + α` (Yu, text
/// after Eq. 7), rad.
#[inline]
pub fn roll_angle(pressure_angle: f64) -> f64 {
    pressure_angle.dtan()
}

/// Arc length of an involute of base radius `r_b` between roll angles `β0` and `βc` (Yu Eq. 7):
/// `∫ r_b β dβ = r_b(βc² − β0²)/2`, m.
#[inline]
pub fn involute_arc_length(base_radius: f64, beta0: f64, beta_c: f64) -> f64 {
    0.5 * base_radius * (beta_c * beta_c - beta0 * beta0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nominal_distance_gives_twenty_degrees_only_in_consistent_form() {
        // module 3 mm, 50/50 teeth, α0 = 20° (the pair of Yu 2021 Table 2)
        let s = SpurPair::from_module(3e-3, 50, 50, 20f64.to_radians()).unwrap();
        let a0 = s.nominal_centre_distance();
        assert!((a0 - 0.15).abs() < 1e-15);
        let c = s
            .operating_pressure_angle(a0, PressureAngleLaw::Involute)
            .unwrap();
        assert!((c.to_degrees() - 20.0).abs() < 1e-12);
        let p = s
            .operating_pressure_angle(a0, PressureAngleLaw::PrintedEq16)
            .unwrap();
        assert!(p.abs() < 1e-12);
        assert!(
            s.operating_pressure_angle(0.9 * a0, PressureAngleLaw::PrintedEq16)
                .is_err()
        );
        assert!(
            s.operating_pressure_angle(f64::NAN, PressureAngleLaw::Involute)
                .is_err()
        );
        // a larger centre distance opens the pressure angle (base radii fixed)
        let c2 = s
            .operating_pressure_angle(a0 + 1e-4, PressureAngleLaw::Involute)
            .unwrap();
        assert!(c2 > c);
    }

    #[test]
    fn involute_arc_length_matches_quadrature() {
        let rb = 0.07;
        let q = system::numeric::integrate(|b| rb * b, 0.2, 0.5, 1e-15);
        assert!((q.value - involute_arc_length(rb, 0.2, 0.5)).abs() < 1e-16);
        assert!((roll_angle(20f64.to_radians()) - 0.363_970_234_266_202_4).abs() < 1e-15);
    }
}
