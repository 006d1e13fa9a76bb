//! Harmonic balance for the 1-DOF (torsional) Yu 2021 models: Kahraman–Singh, or Yu with
//! locked centres. Period-1 response at the mesh frequency, alternating frequency–time
//! residual, Newton with a finite-difference Jacobian.
//!
//! A small local solver: the `hbm` engine crate was a placeholder when this was written.

use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

use crate::Error;

use super::model::{ModelKind, STATE_LEN, Yu2021Model};

/// Harmonic-balance settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct HbmSettings {
    /// Number of harmonics `H` of `ω*` (unknowns `2H + 1`).
    pub harmonics: usize,
    /// Time samples per period of the AFT (≥ 4H + 2; a power of two is customary).
    pub samples: usize,
    /// Residual-norm tolerance.
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
    /// `[c_0, a_1, b_1, …, a_H, b_H]`: `q(τ) = c_0 + Σ a_j cos(jω*τ) + b_j sin(jω*τ)`.
    pub coefficients: Vec<f64>,
    /// Whether the residual norm fell below the tolerance.
    pub converged: bool,
    /// Newton iterations used.
    pub iterations: usize,
    /// Final residual norm.
    pub residual_norm: f64,
}

impl HbmSolution {
    /// Evaluate `q(τ)` (the DTE `δ*` for the torsional models).
    pub fn eval(&self, omega: f64, tau: f64) -> f64 {
        let c = &self.coefficients;
        let mut v = c[0];
        for j in 1..=(c.len() - 1) / 2 {
            let ph = j as f64 * omega * tau;
            v += c[2 * j - 1] * ph.cos() + c[2 * j] * ph.sin();
        }
        v
    }
}

fn residual(model: &Yu2021Model, omega: f64, c: &[f64], n: usize) -> Vec<f64> {
    let h = (c.len() - 1) / 2;
    let period = std::f64::consts::TAU / omega;
    let mut r = vec![0.0; c.len()];
    for i in 0..n {
        let tau = period * i as f64 / n as f64;
        let (mut q, mut dq, mut ddq) = (c[0], 0.0, 0.0);
        for j in 1..=h {
            let wj = j as f64 * omega;
            let (s, co) = (wj * tau).sin_cos();
            let (a, b) = (c[2 * j - 1], c[2 * j]);
            q += a * co + b * s;
            dq += wj * (-a * s + b * co);
            ddq -= wj * wj * (a * co + b * s);
        }
        let mut st = [0.0; STATE_LEN];
        st[0] = q;
        st[5] = dq;
        let res = ddq - model.rhs(omega, tau, &st, None)[5];
        r[0] += res / n as f64;
        for j in 1..=h {
            let (s, co) = (j as f64 * omega * tau).sin_cos();
            r[2 * j - 1] += 2.0 * res * co / n as f64;
            r[2 * j] += 2.0 * res * s / n as f64;
        }
    }
    r
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

impl Yu2021Model {
    /// Period-1 harmonic balance of a torsional model (Kahraman–Singh, or Yu with
    /// `lock_centres`). `guess` (length `2H + 1`) defaults to the static contact solution.
    pub fn harmonic_balance(
        &self,
        omega: f64,
        settings: &HbmSettings,
        guess: Option<&[f64]>,
    ) -> Result<HbmSolution, Error> {
        let torsional = match self.options.kind {
            ModelKind::KahramanSingh => true,
            ModelKind::Yu => self.options.lock_centres,
            ModelKind::ChenFractal => false,
        };
        if !torsional {
            return Err(Error::Solver(
                "yu2021 harmonic balance needs a periodic 1-DOF model (Kahraman-Singh or locked centres)".into(),
            ));
        }
        if !(omega > 0.0 && omega.is_finite()) {
            return Err(Error::invalid("yu2021.omega", "> 0 and finite", omega));
        }
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
        let mut c = match guess {
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
                c[0] = self.initial_state()[0];
                c
            }
        };
        let n = settings.samples;
        let mut r = residual(self, omega, &c, n);
        let mut rn = norm(&r);
        let mut it = 0;
        while rn > settings.tolerance && it < settings.max_iterations {
            it += 1;
            let mut jac = DMatrix::zeros(m, m);
            for k in 0..m {
                let step = 1e-7 * (1.0 + c[k].abs());
                let mut cp = c.clone();
                cp[k] += step;
                let rp = residual(self, omega, &cp, n);
                for i in 0..m {
                    jac[(i, k)] = (rp[i] - r[i]) / step;
                }
            }
            let Some(dx) = jac.lu().solve(&DVector::from_vec(r.clone())) else {
                return Ok(HbmSolution {
                    coefficients: c,
                    converged: false,
                    iterations: it,
                    residual_norm: rn,
                });
            };
            // damped Newton: halve the step until the residual decreases
            let mut lam = 1.0;
            loop {
                let trial: Vec<f64> = c.iter().zip(dx.iter()).map(|(a, d)| a - lam * d).collect();
                let rt = residual(self, omega, &trial, n);
                let nt = norm(&rt);
                if nt < rn || lam < 1e-3 {
                    c = trial;
                    r = rt;
                    rn = nt;
                    break;
                }
                lam *= 0.5;
            }
        }
        Ok(HbmSolution {
            coefficients: c,
            converged: rn <= settings.tolerance,
            iterations: it,
            residual_norm: rn,
        })
    }
}
