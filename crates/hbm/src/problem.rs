//! The harmonic balance residual and its Jacobian by alternating frequency/time (AFT).

use crate::error::check_positive;
use crate::{Basis, CoefficientKind, HbmError, SecondOrderSystem};
use fft::{Fft, RealToComplex};
use nalgebra::DMatrix;
use num_complex::Complex;
use std::mem::take;
use std::sync::Arc;

/// A harmonic balance problem: a system, a basis, a base frequency `ω` and an AFT grid, with
/// preallocated FFT plans and buffers (no allocation when evaluating residual and Jacobian unless
/// the system relies on the finite-difference default Jacobian).
///
/// Unknowns: `z[c·n + i]` is coefficient `c` (see [`Basis`]) of degree of freedom `i`. The
/// residual has the same layout: for harmonic `k` and `a, b` the cos/sin coefficient vectors,
///
/// ```text
/// r_0   = K a_0 + ĥ_0
/// r_cos = (K − (kω)² M) a + kω C b + ĥ_cos,k
/// r_sin = (K − (kω)² M) b − kω C a + ĥ_sin,k
/// ```
///
/// where `ĥ` are the Fourier coefficients of `h(t) = g(t, q, q') − f(t)` sampled on
/// `t_m = m T / N`, `T = 2π/ω` (Liu et al. 2021, Eq. 15–17, with the consistent `2/N` scaling of
/// the cosine/sine coefficients, see reading R-LIU-EQ17).
pub struct HbmProblem<S> {
    system: S,
    basis: Basis,
    omega: f64,
    n: usize,
    m: DMatrix<f64>,
    c: DMatrix<f64>,
    k: DMatrix<f64>,
    ws: Workspace,
    dense_lu: crate::DenseLu,
}

/// Work counters of an [`HbmProblem`] (see [`HbmProblem::counters`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct Counters {
    /// Residual evaluations that ran the AFT (a repeated evaluation at the same point is
    /// served from the cache and not counted).
    pub residuals: u64,
    /// Jacobian-vector products of Newton–Krylov (each costs about one residual evaluation:
    /// `2n` FFTs and `N n²` multiplications).
    pub jacobian_products: u64,
}

struct Workspace {
    n_grid: usize,
    fwd: Arc<dyn Fft<f64>>,
    inv: Arc<dyn Fft<f64>>,
    scratch: Vec<Complex<f64>>,
    buf: Vec<Complex<f64>>,
    /// real-to-complex forward plan (the analysis of real samples), its input (`N` reals,
    /// overwritten), its output (bins `0..=N/2`) and scratch
    r2c: Arc<dyn RealToComplex<f64>>,
    rin: Vec<f64>,
    rout: Vec<Complex<f64>>,
    rscratch: Vec<Complex<f64>>,
    /// time samples, time-major: q[m*n + i]
    q: Vec<f64>,
    qd: Vec<f64>,
    h: Vec<f64>,
    gtmp: Vec<f64>,
    /// forcing `f(t_m)` tabulated once per problem and `ω`: ftab[m*n + i]
    ftab: Vec<f64>,
    /// the system's time table (`SecondOrderSystem::fill_time_table`): ttab[m*L + l]
    ttab: Vec<f64>,
    /// `L`, the system's time-table row length
    tab_len: usize,
    /// coefficients of h: hc[c*n + i]
    hc: Vec<f64>,
    /// Jacobian samples: jq[m*n*n + i*n + j]
    jq: Vec<f64>,
    jv: Vec<f64>,
    /// spectra of the Jacobian entries: jq_hat[(i*n + j)*N + l]
    jq_hat: Vec<Complex<f64>>,
    jv_hat: Vec<Complex<f64>>,
    /// the coefficients the samples `q`, `qd`, `h` and `hc` belong to (valid if `last_valid`):
    /// a Newton iteration asks for the residual and Jacobian at the point its line search has
    /// just evaluated, which then costs no AFT
    last_z: Vec<f64>,
    last_valid: bool,
    /// `in_basis[k]`: DFT bin `k` (`k < N`) is the constant or a retained harmonic
    in_basis: Vec<bool>,
    /// `Σ |ĥ_k|²` over the retained bins and over the discarded bins below Nyquist, of the
    /// last AFT (all DOFs)
    spectrum_kept: f64,
    spectrum_tail: f64,
    /// Jacobian-vector products: samples of `δq`, `δq'`, `δh` and coefficients of `δh`
    /// (sized on first use)
    vq: Vec<f64>,
    vqd: Vec<f64>,
    vh: Vec<f64>,
    vhc: Vec<f64>,
    /// work counters (see [`HbmProblem::counters`])
    counters: Counters,
}

