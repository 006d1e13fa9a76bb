//! The study lists, one file per area; each exposes `pub fn studies() -> Vec<Study>`.

use crate::Study;

mod geometry;
mod karpov2017;
mod karpov2017_kinematics;
mod liu2021;
pub(crate) mod user_models;
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
