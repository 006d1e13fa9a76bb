//! The own DOP853 ([`Method::Dop853`]): order, closed-form cases, dense output, events against
//! Dormand–Prince 5(4), work counters, thread-count independence and input errors.

use geardyn_timestep::*;
use math::DetMath;

fn oscillator() -> FirstOrder<LinearOscillator> {
    LinearOscillator {
        omega0: 1.3,
        zeta: 0.0,
        force: 0.0,
        omega: 1.0,
    }
    .first_order()
}

/// Options that pin the step to `h` (accepted whatever the error: loose tolerances, and
/// `h_init = h_max = h`): the fixed-step test hook of the adaptive methods.
fn pinned(h: f64) -> Options {
    Options::default()
        .with_method(Method::Dop853)
        .with_tol(1e3, 1e3)
        .with_h_init(h)
        .with_h_max(h)
}

/// Global error at t = 10 of `y' = -y` (closed form `e^{-t}`) and of the harmonic oscillator
/// (closed form in `LinearOscillator::free_undamped`) with fixed steps: halving `h` divides
/// the error by 2⁸.
#[test]
fn fixed_step_global_order_is_eight() {
    let decay = FnSystem::new(1, |_t, y: &[f64], d: &mut [f64]| d[0] = -y[0]);
    let osc = oscillator();
    let err_decay = |h: f64| {
        let s = integrate(
            &decay,
            0.0,
            &[1.0],
            10.0,
            &pinned(h).with_output(Output::Final),
        );
        (s.unwrap().y_final[0] - (-10.0f64).dexp()).abs()
    };
    let err_osc = |h: f64| {
        let s = integrate(
            &osc,
            0.0,
            &[1.0, 0.0],
            10.0,
            &pinned(h).with_output(Output::Final),
        )
        .unwrap();
        let (x, v) = osc.0.free_undamped(1.0, 0.0, 10.0);
        (s.y_final[0] - x).abs().max((s.y_final[1] - v).abs())
    };
    for (name, e1, e2) in [
        ("decay", err_decay(1.0), err_decay(0.5)),
        ("oscillator", err_osc(0.5), err_osc(0.25)),
    ] {
        let order = (e1 / e2).dlog2();
        assert!(
            (order - 8.0).abs() < 0.4,
            "{name}: measured order {order} ({e1:e}, {e2:e})"
        );
    }
}

/// Adaptive: the global error follows the tolerance (proportionality of a method with local
/// error control) and stays within a small multiple of it, on the closed forms.
#[test]
fn adaptive_error_is_proportional_to_the_tolerance() {
    let decay = FnSystem::new(1, |_t, y: &[f64], d: &mut [f64]| d[0] = -y[0]);
    let mut last = f64::INFINITY;
    for rtol in [1e-6, 1e-8, 1e-10, 1e-12] {
        let o = Options::default()
            .with_method(Method::Dop853)
            .with_tol(rtol, rtol * 1e-3)
            .with_output(Output::Final);
        let s = integrate(&decay, 0.0, &[1.0], 10.0, &o).unwrap();
        let err = (s.y_final[0] - (-10.0f64).dexp()).abs() / (-10.0f64).dexp();
        assert!(err < 10.0 * rtol, "rtol {rtol:e}: relative error {err:e}");
        assert!(err < last, "rtol {rtol:e}: {err:e} not below {last:e}");
        last = err;
    }
    let osc = oscillator();
    for rtol in [1e-7, 1e-10, 1e-13] {
        let o = Options::default()
            .with_method(Method::Dop853)
            .with_tol(rtol, rtol)
            .with_output(Output::Uniform { dt: 0.25 });
        let s = integrate(&osc, 0.0, &[1.0, 0.3], 30.0, &o).unwrap();
        assert_eq!(s.len(), 121);
        let mut err: f64 = 0.0;
        for i in 0..s.len() {
            let (x, v) = osc.0.free_undamped(1.0, 0.3, s.t[i]);
            err = err
                .max((s.state(i)[0] - x).abs())
                .max((s.state(i)[1] - v).abs());
        }
        // samples come from the 7th-order dense output: as accurate as the steps
        assert!(
            err < 300.0 * rtol,
            "rtol {rtol:e}: max sample error {err:e}"
        );
    }
}

