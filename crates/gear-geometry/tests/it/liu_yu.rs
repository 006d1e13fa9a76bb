//! Liu 2021 NFG kinematics (Eq. 8, 18, 20, 22) and Yu 2021 spur geometry (Eq. 16). The Table 2
//! rig tests live with the model (`geardyn-models`, `liu2021::Rig`).

use math::DetMath;
use std::f64::consts::TAU;

use geardyn_gear_geometry::{
    NfgPair, NfgPairParams, PressureAngleLaw, RigidAccelerationForm, SpurPair, SpurPairParams,
};
use proptest::prelude::*;

/// An NFG pair with literal inputs: the values of Liu 2021 Table 1 (`m = 2.5 mm`, `Z1 = 18`,
/// `i_j = 3.5`, `ε = 0.2`, `α = 20°`). The paper's sets live with the model (`geardyn-models`).
fn nfg() -> NfgPair {
    NfgPair::new(NfgPairParams {
        module: 2.5e-3,
        z1: 18,
        ratio: 3.5,
        eccentricity: 0.2,
        pressure_angle: 20f64.to_radians(),
    })
    .unwrap()
}

/// A spur pair from its reference radii and `α0 = 20°`.
fn spur(rp: f64, rg: f64) -> SpurPair {
    SpurPair::new(SpurPairParams {
        rp,
        rg,
        pressure_angle: 20f64.to_radians(),
    })
    .unwrap()
}

#[test]
fn eq8_is_exact_in_time_and_first_harmonic_in_nfg_angle() {
    let p = nfg();
    for k in 0..50 {
        let t = k as f64 * 0.13;
        assert!((p.base_radius(t) - p.base_radius_eq8(t)).abs() < 1e-16);
    }
    // Table 1 numbers: r1 = 22.5 mm, L = 80.168 mm, β = 0.3846.
    assert!((p.pinion_pitch_radius() - 0.0225).abs() < 1e-16);
    assert!(
        (p.base_radius_mean() - 0.080_167_53).abs() < 1e-8,
        "{}",
        p.base_radius_mean()
    );
    assert!((p.base_radius_variation() - 0.384_615_38).abs() < 1e-8);
    // the time mean of r_b2 and r_b2² (Eq. 10) by quadrature
    let n = 256;
    let (mut m1, mut m2) = (0.0, 0.0);
    for k in 0..n {
        let r = p.base_radius(TAU * k as f64 / n as f64);
        m1 += r / n as f64;
        m2 += r * r / n as f64;
    }
    assert!((m1 - p.base_radius_mean()).abs() < 1e-16);
    assert!((m2 - p.base_radius_mean_square()).abs() < 1e-17);
    // over the NFG polar angle the first harmonic is (r_b1 i_j, 2ε) and the second is 2ε²
    let (l1, b1) = p.base_radius_first_harmonic_in_nfg_angle();
    let (mut c0, mut c1, mut c2) = (0.0, 0.0, 0.0);
    for k in 0..n {
        let f = TAU * k as f64 / n as f64;
        let r = p.pinion_base_radius() * p.ratio_at_nfg_angle(f);
        c0 += r / n as f64;
        c1 += 2.0 * r * f.dcos() / n as f64;
        c2 += 2.0 * r * (2.0 * f).dcos() / n as f64;
    }
    assert!((c0 - l1).abs() < 1e-15 && (c1 - l1 * b1).abs() < 1e-15);
    assert!((c2 - l1 * 2.0 * 0.04).abs() < 1e-15);
}

#[test]
fn rigid_acceleration_is_the_second_derivative_of_the_rigid_angle() {
    // θ2(τ) = (ω̄1/i_j)·∫ i_j/i12 dτ = nfg_angle(ω̄c τ); check d²/dτ² by finite differences.
    let p = nfg();
    let wc = 0.5;
    let th = |tau: f64| p.nfg_angle(wc * tau);
    let h = 1e-3;
    for tau in [0.3, 2.0, 7.0, 11.0] {
        let fd = (th(tau + h) - 2.0 * th(tau) + th(tau - h)) / (h * h);
        let exact = p.rigid_acceleration(RigidAccelerationForm::Derived, wc, tau);
        assert!((fd - exact).abs() < 1e-6, "{fd} vs {exact}");
        let printed = p.rigid_acceleration(RigidAccelerationForm::PrintedEq20, wc, tau);
        assert!((printed - exact).abs() > 1e-3);
    }
}

