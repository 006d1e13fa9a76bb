//! The one accuracy check of the time-stepping methods: repeat the point at a
//! [`TIGHTER`]-times tighter tolerance and report the largest relative change of its outputs,
//! and the step statistics every time-stepping point carries.

use super::{Kind, PointError, Record, SettingDef};

/// The factor by which the accuracy check tightens the tolerance.
pub const TIGHTER: f64 = 100.0;

/// Setting `tolerance_check` (time stepping): `"on"` repeats every point at a [`TIGHTER`]
/// tolerance and adds the column [`CHANGE_COLUMN`].
pub const TOLERANCE_CHECK: SettingDef = SettingDef {
    name: "tolerance_check",
    kind: Kind::Name {
        options: &["off", "on"],
        default: "off",
    },
    doc: "on: repeat every point at a 100× tighter integrator tolerance and add the column \
          `change_100x_tighter`, the largest relative change of the point's outputs",
};

/// The column of [`TOLERANCE_CHECK`].
pub const CHANGE_COLUMN: (&str, &str) = ("change_100x_tighter", "1");

/// Largest relative change `|a_i − b_i| / max(|a_i|, |b_i|)` over the outputs (0 where both are
/// equal, including both zero).
pub fn relative_change(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| {
            let d = (x - y).abs();
            if d == 0.0 {
                0.0
            } else {
                d / x.abs().max(y.abs())
            }
        })
        .fold(0.0, f64::max)
}

/// The step statistics of every time-stepping point, the last columns of its row (always on):
/// accepted and rejected steps, right-hand-side evaluations and located events of the whole
/// run (transient included) at the study's tolerance ([`timestep::Stats`]).
pub const STEP_STATISTICS: [(&str, &str); 4] = [
    ("steps_accepted", "1"),
    ("steps_rejected", "1"),
    ("rhs_calls", "1"),
    ("events", "1"),
];

/// True for a column that describes the computation rather than the model (the
/// [`STEP_STATISTICS`]): in the CSV and the JSON ranges, without a figure or heat map.
pub fn is_step_statistic(column: &str) -> bool {
    STEP_STATISTICS.iter().any(|(n, _)| *n == column)
}

/// The values of the [`STEP_STATISTICS`] columns (exact: counts below 2⁵³).
pub fn step_statistics(s: &timestep::Stats) -> [f64; 4] {
    [s.n_accepted, s.n_rejected, s.n_rhs, s.n_events].map(|n| n as f64)
}

/// The outputs of a time-stepping method: the model's, the [`CHANGE_COLUMN`] when the check is
/// on, then the [`STEP_STATISTICS`].
pub(crate) fn outs_stepped(v: &[(&str, &str)], check: bool) -> Vec<(String, String)> {
    let mut o = super::describe::outs(v);
    if check {
        o.push((CHANGE_COLUMN.0.to_owned(), CHANGE_COLUMN.1.to_owned()));
    }
    o.extend(super::describe::outs(&STEP_STATISTICS));
    o
}

/// Run `job(1)` and, when `check`, `job(`[`TIGHTER`]`)` (the tolerance divided by the factor
/// given), appending the relative change of the outputs ([`CHANGE_COLUMN`]), then the step
/// statistics of the run at the study's tolerance (the columns of a time-stepping method).
/// `job` returns the outputs and the statistics.
pub fn run_stepped(
    check: bool,
    job: impl Fn(f64) -> Result<(Record, timestep::Stats), PointError>,
) -> Result<Record, PointError> {
    let (mut r, stats) = job(1.0)?;
    if check {
        let (tight, _) = job(TIGHTER)?;
        let c = relative_change(&r.values(), &tight.values());
        r.push(CHANGE_COLUMN.0, CHANGE_COLUMN.1, c);
    }
    for ((name, unit), v) in STEP_STATISTICS.iter().zip(step_statistics(&stats)) {
        r.push(name, unit, v);
    }
    Ok(r)
}
