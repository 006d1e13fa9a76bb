//! Property test: event times of the free dead-zone oscillator equal the analytic
//! free-flight/contact schedule for any gap and impact speed.

use geardyn_timestep::*;
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]
    #[test]
    fn dead_zone_events_match_schedule(b in 0.05f64..2.0, v0 in 0.2f64..3.0) {
        let sys = FirstOrder(DeadZoneOscillator::free(b));
        let exact = DeadZoneOscillator::free_event_times(b, v0, 8);
        let o = Options::default().with_tol(1e-11, 1e-13).with_output(Output::Final);
        let s = integrate(&sys, 0.0, &[0.0, v0], exact[7] + 0.5 * b / v0, &o).unwrap();
        prop_assert_eq!(s.events.len(), 8);
        for (ev, te) in s.events.iter().zip(&exact) {
            prop_assert!((ev.t - te).abs() < 1e-8 * te.max(1.0), "{} vs {}", ev.t, te);
        }
        // energy is conserved across the piecewise phases: v² + f(x)² constant
        let x = s.y_final[0];
        let f = DeadZoneOscillator::free(b).dead_zone(x);
        let e = s.y_final[1].powi(2) + f * f;
        prop_assert!((e - v0 * v0).abs() < 1e-7 * v0 * v0);
    }
}
