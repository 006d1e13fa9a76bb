//! Bifurcation sweeps: reference motions of the Duffing and backlash oscillators, quasi-periodic
//! and chaotic cases, continuation with hysteresis, failed points, thread-count determinism.

use geardyn_timestep::*;
use math::DetMath;

fn opts() -> Options {
    Options::default().with_tol(1e-9, 1e-11)
}

fn bo(coordinate: usize) -> BifurcationOptions {
    let mut b = BifurcationOptions::new(coordinate);
    b.classify.transient_periods = 100;
    b.classify.n_points = 32;
    b.classify.lyapunov_intervals = 150;
    b
}

fn duffing(d: Duffing) -> Result<(FirstOrder<Duffing>, f64)> {
    Ok((FirstOrder(d), d.period()))
}

/// Duffing δ = 0.3, α = −1, β = 1, ω = 1.2 from (1, 0): period-1 at γ = 0.20, period-2 at
/// γ = 0.28 (the period-doubling of Holmes 1979; Guckenheimer & Holmes 1983 §2.2), chaotic at
/// γ = 0.50 with λ ≈ 0.1–0.2 per unit time (same sources).
#[test]
fn duffing_period_one_period_two_and_chaos() {
    let gammas = [0.20, 0.28, 0.50];
    let pts = bifurcation_sweep(
        &gammas,
        |&g| duffing(Duffing::holmes(g)),
        &[1.0, 0.0],
        &bo(0),
        &opts(),
    )
    .unwrap();
    let p1 = pts[0].as_ref().unwrap();
    assert_eq!(p1.motion, Motion::Periodic(1));
    assert_eq!(p1.section.len(), 32);
    assert!(p1.lyapunov.is_none());
    // period-1: every section value the same (to the classification tolerance)
    let spread = |s: &[f64]| {
        s.iter().copied().fold(f64::NEG_INFINITY, f64::max)
            - s.iter().copied().fold(f64::INFINITY, f64::min)
    };
    assert!(spread(&p1.section) < 1e-5);
    let p2 = pts[1].as_ref().unwrap();
    assert_eq!(p2.motion, Motion::Periodic(2));
    // two distinct values alternating
    assert!((p2.section[0] - p2.section[1]).abs() > 1e-2);
    assert!((p2.section[0] - p2.section[2]).abs() < 1e-5);
    let c = pts[2].as_ref().unwrap();
    assert_eq!(c.motion, Motion::Chaotic);
    let l = c.lyapunov.unwrap();
    assert!(l > 0.05 && l < 0.3, "lambda = {l}");
}

/// Ueda's oscillator x'' + 0.05 x' + x³ = 7.5 cos t is chaotic (Ueda 1979, "Randomly
/// transitional phenomena"; λ₁ ≈ 0.1 per unit time): classified chaotic with λ > 0.
#[test]
fn ueda_oscillator_is_chaotic() {
    let ueda = Duffing {
        delta: 0.05,
        alpha: 0.0,
        beta: 1.0,
        gamma: 7.5,
        omega: 1.0,
    };
    let pts = bifurcation_sweep(
        &[7.5],
        |&g| duffing(Duffing { gamma: g, ..ueda }),
        &[2.5, 0.0],
        &bo(0),
        &opts(),
    )
    .unwrap();
    let p = pts[0].as_ref().unwrap();
    assert_eq!(p.motion, Motion::Chaotic);
    let l = p.lyapunov.unwrap();
    assert!(l > 0.02 && l < 0.5, "lambda = {l}");
}

/// x'' + x = cos(√2 t) sampled at the forcing period 2π/√2: the free oscillation at frequency 1
/// is incommensurate with the section period, so the section fills a closed curve and λ = 0.
#[test]
fn incommensurate_section_is_quasi_periodic() {
    let w = 2f64.sqrt();
    let pts = bifurcation_sweep(
        &[w],
        |&omega| {
            let q = LinearOscillator {
                omega0: 1.0,
                zeta: 0.0,
                force: 1.0,
                omega,
            };
            Ok((q.first_order(), std::f64::consts::TAU / omega))
        },
        &[1.0, 0.0],
        &bo(0),
        &opts(),
    )
    .unwrap();
    let p = pts[0].as_ref().unwrap();
    assert_eq!(p.motion, Motion::QuasiPeriodic);
    assert!(p.lyapunov.unwrap().abs() < 1e-3);
}

