//! Pseudo-arclength continuation of the harmonic-balance response in the input speed `ω₁`,
//! through the `hbm` engine (`HbmProblem::continuation` in the base frequency `ω̄_c`).
//!
//! `ω₁` enters the model only through `ω̄_c = ω₁/(i_j ω_n)`: `ω̄_e = Z₂ ω̄_c` and the Eq. (22)
//! amplitudes follow it ([`Model::with_omega_c`], called by the engine through
//! `SecondOrderSystem::set_base_frequency`), so continuing the base frequency is continuing
//! the speed. Folds (`dω₁/ds = 0`) are the jump points; multipliers flag stability
//! ([`BranchStability`]).

use serde::{Deserialize, Serialize};

use super::harmonic::{
    HbmOptions, HbmResponse, HbmStart, problem_of, rattle_of, residual_scale, solve_hbm_with,
};
use super::integrate::{IntegrationOptions, integrate};
use super::model::{Model, Rattle};
use super::params::Parameters;
use crate::Error;

/// How the stability of the branch points is judged.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum BranchStability {
    /// No stability.
    None,
    /// The engine's Floquet multipliers: the variational equation along the harmonic-balance
    /// orbit (RK4). Reliable without back-flank contact; on bilateral (impacting) orbits the
    /// truncated orbit's spurious contact switching makes the linearisation blow up
    /// (`|μ| ~ 1e30` at ω₁ = 250 rad/s, K = 65, where time integration converges to the
    /// orbit) — see `R-LIU-STABILITY` in `docs/readings/liu.md`.
    Floquet,
    /// Multipliers of the time-integration Poincaré map: the 2×2 monodromy by finite
    /// differences (perturbations `1e-7 b̄` of `q` and `q'`) of one period of the ODE started
    /// at the harmonic-balance state `q(0), q'(0)`. Three integrations per point.
    Shooting,
}

/// [`BranchStability::Shooting`]: multipliers of the one-period map of Eq. (9) at the state of
/// `response` at `τ = 0`, as `[Re μ, Im μ]`; the largest modulus decides stability.
///
/// # Errors
/// Integration failures.
pub fn shooting_multipliers(model: &Model, response: &HbmResponse) -> Result<[[f64; 2]; 2], Error> {
    let (q, v) = response.solution.state_at(0.0);
    let (q0, v0) = (q[0], v[0]);
    let period = model.period();
    let run = |q: f64, v: f64| -> Result<(f64, f64), Error> {
        let r = integrate(
            model,
            &IntegrationOptions {
                transient_periods: 0.0,
                record_periods: 1.0,
                sample_step: period / 16.0,
                max_step: 0.25,
                rtol: 1e-11,
                initial: Some((q, v)),
            },
        )?;
        match (r.q.last(), r.v.last()) {
            (Some(&q), Some(&v)) => Ok((q, v)),
            _ => Err(Error::Solver("liu2021: empty shooting run".into())),
        }
    };
    let d = 1e-7 * model.backlash.max(1e-12);
    let (qb, vb) = run(q0, v0)?;
    let (qa, va) = run(q0 + d, v0)?;
    let (qv, vv) = run(q0, v0 + d)?;
    let (a, b, c, e) = ((qa - qb) / d, (qv - qb) / d, (va - vb) / d, (vv - vb) / d);
    let tr = a + e;
    let det = a * e - b * c;
    let disc = 0.25 * tr * tr - det;
    Ok(if disc >= 0.0 {
        let r = disc.sqrt();
        [[0.5 * tr + r, 0.0], [0.5 * tr - r, 0.0]]
    } else {
        let i = (-disc).sqrt();
        [[0.5 * tr, i], [0.5 * tr, -i]]
    })
}

/// [`shooting_multipliers`] as the workspace's one stability type (`orbit::Stability`: largest
/// modulus and the verdict under `system::STABILITY_TOLERANCE`).
///
/// # Errors
/// Integration failures.
pub fn shooting_stability(
    model: &Model,
    response: &HbmResponse,
) -> Result<orbit::Stability, Error> {
    Ok(orbit::Stability::from_multipliers(
        shooting_multipliers(model, response)?.to_vec(),
    ))
}

