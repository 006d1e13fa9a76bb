//! The contact of reading R-YU-EQ18 (`docs/readings/mesh-stiffness.md`), shared by this crate's
//! unit tests, integration tests and bench (each includes this file with `#[path]`). The set is
//! Yu's and is kept by the model (`geardyn_models::yu2021::fractal_contact_default`); it is
//! written out here so that the law's tests stand without the model.

use super::{CurvatureCoefficient, FractalContact};
use math::DetMath;

/// D = 1.5, G = 1e-11 m, E = 2.06e11 Pa, H = 2.2e9 Pa, ν = 0.3, R₁ = R₂ = 0.094 sin 20° m,
/// F = 107.8/0.094 N, l_a = 1e-4 m, l_s = 1e-8 m, a_L = π l_a²/4, λ_c = 1.
pub fn reference_contact() -> FractalContact {
    let r = 0.094 * 20f64.to_radians().dsin();
    let la = 1e-4;
    FractalContact {
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
        curvature_coefficient: CurvatureCoefficient::Value(1.0),
    }
}
