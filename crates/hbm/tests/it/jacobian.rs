//! The analytic (AFT) Jacobian against finite differences of the residual.

use crate::common::TwoDof;
use geardyn_hbm::{Basis, HbmProblem};
use nalgebra::DMatrix;
use proptest::prelude::*;

fn fd_check(basis: Basis, n_grid: usize, analytic: bool, z: &[f64], omega: f64) -> f64 {
    let sys = TwoDof { omega, analytic };
    let mut p = HbmProblem::with_grid_size(sys, basis, omega, n_grid).unwrap();
    let nz = p.n_unknowns();
    let z = &z[..nz];
    let mut r = vec![0.0; nz];
    let mut jac = DMatrix::zeros(nz, nz);
    p.residual_and_jacobian(z, &mut r, &mut jac).unwrap();
    let (mut rp, mut rm) = (vec![0.0; nz], vec![0.0; nz]);
    let mut worst: f64 = 0.0;
    let scale = jac.amax().max(1.0);
    for j in 0..nz {
        let h = 1e-6;
        let mut zp = z.to_vec();
        zp[j] += h;
        p.residual(&zp, &mut rp).unwrap();
        zp[j] -= 2.0 * h;
        p.residual(&zp, &mut rm).unwrap();
        for i in 0..nz {
            let fd = (rp[i] - rm[i]) / (2.0 * h);
            worst = worst.max((fd - jac[(i, j)]).abs() / scale);
        }
    }
    worst
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn full_basis_jacobian_matches_finite_differences(
        z in proptest::collection::vec(-0.6f64..0.6, 14),
        omega in 0.3f64..3.0,
    ) {
        // full basis H = 3 (14 unknowns for 2 DOF), default grid, and a coarse aliasing grid
        prop_assert!(fd_check(Basis::full(3).unwrap(), 16, true, &z, omega) < 1e-7);
        prop_assert!(fd_check(Basis::full(3).unwrap(), 7, true, &z, omega) < 1e-7);
    }

    #[test]
    fn liu_basis_jacobian_matches_finite_differences(
        z in proptest::collection::vec(-0.3f64..0.3, 30),
        omega in 0.3f64..2.0,
    ) {
        let basis = Basis::liu_multifrequency(1, 6).unwrap();
        prop_assert!(fd_check(basis.clone(), 64, true, &z, omega) < 1e-7);
        // finite-difference default Jacobian of g: still close
        prop_assert!(fd_check(basis, 64, false, &z, omega) < 1e-6);
    }
}
