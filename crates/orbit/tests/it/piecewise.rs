//! Non-smooth checks: the bilinear oscillator's monodromy as a product of closed-form matrix
//! exponentials, S = I at kinks, and the monodromy against finite differences of the
//! event-located flow.

use crate::common::{bilinear, bilinear_monodromy, two_sided_rattle};
use math::DetMath;
use nalgebra::DMatrix;
use orbit::{OrbitProblem, ShootingOptions};
use std::f64::consts::PI;

/// Between events the variational equation is linear with constant coefficients, so the
/// monodromy is `e^{A_m Δt_m} ⋯ S₂ e^{A_2 Δt_2} S₁ e^{A_1 Δt_1}` with `S_i = I` (the force is
/// continuous across the kink). The event times come from the shooting solution.
#[test]
fn bilinear_monodromy_is_the_product_of_exponentials() {
    let s = bilinear();
    let t = 2.0 * PI / s.omega;
    let p = OrbitProblem::new(s, t).unwrap();
    let o = p.shoot(&[-0.5, 0.9], &ShootingOptions::default()).unwrap();
    assert_eq!(o.events.len(), 2, "one excursion past the kink per period");
    // saltation is the identity for the continuous (kinked) force
    for e in &o.events {
        assert!(e.saltation_jump < 1e-9, "S − I = {}", e.saltation_jump);
        assert!(!e.impact);
    }
    let phi = bilinear_monodromy(&s, &o.x0, &o.events, t);
    assert!(
        (&o.monodromy - &phi).amax() < 1e-7,
        "{} vs {phi}",
        o.monodromy
    );
    // Liouville holds piece by piece
    assert!((o.monodromy.determinant() - (-2.0 * s.zeta * t).dexp()).abs() < 1e-9);
    // multiple shooting: same orbit, same monodromy
    let o3 = p
        .shoot(
            &o.x0,
            &ShootingOptions {
                segments: 4,
                ..Default::default()
            },
        )
        .unwrap();
    assert!((o3.x0[0] - o.x0[0]).abs() < 1e-8 && (o3.x0[1] - o.x0[1]).abs() < 1e-8);
    assert!((&o3.monodromy - &o.monodromy).amax() < 1e-7);
    let m3 = &o3.floquet.multipliers;
    for (a, b) in m3.iter().zip(&o.floquet.multipliers) {
        assert!((a[0] - b[0]).abs() < 1e-7 && (a[1] - b[1]).abs() < 1e-7);
    }
}

/// The monodromy from the variational equations and saltation matrices against central
/// differences of the event-located period map, on a two-sided rattle orbit (four contact
/// events per period); and the multipliers of both.
#[test]
fn monodromy_matches_finite_differences_of_the_flow() {
    let s = two_sided_rattle();
    let t = 2.0 * PI / s.omega;
    let p = OrbitProblem::new(s, t).unwrap();
    let o = p.shoot(&[0.0, 1.0], &ShootingOptions::default()).unwrap();
    assert!(o.events.len() >= 4, "{} events", o.events.len());
    let mut fd = DMatrix::zeros(2, 2);
    for j in 0..2 {
        let h = 1e-6;
        let (mut xp, mut xm) = (o.x0.clone(), o.x0.clone());
        xp[j] += h;
        xm[j] -= h;
        let fp = p.flow(0.0, &xp, t, false).unwrap().state;
        let fm = p.flow(0.0, &xm, t, false).unwrap().state;
        for i in 0..2 {
            fd[(i, j)] = (fp[i] - fm[i]) / (2.0 * h);
        }
    }
    let scale = fd.amax().max(1.0);
    assert!(
        (&o.monodromy - &fd).amax() < 1e-5 * scale,
        "{} vs {fd}",
        o.monodromy
    );
    let ffd = orbit::floquet(&fd).unwrap();
    for (a, b) in ffd.multipliers.iter().zip(&o.floquet.multipliers) {
        assert!(
            (a[0] - b[0]).abs() < 1e-5 && (a[1] - b[1]).abs() < 1e-5,
            "{a:?} vs {b:?}"
        );
    }
    for c in &o.floquet.condition {
        assert!(c.is_finite() && *c >= 1.0 - 1e-9);
    }
}

/// Continuation in a *named* parameter (the forcing amplitude `f`): the linear orbit
/// `q = P cos(ωt − ψ)`, `P = f/√((1−ω²)² + (2ζω)²)`, grazes the kink at `q = d` when `P = d`.
#[test]
fn grazing_in_a_named_parameter_matches_closed_form() {
    let mut s = bilinear();
    s.f = 0.3;
    let t = 2.0 * PI / s.omega;
    let mut p = OrbitProblem::new(s, t).unwrap();
    let opts = orbit::ContinuationOptions {
        initial_step: 0.05,
        max_step: 0.1,
        corrector: orbit::ShootingCorrection {
            parameter: orbit::Parameter::Named("f".into()),
            range: [0.0, 1.2],
            locate_tol: 1e-10,
            ..orbit::ShootingCorrection::default()
        },
        ..Default::default()
    };
    let br = p.continuation(&[0.0, 0.0], 0.3, &opts).unwrap();
    assert_eq!(br.stop, orbit::StopReason::ReachedEnd);
    let g: Vec<_> = br
        .special
        .iter()
        .filter(|x| {
            matches!(
                x.kind,
                orbit::SpecialKind::Grazing {
                    event: 0,
                    extremum: orbit::Extremum::Max
                }
            )
        })
        .collect();
    assert_eq!(g.len(), 1);
    let w = s.omega;
    let f_closed = s.d * ((1.0 - w * w).powi(2) + (2.0 * s.zeta * w).powi(2)).sqrt();
    assert!(
        (g[0].point.parameter - f_closed).abs() < 1e-8,
        "{} vs {f_closed}",
        g[0].point.parameter
    );
    assert!((p.system().f - br.points.last().unwrap().parameter).abs() < 1e-12);
}
