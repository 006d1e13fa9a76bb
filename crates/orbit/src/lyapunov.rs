//! Lyapunov exponents of the event-located flow: the variational equations composed with the
//! saltation matrices, renormalised by QR after every window (Benettin, Galgani, Giorgilli &
//! Strelcyn 1980; Shimada & Nagashima 1979; Müller 1995 for the non-smooth flow).
//!
//! ## The method
//!
//! Over windows `[t_j, t_j + τ]`, `j = 0 … N−1`, the window map of the tangent space is the
//! Jacobian of the flow over the window, the product of the smooth variational flows and the
//! saltation matrices `S` of the events met ([`crate::flow`]):
//!
//! ```text
//! Φ_j = Φ(t_j + τ ← t_e,last) S_last ⋯ S_1 Φ(t_e,1 ← t_j)
//! Φ_j Q_j = Q_{j+1} R_j            (modified Gram–Schmidt, columns in order 1 … k)
//! λ_i ≈ Λ_i(N) = (1 / (N − N₀)τ) Σ_{N₀ ≤ j < N} ln |R_j,ii|,     i = 1 … k,   Q_0 = [e_1 … e_k]
//! ```
//!
//! (`N₀` warm-up windows align `Q` before the sum starts, [`LyapunovOptions::warmup`].)
//!
//! `Q_j` (`2n × k`, orthonormal columns) spans the first `k` directions; `R_j` is `k × k` upper
//! triangular with a positive diagonal. `Λ_1 ≥ … ≥ Λ_k` converge to the `k` largest exponents
//! for almost every start. At the backlash kinks (force continuous, state continuous) `S = I`;
//! at a restitution impact `q'⁺ = −r q'⁻` on the stop `h = q − σ`,
//! `S = [[−r, 0], [(a⁺ + r a⁻)/v⁻, −r]]`, `det S = r²`.
//!
//! ## Invariants the tests check
//!
//! * **Volume.** With the full spectrum (`k = 2n`), `Σ_i Λ_i(N) Nτ = ln |det Φ_{N−1} ⋯ Φ_0|`,
//!   and by Liouville `det Φ = exp(∫ tr A dt) · Π det S`. For linear damping, `tr A =
//!   −tr(M⁻¹ C)` whatever the stiffness does (kinks included), so
//!   `Σ λ_i = −tr(M⁻¹C) + (N_impacts ln r²) / (Nτ)` exactly, up to the integrator's error.
//! * **Periodic orbits.** On a period-`T` orbit with `τ = T`, `Φ_j` is the monodromy, the QR
//!   iteration is the orthogonal (subspace) iteration, and `Λ_i → ln |μ_i| / T` with the
//!   Floquet multipliers `μ_i` ordered by modulus.
//!
//! ## Convergence
//!
//! The running estimate `Λ_i(j)` after each window is kept. Its **spread** over the last `K`
//! windows (`max − min`), and over the last half of the run, measure convergence; the run is
//! **converged** when, for every computed exponent,
//! `spread_last_i ≤ rtol |Λ_i(N)| + atol / τ` ([`LyapunovOptions::rtol`],
//! [`LyapunovOptions::atol`]: `atol` is in nepers per window).

use crate::error::{OrbitError, Result, check};
use math::DetMath;
use nalgebra::DMatrix;

/// Cap on [`LyapunovOptions::windows`] (a run stores `windows × exponents` running estimates).
pub const MAX_LYAPUNOV_WINDOWS: usize = 1_000_000;

/// Settings of a QR Lyapunov run ([`lyapunov_qr`], [`OrbitProblem::lyapunov`](crate::OrbitProblem::lyapunov)).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct LyapunovOptions {
    /// Window length `τ` between renormalisations (e.g. the forcing period), `> 0`, finite.
    pub window: f64,
    /// Number of windows `N`, in `[1, MAX_LYAPUNOV_WINDOWS]`.
    pub windows: usize,
    /// Warm-up windows `N₀ < N` renormalised but not accumulated: the QR basis aligns with the
    /// leading directions first, so that the average starts without its alignment transient
    /// (which otherwise decays only as `1/N`).
    pub warmup: usize,
    /// Number of exponents `k`, in `[1, state dimension]`.
    pub exponents: usize,
    /// `K`: the windows over which the convergence spread is taken, in `[1, windows]`.
    pub last: usize,
    /// Relative part of the convergence bound, `≥ 0`, finite.
    pub rtol: f64,
    /// Absolute part of the convergence bound in nepers per window (the bound is `atol / τ`
    /// per unit time), `≥ 0`, finite.
    pub atol: f64,
}

