//! The Lyapunov spectrum of a settled response: a long-window statistic of any model that is a
//! [`SecondOrderSystem`] (Liu, Yu's 6-DOF pair, the generic pair).
//!
//! From a state on the attractor (the end of a model's settled time integration), the
//! event-located variational flow of [`orbit`] runs `windows` forcing periods `T`, each split
//! into `m` windows (`m = ⌈|tr M⁻¹(C + ∂g/∂q')| T/10⌉`, so that a window contracts volumes by
//! at most about `e^{−10}` and `Φ_j` keeps its contracting directions above rounding); after
//! each window the tangent basis is re-orthonormalised by QR and `ln R_ii` accumulated
//! ([`orbit::lyapunov_qr`], saltation matrices at every event: the identity at the backlash
//! kinks):
//!
//! ```text
//! λ_i = (1 / NT) Σ_{j<N} ln R_j,ii,     Φ_j Q_j = Q_{j+1} R_j
//! ```
//!
//! Each value comes with its convergence: the spread (max − min) of the running estimate over
//! the last quarter of the windows, and whether it is within `5 % |λ| + 10⁻³/T`
//! ([`orbit::LyapunovSpectrum::converged`]). A chaos verdict may use `λ1 > 0` only when it
//! converged; `λ1 T` (nepers per forcing period) compares across models whatever their time
//! unit. On a chaotic attractor that spread says how settled one run's average is, not how far
//! the next stretch of trajectory lands: [`settled_lyapunov_batches`] runs consecutive batches
//! and [`lyapunov_batch_spread`] puts their difference into the uncertainty (batch means).

use orbit::{
    FlowOptions, LyapunovOptions, LyapunovSpectrum, MAX_LYAPUNOV_WINDOWS, OrbitError, OrbitProblem,
};
use system::SecondOrderSystem;

/// Most exponents a study may ask for (the state dimension of Yu's 6-DOF pair).
pub const MAX_LYAPUNOV_EXPONENTS: usize = 12;

/// Settings of [`settled_lyapunov`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LyapunovWindowOptions {
    /// Forcing periods `N` (windows of one period each), in `[4, 100000]`.
    pub windows: usize,
    /// Exponents `k`, in `[1, min(2n, MAX_LYAPUNOV_EXPONENTS)]`.
    pub exponents: usize,
    /// Relative tolerance of the variational flow (`FlowOptions::rtol`).
    pub rtol: f64,
}

impl Default for LyapunovWindowOptions {
    /// 200 periods, the largest exponent, `rtol = 1e-9`.
    fn default() -> Self {
        Self {
            windows: 200,
            exponents: 1,
            rtol: 1e-9,
        }
    }
}

/// Renormalisations per forcing period: `m = ⌈|tr M⁻¹(C + ∂g/∂q')| T / 10⌉` at the start
/// state, in `[1, 1024]`. A window then contracts volumes by about `e^{−10}` at most, so the
/// contracting directions of `Φ_j` stay above the rounding of its expanding ones (over one Liu
/// period, `2ζT ≈ 54`: `e^{−54}` is below `ε ≈ 2e-16`, and `Φ Q` would lose them).
fn windows_per_period<S: SecondOrderSystem>(sys: &S, period: f64, t0: f64, x0: &[f64]) -> usize {
    let n = sys.n_dof();
    let (mut dq, mut dv) = (vec![0.0; n * n], vec![0.0; n * n]);
    sys.force_jacobian(t0, &x0[..n], &x0[n..], &mut dq, &mut dv);
    let c = sys.damping() + nalgebra::DMatrix::from_row_slice(n, n, &dv);
    let tr = sys.mass().lu().solve(&c).map_or(0.0, |a| a.trace());
    let m = (tr.abs() * period / 10.0).ceil();
    if m.is_finite() && m >= 1.0 {
        (m as usize).min(1024)
    } else {
        1
    }
}

