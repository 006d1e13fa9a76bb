//! The presets of Yu 2021: the spur-pair geometry of a parameter set
//! ([`Yu2021Params::spur_pair`]; Table 1 and Table 2 are [`Yu2021Params::table1`] and
//! [`Yu2021Params::table2`]) and the model as the generic spur pair ([`crate::pair`]),
//! [`PairParams::yu2021`]. The pair stands under the papers and knows none of them; each
//! paper's preset lives in its own folder.

use gear_geometry::{SpurPair, SpurPairParams};
use math::DetMath;
use mesh_stiffness::Stiffness;

use super::Yu2021Params;
use crate::Error;
use crate::pair::{Dofs, PairParams};

/// The fractal contact of Yu Eq. (18) with the values chosen here (reading R-YU-EQ18 in
/// `docs/readings/mesh-stiffness.md`, every value with its source; the law is the
/// `mesh-stiffness` leaf's [`mesh_stiffness::FractalContact`], the set is Yu's):
///
/// - `D = 1.5`, `G = 1e-11 m`: mid-range of Yu Figs. 9–12 (`G = 1e-11 m` in Fig. 9).
/// - `E = 2.06e11 Pa`: Yu Table 2 (2.06×10⁵ N/mm²). `ν = 0.3` (steel).
/// - `H = 2.2e9 Pa`: Tabor `H ≈ 2.8 σ_y` with `σ_y = 785 MPa` (quenched and tempered 40Cr,
///   GB/T 3077); Yu gives no hardness.
/// - `R₁ = R₂ = 0.094 sin 20° m`: flank curvature at the pitch point of Yu Table 1's pair
///   (`R_p = R_g = 0.094 m`, 20° pressure angle).
/// - `F = 107.8 N m / 0.094 m = 1146.8 N`: Yu Table 1 torque over the radius.
/// - `l_a = 1e-4 m`, `l_s = 1e-8 m`: four decades of asperity scales (Yu gives none).
/// - `a_L = π l_a²/4`: the base area of the largest asperity, an upper bound for its contact.
/// - `λ_c = 1`: no curvature correction (the printed definition is unit-dependent).
pub fn fractal_contact_default() -> mesh_stiffness::FractalContact {
    let r = 0.094 * 20f64.to_radians().dsin();
    let la = 1e-4;
    mesh_stiffness::FractalContact {
        fractal_dimension: 1.5,
        fractal_roughness: 1e-11,
        elastic_modulus: 2.06e11,
        hardness: 2.2e9,
        poisson_ratio: 0.3,
        radius_pinion: r,
        radius_gear: r,
        load: 107.8 / 0.094,
        largest_asperity: la,
        smallest_asperity: 1e-8,
        largest_contact_area: std::f64::consts::PI * la * la / 4.0,
        curvature_coefficient: mesh_stiffness::CurvatureCoefficient::Value(1.0),
    }
}

/// The constant-backlash parameters chosen here for Yu Fig. 4 (the paper prints none; reading
/// R-YU-FIG4 in `docs/readings/backlash.md`): `b_0 = 30 µm`, `λ = 1.5`, `l_a = L = 1 mm`,
/// `l_s = 1 µm`, 8 quadrature points per smallest wavelength, Eq. (4)–(5) with `|z|`.
/// The law is the backlash leaf's ([`backlash::ConstantBacklashParams`]); the set is Yu's.
pub fn fig4_backlash_params() -> backlash::ConstantBacklashParams {
    backlash::ConstantBacklashParams {
        b0: 30e-6,
        gamma: 1.5,
        l_a: 1e-3,
        l_s: 1e-6,
        sampling_length: 1e-3,
        quadrature: backlash::Quadrature::default(),
        form: backlash::ConstantPartForm::AbsoluteMean,
    }
}

/// Yu Fig. 4 as data with [`fig4_backlash_params`]: `b_s(D, G)` for D = 1.2, 1.3, …, 1.8 and
/// G = 1e-12 … 1e-11 m (5 log-spaced values; the decade of Fig. 12(b), containing the
/// G = 1e-11 m of Fig. 9), through the leaf's [`backlash::constant_part_grid`].
pub fn fig4() -> Result<backlash::ConstantPartGrid, backlash::Error> {
    let d: Vec<f64> = (0..7).map(|i| 1.2 + 0.1 * f64::from(i)).collect();
    let g: Vec<f64> = (0..5)
        .map(|j| 10f64.dpowf(-12.0 + 0.25 * f64::from(j)))
        .collect();
    backlash::constant_part_grid(fig4_backlash_params(), &d, &g)
}

