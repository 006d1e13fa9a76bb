//! The generic spur pair (`models::pair`) and the Yu et al. (2021) 6-DOF transverse-torsional
//! model (`models::yu2021::Yu2021SixDof`) through the same API as every other system: shooting,
//! monodromy from the variational equations and Floquet multipliers, each held against an
//! independent engine (the `timestep` integrator's period map; the `hbm` orbit and its own
//! period-map multipliers).

use math::DetMath;
use models::pair::{GearPair, PairParams, TimeSettings};
use models::yu2021::{Options, Yu2021Model, Yu2021Params};
use nalgebra::DMatrix;
use orbit::{OrbitProblem, ShootingOptions};
use std::f64::consts::PI;

/// End state of the `timestep` engine over one mesh period from `x` (no transient).
fn pair_period_map(pair: &GearPair, x: &[f64]) -> Vec<f64> {
    pair.time_response(
        &TimeSettings {
            transient_periods: 0,
            record_periods: 1,
            samples_per_period: 4,
            rtol: 1e-12,
            atol: 1e-18,
        },
        Some(x),
    )
    .unwrap()
    .final_state
}

/// The example spur pair (tooth-pair stiffness, 50 µm half backlash, 2000 rad/s mesh
/// frequency) at its 100 N·m (contact kept), and with 20 µm STE near resonance at 2 N·m,
/// 6000 rad/s (stable, four contact events per mesh period) and 1 N·m, 7000 rad/s (an
/// unstable rattling orbit, |μ| ≈ 1.3, which time integration alone cannot reach): the
/// shooting orbit is a fixed point of the `timestep` period map, and the monodromy from the
/// variational equations equals central differences of that map.
#[test]
fn pair_orbit_and_monodromy_match_the_timestep_engine() {
    for (torque, omega, ste, rattles) in [
        (100.0, 2000.0, 10e-6, false),
        (2.0, 6000.0, 20e-6, true),
        (1.0, 7000.0, 20e-6, true),
    ] {
        let mut pp = PairParams::example_spur();
        pp.static_force = torque / 0.094;
        pp.ste_amplitude = ste;
        let mut pair = GearPair::from_params(&pp).unwrap();
        pair.set_mesh_frequency(omega).unwrap();
        pair_case(&pair, omega, rattles);
    }
}

fn pair_case(pair: &GearPair, omega: f64, rattles: bool) {
    let t = 2.0 * PI / omega;
    let guess = pair
        .time_response(
            &TimeSettings {
                transient_periods: 100,
                record_periods: 1,
                ..TimeSettings::default()
            },
            None,
        )
        .unwrap()
        .final_state;
    let p = OrbitProblem::new(pair.clone(), t)
        .unwrap()
        .with_flow_options(orbit::FlowOptions {
            rtol: 1e-12,
            atol: 1e-16,
            ..orbit::FlowOptions::default()
        })
        .unwrap();
    let pair = pair.clone();
    let o = p.shoot(&guess, &ShootingOptions::default()).unwrap();
    let scale: Vec<f64> = o.x0.iter().map(|v| v.abs().max(1e-9)).collect();
    let back = pair_period_map(&pair, &o.x0);
    for i in 0..2 {
        assert!(
            (back[i] - o.x0[i]).abs() < 1e-6 * scale[i],
            "component {i}: {back:?} vs {:?}",
            o.x0
        );
    }
    let fd_at = |rel: f64| {
        let mut fd = DMatrix::zeros(2, 2);
        for j in 0..2 {
            let d = rel * scale[j];
            let (mut xp, mut xm) = (o.x0.clone(), o.x0.clone());
            xp[j] += d;
            xm[j] -= d;
            let (a, b) = (pair_period_map(&pair, &xp), pair_period_map(&pair, &xm));
            for i in 0..2 {
                fd[(i, j)] = (a[i] - b[i]) / (2.0 * d);
            }
        }
        fd
    };
    // compare in the scaled state (diag(1/scale) Φ diag(scale)), against the largest entry
    let sc = |a: &DMatrix<f64>| DMatrix::from_fn(2, 2, |i, j| a[(i, j)] * scale[j] / scale[i]);
    let ms = sc(&o.monodromy);
    // the contact-keeping map is affine (any step is exact up to round-off: 1e-3); the rattling
    // map has a contact change within 1e-3 of the orbit, so its step is 1e-5
    let fd = fd_at(if rattles { 1e-5 } else { 1e-3 });
    let err = (&ms - &sc(&fd)).amax() / ms.amax();
    // contact kept: 1.9e-6. Rattling: 1.4e-4 (four events a period) and 2.2e-5 (two); 3.6e-4
    // before the flows' no-growth rule after a rejection (round 17), 1.1e-3 with
    // `FlowOptions::crossing_retry` (larger steps end at the events), 9.3e-5 with
    // max_step_fraction 0.001: an error of the variational equations across the contact events
    // that shrinks with the step ending at the event (open; the closed-form bilinear test,
    // time-independent gap function, agrees to 5e-11)
    let tol = if rattles { 1e-3 } else { 1e-5 };
    assert!(err < tol, "{err:e}: {} vs {fd}", o.monodromy);
    let unstable_expected = omega > 6500.0;
    assert_eq!(o.floquet.stable, !unstable_expected);
    println!(
        "pair: x0 {:?}, events {}, monodromy error {err:.1e}, μ {:?}",
        o.x0,
        o.events.len(),
        o.floquet.multipliers
    );
    assert_eq!(!o.events.is_empty(), rattles);
    // multipliers of the finite-difference map agree too
    let ffd = orbit::floquet(&fd).unwrap();
    assert!(
        (ffd.max_modulus - o.floquet.max_modulus).abs() < tol * o.floquet.max_modulus.max(1e-3),
        "{} vs {}",
        ffd.max_modulus,
        o.floquet.max_modulus
    );
    assert_eq!(ffd.stable, o.floquet.stable);
}