/// Settings of [`continue_in_speed`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SpeedContinuationOptions {
    /// Basis, AFT samples and tolerance (relative, as in [`HbmOptions::tol`]) of every point.
    pub hbm: HbmOptions,
    /// Input speed `ω₁` \[rad/s\] where the continuation stops.
    pub omega1_end: f64,
    /// First step, as an `ω₁` increment \[rad/s\] (converted to `ω̄_c`; the engine's
    /// arclength also counts the change of the coefficients).
    pub initial_step: f64,
    /// Largest step \[rad/s\] (same convention).
    pub max_step: f64,
    /// Smallest step \[rad/s\] before the engine gives up.
    pub min_step: f64,
    /// Maximum number of branch points.
    pub max_points: usize,
    /// Stability of every point.
    pub stability: BranchStability,
    /// RK4 steps per period `2π/ω̄_c` for [`BranchStability::Floquet`] (≈ 5 per unit τ
    /// resolves the contact frequency `√F ≤ 1.4` at Table 1 values).
    pub stability_steps: usize,
}

impl Default for SpeedContinuationOptions {
    fn default() -> Self {
        Self {
            hbm: HbmOptions::default(),
            omega1_end: 250.0,
            initial_step: 0.5,
            max_step: 2.0,
            min_step: 1e-5,
            max_points: 600,
            stability: BranchStability::Shooting,
            stability_steps: 8192,
        }
    }
}

/// One point of a continued branch.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpeedBranchPoint {
    /// Input speed `ω₁` \[rad/s\].
    pub omega1: f64,
    /// Rattle state and ppv of the periodic response.
    pub rattle: Rattle,
    /// Stability verdict (`max |μ| ≤ 1 + 1e-6`); `None` without stability.
    pub stable: Option<bool>,
    /// Largest multiplier modulus; `None` without stability.
    pub max_multiplier: Option<f64>,
    /// The harmonic-balance solution (coefficients at this speed).
    pub solution: hbm::PeriodicSolution,
}

/// A fold (turning point) of a branch: where `dω₁/ds` changes sign.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SpeedFold {
    /// Input speed `ω₁` \[rad/s\] at the fold (quadratic fit of `ω₁(s)`).
    pub omega1: f64,
    /// The fold lies between points `after_index` and `after_index + 1`.
    pub after_index: usize,
}

/// A branch of periodic responses over `ω₁`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpeedBranch {
    /// Points in arclength order.
    pub points: Vec<SpeedBranchPoint>,
    /// Folds (turning points: the jumps).
    pub folds: Vec<SpeedFold>,
    /// Why the engine stopped.
    pub end: hbm::ContinuationEnd,
}

