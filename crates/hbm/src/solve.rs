//! Newton (with backtracking line search) and Broyden as argmin solvers.

use crate::{BlockedLu, DenseLu, HbmError};
use argmin::core::{
    Executor, IterState, KV, Problem, Solver, State, TerminationReason, TerminationStatus,
};
use nalgebra::{DMatrix, DVector};

/// A square nonlinear system `r(x) = 0` with a Jacobian, as seen by [`Newton`] and [`Broyden`].
pub trait NonlinearEquations {
    /// Number of unknowns (= number of equations).
    fn dim(&self) -> usize;
    /// Evaluate `r(x)`.
    ///
    /// # Errors
    /// Implementation-defined (non-finite values, bad parameters).
    fn residual(&mut self, x: &[f64], r: &mut [f64]) -> Result<(), HbmError>;
    /// Evaluate `r(x)` and `∂r/∂x`.
    ///
    /// # Errors
    /// Implementation-defined.
    fn residual_and_jacobian(
        &mut self,
        x: &[f64],
        r: &mut [f64],
        jac: &mut DMatrix<f64>,
    ) -> Result<(), HbmError>;
}

/// The argmin state used by the solvers: parameter and residual vectors, cost = `‖r‖₂`.
pub type SolverState = IterState<Vec<f64>, (), (), (), Vec<f64>, f64>;

/// Which nonlinear solver to use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum Method {
    /// Newton's method with the analytic Jacobian and a backtracking line search.
    #[default]
    Newton,
    /// Broyden's ("good") method with inverse updates, started from the analytic Jacobian
    /// (Liu et al. 2021, Sect. 2.5). Restarts from a fresh Jacobian when a step fails.
    Broyden,
    /// Jacobian-free Newton–Krylov for large bases: each Newton step solved by GMRES on exact
    /// AFT Jacobian-vector products with a harmonic-block preconditioner (the force Jacobians'
    /// period means), no dense Jacobian; the same line search as [`Method::Newton`]. Bounds of
    /// the inner solve: [`KrylovOptions::default`](crate::KrylovOptions) (or
    /// [`HbmProblem::solve_newton_krylov`](crate::HbmProblem::solve_newton_krylov)); a linear
    /// solve that misses its tolerance is [`HbmError::KrylovNotConverged`]. Only an
    /// [`HbmProblem`](crate::HbmProblem) can take it: [`solve_equations`] on other equations
    /// runs [`Method::Newton`] instead. On a Duffing oscillator it is faster than the dense path
    /// from `H ≈ 30` on and 130× faster at `H = 400` (see [`Method::Auto`]); a weakly
    /// preconditioned (strongly non-smooth) problem needs more products per step.
    NewtonKrylov,
    /// [`Method::NewtonKrylov`] for problems with at least [`AUTO_KRYLOV_UNKNOWNS`] unknowns,
    /// [`Method::Newton`] below (the crossover measured in `docs/performance/hbm.md`).
    Auto,
}

/// Number of unknowns from which [`Method::Auto`] takes [`Method::NewtonKrylov`]: `H = 50` of a
/// one-DOF full basis. The measured crossover of the dense and Jacobian-free paths on a Duffing
/// oscillator lies between `H = 20` (dense 1.5× faster) and `H = 50` (Krylov 2.4× faster);
/// `docs/performance/hbm.md` has the table.
pub const AUTO_KRYLOV_UNKNOWNS: usize = 101;

/// Options of a nonlinear solve.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SolverOptions {
    /// Solver.
    pub method: Method,
    /// Converged when `‖r‖₂ ≤ tolerance` (absolute, in the units of the equations).
    pub tolerance: f64,
    /// Maximum number of iterations.
    pub max_iters: u64,
}

impl Default for SolverOptions {
    fn default() -> Self {
        Self {
            method: Method::Newton,
            tolerance: 1e-10,
            max_iters: 50,
        }
    }
}

