//! Motion type of a time response from its stroboscopic Poincaré sections, shared by the time
//! references of the models (`liu2021::time_reference`, `yu2021::Yu2021Model::reference_run`).
//!
//! A steady response sampled `N` times per forcing period `T` is *period-n* when every
//! stroboscopic section repeats after `n` periods: `|x_{k+n} − x_k| ≤ tol·scale` for all section
//! points `x_k`. The smallest such `n ≤ 4` is reported; otherwise the motion is non-periodic
//! (quasi-periodic, chaotic, or a transient that has not yet decayed — the test does not tell
//! them apart, and none of them can carry a verdict that assumes periodicity).

/// Largest period multiple the classification accepts.
pub const MAX_PERIOD_MULTIPLE: usize = 4;

/// Motion type of a time response: the workspace's one [`timestep::Motion`] (the section tests
/// here give `Periodic(n)` or `NonPeriodic`).
pub use timestep::Motion;

/// Classify a stroboscopic section `(q_k, v_k)` (one point per period): the smallest `n ≤ 4`
/// with `|x_{k+n} − x_k| ≤ tol·scale` for every `k` of the section, else non-periodic.
/// Needs at least `n + 2` points to accept period `n` ([`timestep::detect_period_abs`]).
pub fn classify_section(q: &[f64], v: &[f64], tol: f64, scale: f64) -> Motion {
    timestep::detect_period_abs(q, v, MAX_PERIOD_MULTIPLE, tol * scale)
}

/// Repeat distance of a stroboscopic section as a fraction of the classification tolerance
/// `tol·scale` ([`timestep::section_repeat_distance`]): at the period `n` of `motion` when it is
/// periodic (≤ 1 by construction), else the smallest over `n ≤ 4` (> 1). `+∞` when no period can
/// be tested (too few points, non-finite data or a non-positive tolerance).
///
/// The margin of [`classify_section`]: a section at 1/100 of the tolerance stays periodic under
/// a solver retune that moves its points by less than that; one near 1 can flip either way.
pub fn section_margin(q: &[f64], v: &[f64], motion: Motion, tol: f64, scale: f64) -> f64 {
    let t = tol * scale;
    if !(t > 0.0 && t.is_finite()) {
        return f64::INFINITY;
    }
    match motion {
        Motion::Periodic(n) => timestep::section_repeat_distance(q, v, n) / t,
        _ => (1..=MAX_PERIOD_MULTIPLE)
            .map(|n| timestep::section_repeat_distance(q, v, n) / t)
            .fold(f64::INFINITY, f64::min),
    }
}

/// Classify a uniformly sampled record of whole periods (`samples_per_period` samples per
/// forcing period, record starting at a period boundary) by the stroboscopic sections at every
/// sampled phase at once: period-n when `|x_{i+n·N} − x_i| ≤ tol·scale` for every sample `i`
/// of every series, with at least `n + 2` periods recorded. A stricter test than one section
/// (every phase must repeat). Non-finite samples, an empty series list or `N = 0` give
/// non-periodic.
pub fn classify_record(
    series: &[&[f64]],
    samples_per_period: usize,
    tol: f64,
    scale: f64,
) -> Motion {
    let n_per = samples_per_period;
    let len = series.iter().map(|s| s.len()).min().unwrap_or(0);
    if n_per == 0 || series.is_empty() || series.iter().any(|s| s.iter().any(|x| !x.is_finite())) {
        return Motion::NonPeriodic;
    }
    let periods = len / n_per;
    for n in 1..=MAX_PERIOD_MULTIPLE {
        if periods < n + 2 {
            break;
        }
        let shift = n * n_per;
        let used = periods * n_per;
        let repeats = series
            .iter()
            .all(|s| (0..used - shift).all(|i| (s[i + shift] - s[i]).abs() <= tol * scale));
        if repeats {
            return Motion::Periodic(n);
        }
    }
    Motion::NonPeriodic
}

#[cfg(test)]
mod tests {
    use super::*;
    use math::DetMath;