/// The Lyapunov spectrum of the response of `sys` (forcing period `period`) from the state
/// `x0 = (q, q')` at time `t0` (a state of the settled response): `windows` forcing periods
/// (the first fifth a QR warm-up, not accumulated), each split into `m` renormalisation windows (`m` from the dissipation, see
/// `windows_per_period`: 1 for a lightly damped flow), convergence judged over the last
/// quarter of them within `5 % |λ| + 10⁻³/T`.
///
/// # Errors
/// Invalid options (named with their bounds: fewer than 4 or more than 100000 windows, `k`
/// outside `[1, min(2n, 12)]`, `rtol` outside `(0, 1)`), a non-finite state, an integration
/// failure of the flow.
pub fn settled_lyapunov<S: SecondOrderSystem>(
    sys: S,
    period: f64,
    t0: f64,
    x0: &[f64],
    o: &LyapunovWindowOptions,
) -> Result<LyapunovSpectrum, OrbitError> {
    let mut b = settled_lyapunov_batches(sys, period, t0, x0, o, 1)?;
    b.pop().ok_or(OrbitError::InvalidInput {
        field: "lyapunov_batches",
        bound: "in [1, 16]",
        value: 0.0,
    })
}

/// Most batches of [`settled_lyapunov_batches`].
pub const MAX_LYAPUNOV_BATCHES: usize = 16;

/// [`settled_lyapunov`] as `batches` consecutive runs (batch means): batch `b` starts where
/// batch `b − 1` ended, at `t0 + b·N·T`, each with its own QR warm-up (the first fifth of its
/// `N` periods) and its own convergence record. On a chaotic attractor a finite-time exponent
/// fluctuates from one stretch of trajectory to the next by more than the spread of its own
/// running estimate (which measures how settled the average is, not how far another stretch
/// lands); the batches measure that fluctuation: [`lyapunov_batch_spread`]. Batch 0 is
/// [`settled_lyapunov`] bit for bit.
///
/// # Errors
/// As [`settled_lyapunov`]; `batches` outside `[1, 16]`.
pub fn settled_lyapunov_batches<S: SecondOrderSystem>(
    sys: S,
    period: f64,
    t0: f64,
    x0: &[f64],
    o: &LyapunovWindowOptions,
    batches: usize,
) -> Result<Vec<LyapunovSpectrum>, OrbitError> {
    if !(1..=MAX_LYAPUNOV_BATCHES).contains(&batches) {
        return Err(OrbitError::InvalidInput {
            field: "lyapunov_batches",
            bound: "in [1, 16]",
            value: batches as f64,
        });
    }
    if !(4..=100_000).contains(&o.windows) {
        return Err(OrbitError::InvalidInput {
            field: "lyapunov_windows",
            bound: "in [4, 100000]",
            value: o.windows as f64,
        });
    }
    if o.exponents > MAX_LYAPUNOV_EXPONENTS {
        return Err(OrbitError::InvalidInput {
            field: "lyapunov_exponents",
            bound: "in [1, 12]",
            value: o.exponents as f64,
        });
    }
    let n = sys.n_dof();
    if x0.len() != 2 * n {
        return Err(OrbitError::DimensionMismatch {
            what: "state (q, q')",
            expected: 2 * n,
            got: x0.len(),
        });
    }
    let m = windows_per_period(&sys, period, t0, x0).min(MAX_LYAPUNOV_WINDOWS / o.windows);
    let flow = FlowOptions {
        rtol: o.rtol,
        ..FlowOptions::default()
    };
    let p = OrbitProblem::new(sys, period)?.with_flow_options(flow)?;
    let windows = o.windows * m;
    // the first fifth aligns the QR basis (not accumulated)
    let warmup = (o.windows / 5) * m;
    let opts = LyapunovOptions {
        window: period / m as f64,
        windows,
        warmup,
        exponents: o.exponents,
        last: ((windows - warmup) / 4).max(1),
        // the bound atol/τ stays 10⁻³ per period
        atol: 1e-3 / m as f64,
        ..LyapunovOptions::default()
    };
    let mut out = Vec::with_capacity(batches);
    let mut x = x0.to_vec();
    for b in 0..batches {
        let (s, end) = p.lyapunov(t0 + (b * o.windows) as f64 * period, &x, &opts)?;
        out.push(s);
        x = end;
    }
    Ok(out)
}

