//! The backlash-law trait: what a model needs from a backlash curve.
//!
//! A backlash law gives the half gap `b` of the dead zone (Liu Eq. 12, Yu Eq. 14) at time `t`
//! and centre displacement `c = (x_p, y_p, x_g, y_g)`, with its derivatives, and says how the
//! corners of the dead zone are treated:
//!
//! ```text
//! b = b(t, c),   ∂b/∂t,   ∂b/∂c;      F = f(x; b(t, c))  (exact or smoothed dead zone)
//! ∂F/∂x = f_x,   ∂F/∂t = f_b ∂b/∂t,   ∂F/∂c = f_b ∂b/∂c
//! ```
//!
//! | law | half gap | type |
//! | --- | --- | --- |
//! | constant | `b` | `f64` |
//! | W-M fractal constant part (Yu Eq. 5) | `b_s = b_0 − b_p − b_g` | [`ConstantPart`] |
//! | Chen's fractal (Yu Eq. 3) | `b_s + a_z z(ω t)` | [`ChenBacklash`] |
//! | base-radius modulated (Liu Eq. 11–12) | `b/(1 + β cos(ω t))` | [`RadiusModulatedBacklash`] |
//! | dynamic from centre motion (Yu Eq. 6–11) | `b_s + b_dy(c)` | [`DynamicBacklash`] |
//! | smoothed corners | any of the above | [`Smoothed`] |
//!
//! [`Backlash`] is the serde form: one enum over all of them, itself a law.

use crate::deadzone::{DeadZone, Regularisation};
use crate::dynamic::{CentreDisplacement, DynamicBacklash};
use crate::error::{Error, finite, non_negative};
use crate::fractal::{ChenFractal, ConstantPart};
use math::DetMath;

/// A half gap and its derivatives at one instant and centre displacement.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct GapEval {
    /// Half gap `b` (units of the displacement). May be negative (interference) for the
    /// signed dynamic forms; the dead zone treats a negative gap as 0.
    pub b: f64,
    /// `∂b/∂t`.
    pub db_dt: f64,
    /// `∂b/∂(x_p, y_p, x_g, y_g)`.
    pub db_dc: [f64; 4],
}

impl GapEval {
    /// A constant half gap `b`.
    #[inline]
    pub fn constant(b: f64) -> Self {
        Self {
            b,
            ..Self::default()
        }
    }
}

/// The dead-zone force of a law at one point and its derivatives.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ContactEval {
    /// `f(x; b)`.
    pub f: f64,
    /// `∂f/∂x`.
    pub df_dx: f64,
    /// `∂f/∂t` through the gap, `f_b ∂b/∂t`.
    pub df_dt: f64,
    /// `∂f/∂c` through the gap, `f_b ∂b/∂c`.
    pub df_dc: [f64; 4],
    /// The half gap used.
    pub gap: GapEval,
}

/// A backlash law: the half gap `b(t, c)` of the dead zone with its derivatives, and the
/// dead-zone corner treatment. Implemented by every law of this crate (see the module docs);
/// a model holds any `L: BacklashLaw` and never re-implements the gap.
///
/// `t` is the model's time (its units are the law's: a dimensionless model builds its laws in
/// dimensionless time); `c` the centre displacements in the units of the gap (ignored by
/// laws for which [`BacklashLaw::depends_on_centres`] is `false`; pass
/// `CentreDisplacement::default()`).
pub trait BacklashLaw {
    /// `b(t, c)`, `∂b/∂t`, `∂b/∂c`. Errors: non-finite input, or an option that rejects the
    /// point (e.g. [`RadicandPolicy::Reject`](crate::RadicandPolicy::Reject)).
    fn half_gap(&self, t: f64, c: &CentreDisplacement) -> Result<GapEval, Error>;

    /// `true` if the gap depends on the centre displacements (a state-dependent gap).
    fn depends_on_centres(&self) -> bool {
        false
    }

    /// `true` if the gap depends on time (an engine may then tabulate it per time grid).
    fn depends_on_time(&self) -> bool {
        false
    }

    /// How the dead-zone corners are treated (exact by default).
    fn dead_zone(&self) -> DeadZone {
        DeadZone::EXACT
    }

    /// `f(x; b(t, c))` with the chain rule through the gap.
    #[inline]
    fn contact(&self, t: f64, x: f64, c: &CentreDisplacement) -> Result<ContactEval, Error> {
        let gap = self.half_gap(t, c)?;
        let dz = self.dead_zone().eval(x, gap.b);
        Ok(ContactEval {
            f: dz.f,
            df_dx: dz.df_dx,
            df_dt: dz.df_db * gap.db_dt,
            df_dc: gap.db_dc.map(|g| dz.df_db * g),
            gap,
        })
    }
}

