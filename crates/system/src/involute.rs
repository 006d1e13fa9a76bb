//! The one operating-pressure-angle law and the one centre-distance form of an involute spur
//! pair (Yu et al. 2021, Eq. 8 and Eq. 16; readings `R-YU-EQ16`, `R-YU-EQ8`).
//!
//! Two leaves need them and may depend only on this crate: `geardyn-gear-geometry`
//! (`SpurPair::operating_pressure_angle`, `SpurPair::centre_distance`) and `geardyn-backlash`
//! (the dynamic backlash). Both re-export these types, so there is one enum per concept and one
//! formula behind it. The pair's geometry itself is one type too, [`PairGeometry`] (reference
//! radii, `α_0`, centre distance, pressure angle, Δp of Eq. 7) with [`CentreDisplacement`] and
//! [`Beta0`]: the backlash leaf re-exports it and `gear_geometry::SpurPair` is built on it.
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

use math::DetMath;
use std::cell::Cell;

thread_local! {
    /// The last `(α0 bits, cos α0)` of [`cos_standard_angle`] on this thread.
    static COS_ALPHA0: Cell<Option<(u64, f64)>> = const { Cell::new(None) };
    /// The last key of [`PairGeometry::delta_p_with`] under [`Beta0::LawAtRest`] on this
    /// thread and its `tan α(a0)`.
    static TAN_AT_REST: Cell<Option<(RestKey, f64)>> = const { Cell::new(None) };
}

/// The bits of `a0` and `α0` and the law: what `tan α(a0)` depends on.
type RestKey = (u64, u64, PressureAngleLaw);

/// `cos α0`: the same double as `α0.dcos()` (`geardyn-math`), kept per thread for the last
/// `α0` asked (keyed on its bits). The pair's laws ask it several times in every evaluation
/// (the cosine numerator `c`, the base radii, Δp of Eq. 7), and the time stepping of a model
/// evaluates them at every right-hand side with one `α0`.
#[inline]
pub fn cos_standard_angle(alpha0: f64) -> f64 {
    kept(&COS_ALPHA0, alpha0.to_bits(), || alpha0.dcos())
}

/// The value kept in `slot` for `key`, or `value()` computed, kept and returned.
#[inline]
fn kept<K: Copy + PartialEq + 'static>(
    slot: &'static std::thread::LocalKey<Cell<Option<(K, f64)>>>,
    key: K,
    value: impl FnOnce() -> f64,
) -> f64 {
    slot.with(|slot| match slot.get() {
        Some((k, v)) if k == key => v,
        _ => {
            let v = value();
            slot.set(Some((key, v)));
            v
        }
    })
}
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
            PressureAngleLaw::Involute | PressureAngleLaw::Constant => {
                a0 * cos_standard_angle(alpha0)
            }
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
            let alpha = (c / a).dacos();
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
        let a = x.dhypot(dy);
        let delta_a = (dx * (2.0 * a0 + dx) + dy * dy) / (a + a0);
        let (ux, uy) = if a > 0.0 {
            (self.sign() * x / a, dy / a)
        } else {
            (0.0, 0.0)
        };
        (a, delta_a, [ux, uy, -ux, -uy])
    }
}

/// The field of a [`PairGeometry`] outside its range.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum GeometryField {
    /// `R_p`: finite and `> 0`.
    PinionRadius,
    /// `R_g`: finite and `> 0`.
    GearRadius,
    /// `α_0`: in `(0, π/2)` rad.
    PressureAngle,
}

/// A [`PairGeometry`] field outside its range, with the value given.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error("spur pair: {field:?} = {value} is outside its range")]
pub struct InvalidGeometry {
    /// Which field.
    pub field: GeometryField,
    /// The value given.
    pub value: f64,
}

/// The nominal geometry of an involute spur pair: reference radii and standard pressure angle,
/// with the nominal centre distance, base radii, the centre distance of displaced centres
/// (Eq. 8–9) and the operating pressure angle (Eq. 16) under [`PressureAngleLaw`], and Δp of
/// Eq. (7). The one home of the spur-pair geometry: `geardyn_backlash::PairGeometry` is this type,
/// and `geardyn_gear_geometry::SpurPair` is built on it.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct PairGeometry {
    /// Reference (pitch) radius of the pinion R_p (m), > 0 (Yu Eq. 8, 16).
    pub r_p: f64,
    /// Reference (pitch) radius of the gear R_g (m), > 0 (Yu Eq. 8, 16).
    pub r_g: f64,
    /// Nominal pressure angle α_0 (rad), in (0, π/2) (Yu §3: 20°).
    pub alpha0: f64,
}

impl PairGeometry {
    /// Checked constructor: radii finite and `> 0`, `α_0` in `(0, π/2)`; the error names the
    /// field ([`GeometryField`]) and carries the value, and each leaf words it in its own terms.
    pub fn new(r_p: f64, r_g: f64, alpha0: f64) -> Result<Self, InvalidGeometry> {
        let bad = |field, value| Err(InvalidGeometry { field, value });
        if !(r_p.is_finite() && r_p > 0.0) {
            return bad(GeometryField::PinionRadius, r_p);
        }
        if !(r_g.is_finite() && r_g > 0.0) {
            return bad(GeometryField::GearRadius, r_g);
        }
        if !(alpha0.is_finite() && alpha0 > 0.0 && alpha0 < std::f64::consts::FRAC_PI_2) {
            return bad(GeometryField::PressureAngle, alpha0);
        }
        Ok(Self { r_p, r_g, alpha0 })
    }