#[test]
fn fourier_coefficients_closed_form_vs_quadrature() {
    let p = nfg();
    let wc = 0.003_697;
    for form in [
        RigidAccelerationForm::Derived,
        RigidAccelerationForm::PrintedEq20,
    ] {
        for n in 1..6 {
            let a = p.rigid_acceleration_coefficient(form, n, wc);
            let b = p.rigid_acceleration_coefficient_numeric(form, n, wc, 64);
            assert!(
                (a - b).abs() < 1e-15 * wc.max(wc * wc) * 10.0 + 1e-20,
                "{form:?} n={n}: {a} {b}"
            );
        }
    }
    // B1 (derived) = 2εω̄c² exactly; the first-harmonic route underestimates by (1−ε²)/(1+ε²)².
    let b1 = p.rigid_acceleration_coefficient(RigidAccelerationForm::Derived, 1, wc);
    assert!((b1 - 0.4 * wc * wc).abs() < 1e-20);
    let fh = p.rigid_acceleration_b1_first_harmonic(wc);
    assert!((fh / b1 - 0.96 / 1.0816).abs() < 1e-12);
    // printed/derived = (1 − ε²)/ω̄c for B1
    let b1p = p.rigid_acceleration_coefficient(RigidAccelerationForm::PrintedEq20, 1, wc);
    assert!((b1p / b1 - 0.96 / wc).abs() < 1e-9);
}

#[test]
fn frequencies_for_a_pinion_speed() {
    // Section 2.2: f1 = ω1/(2π i_j), f2 = ω1 Z1/(2π); at Table 1's ω1 = 160 rad/s.
    let p = nfg();
    assert!((p.centre_frequency(160.0) - 160.0 / (TAU * 3.5)).abs() < 1e-13);
    assert!((p.mesh_frequency(160.0) - 160.0 * 18.0 / TAU).abs() < 1e-12);
    assert!((p.mesh_angular_frequency(1.0) / p.centre_angular_frequency(1.0) - 63.0).abs() < 1e-12);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// The NFG turns exactly once per period of θc for any ε (Eq. 18 closes), and ε → 0 gives a
    /// circular face gear.
    #[test]
    fn nfg_closes(e in 0.0..0.9f64, t in -10.0..10.0f64) {
        let p = nfg().with_eccentricity(e).unwrap();
        prop_assert!((p.nfg_angle(t + TAU) - p.nfg_angle(t) - TAU).abs() < 1e-12);
        let c = nfg().with_eccentricity(0.0).unwrap();
        prop_assert!((c.ratio(t) - 3.5).abs() < 1e-15);
        prop_assert!(c.rigid_acceleration(RigidAccelerationForm::Derived, 0.1, t).abs() < 1e-18);
    }

    /// Yu: the consistent operating pressure angle keeps the base radii (a cos α = a0 cos α0).
    #[test]
    fn pressure_angle_keeps_base_circles(da in -0.005..0.01f64) {
        let s = spur(0.075, 0.075);
        let a0 = s.nominal_centre_distance();
        let a = a0 + da;
        let al = s.operating_pressure_angle(a, PressureAngleLaw::Involute).unwrap();
        prop_assert!((a * al.dcos() - a0 * 20f64.to_radians().dcos()).abs() < 1e-15);
        let (rbp, rbg) = s.base_radii();
        prop_assert!((rbp + rbg - a * al.dcos()).abs() < 1e-15);
    }
}

#[test]
fn yu_table_geometry() {
    let t1 = spur(0.094, 0.094);
    assert!((t1.nominal_centre_distance() - 0.188).abs() < 1e-15);
    let t2 = spur(0.075, 0.075);
    assert_eq!(t2.reference_radii(), (0.075, 0.075));
    assert!((t2.centre_distance(1e-4, 0.0, 0.0, 0.0) - 0.1501).abs() < 1e-15);
    // Eq. 16 as printed at 0.1 mm over the nominal distance: 2.09°, consistent: 20.10°.
    let a = 0.1501;
    let p = t2
        .operating_pressure_angle(a, PressureAngleLaw::PrintedEq16)
        .unwrap();
    let c = t2
        .operating_pressure_angle(a, PressureAngleLaw::Involute)
        .unwrap();
    assert!((p.to_degrees() - 2.092).abs() < 1e-3, "{}", p.to_degrees());
    assert!(
        (c.to_degrees() - 20.1046).abs() < 1e-3,
        "{}",
        c.to_degrees()
    );
    assert!(SpurPair::from_module(-1.0, 50, 50, 0.3).is_err());
    assert!(SpurPair::from_module(3e-3, 0, 50, 0.3).is_err());
}
