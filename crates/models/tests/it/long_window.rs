//! Long-window rattle statistics are robust where one-period metrics are not.
//!
//! At three non-periodic points of the Liu ω1 sweep (Table 1, constant b̄; the stroboscopic
//! section does not repeat there, `validation/liu2021/liu2021-fig11-speed-sweep_sweep.csv`), the
//! rattle state over 50 periods and the fraction of bilateral periods do not depend on the
//! tolerance (rtol and rtol/100), the window (two consecutive 50-period windows) or the start
//! (drive-flank contact at rest, or the middle of the gap at rest). At the periodic bilateral
//! points next to them the section repeats in every variant once the record has discarded the
//! window that still held the end of the transient.

use geardyn_models::liu2021::{self, BaseRadius, LongWindowOptions, RattleState};

/// Largest spread of the bilateral fraction over the variants: a tenth of the periods. The
/// rattle claims of Liu's Sect. 3 judge with ×2 / ×3 margins, so a 0.1 spread cannot move them.
const FRACTION_SPREAD: f64 = 0.1;

fn model(omega1: f64) -> liu2021::Model {
    let mut p = liu2021::table1();
    p.omega1 = omega1;
    p.readings.base_radius = BaseRadius::Mean;
    p.model().unwrap()
}

#[test]
#[ignore = "heavy: run optimised by `cargo xtask heavy-tests` (.ci/run)"]
fn state_and_bilateral_fraction_are_invariant_at_chaotic_points() {
    for (omega1, state) in [
        (162.5, RattleState::Unilateral),
        (165.0, RattleState::Bilateral),
        (167.5, RattleState::Bilateral),
    ] {
        let r = liu2021::long_window(&model(omega1), &LongWindowOptions::default()).unwrap();
        assert_eq!(r.variants.len(), 3);
        assert_eq!(r.state(), Some(state), "{omega1}: {}", r.describe());
        let spread = r.bilateral_fraction_spread();
        assert!(spread <= FRACTION_SPREAD, "{omega1}: {}", r.describe());
        // not periodic: the section does not repeat (the 0–1 test is 0 for a repeating one),
        // so no statistic is a reproducible value
        assert!(r.nominal.chaos_k > 0.3, "{omega1}: {}", r.describe());
        assert!(!r.regular(), "{omega1}: {}", r.describe());
        assert!(
            !r.reproducible(|w| w.ppv, 1.0),
            "{omega1}: {}",
            r.describe()
        );
        // the long-window ppv moves by well under the claims' ×2 margins
        assert!(r.ppv_spread() < 0.2, "{omega1}: {}", r.describe());
    }
}

/// At 180 rad/s the first 50-period window after 2 transient periods still holds the end of the
/// transient: its section does not repeat over the window, only over its last half. The record
/// discards it and the next window repeats, in every variant, to integration noise; the
/// statistics then agree over the variants far inside the committed precision (1e-5). (How long
/// the transient lasts moves with rounding: under `Trig::Kernel` the window after 10 periods
/// still held it, under the default `Trig::Table` the window after 4 no longer does.)
#[test]
#[ignore = "heavy: run optimised by `cargo xtask heavy-tests` (.ci/run)"]
fn a_window_with_the_end_of_a_transient_is_discarded() {
    let m = model(180.0);
    let short = LongWindowOptions {
        transient_periods: 2.0,
        ..LongWindowOptions::default()
    };
    let bare = LongWindowOptions {
        settle_windows: 0,
        ..short
    };
    let r0 = liu2021::long_window(&m, &bare).unwrap();
    assert!(r0.nominal.transient(), "{}", r0.describe());
    assert!(!r0.regular());
    let r = liu2021::long_window(&m, &short).unwrap();
    assert!(r.regular(), "{}", r.describe());
    assert_eq!(r.state(), Some(RattleState::Bilateral));
    assert!(r.nominal.chaos_k.abs() < f64::MIN_POSITIVE);
    assert!(r.reproducible(|w| w.ppv, 1e-7), "{}", r.describe());
    assert!(
        r.reproducible(|w| w.line_incoherent[1], 1e-6),
        "{}",
        r.describe()
    );
    // the settled window is the old window B: the same orbit, 50 periods later
    let b = &r0.variants[0].1;
    assert!((r.nominal.ppv - b.ppv).abs() <= 1e-9 * b.ppv);
}

/// At 190 rad/s some starts leave a unilateral transient of 30–50 periods: the first 50-period
/// window after the 10 transient periods then ends the transient in its last half, and its
/// section repeats neither over the window nor over its last half, so it does not show the
/// end of its transient. The next window repeats. The record holds the first window until the
/// next one has been judged, and discards it: the kept window is periodic and bilateral, as
/// from the other starts (`docs/performance.md`, Round 20). Which starts leave such a
/// transient moves with every change of the step sequence (round 20: the default start under
/// `Trig::Table`, and 3–5 of the 25 starts `q_s + k·10⁻¹²`, `k = −12 … 12`, under each `Trig`
/// path; round 21's controller: 1 of those 25, `k = −10`; round 22's crossing retry: none of
/// the 250 starts `k = −50 … 200` at that spacing, while 11 of the 101 starts
/// `q_s + k·10⁻¹⁰`, `k = −50 … 50` do), so the test looks for them among the 101 starts
/// `q_s + k·10⁻¹⁰`. From some of those starts the transient outlasts the second window as
/// well (round 22: from 1 of the 11, `q_s − 49·10⁻¹⁰`, whose kept window is then
/// chaotic-looking, 0–1 test K = 0.96): the hold covers one window, and two non-periodic
/// windows in a row are kept as the motion. Every other start must be held, discarded and
/// reach the periodic bilateral orbit, and at least one must.
#[test]
#[ignore = "heavy: run optimised by `cargo xtask heavy-tests` (.ci/run)"]
fn a_window_whose_transient_ends_in_its_last_half_is_held_and_discarded() {
    let m = model(190.0);
    let bare = LongWindowOptions {
        settle_windows: 0,
        ..LongWindowOptions::default()
    };
    let q_s = m.static_position(0.0);
    let held: Vec<(f64, f64)> = (-50..=50)
        .map(|k| (q_s + f64::from(k) * 1e-10, 0.0))
        .filter(|&start| {
            let first = liu2021::settled_window(&m, &bare, Some(start))
                .unwrap()
                .stats;
            !first.regular() && !first.transient()
        })
        .collect();
    // starts whose transient outlasts the second window too: two non-periodic windows in a
    // row are kept as the motion (the hold covers one window)
    let mut longer = Vec::new();
    let mut discarded = 0;
    for &start in &held {
        // the kept window is the nominal window of the robust record (`settled_window`'s docs)
        let (r, kept) =
            liu2021::robust_window(&m, &LongWindowOptions::default(), Some(start)).unwrap();
        if !kept.stats.regular() {
            longer.push(start);
            continue;
        }
        assert_eq!(kept.stats.state, RattleState::Bilateral);
        assert!(kept.transient_periods > 10.0, "{}", kept.transient_periods);
        assert!(r.regular(), "{start:?}: {}", r.describe());
        assert!(
            r.reproducible(|w| w.ppv, 1e-7),
            "{start:?}: {}",
            r.describe()
        );
        discarded += 1;
    }
    assert!(
        discarded > 0,
        "of the 101 starts, {} leave the long transient and none is held and discarded \
         (longer transients from {longer:?})",
        held.len()
    );
}
