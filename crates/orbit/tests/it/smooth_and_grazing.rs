//! Duffing against harmonic balance (orbit and Floquet multipliers), folds of the Duffing
//! resonance curve, and the grazing that starts rattle located by continuation, by bisection on
//! time integration and in closed form.

use crate::common::{Duffing, Rattle};
use math::DetMath;
use orbit::{
    ContinuationOptions, Extremum, OrbitProblem, Parameter, ShootingCorrection, ShootingOptions,
    SpecialKind,
};
use std::f64::consts::PI;

/// A smooth Duffing orbit: the shooting orbit agrees with the harmonic balance solution
/// (`hbm`, 15 harmonics) and the multipliers with the engine's Floquet multipliers (RK4
/// monodromy along the HBM orbit).
#[test]
fn duffing_multipliers_match_harmonic_balance() {
    for omega in [0.8, 1.2, 1.6] {
        let s = Duffing {
            zeta: 0.05,
            gamma: 0.3,
            force: 0.2,
            omega,
        };
        let basis = hbm::Basis::full(15).unwrap();
        let mut hp = hbm::HbmProblem::new(s, basis, omega).unwrap();
        let z0 = hp.zero_guess();
        let sol = hp.solve(&z0, &hbm::SolverOptions::default()).unwrap();
        assert!(sol.converged);
        let st = hp.stability(&sol, Some(4000)).unwrap();
        let (q, v) = sol.state_at(0.0);
        let p = OrbitProblem::new(s, 2.0 * PI / omega).unwrap();
        let o = p.shoot(&[q[0], v[0]], &ShootingOptions::default()).unwrap();
        assert!(
            (o.x0[0] - q[0]).abs() < 1e-6 && (o.x0[1] - v[0]).abs() < 1e-6,
            "{:?} vs {q:?} {v:?}",
            o.x0
        );
        let mut a = o.floquet.multipliers.clone();
        let mut b = st.multipliers.clone();
        let key = |m: &[f64; 2]| (m[0], m[1]);
        a.sort_by(|x, y| key(x).partial_cmp(&key(y)).unwrap());
        b.sort_by(|x, y| key(x).partial_cmp(&key(y)).unwrap());
        for (x, y) in a.iter().zip(&b) {
            assert!(
                (x[0] - y[0]).abs() < 1e-6 && (x[1] - y[1]).abs() < 1e-6,
                "ω = {omega}: {a:?} vs {b:?}"
            );
        }
        assert_eq!(o.floquet.stable, st.stable);
    }
}

