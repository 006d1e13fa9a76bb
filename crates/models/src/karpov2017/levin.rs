//! Levin collocation for the chirps `∫ e^{iψ(s)} ds` of the Duhamel integral (issue 13).
//!
//! On a panel `[a, b]`, `s = m + (L/2)x`, a polynomial `p` of degree `N − 1` in nodal form at
//! the `N` Chebyshev–Lobatto points solves the collocation equations of
//! `p' + iψ' p = 1`; then `d/ds (p e^{iψ}) = e^{iψ} − r e^{iψ}` with the residual
//! `r = p' + iψ'p − 1` gives exactly
//!
//! ```text
//! ∫_a^b e^{iψ} ds = p(b) e^{iψ(b)} − p(a) e^{iψ(a)} − ∫_a^b r e^{iψ} ds,
//! ```
//!
//! so `L·max|r|` (sampled at the `N − 1` points halfway, in angle, between the collocation
//! points, where `r` peaks between its zeros) estimates the error whatever `p` the solve
//! produced; where `ψ'` keeps its sign, `r` vanishing at both ends gives the sharper
//! `|∫ r e^{iψ}| = |∫ (r/ψ')' e^{iψ}| ≤ TV(r/ψ') ≈ 2 Σ |r/ψ'|`. Where `ψ` has a stationary point with a large phase change on the panel no
//! slowly varying `p` exists and the residual is large: the caller shrinks the panel or falls
//! back to Gauss–Legendre.

use math::DetMath;
use std::f64::consts::PI;

use nalgebra::Complex;

/// Collocation points per panel.
pub(super) const N: usize = 16;
/// Check points of the residual.
const M: usize = N - 1;

type C = Complex<f64>;

/// Chebyshev–Lobatto collocation data (built once per run).
pub(super) struct Levin {
    /// Nodes `x_j = cos(πj/(N−1))` (`x_0 = 1`, `x_{N−1} = −1`).
    pub(super) x: [f64; N],
    /// Check points `cos(π(j + ½)/(N−1))`.
    pub(super) y: [f64; M],
    /// Differentiation matrix on the nodes.
    d: [[f64; N]; N],
    /// Interpolation from the nodes to the check points.
    e: [[f64; N]; M],
    /// `e · d`: the derivative at the check points.
    ed: [[f64; N]; M],
}

/// One chirp on one panel.
pub(super) struct Chirp {
    /// `p(b) e^{iψ(b)} − p(a) e^{iψ(a)}`.
    pub(super) value: C,
    /// Truncation estimate: `min(L·max|r|, 2 Σ|r/ψ'|)` over the check points (the second only
    /// where `ψ'` keeps its sign on the panel).
    pub(super) truncation: f64,
    /// `|p(a)| + |p(b)|` (scale of the rounding of the end formula).
    pub(super) scale: f64,
}

impl Levin {
    pub(super) fn new() -> Self {
        let nn = (N - 1) as f64;
        let x: [f64; N] = std::array::from_fn(|j| (PI * j as f64 / nn).dcos());
        let y: [f64; M] = std::array::from_fn(|j| (PI * (j as f64 + 0.5) / nn).dcos());
        let c = |j: usize| if j == 0 || j == N - 1 { 2.0 } else { 1.0 };
        let sign = |j: usize| if j % 2 == 0 { 1.0 } else { -1.0 };
        let mut d = [[0.0; N]; N];
        for i in 0..N {
            let mut diag = 0.0;
            for j in 0..N {
                if i != j {
                    d[i][j] = c(i) / c(j) * sign(i + j) / (x[i] - x[j]);
                    diag -= d[i][j];
                }
            }
            d[i][i] = diag;
        }
        // barycentric weights of the Lobatto points: (−1)^j, halved at the ends
        let w = |j: usize| sign(j) / c(j);
        let mut e = [[0.0; N]; M];
        for (m, row) in e.iter_mut().enumerate() {
            let den: f64 = (0..N).map(|j| w(j) / (y[m] - x[j])).sum();
            for (j, v) in row.iter_mut().enumerate() {
                *v = w(j) / (y[m] - x[j]) / den;
            }
        }
        let mut ed = [[0.0; N]; M];
        for m in 0..M {
            for j in 0..N {
                ed[m][j] = (0..N).map(|k| e[m][k] * d[k][j]).sum();
            }
        }
        Self { x, y, d, e, ed }
    }

