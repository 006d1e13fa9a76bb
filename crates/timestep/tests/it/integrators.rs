//! Integrator accuracy, order, events and interface checks.

use geardyn_timestep::*;
use math::DetMath;

const ALL: [Method; 5] = [
    Method::DormandPrince54,
    Method::Dop853,
    Method::Rk4 { h: 0.005 },
    Method::OdeSolversDopri5,
    Method::OdeSolversDop853,
];

fn lin() -> FirstOrder<LinearOscillator> {
    LinearOscillator {
        omega0: 1.3,
        zeta: 0.0,
        force: 0.0,
        omega: 1.0,
    }
    .first_order()
}

#[test]
fn linear_oscillator_matches_exact_solution() {
    let sys = lin();
    for m in ALL {
        let o = Options::default()
            .with_method(m)
            .with_tol(1e-11, 1e-13)
            .with_output(Output::Uniform { dt: 0.5 });
        let s = integrate(&sys, 0.0, &[1.0, 0.3], 50.0, &o).unwrap();
        assert_eq!(s.status, Status::Completed);
        assert_eq!(s.len(), 101, "{m:?}");
        let mut err: f64 = 0.0;
        for i in 0..s.len() {
            let (x, v) = sys.0.free_undamped(1.0, 0.3, s.t[i]);
            err = err
                .max((s.state(i)[0] - x).abs())
                .max((s.state(i)[1] - v).abs());
        }
        // native dense output is accurate to about the step tolerance; the ode_solvers
        // backends interpolate between their (large) steps with a cubic Hermite, O(h^4)
        let bound = match m {
            Method::OdeSolversDop853 => 1e-4,
            _ => 2e-8,
        };
        assert!(err < bound, "{m:?}: max error {err:e}");
    }
}

#[test]
fn energy_drift_of_undamped_oscillator_is_small() {
    let sys = lin();
    let w2 = 1.3f64 * 1.3;
    let e = |y: &[f64]| 0.5 * y[1] * y[1] + 0.5 * w2 * y[0] * y[0];
    let y0 = [1.0, 0.0];
    for m in [
        Method::DormandPrince54,
        Method::Dop853,
        Method::OdeSolversDop853,
    ] {
        let o = Options::default()
            .with_method(m)
            .with_tol(1e-10, 1e-12)
            .with_output(Output::Final);
        let s = integrate(&sys, 0.0, &y0, 1000.0, &o).unwrap();
        let drift = (e(&s.y_final) - e(&y0)).abs() / e(&y0);
        assert!(drift < 1e-6, "{m:?}: relative energy drift {drift:e}");
    }
}

/// Error at t = 10 with a fixed step `h` (adaptive methods pinned by h_init = h_max = h and
/// loose tolerances).
fn fixed_step_error(m: Method, h: f64) -> f64 {
    let sys = lin();
    let m = match m {
        Method::Rk4 { .. } => Method::Rk4 { h },
        other => other,
    };
    let o = Options::default()
        .with_method(m)
        .with_tol(1e3, 1e3)
        .with_h_init(h)
        .with_h_max(h)
        .with_output(Output::Final);
    let s = integrate(&sys, 0.0, &[1.0, 0.0], 10.0, &o).unwrap();
    let (x, v) = sys.0.free_undamped(1.0, 0.0, 10.0);
    (s.y_final[0] - x).abs().max((s.y_final[1] - v).abs())
}

#[test]
fn measured_order_of_accuracy() {
    for (m, h, p) in [
        (Method::Rk4 { h: 0.1 }, 0.1, 4.0),
        (Method::DormandPrince54, 0.2, 5.0),
        (Method::OdeSolversDopri5, 0.2, 5.0),
        (Method::OdeSolversDop853, 0.5, 8.0),
        (Method::Dop853, 0.5, 8.0),
    ] {
        let e1 = fixed_step_error(m, h);
        let e2 = fixed_step_error(m, h / 2.0);
        let order = (e1 / e2).dlog2();
        assert!(
            (order - p).abs() < 0.35,
            "{m:?}: measured order {order} (errors {e1:e}, {e2:e})"
        );
    }
}

