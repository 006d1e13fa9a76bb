//! Mean mesh stiffness `k_am` from the fractal contact stiffness of Eq. (18), so that the
//! fractal dimension `D` and roughness `G` act on the stiffness of the dynamic model (Sec. 3:
//! "taking `k_c` as `k_am`, the meshing stiffness can be obtained by Eq. (17)").
//!
//! Eq. (18) is evaluated by the `mesh-stiffness` leaf ([`FractalContact::stiffness`],
//! [`FractalForm::Consistent`]: the printed expression is negative for every `1 < D < 2`,
//! reading R-YU-EQ18). Its number has the unit of a force (N), not N/m (length exponent 2 with a
//! dimensionless `λ_c`; `docs/readings/mesh-stiffness.md`), so it cannot be used as `k_am` as it
//! stands: the level is set by one reference stiffness at a reference surface, and Eq. (18)
//! supplies the dependence on `D` and `G`:
//!
//! ```text
//! k_am(D, G) = k_ref · k_c(D, G) / k_c(D_ref, G_ref)
//! ```
//!
//! with `(D_ref, G_ref)` the fractal parameters of [`FractalMeshStiffness::contact`] and every
//! other input of Eq. (18) (E, H, ν, radii, load, `l_a`, `l_s`, `a_L`, `λ_c`) held fixed.

use math::DetMath;
use serde::{Deserialize, Serialize};

use crate::Error;

/// How the largest contact area `a_L` of one asperity in Eq. (18) is obtained (reading
/// R-YU-EQ18-AL). The text calls `a_L` "the largest contact area of a single asperity related
/// to force applied on surface" without a formula.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[non_exhaustive]
pub enum ContactAreaLaw {
    /// `a_L` = [`FractalContact::largest_contact_area`] as given (the leaf's default
    /// `π l_a²/4`, the base area of the largest asperity), the same for every `D` and `G`.
    #[default]
    Fixed,
    /// `a_L` from the Majumdar–Bhushan load balance at [`FractalContact::load`] for the
    /// surface's `D` and `G` ([`majumdar_bhushan_area`]): the elastic and plastic spot loads
    /// summed over the spot-size distribution equal the mesh load.
    LoadBalance,
}

/// Composite modulus `E* = E/(2(1 − ν²))` (Pa) of two flanks of the same material.
fn composite_modulus(c: &FractalContact) -> f64 {
    c.elastic_modulus / (2.0 * (1.0 - c.poisson_ratio * c.poisson_ratio))
}

/// `ln a_c`: the critical spot area of Majumdar–Bhushan (1991),
/// `a_c = G² (2E*/H)^{2/(D−1)}` (spots larger than `a_c` are elastic, smaller plastic).
fn ln_critical_area(c: &FractalContact) -> f64 {
    let d = c.fractal_dimension;
    2.0 * c.fractal_roughness.dln()
        + 2.0 / (d - 1.0) * (2.0 * composite_modulus(c) / c.hardness).dln()
}

/// Total load `P(a_L)` (N) carried by a fractal contact whose largest spot has area
/// `a_L = exp(ln_al)`, Majumdar & Bhushan (1991), spot-size distribution
/// `n(a) = (D/2) a_L^{D/2} a^{−(D+2)/2}`:
///
/// ```text
/// a_L ≤ a_c:  P = H D/(2−D) a_L                                         (all plastic)
/// a_L > a_c:  P = (4√π/3) E* G^{D−1} (D/2) a_L^{D/2} ∫_{a_c}^{a_L} a^{(1−2D)/2} da
///                 + H D/(2−D) a_L^{D/2} a_c^{(2−D)/2}
/// ```
///
/// (elastic spot load `f_e(a) = (4√π/3) E* G^{D−1} a^{(3−D)/2}`, plastic `H a`). Continuous and
/// increasing in `a_L`.
pub fn majumdar_bhushan_load(c: &FractalContact, ln_al: f64) -> f64 {
    let d = c.fractal_dimension;
    let h = c.hardness;
    let ln_ac = ln_critical_area(c);
    if ln_al <= ln_ac {
        return h * d / (2.0 - d) * ln_al.dexp();
    }
    let m = 0.5 * (3.0 - 2.0 * d);
    // ∫_{a_c}^{a_L} a^{m−1} da = a_c^m (exp(m ln(a_L/a_c)) − 1)/m, → ln(a_L/a_c) as m → 0
    let r = ln_al - ln_ac;
    let integral = if m.abs() < 1e-12 {
        r
    } else {
        (m * ln_ac).dexp() * (m * r).dexp_m1() / m
    };
    let elastic = 4.0 * std::f64::consts::PI.sqrt() / 3.0
        * composite_modulus(c)
        * c.fractal_roughness.dpowf(d - 1.0)
        * 0.5
        * d
        * (0.5 * d * ln_al).dexp()
        * integral;
    let plastic = h * d / (2.0 - d) * (0.5 * d * ln_al + 0.5 * (2.0 - d) * ln_ac).dexp();
    elastic + plastic
}

