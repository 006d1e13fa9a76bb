//! Fit of a Fourier series (Liu Eq. 6) to a sampled stiffness curve with rustfft.

use std::sync::Arc;

use fft::{Fft, FftPlanner};
use num_complex::Complex;

use crate::error::{Error, Result, positive};
use crate::series::{FourierStiffness, SingleHarmonicStiffness, Waveform};

/// Result of [`fit_fourier`]: the series and what it leaves out.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FourierFit {
    /// The fitted series `k0 + Σ_{n≤N} [a_n cos nω_e t + b_n sin nω_e t]`.
    pub series: FourierStiffness,
    /// RMS \[N/m\] of `samples − series` at the sample points, from Parseval (everything the
    /// truncated series does not carry). Zero (to rounding) for a curve band-limited to N
    /// harmonics of `ω_e`.
    pub residual_rms: f64,
    /// RMS \[N/m\] of the part of the curve that is *not* periodic with the mesh period, i.e. the
    /// DFT bins that are not multiples of `periods` (sidebands of a curve that changes from one
    /// mesh period to the next, like the NFG curve of Liu Fig. 7). Included in `residual_rms`.
    pub aperiodic_rms: f64,
}

impl FourierFit {
    /// Liu's path from a curve to Eq. (19): `(k0, k_r, φ_m)` of the fitted fundamental.
    pub fn fundamental(&self, waveform: Waveform) -> SingleHarmonicStiffness {
        self.series.fundamental(waveform)
    }
}

/// A reusable fitter for one sample count: the FFT plan and scratch are made once.
///
/// Conventions: `samples[j] = k(t_j)`, `t_j = j · P T_e / M`, j = 0..M, i.e. `M` uniform samples
/// over `P` whole mesh periods with the end point excluded (the point `t = P T_e` repeats
/// `t = 0`). With the forward DFT `X_m = Σ_j samples[j] e^{−2πi jm/M}`, harmonic n of the mesh
/// frequency sits in bin `m = nP` and
///
/// `k0 = X_0 / M`, `k_{2n−1} = a_n = 2 Re X_{nP} / M`, `k_{2n} = b_n = −2 Im X_{nP} / M`.
///
/// `N` harmonics need `N P < M / 2` (strictly: the Nyquist bin cannot separate cosine and
/// sine). For a curve band-limited to N harmonics the round trip samples → series → samples is
/// exact to rounding.
pub struct FourierFitter {
    len: usize,
    fft: Arc<dyn Fft<f64>>,
    buffer: Vec<Complex<f64>>,
    scratch: Vec<Complex<f64>>,
}

impl std::fmt::Debug for FourierFitter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FourierFitter")
            .field("len", &self.len)
            .finish_non_exhaustive()
    }
}

impl FourierFitter {
    /// Plan a fitter for `len ≥ 3` samples.
    pub fn new(len: usize) -> Result<Self> {
        if len < 3 {
            return Err(Error::TooFewSamples { min: 3, got: len });
        }
        let fft = FftPlanner::new().plan_forward(len);
        let scratch = vec![Complex::new(0.0, 0.0); fft.get_inplace_scratch_len()];
        Ok(Self {
            len,
            fft,
            buffer: vec![Complex::new(0.0, 0.0); len],
            scratch,
        })
    }

    /// Number of samples this fitter was planned for.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Always false (a fitter has at least 3 samples); present for API symmetry with `len`.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Largest number of harmonics resolvable from `len` samples over `periods` periods.
    pub fn max_harmonics(&self, periods: usize) -> usize {
        if periods == 0 {
            0
        } else {
            (self.len - 1) / (2 * periods)
        }
    }

