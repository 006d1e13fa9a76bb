//! Alternating single/double tooth-pair mesh stiffness (shape of Liu 2021 Fig. 7) and its
//! noncircular-face-gear (NFG) variant whose per-period curve changes around the pitch curve.

use math::DetMath;
use std::f64::consts::{FRAC_PI_4, PI, TAU};

use crate::error::{Error, Result, non_negative, positive};
use crate::series::FourierStiffness;

/// Smoothed unit step of width `s` centred on 0: 0 below `−s/2`, 1 above `s/2`,
/// `½(1 + sin(πx/s))` in between; `½` exactly at 0 when `s = 0`.
#[inline]
fn smooth_step(x: f64, s: f64) -> f64 {
    let h = 0.5 * s;
    if x > h {
        1.0
    } else if x < -h {
        0.0
    } else if s > 0.0 {
        0.5 * (1.0 + (PI * x / s).dsin())
    } else {
        0.5
    }
}

/// Derivative of [`smooth_step`] in `x` (0 off the ramp and for a sharp step).
#[inline]
fn smooth_step_rate(x: f64, s: f64) -> f64 {
    if s > 0.0 && x.abs() < 0.5 * s {
        0.5 * PI / s * (PI * x / s).dcos()
    } else {
        0.0
    }
}

/// Classic alternating single/double tooth-pair mesh stiffness: a rectangular wave per mesh
/// period (Liu 2021 Sect. 3.1, Fig. 7: "the alternation rule of one and two pairs of teeth").
///
/// With mesh phase `u = t/T_e` (mesh periods) and `w = ε_α − 1` the double-contact fraction of
/// the period, one period reads
///
/// `k(u) = k_double` on `[0, w)`, `k_single` on `[w, 1)`
///
/// (the period starts where the second pair enters). At a sharp jump the value is the mean of
/// the two sides (Dirichlet's convention, which makes the sampled DFT converge as `O(1/M²)`).
/// With `smoothing = s > 0` each jump becomes a raised-sine ramp of width `s` (mesh periods)
/// centred on the jump, which is the sharp wave convolved with the kernel
/// `(π/2s) cos(πx/s)` on `|x| < s/2`; the analytic Fourier coefficients
/// ([`ToothPairStiffness::analytic_series`]) are then those of the sharp wave times
/// `cos(πns)/(1 − (2ns)²)`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ToothPairStiffness {
    /// Transverse contact ratio `ε_α` \[-\], in (1, 2].
    pub contact_ratio: f64,
    /// Mesh stiffness with one tooth pair in contact \[N/m\].
    pub k_single: f64,
    /// Mesh stiffness with two tooth pairs in contact \[N/m\] (two pair springs in parallel,
    /// Liu Sect. 3.1).
    pub k_double: f64,
    /// Width of each transition ramp \[mesh periods\], `0 ≤ s ≤ min(w, 1 − w)`.
    pub smoothing: f64,
}

impl ToothPairStiffness {
    /// Validated constructor (see the field docs for the ranges).
    pub fn new(contact_ratio: f64, k_single: f64, k_double: f64, smoothing: f64) -> Result<Self> {
        if !(contact_ratio > 1.0 && contact_ratio <= 2.0) {
            return Err(Error::InvalidParameter {
                name: "contact ratio",
                bound: "in (1, 2]",
                value: contact_ratio,
            });
        }
        positive("k_single", k_single)?;
        positive("k_double", k_double)?;
        non_negative("smoothing", smoothing)?;
        let w = contact_ratio - 1.0;
        if smoothing > w.min(1.0 - w) {
            return Err(Error::InvalidParameter {
                name: "smoothing",
                bound: "<= min(contact ratio - 1, 2 - contact ratio) mesh periods",
                value: smoothing,
            });
        }
        Ok(Self {
            contact_ratio,
            k_single,
            k_double,
            smoothing,
        })
    }

    /// Two identical pairs of stiffness `k_pair` \[N/m\] in parallel: `k_single = k_pair`,
    /// `k_double = 2 k_pair`.
    pub fn from_pair_stiffness(contact_ratio: f64, k_pair: f64, smoothing: f64) -> Result<Self> {
        Self::new(contact_ratio, k_pair, 2.0 * k_pair, smoothing)
    }

    /// Double-contact fraction of the mesh period `w = ε_α − 1`.
    pub fn double_fraction(&self) -> f64 {
        self.contact_ratio - 1.0
    }

