//! The quadrature engine of Karpov's Duhamel integral (the module docs of `karpov2017`,
//! "Methods"): one run over phase-bounded Gauss–Legendre pairs with the bulk by pairs, Levin
//! panels (`super::levin`) or period folding (`super::fold`); the last cycle sampled with its
//! extrema refined; the kernel of the integrand `e^{i(s ± Φ(s))}` with its rotors, the
//! accumulators with their error estimate, and the panel-count estimate. The model (`super`)
//! holds the parameters, the phase and the public entry points (`duhamel*`).

use math::DetMath;
use std::cell::OnceCell;
use std::f64::consts::TAU;
use std::sync::OnceLock;

use nalgebra::Complex;
use system::numeric::GaussLegendre;

use super::{
    AmplitudeMeasure, Excitation, Karpov2017, KarpovResponse, LAST_CYCLE_PHASE, LEVELS,
    LEVELS_PER_OCTAVE, MAX_PANELS, SAMPLE, fold, levin,
};
use crate::Error;
use crate::fastlog::ln;
use crate::trig::sin_cos;

impl Karpov2017 {
    pub(super) fn panel_estimate_with(&self, ker: &Kernel, theta: f64) -> f64 {
        let a_min = 1.0 + self.p.omega * (1.0 - self.p.b);
        let m2_min = ker.m2(0.0);
        let l_max = 4.0 * theta / (a_min + (a_min * a_min + 4.0 * m2_min * theta).sqrt());
        (2.0 * self.p.tau_end / l_max).max(self.p.tau_end * a_min / (2.0 * theta))
    }

    /// One quadrature run: Gauss–Legendre panels of phase budget `theta` everywhere, or, with
    /// `levin = Some(settings)`, Levin panels in the bulk `[0, τ_end − T]` where their residual
    /// passes and Gauss–Legendre panels elsewhere (see [`Karpov2017::duhamel_tol`]).
    pub(super) fn run(&self, theta: f64, bulk: Bulk) -> Result<KarpovResponse, Error> {
        if !(theta.is_finite() && (1e-3..=8.0).contains(&theta)) {
            return Err(Error::invalid(
                "karpov2017.phase_budget",
                "in [1e-3, 8]",
                theta,
            ));
        }
        // Each pair of panels spans a phase of at most 2θ and the phase advances at least at
        // 1 + ω(1 − B) (the smallest |Φ'| + 1), so at least this many panels are needed: refuse
        // at once what the budget cannot hold instead of running into it.
        let estimate = self.p.tau_end * (1.0 + self.p.omega * (1.0 - self.p.b)) / (2.0 * theta);
        if estimate.is_nan() || estimate > MAX_PANELS as f64 {
            return Err(Error::Quadrature {
                reason: format!(
                    "Duhamel integral: about {estimate:.3e} panels needed for tau_end = {} and \
                     omega = {}, over the budget of {MAX_PANELS} panels",
                    self.p.tau_end, self.p.omega
                ),
                at: 0.0,
            });
        }
        let ker = Kernel::new(self);
        let estimate = self.panel_estimate_with(&ker, theta);
        if estimate.is_nan() || estimate > MAX_PANELS as f64 {
            return Err(Error::Quadrature {
                reason: format!(
                    "Duhamel integral: about {estimate:.3e} panels needed (the chirp of k = {} \
                     included), over the budget of {MAX_PANELS} panels",
                    self.p.k
                ),
                at: 0.0,
            });
        }
        // node rotations of the quantised panel lengths, each level computed when first used
        // (kept for the thread's next run with the same θ, ω, k and reading: `RotTable`)
        let rots = RotTable::take(&ker, theta);
        let table = &rots.levels[..];
        let tau_end = self.p.tau_end;
        let t_w = (tau_end - self.last_cycle()).max(0.0);
        let mut acc = Acc::default();
        let mut t = 0.0;
        // Bulk: [0, t_w].
        let mut stats = LevinStats::default();
        let mut folded_periods = 0;
        match bulk {
            Bulk::Levin(set) => {
                stats = self.bulk_levin(&ker, table, theta, t_w, set, &mut acc)?;
                t = t_w;
            }
            Bulk::Fold => {
                if let Some(f) = fold::Fold::ending_at(TAU / ker.kw, t_w) {
                    let est = fold::panel_estimate(&ker, &f, theta, self.p.b);
                    if est.is_nan() || est > MAX_PANELS as f64 {
                        return Err(Error::Quadrature {
                            reason: format!(
                                "Duhamel integral (folded): about {est:.3e} panels needed, over \
                                 the budget of {MAX_PANELS} panels"
                            ),
                            at: 0.0,
                        });
                    }
                    // head [0, s₀) directly, then N periods folded onto [s₀, s₀ + T]
                    while t < f.s0 {
                        let h = ker.pair_length(self, t, theta) * 0.5;
                        let (h, done) = acc.pair(&ker, table, theta, t, h, f.s0, None)?;
                        t = if done { f.s0 } else { t + 2.0 * h };
                    }
                    fold::integrate(&ker, table, &f, theta, &mut acc)?;
                    folded_periods = f.n as u64;
                    t = t_w;
                }
            }
            Bulk::GaussLegendre => {}
        }
        while t < t_w {
            let h = ker.pair_length(self, t, theta) * 0.5;
            let (h, done) = acc.pair(&ker, table, theta, t, h, t_w, None)?;
            t = if done { t_w } else { t + 2.0 * h };
        }
        // Last cycle: sampled, extrema refined.
        let x_at = |t: f64, c: f64, s: f64| {
            let (st, ct) = sin_cos(t);
            (st * c - ct * s, ct * c + st * s)
        };
        let (mut c0, mut s0) = (acc.c.value(), acc.s.value());
        let (mut x0, mut v0) = x_at(t, c0, s0);
        let mut max_abs = x0.abs();
        let mut est = acc.dc.dhypot(acc.ds);
        // the largest remainder of the extremum searches (part of A's estimate)
        let mut newton_rest = 0.0f64;
        while t < tau_end {
            // at most `LAST_CYCLE_PHASE` rad of phase per sample interval: `X' = 0` can then
            // hold at most one root between samples, however fast the forcing. The panels span
            // `DENSE` sample intervals; the samples inside a panel come from its own nodes
            // (`DENSE_WEIGHTS`, to within `DENSE_TOL`), the panel ends are exact.
            let sub = DENSE as f64;
            let h = (ker.pair_length(self, t, theta.min(sub * LAST_CYCLE_PHASE)) * 0.5)
                .min(sub * SAMPLE);
            let mut mid = (c0, s0);
            let mut dense = [[(0.0, 0.0); DENSE - 1]; 2];
            let (h, done) =
                acc.pair_dense(&ker, table, theta, t, h, tau_end, &mut mid, &mut dense)?;
            let t_next = if done { tau_end } else { t + 2.0 * h };
            let panels = [
                ((t, c0, s0), (t + h, mid.0, mid.1), &dense[0]),
                (
                    (t + h, mid.0, mid.1),
                    (t_next, acc.c.value(), acc.s.value()),
                    &dense[1],
                ),
            ];
            for ((tp, cp, sp), (tq, cq, sq), d) in panels {
                let mut ta = tp;
                for k in 1..=DENSE {
                    let (tb, mut xb, mut vb);
                    if k == DENSE {
                        tb = tq;
                        (xb, vb) = x_at(tq, cq, sq);
                        max_abs = max_abs.max(xb.abs());
                    } else {
                        tb = tp + k as f64 * h / sub;
                        let (dc, ds) = d[k - 1];
                        (xb, vb) = x_at(tb, cp + dc, sp + ds);
                        if vb.abs() <= DENSE_TOL {
                            // the sign of X' is not certain: the exact state there
                            (xb, vb) = ker.state_at(tp, cp, sp, tb);
                            max_abs = max_abs.max(xb.abs());
                        }
                    }
                    if ((v0 > 0.0 && vb < 0.0) || (v0 < 0.0 && vb > 0.0))
                        && extremum_bound(tb - ta, (x0, v0), (xb, vb)) + DENSE_TOL > max_abs
                    {
                        let (m, rest) = ker.extremum(tp, cp, sp, (ta, v0), (tb, vb));
                        max_abs = max_abs.max(m);
                        newton_rest = newton_rest.max(rest);
                    }
                    (ta, x0, v0) = (tb, xb, vb);
                }
            }
            (c0, s0) = (acc.c.value(), acc.s.value());
            est = est.max(acc.dc.dhypot(acc.ds));
            t = t_next;
        }
        let (x, v) = x_at(tau_end, acc.c.value(), acc.s.value());
        let envelope = x.dhypot(v);
        let amplitude = match self.p.measure {
            AmplitudeMeasure::LastCycleMax => max_abs,
            AmplitudeMeasure::Envelope => envelope,
        };
        Ok(KarpovResponse {
            x,
            v,
            envelope,
            last_cycle_max: max_abs,
            amplitude,
            error_estimate: est + newton_rest + stats.truncation + stats.rounding + acc.round,
            rounding_estimate: acc.round,
            phase_budget: theta,
            panels: acc.panels,
            levin_panels: stats.panels,
            folded_periods,
        })
    }
}

