//! A blocked, right-looking LU factorisation with partial pivoting for the dense Newton path.
//!
//! nalgebra's [`LU`](nalgebra::LU) eliminates one column at a time: every step is a rank-1
//! update of the whole trailing matrix, so the `⅔ n³` flops stream the matrix through memory
//! `n` times. [`BlockedLu`] does the same elimination in blocks of `nb` columns (LAPACK's
//! `getrf` scheme), so that almost all the flops are one matrix–matrix product per block,
//! done by nalgebra's `gemm` (which calls `matrixmultiply::dgemm`, cache-blocked and
//! vectorised, for every factor larger than 5).
//!
//! `matrixmultiply` picks its kernel by CPU at run time (AVX-512, FMA + AVX2, AVX, SSE2,
//! NEON), and the kernels round differently (fused multiply-adds, other blockings), so the
//! factors of [`BlockedLu`] agree to rounding, not bit for bit, across machines. The path is
//! taken for at least [`AUTO_BLOCKED_LU_UNKNOWNS`] unknowns under [`DenseLu::Auto`]; no
//! committed output of `validation/` comes near it (the largest HBM systems there are the
//! Liu 2021 full basis with `R = 2`, 2·128 + 1 = 257 unknowns, and `R = 1`, 131), so those
//! are the same bits on every platform. The rest of the engines multiplies dynamic matrices in
//! a fixed order of their own (`geardyn-hbm`'s stability, `geardyn-orbit`'s variational flow).
//!
//! ## Algorithm
//! `P A = L U` with `P` a permutation, `L` unit lower triangular, `U` upper triangular, all
//! stored in one column-major `n × n` matrix (`L` below the diagonal, `U` on and above it) and
//! the row interchanges `piv` (at step `k`, rows `k` and `piv[k] ≥ k` are swapped). For the
//! block of columns `j₀ … j₀ + b − 1` (`b = min(nb, n − j₀)`), with the part already factored
//! to its left, partition the remaining rows and columns as
//!
//! ```text
//!     ⎡ A11  A12 ⎤      A11: b × b,  A12: b × m,  A21: m × b,  A22: m × m,  m = n − j₀ − b.
//!     ⎣ A21  A22 ⎦
//! ```
//!
//! 1. **Panel.** Factor the `(b + m) × b` panel `[A11; A21]` with partial pivoting: for
//!    column `k`, the pivot is the entry of largest magnitude on or below the diagonal; swap
//!    it into row `k` (within the panel), divide the entries below it by it (the column of
//!    `L`) and subtract the rank-1 product from the panel's columns to the right. Result:
//!    `P₁ [A11; A21] = [L11; L21] U11`. Done column by column for panels of at most 8
//!    columns; a wider panel is split into halves, the same three steps below applied
//!    recursively between them (so that the panel's work is also mostly `gemm`).
//! 2. **Interchanges.** Apply the panel's row swaps to the columns left of it (the `L` already
//!    computed) and right of it (`A12`, `A22`).
//! 3. **Row block of `U`.** `U12 = L11⁻¹ A12` (forward substitution with the unit lower
//!    triangular `L11`, one column of `A12` at a time).
//! 4. **Trailing update.** `A22 ← A22 − L21 U12`: a `m × b` by `b × m` product, `2 b m²` of the
//!    block's flops, through `gemm`.
//!
//! and continue with `A22`. With `nb ≥ n` the whole matrix is one (recursively factored)
//! panel. In exact arithmetic every block width gives the pivots and factors of nalgebra's
//! column-by-column elimination; in floating point the sums run in another order, so the
//! factors agree to rounding, not bit for bit.
//!
//! A solve of `A x = b` applies the interchanges to `b`, then `L y = P b` (forward) and
//! `U x = y` (backward substitution), column-oriented on the stored factors.
//!
//! ## Errors, not panics
//! A non-finite entry (on input, or produced by overflow during the elimination) is
//! [`HbmError::NonFiniteMatrix`] and a column without a non-zero pivot is
//! [`HbmError::SingularPivot`], both naming the column; a non-square matrix, a zero block
//! size and a right-hand side of the wrong length are [`HbmError::DimensionMismatch`] /
//! [`HbmError::InvalidParameter`].

use crate::HbmError;
use nalgebra::DMatrix;

/// The block width `nb` of [`BlockedLu::new`]: of 16–128, the fastest at `n = 801` (with 64)
/// and within 3 % of the fastest at `n = 401` on the development machine
/// (`docs/performance/hbm.md`, "Round 12").
pub const DEFAULT_LU_BLOCK: usize = 48;