/// The dead-zone (backlash) oscillator under weak forcing stays in contact and responds at
/// the forcing period (period-1), from the contact position; with `lyapunov_always` the
/// exponent of the stable cycle is negative, about −ζ (the decay rate of a lightly damped
/// linear oscillator in permanent contact, x'' + 2ζx' + x).
#[test]
fn weakly_forced_backlash_oscillator_is_period_one() {
    let base = DeadZoneOscillator {
        zeta: 0.05,
        kappa: 0.2,
        omega: 1.5,
        f_mean: 0.1,
        f_amp: 0.02,
        b: 1.0,
    };
    let mut b = bo(0);
    b.classify.lyapunov_always = true;
    let pts = bifurcation_sweep(
        &[0.01, 0.02],
        |&f_amp| {
            let p = DeadZoneOscillator { f_amp, ..base };
            Ok((FirstOrder(p), std::f64::consts::TAU / p.omega))
        },
        &[1.1, 0.0],
        &b,
        &opts(),
    )
    .unwrap();
    for p in &pts {
        let p = p.as_ref().unwrap();
        assert_eq!(p.motion, Motion::Periodic(1));
        assert!(p.section.iter().all(|&x| x > base.b), "in contact");
        let l = p.lyapunov.unwrap();
        assert!(l < -0.02 && l > -0.1, "lambda = {l}");
    }
}

/// Hardening Duffing x'' + 0.1x' + x + x³ = 0.3 cos ωt: the resonance bends right and two
/// period-1 responses coexist between the jump frequencies (backbone ω² = 1 + ¾A², peak
/// A ≈ γ/(δω) ≈ 1.7 at ω ≈ 1.77; Nayfeh & Mook 1979 §4.1). Sweeping up follows the large
/// response past ω = 1.5, sweeping down the small one: hysteresis.
#[test]
fn continuation_up_and_down_shows_hysteresis() {
    let omegas = [1.1, 1.2, 1.3, 1.4, 1.5];
    let run = |start| {
        let mut b = bo(0);
        b.start = start;
        b.classify.transient_periods = 60;
        b.classify.n_points = 8;
        b.classify.max_period = 4;
        bifurcation_sweep(
            &omegas,
            |&omega| {
                duffing(Duffing {
                    delta: 0.1,
                    alpha: 1.0,
                    beta: 1.0,
                    gamma: 0.3,
                    omega,
                })
            },
            &[0.0, 0.0],
            &b,
            &opts(),
        )
        .unwrap()
    };
    let amp = |p: &Result<BifurcationPoint>| {
        let p = p.as_ref().unwrap();
        assert_eq!(p.motion, Motion::Periodic(1));
        p.final_state[0].dhypot(p.final_state[1])
    };
    let up = run(Start::ContinueUp);
    let down = run(Start::ContinueDown);
    let (a_up, a_down) = (amp(&up[4]), amp(&down[4]));
    assert!(a_up > 2.0 * a_down, "up {a_up}, down {a_down}");
    // far below resonance there is one response: both directions agree
    assert!((amp(&up[0]) - amp(&down[0])).abs() < 1e-4);
}

#[test]
fn a_failed_point_is_a_failed_row_and_continuation_restarts() {
    let gammas = [0.20, f64::NAN, 0.20];
    for start in [Start::Independent, Start::ContinueUp] {
        let mut b = bo(0);
        b.start = start;
        let pts = bifurcation_sweep(
            &gammas,
            |&g: &f64| {
                if g.is_nan() {
                    Err(Error::System("gamma is NaN".into()))
                } else {
                    duffing(Duffing::holmes(g))
                }
            },
            &[1.0, 0.0],
            &b,
            &opts(),
        )
        .unwrap();
        assert!(matches!(pts[1], Err(Error::System(_))));
        assert_eq!(pts[0].as_ref().unwrap().motion, Motion::Periodic(1));
        // restarted from the given state: the same as the first point, bit for bit
        assert_eq!(pts[2], pts[0]);
    }
    assert!(
        bifurcation_sweep(
            &gammas,
            |&g| duffing(Duffing::holmes(g)),
            &[1.0, f64::NAN],
            &bo(0),
            &opts()
        )
        .is_err()
    );
    assert!(
        bifurcation_sweep(
            &gammas,
            |&g| duffing(Duffing::holmes(g)),
            &[1.0, 0.0],
            &bo(2),
            &opts()
        )
        .is_err()
    );
}

#[test]
fn independent_sweep_is_bit_identical_for_any_thread_count() {
    let gammas: Vec<f64> = (0..6).map(|i| 0.26 + 0.05 * i as f64).collect();
    let mut b = bo(1);
    b.classify.transient_periods = 40;
    b.classify.n_points = 12;
    b.classify.max_period = 4;
    b.classify.lyapunov_intervals = 20;
    b.classify.lyapunov_always = true;
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                bifurcation_sweep(
                    &gammas,
                    |&g| duffing(Duffing::holmes(g)),
                    &[1.0, 0.0],
                    &b,
                    &opts(),
                )
                .unwrap()
            })
    };
    let bits = |v: Vec<Result<BifurcationPoint>>| -> Vec<(Motion, Vec<u64>)> {
        v.into_iter()
            .map(|p| {
                let p = p.unwrap();
                let mut x: Vec<u64> = p.section.iter().map(|v| v.to_bits()).collect();
                x.push(p.lyapunov.unwrap().to_bits());
                (p.motion, x)
            })
            .collect()
    };
    let one = bits(run(1));
    assert_eq!(one, bits(run(2)));
    assert_eq!(one, bits(run(3)));
}
