//! Fourier-series mesh stiffness (Liu 2021 Eq. 6) and its single-harmonic form (Liu Eq. 19,
//! Yu 2021 Eq. 17).

use crate::error::{Error, Result, finite, non_negative, positive};
use math::DetMath;

/// Which trigonometric function carries the phase in the single-harmonic form.
///
/// Both papers print the sine form: `k0 + k_r sin(ω_e t + φ_m)` (Liu Eq. 19, Yu Eq. 17). Liu then
/// takes `φ_m = π/2`, which turns it into `k0 + k_r cos(ω_e t)`. The cosine form
/// `k0 + k_r cos(ω_e t + φ_m)` is offered for callers who prefer it; the two are the same curve
/// when `φ_cos = φ_sin − π/2`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum Waveform {
    /// `k0 + k_r sin(ω_e t + φ_m)`, as printed in Liu Eq. (19) and Yu Eq. (17). Default.
    #[default]
    Sine,
    /// `k0 + k_r cos(ω_e t + φ_m)`.
    Cosine,
}

/// Mesh stiffness as a truncated Fourier series (Liu 2021 Eq. 6):
///
/// `k_m(t) = k0 + Σ_{n=1}^{N} [ k_{2n−1} cos(n ω_e t) + k_{2n} sin(n ω_e t) ]`.
///
/// The cosine coefficients `a_n = k_{2n−1}` and sine coefficients `b_n = k_{2n}` are stored
/// separately (`cos()[n−1]`, `sin()[n−1]`); [`FourierStiffness::from_liu_coefficients`] accepts
/// the interleaved layout of Eq. 6. Evaluation needs one `sin_cos` call and a rotation recurrence
/// for the higher harmonics, and never allocates.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(try_from = "FourierStiffnessData", into = "FourierStiffnessData")
)]
pub struct FourierStiffness {
    k0: f64,
    omega_e: f64,
    cos: Vec<f64>,
    sin: Vec<f64>,
}

/// Serialised form of [`FourierStiffness`] (validated on deserialisation).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FourierStiffnessData {
    /// Mean stiffness `k0` \[N/m\] (Liu Eq. 6).
    pub k0: f64,
    /// Mesh (stiffness excitation) angular frequency `ω_e` \[rad/s\] (Liu Eq. 6).
    pub omega_e: f64,
    /// Cosine coefficients `k_{2n−1}`, n = 1..N \[N/m\].
    pub cos: Vec<f64>,
    /// Sine coefficients `k_{2n}`, n = 1..N \[N/m\].
    pub sin: Vec<f64>,
}

impl TryFrom<FourierStiffnessData> for FourierStiffness {
    type Error = Error;
    fn try_from(d: FourierStiffnessData) -> Result<Self> {
        Self::new(d.k0, d.omega_e, d.cos, d.sin)
    }
}

impl From<FourierStiffness> for FourierStiffnessData {
    fn from(s: FourierStiffness) -> Self {
        Self {
            k0: s.k0,
            omega_e: s.omega_e,
            cos: s.cos,
            sin: s.sin,
        }
    }
}

impl FourierStiffness {
    /// Series from the mean `k0` \[N/m\], the mesh angular frequency `ω_e` \[rad/s\] and the cosine
    /// (`k_{2n−1}`) and sine (`k_{2n}`) coefficients \[N/m\], harmonic n = 1, 2, … in order.
    ///
    /// Errors: non-finite values, `ω_e ≤ 0`, lists of different length. A negative mean is
    /// allowed only as far as the numbers go (`k0` must be finite); positivity of the stiffness
    /// is the caller's model choice.
    pub fn new(k0: f64, omega_e: f64, cos: Vec<f64>, sin: Vec<f64>) -> Result<Self> {
        finite("k0", k0)?;
        positive("omega_e", omega_e)?;
        if cos.len() != sin.len() {
            return Err(Error::CoefficientLengthMismatch {
                cos: cos.len(),
                sin: sin.len(),
            });
        }
        for &c in cos.iter() {
            finite("k_{2n-1} (cosine coefficient)", c)?;
        }
        for &s in sin.iter() {
            finite("k_{2n} (sine coefficient)", s)?;
        }
        Ok(Self {
            k0,
            omega_e,
            cos,
            sin,
        })
    }