/// `rtol` of the error-controlled rules: in `[1e-13, 1)`.
pub(super) fn check_rtol(rtol: f64) -> Result<(), Error> {
    if rtol.is_finite() && (1e-13..1.0).contains(&rtol) {
        Ok(())
    } else {
        Err(Error::invalid("karpov2017.rtol", "in [1e-13, 1)", rtol))
    }
}

/// How one run integrates the bulk `[0, τ_end − T_last]`.
#[derive(Debug, Clone, Copy)]
pub(super) enum Bulk {
    /// Phase-bounded Gauss–Legendre pairs throughout.
    GaussLegendre,
    /// Levin panels where their residual passes, Gauss–Legendre pairs elsewhere.
    Levin(LevinSettings),
    /// Whole periods of `g` folded onto one (module `fold`), a direct head before them.
    Fold,
}

/// Settings of the Levin bulk of one run.
#[derive(Debug, Clone, Copy)]
pub(super) struct LevinSettings {
    /// Tolerance on `(C, S)` over the bulk relative to the running envelope `|C + iS|` (at
    /// least 1): a panel of length `L` is accepted when its truncation estimate is
    /// `≤ eps·max(1, |C + iS|)·L/t_w`.
    pub(super) eps: f64,
    /// Longest panel, as a multiple of `π/(2kω)` (a quarter period of `g`).
    pub(super) span: f64,
}

/// What the Levin bulk did.
#[derive(Debug, Default, Clone, Copy)]
pub(super) struct LevinStats {
    pub(super) panels: u64,
    /// Sum of the accepted panels' truncation estimates (`∫|r|`, halved for `sin Φ`).
    pub(super) truncation: f64,
    /// Bound of the rounding of the end formulas (`ε|p|·|ψ|` per end).
    pub(super) rounding: f64,
}

/// Levin panels shorter than this many Gauss–Legendre pairs are not tried (a Levin attempt,
/// both chirps, costs about as much as 4 pairs).
pub(super) const LEVIN_MIN_PAIRS: f64 = 4.0;
/// Cap of the Levin attempts of one run (a typed error beyond it; never reached in practice:
/// each attempt either advances `τ` by `≥ LEVIN_MIN_PAIRS` pairs or shrinks the trial length).
pub(super) const MAX_LEVIN_ATTEMPTS: u64 = 20_000_000;
/// Longest stretch of Gauss–Legendre pairs between two Levin attempts.
pub(super) const MAX_GL_STRETCH: f64 = 4096.0;

