//! The one mesh kinematics of a spur pair whose centres move (Yu 2021 Eq. 8–9, 13–16): the
//! operating pressure angle from the centre displacements, and the dynamic transmission error
//! along the line of action. [`super::GearPair`] and `yu2021::Yu2021Model` both evaluate
//! their mesh through these functions.
//!
//! ```text
//! a = √((a₀ ± (x_p − x_g))² + (y_p − y_g)²),   α = α(a)       (Eq. 8–9, 16; the leaf's laws)
//! δ  = u + (x_p − x_g) sin α + (y_p − y_g) cos α − e(t)
//! δ' = u' + (x_p' − x_g') sin α + (y_p' − y_g') cos α + α' ((x_p − x_g) cos α − (y_p − y_g) sin α) − e'(t)
//! e(t) = e_r cos(ω t + φ)                                      (static transmission error)
//! ```

use backlash::{CentreDisplacement, CentreDistanceForm, PairGeometry, PressureAngleLaw};
use math::DetMath;

/// The line of action of a pair with displaced centres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineOfAction {
    /// Operating pressure angle `α` \[rad\].
    pub alpha: f64,
    /// Its rate `α' = (dα/da) a'`.
    pub alpha_rate: f64,
    /// Change of the centre distance `Δa = a − a₀`.
    pub centre_change: f64,
}

/// The part of a line of action that depends on the centre displacements alone: the angle
/// `α`, its slope `dα/da`, the centre-distance change `Δa` and its gradient `∇a` (with respect
/// to `[x_p, y_p, x_g, y_g]`). [`LinePosition::with_velocity`] completes it to a
/// [`LineOfAction`]; a caller that holds the positions and varies the velocities (a
/// finite-difference Jacobian) computes this part once.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinePosition {
    /// Operating pressure angle `α` \[rad\].
    pub alpha: f64,
    /// `dα/da`.
    pub dalpha_da: f64,
    /// Change of the centre distance `Δa = a − a₀`.
    pub centre_change: f64,
    /// `∇a`.
    pub grad: [f64; 4],
}

impl LinePosition {
    /// The line of action for the centre velocities `[x_p', y_p', x_g', y_g']`:
    /// `α' = (dα/da) (∇a · c')`, the one arithmetic of every construction here.
    #[inline]
    pub fn with_velocity(&self, centre_velocity: &[f64]) -> LineOfAction {
        let a_rate: f64 = self
            .grad
            .iter()
            .zip(centre_velocity)
            .map(|(g, v)| g * v)
            .sum();
        LineOfAction {
            alpha: self.alpha,
            alpha_rate: self.dalpha_da * a_rate,
            centre_change: self.centre_change,
        }
    }
}

/// The position part of [`line_of_action`]: the centre distance by the `form` of Eq. (8) and
/// the pressure angle by `law` (both the `backlash` leaf's, [`PairGeometry`]).
#[inline]
pub fn line_position(
    geometry: &PairGeometry,
    form: CentreDistanceForm,
    law: PressureAngleLaw,
    c: &CentreDisplacement,
) -> LinePosition {
    let (a, centre_change, grad) = geometry.centre_distance_with(c, form);
    let (alpha, dalpha_da) = geometry.pressure_angle(a, law);
    LinePosition {
        alpha,
        dalpha_da,
        centre_change,
        grad,
    }
}

/// The line of action for centre displacements `c` and their velocities
/// `centre_velocity = [x_p', y_p', x_g', y_g']`: the centre distance by the `form` of Eq. (8)
/// and the pressure angle by `law` (both the `backlash` leaf's, [`PairGeometry`]).
#[inline]
pub fn line_of_action(
    geometry: &PairGeometry,
    form: CentreDistanceForm,
    law: PressureAngleLaw,
    c: &CentreDisplacement,
    centre_velocity: &[f64],
) -> LineOfAction {
    line_position(geometry, form, law, c).with_velocity(centre_velocity)
}

/// The position part of [`line_of_action_from`]: `None` for
/// [`backlash::DynamicForm::Involute`].
#[inline]
pub fn line_position_from(
    law: &backlash::DynamicBacklash,
    eval: &backlash::BacklashEval,
) -> Option<LinePosition> {
    match law.form {
        backlash::DynamicForm::YuEq10 | backlash::DynamicForm::LineOfAction => Some(LinePosition {
            alpha: eval.alpha,
            dalpha_da: eval.alpha_slope,
            centre_change: eval.delta_a,
            grad: eval.centre_gradient,
        }),
        _ => None,
    }
}

