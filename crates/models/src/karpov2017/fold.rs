//! Period folding of the Duhamel integral (issue 13).
//!
//! `g(kωs)` has the period `T = 2π/(kω)` in `s`, and in both readings the phases of the two
//! chirps are, for `s = u + nT`,
//!
//! ```text
//! ψ±(u + nT) = b±(u) + nT·a±(u),   b± = u ± Φ(u),
//! a± = 1 ± ω(1 + g(kωu))   (printed: Φ = ω(1 + g)s),
//! a± = 1 ± ω               (accumulated: Φ = ωs + G(kωs)/k),
//! ```
//!
//! so the sum over `N` whole periods from `s₀` is one integral over a single period,
//!
//! ```text
//! ∫_{s₀}^{s₀+NT} e^{iψ±} ds = ∫_{s₀}^{s₀+T} e^{ib±(u)} D_N(T a±(u)) du,
//! D_N(x) = Σ_{n<N} e^{inx} = e^{i(N−1)δ/2} sin(Nδ/2)/sin(δ/2),   δ = x − 2π·round(x/2π),
//! ```
//!
//! (`D_N(0) = N`). The geometric sum over the periods is done in closed form at every node, so
//! the work no longer grows with the square of `τ_end` (the printed reading's total phase,
//! `~ωkω·max|g'|·τ²`) but with the phase of the folded integrand over one period,
//! `T·max(1 + |Φ'|) + N·T·ω·TV(g) ≈ 4Bωτ_end` (`D_N(T a(u))` is a trigonometric polynomial
//! of degree `N − 1` in `x = T a(u)`, so its local frequency in `u` is at most `N·T·|a'(u)|`).
//!
//! The folded integral is taken by the same phase-bounded pairs of 10-point Gauss–Legendre
//! panels as the direct rule: the pair length `L` obeys `r L + M₂ L²/2 ≤ 2θ` with the rate
//! `r = 1 + |Φ'(u)| + N T ω kω |g'(kωu)|` at the pair's start and `M₂` a bound of its
//! derivative (`max|Φ''| + N T ω (kω)² max|g''|`); one more panel over each pair gives the
//! error estimate, summed with signs as in the direct rule.

use std::f64::consts::TAU;

use nalgebra::Complex;

use std::cell::OnceCell;

use super::{Acc, EMBED_PAIR, Kernel, MAX_PANELS, Rot, level_rot};
use crate::Error;
use crate::trig::sin_cos;

/// `N` whole periods `T` folded onto `[s₀, s₀ + T]`.
#[derive(Debug, Clone, Copy)]
pub(super) struct Fold {
    /// Start of the folded stretch.
    pub s0: f64,
    /// Period `T = 2π/(kω)` of `g(kωs)`.
    pub period: f64,
    /// Number of periods `N` (≥ 2), as `f64`.
    pub n: f64,
    /// `±D_N(T a±)` as `σ R± e^{ih±}` (`R± = sin(Nδ/2)/sin(δ/2)`, `h± = (N − 1)δ/2`) for
    /// `σ = +1, −1` when `a±` does not depend on `u` (the accumulated reading): computed once
    /// per fold by [`integrate`] instead of at every node.
    pub fixed_rotors: Option<[Complex<f64>; 2]>,
}

impl Fold {
    /// The fold of period `T = period` that ends at `t_w`: `N = ⌊t_w/T⌋` periods after a
    /// head `[0, s₀)`, `s₀ = t_w − N T < T`. `None` when fewer than two periods fit (or `T`
    /// is not finite).
    pub fn ending_at(period: f64, t_w: f64) -> Option<Self> {
        if !(period.is_finite() && period > 0.0 && t_w.is_finite()) {
            return None;
        }
        let n = (t_w / period).floor();
        if !(2.0..1e15).contains(&n) {
            return None;
        }
        let s0 = (t_w - n * period).max(0.0);
        Some(Self {
            s0,
            period,
            n,
            fixed_rotors: None,
        })
    }
}

