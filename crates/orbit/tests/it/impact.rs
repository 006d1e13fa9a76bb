//! The harmonically forced impact oscillator `q'' + 2ζ q' + q = cos ωt`, `q ≤ σ`, Newton's
//! restitution `q'⁺ = −r q'⁻` (Shaw & Holmes 1983; Bishop 1994; Budd & Dux 1994; Nordmark 1991).
//!
//! Reference: the period-1 orbit with one impact per forcing period in closed form. Between
//! impacts the motion is linear, `z(t) = e^{A(t−t_i)} (z⁺ − p(t_i)) + p(t)` with `p` the
//! periodic particular solution; periodicity `z(t_i + T) = (σ, V)` from `z⁺ = (σ, −rV)` gives
//! `V` linearly in the impact phase `t_i` and one scalar equation in `t_i`, solved here by
//! bisection. Its monodromy is `e^{A(T−t_i)} S e^{A t_i}` with the impact saltation matrix
//! `S = [[−r, 0], [(a⁺ + r a⁻)/V, −r]]`, `a^∓` the accelerations before and after impact
//! (Nordmark 1991; Leine & Nijmeijer 2004, Sec. 7.2); `det Φ = r² e^{−2ζT}`.

use crate::common::{ImpactOscillator, exp_oscillator};
use math::DetMath;
use nalgebra::DMatrix;
use orbit::{
    ContinuationOptions, OrbitProblem, Parameter, Restitution, ShootingCorrection, ShootingOptions,
    SpecialKind,
};
use std::f64::consts::PI;

pub(crate) struct Closed {
    ti: f64,
    v: f64,
    pub(crate) x_section: [f64; 2],
    pub(crate) monodromy: DMatrix<f64>,
}

fn particular(s: &ImpactOscillator, t: f64) -> [f64; 2] {
    let w = s.omega;
    let d = (1.0 - w * w).powi(2) + (2.0 * s.zeta * w).powi(2);
    let (a, b) = ((1.0 - w * w) / d, 2.0 * s.zeta * w / d);
    let (sn, cs) = (w * t).dsin_cos();
    [a * cs + b * sn, w * (-a * sn + b * cs)]
}

fn state(s: &ImpactOscillator, ti: f64, zp: [f64; 2], t: f64) -> [f64; 2] {
    let e = exp_oscillator(1.0, 2.0 * s.zeta, t - ti);
    let p = particular(s, ti);
    let d = [zp[0] - p[0], zp[1] - p[1]];
    let q = particular(s, t);
    [
        e[(0, 0)] * d[0] + e[(0, 1)] * d[1] + q[0],
        e[(1, 0)] * d[0] + e[(1, 1)] * d[1] + q[1],
    ]
}

/// All admissible period-1 single-impact orbits at `s` (closed form).
pub(crate) fn closed_form(s: &ImpactOscillator, r: f64) -> Vec<Closed> {
    let t = 2.0 * PI / s.omega;
    let e = exp_oscillator(1.0, 2.0 * s.zeta, t);
    let sig = s.sigma;
    let vel = |ti: f64| {
        let u = particular(s, ti);
        (e[(0, 0)] * (sig - u[0]) - e[(0, 1)] * u[1] + u[0] - sig) / (r * e[(0, 1)])
    };
    let res = |ti: f64| {
        let u = particular(s, ti);
        let v = vel(ti);
        e[(1, 0)] * (sig - u[0]) - e[(1, 1)] * (r * v + u[1]) + u[1] - v
    };
    let n = 4000;
    let mut out = vec![];
    for k in 0..n {
        let (mut a, mut b) = (t * k as f64 / n as f64, t * (k + 1) as f64 / n as f64);
        let (mut fa, fb) = (res(a), res(b));
        if fa * fb > 0.0 {
            continue;
        }
        for _ in 0..200 {
            let m = 0.5 * (a + b);
            let fm = res(m);
            if fm * fa > 0.0 {
                a = m;
                fa = fm;
            } else {
                b = m;
            }
        }
        let ti = 0.5 * (a + b);
        let v = vel(ti);
        if v <= 0.0 {
            continue;
        }
        let zp = [sig, -r * v];
        // free flight must stay on the admissible side
        let ok = (1..400).all(|j| state(s, ti, zp, ti + t * j as f64 / 400.0)[0] <= sig + 1e-12);
        if !ok {
            continue;
        }
        let acc = |vel: f64| (s.omega * ti).dcos() - 2.0 * s.zeta * vel - sig;
        let (am, ap) = (acc(v), acc(-r * v));
        let salt = DMatrix::from_row_slice(2, 2, &[-r, 0.0, (ap + r * am) / v, -r]);
        let mono = exp_oscillator(1.0, 2.0 * s.zeta, t - ti)
            * salt
            * exp_oscillator(1.0, 2.0 * s.zeta, ti);
        out.push(Closed {
            ti,
            v,
            x_section: state(s, ti, zp, t),
            monodromy: mono,
        });
    }
    out
}

pub(crate) fn problem(omega: f64, r: f64) -> OrbitProblem<ImpactOscillator> {
    let s = ImpactOscillator {
        zeta: 0.05,
        sigma: 0.0,
        omega,
    };
    OrbitProblem::new(s, 2.0 * PI / omega)
        .unwrap()
        .with_impacts(Restitution::new(0, r, vec![0]).unwrap())
}

