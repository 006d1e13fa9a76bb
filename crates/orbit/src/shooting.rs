//! Single and multiple shooting on the event-located flow.

use crate::error::{OrbitError, Result, check};
use crate::floquet::{Floquet, floquet};
use crate::flow::EventRecord;
use crate::problem::OrbitProblem;
use nalgebra::{DMatrix, DVector};
use system::SecondOrderSystem;

/// Settings of [`OrbitProblem::shoot`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ShootingOptions {
    /// Orbit period in forcing periods `k` (period-`k` orbit, shot over `kT`).
    pub periods: usize,
    /// Shooting segments `m` (1 = single shooting).
    pub segments: usize,
    /// Converged when `‖r‖_∞ ≤ tol (1 + ‖x‖_∞)` (`r` the matching residuals).
    pub tol: f64,
    /// Newton iteration cap.
    pub max_iter: usize,
}

impl Default for ShootingOptions {
    fn default() -> Self {
        Self {
            periods: 1,
            segments: 1,
            tol: 1e-9,
            max_iter: 40,
        }
    }
}

impl ShootingOptions {
    /// Checks every field.
    ///
    /// # Errors
    /// [`OrbitError::InvalidInput`] naming the field.
    pub fn validate(&self) -> Result<()> {
        check(
            self.periods >= 1 && self.periods <= 1 << 20,
            "ShootingOptions::periods",
            "in [1, 2^20]",
            self.periods as f64,
        )?;
        check(
            self.segments >= 1 && self.segments <= 4096,
            "ShootingOptions::segments",
            "in [1, 4096]",
            self.segments as f64,
        )?;
        check(
            self.tol.is_finite() && self.tol > 0.0,
            "ShootingOptions::tol",
            "> 0 and finite",
            self.tol,
        )?;
        check(
            self.max_iter >= 1,
            "ShootingOptions::max_iter",
            ">= 1",
            self.max_iter as f64,
        )
    }
}

/// A periodic orbit found by shooting.
#[derive(Debug, Clone, PartialEq)]
pub struct PeriodicOrbit {
    /// State `(q, q')` on the section `t = t₀`.
    pub x0: Vec<f64>,
    /// Section time `t₀`.
    pub t0: f64,
    /// Orbit period `kT`.
    pub period: f64,
    /// `k`.
    pub periods: usize,
    /// States at the segment starts `t₀ + j kT/m` (the first is `x0`).
    pub segment_states: Vec<Vec<f64>>,
    /// Monodromy matrix `Φ(kT)` = product of the segment Jacobians (variational equations and
    /// saltation matrices).
    pub monodromy: DMatrix<f64>,
    /// Multipliers, conditioning, stability.
    pub floquet: Floquet,
    /// Events along one orbit period, in time order.
    pub events: Vec<EventRecord>,
    /// Final `‖r‖_∞`.
    pub residual: f64,
    /// Newton iterations taken.
    pub iterations: usize,
}

struct Eval {
    r: DVector<f64>,
    phis: Vec<DMatrix<f64>>,
    events: Vec<EventRecord>,
}

impl<S: SecondOrderSystem> OrbitProblem<S> {
    fn eval_segments(&self, xs: &DVector<f64>, opts: &ShootingOptions, var: bool) -> Result<Eval> {
        let nn = self.dim();
        let m = opts.segments;
        let tau = opts.periods as f64 * self.period() / m as f64;
        let mut r = DVector::zeros(nn * m);
        let mut phis = vec![];
        let mut events = vec![];
        for j in 0..m {
            let xj = xs.rows(j * nn, nn);
            let t = self.phase() + j as f64 * tau;
            let f = self.flow(t, xj.as_slice(), tau, var)?;
            let jn = (j + 1) % m;
            for i in 0..nn {
                r[j * nn + i] = f.state[i] - xs[jn * nn + i];
            }
            if let Some(p) = f.jacobian {
                phis.push(p);
            }
            events.extend(f.events);
        }
        Ok(Eval { r, phis, events })
    }

    /// Integrates the segments' starting states from `x0` (the guess for multiple shooting).
    fn segment_guess(&self, x0: &[f64], opts: &ShootingOptions) -> Result<DVector<f64>> {
        let nn = self.dim();
        let m = opts.segments;
        let tau = opts.periods as f64 * self.period() / m as f64;
        let mut xs = DVector::zeros(nn * m);
        let mut x = x0.to_vec();
        for j in 0..m {
            xs.rows_mut(j * nn, nn).copy_from_slice(&x);
            if j + 1 < m {
                x = self
                    .flow(self.phase() + j as f64 * tau, &x, tau, false)?
                    .state;
            }
        }
        Ok(xs)
    }

    /// Newton's method on the periodicity conditions of `m` segments,
    /// `x_{j+1 mod m} = φ(t₀ + (j+1)τ; t₀ + jτ, x_j)`, `τ = kT/m`, with the exact Jacobian
    /// (segment monodromies and `−I` blocks) and a backtracking line search on `‖r‖_∞`.
    /// The segment starts are first integrated from `x0`.
    ///
    /// # Errors
    /// Invalid input, integration failures, [`OrbitError::NotConverged`].
    pub fn shoot(&self, x0: &[f64], opts: &ShootingOptions) -> Result<PeriodicOrbit> {
        opts.validate()?;
        self.check_state(x0)?;
        let xs = self.segment_guess(x0, opts)?;
        self.shoot_segments(xs, opts)
    }

