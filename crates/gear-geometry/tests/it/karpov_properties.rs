//! Invariants and convergence orders of the Karpov 2017 kinematics (Eq. 1–7).

use math::DetMath;
use std::f64::consts::TAU;

use geardyn_gear_geometry::{CentreDistance, KarpovPair, KarpovPairParams, SpeedFluctuationForm};
use proptest::prelude::*;

fn pair(b: f64, xi: f64, u: f64, j: u32, c: CentreDistance) -> KarpovPair {
    KarpovPair::new(KarpovPairParams {
        r: 0.05,
        u,
        b,
        xi,
        j,
        z1: 32,
        centre_distance: c,
    })
    .unwrap()
}

// `pair(0.01, 2.0, 2.0, 4, CentreDistance::Closing)` has the values of Karpov 2017 Table 1 as
// literal inputs; the paper's set itself is `geardyn_models::karpov2017::pair_table1()`.

/// Observed order `log2(e(h)/e(h/2))` of an error function of `B`, averaged over a few halvings.
fn order(mut err: impl FnMut(f64) -> f64, b0: f64) -> f64 {
    let mut orders = Vec::new();
    let mut b = b0;
    for _ in 0..3 {
        orders.push((err(b) / err(0.5 * b)).dlog2());
        b *= 0.5;
    }
    orders.iter().sum::<f64>() / orders.len() as f64
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// r1 + r2 is the same at every input angle (Eq. 1).
    #[test]
    fn centre_distance_is_constant(
        b in 0.0..0.9f64, xi in 1.01..50.0f64, u in 1.0..5.0f64, j in 1u32..6, phi in -20.0..20.0f64,
        closing in any::<bool>(),
    ) {
        let c = if closing { CentreDistance::Closing } else { CentreDistance::AsPrinted };
        let p = pair(b, xi, u, j, c);
        let a = p.centre_distance();
        prop_assert!(((p.r1(phi) + p.r2(phi)) - a).abs() <= 1e-15 * a * 4.0);
        prop_assert!(p.r1(phi) > 0.0 && p.r2(phi) > 0.0);
        if !closing {
            prop_assert!((a - 0.05 * (1.0 + u)).abs() < 1e-15);
        }
    }

    /// With the closing centre distance the output turns exactly 2π/u per input revolution, and
    /// the closed form agrees with quadrature at arbitrary angles.
    #[test]
    fn output_angle_closes(b in 0.0..0.9f64, xi in 1.05..100.0f64, u in 1.0..5.0f64, j in 1u32..6,
                           phi in 0.0..7.0f64) {
        let p = pair(b, xi, u, j, CentreDistance::Closing);
        let turn = p.output_angle(TAU);
        prop_assert!((turn - TAU / u).abs() < 1e-12, "{} vs {}", turn, TAU / u);
        let q = p.output_angle_quadrature(phi, 1e-13);
        prop_assert!((q.value - p.output_angle(phi)).abs() < 1e-11);
        // and the mesh phase gains exactly 2π z1 per revolution whatever the shape
        prop_assert!((p.mesh_phase(phi + TAU) - p.mesh_phase(phi) - TAU * 32.0).abs() < 1e-9);
    }

    /// The exact speed fluctuation tends to the linearised Eq. (4), 2B(1+u)/u, with relative
    /// error B²/(u² − B²) (A = u); Eq. (4) as printed is u times smaller (R-KARPOV-EQ4).
    #[test]
    fn delta_exact_tends_to_eq4(b in 1e-4..0.5f64, xi in 1.1..20.0f64, u in 1.0..4.0f64) {
        let p = pair(b, xi, u, 2, CentreDistance::AsPrinted);
        let rel = p.speed_fluctuation() / p.speed_fluctuation_linear() - 1.0;
        let expect = b * b / (u * u - b * b);
        prop_assert!((rel - expect).abs() < 1e-12 * (1.0 + expect));
        prop_assert!((p.speed_fluctuation_linear() / p.speed_fluctuation_eq4() - u).abs() < 1e-12 * u);
    }
}