/// One step of size `h` from the exact state: the dense output at θ = 0.37 has a local error
/// O(h⁸) (a continuous extension of order 7), against O(h⁵) for DP5's.
#[test]
fn dense_output_local_order_is_seven() {
    let osc = oscillator();
    let err = |m: Method, h: f64| {
        let th = 0.37 * h;
        let o = Options::default()
            .with_method(m)
            .with_tol(1e3, 1e3)
            .with_h_init(h)
            .with_output(Output::Times(vec![th]));
        let s = integrate(&osc, 0.0, &[1.0, 0.0], h, &o).unwrap();
        assert_eq!(s.stats.n_accepted, 1);
        let (x, v) = osc.0.free_undamped(1.0, 0.0, th);
        (s.y[0] - x).abs().max((s.y[1] - v).abs())
    };
    for (m, h, p) in [
        (Method::Dop853, 1.0, 8.0),
        (Method::DormandPrince54, 0.5, 5.0),
    ] {
        let (e1, e2) = (err(m, h), err(m, h / 2.0));
        let order = (e1 / e2).dlog2();
        assert!(
            (order - p).abs() < 0.4,
            "{m:?}: local dense order {order} ({e1:e}, {e2:e})"
        );
    }
}

/// The forced, damped backlash (dead-zone) oscillator of the benches: DOP853 and DP5, both at
/// tight tolerances, locate the same contact events (same index and direction, times within
/// 1e-8) over a rattling window.
#[test]
fn backlash_event_times_agree_with_dormand_prince() {
    let mut osc = DeadZoneOscillator::free(1.0);
    (osc.zeta, osc.kappa, osc.omega) = (0.05, 0.2, 1.5);
    (osc.f_mean, osc.f_amp) = (0.1, 0.5);
    let sys = FirstOrder(osc);
    let run = |m: Method| {
        let o = Options::default()
            .with_method(m)
            .with_tol(1e-12, 1e-14)
            .with_output(Output::Final);
        integrate(&sys, 0.0, &[1.1, 0.0], 60.0, &o).unwrap()
    };
    let (a, b) = (run(Method::Dop853), run(Method::DormandPrince54));
    assert_eq!(a.status, Status::Completed);
    assert!(a.events.len() >= 10, "{}", a.events.len());
    assert_eq!(a.events.len(), b.events.len());
    for (ea, eb) in a.events.iter().zip(&b.events) {
        assert_eq!((ea.index, ea.direction), (eb.index, eb.direction));
        assert!((ea.t - eb.t).abs() < 1e-8, "{} vs {}", ea.t, eb.t);
    }
    assert!((a.y_final[0] - b.y_final[0]).abs() < 1e-8);
    // fewer steps for the higher order at this tolerance
    assert!(
        a.stats.n_accepted * 2 < b.stats.n_accepted,
        "{:?} vs {:?}",
        a.stats,
        b.stats
    );
    assert_eq!(a.stats.n_events, a.events.len() as u64);
}

/// Work counters: without events or samples inside steps, each attempted step costs 12
/// evaluations, plus 1 for the start and 2 for the automatic initial step.
#[test]
fn statistics_count_the_work() {
    let osc = oscillator();
    let o = Options::default()
        .with_method(Method::Dop853)
        .with_output(Output::Final);
    let s = integrate(&osc, 0.0, &[1.0, 0.0], 50.0, &o).unwrap();
    let st = s.stats;
    assert!(st.n_accepted > 10);
    assert_eq!(st.n_rhs, 3 + 12 * (st.n_accepted + st.n_rejected));
    assert_eq!(st.n_events, 0);
    // samples read the dense output: 3 more evaluations in each step that holds one
    let o = o.with_output(Output::Times(vec![1.0, 30.0]));
    let s2 = integrate(&osc, 0.0, &[1.0, 0.0], 50.0, &o).unwrap();
    assert_eq!(s2.stats.n_accepted, st.n_accepted);
    assert_eq!(s2.stats.n_rhs, st.n_rhs + 2 * 3);
    assert_eq!(s2.y_final, s.y_final);
}

