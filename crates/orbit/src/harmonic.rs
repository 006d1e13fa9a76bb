//! The harmonic-balance corrector of the one continuation: branches of [`HbmProblem`]
//! solutions in the base frequency or a named parameter ([`continue_hbm`]).
//!
//! Unknowns `y = (z, λ)` with `z` the harmonic-balance coefficients; `F(y) = r(z, λ)` the
//! harmonic-balance residual; the corrector is Newton (argmin `Executor`, line search) on the
//! bordered system `[r(z, λ); bᵀ(y − y_p)] = 0` with `∂r/∂λ` by central differences
//! (`h = 10⁻⁶ (1 + |λ|)`) and `b` the tangent (pseudo-arclength) or `e_λ` (natural).

use hbm::{
    HbmError, HbmProblem, Method, NonlinearEquations, PeriodicSolution, SecondOrderSystem,
    SolverOptions, solve_equations,
};
use nalgebra::{DMatrix, DVector};

use crate::error::{OrbitError, check};
use crate::path::{
    self, Branch, BranchPoint, ContinuationOptions, Corrector, Node, StepControl, StopReason,
    bordered_tangent,
};
use crate::problem::Parameter;

/// The harmonic-balance corrector's part of [`ContinuationOptions`] ([`continue_hbm`]): the
/// Newton tolerance and iteration cap of every correction, and the Floquet stability of the
/// points.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct HbmCorrection {
    /// Corrector tolerance on `‖r‖₂`.
    pub tolerance: f64,
    /// Corrector iteration limit (the first point gets at least 25).
    pub max_iters: u64,
    /// Compute Floquet stability of every point.
    pub stability: bool,
    /// RK4 steps per period for stability (`None` = default of [`HbmProblem::stability`]; at
    /// least 4).
    pub stability_steps: Option<usize>,
}

impl Default for HbmCorrection {
    fn default() -> Self {
        Self {
            tolerance: 1e-9,
            max_iters: 10,
            stability: true,
            stability_steps: None,
        }
    }
}

impl HbmCorrection {
    /// Checks every field with a bound (`stability` is a switch; `stability_steps` is raised
    /// to at least 4 by the engine).
    ///
    /// # Errors
    /// [`OrbitError::InvalidInput`] naming the field.
    pub fn validate(&self) -> Result<(), OrbitError> {
        check(
            self.tolerance.is_finite() && self.tolerance > 0.0,
            "HbmCorrection::tolerance",
            "> 0 and finite",
            self.tolerance,
        )?;
        check(
            self.max_iters >= 1,
            "HbmCorrection::max_iters",
            ">= 1",
            self.max_iters as f64,
        )
    }
}

/// Options of [`continue_hbm`]: the one [`ContinuationOptions`] with the harmonic-balance
/// corrector's part (steps in the unscaled `(z, λ)` space).
pub type HbmContinuationOptions = ContinuationOptions<HbmCorrection>;

impl Default for ContinuationOptions<HbmCorrection> {
    /// The shared defaults ([`ContinuationOptions::with_corrector`]).
    fn default() -> Self {
        Self::with_corrector(HbmCorrection::default())
    }
}

impl ContinuationOptions<HbmCorrection> {
    /// Checks every field (the shared ones and the harmonic-balance corrector's).
    ///
    /// # Errors
    /// [`OrbitError::InvalidInput`] naming the field.
    pub fn validate(&self) -> Result<(), OrbitError> {
        self.corrector.validate()?;
        self.validate_steps()
    }
}

fn invalid(name: &'static str, bound: &'static str, value: f64) -> HbmError {
    HbmError::InvalidParameter { name, bound, value }
}

/// An invalid option as the harmonic-balance error [`continue_hbm`] returns (same field name
/// and bound).
fn as_hbm_error(e: OrbitError) -> HbmError {
    match e {
        OrbitError::InvalidInput {
            field,
            bound,
            value,
        } => invalid(field, bound, value),
        _ => invalid("ContinuationOptions", "valid", f64::NAN),
    }
}