/// Bracket of the `a_L` search (m²): far below any asperity and far above any gear flank.
const AREA_BRACKET: (f64, f64) = (1e-30, 1e2);

/// `a_L` (m²) of the Majumdar–Bhushan load balance `P(a_L) = F` at the contact's load `F`
/// ([`majumdar_bhushan_load`]), by bisection on `ln a_L` over `[1e-30, 1e2] m²` (200 halvings of
/// a bracket 74 units wide in `ln a_L`: the result is the bisection limit, relative error
/// ~1e-15). `E* = E/(2(1−ν²))`, `H` and `ν` from the contact; `D`, `G` its fractal parameters.
/// Errors on invalid contact inputs or a load outside the bracket.
pub fn majumdar_bhushan_area(c: &FractalContact) -> Result<f64, Error> {
    c.validate().map_err(|source| Error::Stiffness {
        context: "yu2021 Majumdar–Bhushan load balance",
        source,
    })?;
    let (mut lo, mut hi) = (AREA_BRACKET.0.dln(), AREA_BRACKET.1.dln());
    let f = c.load;
    let (p_lo, p_hi) = (majumdar_bhushan_load(c, lo), majumdar_bhushan_load(c, hi));
    if !(p_lo < f && f < p_hi) {
        return Err(Error::invalid(
            "yu2021.fractal_contact.load (Majumdar–Bhushan a_L)",
            format!("between P(a_L = 1e-30 m²) = {p_lo:e} N and P(a_L = 100 m²) = {p_hi:e} N"),
            f,
        ));
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if majumdar_bhushan_load(c, mid) < f {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok((0.5 * (lo + hi)).dexp())
}

impl ContactAreaLaw {
    /// The contact with `a_L` set by this law.
    pub fn apply(&self, c: &FractalContact) -> Result<FractalContact, Error> {
        Ok(match self {
            ContactAreaLaw::Fixed => *c,
            ContactAreaLaw::LoadBalance => FractalContact {
                largest_contact_area: majumdar_bhushan_area(c)?,
                ..*c
            },
        })
    }
}

use super::fractal::{FractalContact, FractalForm, FractalSurface, fractal_contact_stiffness};
use super::params::{BacklashSpec, Yu2021Params};
use crate::error::check_pos;

/// Mean mesh stiffness from Eq. (18) with one calibrated level (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FractalMeshStiffness {
    /// Inputs of Eq. (18) at the reference surface: its `fractal_dimension` and
    /// `fractal_roughness` are `D_ref`, `G_ref`; the other fields stay fixed when `D`, `G` vary.
    pub contact: FractalContact,
    /// `k_am` (N/m) at the reference surface.
    pub reference_stiffness: f64,
    /// How `a_L` is obtained, at the reference and at every `(D, G)` (default: fixed).
    #[serde(default)]
    pub area: ContactAreaLaw,
}

impl FractalMeshStiffness {
    /// The reference used by the Yu dynamic studies on the Table 2 rig: the
    /// model's documented contact ([`crate::yu2021::fractal_contact_default`], reading R-YU-EQ18: `D_ref = 1.5`,
    /// `G_ref = 1e-11 m`, steel, `l_a = 1e-4 m`, `l_s = 1e-8 m`, `a_L = π l_a²/4`, `λ_c = 1`)
    /// with the Table 2 pair's flank radii (`0.075 sin 20°` m) and load (340 N·m / 0.075 m),
    /// and `k_ref` = the Table 2 parameter set's mean stiffness (4e8 N/m, ISO 6336-1 typical
    /// `c_γ = 20 N/(mm·µm)` times the 20 mm face width).
    pub fn table2() -> Self {
        let p = Yu2021Params::table2();
        let r = p.radius_p * p.pressure_angle.dsin();
        FractalMeshStiffness {
            contact: FractalContact {
                radius_pinion: r,
                radius_gear: p.radius_g * p.pressure_angle.dsin(),
                load: p.static_force(),
                ..crate::yu2021::fractal_contact_default()
            },
            reference_stiffness: p.mesh_stiffness,
            area: ContactAreaLaw::Fixed,
        }
    }

    /// The same law with `a_L` obtained by `area`.
    pub fn with_area(self, area: ContactAreaLaw) -> Self {
        FractalMeshStiffness { area, ..self }
    }

    /// The contact of Eq. (18) at `(D, G)`: the reference contact with `D`, `G` replaced and
    /// `a_L` from [`FractalMeshStiffness::area`].
    pub fn contact_at(&self, dimension: f64, roughness: f64) -> Result<FractalContact, Error> {
        self.area.apply(&FractalContact {
            fractal_dimension: dimension,
            fractal_roughness: roughness,
            ..self.contact
        })
    }

    /// `k_am(D, G)` (N/m). Errors if `D ∉ (1, 2)`, `G ≤ 0`, the reference is invalid or the
    /// leaf cannot evaluate Eq. (18).
    pub fn stiffness(&self, dimension: f64, roughness: f64) -> Result<f64, Error> {
        check_pos(
            "yu2021.fractal_stiffness.reference_stiffness",
            self.reference_stiffness,
        )?;
        let reference =
            fractal_contact_stiffness(&self.area.apply(&self.contact)?, FractalForm::Consistent)?;
        let at = self.contact_at(dimension, roughness)?;
        let k = fractal_contact_stiffness(&at, FractalForm::Consistent)?;
        let v = self.reference_stiffness * k / reference;
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(Error::invalid(
                "yu2021.fractal_stiffness (k_am computed)",
                "> 0 and finite",
                v,
            ))
        }
    }

    /// `k_am` for a surface of the backlash model (its `D` and `G`).
    pub fn for_surface(&self, surface: &FractalSurface) -> Result<f64, Error> {
        self.stiffness(surface.dimension, surface.roughness)
    }
}