    /// Mean stiffness `k0 = k_single + (k_double − k_single) w` \[N/m\] (smoothing keeps it).
    pub fn mean(&self) -> f64 {
        self.k_single + (self.k_double - self.k_single) * self.double_fraction()
    }

    /// Stiffness \[N/m\] at mesh phase `u` \[mesh periods\] (any real; periodic with period 1).
    #[inline]
    pub fn value_at_phase(&self, u: f64) -> f64 {
        let u = u.rem_euclid(1.0);
        let w = self.double_fraction();
        let s = self.smoothing;
        let ind = smooth_step(u, s) - smooth_step(u - w, s) + smooth_step(u - 1.0, s);
        self.k_single + (self.k_double - self.k_single) * ind
    }

    /// `dk/du` \[N/m per mesh period\] at mesh phase `u`: 0 on the flats and at a sharp jump
    /// (the jump is a Dirac the law does not report), the ramp's slope with smoothing.
    #[inline]
    pub fn rate_at_phase(&self, u: f64) -> f64 {
        let u = u.rem_euclid(1.0);
        let w = self.double_fraction();
        let s = self.smoothing;
        let d = smooth_step_rate(u, s) - smooth_step_rate(u - w, s) + smooth_step_rate(u - 1.0, s);
        (self.k_double - self.k_single) * d
    }

    /// Stiffness \[N/m\] at time `t` \[s\] for mesh angular frequency `ω_e` \[rad/s\].
    #[inline]
    pub fn value_at_time(&self, t: f64, omega_e: f64) -> f64 {
        self.value_at_phase(omega_e * t / TAU)
    }

    /// `samples_per_period × periods` samples at `u_j = j / samples_per_period` (end point
    /// excluded), the layout [`crate::fit_fourier`] expects.
    pub fn sample(&self, samples_per_period: usize, periods: usize) -> Vec<f64> {
        let n = samples_per_period as f64;
        (0..samples_per_period * periods)
            .map(|j| self.value_at_phase(j as f64 / n))
            .collect()
    }

    /// Exact Fourier coefficients of the (smoothed) wave up to `harmonics`, as a series in
    /// `ω_e` \[rad/s\]:
    ///
    /// `a_n = Δ sin(2πnw)/(πn) · H_n`, `b_n = Δ (1 − cos 2πnw)/(πn) · H_n`,
    /// `Δ = k_double − k_single`, `H_n = cos(πns)/(1 − (2ns)²)` (`π/4` at `2ns = 1`, 1 for s = 0).
    pub fn analytic_series(&self, harmonics: usize, omega_e: f64) -> Result<FourierStiffness> {
        let d = self.k_double - self.k_single;
        let w = self.double_fraction();
        let mut cos = Vec::with_capacity(harmonics);
        let mut sin = Vec::with_capacity(harmonics);
        for n in 1..=harmonics {
            let nf = n as f64;
            let x = 2.0 * nf * self.smoothing;
            let h = if (1.0 - x * x).abs() < 1e-9 {
                FRAC_PI_4
            } else {
                (0.5 * PI * x).dcos() / (1.0 - x * x)
            };
            let (s, c) = (TAU * nf * w).dsin_cos();
            cos.push(d * s / (PI * nf) * h);
            sin.push(d * (1.0 - c) / (PI * nf) * h);
        }
        FourierStiffness::new(self.mean(), omega_e, cos, sin)
    }
}

/// Tooth-pair stiffness of a noncircular face gear (NFG) whose per-period curve changes with
/// the mesh position around the pitch curve (Liu 2021 Sect. 3.1: "Due to the asymmetry of the
/// teeth of the NFG, the stiffness curve in every meshing period is various", Fig. 7).
///
/// Liu computes each period by FE and gives no formula; this crate's model (see
/// `docs/readings/mesh-stiffness.md`, R-LIU-FIG7) ties the variation to the instantaneous-centre
/// radius: mesh period `j` of the `Z₂` periods of one NFG revolution has the centre angle
/// `θ_j = 2π (j + ½)/Z₂` and the normalised pitch radius of Liu Eq. (18),
///
/// `ρ(θ) = (1 + 2e cos θ + e²)/(1 + e²)`  (mean 1; `r₂ ∝ i₁₂`, Eq. 1),
///
/// and its contact ratio and pair stiffnesses are
///
/// `ε_α,j = ε_α [1 + γ_ε (ρ_j − 1)]`, `k_j = k [1 + γ_k (ρ_j − 1)]` (both single and double).
///
/// A larger local pitch radius means a longer path of contact and a flatter, stiffer tooth
/// engagement; `γ_ε`, `γ_k` are sensitivities the user chooses (0 gives the circular gear).
/// Within a period the curve is the rectangular wave of [`ToothPairStiffness`]. Over one NFG
/// revolution (`Z₂` periods, frequency `ω_c = ω_e/Z₂`) the DFT then shows the mesh harmonics
/// plus sidebands at `nω_e ± ω_c`; [`crate::FourierFit::aperiodic_rms`] measures them.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct NfgToothPairStiffness {
    /// The mean (circular-gear) curve: `ε_α`, `k_single`, `k_double`, smoothing.
    pub base: ToothPairStiffness,
    /// Number of NFG teeth `Z₂` = mesh periods per NFG revolution (Liu Sect. 2.2, `ω_e/ω_c = Z₂`).
    pub teeth: usize,
    /// Eccentric ratio `e` of the pitch curve \[-\], in [0, 1) (Liu Eq. 18, `ε` there).
    pub eccentricity: f64,
    /// Sensitivity `γ_ε` of the contact ratio to the pitch radius \[-\].
    pub contact_ratio_sensitivity: f64,
    /// Sensitivity `γ_k` of the pair stiffnesses to the pitch radius \[-\].
    pub stiffness_sensitivity: f64,
}