    /// Fit `harmonics` harmonics of `ω_e` to `samples` covering `periods` whole mesh periods.
    /// See the type docs for the conventions.
    pub fn fit(
        &mut self,
        samples: &[f64],
        periods: usize,
        harmonics: usize,
        omega_e: f64,
    ) -> Result<FourierFit> {
        positive("omega_e", omega_e)?;
        if samples.len() != self.len {
            return Err(Error::InvalidCount {
                name: "samples (length the fitter was planned for)",
                min: self.len,
                value: samples.len(),
            });
        }
        if periods == 0 {
            return Err(Error::InvalidCount {
                name: "periods",
                min: 1,
                value: 0,
            });
        }
        let max = self.max_harmonics(periods);
        if harmonics > max {
            return Err(Error::TooManyHarmonics {
                requested: harmonics,
                max,
                samples: self.len,
                periods,
            });
        }
        for (index, (&x, b)) in samples.iter().zip(self.buffer.iter_mut()).enumerate() {
            if !x.is_finite() {
                return Err(Error::NonFiniteSample { index, value: x });
            }
            *b = Complex::new(x, 0.0);
        }
        self.fft
            .process_with_scratch(&mut self.buffer, &mut self.scratch);

        let m = self.len as f64;
        let x = &self.buffer;
        let k0 = x[0].re / m;
        let mut cos = Vec::with_capacity(harmonics);
        let mut sin = Vec::with_capacity(harmonics);
        for n in 1..=harmonics {
            let c = x[n * periods];
            cos.push(2.0 * c.re / m);
            sin.push(-2.0 * c.im / m);
        }
        // Parseval: (1/M) Σ |x_j − fit_j|² = (1/M²) Σ_{bins not kept} |X_m|².
        let mut residual = 0.0;
        let mut aperiodic = 0.0;
        for (bin, c) in x.iter().enumerate().skip(1) {
            let folded = bin.min(self.len - bin);
            let p = c.norm_sqr();
            if folded % periods != 0 {
                aperiodic += p;
                residual += p;
            } else if folded / periods > harmonics {
                residual += p;
            }
        }
        let series = FourierStiffness::new(k0, omega_e, cos, sin)?;
        Ok(FourierFit {
            series,
            residual_rms: residual.sqrt() / m,
            aperiodic_rms: aperiodic.sqrt() / m,
        })
    }
}

/// Fit a Fourier series (Liu Eq. 6) with `harmonics` harmonics of the mesh frequency `ω_e`
/// \[rad/s\] to `samples` \[N/m\] taken uniformly over `periods` whole mesh periods (end point
/// excluded). Plans a fresh FFT; use [`FourierFitter`] to fit many curves of one length.
///
/// ```
/// use geardyn_mesh_stiffness::{fit_fourier, FourierStiffness};
/// let k = FourierStiffness::new(3.0e8, 100.0, vec![4.0e7, 1.0e7], vec![-2.0e7, 0.0]).unwrap();
/// let samples = k.sample(2, 64); // two mesh periods, 64 samples
/// let fit = fit_fourier(&samples, 2, 2, 100.0).unwrap();
/// assert!((fit.series.cos()[0] - 4.0e7).abs() < 1e-6);
/// assert!(fit.residual_rms < 1e-6);
/// ```
pub fn fit_fourier(
    samples: &[f64],
    periods: usize,
    harmonics: usize,
    omega_e: f64,
) -> Result<FourierFit> {
    FourierFitter::new(samples.len())?.fit(samples, periods, harmonics, omega_e)
}

/// Liu's path from a sampled curve to Eq. (19): fit the mean and the fundamental and return
/// `(k0, k_r, φ_m)` as a [`SingleHarmonicStiffness`] in the given waveform convention.
pub fn fit_single_harmonic(
    samples: &[f64],
    periods: usize,
    omega_e: f64,
    waveform: Waveform,
) -> Result<SingleHarmonicStiffness> {
    Ok(fit_fourier(samples, periods, 1, omega_e)?.fundamental(waveform))
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use math::DetMath;

    #[test]
    fn errors() {
        assert!(matches!(
            fit_fourier(&[1.0, 2.0], 1, 0, 1.0),
            Err(Error::TooFewSamples { .. })
        ));
        let s = vec![1.0; 16];
        assert!(matches!(
            fit_fourier(&s, 2, 4, 1.0),
            Err(Error::TooManyHarmonics { max: 3, .. })
        ));
        assert!(fit_fourier(&s, 0, 1, 1.0).is_err());
        assert!(fit_fourier(&s, 1, 1, -1.0).is_err());
        let mut bad = s.clone();
        bad[5] = f64::NAN;
        assert!(matches!(
            fit_fourier(&bad, 1, 1, 1.0),
            Err(Error::NonFiniteSample { index: 5, .. })
        ));
        let mut f = FourierFitter::new(16).unwrap();
        assert!(f.fit(&s[..8], 1, 1, 1.0).is_err());
    }

    #[test]
    fn aperiodic_part_is_detected() {
        // a component at half the mesh frequency over 2 periods is not mesh-periodic
        let m = 64;
        let samples: Vec<f64> = (0..m)
            .map(|j| 1.0 + 0.5 * (std::f64::consts::TAU * j as f64 / m as f64).dcos())
            .collect();
        let fit = fit_fourier(&samples, 2, 3, 1.0).unwrap();
        assert_relative_eq!(fit.series.k0(), 1.0, epsilon = 1e-15);
        assert!(fit.series.amplitude(1) < 1e-15);
        // rms of 0.5 cos = 0.5/√2
        assert_relative_eq!(fit.aperiodic_rms, 0.5 / 2f64.sqrt(), epsilon = 1e-14);
        assert_relative_eq!(fit.residual_rms, fit.aperiodic_rms, epsilon = 1e-15);
    }
}