impl Workspace {
    fn new(n: usize, n_grid: usize, nc: usize, tab_len: usize) -> Self {
        let (fwd, inv) = crate::plans::plans(n_grid);
        let len = fwd
            .get_inplace_scratch_len()
            .max(inv.get_inplace_scratch_len());
        let r2c = crate::plans::real_forward(n_grid);
        Self {
            n_grid,
            fwd,
            inv,
            scratch: vec![Complex::default(); len],
            buf: vec![Complex::default(); n_grid],
            rin: r2c.make_input_vec(),
            rout: r2c.make_output_vec(),
            rscratch: r2c.make_scratch_vec(),
            r2c,
            q: vec![0.0; n_grid * n],
            qd: vec![0.0; n_grid * n],
            h: vec![0.0; n_grid * n],
            gtmp: vec![0.0; n],
            ftab: vec![0.0; n_grid * n],
            ttab: vec![0.0; n_grid * tab_len],
            tab_len,
            hc: vec![0.0; nc * n],
            jq: vec![0.0; n_grid * n * n],
            jv: vec![0.0; n_grid * n * n],
            jq_hat: vec![Complex::default(); n_grid * n * n],
            jv_hat: vec![Complex::default(); n_grid * n * n],
            last_z: Vec::with_capacity(nc * n),
            last_valid: false,
            in_basis: vec![false; n_grid],
            spectrum_kept: 0.0,
            spectrum_tail: 0.0,
            vq: Vec::new(),
            vqd: Vec::new(),
            vh: Vec::new(),
            vhc: Vec::new(),
            counters: Counters::default(),
        }
    }
}

fn check_matrix(what: &'static str, m: &DMatrix<f64>, n: usize) -> Result<(), HbmError> {
    if m.nrows() != n || m.ncols() != n {
        return Err(HbmError::DimensionMismatch {
            what,
            expected: n * n,
            got: m.nrows() * m.ncols(),
        });
    }
    if m.iter().any(|x| !x.is_finite()) {
        return Err(HbmError::NonFinite { what, time: 0.0 });
    }
    Ok(())
}

impl<S: SecondOrderSystem> HbmProblem<S> {
    /// Build a problem with the default grid size [`Basis::default_grid_size`].
    ///
    /// # Errors
    /// `omega` not finite and > 0, `n_dof() == 0`, matrices of the wrong size or non-finite.
    pub fn new(system: S, basis: Basis, omega: f64) -> Result<Self, HbmError> {
        let n_grid = basis.default_grid_size();
        Self::with_grid_size(system, basis, omega, n_grid)
    }

    /// Build a problem with a user-chosen AFT grid size `N ≥ 2 k_max + 1`.
    ///
    /// # Errors
    /// As [`HbmProblem::new`], and `N` too small.
    pub fn with_grid_size(
        system: S,
        basis: Basis,
        omega: f64,
        n_grid: usize,
    ) -> Result<Self, HbmError> {
        check_positive("omega", omega)?;
        let mut system = system;
        system.set_base_frequency(omega)?;
        let n = system.n_dof();
        if n == 0 {
            return Err(HbmError::InvalidParameter {
                name: "n_dof",
                bound: ">= 1",
                value: 0.0,
            });
        }
        if n_grid < basis.min_grid_size() || n_grid < 2 {
            return Err(HbmError::InvalidParameter {
                name: "grid size N",
                bound: ">= 2 k_max + 1 and >= 2",
                value: n_grid as f64,
            });
        }
        let nc = basis.n_coefficients();
        let mut p = Self {
            system,
            basis,
            omega,
            n,
            m: DMatrix::zeros(n, n),
            c: DMatrix::zeros(n, n),
            k: DMatrix::zeros(n, n),
            ws: Workspace::new(n, n_grid, nc, 0),
            dense_lu: crate::DenseLu::Auto,
        };
        p.mark_basis();
        p.refresh_matrices()?;
        Ok(p)
    }

    /// Mark the DFT bins of the constant and the retained harmonics.
    fn mark_basis(&mut self) {
        let nn = self.ws.n_grid;
        self.ws.in_basis.fill(false);
        self.ws.in_basis[0] = true;
        for &k in self.basis.harmonics() {
            self.ws.in_basis[k % nn] = true;
            self.ws.in_basis[(nn - k % nn) % nn] = true;
        }
    }

