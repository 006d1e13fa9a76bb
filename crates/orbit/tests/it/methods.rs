//! The two Runge–Kutta pairs of the flows ([`orbit::FlowMethod`]) and the crossing retry
//! ([`orbit::FlowOptions::crossing_retry`]): exact orbits and monodromies, the convergence
//! order of each pair, event times of one pair against the other, and the retry keeping the
//! flow while saving rejections.

use crate::common::{
    bilinear, bilinear_monodromy, exp_oscillator, linear_oscillator, two_sided_rattle,
};
use math::DetMath;
use orbit::{FlowMethod, FlowOptions, OrbitProblem, ShootingOptions};
use std::f64::consts::PI;

const METHODS: [FlowMethod; 2] = [FlowMethod::DormandPrince54, FlowMethod::Dop853];

fn with(method: FlowMethod) -> FlowOptions {
    FlowOptions {
        method,
        ..FlowOptions::default()
    }
}

/// Both pairs give the closed-form periodic orbit and monodromy `exp(A T)` (tolerance 1e-8:
/// the shooting tolerance 1e-9 and the flows' rtol 1e-10 over one period).
#[test]
fn both_pairs_give_the_exact_linear_orbit_and_monodromy() {
    let (s, x) = linear_oscillator();
    let t = 2.0 * PI / s.omega;
    for method in METHODS {
        let p = OrbitProblem::new(s, t)
            .unwrap()
            .with_flow_options(with(method))
            .unwrap();
        let o = p.shoot(&[0.0, 0.0], &ShootingOptions::default()).unwrap();
        assert!((o.x0[0] - x[0]).abs() < 1e-8, "{method:?}: {:?}", o.x0);
        assert!((o.x0[1] - x[1]).abs() < 1e-8, "{method:?}: {:?}", o.x0);
        let exact = exp_oscillator(1.0, 2.0 * s.zeta, t);
        assert!(
            (&o.monodromy - &exact).amax() < 1e-8,
            "{method:?}: {} vs {exact}",
            o.monodromy
        );
    }
}

/// The global error of one period on the exact orbit with the step held at `T/n` (a loose
/// tolerance never rejects, the step cap `T/n` binds): halving the step divides it by `2^p`,
/// `p = 5` for DP5 (local extrapolation) and 8 for DOP853. Observed orders within
/// `[p − 0.5, p + 1]` (the first steps grow up to the cap, and the error constant is not yet
/// asymptotic at the coarsest step).
#[test]
fn each_pair_converges_at_its_order() {
    let (s, x) = linear_oscillator();
    let t = 2.0 * PI / s.omega;
    for (method, order, n) in [
        (FlowMethod::DormandPrince54, 5.0, 24.0),
        (FlowMethod::Dop853, 8.0, 8.0),
    ] {
        let err = |n: f64| {
            let p = OrbitProblem::new(s, t)
                .unwrap()
                .with_flow_options(FlowOptions {
                    method,
                    rtol: 0.5,
                    atol: 0.5,
                    max_step_fraction: 1.0 / n,
                    ..FlowOptions::default()
                })
                .unwrap();
            let f = p.flow(0.0, &x, t, false).unwrap();
            assert_eq!(f.rejected, 0, "{method:?}");
            (f.state[0] - x[0]).abs().max((f.state[1] - x[1]).abs())
        };
        let (e1, e2) = (err(n), err(2.0 * n));
        let observed = (e1 / e2).dlog2();
        assert!(
            observed > order - 0.5 && observed < order + 1.0,
            "{method:?}: errors {e1:e}, {e2:e}, order {observed}"
        );
    }
}

/// On the bilinear oscillator (one excursion past the kink per period), DOP853's monodromy is
/// the product of closed-form exponentials between its event times, and its event times equal
/// DP5's to 1e-9 (both locate to 1e-13 on flows accurate to about rtol 1e-10).
#[test]
fn dop853_events_and_monodromy_match_dp5_and_the_closed_form() {
    let s = bilinear();
    let t = 2.0 * PI / s.omega;
    let shoot = |method| {
        OrbitProblem::new(s, t)
            .unwrap()
            .with_flow_options(with(method))
            .unwrap()
            .shoot(&[-0.5, 0.9], &ShootingOptions::default())
            .unwrap()
    };
    let (o5, o8) = (
        shoot(FlowMethod::DormandPrince54),
        shoot(FlowMethod::Dop853),
    );
    assert_eq!(o8.events.len(), 2);
    assert_eq!(o5.events.len(), o8.events.len());
    for (a, b) in o5.events.iter().zip(&o8.events) {
        assert_eq!(a.index, b.index);
        assert!((a.time - b.time).abs() < 1e-9, "{} vs {}", a.time, b.time);
    }
    let phi = bilinear_monodromy(&s, &o8.x0, &o8.events, t);
    assert!(
        (&o8.monodromy - &phi).amax() < 1e-7,
        "{} vs {phi}",
        o8.monodromy
    );
}

/// The retry at an estimated crossing changes the step sequence, not the flow: on a two-sided
/// rattle (about four contact events a period, over ten periods from rest) with and without it, for both pairs,
/// the same events at the same times (1e-8) and the same end state (1e-8); with it, fewer
/// rejected steps.
#[test]
fn crossing_retry_keeps_the_flow_and_saves_rejections() {
    let s = two_sided_rattle();
    let t = 2.0 * PI / s.omega;
    for method in METHODS {
        let run = |retry: bool| {
            OrbitProblem::new(s, t)
                .unwrap()
                .with_flow_options(FlowOptions {
                    method,
                    crossing_retry: retry,
                    ..FlowOptions::default()
                })
                .unwrap()
                .flow(0.0, &[0.0, 1.0], 10.0 * t, false)
                .unwrap()
        };
        let (on, off) = (run(true), run(false));
        assert!(
            on.events.len() >= 30,
            "{method:?}: {} events",
            on.events.len()
        );
        assert_eq!(on.events.len(), off.events.len(), "{method:?}");
        for (a, b) in on.events.iter().zip(&off.events) {
            assert_eq!(a.index, b.index);
            assert!(
                (a.time - b.time).abs() < 1e-8,
                "{method:?}: {} vs {}",
                a.time,
                b.time
            );
        }
        for i in 0..2 {
            assert!((on.state[i] - off.state[i]).abs() < 1e-8, "{method:?}");
        }
        assert!(
            on.rejected < off.rejected,
            "{method:?}: {} rejections with the retry, {} without",
            on.rejected,
            off.rejected
        );
    }
}