impl Karpov2017 {
    /// The bulk `[0, t_w]` of the Duhamel integral: `C + iS = (I₊ − I₋)/(2i)`,
    /// `I± = ∫ e^{i(s ± Φ(s))} ds`, by Levin panels (`levin::Levin`) whose length `L` is
    /// controlled like a step size from the ratio `ρ` of the truncation estimate to the
    /// panel's tolerance (`L·0.9ρ^{−1/8}`, clamped to `[1, 2]` after an accepted panel, up to
    /// `span·π/(2kω)`, and to `[¼, 0.7]` after a rejected one). Where `L` falls below
    /// `LEVIN_MIN_PAIRS` Gauss–Legendre pairs (around the stationary points `Φ' = ∓1`, and at
    /// small `τ` where the phase is slow) a stretch of phase-bounded Gauss–Legendre pairs
    /// follows, doubled each time no Levin panel passed since the previous stretch.
    ///
    /// Termination: every iteration advances `τ` by an accepted panel or a stretch of pairs
    /// (each pair counted against `MAX_PANELS`), or shrinks `L` by at least 0.7, which can
    /// happen only `log(L/(LEVIN_MIN_PAIRS·pair))/log(1/0.7)` times before a stretch; the
    /// attempts are capped at `MAX_LEVIN_ATTEMPTS` (typed error).
    pub(super) fn bulk_levin(
        &self,
        ker: &Kernel,
        table: &[OnceCell<Rot>],
        theta: f64,
        t_w: f64,
        set: LevinSettings,
        acc: &mut Acc,
    ) -> Result<LevinStats, Error> {
        let mut st = LevinStats::default();
        if t_w <= 0.0 {
            return Ok(st);
        }
        let lv = levin::Levin::new();
        let l_max = (set.span * 0.5 * std::f64::consts::PI / ker.kw).min(t_w);
        let mut l = 0.25 * l_max;
        let min_pairs = LEVIN_MIN_PAIRS;
        let mut stretch = min_pairs;
        let mut after_gl = false;
        let mut attempts = 0u64;
        let mut t = 0.0;
        let (mut phi_a, mut s_a) = ker.rotors(t);
        let mut dpsi = [0.0; levin::N];
        let mut dpsi_y = [0.0; levin::N - 1];
        while t < t_w {
            let lg = ker.pair_length(self, t, theta);
            let len = l.min(t_w - t);
            if len < min_pairs * lg || t + len <= t {
                let end = (t + stretch * lg).min(t_w);
                while t < end {
                    let h = ker.pair_length(self, t, theta) * 0.5;
                    let (h, done) = acc.pair(ker, table, theta, t, h, end, None)?;
                    t = if done { end } else { t + 2.0 * h };
                }
                (phi_a, s_a) = ker.rotors(t);
                l = l.max(2.0 * min_pairs * ker.pair_length(self, t, theta));
                if after_gl {
                    // no Levin panel passed since the last stretch: make the next one longer
                    stretch = (2.0 * stretch).min(MAX_GL_STRETCH);
                }
                after_gl = true;
                continue;
            }
            attempts += 1;
            if attempts > MAX_LEVIN_ATTEMPTS {
                return Err(Error::Quadrature {
                    reason: format!(
                        "Duhamel integral: more than {MAX_LEVIN_ATTEMPTS} Levin panels tried"
                    ),
                    at: t,
                });
            }
            let b = t + len;
            let mid = t + 0.5 * len;
            for (d, x) in dpsi.iter_mut().zip(lv.x) {
                *d = ker.phi_rate(mid + 0.5 * len * x);
            }
            for (d, y) in dpsi_y.iter_mut().zip(lv.y) {
                *d = ker.phi_rate(mid + 0.5 * len * y);
            }
            let (phi_b, s_b) = ker.rotors(b);
            let plus = {
                let dp = dpsi.map(|d| 1.0 + d);
                let dy = dpsi_y.map(|d| 1.0 + d);
                lv.chirp(len, &dp, &dy, s_a * phi_a, s_b * phi_b)
            };
            let minus = {
                let dp = dpsi.map(|d| 1.0 - d);
                let dy = dpsi_y.map(|d| 1.0 - d);
                lv.chirp(len, &dp, &dy, s_a * phi_a.conj(), s_b * phi_b.conj())
            };
            // the tolerance scales with the running envelope |C + iS| (≥ 1)
            let tol = set.eps * acc.c.value().dhypot(acc.s.value()).max(1.0) * len / t_w;
            let (ok, ratio) = match (&plus, &minus) {
                (Some(p), Some(m)) => {
                    let tr = 0.5 * (p.truncation + m.truncation);
                    ((tr <= tol).then_some(tr), tr / tol)
                }
                _ => (None, f64::INFINITY),
            };
            // next trial length from the estimate, as a step-size controller would (the
            // estimate falls roughly like L^8 or faster); NaN-safe clamps
            let factor = 0.9 * ratio.dpowf(-0.125);
            let factor = if factor.is_nan() { 0.25 } else { factor };
            if let (Some(tr), Some(p), Some(m)) = (ok, plus, minus) {
                // (I₊ − I₋)/(2i)
                let v = (p.value - m.value) * Complex::new(0.0, -0.5);
                acc.c.add(v.re);
                acc.s.add(v.im);
                st.panels += 1;
                st.truncation += tr;
                let psi = 1.0 + b.abs() + self.phase(b).abs();
                st.rounding += 2.0 * f64::EPSILON * (p.scale + m.scale) * psi;
                t = b;
                (phi_a, s_a) = (phi_b, s_b);
                l = (len * factor.clamp(1.0, 2.0)).max(l).min(l_max);
                stretch = min_pairs;
                after_gl = false;
            } else {
                l = len * factor.clamp(0.25, 0.7);
            }
        }
        Ok(st)
    }
}

/// An upper bound of `|X|` on a sample interval of length `h` from its ends `(X, X')`:
/// with `|X''| = |sin Φ − X| ≤ 1 + m`, `m = sup|X|`, Taylor from either end gives
/// `m ≤ |X| + |X'| h + (1 + m) h²/2`, i.e. `m ≤ (|X| + |X'| h + h²/2)/(1 − h²/2)` (`h < √2`;
/// the last cycle's samples are `≤ SAMPLE = 0.5` apart). An extremum search between the
/// samples is skipped when this bound cannot exceed the running maximum, which leaves `A`
/// unchanged and avoids a Newton search at every root of the forcing's ripple in `X'`
/// (the fuzzer's `ω = 9.2·10¹⁸`, `τ_end = 10⁻¹²`: ~10⁶ searches, 18 s).
pub(super) fn extremum_bound(h: f64, (xa, va): (f64, f64), (xb, vb): (f64, f64)) -> f64 {
    let q = 0.5 * h * h;
    if q.is_nan() || q >= 1.0 {
        return f64::INFINITY;
    }
    let from = |x: f64, v: f64| (x.abs() + v.abs() * h + q) / (1.0 - q);
    from(xa, va).min(from(xb, vb))
}

