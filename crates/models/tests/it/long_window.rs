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

/// At 190 rad/s the default start leaves a unilateral transient of about 40 periods: the first
/// 50-period window after the 10 transient periods is bilateral in a quarter of its periods
/// only, and its section repeats neither over the window nor over its last half, so it does not
/// show the end of its transient. The next window repeats. The record holds the first window
/// until the next one has been judged, and discards it: the kept window is periodic and
/// bilateral, as from most starts within 10⁻¹¹ of this one (`docs/performance.md`, Round 20).
/// (Which start leaves such a transient moves with rounding: this one does under the default
/// `Trig::Table`.)
#[test]
#[ignore = "heavy: run optimised by `cargo xtask heavy-tests` (.ci/run)"]
fn a_window_whose_transient_ends_in_its_last_half_is_held_and_discarded() {
    let m = model(190.0);
    let bare = LongWindowOptions {
        settle_windows: 0,
        ..LongWindowOptions::default()
    };
    let first = liu2021::settled_window(&m, &bare, None).unwrap().stats;
    assert!(!first.regular() && !first.transient(), "{first:?}");
    assert!(first.bilateral_fraction() < 0.5, "{first:?}");
    let kept = liu2021::settled_window(&m, &LongWindowOptions::default(), None).unwrap();
    assert!(kept.stats.regular(), "{:?}", kept.stats);
    assert_eq!(kept.stats.state, RattleState::Bilateral);
    assert!(kept.transient_periods > 10.0, "{}", kept.transient_periods);
    let r = liu2021::long_window(&m, &LongWindowOptions::default()).unwrap();
    assert!(r.regular(), "{}", r.describe());
    assert!(r.reproducible(|w| w.ppv, 1e-7), "{}", r.describe());
}
