//! Fractal pieces of Yu 2021: W-M profile mean height (Eq. 2, 4), Chen's fractal backlash
//! function (Eq. 3) and the fractal contact stiffness (Eq. 18).
//!
//! The W-M mean height and Chen's `z` come from the `backlash` leaf, Eq. (18) from the
//! `mesh-stiffness` leaf (with the printed or the sign-consistent form selected explicitly).

use serde::{Deserialize, Serialize};

use crate::Error;

use crate::error::check_pos;

pub use mesh_stiffness::{CurvatureCoefficient, FractalContact, FractalForm};

/// A rough surface described by the modified Weierstrass–Mandelbrot function, Eq. (2).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FractalSurface {
    /// Fractal dimension `D` (–), in (1, 2).
    pub dimension: f64,
    /// Fractal roughness `G` (m).
    pub roughness: f64,
    /// Frequency density factor `λ` (–), 1.5 for most surfaces (Sec. 2.1).
    pub lambda: f64,
    /// Largest asperity base diameter `l_a` (m): `λ^{k_min} = 1/l_a`.
    pub l_max: f64,
    /// Smallest asperity base diameter `l_s` (m): truncates the series at `λ^{k_max} = 1/l_s`.
    pub l_min: f64,
    /// Sampling length `L` (m) of Eq. (4) (length of the contact region).
    pub length: f64,
}

impl FractalSurface {
    fn validate(&self) -> Result<(), Error> {
        let d = self.dimension;
        if !(d > 1.0 && d < 2.0) {
            return Err(Error::invalid("yu2021.surface.dimension", "in (1, 2)", d));
        }
        check_pos("yu2021.surface.roughness", self.roughness)?;
        if !(self.lambda > 1.0 && self.lambda.is_finite()) {
            return Err(Error::invalid("yu2021.surface.lambda", "> 1", self.lambda));
        }
        check_pos("yu2021.surface.l_max", self.l_max)?;
        check_pos("yu2021.surface.l_min", self.l_min)?;
        if self.l_min >= self.l_max {
            return Err(Error::invalid(
                "yu2021.surface.l_min",
                "< l_max",
                self.l_min,
            ));
        }
        check_pos("yu2021.surface.length", self.length)?;
        Ok(())
    }
}

/// Effective mean asperity height `b_i` (m) of Eq. (4): `(1/L) ∫_0^L |z(l)| dl` with `z` of
/// Eq. (2), `k` from `λ^{k_min} ≈ 1/l_a` to `λ^{k_max} ≤ 1/l_s`. Computed by the `backlash`
/// leaf ([`backlash::mean_asperity_height`], midpoint rule, 8 points per shortest wavelength).
pub fn fractal_mean_height(s: &FractalSurface) -> Result<f64, Error> {
    s.validate()?;
    let leaf = |source: backlash::Error| Error::Backlash {
        context: "yu2021 fractal backlash",
        source,
    };
    let surface = backlash::SurfaceFractal::new(s.dimension, s.roughness).map_err(leaf)?;
    let profile = backlash::WmProfile::new(surface, s.lambda, s.l_max, s.l_min).map_err(leaf)?;
    let h = backlash::mean_asperity_height(&profile, s.length, backlash::Quadrature::default())
        .map_err(leaf)?;
    Ok(h.value)
}

/// Chen's fractal backlash function, Eq. (3): `z(t) = Σ_{k=0}^{K-1} λ^{(D-2)k} sin(λ^k t)`,
/// truncated at `K = 12` terms with `λ = 1.5` (the `backlash` leaf's [`backlash::ChenFractal`]).
pub fn chen_z(dimension: f64, t: f64) -> f64 {
    chen_fractal(dimension).value(t)
}

/// Chen's `z` of Eq. (3) as the model truncates it: `λ = 1.5`, 12 terms.
pub(crate) fn chen_fractal(dimension: f64) -> backlash::ChenFractal {
    backlash::ChenFractal {
        d: dimension,
        gamma: 1.5,
        n_terms: 12,
    }
}

