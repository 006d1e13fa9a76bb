//! The time functions of Eq. (9) tabulated over one period ([`super::Trig::Table`]).
//!
//! `F(τ)`, `b̄(τ)` and `f_r(τ)` are periodic with the period `T = 2π/ω̄_c` of the centrode
//! (`ω̄_e = Z₂ ω̄_c`, [`Model::new`]; the stored doubles to rounding, see [`TimeTable::eval`]).
//! [`TimeTable`] splits one period into `n` pieces of
//! width `w = T/n` and holds, per piece and function, the polynomial of degree [`DEGREE`] that
//! interpolates the function at the piece's Chebyshev points (sampled with the phases carried
//! in double-double, `Model::time_functions_accurate`). A value is then
//!
//! ```text
//! k = ⌊τ/T⌋,  r = τ − k T_hi − k T_lo,  i = ⌊r/w⌋,  s = (r − c_i)/(w/2),  f ≈ Σ_l m_{i,l} s^l
//! ```
//!
//! (`T = T_hi + T_lo` split so that `k T_hi` is exact for `|k| < 2²⁰`; `r` kept as an
//! error-free sum `r_hi + r_lo`, so that a `τ` just below a period's start keeps its own
//! accuracy; `c_i` the stored centre of piece `i`, so `r_hi − c_i` is exact): one reduction and
//! three polynomials of 12 terms (Estrin's scheme), where the direct evaluation takes two
//! `sin_cos` and three divisions.
//!
//! **Accuracy.** The interpolation error of degree `d` on a piece of half-width `a` is at most
//! `(ω a)^{d+1} A / ((d+1)! 2^d)` for a function of amplitude `A` and highest angular frequency
//! `ω`. [`TimeTable::new`] takes `ω = ω̄_e + 16 ω̄_c` and chooses `n` so that this bound is
//! `10⁻¹⁷` of the amplitude. The mesh term has the frequency `ω̄_e`; the radius terms
//! `1/(1 + β cos)` and the exact rigid series add harmonics of `ω̄_c` whose amplitudes fall as
//! `εⁿ` (`(1 − √(1 − β²))/β = ε` for `β = 2ε/(1 + ε²)`): harmonic `n > 16` adds at most
//! `((ω̄_e + n ω̄_c)/ω)^{12} εⁿ` times the bound, below one for every `n` at `ε ≤ 0.9` (the test
//! runs `ε` = 0.2 of Table 1 up to 0.9). The rounding of the monomial
//! coefficients and the polynomial sums adds a few units in the last place. The test bounds the
//! difference from the direct evaluation by `2·10⁻¹⁵` of each function's scale plus the
//! rounding of the phase argument (as for [`super::Trig::Kernel`]). Outside the reduction's
//! exact range (`τ < 0`, `τ ≥ 2²⁰ T`) and for a non-finite `τ` the direct evaluation is used.

use std::sync::Arc;

use math::DetMath;

use super::model::Model;

/// Degree of the interpolating polynomial of each piece.
pub(crate) const DEGREE: usize = 11;
/// Coefficients per piece and function.
const NC: usize = DEGREE + 1;
/// Largest table (pieces per period): a model whose error bound needs more is not tabulated.
const MAX_PIECES: usize = 1 << 14;
/// The largest `ω a` (angular frequency times half-width of a piece) whose interpolation
/// bound `(ω a)^{12} / (12! 2^{11})` is at most `10⁻¹⁷`: `(10⁻¹⁷ · 12! · 2¹¹)^{1/12} = 0.3825…`,
/// rounded down (checked by a test).
const MAX_OMEGA_HALF_WIDTH: f64 = 0.38;
/// Periods below which the reduction `k T_hi` is exact.
const K_MAX: f64 = 1_048_576.0; // 2^20

/// One period of `[F, b̄, f_r]` as piecewise polynomials (module docs).
#[derive(Debug, Clone)]
pub struct TimeTable {
    /// `T_hi + T_lo = T`, `T_hi` with its last 21 bits zero.
    period_hi: f64,
    period_lo: f64,
    /// `1/T`, `1/w`, `2/w` (rounded).
    inv_period: f64,
    inv_width: f64,
    inv_half: f64,
    /// Pieces per period.
    pieces: usize,
    /// Per piece: its centre, then the 3 × [`NC`] monomial coefficients interleaved by degree
    /// (`[m_{F,l}, m_{b,l}, m_{f,l}]` for `l = 0..NC`), so the three polynomials read one stretch
    /// of memory.
    data: Vec<f64>,
}

