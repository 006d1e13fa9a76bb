//! Fractal backlash: the Weierstrass–Mandelbrot profile (Yu Eq. 2), Chen's fractal backlash
//! (Yu Eq. 3), the effective mean asperity height b_i (Eq. 4) and the constant part b_s (Eq. 5).

use math::DetMath;
use math::short;
use std::f64::consts::PI;

use crate::error::{Error, finite, non_negative, positive};

fn check_d(d: f64) -> Result<f64, Error> {
    if d.is_finite() && d > 1.0 && d < 2.0 {
        Ok(d)
    } else {
        Err(Error::InvalidParameter {
            name: "D",
            bound: "in (1, 2)",
            value: d,
        })
    }
}

fn check_gamma(gamma: f64) -> Result<f64, Error> {
    if gamma.is_finite() && gamma > 1.0 {
        Ok(gamma)
    } else {
        Err(Error::InvalidParameter {
            name: "λ (gamma)",
            bound: "finite and > 1",
            value: gamma,
        })
    }
}

/// Fractal parameters of one rough surface (Yu Eq. 2).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SurfaceFractal {
    /// Fractal dimension D, dimensionless, in (1, 2); larger is smoother (Yu Eq. 2).
    pub d: f64,
    /// Fractal roughness G in m, > 0; smaller is smoother (Yu Eq. 2).
    pub g: f64,
}

impl SurfaceFractal {
    /// Checked constructor: `D ∈ (1, 2)`, `G > 0`.
    pub fn new(d: f64, g: f64) -> Result<Self, Error> {
        Ok(Self {
            d: check_d(d)?,
            g: positive("G", g)?,
        })
    }
}

/// Truncated Weierstrass–Mandelbrot profile, Yu Eq. (2):
///
/// z(l) = G^{D−1} Σ_{k=k_min}^{n_max} λ^{(D−2)k} cos(2π λ^k l),
///
/// with λ^{k_min} ≈ 1/l_a (largest wavelength ≤ l_a, the maximum asperity base diameter) and
/// λ^{n_max} ≤ 1/l_s (smallest wavelength ≥ l_s, the smallest resolvable wavelength). The
/// neglected tail is bounded uniformly in l by [`WmProfile::truncation_bound`].
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct WmProfile {
    surface: SurfaceFractal,
    gamma: f64,
    l_a: f64,
    l_s: f64,
    k_min: i32,
    n_max: i32,
}

impl WmProfile {
    /// Profile for `surface`, frequency density `gamma` (λ > 1, 1.5 "for most surfaces"),
    /// largest wavelength `l_a` (m) and smallest resolvable wavelength `l_s` (m, `0 < l_s < l_a`).
    pub fn new(surface: SurfaceFractal, gamma: f64, l_a: f64, l_s: f64) -> Result<Self, Error> {
        let surface = SurfaceFractal::new(surface.d, surface.g)?;
        let gamma = check_gamma(gamma)?;
        positive("l_a", l_a)?;
        positive("l_s", l_s)?;
        let ln_g = gamma.dln();
        // small tolerance so that l_a = λ^{-k} exactly gives k, not k+1
        let k_min = ((1.0 / l_a).dln() / ln_g - 1e-9).ceil();
        let n_max = ((1.0 / l_s).dln() / ln_g + 1e-9).floor();
        if !(k_min.abs() < 1e6 && n_max.abs() < 1e6) || n_max < k_min {
            return Err(Error::Inconsistent {
                what: "l_a, l_s, λ",
                detail: format!(
                    "no W-M level k with l_s = {l_s} m <= λ^-k <= l_a = {l_a} m (λ = {gamma})"
                ),
            });
        }
        Ok(Self {
            surface,
            gamma,
            l_a,
            l_s,
            k_min: k_min as i32,
            n_max: n_max as i32,
        })
    }