/// Yu Table 1 at ω* = 0.5 (six degrees of freedom, five coordinates): shooting from the
/// harmonic-balance orbit (H = 32) converges to it (the models test finds H = 32 within 5.5e-7
/// of the time response), and the multipliers agree with those of the `hbm` engine's period
/// map at its orbit.
#[test]
#[ignore = "heavy: run optimised by `cargo xtask heavy-tests` (.ci/run)"]
fn yu_six_dof_orbit_and_multipliers_match_harmonic_balance() {
    let omega = 0.5;
    let h = 32;
    let m = Yu2021Model::new(&Yu2021Params::table1(), Options::default()).unwrap();
    let mut hp = m
        .hbm_problem_six_dof(omega, h, (8 * h).next_power_of_two())
        .unwrap();
    let mut z0 = vec![0.0; 5 * (2 * h + 1)];
    z0[0] = m.initial_state()[0];
    let sol = hp
        .solve(
            &z0,
            &hbm::SolverOptions {
                method: hbm::Method::Newton,
                tolerance: 1e-10,
                max_iters: 60,
            },
        )
        .unwrap();
    assert!(sol.converged);
    let st = hp.stability(&sol, Some(4000)).unwrap();
    let (q, v) = sol.state_at(0.0);
    let x: Vec<f64> = q.iter().chain(&v).copied().collect();
    let sys = models::yu2021::Yu2021SixDof::new(&m, omega).unwrap();
    let p = OrbitProblem::new(sys, 2.0 * PI / omega).unwrap();
    let o = p.shoot(&x, &ShootingOptions::default()).unwrap();
    let ptp = x.iter().fold(0.0_f64, |a, b| a.max(b.abs()));
    let dx =
        o.x0.iter()
            .zip(&x)
            .fold(0.0_f64, |a, (s, h)| a.max((s - h).abs()));
    assert!(dx < 1e-5 * ptp, "shooting vs HBM orbit: {dx} (scale {ptp})");
    let mut a: Vec<f64> = o
        .floquet
        .multipliers
        .iter()
        .map(|m| m[0].dhypot(m[1]))
        .collect();
    let mut b: Vec<f64> = st.multipliers.iter().map(|m| m[0].dhypot(m[1])).collect();
    a.sort_by(f64::total_cmp);
    b.sort_by(f64::total_cmp);
    assert_eq!(a.len(), 10);
    for (x, y) in a.iter().zip(&b) {
        assert!((x - y).abs() < 1e-4, "|μ| shooting {a:?} vs hbm {b:?}");
    }
    println!(
        "yu 6-DOF ω* = {omega}: events {}, |μ| {a:?}, stable {}",
        o.events.len(),
        o.floquet.stable
    );
    assert_eq!(o.floquet.stable, st.stable);
}