fn finite_time(t: f64) -> Result<f64, Error> {
    finite("t", t)
}

impl BacklashLaw for f64 {
    #[inline]
    fn half_gap(&self, _t: f64, _c: &CentreDisplacement) -> Result<GapEval, Error> {
        Ok(GapEval::constant(*self))
    }
}

/// Yu Eq. (5): the constant part `b_s = b_0 − b_p − b_g` from the W-M surfaces (computed once
/// by [`ConstantBacklashParams::constant_part`](crate::ConstantBacklashParams::constant_part)).
impl BacklashLaw for ConstantPart {
    #[inline]
    fn half_gap(&self, _t: f64, _c: &CentreDisplacement) -> Result<GapEval, Error> {
        Ok(GapEval::constant(self.b_s))
    }
}

impl BacklashLaw for DynamicBacklash {
    #[inline]
    fn half_gap(&self, _t: f64, c: &CentreDisplacement) -> Result<GapEval, Error> {
        let e = self.eval(c)?;
        Ok(GapEval {
            b: e.b,
            db_dt: 0.0,
            db_dc: e.grad,
        })
    }

    fn depends_on_centres(&self) -> bool {
        true
    }
}

/// Chen's time-varying fractal backlash (Yu Sec. 4.4, Eq. 3): `b(t) = b_s + a_z z(ω t)`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ChenBacklash {
    /// Constant part `b_s`.
    pub b_s: f64,
    /// Amplitude `a_z` (units of `b_s`), ≥ 0.
    pub amplitude: f64,
    /// Frequency `ω` of the argument of `z` (per unit of the law's time), > 0.
    pub omega: f64,
    /// Chen's `z` (Eq. 3).
    pub fractal: ChenFractal,
}

impl ChenBacklash {
    /// Checked constructor: `b_s` finite, `a_z ≥ 0`, `ω` finite; `fractal` re-checked.
    pub fn new(b_s: f64, amplitude: f64, omega: f64, fractal: ChenFractal) -> Result<Self, Error> {
        finite("b_s", b_s)?;
        non_negative("a_z", amplitude)?;
        finite("omega", omega)?;
        let fractal = ChenFractal::new(fractal.d, fractal.gamma, fractal.n_terms)?;
        Ok(Self {
            b_s,
            amplitude,
            omega,
            fractal,
        })
    }
}

impl BacklashLaw for ChenBacklash {
    #[inline]
    fn half_gap(&self, t: f64, _c: &CentreDisplacement) -> Result<GapEval, Error> {
        let t = finite_time(t)?;
        let (z, dz) = self.fractal.value_and_derivative(self.omega * t);
        Ok(GapEval {
            b: self.b_s + self.amplitude * z,
            db_dt: self.amplitude * self.omega * dz,
            db_dc: [0.0; 4],
        })
    }

    fn depends_on_time(&self) -> bool {
        true
    }
}

/// A half gap measured on a base radius that varies as `r(t) = L (1 + β cos(ω t))` and
/// expressed in units of `L`: `b̄(t) = b/(1 + β cos(ω t))` (Liu Eq. 8, 11–12, `b̄ = b/r_b2`).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct RadiusModulatedBacklash {
    /// `b` over the mean radius (`b/L`), ≥ 0.
    pub b: f64,
    /// Radius change rate `β`, in `[0, 1)`.
    pub beta: f64,
    /// `ω` (per unit of the law's time).
    pub omega: f64,
}

impl RadiusModulatedBacklash {
    /// Checked constructor.
    pub fn new(b: f64, beta: f64, omega: f64) -> Result<Self, Error> {
        non_negative("b", b)?;
        if !(0.0..1.0).contains(&beta) {
            return Err(Error::InvalidParameter {
                name: "beta",
                bound: "in [0, 1)",
                value: beta,
            });
        }
        finite("omega", omega)?;
        Ok(Self { b, beta, omega })
    }

    /// `r(t)/L = 1 + β cos(ω t)`.
    #[inline]
    pub fn radius_ratio(&self, t: f64) -> f64 {
        1.0 + self.beta * (self.omega * t).dcos()
    }

    /// `b̄ = b/(1 + β c)` from `c = cos(ω t)`: the half gap of
    /// [`half_gap`](BacklashLaw::half_gap) for a caller that has the cosine already (from an
    /// addition theorem or a table). No check of `c`: NaN in, NaN out.
    #[inline]
    pub fn half_gap_at_phase(&self, c: f64) -> f64 {
        self.b / (1.0 + self.beta * c)
    }
}