    /// Surface parameters (D, G).
    pub fn surface(&self) -> SurfaceFractal {
        self.surface
    }
    /// λ.
    pub fn gamma(&self) -> f64 {
        self.gamma
    }
    /// Lowest level k_min (λ^{k_min} ≥ 1/l_a).
    pub fn k_min(&self) -> i32 {
        self.k_min
    }
    /// Highest level n_max (λ^{n_max} ≤ 1/l_s).
    pub fn n_max(&self) -> i32 {
        self.n_max
    }
    /// Number of terms kept.
    pub fn n_terms(&self) -> usize {
        (self.n_max - self.k_min + 1) as usize
    }
    /// Smallest wavelength kept, λ^{−n_max} (m).
    pub fn smallest_wavelength(&self) -> f64 {
        self.gamma.powi(-self.n_max)
    }
    /// Largest wavelength kept, λ^{−k_min} (m).
    pub fn largest_wavelength(&self) -> f64 {
        self.gamma.powi(-self.k_min)
    }
    /// The prefactor G^{D−1} (m^{D−1}).
    pub fn prefactor(&self) -> f64 {
        self.surface.g.dpowf(self.surface.d - 1.0)
    }

    /// (amplitude, angular wavenumber) of every kept term, without the prefactor.
    fn terms(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        let ln_g = self.gamma.dln();
        let e = self.surface.d - 2.0;
        (self.k_min..=self.n_max).map(move |k| {
            let kf = f64::from(k);
            ((e * kf * ln_g).dexp(), 2.0 * PI * (kf * ln_g).dexp())
        })
    }

    /// z(l) of Eq. (2), truncated (m). `l` in m.
    pub fn height(&self, l: f64) -> f64 {
        self.prefactor() * self.terms().map(|(a, w)| a * (w * l).dcos()).sum::<f64>()
    }

    /// Upper bound of |z(l)| for the truncated profile: G^{D−1} Σ λ^{(D−2)k} (m).
    pub fn amplitude_sum(&self) -> f64 {
        self.prefactor() * self.terms().map(|(a, _)| a).sum::<f64>()
    }

    /// Uniform bound of the neglected tail of Eq. (2) (m):
    /// G^{D−1} λ^{(D−2)(n_max+1)} / (1 − λ^{D−2}).
    pub fn truncation_bound(&self) -> f64 {
        let r = self.gamma.dpowf(self.surface.d - 2.0);
        self.prefactor() * r.powi(self.n_max + 1) / (1.0 - r)
    }
}

/// Resolution of the quadrature of Eq. (4).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Quadrature {
    /// Midpoint samples per smallest kept wavelength (≥ 2; default 8).
    pub points_per_wavelength: f64,
    /// Refuse settings that need more samples than this (default 2^25).
    pub max_points: usize,
}

impl Default for Quadrature {
    fn default() -> Self {
        Self {
            points_per_wavelength: 8.0,
            max_points: 1 << 25,
        }
    }
}

/// Result of the mean-height integral (Eq. 4) with its error budget.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct MeanHeight {
    /// b_i = (1/L)∫₀^L |z(l)| dl of the truncated profile (m).
    pub value: f64,
    /// Quadrature error estimate (m): half the difference of the two interleaved half-rules
    /// (even and odd midpoints), a conservative estimate of the error of the full rule.
    pub quadrature_error: f64,
    /// Bound of the change of b_i from the truncated tail of Eq. (2) (m); by the triangle
    /// inequality |mean|z_∞| − mean|z_N|| ≤ this.
    pub truncation_bound: f64,
    /// Number of midpoint samples used.
    pub n_points: usize,
    /// Number of W-M terms used.
    pub n_terms: usize,
}

impl MeanHeight {
    /// Total error bound/estimate (m): quadrature estimate + truncation bound.
    pub fn error(&self) -> f64 {
        self.quadrature_error + self.truncation_bound
    }
}

