//! Linear and smooth checks: exact periodic orbit and monodromy of a forced linear oscillator,
//! Liouville's formula, finite-difference monodromy.

use crate::common::{Bilinear, exp_oscillator, linear_oscillator};
use math::DetMath;
use orbit::{OrbitProblem, ShootingOptions};

/// Far below the kink the bilinear oscillator is linear: `q'' + 2ζq' + q = F cos ωt`, periodic
/// orbit `q = P cos(ωt − ψ)`, monodromy `exp(A T)`.
#[test]
fn linear_orbit_and_monodromy_are_exact() {
    let (s, _) = linear_oscillator();
    let t = 2.0 * std::f64::consts::PI / s.omega;
    let p = OrbitProblem::new(s, t).unwrap();
    for segments in [1, 3] {
        let o = p
            .shoot(
                &[0.0, 0.0],
                &ShootingOptions {
                    segments,
                    ..Default::default()
                },
            )
            .unwrap();
        let (w, z) = (s.omega, s.zeta);
        let den = (1.0 - w * w).powi(2) + (2.0 * z * w).powi(2);
        let (a, b) = (s.f * (1.0 - w * w) / den, s.f * 2.0 * z * w / den); // q = a cos + b sin
        assert!((o.x0[0] - a).abs() < 1e-8, "{} vs {a}", o.x0[0]);
        assert!((o.x0[1] - b * w).abs() < 1e-8, "{} vs {}", o.x0[1], b * w);
        let exact = exp_oscillator(1.0, 2.0 * z, t);
        assert!(
            (&o.monodromy - &exact).amax() < 1e-8,
            "{} vs {exact}",
            o.monodromy
        );
        // Liouville: det Φ = exp(−2ζ T)
        assert!((o.monodromy.determinant() - (-2.0 * z * t).dexp()).abs() < 1e-9);
        assert!(o.floquet.stable);
        assert!(o.events.is_empty());
    }
}

#[test]
fn closed_form_exponential_matches_nalgebra() {
    for (k, c) in [(1.0, 0.1), (1.0, 3.0), (1.0, 2.0), (-0.5, 0.2)] {
        let a = nalgebra::DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -k, -c]);
        let e = (a * 0.7).exp();
        assert!((e - exp_oscillator(k, c, 0.7)).amax() < 1e-12);
    }
}

/// [`OrbitProblem::period_map`] is shooting without Newton: at a converged orbit it gives the
/// bits of the shot monodromy and multipliers; elsewhere its residual is the periodicity defect.
#[test]
fn period_map_is_the_shooting_monodromy() {
    let s = Bilinear {
        zeta: 0.05,
        kappa: 10.0,
        d: 0.5,
        f0: 0.0,
        f: 0.3,
        omega: 1.3,
    };
    let t = 2.0 * std::f64::consts::PI / s.omega;
    let p = OrbitProblem::new(s, t).unwrap();
    let o = p.shoot(&[0.0, 0.0], &ShootingOptions::default()).unwrap();
    let m = p.period_map(&o.x0, 1).unwrap();
    assert_eq!(m.monodromy, o.monodromy);
    assert_eq!(m.floquet, o.floquet);
    assert_eq!(m.iterations, 0);
    assert!(m.residual <= 1e-9);
    // off the orbit: the residual is the defect of the period map
    let x = [o.x0[0] + 0.01, o.x0[1]];
    let off = p.period_map(&x, 1).unwrap();
    let flow = p.flow(0.0, &x, t, false).unwrap();
    let defect = (flow.state[0] - x[0])
        .abs()
        .max((flow.state[1] - x[1]).abs());
    assert_eq!(off.residual.to_bits(), defect.to_bits());
    assert!(off.residual > 1e-4);
    assert!(p.period_map(&[0.0], 1).is_err());
    assert!(p.period_map(&[0.0, 0.0], 0).is_err());
}