/// The text's claims about Yu Fig. 4 (Sect. 2.1), evaluated on a grid of the backlash leaf
/// ([`backlash::ConstantPartGrid`], from [`fig4`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Fig4Claims {
    /// Largest b_s over G at the row D = 1.2 (m); the text: below 20 µm.
    pub max_b_s_at_d12: f64,
    /// Smallest b_s over G at the row D = 1.2 (m) (negative means interference).
    pub min_b_s_at_d12: f64,
    /// Largest |b_s − b_0| / b_0 over G at the row D = 1.8; the text: b_s ≈ b_0.
    pub max_rel_dev_at_d18: f64,
    /// b_s non-decreasing in D for every G.
    pub rises_with_d: bool,
    /// b_s non-increasing in G for every D.
    pub falls_with_g: bool,
}

impl Fig4Claims {
    /// All claims hold: b_s(1.2, ·) < 20 µm, |b_s(1.8, ·) − b0| < 1 % b0, monotone in D and G.
    pub fn all_hold(&self) -> bool {
        self.max_b_s_at_d12 < 20e-6
            && self.max_rel_dev_at_d18 < 0.01
            && self.rises_with_d
            && self.falls_with_g
    }
}

/// Evaluate the text's claims about Fig. 4 on `grid`. Needs rows D = 1.2 and D = 1.8 (within
/// 1e-9); otherwise [`backlash::Error::Inconsistent`] names the missing row.
pub fn fig4_claims(grid: &backlash::ConstantPartGrid) -> Result<Fig4Claims, backlash::Error> {
    {
        let row = |d: f64| {
            grid.d
                .iter()
                .position(|&x| (x - d).abs() < 1e-9)
                .ok_or_else(|| backlash::Error::Inconsistent {
                    what: "Fig. 4 grid",
                    detail: format!("no row D = {d}"),
                })
        };
        let r12 = row(1.2)?;
        let r18 = row(1.8)?;
        let b0 = grid.params.b0;
        let max12 = grid.b_s[r12]
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max);
        let min12 = grid.b_s[r12].iter().copied().fold(f64::INFINITY, f64::min);
        let dev18 = grid.b_s[r18]
            .iter()
            .map(|b| (b - b0).abs() / b0.max(f64::MIN_POSITIVE))
            .fold(0.0, f64::max);
        let mut rises = true;
        let mut falls = true;
        for i in 0..grid.d.len() {
            for j in 0..grid.g.len() {
                if i + 1 < grid.d.len() && grid.d[i + 1] > grid.d[i] {
                    rises &= grid.b_s[i + 1][j] >= grid.b_s[i][j];
                }
                if j + 1 < grid.g.len() && grid.g[j + 1] > grid.g[j] {
                    falls &= grid.b_s[i][j + 1] <= grid.b_s[i][j];
                }
            }
        }
        Ok(Fig4Claims {
            max_b_s_at_d12: max12,
            min_b_s_at_d12: min12,
            max_rel_dev_at_d18: dev18,
            rises_with_d: rises,
            falls_with_g: falls,
        })
    }
}

impl Yu2021Params {
    /// The involute spur pair of this parameter set: reference radii `R_p`, `R_g` and `α_0`
    /// (Table 1: `R_p = R_g = 0.094 m`; Table 2: module 3 mm, 50/50 teeth, `R = 75 mm`; both
    /// `α_0 = 20°`). Errors name the field (`rp`, `rg`, `pressure_angle`).
    pub fn spur_pair(&self) -> Result<SpurPair, Error> {
        Ok(SpurPair::new(SpurPairParams {
            rp: self.radius_p,
            rg: self.radius_g,
            pressure_angle: self.pressure_angle,
        })?)
    }
}

impl PairParams {
    /// The Yu 2021 model (consistent form) as this pair, in its dimensionless units at `ω*`
    /// (see the module docs). Errors for the forms the pair does not cover: Eq. (19) as
    /// printed, Fig. 8's previous-step update.
    pub fn yu2021(model: &super::Yu2021Model, omega: f64) -> Result<Self, Error> {
        use super::{BacklashUpdate, EquationForm, ModelKind};
        let o = &model.options;
        if o.form != EquationForm::Consistent || o.update != BacklashUpdate::InRhs {
            return Err(Error::UnsupportedReading {
                field: "pair.yu2021",
                reading: format!("{:?}/{:?}", o.form, o.update),
            });
        }
        let p = &model.params;
        let law = model.dynamic_backlash_law();
        let six = o.kind == ModelKind::Yu && !o.lock_centres;
        let m = [1.0 / p.mass_ratio[0], 1.0 / p.mass_ratio[1]];
        let mi = [m[0], m[0], m[1], m[1]];
        Ok(Self {
            geometry: gear_geometry::SpurPairParams {
                rp: law.geometry.r_p,
                rg: law.geometry.r_g,
                pressure_angle: law.geometry.alpha0,
            },
            dofs: if six {
                Dofs::TransverseTorsional
            } else {
                Dofs::Torsional
            },
            equivalent_mass: 1.0,
            masses: m,
            bearing_stiffness: std::array::from_fn(|i| p.kappa[i] * mi[i]),
            bearing_damping: std::array::from_fn(|i| p.zeta_bearing[i] * mi[i]),
            mesh_damping: p.zeta,
            static_force: p.load,
            ste_amplitude: p.ste,
            ste_phase: p.phase,
            mesh_frequency: omega,
            stiffness: Stiffness::SingleHarmonic(model.mesh_stiffness_law(omega)),
            backlash: model.backlash_law(omega),
            pressure_angle: o.pressure_angle,
            centre_distance: law.centre_distance,
        })
    }
}