    /// Tabulate the time-only functions on the AFT grid: the forcing `f(t_m)` and the system's
    /// time table ([`SecondOrderSystem::fill_time_table`]). Called whenever `ω` or a parameter
    /// changes.
    fn refresh_tables(&mut self) -> Result<(), HbmError> {
        let n = self.n;
        let len = self.system.time_table_len();
        let nn = self.ws.n_grid;
        self.ws.last_valid = false;
        if self.ws.tab_len != len {
            self.ws.tab_len = len;
            self.ws.ttab = vec![0.0; nn * len];
        }
        self.system
            .tabulate_grid(self.omega, nn, &mut self.ws.ftab, &mut self.ws.ttab);
        for m in 0..nn {
            let f = &self.ws.ftab[m * n..(m + 1) * n];
            let row = &self.ws.ttab[m * len..(m + 1) * len];
            if f.iter().chain(row.iter()).any(|x| !x.is_finite()) {
                return Err(HbmError::NonFinite {
                    what: "forcing or time table",
                    time: self.time(m),
                });
            }
        }
        Ok(())
    }

    fn refresh_matrices(&mut self) -> Result<(), HbmError> {
        let (m, c, k) = (
            self.system.mass(),
            self.system.damping(),
            self.system.stiffness(),
        );
        check_matrix("mass matrix", &m, self.n)?;
        check_matrix("damping matrix", &c, self.n)?;
        check_matrix("stiffness matrix", &k, self.n)?;
        self.m = m;
        self.c = c;
        self.k = k;
        self.refresh_tables()
    }

    /// Number of unknowns `n × n_coefficients`.
    pub fn n_unknowns(&self) -> usize {
        self.n * self.basis.n_coefficients()
    }
    /// Number of degrees of freedom.
    pub fn n_dof(&self) -> usize {
        self.n
    }
    /// The basis.
    pub fn basis(&self) -> &Basis {
        &self.basis
    }
    /// Base frequency `ω` (rad per time unit).
    pub fn omega(&self) -> f64 {
        self.omega
    }
    /// AFT grid size `N`.
    pub fn grid_size(&self) -> usize {
        self.ws.n_grid
    }
    /// The system.
    pub fn system(&self) -> &S {
        &self.system
    }
    /// Consume the problem and return the system.
    pub fn into_system(self) -> S {
        self.system
    }

    /// Change the base frequency `ω` (also passed to
    /// [`SecondOrderSystem::set_base_frequency`]).
    ///
    /// # Errors
    /// `omega` not finite and > 0.
    pub fn set_omega(&mut self, omega: f64) -> Result<(), HbmError> {
        check_positive("omega", omega)?;
        self.system.set_base_frequency(omega)?;
        self.omega = omega;
        self.refresh_tables()
    }

    /// Set a named system parameter (see [`SecondOrderSystem::set_parameter`]) and re-read the
    /// matrices.
    ///
    /// # Errors
    /// Whatever the system reports; non-finite values.
    pub fn set_parameter(&mut self, name: &str, value: f64) -> Result<(), HbmError> {
        if !value.is_finite() {
            return Err(HbmError::InvalidParameter {
                name: "continuation parameter",
                bound: "finite",
                value,
            });
        }
        self.system.set_parameter(name, value)?;
        self.refresh_matrices()
    }

    /// Replace the system by another with the same number of degrees of freedom (e.g. the same
    /// model at another speed or load) at base frequency `omega`, keeping the basis, the grid,
    /// the FFT plans and every buffer: the matrices and the time tables are re-read, as after
    /// [`HbmProblem::with_grid_size`]. A solve afterwards gives the same bits as one on a
    /// freshly built problem of the new system.
    ///
    /// # Errors
    /// `omega` not finite and > 0; a different `n_dof()` (the problem is left unchanged);
    /// matrices of the wrong size or non-finite, non-finite time tables.
    pub fn set_system(&mut self, system: S, omega: f64) -> Result<(), HbmError> {
        check_positive("omega", omega)?;
        let mut system = system;
        system.set_base_frequency(omega)?;
        if system.n_dof() != self.n {
            return Err(HbmError::DimensionMismatch {
                what: "degrees of freedom of the new system",
                expected: self.n,
                got: system.n_dof(),
            });
        }
        self.system = system;
        self.omega = omega;
        self.refresh_matrices()
    }

    pub(crate) fn check_len(&self, what: &'static str, len: usize) -> Result<(), HbmError> {
        if len != self.n_unknowns() {
            return Err(HbmError::DimensionMismatch {
                what,
                expected: self.n_unknowns(),
                got: len,
            });
        }
        Ok(())
    }

    /// Time of grid sample `m`.
    fn time(&self, m: usize) -> f64 {
        system::grid_time(self.omega, self.ws.n_grid, m)
    }

