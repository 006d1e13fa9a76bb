//! The mesh-stiffness law trait: what a model needs from a stiffness curve.

use crate::{FourierStiffness, SingleHarmonicStiffness};

/// A mesh stiffness `k(t)` that a model evaluates in every right-hand side / collocation point.
///
/// Implemented by [`FourierStiffness`] (Liu Eq. 6), [`SingleHarmonicStiffness`] (Liu Eq. 19,
/// Yu Eq. 17) and `f64` (a constant stiffness, e.g. the fractal contact stiffness of Yu Eq. 18
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
        assert_eq!(s.stiffness(0.3).to_bits(), s.eval(0.3).to_bits());
    }
}