/// Composite Simpson weight (without `h/3`) of point `i` of `0..=n` (`n` even); tests only.
#[cfg(test)]
pub(super) fn simpson_weight(i: usize, n: usize) -> f64 {
    if i == 0 || i == n {
        1.0
    } else if i % 2 == 1 {
        4.0
    } else {
        2.0
    }
}

/// Length of the fine panels of level `j`: `2θ·2^(−j/LEVELS_PER_OCTAVE)`.
pub(super) fn level_length(theta: f64, j: usize) -> f64 {
    2.0 * theta * (-(j as f64) / f64::from(LEVELS_PER_OCTAVE)).dexp2()
}

/// The node rotations of a panel of length `≤ h`, `h` rounded down to the tabulated level
/// lengths [`level_length`] (each level computed when first used; beyond the last level, the
/// exact `h` computed directly).
pub(super) fn level_rot(ker: &Kernel, table: &[OnceCell<Rot>], theta: f64, h: f64) -> Rot {
    let j = (f64::from(LEVELS_PER_OCTAVE) * (2.0 * theta / h).dlog2()).ceil();
    let j = if j.is_finite() {
        j.max(f64::from(LEVELS_PER_OCTAVE))
    } else {
        f64::MAX
    };
    // the folded accumulated reading also rotates e^{iωu} (`fold`)
    let om = !ker.printed;
    if j < LEVELS as f64 {
        let j = j as usize;
        *table[j].get_or_init(|| ker.rot_with(level_length(theta, j), om))
    } else {
        ker.rot_with(h, om)
    }
}

/// Weights of the embedded error estimate of a pair of 10-point Gauss–Legendre panels, for
/// the nodes of its first panel (those of the second are the same reversed).
///
/// The 20 nodes of the pair `[t, t + 2h]` (`y = (x_i ∓ 1)/2` on `[−1, 1]`, `x_i` the
/// Gauss–Legendre nodes) without the two next to the midpoint carry an 18-point interpolatory
/// rule `W_j` (exact for degree 17, all weights positive, `ΣW_j = 2`). The pair's result is
/// the composite rule (`w_i/2` on each half, exact for degree 19 and much more accurate on
/// oscillatory integrands), so `(embedded − composite)` estimates the error of the embedded
/// rule, an upper estimate for the composite one: on `e^{iay}` over the pair, `a = 2θ/2`,
/// the embedded rule's error is 1e-13 at `θ = 4` (the coarse panel over the pair it replaces:
/// 1e-12) where the composite's is 7e-18. As weights of the half-panel sum `h/2·Σ e_i f_i`:
/// `e_i = 2W_i − w_i` (`W = 0` for the dropped node, `e_9 = −w_9`). Computed in 60-digit
/// decimal arithmetic (Legendre-basis moment equations, Gauss–Jordan); the test
/// `embedded_rule_is_exact_to_degree_17` checks them.
pub(super) const EMBED: [f64; 10] = [
    2.065370749174635e-06,
    -9.591936948453146e-06,
    3.12881184360725e-05,
    -0.00010308814108293743,
    0.0003756532832240153,
    -0.0015404223212395968,
    0.006861534340057197,
    -0.029562920401286687,
    0.09061682599677935,
    -0.06667134430868814,
];

/// [`EMBED`] for the first (`[0]`) and the second (`[1]`, reversed) panel of a pair.
pub(super) const EMBED_PAIR: [[f64; 10]; 2] = {
    let mut r = [[0.0; 10]; 2];
    let mut i = 0;
    while i < 10 {
        r[0][i] = EMBED[i];
        r[1][i] = EMBED[9 - i];
        i += 1;
    }
    r
};

/// Relative gain in `|X|` below which the extremum search of the last cycle stops
/// ([`Kernel::extremum`]; the gain is added to the error estimate): from the secant start,
/// usually after two or three Newton iterates instead of four or five.
pub(super) const NEWTON_GAIN: f64 = 1e-13;

/// Sample intervals per last-cycle panel (the run's `run` loop).
pub(super) const DENSE: usize = 4;
/// Bound used for the interior samples of a last-cycle panel: their `(X, X')` come from the
/// panel's nodes to within ~5e-8 (the interpolant's error at `θ = 4`: 2.3e-8 of a panel's
/// half-length at a quarter, on `e^{iay}`), so a sample with `|X'| ≤ DENSE_TOL` gets its exact
/// state, and the bound that skips an extremum search is widened by it.
pub(super) const DENSE_TOL: f64 = 1e-6;

/// `q[k][i]`: the weights of `∫_{−1}^{y_k}` of the degree-9 interpolant at the Gauss–Legendre
/// nodes `x_i`, `y_k = −1 + 2(k + 1)/DENSE`:
/// `q[k][i] = w_i ((y + 1)/2 + Σ_{j=1}^{9} P_j(x_i)(P_{j+1}(y) − P_{j−1}(y))/2)`
/// (the interpolant's Legendre series by the rule's discrete orthogonality, integrated term by
/// term with `∫_{−1}^{y} P_j = (P_{j+1}(y) − P_{j−1}(y))/(2j + 1)`; at `y = 1` it is `w_i`).
pub(super) type DenseWeights = [[f64; 10]; DENSE - 1];
/// The partial `(ΔC, ΔS)` of a panel at its inner samples ([`Kernel::panel_dense`]).
pub(super) type DenseSums = [(f64, f64); DENSE - 1];

pub(super) fn dense_weights() -> &'static DenseWeights {
    static Q: OnceLock<DenseWeights> = OnceLock::new();
    Q.get_or_init(|| {
        let gl = gauss_legendre_10();
        let legendre = |n: usize, x: f64| {
            let (mut p0, mut p1) = (1.0, x);
            if n == 0 {
                return 1.0;
            }
            for j in 2..=n {
                let j = j as f64;
                (p0, p1) = (p1, ((2.0 * j - 1.0) * x * p1 - (j - 1.0) * p0) / j);
            }
            p1
        };
        let mut q = [[0.0; 10]; DENSE - 1];
        for (k, row) in q.iter_mut().enumerate() {
            let y = -1.0 + 2.0 * (k + 1) as f64 / DENSE as f64;
            for (i, v) in row.iter_mut().enumerate() {
                let x = gl.nodes[i];
                let mut sum = 0.5 * (y + 1.0);
                for j in 1..10 {
                    sum += 0.5 * legendre(j, x) * (legendre(j + 1, y) - legendre(j - 1, y));
                }
                *v = gl.weights[i] * sum;
            }
        }
        q
    })
}