    /// Coefficients → time samples of `q` and `q'` (one packed inverse FFT per DOF).
    fn synthesize(&mut self, z: &[f64]) {
        let (mut q, mut qd) = (take(&mut self.ws.q), take(&mut self.ws.qd));
        self.synthesize_into(z, &mut q, &mut qd);
        (self.ws.q, self.ws.qd) = (q, qd);
    }

    /// Coefficients `z` → samples `q[m·n + i]`, `qd[m·n + i]`.
    fn synthesize_into(&mut self, z: &[f64], q: &mut [f64], qd: &mut [f64]) {
        let n = self.n;
        let nn = self.ws.n_grid;
        let w = self.omega;
        for i in 0..n {
            let buf = &mut self.ws.buf;
            buf.fill(Complex::default());
            buf[0] = Complex::new(z[i], 0.0);
            for (j, &k) in self.basis.harmonics().iter().enumerate() {
                let a = z[(2 * j + 1) * n + i];
                let b = z[(2 * j + 2) * n + i];
                // q: X = (a − ib)/2 at +k; q': Y = kω(b + ia)/2; packed as X + iY
                let x = Complex::new(a, -b) * 0.5;
                let y = Complex::new(b, a) * (0.5 * k as f64 * w);
                let kk = k % nn;
                buf[kk] += x + Complex::<f64>::i() * y;
                buf[(nn - kk) % nn] += x.conj() + Complex::<f64>::i() * y.conj();
            }
            self.ws
                .inv
                .process_with_scratch(&mut self.ws.buf, &mut self.ws.scratch);
            for m in 0..nn {
                q[m * n + i] = self.ws.buf[m].re;
                qd[m * n + i] = self.ws.buf[m].im;
            }
        }
    }

    /// Sample `h = g − f` on the grid.
    fn sample_forces(&mut self) -> Result<(), HbmError> {
        let n = self.n;
        let len = self.ws.tab_len;
        for m in 0..self.ws.n_grid {
            let t = self.time(m);
            let ws = &mut self.ws;
            let q = &ws.q[m * n..(m + 1) * n];
            let qd = &ws.qd[m * n..(m + 1) * n];
            let row = &ws.ttab[m * len..(m + 1) * len];
            self.system
                .nonlinear_force_tabulated(t, row, q, qd, &mut ws.gtmp);
            for i in 0..n {
                let v = ws.gtmp[i] - ws.ftab[m * n + i];
                if !v.is_finite() {
                    return Err(HbmError::NonFinite {
                        what: "nonlinear force or forcing",
                        time: t,
                    });
                }
                ws.h[m * n + i] = v;
            }
        }
        Ok(())
    }

    /// Time samples of `h` → coefficients `hc`.
    fn analyse_forces(&mut self) {
        let (h, mut hc) = (take(&mut self.ws.h), take(&mut self.ws.hc));
        let (kept, tail) = self.analyse_into(&h, &mut hc);
        (self.ws.h, self.ws.hc) = (h, hc);
        self.ws.spectrum_kept = kept;
        self.ws.spectrum_tail = tail;
    }

    /// Samples `h[m·n + i]` → coefficients `hc[c·n + i]`; returns `Σ|ĥ_k|²` over the retained
    /// and over the discarded bins below Nyquist.
    fn analyse_into(&mut self, h: &[f64], hc: &mut [f64]) -> (f64, f64) {
        let n = self.n;
        let nn = self.ws.n_grid;
        let scale = 1.0 / nn as f64;
        let (mut kept, mut tail) = (0.0, 0.0);
        let ws = &mut self.ws;
        for i in 0..n {
            for m in 0..nn {
                ws.rin[m] = h[m * n + i];
            }
            // real-to-complex: bins 0..=N/2 (the upper half of a real signal's DFT mirrors
            // them); the lengths are the plan's own, so this cannot fail
            let done = ws
                .r2c
                .process_with_scratch(&mut ws.rin, &mut ws.rout, &mut ws.rscratch);
            debug_assert!(done.is_ok());
            // truncation indicator: bins 0 ≤ k < N/2 (the upper half mirrors them)
            for k in 0..nn.div_ceil(2) {
                let p = ws.rout[k].norm_sqr();
                if ws.in_basis[k] {
                    kept += p;
                } else {
                    tail += p;
                }
            }
            hc[i] = ws.rout[0].re * scale;
            for (j, &k) in self.basis.harmonics().iter().enumerate() {
                // k ≤ (N − 1)/2 (the grid holds at least 2 k_max + 1 points)
                let hk = ws.rout[k % nn];
                hc[(2 * j + 1) * n + i] = 2.0 * hk.re * scale;
                hc[(2 * j + 2) * n + i] = -2.0 * hk.im * scale;
            }
        }
        (kept, tail)
    }

