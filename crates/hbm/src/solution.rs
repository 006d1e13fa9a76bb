//! Solving one periodic response, and what a solution can tell.

use crate::solve::{NonlinearEquations, solve_equations_with};
use crate::{
    Basis, HbmError, HbmProblem, KrylovOptions, Method, SecondOrderSystem, SolverOptions, Stability,
};
use math::DetMath;
use nalgebra::DMatrix;
use num_complex::Complex;
use std::f64::consts::PI;

/// A periodic solution `q(t) = a_0 + Σ a_k cos(kωt) + b_k sin(kωt)` and how its solve ended.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct PeriodicSolution {
    /// The basis of the coefficients.
    pub basis: Basis,
    /// Base frequency `ω` (rad per time unit); the period is `2π/ω`.
    pub omega: f64,
    /// Number of degrees of freedom `n`.
    pub n_dof: usize,
    /// Coefficients, `coefficients[c·n + i]` (see [`Basis`]).
    pub coefficients: Vec<f64>,
    /// Whether the solver reached its tolerance.
    pub converged: bool,
    /// Solver iterations.
    pub iterations: u64,
    /// Final residual norm `‖r‖₂`.
    pub residual_norm: f64,
    /// Truncation indicator `ε` at the final coefficients: the relative size of the force
    /// harmonics the basis discards ([`HbmProblem::truncation_indicator`], equation in the crate
    /// docs); NaN where it could not be evaluated (absent in data written before it existed).
    #[cfg_attr(feature = "serde", serde(default = "nan"))]
    pub truncation: f64,
    /// Termination reason, in words.
    pub termination: String,
    /// Floquet stability, when computed.
    pub stability: Option<Stability>,
}

/// Amplitude of one harmonic of one degree of freedom.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct HarmonicAmplitude {
    /// Harmonic index `k` (0 = constant).
    pub harmonic: usize,
    /// Angular frequency `kω`.
    pub frequency: f64,
    /// Amplitude `√(a_k² + b_k²)` (`|a_0|` for the constant).
    pub amplitude: f64,
}

/// A sampled time series over one period.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct TimeSeries {
    /// Sample times `t_m = m T / N`, `m = 0..N`.
    pub time: Vec<f64>,
    /// Displacements, `displacement[i][m]` for DOF `i`.
    pub displacement: Vec<Vec<f64>>,
    /// Velocities, `velocity[i][m]`.
    pub velocity: Vec<Vec<f64>>,
}

/// Change of a solution when the basis is enlarged (harmonic truncation error estimate).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct TruncationEstimate {
    /// Per DOF: `max_t |q_small(t) − q_large(t)|`.
    pub max_abs_difference: Vec<f64>,
    /// Per DOF: the same divided by the peak-to-peak value of the larger-basis solution.
    pub relative_to_peak_to_peak: Vec<f64>,
    /// The solution in the enlarged basis.
    pub refined: PeriodicSolution,
}

impl PeriodicSolution {
    /// Period `T = 2π/ω`.
    pub fn period(&self) -> f64 {
        2.0 * PI / self.omega
    }

    /// `q(t)` and `q'(t)` for all DOFs.
    pub fn state_at(&self, t: f64) -> (Vec<f64>, Vec<f64>) {
        let n = self.n_dof;
        let (mut q, mut qd) = (vec![0.0; n], vec![0.0; n]);
        eval_state(
            &self.basis,
            n,
            self.omega,
            &self.coefficients,
            t,
            &mut q,
            &mut qd,
        );
        (q, qd)
    }

    /// Sample one period at `n_points` equidistant times (`n_points ≥ 2`).
    ///
    /// By one inverse FFT per degree of freedom (`q` and `q'` packed as the real and imaginary
    /// parts) when `n_points > 2 k_max`, else by direct summation.
    pub fn time_series(&self, n_points: usize) -> TimeSeries {
        let n_points = n_points.max(2);
        let n = self.n_dof;
        if n_points > 2 * self.basis.max_harmonic()
            && self.coefficients.len() == n * self.basis.n_coefficients()
        {
            return self.time_series_fft(n_points);
        }
        let mut ts = TimeSeries {
            time: Vec::with_capacity(n_points),
            displacement: vec![Vec::with_capacity(n_points); n],
            velocity: vec![Vec::with_capacity(n_points); n],
        };
        let (mut q, mut qd) = (vec![0.0; n], vec![0.0; n]);
        for m in 0..n_points {
            let t = self.period() * m as f64 / n_points as f64;
            eval_state(
                &self.basis,
                n,
                self.omega,
                &self.coefficients,
                t,
                &mut q,
                &mut qd,
            );
            ts.time.push(t);
            for i in 0..n {
                ts.displacement[i].push(q[i]);
                ts.velocity[i].push(qd[i]);
            }
        }
        ts
    }

