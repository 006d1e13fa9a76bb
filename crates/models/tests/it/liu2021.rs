//! Integration tests of the Liu et al. 2021 NFG model: parameters, readings, both engines.

use geardyn_models::Error;
use geardyn_models::liu2021::{
    self, BaseRadius, Basis, BranchStability, HbmOptions, HbmStart, IntegrationOptions, Parameters,
    RattleState, Readings, SpeedContinuationOptions, solve_hbm, solve_hbm_from_time_response,
    solve_hbm_with,
};

/// Table 1 with the constant-b̄ reading (`R-LIU-EQ11`, the one the paper's figures follow).
fn paper(omega1: f64) -> Parameters {
    let mut p = liu2021::table1();
    p.omega1 = omega1;
    p.readings.base_radius = BaseRadius::Mean;
    p
}

fn short() -> IntegrationOptions {
    IntegrationOptions {
        transient_periods: 1.0,
        ..IntegrationOptions::default()
    }
}

#[test]
fn serde_round_trip_json_and_toml() {
    let mut p = liu2021::table1();
    p.readings = Readings::printed();
    let json = serde_json::to_string(&p).unwrap();
    let back: Parameters = serde_json::from_str(&json).unwrap();
    assert_eq!(p, back);
    let toml_s = toml::to_string(&p).unwrap();
    let back: Parameters = toml::from_str(&toml_s).unwrap();
    assert_eq!(p, back);
    // readings are optional in files and default to the consistent forms
    let mut v: serde_json::Value = serde_json::from_str(&json).unwrap();
    v.as_object_mut().unwrap().remove("readings");
    let back: Parameters = serde_json::from_value(v).unwrap();
    assert_eq!(back.readings, Readings::default());
}

#[test]
fn validation_names_the_field() {
    let field = |p: Parameters| match p.model() {
        Err(Error::InvalidParameter { field, .. }) => field,
        other => panic!("expected InvalidParameter, got {other:?}"),
    };
    let t = liu2021::table1();
    assert_eq!(
        field(Parameters {
            eccentricity: 1.0,
            ..t
        }),
        "liu2021.eccentricity"
    );
    assert_eq!(field(Parameters { k0: f64::NAN, ..t }), "liu2021.k0");
    assert_eq!(field(Parameters { kr: 4e8, ..t }), "liu2021.kr");
    assert_eq!(field(Parameters { ratio: 3.52, ..t }), "liu2021.ratio");
    assert_eq!(field(Parameters { inertia: 0.0, ..t }), "liu2021.inertia");
    assert_eq!(
        field(Parameters {
            half_backlash: -1e-6,
            ..t
        }),
        "liu2021.half_backlash"
    );
    assert_eq!(
        field(Parameters {
            omega1: f64::INFINITY,
            ..t
        }),
        "liu2021.omega1"
    );
    let msg = Parameters {
        damping_ratio: -0.1,
        ..t
    }
    .validate()
    .unwrap_err()
    .to_string();
    assert_eq!(msg, "liu2021.damping_ratio must be >= 0, got -0.1");
    let m = t.model().unwrap();
    let bad = IntegrationOptions {
        sample_step: 0.0,
        ..IntegrationOptions::default()
    };
    assert!(liu2021::integrate(&m, &bad).is_err());
}

#[test]
fn table1_dimensionless_numbers() {
    // Hand values: L = 0.0225*3.5*cos20°*1.04/0.96, β = 0.4/1.04, ω_n from Eq. (10).
    let m = paper(160.0).model().unwrap();
    let l = 0.0225 * 3.5 * 20f64.to_radians().cos() * 1.04 / 0.96;
    let beta = 0.4 / 1.04;
    let wn = (3.1e8 * l * l * (1.0 + beta * beta / 2.0) / 0.014_f64).sqrt();
    assert!((m.omega_n / wn - 1.0).abs() < 1e-12);
    assert_eq!(m.z2, 63);
    assert!((m.omega_c - 160.0 / 3.5 / wn).abs() < 1e-15);
    assert!((m.omega_e / m.omega_c - 63.0).abs() < 1e-9);
    assert!((m.b0 - 30.0 / (0.014 * wn * wn)).abs() < 1e-18);
    assert!((m.backlash - 5e-5 / l).abs() < 1e-15);
    assert!((m.b3 - 1e-5 / l * m.omega_e * m.omega_e).abs() < 1e-18);
}