impl BacklashLaw for RadiusModulatedBacklash {
    #[inline]
    fn half_gap(&self, t: f64, _c: &CentreDisplacement) -> Result<GapEval, Error> {
        let t = finite_time(t)?;
        let (s, c) = (self.omega * t).dsin_cos();
        let r = 1.0 + self.beta * c;
        let b = self.half_gap_at_phase(c);
        Ok(GapEval {
            b,
            db_dt: b / r * self.beta * self.omega * s,
            db_dc: [0.0; 4],
        })
    }

    fn depends_on_time(&self) -> bool {
        self.beta != 0.0
    }
}

/// Any law with the dead-zone corners smoothed ([`Regularisation::Smooth`], error ≤ ε/2):
/// for Newton iterations in harmonic balance.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Smoothed<L> {
    /// The half-gap law.
    pub law: L,
    /// The (smoothed) dead zone.
    pub dead_zone: DeadZone,
}

impl<L> Smoothed<L> {
    /// `law` with smoothing width `eps > 0` (units of the displacement).
    pub fn new(law: L, eps: f64) -> Result<Self, Error> {
        Ok(Self {
            law,
            dead_zone: DeadZone::new(Regularisation::Smooth { eps })?,
        })
    }
}

impl<L: BacklashLaw> BacklashLaw for Smoothed<L> {
    #[inline]
    fn half_gap(&self, t: f64, c: &CentreDisplacement) -> Result<GapEval, Error> {
        self.law.half_gap(t, c)
    }
    fn depends_on_centres(&self) -> bool {
        self.law.depends_on_centres()
    }
    fn depends_on_time(&self) -> bool {
        self.law.depends_on_time()
    }
    fn dead_zone(&self) -> DeadZone {
        self.dead_zone
    }
}

/// A law behind a reference or a box is the same law.
macro_rules! forward_law {
    ($($ty:ty),*) => {$(
        impl<L: BacklashLaw + ?Sized> BacklashLaw for $ty {
            #[inline]
            fn half_gap(&self, t: f64, c: &CentreDisplacement) -> Result<GapEval, Error> {
                (**self).half_gap(t, c)
            }
            fn depends_on_centres(&self) -> bool {
                (**self).depends_on_centres()
            }
            fn depends_on_time(&self) -> bool {
                (**self).depends_on_time()
            }
            fn dead_zone(&self) -> DeadZone {
                (**self).dead_zone()
            }
        }
    )*};
}
forward_law!(&L, Box<L>);

/// Every law of this crate in one enum: the serde form of a backlash law (e.g. in a study
/// file), itself a [`BacklashLaw`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(tag = "kind", rename_all = "snake_case")
)]
#[non_exhaustive]
pub enum Backlash {
    /// A constant half gap.
    Constant {
        /// `b`.
        b: f64,
    },
    /// The W-M fractal constant part (Yu Eq. 5), computed beforehand.
    Fractal(ConstantPart),
    /// Chen's time-varying fractal backlash.
    Chen(ChenBacklash),
    /// The base-radius modulated gap of Liu Eq. (11)–(12).
    RadiusModulated(RadiusModulatedBacklash),
    /// Dynamic backlash from the centre motion (Yu Eq. 6–11), every option of
    /// [`DynamicBacklash`].
    Dynamic(DynamicBacklash),
}

impl Backlash {
    /// Check the fields (they are public, e.g. from serde) with the laws' checked
    /// constructors; the error names the field and the bound.
    pub fn validate(&self) -> Result<(), Error> {
        match self {
            Backlash::Constant { b } => finite("b", *b).map(|_| ()),
            Backlash::Fractal(p) => finite("b_s", p.b_s).map(|_| ()),
            Backlash::Chen(l) => {
                ChenBacklash::new(l.b_s, l.amplitude, l.omega, l.fractal).map(|_| ())
            }
            Backlash::RadiusModulated(l) => {
                RadiusModulatedBacklash::new(l.b, l.beta, l.omega).map(|_| ())
            }
            Backlash::Dynamic(l) => {
                DynamicBacklash::new(l.geometry, l.b_s, l.form, l.law, l.policy).map(|_| ())
            }
        }
    }

    fn as_law(&self) -> &dyn BacklashLaw {
        match self {
            Backlash::Constant { b } => b,
            Backlash::Fractal(l) => l,
            Backlash::Chen(l) => l,
            Backlash::RadiusModulated(l) => l,
            Backlash::Dynamic(l) => l,
        }
    }
}