/// The hardening resonance curve folds twice; at each located fold a multiplier is `+1`, and
/// the orbits between the folds are unstable.
#[test]
#[ignore = "heavy: run optimised by `cargo xtask heavy-tests` (.ci/run)"]
fn duffing_folds_are_located_with_a_unit_multiplier() {
    let s = Duffing {
        zeta: 0.05,
        gamma: 0.3,
        force: 0.2,
        omega: 0.8,
    };
    let mut p = OrbitProblem::new(s, 2.0 * PI / 0.8).unwrap();
    let opts = ContinuationOptions {
        initial_step: 0.02,
        max_step: 0.1,
        corrector: ShootingCorrection {
            parameter: Parameter::BaseFrequency,
            range: [0.7, 2.0],
            ..ShootingCorrection::default()
        },
        ..Default::default()
    };
    let br = p.continuation(&[0.3, 0.0], 0.8, &opts).unwrap();
    let folds: Vec<_> = br
        .special
        .iter()
        .filter(|s| s.kind == SpecialKind::Fold)
        .collect();
    assert_eq!(
        folds.len(),
        2,
        "{:?}",
        br.special
            .iter()
            .map(|s| (s.kind, s.point.parameter))
            .collect::<Vec<_>>()
    );
    for f in &folds {
        assert!(f.located);
        let near = f.floquet_distance_to_one();
        assert!(
            near < 1e-4,
            "fold at ω = {}: |μ − 1| = {near}",
            f.point.parameter
        );
    }
    let (w1, w2) = (folds[0].point.parameter, folds[1].point.parameter);
    // the located folds do not depend on the arclength scaling
    let mut p2 = OrbitProblem::new(s, 2.0 * PI / 0.8).unwrap();
    let scaled = ContinuationOptions {
        initial_step: 0.04,
        max_step: 0.2,
        corrector: ShootingCorrection {
            state_scale: 0.3,
            parameter_scale: 0.5,
            ..ShootingCorrection::default()
        },
        ..opts.clone()
    };
    let br2 = p2.continuation(&[0.3, 0.0], 0.8, &scaled).unwrap();
    let f2: Vec<f64> = br2
        .special
        .iter()
        .filter(|s| s.kind == SpecialKind::Fold)
        .map(|s| s.point.parameter)
        .collect();
    assert_eq!(f2.len(), 2);
    assert!(
        (f2[0] - w1).abs() < 1e-6 && (f2[1] - w2).abs() < 1e-6,
        "{f2:?} vs {w1}, {w2}"
    );
    assert!(
        w1 > w2,
        "the upper fold comes first along the branch: {w1}, {w2}"
    );
    // between the folds (the middle branch) unstable, outside stable
    let i1 = folds[0].after;
    let i2 = folds[1].after;
    for (i, pt) in br.points.iter().enumerate() {
        let middle = i > i1 && i <= i2;
        assert_eq!(
            pt.floquet.stable, !middle,
            "point {i} at ω = {}",
            pt.parameter
        );
    }
    // locating only other kinds (`locate_only`) leaves the folds detected, not located, and
    // the branch the same bit for bit: its points, the tangent's folds and its stop
    let mut p3 = OrbitProblem::new(s, 2.0 * PI / 0.8).unwrap();
    let unlocated = ContinuationOptions {
        corrector: ShootingCorrection {
            locate_only: Some(vec![SpecialKind::PeriodDoubling]),
            ..opts.corrector.clone()
        },
        ..opts.clone()
    };
    let br3 = p3.continuation(&[0.3, 0.0], 0.8, &unlocated).unwrap();
    assert_eq!(br3.points, br.points);
    assert_eq!(br3.folds, br.folds);
    assert_eq!(br3.stop, br.stop);
    let f3: Vec<_> = br3
        .special
        .iter()
        .filter(|s| s.kind == SpecialKind::Fold)
        .collect();
    assert_eq!(f3.len(), 2);
    for (f, located) in f3.iter().zip(&folds) {
        assert!(!f.located);
        assert_eq!(f.after, located.after);
        // the detected point is the end of the step that holds the fold
        assert_eq!(f.point, br3.points[f.after + 1]);
    }
}

trait Dist {
    fn floquet_distance_to_one(&self) -> f64;
}
impl Dist for orbit::SpecialPoint<orbit::ShootingPoint> {
    fn floquet_distance_to_one(&self) -> f64 {
        self.point
            .floquet
            .multipliers
            .iter()
            .map(|m| (m[0] - 1.0).dhypot(m[1]))
            .fold(f64::INFINITY, f64::min)
    }
}

fn rattle(omega: f64) -> Rattle {
    Rattle {
        zeta: 0.05,
        b: 0.2,
        f0: 0.5,
        f: 0.2,
        omega,
    }
}

/// `min_t q(t) − b` of the steady state at `ω` by plain time integration from the linear
/// in-contact response: 300 periods of transient, then one period sampled 4000 times.
fn min_gap_by_time_integration(omega: f64) -> f64 {
    let s = rattle(omega);
    let t = 2.0 * PI / omega;
    let p = OrbitProblem::new(s, t).unwrap();
    // start on the in-contact (linear) periodic response: below the grazing it coexists with a
    // rattling attractor that a start from rest may reach instead
    let d = (1.0 - omega * omega).powi(2) + (2.0 * s.zeta * omega).powi(2);
    let (a, b) = (
        s.f * (1.0 - omega * omega) / d,
        s.f * 2.0 * s.zeta * omega / d,
    );
    let x0 = [s.b + s.f0 + a, omega * b];
    let x = p.flow(0.0, &x0, 300.0 * t, false).unwrap().state;
    let n = 4000;
    let mut x = x;
    let mut m = f64::INFINITY;
    for k in 0..n {
        let tk = 300.0 * t + t * k as f64 / n as f64;
        x = p.flow(tk, &x, t / n as f64, false).unwrap().state;
        m = m.min(x[0] - s.b);
    }
    m
}

