//! The shooting method shared by every model: the solver settings, the columns and the one
//! solve ([`shoot_on`]) on the event-located flow of any [`system::SecondOrderSystem`].

use super::{Kind, PointError, Record, SettingDef, Settings};
use math::DetMath;

/// The solver settings of the shooting method (after the model's `transient_periods`).
pub(crate) const SHOOT_SOLVER: [SettingDef; 5] = [
    SettingDef {
        name: "rtol",
        kind: Kind::Num {
            lo: 1e-14,
            hi: 1e-4,
            default: 1e-10,
        },
        doc: "relative tolerance of the event-located flow and its variational equations",
    },
    SettingDef {
        name: "tol",
        kind: Kind::Num {
            lo: 1e-14,
            hi: 1e-3,
            default: 1e-8,
        },
        doc: "Newton tolerance on the periodicity residual",
    },
    SettingDef {
        name: "max_iter",
        kind: Kind::Int {
            lo: 1,
            hi: 1000,
            default: Some(20),
        },
        doc: "Newton iterations",
    },
    SettingDef {
        name: "segments",
        kind: Kind::Int {
            lo: 1,
            hi: 64,
            default: Some(1),
        },
        doc: "shooting segments per period (1: single shooting)",
    },
    SettingDef {
        name: "flow_method",
        kind: Kind::Name {
            options: &["dp5", "dop853"],
            default: "dp5",
        },
        doc: "Runge–Kutta pair of the flow and its variational equations: \"dp5\" \
              (Dormand–Prince 5(4)) or \"dop853\" (Hairer's 8(5,3), cheaper without contact loss \
              and on one flank, dearer in bilateral rattle; docs/performance.md, Shooting flows)",
    },
];

/// The shooting settings of a model: the guess from `transient` (the model's own time
/// integration), then [`SHOOT_SOLVER`].
pub(crate) fn shoot_settings(transient: SettingDef) -> Vec<SettingDef> {
    std::iter::once(transient)
        .chain(SHOOT_SOLVER.iter().copied())
        .collect()
}

/// An integer `transient_periods` setting of a shooting guess (mesh periods).
pub(crate) fn shoot_transient(default: u64, doc: &'static str) -> SettingDef {
    SettingDef {
        name: "transient_periods",
        kind: Kind::Int {
            lo: 0,
            hi: 100_000,
            default: Some(default),
        },
        doc,
    }
}

/// The shooting outputs of any model: events per period, the multipliers (largest two by
/// modulus), stability and the period-doubling test function, the Newton work.
pub(crate) const SHOOT_OUT: &[(&str, &str)] = &[
    ("events_per_period", "1"),
    ("max_multiplier", "1"),
    ("mu1_re", "1"),
    ("mu1_im", "1"),
    ("mu2_re", "1"),
    ("mu2_im", "1"),
    ("stable", "1"),
    ("det_phi_plus_i", "1"),
    ("newton_iterations", "1"),
    ("residual", "1"),
];

/// The flow options of the shooting settings (`rtol`, `flow_method`).
pub(crate) fn flow_options(s: &Settings) -> orbit::FlowOptions {
    orbit::FlowOptions {
        rtol: s.f("rtol"),
        method: match s.name("flow_method") {
            "dop853" => orbit::FlowMethod::Dop853,
            _ => orbit::FlowMethod::DormandPrince54,
        },
        ..orbit::FlowOptions::default()
    }
}

/// The Newton options of the shooting settings (`tol`, `max_iter`, `segments`).
pub(crate) fn shooting_options(s: &Settings) -> orbit::ShootingOptions {
    orbit::ShootingOptions {
        tol: s.f("tol"),
        max_iter: s.u("max_iter").unwrap_or(20) as usize,
        segments: s.u("segments").unwrap_or(1) as usize,
        ..orbit::ShootingOptions::default()
    }
}

/// Shoot the periodic orbit of `sys` (period `period`) from `guess` with the settings of
/// [`shoot_settings`]: the problem, the orbit and the record of [`SHOOT_OUT`].
pub(crate) fn shoot_on<S: system::SecondOrderSystem>(
    what: &'static str,
    sys: S,
    period: f64,
    guess: &[f64],
    s: &Settings,
) -> Result<(orbit::OrbitProblem<S>, orbit::PeriodicOrbit, Record), PointError> {
    let p = orbit::OrbitProblem::new(sys, period)
        .and_then(|p| p.with_flow_options(flow_options(s)))
        .map_err(|e| PointError::Compute(format!("{what} orbit problem: {e}")))?;
    let opts = shooting_options(s);
    let o = p
        .shoot(guess, &opts)
        .map_err(|e| PointError::Compute(format!("{what} shooting: {e}")))?;
    let mut mu = o.floquet.multipliers.clone();
    mu.sort_by(|x, y| y[0].dhypot(y[1]).total_cmp(&x[0].dhypot(x[1])));
    let m = |i: usize, j: usize| mu.get(i).map_or(f64::NAN, |c| c[j]);
    let mut r = Record::new();
    r.push("events_per_period", "1", o.events.len() as f64)
        .push("max_multiplier", "1", o.floquet.max_modulus)
        .push("mu1_re", "1", m(0, 0))
        .push("mu1_im", "1", m(0, 1))
        .push("mu2_re", "1", m(1, 0))
        .push("mu2_im", "1", m(1, 1))
        .push("stable", "1", if o.floquet.stable { 1.0 } else { 0.0 })
        .push("det_phi_plus_i", "1", o.floquet.test_period_doubling)
        .push("newton_iterations", "1", o.iterations as f64)
        .push("residual", "1", o.residual);
    Ok((p, o, r))
}

/// [`shoot_on`], the record only.
pub(crate) fn shoot_any<S: system::SecondOrderSystem>(
    what: &'static str,
    sys: S,
    period: f64,
    guess: &[f64],
    s: &Settings,
) -> Result<Record, PointError> {
    shoot_on(what, sys, period, guess, s).map(|(_, _, r)| r)
}