/// Unit-prefactor mean |Σ a_k cos(w_k l)| over [0, L] by the composite midpoint rule, and the
/// even/odd half-rule difference. Terms are advanced by rotation, re-synchronised every block.
fn mean_abs_series(terms: &[(f64, f64)], l_len: f64, n: usize) -> (f64, f64) {
    const CHUNK: usize = 4096;
    const RESYNC: usize = 256;
    let h = l_len / n as f64;
    let mut buf = vec![0.0_f64; CHUNK];
    let (mut s_even, mut s_odd) = (0.0_f64, 0.0_f64);
    let mut start = 0usize;
    while start < n {
        let len = CHUNK.min(n - start);
        let z = &mut buf[..len];
        z.iter_mut().for_each(|v| *v = 0.0);
        for &(a, w) in terms {
            let (s1, c1) = (w * h).dsin_cos();
            let mut j = 0;
            while j < len {
                let l0 = (start + j) as f64 * h + 0.5 * h;
                let (mut s, mut c) = (w * l0).dsin_cos();
                let end = (j + RESYNC).min(len);
                for v in &mut z[j..end] {
                    *v += a * c;
                    let cn = c * c1 - s * s1;
                    s = s * c1 + c * s1;
                    c = cn;
                }
                j = end;
            }
        }
        for (j, v) in z.iter().enumerate() {
            if (start + j) % 2 == 0 {
                s_even += v.abs();
            } else {
                s_odd += v.abs();
            }
        }
        start += len;
    }
    let n_even = n.div_ceil(2) as f64;
    let n_odd = (n / 2) as f64;
    let mean = (s_even + s_odd) / n as f64;
    let est = 0.5 * (s_even / n_even - s_odd / n_odd).abs();
    (mean, est)
}

/// Effective mean asperity height b_i of Yu Eq. (4) for the truncated profile, over the
/// sampling length `l_len` = L (m), with an error budget.
///
/// Cost: N × n_terms with N = points_per_wavelength · L / λ^{−n_max}.
pub fn mean_asperity_height(
    profile: &WmProfile,
    l_len: f64,
    quad: Quadrature,
) -> Result<MeanHeight, Error> {
    let unit = unit_mean_height(profile, l_len, quad)?;
    let p = profile.prefactor();
    Ok(MeanHeight {
        value: unit.value * p,
        quadrature_error: unit.quadrature_error * p,
        truncation_bound: unit.truncation_bound * p,
        ..unit
    })
}

/// b_i / G^{D−1}: the integral does not depend on G, which only scales the profile.
fn unit_mean_height(
    profile: &WmProfile,
    l_len: f64,
    quad: Quadrature,
) -> Result<MeanHeight, Error> {
    positive("L", l_len)?;
    let ppw = positive("points_per_wavelength", quad.points_per_wavelength)?;
    if ppw < 2.0 {
        return Err(Error::InvalidParameter {
            name: "points_per_wavelength",
            bound: ">= 2",
            value: ppw,
        });
    }
    let needed = (ppw * l_len / profile.smallest_wavelength())
        .ceil()
        .max(2.0);
    if !needed.is_finite() || needed > quad.max_points as f64 {
        return Err(Error::ResolutionTooFine {
            what: "Yu Eq. (4) quadrature",
            needed,
            limit: quad.max_points,
        });
    }
    let n = needed as usize;
    let terms: Vec<(f64, f64)> = profile.terms().collect();
    let (mean, est) = mean_abs_series(&terms, l_len, n);
    let p = profile.prefactor();
    Ok(MeanHeight {
        value: mean,
        quadrature_error: est,
        truncation_bound: profile.truncation_bound() / p,
        n_points: n,
        n_terms: terms.len(),
    })
}

/// Which form of the constant part b_s to evaluate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum ConstantPartForm {
    /// Yu Eq. (4)–(5): mean of |z| over L with k from k_min (default; the form the text argues).
    #[default]
    AbsoluteMean,
    /// The b_s under-brace of Yu Eq. (11) as printed: no absolute value and k from 0, i.e.
    /// b_i = G^{D−1} Σ_{k=0}^{n_max} λ^{(D−2)k} sin(2πλ^k L)/(2πλ^k L) with l in metres.
    /// Kept for the reading R-YU-EQ11-BS; it gives metre-scale b_i (see docs/readings).
    PrintedEq11,
}

/// Parameters of the constant part of the backlash, Yu Eq. (5).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ConstantBacklashParams {
    /// Initial backlash b_0 between ideal flat flanks (m), ≥ 0 (Yu Eq. 5).
    pub b0: f64,
    /// Frequency density λ of the W-M profile, > 1 (Yu Eq. 2: 1.5).
    pub gamma: f64,
    /// Maximum asperity base diameter l_a (m): λ^{k_min} = 1/l_a (Yu Eq. 2).
    pub l_a: f64,
    /// Smallest resolvable wavelength l_s (m): sets n_max (truncation of Eq. 2).
    pub l_s: f64,
    /// Sampling length L (m), the length of the contact region (Yu Eq. 4).
    pub sampling_length: f64,
    /// Quadrature resolution of Eq. (4).
    pub quadrature: Quadrature,
    /// Which printed form to use.
    pub form: ConstantPartForm,
}

