//! The mesh-stiffness law trait: what a model needs from a stiffness curve.

use std::f64::consts::TAU;

use crate::{
    FourierStiffness, NfgToothPairStiffness, Result, SingleHarmonicStiffness, ToothPairStiffness,
};

/// A mesh stiffness `k(t)` that a model evaluates in every right-hand side / collocation point.
///
/// Implemented by [`FourierStiffness`] (Liu Eq. 6), [`SingleHarmonicStiffness`] (Liu Eq. 19,
/// Yu Eq. 17), the tooth-pair curves in time ([`MeshTimed`] of [`ToothPairStiffness`] and of
/// [`NfgToothPairStiffness`], Liu Sect. 3.1 and Eq. 18), [`Stiffness`] (the serde form) and
/// `f64` (a constant stiffness, e.g. the fractal contact stiffness of Yu Eq. 18
/// from [`FractalContact::stiffness`](crate::FractalContact::stiffness) or a Hertz value). A
/// model holds any `S: StiffnessLaw` and never re-implements the curve.
pub trait StiffnessLaw {
    /// `(k(t), dk/dt)`.
    fn stiffness_and_rate(&self, t: f64) -> (f64, f64);
    /// `k(t)`.
    #[inline]
    fn stiffness(&self, t: f64) -> f64 {
        self.stiffness_and_rate(t).0
    }
}

impl StiffnessLaw for f64 {
    #[inline]
    fn stiffness_and_rate(&self, _t: f64) -> (f64, f64) {
        (*self, 0.0)
    }
}

impl StiffnessLaw for SingleHarmonicStiffness {
    #[inline]
    fn stiffness_and_rate(&self, t: f64) -> (f64, f64) {
        self.eval_with_derivative(t)
    }
}

impl StiffnessLaw for FourierStiffness {
    #[inline]
    fn stiffness_and_rate(&self, t: f64) -> (f64, f64) {
        self.eval_with_derivative(t)
    }
}

/// A per-mesh-period curve (phase `u` in mesh periods) run at mesh frequency `ω_e`:
/// `k(t) = curve(ω_e t/2π)`, `dk/dt = (ω_e/2π) dk/du`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct MeshTimed<C> {
    /// The curve over mesh phase.
    pub curve: C,
    /// Mesh angular frequency `ω_e` (per unit of the law's time).
    pub omega_e: f64,
}

/// A curve over the mesh phase `u` (mesh periods) with its slope.
pub trait PhaseCurve {
    /// `(k(u), dk/du)`.
    fn at_phase(&self, u: f64) -> (f64, f64);
}

impl PhaseCurve for ToothPairStiffness {
    #[inline]
    fn at_phase(&self, u: f64) -> (f64, f64) {
        (self.value_at_phase(u), self.rate_at_phase(u))
    }
}

impl PhaseCurve for NfgToothPairStiffness {
    #[inline]
    fn at_phase(&self, u: f64) -> (f64, f64) {
        (self.value_at_phase(u), self.rate_at_phase(u))
    }
}

impl<C: PhaseCurve> StiffnessLaw for MeshTimed<C> {
    #[inline]
    fn stiffness_and_rate(&self, t: f64) -> (f64, f64) {
        let (k, dk) = self.curve.at_phase(self.omega_e * t / TAU);
        (k, self.omega_e / TAU * dk)
    }
}

impl<S: StiffnessLaw + ?Sized> StiffnessLaw for &S {
    #[inline]
    fn stiffness_and_rate(&self, t: f64) -> (f64, f64) {
        (**self).stiffness_and_rate(t)
    }
}

impl<S: StiffnessLaw + ?Sized> StiffnessLaw for Box<S> {
    #[inline]
    fn stiffness_and_rate(&self, t: f64) -> (f64, f64) {
        (**self).stiffness_and_rate(t)
    }
}

/// Every stiffness law of this crate in one enum: the serde form of a law (e.g. in a study
/// file), itself a [`StiffnessLaw`]. The fractal contact stiffness of Yu Eq. (18)
/// ([`FractalContact::stiffness`](crate::FractalContact::stiffness)) is a constant.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(tag = "kind", rename_all = "snake_case")
)]
#[non_exhaustive]
pub enum Stiffness {
    /// A constant stiffness (e.g. Hertz, or Yu Eq. 18).
    Constant {
        /// `k`.
        k: f64,
    },
    /// Liu Eq. (19) / Yu Eq. (17).
    SingleHarmonic(SingleHarmonicStiffness),
    /// Liu Eq. (6).
    Fourier(FourierStiffness),
    /// The single/double tooth-pair wave in time.
    ToothPair(MeshTimed<ToothPairStiffness>),
    /// The NFG tooth-pair wave in time.
    Nfg(MeshTimed<NfgToothPairStiffness>),
}

