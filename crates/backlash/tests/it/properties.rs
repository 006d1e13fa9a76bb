//! Property and reference tests of the public API.

use approx::assert_relative_eq;
use geardyn_backlash::{
    CentreDisplacement, ChenFractal, ConstantBacklashParams, ConstantPartForm, DeadZone,
    DynamicBacklash, DynamicForm, PairGeometry, PressureAngleLaw, Quadrature, RadicandPolicy,
    Regularisation, SurfaceFractal, WmProfile, dead_zone, dead_zone_dx, mean_asperity_height,
};
use math::DetMath;
use proptest::prelude::*;

/// The constant-part parameters of reading R-YU-FIG4 (`docs/readings/backlash.md`; Yu's set,
/// kept by the model as `geardyn_models::yu2021::fig4_backlash_params`), written out here so
/// that the law's tests stand without the model: b0 = 30 µm, λ = 1.5, l_a = L = 1 mm,
/// l_s = 1 µm, 8 points per wavelength, Eq. (4)–(5).
fn fig4_params() -> ConstantBacklashParams {
    ConstantBacklashParams {
        b0: 30e-6,
        gamma: 1.5,
        l_a: 1e-3,
        l_s: 1e-6,
        sampling_length: 1e-3,
        quadrature: Quadrature::default(),
        form: ConstantPartForm::AbsoluteMean,
    }
}

/// R_p = R_g = 0.094 m, α_0 = 20° (the values of Yu 2021 Table 1, as literal inputs).
fn geometry() -> PairGeometry {
    PairGeometry::new(0.094, 0.094, 20f64.to_radians()).unwrap()
}

/// The dead zone's properties at `(x, b)`: odd, zero inside the gap, slope 1 outside (Liu
/// Eq. 12). The slope is a forward difference over `h = 10⁻³ min(|x| − b, 1)`: each of its two
/// values `±(|x| − b)` carries a rounding error of at most `ε (|x| + b)` (the subtraction and
/// the rounding of `x + h`), so the quotient is 1 to within `2 ε (|x| + b) / h` (a fixed 1e-9
/// failed at `|x| − b = 6e-5`: the regression test below).
fn dead_zone_holds(x: f64, b: f64) -> Result<(), TestCaseError> {
    prop_assert!((dead_zone(x, b) + dead_zone(-x, b)).abs() <= 1e-15 * x.abs().max(1.0));
    if x.abs() <= b {
        prop_assert!(dead_zone(x, b).abs() < f64::MIN_POSITIVE);
    } else {
        // slope 1: f(x + h) − f(x) = h on the same side
        let h = 1e-3 * (x.abs() - b).min(1.0);
        let s = (dead_zone(x + h.copysign(x), b) - dead_zone(x, b)) / h.copysign(x);
        let rounding = 2.0 * f64::EPSILON * (x.abs() + b) / h;
        prop_assert!((s - 1.0).abs() <= rounding, "{s} (x = {x}, b = {b})");
        prop_assert!((dead_zone_dx(x, b) - 1.0).abs() < f64::EPSILON);
        prop_assert!((dead_zone(x, b).abs() - (x.abs() - b)).abs() <= 1e-15 * x.abs());
    }
    Ok(())
}