#[test]
fn dead_zone_event_times_match_free_flight_solution() {
    let b = 0.5;
    let sys = FirstOrder(DeadZoneOscillator::free(b));
    let exact = DeadZoneOscillator::free_event_times(b, 1.0, 24);
    for m in ALL {
        let o = Options::default()
            .with_method(m)
            .with_tol(1e-11, 1e-13)
            .with_output(Output::Final);
        let s = integrate(&sys, 0.0, &[0.0, 1.0], exact[23] + 0.1, &o).unwrap();
        assert_eq!(s.events.len(), 24, "{m:?}");
        for (k, (ev, te)) in s.events.iter().zip(&exact).enumerate() {
            assert!(
                (ev.t - te).abs() < 1e-8,
                "{m:?}: event {k} at {} vs {te}",
                ev.t
            );
            // order: upper edge in, upper edge out, lower edge in, lower edge out
            let (idx, dir) = [
                (0, Direction::Rising),
                (0, Direction::Falling),
                (1, Direction::Falling),
                (1, Direction::Rising),
            ][k % 4];
            assert_eq!((ev.index, ev.direction), (idx, dir), "{m:?} event {k}");
        }
    }
}

#[test]
fn impact_oscillator_times_and_restitution() {
    let ball = BouncingBall {
        gravity: 9.81,
        restitution: 0.7,
    };
    let exact = ball.impact_times(1.0, 8);
    let sys = FirstOrder(ball);
    for m in [
        Method::DormandPrince54,
        Method::Dop853,
        Method::OdeSolversDop853,
    ] {
        let o = Options::default().with_method(m).with_output(Output::Final);
        let s = integrate(&sys, 0.0, &[1.0, 0.0], exact[7] + 1e-3, &o).unwrap();
        assert_eq!(s.events.len(), 8, "{m:?}");
        for (ev, te) in s.events.iter().zip(&exact) {
            assert!(
                (ev.t - te).abs() < 1e-9 * te.max(1.0),
                "{m:?}: {} vs {te}",
                ev.t
            );
            assert_eq!(ev.direction, Direction::Falling);
        }
        // after the 8th impact the ball rises with 0.7^8 of the first impact speed
        let v_expected = 0.7f64.powi(8) * (2.0f64 * 9.81).sqrt() - 9.81 * 1e-3;
        assert!((s.y_final[1] - v_expected).abs() < 1e-8);
    }
}

/// Exact state of the free dead-zone oscillator (b, unit stiffness, x(0) = 0, v(0) = 1).
fn dead_zone_exact(b: f64, t: f64) -> (f64, f64) {
    use std::f64::consts::PI;
    let period = 4.0 * b + 2.0 * PI;
    let mut s = t.rem_euclid(period);
    // phases: free (0→b), upper contact, free (b→−b), lower contact, free (−b→0)
    if s < b {
        return (s, 1.0);
    }
    s -= b;
    if s < PI {
        return (b + s.dsin(), s.dcos());
    }
    s -= PI;
    if s < 2.0 * b {
        return (b - s, -1.0);
    }
    s -= 2.0 * b;
    if s < PI {
        return (-b - s.dsin(), -s.dcos());
    }
    s -= PI;
    (-b + s, 1.0)
}

/// Event location restores the method's accuracy across the dead-zone kinks: with events the
/// error follows the tolerance (two decades of `rtol` take it down by more than 30×; measured:
/// 95×), and at every tolerance it is below the error of the plain run, which steps across the
/// kinks (by more than 3×; measured: 4.5×, 24×, 10× at rtol 1e-8, 1e-9, 1e-10 — the plain
/// run's error depends on where its steps happen to fall on the kinks, so a single tolerance
/// and a tight factor would test the step sequence rather than the event location).
#[test]
fn event_location_improves_accuracy_on_piecewise_system() {
    let b = 0.5;
    let sys = FirstOrder(DeadZoneOscillator::free(b));
    let t_end = 200.0;
    let (xe, ve) = dead_zone_exact(b, t_end);
    let run = |rtol: f64, events: bool| {
        let o = Options::default()
            .with_tol(rtol, rtol * 1e-2)
            .with_events(events)
            .with_output(Output::Final);
        let s = integrate(&sys, 0.0, &[0.0, 1.0], t_end, &o).unwrap();
        (
            (s.y_final[0] - xe).abs().max((s.y_final[1] - ve).abs()),
            s.stats,
        )
    };
    let mut with_events = Vec::new();
    for rtol in [1e-8, 1e-9, 1e-10] {
        let (err_ev, st_ev) = run(rtol, true);
        let (err_plain, st_plain) = run(rtol, false);
        println!(
            "rtol {rtol:e}: with events err {err_ev:e} {st_ev:?}\nplain: err {err_plain:e} {st_plain:?}"
        );
        assert!(st_ev.n_events > 50 && st_plain.n_events == 0);
        assert!(
            err_ev * 3.0 < err_plain,
            "rtol {rtol:e}: events {err_ev:e} vs plain {err_plain:e}"
        );
        with_events.push(err_ev);
    }
    assert!(
        with_events[2] * 30.0 < with_events[0],
        "with events the error does not follow the tolerance: {with_events:?}"
    );
}

