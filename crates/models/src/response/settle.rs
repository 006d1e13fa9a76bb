//! When a time-stepping answer is settled: the one home of the judgements the validation and the
//! user studies share.
//!
//! A steady response is judged on its long window ([`WindowStats`]): integrate a transient,
//! then windows of `P ≥ 20` forcing periods, discarding a window that still holds the end of a
//! transient up to a stated cap: its stroboscopic section repeats over its last half but not over
//! the whole ([`WindowStats::transient`]), or it repeats nowhere while the next window repeats
//! (a transient that ended inside the window's last half: such a window is held until the next
//! one is judged; two non-periodic windows in a row are the motion). The window that is kept is
//!
//! * **period-n** when its section repeats with period `n ≤ 4` to the section tolerance
//!   ([`WindowStats::regular`], [`WindowStats::period_multiple`]);
//! * **chaotic** when it does not and the 0–1 test gives `K > ` [`CHAOTIC_K`]
//!   ([`WindowStats::chaos_k`]), **quasi-periodic** when `K ≤` [`CHAOTIC_K`];
//! * **unsettled** when it still holds a transient at the cap, or holds fewer than 20 periods
//!   (too few for the section test and the 0–1 test: a one-period record is always unsettled).
//!
//! Its statistics are values of the point only when they are also reproducible over the
//! variants of [`Robust`] (`rtol/100`, a second window, a second start) to [`SETTLED`]
//! ([`window_unsettled`]). A one-period reference classified on a short section is confirmed
//! periodic only with the margin [`CONFIRMED`] ([`section_confirmed`]).

use super::{Robust, WindowStats};
use crate::motion::Motion;

/// Relative spread over the long-window variants below which a window statistic is a value of
/// the point (validation: committed): a tenth of the finest committed step of a 4-significant-
/// digit table number, so that a value that settles to this spread moves its digits under a
/// solver retune with a probability of about 1/10 at most. A periodic orbit settles to the
/// integrator's tolerance (~1e-8).
pub const SETTLED: f64 = 1e-5;

/// Margin below which a periodic classification of a short section is confirmed: the section
/// repeats within 1/100 of its tolerance ([`crate::motion::section_margin`]). A settled periodic
/// orbit repeats at the integrator's error, orders inside it; a section that repeats only just
/// inside the tolerance (Liu Fig. 11, bilateral points between 165 and 250 rad/s) flipped between
/// period-1 and non-periodic under a retune of the step-size controller.
pub const CONFIRMED: f64 = 1e-2;

/// 0–1 test threshold between quasi-periodic (`K ≤ 0.5`) and chaotic (`K > 0.5`) windows whose
/// section does not repeat (Gottwald & Melbourne 2009: `K → 0` for regular, `K → 1` for chaotic
/// dynamics; 0.5 is the midpoint).
pub const CHAOTIC_K: f64 = 0.5;

/// Fewest periods of a window that can be classified (the section test and the 0–1 test).
pub const MIN_CLASSIFIED_PERIODS: usize = 20;

/// The table code of an unsettled point in a `motion` column (the codes of [`Motion::code`]
/// otherwise: `n ≥ 1` period-n, 0 quasi-periodic, −1 chaotic).
pub const UNSETTLED_CODE: f64 = -3.0;

/// The motion of a kept window, `None` when it is unsettled (a transient at the cap, or fewer
/// than [`MIN_CLASSIFIED_PERIODS`] periods).
pub fn window_motion(w: &WindowStats) -> Option<Motion> {
    if w.periods < MIN_CLASSIFIED_PERIODS || w.chaos_k.is_nan() || w.transient() {
        None
    } else if w.regular() {
        Some(Motion::Periodic(w.period_multiple.max(1)))
    } else if w.chaos_k > CHAOTIC_K {
        Some(Motion::Chaotic)
    } else {
        Some(Motion::QuasiPeriodic)
    }
}