fn set_lambda<S: SecondOrderSystem>(
    p: &mut HbmProblem<S>,
    which: &Parameter,
    lambda: f64,
) -> Result<(), HbmError> {
    match which {
        Parameter::BaseFrequency => p.set_omega(lambda),
        Parameter::Named(name) => p.set_parameter(name, lambda),
    }
}

/// `[r(z, λ); b·(y − y_pred)] = 0`.
struct Augmented<'a, S> {
    p: &'a mut HbmProblem<S>,
    which: &'a Parameter,
    pred: Vec<f64>,
    border: Vec<f64>,
    jz: DMatrix<f64>,
    rp: Vec<f64>,
    rm: Vec<f64>,
}

impl<S: SecondOrderSystem> Augmented<'_, S> {
    /// `∂r/∂λ` by central differences at `(z, λ)`; leaves the problem at `λ`.
    fn dr_dlambda(&mut self, z: &[f64], lambda: f64, out: &mut [f64]) -> Result<(), HbmError> {
        let h = 1e-6 * (1.0 + lambda.abs());
        set_lambda(self.p, self.which, lambda + h)?;
        let a = self.p.residual(z, &mut self.rp);
        let b = set_lambda(self.p, self.which, lambda - h)
            .and_then(|()| self.p.residual(z, &mut self.rm));
        set_lambda(self.p, self.which, lambda)?;
        a?;
        b?;
        for i in 0..out.len() {
            out[i] = (self.rp[i] - self.rm[i]) / (2.0 * h);
        }
        Ok(())
    }

    fn constraint(&self, y: &[f64]) -> f64 {
        (0..y.len())
            .map(|i| self.border[i] * (y[i] - self.pred[i]))
            .sum()
    }
}

impl<S: SecondOrderSystem> NonlinearEquations for Augmented<'_, S> {
    fn dim(&self) -> usize {
        self.p.n_unknowns() + 1
    }
    fn residual(&mut self, y: &[f64], r: &mut [f64]) -> Result<(), HbmError> {
        let nz = self.p.n_unknowns();
        set_lambda(self.p, self.which, y[nz])?;
        self.p.residual(&y[..nz], &mut r[..nz])?;
        r[nz] = self.constraint(y);
        Ok(())
    }
    fn residual_and_jacobian(
        &mut self,
        y: &[f64],
        r: &mut [f64],
        jac: &mut DMatrix<f64>,
    ) -> Result<(), HbmError> {
        let nz = self.p.n_unknowns();
        set_lambda(self.p, self.which, y[nz])?;
        let mut jz = std::mem::replace(&mut self.jz, DMatrix::zeros(0, 0));
        let res = self
            .p
            .residual_and_jacobian(&y[..nz], &mut r[..nz], &mut jz);
        jac.view_mut((0, 0), (nz, nz)).copy_from(&jz);
        self.jz = jz;
        res?;
        let mut col = vec![0.0; nz];
        self.dr_dlambda(&y[..nz], y[nz], &mut col)?;
        for i in 0..nz {
            jac[(i, nz)] = col[i];
        }
        for i in 0..=nz {
            jac[(nz, i)] = self.border[i];
        }
        r[nz] = self.constraint(y);
        Ok(())
    }
}

/// What a harmonic-balance correction returns.
#[derive(Debug, Clone)]
struct Raw {
    residual_norm: f64,
    termination: String,
}

/// The harmonic-balance corrector.
struct Harmonic<'a, S> {
    p: &'a mut HbmProblem<S>,
    which: &'a Parameter,
    jz: DMatrix<f64>,
    options: &'a HbmContinuationOptions,
}