    /// The period map at `x0` without correcting it: one flow over `kT` (`k = periods`) from
    /// `(t₀, x0)` with its variational equations and saltation matrices, as the same record
    /// [`shoot`](Self::shoot) returns for a converged orbit (the monodromy
    /// `Φ = ∂φ_{kT}(x0)/∂x0`, its multipliers and conditioning, the events), with
    /// [`residual`](PeriodicOrbit::residual) the periodicity defect `‖φ_{kT}(x0) − x0‖_∞` and no
    /// Newton iteration. The multipliers of a state that another method found periodic (a
    /// harmonic-balance orbit, a long time integration) through the one monodromy of shooting.
    ///
    /// # Errors
    /// Invalid input, integration failures, a non-finite monodromy.
    pub fn period_map(&self, x0: &[f64], periods: usize) -> Result<PeriodicOrbit> {
        let opts = ShootingOptions {
            periods,
            segments: 1,
            ..ShootingOptions::default()
        };
        opts.validate()?;
        self.check_state(x0)?;
        let xs = DVector::from_column_slice(x0);
        let ev = self.eval_segments(&xs, &opts, true)?;
        self.finish(xs, ev, &opts, 0)
    }

    /// As [`shoot`](Self::shoot), from given segment starts (`m · 2n` values).
    ///
    /// # Errors
    /// As [`shoot`](Self::shoot).
    pub fn shoot_segments(
        &self,
        xs: DVector<f64>,
        opts: &ShootingOptions,
    ) -> Result<PeriodicOrbit> {
        opts.validate()?;
        let nn = self.dim();
        let m = opts.segments;
        if xs.len() != nn * m {
            return Err(OrbitError::DimensionMismatch {
                what: "segment states",
                expected: nn * m,
                got: xs.len(),
            });
        }
        let mut xs = xs;
        let norm = |v: &DVector<f64>| v.amax();
        for it in 0..=opts.max_iter {
            let ev = self.eval_segments(&xs, opts, true)?;
            let res = norm(&ev.r);
            if res <= opts.tol * (1.0 + norm(&xs)) {
                return self.finish(xs, ev, opts, it);
            }
            if it == opts.max_iter {
                return Err(OrbitError::NotConverged {
                    what: "shooting Newton",
                    iterations: it,
                    residual: res,
                });
            }
            let jac = self.shooting_jacobian(&ev.phis, m);
            let delta = jac
                .lu()
                .solve(&(-&ev.r))
                .filter(|d| d.iter().all(|v| v.is_finite()))
                .ok_or(OrbitError::Singular {
                    what: "shooting Jacobian Φ − I (multiplier at +1?)",
                })?;
            let mut lambda = 1.0;
            let mut accepted = false;
            for _ in 0..12 {
                let trial = &xs + &delta * lambda;
                if let Ok(e) = self.eval_segments(&trial, opts, false) {
                    if norm(&e.r) < res {
                        xs = trial;
                        accepted = true;
                        break;
                    }
                }
                lambda *= 0.5;
            }
            if !accepted {
                return Err(OrbitError::NotConverged {
                    what: "shooting Newton (line search)",
                    iterations: it,
                    residual: res,
                });
            }
        }
        Err(OrbitError::NotConverged {
            what: "shooting Newton",
            iterations: opts.max_iter,
            residual: f64::NAN,
        })
    }

    /// The block-cyclic Jacobian of the matching conditions.
    pub(crate) fn shooting_jacobian(&self, phis: &[DMatrix<f64>], m: usize) -> DMatrix<f64> {
        let nn = self.dim();
        let mut jac = DMatrix::zeros(nn * m, nn * m);
        for (j, p) in phis.iter().enumerate() {
            jac.view_mut((j * nn, j * nn), (nn, nn)).copy_from(p);
            let jn = (j + 1) % m;
            for i in 0..nn {
                jac[(j * nn + i, jn * nn + i)] -= 1.0;
            }
        }
        jac
    }

    fn finish(
        &self,
        xs: DVector<f64>,
        ev: Eval,
        opts: &ShootingOptions,
        iterations: usize,
    ) -> Result<PeriodicOrbit> {
        let nn = self.dim();
        let mut mono = DMatrix::identity(nn, nn);
        for p in &ev.phis {
            mono = p * mono;
        }
        let fl = floquet(&mono)?;
        let segs: Vec<Vec<f64>> = (0..opts.segments)
            .map(|j| xs.rows(j * nn, nn).iter().copied().collect())
            .collect();
        Ok(PeriodicOrbit {
            x0: segs[0].clone(),
            t0: self.phase(),
            period: opts.periods as f64 * self.period(),
            periods: opts.periods,
            segment_states: segs,
            monodromy: mono,
            floquet: fl,
            events: ev.events,
            residual: ev.r.amax(),
            iterations,
        })
    }
}