/// Every output mode, with events on: steps end on the events, samples are ascending.
#[test]
fn output_modes() {
    let b = 0.5;
    let sys = FirstOrder(DeadZoneOscillator::free(b));
    let exact = DeadZoneOscillator::free_event_times(b, 1.0, 4);
    let base = Options::default()
        .with_method(Method::Dop853)
        .with_tol(1e-10, 1e-12);
    let steps = integrate(&sys, 0.0, &[0.0, 1.0], 10.0, &base).unwrap();
    for te in &exact {
        assert!(
            steps.t.iter().any(|t| (t - te).abs() < 1e-9),
            "no step ends at {te}"
        );
    }
    let uni = integrate(
        &sys,
        0.0,
        &[0.0, 1.0],
        10.0,
        &base.clone().with_output(Output::Uniform { dt: 0.1 }),
    )
    .unwrap();
    assert_eq!(uni.len(), 101);
    // free flight x = t before the first contact at t = b
    for i in 0..5 {
        assert!((uni.state(i)[0] - uni.t[i]).abs() < 1e-10);
    }
    let times = integrate(
        &sys,
        0.0,
        &[0.0, 1.0],
        10.0,
        &base
            .clone()
            .with_output(Output::Times(vec![0.25, 2.0, 9.0])),
    )
    .unwrap();
    assert_eq!(times.t, vec![0.25, 2.0, 9.0]);
    let fin = integrate(
        &sys,
        0.0,
        &[0.0, 1.0],
        10.0,
        &base.with_output(Output::Final),
    )
    .unwrap();
    assert!(fin.is_empty());
    assert_eq!(fin.y_final, steps.y_final);
    assert_eq!(fin.events, steps.events);
}

/// A sweep of forced backlash runs gives the same bits on 1 and 2 threads.
#[cfg(feature = "parallel")]
#[test]
fn sweep_is_bit_identical_for_one_and_two_threads() {
    let omegas: Vec<f64> = (0..6).map(|i| 0.8 + 0.15 * i as f64).collect();
    let run = |w: &f64| {
        let mut osc = DeadZoneOscillator::free(1.0);
        (osc.zeta, osc.kappa, osc.omega) = (0.05, 0.2, *w);
        (osc.f_mean, osc.f_amp) = (0.1, 0.5);
        let o = Options::default()
            .with_method(Method::Dop853)
            .with_output(Output::Uniform { dt: 0.5 });
        integrate(&FirstOrder(osc), 0.0, &[1.1, 0.0], 40.0, &o).unwrap()
    };
    let one = sweep_with_threads(1, &omegas, run, None).unwrap();
    let two = sweep_with_threads(2, &omegas, run, None).unwrap();
    let bits = |s: &Solution| {
        let mut v: Vec<u64> = s.y.iter().chain(&s.y_final).map(|x| x.to_bits()).collect();
        v.extend(s.events.iter().map(|e| e.t.to_bits()));
        v
    };
    for (a, b) in one.iter().zip(&two) {
        assert_eq!(bits(a), bits(b));
        assert_eq!(a.stats, b.stats);
    }
}

/// Invalid options are typed errors naming the field.
#[test]
fn invalid_options_are_typed_errors() {
    let osc = oscillator();
    let base = Options::default().with_method(Method::Dop853);
    for (o, field) in [
        (base.clone().with_tol(-1.0, 1e-9), "rtol"),
        (base.clone().with_tol(1e-6, f64::NAN), "atol"),
        (base.clone().with_h_max(0.0), "h_max"),
        (base.clone().with_h_init(f64::INFINITY), "h_init"),
        (
            base.clone().with_output(Output::Uniform { dt: -1.0 }),
            "output dt",
        ),
    ] {
        match integrate(&osc, 0.0, &[1.0, 0.0], 1.0, &o) {
            Err(Error::InvalidParameter { name, .. }) => assert_eq!(name, field),
            other => panic!("{field}: {other:?}"),
        }
    }
    assert!(matches!(
        integrate(&osc, 0.0, &[1.0], 1.0, &base),
        Err(Error::DimensionMismatch { name: "y0", .. })
    ));
    // a right-hand side that blows up is a status, not a panic
    let bad = FnSystem::new(1, |_t, y: &[f64], d: &mut [f64]| {
        d[0] = if y[0] > 2.0 { f64::NAN } else { 1.0 }
    });
    let s = integrate(&bad, 0.0, &[0.0], 10.0, &base).unwrap();
    assert!(!s.status.is_success());
}