    /// [`time_series`](Self::time_series) by inverse FFT (needs `n_points > 2 k_max` and
    /// consistent coefficients).
    fn time_series_fft(&self, n_points: usize) -> TimeSeries {
        let n = self.n_dof;
        let (_, inv) = crate::plans::plans(n_points);
        let mut buf = vec![Complex::<f64>::default(); n_points];
        let mut scratch = vec![Complex::<f64>::default(); inv.get_inplace_scratch_len()];
        let mut ts = TimeSeries {
            time: (0..n_points)
                .map(|m| self.period() * m as f64 / n_points as f64)
                .collect(),
            displacement: Vec::with_capacity(n),
            velocity: Vec::with_capacity(n),
        };
        for i in 0..n {
            self.samples_fft(i, &*inv, &mut buf, &mut scratch);
            ts.displacement.push(buf.iter().map(|c| c.re).collect());
            ts.velocity.push(buf.iter().map(|c| c.im).collect());
        }
        ts
    }

    /// `q_i + i q'_i` at the `buf.len()` samples of one period, by the inverse FFT `inv` of that
    /// size (needs `buf.len() > 2 k_max` and consistent coefficients).
    fn samples_fft(
        &self,
        i: usize,
        inv: &dyn fft::Fft<f64>,
        buf: &mut [Complex<f64>],
        scratch: &mut [Complex<f64>],
    ) {
        let (n, n_points, z) = (self.n_dof, buf.len(), &self.coefficients);
        buf.fill(Complex::default());
        buf[0] = Complex::new(z[i], 0.0);
        for (j, &k) in self.basis.harmonics().iter().enumerate() {
            let (a, b) = (z[(2 * j + 1) * n + i], z[(2 * j + 2) * n + i]);
            // q: X = (a − ib)/2 at +k; q': Y = kω(b + ia)/2; packed as X + iY
            let x = Complex::new(a, -b) * 0.5;
            let y = Complex::new(b, a) * (0.5 * k as f64 * self.omega);
            buf[k] += x + Complex::<f64>::i() * y;
            buf[(n_points - k) % n_points] += x.conj() + Complex::<f64>::i() * y.conj();
        }
        inv.process_with_scratch(buf, scratch);
    }

    /// The displacement of DOF `dof` at the `n_points` sample times `t_m = m T / n_points` of
    /// [`time_series`](Self::time_series) (the same values), without the times and velocities;
    /// `None` for an invalid DOF. Cheap metrics (extrema, contact states) of a solution use it.
    pub fn displacement_samples(&self, dof: usize, n_points: usize) -> Option<Vec<f64>> {
        if dof >= self.n_dof {
            return None;
        }
        let n_points = n_points.max(2);
        if n_points > 2 * self.basis.max_harmonic()
            && self.coefficients.len() == self.n_dof * self.basis.n_coefficients()
        {
            let (_, inv) = crate::plans::plans(n_points);
            let scratch = inv.get_inplace_scratch_len();
            return Some(crate::plans::with_buffers(n_points, scratch, |buf, scr| {
                self.samples_fft(dof, &*inv, buf, scr);
                buf.iter().map(|c| c.re).collect()
            }));
        }
        let ts = self.time_series(n_points);
        ts.displacement.into_iter().nth(dof)
    }

    /// Default number of samples for extrema: `max(512, 16 k_max)`.
    fn default_samples(&self) -> usize {
        (16 * self.basis.max_harmonic()).max(512)
    }

    /// Peak-to-peak displacement of DOF `dof` (sampled at `max(512, 16 k_max)` points);
    /// `None` for an invalid DOF.
    pub fn peak_to_peak(&self, dof: usize) -> Option<f64> {
        if dof >= self.n_dof {
            return None;
        }
        Some(spread(
            &self.time_series(self.default_samples()).displacement[dof],
        ))
    }

    /// Peak-to-peak velocity of DOF `dof` (the "ppv" of Liu et al.); `None` for an invalid DOF.
    pub fn peak_to_peak_velocity(&self, dof: usize) -> Option<f64> {
        if dof >= self.n_dof {
            return None;
        }
        Some(spread(
            &self.time_series(self.default_samples()).velocity[dof],
        ))
    }

