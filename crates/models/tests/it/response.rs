//! Gear metrics of `models::response` on records of the `timestep` engine.

use geardyn_models::response;
use timestep::{DeadZoneOscillator, FirstOrder, Options, SteadyOptions, Transient, steady_state};

/// A forced backlash oscillator held on one flank, rattling on one, rattling on both, as the
/// forcing amplitude grows (moved here from `timestep` with the metric).
#[test]
fn rattle_states_of_backlash_oscillator() {
    let base = DeadZoneOscillator {
        zeta: 0.05,
        kappa: 0.2,
        omega: 1.5,
        f_mean: 0.1,
        f_amp: 0.0,
        b: 1.0,
    };
    let run = |f_amp: f64| {
        let p = DeadZoneOscillator { f_amp, ..base };
        let period = 2.0 * std::f64::consts::PI / p.omega;
        let ss = SteadyOptions {
            transient: Transient::Periods(150),
            ..SteadyOptions::new(period)
        };
        let st = steady_state(&FirstOrder(p), 0.0, &[1.1, 0.0], &Options::default(), &ss).unwrap();
        response::rattle_state(&st.component(0), p.b, 1e-9).unwrap()
    };
    assert_eq!(run(0.02), response::RattleState::NoRattle);
    assert_eq!(run(0.5), response::RattleState::Unilateral);
    assert_eq!(run(3.0), response::RattleState::Bilateral);
}