    /// Base radii `(R_p cos α_0, R_g cos α_0)` (m).
    #[inline]
    pub fn base_radii(&self) -> (f64, f64) {
        let c = cos_standard_angle(self.alpha0);
        (self.r_p * c, self.r_g * c)
    }

    /// Nominal centre distance a_0 = R_p + R_g (m).
    #[inline]
    pub fn a0(&self) -> f64 {
        self.r_p + self.r_g
    }

    /// Pinion base radius R_pb = R_p cos α_0 (m) (Yu Eq. 7).
    #[inline]
    pub fn r_pb(&self) -> f64 {
        self.r_p * cos_standard_angle(self.alpha0)
    }

    /// Sum of base radii R_pb + R_gb = a_0 cos α_0 (m).
    #[inline]
    pub fn base_sum(&self) -> f64 {
        self.a0() * cos_standard_angle(self.alpha0)
    }

    /// Actual centre distance a (Yu Eq. 8, printed sign) and Δa = a − a_0 (Eq. 9), with
    /// ∂a/∂(x_p, y_p, x_g, y_g). Δa is computed as (a² − a_0²)/(a + a_0), free of cancellation
    /// for tiny displacements. [`PairGeometry::centre_distance_with`] takes the sign option.
    #[inline]
    pub fn centre_distance(&self, c: &CentreDisplacement) -> (f64, f64, [f64; 4]) {
        self.centre_distance_with(c, CentreDistanceForm::PrintedEq8)
    }

    /// As [`PairGeometry::centre_distance`] under the sign convention `form` (Yu Eq. 8 as
    /// printed, `a_0 + x_p − x_g`, or the frame of Eq. 12/15, `a_0 − x_p + x_g`).
    #[inline]
    pub fn centre_distance_with(
        &self,
        c: &CentreDisplacement,
        form: CentreDistanceForm,
    ) -> (f64, f64, [f64; 4]) {
        form.centre_distance(self.a0(), c.x_p - c.x_g, c.y_p - c.y_g)
    }

    /// Operating pressure angle α at centre distance `a` (rad) and dα/da, for the given law.
    /// `cos α = c/a` with c = R_pb + R_gb (involute) or c = R_p + R_g (printed Eq. 16); for
    /// a ≤ c the angle is clamped to 0 (and dα/da = 0): no NaN.
    /// [`PressureAngleLaw::Constant`] gives `(α_0, 0)`.
    #[inline]
    pub fn pressure_angle(&self, a: f64, law: PressureAngleLaw) -> (f64, f64) {
        law.angle(a, self.a0(), self.alpha0)
    }

    /// The numerator `c` of `cos α = c/a` of `law` for this pair (m).
    #[inline]
    pub fn law_constant(&self, law: PressureAngleLaw) -> f64 {
        law.cosine_numerator(self.a0(), self.alpha0)
    }

    /// Δp of Yu Eq. (7): (R_pb/2)(β_c² − β_0²), β = tan α, β_0 = tan α_0, β_c from the law at
    /// centre distance `a`; returns (Δp, dΔp/da). Uses tan²α = a²/c² − 1 (no trigonometry).
    /// [`PairGeometry::delta_p_with`] takes the reference angle option.
    #[inline]
    pub fn delta_p(&self, a: f64, law: PressureAngleLaw) -> (f64, f64) {
        self.delta_p_with(a, law, Beta0::Nominal)
    }

    /// Δp of Yu Eq. (7) with β_0 per `beta0`: `tan α_0` ([`Beta0::Nominal`]) or the law's own
    /// angle at `a_0` ([`Beta0::LawAtRest`], zero under the printed Eq. 16, so that Δp = 0 at
    /// rest under every law).
    #[inline]
    pub fn delta_p_with(&self, a: f64, law: PressureAngleLaw, beta0: Beta0) -> (f64, f64) {
        if law == PressureAngleLaw::Constant {
            return (0.0, 0.0);
        }
        let c = self.law_constant(law);
        let r_pb = self.r_pb();
        let t0 = match beta0 {
            Beta0::Nominal => self.alpha0.dtan(),
            Beta0::LawAtRest => {
                // a constant of the pair and the law: kept per thread for the last pair asked
                let key = (self.a0().to_bits(), self.alpha0.to_bits(), law);
                kept(&TAN_AT_REST, key, || {
                    self.pressure_angle(self.a0(), law).0.dtan()
                })
            }
        };
        let (beta_c_sq, d) = if a > c {
            (a * a / (c * c) - 1.0, 2.0 * a / (c * c))
        } else {
            (0.0, 0.0)
        };
        let diff = match law {
            // β_c² − β_0² = (a² − a_0²)/c² exactly, since tan²α_0 = a_0²/c² − 1
            PressureAngleLaw::Involute if a > c => {
                let a0 = self.a0();
                (a - a0) * (a + a0) / (c * c)
            }
            _ => beta_c_sq - t0 * t0,
        };
        (0.5 * r_pb * diff, 0.5 * r_pb * d)
    }
}