impl<S: SecondOrderSystem> Harmonic<'_, S> {
    /// Unit tangent at `y` oriented along `reference`: `None` if the bordered Jacobian is
    /// singular.
    fn tangent(
        &mut self,
        y: &[f64],
        reference: &DVector<f64>,
    ) -> Result<Option<DVector<f64>>, HbmError> {
        let nz = self.p.n_unknowns();
        let mut aug = Augmented {
            p: &mut *self.p,
            which: self.which,
            pred: y.to_vec(),
            border: reference.as_slice().to_vec(),
            jz: std::mem::replace(&mut self.jz, DMatrix::zeros(0, 0)),
            rp: vec![0.0; nz],
            rm: vec![0.0; nz],
        };
        let mut jac = DMatrix::zeros(nz + 1, nz + 1);
        let mut r = vec![0.0; nz + 1];
        let res = aug.residual_and_jacobian(y, &mut r, &mut jac);
        self.jz = aug.jz;
        res?;
        let j = jac.rows(0, nz).into_owned();
        Ok(bordered_tangent(&j, reference))
    }

    /// The solution at `y` with its stability.
    fn solution(
        &mut self,
        y: &[f64],
        iterations: u64,
        raw: &Raw,
    ) -> Result<PeriodicSolution, HbmError> {
        let nz = self.p.n_unknowns();
        set_lambda(self.p, self.which, y[nz])?;
        let truncation = self.p.truncation_indicator(&y[..nz]).unwrap_or(f64::NAN);
        let mut sol = PeriodicSolution {
            basis: self.p.basis().clone(),
            omega: self.p.omega(),
            n_dof: self.p.n_dof(),
            coefficients: y[..nz].to_vec(),
            converged: true,
            iterations,
            residual_norm: raw.residual_norm,
            truncation,
            termination: raw.termination.clone(),
            stability: None,
        };
        self.with_stability(&mut sol)?;
        Ok(sol)
    }

    fn with_stability(&mut self, sol: &mut PeriodicSolution) -> Result<(), HbmError> {
        if self.options.corrector.stability {
            sol.stability = Some(
                self.p
                    .stability(sol, self.options.corrector.stability_steps)?,
            );
        }
        Ok(())
    }
}

impl<S: SecondOrderSystem> Corrector for Harmonic<'_, S> {
    type Raw = Raw;
    type Point = PeriodicSolution;
    type Error = HbmError;

    fn correct(
        &mut self,
        pred: &DVector<f64>,
        border: &DVector<f64>,
        reference: &DVector<f64>,
    ) -> Result<Result<Node<Raw>, OrbitError>, HbmError> {
        let nz = self.p.n_unknowns();
        let attempt = solve_equations(
            Augmented {
                p: &mut *self.p,
                which: self.which,
                pred: pred.as_slice().to_vec(),
                border: border.as_slice().to_vec(),
                jz: std::mem::replace(&mut self.jz, DMatrix::zeros(0, 0)),
                rp: vec![0.0; nz],
                rm: vec![0.0; nz],
            },
            pred.as_slice().to_vec(),
            &SolverOptions {
                method: Method::Newton,
                tolerance: self.options.corrector.tolerance,
                max_iters: self.options.corrector.max_iters,
            },
        );
        let report = match attempt {
            Ok((report, eq)) => {
                self.jz = eq.jz;
                report
            }
            Err(_) => {
                self.jz = DMatrix::zeros(nz, nz);
                return Ok(Err(OrbitError::NotConverged {
                    what: "harmonic-balance corrector",
                    iterations: 0,
                    residual: f64::NAN,
                }));
            }
        };
        if !report.converged {
            return Ok(Err(OrbitError::NotConverged {
                what: "harmonic-balance corrector",
                iterations: usize::try_from(report.iterations).unwrap_or(usize::MAX),
                residual: report.residual_norm,
            }));
        }
        let Some(tangent) = self.tangent(&report.x, reference)? else {
            return Ok(Err(OrbitError::Singular {
                what: "bordered harmonic-balance Jacobian",
            }));
        };
        Ok(Ok(Node {
            y: DVector::from_vec(report.x),
            tangent,
            iterations: report.iterations,
            raw: Raw {
                residual_norm: report.residual_norm,
                termination: report.termination,
            },
        }))
    }

    fn accept(&mut self, node: &Node<Raw>) -> Result<BranchPoint<PeriodicSolution>, HbmError> {
        let nz = self.p.n_unknowns();
        let sol = self.solution(node.y.as_slice(), node.iterations, &node.raw)?;
        Ok(BranchPoint {
            parameter: node.y[nz],
            tangent_parameter: node.tangent[nz],
            stability: sol.stability.clone(),
            orbit: sol,
        })
    }

    fn leave_at(&mut self, y: &DVector<f64>) -> Result<(), HbmError> {
        set_lambda(self.p, self.which, y[self.p.n_unknowns()])
    }
}

