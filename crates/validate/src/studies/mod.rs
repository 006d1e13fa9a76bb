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