    fn wave(periods: usize, n: usize, sub: bool) -> Vec<f64> {
        (0..periods * n)
            .map(|i| {
                let t = i as f64 / n as f64 * std::f64::consts::TAU;
                t.dsin() + if sub { 0.3 * (0.5 * t).dcos() } else { 0.0 }
            })
            .collect()
    }

    #[test]
    fn record_classification_finds_the_period() {
        let p1 = wave(8, 16, false);
        assert_eq!(classify_record(&[&p1], 16, 1e-9, 1.0), Motion::Periodic(1));
        let p2 = wave(8, 16, true);
        assert_eq!(classify_record(&[&p2], 16, 1e-9, 1.0), Motion::Periodic(2));
        // incommensurate component: non-periodic
        let q: Vec<f64> = (0..8 * 16)
            .map(|i| {
                (i as f64 / 16.0 * std::f64::consts::TAU).dsin() + 0.1 * (0.37 * i as f64).dsin()
            })
            .collect();
        assert_eq!(classify_record(&[&q], 16, 1e-6, 1.0), Motion::NonPeriodic);
        // one repeating series is not enough when another does not repeat
        assert_eq!(
            classify_record(&[&p1, &q], 16, 1e-6, 1.0),
            Motion::NonPeriodic
        );
    }

    #[test]
    fn record_classification_needs_enough_periods_and_finite_data() {
        let p2 = wave(3, 16, true);
        // period 2 needs 4 periods
        assert_eq!(classify_record(&[&p2], 16, 1e-9, 1.0), Motion::NonPeriodic);
        let mut p1 = wave(6, 16, false);
        assert_eq!(classify_record(&[&p1], 0, 1e-9, 1.0), Motion::NonPeriodic);
        assert_eq!(classify_record(&[], 16, 1e-9, 1.0), Motion::NonPeriodic);
        p1[5] = f64::NAN;
        assert_eq!(classify_record(&[&p1], 16, 1e-9, 1.0), Motion::NonPeriodic);
    }

    #[test]
    fn section_classification() {
        let q = [1.0, 2.0, 1.0, 2.0, 1.0];
        let v = [0.0; 5];
        assert_eq!(classify_section(&q, &v, 1e-12, 1.0), Motion::Periodic(2));
        assert_eq!(Motion::Periodic(2).label(), "period-2");
        assert_eq!(Motion::NonPeriodic.period_multiple(), 0);
    }

    #[test]
    fn section_margin_is_the_repeat_distance_over_the_tolerance() {
        // period 1 with a largest repeat error of 2e-7 against a tolerance of 1e-6·2
        let q = [1.0, 1.0 + 2e-7, 1.0, 1.0, 1.0];
        let v = [0.0; 5];
        let m = classify_section(&q, &v, 1e-6, 2.0);
        assert_eq!(m, Motion::Periodic(1));
        let r = section_margin(&q, &v, m, 1e-6, 2.0);
        assert!((r - 0.1).abs() < 1e-9, "{r}");
        // non-periodic: the smallest ratio over n <= 4 is > 1
        let qn = [0.1, 0.5, 0.9, 0.3, 0.7, 0.2, 0.8];
        let vn = [0.0; 7];
        let mn = classify_section(&qn, &vn, 1e-6, 1.0);
        assert_eq!(mn, Motion::NonPeriodic);
        let rn = section_margin(&qn, &vn, mn, 1e-6, 1.0);
        // largest repeat distances: n = 1: 0.6, n = 2: 0.8, n = 3: 0.7, n = 4: 0.6 -> 0.6
        assert!((rn - 0.6e6).abs() < 1e-3, "{rn}");
        // too few points, zero tolerance, NaN data
        let inf = |x: f64| x.is_infinite() && x > 0.0;
        assert!(inf(section_margin(
            &[1.0, 1.0],
            &[0.0, 0.0],
            Motion::Periodic(1),
            1e-6,
            1.0
        )));
        assert!(inf(section_margin(&q, &v, m, 0.0, 1.0)));
        let qnan = [1.0, f64::NAN, 1.0, 1.0];
        assert!(inf(section_margin(
            &qnan,
            &[0.0; 4],
            Motion::Periodic(1),
            1e-6,
            1.0
        )));
    }
}