#[cfg(test)]
mod tests {
    use math::DetMath;

    /// The Fig. 4 set is the one R-YU-FIG4 states, and its grid reproduces the table of
    /// `docs/readings/backlash.md` (b_s in µm, printed to 2 decimals, so within 0.005 µm) and
    /// the text's claims (D = 1.2: b_s < 20 µm; D = 1.8: b_s ≈ b_0; monotone in D and G).
    /// The Eq. (18) contact is the one R-YU-EQ18 states (values with their sources in the
    /// function's docs) and the leaf accepts it.
    #[test]
    #[allow(clippy::float_cmp)] // exact: the stated literals
    fn fractal_contact_is_the_documented_one() {
        let c = super::fractal_contact_default();
        let r = 0.094 * 20f64.to_radians().dsin();
        assert_eq!((c.fractal_dimension, c.fractal_roughness), (1.5, 1e-11));
        assert_eq!(
            (c.elastic_modulus, c.hardness, c.poisson_ratio),
            (2.06e11, 2.2e9, 0.3)
        );
        assert_eq!(
            (c.radius_pinion, c.radius_gear, c.load),
            (r, r, 107.8 / 0.094)
        );
        assert_eq!((c.largest_asperity, c.smallest_asperity), (1e-4, 1e-8));
        assert_eq!(c.largest_contact_area, std::f64::consts::PI * 1e-8 / 4.0);
        let k = c
            .stiffness(mesh_stiffness::FractalForm::Consistent)
            .unwrap();
        assert!(k.is_finite() && k > 0.0, "{k}");
    }

    #[test]
    #[allow(clippy::float_cmp)] // exact: the stated literals
    fn fig4_set_and_grid_are_the_documented_ones() {
        let p = super::fig4_backlash_params();
        assert_eq!(
            (p.b0, p.gamma, p.l_a, p.l_s, p.sampling_length),
            (30e-6, 1.5, 1e-3, 1e-6, 1e-3)
        );
        assert_eq!(p.form, backlash::ConstantPartForm::AbsoluteMean);
        let data = super::fig4().unwrap();
        assert_eq!((data.d.len(), data.g.len()), (7, 5));
        for (row, d, want) in [
            (0, 1.2, [13.57, 11.57, 9.32, 6.80, 3.96]),
            (1, 1.3, [27.74, 27.31, 26.80, 26.20, 25.49]),
            (2, 1.4, [29.68, 29.60, 29.50, 29.37, 29.21]),
        ] {
            assert!((data.d[row] - d).abs() < 1e-12);
            for (j, w) in want.iter().enumerate() {
                let got = 1e6 * data.b_s[row][j];
                assert!(
                    (got - w).abs() <= 0.005 + 1e-9,
                    "D {d}, G {}: {got} vs {w}",
                    data.g[j]
                );
            }
        }
        assert!(super::fig4_claims(&data).unwrap().all_hold());
    }
    use crate::pair::test_support::{accel, close};

    /// Table 1 and Table 2 geometry: `a0 = 0.188 m`, and Table 2's `R = m z/2 = 75 mm`
    /// (module 3 mm, 50/50 teeth). The pressure-angle law on these pairs is tested in the
    /// geometry leaf (literal inputs) and in `system::involute`.
    #[test]
    fn table_spur_pairs() {
        use crate::yu2021::Yu2021Params;
        use gear_geometry::SpurPair;
        let t1 = Yu2021Params::table1().spur_pair().unwrap();
        assert!((t1.nominal_centre_distance() - 0.188).abs() < 1e-15);
        let t2 = Yu2021Params::table2().spur_pair().unwrap();
        assert_eq!(
            t2,
            SpurPair::from_module(3e-3, 50, 50, 20f64.to_radians()).unwrap()
        );
        let mut bad = Yu2021Params::table1();
        bad.radius_g = -1.0;
        assert!(bad.spur_pair().unwrap_err().to_string().contains("rg"));
    }
    use crate::pair::{Dofs, GearPair, PairParams};