/// The input at which a fixed slope tolerance of 1e-9 failed (a random `proptest` case:
/// `|x| − b = 6.1e-5`, so `h = 6.1e-8` and the rounding of values near 3.6 shows as 1.5e-8 in
/// the slope); the bound of [`dead_zone_holds`] is the rounding's.
#[test]
fn dead_zone_slope_near_the_gap_edge() {
    dead_zone_holds(-3.614_977_466_929_093_3, 3.614_916_386_200_521).unwrap();
    dead_zone_holds(3.614_977_466_929_093_3, 3.614_916_386_200_521).unwrap();
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// f is odd, zero inside the gap, slope 1 outside (Liu Eq. 12).
    #[test]
    fn dead_zone_properties(x in -10.0..10.0f64, b in 0.0..5.0f64) {
        dead_zone_holds(x, b)?;
    }

    /// Smooth regularisation: derivatives vs central differences, and |f_ε − f| ≤ ε/2.
    #[test]
    fn smooth_derivatives(x in -3.0..3.0f64, b in 0.1..2.0f64, eps in 1e-3..0.3f64) {
        let dz = DeadZone::new(Regularisation::Smooth { eps }).unwrap();
        let e = dz.eval(x, b);
        let h = 1e-6;
        let fx = (dz.eval(x + h, b).f - dz.eval(x - h, b).f) / (2.0 * h);
        let fb = (dz.eval(x, b + h).f - dz.eval(x, b - h).f) / (2.0 * h);
        prop_assert!((fx - e.df_dx).abs() < 1e-6, "{} {}", fx, e.df_dx);
        prop_assert!((fb - e.df_db).abs() < 1e-6, "{} {}", fb, e.df_db);
        prop_assert!((e.f - dead_zone(x, b)).abs() <= 0.5 * eps * (1.0 + 1e-12));
    }

    /// Exact dead zone: ∂f/∂b vs finite differences away from the corners.
    #[test]
    fn exact_db(x in -3.0..3.0f64, b in 0.1..2.0f64) {
        prop_assume!((x.abs() - b).abs() > 1e-3);
        let e = DeadZone::EXACT.eval(x, b);
        let h = 1e-6;
        let fb = (dead_zone(x, b + h) - dead_zone(x, b - h)) / (2.0 * h);
        prop_assert!((fb - e.df_db).abs() < 1e-6);
    }

    /// ∂B/∂(x_p, y_p, x_g, y_g) vs central differences, every form/law/policy, displacements
    /// up to 50 µm (gradients are not checked within 1e-3 relative of a kink of Δb).
    #[test]
    fn dynamic_gradient(
        q in proptest::array::uniform4(-5e-5..5e-5f64),
        form_i in 0usize..2, law_i in 0usize..2, pol_i in 0usize..2,
    ) {
        let form = [DynamicForm::Involute, DynamicForm::YuEq10][form_i];
        let law = [PressureAngleLaw::Involute, PressureAngleLaw::PrintedEq16][law_i];
        let policy = [RadicandPolicy::ClampZero, RadicandPolicy::SignedRoot][pol_i];
        let d = DynamicBacklash::new(geometry(), 3e-5, form, law, policy)
            .unwrap();
        let c = CentreDisplacement::from_array(q);
        let e = d.eval(&c).unwrap();
        // stay away from kinks: radicand sign change and a = a0 for the printed law
        let r_scale = e.delta_a * e.delta_a + e.delta_p * e.delta_p;
        prop_assume!(form_i == 0 || e.radicand.abs() > 1e-3 * r_scale);
        prop_assume!(law_i == 0 || form_i == 0 || e.delta_a.abs() > 1e-7);
        let h = 1e-10;
        for i in 0..4 {
            let mut p = q;
            let mut m = q;
            p[i] += h;
            m[i] -= h;
            let bp = d.eval(&CentreDisplacement::from_array(p)).unwrap().b;
            let bm = d.eval(&CentreDisplacement::from_array(m)).unwrap().b;
            let fd = (bp - bm) / (2.0 * h);
            let tol = 1e-4 * e.grad[i].abs().max(1.0);
            prop_assert!((fd - e.grad[i]).abs() < tol, "i={} fd={} an={}", i, fd, e.grad[i]);
        }
    }

    /// No NaN ever leaves for finite displacements, even far outside the physical range.
    #[test]
    fn dynamic_never_nan(
        q in proptest::array::uniform4(-0.5..0.5f64),
        form_i in 0usize..2, law_i in 0usize..2, pol_i in 0usize..2,
    ) {
        let form = [DynamicForm::Involute, DynamicForm::YuEq10][form_i];
        let law = [PressureAngleLaw::Involute, PressureAngleLaw::PrintedEq16][law_i];
        let policy = [RadicandPolicy::ClampZero, RadicandPolicy::SignedRoot][pol_i];
        let d = DynamicBacklash::new(geometry(), 3e-5, form, law, policy)
            .unwrap();
        let e = d.eval(&CentreDisplacement::from_array(q)).unwrap();
        prop_assert!(e.b.is_finite() && e.grad.iter().all(|g| g.is_finite()));
    }

    /// Δb → 0 when the centres do not move, and B → b_s (rigid-body translation of both
    /// centres together does not change the backlash either).
    #[test]
    fn common_translation_keeps_backlash(tx in -1e-3..1e-3f64, ty in -1e-3..1e-3f64, form_i in 0usize..2) {
        let form = [DynamicForm::Involute, DynamicForm::YuEq10][form_i];
        let d = DynamicBacklash::new(
            geometry(), 3e-5, form,
            PressureAngleLaw::Involute, RadicandPolicy::Reject,
        ).unwrap();
        let e = d.eval(&CentreDisplacement::new(tx, ty, tx, ty)).unwrap();
        prop_assert!(e.b_dy.abs() < 1e-15);
        prop_assert!((e.b - 3e-5).abs() < 1e-15);
    }
}