    /// Series from the interleaved coefficient list of Liu Eq. (6): `[k1, k2, k3, k4, …]` where
    /// `k_{2n−1}` multiplies `cos(nω_e t)` and `k_{2n}` multiplies `sin(nω_e t)`. The list must
    /// have even length.
    pub fn from_liu_coefficients(k0: f64, omega_e: f64, k: &[f64]) -> Result<Self> {
        if k.len() % 2 != 0 {
            return Err(Error::CoefficientLengthMismatch {
                cos: k.len().div_ceil(2),
                sin: k.len() / 2,
            });
        }
        let cos = k.iter().step_by(2).copied().collect();
        let sin = k.iter().skip(1).step_by(2).copied().collect();
        Self::new(k0, omega_e, cos, sin)
    }

    /// A constant stiffness `k0` (no harmonics).
    pub fn constant(k0: f64, omega_e: f64) -> Result<Self> {
        Self::new(k0, omega_e, Vec::new(), Vec::new())
    }

    /// Mean stiffness `k0` \[N/m\].
    pub fn k0(&self) -> f64 {
        self.k0
    }

    /// Mesh angular frequency `ω_e` \[rad/s\].
    pub fn omega_e(&self) -> f64 {
        self.omega_e
    }

    /// Mesh period `T_e = 2π/ω_e` \[s\].
    pub fn period(&self) -> f64 {
        std::f64::consts::TAU / self.omega_e
    }

    /// Cosine coefficients `k_{2n−1}` \[N/m\], index `n − 1`.
    pub fn cos(&self) -> &[f64] {
        &self.cos
    }

    /// Sine coefficients `k_{2n}` \[N/m\], index `n − 1`.
    pub fn sin(&self) -> &[f64] {
        &self.sin
    }

    /// Number of harmonics N.
    pub fn harmonics(&self) -> usize {
        self.cos.len()
    }

    /// The coefficients in the interleaved layout of Liu Eq. (6): `[k1, k2, …, k_{2N}]`.
    pub fn liu_coefficients(&self) -> Vec<f64> {
        self.cos
            .iter()
            .zip(&self.sin)
            .flat_map(|(&a, &b)| [a, b])
            .collect()
    }

    /// Amplitude `sqrt(k_{2n−1}² + k_{2n}²)` of harmonic `n` \[N/m\] (0 for `n = 0` is `|k0|`;
    /// 0 beyond the truncation).
    pub fn amplitude(&self, n: usize) -> f64 {
        if n == 0 {
            return self.k0.abs();
        }
        match (self.cos.get(n - 1), self.sin.get(n - 1)) {
            (Some(a), Some(b)) => a.dhypot(*b),
            _ => 0.0,
        }
    }

    /// Phase of harmonic `n ≥ 1` in the given waveform convention \[rad\], in (−π, π]:
    /// `a cos θ + b sin θ = A sin(θ + φ)` with `φ = atan2(a, b)` (sine form) or
    /// `= A cos(θ + φ)` with `φ = atan2(−b, a)` (cosine form). 0 beyond the truncation or for n = 0.
    pub fn phase(&self, n: usize, waveform: Waveform) -> f64 {
        if n == 0 {
            return 0.0;
        }
        match (self.cos.get(n - 1), self.sin.get(n - 1)) {
            (Some(&a), Some(&b)) => match waveform {
                Waveform::Sine => a.datan2(b),
                Waveform::Cosine => (-b).datan2(a),
            },
            _ => 0.0,
        }
    }

