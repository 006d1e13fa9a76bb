//! One-sided amplitude spectra (rustfft).

use fft::FftPlanner;
use num_complex::Complex;

use crate::error::{Error, Result, check_finite_slice, check_positive};

/// One-sided amplitude spectrum of a real signal.
///
/// Scaling: for `N` samples `x_n` with DFT `X_k = Σ x_n e^{-2πi kn/N}`, the amplitude is
/// `|X_0|/N` at `k = 0`, `2|X_k|/N` for `0 < k < N/2` and `|X_{N/2}|/N` at the Nyquist bin
/// (even `N`). A sine `A sin(2π f t)` sampled over an integer number of its periods therefore
/// shows exactly `A` in the bin of `f` (no leakage).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Spectrum {
    /// Bin spacing `1/(N dt)` (cycles per unit time).
    pub df: f64,
    /// Amplitudes, bins `0 ..= N/2`.
    pub amplitude: Vec<f64>,
    /// Phases (rad) of the cosine components, `x ≈ Σ A_k cos(2π f_k t + φ_k)`.
    pub phase: Vec<f64>,
}

impl Spectrum {
    /// Frequency of bin `k`.
    pub fn frequency(&self, k: usize) -> f64 {
        k as f64 * self.df
    }

    /// All bin frequencies.
    pub fn frequencies(&self) -> Vec<f64> {
        (0..self.amplitude.len())
            .map(|k| self.frequency(k))
            .collect()
    }

    /// Amplitude in the bin nearest to frequency `f` (cycles per unit time), with that bin's
    /// frequency. Exact when `f` is a multiple of `df` (integer number of periods sampled).
    pub fn amplitude_at(&self, f: f64) -> Result<(f64, f64)> {
        if !(f.is_finite() && f >= 0.0) {
            return Err(Error::InvalidParameter {
                name: "frequency",
                bound: "finite and >= 0",
                value: f,
            });
        }
        let k = (f / self.df).round() as usize;
        if k >= self.amplitude.len() {
            return Err(Error::InvalidParameter {
                name: "frequency",
                bound: "<= Nyquist frequency",
                value: f,
            });
        }
        Ok((self.frequency(k), self.amplitude[k]))
    }
}

/// One-sided amplitude spectrum of `signal` sampled at interval `dt` (see [`Spectrum`]).
pub fn amplitude_spectrum(signal: &[f64], dt: f64) -> Result<Spectrum> {
    check_positive("dt", dt)?;
    check_finite_slice("signal", signal)?;
    let n = signal.len();
    if n < 2 {
        return Err(Error::TooFewSamples {
            name: "signal",
            needed: 2,
            got: n,
        });
    }
    let mut buf: Vec<Complex<f64>> = signal.iter().map(|&x| Complex::new(x, 0.0)).collect();
    FftPlanner::new().plan_forward(n).process(&mut buf);
    let half = n / 2;
    let nf = n as f64;
    let mut amplitude = Vec::with_capacity(half + 1);
    let mut phase = Vec::with_capacity(half + 1);
    for (k, c) in buf.iter().take(half + 1).enumerate() {
        let scale = if k == 0 || (n % 2 == 0 && k == half) {
            1.0
        } else {
            2.0
        };
        amplitude.push(scale * c.norm() / nf);
        phase.push(c.arg());
    }
    Ok(Spectrum {
        df: 1.0 / (nf * dt),
        amplitude,
        phase,
    })
}

/// Amplitudes of harmonics `1..=n_harmonics` of the fundamental when `signal` spans exactly
/// `n_periods` periods of it (uniform samples, end point excluded): harmonic `h` is bin
/// `h·n_periods` (exact-bin sampling, no leakage).
pub fn harmonic_amplitudes(
    signal: &[f64],
    n_periods: usize,
    n_harmonics: usize,
) -> Result<Vec<f64>> {
    if n_periods == 0 {
        return Err(Error::InvalidParameter {
            name: "n_periods",
            bound: ">= 1",
            value: 0.0,
        });
    }
    let needed = 2 * n_harmonics * n_periods + 1;
    if signal.len() < needed {
        return Err(Error::TooFewSamples {
            name: "signal (for the requested harmonics)",
            needed,
            got: signal.len(),
        });
    }
    let sp = amplitude_spectrum(signal, 1.0)?;
    Ok((1..=n_harmonics)
        .map(|h| sp.amplitude[h * n_periods])
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use math::DetMath;
    use std::f64::consts::PI;

    #[test]
    fn sine_of_amplitude_a_shows_a() {
        let n = 256;
        let dt = 0.01;
        let f = 1.0 / (n as f64 * dt) * 5.0; // exactly bin 5
        let x: Vec<f64> = (0..n)
            .map(|i| {
                0.7 + 1.3 * (2.0 * PI * f * i as f64 * dt).dsin()
                    + 0.2 * (2.0 * PI * 3.0 * f * i as f64 * dt).dcos()
            })
            .collect();
        let sp = amplitude_spectrum(&x, dt).unwrap();
        assert!((sp.amplitude[0] - 0.7).abs() < 1e-12);
        assert!((sp.amplitude[5] - 1.3).abs() < 1e-12);
        assert!((sp.amplitude[15] - 0.2).abs() < 1e-12);
        let (fb, a) = sp.amplitude_at(f).unwrap();
        assert!((fb - f).abs() < 1e-12 && (a - 1.3).abs() < 1e-12);
        assert!(sp.amplitude[7] < 1e-12);
    }

    #[test]
    fn nyquist_and_odd_lengths() {
        let x: Vec<f64> = (0..8)
            .map(|i| if i % 2 == 0 { 0.5 } else { -0.5 })
            .collect();
        let sp = amplitude_spectrum(&x, 1.0).unwrap();
        assert!((sp.amplitude[4] - 0.5).abs() < 1e-12);
        let x: Vec<f64> = (0..9)
            .map(|i| (2.0 * PI * 2.0 * i as f64 / 9.0).dcos())
            .collect();
        let sp = amplitude_spectrum(&x, 1.0).unwrap();
        assert!((sp.amplitude[2] - 1.0).abs() < 1e-12);
    }

    #[test]
    fn harmonics_exact_bins_and_errors() {
        let np = 3;
        let spp = 32;
        let x: Vec<f64> = (0..np * spp)
            .map(|i| {
                let th = 2.0 * PI * i as f64 / spp as f64;
                2.0 * th.dcos() + 0.5 * (2.0 * th).dsin()
            })
            .collect();
        let h = harmonic_amplitudes(&x, np, 3).unwrap();
        assert!((h[0] - 2.0).abs() < 1e-12 && (h[1] - 0.5).abs() < 1e-12 && h[2] < 1e-12);
        assert!(amplitude_spectrum(&[1.0], 1.0).is_err());
        assert!(amplitude_spectrum(&[1.0, f64::NAN], 1.0).is_err());
        assert!(amplitude_spectrum(&[1.0, 2.0], -1.0).is_err());
    }
}