/// Involute form: exact against small-displacement theory — the half gap changes by
/// b_dy ≈ sin α0 Δa (half the textbook normal-backlash change 2 sin α0 Δa) — and second order.
#[test]
fn involute_second_order() {
    let g = geometry();
    let d = DynamicBacklash::involute(g, 0.0).unwrap();
    let mut prev_err = f64::INFINITY;
    for k in 0..4 {
        let da = 1e-4 / 10f64.powi(k);
        let e = d.eval(&CentreDisplacement::new(da, 0.0, 0.0, 0.0)).unwrap();
        let err = (e.b_dy - g.alpha0.dsin() * da).abs();
        // error is O(Δa²): drops by ~100 per decade
        assert!(err < prev_err / 50.0 || err < 1e-20, "k={k} err={err}");
        prev_err = err;
    }
}

/// Yu Eq. (10) with the involute pressure-angle law: Δb = |Δa| √(1 − κ²) to first order with
/// κ = R_pb (a + a0)/(2 c²) → R_p/(a0 cos α0) = 0.532 for equal gears at 20°.
#[test]
fn yu_eq10_first_order() {
    let g = geometry();
    let d = DynamicBacklash::new(
        g,
        0.0,
        DynamicForm::YuEq10,
        PressureAngleLaw::Involute,
        RadicandPolicy::Reject,
    )
    .unwrap();
    let kappa = g.r_p / (g.a0() * g.alpha0.dcos());
    for da in [1e-6, -1e-6] {
        let e = d.eval(&CentreDisplacement::new(da, 0.0, 0.0, 0.0)).unwrap();
        assert_relative_eq!(
            e.b_dy,
            da.abs() * (1.0 - kappa * kappa).sqrt(),
            max_relative = 1e-4
        );
    }
}

/// W-M sum: the truncation bound holds and the computed b_i converges as l_s → 0.
#[test]
fn wm_truncation_convergence() {
    let s = SurfaceFractal::new(1.4, 1e-11).unwrap();
    let fine = WmProfile::new(s, 1.5, 1e-3, 1e-9).unwrap();
    for l_s in [1e-4, 1e-5, 1e-6] {
        let p = WmProfile::new(s, 1.5, 1e-3, l_s).unwrap();
        for l in [1.3e-5, 2.7e-4, 8.1e-4] {
            let diff = (fine.height(l) - p.height(l)).abs();
            assert!(diff <= p.truncation_bound() + 1e-22, "l_s={l_s} {diff}");
        }
    }
    // bounds decrease geometrically with n_max
    let b5 = WmProfile::new(s, 1.5, 1e-3, 1e-5)
        .unwrap()
        .truncation_bound();
    let b6 = WmProfile::new(s, 1.5, 1e-3, 1e-6)
        .unwrap()
        .truncation_bound();
    assert!(b6 < 0.3 * b5);
}

/// b_i (Eq. 4): quadrature converges with points per wavelength, and b_i converges with n_max
/// within the stated truncation bound.
#[test]
fn mean_height_convergence() {
    let s = SurfaceFractal::new(1.3, 1e-11).unwrap();
    let p = WmProfile::new(s, 1.5, 1e-3, 1e-5).unwrap();
    let q = |ppw| Quadrature {
        points_per_wavelength: ppw,
        max_points: 1 << 22,
    };
    let m4 = mean_asperity_height(&p, 1e-3, q(4.0)).unwrap();
    let m8 = mean_asperity_height(&p, 1e-3, q(8.0)).unwrap();
    let m32 = mean_asperity_height(&p, 1e-3, q(32.0)).unwrap();
    assert!((m8.value - m32.value).abs() <= m8.quadrature_error.max(1e-3 * m32.value));
    assert!((m4.value - m32.value).abs() <= 2.0 * m4.quadrature_error.max(1e-3 * m32.value));
    assert!(m8.quadrature_error < 0.01 * m8.value);

    let pf = WmProfile::new(s, 1.5, 1e-3, 1e-6).unwrap();
    let mf = mean_asperity_height(&pf, 1e-3, q(8.0)).unwrap();
    assert!(
        (mf.value - m8.value).abs() <= m8.truncation_bound + m8.quadrature_error + mf.error(),
        "{} {} {}",
        mf.value,
        m8.value,
        m8.truncation_bound
    );
    // b_i scales exactly with G^{D−1}
    let s2 = SurfaceFractal::new(1.3, 1e-10).unwrap();
    let p2 = WmProfile::new(s2, 1.5, 1e-3, 1e-5).unwrap();
    let m2 = mean_asperity_height(&p2, 1e-3, q(8.0)).unwrap();
    assert_relative_eq!(m2.value / m8.value, 10f64.dpowf(0.3), max_relative = 1e-12);
    // b_i settles as L grows past ~10 l_a (at L = l_a it is ~15 % below the long-L value,
    // see docs/readings/backlash.md R-YU-FIG4)
    let m10 = mean_asperity_height(&p, 10e-3, q(8.0)).unwrap();
    let m20 = mean_asperity_height(&p, 20e-3, q(8.0)).unwrap();
    assert!((m20.value - m10.value).abs() < 0.02 * m20.value);
}