thread_local! {
    /// The rotation table of this thread's last run ([`RotTable`]).
    static ROT_TABLE: std::cell::RefCell<Option<RotTable>> = const { std::cell::RefCell::new(None) };
}

/// The node rotations of the tabulated panel levels ([`level_rot`]) of one run, kept per
/// thread for the next run with the same key: they depend only on `θ`, `kω`, `ω` and the
/// reading (the same values bit for bit whether computed now or by an earlier run), so
/// repeated calls and sweeps over `B`, `ξ` or `τ_end` at fixed `ω`, `k` skip their `sin_cos`.
/// Taken out of the thread's slot for the run and put back when dropped.
pub(super) struct RotTable {
    key: [u64; 4],
    pub(super) levels: Vec<OnceCell<Rot>>,
}

impl RotTable {
    pub(super) fn take(ker: &Kernel, theta: f64) -> Self {
        let key = [
            theta.to_bits(),
            ker.kw.to_bits(),
            ker.w.to_bits(),
            u64::from(ker.printed),
        ];
        let cached = ROT_TABLE
            .try_with(|c| c.try_borrow_mut().ok().and_then(|mut slot| slot.take()))
            .ok()
            .flatten();
        match cached {
            Some(t) if t.key == key => t,
            Some(mut t) => {
                // another key: the allocation reused, the levels cleared
                for level in &mut t.levels {
                    level.take();
                }
                t.key = key;
                t
            }
            None => Self {
                key,
                levels: (0..LEVELS).map(|_| OnceCell::new()).collect(),
            },
        }
    }
}

impl Drop for RotTable {
    fn drop(&mut self) {
        if self.levels.is_empty() {
            // the husk of a table moved into the slot (below)
            return;
        }
        // `try_with`/`try_borrow_mut`: nothing is kept while the thread is being torn down
        let _ = ROT_TABLE.try_with(|c| {
            if let Ok(mut slot) = c.try_borrow_mut() {
                let old = slot.replace(Self {
                    key: self.key,
                    levels: std::mem::take(&mut self.levels),
                });
                drop(slot);
                // a table replaced in the slot is dropped as a husk (not put back)
                if let Some(mut o) = old {
                    drop(std::mem::take(&mut o.levels));
                }
            }
        });
    }
}

/// The 10 Gauss–Legendre node offsets `d = h/2·x_i` of one panel length as rotations.
#[derive(Clone, Copy)]
pub(super) struct Rot {
    /// Panel length.
    pub(super) h: f64,
    /// `(sin d, cos d)`.
    pub(super) s: [(f64, f64); 10],
    /// `(sin kωd, cos kωd)`.
    pub(super) th: [(f64, f64); 10],
    /// `(sin ωd, cos ωd)` (the folded accumulated reading, [`Kernel::rot_with`]; else unset).
    pub(super) om: [(f64, f64); 10],
}

/// The integrand of the Duhamel integral with the constants of `g` unpacked.
pub(super) struct Kernel {
    pub(super) w: f64,
    pub(super) k: f64,
    pub(super) kw: f64,
    /// `B√(1 − 1/ξ²)`.
    pub(super) c: f64,
    /// `1/ξ` (0 in the sinusoidal limit).
    pub(super) eps: f64,
    pub(super) printed: bool,
    /// `c/ε`, `ln(1 + ε)` and `1/k` of the accumulated phase `G/k` (0 for `ε = 0`).
    pub(super) c_over_eps: f64,
    pub(super) ln_1p_eps: f64,
    pub(super) inv_k: f64,
    pub(super) gl: GaussLegendre<10>,
    /// Bounds of `|g'|` and `|g''|` (+5 %).
    pub(super) g1: f64,
    pub(super) g2: f64,
    /// `1 + ω(1 + max|g|)`, `max|g| ≤ c/(1 − ε)`: `|s| + |Φ(s)| ≤ |s|·psi_rate` in both
    /// readings ([`Kernel::phase_bound`]).
    pub(super) psi_rate: f64,
}

impl Kernel {
    pub(super) fn new(m: &Karpov2017) -> Self {
        let (b, xi) = (m.dev.b(), m.dev.xi());
        let eps = if xi.is_infinite() { 0.0 } else { 1.0 / xi };
        let c = b * ((1.0 - eps) * (1.0 + eps)).sqrt();
        // the bounds of |g'|/c, |g''|/c were computed with the model (`shape_bounds`)
        let [g1, g2] = m.shape.map(|h| c * h);
        Self {
            w: m.p.omega,
            k: m.p.k,
            kw: m.p.k * m.p.omega,
            c,
            eps,
            printed: m.p.excitation == Excitation::PrintedPhase,
            c_over_eps: if eps == 0.0 { 0.0 } else { c / eps },
            ln_1p_eps: ln(1.0 + eps),
            inv_k: 1.0 / m.p.k,
            gl: gauss_legendre_10(),
            g1: 1.05 * g1,
            g2: 1.05 * g2,
            psi_rate: 1.0 + m.p.omega * (1.0 + c / (1.0 - eps)),
        }
    }

    /// Bound of the size of the chirp phases `s ± Φ(s)` on `[0, s]`, plus 1: the absolute
    /// rounding of a node's phase is about `ε` times this (the rounding estimate, `Acc::round`).
    #[inline]
    pub(super) fn phase_bound(&self, s: f64) -> f64 {
        1.0 + s.abs() * self.psi_rate
    }

    /// Node rotations of panel length `h`.
    pub(super) fn rot(&self, h: f64) -> Rot {
        self.rot_with(h, false)
    }