impl SolverOptions {
    /// Validate the options.
    ///
    /// # Errors
    /// Non-positive or NaN tolerance, zero iterations.
    pub fn validate(&self) -> Result<(), HbmError> {
        crate::error::check_positive("tolerance", self.tolerance)?;
        if self.max_iters == 0 {
            return Err(HbmError::InvalidParameter {
                name: "max_iters",
                bound: ">= 1",
                value: 0.0,
            });
        }
        Ok(())
    }
}

/// How a nonlinear solve ended.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SolveReport {
    /// The final iterate.
    pub x: Vec<f64>,
    /// Whether `‖r‖₂ ≤ tolerance` was reached.
    pub converged: bool,
    /// Iterations taken.
    pub iterations: u64,
    /// Final `‖r‖₂`.
    pub residual_norm: f64,
    /// argmin's termination reason, in words.
    pub termination: String,
}

pub(crate) fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

fn op<O>(problem: &mut Problem<O>) -> Result<&mut O, argmin::core::Error> {
    problem.problem.as_mut().ok_or_else(|| {
        HbmError::Solver {
            message: "problem missing".into(),
        }
        .into()
    })
}

/// Newton's method with backtracking (Armijo) line search, as an argmin [`Solver`].
#[derive(Debug, Clone)]
pub struct Newton {
    tolerance: f64,
    jac: DMatrix<f64>,
    r: Vec<f64>,
    trial: Vec<f64>,
    dense_lu: DenseLu,
    blocked: BlockedLu,
}

impl Newton {
    /// A Newton solver that stops when `‖r‖₂ ≤ tolerance`.
    ///
    /// # Errors
    /// Tolerance not finite and > 0.
    pub fn new(tolerance: f64) -> Result<Self, HbmError> {
        crate::error::check_positive("tolerance", tolerance)?;
        Ok(Self {
            tolerance,
            jac: DMatrix::zeros(0, 0),
            r: Vec::new(),
            trial: Vec::new(),
            dense_lu: DenseLu::Auto,
            blocked: BlockedLu::empty(),
        })
    }

    /// Factor the Jacobian with `lu` ([`DenseLu::Auto`] unless set).
    #[must_use]
    pub fn with_dense_lu(mut self, lu: DenseLu) -> Self {
        self.dense_lu = lu;
        self
    }
}

fn init_state<O: NonlinearEquations>(
    problem: &mut Problem<O>,
    mut state: SolverState,
) -> Result<(SolverState, Vec<f64>), argmin::core::Error> {
    let x = state.take_param().ok_or_else(|| HbmError::Solver {
        message: "no initial guess".into(),
    })?;
    let o = op(problem)?;
    if x.len() != o.dim() {
        return Err(HbmError::DimensionMismatch {
            what: "initial guess",
            expected: o.dim(),
            got: x.len(),
        }
        .into());
    }
    let mut r = vec![0.0; x.len()];
    o.residual(&x, &mut r)?;
    let c = norm(&r);
    Ok((state.param(x).cost(c), r))
}

/// Backtracking line search along `dx`: returns the accepted step length or `None`.
pub(crate) fn line_search<O: NonlinearEquations>(
    o: &mut O,
    x: &[f64],
    dx: &[f64],
    f0: f64,
    trial: &mut Vec<f64>,
    r_out: &mut [f64],
) -> Result<Option<f64>, HbmError> {
    let mut alpha = 1.0;
    trial.resize(x.len(), 0.0);
    for _ in 0..12 {
        for i in 0..x.len() {
            trial[i] = x[i] + alpha * dx[i];
        }
        match o.residual(trial, r_out) {
            Ok(()) => {
                let f = norm(r_out);
                if f.is_finite() && f <= (1.0 - 1e-4 * alpha) * f0 {
                    return Ok(Some(alpha));
                }
            }
            // a step into a region where the model is not defined: shorten it
            Err(HbmError::NonFinite { .. }) => {}
            Err(e) => return Err(e),
        }
        alpha *= 0.5;
    }
    Ok(None)
}

