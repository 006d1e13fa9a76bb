//! The blocked LU (`BlockedLu`): backward error of `P A = L U` and of solves on random
//! matrices, agreement with nalgebra's LU, exact small cases, typed errors, and the dense
//! Newton path with either LU.

use geardyn_hbm::{
    AUTO_BLOCKED_LU_UNKNOWNS, Basis, BlockedLu, DenseLu, HbmError, HbmProblem, SolverOptions,
};
use math::DetMath;
use nalgebra::{DMatrix, DVector};
use proptest::prelude::*;

use crate::common::random_matrix::random_matrix;

/// `‖P A − L U‖_F / ‖A‖_F`.
fn factor_error(a: &DMatrix<f64>, lu: &BlockedLu) -> f64 {
    let pa = lu.permute_rows(a).unwrap();
    (pa - lu.l() * lu.u()).norm() / a.norm()
}

/// `‖A x − b‖ / (‖A‖_F ‖x‖)` of the blocked solve of `A x = b`.
fn solve_error(a: &DMatrix<f64>, lu: &BlockedLu, b: &DVector<f64>) -> (f64, DVector<f64>) {
    let mut x = b.clone();
    lu.solve_mut(x.as_mut_slice()).unwrap();
    let err = (a * &x - b).norm() / (a.norm() * x.norm());
    (err, x)
}

/// Backward errors at the `n ε` level for every tested size and block width, including `n`
/// not a multiple of `nb` and `nb ≥ n` (unblocked).
#[test]
fn backward_error_at_n_eps() {
    let eps = f64::EPSILON;
    for (n, nb) in [
        (1, 4),
        (2, 1),
        (7, 3),
        (15, 48),
        (31, 8),
        (65, 16),
        (100, 32),
        (131, 48),
        (201, 64),
        (257, 48),
    ] {
        let a = random_matrix(n, 1000 + n as u64);
        let lu = BlockedLu::with_block_size(a.clone(), nb).unwrap();
        assert_eq!(lu.dim(), n);
        assert_eq!(lu.block_size(), nb);
        let fe = factor_error(&a, &lu);
        assert!(
            fe <= n as f64 * eps,
            "n = {n}, nb = {nb}: ‖PA − LU‖/‖A‖ = {fe:e}"
        );
        let b = DVector::from_fn(n, |i, _| (i as f64 + 0.5).dcos());
        let (se, x) = solve_error(&a, &lu, &b);
        assert!(
            se <= n as f64 * eps,
            "n = {n}, nb = {nb}: solve residual {se:e}"
        );
        // L is unit lower triangular with |l_ij| ≤ 1 (partial pivoting), pivots below or at k
        let l = lu.l();
        assert!(l.iter().all(|v| v.abs() <= 1.0));
        for (k, &p) in lu.pivots().iter().enumerate() {
            assert!(p >= k && p < n);
        }
        // the same solution as nalgebra's LU, to the conditioning of A
        let xn = a.clone().lu().solve(&b).unwrap();
        let diff = (&x - &xn).norm() / xn.norm();
        assert!(diff <= 1e-11, "n = {n}: |x − x_nalgebra|/|x| = {diff:e}");
    }
}

/// The blocked and unblocked (nb ≥ n) eliminations choose the same pivots (in exact
/// arithmetic they are the same algorithm) and agree to rounding.
#[test]
fn block_width_changes_only_rounding() {
    let n = 150;
    let a = random_matrix(n, 99);
    let un = BlockedLu::with_block_size(a.clone(), n).unwrap();
    for nb in [1, 5, 32, 48, 149] {
        let lu = BlockedLu::with_block_size(a.clone(), nb).unwrap();
        assert_eq!(lu.pivots(), un.pivots(), "nb = {nb}");
        let d = (lu.u() - un.u()).norm() / un.u().norm();
        assert!(d <= 1e-12, "nb = {nb}: {d:e}");
    }
}