/// Continuation of the periodic response of `problem` in `parameter` from `(z0, lambda0)`
/// towards `lambda_end` (pseudo-arclength, going round folds, or natural), through the one
/// loop [`path::trace`] with the harmonic-balance step control
/// ([`StepControl::harmonic`]).
///
/// The first point is solved by Newton from `z0` (at least 25 iterations); its failure is
/// [`StopReason::InitialSolveFailed`]. Folds are reported where `dλ/ds` changes sign. The
/// problem is left at the last parameter value.
///
/// # Errors
/// Invalid options or parameter values, wrong `z0` length.
pub fn continue_hbm<S: SecondOrderSystem>(
    problem: &mut HbmProblem<S>,
    parameter: Parameter,
    z0: &[f64],
    lambda0: f64,
    lambda_end: f64,
    options: &HbmContinuationOptions,
) -> Result<Branch<PeriodicSolution>, HbmError> {
    options.validate().map_err(as_hbm_error)?;
    if !lambda_end.is_finite() {
        return Err(invalid("lambda_end", "finite", lambda_end));
    }
    let nz = problem.n_unknowns();
    set_lambda(problem, &parameter, lambda0)?;
    let corr = SolverOptions {
        method: Method::Newton,
        tolerance: options.corrector.tolerance,
        max_iters: options.corrector.max_iters.max(25),
    };
    let mut first = problem.solve(z0, &corr)?;
    let mut branch = Branch::new(parameter.clone(), 1);
    if !first.converged {
        branch.stop = StopReason::InitialSolveFailed {
            residual_norm: first.residual_norm,
        };
        return Ok(branch);
    }
    let dir = if lambda_end >= lambda0 { 1.0 } else { -1.0 };
    let mut y = first.coefficients.clone();
    y.push(lambda0);
    let y = DVector::from_vec(y);
    let mut border = DVector::zeros(nz + 1);
    border[nz] = dir;
    let mut h = Harmonic {
        p: problem,
        which: &parameter,
        jz: DMatrix::zeros(nz, nz),
        options,
    };
    let Some(t) = h.tangent(y.as_slice(), &border)? else {
        branch.stop = StopReason::StepTooSmall {
            parameter: lambda0,
            cause: Some(OrbitError::Singular {
                what: "bordered harmonic-balance Jacobian at the first point",
            }),
        };
        return Ok(branch);
    };
    set_lambda(h.p, h.which, lambda0)?;
    first.omega = h.p.omega();
    h.with_stability(&mut first)?;
    branch.points.push(BranchPoint {
        parameter: lambda0,
        tangent_parameter: t[nz],
        stability: first.stability.clone(),
        orbit: first.clone(),
    });
    let start = Node {
        y,
        tangent: t,
        iterations: first.iterations,
        raw: Raw {
            residual_norm: first.residual_norm,
            termination: first.termination.clone(),
        },
    };
    let control = StepControl::harmonic(options.initial_step, options.min_step, options.max_step);
    let course = options.course([lambda0.min(lambda_end), lambda0.max(lambda_end)], dir);
    path::trace(&mut h, start, &control, &course, &mut branch)?;
    Ok(branch)
}
