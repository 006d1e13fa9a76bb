//! The settings and method list the spur-pair models share (`yu2021`, `generic-pair`): one
//! definition, so that the generic pair does not import a paper's registry.

use super::{Kind, Method, MethodInfo, SettingDef, outs, outs_stepped};

/// Mesh periods discarded (time stepping of the spur-pair models).
pub(crate) const TRANSIENT_PERIODS: SettingDef = SettingDef {
    name: "transient_periods",
    kind: Kind::Int {
        lo: 0,
        hi: 100_000,
        default: Some(200),
    },
    doc: "mesh periods discarded",
};

/// Mesh periods recorded (time stepping of the spur-pair models).
pub(crate) const RECORD_PERIODS: SettingDef = SettingDef {
    name: "record_periods",
    kind: Kind::Int {
        lo: 1,
        hi: 10_000,
        default: Some(20),
    },
    doc: "mesh periods recorded",
};

/// AFT samples per period (harmonic balance of the spur-pair models; default: the model's).
pub(crate) const AFT_SAMPLES: SettingDef = SettingDef {
    name: "samples",
    kind: Kind::Int {
        lo: 6,
        hi: 65_536,
        default: None,
    },
    doc: "AFT samples per period (≥ 4H + 2)",
};

/// The two methods of the spur-pair models: time stepping (with an initial state) and HBM.
pub(crate) fn time_stepping_and_hbm(
    ts: (&[SettingDef], &[(&str, &str)]),
    initial: &'static str,
    hbm: (&[SettingDef], &[(&str, &str)]),
) -> Vec<MethodInfo> {
    vec![
        MethodInfo {
            method: Method::TimeStepping,
            settings: ts.0.to_vec(),
            outputs: outs_stepped(ts.1, false),
            initial: Some(initial),
        },
        MethodInfo {
            method: Method::Hbm,
            settings: hbm.0.to_vec(),
            outputs: outs(hbm.1),
            initial: None,
        },
    ]
}