/// The `motion` column of a window: [`Motion::code`] of [`window_motion`], [`UNSETTLED_CODE`]
/// when unsettled.
pub fn motion_code(w: &WindowStats) -> f64 {
    window_motion(w).map_or(UNSETTLED_CODE, Motion::code)
}

/// The label of a `motion` code (`period-n`, `quasi-periodic`, `chaotic`, `non-periodic`,
/// `unsettled`); `None` for a code that is none of them.
pub fn motion_label(code: f64) -> Option<String> {
    #[allow(clippy::float_cmp)] // exact: the codes are small integers
    if code == UNSETTLED_CODE {
        return Some("unsettled".to_owned());
    }
    Motion::from_code(code).map(Motion::label)
}

/// The long-window statistics are samples rather than values: the window is not periodic in
/// every variant, the variants disagree on the rattle state, or the ppv moves over them by more
/// than `rel` (relative; the validation uses [`SETTLED`]).
pub fn window_unsettled(w: &Robust, rel: f64) -> bool {
    w.state().is_none() || !w.reproducible(|s| s.ppv, rel)
}

/// A periodic classification of a short section is confirmed: `motion` is periodic and the
/// section's repeat distance over its tolerance (`margin`, [`crate::motion::section_margin`]) is
/// at most `confirmed` (the validation uses [`CONFIRMED`]).
pub fn section_confirmed(motion: Motion, margin: f64, confirmed: f64) -> bool {
    motion.period_multiple() != 0 && !margin.is_nan() && margin <= confirmed
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::response::{FlankImpacts, RattleState};

    fn stats(periods: usize, chaos_k: f64, tail: bool, n: usize) -> WindowStats {
        let f = FlankImpacts {
            count: 0,
            rate: 0.0,
            mean_speed: 0.0,
            max_speed: 0.0,
        };
        WindowStats {
            periods,
            state: RattleState::Unilateral,
            fraction: [0.0, 1.0, 0.0],
            ppv: 1.0,
            q_min: -0.5,
            q_max: 0.5,
            max_depth: 0.5,
            drive: f,
            back: f,
            line_coherent: [0.0; 2],
            line_incoherent: [0.0; 2],
            chaos_k,
            tail_regular: tail,
            period_multiple: n,
        }
    }

    #[test]
    #[allow(clippy::float_cmp)] // exact: the codes are small integers
    fn windows_are_classified_or_unsettled() {
        let code = |w: &WindowStats| motion_code(w);
        assert_eq!(code(&stats(50, 0.0, true, 2)), 2.0);
        assert_eq!(code(&stats(50, 0.93, false, 0)), -1.0);
        assert_eq!(code(&stats(50, 0.1, false, 0)), 0.0);
        // the end of a transient at the cap, a too-short window, no 0–1 test
        assert_eq!(code(&stats(50, 0.93, true, 0)), UNSETTLED_CODE);
        assert_eq!(code(&stats(19, 0.0, true, 1)), UNSETTLED_CODE);
        assert_eq!(code(&stats(1, f64::NAN, false, 0)), UNSETTLED_CODE);
        assert_eq!(motion_label(UNSETTLED_CODE).as_deref(), Some("unsettled"));
        assert_eq!(motion_label(2.0).as_deref(), Some("period-2"));
        assert_eq!(motion_label(-1.0).as_deref(), Some("chaotic"));
        assert_eq!(motion_label(0.5), None);
    }

    #[test]
    fn confirmation_needs_a_periodic_motion_within_the_margin() {
        assert!(section_confirmed(Motion::Periodic(1), 1e-3, CONFIRMED));
        assert!(!section_confirmed(Motion::Periodic(1), 0.5, CONFIRMED));
        assert!(!section_confirmed(Motion::Periodic(1), f64::NAN, CONFIRMED));
        assert!(!section_confirmed(Motion::NonPeriodic, 0.0, CONFIRMED));
    }
}