    /// Amplitude of every retained harmonic of DOF `dof` (constant first); empty for an invalid
    /// DOF.
    pub fn harmonic_amplitudes(&self, dof: usize) -> Vec<HarmonicAmplitude> {
        let n = self.n_dof;
        if dof >= n {
            return Vec::new();
        }
        let at = |idx: usize| self.coefficients.get(idx).copied().unwrap_or(0.0);
        let mut out = vec![HarmonicAmplitude {
            harmonic: 0,
            frequency: 0.0,
            amplitude: at(dof).abs(),
        }];
        for (j, &k) in self.basis.harmonics().iter().enumerate() {
            let a = at((2 * j + 1) * n + dof);
            let b = at((2 * j + 2) * n + dof);
            out.push(HarmonicAmplitude {
                harmonic: k,
                frequency: k as f64 * self.omega,
                amplitude: a.dhypot(b),
            });
        }
        out
    }

    /// Cheap truncation indicator of DOF `dof`: amplitude of the highest retained harmonic
    /// divided by the largest non-constant amplitude (0 when all are zero). Values that are not
    /// small mean the basis is too short; [`HbmProblem::truncation_estimate`] measures it.
    pub fn spectral_tail(&self, dof: usize) -> f64 {
        let amps = self.harmonic_amplitudes(dof);
        let max = amps.iter().skip(1).map(|a| a.amplitude).fold(0.0, f64::max);
        match amps.last() {
            Some(last) if max > 0.0 && amps.len() > 1 => last.amplitude / max,
            _ => 0.0,
        }
    }

    /// The coefficients re-expressed in a larger basis (missing harmonics are zero, harmonics
    /// not in `basis` are dropped).
    pub fn embed(&self, basis: &Basis) -> Vec<f64> {
        let n = self.n_dof;
        let at = |idx: usize| self.coefficients.get(idx).copied().unwrap_or(0.0);
        let mut z = vec![0.0; n * basis.n_coefficients()];
        for i in 0..n {
            z[i] = at(i);
        }
        for (j, &k) in self.basis.harmonics().iter().enumerate() {
            if let Ok(jn) = basis.harmonics().binary_search(&k) {
                for i in 0..n {
                    z[(2 * jn + 1) * n + i] = at((2 * j + 1) * n + i);
                    z[(2 * jn + 2) * n + i] = at((2 * j + 2) * n + i);
                }
            }
        }
        z
    }
}

/// Adapter: a [`HbmProblem`] seen as [`NonlinearEquations`].
pub(crate) struct HbmEquations<'a, S>(pub(crate) &'a mut HbmProblem<S>);

impl<S: SecondOrderSystem> NonlinearEquations for HbmEquations<'_, S> {
    fn dim(&self) -> usize {
        self.0.n_unknowns()
    }
    fn residual(&mut self, x: &[f64], r: &mut [f64]) -> Result<(), HbmError> {
        self.0.residual(x, r)
    }
    fn residual_and_jacobian(
        &mut self,
        x: &[f64],
        r: &mut [f64],
        jac: &mut DMatrix<f64>,
    ) -> Result<(), HbmError> {
        self.0.residual_and_jacobian(x, r, jac)
    }
}

/// `q(t)`, `q'(t)` of coefficients `z` by direct summation.
pub(crate) fn eval_state(
    basis: &Basis,
    n: usize,
    omega: f64,
    z: &[f64],
    t: f64,
    q: &mut [f64],
    qd: &mut [f64],
) {
    // `get` so that a hand-built, inconsistent solution gives zeros instead of a panic
    let at = |idx: usize| z.get(idx).copied().unwrap_or(0.0);
    for i in 0..n {
        q[i] = at(i);
        qd[i] = 0.0;
    }
    for (j, &k) in basis.harmonics().iter().enumerate() {
        let kw = k as f64 * omega;
        let (s, c) = (kw * t).dsin_cos();
        for i in 0..n {
            let a = at((2 * j + 1) * n + i);
            let b = at((2 * j + 2) * n + i);
            q[i] += a * c + b * s;
            qd[i] += kw * (b * c - a * s);
        }
    }
}