#[test]
fn no_rattle_point_hbm_matches_time_integration() {
    // ω1 = 120 rad/s: contact is never lost, the system is linear-parametric and a full basis
    // with two mesh harmonics (K = 2 Z2 + 2) must reproduce the time integration up to the
    // truncation (measured: ppv 6.08e-5 vs 6.27e-5, 3 %). The largest pointwise difference,
    // 3.9e-6 (6 % of ppv), sits near τ ≈ T/2 where F is smallest: ringing at the local natural
    // frequency √F ∈ [0.59, 1.34], i.e. harmonics k ≈ 210–480 of ω̄_c, beyond K = 128.
    let m = paper(120.0).model().unwrap();
    let ti = liu2021::integrate(&m, &short()).unwrap();
    let full = solve_hbm(&m, &HbmOptions::full(&m, 2), None).unwrap();
    let sparse = solve_hbm(&m, &HbmOptions::default(), None).unwrap();
    assert!(full.converged() && sparse.converged());
    assert_eq!(ti.rattle.state, RattleState::NoRattle);
    assert_eq!(full.rattle.state, RattleState::NoRattle);
    assert_eq!(sparse.rattle.state, RattleState::NoRattle);
    let rel = (full.rattle.ppv / ti.rattle.ppv - 1.0).abs();
    assert!(
        rel < 0.05,
        "ppv full HBM {} vs time {}",
        full.rattle.ppv,
        ti.rattle.ppv
    );
    // pointwise agreement over the recorded period
    let max_dev = ti
        .tau
        .iter()
        .zip(&ti.q)
        .map(|(&t, &q)| (full.eval(t) - q).abs())
        .fold(0.0, f64::max);
    assert!(
        max_dev < 0.1 * ti.rattle.ppv,
        "max |q_hbm - q_ti| = {max_dev}"
    );
}

#[test]
fn unilateral_point_both_engines() {
    // ω1 = 160 rad/s (Fig. 8): unilateral rattle.
    let m = paper(160.0).model().unwrap();
    let ti = liu2021::integrate(&m, &short()).unwrap();
    assert_eq!(ti.rattle.state, RattleState::Unilateral);
    assert!(ti.rattle.q_max < m.backlash);
    let hb = solve_hbm(&m, &HbmOptions::default(), None).unwrap();
    assert!(hb.converged());
    assert_eq!(hb.rattle.state, RattleState::Unilateral);
    let ratio = hb.rattle.ppv / ti.rattle.ppv;
    assert!((0.4..1.5).contains(&ratio), "ppv ratio HBM/time = {ratio}");
}

#[test]
fn bilateral_point_both_engines() {
    // ω1 = 220 rad/s: bilateral rattle; HBM started from the time response lands on it.
    let m = paper(220.0).model().unwrap();
    let ti = liu2021::integrate(&m, &short()).unwrap();
    assert_eq!(ti.rattle.state, RattleState::Bilateral);
    let hb = solve_hbm_from_time_response(&m, &HbmOptions::full(&m, 1), &ti).unwrap();
    assert!(hb.converged(), "{}", hb.solution.termination);
    assert_eq!(hb.rattle.state, RattleState::Bilateral);
    let rel = (hb.rattle.ppv / ti.rattle.ppv - 1.0).abs();
    assert!(
        rel < 0.15,
        "ppv HBM {} vs time {}",
        hb.rattle.ppv,
        ti.rattle.ppv
    );
}