    /// Node rotations of panel length `h`, with those of `ωd` when `omega`.
    pub(super) fn rot_with(&self, h: f64, omega: bool) -> Rot {
        let mut r = Rot {
            h,
            s: [(0.0, 1.0); 10],
            th: [(0.0, 1.0); 10],
            om: [(0.0, 1.0); 10],
        };
        for i in 0..10 {
            let d = 0.5 * h * self.gl.nodes[i];
            r.s[i] = sin_cos(d);
            r.th[i] = sin_cos(self.kw * d);
            if omega {
                r.om[i] = sin_cos(self.w * d);
            }
        }
        r
    }

    /// `G(kωs)/k` of the accumulated phase `Φ = ωs + G/k`, given `cos θ` of `θ = kωs`.
    #[inline]
    pub(super) fn g_over_k(&self, ct: f64) -> f64 {
        let big_g = if self.eps == 0.0 {
            self.c * (1.0 - ct)
        } else {
            -self.c_over_eps * (ln(1.0 + self.eps * ct) - self.ln_1p_eps)
        };
        big_g * self.inv_k
    }

    /// `Φ(s)` given `sin θ`, `cos θ` of `θ = kωs`.
    #[inline]
    pub(super) fn phi(&self, s: f64, st: f64, ct: f64) -> f64 {
        if self.printed {
            let g = self.c * st / (1.0 + self.eps * ct);
            self.w * (1.0 + g) * s
        } else {
            self.w * s + self.g_over_k(ct)
        }
    }

    /// `sin Φ(s)` given `sin θ`, `cos θ` of `θ = kωs`.
    #[inline]
    pub(super) fn sin_phi(&self, s: f64, st: f64, ct: f64) -> f64 {
        sin_cos(self.phi(s, st, ct)).0
    }

    /// `Φ'(s)`: `ω(1 + g)` (accumulated) or `ω(1 + g) + s ω kω g'` (printed), with
    /// `g' = c(ε + cos θ)/(1 + ε cos θ)²`.
    #[inline]
    pub(super) fn phi_rate(&self, s: f64) -> f64 {
        let (st, ct) = sin_cos(self.kw * s);
        let den = 1.0 + self.eps * ct;
        let g = self.c * st / den;
        let base = self.w * (1.0 + g);
        if self.printed {
            base + s * self.w * self.kw * self.c * (self.eps + ct) / (den * den)
        } else {
            base
        }
    }

    /// `(e^{iΦ(s)}, e^{is})`.
    pub(super) fn rotors(&self, s: f64) -> (Complex<f64>, Complex<f64>) {
        let (st, ct) = sin_cos(self.kw * s);
        let (sp, cp) = sin_cos(self.phi(s, st, ct));
        let (ss, cs) = sin_cos(s);
        (Complex::new(cp, sp), Complex::new(cs, ss))
    }

    /// `(∫ cos s sin Φ, ∫ sin s sin Φ)` over `[t, t + r.h]` by 10-point Gauss–Legendre.
    #[inline]
    pub(super) fn panel(&self, t: f64, r: &Rot) -> (f64, f64) {
        self.panel_impl::<false>(t, r, &[0.0; 10], None).0
    }

    /// [`Kernel::panel`] and the same sums with the weights `e` of the embedded estimate
    /// ([`EMBED_PAIR`]) on the same nodes.
    #[inline]
    pub(super) fn panel_est(&self, t: f64, r: &Rot, e: &[f64; 10]) -> ((f64, f64), (f64, f64)) {
        self.panel_impl::<true>(t, r, e, None)
    }

    /// [`Kernel::panel_est`] and the partial sums over `[t, t + k·r.h/DENSE]`,
    /// `k = 1 … DENSE − 1`, from the same nodes (`DENSE_WEIGHTS`).
    pub(super) fn panel_dense(
        &self,
        t: f64,
        r: &Rot,
        e: &[f64; 10],
    ) -> ((f64, f64), (f64, f64), DenseSums) {
        let q = dense_weights();
        let half = 0.5 * r.h;
        let mut part = [(0.0, 0.0); DENSE - 1];
        let (main, est) = self.panel_impl::<true>(t, r, e, Some((q, &mut part)));
        for p in &mut part {
            *p = (p.0 * half, p.1 * half);
        }
        (main, est, part)
    }

    #[inline(always)]
    fn panel_impl<const EST: bool>(
        &self,
        t: f64,
        r: &Rot,
        e: &[f64; 10],
        mut dense: Option<(&DenseWeights, &mut [(f64, f64); DENSE - 1])>,
    ) -> ((f64, f64), (f64, f64)) {
        let half = 0.5 * r.h;
        let mid = t + half;
        let (sm, cm) = sin_cos(mid);
        let (stm, ctm) = sin_cos(self.kw * mid);
        let (mut pc, mut ps) = (0.0, 0.0);
        let (mut ec, mut es) = (0.0, 0.0);
        for i in 0..10 {
            let (sd, cd) = r.s[i];
            let (sdt, cdt) = r.th[i];
            let ss = sm * cd + cm * sd;
            let cs = cm * cd - sm * sd;
            let st = stm * cdt + ctm * sdt;
            let ct = ctm * cdt - stm * sdt;
            let sp = self.sin_phi(mid + half * self.gl.nodes[i], st, ct);
            let f = self.gl.weights[i] * sp;
            pc += f * cs;
            ps += f * ss;
            if EST {
                let g = e[i] * sp;
                ec += g * cs;
                es += g * ss;
            }
            if let Some((q, part)) = dense.as_mut() {
                for (k, p) in part.iter_mut().enumerate() {
                    let g = q[k][i] * sp;
                    p.0 += g * cs;
                    p.1 += g * ss;
                }
            }
        }
        ((pc * half, ps * half), (ec * half, es * half))
    }

    /// Bound of `|Φ''|` on `[0, tau]`.
    pub(super) fn m2(&self, tau: f64) -> f64 {
        let (w, k) = (self.w, self.k);
        if self.printed {
            2.0 * w * w * k * self.g1 + w * w * w * k * k * tau * self.g2
        } else {
            w * w * k * self.g1
        }
    }

    /// Length `L` of a pair starting at `t` whose integrand phase changes by `≤ 2θ`:
    /// `a L + M₂ L²/2 = 2θ`.
    pub(super) fn pair_length(&self, m: &Karpov2017, t: f64, theta: f64) -> f64 {
        let a = 1.0 + m.phase_rate(t).abs();
        let m2 = self.m2(t + 2.0 * theta);
        4.0 * theta / (a + (a * a + 4.0 * m2 * theta).sqrt())
    }