/// `q` rounded to an integer: by adding and subtracting `1.5·2⁵²` below `2⁵¹` in magnitude
/// (ties to even; `f64::round`, ties away from zero, is a library call on the baseline x86-64
/// target), `f64::round` beyond and for NaN. `D_N` is `2π`-periodic in `x`, so any integer
/// would do; this one is `round` except at exact ties.
#[inline]
fn round_int(q: f64) -> f64 {
    const SHIFT: f64 = 6_755_399_441_055_744.0;
    if q.abs() < 2_251_799_813_685_248.0 {
        (q + SHIFT) - SHIFT
    } else {
        q.round()
    }
}

/// `(sin(Nδ/2)/sin(δ/2), (N − 1)δ/2)` with `δ = x − 2π round(x/2π)`, `x = T(1 + σA)`: the
/// modulus-and-phase form of `D_N(x)` (`(N, 0)` at `δ = 0`).
#[inline]
fn dirichlet(f: &Fold, big_a: f64, sigma: f64) -> (f64, f64) {
    let x = f.period * (1.0 + sigma * big_a);
    let d = x - TAU * round_int(x / TAU);
    if d == 0.0 {
        (f.n, 0.0)
    } else {
        (
            sin_cos(0.5 * f.n * d).0 / sin_cos(0.5 * d).0,
            0.5 * (f.n - 1.0) * d,
        )
    }
}

impl Kernel {
    /// `|g'(θ)| = |c(ε + cos θ)|/(1 + ε cos θ)²`.
    #[inline]
    fn g_prime_abs(&self, ct: f64) -> f64 {
        let den = 1.0 + self.eps * ct;
        (self.c * (self.eps + ct) / (den * den)).abs()
    }

    /// `e^{ib₊}D_N(T a₊) − e^{ib₋}D_N(T a₋)` at `u` (`= 2i ×` the folded `e^{iu} sin Φ`),
    /// given `sin`, `cos` of `kωu`, `e^{iu}` and `e^{iωu}` (the rotations of exactly the same
    /// node), and `|D_N(T a₊)| + |D_N(T a₋)|` (0 with `f.fixed_rotors`, whose moduli are
    /// fixed).
    #[inline]
    fn folded(
        &self,
        u: f64,
        (st, ct): (f64, f64),
        eu: Complex<f64>,
        ewu: Complex<f64>,
        f: &Fold,
    ) -> (Complex<f64>, f64) {
        if let Some([p, m]) = f.fixed_rotors {
            // accumulated: e^{iΦ} = e^{iωu} e^{iG/k}, and the sum is
            // e^{iu}(R₊e^{ih₊} e^{iΦ} − R₋e^{ih₋} e^{−iΦ}): no large phase is rounded
            let (sg, cg) = sin_cos(self.g_over_k(ct));
            let e = ewu * Complex::new(cg, sg);
            return (eu * (p * e - m * e.conj()), 0.0);
        }
        let phi = self.phi(u, st, ct);
        let big_a = self.w * (1.0 + self.c * st / (1.0 + self.eps * ct));
        let mut out = Complex::new(0.0, 0.0);
        let mut amp = 0.0;
        for sigma in [1.0, -1.0] {
            let b = u + sigma * phi;
            let (ratio, half) = dirichlet(f, big_a, sigma);
            let (s, c) = sin_cos(b + half);
            out += Complex::new(c, s) * (sigma * ratio);
            amp += ratio.abs();
        }
        (out, amp)
    }