#[test]
fn circular_face_gear_limit_has_no_centre_excitation() {
    // ε = 0: β = 0, B1 = B2 = 0, F depends on the mesh only; the response holds no harmonic
    // of ω̄_c other than multiples of ω̄_e.
    let mut p = paper(160.0);
    p.eccentricity = 0.0;
    let m = p.model().unwrap();
    assert!(m.beta.abs() < 1e-15 && m.b1.abs() < 1e-30 && m.b2.abs() < 1e-30);
    let s = solve_hbm(&m, &HbmOptions::default(), None).unwrap();
    assert!(s.converged());
    let mesh = s.amplitude(63);
    assert!(mesh > 0.0);
    for k in [1, 2, 61, 62, 64, 65] {
        assert!(
            s.amplitude(k) < 1e-9 * mesh,
            "harmonic {k}: {}",
            s.amplitude(k)
        );
    }
    // and the circular gear vibrates less than the NFG (Sect. 3.5, Fig. 13b)
    let nfg = solve_hbm(&paper(160.0).model().unwrap(), &HbmOptions::default(), None).unwrap();
    assert!(s.rattle.ppv < nfg.rattle.ppv);
}

#[test]
fn printed_eq20_gives_bilateral_rattle_everywhere() {
    // R-LIU-EQ20: with the printed rigid acceleration B1 ≈ 100 B0 and the NFG rattles on both
    // flanks even at 100 rad/s, contradicting Fig. 9 and 11.
    let mut p = paper(100.0);
    p.readings = Readings::printed();
    let m = p.model().unwrap();
    assert!(m.b1 > 50.0 * m.b0);
    let s = solve_hbm(&m, &HbmOptions::default(), None).unwrap();
    assert_eq!(s.rattle.state, RattleState::Bilateral);
}

#[test]
fn hbm_basis_sizes() {
    let m = paper(160.0).model().unwrap();
    assert_eq!(Basis::PAPER.to_hbm(m.z2).unwrap().n_coefficients(), 15);
    let full = HbmOptions::full(&m, 1).basis.to_hbm(m.z2).unwrap();
    assert_eq!(full.n_coefficients(), 2 * 65 + 1);
}

#[test]
fn model_is_send_sync() {
    fn is<T: Send + Sync + Clone>() {}
    is::<liu2021::Model>();
    is::<liu2021::Parameters>();
    is::<liu2021::HbmResponse>();
    is::<liu2021::TimeResponse>();
    is::<liu2021::SpeedBranch>();
    is::<liu2021::SpeedContinuationOptions>();
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(32))]

    /// Invariants of the dimensionless model for any admissible ε, a_k and ω₁: the mean of
    /// F(τ) over a period is 1 (Eq. 10 normalisation), the rigid acceleration has zero mean,
    /// and the Eq. (22) amplitudes are the Fourier coefficients of the exact derived form.
    #[test]
    fn dimensionless_invariants(eps in 0.0f64..0.6, ak in 0.0f64..0.9, w1 in 50.0f64..300.0) {
        let mut p = liu2021::table1();
        p.eccentricity = eps;
        p.kr = ak * p.k0;
        p.omega1 = w1;
        p.readings.rigid_series = liu2021::RigidSeries::Exact;
        let m = p.model().unwrap();
        let n = 4096;
        let t = m.period();
        let (mut f_mean, mut a_mean, mut s1, mut s2) = (0.0, 0.0, 0.0, 0.0);
        for i in 0..n {
            let tau = t * i as f64 / n as f64;
            let x = m.omega_c * tau;
            let a = m.rigid_acceleration(tau);
            f_mean += m.stiffness(tau) / n as f64;
            a_mean += a / n as f64;
            s1 += 2.0 * a * x.sin() / n as f64;
            s2 += 2.0 * a * (2.0 * x).sin() / n as f64;
        }
        let scale = m.omega_c * m.omega_c;
        proptest::prop_assert!((f_mean - 1.0).abs() < 1e-9);
        proptest::prop_assert!(a_mean.abs() < 1e-12 * scale);
        proptest::prop_assert!((s1 - m.b1).abs() < 1e-9 * scale);
        proptest::prop_assert!((s2 - m.b2).abs() < 1e-9 * scale);
    }
}

