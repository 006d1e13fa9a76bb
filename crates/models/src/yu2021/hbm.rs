//! Harmonic balance of the periodic 1-DOF (torsional) Yu 2021 models through the `hbm`
//! engine: Kahraman–Singh, and Yu with locked centres (both forms of Eq. 19).
//!
//! [`Yu2021Torsional`] implements [`system::SecondOrderSystem`] for the DTE `q = δ*`:
//!
//! ```text
//! q'' + ζ q' + k(τ) f(q, B) = T* + F_e(τ),   k = 1 + ε sin(ω*τ + φ_0),  f: dead zone (Eq. 14)
//! F_e = ω*² ē cos(ω*τ + φ_0)  (consistent: −ë of Eq. 15)   or   ē cos(ω*τ + φ_0)  (Eq. 19 printed)
//! ```
//!
//! with the analytic Jacobian `∂g/∂q = k(τ) f'(q, B)` (`backlash::dead_zone_dx`) and the full
//! basis `0..H` of `ω*`. For the locked Yu model in the consistent form the state of
//! [`Yu2021Model::rhs`] is `u = δ* + e`; its DTE obeys the equation above, so the harmonic
//! balance unknowns are always the DTE's Fourier coefficients.
//!
//! Chen's model is not offered: its backlash `b_s + a_z z(ω*τ)` with `z = Σ λ^{(D−2)k}
//! sin(λ^k ω*τ)`, `λ = 1.5`, is not periodic in `2π/ω*` (the common period of `λ^k`,
//! `k < 12`, is `2^11` mesh periods with harmonics up to `3^11`), so no periodic response of
//! the mesh frequency exists.
//!
//! Both implement the shared system description `system::SecondOrderSystem` once; the
//! `timestep` engine integrates the same values through `timestep::Mechanical`.
//!
//! [`Yu2021SixDof`] puts the full 6-DOF model (state-dependent dynamic backlash and pressure
//! angle, [`BacklashUpdate::InRhs`]) on the same engine: five second-order coordinates
//! `q = [u, x_p, y_p, x_g, y_g]` with `M = I`, `C = 0` and the whole right-hand side of
//! [`Yu2021Model::rhs`] as the nonlinear force `g = −q''(τ, q, q')`; its Jacobian is the
//! engine's finite-difference fallback (the dynamic backlash of Eq. 10 has a square root whose
//! derivative is unbounded where `Δa² = Δp²`, so no analytic form is offered).

use math::DetMath;
use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};

use crate::Error;

use super::model::{
    BacklashUpdate, EquationForm, ModelKind, PositionTerms, STATE_LEN, Yu2021Model,
};

/// Harmonic-balance settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct HbmSettings {
    /// Number of harmonics `H` of `ω*` (full basis `0..H`, unknowns `2H + 1`).
    pub harmonics: usize,
    /// Time samples per period of the AFT (≥ 4H + 2; a power of two is customary and fastest).
    pub samples: usize,
    /// Residual-norm tolerance (2-norm of the residual's Fourier coefficients, units of `b_n`).
    pub tolerance: f64,
    /// Maximum Newton iterations.
    pub max_iterations: usize,
}

impl Default for HbmSettings {
    fn default() -> Self {
        HbmSettings {
            harmonics: 12,
            samples: 256,
            tolerance: 1e-10,
            max_iterations: 50,
        }
    }
}

/// Result of a harmonic-balance solve; `converged` says how it ended.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HbmSolution {
    /// `[c_0, a_1, b_1, …, a_H, b_H]`: `δ*(τ) = c_0 + Σ a_j cos(jω*τ) + b_j sin(jω*τ)`.
    pub coefficients: Vec<f64>,
    /// Whether the residual norm fell below the tolerance.
    pub converged: bool,
    /// Newton iterations used.
    pub iterations: usize,
    /// Final residual norm.
    pub residual_norm: f64,
    /// Truncation indicator of the engine ([`hbm::PeriodicSolution::truncation`]): the relative
    /// size of the force harmonics above the basis (NaN in data written before it existed).
    #[serde(default = "f64_nan")]
    pub truncation: f64,
}

fn f64_nan() -> f64 {
    f64::NAN
}

