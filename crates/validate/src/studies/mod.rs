//! The study lists, one file per area; each exposes `pub fn studies() -> Vec<Study>`.

use std::collections::BTreeMap;

use crate::user::{Method, Solver};
use crate::{Error, ResultExt, Study, apply_overrides};

mod geometry;
mod karpov2017;
mod liu2021;
mod user_models;
mod yu2021;
mod yu2021_backlash;
mod yu2021_scaling;

/// Every study, in report order (Karpov, Liu, Yu; geometry first within a paper).
pub fn all_studies() -> Vec<Study> {
    let mut v = geometry::studies();
    v.extend(karpov2017::studies());
    v.extend(liu2021::studies());
    v.extend(yu2021_backlash::studies());
    v.extend(yu2021::studies());
    v.extend(yu2021_scaling::studies());
    v.sort_by_key(|s| s.paper);
    v
}

/// Output columns and evaluator of one user-study point.
pub(crate) type Adapter = (
    Vec<(&'static str, &'static str)>,
    Box<dyn Fn(&BTreeMap<String, f64>) -> Result<Vec<f64>, Error> + Sync>,
);

/// The user-study adapter of a model (see `crate::user` and `docs/studies.md`).
pub(crate) fn user_adapter(model: &str, solver: &Solver) -> Result<Adapter, Error> {
    match model {
        "karpov2017-kinematics" => {
            if solver.method != Method::Kinematics {
                return Err(Error::StudyFile(
                    "karpov2017-kinematics needs solver.method = \"kinematics\"".to_owned(),
                ));
            }
            if let Some(k) = solver.settings.keys().next() {
                return Err(Error::StudyFile(format!(
                    "karpov2017-kinematics takes no solver settings, got `{k}`"
                )));
            }
            Ok((
                vec![
                    ("delta_exact", "1"),
                    ("delta_eq4", "1"),
                    ("emax_exact", "rad/s^2"),
                    ("emax_eq6", "rad/s^2"),
                    ("b_max_exact", "1"),
                ],
                Box::new(karpov_kinematics_point),
            ))
        }
        "karpov2017" => user_models::karpov2017(solver),
        "liu2021" => user_models::liu2021(solver),
        "yu2021" => user_models::yu2021(solver),
        _ => Err(Error::StudyFile(format!(
            "model `{model}` is not wired to `cargo xtask study` yet"
        ))),
    }
}

/// One point of the `karpov2017-kinematics` user model: Table 1 pair with overrides of its
/// fields (`r`, `u`, `b`, `xi`, `j`, `z1`) plus `omega1` (rad/s, default 1) and `delta_max`
/// (default 0.001).
fn karpov_kinematics_point(p: &BTreeMap<String, f64>) -> Result<Vec<f64>, Error> {
    let mut fields = p.clone();
    let omega1 = fields.remove("omega1").unwrap_or(1.0);
    let delta_max = fields.remove("delta_max").unwrap_or(0.001);
    let base = gear_geometry::KarpovPair::karpov2017_table1().params();
    let params = apply_overrides(&base, &fields)?;
    let pair = gear_geometry::KarpovPair::new(params).context("Karpov pair")?;
    let check = pair.design_check(delta_max).context("design check")?;
    Ok(vec![
        pair.speed_fluctuation(),
        pair.speed_fluctuation_eq4(),
        pair.max_acceleration(omega1),
        pair.max_acceleration_eq6(omega1),
        check.b_max_exact,
    ])
}
