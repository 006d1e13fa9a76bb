//! The one operating-pressure-angle law and the one centre-distance form of an involute spur
//! pair (Yu et al. 2021, Eq. 8 and Eq. 16; readings `R-YU-EQ16`, `R-YU-EQ8`).
//!
//! Two leaves need them and may depend only on this crate: `geardyn-gear-geometry`
//! (`SpurPair::operating_pressure_angle`, `SpurPair::centre_distance`) and `geardyn-backlash`
//! (`PairGeometry`, the dynamic backlash). Both re-export these types, so there is one enum per
//! concept and one formula behind it.
//!
//! Pressure angle at centre distance `a` of a pair with nominal distance `a0 = R_p + R_g` and
//! standard pressure angle `α0`:
//!
//! ```text
//! cos α = c/a,   c = a0 cos α0 = R_pb + R_gb   (involute: base circles fixed, α(a0) = α0)
//!                c = a0 = R_p + R_g            (Yu Eq. 16 as printed: α(a0) = 0)
//! dα/da = c/(a √(a² − c²))
//! ```
//!
//! Centre distance for centre displacements (Eq. 8), `s = +1` as printed, `s = −1` in the
//! frame of Eq. (12) and (15):
//!
//! ```text
//! a = √((a0 + s(x_p − x_g))² + (y_p − y_g)²),   Δa = a − a0 = (dx(2a0 + dx) + y²)/(a + a0)
//! ```

/// Law of the operating pressure angle `α(a)` of a spur pair (reading `R-YU-EQ16`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum PressureAngleLaw {
    /// Involute geometry: `cos α = (R_pb + R_gb)/a = a0 cos α0/a` (default; `α = α0` at
    /// `a = a0`).
    #[default]
    Involute,
    /// Yu Eq. (16) as printed: `cos α = (R_p + R_g)/a`; `α = 0` at `a = a0`, undefined for
    /// `a < a0`.
    PrintedEq16,
    /// `α = α0` whatever the centre distance.
    Constant,
}

impl PressureAngleLaw {
    /// The numerator `c` of `cos α = c/a`: `a0 cos α0` ([`PressureAngleLaw::Involute`] and,
    /// as the base-circle sum, [`PressureAngleLaw::Constant`]) or `a0`
    /// ([`PressureAngleLaw::PrintedEq16`]), m.
    #[inline]
    pub fn cosine_numerator(self, a0: f64, alpha0: f64) -> f64 {
        match self {
            PressureAngleLaw::Involute | PressureAngleLaw::Constant => a0 * alpha0.cos(),
            PressureAngleLaw::PrintedEq16 => a0,
        }
    }

    /// `α(a)` (rad) and `dα/da` for nominal distance `a0` and standard angle `α0`. Where the
    /// law is undefined (`a ≤ c`, or `a` NaN) the angle is clamped to `(0, 0)`: no NaN.
    /// [`PressureAngleLaw::Constant`] gives `(α0, 0)`. Callers that must reject `a < c`
    /// check [`PressureAngleLaw::cosine_numerator`] first.
    #[inline]
    pub fn angle(self, a: f64, a0: f64, alpha0: f64) -> (f64, f64) {
        if self == PressureAngleLaw::Constant {
            return (alpha0, 0.0);
        }
        let c = self.cosine_numerator(a0, alpha0);
        if a > c {
            let alpha = (c / a).acos();
            (alpha, c / (a * (a * a - c * c).sqrt()))
        } else {
            (0.0, 0.0)
        }
    }
}

/// Sign of the centre separation in the centre distance, Yu Eq. (8)–(9) (reading `R-YU-EQ8`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum CentreDistanceForm {
    /// Eq. (8) as printed, `a = √((a0 + x_p − x_g)² + (y_p − y_g)²)` (default of the leaves:
    /// `x_p > 0` or `x_g < 0` moves the centres apart).
    #[default]
    PrintedEq8,
    /// `a = √((a0 − x_p + x_g)² + (y_p − y_g)²)`: the frame of Yu Eq. (12) and (15), in which a
    /// growing `x_p − x_g` moves the centres together (the `models::yu2021` default).
    Consistent,
}

