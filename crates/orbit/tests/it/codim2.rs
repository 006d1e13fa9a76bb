//! Codim-2 continuation: grazing curves against closed forms and time integration, fold
//! curves against harmonic balance, option checks and named stops.

use crate::common::Bilinear;
use math::DetMath;
use orbit::{
    Codim2ContinuationOptions, ContinuationOptions, Extremum, OrbitProblem, Parameter,
    ShootingCorrection, SpecialKind, StopReason,
};
use std::f64::consts::PI;

/// `q'' + 2ζq' + k(q) = f₀ + f cos ωt`, kink at `q = d` (`ζ = 0.05`, `κ = 4`, `d = 0.5`,
/// `f₀ = 0.1`).
fn bilinear(f: f64, omega: f64) -> Bilinear {
    Bilinear {
        zeta: 0.05,
        kappa: 4.0,
        d: 0.5,
        f0: 0.1,
        f,
        omega,
    }
}

/// Below the kink the orbit is linear, `q = f₀ + P cos(ωt − ψ)` with
/// `P = f/√((1−ω²)² + (2ζω)²)`, `ψ = atan2(2ζω, 1 − ω²)`: its maximum `f₀ + P` touches the
/// kink `q = d` (the maximum of the event function `q − d` grazes zero) at
/// `f_g(ω) = (d − f₀) √((1−ω²)² + (2ζω)²)`, at the time `t_g = ψ/ω (mod 2π/ω)`.
fn grazing_closed_form(s: &Bilinear, omega: f64) -> (f64, f64) {
    let w = omega;
    let f = (s.d - s.f0) * ((1.0 - w * w).powi(2) + (2.0 * s.zeta * w).powi(2)).sqrt();
    let psi = (2.0 * s.zeta * w).datan2(1.0 - w * w);
    (f, psi / w)
}

/// The grazing of the bilinear oscillator located on a branch in `f` at `ω = omega`.
fn grazing_start(
    omega: f64,
) -> (
    OrbitProblem<Bilinear>,
    orbit::SpecialPoint<orbit::ShootingPoint>,
) {
    let s = bilinear(0.2, omega);
    let mut p = OrbitProblem::new(s, 2.0 * PI / omega).unwrap();
    let opts = ContinuationOptions {
        initial_step: 0.05,
        max_step: 0.1,
        corrector: ShootingCorrection {
            parameter: Parameter::Named("f".into()),
            range: [0.0, 2.0],
            locate_tol: 1e-10,
            ..ShootingCorrection::default()
        },
        ..Default::default()
    };
    let br = p.continuation(&[0.1, 0.0], 0.2, &opts).unwrap();
    let g = br
        .special
        .iter()
        .find(|x| {
            x.kind
                == SpecialKind::Grazing {
                    event: 0,
                    extremum: Extremum::Max,
                }
        })
        .expect("grazing on the branch in f")
        .clone();
    assert!(g.located);
    (p, g)
}

/// The grazing curve of the bilinear oscillator in (f, ω) from a grazing located on a branch
/// in `f`: every point on the closed form `f_g(ω)` (source: the linear response, see
/// [`grazing_closed_form`]) to 1e-7 and at the closed-form grazing time, stable, and the curve
/// reaches the end of its `ω` range.
#[test]
fn bilinear_grazing_curve_matches_closed_form() {
    let (mut p, g) = grazing_start(1.5);
    let mut opts =
        Codim2ContinuationOptions::codim2(Parameter::Named("f".into()), Parameter::BaseFrequency);
    opts.initial_step = 0.05;
    opts.max_step = 0.2;
    opts.max_points = 12;
    opts.corrector.range = [1.2, 2.0];
    let curve = p.continue_codim2(&g, &opts).unwrap();
    assert_eq!(curve.stop, StopReason::ReachedEnd, "{:?}", curve.stop);
    assert!(curve.points.len() >= 4);
    let s = bilinear(0.2, 1.5);
    for pt in &curve.points {
        let w = pt.parameter;
        let (f, tg) = grazing_closed_form(&s, w);
        assert!(
            (pt.first_parameter - f).abs() < 1e-9 * (1.0 + f),
            "ω = {w}: f = {} vs {f}",
            pt.first_parameter
        );
        let t = 2.0 * PI / w;
        let dt = (pt.grazing_time.unwrap() - tg).rem_euclid(t);
        assert!(
            dt.min(t - dt) < 1e-5,
            "ω = {w}: t_g {:?} vs {tg}",
            pt.grazing_time
        );
        assert!(pt.stable().unwrap());
        assert!(pt.curvature.unwrap() < 0.0);
    }
}