impl HbmSolution {
    /// Evaluate the DTE `δ*(τ)`.
    pub fn eval(&self, omega: f64, tau: f64) -> f64 {
        let c = &self.coefficients;
        let Some(&c0) = c.first() else {
            return 0.0;
        };
        let mut v = c0;
        for j in 1..=(c.len() - 1) / 2 {
            let ph = j as f64 * omega * tau;
            v += c[2 * j - 1] * ph.dcos() + c[2 * j] * ph.dsin();
        }
        v
    }
}

/// A periodic torsional Yu 2021 model (Kahraman–Singh, or Yu with locked centres) as an
/// [`system::SecondOrderSystem`] in the DTE `q = δ*` (see the module equations). Build with
/// [`Yu2021Torsional::new`]; the base frequency of the harmonic balance is `ω*`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Yu2021Torsional {
    model: Yu2021Model,
    omega: f64,
    backlash: f64,
}

impl Yu2021Torsional {
    /// Wrap a periodic 1-DOF model at `ω*`. Errors for Chen's model (not periodic), the
    /// 6-DOF model, and a non-positive or non-finite `ω*`.
    pub fn new(model: &Yu2021Model, omega: f64) -> Result<Self, Error> {
        let torsional = match model.options.kind {
            ModelKind::KahramanSingh => true,
            ModelKind::Yu => model.options.lock_centres,
            ModelKind::ChenFractal => false,
        };
        if !torsional {
            return Err(Error::Solver(
                "yu2021 harmonic balance needs a periodic 1-DOF model (Kahraman-Singh or \
                 Yu with locked centres); Chen's fractal backlash is not periodic"
                    .into(),
            ));
        }
        if !(omega > 0.0 && omega.is_finite()) {
            return Err(Error::invalid("yu2021.omega", "> 0 and finite", omega));
        }
        // centres at rest: B = b_s for every option (Eq. 10 vanishes at Δa = 0)
        let backlash = model.geometry(omega, 0.0, &[0.0; STATE_LEN]).backlash;
        Ok(Yu2021Torsional {
            model: *model,
            omega,
            backlash,
        })
    }

    /// The wrapped model.
    pub fn model(&self) -> &Yu2021Model {
        &self.model
    }

    /// Current `ω*`.
    pub fn omega(&self) -> f64 {
        self.omega
    }

    fn phase(&self, t: f64) -> f64 {
        self.omega * t + self.model.params.phase
    }

    fn stiffness(&self, t: f64) -> f64 {
        mesh_stiffness::StiffnessLaw::stiffness(&self.model.mesh_stiffness_law(self.omega), t)
    }
}

/// The shared system description (solved by `hbm` directly and by `timestep` through
/// [`timestep::Mechanical`]), with the dead-zone edges `q = ±B` as events.
impl system::SecondOrderSystem for Yu2021Torsional {
    fn n_dof(&self) -> usize {
        1
    }
    fn mass(&self) -> DMatrix<f64> {
        DMatrix::identity(1, 1)
    }
    fn damping(&self) -> DMatrix<f64> {
        DMatrix::from_element(1, 1, self.model.params.zeta)
    }
    fn nonlinear_force(&self, t: f64, q: &[f64], _qd: &[f64], g: &mut [f64]) {
        g[0] = self.stiffness(t) * backlash::dead_zone(q[0], self.backlash);
    }
    fn forcing(&self, t: f64, f: &mut [f64]) {
        let p = &self.model.params;
        let e = p.ste * self.phase(t).dcos();
        f[0] = p.load
            + match self.model.options.form {
                EquationForm::Consistent => self.omega * self.omega * e,
                EquationForm::Printed => e,
            };
    }
    fn force_jacobian(&self, t: f64, q: &[f64], _qd: &[f64], dq: &mut [f64], dv: &mut [f64]) {
        dq[0] = self.stiffness(t) * backlash::dead_zone_dx(q[0], self.backlash);
        dv[0] = 0.0;
    }
    fn n_events(&self) -> usize {
        2
    }
    fn events(&self, _t: f64, q: &[f64], _qd: &[f64], e: &mut [f64]) {
        system::gap_edges(q[0], self.backlash, e);
    }
    fn set_base_frequency(&mut self, omega: f64) -> Result<(), system::SystemError> {
        self.omega = checked_omega(omega)?;
        Ok(())
    }
}

/// Yu's 6-DOF model at `ω*` as an [`system::SecondOrderSystem`] in `q = [u, x_p, y_p, x_g, y_g]`
/// (the first five entries of the [`Yu2021Model::rhs`] state; `M = I`, `C = 0`,
/// `g(τ, q, q') = −(rhs accelerations)`, `f = 0`). Build with [`Yu2021SixDof::new`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Yu2021SixDof {
    model: Yu2021Model,
    omega: f64,
}