/// Under a mean load `F₀` the pair stays in contact (`q > b`) until the forcing amplitude
/// `P = F/√((1−ω²)² + (2ζω)²)` of the linear in-contact response reaches `F₀`: the minimum of
/// the gap function `q − b` grazes zero, contact is lost and rattle starts. Continuation in `ω`
/// locates that grazing; it agrees with bisection in `ω` on the time-integrated minimum gap and
/// with the closed form.
#[test]
#[ignore = "heavy: run optimised by `cargo xtask heavy-tests` (.ci/run)"]
fn grazing_by_continuation_matches_time_integration_and_closed_form() {
    let s = rattle(0.5);
    let mut p = OrbitProblem::new(s, 2.0 * PI / 0.5).unwrap();
    let opts = ContinuationOptions {
        initial_step: 0.02,
        max_step: 0.05,
        corrector: ShootingCorrection {
            parameter: Parameter::BaseFrequency,
            range: [0.4, 0.9],
            locate_tol: 1e-10,
            ..ShootingCorrection::default()
        },
        ..Default::default()
    };
    let br = p.continuation(&[s.b + s.f0, 0.0], 0.5, &opts).unwrap();
    let g: Vec<_> = br
        .special
        .iter()
        .filter(|x| {
            matches!(
                x.kind,
                SpecialKind::Grazing {
                    event: 0,
                    extremum: Extremum::Min
                }
            )
        })
        .collect();
    assert_eq!(
        g.len(),
        1,
        "{:?}",
        br.special
            .iter()
            .map(|s| (s.kind, s.point.parameter))
            .collect::<Vec<_>>()
    );
    assert!(g[0].located);
    let w_cont = g[0].point.parameter;
    // closed form: (1 − ω²)² + (2ζω)² = (F/F₀)²
    let r2 = (s.f / s.f0).powi(2);
    let c = 4.0 * s.zeta * s.zeta;
    // u² − (2 − c) u + 1 − r² = 0, smaller root
    let u = 0.5 * ((2.0 - c) - ((2.0 - c).powi(2) - 4.0 * (1.0 - r2)).sqrt());
    let w_closed = u.sqrt();
    assert!((w_cont - w_closed).abs() < 1e-7, "{w_cont} vs {w_closed}");
    // the reported bracket is tight and holds the closed form
    let [lo, hi] = g[0].bracket;
    assert!(g[0].precision() < 1e-8, "bracket {lo} … {hi}");
    assert!(
        lo - 1e-8 <= w_closed && w_closed <= hi + 1e-8,
        "{lo} … {hi} vs {w_closed}"
    );
    // bisection on time integration
    let (mut a, mut b) = (0.7, 0.85);
    let (fa, fb) = (
        min_gap_by_time_integration(a),
        min_gap_by_time_integration(b),
    );
    assert!(fa > 0.0 && fb < 0.0, "{fa} {fb}");
    for _ in 0..18 {
        let m = 0.5 * (a + b);
        if min_gap_by_time_integration(m) > 0.0 {
            a = m;
        } else {
            b = m;
        }
    }
    let w_ti = 0.5 * (a + b);
    assert!((w_cont - w_ti).abs() < 1e-4, "{w_cont} vs {w_ti}");
    // along the branch: no events before the grazing, contact loss and regain after it (the
    // rattling branch then bends back to lower ω: a fold, the hysteresis seen from rest)
    let after = g[0].after;
    for (i, pt) in br.points.iter().enumerate() {
        if i <= after {
            assert_eq!(pt.events, 0, "point {i} at ω = {}", pt.parameter);
        } else if i == after + 1 {
            assert!(pt.events >= 2, "ω = {}: {} events", pt.parameter, pt.events);
        }
    }
    let folds: Vec<f64> = br
        .special
        .iter()
        .filter(|x| x.kind == SpecialKind::Fold)
        .map(|x| x.point.parameter)
        .collect();
    println!("grazing {w_cont} (closed form {w_closed}, time integration {w_ti}); folds {folds:?}");
}