#[test]
fn time_varying_backlash_needs_a_full_basis() {
    // R-LIU-EQ11: with the exact b̄(τ) = b/r_b2(τ) the contact position follows 1/r_b2(τ),
    // which two harmonics of ω̄_c cannot represent: the paper basis misreports rattle at
    // 120 rad/s, the full basis agrees with time integration (no rattle).
    let mut p = liu2021::table1();
    p.omega1 = 120.0;
    let m = p.model().unwrap();
    let ti = liu2021::integrate(&m, &short()).unwrap();
    let sparse = solve_hbm(&m, &HbmOptions::default(), None).unwrap();
    let full = solve_hbm(&m, &HbmOptions::full(&m, 1), None).unwrap();
    assert_eq!(ti.rattle.state, RattleState::NoRattle);
    assert_eq!(full.rattle.state, RattleState::NoRattle);
    assert_eq!(sparse.rattle.state, RattleState::Unilateral);
    assert!((full.rattle.ppv / ti.rattle.ppv - 1.0).abs() < 0.05);
}

#[test]
fn warm_start_converges_where_cold_start_fails() {
    // ω1 = 205 rad/s, paper basis: from the quasi-static start Newton stalls on the unilateral
    // branch (measured residual 3.2e-3 of the forcing scale); started from the harmonics of
    // the time-integrated period it converges on the bilateral branch, ppv within 10 % of the
    // time integration (measured 2.07e-3 vs 2.22e-3: the 15 paper harmonics cannot carry the
    // impacts).
    let m = paper(205.0).model().unwrap();
    let ti = liu2021::integrate(&m, &IntegrationOptions::default()).unwrap();
    assert_eq!(ti.rattle.state, RattleState::Bilateral);
    let o = HbmOptions::default();
    let cold = solve_hbm_with(&m, &o, HbmStart::Cold).unwrap();
    assert!(!cold.converged());
    assert_ne!(cold.rattle.state, RattleState::Bilateral);
    let warm = solve_hbm_with(&m, &o, HbmStart::FromTimeResponse(&ti)).unwrap();
    assert!(warm.converged(), "{}", warm.solution.termination);
    assert_eq!(warm.rattle.state, RattleState::Bilateral);
    let rel = (warm.rattle.ppv / ti.rattle.ppv - 1.0).abs();
    assert!(
        rel < 0.1,
        "ppv HBM {} vs time {}",
        warm.rattle.ppv,
        ti.rattle.ppv
    );
    // the same through the legacy entry point
    let legacy = solve_hbm_from_time_response(&m, &o, &ti).unwrap();
    assert_eq!(legacy.solution.coefficients, warm.solution.coefficients);
    // sequential continuation: the 205 rad/s solution as start at 202.5 rad/s stays bilateral
    let m2 = paper(202.5).model().unwrap();
    let next = solve_hbm_with(&m2, &o, HbmStart::Given(&warm)).unwrap();
    assert!(next.converged(), "{}", next.solution.termination);
    assert_eq!(next.rattle.state, RattleState::Bilateral);
}

