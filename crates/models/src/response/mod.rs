//! Gear response metrics on any record (design: `models/response/`): the one-record metrics
//! ([`RattleState`] and [`rattle_state`], [`dynamic_factor`], [`rms_of_harmonics`]) and the
//! long-window rattle statistics that decide rattle claims for periodic, intermittent and
//! chaotic motion alike.
//!
//! One-period metrics (Liu's `rsv` and `ppv` of the last period, [`crate::liu2021::Rattle`])
//! describe a period-1 orbit and nothing else. For an intermittent or chaotic orbit the
//! questions a rattle claim asks — does the back flank get hit, how often, how large is the
//! motion — are answered by statistics over many forcing periods:
//!
//! * the **rattle state over the window**: bilateral on any back-flank contact, unilateral on any
//!   separation from the drive flank deeper than a stated minimum depth, else no rattle;
//! * the **fraction of periods** in each state;
//! * the **impact rate** (impacts per forcing period) and the **impact velocity** per flank;
//! * the **long-window ppv** `max q − min q` over the whole window;
//! * the **window-averaged amplitude** of the phase-locked lines `k·(2π/T)` (coherent: modulus
//!   of the mean complex amplitude; incoherent: mean of the moduli);
//! * a **chaos indicator**: the 0–1 test for chaos of Gottwald & Melbourne (SIAM J. Appl. Dyn.
//!   Syst. 8:129, 2009) on the stroboscopic section — `K ≈ 0` regular, `K ≈ 1` chaotic.
//!
//! * the **Lyapunov spectrum** of the settled response ([`settled_lyapunov`]: QR renormalisation
//!   of the event-located variational flow, with its convergence; in consecutive batches with
//!   [`settled_lyapunov_batches`], whose spread [`lyapunov_batch_spread`] is the finite-time
//!   fluctuation of the exponent), beside the 0–1 test.
//!
//! [`window_stats`] computes them from uniform samples `(t, q, q')` of one record (fed one
//! sample at a time, while a record integrates, through a [`WindowAccumulator`]); [`Robust`]
//! combines the statistics of several records of the same point (two tolerances, two windows,
//! two initial states) into intervals, so that a verdict can say whether its statistic is robust;
//! [`window_motion`] and [`window_unsettled`] say whether a window's answer is settled (one
//! home for the validation and the user studies); [`basin`] names the attractors that a grid of
//! initial states reaches and gives their basins of attraction.

pub mod basin;
mod lyapunov;
mod metrics;
mod settle;
mod window;

pub use lyapunov::{
    LyapunovWindowOptions, MAX_LYAPUNOV_BATCHES, MAX_LYAPUNOV_EXPONENTS, describe_lyapunov,
    lyapunov_batch_spread, settled_lyapunov, settled_lyapunov_batches,
};
pub use metrics::{
    RattleState, dynamic_factor, order_of_magnitude, rattle_state, rattle_state_with_gap,
    rms_of_harmonics,
};
pub use settle::{
    CHAOTIC_K, CONFIRMED, MIN_CLASSIFIED_PERIODS, SETTLED, UNSETTLED_CODE, motion_code,
    motion_label, section_confirmed, window_motion, window_unsettled,
};
pub use window::{
    Crossing, Flank, FlankImpacts, Robust, WindowAccumulator, WindowDetail, WindowOptions,
    WindowStats, student_t_975, window_stats, zero_one_test,
};
#[cfg(test)]
pub(crate) use window::{assert_motion_only, motion_fields};