/// Several right-hand sides at once give the columns' single solves exactly.
#[test]
fn several_right_hand_sides() {
    let n = 70;
    let a = random_matrix(n, 5);
    let lu = BlockedLu::with_block_size(a.clone(), 16).unwrap();
    let b = random_matrix(n, 6).columns(0, 3).into_owned();
    let mut x = b.clone();
    lu.solve_matrix_mut(&mut x).unwrap();
    for j in 0..3 {
        let mut xj: Vec<f64> = b.column(j).iter().copied().collect();
        lu.solve_mut(&mut xj).unwrap();
        assert_eq!(x.column(j).as_slice(), xj.as_slice());
    }
    let res = (&a * &x - &b).norm() / (a.norm() * x.norm());
    assert!(res <= n as f64 * f64::EPSILON, "{res:e}");
    let mut wrong = DMatrix::zeros(n + 1, 2);
    assert!(matches!(
        lu.solve_matrix_mut(&mut wrong),
        Err(HbmError::DimensionMismatch {
            expected: 70,
            got: 71,
            ..
        })
    ));
}

/// Exact small cases (exact comparisons on purpose): a 1 × 1, a matrix that needs a row interchange (zero leading entry),
/// and a permutation matrix, solved exactly.
#[test]
#[allow(clippy::float_cmp)]
fn exact_small_cases() {
    // 1 × 1
    let lu = BlockedLu::new(DMatrix::from_element(1, 1, 4.0)).unwrap();
    let mut x = [2.0];
    lu.solve_mut(&mut x).unwrap();
    assert_eq!(x, [0.5]);
    // [[0, 2], [3, 1]]: the zero pivot forces the swap
    let a = DMatrix::from_row_slice(2, 2, &[0.0, 2.0, 3.0, 1.0]);
    let lu = BlockedLu::new(a).unwrap();
    assert_eq!(lu.pivots(), &[1, 1]);
    assert_eq!(lu.l(), DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, 1.0]));
    assert_eq!(lu.u(), DMatrix::from_row_slice(2, 2, &[3.0, 1.0, 0.0, 2.0]));
    let mut x = [4.0, 7.0]; // 2y = 4, 3x + y = 7 → (5/3, 2)
    lu.solve_mut(&mut x).unwrap();
    assert_eq!(x[1], 2.0);
    assert!((x[0] - 5.0 / 3.0).abs() <= f64::EPSILON);
    // a permutation matrix (rows 2, 0, 3, 1 of I), in blocks of 1 and 2
    let p = DMatrix::from_row_slice(
        4,
        4,
        &[
            0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0,
        ],
    );
    for nb in [1, 2, 4] {
        let lu = BlockedLu::with_block_size(p.clone(), nb).unwrap();
        assert_eq!(lu.l(), DMatrix::identity(4, 4));
        assert_eq!(lu.u(), DMatrix::identity(4, 4));
        assert_eq!(lu.permute_rows(&p).unwrap(), DMatrix::identity(4, 4));
        let mut x = [1.0, 2.0, 3.0, 4.0]; // P x = b → x = Pᵀ b
        lu.solve_mut(&mut x).unwrap();
        assert_eq!(x, [2.0, 4.0, 1.0, 3.0]);
    }
}