#[test]
fn output_modes_and_input_errors() {
    let sys = lin();
    let o = Options::default().with_output(Output::Times(vec![-1.0, 0.0, 0.25, 3.0, 7.0]));
    let s = integrate(&sys, 0.0, &[1.0, 0.0], 5.0, &o).unwrap();
    assert_eq!(s.t, vec![0.0, 0.25, 3.0]);
    let s = integrate(
        &sys,
        0.0,
        &[1.0, 0.0],
        5.0,
        &Options::default().with_output(Output::Final),
    )
    .unwrap();
    assert!(s.is_empty() && (s.t_final - 5.0).abs() < 1e-15);
    let s = integrate(&sys, 0.0, &[1.0, 0.0], 5.0, &Options::default()).unwrap();
    assert_eq!(s.component(0).len(), s.len());
    assert!(s.component(5).is_empty());
    assert!(integrate(&sys, 0.0, &[1.0], 1.0, &Options::default()).is_err());
    assert!(integrate(&sys, 0.0, &[f64::NAN, 0.0], 1.0, &Options::default()).is_err());
    assert!(integrate(&sys, 1.0, &[1.0, 0.0], 0.0, &Options::default()).is_err());
    assert!(
        integrate(
            &sys,
            0.0,
            &[1.0, 0.0],
            1.0,
            &Options::default().with_tol(-1.0, 1e-9)
        )
        .is_err()
    );
    assert!(
        integrate(
            &sys,
            0.0,
            &[1.0, 0.0],
            1.0,
            &Options::default().with_method(Method::Rk4 { h: f64::NAN })
        )
        .is_err()
    );
    let e = integrate(&sys, 0.0, &[1.0, 0.0], f64::INFINITY, &Options::default()).unwrap_err();
    assert!(e.to_string().contains("t_end"));
    // the step limit is a status, not an error
    let s = integrate(
        &sys,
        0.0,
        &[1.0, 0.0],
        100.0,
        &Options::default().with_max_steps(10),
    )
    .unwrap();
    assert!(matches!(s.status, Status::MaxSteps { .. }));
    // a right-hand side that blows up is reported
    let bad = FnSystem::new(1, |_t, y: &[f64], d: &mut [f64]| {
        d[0] = if y[0] > 2.0 { f64::NAN } else { 1.0 }
    });
    let s = integrate(&bad, 0.0, &[0.0], 10.0, &Options::default()).unwrap();
    assert!(!s.status.is_success());
}

#[test]
fn types_are_send_sync() {
    fn check<T: Send + Sync + Clone>() {}
    check::<Options>();
    check::<Solution>();
    check::<Duffing>();
    check::<FirstOrder<DeadZoneOscillator>>();
    check::<SteadyState>();
    check::<Spectrum>();
}

#[test]
fn every_method_stops_at_the_threads_deadline() {
    use std::time::{Duration, Instant};
    let sys = lin();
    for m in ALL {
        let o = Options::default()
            .with_method(m)
            .with_max_steps(u64::MAX / 2);
        // Already passed: stopped before the first step.
        let s = system::deadline::scope(Some(Instant::now()), || {
            integrate(&sys, 0.0, &[1.0, 0.0], 1e12, &o).unwrap()
        });
        assert!(
            matches!(s.status, Status::TimeLimit { .. }),
            "{m:?}: {:?}",
            s.status
        );
        assert!(!s.status.is_success());
        assert!(s.stats.n_accepted <= 1, "{m:?}: {}", s.stats.n_accepted);
        // Passes mid-run: stopped between steps, the state is the last accepted one.
        let s = system::deadline::scope(Some(Instant::now() + Duration::from_millis(20)), || {
            integrate(&sys, 0.0, &[1.0, 0.0], 1e12, &o).unwrap()
        });
        match s.status {
            Status::TimeLimit { t } => {
                assert!(t > 0.0 && t < 1e12, "{m:?}: {t}");
                assert_eq!(s.t_final.to_bits(), t.to_bits());
                // the undamped oscillator keeps its energy to the tolerance: a real state
                let (x, v) = (s.y_final[0], s.y_final[1]);
                let e = 1.3f64.powi(2) * x * x + v * v;
                assert!((e / 1.3f64.powi(2) - 1.0).abs() < 0.5, "{m:?}: {e}");
            }
            other => panic!("{m:?}: {other:?}"),
        }
        // No deadline: the same call is unaffected (short end time).
        let s = integrate(&sys, 0.0, &[1.0, 0.0], 1.0, &o).unwrap();
        assert_eq!(s.status, Status::Completed);
    }
}
