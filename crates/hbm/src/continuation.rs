//! Pseudo-arclength continuation in one parameter, with fold detection and stability.

use crate::solve::{NonlinearEquations, solve_equations};
use crate::{HbmError, HbmProblem, Method, PeriodicSolution, SecondOrderSystem, SolverOptions};
use nalgebra::{DMatrix, DVector};

/// The parameter `λ` that is continued.
#[derive(Debug, Clone, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum ContinuationParameter {
    /// The base frequency `ω` of the basis.
    Frequency,
    /// A named system parameter, set through [`SecondOrderSystem::set_parameter`].
    Named(String),
}

/// Options of [`HbmProblem::continuation`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ContinuationOptions {
    /// First arclength step (in the unscaled `(z, λ)` space).
    pub initial_step: f64,
    /// Smallest step before giving up.
    pub min_step: f64,
    /// Largest step.
    pub max_step: f64,
    /// Maximum number of branch points (including the first).
    pub max_points: usize,
    /// Corrector tolerance on `‖r‖₂`.
    pub tolerance: f64,
    /// Corrector iteration limit.
    pub corrector_max_iters: u64,
    /// Compute Floquet stability of every point.
    pub stability: bool,
    /// RK4 steps per period for stability (`None` = default of [`HbmProblem::stability`]).
    pub stability_steps: Option<usize>,
}

impl Default for ContinuationOptions {
    fn default() -> Self {
        Self {
            initial_step: 0.01,
            min_step: 1e-6,
            max_step: 0.1,
            max_points: 500,
            tolerance: 1e-9,
            corrector_max_iters: 10,
            stability: true,
            stability_steps: None,
        }
    }
}

impl ContinuationOptions {
    fn validate(&self) -> Result<(), HbmError> {
        use crate::error::check_positive;
        check_positive("initial_step", self.initial_step)?;
        check_positive("min_step", self.min_step)?;
        check_positive("max_step", self.max_step)?;
        check_positive("tolerance", self.tolerance)?;
        if self.min_step > self.max_step {
            return Err(HbmError::InvalidParameter {
                name: "min_step",
                bound: "<= max_step",
                value: self.min_step,
            });
        }
        if self.max_points < 1 || self.corrector_max_iters < 1 {
            return Err(HbmError::InvalidParameter {
                name: "max_points and corrector_max_iters",
                bound: ">= 1",
                value: 0.0,
            });
        }
        Ok(())
    }
}

/// One point on a branch.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct BranchPoint {
    /// Parameter value `λ`.
    pub parameter: f64,
    /// `dλ/ds` of the unit tangent (changes sign at folds).
    pub dparameter_ds: f64,
    /// The periodic solution (with stability if requested).
    pub solution: PeriodicSolution,
}

/// A fold (turning point, saddle-node) detected between two branch points.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FoldPoint {
    /// The fold lies between points `after_index` and `after_index + 1`.
    pub after_index: usize,
    /// Parameter at the fold, from a quadratic fit of `λ(s)` using `dλ/ds` at both ends.
    pub parameter: f64,
}

/// Why a continuation stopped.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum ContinuationEnd {
    /// The end value of the parameter was reached.
    ReachedEnd,
    /// `max_points` were computed.
    MaxPoints,
    /// The branch turned back and left the interval on the side of the start value.
    LeftRange {
        /// Parameter of the last point.
        parameter: f64,
    },
    /// The corrector failed even at the minimum step.
    StepTooSmall {
        /// Parameter of the last accepted point.
        parameter: f64,
    },
    /// The first point did not converge.
    InitialSolveFailed {
        /// Residual norm reached.
        residual_norm: f64,
    },
}

/// A computed solution branch.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Branch {
    /// The continued parameter.
    pub parameter: ContinuationParameter,
    /// Points in arclength order.
    pub points: Vec<BranchPoint>,
    /// Folds found.
    pub folds: Vec<FoldPoint>,
    /// Why it stopped.
    pub end: ContinuationEnd,
}

fn set_lambda<S: SecondOrderSystem>(
    p: &mut HbmProblem<S>,
    which: &ContinuationParameter,
    lambda: f64,
) -> Result<(), HbmError> {
    match which {
        ContinuationParameter::Frequency => p.set_omega(lambda),
        ContinuationParameter::Named(name) => p.set_parameter(name, lambda),
    }
}