    /// Truncation indicator of the coefficients `z`: the relative size of the part of the
    /// force spectrum the basis discards,
    ///
    /// ```text
    /// ε = sqrt( Σ_i Σ_{k∈T} |ĥ_{i,k}|² ) / sqrt( Σ_i Σ_{k∈B₀} |ĥ_{i,k}|² )
    /// ```
    ///
    /// with `ĥ_{i,k}` the DFT of `h_i = g_i − f_i` on the AFT grid, `B₀` the constant and the
    /// retained harmonics, `T` every other bin `1 ≤ k < N/2`; 0 when `h` vanishes. The
    /// residual only balances `B₀`; `ε` says how much of the force it ignores (0 for a linear
    /// system whose forcing lies in the basis, of order 1 when the basis misses most of the
    /// force, e.g. a hard impact on a short basis). Costs one AFT unless `z` is the point the
    /// last residual was evaluated at.
    ///
    /// # Errors
    /// As [`HbmProblem::residual`].
    pub fn truncation_indicator(&mut self, z: &[f64]) -> Result<f64, HbmError> {
        let mut r = vec![0.0; self.n_unknowns()];
        self.residual(z, &mut r)?;
        let (kept, tail) = (self.ws.spectrum_kept, self.ws.spectrum_tail);
        Ok(if kept + tail > 0.0 {
            (tail / kept.max(f64::MIN_POSITIVE)).sqrt()
        } else {
            0.0
        })
    }

    /// Assemble the residual from `z` and the force coefficients already in the workspace.
    fn assemble_residual(&self, z: &[f64], r: &mut [f64]) {
        self.assemble(&self.ws.hc, z, r);
    }

    /// `r = L(ω) z + hc`: the linear part of the residual plus force coefficients `hc`.
    fn assemble(&self, hc: &[f64], z: &[f64], r: &mut [f64]) {
        let n = self.n;
        for i in 0..n {
            let mut s = hc[i];
            for j in 0..n {
                s += self.k[(i, j)] * z[j];
            }
            r[i] = s;
        }
        for (jh, &k) in self.basis.harmonics().iter().enumerate() {
            let kw = k as f64 * self.omega;
            let (ca, cb) = ((2 * jh + 1) * n, (2 * jh + 2) * n);
            for i in 0..n {
                let mut rc = hc[ca + i];
                let mut rs = hc[cb + i];
                for j in 0..n {
                    let d = self.k[(i, j)] - kw * kw * self.m[(i, j)];
                    let cw = kw * self.c[(i, j)];
                    rc += d * z[ca + j] + cw * z[cb + j];
                    rs += d * z[cb + j] - cw * z[ca + j];
                }
                r[ca + i] = rc;
                r[cb + i] = rs;
            }
        }
    }

    /// Evaluate the harmonic balance residual `r(z)`.
    ///
    /// # Errors
    /// Wrong lengths; non-finite forces or coefficients.
    pub fn residual(&mut self, z: &[f64], r: &mut [f64]) -> Result<(), HbmError> {
        self.check_len("coefficients", z.len())?;
        self.check_len("residual", r.len())?;
        if z.iter().any(|x| !x.is_finite()) {
            return Err(HbmError::NonFinite {
                what: "coefficients",
                time: 0.0,
            });
        }
        if !(self.ws.last_valid && self.ws.last_z == z) {
            self.ws.last_valid = false;
            self.ws.counters.residuals += 1;
            self.synthesize(z);
            self.sample_forces()?;
            self.analyse_forces();
            self.ws.last_z.clear();
            self.ws.last_z.extend_from_slice(z);
            self.ws.last_valid = true;
        }
        self.assemble_residual(z, r);
        Ok(())
    }

    /// Evaluate the residual and its analytic Jacobian `∂r/∂z` (by AFT of the force Jacobians).
    ///
    /// The Jacobian is the exact derivative of the discrete (AFT) residual for any grid size.
    ///
    /// # Errors
    /// As [`HbmProblem::residual`]; wrong Jacobian shape.
    pub fn residual_and_jacobian(
        &mut self,
        z: &[f64],
        r: &mut [f64],
        jac: &mut DMatrix<f64>,
    ) -> Result<(), HbmError> {
        self.residual(z, r)?;
        let nz = self.n_unknowns();
        if jac.nrows() != nz || jac.ncols() != nz {
            return Err(HbmError::DimensionMismatch {
                what: "Jacobian",
                expected: nz * nz,
                got: jac.nrows() * jac.ncols(),
            });
        }
        self.sample_jacobians()?;
        self.jacobian_spectra();
        jac.fill(0.0);
        self.jacobian_entries(None, |i, j, v| jac[(i, j)] += v);
        Ok(())
    }