#[test]
fn continuation_finds_the_jump_fold_of_the_unilateral_branch() {
    // Paper basis, from the unilateral response at 180 rad/s upwards: the branch turns back at
    // a fold (measured 185.5 rad/s) where ppv grows; beyond it only the bilateral branch exists.
    let p = paper(180.0);
    let o = SpeedContinuationOptions {
        omega1_end: 195.0,
        max_points: 40,
        stability: BranchStability::None,
        ..SpeedContinuationOptions::default()
    };
    let b = liu2021::continue_in_speed(&p, &o, HbmStart::Cold).unwrap();
    assert!(!b.points.is_empty());
    assert!((b.points[0].parameter - 180.0).abs() < 1e-9);
    let fold = b.folds.first().expect("a fold");
    assert!(
        (184.0..187.0).contains(&fold.parameter),
        "fold at {}",
        fold.parameter
    );
    let before = &b.points[fold.after_index];
    assert_eq!(before.rattle.state, RattleState::Unilateral);
    // past the fold the branch runs back to lower speeds with a larger ppv
    let last = b.points.last().unwrap();
    assert!(last.parameter < fold.parameter && last.rattle.ppv > before.rattle.ppv);
    assert!(b.points.iter().all(|p| p.stable().is_none()));
    let bad = SpeedContinuationOptions {
        initial_step: f64::NAN,
        ..o
    };
    assert!(liu2021::continue_in_speed(&p, &bad, HbmStart::Cold).is_err());

    // Thinned stability (the library's policy the Fig. 11 study uses): points ≥ 2 rad/s apart,
    // each checked, the rest left `None`; each checked value equals the direct call.
    let mut thinned = b.clone();
    liu2021::add_branch_stability(&p, &mut thinned, 2.0).unwrap();
    let picked: Vec<usize> = (0..thinned.points.len())
        .filter(|&i| thinned.points[i].stable().is_some())
        .collect();
    assert_eq!(picked.first(), Some(&0));
    for w in picked.windows(2) {
        assert!((thinned.points[w[1]].parameter - thinned.points[w[0]].parameter).abs() >= 2.0);
    }
    let i = *picked.last().unwrap();
    let m = p
        .model()
        .unwrap()
        // the library's order of operations (`ω₁ · (ω̄_c/ω₁,params)`): the multiplier of this
        // unstable orbit moves by ~1e-3 under a one-ulp change of ω̄_c
        .with_omega_c(thinned.points[i].parameter * (p.model().unwrap().omega_c / p.omega1))
        .unwrap();
    let r = liu2021::HbmResponse {
        solution: thinned.points[i].solution.clone(),
        rattle: thinned.points[i].rattle,
    };
    assert_eq!(
        thinned.points[i].max_multiplier(),
        Some(liu2021::max_multiplier(&m, &r).unwrap())
    );
    assert!(liu2021::add_branch_stability(&p, &mut thinned, -1.0).is_err());
    assert!(liu2021::add_branch_stability(&p, &mut thinned, f64::NAN).is_err());
}

#[test]
fn shooting_multipliers_flag_stable_orbits() {
    // Without contact loss (120 rad/s) the true multipliers are ~exp(−ζT) ≈ 1e-10; the
    // finite-difference period map resolves them only down to its noise floor (perturbation
    // 1e-7 b̄ against the integrator's absolute tolerance), so the test bounds them by 1e-3.
    // The bilateral orbit at 220 rad/s, to which time integration converges, is stable too.
    let m = paper(120.0).model().unwrap();
    let hb = solve_hbm(&m, &HbmOptions::default(), None).unwrap();
    let modulus = |mu: [[f64; 2]; 2]| mu.iter().map(|z| z[0].hypot(z[1])).fold(0.0, f64::max);
    let mu = liu2021::shooting_multipliers(&m, &hb).unwrap();
    assert!(modulus(mu) < 1e-3, "{mu:?}");
    let m = paper(220.0).model().unwrap();
    let ti = liu2021::integrate(&m, &short()).unwrap();
    let hb = solve_hbm_from_time_response(&m, &HbmOptions::full(&m, 1), &ti).unwrap();
    let mu = liu2021::shooting_multipliers(&m, &hb).unwrap();
    assert!(modulus(mu) < 1.0, "{mu:?}");
}
