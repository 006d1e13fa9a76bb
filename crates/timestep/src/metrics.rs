//! Response metrics used by the papers: peak-to-peak (Liu ppv), rattle state (Liu rsv),
//! dynamic factor (Yu Eq. 20) and RMS over harmonics (Yu Eq. 21).

use crate::error::{Error, Result, check_finite, check_finite_slice};

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

/// Rattle state of a backlash coordinate (Liu et al. 2021, Sect. 3.2, "rsv"): the one rattle
/// state of the workspace (the Liu 2021 model classifies into it too).
///
/// With relative displacement `x` and gap edges `±b` (dead zone `|x| ≤ b`), contact on the
/// upper flank means `x > b`, on the lower flank `x < −b`. Ordered by rsv (so that the worst
/// state of a record is the `max` of its samples' states); serde names in snake_case
/// (`no_rattle`, `unilateral`, `no_contact`, `bilateral`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum RattleState {
    /// Permanent contact on one flank, never separating (rsv = 0).
    NoRattle,
    /// Contact on one flank only, with separations into the gap (rsv = 1).
    Unilateral,
    /// Never in contact (pure free flight); only [`rattle_state`] (flank-agnostic) gives it.
    NoContact,
    /// Contact on both flanks (rsv = 2).
    Bilateral,
}

impl RattleState {
    /// Liu's rattle-state value: 0, 1, 2. [`RattleState::NoContact`] counts as 1: in Liu's
    /// definition rsv 1 means "the flanks are apart somewhere and the back flank is never
    /// reached", which free flight satisfies (Sect. 3.2; `docs/readings/timestep.md`).
    pub fn rsv(self) -> u8 {
        match self {
            RattleState::NoRattle => 0,
            RattleState::Unilateral | RattleState::NoContact => 1,
            RattleState::Bilateral => 2,
        }
    }

    /// `no rattle`, `unilateral`, `no contact`, `bilateral`.
    pub fn label(self) -> &'static str {
        match self {
            RattleState::NoRattle => "no rattle",
            RattleState::Unilateral => "unilateral",
            RattleState::NoContact => "no contact",
            RattleState::Bilateral => "bilateral",
        }
    }
}

/// Rattle state of the steady-state samples `x` for a constant gap half-width `b`;
/// `tol` (≥ 0) is a margin: separation means going more than `tol` into the gap.
pub fn rattle_state(x: &[f64], b: f64, tol: f64) -> Result<RattleState> {
    check_finite("b", b)?;
    rattle_state_with_gap(x, &vec![b; x.len()], tol)
}

/// As [`rattle_state`] with a time-varying gap `b[i]` at each sample (dynamic backlash).
pub fn rattle_state_with_gap(x: &[f64], b: &[f64], tol: f64) -> Result<RattleState> {
    nonempty("signal", x)?;
    check_finite_slice("gap", b)?;
    if b.len() != x.len() {
        return Err(Error::DimensionMismatch {
            name: "gap",
            expected: x.len(),
            got: b.len(),
        });
    }
    if !(tol >= 0.0 && tol.is_finite()) {
        return Err(Error::InvalidParameter {
            name: "tol",
            bound: "finite and >= 0",
            value: tol,
        });
    }
    if let Some(i) = b.iter().position(|&v| v < 0.0) {
        return Err(Error::InvalidParameter {
            name: "gap",
            bound: ">= 0",
            value: b[i],
        });
    }
    let upper = x.iter().zip(b).any(|(&v, &g)| v > g);
    let lower = x.iter().zip(b).any(|(&v, &g)| v < -g);
    Ok(match (upper, lower) {
        (true, true) => RattleState::Bilateral,
        (false, false) => RattleState::NoContact,
        (true, false) => {
            if x.iter().zip(b).all(|(&v, &g)| v >= g - tol) {
                RattleState::NoRattle
            } else {
                RattleState::Unilateral
            }
        }
        (false, true) => {
            if x.iter().zip(b).all(|(&v, &g)| v <= -g + tol) {
                RattleState::NoRattle
            } else {
                RattleState::Unilateral
            }
        }
    })
}

/// Dynamic factor `DF = max F_m / F_s` (Yu et al. 2021, Eq. 20): maximum dynamic mesh force
/// over the static force.
pub fn dynamic_factor(mesh_force: &[f64], static_force: f64) -> Result<f64> {
    nonempty("mesh force", mesh_force)?;
    if !(static_force.is_finite() && static_force != 0.0) {
        return Err(Error::InvalidParameter {
            name: "static force",
            bound: "finite and nonzero",
            value: static_force,
        });
    }
    let max = mesh_force.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    Ok(max / static_force)
}

/// RMS over harmonic amplitudes `A_1..A_n` (Yu et al. 2021, Eq. 21):
/// `RMS = sqrt(Σ A_i² / n)`. Use [`crate::harmonic_amplitudes`] for the `A_i`.
pub fn rms_of_harmonics(amplitudes: &[f64]) -> Result<f64> {
    nonempty("harmonic amplitudes", amplitudes)?;
    let s: f64 = amplitudes.iter().map(|a| a * a).sum();
    Ok((s / amplitudes.len() as f64).sqrt())
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
            let (s, co) = (k as f64 * omega * ti).sin_cos();
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
        .map(|ab| ab[0].hypot(ab[1]))
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
    fn rattle_states() {
        let b = 1.0;
        let contact = [1.5, 2.0, 1.2];
        assert_eq!(rattle_state(&contact, b, 0.0).unwrap().rsv(), 0);
        let neg = [-1.5, -2.0, -1.2];
        assert_eq!(rattle_state(&neg, b, 0.0).unwrap(), RattleState::NoRattle);
        let uni = [1.5, 0.0, 1.2];
        assert_eq!(rattle_state(&uni, b, 0.0).unwrap().rsv(), 1);
        let bi = [1.5, 0.0, -1.2];
        assert_eq!(rattle_state(&bi, b, 0.0).unwrap().rsv(), 2);
        assert_eq!(
            rattle_state(&[0.0, 0.5], b, 0.0).unwrap(),
            RattleState::NoContact
        );
        assert_eq!(RattleState::NoContact.rsv(), 1);
        // ordered by rsv: the worst state of a record is the max
        assert!(RattleState::NoRattle < RattleState::Unilateral);
        assert!(RattleState::NoContact < RattleState::Bilateral);
        assert!(rattle_state(&[], b, 0.0).is_err());
        assert!(rattle_state(&[1.0], f64::NAN, 0.0).is_err());
    }

    #[test]
    fn projection_recovers_a_trigonometric_polynomial() {
        let w = 1.7;
        let n = 64;
        let period = std::f64::consts::TAU / w;
        let t: Vec<f64> = (0..2 * n).map(|i| i as f64 * period / n as f64).collect();
        let x: Vec<f64> = t
            .iter()
            .map(|&ti| 0.3 + 1.2 * (w * ti).cos() - 0.4 * (3.0 * w * ti).sin())
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
    fn df_rms_ppv() {
        assert!((dynamic_factor(&[1.0, 3.0, 2.0], 2.0).unwrap() - 1.5).abs() < 1e-15);
        assert!(dynamic_factor(&[1.0], 0.0).is_err());
        assert!((rms_of_harmonics(&[3.0, 4.0]).unwrap() - (12.5f64).sqrt()).abs() < 1e-15);
        assert!((peak_to_peak(&[-1.0, 2.0, 0.5]).unwrap() - 3.0).abs() < 1e-15);
        assert!((rms(&[1.0, -1.0]).unwrap() - 1.0).abs() < 1e-15);
    }
}