impl Stiffness {
    /// Check the fields (they are public, e.g. from serde) with the laws' checked
    /// constructors; the error names the field and the bound.
    pub fn validate(&self) -> Result<()> {
        match self {
            Stiffness::Constant { k } => crate::error::finite("k", *k).map(|_| ()),
            Stiffness::SingleHarmonic(l) => {
                SingleHarmonicStiffness::new(l.k0, l.k_r, l.omega_e, l.phi_m, l.waveform)
                    .map(|_| ())
            }
            // validated by its serde form (`try_from`) and its constructor
            Stiffness::Fourier(_) => Ok(()),
            Stiffness::ToothPair(l) => {
                let c = &l.curve;
                ToothPairStiffness::new(c.contact_ratio, c.k_single, c.k_double, c.smoothing)
                    .map(|_| ())
            }
            Stiffness::Nfg(l) => {
                let c = &l.curve;
                NfgToothPairStiffness::new(
                    c.base,
                    c.teeth,
                    c.eccentricity,
                    c.contact_ratio_sensitivity,
                    c.stiffness_sensitivity,
                )
                .map(|_| ())
            }
        }
    }

    /// The same law at mesh frequency `omega_e` (> 0, finite): every law keeps its shape over
    /// the mesh phase; a constant is unchanged.
    pub fn at_mesh_frequency(&self, omega_e: f64) -> Result<Self> {
        crate::error::positive("omega_e", omega_e)?;
        Ok(match self {
            Stiffness::Constant { k } => Stiffness::Constant { k: *k },
            Stiffness::SingleHarmonic(l) => {
                Stiffness::SingleHarmonic(SingleHarmonicStiffness { omega_e, ..*l })
            }
            Stiffness::Fourier(l) => Stiffness::Fourier(FourierStiffness::new(
                l.k0(),
                omega_e,
                l.cos().to_vec(),
                l.sin().to_vec(),
            )?),
            Stiffness::ToothPair(l) => Stiffness::ToothPair(MeshTimed { omega_e, ..*l }),
            Stiffness::Nfg(l) => Stiffness::Nfg(MeshTimed { omega_e, ..*l }),
        })
    }
}

impl StiffnessLaw for Stiffness {
    #[inline]
    fn stiffness_and_rate(&self, t: f64) -> (f64, f64) {
        match self {
            Stiffness::Constant { k } => (*k, 0.0),
            Stiffness::SingleHarmonic(l) => l.stiffness_and_rate(t),
            Stiffness::Fourier(l) => l.stiffness_and_rate(t),
            Stiffness::ToothPair(l) => l.stiffness_and_rate(t),
            Stiffness::Nfg(l) => l.stiffness_and_rate(t),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Waveform;

    fn check_rate<S: StiffnessLaw>(law: &S, t: f64) {
        let h = 1e-6;
        let fd = (law.stiffness(t + h) - law.stiffness(t - h)) / (2.0 * h);
        let (_, rate) = law.stiffness_and_rate(t);
        assert!(
            (fd - rate).abs() <= 1e-6 * (1.0 + rate.abs()),
            "{fd} vs {rate}"
        );
    }

    #[test]
    fn rates_match_finite_differences() {
        let s = SingleHarmonicStiffness::new(1.0, 0.3, 2.0, 0.4, Waveform::Sine).unwrap();
        let c = SingleHarmonicStiffness::new(1.0, 0.3, 2.0, 0.4, Waveform::Cosine).unwrap();
        let f = FourierStiffness::new(1.0, 1.5, vec![0.2, -0.05], vec![0.1, 0.03]).unwrap();
        for t in [0.0, 0.3, 1.7] {
            check_rate(&s, t);
            check_rate(&c, t);
            check_rate(&f, t);
            check_rate(&2.5, t);
        }
        assert_eq!(2.5.stiffness(3.0).to_bits(), 2.5f64.to_bits());
        // tooth-pair curves: value is the curve at the mesh phase, rate off the jumps
        let tp = ToothPairStiffness::new(1.6, 2.0, 3.5, 0.2).unwrap();
        let timed = MeshTimed {
            curve: tp,
            omega_e: 3.0,
        };
        let nfg = MeshTimed {
            curve: NfgToothPairStiffness::new(tp, 7, 0.2, 0.3, 0.4).unwrap(),
            omega_e: 3.0,
        };
        for t in [0.05, 0.3, 1.1, 1.7] {
            check_rate(&timed, t);
            check_rate(&nfg, t);
            let u = 3.0 * t / TAU;
            assert_eq!(timed.stiffness(t).to_bits(), tp.value_at_phase(u).to_bits());
        }
        for (law, omega) in [
            (Stiffness::Constant { k: 2.0 }, 1.0),
            (Stiffness::SingleHarmonic(s), 2.0),
            (Stiffness::Fourier(f.clone()), 1.5),
            (Stiffness::ToothPair(timed), 3.0),
            (Stiffness::Nfg(nfg), 3.0),
        ] {
            let moved = law.at_mesh_frequency(2.0 * omega).unwrap();
            // twice the frequency: the value at t is the old law's at 2t
            for t in [0.05, 0.3] {
                assert!((moved.stiffness(t) - law.stiffness(2.0 * t)).abs() < 1e-12);
            }
            check_rate(&law, 0.3);
        }
        assert_eq!(s.stiffness(0.3).to_bits(), s.eval(0.3).to_bits());
    }
}