/// Stride of one piece in [`TimeTable::data`].
const STRIDE: usize = 1 + 3 * NC;

/// Tables kept for reuse ([`TimeTable::shared`]): the runs of one sweep point (its windows,
/// variants, refinements) share one model; a sweep moves on to the next.
const SHARED: usize = 8;

/// The last [`SHARED`] tables, keyed by the `Debug` text of their model (every `f64` in its
/// shortest round-trip form: equal keys are equal models, bit for bit).
static TABLES: std::sync::Mutex<std::collections::VecDeque<(String, Arc<TimeTable>)>> =
    std::sync::Mutex::new(std::collections::VecDeque::new());

impl TimeTable {
    /// The table of `model`'s time functions; `None` when the period is not finite or the error
    /// bound would need more than 2¹⁴ pieces per period.
    pub fn new(model: &Model) -> Option<Self> {
        let period = model.period();
        let omega = model.omega_e.abs() + 16.0 * model.omega_c.abs();
        if !(period.is_finite() && period > 0.0 && omega.is_finite() && omega > 0.0) {
            return None;
        }
        let pieces_f = (period * omega / (2.0 * MAX_OMEGA_HALF_WIDTH)).ceil();
        if !(pieces_f >= 1.0 && pieces_f <= MAX_PIECES as f64) {
            return None;
        }
        let pieces = pieces_f as usize;
        let width = period / pieces as f64;
        let half = 0.5 * width;
        // Cody–Waite split: T_hi keeps the leading 32 bits
        let period_hi = f64::from_bits(period.to_bits() & !((1u64 << 21) - 1));
        let period_lo = period - period_hi;
        // Chebyshev points of the first kind on [-1, 1] (the doubles nearest) and the Lagrange
        // polynomials of exactly those points in monomials, in double-double
        let nodes: [f64; NC] =
            std::array::from_fn(|j| (std::f64::consts::PI * (j as f64 + 0.5) / NC as f64).dcos());
        let lagrange = lagrange_monomials(&nodes).map(|row| row.map(SplitDd::of));
        let mut data = Vec::with_capacity(pieces * STRIDE);
        let mut values = [[0.0; NC]; 3];
        for i in 0..pieces {
            let centre = (i as f64 + 0.5) * width;
            for (j, &s) in nodes.iter().enumerate() {
                // the node's time τ = centre + half·s in double-double: the sample is at the
                // node itself, not at its rounding (which would shift it by up to ulp(τ))
                let (p, e) = two_product(half, s);
                let (t, f) = two_sum(centre, p);
                let v = model.time_functions_accurate_at(t, f + e);
                for (k, vals) in values.iter_mut().enumerate() {
                    vals[j] = v[k];
                }
            }
            data.push(centre);
            // m_{k,l} = Σ_j L[j][l] f_{k,j}, each sum over `j` in ascending order; the 3 × NC
            // sums side by side (independent chains), the splits of `L` and of the values once
            let mut acc = [[Dd::default(); 3]; NC];
            for (j, row) in lagrange.iter().enumerate() {
                let f: [Split; 3] = std::array::from_fn(|k| Split::of(values[k][j]));
                for (a, sums) in row.iter().zip(acc.iter_mut()) {
                    for (sum, fk) in sums.iter_mut().zip(&f) {
                        sum.add_split_product(a, fk);
                    }
                }
            }
            for sums in &acc {
                for sum in sums {
                    data.push(sum.value());
                }
            }
        }
        Some(Self {
            period_hi,
            period_lo,
            inv_period: 1.0 / period,
            inv_width: pieces as f64 / period,
            inv_half: 1.0 / half,
            pieces,
            data,
        })
    }

    /// The table of `model`, shared with the last few systems that asked for the same model
    /// (a table is a pure function of its model, so a shared one is the table this call would
    /// build, bit for bit; building one costs about as much as integrating a few periods).
    pub fn shared(model: &Model) -> Option<Arc<Self>> {
        let key = format!("{model:?}");
        let lock = || TABLES.lock().unwrap_or_else(|p| p.into_inner());
        if let Some((_, t)) = lock().iter().find(|(k, _)| *k == key) {
            return Some(Arc::clone(t));
        }
        let t = Arc::new(Self::new(model)?);
        let mut cache = lock();
        if !cache.iter().any(|(k, _)| *k == key) {
            if cache.len() == SHARED {
                cache.pop_front();
            }
            cache.push_back((key, Arc::clone(&t)));
        }
        Some(t)
    }