impl NfgToothPairStiffness {
    /// Validated constructor: `teeth ≥ 1`, `0 ≤ e < 1`, finite sensitivities, and every period's
    /// contact ratio, stiffnesses and smoothing within the ranges of [`ToothPairStiffness`].
    pub fn new(
        base: ToothPairStiffness,
        teeth: usize,
        eccentricity: f64,
        contact_ratio_sensitivity: f64,
        stiffness_sensitivity: f64,
    ) -> Result<Self> {
        // re-validate the base (its fields are public)
        ToothPairStiffness::new(
            base.contact_ratio,
            base.k_single,
            base.k_double,
            base.smoothing,
        )?;
        if teeth == 0 {
            return Err(Error::InvalidCount {
                name: "teeth (Z2)",
                min: 1,
                value: 0,
            });
        }
        if !(0.0..1.0).contains(&eccentricity) {
            return Err(Error::InvalidParameter {
                name: "eccentricity",
                bound: "in [0, 1)",
                value: eccentricity,
            });
        }
        crate::error::finite("contact ratio sensitivity", contact_ratio_sensitivity)?;
        crate::error::finite("stiffness sensitivity", stiffness_sensitivity)?;
        let s = Self {
            base,
            teeth,
            eccentricity,
            contact_ratio_sensitivity,
            stiffness_sensitivity,
        };
        // the extremes of ρ − 1 are ±2e/(1+e²); check both ends (the map is affine in ρ)
        let m = 2.0 * eccentricity / (1.0 + eccentricity * eccentricity);
        for dr in [m, -m] {
            s.curve_for(dr)?;
        }
        for j in 0..teeth {
            s.period_curve(j)?;
        }
        Ok(s)
    }

    fn curve_for(&self, rho_minus_one: f64) -> Result<ToothPairStiffness> {
        let b = &self.base;
        let fe = 1.0 + self.contact_ratio_sensitivity * rho_minus_one;
        let fk = 1.0 + self.stiffness_sensitivity * rho_minus_one;
        ToothPairStiffness::new(
            b.contact_ratio * fe,
            b.k_single * fk,
            b.k_double * fk,
            b.smoothing,
        )
    }

    /// Normalised pitch radius `ρ(θ) = (1 + 2e cos θ + e²)/(1 + e²)` (Liu Eq. 18 over its mean).
    pub fn normalized_radius(&self, theta: f64) -> f64 {
        let e = self.eccentricity;
        (1.0 + 2.0 * e * theta.dcos() + e * e) / (1.0 + e * e)
    }

    /// The rectangular-wave curve of mesh period `j` (taken modulo `Z₂`), at centre angle
    /// `θ_j = 2π (j + ½)/Z₂`.
    pub fn period_curve(&self, j: usize) -> Result<ToothPairStiffness> {
        let j = j % self.teeth;
        let theta = TAU * (j as f64 + 0.5) / self.teeth as f64;
        self.curve_for(self.normalized_radius(theta) - 1.0)
    }

    /// Stiffness \[N/m\] at mesh phase `u` \[mesh periods\] counted from the start of period 0
    /// (periodic with period `Z₂`). At a period boundary the value is that of the new period.
    pub fn value_at_phase(&self, u: f64) -> f64 {
        let (c, v) = self.curve_at(u);
        c.value_at_phase(v)
    }