/// Translations of the two gear centres (m), Yu Fig. 6 / Eq. (8): x along the line of centres,
/// y normal to it, signed so that a = √((a_0 + x_p − x_g)² + (y_p − y_g)²) (x_p > 0 or x_g < 0
/// moves the centres apart).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct CentreDisplacement {
    /// x_p (m).
    pub x_p: f64,
    /// y_p (m).
    pub y_p: f64,
    /// x_g (m).
    pub x_g: f64,
    /// y_g (m).
    pub y_g: f64,
}

impl CentreDisplacement {
    /// From (x_p, y_p, x_g, y_g) in m.
    pub fn new(x_p: f64, y_p: f64, x_g: f64, y_g: f64) -> Self {
        Self { x_p, y_p, x_g, y_g }
    }

    /// As an array in the order of the gradients: [x_p, y_p, x_g, y_g].
    pub fn to_array(&self) -> [f64; 4] {
        [self.x_p, self.y_p, self.x_g, self.y_g]
    }

    /// From an array [x_p, y_p, x_g, y_g].
    pub fn from_array(v: [f64; 4]) -> Self {
        Self::new(v[0], v[1], v[2], v[3])
    }
}

/// Reference angle β_0 = tan α of Yu Eq. (7) (reading R-YU-EQ16).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Beta0 {
    /// β_0 = tan α_0, the nominal pressure angle (default).
    #[default]
    Nominal,
    /// β_0 from the pressure-angle law at the nominal centre distance (0 under the printed
    /// Eq. 16): Δp vanishes at rest under every law.
    LawAtRest,
}

#[cfg(test)]
#[allow(clippy::float_cmp)] // exact values: the clamped branches and a 3-4-5 triangle
mod tests {
    use super::*;

    /// The values kept per thread are the ones computed afresh, bit for bit: pairs and laws
    /// that alternate, a public field changed between calls, and another thread.
    #[test]
    fn kept_constants_are_never_stale() {
        // the law constant `c` and `R_pb` computed afresh (no kept value)
        let fresh = |g: &PairGeometry, law: PressureAngleLaw| {
            let c = match law {
                PressureAngleLaw::PrintedEq16 => g.a0(),
                _ => g.a0() * g.alpha0.dcos(),
            };
            (c, g.r_p * g.alpha0.dcos())
        };
        let mut g = PairGeometry::new(0.094, 0.094, 20f64.to_radians()).unwrap();
        let h = PairGeometry::new(0.05, 0.12, 25f64.to_radians()).unwrap();
        let laws = [PressureAngleLaw::Involute, PressureAngleLaw::PrintedEq16];
        let check = |g: &PairGeometry, law: PressureAngleLaw| {
            let (c, r_pb) = fresh(g, law);
            assert_eq!(g.law_constant(law).to_bits(), c.to_bits());
            assert_eq!(g.r_pb().to_bits(), r_pb.to_bits());
            assert_eq!(
                cos_standard_angle(g.alpha0).to_bits(),
                g.alpha0.dcos().to_bits()
            );
            // Δp at a displaced centre distance, against the same law with β0 computed afresh
            let a = g.a0() * 1.001;
            let got = g.delta_p_with(a, law, Beta0::LawAtRest);
            let cold = {
                TAN_AT_REST.with(|k| k.set(None));
                COS_ALPHA0.with(|k| k.set(None));
                g.delta_p_with(a, law, Beta0::LawAtRest)
            };
            assert_eq!(
                (got.0.to_bits(), got.1.to_bits()),
                (cold.0.to_bits(), cold.1.to_bits())
            );
        };
        for _ in 0..3 {
            for law in laws {
                check(&g, law);
                check(&h, law);
                check(&g, law);
            }
        }
        // a public field changed after the values were kept
        g.alpha0 = 22f64.to_radians();
        check(&g, PressureAngleLaw::Involute);
        g.r_g = 0.2;
        check(&g, PressureAngleLaw::Involute);
        std::thread::scope(|s| {
            s.spawn(|| check(&h, PressureAngleLaw::Involute));
        });
        check(&g, PressureAngleLaw::Involute);
    }

    #[test]
    fn pressure_angle_laws() {
        let (a0, al0) = (0.15, 20f64.to_radians());
        // involute: α0 at a0, and a cos α = a0 cos α0 at any a above the base-circle sum
        let (a, _) = PressureAngleLaw::Involute.angle(a0, a0, al0);
        assert!((a - al0).abs() < 1e-15);
        for da in [-0.005, 1e-4, 0.01] {
            let (al, d) = PressureAngleLaw::Involute.angle(a0 + da, a0, al0);
            assert!(((a0 + da) * al.dcos() - a0 * al0.dcos()).abs() < 1e-15);
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