/// The current iterate, taken out of the state.
fn take_iterate(state: &mut SolverState) -> Result<Vec<f64>, argmin::core::Error> {
    state.take_param().ok_or_else(|| {
        HbmError::Solver {
            message: "no iterate".into(),
        }
        .into()
    })
}

/// Stay at `x` (residual norm `f0`) and stop with `reason`.
fn stop_at(state: SolverState, x: Vec<f64>, f0: f64, reason: &str) -> SolverState {
    state
        .param(x)
        .cost(f0)
        .terminate_with(TerminationReason::SolverExit(reason.into()))
}

/// Accept the line-search trial point: it becomes the iterate and `r_new` the stored residual.
fn accept_trial(
    state: SolverState,
    trial: &[f64],
    r_new: Vec<f64>,
    r: &mut Vec<f64>,
) -> SolverState {
    let f = norm(&r_new);
    *r = r_new;
    state.param(trial.to_vec()).cost(f)
}

/// Converged when the cost `‖r‖₂` is within the tolerance.
fn status(state: &SolverState, tolerance: f64) -> TerminationStatus {
    if state.get_cost() <= tolerance {
        TerminationStatus::Terminated(TerminationReason::SolverConverged)
    } else if ::system::deadline::expired() {
        // Checked between iterations: the thread's wall-clock deadline has passed.
        TerminationStatus::Terminated(TerminationReason::SolverExit(
            ::system::deadline::REASON.into(),
        ))
    } else {
        TerminationStatus::NotTerminated
    }
}

impl<O: NonlinearEquations> Solver<O, SolverState> for Newton {
    fn name(&self) -> &str {
        "Newton (backtracking line search)"
    }

    fn init(
        &mut self,
        problem: &mut Problem<O>,
        state: SolverState,
    ) -> Result<(SolverState, Option<KV>), argmin::core::Error> {
        let (state, r) = init_state(problem, state)?;
        let n = r.len();
        self.jac = DMatrix::zeros(n, n);
        self.r = r;
        Ok((state, None))
    }

    fn next_iter(
        &mut self,
        problem: &mut Problem<O>,
        mut state: SolverState,
    ) -> Result<(SolverState, Option<KV>), argmin::core::Error> {
        let x = take_iterate(&mut state)?;
        let o = op(problem)?;
        o.residual_and_jacobian(&x, &mut self.r, &mut self.jac)?;
        let f0 = norm(&self.r);
        let mut dx = DVector::from_iterator(self.r.len(), self.r.iter().map(|v| -v));
        let solved = if self.dense_lu.uses_blocked(dx.len()) {
            // a singular or non-finite Jacobian stops the solve, as nalgebra's `false` does
            self.blocked.refactor(&self.jac).is_ok()
                && self.blocked.solve_mut(dx.as_mut_slice()).is_ok()
        } else {
            self.jac.clone().lu().solve_mut(&mut dx)
        };
        if !solved || dx.iter().any(|v| !v.is_finite()) {
            return Ok((stop_at(state, x, f0, "singular Jacobian"), None));
        }
        let mut r_new = vec![0.0; self.r.len()];
        match line_search(o, &x, dx.as_slice(), f0, &mut self.trial, &mut r_new)? {
            Some(_) => Ok((accept_trial(state, &self.trial, r_new, &mut self.r), None)),
            None => Ok((stop_at(state, x, f0, "line search failed"), None)),
        }
    }

    fn terminate(&mut self, state: &SolverState) -> TerminationStatus {
        status(state, self.tolerance)
    }
}

/// Broyden's ("good") method with Sherman–Morrison updates of the inverse Jacobian, as an argmin
/// [`Solver`]; the inverse is initialised (and re-initialised after a failed step) from the
/// analytic Jacobian.
#[derive(Debug, Clone)]
pub struct Broyden {
    tolerance: f64,
    inv: DMatrix<f64>,
    r: Vec<f64>,
    trial: Vec<f64>,
    fresh: bool,
    restarts: u64,
}