impl ConstantBacklashParams {
    fn validate(&self) -> Result<(), Error> {
        non_negative("b0", self.b0)?;
        check_gamma(self.gamma)?;
        positive("l_a", self.l_a)?;
        positive("l_s", self.l_s)?;
        positive("L", self.sampling_length)?;
        Ok(())
    }

    fn profile(&self, s: SurfaceFractal) -> Result<WmProfile, Error> {
        WmProfile::new(s, self.gamma, self.l_a, self.l_s)
    }

    /// b_i of one surface (Eq. 4, or the printed Eq. 11 form) with its error budget.
    pub fn mean_height(&self, s: SurfaceFractal) -> Result<MeanHeight, Error> {
        self.validate()?;
        let prof = self.profile(s)?;
        match self.form {
            ConstantPartForm::AbsoluteMean => {
                mean_asperity_height(&prof, self.sampling_length, self.quadrature)
            }
            ConstantPartForm::PrintedEq11 => Ok(printed_eq11_mean(&prof, self.sampling_length)),
        }
    }

    /// Constant part b_s = b_0 − b_p − b_g (Yu Eq. 5) for pinion and gear surfaces.
    ///
    /// b_s can come out negative (asperities taller than the initial gap); it is returned as
    /// computed, and [`ConstantPart::b_s_clamped`] gives max(b_s, 0).
    pub fn constant_part(
        &self,
        pinion: SurfaceFractal,
        gear: SurfaceFractal,
    ) -> Result<ConstantPart, Error> {
        let bp = self.mean_height(pinion)?;
        let bg = self.mean_height(gear)?;
        Ok(ConstantPart {
            b_s: self.b0 - bp.value - bg.value,
            b_p: bp.value,
            b_g: bg.value,
            error: bp.error() + bg.error(),
        })
    }
}

fn printed_eq11_mean(prof: &WmProfile, l_len: f64) -> MeanHeight {
    let ln_g = prof.gamma.dln();
    let e = prof.surface.d - 2.0;
    let p = prof.prefactor();
    let mut sum = 0.0;
    for k in 0..=prof.n_max.max(0) {
        let kf = f64::from(k);
        let x = 2.0 * PI * (kf * ln_g).dexp() * l_len;
        sum += (e * kf * ln_g).dexp() * x.dsin() / x;
    }
    let r = prof.gamma.dpowf(e);
    let tail = r.powi(prof.n_max.max(0) + 1)
        / (1.0 - r)
        / (2.0 * PI * l_len * prof.gamma.powi(prof.n_max.max(0) + 1));
    MeanHeight {
        value: p * sum,
        quadrature_error: 0.0,
        truncation_bound: p * tail,
        n_points: 0,
        n_terms: (prof.n_max.max(0) + 1) as usize,
    }
}

/// Constant part of the backlash (Yu Eq. 5).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ConstantPart {
    /// b_s = b_0 − Σ b_i (m); may be negative.
    pub b_s: f64,
    /// b_p, mean asperity height of the pinion flank (m).
    pub b_p: f64,
    /// b_g, mean asperity height of the gear flank (m).
    pub b_g: f64,
    /// Error budget of b_s (m): quadrature estimates + truncation bounds of both surfaces.
    pub error: f64,
}

impl ConstantPart {
    /// max(b_s, 0): a negative constant part means interference, not a gap.
    pub fn b_s_clamped(&self) -> f64 {
        self.b_s.max(0.0)
    }
}

