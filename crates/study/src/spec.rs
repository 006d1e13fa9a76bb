//! The vocabulary of study files: sweeps, the wall-clock limit of a point, and (re-exported
//! from the model contract, [`models::contract`]) values, methods, solver settings, limits and
//! the serde helpers that set any model parameter by its Rust name.

use serde::{Deserialize, Serialize};

use crate::error::Error;

pub use models::contract::{
    Limits, MAX_POINTS_BOUND, MAX_SECONDS_BOUND, MAX_STEPS_BOUND, Method, Point, Solver, Value,
    apply_overrides, apply_values, camel_to_kebab, choice, display_name, field_names,
    kebab_to_camel, variant_names,
};

/// Longest study name (bytes).
pub const MAX_NAME_LEN: usize = 64;
/// Most values one sweep may have.
pub const MAX_SWEEP_VALUES: usize = 100_000;
/// The reason of a point stopped by [`Limits::max_seconds_per_point`] (the start of its message).
pub const TIME_LIMIT: &str = "time limit";

/// One swept parameter: a range (`from`, `to`, `steps`, linear) or explicit `values` (numbers,
/// or names for a choice such as `variant`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sweep {
    /// Parameter or choice name (see `geardyn models`).
    pub parameter: String,
    /// Start of a linear range.
    pub from: Option<f64>,
    /// End of a linear range (inclusive).
    pub to: Option<f64>,
    /// Number of points of the range (2 ..= [`MAX_SWEEP_VALUES`]).
    pub steps: Option<i64>,
    /// Explicit values (instead of a range).
    pub values: Option<Vec<Value>>,
}

impl Sweep {
    /// The swept values, in order. Errors name the sweep and the bound.
    pub fn points(&self) -> Result<Vec<Value>, Error> {
        let bad = |m: String| Error::StudyFile(format!("sweep of `{}`: {m}", self.parameter));
        let v = match (&self.values, self.from, self.to, self.steps) {
            (Some(v), None, None, None) => {
                if v.len() > MAX_SWEEP_VALUES {
                    return Err(bad(format!(
                        "{} values, at most {MAX_SWEEP_VALUES} allowed",
                        v.len()
                    )));
                }
                v.clone()
            }
            (None, Some(a), Some(b), Some(n)) => {
                if !(2..=MAX_SWEEP_VALUES as i64).contains(&n) {
                    return Err(bad(format!(
                        "steps must be in [2, {MAX_SWEEP_VALUES}], got {n}"
                    )));
                }
                if !(a.is_finite() && b.is_finite()) {
                    return Err(bad(format!("from and to must be finite, got {a} and {b}")));
                }
                // (b − a) may overflow for |a|, |b| near f64::MAX: interpolate without it.
                let n = n as usize;
                (0..n)
                    .map(|i| {
                        let t = i as f64 / (n - 1) as f64;
                        Value::Num(a * (1.0 - t) + b * t)
                    })
                    .collect()
            }
            _ => {
                return Err(bad(
                    "give either `values = [...]` or all of `from`, `to`, `steps`".to_owned(),
                ));
            }
        };
        if v.is_empty() {
            return Err(bad("no values".to_owned()));
        }
        for x in &v {
            x.check_finite(&format!("sweep of `{}`: every value", self.parameter))?;
        }
        Ok(v)
    }
}

/// Run `job` under a wall-clock limit of `seconds` (`None`: on the calling thread, no limit).
///
/// Two layers stop a point that runs too long:
///
/// 1. **Cooperative.** The job runs with a [`system::deadline`] in force on its thread, so the
///    engines stop themselves at the limit: the integrators between steps, the harmonic balance
///    solvers between iterations, shooting between flow steps. A job that ends after the
///    limit, however it ends, becomes `Err` with a message starting with [`TIME_LIMIT`] and
///    naming what the engine reported.
/// 2. **Watchdog.** The job runs on a thread of its own and the caller waits at most
///    `seconds × 1.1 + 1 s` for it, for work the deadline does not reach (a model that hands
///    work to other threads). Over that, `Err` with [`TIME_LIMIT`] and the caller goes on; the
///    abandoned job ends by itself (every engine has a step budget, [`Limits::max_steps`]) and
///    its result is dropped.
///
/// A panic in the job becomes an `Err` with the panic's message.
pub fn run_with_time_limit<T: Send + 'static>(
    seconds: Option<f64>,
    job: impl FnOnce() -> Result<T, String> + Send + 'static,
) -> Result<T, String> {
    let Some(limit) = seconds else {
        return job();
    };
    let budget =
        std::time::Duration::try_from_secs_f64(limit.max(0.0)).unwrap_or(std::time::Duration::MAX);
    let (tx, rx) = std::sync::mpsc::sync_channel(1);
    // the point's thread charges the caller's work account (steps, RHS calls, CPU time)
    let account = system::account::current();
    let spawned = std::thread::Builder::new()
        .name("geardyn-point".to_owned())
        .spawn(move || {
            let start = std::time::Instant::now();
            let deadline = start.checked_add(budget);
            let r = system::account::scope_opt(account.as_ref(), || {
                system::deadline::scope(deadline, || {
                    std::panic::catch_unwind(std::panic::AssertUnwindSafe(job))
                        .unwrap_or_else(|p| Err(crate::user::panic_message(p.as_ref())))
                })
            });
            let r = if start.elapsed() >= budget {
                Err(match r {
                    Err(e) => format!(
                        "{TIME_LIMIT}: the point ran longer than limits.max_seconds_per_point = \
                         {limit} s and was stopped by its solver ({e})"
                    ),
                    Ok(_) => format!(
                        "{TIME_LIMIT}: the point ran longer than limits.max_seconds_per_point = \
                         {limit} s"
                    ),
                })
            } else {
                r
            };
            // The receiver may have given up (watchdog): nothing to do then.
            let _ = tx.send(r);
        });
    if let Err(e) = spawned {
        return Err(format!("{TIME_LIMIT}: no thread for the point ({e})"));
    }
    let grace = budget
        .checked_mul(11)
        .map(|d| d / 10)
        .and_then(|d| d.checked_add(std::time::Duration::from_secs(1)))
        .unwrap_or(std::time::Duration::MAX);
    match rx.recv_timeout(grace) {
        Ok(r) => r,
        Err(std::sync::mpsc::RecvTimeoutError::Timeout) => Err(format!(
            "{TIME_LIMIT}: the point ran longer than limits.max_seconds_per_point = {limit} s \
             and was abandoned (its solver did not stop at the deadline)"
        )),
        Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => {
            Err("internal error: the point's thread ended without a result".to_owned())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A point under a time limit runs on a thread of its own: its work is still charged to
    /// the caller's account (the cost line of `geardyn study` and the validation's table).
    #[test]
    fn a_time_limited_point_charges_the_callers_account() {
        let account = system::account::Account::new("test");
        for seconds in [None, Some(30.0)] {
            let r = system::account::scope(&account, || {
                run_with_time_limit(seconds, || {
                    system::account::record_steps(5, 1, 30);
                    Ok(7)
                })
            });
            assert_eq!(r, Ok(7));
        }
        let u = account.usage();
        assert_eq!(
            (u.steps_accepted, u.steps_rejected, u.rhs_calls),
            (10, 2, 60)
        );
    }
}
