//! The Liu et al. (2021) NFG rattle model (`models::liu2021`, Table 1, constant b̄) through the
//! same API: shooting from a time-integration guess, multipliers against central differences
//! of the `timestep` engine's period map (an independent integrator with its own event
//! location).

use models::liu2021::{self, BaseRadius, IntegrationOptions, Model};
use orbit::{OrbitProblem, ShootingOptions};

fn model(omega1: f64) -> Model {
    let mut p = liu2021::table1();
    p.readings.base_radius = BaseRadius::Mean;
    p.omega1 = omega1;
    p.model().unwrap()
}

/// End state of a time integration from `(q, v)` over `periods` periods (the `timestep`
/// engine, rtol 1e-11).
fn timestep_map(m: &Model, q: f64, v: f64, periods: f64, rtol: f64) -> (f64, f64) {
    let r = liu2021::integrate(
        m,
        &IntegrationOptions {
            transient_periods: 0.0,
            record_periods: periods,
            sample_step: m.period() / 16.0,
            max_step: 0.25,
            rtol,
            initial: Some((q, v)),
            method: liu2021::Stepping::Auto,
            transient_rtol: None,
        },
    )
    .unwrap();
    (*r.q.last().unwrap(), *r.v.last().unwrap())
}

#[test]
#[ignore = "heavy: run optimised by `cargo xtask heavy-tests` (.ci/run)"]
fn liu_orbits_and_multipliers_match_the_timestep_engine() {
    for omega1 in [120.0, 160.0, 200.0, 220.0] {
        let m = model(omega1);
        let t = m.period();
        // time-integration guess: 200 periods from the quasi-static contact position
        let (q, v) = timestep_map(&m, -m.backlash - m.b0, 0.0, 200.0, 1e-9);
        let p = OrbitProblem::new(m, t).unwrap();
        let o = p.shoot(&[q, v], &ShootingOptions::default()).unwrap();
        // the orbit is periodic under the independent engine too
        let (qb, vb) = timestep_map(&m, o.x0[0], o.x0[1], 1.0, 1e-12);
        assert!(
            (qb - o.x0[0]).abs() < 1e-9 && (vb - o.x0[1]).abs() < 1e-9,
            "ω1 {omega1}"
        );
        // finite-difference monodromy of the timestep engine's period map
        let d = 1e-5 * m.backlash;
        let mut fd = nalgebra::DMatrix::zeros(2, 2);
        for j in 0..2 {
            let mut xp = o.x0.clone();
            let mut xm = o.x0.clone();
            xp[j] += d;
            xm[j] -= d;
            let a = timestep_map(&m, xp[0], xp[1], 1.0, 1e-12);
            let b = timestep_map(&m, xm[0], xm[1], 1.0, 1e-12);
            fd[(0, j)] = (a.0 - b.0) / (2.0 * d);
            fd[(1, j)] = (a.1 - b.1) / (2.0 * d);
        }
        // Liu's period spans Z2 mesh cycles: the map contracts strongly (|μ| ≤ 1e-4), so the
        // comparison is absolute, at the finite-difference noise (rtol·|x|/d ≈ 1e-7)
        assert!(
            (&o.monodromy - &fd).amax() < 2e-6,
            "ω1 {omega1}: {} vs {fd}",
            o.monodromy
        );
        let ffd = orbit::floquet(&fd).unwrap();
        for (a, b) in o.floquet.multipliers.iter().zip(&ffd.multipliers) {
            assert!((a[0] - b[0]).abs() < 2e-6 && (a[1].abs() - b[1].abs()).abs() < 2e-6);
        }
        println!(
            "ω1 {omega1}: events {}, μ {:?}, fd μ {:?}, stable {}",
            o.events.len(),
            o.floquet.multipliers,
            ffd.multipliers,
            o.floquet.stable
        );
        assert!(o.floquet.stable);
        assert!(o.events.iter().all(|e| e.saltation_jump < 1e-8));
    }
}