impl Yu2021Params {
    /// The same parameters with `mesh_stiffness = k_am(D, G)` of `law`, `D` and `G` taken from
    /// the fractal constant part of the backlash, so that one surface sets both the backlash
    /// (Eq. 4–5) and the stiffness (Eq. 17–18). Errors if the backlash is not
    /// [`BacklashSpec::Fractal`] or Eq. (18) cannot be evaluated.
    pub fn with_fractal_stiffness(&self, law: &FractalMeshStiffness) -> Result<Self, Error> {
        let BacklashSpec::Fractal { surface, .. } = self.backlash else {
            return Err(Error::invalid(
                "yu2021.backlash (for the Eq. 18 stiffness)",
                "a fractal surface (BacklashSpec::Fractal)",
                f64::NAN,
            ));
        };
        Ok(Yu2021Params {
            mesh_stiffness: law.for_surface(&surface)?,
            ..*self
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reference_surface_gives_reference_stiffness() {
        let law = FractalMeshStiffness::table2();
        let k = law.stiffness(1.5, 1e-11).unwrap();
        assert!((k / 4e8 - 1.0).abs() < 1e-14, "{k}");
    }

    #[test]
    fn ratio_is_the_ratio_of_eq18() {
        let law = FractalMeshStiffness::table2();
        let c = |d: f64| {
            let at = FractalContact {
                fractal_dimension: d,
                ..law.contact
            };
            fractal_contact_stiffness(&at, FractalForm::Consistent).unwrap()
        };
        let r = law.stiffness(1.2, 1e-11).unwrap() / law.stiffness(1.8, 1e-11).unwrap();
        assert!((r / (c(1.2) / c(1.8)) - 1.0).abs() < 1e-12);
        // with the leaf's defaults Eq. (18) falls with D (docs/readings/mesh-stiffness.md)
        assert!(r > 1.0, "{r}");
    }

    #[test]
    fn params_take_d_and_g_from_the_backlash_surface() {
        let mut p = Yu2021Params::table2();
        let surface = FractalSurface {
            dimension: 1.4,
            roughness: 1e-11,
            lambda: 1.5,
            l_max: 1e-3,
            l_min: 1e-6,
            length: 1e-3,
        };
        let law = FractalMeshStiffness::table2();
        assert!(p.with_fractal_stiffness(&law).is_err());
        p.backlash = BacklashSpec::Fractal { b0: 30e-6, surface };
        let q = p.with_fractal_stiffness(&law).unwrap();
        assert_eq!(
            q.mesh_stiffness.to_bits(),
            law.stiffness(1.4, 1e-11).unwrap().to_bits()
        );
        assert_eq!(q.torque.to_bits(), p.torque.to_bits());
    }

    /// The balance is exact where it has a closed form: below `a_c` every spot is plastic and
    /// `P = H D/(2−D) a_L`, so `a_L = F (2−D)/(H D)`.
    #[test]
    fn all_plastic_balance_is_exact() {
        // D = 1.2, G = 1e-11 m: a_c = G² (2E*/H)^10 ≈ 1.3e-2 m², far above the solution
        let c = FractalContact {
            fractal_dimension: 1.2,
            ..FractalMeshStiffness::table2().contact
        };
        assert!(ln_critical_area(&c) > (1e-3f64).dln());
        let a = majumdar_bhushan_area(&c).unwrap();
        let want = c.load * 0.8 / (c.hardness * 1.2);
        assert!((a / want - 1.0).abs() < 1e-12, "{a} vs {want}");
    }

    /// The load is continuous at `a_L = a_c` (elastic integral 0, plastic part `H D/(2−D) a_c`),
    /// increasing, and the solved `a_L` balances the load; the D = 1.5 limit of the integral
    /// (a logarithm) joins its neighbours.
    #[test]
    fn load_balance_is_continuous_increasing_and_solved() {
        for d in [1.3, 1.45, 1.5, 1.55, 1.8] {
            let c = FractalContact {
                fractal_dimension: d,
                ..FractalMeshStiffness::table2().contact
            };
            let ln_ac = ln_critical_area(&c);
            let below = majumdar_bhushan_load(&c, ln_ac);
            let above = majumdar_bhushan_load(&c, ln_ac + 1e-12);
            assert!((above / below - 1.0).abs() < 1e-9, "D = {d}");
            let mut prev = 0.0;
            for i in 0..60 {
                let p = majumdar_bhushan_load(&c, -60.0 + f64::from(i));
                assert!(p > prev, "D = {d}, step {i}");
                prev = p;
            }
            let a = majumdar_bhushan_area(&c).unwrap();
            let p = majumdar_bhushan_load(&c, a.dln());
            assert!((p / c.load - 1.0).abs() < 1e-12, "D = {d}: {p}");
        }
        let near = |d: f64| {
            majumdar_bhushan_area(&FractalContact {
                fractal_dimension: d,
                ..FractalMeshStiffness::table2().contact
            })
            .unwrap()
        };
        let (a0, a1, a2) = (near(1.5 - 1e-7), near(1.5), near(1.5 + 1e-7));
        assert!((a1 / a0 - 1.0).abs() < 1e-4 && (a2 / a1 - 1.0).abs() < 1e-4);
    }

    /// With the load-dependent `a_L` the level stays at the reference surface and Eq. (18)
    /// rises from D = 1.2 to 1.6 (the fixed `a_L` falls): values of docs/models/yu2021.md.
    #[test]
    fn load_dependent_area_reverses_the_d_trend_up_to_1_6() {
        let fixed = FractalMeshStiffness::table2();
        let lb = fixed.with_area(ContactAreaLaw::LoadBalance);
        assert!((lb.stiffness(1.5, 1e-11).unwrap() / 4e8 - 1.0).abs() < 1e-12);
        let k = |l: &FractalMeshStiffness, d: f64| l.stiffness(d, 1e-11).unwrap();
        assert!(k(&fixed, 1.4) < k(&fixed, 1.2) && k(&fixed, 1.6) < k(&fixed, 1.4));
        let r1 = k(&lb, 1.4) / k(&lb, 1.2);
        let r2 = k(&lb, 1.6) / k(&lb, 1.4);
        let r3 = k(&lb, 1.8) / k(&lb, 1.6);
        assert!((2.3..2.7).contains(&r1), "{r1}");
        assert!((1.7..2.0).contains(&r2), "{r2}");
        assert!(r3 < 0.2, "{r3}");
    }

    #[test]
    fn load_outside_the_bracket_is_an_error() {
        let c = FractalContact {
            load: 1e30,
            ..FractalMeshStiffness::table2().contact
        };
        let e = majumdar_bhushan_area(&c).unwrap_err();
        assert!(e.to_string().contains("Majumdar"), "{e}");
        let bad = FractalContact {
            fractal_dimension: 2.5,
            ..FractalMeshStiffness::table2().contact
        };
        assert!(majumdar_bhushan_area(&bad).is_err());
    }

    #[test]
    fn invalid_inputs_are_errors() {
        let law = FractalMeshStiffness::table2();
        assert!(law.stiffness(2.2, 1e-11).is_err());
        assert!(law.stiffness(1.4, -1.0).is_err());
        let bad = FractalMeshStiffness {
            reference_stiffness: 0.0,
            ..law
        };
        let e = bad.stiffness(1.4, 1e-11).unwrap_err();
        assert!(e.to_string().contains("reference_stiffness"), "{e}");
    }
}