    /// The single-harmonic form (Liu Eq. 19) that keeps `k0` and the fundamental only:
    /// `k_r = amplitude(1)`, `φ_m = phase(1, waveform)`.
    pub fn fundamental(&self, waveform: Waveform) -> SingleHarmonicStiffness {
        SingleHarmonicStiffness {
            k0: self.k0,
            k_r: self.amplitude(1),
            omega_e: self.omega_e,
            phi_m: self.phase(1, waveform),
            waveform,
        }
    }

    /// `k_m(t)` \[N/m\] (Liu Eq. 6).
    #[inline]
    pub fn eval(&self, t: f64) -> f64 {
        self.eval_with_derivative(t).0
    }

    /// `dk_m/dt` \[N/(m s)\]: `ω_e Σ n [k_{2n} cos(nω_e t) − k_{2n−1} sin(nω_e t)]`.
    #[inline]
    pub fn derivative(&self, t: f64) -> f64 {
        self.eval_with_derivative(t).1
    }

    /// `(k_m(t), dk_m/dt)` together, for the cost of one `sin_cos`.
    ///
    /// Harmonic n ≥ 2 comes from the rotation `(c, s)_{n+1} = (c c₁ − s s₁, s c₁ + c s₁)`; its
    /// rounding error grows like `n ε`, i.e. about 1e-15 relative for ten harmonics.
    #[inline]
    pub fn eval_with_derivative(&self, t: f64) -> (f64, f64) {
        let (s1, c1) = (self.omega_e * t).dsin_cos();
        let (mut s, mut c) = (s1, c1);
        let mut k = self.k0;
        let mut dk = 0.0;
        let mut n = 1.0;
        for (&a, &b) in self.cos.iter().zip(&self.sin) {
            k += a * c + b * s;
            dk += n * (b * c - a * s);
            let c_next = c * c1 - s * s1;
            s = s * c1 + c * s1;
            c = c_next;
            n += 1.0;
        }
        (k, dk * self.omega_e)
    }

    /// Fill `out` with `k_m` sampled at `t_j = j T_e periods / out.len()`, j = 0..len, i.e.
    /// uniformly over `periods` whole mesh periods with the end point excluded — the layout
    /// [`crate::fit_fourier`] expects.
    pub fn sample_into(&self, periods: usize, out: &mut [f64]) {
        let n = out.len() as f64;
        let span = self.period() * periods as f64;
        for (j, o) in out.iter_mut().enumerate() {
            *o = self.eval(span * j as f64 / n);
        }
    }

    /// Evaluate `k_m` at arbitrary times: `out[i] = k_m(times[i])` (lengths must match; extra
    /// entries of the longer slice are left untouched). No allocation.
    pub fn eval_into(&self, times: &[f64], out: &mut [f64]) {
        for (o, &t) in out.iter_mut().zip(times) {
            *o = self.eval(t);
        }
    }

    /// `samples` values over `periods` whole mesh periods (see [`FourierStiffness::sample_into`]).
    pub fn sample(&self, periods: usize, samples: usize) -> Vec<f64> {
        let mut v = vec![0.0; samples];
        self.sample_into(periods, &mut v);
        v
    }
}

/// Single-harmonic mesh stiffness with phase (Liu 2021 Eq. 19, Yu 2021 Eq. 17):
/// `k_m(t) = k0 + k_r sin(ω_e t + φ_m)` (or the cosine form, see [`Waveform`]).
///
/// Yu's `k_am (1 + ε sin(ω_h t + φ0))` is the same curve with `k0 = k_am`, `k_r = ε k_am`; see
/// [`SingleHarmonicStiffness::yu2021`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SingleHarmonicStiffness {
    /// Mean stiffness `k0` \[N/m\] (Liu Eq. 19; Yu's `k_am`, Eq. 17).
    pub k0: f64,
    /// Amplitude of the fundamental `k_r` \[N/m\] (Liu Eq. 19; Yu's `ε k_am`).
    pub k_r: f64,
    /// Mesh angular frequency `ω_e` \[rad/s\] (Liu Eq. 19; Yu's `ω_h`).
    pub omega_e: f64,
    /// Phase `φ_m` \[rad\] (Liu Eq. 19; Yu's `φ0`).
    pub phi_m: f64,
    /// Whether the phase rides on a sine (as printed) or a cosine.
    pub waveform: Waveform,
}