impl Yu2021SixDof {
    /// Wrap the 6-DOF Yu model (centres free) at `ω*`. Errors for the torsional models, locked
    /// centres, Fig. 8's previous-step backlash update (not a function of the state) and a
    /// non-positive or non-finite `ω*`.
    pub fn new(model: &Yu2021Model, omega: f64) -> Result<Self, Error> {
        if model.options.kind != ModelKind::Yu || model.options.lock_centres {
            return Err(Error::Solver(
                "Yu2021SixDof needs Yu's model with free centres (use Yu2021Torsional for the \
                 1-DOF models)"
                    .into(),
            ));
        }
        if model.options.update == BacklashUpdate::PreviousStep {
            return Err(Error::Solver(
                "harmonic balance needs the state-dependent backlash (BacklashUpdate::InRhs); \
                 Fig. 8's previous-step update is a fixed-step algorithm"
                    .into(),
            ));
        }
        if !(omega > 0.0 && omega.is_finite()) {
            return Err(Error::invalid("yu2021.omega", "> 0 and finite", omega));
        }
        Ok(Yu2021SixDof {
            model: *model,
            omega,
        })
    }

    /// Any Yu 2021 model at `ω*` without the harmonic-balance restrictions of
    /// [`Yu2021SixDof::new`], for time stepping (locked centres stay at rest: their
    /// accelerations are zero). The caller checks `ω*` and the backlash update.
    pub(super) fn for_time_stepping(model: &Yu2021Model, omega: f64) -> Self {
        Yu2021SixDof {
            model: *model,
            omega,
        }
    }

    /// The full [`Yu2021Model::rhs`] state of the coordinates `q` and rates `qd`.
    pub fn state(q: &[f64], qd: &[f64]) -> [f64; STATE_LEN] {
        let mut s = [0.0; STATE_LEN];
        s[..5].copy_from_slice(&q[..5]);
        s[5..].copy_from_slice(&qd[..5]);
        s
    }
}

impl Yu2021Model {
    /// The Lyapunov spectrum of a settled response of this model at `ω*`
    /// ([`crate::response::settled_lyapunov`] on the 6-DOF system description, the one the
    /// `timestep` engine integrates; locked centres stay at rest): from `final_state` (the
    /// [`super::Response::final_state`] of a run of `settings`) at its time
    /// `τ = (transient + record periods) · 2π/ω*`, windows of one period `2π/ω*`.
    ///
    /// # Errors
    /// Fig. 8's previous-step backlash update (not a function of the state), a non-positive
    /// `ω*`, invalid options, a failed flow.
    pub fn lyapunov(
        &self,
        settings: &super::RunSettings,
        final_state: &[f64],
        options: &crate::response::LyapunovWindowOptions,
    ) -> Result<orbit::LyapunovSpectrum, Error> {
        let mut b = self.lyapunov_batches(settings, final_state, options, 1)?;
        b.pop()
            .ok_or_else(|| Error::Solver("yu2021 Lyapunov run: no batch".into()))
    }

    /// [`Yu2021Model::lyapunov`] in `batches` consecutive batches
    /// ([`crate::response::settled_lyapunov_batches`]; batch 0 is [`Yu2021Model::lyapunov`]
    /// bit for bit).
    ///
    /// # Errors
    /// As [`Yu2021Model::lyapunov`]; `batches` outside `[1, 16]`.
    pub fn lyapunov_batches(
        &self,
        settings: &super::RunSettings,
        final_state: &[f64],
        options: &crate::response::LyapunovWindowOptions,
        batches: usize,
    ) -> Result<Vec<orbit::LyapunovSpectrum>, Error> {
        let w = settings.omega;
        if !(w > 0.0 && w.is_finite()) {
            return Err(Error::invalid("yu2021.omega", "> 0 and finite", w));
        }
        if self.options.update == BacklashUpdate::PreviousStep {
            return Err(Error::Solver(
                "yu2021 Lyapunov run: Fig. 8's previous-step backlash update is not a function \
                 of the state"
                    .into(),
            ));
        }
        let period = std::f64::consts::TAU / w;
        let t0 = (settings.transient_periods + settings.record_periods) as f64 * period;
        crate::response::settled_lyapunov_batches(
            Yu2021SixDof::for_time_stepping(self, w),
            period,
            t0,
            final_state,
            options,
            batches,
        )
        .map_err(|e| Error::Solver(format!("yu2021 Lyapunov run: {e}")))
    }
}