impl Broyden {
    /// A Broyden solver that stops when `‖r‖₂ ≤ tolerance`.
    ///
    /// # Errors
    /// Tolerance not finite and > 0.
    pub fn new(tolerance: f64) -> Result<Self, HbmError> {
        crate::error::check_positive("tolerance", tolerance)?;
        Ok(Self {
            tolerance,
            inv: DMatrix::zeros(0, 0),
            r: Vec::new(),
            trial: Vec::new(),
            fresh: false,
            restarts: 0,
        })
    }

    /// Number of Jacobian (re)initialisations so far.
    pub fn jacobian_evaluations(&self) -> u64 {
        self.restarts
    }

    fn reinit<O: NonlinearEquations>(&mut self, o: &mut O, x: &[f64]) -> Result<bool, HbmError> {
        let n = x.len();
        let mut jac = DMatrix::zeros(n, n);
        o.residual_and_jacobian(x, &mut self.r, &mut jac)?;
        self.restarts += 1;
        self.fresh = true;
        match jac.lu().try_inverse() {
            Some(inv) if inv.iter().all(|v| v.is_finite()) => {
                self.inv = inv;
                Ok(true)
            }
            _ => Ok(false),
        }
    }
}

impl<O: NonlinearEquations> Solver<O, SolverState> for Broyden {
    fn name(&self) -> &str {
        "Broyden (inverse update)"
    }

    fn init(
        &mut self,
        problem: &mut Problem<O>,
        state: SolverState,
    ) -> Result<(SolverState, Option<KV>), argmin::core::Error> {
        let (mut state, r) = init_state(problem, state)?;
        self.r = r;
        if state.get_cost() > self.tolerance {
            let x = state.take_param().unwrap_or_default();
            let ok = self.reinit(op(problem)?, &x)?;
            state = state.param(x);
            if !ok {
                state =
                    state.terminate_with(TerminationReason::SolverExit("singular Jacobian".into()));
            }
        }
        Ok((state, None))
    }

    fn next_iter(
        &mut self,
        problem: &mut Problem<O>,
        mut state: SolverState,
    ) -> Result<(SolverState, Option<KV>), argmin::core::Error> {
        let x = take_iterate(&mut state)?;
        let o = op(problem)?;
        let n = x.len();
        let f0 = norm(&self.r);
        let rv = DVector::from_column_slice(&self.r);
        let dx = -(&self.inv * &rv);
        let mut r_new = vec![0.0; n];
        match line_search(o, &x, dx.as_slice(), f0, &mut self.trial, &mut r_new)? {
            Some(alpha) => {
                let s = dx * alpha;
                let y = DVector::from_column_slice(&r_new) - rv;
                let hy = &self.inv * &y;
                let st_h = s.transpose() * &self.inv;
                let denom = s.dot(&hy);
                if denom.abs() > 1e-300 {
                    let u = (s - hy) / denom;
                    self.inv.ger(1.0, &u, &st_h.transpose(), 1.0);
                }
                self.fresh = false;
                Ok((accept_trial(state, &self.trial, r_new, &mut self.r), None))
            }
            None if !self.fresh => {
                // the secant model went stale: start again from the exact Jacobian
                if self.reinit(o, &x)? {
                    Ok((state.param(x).cost(f0), None))
                } else {
                    Ok((stop_at(state, x, f0, "singular Jacobian"), None))
                }
            }
            None => Ok((stop_at(state, x, f0, "line search failed"), None)),
        }
    }

    fn terminate(&mut self, state: &SolverState) -> TerminationStatus {
        status(state, self.tolerance)
    }
}

/// Run one solver from `x0` for at most `max_iters` iterations through argmin's [`Executor`].
fn run<O, S>(
    equations: O,
    solver: S,
    x0: Vec<f64>,
    max_iters: u64,
) -> Result<(Problem<O>, SolverState), HbmError>
where
    O: NonlinearEquations,
    S: Solver<O, SolverState>,
{
    let res = Executor::new(equations, solver)
        .configure(|s: SolverState| s.param(x0).max_iters(max_iters))
        .timer(false)
        .run()
        .map_err(HbmError::from_argmin)?;
    Ok((res.problem, res.state))
}

