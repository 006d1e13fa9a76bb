//! The Lyapunov option of the time-stepping methods (off by default: it costs about one more
//! integration of `lyapunov_periods` periods, per batch, with the `2n × 2n` variational
//! equations): the settings, the columns and the one computation
//! ([`crate::response::settled_lyapunov_batches`]) from the end state of a model's settled
//! time integration.

use super::{Kind, PointError, Record, SettingDef, Settings};
use crate::response::{
    LyapunovWindowOptions, MAX_LYAPUNOV_BATCHES, MAX_LYAPUNOV_EXPONENTS, lyapunov_batch_spread,
    settled_lyapunov_batches,
};
use orbit::LyapunovSpectrum;

/// Setting `lyapunov`: `"on"` adds the Lyapunov columns.
pub(crate) const LYAPUNOV: SettingDef = SettingDef {
    name: "lyapunov",
    kind: Kind::Name {
        options: &["off", "on"],
        default: "off",
    },
    doc: "\"on\": the Lyapunov spectrum of the settled response (QR renormalisation of the \
          event-located variational flow with saltation matrices, renormalised once or more per \
          forcing period, from the end of the time integration) in columns lambda1 … lambda<k>, \
          lambda1_per_period, lambda1_spread, lambda_converged, lambda_sum, \
          lyapunov_events_per_period; \"off\": absent",
};

/// Setting `lyapunov_periods`.
pub(crate) const LYAPUNOV_PERIODS: SettingDef = SettingDef {
    name: "lyapunov_periods",
    kind: Kind::Int {
        lo: 4,
        hi: 100_000,
        default: Some(200),
    },
    doc: "forcing periods of the Lyapunov run (each split into m = ⌈|tr M⁻¹(C + ∂g/∂q')| T/10⌉ \
          renormalisation windows); the spread is taken over the last quarter",
};

/// Setting `lyapunov_exponents`.
pub(crate) const LYAPUNOV_EXPONENTS: SettingDef = SettingDef {
    name: "lyapunov_exponents",
    kind: Kind::Int {
        lo: 1,
        hi: MAX_LYAPUNOV_EXPONENTS as u64,
        default: Some(1),
    },
    doc: "number k of exponents (at most the state dimension 2n)",
};

/// Setting `lyapunov_rtol`.
pub(crate) const LYAPUNOV_RTOL: SettingDef = SettingDef {
    name: "lyapunov_rtol",
    kind: Kind::Num {
        lo: 1e-14,
        hi: 1e-4,
        default: 1e-9,
    },
    doc: "relative tolerance of the variational flow of the Lyapunov run",
};

/// Setting `lyapunov_batches`.
pub(crate) const LYAPUNOV_BATCHES: SettingDef = SettingDef {
    name: "lyapunov_batches",
    kind: Kind::Int {
        lo: 1,
        hi: MAX_LYAPUNOV_BATCHES as u64,
        default: Some(1),
    },
    doc: "consecutive batches of lyapunov_periods periods each, the next one on from the end \
          of the last (batch means): the exponent columns are the batches' mean, lambda1_spread \
          the larger of their spread and a batch's own running spread (the finite-time \
          fluctuation on a chaotic attractor, which one run's running spread understates), \
          lambda_converged 1 only when every batch converged; 1: one run",
};

/// A study's Lyapunov run: the window settings and the number of consecutive batches.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct LyapunovPlan {
    /// Periods, exponents and tolerance of each batch.
    pub window: LyapunovWindowOptions,
    /// Consecutive batches (`lyapunov_batches`).
    pub batches: usize,
}

/// The names of the exponent columns.
const LAMBDA: [&str; MAX_LYAPUNOV_EXPONENTS] = [
    "lambda1", "lambda2", "lambda3", "lambda4", "lambda5", "lambda6", "lambda7", "lambda8",
    "lambda9", "lambda10", "lambda11", "lambda12",
];

