//! Signal metrics of a record: peak-to-peak, RMS and Fourier projection onto the harmonics of a
//! frequency. (The gear metrics built on them — rattle state, dynamic factor, RMS over
//! harmonics — are in `geardyn_models::response`.)

use crate::error::{Error, Result, check_finite, check_finite_slice};
use math::DetMath;

fn nonempty(name: &'static str, x: &[f64]) -> Result<()> {
    if x.is_empty() {
        return Err(Error::TooFewSamples {
            name,
            needed: 1,
            got: 0,
        });
    }
    check_finite_slice(name, x)
}

/// Peak-to-peak value `max x − min x` (Liu et al. 2021 "ppv", of the steady-state response).
pub fn peak_to_peak(x: &[f64]) -> Result<f64> {
    nonempty("signal", x)?;
    let (lo, hi) = x
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });
    Ok(hi - lo)
}

/// Fourier projection of samples `x(t_i)` onto the harmonics of `omega`:
/// `[c_0, a_1, b_1, …, a_h, b_h]` with `c_0 = Σ x_i / N`, `a_j = (2/N) Σ x_i cos(jωt_i)`,
/// `b_j = (2/N) Σ x_i sin(jωt_i)`, so that `x(t) ≈ c_0 + Σ a_j cos(jωt) + b_j sin(jωt)`.
/// Exact (the discrete orthogonality of the rectangle rule) when the `N` samples are uniform
/// over whole periods of `2π/ω` and `N > 2h`; the amplitude of harmonic `j` is
/// `hypot(a_j, b_j)` ([`harmonic_amplitudes_of_projection`]).
pub fn fourier_projection(t: &[f64], x: &[f64], omega: f64, h: usize) -> Result<Vec<f64>> {
    let harmonics: Vec<usize> = (1..=h).collect();
    fourier_projection_at(t, x, omega, &harmonics)
}

/// As [`fourier_projection`] onto a chosen set of harmonics `k_1, k_2, …` (e.g. the sparse
/// basis of a harmonic-balance solution): `[c_0, a_{k_1}, b_{k_1}, a_{k_2}, b_{k_2}, …]`, with
/// `a_k = (2/N) Σ x_i cos(kωt_i)` and `b_k = (2/N) Σ x_i sin(kωt_i)`. Exact when the samples
/// are uniform over whole periods and `N > 2·max k`.
pub fn fourier_projection_at(
    t: &[f64],
    x: &[f64],
    omega: f64,
    harmonics: &[usize],
) -> Result<Vec<f64>> {
    nonempty("signal", x)?;
    check_finite_slice("time", t)?;
    check_finite("omega", omega)?;
    if t.len() != x.len() {
        return Err(Error::DimensionMismatch {
            name: "time",
            expected: x.len(),
            got: t.len(),
        });
    }
    let n = x.len() as f64;
    let mut c = vec![0.0; 2 * harmonics.len() + 1];
    c[0] = x.iter().sum::<f64>() / n;
    for (j, &k) in harmonics.iter().enumerate() {
        let (mut a, mut b) = (0.0, 0.0);
        for (ti, xi) in t.iter().zip(x) {
            let (s, co) = (k as f64 * omega * ti).dsin_cos();
            a += xi * co;
            b += xi * s;
        }
        c[2 * j + 1] = 2.0 * a / n;
        c[2 * j + 2] = 2.0 * b / n;
    }
    Ok(c)
}

/// Amplitudes `A_j = hypot(a_j, b_j)`, `j = 1..=h`, of a [`fourier_projection`].
pub fn harmonic_amplitudes_of_projection(coefficients: &[f64]) -> Vec<f64> {
    coefficients
        .get(1..)
        .unwrap_or(&[])
        .chunks_exact(2)
        .map(|ab| ab[0].dhypot(ab[1]))
        .collect()
}

/// Plain RMS of a signal, `sqrt(mean x²)`.
pub fn rms(x: &[f64]) -> Result<f64> {
    nonempty("signal", x)?;
    Ok((x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn projection_recovers_a_trigonometric_polynomial() {
        let w = 1.7;
        let n = 64;
        let period = std::f64::consts::TAU / w;
        let t: Vec<f64> = (0..2 * n).map(|i| i as f64 * period / n as f64).collect();
        let x: Vec<f64> = t
            .iter()
            .map(|&ti| 0.3 + 1.2 * (w * ti).dcos() - 0.4 * (3.0 * w * ti).dsin())
            .collect();
        let c = fourier_projection(&t, &x, w, 3).unwrap();
        let want = [0.3, 1.2, 0.0, 0.0, 0.0, 0.0, -0.4];
        for (a, b) in c.iter().zip(want) {
            assert!((a - b).abs() < 1e-13, "{c:?}");
        }
        let amp = harmonic_amplitudes_of_projection(&c);
        assert!((amp[0] - 1.2).abs() < 1e-13 && amp[1].abs() < 1e-13);
        assert!((amp[2] - 0.4).abs() < 1e-13);
        assert!(fourier_projection(&t[1..], &x, w, 3).is_err());
        // a sparse set: harmonics 3 and 1, in that order
        let sparse = fourier_projection_at(&t, &x, w, &[3, 1]).unwrap();
        let want = [0.3, 0.0, -0.4, 1.2, 0.0];
        for (a, b) in sparse.iter().zip(want) {
            assert!((a - b).abs() < 1e-13, "{sparse:?}");
        }
        assert!(fourier_projection(&[], &[], w, 3).is_err());
    }

    #[test]
    fn rms_ppv() {
        assert!((peak_to_peak(&[-1.0, 2.0, 0.5]).unwrap() - 3.0).abs() < 1e-15);
        assert!((rms(&[1.0, -1.0]).unwrap() - 1.0).abs() < 1e-15);
    }
}