impl BacklashLaw for Backlash {
    #[inline]
    fn half_gap(&self, t: f64, c: &CentreDisplacement) -> Result<GapEval, Error> {
        match self {
            Backlash::Constant { b } => Ok(GapEval::constant(*b)),
            Backlash::Fractal(l) => l.half_gap(t, c),
            Backlash::Chen(l) => l.half_gap(t, c),
            Backlash::RadiusModulated(l) => l.half_gap(t, c),
            Backlash::Dynamic(l) => l.half_gap(t, c),
        }
    }
    fn depends_on_centres(&self) -> bool {
        self.as_law().depends_on_centres()
    }
    fn depends_on_time(&self) -> bool {
        self.as_law().depends_on_time()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{PairGeometry, dead_zone};

    fn laws() -> Vec<Backlash> {
        let g = PairGeometry::new(0.094, 0.094, 20f64.to_radians()).unwrap();
        vec![
            Backlash::Constant { b: 1e-4 },
            Backlash::Fractal(ConstantPart {
                b_s: 2e-5,
                b_p: 5e-6,
                b_g: 5e-6,
                error: 0.0,
            }),
            Backlash::Chen(
                ChenBacklash::new(1e-4, 5e-6, 3.0, ChenFractal::new(1.5, 1.5, 12).unwrap())
                    .unwrap(),
            ),
            Backlash::RadiusModulated(RadiusModulatedBacklash::new(1e-3, 0.38, 0.7).unwrap()),
            Backlash::Dynamic(
                DynamicBacklash::involute(g, 1e-4)
                    .unwrap()
                    .with_centre_distance(crate::CentreDistanceForm::Consistent),
            ),
        ]
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let c0 = [3e-6, -2e-6, -1e-6, 4e-6];
        for law in laws() {
            for t in [0.0, 0.4, 2.9] {
                let c = CentreDisplacement::from_array(c0);
                let e = law.half_gap(t, &c).unwrap();
                let h = 1e-6;
                let fd = (law.half_gap(t + h, &c).unwrap().b - law.half_gap(t - h, &c).unwrap().b)
                    / (2.0 * h);
                assert!(
                    (fd - e.db_dt).abs() <= 1e-6 * (1e-4 + e.db_dt.abs()),
                    "{law:?}: {fd} vs {}",
                    e.db_dt
                );
                for i in 0..4 {
                    let h = 1e-9;
                    let (mut p, mut m) = (c0, c0);
                    p[i] += h;
                    m[i] -= h;
                    let bp = law.half_gap(t, &CentreDisplacement::from_array(p)).unwrap();
                    let bm = law.half_gap(t, &CentreDisplacement::from_array(m)).unwrap();
                    let fd = (bp.b - bm.b) / (2.0 * h);
                    assert!((fd - e.db_dc[i]).abs() < 1e-6, "{law:?} {i}");
                }
                assert_eq!(law.depends_on_centres(), e.db_dc.iter().any(|g| *g != 0.0));
            }
        }
    }

    #[test]
    fn contact_chains_the_gap_into_the_dead_zone() {
        let c = CentreDisplacement::new(1e-6, 0.0, -2e-6, 1e-6);
        for law in laws() {
            let x = 5e-3;
            let e = law.contact(0.3, x, &c).unwrap();
            assert_eq!(e.f.to_bits(), dead_zone(x, e.gap.b).to_bits());
            assert_eq!(e.df_dx.to_bits(), 1f64.to_bits());
            assert_eq!(e.df_dt.to_bits(), (-e.gap.db_dt).to_bits());
            let inside = law.contact(0.3, 0.0, &c).unwrap();
            assert_eq!(inside.f.to_bits(), 0f64.to_bits());
        }
        let s = Smoothed::new(1e-4, 1e-6).unwrap();
        let e = s
            .contact(0.0, 1e-4, &CentreDisplacement::default())
            .unwrap();
        assert!(e.f > 0.0 && e.f <= 0.5e-6 + 1e-18);
    }

    #[test]
    fn bad_times_are_errors() {
        for law in laws() {
            let r = law.half_gap(f64::NAN, &CentreDisplacement::new(f64::NAN, 0.0, 0.0, 0.0));
            if law.depends_on_time() || law.depends_on_centres() {
                assert!(r.is_err(), "{law:?}");
            }
        }
        assert!(RadiusModulatedBacklash::new(1.0, 1.0, 1.0).is_err());
        assert!(ChenBacklash::new(1.0, -1.0, 1.0, ChenFractal::new(1.5, 1.5, 3).unwrap()).is_err());
    }
}