    /// Fourier spectra of the sampled force-Jacobian entries (`jq_hat`, `jv_hat`, scaled by
    /// `1/N`), from the samples of the last [`sample_jacobians`](Self::sample_jacobians).
    pub(crate) fn jacobian_spectra(&mut self) {
        let n = self.n;
        let nn = self.ws.n_grid;
        let nsq = n * n;
        // spectra of each entry
        let scale = 1.0 / nn as f64;
        for e in 0..nsq {
            for src in 0..2 {
                let samples = if src == 0 { &self.ws.jq } else { &self.ws.jv };
                let out = if src == 0 {
                    &mut self.ws.jq_hat
                } else {
                    &mut self.ws.jv_hat
                };
                // an entry that is zero at every sample (e.g. ∂g/∂q' of a force without
                // damping terms) has a zero spectrum: the FFT is skipped, the result is the same
                if (0..nn).all(|m| samples[m * nsq + e] == 0.0) {
                    out[e * nn..(e + 1) * nn].fill(Complex::default());
                    continue;
                }
                for m in 0..nn {
                    self.ws.buf[m] = Complex::new(samples[m * nsq + e] * scale, 0.0);
                }
                self.ws
                    .fwd
                    .process_with_scratch(&mut self.ws.buf, &mut self.ws.scratch);
                out[e * nn..(e + 1) * nn].copy_from_slice(&self.ws.buf);
            }
        }
    }

    /// The entries of the AFT Jacobian `∂r/∂z` at the point of the last
    /// [`jacobian_spectra`](Self::jacobian_spectra), passed as `add(row, col, value)` (an entry
    /// may come in several parts, to be summed; the linear part first).
    ///
    /// `band = Some(b)`: the Jacobian of the force with its Jacobians low-passed to the
    /// harmonics `|l| ≤ b`, `J_b(t) = Σ_{|l|≤b} Ĵ_l e^{ilωt}` — harmonic `k'` couples to `k` only
    /// where `|k − k'| ≤ b` or `k + k' ≤ b`, a band matrix in the unknowns of an ordered basis
    /// (the preconditioner of Newton–Krylov). `None`: the exact Jacobian.
    pub(crate) fn jacobian_entries<F: FnMut(usize, usize, f64)>(
        &self,
        band: Option<usize>,
        mut add: F,
    ) {
        let n = self.n;
        let nn = self.ws.n_grid;
        let nsq = n * n;
        // linear part
        for i in 0..n {
            for j in 0..n {
                add(i, j, self.k[(i, j)]);
            }
        }
        for (jh, &k) in self.basis.harmonics().iter().enumerate() {
            let kw = k as f64 * self.omega;
            let (ca, cb) = ((2 * jh + 1) * n, (2 * jh + 2) * n);
            for i in 0..n {
                for j in 0..n {
                    let d = self.k[(i, j)] - kw * kw * self.m[(i, j)];
                    let cw = kw * self.c[(i, j)];
                    add(ca + i, ca + j, d);
                    add(ca + i, cb + j, cw);
                    add(cb + i, cb + j, d);
                    add(cb + i, ca + j, -cw);
                }
            }
        }
        // nonlinear part: row coefficient (k, kind) of J(θ)·φ_col(θ)
        let nc = self.basis.n_coefficients();
        let w = self.omega;
        let half_i = Complex::new(0.0, -0.5); // 1/(2i)
        let hs = self.basis.harmonics();
        let sorted = hs.windows(2).all(|w| w[0] < w[1]);
        for e in 0..nsq {
            let (i, j) = (e / n, e % n);
            let jq = &self.ws.jq_hat[e * nn..(e + 1) * nn];
            let jv = &self.ws.jv_hat[e * nn..(e + 1) * nn];
            let at = |spec: &[Complex<f64>], l: i64| match band {
                Some(b) if l.unsigned_abs() > b as u64 => Complex::default(),
                _ => spec[l.rem_euclid(nn as i64) as usize],
            };
            for col in 0..nc {
                let (kp, kind_p) = self
                    .basis
                    .coefficient(col)
                    .unwrap_or((0, CoefficientKind::Constant));
                let kp = kp as i64;
                // P_k of J·φ (φ = column function), and of Jv·φ' (φ' = time derivative)
                let prod = |k: i64| -> Complex<f64> {
                    match kind_p {
                        CoefficientKind::Constant => at(jq, k),
                        CoefficientKind::Cos => {
                            let pq = (at(jq, k - kp) + at(jq, k + kp)) * 0.5;
                            // d/dt cos(kpθ) = −kp ω sin(kpθ)
                            let pv = (at(jv, k - kp) - at(jv, k + kp)) * half_i;
                            pq - pv * (kp as f64 * w)
                        }
                        CoefficientKind::Sin => {
                            let pq = (at(jq, k - kp) - at(jq, k + kp)) * half_i;
                            // d/dt sin(kpθ) = kp ω cos(kpθ)
                            let pv = (at(jv, k - kp) + at(jv, k + kp)) * 0.5;
                            pq + pv * (kp as f64 * w)
                        }
                    }
                };
                // (k + k' ≤ b implies |k − k'| ≤ b: one condition)
                let coupled = |k: i64| band.is_none_or(|b| (k - kp).unsigned_abs() <= b as u64);
                if coupled(0) {
                    add(i, col * n + j, prod(0).re);
                }
                let rows = match band {
                    Some(b) if sorted => {
                        let (lo, hi) = (kp - b as i64, kp + b as i64);
                        hs.partition_point(|&k| (k as i64) < lo)
                            ..hs.partition_point(|&k| (k as i64) <= hi)
                    }
                    _ => 0..hs.len(),
                };
                for jh in rows {
                    let k = hs[jh];
                    if !coupled(k as i64) {
                        continue;
                    }
                    let p = prod(k as i64);
                    add((2 * jh + 1) * n + i, col * n + j, 2.0 * p.re);
                    add((2 * jh + 2) * n + i, col * n + j, -(2.0 * p.im));
                }
            }
        }
    }