/// Shooting with the impact saltation matrix reproduces the closed-form orbit, its impact and
/// its monodromy, and `det Φ = r² e^{−2ζT}`.
#[test]
fn period_one_impacting_orbit_matches_closed_form() {
    let r = 0.8;
    for omega in [2.3, 2.8] {
        let p = problem(omega, r);
        let c = closed_form(p.system(), r);
        assert_eq!(c.len(), 1, "one admissible period-1 orbit at ω = {omega}");
        let c = &c[0];
        let guess = [c.x_section[0] + 1e-3, c.x_section[1] - 2e-3];
        let o = p.shoot(&guess, &ShootingOptions::default()).unwrap();
        assert!(
            (o.x0[0] - c.x_section[0]).abs() < 1e-8,
            "{:?} vs {:?}",
            o.x0,
            c.x_section
        );
        assert!((o.x0[1] - c.x_section[1]).abs() < 1e-8);
        assert_eq!(o.events.len(), 1);
        assert!(o.events[0].impact);
        assert!((o.events[0].time - c.ti).abs() < 1e-8);
        assert!((o.events[0].state[1] - c.v).abs() < 1e-8);
        assert!(
            (&o.monodromy - &c.monodromy).amax() < 1e-7 * c.monodromy.amax().max(1.0),
            "{} vs {}",
            o.monodromy,
            c.monodromy
        );
        let t = 2.0 * PI / omega;
        let det = r * r * (-2.0 * 0.05 * t).dexp();
        assert!((o.monodromy.determinant() - det).abs() < 1e-8);
        assert_eq!(o.floquet.stable, omega < 2.65);
    }
}

/// The flip of the period-1 impacting orbit (one multiplier through −1, r = 0.8, ζ = 0.05,
/// σ = 0; near ω ≈ 2.65, cf. the period-doubling cascade of Shaw & Holmes 1983 and Budd & Dux
/// 1994): continuation in ω locates it where the closed-form monodromy has
/// `det(Φ + I) = 0`; branch switching gives a genuine period-2 orbit with two impacts.
#[test]
#[ignore = "heavy: run optimised by `cargo xtask heavy-tests` (.ci/run)"]
fn period_doubling_located_by_continuation_matches_closed_form() {
    let r = 0.8;
    let pd_closed = {
        let f = |w: f64| {
            let s = ImpactOscillator {
                zeta: 0.05,
                sigma: 0.0,
                omega: w,
            };
            let c = closed_form(&s, r);
            (&c[0].monodromy + DMatrix::identity(2, 2)).determinant()
        };
        let (mut a, mut b) = (2.6, 2.7);
        assert!(f(a) * f(b) < 0.0);
        for _ in 0..60 {
            let m = 0.5 * (a + b);
            if f(m) * f(a) > 0.0 {
                a = m;
            } else {
                b = m;
            }
        }
        0.5 * (a + b)
    };
    let w0 = 2.5;
    let mut p = problem(w0, r);
    let c = closed_form(p.system(), r);
    let opts = ContinuationOptions {
        initial_step: 0.02,
        max_step: 0.05,
        corrector: ShootingCorrection {
            parameter: Parameter::BaseFrequency,
            range: [2.0, 2.8],
            ..ShootingCorrection::default()
        },
        ..Default::default()
    };
    let br = p.continuation(&c[0].x_section, w0, &opts).unwrap();
    // sampling the step before locating finds the same (single) flip
    let sampled = problem(w0, r)
        .continuation(
            &c[0].x_section,
            w0,
            &ContinuationOptions {
                corrector: ShootingCorrection {
                    locate_samples: 4,
                    ..ShootingCorrection::default()
                },
                ..opts.clone()
            },
        )
        .unwrap();
    let pd_sampled: Vec<f64> = sampled
        .special
        .iter()
        .filter(|s| s.kind == SpecialKind::PeriodDoubling && s.located)
        .map(|s| s.point.parameter)
        .collect();
    assert_eq!(pd_sampled.len(), 1);
    assert!(
        (pd_sampled[0] - pd_closed).abs() < 1e-6,
        "{pd_sampled:?} vs {pd_closed}"
    );
    let pd: Vec<_> = br
        .special
        .iter()
        .filter(|s| s.kind == SpecialKind::PeriodDoubling)
        .collect();
    assert_eq!(
        pd.len(),
        1,
        "{:?}",
        br.special
            .iter()
            .map(|s| (s.kind, s.point.parameter))
            .collect::<Vec<_>>()
    );
    assert!(pd[0].located);
    let w_pd = pd[0].point.parameter;
    assert!((w_pd - pd_closed).abs() < 1e-6, "{w_pd} vs {pd_closed}");
    // the reported bracket is tight and holds the closed-form flip
    let [lo, hi] = pd[0].bracket;
    assert!(pd[0].precision() < 1e-6, "bracket {lo} … {hi}");
    assert!(
        lo - 1e-9 <= pd_closed && pd_closed <= hi + 1e-9,
        "{lo} … {hi} vs {pd_closed}"
    );
    // stable before, unstable after
    for pt in &br.points {
        assert_eq!(
            pt.floquet.stable,
            pt.parameter < w_pd,
            "ω = {}",
            pt.parameter
        );
    }
    // branch switching: a period-2 orbit with two impacts per 2T
    let (w2, o2) = p
        .switch_at_period_doubling(
            &pd[0].point,
            &Parameter::BaseFrequency,
            1,
            1e-2,
            5e-3,
            &ShootingOptions::default(),
        )
        .unwrap();
    assert!(
        w2 > w_pd,
        "supercritical flip: the period-2 orbit exists past the flip"
    );
    assert_eq!(o2.periods, 2);
    assert_eq!(o2.events.len(), 2);
    assert!(o2.floquet.stable);
}