/// The line of action from a dynamic backlash's evaluation at the same displacement, where
/// that law's angle is the one of the line ([`backlash::DynamicForm::YuEq10`] and
/// [`backlash::DynamicForm::LineOfAction`] under the pressure-angle law `law` and centre
/// distance form of [`line_of_action`]): the same numbers as [`line_of_action`], bit for bit,
/// without computing the centre distance and the angle a second time. `None` for
/// [`backlash::DynamicForm::Involute`], whose angle is the involute law's whatever `law` says.
#[inline]
pub fn line_of_action_from(
    law: &backlash::DynamicBacklash,
    eval: &backlash::BacklashEval,
    centre_velocity: &[f64],
) -> Option<LineOfAction> {
    line_position_from(law, eval).map(|p| p.with_velocity(centre_velocity))
}

/// The static transmission error `(e, e') = (e_r cos ψ, −e_r ω sin ψ)`, `ψ = ω t + φ`.
#[inline]
pub fn static_error(amplitude: f64, omega: f64, phase: f64, t: f64) -> (f64, f64) {
    let (s, c) = (omega * t + phase).dsin_cos();
    (amplitude * c, -amplitude * omega * s)
}

/// The dynamic transmission error `(δ, δ')` along the line of action (module docs) from the
/// torsional coordinate `(u, u')`, the centre displacements `centres = [x_p, y_p, x_g, y_g]`,
/// their velocities, the line of action and the static error `(e, e')`.
#[inline]
pub fn transmission_error(
    u: (f64, f64),
    centres: &[f64],
    velocities: &[f64],
    line: &LineOfAction,
    static_error: (f64, f64),
) -> (f64, f64) {
    let sin_cos = line.alpha.dsin_cos();
    transmission_error_sin_cos(u, centres, velocities, line, sin_cos, static_error)
}