impl CentreDistanceForm {
    /// `+1` (printed) or `−1` (consistent): the factor of `x_p − x_g` in `a`.
    #[inline]
    pub fn sign(self) -> f64 {
        match self {
            CentreDistanceForm::PrintedEq8 => 1.0,
            CentreDistanceForm::Consistent => -1.0,
        }
    }

    /// Centre distance `a`, `Δa = a − a0` (free of cancellation) and the gradient
    /// `∂a/∂(x_p, y_p, x_g, y_g)`, for nominal distance `a0` and relative displacements
    /// `dx = x_p − x_g`, `dy = y_p − y_g` (m). The gradient is 0 at `a = 0`.
    #[inline]
    pub fn centre_distance(self, a0: f64, dx: f64, dy: f64) -> (f64, f64, [f64; 4]) {
        let dx = self.sign() * dx;
        let x = a0 + dx;
        let a = x.hypot(dy);
        let delta_a = (dx * (2.0 * a0 + dx) + dy * dy) / (a + a0);
        let (ux, uy) = if a > 0.0 {
            (self.sign() * x / a, dy / a)
        } else {
            (0.0, 0.0)
        };
        (a, delta_a, [ux, uy, -ux, -uy])
    }
}

#[cfg(test)]
#[allow(clippy::float_cmp)] // exact values: the clamped branches and a 3-4-5 triangle
mod tests {
    use super::*;

    #[test]
    fn pressure_angle_laws() {
        let (a0, al0) = (0.15, 20f64.to_radians());
        // involute: α0 at a0, and a cos α = a0 cos α0 at any a above the base-circle sum
        let (a, _) = PressureAngleLaw::Involute.angle(a0, a0, al0);
        assert!((a - al0).abs() < 1e-15);
        for da in [-0.005, 1e-4, 0.01] {
            let (al, d) = PressureAngleLaw::Involute.angle(a0 + da, a0, al0);
            assert!(((a0 + da) * al.cos() - a0 * al0.cos()).abs() < 1e-15);
            // dα/da by central differences
            let h = 1e-7;
            let fd = (PressureAngleLaw::Involute.angle(a0 + da + h, a0, al0).0
                - PressureAngleLaw::Involute.angle(a0 + da - h, a0, al0).0)
                / (2.0 * h);
            assert!((fd - d).abs() < 1e-6 * d.abs(), "{fd} vs {d}");
        }
        // printed Eq. 16: 0 at a0 and clamped below; 2.09° at a0 + 0.1 mm (Yu Table 2 pair)
        assert_eq!(PressureAngleLaw::PrintedEq16.angle(a0, a0, al0), (0.0, 0.0));
        assert_eq!(
            PressureAngleLaw::PrintedEq16.angle(0.9 * a0, a0, al0),
            (0.0, 0.0)
        );
        let p = PressureAngleLaw::PrintedEq16.angle(0.1501, a0, al0).0;
        assert!((p.to_degrees() - 2.092).abs() < 1e-3);
        assert_eq!(PressureAngleLaw::Constant.angle(0.2, a0, al0), (al0, 0.0));
        assert_eq!(
            PressureAngleLaw::Involute.angle(f64::NAN, a0, al0),
            (0.0, 0.0)
        );
    }

    #[test]
    fn centre_distance_forms() {
        let a0 = 0.188;
        let (a, da, g) = CentreDistanceForm::PrintedEq8.centre_distance(a0, 1e-4, 0.0);
        assert!((a - 0.1881).abs() < 1e-15 && (da - 1e-4).abs() < 1e-16);
        assert_eq!(g, [1.0, 0.0, -1.0, -0.0]);
        let (a, da, _) = CentreDistanceForm::Consistent.centre_distance(a0, 1e-4, 0.0);
        assert!((a - 0.1879).abs() < 1e-15 && (da + 1e-4).abs() < 1e-16);
        // Δa is exact where a − a0 cancels: 3-4-5 triangle scaled
        let (a, da, _) = CentreDistanceForm::PrintedEq8.centre_distance(3.0, 0.0, 4.0);
        assert_eq!((a, da), (5.0, 2.0));
        assert_eq!(
            CentreDistanceForm::PrintedEq8
                .centre_distance(0.0, 0.0, 0.0)
                .2,
            [0.0; 4]
        );
    }
}