    /// Pieces per period.
    pub fn pieces(&self) -> usize {
        self.pieces
    }

    /// `[F(τ), b̄(τ), f_r(τ)]`; `None` where the table does not apply (`τ < 0`, non-finite,
    /// or `τ ≥ 2²⁰ T`): the caller evaluates directly. (The stored doubles `ω̄_c`, `ω̄_e` make
    /// the model's functions periodic only to rounding: a period later the phase of the mesh
    /// term differs by about `ε ω̄_e T`. The table repeats the first period, `[0, T)`, whose
    /// values it holds to a few units in the last place; its difference from the direct
    /// evaluation then grows as `ε ω̄_e τ`, as the direct evaluation's own rounding of the phase
    /// argument does. Below `τ = 0` it would hold that difference at once, so it declines.)
    #[inline]
    pub fn eval(&self, tau: f64) -> Option<[f64; 3]> {
        let u = tau * self.inv_period;
        if !(0.0..K_MAX).contains(&u) {
            return None;
        }
        // ⌊u⌋ for 0 ≤ u < 2²⁰ by truncation (a `floor` call is a libm call on baseline x86-64)
        let k = u as u32 as f64;
        // r = τ − k T as rh + rl: k T_hi is exact, the two differences error-free
        let (a, b) = two_sum(tau, -k * self.period_hi);
        let (rh, e) = two_sum(a, -k * self.period_lo);
        let rl = e + b;
        let i = ((rh * self.inv_width) as isize).clamp(0, self.pieces as isize - 1) as usize;
        let p = &self.data[i * STRIDE..(i + 1) * STRIDE];
        // rh − c_i is exact (both within one period, the difference below a piece)
        let s = ((rh - p[0]) + rl) * self.inv_half;
        let c: &[f64; 3 * NC] = p[1..].try_into().ok()?;
        // Estrin's scheme: pairs, then pairs of pairs with s², then with s⁴ and s⁸: four
        // multiply–add levels deep where Horner's rule is eleven (the three functions side by
        // side; the evaluation's latency, not its arithmetic, is what the stepper waits on)
        let s2 = s * s;
        let s4 = s2 * s2;
        let s8 = s4 * s4;
        let mut out = [0.0; 3];
        for (j, o) in out.iter_mut().enumerate() {
            let pair = |l: usize| c[3 * l + j] + c[3 * (l + 1) + j] * s;
            let quad = |l: usize| pair(l) + pair(l + 2) * s2;
            *o = (quad(0) + quad(4) * s4) + quad(8) * s8;
        }
        Some(out)
    }
}

/// `L[j][l]`: the coefficient of `s^l` of the Lagrange polynomial `L_j(s) = Π_{i≠j} (s − s_i)
/// / (s_j − s_i)` of the points `nodes`, in double-double. The interpolant of values `f_j` is
/// then `Σ_l (Σ_j L[j][l] f_j) s^l`; summed in double-double, its monomial coefficients are
/// exact to their last place, where a transform in plain sums (or with rounded weights) would
/// leave about `NC` units in the last place of `max |f|` in every coefficient, and in the
/// interpolant.
fn lagrange_monomials(nodes: &[f64; NC]) -> [[Dd; NC]; NC] {
    let mut out = [[Dd::default(); NC]; NC];
    for (j, &sj) in nodes.iter().enumerate() {
        // Π_{i≠j} (s − s_i), coefficients from s^0 up
        let mut poly = [Dd::default(); NC];
        poly[0] = Dd::from(1.0);
        let mut denom = Dd::from(1.0);
        let mut deg = 0;
        for (i, &si) in nodes.iter().enumerate() {
            if i == j {
                continue;
            }
            // multiply by (s − s_i)
            for l in (0..=deg + 1).rev() {
                let shifted = if l > 0 { poly[l - 1] } else { Dd::default() };
                let here = if l <= deg { poly[l] } else { Dd::default() };
                poly[l] = shifted.sub(here.mul_f64(si));
            }
            deg += 1;
            let (d, e) = two_sum(sj, -si);
            denom = denom.mul(Dd { hi: d, lo: e });
        }
        for l in 0..NC {
            out[j][l] = poly[l].div(denom);
        }
    }
    out
}

/// A double-double accumulator: `hi + lo` with `|lo| ≤ ulp(hi)/2`, fed by error-free products
/// (Dekker's split: no fused multiply–add, so the same bits on every platform).
#[derive(Debug, Default, Clone, Copy)]
struct Dd {
    hi: f64,
    lo: f64,
}