    /// `∫ e^{iψ}` over a panel of length `len` given `ψ'` at the nodes (`dpsi`) and at the check
    /// points (`dpsi_y`) and `e^{iψ}` at the ends (`ea` at `x = −1`, `eb` at `x = 1`).
    /// `None` when the collocation matrix is singular.
    pub(super) fn chirp(
        &self,
        len: f64,
        dpsi: &[f64; N],
        dpsi_y: &[f64; M],
        ea: C,
        eb: C,
    ) -> Option<Chirp> {
        let h2 = 2.0 / len;
        let p = match self.iterate(h2, dpsi) {
            Some(p) => p,
            None => {
                let mut a = [[C::new(0.0, 0.0); N]; N];
                for i in 0..N {
                    for j in 0..N {
                        a[i][j] = C::new(h2 * self.d[i][j], 0.0);
                    }
                    a[i][i].im = dpsi[i];
                }
                let mut p = [C::new(1.0, 0.0); N];
                solve(&mut a, &mut p)?;
                p
            }
        };
        let mut rmax = 0.0f64;
        let mut tv = 0.0f64;
        for m in 0..M {
            let (mut q, mut dq) = (C::new(0.0, 0.0), C::new(0.0, 0.0));
            for j in 0..N {
                q += p[j] * self.e[m][j];
                dq += p[j] * self.ed[m][j];
            }
            let r = dq * h2 + C::new(-dpsi_y[m] * q.im, dpsi_y[m] * q.re) - 1.0;
            rmax = rmax.max(r.norm());
            tv += r.norm() / dpsi_y[m].abs();
        }
        if !(rmax.is_finite() && tv.is_finite()) {
            return None;
        }
        // Where ψ' keeps its sign, r vanishes at the ends (Lobatto collocation) and integration
        // by parts gives |∫ r e^{iψ}| = |∫ (r/ψ')' e^{iψ}| ≤ TV(r/ψ'), about 2 Σ |r/ψ'| over the
        // bumps of r between its zeros (peaks near the check points).
        let one_sign = dpsi.iter().chain(dpsi_y).all(|&d| d > 0.0)
            || dpsi.iter().chain(dpsi_y).all(|&d| d < 0.0);
        let truncation = if one_sign {
            (len * rmax).min(2.0 * tv)
        } else {
            len * rmax
        };
        Some(Chirp {
            value: p[0] * eb - p[N - 1] * ea,
            truncation,
            scale: p[0].norm() + p[N - 1].norm(),
        })
    }
}

impl Levin {
    /// Where `|ψ'|` is large the collocation equations are solved by the fixed-point
    /// iteration `p ← p − r/(iψ')` from `p = 1/(iψ')` (the asymptotic series of the slowly
    /// varying solution, `O(N²)` per step instead of the `O(N³)` elimination): at most
    /// `ITER` steps, `None` (use the elimination) unless the nodal residual falls below
    /// `1e-14` and keeps falling.
    fn iterate(&self, h2: f64, dpsi: &[f64; N]) -> Option<[C; N]> {
        const ITER: usize = 12;
        let min = dpsi.iter().fold(f64::INFINITY, |m, d| m.min(d.abs()));
        // the iteration map has norm ~ h2·‖D‖/|ψ'| ≈ h2·0.1 N²/|ψ'| on the highest modes
        if min.is_nan() || min <= 0.2 * h2 * (N * N) as f64 {
            return None;
        }
        let mut p: [C; N] = std::array::from_fn(|j| C::new(0.0, -1.0 / dpsi[j]));
        let mut last = f64::INFINITY;
        for _ in 0..ITER {
            let mut rmax = 0.0f64;
            let mut r = [C::new(0.0, 0.0); N];
            for i in 0..N {
                let mut dp = C::new(0.0, 0.0);
                for j in 0..N {
                    dp += p[j] * self.d[i][j];
                }
                r[i] = dp * h2 + C::new(-dpsi[i] * p[i].im, dpsi[i] * p[i].re) - 1.0;
                rmax = rmax.max(r[i].norm());
            }
            if rmax.is_nan() || rmax >= last {
                return None;
            }
            if rmax <= 1e-14 {
                return Some(p);
            }
            last = rmax;
            for i in 0..N {
                // p −= r/(iψ') = p + i r/ψ'
                p[i] += C::new(-r[i].im, r[i].re) / dpsi[i];
            }
        }
        None
    }
}