/// Number of unknowns from which [`DenseLu::Auto`] factors the Newton Jacobian with
/// [`BlockedLu`] instead of nalgebra's LU. The measured crossover lies below it
/// (`docs/performance/hbm.md`, "Round 12"); it is set above the largest dense system of the
/// validation studies (Liu's full basis `K = 2 Z₂ + 2` of the `liu-hbm-single-point`
/// example: 257 unknowns), so that their results stay those of nalgebra bit for bit.
pub const AUTO_BLOCKED_LU_UNKNOWNS: usize = 300;

/// Which LU factorisation the dense [`Newton`](crate::Newton) solve uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum DenseLu {
    /// [`DenseLu::Blocked`] for systems of at least [`AUTO_BLOCKED_LU_UNKNOWNS`] unknowns,
    /// [`DenseLu::Nalgebra`] below.
    #[default]
    Auto,
    /// nalgebra's unblocked LU with partial pivoting (`DMatrix::lu`).
    Nalgebra,
    /// [`BlockedLu`] with [`DEFAULT_LU_BLOCK`].
    Blocked,
}

impl DenseLu {
    /// Whether a system of `n` unknowns is factored by [`BlockedLu`].
    pub fn uses_blocked(self, n: usize) -> bool {
        match self {
            DenseLu::Auto => n >= AUTO_BLOCKED_LU_UNKNOWNS,
            DenseLu::Nalgebra => false,
            DenseLu::Blocked => true,
        }
    }
}

/// `P A = L U` of a square matrix by the blocked right-looking algorithm of the
/// [module docs](self).
#[derive(Debug, Clone, PartialEq)]
pub struct BlockedLu {
    /// `L` (strictly below the diagonal, unit diagonal implied) and `U` (on and above).
    lu: DMatrix<f64>,
    /// At step `k`, rows `k` and `piv[k]` were interchanged.
    piv: Vec<usize>,
    /// Block width `nb`.
    block: usize,
}

impl BlockedLu {
    /// Factor `a` with the block width [`DEFAULT_LU_BLOCK`].
    ///
    /// # Errors
    /// As [`BlockedLu::with_block_size`].
    pub fn new(a: DMatrix<f64>) -> Result<Self, HbmError> {
        Self::with_block_size(a, DEFAULT_LU_BLOCK)
    }

    /// Factor `a` in blocks of `block` columns (`block ≥ n`: unblocked).
    ///
    /// # Errors
    /// `a` not square ([`HbmError::DimensionMismatch`]), `block = 0`
    /// ([`HbmError::InvalidParameter`]), a non-finite entry ([`HbmError::NonFiniteMatrix`]),
    /// a singular matrix ([`HbmError::SingularPivot`]).
    pub fn with_block_size(a: DMatrix<f64>, block: usize) -> Result<Self, HbmError> {
        if block == 0 {
            return Err(HbmError::InvalidParameter {
                name: "LU block size",
                bound: ">= 1",
                value: 0.0,
            });
        }
        let mut lu = Self {
            lu: DMatrix::zeros(0, 0),
            piv: Vec::new(),
            block,
        };
        lu.lu = a;
        lu.factor_in_place()?;
        Ok(lu)
    }

    /// A factorisation of the `0 × 0` matrix, to be filled by [`BlockedLu::refactor`] (which
    /// then reuses its storage).
    pub fn empty() -> Self {
        Self {
            lu: DMatrix::zeros(0, 0),
            piv: Vec::new(),
            block: DEFAULT_LU_BLOCK,
        }
    }

    /// Factor `a` into this object's storage (no allocation when the size is unchanged).
    ///
    /// # Errors
    /// As [`BlockedLu::with_block_size`]; after an error the factors are unusable until the
    /// next successful call.
    pub fn refactor(&mut self, a: &DMatrix<f64>) -> Result<(), HbmError> {
        if self.lu.shape() == a.shape() {
            self.lu.copy_from(a);
        } else {
            self.lu = a.clone();
        }
        self.factor_in_place()
    }

    /// Order `n` of the factored matrix.
    pub fn dim(&self) -> usize {
        self.lu.nrows()
    }

    /// The block width `nb` used.
    pub fn block_size(&self) -> usize {
        self.block
    }

    /// The row interchanges: at step `k`, rows `k` and `pivots()[k]` were swapped.
    pub fn pivots(&self) -> &[usize] {
        &self.piv
    }

    /// The unit lower triangular factor `L`.
    pub fn l(&self) -> DMatrix<f64> {
        let n = self.dim();
        DMatrix::from_fn(n, n, |i, j| match i.cmp(&j) {
            std::cmp::Ordering::Greater => self.lu[(i, j)],
            std::cmp::Ordering::Equal => 1.0,
            std::cmp::Ordering::Less => 0.0,
        })
    }

