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
    /// Multipliers of the time-integration period map at the harmonic-balance state
    /// `x₀ = (q(0), q'(0))`: the monodromy of the workspace's one shooting
    /// ([`orbit::OrbitProblem::period_map`], variational equations on the event-located
    /// flow, one integration per point), see [`shooting_multipliers`].
    Shooting,
}

/// Largest step in `τ` of the period map. The step-size control sees the state only; the
/// variational equation rides on the same steps, so its global error is set by this bound:
/// at Fig. 11 points the monodromy is within 6e-8 of a converged central difference with
/// 0.05 (4e-7 at 160 rad/s with 0.1; on the linear mesh 1.4e-7 relative, 3e-5 with 0.1,
/// 8e-4 with 0.25) — tested in `tests/it/liu2021.rs`.
const PERIOD_MAP_MAX_STEP: f64 = 0.05;

/// Integrator of the period map: relative tolerance `10⁻¹¹` and steps of at most
/// [`PERIOD_MAP_MAX_STEP`]; the contact changes are located as events.
fn period_map_problem(model: &Model) -> Result<orbit::OrbitProblem<Model>, Error> {
    let period = model.period();
    let flow = orbit::FlowOptions {
        rtol: 1e-11,
        max_step_fraction: (PERIOD_MAP_MAX_STEP / period).min(1.0),
        ..orbit::FlowOptions::default()
    };
    Ok(orbit::OrbitProblem::new(*model, period)?.with_flow_options(flow)?)
}

/// [`BranchStability::Shooting`]: the Floquet multipliers (with their conditioning) of the
/// one-period map of Eq. (9) at the state of `response` at `τ = 0`, by the shooting monodromy
/// of `orbit` ([`orbit::OrbitProblem::period_map`]; the state is not corrected, so the
/// multipliers are those of the period map at the harmonic-balance state).
///
/// With `x = (q, q')`, Eq. (9) `q'' + 2ζ q' + F(τ) f(q; b̄(τ)) = f_r(τ)` and its variational
/// equation read
///
/// ```text
/// x' = V(τ, x) = ( q',  f_r(τ) − 2ζ q' − F(τ) f(q; b̄(τ)) )
/// Φ' = A Φ,   A = [[0, 1], [−F(τ) f'(q; b̄), −2ζ]],   f' = 1 in contact (|q| > b̄), 0 in the gap,
/// ```
///
/// integrated over `T = 2π/ω̄_c` from `Φ(0) = I` with the gap edges `h± = q ∓ b̄(τ)` located as
/// events. At an edge the state is continuous (no reset, `G = I`) and the restoring force
/// is continuous in `q` (`f(±b̄; b̄) = 0` from both sides; only its slope jumps), so
/// the vector field is continuous across the edge, `V⁺ = V⁻`, and the saltation matrix
///
/// ```text
/// S = I + (V⁺ − V⁻) ∇hᵀ / (∇hᵀ V⁻ + ∂h/∂τ) = I
/// ```
///
/// (also for the moving edge of a time-varying `b̄`, which only enters the denominator): the
/// contacts enter the monodromy `Φ(T)` only through `A` switching between its two values
/// along the orbit (tested: `‖S − I‖ ≈ 0` at every contact change of a bilateral Fig. 11
/// orbit).
///
/// # Errors
/// Integration failures, a non-finite monodromy.
pub fn shooting_multipliers(
    model: &Model,
    response: &HbmResponse,
) -> Result<orbit::Floquet, Error> {
    Ok(shooting_period_map(model, response)?.floquet)
}

/// The period map of Eq. (9) at the state of `response` at `τ = 0` (monodromy, multipliers,
/// contact events, periodicity defect): the record behind [`shooting_multipliers`].
///
/// # Errors
/// Integration failures, a non-finite monodromy.
pub fn shooting_period_map(
    model: &Model,
    response: &HbmResponse,
) -> Result<orbit::PeriodicOrbit, Error> {
    let (q, v) = response.solution.state_at(0.0);
    Ok(period_map_problem(model)?.period_map(&[q[0], v[0]], 1)?)
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
    Ok(shooting_multipliers(model, response)?.stability())
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
/// folds are the jumps, in rad/s). Every parameter is `ω₁` in rad/s, the swept speed of the
/// study: the points, the folds and the stop reason ([`orbit::Branch::stop`],
/// [`orbit::StopReason::parameter`]). The engine's dimensionless base frequency of any of
/// them is `ω̄_c = ω₁ · ω̄_c,0/ω₁,0` (the ratio of the parameter set the branch was continued
/// from, [`Model::omega_c`] over [`Parameters::omega1`]); [`Model::with_omega_c`] of it is
/// the point's model.
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
        predictor: orbit::Predictor::Arclength,
        stall: None,
        corrector: orbit::HbmCorrection {
            tolerance: options.hbm.tol * residual_scale(&model),
            max_iters: options.hbm.max_iter.max(1),
            stability: options.stability == BranchStability::Floquet,
            stability_steps: Some(options.stability_steps.max(4)),
        },
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

/// Shooting stability ([`BranchStability::Shooting`], one variational integration per point) of a
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