/// Continue the harmonic-balance response of `params` from `params.omega1` to
/// `options.omega1_end` by pseudo-arclength continuation, going round folds.
///
/// The first point is solved from `start` (a warm start picks the branch). Non-convergence is
/// reported in [`SpeedBranch::end`], not as an error.
///
/// # Errors
/// Invalid parameters or options.
pub fn continue_in_speed(
    params: &Parameters,
    options: &SpeedContinuationOptions,
    start: HbmStart<'_>,
) -> Result<SpeedBranch, Error> {
    let model = params.model()?;
    let to_omega1 = params.omega1 / model.omega_c;
    let positive = |name: &'static str, v: f64| {
        if v > 0.0 && v.is_finite() {
            Ok(())
        } else {
            Err(Error::invalid(
                format!("liu2021.continuation.{name}"),
                "> 0",
                v,
            ))
        }
    };
    positive("omega1_end", options.omega1_end)?;
    positive("initial_step", options.initial_step)?;
    positive("max_step", options.max_step)?;
    positive("min_step", options.min_step)?;
    let first = solve_hbm_with(&model, &options.hbm, start)?;
    let basis = options.hbm.basis.to_hbm(model.z2)?;
    let mut problem = problem_of(&model, basis, options.hbm.samples)?;
    let copts = hbm::ContinuationOptions {
        initial_step: options.initial_step / to_omega1,
        min_step: options.min_step / to_omega1,
        max_step: options.max_step / to_omega1,
        max_points: options.max_points,
        tolerance: options.hbm.tol * residual_scale(&model),
        corrector_max_iters: options.hbm.max_iter.max(1),
        stability: options.stability == BranchStability::Floquet,
        stability_steps: Some(options.stability_steps.max(4)),
    };
    let branch = problem
        .continuation(
            hbm::ContinuationParameter::Frequency,
            &first.solution.coefficients,
            model.omega_c,
            options.omega1_end / to_omega1,
            &copts,
        )
        .map_err(Error::from)?;
    let points = branch
        .points
        .iter()
        .map(|p| {
            let m = model.with_omega_c(p.parameter)?;
            let rattle = rattle_of(&m, &p.solution);
            let stability = match options.stability {
                BranchStability::None => None,
                BranchStability::Floquet => p.solution.stability.clone(),
                BranchStability::Shooting => {
                    let r = HbmResponse {
                        solution: p.solution.clone(),
                        rattle,
                    };
                    Some(shooting_stability(&m, &r)?)
                }
            };
            Ok(SpeedBranchPoint {
                omega1: p.parameter * to_omega1,
                rattle,
                stable: stability.as_ref().map(|s| s.stable),
                max_multiplier: stability.map(|s| s.max_modulus),
                solution: p.solution.clone(),
            })
        })
        .collect::<Result<Vec<_>, Error>>()?;
    Ok(SpeedBranch {
        points,
        folds: branch
            .folds
            .iter()
            .map(|f| SpeedFold {
                omega1: f.parameter * to_omega1,
                after_index: f.after_index,
            })
            .collect(),
        end: branch.end,
    })
}

/// Shooting stability ([`BranchStability::Shooting`], three integrations per point) of a
/// branch continued without it, on a thinned subset: the first point and then every point at
/// least `spacing` rad/s of `ω₁` from the last one taken, in arclength order. The points are
/// evaluated in parallel and written back in order, so the branch is bit-identical for any
/// thread count; the points not taken keep `stable = None`. `params` is the parameter set the
/// branch was continued from (its `ω̄_c/ω₁` ratio maps each point's `ω₁` to its model).
///
/// # Errors
/// `spacing` not finite or negative, invalid parameters, integration failures.
pub fn add_branch_stability(
    params: &Parameters,
    branch: &mut SpeedBranch,
    spacing: f64,
) -> Result<(), Error> {
    if !(spacing.is_finite() && spacing >= 0.0) {
        return Err(Error::invalid(
            "liu2021.stability_spacing",
            ">= 0 and finite",
            spacing,
        ));
    }
    let mut last = f64::NAN;
    let picked: Vec<usize> = (0..branch.points.len())
        .filter(|&i| {
            let w = branch.points[i].omega1;
            let take = last.is_nan() || (w - last).abs() >= spacing;
            if take {
                last = w;
            }
            take
        })
        .collect();
    let base_model = params.model()?;
    let to_wc = base_model.omega_c / params.omega1;
    let points = &branch.points;
    let verdicts: Vec<orbit::Stability> = timestep::sweep(
        &picked,
        |&i| {
            let pt = &points[i];
            let m = base_model.with_omega_c(pt.omega1 * to_wc)?;
            let r = HbmResponse {
                solution: pt.solution.clone(),
                rattle: pt.rattle,
            };
            shooting_stability(&m, &r)
        },
        None,
    )
    .into_iter()
    .collect::<Result<_, Error>>()?;
    for (&i, s) in picked.iter().zip(verdicts) {
        branch.points[i].max_multiplier = Some(s.max_modulus);
        branch.points[i].stable = Some(s.stable);
    }
    Ok(())
}