/// `[r(z, λ); t·(y − y_pred)] = 0`.
struct Augmented<'a, S> {
    p: &'a mut HbmProblem<S>,
    which: &'a ContinuationParameter,
    pred: Vec<f64>,
    tangent: Vec<f64>,
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
}

impl<S: SecondOrderSystem> NonlinearEquations for Augmented<'_, S> {
    fn dim(&self) -> usize {
        self.p.n_unknowns() + 1
    }
    fn residual(&mut self, y: &[f64], r: &mut [f64]) -> Result<(), HbmError> {
        let nz = self.p.n_unknowns();
        set_lambda(self.p, self.which, y[nz])?;
        self.p.residual(&y[..nz], &mut r[..nz])?;
        r[nz] = (0..=nz)
            .map(|i| self.tangent[i] * (y[i] - self.pred[i]))
            .sum();
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
            jac[(nz, i)] = self.tangent[i];
        }
        r[nz] = (0..=nz)
            .map(|i| self.tangent[i] * (y[i] - self.pred[i]))
            .sum();
        Ok(())
    }
}

/// Unit tangent at `y` oriented along `border` (`border·t > 0`).
fn tangent<S: SecondOrderSystem>(
    aug: &mut Augmented<'_, S>,
    y: &[f64],
    border: &[f64],
) -> Result<Option<Vec<f64>>, HbmError> {
    let nz = aug.p.n_unknowns();
    aug.tangent = border.to_vec();
    aug.pred = y.to_vec();
    let mut jac = DMatrix::zeros(nz + 1, nz + 1);
    let mut r = vec![0.0; nz + 1];
    aug.residual_and_jacobian(y, &mut r, &mut jac)?;
    let mut rhs = DVector::zeros(nz + 1);
    rhs[nz] = 1.0;
    if !jac.lu().solve_mut(&mut rhs) {
        return Ok(None);
    }
    let norm = rhs.norm();
    if !norm.is_finite() || norm == 0.0 {
        return Ok(None);
    }
    Ok(Some((rhs / norm).as_slice().to_vec()))
}