impl Default for LyapunovOptions {
    /// `τ = 1`, 400 windows without warm-up, the largest exponent, spread over the last 50 windows within
    /// `5 % |λ| + 10⁻³/τ`.
    fn default() -> Self {
        Self {
            window: 1.0,
            windows: 400,
            warmup: 0,
            exponents: 1,
            last: 50,
            rtol: 0.05,
            atol: 1e-3,
        }
    }
}

impl LyapunovOptions {
    /// Checks every field against the state dimension `dim`.
    ///
    /// # Errors
    /// [`OrbitError::InvalidInput`] naming the field and its bound.
    pub fn validate(&self, dim: usize) -> Result<()> {
        check(
            self.window.is_finite() && self.window > 0.0,
            "LyapunovOptions::window",
            "> 0 and finite",
            self.window,
        )?;
        check(
            (1..=MAX_LYAPUNOV_WINDOWS).contains(&self.windows),
            "LyapunovOptions::windows",
            "in [1, 1000000]",
            self.windows as f64,
        )?;
        check(
            self.warmup < self.windows,
            "LyapunovOptions::warmup",
            "< windows",
            self.warmup as f64,
        )?;
        check(
            self.exponents >= 1 && self.exponents <= dim,
            "LyapunovOptions::exponents",
            "in [1, state dimension]",
            self.exponents as f64,
        )?;
        check(
            self.last >= 1 && self.last <= self.windows - self.warmup,
            "LyapunovOptions::last",
            "in [1, windows − warmup]",
            self.last as f64,
        )?;
        check(
            self.rtol.is_finite() && self.rtol >= 0.0,
            "LyapunovOptions::rtol",
            ">= 0 and finite",
            self.rtol,
        )?;
        check(
            self.atol.is_finite() && self.atol >= 0.0,
            "LyapunovOptions::atol",
            ">= 0 and finite",
            self.atol,
        )
    }
}

/// The map of the tangent space over one window, as [`lyapunov_qr`]'s caller computes it.
#[derive(Debug, Clone, PartialEq)]
pub struct WindowMap {
    /// `Φ_j`, the Jacobian of the flow over the window (`dim × dim`), saltation included.
    pub jacobian: DMatrix<f64>,
    /// Events located in the window.
    pub events: usize,
    /// Of those, impacts (state resets).
    pub impacts: usize,
}

/// A Lyapunov spectrum with its convergence record.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct LyapunovSpectrum {
    /// `Λ_1 ≥ … ≥ Λ_k` after the last window (per unit time; ordered as the QR columns, which
    /// orders them for a converged run).
    pub exponents: Vec<f64>,
    /// `running[j][i]`: `Λ_i` after window `N₀ + j + 1` (the accumulated windows).
    pub running: Vec<Vec<f64>>,
    /// Per exponent: `max − min` of the running estimate over the last
    /// [`LyapunovOptions::last`] windows.
    pub spread_last: Vec<f64>,
    /// Per exponent: `max − min` of the running estimate over the last half of the windows.
    pub spread_half: Vec<f64>,
    /// Window length `τ`.
    pub window: f64,
    /// Events met over the run.
    pub events: usize,
    /// Of those, impacts.
    pub impacts: usize,
    /// True when `spread_last_i ≤ rtol |Λ_i| + atol/τ` for every exponent.
    pub converged: bool,
}

impl LyapunovSpectrum {
    /// The largest exponent `Λ_1`.
    pub fn largest(&self) -> f64 {
        self.exponents[0]
    }
    /// `Σ Λ_i` of the computed exponents.
    pub fn sum(&self) -> f64 {
        self.exponents.iter().sum()
    }
}

/// Modified Gram–Schmidt of `a` (`m × k`) in place: `a ← Q`, returns the diagonal of `R`
/// (positive). Columns in fixed order; an exactly dependent or non-finite column is an error.
fn mgs(a: &mut DMatrix<f64>, time: f64) -> Result<Vec<f64>> {
    let (m, k) = (a.nrows(), a.ncols());
    let mut diag = vec![0.0; k];
    for j in 0..k {
        for i in 0..j {
            let mut r = 0.0;
            for l in 0..m {
                r += a[(l, i)] * a[(l, j)];
            }
            for l in 0..m {
                let qi = a[(l, i)];
                a[(l, j)] -= r * qi;
            }
        }
        let mut nn = 0.0;
        for l in 0..m {
            nn += a[(l, j)] * a[(l, j)];
        }
        let norm = nn.sqrt();
        if !(norm.is_finite() && norm > 0.0) {
            return Err(OrbitError::NonFinite {
                what: "Lyapunov QR tangent vector (its norm after orthogonalisation is zero or \
                       not finite: the window map's singular values span more than the \
                       precision; shorten the window or ask fewer exponents)",
                time,
            });
        }
        for l in 0..m {
            a[(l, j)] /= norm;
        }
        diag[j] = norm;
    }
    Ok(diag)
}