impl SingleHarmonicStiffness {
    /// Validated constructor: `k0` finite, `k_r ≥ 0` finite, `ω_e > 0`, `φ_m` finite.
    pub fn new(k0: f64, k_r: f64, omega_e: f64, phi_m: f64, waveform: Waveform) -> Result<Self> {
        finite("k0", k0)?;
        non_negative("k_r", k_r)?;
        positive("omega_e", omega_e)?;
        finite("phi_m", phi_m)?;
        Ok(Self {
            k0,
            k_r,
            omega_e,
            phi_m,
            waveform,
        })
    }

    /// Yu et al. 2021 Eq. (17): `k_am (1 + ε sin(ω_h t + φ0))`, with `k_am > 0` \[N/m\],
    /// fluctuation ratio `0 ≤ ε` \[-\], `ω_h > 0` \[rad/s\], `φ0` \[rad\].
    pub fn yu2021(k_am: f64, epsilon: f64, omega_h: f64, phi0: f64) -> Result<Self> {
        positive("k_am", k_am)?;
        non_negative("epsilon (stiffness fluctuation ratio)", epsilon)?;
        Self::new(k_am, epsilon * k_am, omega_h, phi0, Waveform::Sine)
    }

    /// Ratio `a_k = k_r / k0` (Liu Sect. 3.6 "amplitude coefficient of the mesh stiffness").
    pub fn amplitude_coefficient(&self) -> f64 {
        self.k_r / self.k0
    }

    /// `k_m(t)` \[N/m\].
    #[inline]
    pub fn eval(&self, t: f64) -> f64 {
        self.eval_with_derivative(t).0
    }

    /// `dk_m/dt` \[N/(m s)\].
    #[inline]
    pub fn derivative(&self, t: f64) -> f64 {
        self.eval_with_derivative(t).1
    }

    /// `(k_m(t), dk_m/dt)` for one `sin_cos`.
    #[inline]
    pub fn eval_with_derivative(&self, t: f64) -> (f64, f64) {
        let (s, c) = (self.omega_e * t + self.phi_m).dsin_cos();
        let rate = match self.waveform {
            Waveform::Sine => self.k_r * self.omega_e * c,
            Waveform::Cosine => -self.k_r * self.omega_e * s,
        };
        (self.eval_at_phase(s, c), rate)
    }

    /// `k_m` from the sine `s` and cosine `c` of the phase `ψ = ω_e t + φ_m`:
    /// `k0 + k_r s` ([`Waveform::Sine`]) or `k0 + k_r c` ([`Waveform::Cosine`]); the one the
    /// waveform does not read may be anything. For a caller that has the phase's sine and
    /// cosine already (from an addition theorem or a table); [`eval`](Self::eval) is this
    /// with `(s, c) = sin_cos(ψ)`.
    #[inline]
    pub fn eval_at_phase(&self, s: f64, c: f64) -> f64 {
        match self.waveform {
            Waveform::Sine => self.k0 + self.k_r * s,
            Waveform::Cosine => self.k0 + self.k_r * c,
        }
    }