    /// 10-point Gauss–Legendre panel of [`Kernel::folded`] over `[u, u + r.h]`, as
    /// `(ΔC, ΔS)`, and the same sum with the weights `e` of the embedded estimate
    /// ([`EMBED_PAIR`]), and `∫|D_N(T a₊)| + |D_N(T a₋)|` over the panel (the weight of the
    /// rounding estimate); the nodes' `e^{iu}`, `e^{ikωu}` by rotating the midpoint's by `r`.
    fn folded_panel(
        &self,
        u: f64,
        r: &Rot,
        f: &Fold,
        e: &[f64; 10],
    ) -> ((f64, f64), (f64, f64), f64) {
        let half = 0.5 * r.h;
        let mid = u + half;
        let (sm, cm) = sin_cos(mid);
        let (stm, ctm) = sin_cos(self.kw * mid);
        let ewm = if f.fixed_rotors.is_some() {
            let (s, c) = sin_cos(self.w * mid);
            Complex::new(c, s)
        } else {
            Complex::new(1.0, 0.0)
        };
        let mut acc = Complex::new(0.0, 0.0);
        let mut est = Complex::new(0.0, 0.0);
        let mut amp = 0.0;
        for i in 0..10 {
            let (sd, cd) = r.s[i];
            let (sdt, cdt) = r.th[i];
            let (sdw, cdw) = r.om[i];
            let eu = Complex::new(cm * cd - sm * sd, sm * cd + cm * sd);
            let ewu = ewm * Complex::new(cdw, sdw);
            let st = stm * cdt + ctm * sdt;
            let ct = ctm * cdt - stm * sdt;
            let x = mid + half * self.gl.nodes[i];
            let (v, a) = self.folded(x, (st, ct), eu, ewu, f);
            acc += v * self.gl.weights[i];
            est += v * e[i];
            amp += a * self.gl.weights[i];
        }
        if let Some([p, m]) = f.fixed_rotors {
            amp = 2.0 * (p.norm() + m.norm());
        }
        // (I₊ − I₋)/(2i)
        let v = acc * Complex::new(0.0, -0.5 * half);
        let d = est * Complex::new(0.0, -0.5 * half);
        ((v.re, v.im), (d.re, d.im), amp * half)
    }

    /// Local frequency bound of the folded integrand at `u` (see the module docs).
    fn folded_rate(&self, u: f64, f: &Fold) -> f64 {
        let base = 1.0 + self.phi_rate(u).abs();
        if self.printed {
            let ct = sin_cos(self.kw * u).1;
            base + f.n * f.period * self.w * self.kw * self.g_prime_abs(ct)
        } else {
            base
        }
    }

    /// Bound of the derivative of [`Kernel::folded_rate`] on the folded period.
    fn folded_m2(&self, f: &Fold) -> f64 {
        let m2 = self.m2(f.s0 + f.period);
        if self.printed {
            m2 + f.n * f.period * self.w * self.kw * self.kw * self.g2
        } else {
            m2
        }
    }
}

/// Estimated panels of [`integrate`] at budget `theta`: two per pair, the pairs from the
/// phase of the folded integrand over the period (`T(1 + ω(1 + B) + (s₀ + T)ω kω max|g'|)`
/// bounds the `1 + |Φ'|` part, `N T ω·TV(g) = 4BωNT` the `D_N` part) over `2θ`, plus the
/// pairs the chirp bound `M₂` alone allows (`T·√(M₂/(4θ))`).
pub(super) fn panel_estimate(ker: &Kernel, f: &Fold, theta: f64, b: f64) -> f64 {
    let t = f.period;
    let base = t * (1.0 + ker.w * (1.0 + b));
    let chirp = if ker.printed {
        t * (f.s0 + t) * ker.w * ker.kw * ker.g1 + 4.0 * b * ker.w * f.n * t
    } else {
        0.0
    };
    let m2 = ker.folded_m2(f);
    2.0 * ((base + chirp) / (2.0 * theta) + t * (m2 / (4.0 * theta)).sqrt() + 1.0)
}