/// `a + b = s + e` exactly (Knuth's two-sum).
pub(super) fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// Dekker's split of `a` into two halves of 26 bits.
fn split(a: f64) -> (f64, f64) {
    let c = 134_217_729.0 * a; // 2^27 + 1
    let hi = c - (c - a);
    (hi, a - hi)
}

/// `a b = p + e` exactly (Dekker; no fused multiply–add, the same bits on every platform;
/// for `|a b|` far from overflow).
pub(super) fn two_product(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    let (ah, al) = split(a);
    let (bh, bl) = split(b);
    (p, al * bl - (((p - ah * bh) - al * bh) - ah * bl))
}

impl Dd {
    fn from(a: f64) -> Self {
        Self { hi: a, lo: 0.0 }
    }

    fn renorm(hi: f64, lo: f64) -> Self {
        let (hi, lo) = two_sum(hi, lo);
        Self { hi, lo }
    }

    fn sub(self, b: Self) -> Self {
        let (s, e) = two_sum(self.hi, -b.hi);
        Self::renorm(s, e + self.lo - b.lo)
    }

    fn mul(self, b: Self) -> Self {
        let (p, e) = two_product(self.hi, b.hi);
        Self::renorm(p, e + self.hi * b.lo + self.lo * b.hi)
    }

    fn mul_f64(self, b: f64) -> Self {
        let (p, e) = two_product(self.hi, b);
        Self::renorm(p, e + self.lo * b)
    }

    /// `self / b` to double-double accuracy (one Newton correction of the quotient).
    fn div(self, b: Self) -> Self {
        let q1 = self.hi / b.hi;
        let r = self.sub(b.mul_f64(q1));
        let q2 = r.hi / b.hi;
        Self::renorm(q1, q2)
    }

    /// `self += a b` for a double-double `a` and a double `b` (the reference of
    /// [`add_split_product`](Self::add_split_product) in the tests).
    #[cfg(test)]
    fn add_dd_product(&mut self, a: Dd, b: f64) {
        let (p, e) = two_product(a.hi, b);
        let (s, f) = two_sum(self.hi, p);
        *self = Self::renorm(s, self.lo + e + f + a.lo * b);
    }

    fn value(self) -> f64 {
        self.hi + self.lo
    }

    /// `self += a b` for a double-double `a` and a double `b`: Dekker's product `a.hi b = p + e`
    /// with the splits of `a.hi` and `b` done beforehand, then `(s, f) = two_sum(hi, p)` and
    /// `renorm(s, lo + e + f + a.lo b)`.
    fn add_split_product(&mut self, a: &SplitDd, b: &Split) {
        let p = a.hi.value * b.value;
        let e = a.hi.lo * b.lo - (((p - a.hi.hi * b.hi) - a.hi.lo * b.hi) - a.hi.hi * b.lo);
        let (s, f) = two_sum(self.hi, p);
        *self = Self::renorm(s, self.lo + e + f + a.lo * b.value);
    }
}

/// A double with its Dekker split ([`split`]).
#[derive(Debug, Clone, Copy)]
struct Split {
    value: f64,
    hi: f64,
    lo: f64,
}

impl Split {
    fn of(value: f64) -> Self {
        let (hi, lo) = split(value);
        Self { value, hi, lo }
    }
}

/// A double-double whose leading part comes with its split.
#[derive(Debug, Clone, Copy)]
struct SplitDd {
    hi: Split,
    lo: f64,
}

