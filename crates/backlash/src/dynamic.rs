//! Dynamic backlash from gear-centre motion, Yu Eq. (6)–(11).

use crate::error::{Error, finite};
use math::DetMath;
pub use system::involute::{Beta0, CentreDisplacement, PairGeometry};
pub use system::{CentreDistanceForm, PressureAngleLaw};

/// Which relation turns centre motion into a backlash change b_dy.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum DynamicForm {
    /// Involute geometry (default): change of the *half* gap along the line of action,
    /// b_dy = (R_pb + R_gb)(inv α' − inv α_0), inv α = tan α − α, cos α' = (R_pb + R_gb)/a —
    /// half the change of the normal backlash `Δj_n = 2(R_pb + R_gb)(inv α' − inv α_0)`, because
    /// the dead zone takes a half gap (derivation in `docs/readings/backlash.md`,
    /// R-BACKLASH-HALF-GAP). Signed (centres apart → more backlash); linearisation
    /// b_dy ≈ sin α_0 Δa. Reading R-YU-EQ6.
    #[default]
    Involute,
    /// The line-of-action projection of the centre-distance change with the current angle,
    /// b_dy = Δa sin α(a), α from the [`PressureAngleLaw`]: the first-order form of
    /// [`DynamicForm::Involute`] (same half gap, same slope sin α_0 at rest; `models::yu2021`'s
    /// `DynamicBacklashLaw::Involute`).
    LineOfAction,
    /// Yu Eq. (6)/(10) as printed: Δb = (Δa² − Δp²)^{1/2} with Δp from Eq. (7); always ≥ 0
    /// (sign-blind) under the default radicand policy.
    YuEq10,
}

/// What to do when the radicand Δa² − Δp² of Yu Eq. (6) is negative.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum RadicandPolicy {
    /// Δb = √max(r, 0) (default): a negative radicand means "no change of backlash".
    #[default]
    ClampZero,
    /// Δb = sign(r)·√|r|: continuous, lets the backlash shrink.
    SignedRoot,
    /// Return [`Error::NegativeRadicand`].
    Reject,
}

/// Complete backlash B = b_s + b_dy (Yu Eq. 11) as a function of the centre displacements.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct DynamicBacklash {
    /// Pair geometry.
    pub geometry: PairGeometry,
    /// Constant part b_s (m) (Yu Eq. 5), e.g. from
    /// [`ConstantBacklashParams::constant_part`](crate::ConstantBacklashParams::constant_part).
    pub b_s: f64,
    /// Relation used for b_dy.
    pub form: DynamicForm,
    /// Pressure-angle law used for β_c in Eq. (7) (only for [`DynamicForm::YuEq10`]).
    pub law: PressureAngleLaw,
    /// Policy for a negative radicand (only for [`DynamicForm::YuEq10`]).
    pub policy: RadicandPolicy,
    /// Sign convention of Eq. (8) for the centre distance.
    #[cfg_attr(feature = "serde", serde(default))]
    pub centre_distance: CentreDistanceForm,
    /// Reference angle β_0 of Eq. (7) (only for [`DynamicForm::YuEq10`]).
    #[cfg_attr(feature = "serde", serde(default))]
    pub beta0: Beta0,
}