/// The shared system description (solved by `hbm` directly and by `timestep` through
/// [`timestep::Mechanical`]), with the dead-zone edges `δ* = ±B` as events (`B` and `δ*` from
/// the state, Eq. 10–11 and 14).
impl system::SecondOrderSystem for Yu2021SixDof {
    fn n_dof(&self) -> usize {
        5
    }
    fn mass(&self) -> DMatrix<f64> {
        DMatrix::identity(5, 5)
    }
    fn damping(&self) -> DMatrix<f64> {
        DMatrix::zeros(5, 5)
    }
    fn nonlinear_force(&self, t: f64, q: &[f64], qd: &[f64], g: &mut [f64]) {
        let d = self
            .model
            .rhs(self.omega, t, &Yu2021SixDof::state(q, qd), None);
        for (gi, di) in g.iter_mut().zip(&d[5..]) {
            *gi = -di;
        }
    }
    fn forcing(&self, _t: f64, f: &mut [f64]) {
        f.fill(0.0);
    }
    /// The default central differences ([`system::finite_difference_force_jacobian`]: the
    /// same steps, the same bits), with the terms of `τ` alone computed once and the
    /// displacement terms (the dynamic backlash, the line of action, `sin α`, `cos α`) once
    /// for the twelve of the twenty evaluations that perturb `u` or a velocity, on which they
    /// do not depend.
    fn force_jacobian(&self, t: f64, q: &[f64], qd: &[f64], dg_dq: &mut [f64], dg_dqd: &mut [f64]) {
        const N: usize = 5;
        let m = &self.model;
        let time = m.time_terms(self.omega, t);
        let mut s = Yu2021SixDof::state(q, qd);
        let sin_cos = m.rhs_reads_sin_cos();
        let base = m.position_terms(self.omega, t, &s, sin_cos);
        let force = |s: &[f64; STATE_LEN], position: &PositionTerms| -> [f64; N] {
            let d = m.rhs_with(self.omega, t, s, None, &time, position);
            std::array::from_fn(|i| -d[N + i])
        };
        // `u = q[0]` is not a displacement of the centres: its perturbations keep `base`
        let perturbed = |s: &[f64; STATE_LEN], j: usize| {
            if j == 0 {
                force(s, &base)
            } else {
                force(s, &m.position_terms(self.omega, t, s, sin_cos))
            }
        };
        for j in 0..N {
            let h = system::finite_difference_step(q[j]);
            s[j] = q[j] + h;
            let gp = perturbed(&s, j);
            s[j] = q[j] - h;
            let gm = perturbed(&s, j);
            s[j] = q[j];
            for i in 0..N {
                dg_dq[i * N + j] = (gp[i] - gm[i]) / (2.0 * h);
            }
            let h = system::finite_difference_step(qd[j]);
            s[N + j] = qd[j] + h;
            let gp = force(&s, &base);
            s[N + j] = qd[j] - h;
            let gm = force(&s, &base);
            s[N + j] = qd[j];
            for i in 0..N {
                dg_dqd[i * N + j] = (gp[i] - gm[i]) / (2.0 * h);
            }
        }
    }
    fn n_events(&self) -> usize {
        2
    }
    fn events(&self, t: f64, q: &[f64], qd: &[f64], e: &mut [f64]) {
        let s = Yu2021SixDof::state(q, qd);
        let (delta, backlash) = self.model.dte_and_backlash(self.omega, t, &s);
        system::gap_edges(delta, backlash, e);
    }
    fn set_base_frequency(&mut self, omega: f64) -> Result<(), system::SystemError> {
        self.omega = checked_omega(omega)?;
        Ok(())
    }
}

fn engine_error(e: hbm::HbmError) -> Error {
    Error::hbm("yu2021 hbm engine: ")(e)
}

/// `ω*` for the engine's frequency continuation: positive and finite.
fn checked_omega(omega: f64) -> Result<f64, system::SystemError> {
    if omega > 0.0 && omega.is_finite() {
        Ok(omega)
    } else {
        Err(system::SystemError::invalid(
            "yu2021.omega",
            "> 0 and finite",
            omega,
        ))
    }
}