/// Fractal contact stiffness `k_c` of Eq. (18) (N/m as Yu uses it), from the
/// `mesh-stiffness` leaf ([`mesh_stiffness::FractalContact::stiffness`]) with the reading
/// selected explicitly: `form` = [`FractalForm::Printed`] is Eq. (18) exactly as printed
/// (**negative** for every `1 < D < 2`: the factor `1/((D−D²+1)(1−D))` and the bracket
/// `l_a^{D−D²+1} − l_s^{D−D²+1}` have opposite signs), [`FractalForm::Consistent`] its
/// sign-consistent form (positive). `λ_c` follows [`FractalContact::curvature_coefficient`]
/// (its printed formula has the exponent `2/R` with a dimensional `R`). Reading R-YU-EQ18.
///
/// The Yu model takes the mean mesh stiffness `k_am` from its parameter sets; this function is
/// offered for studies of Eq. (18).
pub fn fractal_contact_stiffness(c: &FractalContact, form: FractalForm) -> Result<f64, Error> {
    c.stiffness(form).map_err(|source| Error::Stiffness {
        context: "yu2021 fractal contact stiffness",
        source,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use math::DetMath;

    fn surface(d: f64, g: f64) -> FractalSurface {
        FractalSurface {
            dimension: d,
            roughness: g,
            lambda: 1.5,
            l_max: 1e-3,
            l_min: 1e-5,
            length: 1e-3,
        }
    }

    #[test]
    fn mean_height_decreases_with_d_and_increases_with_g() {
        let h12 = fractal_mean_height(&surface(1.2, 1e-11)).unwrap();
        let h14 = fractal_mean_height(&surface(1.4, 1e-11)).unwrap();
        let h16 = fractal_mean_height(&surface(1.6, 1e-11)).unwrap();
        assert!(h12 > h14 && h14 > h16, "{h12} {h14} {h16}");
        let hg = fractal_mean_height(&surface(1.4, 1e-10)).unwrap();
        assert!(hg > h14);
    }

    #[test]
    fn mean_height_rejects_bad_d() {
        let e = fractal_mean_height(&surface(2.3, 1e-11)).unwrap_err();
        assert!(e.to_string().contains("dimension"), "{e}");
    }

    #[test]
    fn eq18_as_printed_is_negative_and_consistent_is_its_magnitude() {
        for d in [1.2, 1.4, 1.8] {
            let c = FractalContact {
                fractal_dimension: d,
                fractal_roughness: 1e-11,
                elastic_modulus: 2.06e11,
                hardness: 6e9,
                poisson_ratio: 0.3,
                largest_contact_area: 1e-8,
                largest_asperity: 1e-4,
                smallest_asperity: 1e-7,
                curvature_coefficient: CurvatureCoefficient::Value(1.0),
                ..crate::yu2021::fractal_contact_default()
            };
            let printed = fractal_contact_stiffness(&c, FractalForm::Printed).unwrap();
            let consistent = fractal_contact_stiffness(&c, FractalForm::Consistent).unwrap();
            assert!(printed < 0.0, "D = {d}");
            assert!(
                (printed + consistent).abs() <= 1e-12 * consistent,
                "D = {d}"
            );
            // the closed form of the printed Eq. (18), evaluated independently
            let e3 = d - d * d + 1.0;
            let (phi, q): (f64, f64) = (6e9 / 2.06e11, 0.454 + 0.41 * 0.3);
            let want = 2f64.dpowf(d) * d * 1e-11f64.dpowf(1.0 + d * d - 2.0 * d) / (e3 * (1.0 - d))
                * 2.06e11
                * 1e-8f64.dpowf(d / 2.0)
                / (std::f64::consts::PI.dpowf((2.0 - d) / 2.0) * (phi * q).dpowf(d - 1.0))
                * (1e-4f64.dpowf(e3) - 1e-7f64.dpowf(e3));
            assert!(
                (printed - want).abs() <= 1e-9 * want.abs(),
                "D = {d}: {printed} vs {want}"
            );
        }
    }

    #[test]
    fn chen_z_is_odd() {
        assert!((chen_z(1.5, 0.7) + chen_z(1.5, -0.7)).abs() < 1e-12);
    }
}
