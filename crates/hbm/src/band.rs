//! A square band matrix and its LU factorisation with partial pivoting (the preconditioner of
//! Newton–Krylov for an ordered harmonic basis).
//!
//! Storage: `kl` sub-diagonals, `ku` super-diagonals, and `kl` more super-diagonals for the
//! fill that row interchanges bring (as LAPACK `dgbtrf`): entry `(i, j)`, `i − kl ≤ j ≤
//! i + kl + ku`, at `a[i·w + (j + kl − i)]`, `w = 2 kl + ku + 1`. Factorisation costs
//! `O(n · kl · (kl + ku))`, a solve `O(n · (2 kl + ku))`.
//!
//! The factors are kept in the LAPACK `gbtf2` form: the multipliers of step `k` stay in the
//! rows they were computed in, and the solve replays interchange `k` and elimination `k` in
//! order, so earlier multipliers are never permuted.

/// A band matrix, filled with [`BandLu::add`] and factorised in place by [`BandLu::factor`].
#[derive(Debug, Clone)]
pub(crate) struct BandLu {
    n: usize,
    kl: usize,
    ku: usize,
    w: usize,
    a: Vec<f64>,
    piv: Vec<usize>,
}

impl BandLu {
    /// The zero `n × n` matrix with `kl` sub- and `ku` super-diagonals.
    pub(crate) fn zeros(n: usize, kl: usize, ku: usize) -> Self {
        let w = 2 * kl + ku + 1;
        Self {
            n,
            kl,
            ku,
            w,
            a: vec![0.0; n * w],
            piv: Vec::new(),
        }
    }

    /// Storage index of `(i, j)` if it lies in the factor's band.
    #[inline]
    fn at(&self, i: usize, j: usize) -> Option<usize> {
        (i < self.n && j < self.n && j + self.kl >= i && j + self.kl - i < self.w)
            .then(|| i * self.w + (j + self.kl - i))
    }

    /// `A[i, j] += v`; `false` (nothing added) outside the declared band `i − kl ≤ j ≤ i + ku`.
    pub(crate) fn add(&mut self, i: usize, j: usize, v: f64) -> bool {
        if j > i + self.ku || j + self.kl < i {
            return false;
        }
        match self.at(i, j) {
            Some(x) => {
                self.a[x] += v;
                true
            }
            None => false,
        }
    }

    /// Factorise `P A = L U` in place; `false` for a zero or non-finite pivot (singular).
    pub(crate) fn factor(&mut self) -> bool {
        let (n, kl, ku, w) = (self.n, self.kl, self.ku, self.w);
        self.piv = Vec::with_capacity(n);
        for k in 0..n {
            let last_row = (k + kl).min(n - 1);
            let last_col = (k + kl + ku).min(n - 1);
            // pivot: the largest |A[r, k]| over the rows the band reaches
            let mut p = k;
            let mut best = self.a[k * w + kl].abs();
            for r in k + 1..=last_row {
                let v = self.a[r * w + (k + kl - r)].abs();
                if v > best {
                    best = v;
                    p = r;
                }
            }
            if !(best > 0.0 && best.is_finite()) {
                return false;
            }
            self.piv.push(p);
            if p != k {
                for j in k..=last_col {
                    self.a.swap(k * w + (j + kl - k), p * w + (j + kl - p));
                }
            }
            let d = self.a[k * w + kl];
            for r in k + 1..=last_row {
                let x = r * w + (k + kl - r);
                let l = self.a[x] / d;
                self.a[x] = l;
                if l != 0.0 {
                    for j in k + 1..=last_col {
                        self.a[r * w + (j + kl - r)] -= l * self.a[k * w + (j + kl - k)];
                    }
                }
            }
        }
        true
    }

    /// `x ← A⁻¹ x` with the factors of [`factor`](Self::factor) (which must have returned true).
    pub(crate) fn solve(&self, x: &mut [f64]) {
        let (n, kl, ku, w) = (self.n, self.kl, self.ku, self.w);
        for k in 0..n.min(self.piv.len()) {
            let p = self.piv[k];
            if p != k {
                x.swap(k, p);
            }
            let xk = x[k];
            for r in k + 1..=(k + kl).min(n - 1) {
                x[r] -= self.a[r * w + (k + kl - r)] * xk;
            }
        }
        for i in (0..n).rev() {
            let mut s = x[i];
            for j in i + 1..=(i + kl + ku).min(n - 1) {
                s -= self.a[i * w + (j + kl - i)] * x[j];
            }
            x[i] = s / self.a[i * w + kl];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{DMatrix, DVector};

    /// A deterministic pseudo-random number in [−1, 1).
    fn lcg(state: &mut u64) -> f64 {
        *state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((*state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }

    fn check(n: usize, kl: usize, ku: usize, zero_diagonal: bool, seed: u64) {
        let mut s = seed;
        let mut band = BandLu::zeros(n, kl, ku);
        let mut dense = DMatrix::zeros(n, n);
        for i in 0..n {
            for j in i.saturating_sub(kl)..=(i + ku).min(n - 1) {
                let v = if zero_diagonal && i == j {
                    0.0
                } else {
                    lcg(&mut s)
                };
                assert!(band.add(i, j, v));
                dense[(i, j)] = v;
            }
        }
        // outside the declared band: refused
        if n > kl + 1 {
            assert!(!band.add(kl + 1, 0, 1.0));
        }
        if n > ku + 1 {
            assert!(!band.add(0, ku + 1, 1.0));
        }
        let b: Vec<f64> = (0..n).map(|_| lcg(&mut s)).collect();
        assert!(band.factor(), "n {n} kl {kl} ku {ku}");
        let mut x = b.clone();
        band.solve(&mut x);
        let reference = dense
            .clone()
            .lu()
            .solve(&DVector::from_vec(b.clone()))
            .unwrap();
        let err = x
            .iter()
            .zip(reference.iter())
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        let scale = reference.iter().fold(1.0f64, |m, v| m.max(v.abs()));
        assert!(err < 1e-10 * scale, "n {n} kl {kl} ku {ku}: {err}");
        // and the residual of the band solve itself
        let r = &dense * DVector::from_vec(x) - DVector::from_vec(b);
        assert!(r.amax() < 1e-10 * scale, "{}", r.amax());
    }

    #[test]
    fn solves_like_dense_lu_for_any_bandwidths() {
        for (n, kl, ku) in [
            (1, 0, 0),
            (5, 1, 1),
            (12, 3, 2),
            (40, 5, 7),
            (30, 0, 4),
            (30, 4, 0),
        ] {
            check(n, kl, ku, false, 7 + n as u64);
        }
    }

    #[test]
    fn pivots_across_a_zero_diagonal() {
        // every diagonal entry zero: no factorisation without row interchanges exists
        check(20, 2, 2, true, 11);
        check(9, 1, 3, true, 3);
    }

    #[test]
    fn a_singular_matrix_is_reported() {
        let mut z = BandLu::zeros(4, 1, 1);
        for i in 0..4 {
            z.add(i, i, 1.0);
        }
        // row 2 zero
        let mut s = z.clone();
        s.a[2 * s.w + s.kl] = 0.0;
        assert!(z.factor());
        assert!(!s.factor());
        let mut nan = BandLu::zeros(2, 0, 0);
        nan.add(0, 0, f64::NAN);
        nan.add(1, 1, 1.0);
        assert!(!nan.factor());
    }
}
