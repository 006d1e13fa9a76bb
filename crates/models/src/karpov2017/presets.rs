//! The presets of Karpov et al. 2017: the Table 1 gear pair, whose kinematics the geometry
//! studies check and whose `B`, `ξ`, `j`, `z1` the model's parameters are taken from.

use gear_geometry::{CentreDistance, KarpovPair, KarpovPairParams};

/// The parameters of the Karpov et al. 2017 Table 1 pair (p. 8): `u = 2`, `r = 50 mm`,
/// `B = 0.01`, `ξ = 2`, `j = 4`, `z1 = 32` (`z2 = 64`), centre distance 150 mm;
/// [`CentreDistance::Closing`] (reading `R-KARPOV-EQ1-CLOSURE`). Normal module 3 mm, helix
/// angle 16.0911°, face width 46 mm are not used by the kinematics (reading
/// `R-KARPOV-TABLE1`).
pub fn pair_params_table1() -> KarpovPairParams {
    KarpovPairParams {
        r: 0.050,
        u: 2.0,
        b: 0.01,
        xi: 2.0,
        j: 4,
        z1: 32,
        centre_distance: CentreDistance::Closing,
    }
}

/// The validated Table 1 pair ([`pair_params_table1`]).
pub fn pair_table1() -> KarpovPair {
    // constant, valid inputs (tested below): the constructor cannot fail here
    KarpovPair::new(pair_params_table1()).expect("Table 1 parameters are valid")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Karpov 2017 Table 1: `k = j/z1 = 0.125`, speed fluctuation `δ ≈ 2B(1+u)/u = 0.03`
    /// (exact 0.0299994), Eq. (4) as printed 0.015, and the closing centre distance moves `a`
    /// by 3.5 µm from the printed 150 mm.
    #[test]
    fn table1_pair() {
        let p = pair_table1();
        assert_eq!(p.params(), pair_params_table1());
        assert!((p.k() - 0.125).abs() < 1e-16);
        assert!((p.speed_fluctuation() - 0.029_999_36).abs() < 1e-8);
        assert!((p.speed_fluctuation_eq4() - 0.015).abs() < 1e-15);
        assert!((p.centre_distance() - 0.150 - 3.48e-6).abs() < 0.05e-6);
    }
}