    /// The upper triangular factor `U`.
    pub fn u(&self) -> DMatrix<f64> {
        let n = self.dim();
        DMatrix::from_fn(n, n, |i, j| if i <= j { self.lu[(i, j)] } else { 0.0 })
    }

    /// `P a`: the rows of `a` interchanged as in the factorisation (so `P A = L U`).
    ///
    /// # Errors
    /// `a` has not [`dim`](Self::dim) rows.
    pub fn permute_rows(&self, a: &DMatrix<f64>) -> Result<DMatrix<f64>, HbmError> {
        check_len("matrix to permute (rows)", self.dim(), a.nrows())?;
        let mut pa = a.clone();
        for (k, &p) in self.piv.iter().enumerate() {
            if p != k {
                pa.swap_rows(k, p);
            }
        }
        Ok(pa)
    }

    /// Solve `A x = b` in place (`b` becomes `x`).
    ///
    /// # Errors
    /// `b` has not [`dim`](Self::dim) entries.
    pub fn solve_mut(&self, b: &mut [f64]) -> Result<(), HbmError> {
        let n = self.dim();
        check_len("LU right-hand side", n, b.len())?;
        for (k, &p) in self.piv.iter().enumerate() {
            b.swap(k, p);
        }
        let a = self.lu.as_slice();
        // L y = P b, L unit lower triangular, column by column
        for k in 0..n {
            let x = b[k];
            let (_, below) = b.split_at_mut(k + 1);
            for (y, l) in below.iter_mut().zip(&a[k * n + k + 1..(k + 1) * n]) {
                *y -= l * x;
            }
        }
        // U x = y, column by column from the last
        for k in (0..n).rev() {
            b[k] /= a[k * n + k];
            let x = b[k];
            for (y, u) in b[..k].iter_mut().zip(&a[k * n..k * n + k]) {
                *y -= u * x;
            }
        }
        Ok(())
    }

    /// Solve `A X = B` for several right-hand sides (the columns of `b`) in place.
    ///
    /// # Errors
    /// `b` has not [`dim`](Self::dim) rows.
    pub fn solve_matrix_mut(&self, b: &mut DMatrix<f64>) -> Result<(), HbmError> {
        check_len("LU right-hand sides (rows)", self.dim(), b.nrows())?;
        for mut col in b.column_iter_mut() {
            self.solve_mut(col.as_mut_slice())?;
        }
        Ok(())
    }

    /// The blocked elimination of the module docs on `self.lu`.
    fn factor_in_place(&mut self) -> Result<(), HbmError> {
        let (n, ncols) = self.lu.shape();
        check_len("LU matrix columns (square)", n, ncols)?;
        self.piv.clear();
        self.piv.resize(n, 0);
        if let Some(i) = self.lu.iter().position(|v| !v.is_finite()) {
            return Err(HbmError::NonFiniteMatrix { column: i / n });
        }
        let nb = self.block;
        let mut j0 = 0;
        while j0 < n {
            let b = nb.min(n - j0);
            factor_panel(&mut self.lu, j0, b, &mut self.piv)?;
            let data = self.lu.as_mut_slice();
            // the panel's interchanges in the columns left and right of it
            swap_rows(data, n, &self.piv, j0..j0 + b, (0..j0).chain(j0 + b..n));
            if j0 + b < n {
                // U12 = L11⁻¹ A12
                let (left, right) = data.split_at_mut((j0 + b) * n);
                for col in right.chunks_exact_mut(n) {
                    for k in 0..b {
                        let x = col[j0 + k];
                        let l = &left[(j0 + k) * n + j0 + k + 1..(j0 + k) * n + j0 + b];
                        for (y, l) in col[j0 + k + 1..j0 + b].iter_mut().zip(l) {
                            *y -= l * x;
                        }
                    }
                }
                // A22 -= L21 U12
                let (panel, mut trailing) = self.lu.columns_range_pair_mut(j0..j0 + b, j0 + b..n);
                let l21 = panel.rows_range(j0 + b..n);
                let (u12, mut a22) = trailing.rows_range_pair_mut(j0..j0 + b, j0 + b..n);
                a22.gemm(-1.0, &l21, &u12, 1.0);
            }
            j0 += b;
        }
        // overflow in the last updates can leave a non-finite entry the pivot search missed
        if let Some(i) = self.lu.iter().position(|v| !v.is_finite()) {
            return Err(HbmError::NonFiniteMatrix { column: i / n });
        }
        Ok(())
    }
}