    /// The Yu 6-DOF model (every dynamic-backlash, pressure-angle and Eq. 8 option) is the pair
    /// preset: the same accelerations at a state (the pair divides by `m_i = 1/μ_i` where Yu
    /// multiplies by `μ_i`: rounding only).
    #[test]
    fn yu_six_dof_rhs_is_the_pair_preset() {
        use crate::yu2021::{
            CentreDistanceForm as Cdf, DynamicBacklashLaw as Dbl, Options, PressureAngleLaw as Pal,
            STATE_LEN, Yu2021Model, Yu2021Params,
        };
        let mut s = [0.0; STATE_LEN];
        s.copy_from_slice(&[1.3, 0.02, -0.01, -0.015, 0.03, 0.2, 0.1, -0.3, 0.05, 0.02]);
        for dynamic_backlash in [Dbl::Eq10, Dbl::Involute, Dbl::Off] {
            for pressure_angle in [Pal::Involute, Pal::Constant] {
                for centre_distance in [Cdf::Consistent, Cdf::PrintedEq8] {
                    let o = Options {
                        dynamic_backlash,
                        pressure_angle,
                        centre_distance,
                        ..Options::default()
                    };
                    let m = Yu2021Model::new(&Yu2021Params::table1(), o).unwrap();
                    let (w, tau) = (0.9, 0.37);
                    let pair = GearPair::from_params(&PairParams::yu2021(&m, w).unwrap()).unwrap();
                    assert_eq!(pair.dofs(), Dofs::TransverseTorsional);
                    let want = m.rhs(w, tau, &s, None);
                    let got = accel(&pair, tau, &s[..5], &s[5..]);
                    for i in 0..5 {
                        assert!(
                            close(got[i], want[5 + i], 1.0),
                            "{o:?} {i}: {} vs {}",
                            got[i],
                            want[5 + i]
                        );
                    }
                }
            }
        }
        // the printed Eq. (19) and Fig. 8's update are not this pair
        let m = Yu2021Model::new(&Yu2021Params::table1(), Options::yu_as_printed()).unwrap();
        assert!(PairParams::yu2021(&m, 1.0).is_err());
    }

    /// Kahraman–Singh and Chen (1-DOF, consistent forcing) are the torsional pair with
    /// `u = δ* + e`: `δ*'' = u'' + ω*² ē cos(ω*τ + φ_0)`.
    #[test]
    fn yu_torsional_models_are_the_torsional_pair() {
        use crate::yu2021::{Options, STATE_LEN, Yu2021Model, Yu2021Params};
        for o in [Options::kahraman_singh(), Options::chen()] {
            let m = Yu2021Model::new(&Yu2021Params::table1(), o).unwrap();
            let p = m.params;
            let pair = GearPair::from_params(&PairParams::yu2021(&m, 0.8).unwrap()).unwrap();
            assert_eq!(pair.dofs(), Dofs::Torsional);
            for (tau, d, v) in [(0.3, 1.4, 0.2), (2.1, 0.4, -0.1), (5.0, -1.3, 0.05)] {
                let ph = 0.8 * tau + p.phase;
                let e = p.ste * ph.dcos();
                let e_rate = -p.ste * 0.8 * ph.dsin();
                let mut s = [0.0; STATE_LEN];
                s[0] = d;
                s[5] = v;
                let want = m.rhs(0.8, tau, &s, None)[5];
                let u_dd = accel(&pair, tau, &[d + e], &[v + e_rate])[0];
                let got = u_dd + 0.8 * 0.8 * e;
                assert!(close(got, want, 1.0), "{o:?} {tau}: {got} vs {want}");
            }
        }
    }

    /// Yu Fig. 4 claims with coarse settings (l_s = 10 µm, moved from the backlash leaf with
    /// the claims): D = 1.2 → b_s < 20 µm for every G; D = 1.8 → b_s ≈ b0; b_s rises with D,
    /// falls with G. A grid without the row D = 1.8 is an error naming it.
    #[test]
    fn fig4_claims_hold_with_coarse_settings() {
        let mut p = super::fig4_backlash_params();
        p.l_s = 1e-5;
        let d: Vec<f64> = (0..7).map(|i| 1.2 + 0.1 * f64::from(i)).collect();
        let g: Vec<f64> = (0..5)
            .map(|j| 10f64.dpowf(-12.0 + 0.25 * f64::from(j)))
            .collect();
        let data = backlash::constant_part_grid(p, &d, &g).unwrap();
        let c = super::fig4_claims(&data).unwrap();
        assert!(c.all_hold(), "{c:?}");
        assert!(c.min_b_s_at_d12 > 0.0, "{c:?}");
        assert!(c.max_rel_dev_at_d18 < 1e-4, "{c:?}");
        let short = backlash::constant_part_grid(p, &d[..3], &g).unwrap();
        let e = super::fig4_claims(&short).unwrap_err();
        assert!(e.to_string().contains("D = 1.8"), "{e}");
    }
}