    /// The period curve at mesh phase `u` and the phase within it.
    fn curve_at(&self, u: f64) -> (ToothPairStiffness, f64) {
        let z = self.teeth as f64;
        let u = u.rem_euclid(z);
        let j = (u.floor() as usize).min(self.teeth - 1);
        match self.period_curve(j) {
            Ok(c) => (c, u - j as f64),
            // unreachable: every period was validated in `new`; fall back to the base curve
            Err(_) => (self.base, u),
        }
    }

    /// `dk/du` at mesh phase `u` (the period curve's [`ToothPairStiffness::rate_at_phase`]).
    pub fn rate_at_phase(&self, u: f64) -> f64 {
        let (c, v) = self.curve_at(u);
        c.rate_at_phase(v)
    }

    /// One NFG revolution: `Z₂ × samples_per_period` samples (end point excluded). Fit it with
    /// `periods = Z₂` to obtain Liu's `(k0, k_r, φ_m)`.
    pub fn sample_revolution(&self, samples_per_period: usize) -> Vec<f64> {
        let mut out = Vec::with_capacity(self.teeth * samples_per_period);
        let n = samples_per_period as f64;
        for j in 0..self.teeth {
            let c = self.period_curve(j).unwrap_or(self.base);
            out.extend((0..samples_per_period).map(|i| c.value_at_phase(i as f64 / n)));
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn shape_and_mean() {
        let k = ToothPairStiffness::new(1.6, 2.0e8, 3.5e8, 0.0).unwrap();
        assert_relative_eq!(k.value_at_phase(0.3), 3.5e8);
        assert_relative_eq!(k.value_at_phase(0.8), 2.0e8);
        assert_relative_eq!(k.value_at_phase(1.3), 3.5e8);
        assert_relative_eq!(k.value_at_phase(-0.2), 2.0e8);
        assert_relative_eq!(k.value_at_phase(0.0), 2.75e8);
        assert_relative_eq!(k.mean(), 2.0e8 + 1.5e8 * 0.6, max_relative = 1e-15);
        let s = ToothPairStiffness::new(1.6, 2.0e8, 3.5e8, 0.1).unwrap();
        assert_relative_eq!(s.value_at_phase(0.6), 2.75e8, max_relative = 1e-15);
        assert_relative_eq!(s.value_at_phase(0.3), 3.5e8);
        assert_relative_eq!(
            s.value_at_phase(0.98),
            2.0e8 + 1.5e8 * 0.5 * (1.0 + (PI * -0.2).dsin())
        );
    }

    #[test]
    fn invalid() {
        assert!(ToothPairStiffness::new(1.0, 1.0, 2.0, 0.0).is_err());
        assert!(ToothPairStiffness::new(2.1, 1.0, 2.0, 0.0).is_err());
        assert!(ToothPairStiffness::new(f64::NAN, 1.0, 2.0, 0.0).is_err());
        assert!(ToothPairStiffness::new(1.5, -1.0, 2.0, 0.0).is_err());
        assert!(ToothPairStiffness::new(1.5, 1.0, 2.0, 0.6).is_err());
        let e = ToothPairStiffness::new(2.3, 1.0, 2.0, 0.0).unwrap_err();
        assert_eq!(e.to_string(), "contact ratio must be in (1, 2], got 2.3");
        let b = ToothPairStiffness::new(1.6, 1.0, 2.0, 0.0).unwrap();
        assert!(NfgToothPairStiffness::new(b, 0, 0.2, 0.0, 0.0).is_err());
        assert!(NfgToothPairStiffness::new(b, 10, 1.0, 0.0, 0.0).is_err());
        // contact ratio would leave (1, 2]
        assert!(NfgToothPairStiffness::new(b, 10, 0.5, 3.0, 0.0).is_err());
        assert!(NfgToothPairStiffness::new(b, 10, 0.2, 0.5, f64::NAN).is_err());
    }

    #[test]
    fn nfg_reduces_to_circular_without_eccentricity() {
        let b = ToothPairStiffness::new(1.6, 1.0, 2.0, 0.05).unwrap();
        let n = NfgToothPairStiffness::new(b, 7, 0.0, 0.5, 0.5).unwrap();
        let rev = n.sample_revolution(32);
        assert_eq!(rev, b.sample(32, 7));
        for i in 0..100 {
            let u = 0.0731 * i as f64;
            assert_relative_eq!(
                n.value_at_phase(u),
                b.value_at_phase(u),
                max_relative = 1e-15
            );
        }
    }
}