/// Everything computed by [`DynamicBacklash::eval`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct BacklashEval {
    /// B = b_s + b_dy (m) (Yu Eq. 11). May be negative (interference) with the signed forms;
    /// [`dead_zone`](crate::dead_zone) treats a negative gap as 0.
    pub b: f64,
    /// b_dy = Δb (m) (Yu Eq. 6/10 or the involute form).
    pub b_dy: f64,
    /// Actual centre distance a (m) (Eq. 8).
    pub a: f64,
    /// Δa = a − a_0 (m) (Eq. 9).
    pub delta_a: f64,
    /// Δp (m) (Eq. 7); 0 for the involute form.
    pub delta_p: f64,
    /// Δa² − Δp² (m²) (Eq. 6); 0 for the involute form.
    pub radicand: f64,
    /// Operating pressure angle α (rad) under the law in use (involute law for the involute form).
    pub alpha: f64,
    /// `dα/da` (rad per unit of `a`) of [`alpha`](Self::alpha)'s law at `a`; 0 where the
    /// angle is clamped (`a` at or below the law's `c`) and under the constant law.
    #[cfg_attr(feature = "serde", serde(default))]
    pub alpha_slope: f64,
    /// ∂a/∂(x_p, y_p, x_g, y_g) of the centre distance (dimensionless, Eq. 8; 0 at `a = 0`).
    #[cfg_attr(feature = "serde", serde(default))]
    pub centre_gradient: [f64; 4],
    /// ∂B/∂(x_p, y_p, x_g, y_g) (dimensionless). Where Δb has a kink (r = 0, or a clamped
    /// branch) the derivative of the clamped branch (0) is returned.
    pub grad: [f64; 4],
    /// `true` when the radicand was negative and the policy clamped or signed it.
    pub radicand_negative: bool,
}

impl DynamicBacklash {
    /// Checked constructor: `b_s` finite (it may be negative, see [`crate::ConstantPart`]).
    pub fn new(
        geometry: PairGeometry,
        b_s: f64,
        form: DynamicForm,
        law: PressureAngleLaw,
        policy: RadicandPolicy,
    ) -> Result<Self, Error> {
        let geometry = PairGeometry::new(geometry.r_p, geometry.r_g, geometry.alpha0)?;
        finite("b_s", b_s)?;
        Ok(Self {
            geometry,
            b_s,
            form,
            law,
            policy,
            centre_distance: CentreDistanceForm::default(),
            beta0: Beta0::default(),
        })
    }

    /// The same law under the centre-distance sign convention `form` (Yu Eq. 8).
    pub fn with_centre_distance(self, form: CentreDistanceForm) -> Self {
        Self {
            centre_distance: form,
            ..self
        }
    }

    /// The same law with the β_0 reference `beta0` of Eq. (7).
    pub fn with_beta0(self, beta0: Beta0) -> Self {
        Self { beta0, ..self }
    }

    /// Default choices (involute form), constant part `b_s`.
    pub fn involute(geometry: PairGeometry, b_s: f64) -> Result<Self, Error> {
        Self::new(
            geometry,
            b_s,
            DynamicForm::Involute,
            PressureAngleLaw::Involute,
            RadicandPolicy::ClampZero,
        )
    }