    /// Sample the force Jacobians `∂g/∂q`, `∂g/∂q'` at the samples of the last residual.
    fn sample_jacobians(&mut self) -> Result<(), HbmError> {
        let n = self.n;
        let nsq = n * n;
        let len = self.ws.tab_len;
        for m in 0..self.ws.n_grid {
            let t = self.time(m);
            let ws = &mut self.ws;
            let q = &ws.q[m * n..(m + 1) * n];
            let qd = &ws.qd[m * n..(m + 1) * n];
            let row = &ws.ttab[m * len..(m + 1) * len];
            let (a, b) = (
                &mut ws.jq[m * nsq..(m + 1) * nsq],
                &mut ws.jv[m * nsq..(m + 1) * nsq],
            );
            self.system.force_jacobian_tabulated(t, row, q, qd, a, b);
            if a.iter().chain(b.iter()).any(|x| !x.is_finite()) {
                return Err(HbmError::NonFinite {
                    what: "force Jacobian",
                    time: t,
                });
            }
        }
        Ok(())
    }

    /// Evaluate the residual at `z` into `r` and sample the force Jacobians there, for
    /// [`jacobian_times`](Self::jacobian_times); returns the period means `(J̄_q, J̄_v)` of
    /// `∂g/∂q` and `∂g/∂q'` (row-major `n × n`), the harmonic-diagonal part of the Jacobian.
    pub(crate) fn prepare_jacobian_products(
        &mut self,
        z: &[f64],
        r: &mut [f64],
    ) -> Result<(Vec<f64>, Vec<f64>), HbmError> {
        self.residual(z, r)?;
        self.sample_jacobians()?;
        let (n, nn) = (self.n, self.ws.n_grid);
        let nsq = n * n;
        let (mut mq, mut mv) = (vec![0.0; nsq], vec![0.0; nsq]);
        for m in 0..nn {
            for e in 0..nsq {
                mq[e] += self.ws.jq[m * nsq + e];
                mv[e] += self.ws.jv[m * nsq + e];
            }
        }
        for e in 0..nsq {
            mq[e] /= nn as f64;
            mv[e] /= nn as f64;
        }
        Ok((mq, mv))
    }

    /// `out = J v`, the exact product of the AFT Jacobian (at the point of the last
    /// [`prepare_jacobian_products`](Self::prepare_jacobian_products)) with `v`, by AFT:
    /// `δh(t_m) = ∂g/∂q(t_m) δq(t_m) + ∂g/∂q'(t_m) δq'(t_m)`, `2n` FFTs, no matrix.
    pub(crate) fn jacobian_times(&mut self, v: &[f64], out: &mut [f64]) {
        self.ws.counters.jacobian_products += 1;
        let (n, nn) = (self.n, self.ws.n_grid);
        let nsq = n * n;
        let (mut dq, mut dqd) = (take(&mut self.ws.vq), take(&mut self.ws.vqd));
        dq.resize(nn * n, 0.0);
        dqd.resize(nn * n, 0.0);
        self.synthesize_into(v, &mut dq, &mut dqd);
        let mut dh = take(&mut self.ws.vh);
        dh.resize(nn * n, 0.0);
        for m in 0..nn {
            for i in 0..n {
                let mut s = 0.0;
                for j in 0..n {
                    s += self.ws.jq[m * nsq + i * n + j] * dq[m * n + j]
                        + self.ws.jv[m * nsq + i * n + j] * dqd[m * n + j];
                }
                dh[m * n + i] = s;
            }
        }
        let mut dhc = take(&mut self.ws.vhc);
        dhc.resize(self.n_unknowns(), 0.0);
        self.analyse_into(&dh, &mut dhc);
        self.assemble(&dhc, v, out);
        (self.ws.vq, self.ws.vqd, self.ws.vh, self.ws.vhc) = (dq, dqd, dh, dhc);
    }