/// A full-basis `0..H` engine problem of `sys` at `ω*` with an AFT grid of `samples` points.
fn full_basis_problem<S: hbm::SecondOrderSystem>(
    sys: S,
    omega: f64,
    harmonics: usize,
    samples: usize,
) -> Result<hbm::HbmProblem<S>, Error> {
    let basis = hbm::Basis::full(harmonics).map_err(engine_error)?;
    hbm::HbmProblem::with_grid_size(sys, basis, omega, samples).map_err(engine_error)
}

impl Yu2021Model {
    /// The `hbm` engine problem of a torsional model at `ω*` on the full basis `0..H` with an
    /// AFT grid of `samples` points (for continuation, stability, truncation estimates).
    pub fn hbm_problem(
        &self,
        omega: f64,
        harmonics: usize,
        samples: usize,
    ) -> Result<hbm::HbmProblem<Yu2021Torsional>, Error> {
        full_basis_problem(
            Yu2021Torsional::new(self, omega)?,
            omega,
            harmonics,
            samples,
        )
    }

    /// The `hbm` engine problem of the 6-DOF model at `ω*` ([`Yu2021SixDof`]) on the full basis
    /// `0..H` with an AFT grid of `samples` points. Solve it with [`hbm::HbmProblem::solve`];
    /// a start from the static contact state is `[b_s + T*, 0, 0, 0, 0]` in the constant
    /// coefficients (see the test `six_dof_hbm_matches_time_integration`).
    pub fn hbm_problem_six_dof(
        &self,
        omega: f64,
        harmonics: usize,
        samples: usize,
    ) -> Result<hbm::HbmProblem<Yu2021SixDof>, Error> {
        full_basis_problem(Yu2021SixDof::new(self, omega)?, omega, harmonics, samples)
    }