/// `(mean, uncertainty)` of `λ_i` over batches of [`settled_lyapunov_batches`]: the mean of the
/// batches' `λ_i`, and the larger of their spread (`max − min` over the batches) and the
/// largest running-estimate spread of a batch ([`LyapunovSpectrum::spread_last`]). `None`
/// without batches or without exponent `i`.
pub fn lyapunov_batch_spread(batches: &[LyapunovSpectrum], i: usize) -> Option<(f64, f64)> {
    let values: Vec<f64> = batches
        .iter()
        .map(|s| s.exponents.get(i).copied())
        .collect::<Option<_>>()?;
    if values.is_empty() {
        return None;
    }
    let mean = values.iter().sum::<f64>() / values.len() as f64;
    let (lo, hi) = values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });
    let own = batches
        .iter()
        .filter_map(|s| s.spread_last.get(i).copied())
        .fold(0.0_f64, f64::max);
    Some((mean, (hi - lo).max(own)))
}

/// One line of evidence: `λ1 = v ± s per unit time (λ1T = …; converged|not converged over N
/// periods)`, `period` the forcing period `T`.
pub fn describe_lyapunov(s: &LyapunovSpectrum, period: f64) -> String {
    let n = (s.running.len() as f64 * s.window / period).round();
    let l = s.largest();
    format!(
        "λ1 = {} ± {} (λ1·T = {} per period; {} over {n} periods)",
        system::format::fmt_sig(l, 3),
        system::format::fmt_sig(s.spread_last[0], 2),
        system::format::fmt_sig(l * period, 3),
        if s.converged {
            "converged"
        } else {
            "not converged"
        }
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use math::DetMath;
    use nalgebra::DMatrix;

    /// Ueda's oscillator `q'' + 0.05 q' + q³ = 7.5 cos t` (Ueda 1979/1980: a chaotic attractor;
    /// λ1 ≈ 0.1 per unit time).
    #[derive(Debug, Clone, Copy)]
    struct Ueda;

    impl SecondOrderSystem for Ueda {
        fn n_dof(&self) -> usize {
            1
        }
        fn mass(&self) -> DMatrix<f64> {
            DMatrix::identity(1, 1)
        }
        fn damping(&self) -> DMatrix<f64> {
            DMatrix::from_element(1, 1, 0.05)
        }
        fn nonlinear_force(&self, _t: f64, q: &[f64], _v: &[f64], g: &mut [f64]) {
            g[0] = q[0] * q[0] * q[0];
        }
        fn force_jacobian(&self, _t: f64, q: &[f64], _v: &[f64], dq: &mut [f64], dv: &mut [f64]) {
            dq[0] = 3.0 * q[0] * q[0];
            dv[0] = 0.0;
        }
        fn forcing(&self, t: f64, f: &mut [f64]) {
            f[0] = 7.5 * t.dcos();
        }
    }

    /// The QR (variational) λ1 against the two-trajectory estimate of
    /// [`timestep::largest_lyapunov`] on the same settled start: both estimate the same
    /// exponent, but their base trajectories separate (different integrators on a chaotic
    /// flow), so they agree only statistically: over `NT = 300·2π ≈ 1900` time units the
    /// finite-time estimate fluctuates by about `D/√(NT)` with `D ≲ 0.5`, ≈ 0.01; tolerance
    /// 0.03 (about 3σ). Both are positive (chaos) and the volume law holds: `Σλ = −0.05`.
    /// `(T, t0, x)`: a state on Ueda's attractor after 50 periods from `(2.5, 0)`.
    fn on_ueda_attractor() -> (f64, f64, Vec<f64>) {
        let period = 2.0 * std::f64::consts::PI;
        let x = OrbitProblem::new(Ueda, period)
            .unwrap()
            .flow(0.0, &[2.5, 0.0], 50.0 * period, false)
            .unwrap()
            .state;
        (period, 50.0 * period, x)
    }

    #[test]
    fn qr_and_two_trajectory_largest_exponents_agree_on_a_chaotic_duffing() {
        let (period, t0, x) = on_ueda_attractor();
        let o = LyapunovWindowOptions {
            windows: 300,
            exponents: 2,
            rtol: 1e-9,
        };
        let s = settled_lyapunov(Ueda, period, t0, &x, &o).unwrap();
        let sys = timestep::FirstOrder(timestep::Mechanical::new(Ueda).unwrap());
        let two = timestep::largest_lyapunov(
            &sys,
            t0,
            &x,
            &timestep::LyapunovOptions {
                d0: 1e-8,
                interval: period,
                n_intervals: 300,
            },
            &timestep::Options {
                rtol: 1e-10,
                atol: 1e-12,
                ..timestep::Options::default()
            },
        )
        .unwrap();
        let (qr, tt) = (s.largest(), two.value);
        assert!(qr > 0.05 && tt > 0.05, "λ1: QR {qr}, two-trajectory {tt}");
        assert!((qr - tt).abs() < 0.03, "λ1: QR {qr}, two-trajectory {tt}");
        assert!((s.sum() + 0.05).abs() < 1e-6, "Σλ = {}", s.sum());
        assert!(describe_lyapunov(&s, period).starts_with("λ1 = "));
    }

    /// Batches: batch 0 is the single run bit for bit, batch 1 goes on from its end (so it is
    /// the single run started there at `t0 + N T`), and the batch uncertainty covers both the
    /// batches' difference and their own spreads. On Ueda's attractor both are positive.
    #[test]
    fn batches_continue_the_run_and_their_spread_covers_them() {
        let (period, t0, x) = on_ueda_attractor();
        let o = LyapunovWindowOptions {
            windows: 40,
            exponents: 1,
            rtol: 1e-8,
        };
        let b = settled_lyapunov_batches(Ueda, period, t0, &x, &o, 2).unwrap();
        assert_eq!(b.len(), 2);
        assert_eq!(b[0], settled_lyapunov(Ueda, period, t0, &x, &o).unwrap());
        // batch 1 from the end of batch 0 (Ueda's dissipation gives one window per period:
        // the settings below are the ones `settled_lyapunov` derives for it)
        let (_, end) = OrbitProblem::new(Ueda, period)
            .unwrap()
            .with_flow_options(FlowOptions {
                rtol: 1e-8,
                ..FlowOptions::default()
            })
            .unwrap()
            .lyapunov(
                t0,
                &x,
                &LyapunovOptions {
                    window: period,
                    windows: 40,
                    warmup: 8,
                    exponents: 1,
                    last: 8,
                    atol: 1e-3,
                    ..LyapunovOptions::default()
                },
            )
            .unwrap();
        assert_eq!(
            b[1],
            settled_lyapunov(Ueda, period, t0 + 40.0 * period, &end, &o).unwrap()
        );
        let (mean, u) = lyapunov_batch_spread(&b, 0).unwrap();
        let (a, c) = (b[0].largest(), b[1].largest());
        assert!(a > 0.0 && c > 0.0, "λ1 of the batches: {a}, {c}");
        assert_eq!(mean.to_bits(), (0.5 * (a + c)).to_bits());
        assert!(u >= (a - c).abs() && u >= b[0].spread_last[0] && u >= b[1].spread_last[0]);
        assert!(lyapunov_batch_spread(&b, 1).is_none());
        assert!(lyapunov_batch_spread(&[], 0).is_none());
        for bad in [0, MAX_LYAPUNOV_BATCHES + 1] {
            match settled_lyapunov_batches(Ueda, period, t0, &x, &o, bad) {
                Err(OrbitError::InvalidInput { field, .. }) => {
                    assert_eq!(field, "lyapunov_batches");
                }
                other => panic!("{other:?}"),
            }
        }
    }

    #[test]
    fn bad_settings_are_named() {
        let bad = |o: LyapunovWindowOptions| match settled_lyapunov(Ueda, 1.0, 0.0, &[0.0, 0.0], &o)
        {
            Err(OrbitError::InvalidInput { field, .. }) => field,
            other => panic!("{other:?}"),
        };
        let d = LyapunovWindowOptions::default();
        assert_eq!(
            bad(LyapunovWindowOptions { windows: 3, ..d }),
            "lyapunov_windows"
        );
        assert_eq!(
            bad(LyapunovWindowOptions { exponents: 13, ..d }),
            "lyapunov_exponents"
        );
        assert_eq!(
            bad(LyapunovWindowOptions { exponents: 3, ..d }),
            "LyapunovOptions::exponents"
        );
        assert_eq!(
            bad(LyapunovWindowOptions { exponents: 0, ..d }),
            "LyapunovOptions::exponents"
        );
        assert_eq!(
            bad(LyapunovWindowOptions { rtol: 0.0, ..d }),
            "FlowOptions::rtol"
        );
        assert!(matches!(
            settled_lyapunov(Ueda, 1.0, 0.0, &[f64::NAN, 0.0], &d),
            Err(OrbitError::NonFinite { .. })
        ));
    }
}