    /// The work done since the problem was built (or since [`reset_counters`](Self::reset_counters)):
    /// a deterministic measure of a solver's cost, independent of the machine.
    pub fn counters(&self) -> Counters {
        self.ws.counters
    }

    /// Which LU the dense [`Method::Newton`](crate::Method::Newton) solves of
    /// [`solve`](Self::solve) use ([`DenseLu::Auto`](crate::DenseLu::Auto) unless set).
    pub fn dense_lu(&self) -> crate::DenseLu {
        self.dense_lu
    }

    /// Choose the LU of the dense Newton solves ([`DenseLu`](crate::DenseLu)); kept by
    /// [`set_system`](Self::set_system) and clones.
    pub fn set_dense_lu(&mut self, lu: crate::DenseLu) {
        self.dense_lu = lu;
    }

    /// Set the [`counters`](Self::counters) to zero.
    pub fn reset_counters(&mut self) {
        self.ws.counters = Counters::default();
    }

    /// The system's mass, damping and stiffness matrices as currently cached.
    pub(crate) fn matrices(&self) -> (&DMatrix<f64>, &DMatrix<f64>, &DMatrix<f64>) {
        (&self.m, &self.c, &self.k)
    }
}

impl<S: SecondOrderSystem + Clone> Clone for HbmProblem<S> {
    fn clone(&self) -> Self {
        Self {
            system: self.system.clone(),
            basis: self.basis.clone(),
            omega: self.omega,
            n: self.n,
            m: self.m.clone(),
            c: self.c.clone(),
            k: self.k.clone(),
            ws: Workspace {
                ftab: self.ws.ftab.clone(),
                ttab: self.ws.ttab.clone(),
                tab_len: self.ws.tab_len,
                in_basis: self.ws.in_basis.clone(),
                ..Workspace::new(self.n, self.ws.n_grid, self.basis.n_coefficients(), 0)
            },
            dense_lu: self.dense_lu,
        }
    }
}

impl<S: std::fmt::Debug> std::fmt::Debug for HbmProblem<S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("HbmProblem")
            .field("system", &self.system)
            .field("basis", &self.basis)
            .field("omega", &self.omega)
            .field("grid_size", &self.ws.n_grid)
            .finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `g = q²`, no linear part: the residual is the spectrum of `q²`.
    struct Square;
    impl SecondOrderSystem for Square {
        fn n_dof(&self) -> usize {
            1
        }
        fn mass(&self) -> DMatrix<f64> {
            DMatrix::zeros(1, 1)
        }
        fn damping(&self) -> DMatrix<f64> {
            DMatrix::zeros(1, 1)
        }
        fn nonlinear_force(&self, _t: f64, q: &[f64], _qd: &[f64], g: &mut [f64]) {
            g[0] = q[0] * q[0];
        }
        fn forcing(&self, _t: f64, f: &mut [f64]) {
            f[0] = 0.0;
        }
    }

    #[test]
    fn aft_reproduces_product_spectrum() {
        // q = 0.5 + cos θ + 2 sin θ → q² = 0.25 + 2.5 + cos θ + 2 sin θ − 1.5 cos 2θ + 2 sin 2θ
        let mut p = HbmProblem::new(Square, Basis::full(3).unwrap(), 2.0).unwrap();
        let z = [0.5, 1.0, 2.0, 0.0, 0.0, 0.0, 0.0];
        let mut r = [0.0; 7];
        p.residual(&z, &mut r).unwrap();
        let exact = [2.75, 1.0, 2.0, -1.5, 2.0, 0.0, 0.0];
        for (a, b) in r.iter().zip(exact) {
            assert!((a - b).abs() < 1e-13, "{r:?}");
        }
        assert_eq!(p.grid_size(), 16);
        assert_eq!(p.n_unknowns(), 7);
    }
}
