//! Pseudo-arclength continuation of the harmonic-balance response in the input speed `ω₁`:
//! a thin use of the workspace's one continuation (`orbit::continue_hbm` in the base
//! frequency `ω̄_c`, the Liu harmonic-balance problem as corrector), mapped to `ω₁`.
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

/// The orbit of a point of a continued speed branch (the branch point's
/// [`parameter`](orbit::BranchPoint::parameter) is the input speed `ω₁` \[rad/s\], its
/// [`stability`](orbit::BranchPoint::stability) the one stability type).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpeedPoint {
    /// Rattle state and ppv of the periodic response.
    pub rattle: Rattle,
    /// The harmonic-balance solution (coefficients at this speed).
    pub solution: hbm::PeriodicSolution,
}

/// One point of a continued branch: `ω₁` \[rad/s\], stability, rattle and solution.
pub type SpeedBranchPoint = orbit::BranchPoint<SpeedPoint>;

/// A branch of periodic responses over `ω₁` \[rad/s\] (the workspace's one branch type;
/// folds are the jumps, in rad/s). The parameter of [`orbit::Branch::stop`] stays in the
/// engine's `ω̄_c` (as committed in the Fig. 11 run records).
pub type SpeedBranch = orbit::Branch<SpeedPoint>;

/// Continue the harmonic-balance response of `params` from `params.omega1` to
/// `options.omega1_end` by pseudo-arclength continuation, going round folds: the one
/// continuation ([`orbit::continue_hbm`] in the base frequency `ω̄_c`), mapped to `ω₁`.
///
/// The first point is solved from `start` (a warm start picks the branch). Non-convergence is
/// reported in [`orbit::Branch::stop`], not as an error.
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
    let copts = orbit::HbmContinuationOptions {
        initial_step: options.initial_step / to_omega1,
        min_step: options.min_step / to_omega1,
        max_step: options.max_step / to_omega1,
        max_points: options.max_points,
        tolerance: options.hbm.tol * residual_scale(&model),
        corrector_max_iters: options.hbm.max_iter.max(1),
        stability: options.stability == BranchStability::Floquet,
        stability_steps: Some(options.stability_steps.max(4)),
        predictor: orbit::Predictor::Arclength,
    };
    let branch = orbit::continue_hbm(
        &mut problem,
        orbit::Parameter::BaseFrequency,
        &first.solution.coefficients,
        model.omega_c,
        options.omega1_end / to_omega1,
        &copts,
    )
    .map_err(Error::from)?;
    branch.try_map(
        |p| {
            let m = model.with_omega_c(p.parameter)?;
            let rattle = rattle_of(&m, &p.orbit);
            let stability = match options.stability {
                BranchStability::None => None,
                BranchStability::Floquet => p.orbit.stability.clone(),
                BranchStability::Shooting => {
                    let r = HbmResponse {
                        solution: p.orbit.clone(),
                        rattle,
                    };
                    Some(shooting_stability(&m, &r)?)
                }
            };
            Ok(orbit::BranchPoint {
                parameter: p.parameter * to_omega1,
                tangent_parameter: p.tangent_parameter,
                stability,
                orbit: SpeedPoint {
                    rattle,
                    solution: p.orbit.clone(),
                },
            })
        },
        |w| w * to_omega1,
    )
}

/// Shooting stability ([`BranchStability::Shooting`], three integrations per point) of a
/// branch continued without it, on a thinned subset: the first point and then every point at
/// least `spacing` rad/s of `ω₁` from the last one taken, in arclength order. The points are
/// evaluated in parallel and written back in order, so the branch is bit-identical for any
/// thread count; the points not taken keep `stability = None`. `params` is the parameter set the
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
            let w = branch.points[i].parameter;
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
            let m = base_model.with_omega_c(pt.parameter * to_wc)?;
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
        branch.points[i].stability = Some(s);
    }
    Ok(())
}