    /// `(X, X')` at `tau` from `C`, `S` at `t0` (one panel over `[t0, tau]`).
    pub(super) fn state_at(&self, t0: f64, c0: f64, s0: f64, tau: f64) -> (f64, f64) {
        let (dc, ds) = self.panel(t0, &self.rot(tau - t0));
        let (c, s) = (c0 + dc, s0 + ds);
        let (st, ct) = sin_cos(tau);
        (st * c - ct * s, ct * c + st * s)
    }

    /// `|X|` at the extremum in `(lo, hi)` where `X'` changes sign (`v_lo`, `v_hi`: `X'` at the
    /// ends, of opposite signs, the sign of `v_lo` certain), given `C`, `S` at `t0 ≤ lo`
    /// (`hi − t0` at most a panel): safeguarded Newton on `X'(τ) = cos τ C(τ) + sin τ S(τ)`
    /// with `X'' = sin Φ − X`, each iterate's `C`, `S` by one panel from `t0` (at most 60
    /// steps; the bracket always holds a sign change), from the secant root of the ends.
    ///
    /// Returns `(max |X| over the iterates, remainder)`: the search stops once the gain in
    /// `|X|` the next Newton step could still make, `X'²/(2|X''|)` (the quadratic model at the
    /// last iterate), is `≤ NEWTON_GAIN·|X|`; that gain is the remainder, added to the error
    /// estimate of `A` (0 when it stopped on the step length or the bracket).
    pub(super) fn extremum(
        &self,
        t0: f64,
        c0: f64,
        s0: f64,
        (lo, v_lo): (f64, f64),
        (hi, v_hi): (f64, f64),
    ) -> (f64, f64) {
        let eval = |tau: f64| {
            let (dc, ds) = self.panel(t0, &self.rot(tau - t0));
            let (c, s) = (c0 + dc, s0 + ds);
            let (st, ct) = sin_cos(tau);
            let (sth, cth) = sin_cos(self.kw * tau);
            (
                st * c - ct * s,
                ct * c + st * s,
                self.sin_phi(tau, sth, cth),
            )
        };
        let (mut lo, mut hi) = (lo, hi);
        // the secant root of the ends (kept inside the bracket; the midpoint if it is not a
        // number): X' is close to linear over a sample interval
        let w = hi - lo;
        let secant = lo + w * (v_lo / (v_lo - v_hi));
        let mut tau = if secant.is_nan() {
            0.5 * (lo + hi)
        } else {
            // max/min, not clamp: no panic whatever the bounds
            secant.max(lo + 1e-3 * w).min(hi - 1e-3 * w)
        };
        let mut best = 0.0f64;
        let mut rest = 0.0;
        for _ in 0..60 {
            let (x, v, f) = eval(tau);
            best = best.max(x.abs());
            if (v > 0.0) == (v_lo > 0.0) {
                lo = tau;
            } else {
                hi = tau;
            }
            let d2 = f - x;
            let gain = 0.5 * v * v / d2.abs();
            rest = if gain.is_finite() { gain } else { 0.0 };
            if gain <= NEWTON_GAIN * x.abs() {
                break;
            }
            let newton = tau - v / d2;
            let next = if d2 != 0.0 && newton > lo && newton < hi {
                newton
            } else {
                0.5 * (lo + hi)
            };
            if (next - tau).abs() <= 1e-15 * (1.0 + tau.abs()) || hi - lo <= 1e-14 * (1.0 + tau) {
                rest = 0.0;
                break;
            }
            tau = next;
        }
        (best, rest)
    }
}

/// The 10-point Gauss–Legendre rule, built once per process.
fn gauss_legendre_10() -> GaussLegendre<10> {
    static RULE: OnceLock<GaussLegendre<10>> = OnceLock::new();
    *RULE.get_or_init(GaussLegendre::<10>::new)
}

/// Bounds of `|g'|/c` and `|g''|/c` over a period (`c = B√(1 − ε²)`, `ε = 1/ξ`), which depend
/// on `ξ` only: `g'/c = (ε + cos θ)/(1 + ε cos θ)²`, `g''/c = sin θ (2ε² − 1 + ε cos θ)/(1 +
/// ε cos θ)³` on a grid of `n ≥ 4096` points (both peak within ~(1 − ε) of θ = π, so the grid
/// resolves that width 400 times), by the coarse-to-fine [`grid_max`]. The kernel scales them
/// by `c` and adds 5 %.
pub(super) fn shape_bounds(xi: f64) -> [f64; 2] {
    let eps = if xi.is_infinite() { 0.0 } else { 1.0 / xi };
    let n = ((400.0 / (1.0 - eps)) as usize).clamp(4096, 1 << 20);
    grid_max(n, |i| {
        let (s, co) = (TAU * i as f64 / n as f64).dsin_cos();
        let den = 1.0 + eps * co;
        [
            ((eps + co) / (den * den)).abs(),
            (s * (2.0 * eps * eps - 1.0 + eps * co) / (den * den * den)).abs(),
        ]
    })
}

/// Stride of the coarse pass of [`grid_max`].
const GRID_STRIDE: usize = 8;

/// The maxima over `i ∈ [0, n)` of the two components of the periodic `f(i)` (period `n`),
/// evaluated at every [`GRID_STRIDE`]-th point and then at every point within two strides of
/// each local maximum of that coarse pass (wrapping around). For a function whose peaks span
/// several strides (the bounds of `|g'|`, `|g''|` above: each peak ≥ 60 points wide) this is
/// the maximum over all `n` points, bit for bit (the same values at the same points), at
/// about a sixth of the evaluations.
fn grid_max(n: usize, f: impl Fn(usize) -> [f64; 2]) -> [f64; 2] {
    let coarse: Vec<[f64; 2]> = (0..n).step_by(GRID_STRIDE).map(&f).collect();
    let m = coarse.len();
    let mut best = [0.0f64; 2];
    for v in &coarse {
        best = [best[0].max(v[0]), best[1].max(v[1])];
    }
    for comp in 0..2 {
        for j in 0..m {
            let (prev, next) = (coarse[(j + m - 1) % m][comp], coarse[(j + 1) % m][comp]);
            let here = coarse[j][comp];
            if here > prev && here >= next {
                let centre = (j * GRID_STRIDE) as isize;
                let reach = 2 * GRID_STRIDE as isize;
                for i in centre - reach..=centre + reach {
                    let i = i.rem_euclid(n as isize) as usize;
                    best[comp] = best[comp].max(f(i)[comp]);
                }
            }
        }
    }
    best
}