/// Integrate the folded period `[s₀, s₀ + T]` into `acc` with phase budget `theta` per panel
/// (pairs of panels as in the direct rule, their embedded differences into the estimate).
///
/// Ends: each pair advances `u` by a positive length (checked; typed error otherwise) and is
/// counted against `MAX_PANELS`.
pub(super) fn integrate(
    ker: &Kernel,
    table: &[OnceCell<Rot>],
    f: &Fold,
    theta: f64,
    acc: &mut Acc,
) -> Result<(), Error> {
    // accumulated reading: `a± = 1 ± ω` at every node, so `D_N(T a±)` is one pair of numbers
    let rotor = |sigma: f64| {
        let (ratio, half) = dirichlet(f, ker.w, sigma);
        let (s, c) = sin_cos(half);
        Complex::new(c, s) * (sigma * ratio)
    };
    let f = &Fold {
        fixed_rotors: (!ker.printed).then(|| [rotor(1.0), -rotor(-1.0)]),
        ..*f
    };
    let end = f.s0 + f.period;
    let m2 = ker.folded_m2(f);
    let mut u = f.s0;
    while u < end {
        if acc.panels >= MAX_PANELS {
            return Err(Error::Quadrature {
                reason: format!("Duhamel integral (folded): panel budget {MAX_PANELS} exhausted"),
                at: u,
            });
        }
        let r = ker.folded_rate(u, f);
        let l = 4.0 * theta / (r + (r * r + 4.0 * m2 * theta).sqrt());
        let done = u + l >= end;
        let h = if done { 0.5 * (end - u) } else { 0.5 * l };
        // the panel lengths rounded down to the tabulated levels (the node rotations reused)
        let fine = if done {
            ker.rot_with(h, !ker.printed)
        } else {
            level_rot(ker, table, theta, h)
        };
        let h = fine.h;
        if h.is_nan() || h <= 0.0 || (!done && u + h <= u) {
            return Err(Error::Quadrature {
                reason: format!("Duhamel integral (folded): panel length {h:e} does not advance"),
                at: u,
            });
        }
        let (first, e1, a1) = ker.folded_panel(u, &fine, f, &EMBED_PAIR[0]);
        let (second, e2, a2) = ker.folded_panel(u + h, &fine, f, &EMBED_PAIR[1]);
        acc.add(first);
        acc.add(second);
        acc.check(e1, e2);
        // rounding: the phases b± + (N − 1)δ/2 of the nodes, each rounded to ε of its size,
        // weighted by |D_N| (`Acc::round`)
        let psi = ker.phase_bound(u + 2.0 * h) + (f.n - 1.0) * std::f64::consts::PI;
        acc.round += f64::EPSILON * (a1 + a2) * psi;
        u = if done { end } else { u + 2.0 * h };
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `round_int` is `f64::round` except at exact ties (to even there), and beyond `2⁵¹`;
    /// `D_N` does not depend on which integer is taken (`x` and `x + 2π` give the same value).
    #[test]
    #[allow(clippy::float_cmp)]
    fn round_int_rounds_and_the_dirichlet_kernel_is_periodic() {
        for q in [
            0.0, 0.3, -0.3, 0.7, -0.7, 1.49, -1.51, 12_345.678, -9.0e14, 3.0e15, 1e300,
        ] {
            // equal values (the sign of a zero may differ: −0.3 gives +0, `round` −0)
            assert!(round_int(q) == q.round(), "{q}");
        }
        assert_eq!(round_int(2.5).to_bits(), 2.0f64.to_bits());
        assert_eq!(round_int(-3.5).to_bits(), (-4.0f64).to_bits());
        assert!(round_int(f64::NAN).is_nan());
        let f = Fold::ending_at(62.83, 1e5).unwrap();
        for big_a in [0.3, 1.0, 1.0 + 1e-3, 1.7] {
            for sigma in [1.0, -1.0] {
                let (r, h) = dirichlet(&f, big_a, sigma);
                let d = Complex::from_polar(r, h);
                // the geometric sum directly
                let x = f.period * (1.0 + sigma * big_a);
                let mut sum = Complex::new(0.0, 0.0);
                for n in 0..f.n as u64 {
                    sum += Complex::from_polar(1.0, n as f64 * x);
                }
                assert!(
                    (d - sum).norm() <= 1e-9 * f.n,
                    "{big_a} {sigma}: {d} vs {sum}"
                );
            }
        }
    }
}
