//! The random dense test matrix of the LU tests, the `lu_rounds` example and the `dense_lu`
//! bench (one file, included by each with `#[path]`).

use nalgebra::DMatrix;

/// An `n × n` matrix with entries uniform in [−1, 1) from a fixed seed (splitmix64): condition
/// numbers of order `n`, and pivoting needed at almost every step.
pub fn random_matrix(n: usize, seed: u64) -> DMatrix<f64> {
    let mut s = seed;
    DMatrix::from_fn(n, n, |_, _| {
        s = s.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = s;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    })
}
