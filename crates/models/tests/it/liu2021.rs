//! Integration tests of the Liu et al. 2021 NFG model: parameters, readings, both engines.

use geardyn_models::Error;
use geardyn_models::liu2021::{
    self, BaseRadius, Basis, BranchStability, HbmOptions, HbmStart, IntegrationOptions,
    LongWindowOptions, Parameters, RattleState, Readings, SpeedContinuationOptions, Stepping,
    solve_hbm, solve_hbm_from_time_response, solve_hbm_with,
};
use math::DetMath;

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

/// Settled on the bilateral period-1 orbit at 220 rad/s: after one period the response is
/// still a transient whose details (ppv 2.2e-3 … 3.8e-3) change with the tolerance, so a
/// harmonic balance started from it converges or not by chance.
fn settled() -> IntegrationOptions {
    IntegrationOptions {
        transient_periods: 12.0,
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

/// `transient_rtol`: `Some(rtol)` is the default run bit for bit; a transient at 1e-8 before a
/// window at 1e-10 takes fewer steps and leaves the settled window within the window's own
/// tolerance band of the all-1e-10 run (the unilateral orbit at 140 rad/s, 12 + 2 periods:
/// the same contact events, the same rattle state, `q` within 1e-8 b̄); a bad value is an error
/// naming the field.
#[test]
fn transient_rtol_settles_on_the_same_window() {
    let m = paper(140.0).model().unwrap();
    let tight = IntegrationOptions {
        transient_periods: 12.0,
        record_periods: 2.0,
        sample_step: m.period() / 64.0,
        rtol: 1e-10,
        initial: Some((-m.backlash - m.b0, 0.0)),
        method: liu2021::Stepping::DormandPrince54,
        ..IntegrationOptions::default()
    };
    let a = liu2021::integrate(&m, &tight).unwrap();
    let same = liu2021::integrate(
        &m,
        &IntegrationOptions {
            transient_rtol: Some(1e-10),
            ..tight
        },
    )
    .unwrap();
    assert_eq!(a.q, same.q);
    assert_eq!(a.rhs_evaluations, same.rhs_evaluations);
    let loose = liu2021::integrate(
        &m,
        &IntegrationOptions {
            transient_rtol: Some(1e-8),
            ..tight
        },
    )
    .unwrap();
    assert!(
        loose.rhs_evaluations < a.rhs_evaluations * 3 / 4,
        "{} vs {}",
        loose.rhs_evaluations,
        a.rhs_evaluations
    );
    assert!(a.contact_events > 0);
    assert_eq!(loose.contact_events, a.contact_events);
    assert_eq!(loose.rattle.state, a.rattle.state);
    assert_eq!(loose.q.len(), a.q.len());
    let dq = loose
        .q
        .iter()
        .zip(&a.q)
        .fold(0.0_f64, |d, (x, y)| d.max((x - y).abs()));
    assert!(dq < 1e-8 * m.backlash, "max |Δq| = {dq:e}");
    for bad in [0.0, -1e-8, f64::NAN, f64::INFINITY] {
        let e = liu2021::integrate(
            &m,
            &IntegrationOptions {
                transient_rtol: Some(bad),
                ..tight
            },
        )
        .unwrap_err();
        assert!(e.to_string().contains("transient_rtol"), "{e}");
    }
}

#[test]
fn table1_dimensionless_numbers() {
    // Hand values: L = 0.0225*3.5*cos20°*1.04/0.96, β = 0.4/1.04, ω_n from Eq. (10).
    let m = paper(160.0).model().unwrap();
    let l = 0.0225 * 3.5 * 20f64.to_radians().dcos() * 1.04 / 0.96;
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
    let ti = liu2021::integrate(&m, &settled()).unwrap();
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
            s1 += 2.0 * a * x.dsin() / n as f64;
            s2 += 2.0 * a * (2.0 * x).dsin() / n as f64;
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
    // impacts). The time response is the settled one: after 10 transient periods, as the long
    // windows (after the default 2 the motion is still a transient there, ppv 1.77e-3 or
    // 2.22e-3 depending on the step sequence, and a warm start from that transient fails the
    // line search; from 5, 10 or 20 periods the ppv is 2.2160771e-3 under either retry rule).
    let m = paper(205.0).model().unwrap();
    let settled = IntegrationOptions {
        transient_periods: 10.0,
        ..IntegrationOptions::default()
    };
    let ti = liu2021::integrate(&m, &settled).unwrap();
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
#[ignore = "heavy: run optimised by `cargo xtask heavy-tests` (.ci/run)"]
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

/// The speed branch reports every parameter in rad/s, its stop reason included: from 184 rad/s
/// up, the paper-basis unilateral branch turns at its fold (≈ 185.5) and leaves the range
/// `[184, 195]` below its start; the reason carries the last point's `ω₁` (not `ω̄_c`, which
/// is O(0.01) here).
#[test]
fn speed_branch_stop_reason_is_in_rad_per_s() {
    let p = paper(184.0);
    let o = SpeedContinuationOptions {
        omega1_end: 195.0,
        max_points: 300,
        stability: BranchStability::None,
        ..SpeedContinuationOptions::default()
    };
    let b = liu2021::continue_in_speed(&p, &o, HbmStart::Cold).unwrap();
    let last = b.points.last().unwrap().parameter;
    println!(
        "stop {:?}, {} points, last ω1 {last}",
        b.stop,
        b.points.len()
    );
    assert_eq!(b.stop, orbit::StopReason::LeftRange { parameter: last });
    let w = b.stop.parameter().unwrap();
    assert!((150.0..184.0).contains(&w), "{w}");
    // the dimensionless value is the documented ratio away
    let m = p.model().unwrap();
    assert!(w * m.omega_c / p.omega1 < 1.0);
}

#[test]
fn shooting_multipliers_flag_stable_orbits() {
    // Without contact loss (120 rad/s) the true multipliers are ~exp(−ζT) ≈ 1e-10; the
    // variational monodromy resolves them (the deleted finite-difference map had a noise floor
    // of ~1e-7 and was bounded here by 1e-3, the bound kept). The bilateral orbit at
    // 220 rad/s, to which time integration converges, is stable too.
    let m = paper(120.0).model().unwrap();
    let hb = solve_hbm(&m, &HbmOptions::default(), None).unwrap();
    let mu = liu2021::shooting_multipliers(&m, &hb).unwrap();
    assert!(mu.max_modulus < 1e-3, "{:?}", mu.multipliers);
    let m = paper(220.0).model().unwrap();
    let ti = liu2021::integrate(&m, &settled()).unwrap();
    let hb = solve_hbm_from_time_response(&m, &HbmOptions::full(&m, 1), &ti).unwrap();
    let mu = liu2021::shooting_multipliers(&m, &hb).unwrap();
    assert!(mu.max_modulus < 1.0, "{:?}", mu.multipliers);
}

/// End state of one period of the `timestep` engine (its own event location) from `(q, v)`.
fn one_period(m: &liu2021::Model, q: f64, v: f64, max_step: f64, rtol: f64) -> (f64, f64) {
    let r = liu2021::integrate(
        m,
        &IntegrationOptions {
            transient_periods: 0.0,
            record_periods: 1.0,
            sample_step: m.period() / 16.0,
            max_step,
            rtol,
            initial: Some((q, v)),
            method: liu2021::Stepping::Auto,
            transient_rtol: None,
        },
    )
    .unwrap();
    (*r.q.last().unwrap(), *r.v.last().unwrap())
}

/// The monodromy of the deleted `BranchStability::Shooting` implementation, kept as the
/// reference it was: forward differences (`d = 1e-7 b̄` in `q` and in `q'`) of three
/// one-period integrations of the `timestep` engine, rtol 1e-11, steps ≤ 0.25.
fn finite_difference_monodromy(m: &liu2021::Model, q0: f64, v0: f64) -> nalgebra::DMatrix<f64> {
    let d = 1e-7 * m.backlash;
    let (qb, vb) = one_period(m, q0, v0, 0.25, 1e-11);
    let (qa, va) = one_period(m, q0 + d, v0, 0.25, 1e-11);
    let (qv, vv) = one_period(m, q0, v0 + d, 0.25, 1e-11);
    nalgebra::DMatrix::from_row_slice(
        2,
        2,
        &[(qa - qb) / d, (qv - qb) / d, (va - vb) / d, (vv - vb) / d],
    )
}

/// A converged finite-difference monodromy: central differences with `d = 1e-5 b̄` of the
/// `timestep` engine at rtol 1e-13 and steps ≤ 0.1 (noise `rtol·|x|/d ≈ 1e-8`; measured
/// against `d = 1e-4 b̄` and `1e-6 b̄`: the entries move by ≤ 5e-8, except where `d = 1e-4 b̄`
/// changes a contact).
fn central_difference_monodromy(m: &liu2021::Model, q0: f64, v0: f64) -> nalgebra::DMatrix<f64> {
    let d = 1e-5 * m.backlash;
    let map = |q, v| one_period(m, q, v, 0.1, 1e-13);
    let (a, b) = (map(q0 + d, v0), map(q0 - d, v0));
    let (c, e) = (map(q0, v0 + d), map(q0, v0 - d));
    let h = 2.0 * d;
    nalgebra::DMatrix::from_row_slice(
        2,
        2,
        &[
            (a.0 - b.0) / h,
            (c.0 - e.0) / h,
            (a.1 - b.1) / h,
            (c.1 - e.1) / h,
        ],
    )
}

/// Fig. 11 points (no rattle 120, unilateral 150 and 160, bilateral 220 and 250 rad/s, warm
/// from the settled time response on the full basis K = 65): the shooting monodromy of `orbit`
/// (variational equations, one integration) against the deleted finite-difference one and a
/// converged central difference.
///
/// Tolerances (absolute: the map contracts strongly, its entries are 1e-3 or less):
/// * against the deleted forward differences, their own error bound: the two perturbed runs'
///   integration errors over the perturbation, `rtol·‖x₀‖/d` with rtol 1e-11 and
///   `d = 1e-7 b̄` (`≈ 1e-4 ‖x₀‖/b̄`; measured up to 1.2e-5, at 250 rad/s in `Φ₁₂`);
/// * against the central differences, 2e-7: their noise (≤ 5e-8) plus the variational
///   equation's global error, which the step-size control does not see (measured ≤ 6e-8 here
///   at steps ≤ 0.05; 4e-7 at 160 rad/s with steps ≤ 0.1, why the period map takes 0.05).
#[test]
#[ignore = "heavy: run optimised by `cargo xtask heavy-tests` (.ci/run)"]
fn shooting_multipliers_match_the_finite_difference_period_map() {
    for omega1 in [120.0, 150.0, 160.0, 220.0, 250.0] {
        let m = paper(omega1).model().unwrap();
        let ti = liu2021::integrate(&m, &settled()).unwrap();
        let hb = solve_hbm_from_time_response(&m, &HbmOptions::full(&m, 1), &ti).unwrap();
        let map = liu2021::shooting_period_map(&m, &hb).unwrap();
        let (q, v) = hb.solution.state_at(0.0);
        let fd = finite_difference_monodromy(&m, q[0], v[0]);
        let bound = 1e-11 * q[0].abs().max(v[0].abs()).max(m.backlash) / (1e-7 * m.backlash);
        let cd = central_difference_monodromy(&m, q[0], v[0]);
        let (diff, diff_c) = ((&map.monodromy - &fd).amax(), (&map.monodromy - &cd).amax());
        let ffd = orbit::floquet(&fd).unwrap();
        println!(
            "ω1 {omega1}: events {}, |Φ − Φ_fd| {diff:.2e} (bound {bound:.1e}), |Φ − Φ_cd| \
             {diff_c:.2e}, max |μ| {:.4e}, fd {:.4e}, defect {:.1e}",
            map.events.len(),
            map.floquet.max_modulus,
            ffd.max_modulus,
            map.residual
        );
        assert!(diff <= bound, "ω1 {omega1}: {} vs {fd}", map.monodromy);
        assert!(
            (map.floquet.max_modulus - ffd.max_modulus).abs() <= bound,
            "ω1 {omega1}"
        );
        assert_eq!(map.floquet.stable, ffd.stable, "ω1 {omega1}");
        assert!(diff_c <= 2e-7, "ω1 {omega1}: {} vs {cd}", map.monodromy);
        // Liouville, through the contacts: tr A = −2ζ everywhere, so det Φ = exp(−2ζT), to the
        // variational equation's own global error (it is outside the step-size control, which
        // sees the state only; steps ≤ 0.05 in τ: measured ≤ 8e-7 relative here)
        let det = map.monodromy.determinant();
        let exact = (-2.0 * m.zeta * m.period()).dexp();
        println!("  det Φ / exp(−2ζT) − 1 = {:.1e}", det / exact - 1.0);
        assert!(
            (det / exact - 1.0).abs() < 1e-5,
            "ω1 {omega1}: {det} vs {exact}"
        );
        // the restoring force is continuous at the gap edges: the saltation matrices are I
        assert!(map.events.iter().all(|e| e.saltation_jump < 1e-8));
        if omega1 >= 220.0 {
            // bilateral: both edges are crossed, several times per period
            assert!(map.events.iter().any(|e| e.index == 0));
            assert!(map.events.iter().any(|e| e.index == 1));
        }
        // the shooting verdict is this one
        let s = liu2021::shooting_stability(&m, &hb).unwrap();
        assert_eq!(s.max_modulus.to_bits(), map.floquet.max_modulus.to_bits());
    }
}

/// A linear case through the Liu path: no stiffness fluctuation and no eccentricity
/// (`F ≡ 1`), at a speed where the teeth never separate, Eq. (9) is `q'' + 2ζq' + q = f_r(τ)`
/// and the monodromy is `exp(A T)`, `A = [[0, 1], [−1, −2ζ]]`, with the multipliers
/// `exp((−ζ ± i√(1 − ζ²)) T)`.
#[test]
fn shooting_monodromy_is_exact_for_a_linear_mesh() {
    let mut p = paper(120.0);
    p.kr = 0.0;
    p.eccentricity = 0.0;
    let m = p.model().unwrap();
    let hb = solve_hbm(&m, &HbmOptions::default(), None).unwrap();
    let map = liu2021::shooting_period_map(&m, &hb).unwrap();
    assert!(
        map.events.is_empty(),
        "contact is kept: the system is linear"
    );
    let (z, t) = (m.zeta, m.period());
    let wd = (1.0 - z * z).sqrt();
    let (s, c, e) = ((wd * t).dsin(), (wd * t).dcos(), (-z * t).dexp());
    // exp(AT) = e^{−ζT} [cos(ω_d T) I + sin(ω_d T)/ω_d (A + ζ I)]
    let exact = nalgebra::DMatrix::from_row_slice(
        2,
        2,
        &[
            e * (c + z * s / wd),
            e * s / wd,
            -e * s / wd,
            e * (c - z * s / wd),
        ],
    );
    // the entries are O(e) = O(1e-9): relative to that scale, within the variational
    // equation's global error (outside the step-size control; DP5 at steps ≤ 0.05 on the
    // oscillation ω = 1 over T ≈ 2300: measured 1.4e-7, the bound 1e-5)
    println!(
        "linear: |Φ − exp(AT)| / e^(−ζT) = {:.1e}",
        (&map.monodromy - &exact).amax() / e
    );
    assert!(
        (&map.monodromy - &exact).amax() <= 1e-5 * e,
        "{} vs {exact}",
        map.monodromy
    );
    for mu in &map.floquet.multipliers {
        assert!(
            (mu[0].dhypot(mu[1]) / e - 1.0).abs() < 1e-5,
            "{mu:?} vs |μ| {e}"
        );
    }
}

/// The long window's pair by flank (`Stepping::Auto`, rtol 1e-8): without rattle (120 rad/s)
/// and on one flank (150 rad/s) the windows run on DOP853, with fewer right-hand sides than
/// Dormand–Prince 5(4) and the same state, its ppv within the DP5 window's own error (the
/// 100×-tighter run is the reference: DOP853 lies closer to it); in bilateral rattle
/// (200 rad/s) the transient crosses the back flank and the windows stay on DP5, bit for bit.
#[test]
#[ignore = "heavy: run optimised by `cargo xtask heavy-tests` (.ci/run)"]
fn long_window_pair_by_flank() {
    let o = |stepping| LongWindowOptions {
        transient_periods: 5.0,
        periods: 20,
        stepping,
        ..LongWindowOptions::default()
    };
    for (w, one_flank) in [(120.0, true), (150.0, true), (200.0, false)] {
        let m = paper(w).model().unwrap();
        let auto = liu2021::settled_window(&m, &o(Stepping::Auto), None).unwrap();
        let dp5 = liu2021::settled_window(&m, &o(Stepping::DormandPrince54), None).unwrap();
        let tight = liu2021::settled_window(
            &m,
            &LongWindowOptions {
                rtol: 1e-10,
                ..o(Stepping::Auto)
            },
            None,
        )
        .unwrap();
        assert_eq!(auto.stats.state, dp5.stats.state, "{w} rad/s");
        if one_flank {
            assert!(
                auto.work.n_rhs < dp5.work.n_rhs,
                "{w} rad/s: {} vs {}",
                auto.work.n_rhs,
                dp5.work.n_rhs
            );
            let (e_auto, e_dp5) = (
                (auto.stats.ppv - tight.stats.ppv).abs(),
                (dp5.stats.ppv - tight.stats.ppv).abs(),
            );
            assert!(e_auto <= e_dp5, "{w} rad/s: |Δppv| {e_auto} vs DP5 {e_dp5}");
        } else {
            assert_eq!(auto.work, dp5.work, "{w} rad/s");
            assert_eq!(auto.stats.ppv.to_bits(), dp5.stats.ppv.to_bits());
        }
    }
}