/// Panels of at most this many columns are factored unblocked ([`factor_columns`]).
const PANEL_LEAF: usize = 8;

/// LU with partial pivoting of the panel `a[j0.., j0..j0 + b]`, row swaps only within the
/// panel's columns, by recursive halving (Toledo 1997): factor the left half, carry its
/// interchanges and its `U12 = L11⁻¹ A12`, `A22 −= L21 U12` (`gemm`) into the right half,
/// factor the right half below, carry its interchanges back into the left half. Halves of at
/// most [`PANEL_LEAF`] columns are eliminated column by column ([`factor_columns`]). The
/// pivots are those of the column-by-column elimination in exact arithmetic.
fn factor_panel(
    a: &mut DMatrix<f64>,
    j0: usize,
    b: usize,
    piv: &mut [usize],
) -> Result<(), HbmError> {
    let n = a.nrows();
    if b <= PANEL_LEAF {
        return factor_columns(a.as_mut_slice(), n, j0, b, piv);
    }
    let h = b / 2;
    let (c1, c2) = (j0 + h, j0 + b);
    factor_panel(a, j0, h, piv)?;
    let data = a.as_mut_slice();
    swap_rows(data, n, piv, j0..c1, c1..c2);
    // U12 = L11⁻¹ A12 (rows j0..c1 of the right half)
    let (left, right) = data.split_at_mut(c1 * n);
    for col in right.chunks_exact_mut(n).take(c2 - c1) {
        for k in 0..h {
            let x = col[j0 + k];
            let l = &left[(j0 + k) * n + j0 + k + 1..(j0 + k) * n + c1];
            for (y, l) in col[j0 + k + 1..c1].iter_mut().zip(l) {
                *y -= l * x;
            }
        }
    }
    {
        let (lp, mut rp) = a.columns_range_pair_mut(j0..c1, c1..c2);
        let l21 = lp.rows_range(c1..n);
        let (u12, mut a22) = rp.rows_range_pair_mut(j0..c1, c1..n);
        a22.gemm(-1.0, &l21, &u12, 1.0);
    }
    factor_panel(a, c1, b - h, piv)?;
    let data = a.as_mut_slice();
    swap_rows(data, n, piv, c1..c2, j0..c1);
    Ok(())
}

/// Unblocked LU with partial pivoting of the panel `data[j0.., j0..j0 + b]` (column-major,
/// leading dimension `n`); row swaps only within the panel's columns.
fn factor_columns(
    data: &mut [f64],
    n: usize,
    j0: usize,
    b: usize,
    piv: &mut [usize],
) -> Result<(), HbmError> {
    for k in j0..j0 + b {
        let col = &data[k * n..(k + 1) * n];
        let mut p = k;
        let mut best = 0.0_f64;
        for (r, v) in col.iter().enumerate().skip(k) {
            if !v.is_finite() {
                return Err(HbmError::NonFiniteMatrix { column: k });
            }
            if v.abs() > best {
                best = v.abs();
                p = r;
            }
        }
        if best == 0.0 {
            return Err(HbmError::SingularPivot { column: k });
        }
        piv[k] = p;
        if p != k {
            for c in j0..j0 + b {
                data.swap(c * n + k, c * n + p);
            }
        }
        let inv = 1.0 / data[k * n + k];
        for v in &mut data[k * n + k + 1..(k + 1) * n] {
            *v *= inv;
        }
        // rank-1 update of the panel's columns right of k
        let (left, right) = data.split_at_mut((k + 1) * n);
        let l = &left[k * n + k + 1..(k + 1) * n];
        for col in right.chunks_exact_mut(n).take(j0 + b - k - 1) {
            let u = col[k];
            for (y, l) in col[k + 1..].iter_mut().zip(l) {
                *y -= l * u;
            }
        }
    }
    Ok(())
}

fn check_len(what: &'static str, expected: usize, got: usize) -> Result<(), HbmError> {
    if expected == got {
        Ok(())
    } else {
        Err(HbmError::DimensionMismatch {
            what,
            expected,
            got,
        })
    }
}

/// Apply the interchanges `piv[k]` (rows `k` and `piv[k]`, for `k` in `steps`, in order) to the
/// columns `cols` of the column-major `data` with `n` rows.
fn swap_rows(
    data: &mut [f64],
    n: usize,
    piv: &[usize],
    steps: std::ops::Range<usize>,
    cols: impl Iterator<Item = usize> + Clone,
) {
    for k in steps {
        let p = piv[k];
        if p != k {
            for c in cols.clone() {
                data.swap(c * n + k, c * n + p);
            }
        }
    }
}