#[test]
fn printed_centre_distance_misses_closure_by_order_b_squared() {
    // R-KARPOV-EQ1-CLOSURE: φ2(2π) − 2π/u = 2π(1 + u)B²√(ξ²−1)(ξ − √(ξ²−1))/u³ + O(B⁴).
    let (u, xi) = (2.0, 2.0);
    let s = (xi * xi - 1.0f64).sqrt();
    let err = |b: f64| {
        let p = pair(b, xi, u, 4, CentreDistance::AsPrinted);
        p.output_angle(TAU) - TAU / u
    };
    let lead = |b: f64| TAU * (1.0 + u) * b * b * s * (xi - s) / (u * u * u);
    let ord = order(err, 0.04);
    assert!((ord - 2.0).abs() < 0.01, "order {ord}");
    assert!((err(1e-3) / lead(1e-3) - 1.0).abs() < 1e-5);
    // Table 1: 1.09e-4 rad per input revolution
    let t1 = pair(0.01, 2.0, 2.0, 4, CentreDistance::Closing)
        .with_centre_distance(CentreDistance::AsPrinted)
        .unwrap();
    let miss = t1.output_angle(TAU) - TAU / 2.0;
    assert!((miss - 1.0929e-4).abs() < 1e-7, "{miss}");
    // the closing centre distance moves a by O(B²): 3.5 µm for Table 1
    let da = pair(0.01, 2.0, 2.0, 4, CentreDistance::Closing).centre_distance() - 0.150;
    assert!((da - 3.48e-6).abs() < 0.05e-6, "{da}");
}

#[test]
fn exact_vs_approximate_forms_converge_with_order_two() {
    for xi in [1.5, 2.0, 10.0, f64::INFINITY] {
        for c in [CentreDistance::AsPrinted, CentreDistance::Closing] {
            let phi = 0.37;
            // Ratio, Eq. (2): absolute error O(B²).
            let o = order(
                |b| {
                    let p = pair(b, xi, 2.0, 4, c);
                    (p.ratio(phi) - p.ratio_eq2(phi)).abs()
                },
                0.004,
            );
            assert!((o - 2.0).abs() < 0.05, "ratio xi={xi}: {o}");
            // Output angle (after Eq. 2): O(B²).
            let o = order(
                |b| {
                    let p = pair(b, xi, 2.0, 4, c);
                    (p.output_angle(phi) - p.output_angle_approx(phi)).abs()
                },
                0.004,
            );
            assert!((o - 2.0).abs() < 0.05, "phi2 xi={xi}: {o}");
            // Acceleration, Eq. (5): O(B²).
            let o = order(
                |b| {
                    let p = pair(b, xi, 2.0, 4, c);
                    (p.acceleration(phi, 10.0) - p.acceleration_eq5_approx(phi, 10.0)).abs()
                },
                0.004,
            );
            assert!((o - 2.0).abs() < 0.05, "eps2 xi={xi}: {o}");
            // Speed fluctuation, Eq. (4): O(B³) absolute (relative B²).
            let o = order(
                |b| {
                    let p = pair(b, xi, 2.0, 4, c);
                    (p.speed_fluctuation() - p.speed_fluctuation_linear()).abs()
                },
                0.004,
            );
            assert!((o - 3.0).abs() < 0.05, "delta xi={xi}: {o}");
        }
    }
}

#[test]
fn max_acceleration_eq6_is_accurate_to_order_b_squared() {
    // Eq. (6) takes max |(1 + ξ cos)/(ξ + cos)²| = 1/(ξ − 1) at θ = π, where g = 0, so the exact
    // maximum differs only at O(B²) relative.
    for xi in [1.2, 2.0, 5.0] {
        let rel = |b: f64| {
            let p = pair(b, xi, 2.0, 4, CentreDistance::AsPrinted);
            (p.max_acceleration(10.0) / p.max_acceleration_eq6(10.0) - 1.0).abs()
        };
        let o = order(rel, 0.04);
        assert!((o - 2.0).abs() < 0.1, "xi={xi}: order {o}");
    }
    let t1 = pair(0.01, 2.0, 2.0, 4, CentreDistance::Closing);
    let r = t1.max_acceleration(1.0) / t1.max_acceleration_eq6(1.0);
    assert!((r - 1.0).abs() < 1e-4, "{r}");
}

