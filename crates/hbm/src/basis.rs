//! Harmonic bases: which multiples `k ω` of the base frequency are retained.

use crate::HbmError;

/// A set of harmonics `k ω` (`k ≥ 1`) of one base frequency `ω`, always with the constant term.
///
/// The unknowns of one degree of freedom are ordered
/// `[a_0, a_{k_1}, b_{k_1}, a_{k_2}, b_{k_2}, …]` for
/// `q(t) = a_0 + Σ_j a_{k_j} cos(k_j ω t) + b_{k_j} sin(k_j ω t)`, with `k_1 < k_2 < …`.
/// The basis only stores the integers `k_j`: the frequency `ω` is chosen when a
/// [`HbmProblem`](crate::HbmProblem) is built, so any basis (including Liu's sparse one) can be
/// used with any base frequency.
#[derive(Debug, Clone, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Basis {
    harmonics: Vec<usize>,
}

/// Whether a coefficient multiplies the constant, a cosine or a sine.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum CoefficientKind {
    /// The constant term `a_0`.
    Constant,
    /// `a_k cos(k ω t)`.
    Cos,
    /// `b_k sin(k ω t)`.
    Sin,
}

impl Basis {
    /// The full basis `0, 1, …, H` (`2H + 1` coefficients per DOF).
    ///
    /// # Errors
    /// `h == 0` is rejected (use [`Basis::from_harmonics`] with an empty list for a static
    /// problem).
    pub fn full(h: usize) -> Result<Self, HbmError> {
        if h == 0 {
            return Err(HbmError::InvalidParameter {
                name: "H",
                bound: ">= 1",
                value: 0.0,
            });
        }
        Ok(Self {
            harmonics: (1..=h).collect(),
        })
    }

    /// Any set of harmonics; zeros are dropped (the constant is always present), the rest sorted
    /// and deduplicated.
    ///
    /// # Errors
    /// Harmonics above `2^20` are rejected.
    pub fn from_harmonics<I: IntoIterator<Item = usize>>(harmonics: I) -> Result<Self, HbmError> {
        let mut h: Vec<usize> = harmonics.into_iter().filter(|&k| k > 0).collect();
        h.sort_unstable();
        h.dedup();
        if let Some(&k) = h.last() {
            if k > 1 << 20 {
                return Err(HbmError::InvalidBasis {
                    reason: format!("harmonic {k} is above 2^20"),
                });
            }
        }
        Ok(Self { harmonics: h })
    }

    /// The sparse multifrequency basis of Liu et al. (2021), Eq. (13).
    ///
    /// With base frequency `ω = ω_c` and `ω_e = Z_2 ω_c` (`Z_2` a positive integer), the
    /// response holds `ω_c`, `2ω_c` and `r ω_e ± {0, 1, 2} ω_c` for `r = 1..R`, i.e. the harmonics
    /// `1, 2` and `r Z_2 + {-2, -1, 0, 1, 2}` of `ω_c`. For `Z_2 ≥ 5` there are `2 + 5R` distinct
    /// harmonics, i.e. `10R + 5` unknowns per DOF (15 for `R = 1`, as in the paper). For smaller
    /// `Z_2` coinciding or non-positive harmonics are merged/dropped, so there are fewer.
    ///
    /// # Errors
    /// `R = 0` or `Z_2 = 0`.
    pub fn liu_multifrequency(r: usize, z2: usize) -> Result<Self, HbmError> {
        if r == 0 {
            return Err(HbmError::InvalidParameter {
                name: "R",
                bound: ">= 1",
                value: 0.0,
            });
        }
        if z2 == 0 {
            return Err(HbmError::InvalidParameter {
                name: "Z2",
                bound: ">= 1",
                value: 0.0,
            });
        }
        let mut h = vec![1, 2];
        for ri in 1..=r {
            let c = ri * z2;
            for d in [-2i64, -1, 0, 1, 2] {
                let k = c as i64 + d;
                if k > 0 {
                    h.push(k as usize);
                }
            }
        }
        Self::from_harmonics(h)
    }

    /// The retained harmonics `k_j ≥ 1`, ascending (the constant is implicit).
    pub fn harmonics(&self) -> &[usize] {
        &self.harmonics
    }

    /// Number of coefficients per degree of freedom, `1 + 2 × harmonics().len()`.
    pub fn n_coefficients(&self) -> usize {
        1 + 2 * self.harmonics.len()
    }

    /// Largest retained harmonic (0 for the constant-only basis).
    pub fn max_harmonic(&self) -> usize {
        self.harmonics.last().copied().unwrap_or(0)
    }

    /// Harmonic index and kind of coefficient `c` (`c < n_coefficients()`).
    pub fn coefficient(&self, c: usize) -> Option<(usize, CoefficientKind)> {
        if c == 0 {
            return Some((0, CoefficientKind::Constant));
        }
        let j = (c - 1) / 2;
        let k = *self.harmonics.get(j)?;
        Some((
            k,
            if (c - 1) % 2 == 0 {
                CoefficientKind::Cos
            } else {
                CoefficientKind::Sin
            },
        ))
    }

    /// Default AFT grid size: the smallest power of two `N ≥ max(4 k_max + 1, 16)`.
    ///
    /// With `N > (p + 1) k_max` the projection of a polynomial nonlinearity of degree `p` onto
    /// the basis is free of aliasing; the default covers cubic terms (`p = 3`) and keeps the
    /// Jacobian spectra up to `2 k_max` unaliased. Non-smooth forces (dead zones) always alias a
    /// little: raise `N` with [`HbmProblem::with_grid_size`](crate::HbmProblem::with_grid_size).
    pub fn default_grid_size(&self) -> usize {
        (4 * self.max_harmonic() + 1).max(16).next_power_of_two()
    }

    /// The smallest admissible grid size, `2 k_max + 1`.
    pub fn min_grid_size(&self) -> usize {
        2 * self.max_harmonic() + 1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn liu_basis_has_fifteen_unknowns_for_r1() {
        // Liu et al. 2021, Sect. 3: "R ... is equal to 1, resulting in 15 unknown variables".
        let b = Basis::liu_multifrequency(1, 30).unwrap();
        assert_eq!(b.n_coefficients(), 15);
        assert_eq!(b.harmonics(), &[1, 2, 28, 29, 30, 31, 32]);
        // 10R + 5 in general when Z2 >= 5
        assert_eq!(
            Basis::liu_multifrequency(3, 7).unwrap().n_coefficients(),
            35
        );
        // small Z2 merges harmonics
        assert_eq!(
            Basis::liu_multifrequency(1, 2).unwrap().harmonics(),
            &[1, 2, 3, 4]
        );
        assert!(Basis::liu_multifrequency(0, 3).is_err());
        assert!(Basis::liu_multifrequency(1, 0).is_err());
    }

    #[test]
    fn full_basis_and_grid() {
        let b = Basis::full(200).unwrap();
        assert_eq!(b.n_coefficients(), 401);
        assert_eq!(b.default_grid_size(), 1024);
        assert_eq!(Basis::full(1).unwrap().default_grid_size(), 16);
        assert_eq!(b.coefficient(0), Some((0, CoefficientKind::Constant)));
        assert_eq!(b.coefficient(3), Some((2, CoefficientKind::Cos)));
        assert_eq!(b.coefficient(4), Some((2, CoefficientKind::Sin)));
        assert_eq!(b.coefficient(401), None);
        assert!(Basis::full(0).is_err());
        assert_eq!(
            Basis::from_harmonics([0, 3, 1, 3]).unwrap().harmonics(),
            &[1, 3]
        );
    }
}