impl<S: SecondOrderSystem> HbmProblem<S> {
    /// Pseudo-arclength continuation of the periodic response in `parameter` from
    /// `(z0, lambda0)` towards `lambda_end`, going round folds.
    ///
    /// Predictor: tangent step `y + s t`; corrector: Newton (argmin `Executor`) on
    /// `r(z, λ) = 0, t·(y − y_pred) = 0`; `∂r/∂λ` by central differences; step control: ×1.5
    /// after easy corrections (≤ 3 iterations), ×0.5 after failures or tangent turns above ~25°.
    /// Folds are reported where `dλ/ds` changes sign. The problem is left at the last
    /// parameter value.
    ///
    /// # Errors
    /// Invalid options or parameter values, wrong `z0` length.
    pub fn continuation(
        &mut self,
        parameter: ContinuationParameter,
        z0: &[f64],
        lambda0: f64,
        lambda_end: f64,
        options: &ContinuationOptions,
    ) -> Result<Branch, HbmError> {
        options.validate()?;
        if !lambda_end.is_finite() {
            return Err(HbmError::InvalidParameter {
                name: "lambda_end",
                bound: "finite",
                value: lambda_end,
            });
        }
        let nz = self.n_unknowns();
        set_lambda(self, &parameter, lambda0)?;
        let corr = SolverOptions {
            method: Method::Newton,
            tolerance: options.tolerance,
            max_iters: options.corrector_max_iters.max(25),
        };
        let first = self.solve(z0, &corr)?;
        let mut branch = Branch {
            parameter: parameter.clone(),
            points: Vec::new(),
            folds: Vec::new(),
            end: ContinuationEnd::MaxPoints,
        };
        if !first.converged {
            branch.end = ContinuationEnd::InitialSolveFailed {
                residual_norm: first.residual_norm,
            };
            return Ok(branch);
        }
        let dir = if lambda_end >= lambda0 { 1.0 } else { -1.0 };
        let mut y: Vec<f64> = first.coefficients.clone();
        y.push(lambda0);
        let mut border = vec![0.0; nz + 1];
        border[nz] = dir;
        let which = parameter.clone();
        let mut aug = Augmented {
            p: self,
            which: &which,
            pred: Vec::new(),
            tangent: Vec::new(),
            jz: DMatrix::zeros(nz, nz),
            rp: vec![0.0; nz],
            rm: vec![0.0; nz],
        };
        let Some(mut t) = tangent(&mut aug, &y, &border)? else {
            branch.end = ContinuationEnd::StepTooSmall { parameter: lambda0 };
            return Ok(branch);
        };
        let push = |aug: &mut Augmented<'_, S>,
                    y: &[f64],
                    t: &[f64],
                    sol: PeriodicSolution,
                    branch: &mut Branch|
         -> Result<(), HbmError> {
            let mut sol = sol;
            set_lambda(aug.p, aug.which, y[nz])?;
            sol.omega = aug.p.omega();
            if options.stability {
                sol.stability = Some(aug.p.stability(&sol, options.stability_steps)?);
            }
            branch.points.push(BranchPoint {
                parameter: y[nz],
                dparameter_ds: t[nz],
                solution: sol,
            });
            Ok(())
        };
        push(&mut aug, &y, &t, first, &mut branch)?;
        let mut s = options.initial_step.min(options.max_step);
        let (lo, hi) = (lambda0.min(lambda_end), lambda0.max(lambda_end));
        while branch.points.len() < options.max_points {
            let pred: Vec<f64> = (0..=nz).map(|i| y[i] + s * t[i]).collect();
            aug.pred = pred.clone();
            aug.tangent = t.clone();
            let attempt = solve_equations(
                Augmented {
                    p: &mut *aug.p,
                    which: aug.which,
                    pred: pred.clone(),
                    tangent: t.clone(),
                    jz: std::mem::replace(&mut aug.jz, DMatrix::zeros(0, 0)),
                    rp: vec![0.0; nz],
                    rm: vec![0.0; nz],
                },
                pred,
                &SolverOptions {
                    method: Method::Newton,
                    tolerance: options.tolerance,
                    max_iters: options.corrector_max_iters,
                },
            );
            let accepted = match attempt {
                Ok((report, eq)) => {
                    aug.jz = eq.jz;
                    if report.converged {
                        let yn = report.x.clone();
                        match tangent(&mut aug, &yn, &t)? {
                            Some(tn) => {
                                let cos: f64 = (0..=nz).map(|i| tn[i] * t[i]).sum();
                                if cos < 0.9 && s > 2.0 * options.min_step {
                                    None
                                } else {
                                    Some((report, yn, tn))
                                }
                            }
                            None => None,
                        }
                    } else {
                        None
                    }
                }
                Err(_) => {
                    aug.jz = DMatrix::zeros(nz, nz);
                    None
                }
            };
            let Some((report, yn, tn)) = accepted else {
                s *= 0.5;
                if s < options.min_step {
                    set_lambda(aug.p, aug.which, y[nz])?;
                    branch.end = ContinuationEnd::StepTooSmall { parameter: y[nz] };
                    return Ok(branch);
                }
                continue;
            };
            if t[nz] * tn[nz] < 0.0 {
                let sigma = t[nz] * s / (t[nz] - tn[nz]);
                branch.folds.push(FoldPoint {
                    after_index: branch.points.len() - 1,
                    parameter: y[nz] + 0.5 * t[nz] * sigma,
                });
            }
            set_lambda(aug.p, aug.which, yn[nz])?;
            let truncation = aug.p.truncation_indicator(&yn[..nz]).unwrap_or(f64::NAN);
            let sol = PeriodicSolution {
                basis: aug.p.basis().clone(),
                omega: aug.p.omega(),
                n_dof: aug.p.n_dof(),
                coefficients: yn[..nz].to_vec(),
                converged: true,
                iterations: report.iterations,
                residual_norm: report.residual_norm,
                truncation,
                termination: report.termination.clone(),
                stability: None,
            };
            push(&mut aug, &yn, &tn, sol, &mut branch)?;
            if report.iterations <= 3 {
                s = (s * 1.5).min(options.max_step);
            } else if report.iterations >= 7 {
                s = (s * 0.7).max(options.min_step);
            }
            y = yn;
            t = tn;
            if y[nz] > hi || y[nz] < lo {
                branch.end = if (y[nz] - lambda_end) * dir >= 0.0 {
                    ContinuationEnd::ReachedEnd
                } else {
                    ContinuationEnd::LeftRange { parameter: y[nz] }
                };
                return Ok(branch);
            }
        }
        branch.end = ContinuationEnd::MaxPoints;
        Ok(branch)
    }
}