/// Running sums of one quadrature.
#[derive(Default)]
pub(super) struct Acc {
    pub(super) c: Sum,
    pub(super) s: Sum,
    /// Signed sums of `embedded − pair` ([`EMBED`]; error estimate).
    pub(super) dc: f64,
    pub(super) ds: f64,
    /// Rounding estimate: `ε Σ ∫|amplitude|·(phase bound)` over the panels. A node's phase
    /// `ψ` is rounded to about `ε|ψ|` (and so is its `e^{iψ}`), which the embedded estimate,
    /// taken on the same node values, does not see; summed with absolute values (an upper
    /// estimate of the rounding of the sum, whose signs vary).
    pub(super) round: f64,
    pub(super) panels: u64,
}

impl Acc {
    /// One pair of panels of length `≤ h` from `t` (the last one shortened to end at `end`):
    /// adds the result and the embedded rule's difference; returns the panel length used. The
    /// first half's `(C, S)` goes to `mid` when asked.
    pub(super) fn pair(
        &mut self,
        ker: &Kernel,
        table: &[OnceCell<Rot>],
        theta: f64,
        t: f64,
        h: f64,
        end: f64,
        mid: Option<&mut Option<(f64, f64)>>,
    ) -> Result<(f64, bool), Error> {
        let (fine, done) = self.begin_pair(ker, table, theta, t, h, end)?;
        let h = fine.h;
        let (first, e1) = ker.panel_est(t, &fine, &EMBED_PAIR[0]);
        self.add(first);
        if let Some(m) = mid {
            *m = Some((self.c.value(), self.s.value()));
        }
        let (second, e2) = ker.panel_est(t + h, &fine, &EMBED_PAIR[1]);
        self.end_pair(ker, t, h, second, (e1, e2));
        Ok((h, done))
    }

    /// [`Acc::pair`] with the partial sums of both panels at `k/DENSE` of their length
    /// (`dense`, relative to each panel's start) and the first half's `(C, S)` in `mid`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn pair_dense(
        &mut self,
        ker: &Kernel,
        table: &[OnceCell<Rot>],
        theta: f64,
        t: f64,
        h: f64,
        end: f64,
        mid: &mut (f64, f64),
        dense: &mut [[(f64, f64); DENSE - 1]; 2],
    ) -> Result<(f64, bool), Error> {
        let (fine, done) = self.begin_pair(ker, table, theta, t, h, end)?;
        let h = fine.h;
        let (first, e1, d1) = ker.panel_dense(t, &fine, &EMBED_PAIR[0]);
        self.add(first);
        *mid = (self.c.value(), self.s.value());
        let (second, e2, d2) = ker.panel_dense(t + h, &fine, &EMBED_PAIR[1]);
        self.end_pair(ker, t, h, second, (e1, e2));
        *dense = [d1, d2];
        Ok((h, done))
    }

    /// The start of [`Acc::pair`] and [`Acc::pair_dense`]: the panel budget, whether this pair
    /// ends the integral (`t + 2h ≥ end`: then two equal panels up to `end`) and the rotation of
    /// its panel length (a tabulated level otherwise), checked to advance `t`.
    fn begin_pair(
        &self,
        ker: &Kernel,
        table: &[OnceCell<Rot>],
        theta: f64,
        t: f64,
        h: f64,
        end: f64,
    ) -> Result<(Rot, bool), Error> {
        if self.panels >= MAX_PANELS {
            return Err(Error::Quadrature {
                reason: format!("Duhamel integral: panel budget {MAX_PANELS} exhausted"),
                at: t,
            });
        }
        let done = t + 2.0 * h >= end;
        let fine = if done {
            ker.rot(0.5 * (end - t))
        } else {
            level_rot(ker, table, theta, h)
        };
        let h = fine.h;
        // `h` must be positive (not NaN) and large enough to move `t` at all
        if h.is_nan() || h <= 0.0 || t + h <= t {
            return Err(Error::Quadrature {
                reason: format!("Duhamel integral: panel length {h:e} does not advance τ"),
                at: t,
            });
        }
        Ok((fine, done))
    }

    /// The end of a pair from `t` with panels of length `h`: the second panel's result, the
    /// embedded rule's differences of both halves, and the rounding bound of two panels of
    /// length `h` (`|sin Φ| ≤ 1`, [`Acc::round`]).
    fn end_pair(
        &mut self,
        ker: &Kernel,
        t: f64,
        h: f64,
        second: (f64, f64),
        (e1, e2): ((f64, f64), (f64, f64)),
    ) {
        self.add(second);
        self.check(e1, e2);
        self.round += f64::EPSILON * 2.0 * h * ker.phase_bound(t + 2.0 * h);
    }

    /// Adds one fine panel's `(ΔC, ΔS)` to the result.
    pub(super) fn add(&mut self, (c, s): (f64, f64)) {
        self.c.add(c);
        self.s.add(s);
    }

    /// Accounts a pair: the embedded rule's difference to the pair's result ([`EMBED`], the
    /// halves' parts `e1`, `e2`) goes into the error estimate; two panels of work.
    pub(super) fn check(&mut self, (ec1, es1): (f64, f64), (ec2, es2): (f64, f64)) {
        self.dc += ec1 + ec2;
        self.ds += es1 + es2;
        self.panels += 2;
    }
}

/// Neumaier-compensated sum.
#[derive(Default, Clone, Copy)]
pub(super) struct Sum {
    pub(super) s: f64,
    pub(super) c: f64,
}

impl Sum {
    pub(super) fn add(&mut self, x: f64) {
        let t = self.s + x;
        if self.s.abs() >= x.abs() {
            self.c += (self.s - t) + x;
        } else {
            self.c += (x - t) + self.s;
        }
        self.s = t;
    }
    pub(super) fn value(&self) -> f64 {
        self.s + self.c
    }
}