fn spread(rows: &[Vec<f64>], i: usize) -> f64 {
    let (lo, hi) = rows
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), r| {
            (lo.min(r[i]), hi.max(r[i]))
        });
    hi - lo
}

/// The QR (Benettin / Shimada–Nagashima) Lyapunov spectrum from window maps: the one home of
/// the renormalisation. `advance(j)` integrates window `j` (the caller carries the state) and
/// returns its tangent map `Φ_j` (`dim × dim`); the first `k` columns of the identity start
/// `Q`, `Q ← qr(Φ_j Q)` after each window, `Λ_i = Σ ln R_ii / (jτ)`.
///
/// # Errors
/// Invalid options; a window map of the wrong size or not finite; a tangent vector collapsing
/// to zero (these carry the elapsed time `(j + 1) τ` of the window); any error of `advance`.
pub fn lyapunov_qr<F>(
    dim: usize,
    opts: &LyapunovOptions,
    mut advance: F,
) -> Result<LyapunovSpectrum>
where
    F: FnMut(usize) -> Result<WindowMap>,
{
    check(dim >= 1, "state dimension", ">= 1", dim as f64)?;
    opts.validate(dim)?;
    let k = opts.exponents;
    let tau = opts.window;
    let mut q = DMatrix::<f64>::identity(dim, k);
    let mut pq = DMatrix::<f64>::zeros(dim, k);
    let mut sums = vec![0.0; k];
    let mut running = Vec::with_capacity(opts.windows);
    let (mut events, mut impacts) = (0usize, 0usize);
    for j in 0..opts.windows {
        let w = advance(j)?;
        if w.jacobian.nrows() != dim || w.jacobian.ncols() != dim {
            return Err(OrbitError::DimensionMismatch {
                what: "window Jacobian",
                expected: dim * dim,
                got: w.jacobian.len(),
            });
        }
        let t_end = (j + 1) as f64 * tau; // elapsed time
        if w.jacobian.iter().any(|v| !v.is_finite()) {
            return Err(OrbitError::NonFinite {
                what: "window Jacobian",
                time: t_end,
            });
        }
        events += w.events;
        impacts += w.impacts;
        system::numeric::product_into(&w.jacobian, &q, &mut pq);
        let diag = mgs(&mut pq, t_end)?;
        std::mem::swap(&mut q, &mut pq);
        if j < opts.warmup {
            continue;
        }
        let elapsed = (j + 1 - opts.warmup) as f64 * tau;
        let mut row = vec![0.0; k];
        for i in 0..k {
            sums[i] += diag[i].dln();
            row[i] = sums[i] / elapsed;
        }
        running.push(row);
    }
    let n = running.len();
    let tail = &running[n - opts.last..];
    let half = &running[n - n.div_ceil(2)..];
    let exponents = running[n - 1].clone();
    let spread_last: Vec<f64> = (0..k).map(|i| spread(tail, i)).collect();
    let spread_half: Vec<f64> = (0..k).map(|i| spread(half, i)).collect();
    let converged =
        (0..k).all(|i| spread_last[i] <= opts.rtol * exponents[i].abs() + opts.atol / tau);
    Ok(LyapunovSpectrum {
        exponents,
        running,
        spread_last,
        spread_half,
        window: tau,
        events,
        impacts,
        converged,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A constant linear map `diag(e², e⁻¹)` rotated: exponents exactly `2/τ`, `−1/τ` after
    /// every window once aligned; with a diagonal map, from the first window.
    #[test]
    fn constant_diagonal_map_gives_its_log_moduli() {
        let opts = LyapunovOptions {
            window: 0.5,
            windows: 10,
            exponents: 2,
            last: 5,
            ..Default::default()
        };
        let s = lyapunov_qr(2, &opts, |_| {
            Ok(WindowMap {
                jacobian: DMatrix::from_row_slice(
                    2,
                    2,
                    &[2.0_f64.dexp(), 0.0, 0.0, (-1.0_f64).dexp()],
                ),
                events: 1,
                impacts: 0,
            })
        })
        .unwrap();
        assert!((s.exponents[0] - 4.0).abs() < 1e-13, "{:?}", s.exponents);
        assert!((s.exponents[1] + 2.0).abs() < 1e-13);
        assert_eq!(s.events, 10);
        assert!(s.converged);
        assert!(s.spread_last.iter().all(|&v| v < 1e-12));
        assert_eq!(s.running.len(), 10);
    }

    /// A non-normal constant map `P diag(e², e⁻¹) P⁻¹`: from `Q_0 = I` the average carries an
    /// alignment transient of order `1/N`; after a warm-up the basis is aligned (to
    /// `e^{−3·N₀}`) and every accumulated increment is exactly `2` and `−1` nepers.
    #[test]
    fn warmup_removes_the_alignment_transient() {
        let p = DMatrix::from_row_slice(2, 2, &[1.0, 3.0, 0.5, 1.0]);
        let d = DMatrix::from_row_slice(2, 2, &[2.0_f64.dexp(), 0.0, 0.0, (-1.0_f64).dexp()]);
        let phi = &p * d * p.clone().try_inverse().unwrap();
        let run = |warmup: usize| {
            let o = LyapunovOptions {
                windows: 40,
                warmup,
                exponents: 2,
                last: 10,
                ..Default::default()
            };
            lyapunov_qr(2, &o, |_| {
                Ok(WindowMap {
                    jacobian: phi.clone(),
                    events: 0,
                    impacts: 0,
                })
            })
            .unwrap()
        };
        let cold = run(0);
        assert!(
            (cold.exponents[0] - 2.0).abs() > 1e-4,
            "{:?}",
            cold.exponents
        );
        let warm = run(20);
        assert_eq!(warm.running.len(), 20);
        assert!(
            (warm.exponents[0] - 2.0).abs() < 1e-12,
            "{:?}",
            warm.exponents
        );
        assert!(
            (warm.exponents[1] + 1.0).abs() < 1e-12,
            "{:?}",
            warm.exponents
        );
        assert!(warm.spread_last.iter().all(|&v| v < 1e-12));
    }

    #[test]
    fn invalid_options_and_maps_are_typed_errors() {
        let id = |_| {
            Ok(WindowMap {
                jacobian: DMatrix::identity(2, 2),
                events: 0,
                impacts: 0,
            })
        };
        for (o, field) in [
            (
                LyapunovOptions {
                    window: 0.0,
                    ..Default::default()
                },
                "LyapunovOptions::window",
            ),
            (
                LyapunovOptions {
                    window: f64::NAN,
                    ..Default::default()
                },
                "LyapunovOptions::window",
            ),
            (
                LyapunovOptions {
                    windows: 0,
                    ..Default::default()
                },
                "LyapunovOptions::windows",
            ),
            (
                LyapunovOptions {
                    windows: MAX_LYAPUNOV_WINDOWS + 1,
                    ..Default::default()
                },
                "LyapunovOptions::windows",
            ),
            (
                LyapunovOptions {
                    exponents: 3,
                    ..Default::default()
                },
                "LyapunovOptions::exponents",
            ),
            (
                LyapunovOptions {
                    last: 401,
                    ..Default::default()
                },
                "LyapunovOptions::last",
            ),
            (
                LyapunovOptions {
                    rtol: -1.0,
                    ..Default::default()
                },
                "LyapunovOptions::rtol",
            ),
            (
                LyapunovOptions {
                    atol: f64::INFINITY,
                    ..Default::default()
                },
                "LyapunovOptions::atol",
            ),
        ] {
            match lyapunov_qr(2, &o, id) {
                Err(OrbitError::InvalidInput { field: f, .. }) => assert_eq!(f, field),
                other => panic!("{field}: {other:?}"),
            }
        }
        let o = LyapunovOptions {
            windows: 3,
            last: 2,
            ..Default::default()
        };
        let nan = |_| {
            Ok(WindowMap {
                jacobian: DMatrix::from_element(2, 2, f64::NAN),
                events: 0,
                impacts: 0,
            })
        };
        assert!(matches!(
            lyapunov_qr(2, &o, nan),
            Err(OrbitError::NonFinite { .. })
        ));
        let zero = |_| {
            Ok(WindowMap {
                jacobian: DMatrix::zeros(2, 2),
                events: 0,
                impacts: 0,
            })
        };
        assert!(matches!(
            lyapunov_qr(2, &o, zero),
            Err(OrbitError::NonFinite { .. })
        ));
        let wrong = |_| {
            Ok(WindowMap {
                jacobian: DMatrix::identity(3, 3),
                events: 0,
                impacts: 0,
            })
        };
        assert!(matches!(
            lyapunov_qr(2, &o, wrong),
            Err(OrbitError::DimensionMismatch { .. })
        ));
    }
}