/// Gaussian elimination with partial pivoting, `a x = b` in place (`b` becomes `x`); `None` if
/// a pivot vanishes or is not finite.
fn solve(a: &mut [[C; N]; N], b: &mut [C; N]) -> Option<()> {
    let mag = |z: C| z.re.abs() + z.im.abs();
    for k in 0..N {
        let mut piv = k;
        for i in k + 1..N {
            if mag(a[i][k]) > mag(a[piv][k]) {
                piv = i;
            }
        }
        let pm = mag(a[piv][k]);
        if !(pm.is_finite() && pm > 0.0) {
            return None;
        }
        a.swap(k, piv);
        b.swap(k, piv);
        let inv = a[k][k].inv();
        for i in k + 1..N {
            let f = a[i][k] * inv;
            if f.re == 0.0 && f.im == 0.0 {
                continue;
            }
            for j in k + 1..N {
                let t = a[k][j];
                a[i][j] -= f * t;
            }
            let t = b[k];
            b[i] -= f * t;
        }
    }
    for k in (0..N).rev() {
        let mut s = b[k];
        for j in k + 1..N {
            s -= a[k][j] * b[j];
        }
        b[k] = s / a[k][k];
    }
    Some(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Linear phase: `∫_a^b e^{iκs} ds = (e^{iκb} − e^{iκa})/(iκ)` exactly.
    #[test]
    fn linear_phase_is_exact() {
        let lv = Levin::new();
        for (kappa, a, b) in [(3.0, 0.0, 10.0), (-50.0, 2.0, 2.5), (0.7, -1.0, 4.0)] {
            let len = b - a;
            let dpsi = [kappa; N];
            let dpsi_y = [kappa; M];
            let e = |s: f64| {
                let (s_, c_) = (kappa * s).dsin_cos();
                C::new(c_, s_)
            };
            let r = lv.chirp(len, &dpsi, &dpsi_y, e(a), e(b)).unwrap();
            let exact = (e(b) - e(a)) / C::new(0.0, kappa);
            assert!(
                (r.value - exact).norm() < 1e-13,
                "{kappa}: {r:?}",
                r = r.value
            );
            assert!(r.truncation < 1e-12);
        }
    }

    /// Quadratic phase `ψ = s²/2` away from its stationary point against a fine Simpson rule;
    /// across a stationary point with a large phase change the residual flags the failure.
    #[test]
    fn residual_estimates_the_error() {
        let lv = Levin::new();
        let run = |a: f64, b: f64| {
            let len = b - a;
            let mid = 0.5 * (a + b);
            let dpsi: [f64; N] = std::array::from_fn(|j| mid + 0.5 * len * lv.x[j]);
            let dpsi_y: [f64; M] = std::array::from_fn(|j| mid + 0.5 * len * lv.y[j]);
            let e = |s: f64| {
                let (s_, c_) = (0.5 * s * s).dsin_cos();
                C::new(c_, s_)
            };
            let r = lv.chirp(len, &dpsi, &dpsi_y, e(a), e(b)).unwrap();
            let n = 200_000;
            let h = len / n as f64;
            let mut s = C::new(0.0, 0.0);
            for i in 0..=n {
                s += e(a + i as f64 * h) * super::super::simpson_weight(i, n);
            }
            (r, s * (h / 3.0))
        };
        let (r, exact) = run(20.0, 30.0);
        assert!(r.truncation < 1e-9, "{}", r.truncation);
        assert!((r.value - exact).norm() <= r.truncation + 1e-10);
        let (r, exact) = run(-30.0, 30.0);
        assert!(
            r.truncation > (r.value - exact).norm().min(1.0) * 0.1 && r.truncation > 1e-3,
            "{} vs {}",
            r.truncation,
            (r.value - exact).norm()
        );
    }
}