/// [`transmission_error`] with `(sin α, cos α)` of `line.alpha` given (by a caller that needs
/// them for the force directions too: the same bits, one `sin_cos` fewer).
#[inline]
pub fn transmission_error_sin_cos(
    (u, u_rate): (f64, f64),
    centres: &[f64],
    velocities: &[f64],
    line: &LineOfAction,
    (sa, ca): (f64, f64),
    (e, e_rate): (f64, f64),
) -> (f64, f64) {
    let (dx, dy) = (centres[0] - centres[2], centres[1] - centres[3]);
    let (dvx, dvy) = (velocities[0] - velocities[2], velocities[1] - velocities[3]);
    (
        dx * sa + dy * ca + u - e,
        dvx * sa + dvy * ca + line.alpha_rate * (dx * ca - dy * sa) + u_rate - e_rate,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The line read from a dynamic backlash's evaluation is [`line_of_action`]'s, bit for bit,
    /// under every pressure-angle law and Eq. (8) sign, for the two forms whose angle is the
    /// law's; the involute form (the involute law's angle) is declined. The evaluation also
    /// hands over `dα/da` and `∇a` consistent with their definitions (finite differences).
    #[test]
    fn line_from_a_backlash_evaluation_is_the_direct_one() {
        use backlash::{DynamicBacklash, DynamicForm, RadicandPolicy};
        let g = PairGeometry::new(0.05, 0.07, 20f64.to_radians()).unwrap();
        let v = [0.3, -0.2, 0.1, 0.4];
        for form in [
            DynamicForm::YuEq10,
            DynamicForm::LineOfAction,
            DynamicForm::Involute,
        ] {
            for law in [
                PressureAngleLaw::Involute,
                PressureAngleLaw::PrintedEq16,
                PressureAngleLaw::Constant,
            ] {
                for cd in [
                    CentreDistanceForm::Consistent,
                    CentreDistanceForm::PrintedEq8,
                ] {
                    let d = DynamicBacklash::new(g, 1e-4, form, law, RadicandPolicy::ClampZero)
                        .unwrap()
                        .with_centre_distance(cd);
                    for shift in [[3e-5, -2e-5, -1e-5, 4e-5], [-0.01, 0.0, 0.01, 0.0]] {
                        let c = CentreDisplacement::from_array(shift);
                        let e = d.eval(&c).unwrap();
                        let direct = line_of_action(&g, cd, law, &c, &v);
                        match line_of_action_from(&d, &e, &v) {
                            Some(l) => {
                                assert_ne!(form, DynamicForm::Involute);
                                let b = |l: &LineOfAction| {
                                    [l.alpha, l.alpha_rate, l.centre_change].map(f64::to_bits)
                                };
                                assert_eq!(b(&l), b(&direct), "{form:?} {law:?} {cd:?}");
                            }
                            None => assert_eq!(form, DynamicForm::Involute),
                        }
                        // dα/da and ∇a against central differences of the evaluation
                        let h = 1e-9;
                        for k in 0..4 {
                            let (mut up, mut dn) = (shift, shift);
                            up[k] += h;
                            dn[k] -= h;
                            let (eu, ed) = (
                                d.eval(&CentreDisplacement::from_array(up)).unwrap(),
                                d.eval(&CentreDisplacement::from_array(dn)).unwrap(),
                            );
                            let da = (eu.a - ed.a) / (2.0 * h);
                            assert!((da - e.centre_gradient[k]).abs() < 1e-6, "{da}");
                            let dalpha = (eu.alpha - ed.alpha) / (2.0 * h);
                            assert!(
                                (dalpha - e.alpha_slope * e.centre_gradient[k]).abs()
                                    < 1e-5 * (1.0 + e.alpha_slope.abs()),
                                "{form:?} {law:?}: {dalpha} vs {}",
                                e.alpha_slope * e.centre_gradient[k]
                            );
                        }
                    }
                }
            }
        }
    }

    /// With the centres at rest the line of action is the nominal one and `δ = u − e`; a pure
    /// translation of both centres together changes neither `a` nor `δ`.
    #[test]
    fn rest_and_common_translation() {
        let g = PairGeometry::new(0.05, 0.07, 20f64.to_radians()).unwrap();
        let rest = line_of_action(
            &g,
            CentreDistanceForm::Consistent,
            PressureAngleLaw::Involute,
            &CentreDisplacement::default(),
            &[0.0; 4],
        );
        assert!((rest.alpha - 20f64.to_radians()).abs() < 1e-15);
        assert_eq!(rest.centre_change.to_bits(), 0f64.to_bits());
        let e = static_error(1e-6, 100.0, 0.3, 0.01);
        let (d, dr) = transmission_error((2e-6, 0.1), &[0.0; 4], &[0.0; 4], &rest, e);
        assert_eq!(d.to_bits(), (2e-6 - e.0).to_bits());
        assert_eq!(dr.to_bits(), (0.1 - e.1).to_bits());
        let shift = [3e-5, -2e-5, 3e-5, -2e-5];
        let c = CentreDisplacement::from_array(shift);
        let moved = line_of_action(
            &g,
            CentreDistanceForm::Consistent,
            PressureAngleLaw::Involute,
            &c,
            &[1.0, 1.0, 1.0, 1.0],
        );
        assert!(moved.centre_change.abs() < 1e-18 && moved.alpha_rate.abs() < 1e-12);
        let (d2, _) = transmission_error((2e-6, 0.1), &shift, &[0.0; 4], &moved, e);
        assert!((d2 - d).abs() < 1e-18);
    }

    /// `δ'` is the time derivative of `δ` along a moving state (central difference).
    #[test]
    fn rate_is_the_derivative() {
        let g = PairGeometry::new(0.05, 0.07, 20f64.to_radians()).unwrap();
        let path = |t: f64| {
            let c = [1e-4 * t, -2e-4 * t * t, -5e-5 * t, 3e-5 * t];
            let v = [1e-4, -4e-4 * t, -5e-5, 3e-5];
            (c, v, (1e-3 * t * t, 2e-3 * t))
        };
        let eval = |t: f64| {
            let (c, v, u) = path(t);
            let line = line_of_action(
                &g,
                CentreDistanceForm::Consistent,
                PressureAngleLaw::Involute,
                &CentreDisplacement::from_array(c),
                &v,
            );
            transmission_error(u, &c, &v, &line, static_error(1e-5, 50.0, 0.2, t))
        };
        let (t, h) = (0.4, 1e-5);
        let fd = (eval(t + h).0 - eval(t - h).0) / (2.0 * h);
        let rate = eval(t).1;
        assert!(
            (fd - rate).abs() < 1e-7 * rate.abs().max(1e-6),
            "{fd} vs {rate}"
        );
    }
}
