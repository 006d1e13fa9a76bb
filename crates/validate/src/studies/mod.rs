//! The study lists, one file per area; each exposes `pub fn studies() -> Vec<Study>`.

use crate::Study;

mod geometry;
mod karpov2017;
mod karpov2017_kinematics;
mod liu2021;
mod yu2021;
mod yu2021_backlash;
mod yu2021_scaling;
mod yu2021_topography;

/// Every study, in report order (Karpov, Liu, Yu; geometry first within a paper).
pub fn all_studies() -> Vec<Study> {
    let mut v = geometry::studies();
    v.extend(karpov2017_kinematics::studies());
    v.extend(karpov2017::studies());
    v.extend(liu2021::studies());
    v.extend(yu2021_backlash::studies());
    v.extend(yu2021::studies());
    v.extend(yu2021_scaling::studies());
    v.extend(yu2021_topography::studies());
    v.sort_by_key(|s| s.paper);
    v
}

/// The step statistics of a run ([`models::contract::STEP_STATISTICS`]) as table cells
/// (written in full), for the validation studies.
pub(crate) fn step_cells(s: &timestep::Stats) -> [crate::Cell; 4] {
    [s.n_accepted, s.n_rejected, s.n_rhs, s.n_events].map(crate::Cell::Count)
}

/// Forcing periods of the validation's Lyapunov runs (one QR renormalisation each; the spread is
/// taken over the last quarter, [`models::response::settled_lyapunov`]).
pub(crate) const LYAPUNOV_PERIODS: usize = 200;

/// The chaos evidence of a non-periodic response (forcing period `period`): the 0–1 test `K` (when known) beside the
/// largest Lyapunov exponent per forcing period with its spread and convergence, and, with the
/// full spectrum of a model with linear damping only, the volume-law defect `Σλ − div` (the
/// integrator's floor on every exponent). A chaos reading from λ1 is stated only when it
/// converged: `λ1 > spread` (chaotic), `λ1 < −spread` (regular), else undecided.
pub(crate) fn chaos_evidence(
    k: Option<f64>,
    s: &orbit::LyapunovSpectrum,
    period: f64,
    divergence: Option<f64>,
) -> String {
    use models::contract::fmt_sig;
    let t = period;
    let (l, spread) = (s.largest() * t, s.spread_last[0] * t);
    let reading = if !s.converged {
        "not converged: no reading"
    } else if l > spread {
        "converged, positive: chaotic"
    } else if l < -spread {
        "converged, negative: regular"
    } else {
        "converged, within its spread of 0: undecided"
    };
    let mut e = String::new();
    if let Some(k) = k {
        e.push_str(&format!("0–1 test K = {}; ", fmt_sig(k, 2)));
    }
    e.push_str(&format!(
        "λ1·T = {} ± {} per period over {} periods after a warm-up ({reading})",
        fmt_sig(l, 3),
        fmt_sig(spread, 2),
        (s.running.len() as f64 * s.window / period).round()
    ));
    if let Some(d) = divergence {
        e.push_str(&format!(
            ", volume-law defect (Σλ − div)·T = {}",
            fmt_sig((s.sum() - d) * t, 2)
        ));
    }
    e
}