/// b_i and b_s over a (D, G) grid, with D_p = D_g, G_p = G_g (the form of Yu Fig. 4; the
/// paper's parameter set and the checks of its text are the Yu model's:
/// `geardyn_models::yu2021::{fig4, fig4_claims}`).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ConstantPartGrid {
    /// Parameters used.
    pub params: ConstantBacklashParams,
    /// Fractal dimensions D (rows).
    pub d: Vec<f64>,
    /// Fractal roughness values G in m (columns).
    pub g: Vec<f64>,
    /// b_i(D, G) of one surface (m), `b_i[row][col]`.
    pub b_i: Vec<Vec<f64>>,
    /// b_s(D, G) = b_0 − 2 b_i (m).
    pub b_s: Vec<Vec<f64>>,
    /// Error budget of b_s (m).
    pub error: Vec<Vec<f64>>,
}

/// b_i and b_s over a (D, G) grid (the form of Yu Fig. 4), both surfaces alike. The W-M integral is
/// computed once per D; G enters only through the exact factor G^{D−1}.
pub fn constant_part_grid(
    params: ConstantBacklashParams,
    d_values: &[f64],
    g_values: &[f64],
) -> Result<ConstantPartGrid, Error> {
    params.validate()?;
    for &g in g_values {
        positive("G", g)?;
    }
    let mut b_i = Vec::with_capacity(d_values.len());
    let mut b_s = Vec::with_capacity(d_values.len());
    let mut error = Vec::with_capacity(d_values.len());
    for &d in d_values {
        let unit = params.mean_height(SurfaceFractal::new(d, 1.0)?)?;
        let mut ri = Vec::with_capacity(g_values.len());
        let mut rs = Vec::with_capacity(g_values.len());
        let mut re = Vec::with_capacity(g_values.len());
        for &g in g_values {
            let p = g.dpowf(d - 1.0);
            let bi = unit.value * p;
            ri.push(bi);
            rs.push(params.b0 - 2.0 * bi);
            re.push(2.0 * unit.error() * p);
        }
        b_i.push(ri);
        b_s.push(rs);
        error.push(re);
    }
    Ok(ConstantPartGrid {
        params,
        d: d_values.to_vec(),
        g: g_values.to_vec(),
        b_i,
        b_s,
        error,
    })
}

/// What [`ChenFractal::ratio`] and [`ChenFractal::value_and_derivative`] keep per thread: the
/// law's bits, its ratio `λ^{D−2}`, and the last time and its `(z, z')`.
#[derive(Clone, Copy)]
struct Kept {
    law: (u64, u64, u32),
    ratio: f64,
    /// The bits of the last `t` of [`ChenFractal::value_and_derivative`] and its `(z, z')`.
    last: Option<(u64, (f64, f64))>,
}

thread_local! {
    static CHEN_KEPT: std::cell::Cell<Option<Kept>> = const { std::cell::Cell::new(None) };
}

/// Most terms of [`ChenFractal`] (the limit of [`ChenFractal::for_tolerance`] too).
pub const CHEN_MAX_TERMS: u32 = 1_000_000;

/// Chen's fractal backlash (Yu Eq. 3, Chen et al. 2014):
/// z(t) = Σ_{k=0}^{n−1} λ^{(D−2)k} sin(λ^k t), truncated to `n_terms` terms. Dimensionless.
///
/// Each term's `sin` (and `cos`, for `z'`) comes from [`math::short::sin_cos`], a Cody–Waite
/// reduction and Taylor polynomials within a few `10⁻¹⁶` of `geardyn-math`'s `sin_cos`. The
/// terms dominate the right-hand side of the Yu time stepping: on musl's `sin_cos` they would
/// take 44 % of `yu2021-df-rms-sweeps`, and the short kernel runs that study in 0.84× the CPU
/// time (`docs/performance.md`).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ChenFractal {
    /// Fractal dimension D in (1, 2).
    pub d: f64,
    /// Frequency density λ > 1.
    pub gamma: f64,
    /// Number of terms kept (≥ 1).
    pub n_terms: u32,
}

impl ChenFractal {
    /// Checked constructor.
    pub fn new(d: f64, gamma: f64, n_terms: u32) -> Result<Self, Error> {
        check_d(d)?;
        check_gamma(gamma)?;
        if n_terms == 0 {
            return Err(Error::InvalidParameter {
                name: "n_terms",
                bound: ">= 1",
                value: 0.0,
            });
        }
        // Every evaluation sums n_terms terms: bound the work, and keep λ^n finite.
        if n_terms > CHEN_MAX_TERMS || f64::from(n_terms) * gamma.dln() > 700.0 {
            return Err(Error::InvalidParameter {
                name: "n_terms",
                bound: "<= 1e6 and with λ^n_terms < e^700",
                value: f64::from(n_terms),
            });
        }
        Ok(Self { d, gamma, n_terms })
    }