#[test]
fn design_check_root_find_matches_closed_form() {
    // For A = u the exact δ = 2Bu(1+u)/(u² − B²) inverts in closed form.
    let u = 2.0;
    let p = pair(0.01, 2.0, u, 4, CentreDistance::AsPrinted);
    for dmax in [0.001, 0.01, 0.2] {
        let b = p
            .max_admissible_b(dmax, SpeedFluctuationForm::Exact)
            .unwrap();
        // root of δ B² + 2u(1+u)B − δu² = 0 in the cancellation-free form
        let closed = dmax * u * u
            / (u * (1.0 + u) + (u * u * (1.0 + u) * (1.0 + u) + dmax * dmax * u * u).sqrt());
        assert!((b - closed).abs() < 1e-15, "{b} vs {closed}");
        let bl = p
            .max_admissible_b(dmax, SpeedFluctuationForm::Linearised)
            .unwrap();
        assert!((bl - dmax * u / (2.0 * (1.0 + u))).abs() < 1e-16);
        let b4 = p
            .max_admissible_b(dmax, SpeedFluctuationForm::PrintedEq4)
            .unwrap();
        assert!((b4 - dmax * u * u / (2.0 * (1.0 + u))).abs() < 1e-16);
        assert!(b < bl && bl < b4);
    }
    // Table 1 (exact δ = 0.030, Eq. 4 as printed 0.015): admissible for δ_max = 0.04, not 0.02.
    let t1 = pair(0.01, 2.0, 2.0, 4, CentreDistance::Closing);
    assert!(t1.design_check(0.04).unwrap().admissible);
    assert!(!t1.design_check(0.02).unwrap().admissible);
    let c = t1.design_check(0.01).unwrap();
    assert!(!c.admissible);
    let back = t1.with_b(c.b_max_exact).unwrap().speed_fluctuation();
    assert!((back - 0.01).abs() < 1e-14);
    assert!(t1.design_check(-1.0).is_err());
    assert!(t1.design_check(f64::NAN).is_err());
}

#[test]
fn sinusoidal_limit_is_the_large_xi_limit() {
    let s = pair(0.05, f64::INFINITY, 2.0, 2, CentreDistance::Closing);
    let l = pair(0.05, 1e7, 2.0, 2, CentreDistance::Closing);
    for phi in [0.1, 1.0, 2.5, 5.0] {
        assert!((s.r1(phi) - 0.05 * (1.0 + 0.05 * (2.0 * phi).dsin())).abs() < 1e-17);
        assert!((s.ratio(phi) - l.ratio(phi)).abs() < 1e-8);
        assert!((s.output_angle(phi) - l.output_angle(phi)).abs() < 1e-7);
        assert!((s.mesh_phase(phi) - l.mesh_phase(phi)).abs() < 1e-5);
    }
}

#[test]
fn table1_values() {
    // Karpov 2017 Table 1, p. 8: u = 2, r = 50 mm, B = 0.01, ξ = 2, j = 4, z1 = 32.
    let p = pair(0.01, 2.0, 2.0, 4, CentreDistance::Closing);
    assert!((p.k() - 0.125).abs() < 1e-16);
    // exact δ = u[(1+B)/(A−B) − (1−B)/(A+B)] = 0.0299994 (A = 2.0000696); 2Bu(1+u)/(u²−B²)
    // = 0.0300008 for A = u; Eq. (4) as printed gives 0.015.
    assert!(
        (p.speed_fluctuation() - 0.029_999_36).abs() < 1e-8,
        "{}",
        p.speed_fluctuation()
    );
    assert!((p.speed_fluctuation_eq4() - 0.015).abs() < 1e-15);
    // Eq. (6) at ω1 = 1 rad/s: Bj(1+u)√3/u² = 0.0519615
    assert!((p.max_acceleration_eq6(1.0) - 0.051_961_524).abs() < 1e-9);
    // serde round trip keeps validation
    let json = serde_json::to_string(&p).unwrap();
    let back: KarpovPair = serde_json::from_str(&json).unwrap();
    assert_eq!(back, p);
    let bad = json.replace("\"b\":0.01", "\"b\":1.5");
    assert!(serde_json::from_str::<KarpovPair>(&bad).is_err());
}