/// The Lyapunov run of a study (`None`: `lyapunov = "off"`).
pub(crate) fn lyapunov_plan(s: &Settings) -> Option<LyapunovPlan> {
    (s.name("lyapunov") == "on").then(|| LyapunovPlan {
        window: LyapunovWindowOptions {
            windows: s.u("lyapunov_periods").unwrap_or(200) as usize,
            exponents: s.u("lyapunov_exponents").unwrap_or(1) as usize,
            rtol: s.f("lyapunov_rtol"),
        },
        batches: s.u("lyapunov_batches").unwrap_or(1) as usize,
    })
}

/// The Lyapunov columns for `k` exponents; `rate` is the unit of an exponent (per unit time of
/// the model: `"1"` for a dimensionless time, `"1/s"`).
pub(crate) fn lyapunov_columns(k: usize, rate: &'static str) -> Vec<(&'static str, &'static str)> {
    let mut v: Vec<(&str, &str)> = LAMBDA[..k.min(MAX_LYAPUNOV_EXPONENTS)]
        .iter()
        .map(|n| (*n, rate))
        .collect();
    v.extend([
        ("lambda1_per_period", "1"),
        ("lambda1_spread", rate),
        ("lambda_converged", "1"),
        ("lambda_sum", rate),
        ("lyapunov_events_per_period", "1"),
    ]);
    v
}

/// The plan at the integrator tolerance divided by `factor` (the accuracy check's repeat).
pub(crate) fn tighter(o: &LyapunovPlan, factor: f64) -> LyapunovPlan {
    LyapunovPlan {
        window: LyapunovWindowOptions {
            rtol: o.window.rtol / factor,
            ..o.window
        },
        ..*o
    }
}

/// Integrator steps the Lyapunov run may take (the flow's step is at most 1/50 of a period),
/// for the study's step limit.
pub(crate) fn lyapunov_steps(o: &LyapunovPlan) -> f64 {
    50.0 * (o.window.windows * o.batches) as f64
}

/// The Lyapunov batches of `sys` from `(t0, x0)` (the end of the settled integration).
pub(crate) fn run_lyapunov<S: system::SecondOrderSystem>(
    what: &str,
    sys: S,
    period: f64,
    (t0, x0): (f64, &[f64]),
    o: &LyapunovPlan,
) -> Result<Vec<LyapunovSpectrum>, PointError> {
    settled_lyapunov_batches(sys, period, t0, x0, &o.window, o.batches)
        .map_err(|e| PointError::Compute(format!("{what} Lyapunov run: {e}")))
}

/// Appends the batches to `rec` in the columns of [`lyapunov_columns`] (`period`: the window):
/// each exponent the batches' mean, `lambda1_spread` their uncertainty
/// ([`lyapunov_batch_spread`]), converged when every batch is; one batch as it is.
pub(crate) fn push_lyapunov(
    rec: &mut Record,
    batches: &[LyapunovSpectrum],
    period: f64,
    rate: &str,
) {
    let k = batches.first().map_or(0, |s| s.exponents.len());
    let mut l1 = (f64::NAN, f64::NAN);
    let mut sum = 0.0;
    for (i, n) in LAMBDA.iter().enumerate().take(k) {
        let (mean, u) = lyapunov_batch_spread(batches, i).unwrap_or((f64::NAN, f64::NAN));
        if i == 0 {
            l1 = (mean, u);
        }
        sum += mean;
        rec.push(n, rate, mean);
    }
    let periods: f64 = batches
        .iter()
        .map(|s| s.running.len() as f64 * s.window / period)
        .sum();
    let events: usize = batches.iter().map(|s| s.events).sum();
    let converged = !batches.is_empty() && batches.iter().all(|s| s.converged);
    rec.push("lambda1_per_period", "1", l1.0 * period)
        .push("lambda1_spread", rate, l1.1)
        .push("lambda_converged", "1", if converged { 1.0 } else { 0.0 })
        .push("lambda_sum", rate, sum)
        .push("lyapunov_events_per_period", "1", events as f64 / periods);
}