    /// The number of terms for which the tail bound is ≤ `tol` (absolute, dimensionless).
    pub fn for_tolerance(d: f64, gamma: f64, tol: f64) -> Result<Self, Error> {
        check_d(d)?;
        check_gamma(gamma)?;
        positive("tol", tol)?;
        let r = gamma.dpowf(d - 2.0);
        // r^n / (1 − r) ≤ tol  ⇔  n ≥ ln(tol (1 − r)) / ln r
        let n = ((tol * (1.0 - r)).dln() / r.dln()).ceil().max(1.0);
        if n > 1e6 {
            return Err(Error::ResolutionTooFine {
                what: "Chen fractal backlash (Yu Eq. 3)",
                needed: n,
                limit: 1_000_000,
            });
        }
        Self::new(d, gamma, n as u32)
    }

    /// z(t), truncated. `t` must be finite (non-finite gives NaN, use [`Self::try_value`]).
    /// At most [`CHEN_MAX_TERMS`] terms are summed even if the public field says more.
    pub fn value(&self, t: f64) -> f64 {
        let r = self.ratio();
        let (mut a, mut w, mut s) = (1.0, 1.0, 0.0);
        for _ in 0..self.n_terms.min(CHEN_MAX_TERMS) {
            s += a * short::sin_cos(w * t).0;
            a *= r;
            w *= self.gamma;
        }
        s
    }

    /// `(z(t), z'(t))`, `z'(t) = Σ λ^{(D−1)k} cos(λ^k t)`, truncated as [`Self::value`].
    ///
    /// The last `t` asked on a thread and its values are kept for that thread with the
    /// ratio ([`Self::ratio`]): a time stepping asks the same `t` two or three times in a row
    /// (the last stage of a step, the first-same-as-last stage, its events), and a kept value
    /// is the one this call would compute, bit for bit (keyed on the bits of `λ`, `D`, the
    /// number of terms and `t`).
    pub fn value_and_derivative(&self, t: f64) -> (f64, f64) {
        let key = self.key();
        let kept = CHEN_KEPT.with(std::cell::Cell::get);
        let r = match kept {
            Some(k) if k.law == key => {
                if let Some((kt, z)) = k.last
                    && kt == t.to_bits()
                {
                    return z;
                }
                k.ratio
            }
            _ => self.gamma.dpowf(self.d - 2.0),
        };
        let (mut a, mut w, mut s, mut ds) = (1.0, 1.0, 0.0, 0.0);
        for _ in 0..self.n_terms.min(CHEN_MAX_TERMS) {
            let (sn, cs) = short::sin_cos(w * t);
            s += a * sn;
            ds += a * w * cs;
            a *= r;
            w *= self.gamma;
        }
        CHEN_KEPT.with(|c| {
            c.set(Some(Kept {
                law: key,
                ratio: r,
                last: Some((t.to_bits(), (s, ds))),
            }));
        });
        (s, ds)
    }

    /// The bits that determine [`Self::ratio`] and [`Self::value_and_derivative`].
    fn key(&self) -> (u64, u64, u32) {
        (self.gamma.to_bits(), self.d.to_bits(), self.n_terms)
    }

    /// Checked [`Self::value`].
    pub fn try_value(&self, t: f64) -> Result<f64, Error> {
        Ok(self.value(finite("t", t)?))
    }

    /// The amplitude ratio `λ^{D−2}` of consecutive terms.
    ///
    /// The last `(λ, D)` asked on a thread and its ratio are kept for that thread, so the
    /// evaluations of one law (a time stepping calls [`Self::value_and_derivative`] at every
    /// right-hand side, with the same `λ` and `D`) compute the power once, not per call. The
    /// key is the bits of `λ` and `D`: the kept ratio is the one this call would compute, bit
    /// for bit, and a struct whose public fields change is never served a stale one.
    pub fn ratio(&self) -> f64 {
        let key = self.key();
        CHEN_KEPT.with(|kept| match kept.get() {
            Some(k) if k.law == key => k.ratio,
            _ => {
                let ratio = self.gamma.dpowf(self.d - 2.0);
                kept.set(Some(Kept {
                    law: key,
                    ratio,
                    last: None,
                }));
                ratio
            }
        })
    }