    /// B, b_dy and ∂B/∂(x_p, y_p, x_g, y_g) at the displacement `c`.
    ///
    /// Errors: non-finite displacement; negative radicand under [`RadicandPolicy::Reject`].
    /// Inline, allocation-free: meant to be called in every right-hand-side evaluation.
    #[inline]
    pub fn eval(&self, c: &CentreDisplacement) -> Result<BacklashEval, Error> {
        if !(c.x_p.is_finite() && c.y_p.is_finite() && c.x_g.is_finite() && c.y_g.is_finite()) {
            let bad = c
                .to_array()
                .into_iter()
                .find(|v| !v.is_finite())
                .unwrap_or(f64::NAN);
            return Err(Error::InvalidParameter {
                name: "centre displacement",
                bound: "finite",
                value: bad,
            });
        }
        let g = &self.geometry;
        let (a, delta_a, da) = g.centre_distance_with(c, self.centre_distance);
        let mut out = BacklashEval {
            a,
            delta_a,
            centre_gradient: da,
            ..BacklashEval::default()
        };
        let db_da = match self.form {
            DynamicForm::Involute => {
                let cb = g.base_sum();
                // inv α_0 by the same operations as inv α' below, so that Δb = 0 exactly at rest
                let a0 = g.a0();
                let inv0 = ((a0 - cb) * (a0 + cb)).sqrt() / cb - (cb / a0).dacos();
                if a > cb {
                    // tan α' = √(a² − c²)/c, sin α' = √(a² − c²)/a: one sqrt, one acos
                    let s = ((a - cb) * (a + cb)).sqrt();
                    let alpha = (cb / a).dacos();
                    out.alpha = alpha;
                    // dα/da = c/(a √(a² − c²)) with the root above
                    out.alpha_slope = cb / (a * s);
                    out.b_dy = cb * (s / cb - alpha - inv0);
                    s / a
                } else {
                    out.b_dy = -cb * inv0;
                    0.0
                }
            }
            DynamicForm::LineOfAction => {
                let (alpha, dalpha) = g.pressure_angle(a, self.law);
                let (sa, ca) = alpha.dsin_cos();
                out.alpha = alpha;
                out.alpha_slope = dalpha;
                out.b_dy = delta_a * sa;
                sa + delta_a * ca * dalpha
            }
            DynamicForm::YuEq10 => {
                let (alpha, dalpha) = g.pressure_angle(a, self.law);
                let (dp, ddp) = g.delta_p_with(a, self.law, self.beta0);
                let r = delta_a * delta_a - dp * dp;
                let dr = 2.0 * delta_a - 2.0 * dp * ddp;
                out.alpha = alpha;
                out.alpha_slope = dalpha;
                out.delta_p = dp;
                out.radicand = r;
                out.radicand_negative = r < 0.0;
                match self.policy {
                    RadicandPolicy::Reject if r < 0.0 => {
                        return Err(Error::NegativeRadicand {
                            radicand: r,
                            delta_a,
                            delta_p: dp,
                        });
                    }
                    RadicandPolicy::ClampZero | RadicandPolicy::Reject => {
                        if r > 0.0 {
                            let s = r.sqrt();
                            out.b_dy = s;
                            dr / (2.0 * s)
                        } else {
                            0.0
                        }
                    }
                    RadicandPolicy::SignedRoot => {
                        if r != 0.0 {
                            let s = r.abs().sqrt();
                            out.b_dy = s.copysign(r);
                            dr / (2.0 * s)
                        } else {
                            0.0
                        }
                    }
                }
            }
        };
        out.b = self.b_s + out.b_dy;
        out.grad = [db_da * da[0], db_da * da[1], db_da * da[2], db_da * da[3]];
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// R_p = R_g = 0.094 m, α_0 = 20° (the values of Yu 2021 Table 1, as literal inputs).
    fn geometry() -> PairGeometry {
        PairGeometry::new(0.094, 0.094, 20f64.to_radians()).unwrap()
    }

    #[test]
    fn rest_gives_zero_change() {
        let g = geometry();
        for form in [DynamicForm::Involute, DynamicForm::YuEq10] {
            let d = DynamicBacklash::new(
                g,
                5e-5,
                form,
                PressureAngleLaw::Involute,
                RadicandPolicy::Reject,
            )
            .unwrap();
            let e = d.eval(&CentreDisplacement::default()).unwrap();
            assert!(e.b_dy.abs() < 1e-18, "{form:?}: {}", e.b_dy);
            assert!((e.b - 5e-5).abs() < 1e-18);
            assert!((e.alpha - 20f64.to_radians()).abs() < 1e-12);
        }
    }

    #[test]
    fn printed_eq16_is_negative_at_rest() {
        let g = geometry();
        let d = DynamicBacklash::new(
            g,
            5e-5,
            DynamicForm::YuEq10,
            PressureAngleLaw::PrintedEq16,
            RadicandPolicy::Reject,
        )
        .unwrap();
        let e = d.eval(&CentreDisplacement::default());
        assert!(matches!(e, Err(Error::NegativeRadicand { .. })));
        let clamp = DynamicBacklash {
            policy: RadicandPolicy::ClampZero,
            ..d
        };
        let e = clamp.eval(&CentreDisplacement::default()).unwrap();
        assert!(e.radicand_negative && e.b_dy.abs() < 1e-300 && e.b.is_finite());
        // Δp at rest = −(R_pb/2) tan²20° = −5.85 mm
        let expect = -0.5 * 0.094 * 20f64.to_radians().dcos() * 20f64.to_radians().dtan().powi(2);
        assert!((e.delta_p - expect).abs() < 1e-12);
    }

    #[test]
    fn involute_matches_textbook_linearisation() {
        let g = geometry();
        let d = DynamicBacklash::involute(g, 0.0).unwrap();
        let da = 1e-6;
        let e = d.eval(&CentreDisplacement::new(da, 0.0, 0.0, 0.0)).unwrap();
        // half gap: half the textbook change 2 sin α_0 Δa of the normal backlash
        let lin = g.alpha0.dsin() * da;
        assert!((e.b_dy - lin).abs() < 1e-4 * lin, "{} vs {}", e.b_dy, lin);
        // moving the centres together reduces the backlash
        let e = d.eval(&CentreDisplacement::new(0.0, 0.0, da, 0.0)).unwrap();
        assert!(e.b_dy < 0.0);
        assert!(
            d.eval(&CentreDisplacement::new(f64::NAN, 0.0, 0.0, 0.0))
                .is_err()
        );
    }

    #[test]
    fn far_inside_base_circles_stays_finite() {
        let g = geometry();
        for form in [DynamicForm::Involute, DynamicForm::YuEq10] {
            for law in [PressureAngleLaw::Involute, PressureAngleLaw::PrintedEq16] {
                for policy in [RadicandPolicy::ClampZero, RadicandPolicy::SignedRoot] {
                    let d = DynamicBacklash::new(g, 1e-4, form, law, policy).unwrap();
                    for x in [-0.2, -0.05, 0.0, 0.05, 1.0] {
                        let e = d.eval(&CentreDisplacement::new(x, 0.0, 0.0, 0.0)).unwrap();
                        assert!(e.b.is_finite() && e.grad.iter().all(|v| v.is_finite()));
                    }
                }
            }
        }
    }

    #[test]
    fn gradients_match_finite_differences_for_every_option() {
        let g = geometry();
        let c0 = [3e-6, -2e-6, -1e-6, 4e-6];
        for form in [
            DynamicForm::Involute,
            DynamicForm::LineOfAction,
            DynamicForm::YuEq10,
        ] {
            for law in [PressureAngleLaw::Involute, PressureAngleLaw::Constant] {
                for sign in [
                    CentreDistanceForm::PrintedEq8,
                    CentreDistanceForm::Consistent,
                ] {
                    let d = DynamicBacklash::new(g, 1e-4, form, law, RadicandPolicy::ClampZero)
                        .unwrap()
                        .with_centre_distance(sign);
                    let e = d.eval(&CentreDisplacement::from_array(c0)).unwrap();
                    for i in 0..4 {
                        let h = 1e-9;
                        let (mut p, mut m) = (c0, c0);
                        p[i] += h;
                        m[i] -= h;
                        let bp = d.eval(&CentreDisplacement::from_array(p)).unwrap().b;
                        let bm = d.eval(&CentreDisplacement::from_array(m)).unwrap().b;
                        let fd = (bp - bm) / (2.0 * h);
                        assert!(
                            (fd - e.grad[i]).abs() < 1e-5,
                            "{form:?} {law:?} {sign:?} {i}: {fd} vs {}",
                            e.grad[i]
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn consistent_sign_mirrors_the_printed_one() {
        let g = geometry();
        let d = DynamicBacklash::involute(g, 0.0).unwrap();
        let c = CentreDisplacement::new(2e-6, 1e-6, -1e-6, 0.0);
        let mirrored = CentreDisplacement::new(-2e-6, 1e-6, 1e-6, 0.0);
        let a = d.eval(&c).unwrap();
        let b = d
            .with_centre_distance(CentreDistanceForm::Consistent)
            .eval(&mirrored)
            .unwrap();
        assert!((a.b_dy - b.b_dy).abs() < 1e-20);
        // β_0 from the printed law at rest makes Δp vanish at rest
        let p = DynamicBacklash::new(
            g,
            1e-4,
            DynamicForm::YuEq10,
            PressureAngleLaw::PrintedEq16,
            RadicandPolicy::Reject,
        )
        .unwrap()
        .with_beta0(Beta0::LawAtRest);
        let e = p.eval(&CentreDisplacement::default()).unwrap();
        assert!(e.delta_p.abs() < 1e-300 && e.b_dy.abs() < 1e-300);
    }
}