/// Solve `r(x) = 0` from `x0` through argmin's [`Executor`]; returns the report and the
/// equations object (so that its workspace can be reused).
///
/// # Errors
/// Invalid options, wrong `x0` length, or an error raised by the equations themselves at the
/// initial guess. Non-convergence is reported in [`SolveReport::converged`], not as an error.
pub fn solve_equations<O: NonlinearEquations>(
    equations: O,
    x0: Vec<f64>,
    options: &SolverOptions,
) -> Result<(SolveReport, O), HbmError> {
    solve_equations_with(equations, x0, options, DenseLu::Auto)
}

/// [`solve_equations`] with the LU of the dense Newton steps chosen explicitly ([`DenseLu`];
/// ignored by [`Method::Broyden`]).
///
/// # Errors
/// As [`solve_equations`].
pub fn solve_equations_with<O: NonlinearEquations>(
    equations: O,
    x0: Vec<f64>,
    options: &SolverOptions,
    dense_lu: DenseLu,
) -> Result<(SolveReport, O), HbmError> {
    options.validate()?;
    let tol = options.tolerance;
    let max_iters = options.max_iters;
    let (mut problem, mut state) = match options.method {
        Method::Newton | Method::NewtonKrylov | Method::Auto => run(
            equations,
            Newton::new(tol)?.with_dense_lu(dense_lu),
            x0,
            max_iters,
        )?,
        Method::Broyden => run(equations, Broyden::new(tol)?, x0, max_iters)?,
    };
    let residual_norm = state.get_cost();
    let iterations = state.get_iter();
    let termination = state
        .get_termination_reason()
        .map_or_else(|| "not terminated".to_string(), |r| r.text().to_string());
    let x = state.take_param().unwrap_or_default();
    let equations = problem.problem.take().ok_or_else(|| HbmError::Solver {
        message: "argmin lost the problem".into(),
    })?;
    Ok((
        SolveReport {
            x,
            converged: residual_norm <= tol,
            iterations,
            residual_norm,
            termination,
        },
        equations,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `r = (x² − 2, y − x³)`: root `(√2, 2√2)`.
    struct Sqrt2;
    impl NonlinearEquations for Sqrt2 {
        fn dim(&self) -> usize {
            2
        }
        fn residual(&mut self, x: &[f64], r: &mut [f64]) -> Result<(), HbmError> {
            r[0] = x[0] * x[0] - 2.0;
            r[1] = x[1] - x[0].powi(3);
            Ok(())
        }
        fn residual_and_jacobian(
            &mut self,
            x: &[f64],
            r: &mut [f64],
            jac: &mut DMatrix<f64>,
        ) -> Result<(), HbmError> {
            self.residual(x, r)?;
            jac.copy_from_slice(&[2.0 * x[0], -3.0 * x[0] * x[0], 0.0, 1.0]);
            Ok(())
        }
    }

    #[test]
    fn both_solvers_find_sqrt2() {
        for method in [Method::Newton, Method::Broyden] {
            let opts = SolverOptions {
                method,
                tolerance: 1e-12,
                max_iters: 100,
            };
            let (rep, _) = solve_equations(Sqrt2, vec![5.0, 0.0], &opts).unwrap();
            assert!(rep.converged, "{method:?}: {}", rep.termination);
            assert!((rep.x[0] - 2f64.sqrt()).abs() < 1e-10);
            assert!((rep.x[1] - 2.0 * 2f64.sqrt()).abs() < 1e-9);
        }
        assert!(solve_equations(Sqrt2, vec![1.0], &SolverOptions::default()).is_err());
        let opts = SolverOptions {
            max_iters: 0,
            ..SolverOptions::default()
        };
        assert!(solve_equations(Sqrt2, vec![1.0, 1.0], &opts).is_err());
    }
}