    /// Uniform bound of the neglected tail: λ^{(D−2)n} / (1 − λ^{D−2}).
    pub fn truncation_bound(&self) -> f64 {
        let r = self.ratio();
        r.powi(self.n_terms as i32) / (1.0 - r)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn prof(d: f64, l_s: f64) -> WmProfile {
        WmProfile::new(SurfaceFractal::new(d, 1e-11).unwrap(), 1.5, 1e-3, l_s).unwrap()
    }

    #[test]
    fn levels_from_wavelengths() {
        let p = prof(1.5, 1e-6);
        // 1.5^17 = 985.8 < 1000 <= 1.5^18 = 1477.9; 1.5^34 = 9.7e5 <= 1e6 < 1.5^35
        assert_eq!(p.k_min(), 18);
        assert_eq!(p.n_max(), 34);
        assert!(p.largest_wavelength() <= 1e-3 && p.smallest_wavelength() >= 1e-6);
    }

    #[test]
    fn errors_are_typed() {
        assert!(SurfaceFractal::new(2.3, 1e-11).is_err());
        assert!(SurfaceFractal::new(1.0, 1e-11).is_err());
        assert!(SurfaceFractal::new(1.5, 0.0).is_err());
        assert!(SurfaceFractal::new(f64::NAN, 1e-11).is_err());
        let s = SurfaceFractal::new(1.5, 1e-11).unwrap();
        assert!(WmProfile::new(s, 1.0, 1e-3, 1e-6).is_err());
        assert!(WmProfile::new(s, 1.5, 1e-6, 1e-3).is_err());
        assert!(ChenFractal::new(1.5, 0.9, 10).is_err());
        // used to sum 4e9 terms per call
        assert!(ChenFractal::new(1.5, 1.0 + 1e-9, u32::MAX).is_err());
        assert!(ChenFractal::new(1.5, 2.0, 2000).is_err());
        let p = prof(1.5, 1e-6);
        let q = Quadrature {
            points_per_wavelength: 8.0,
            max_points: 10,
        };
        assert!(matches!(
            mean_asperity_height(&p, 1e-3, q),
            Err(Error::ResolutionTooFine { .. })
        ));
    }

    #[test]
    fn rotation_matches_direct_sum() {
        let p = prof(1.4, 1e-5);
        let q = Quadrature::default();
        let m = mean_asperity_height(&p, 1e-3, q).unwrap();
        let n = m.n_points;
        let h = 1e-3 / n as f64;
        let direct: f64 = (0..n)
            .map(|j| p.height((j as f64 + 0.5) * h).abs())
            .sum::<f64>()
            / n as f64;
        assert!((direct - m.value).abs() <= 1e-10 * direct);
    }

    /// The sum on the short `sin_cos` is the sum on `geardyn-math`'s `sin_cos` to rounding: each
    /// term within 3·10⁻¹⁶ of its own amplitude (`math::short` bound; `λ^k` times that for the
    /// derivative's term), plus the sums' own rounding, over times whose top terms leave the
    /// short kernel's range (`|λ^k t| > 2¹⁹`, the fallback: the same bits there).
    #[test]
    fn chen_terms_on_the_short_kernel_are_the_libm_sum_to_rounding() {
        for (d, gamma, n) in [(1.3, 1.5, 12), (1.7, 1.5, 40), (1.5, 2.0, 30)] {
            let c = ChenFractal::new(d, gamma, n).unwrap();
            let r = gamma.dpowf(d - 2.0);
            for k in 0..200 {
                let t = 0.173 * f64::from(k) * (1.0 + 0.01 * f64::from(k));
                let (mut a, mut w) = (1.0, 1.0);
                let (mut s, mut ds, mut bound, mut dbound) = (0.0, 0.0, 0.0, 0.0);
                for _ in 0..n {
                    let (sn, cs) = (w * t).dsin_cos();
                    s += a * sn;
                    ds += a * w * cs;
                    bound += a;
                    dbound += a * w;
                    a *= r;
                    w *= gamma;
                }
                let (z, dz) = c.value_and_derivative(t);
                let eps = f64::EPSILON;
                assert!(
                    (z - s).abs() <= (3e-16 + 4.0 * f64::from(n) * eps) * bound,
                    "{t}"
                );
                assert!(
                    (dz - ds).abs() <= (3e-16 + 4.0 * f64::from(n) * eps) * dbound,
                    "{t}"
                );
                assert_eq!(c.value(t).to_bits(), z.to_bits());
            }
        }
    }

    /// The ratio kept per thread is the power this call would compute, bit for bit: laws that
    /// alternate, a public field changed between calls, a NaN field, and other threads.
    #[test]
    fn kept_chen_ratio_is_never_stale() {
        let direct = |c: &ChenFractal| c.gamma.dpowf(c.d - 2.0);
        let reference = |c: &ChenFractal, t: f64| {
            let r = direct(c);
            let (mut a, mut w, mut s, mut ds) = (1.0, 1.0, 0.0, 0.0);
            for _ in 0..c.n_terms {
                let (sn, cs) = short::sin_cos(w * t);
                s += a * sn;
                ds += a * w * cs;
                a *= r;
                w *= c.gamma;
            }
            (s.to_bits(), ds.to_bits())
        };
        let bits = |(a, b): (f64, f64)| (a.to_bits(), b.to_bits());
        let mut a = ChenFractal::new(1.3, 1.5, 12).unwrap();
        let b = ChenFractal::new(1.7, 1.5, 12).unwrap();
        for k in 0..20 {
            let t = 0.37 * f64::from(k);
            for c in [&a, &b, &a, &a, &b] {
                assert_eq!(c.ratio().to_bits(), direct(c).to_bits());
                assert_eq!(bits(c.value_and_derivative(t)), reference(c, t));
                assert_eq!(c.value(t).to_bits(), reference(c, t).0);
            }
        }
        // a public field changed after the ratio was kept
        assert_eq!(a.ratio().to_bits(), direct(&a).to_bits());
        a.d = 1.31;
        assert_eq!(a.ratio().to_bits(), direct(&a).to_bits());
        a.gamma = 2.0;
        assert_eq!(bits(a.value_and_derivative(0.9)), reference(&a, 0.9));
        a.d = f64::NAN;
        assert!(a.ratio().is_nan() && a.value(0.9).is_nan());
        a.d = 1.31;
        assert_eq!(a.ratio().to_bits(), direct(&a).to_bits());
        // the same time twice, then another time, then the first again: the kept values are
        // served only for the same bits (a time one ulp off is evaluated)
        let c = ChenFractal::new(1.4, 1.5, 12).unwrap();
        let t = 2.5_f64;
        let t_next = f64::from_bits(t.to_bits() + 1);
        for u in [t, t, t_next, t, -0.0, 0.0, f64::NAN, t] {
            let got = bits(c.value_and_derivative(u));
            let want = reference(&c, u);
            if u.is_nan() {
                assert!(f64::from_bits(got.0).is_nan() && f64::from_bits(want.0).is_nan());
            } else {
                assert_eq!(got, want, "t = {u:e}");
            }
        }
        // another thread keeps its own
        std::thread::scope(|s| {
            s.spawn(|| assert_eq!(b.ratio().to_bits(), direct(&b).to_bits()));
        });
        assert_eq!(a.ratio().to_bits(), direct(&a).to_bits());
    }

    #[test]
    fn chen_tolerance() {
        let c = ChenFractal::for_tolerance(1.5, 1.5, 1e-6).unwrap();
        assert!(c.truncation_bound() <= 1e-6);
        let longer = ChenFractal::new(1.5, 1.5, c.n_terms + 40).unwrap();
        for t in [0.1, 1.0, 7.3] {
            assert!((c.value(t) - longer.value(t)).abs() <= 1e-6);
        }
        assert!(c.try_value(f64::INFINITY).is_err());
    }
}