    /// The same curve as a one-harmonic [`FourierStiffness`] (Liu Eq. 6 coefficients
    /// `k1 = k_r sin φ_m`, `k2 = k_r cos φ_m` for the sine form).
    pub fn to_series(&self) -> Result<FourierStiffness> {
        let (s, c) = self.phi_m.dsin_cos();
        let (a, b) = match self.waveform {
            Waveform::Sine => (self.k_r * s, self.k_r * c),
            Waveform::Cosine => (self.k_r * c, -self.k_r * s),
        };
        FourierStiffness::new(self.k0, self.omega_e, vec![a], vec![b])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn liu_layout_round_trip() {
        let s = FourierStiffness::from_liu_coefficients(1.0, 2.0, &[0.1, 0.2, 0.3, 0.4]).unwrap();
        assert_eq!(s.cos(), &[0.1, 0.3]);
        assert_eq!(s.sin(), &[0.2, 0.4]);
        assert_eq!(s.liu_coefficients(), vec![0.1, 0.2, 0.3, 0.4]);
        assert!(FourierStiffness::from_liu_coefficients(1.0, 2.0, &[0.1]).is_err());
    }

    #[test]
    fn recurrence_matches_direct_sum() {
        let cos: Vec<f64> = (1..=10).map(|n| 1.0 / n as f64).collect();
        let sin: Vec<f64> = (1..=10).map(|n| -0.5 / (n * n) as f64).collect();
        let s = FourierStiffness::new(3.0, 7.0, cos.clone(), sin.clone()).unwrap();
        for i in 0..50 {
            let t = 0.037 * i as f64;
            let mut k = 3.0;
            for n in 1..=10 {
                let th = n as f64 * 7.0 * t;
                k += cos[n - 1] * th.dcos() + sin[n - 1] * th.dsin();
            }
            assert_relative_eq!(s.eval(t), k, epsilon = 1e-13);
        }
    }

    #[test]
    fn single_harmonic_conventions_agree() {
        let sh = SingleHarmonicStiffness::new(5.0, 2.0, 3.0, 0.4, Waveform::Sine).unwrap();
        let series = sh.to_series().unwrap();
        let back = series.fundamental(Waveform::Sine);
        assert_relative_eq!(back.phi_m, 0.4, epsilon = 1e-14);
        assert_relative_eq!(back.k_r, 2.0, epsilon = 1e-14);
        let cosf = series.fundamental(Waveform::Cosine);
        assert_relative_eq!(
            cosf.phi_m,
            0.4 - std::f64::consts::FRAC_PI_2,
            epsilon = 1e-14
        );
        for i in 0..20 {
            let t = 0.1 * i as f64;
            assert_relative_eq!(sh.eval(t), series.eval(t), epsilon = 1e-13);
            assert_relative_eq!(cosf.eval(t), series.eval(t), epsilon = 1e-13);
            assert_relative_eq!(cosf.derivative(t), series.derivative(t), epsilon = 1e-12);
        }
    }

    #[test]
    fn liu_table1_is_a_cosine_at_phi_pi_over_2() {
        // k0 = 3.1e8 N/m, k_r = 0.9e8 N/m, ω_e = 2880 rad/s, φ_m = π/2 (Liu 2021 Table 1 values)
        let k = SingleHarmonicStiffness::new(
            3.1e8,
            0.9e8,
            2880.0,
            std::f64::consts::FRAC_PI_2,
            Waveform::Sine,
        )
        .unwrap();
        assert_relative_eq!(k.eval(0.0), 4.0e8, max_relative = 1e-15);
        assert_relative_eq!(k.amplitude_coefficient(), 0.9 / 3.1, max_relative = 1e-15);
    }

    #[test]
    fn invalid_inputs_are_errors() {
        assert!(FourierStiffness::new(f64::NAN, 1.0, vec![], vec![]).is_err());
        assert!(FourierStiffness::new(1.0, 0.0, vec![], vec![]).is_err());
        assert!(FourierStiffness::new(1.0, 1.0, vec![1.0], vec![]).is_err());
        assert!(FourierStiffness::new(1.0, 1.0, vec![f64::INFINITY], vec![0.0]).is_err());
        assert!(SingleHarmonicStiffness::new(1.0, -1.0, 1.0, 0.0, Waveform::Sine).is_err());
        assert!(SingleHarmonicStiffness::yu2021(-1.0, 0.1, 1.0, 0.0).is_err());
        let e = SingleHarmonicStiffness::new(1.0, 1.0, f64::NAN, 0.0, Waveform::Sine).unwrap_err();
        assert_eq!(e.to_string(), "omega_e must be finite and > 0, got NaN");
    }
}