impl<S: SecondOrderSystem> HbmProblem<S> {
    /// Solve for the periodic response from the initial coefficients `z0` (length
    /// [`n_unknowns`](Self::n_unknowns)); the solve runs through argmin's `Executor`.
    ///
    /// # Errors
    /// Wrong `z0` length, invalid options, or a system error at the initial guess.
    /// Non-convergence is reported in [`PeriodicSolution::converged`].
    pub fn solve(
        &mut self,
        z0: &[f64],
        options: &SolverOptions,
    ) -> Result<PeriodicSolution, HbmError> {
        self.check_len("initial coefficients", z0.len())?;
        let krylov = match options.method {
            Method::NewtonKrylov => true,
            Method::Auto => self.n_unknowns() >= crate::AUTO_KRYLOV_UNKNOWNS,
            _ => false,
        };
        if krylov {
            return self.solve_newton_krylov(z0, options, &KrylovOptions::default());
        }
        let lu = self.dense_lu();
        let (report, _) = solve_equations_with(HbmEquations(self), z0.to_vec(), options, lu)?;
        Ok(self.solution_of(
            report.x,
            report.converged,
            report.iterations,
            report.residual_norm,
            report.termination,
        ))
    }

    /// [`solve`](Self::solve) by [`Method::NewtonKrylov`] with explicit bounds of the inner
    /// GMRES solve (`options.method` is ignored).
    ///
    /// # Errors
    /// As [`HbmProblem::solve`]; invalid `krylov` bounds; [`HbmError::KrylovNotConverged`]
    /// when a linear solve misses its tolerance within `krylov.max_products`.
    pub fn solve_newton_krylov(
        &mut self,
        z0: &[f64],
        options: &SolverOptions,
        krylov: &KrylovOptions,
    ) -> Result<PeriodicSolution, HbmError> {
        self.check_len("initial coefficients", z0.len())?;
        let rep = self.newton_krylov(z0, options, krylov)?;
        Ok(self.solution_of(
            rep.x,
            rep.converged,
            rep.iterations,
            rep.residual_norm,
            rep.termination,
        ))
    }

    /// Wrap a solver's final iterate, with its truncation indicator.
    fn solution_of(
        &mut self,
        x: Vec<f64>,
        converged: bool,
        iterations: u64,
        residual_norm: f64,
        termination: String,
    ) -> PeriodicSolution {
        let truncation = self.truncation_indicator(&x).unwrap_or(f64::NAN);
        PeriodicSolution {
            basis: self.basis().clone(),
            omega: self.omega(),
            n_dof: self.n_dof(),
            coefficients: x,
            converged,
            iterations,
            residual_norm,
            truncation,
            termination,
            stability: None,
        }
    }

    /// A zero initial guess of the right length.
    pub fn zero_guess(&self) -> Vec<f64> {
        vec![0.0; self.n_unknowns()]
    }

    /// Harmonic truncation error estimate: re-solve in `larger` (same `ω`, default grid) starting
    /// from `solution` and report how much the response changes.
    ///
    /// # Errors
    /// As [`HbmProblem::solve`].
    pub fn truncation_estimate(
        &self,
        solution: &PeriodicSolution,
        larger: Basis,
        options: &SolverOptions,
    ) -> Result<TruncationEstimate, HbmError>
    where
        S: Clone,
    {
        let n_grid = larger
            .default_grid_size()
            .max(self.grid_size().next_power_of_two());
        let mut big = HbmProblem::with_grid_size(
            self.system().clone(),
            larger.clone(),
            self.omega(),
            n_grid,
        )?;
        let z0 = solution.embed(&larger);
        let refined = big.solve(&z0, options)?;
        let samples = (16 * larger.max_harmonic()).max(512);
        let a = solution.time_series(samples);
        let b = refined.time_series(samples);
        let mut abs = Vec::new();
        let mut rel = Vec::new();
        for i in 0..self.n_dof() {
            let d = a.displacement[i]
                .iter()
                .zip(&b.displacement[i])
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f64::max);
            let ptp = refined.peak_to_peak(i).unwrap_or(0.0);
            abs.push(d);
            rel.push(if ptp > 0.0 { d / ptp } else { d });
        }
        Ok(TruncationEstimate {
            max_abs_difference: abs,
            relative_to_peak_to_peak: rel,
            refined,
        })
    }
}

/// Serde default of [`PeriodicSolution::truncation`]: not known.
#[cfg(feature = "serde")]
fn nan() -> f64 {
    f64::NAN
}

/// `max − min` of the samples.
fn spread(values: &[f64]) -> f64 {
    let (lo, hi) = values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    hi - lo
}