/// Singular, non-finite, non-square and mis-sized input: typed errors naming the column.
#[test]
fn typed_errors() {
    // column 2 = column 0 + column 1, with multipliers 1/2 and 1/4 (exact in binary): the
    // elimination leaves exactly 0 in column 2
    let s = DMatrix::from_row_slice(3, 3, &[4.0, 1.0, 5.0, 2.0, 2.5, 4.5, 1.0, 1.25, 2.25]);
    assert_eq!(
        BlockedLu::new(s).unwrap_err(),
        HbmError::SingularPivot { column: 2 }
    );
    // a zero column
    let mut z = random_matrix(10, 3);
    z.column_mut(6).fill(0.0);
    for nb in [1, 4, 48] {
        assert_eq!(
            BlockedLu::with_block_size(z.clone(), nb).unwrap_err(),
            HbmError::SingularPivot { column: 6 }
        );
    }
    // NaN and infinity
    let mut a = random_matrix(9, 4);
    a[(5, 3)] = f64::NAN;
    assert_eq!(
        BlockedLu::new(a.clone()).unwrap_err(),
        HbmError::NonFiniteMatrix { column: 3 }
    );
    a[(5, 3)] = 0.5;
    a[(0, 8)] = f64::INFINITY;
    assert_eq!(
        BlockedLu::new(a).unwrap_err(),
        HbmError::NonFiniteMatrix { column: 8 }
    );
    // overflow during the elimination: 1e308 − (−1e308) = inf in the trailing update
    let o = DMatrix::from_row_slice(2, 2, &[1.0, -1e308, 1.0, 1e308]);
    assert!(matches!(
        BlockedLu::new(o),
        Err(HbmError::NonFiniteMatrix { column: 1 })
    ));
    // not square, zero block width, wrong right-hand side
    assert!(matches!(
        BlockedLu::new(DMatrix::zeros(3, 4)),
        Err(HbmError::DimensionMismatch { .. })
    ));
    assert!(matches!(
        BlockedLu::with_block_size(DMatrix::identity(3, 3), 0),
        Err(HbmError::InvalidParameter { .. })
    ));
    let lu = BlockedLu::new(DMatrix::identity(3, 3)).unwrap();
    assert!(lu.solve_mut(&mut [1.0, 2.0]).is_err());
    assert!(lu.permute_rows(&DMatrix::zeros(2, 2)).is_err());
    // the empty matrix factors and solves trivially; refactor reuses or resizes storage
    let mut e = BlockedLu::empty();
    assert_eq!(e.dim(), 0);
    e.solve_mut(&mut []).unwrap();
    let a = random_matrix(20, 8);
    e.refactor(&a).unwrap();
    assert!(factor_error(&a, &e) <= 20.0 * f64::EPSILON);
    assert!(e.refactor(&DMatrix::from_element(20, 20, 1.0)).is_err());
    e.refactor(&a).unwrap();
    assert!(factor_error(&a, &e) <= 20.0 * f64::EPSILON);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(40))]
    /// Sizes 1..200, any seed and block width: backward errors at the `n ε` level.
    #[test]
    fn random_sizes_factor_and_solve(n in 1usize..200, nb in 1usize..100, seed in any::<u64>()) {
        let a = random_matrix(n, seed);
        let lu = BlockedLu::with_block_size(a.clone(), nb).unwrap();
        let eps = f64::EPSILON;
        let fe = factor_error(&a, &lu);
        prop_assert!(fe <= n as f64 * eps, "‖PA − LU‖/‖A‖ = {:e}", fe);
        let b = DVector::from_fn(n, |i, _| 1.0 - (i % 3) as f64);
        let (se, _) = solve_error(&a, &lu, &b);
        prop_assert!(se <= n as f64 * eps, "solve residual {:e}", se);
    }
}

/// The dense Newton solve of a Duffing oscillator with the blocked LU converges to the
/// solution of the nalgebra path (the same iterates up to rounding), and `Auto` picks
/// nalgebra below `AUTO_BLOCKED_LU_UNKNOWNS`.
#[test]
fn dense_newton_with_either_lu() {
    use system::problems::BenchDuffing as Duffing;
    let omega = 1.3;
    let mut p1 = HbmProblem::new(Duffing { omega }, Basis::full(1).unwrap(), omega).unwrap();
    let mut g = p1.zero_guess();
    g[1] = 0.8;
    let s1 = p1.solve(&g, &SolverOptions::default()).unwrap();
    let basis = Basis::full(40).unwrap();
    let mut p = HbmProblem::new(Duffing { omega }, basis.clone(), omega).unwrap();
    assert_eq!(p.dense_lu(), DenseLu::Auto);
    let z = s1.embed(&basis);
    let auto = p.solve(&z, &SolverOptions::default()).unwrap();
    p.set_dense_lu(DenseLu::Nalgebra);
    let nal = p.solve(&z, &SolverOptions::default()).unwrap();
    p.set_dense_lu(DenseLu::Blocked);
    let blk = p.clone().solve(&z, &SolverOptions::default()).unwrap();
    assert!(auto.converged && nal.converged && blk.converged);
    // 81 unknowns: Auto is nalgebra, bit for bit
    const { assert!(81 < AUTO_BLOCKED_LU_UNKNOWNS) };
    assert_eq!(auto.coefficients, nal.coefficients);
    assert_eq!(auto.iterations, nal.iterations);
    let d: f64 = blk
        .coefficients
        .iter()
        .zip(&nal.coefficients)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(d <= 1e-10, "max |Δz| = {d:e}");
    assert!(DenseLu::Auto.uses_blocked(AUTO_BLOCKED_LU_UNKNOWNS));
    assert!(!DenseLu::Auto.uses_blocked(AUTO_BLOCKED_LU_UNKNOWNS - 1));
    assert!(DenseLu::Blocked.uses_blocked(1) && !DenseLu::Nalgebra.uses_blocked(10_000));
}