    /// Period-1 harmonic balance of a torsional model (Kahraman–Singh, or Yu with
    /// `lock_centres`) by the `hbm` engine (Newton with the analytic AFT Jacobian). `guess`
    /// (length `2H + 1`) defaults to the static contact solution `δ* = b_s + T*`.
    pub fn harmonic_balance(
        &self,
        omega: f64,
        settings: &HbmSettings,
        guess: Option<&[f64]>,
    ) -> Result<HbmSolution, Error> {
        Yu2021Torsional::new(self, omega)?;
        let h = settings.harmonics;
        if h == 0 {
            return Err(Error::invalid("yu2021.hbm.harmonics", ">= 1", 0.0));
        }
        if settings.samples < 4 * h + 2 {
            return Err(Error::invalid(
                "yu2021.hbm.samples",
                ">= 4 H + 2",
                settings.samples as f64,
            ));
        }
        let m = 2 * h + 1;
        let z0 = match guess {
            Some(g) if g.len() == m => g.to_vec(),
            Some(g) => {
                return Err(Error::invalid(
                    "yu2021.hbm.guess length",
                    "= 2 H + 1",
                    g.len() as f64,
                ));
            }
            None => {
                let mut c = vec![0.0; m];
                c[0] = self.params.backlash + self.params.load;
                c
            }
        };
        let mut problem = self.hbm_problem(omega, h, settings.samples)?;
        let options = hbm::SolverOptions {
            method: hbm::Method::Newton,
            tolerance: settings.tolerance,
            max_iters: settings.max_iterations as u64,
        };
        let sol = problem.solve(&z0, &options).map_err(engine_error)?;
        Ok(HbmSolution {
            coefficients: sol.coefficients,
            converged: sol.converged,
            iterations: usize::try_from(sol.iterations).unwrap_or(usize::MAX),
            residual_norm: sol.residual_norm,
            truncation: sol.truncation,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::yu2021::{Options, Yu2021Params};
    use hbm::SecondOrderSystem;

    #[test]
    fn analytic_jacobian_matches_finite_differences() {
        let m = Yu2021Model::new(&Yu2021Params::table1(), Options::kahraman_singh()).unwrap();
        let sys = Yu2021Torsional::new(&m, 0.7).unwrap();
        for q in [-1.7, -0.3, 0.4, 1.3, 2.2] {
            let (mut a, mut b) = ([0.0], [0.0]);
            let (mut fa, mut fb) = ([0.0], [0.0]);
            sys.force_jacobian(0.4, &[q], &[0.1], &mut a, &mut b);
            hbm::finite_difference_force_jacobian(&sys, 0.4, &[q], &[0.1], &mut fa, &mut fb);
            assert!((a[0] - fa[0]).abs() < 1e-6, "q {q}: {} vs {}", a[0], fa[0]);
            assert!((b[0] - fb[0]).abs() < 1e-9);
        }
    }

    /// The 6-DOF Jacobian with its terms of `τ` and of the displacements computed once is the
    /// default central differences of `nonlinear_force`, bit for bit, and the event functions
    /// are the gap edges about [`Yu2021Model::mesh`]'s DTE, and the right-hand side is the same
    /// from position terms without `(sin α, cos α)`: every dynamic law, both
    /// equation forms, both pressure-angle and centre-distance readings, locked centres, the
    /// torsional models through the time-stepping wrapper, states in and out of the gap.
    #[test]
    fn six_dof_jacobian_is_the_default_finite_differences_bit_for_bit() {
        use super::super::model::{CentreDistanceForm, DynamicBacklashLaw, PressureAngleLaw};
        let p = Yu2021Params::table1();
        let mut options = vec![Options::kahraman_singh(), Options::chen()];
        for dynamic_backlash in [
            DynamicBacklashLaw::Eq10,
            DynamicBacklashLaw::Involute,
            DynamicBacklashLaw::Off,
        ] {
            for form in [EquationForm::Consistent, EquationForm::Printed] {
                for (pressure_angle, centre_distance) in [
                    (PressureAngleLaw::Involute, CentreDistanceForm::Consistent),
                    (
                        PressureAngleLaw::PrintedEq16,
                        CentreDistanceForm::PrintedEq8,
                    ),
                ] {
                    for lock_centres in [false, true] {
                        options.push(Options {
                            dynamic_backlash,
                            form,
                            pressure_angle,
                            centre_distance,
                            lock_centres,
                            ..Options::default()
                        });
                    }
                }
            }
        }
        let states: [[f64; 10]; 3] = [
            [1.3, 0.02, -0.01, 0.015, 0.03, 0.4, -0.2, 0.1, 0.05, -0.3],
            [0.2, -0.3, 0.25, 0.1, -0.05, -1.1, 0.6, -0.4, 0.2, 0.7],
            [-2.1, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        ];
        for o in options {
            let m = Yu2021Model::new(&p, o).unwrap();
            let sys = Yu2021SixDof::for_time_stepping(&m, 0.83);
            for (k, x) in states.iter().enumerate() {
                let t = 0.37 + k as f64;
                let (mut a, mut b) = ([0.0; 25], [0.0; 25]);
                let (mut fa, mut fb) = ([0.0; 25], [0.0; 25]);
                sys.force_jacobian(t, &x[..5], &x[5..], &mut a, &mut b);
                system::finite_difference_force_jacobian(
                    &sys,
                    t,
                    &x[..5],
                    &x[5..],
                    &mut fa,
                    &mut fb,
                );
                let bits = |v: &[f64; 25]| v.map(f64::to_bits);
                assert_eq!(bits(&a), bits(&fa), "{o:?}, state {k}: dg/dq");
                assert_eq!(bits(&b), bits(&fb), "{o:?}, state {k}: dg/dq'");
                assert!(a.iter().chain(&b).all(|v| v.is_finite()));
                // the event functions (without the mesh stiffness) are the mesh's DTE and gap
                let mut e = [0.0; 2];
                sys.events(t, &x[..5], &x[5..], &mut e);
                let g = m.geometry(0.83, t, x);
                let (delta, _, _) = m.mesh(0.83, t, x, &g, g.backlash);
                let want = [delta - g.backlash, delta + g.backlash];
                assert_eq!(e.map(f64::to_bits), want.map(f64::to_bits), "{o:?}: events");
                // position terms without `(sin α, cos α)`: the right-hand side computes them
                let bare = m.position_terms(0.83, t, x, false);
                let d = m.rhs_with(0.83, t, x, None, &m.time_terms(0.83, t), &bare);
                let want = m.rhs(0.83, t, x, None);
                assert_eq!(d.map(f64::to_bits), want.map(f64::to_bits), "{o:?}: rhs");
            }
        }
    }

    #[test]
    fn chen_and_six_dof_are_refused() {
        let p = Yu2021Params::table1();
        for o in [Options::chen(), Options::default()] {
            let m = Yu2021Model::new(&p, o).unwrap();
            assert!(matches!(
                Yu2021Torsional::new(&m, 1.0),
                Err(Error::Solver(_))
            ));
        }
    }
}