impl SplitDd {
    fn of(a: Dd) -> Self {
        Self {
            hi: Split::of(a.hi),
            lo: a.lo,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::params::{BaseRadius, RigidSeries, table1};
    use super::*;

    /// The transform of [`TimeTable::new`] (the 3 × `NC` sums side by side, the splits done
    /// once) gives the bits of the plain one: per function and degree, `Σ_j L[j][l] f_j` by
    /// [`Dd::add_dd_product`] in ascending `j`.
    #[test]
    fn the_transform_is_the_plain_double_double_sum() {
        let mut p = table1();
        p.omega1 = 170.0;
        p.eccentricity = 0.6;
        let model = Model::new(&p).expect("model");
        let table = TimeTable::new(&model).expect("table");
        let nodes: [f64; NC] =
            std::array::from_fn(|j| (std::f64::consts::PI * (j as f64 + 0.5) / NC as f64).dcos());
        let lagrange = lagrange_monomials(&nodes);
        let width = model.period() / table.pieces as f64;
        let half = 0.5 * width;
        for i in [0, 1, table.pieces / 2, table.pieces - 1] {
            let centre = (i as f64 + 0.5) * width;
            let values: [[f64; 3]; NC] = std::array::from_fn(|j| {
                let (p, e) = two_product(half, nodes[j]);
                let (t, f) = two_sum(centre, p);
                model.time_functions_accurate_at(t, f + e)
            });
            let piece = &table.data[i * STRIDE..(i + 1) * STRIDE];
            assert_eq!(piece[0].to_bits(), centre.to_bits());
            for l in 0..NC {
                for k in 0..3 {
                    let mut acc = Dd::default();
                    for (j, v) in values.iter().enumerate() {
                        acc.add_dd_product(lagrange[j][l], v[k]);
                    }
                    let stored = piece[1 + 3 * l + k];
                    assert_eq!(
                        stored.to_bits(),
                        acc.value().to_bits(),
                        "piece {i}, l {l}, k {k}"
                    );
                }
            }
        }
    }

    #[test]
    fn the_piece_width_bound_holds() {
        let factorial: f64 = (1..=NC).map(|k| k as f64).product();
        let bound = MAX_OMEGA_HALF_WIDTH.powi(NC as i32) / (factorial * 2f64.powi(DEGREE as i32));
        assert!(bound <= 1e-17 && bound > 5e-18, "{bound:e}");
    }

    /// Every reading, several speeds, phases and eccentricities (0.2 of Table 1 up to 0.9, where
    /// `β = 0.994`): the table is the direct evaluation to within `2·10⁻¹⁵` of each function's
    /// scale (its largest magnitude over a period) plus the rounding of the phase argument
    /// (`4ε ω̄_e τ`, which every evaluation carries), for τ over thousands of periods; below 0,
    /// past the exact reduction, and at NaN, it declines.
    #[test]
    fn table_is_the_direct_evaluation_to_rounding() {
        for br in [BaseRadius::TimeVarying, BaseRadius::Mean] {
            for rs in [RigidSeries::TwoTerms, RigidSeries::Exact] {
                for (omega1, phase, ecc) in [
                    (100.0, 0.0, 0.2),
                    (160.0, 0.4, 0.2),
                    (250.0, -1.3, 0.2),
                    (160.0, 0.0, 0.6),
                    (120.0, 0.7, 0.9),
                ] {
                    let mut p = table1();
                    p.omega1 = omega1;
                    p.eccentricity = ecc;
                    p.readings.base_radius = br;
                    p.readings.rigid_series = rs;
                    p.phase_error = phase;
                    let m = p.model().unwrap();
                    let t = TimeTable::new(&m).unwrap();
                    assert!(t.pieces() > 100 && t.pieces() < 2000, "{}", t.pieces());
                    // each function's scale: its largest magnitude over one period (at a large
                    // eccentricity b̄ = b/(1 + β cos) reaches b/(1 − β), far above b)
                    let mut scale = [0.0f64; 3];
                    for i in 0..4000 {
                        let f = m.time_functions(m.period() * f64::from(i) / 4000.0);
                        for k in 0..3 {
                            scale[k] = scale[k].max(f[k].abs());
                        }
                    }
                    let mut worst = [0.0f64; 3];
                    for i in 0..20_000 {
                        let tau = 1.37 * f64::from(i) * f64::from(i) / 20.0;
                        let a = m.time_functions(tau);
                        let b = t.eval(tau).unwrap();
                        let bound = 2e-15 + 4.0 * f64::EPSILON * m.omega_e * tau;
                        for k in 0..3 {
                            worst[k] = worst[k].max((a[k] - b[k]).abs() / scale[k] / bound);
                        }
                    }
                    assert!(
                        worst.iter().all(|&w| w <= 1.0),
                        "{br:?} {rs:?} {omega1}: {worst:?}"
                    );
                }
            }
        }
        let m = table1().model().unwrap();
        let t = TimeTable::new(&m).unwrap();
        assert!(t.eval(f64::NAN).is_none());
        assert!(t.eval(-1e-3).is_none());
        assert!(t.eval(0.0).is_some());
        assert!(t.eval(f64::INFINITY).is_none());
        assert!(t.eval(2.0e6 * m.period()).is_none());
        assert!(t.eval(1.0e6 * m.period()).is_some());
    }
}