/// The (D, G) grid of the constant part with coarse settings (l_s = 10 µm): b_s = b0 − 2 b_i
/// in every cell, b_i scales exactly with G^{D−1} along a row, and G ≤ 0 is rejected. (The
/// checks of Yu's text on this grid are the Yu model's: `geardyn_models::yu2021::fig4_claims`.)
#[test]
fn constant_part_grid_is_consistent() {
    let mut p = fig4_params();
    p.l_s = 1e-5;
    let d = [1.2, 1.5];
    let g = [1e-12, 1e-11];
    let data = geardyn_backlash::constant_part_grid(p, &d, &g).unwrap();
    for i in 0..d.len() {
        for j in 0..g.len() {
            assert_relative_eq!(
                data.b_s[i][j],
                p.b0 - 2.0 * data.b_i[i][j],
                max_relative = 1e-12
            );
        }
        let ratio = data.b_i[i][1] / data.b_i[i][0];
        assert_relative_eq!(ratio, 10f64.dpowf(d[i] - 1.0), max_relative = 1e-12);
    }
    assert!(geardyn_backlash::constant_part_grid(p, &d, &[0.0]).is_err());
}

/// The printed b_s of Eq. (11) (no |·|, k from 0) gives metre-scale "heights": b_s ≪ 0.
#[test]
fn printed_eq11_is_unphysical() {
    let mut p = fig4_params();
    p.form = ConstantPartForm::PrintedEq11;
    let s = SurfaceFractal::new(1.2, 1e-11).unwrap();
    let c = p.constant_part(s, s).unwrap();
    // G^{0.2} = 6.3e-3 m for the k = 0 term alone
    assert!(c.b_s < -1e-3, "{c:?}");
    assert!(c.b_s.is_finite());
}

/// Eq. (4)–(5) against an exact solution: with a single kept level k (l_a = 1 mm gives
/// k_min = 18, l_s = 0.5 mm gives n_max = 18), z(l) = G^{D−1} λ^{(D−2)k}
/// cos(2π λ^k l) and, over L = 100 whole wavelengths, the mean of |z| is the amplitude times
/// 2/π (mean of |cos| over a period); b_s = b0 − 2 b_i for two alike surfaces.
#[test]
fn constant_part_of_a_single_level_is_two_over_pi_of_its_amplitude() {
    let (d, g, lambda) = (1.4, 1e-11, 1.5f64);
    let s = SurfaceFractal::new(d, g).unwrap();
    // 1.5^18 = 1477.9 ≤ 2000 < 1.5^19 = 2216.8: n_max = 18 = k_min
    let prof = WmProfile::new(s, lambda, 1e-3, 1.0 / 2000.0).unwrap();
    assert_eq!((prof.k_min(), prof.n_max()), (18, 18));
    let k = 18;
    let amplitude = g.dpowf(d - 1.0) * lambda.dpowf((d - 2.0) * f64::from(k));
    let exact = amplitude * std::f64::consts::FRAC_2_PI;
    let p = ConstantBacklashParams {
        b0: 30e-6,
        gamma: lambda,
        l_a: 1e-3,
        l_s: 1.0 / 2000.0,
        sampling_length: 100.0 * lambda.powi(-k),
        quadrature: Quadrature {
            points_per_wavelength: 1000.0,
            max_points: 1 << 22,
        },
        form: ConstantPartForm::AbsoluteMean,
    };
    let c = p.constant_part(s, s).unwrap();
    // midpoint rule on |cos| (kinks at the zeros): O(h²), h = 1/1000 of a wavelength
    assert!(
        (c.b_p - exact).abs() <= 1e-5 * exact,
        "{} vs {exact}",
        c.b_p
    );
    assert_eq!(c.b_p.to_bits(), c.b_g.to_bits());
    assert!((c.b_s - (30e-6 - 2.0 * exact)).abs() <= 2e-5 * exact);
}

/// Chen's fractal backlash (Eq. 3): the tail bound holds.
#[test]
fn chen_convergence() {
    let long = ChenFractal::new(1.5, 1.5, 200).unwrap();
    for n in [5, 10, 20, 40] {
        let c = ChenFractal::new(1.5, 1.5, n).unwrap();
        for t in [0.3, 1.7, 12.0] {
            assert!((long.value(t) - c.value(t)).abs() <= c.truncation_bound() + 1e-12);
        }
    }
}
