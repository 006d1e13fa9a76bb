//! Floquet multipliers, their conditioning, and the classification of unit-circle crossings.

use crate::error::{OrbitError, Result};
use math::DetMath;
use nalgebra::{Complex, DMatrix, DVector, Schur};

/// Floquet multipliers of a monodromy matrix.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Floquet {
    /// Multipliers `μ` as `[Re μ, Im μ]`, sorted by decreasing modulus.
    pub multipliers: Vec<[f64; 2]>,
    /// Eigenvalue condition number `κ(μ) = ‖x‖‖y‖/|yᴴx|` of each multiplier (`x`, `y` its right
    /// and left eigenvectors): a perturbation `E` of the monodromy moves `μ` by about
    /// `κ(μ) ‖E‖`. `∞` for a (numerically) defective multiplier.
    pub condition: Vec<f64>,
    /// `max |μ|`.
    pub max_modulus: f64,
    /// `max |μ| ≤ 1 + tolerance`.
    pub stable: bool,
    /// `det(Φ + I)`: changes sign when a real multiplier crosses −1 (period doubling).
    pub test_period_doubling: f64,
    /// `det(Φ − I)`: changes sign when a real multiplier crosses +1 (fold, branch point).
    pub test_fold: f64,
    /// `Π_{i<j} (μ_i μ_j − 1)` (real): changes sign when a complex pair crosses the unit circle
    /// (Neimark–Sacker), and also at real crossings.
    pub test_neimark_sacker: f64,
}

/// The one stability type of a periodic orbit (complex multipliers, largest modulus, verdict at
/// the one threshold), defined in `system` so that the harmonic-balance leaf returns it too
/// (`hbm::Stability` is this type).
pub use system::Stability;

impl Floquet {
    /// The multipliers and verdict as the one [`Stability`] type.
    pub fn stability(&self) -> Stability {
        Stability {
            multipliers: self.multipliers.clone(),
            max_modulus: self.max_modulus,
            stable: self.stable,
        }
    }
}

/// A crossing of the unit circle between two points of a branch.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Crossing {
    /// A real multiplier crosses `+1` (saddle-node / fold, or a branch point).
    Fold,
    /// A real multiplier crosses `−1` (flip).
    PeriodDoubling,
    /// A complex pair crosses the unit circle (torus bifurcation).
    NeimarkSacker,
}

/// Multipliers outside the unit circle, by kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct OutsideCount {
    /// Real and `> 1`.
    pub real_plus: usize,
    /// Real and `< −1`.
    pub real_minus: usize,
    /// Complex (`|Im μ| > 10⁻⁷ max(1, |μ|)`) with `|μ| > 1`.
    pub complex: usize,
}

impl OutsideCount {
    /// Counts the multipliers with `|μ| > 1 + tol`.
    pub fn of(multipliers: &[[f64; 2]], tol: f64) -> Self {
        let mut c = Self::default();
        for &[re, im] in multipliers {
            let r = re.dhypot(im);
            if r <= 1.0 + tol {
                continue;
            }
            if im.abs() > 1e-7 * r.max(1.0) {
                c.complex += 1;
            } else if re > 0.0 {
                c.real_plus += 1;
            } else {
                c.real_minus += 1;
            }
        }
        c
    }
    /// All of them.
    pub fn total(&self) -> usize {
        self.real_plus + self.real_minus + self.complex
    }
}

/// The crossings between two sets of multipliers: the kinds whose count outside the unit circle
/// changed in the same sense as the total (a collision of two real multipliers that leaves them
/// a complex pair outside the circle changes no total and is no crossing).
pub fn classify_crossing(before: &[[f64; 2]], after: &[[f64; 2]], tol: f64) -> Vec<Crossing> {
    let (a, b) = (OutsideCount::of(before, tol), OutsideCount::of(after, tol));
    let dt = b.total() as i64 - a.total() as i64;
    if dt == 0 {
        return vec![];
    }
    let mut out = vec![];
    for (da, kind) in [
        (b.real_plus as i64 - a.real_plus as i64, Crossing::Fold),
        (
            b.real_minus as i64 - a.real_minus as i64,
            Crossing::PeriodDoubling,
        ),
        (b.complex as i64 - a.complex as i64, Crossing::NeimarkSacker),
    ] {
        if da != 0 && da.signum() == dt.signum() {
            out.push(kind);
        }
    }
    out
}

/// Stability tolerance on `|μ| − 1`: the workspace's one threshold
/// ([`system::STABILITY_TOLERANCE`]).
pub use system::STABILITY_TOLERANCE;

/// Floquet multipliers of `monodromy` with their condition numbers and the test functions.
///
/// # Errors
/// Non-square or non-finite matrix, eigenvalue iteration failure.
pub fn floquet(monodromy: &DMatrix<f64>) -> Result<Floquet> {
    let m = monodromy.nrows();
    if monodromy.ncols() != m || m == 0 {
        return Err(OrbitError::DimensionMismatch {
            what: "monodromy (square)",
            expected: m * m,
            got: monodromy.len(),
        });
    }
    if monodromy.iter().any(|v| !v.is_finite()) {
        return Err(OrbitError::NonFinite {
            what: "monodromy",
            time: 0.0,
        });
    }
    let schur = Schur::try_new(monodromy.clone(), f64::EPSILON, 10_000).ok_or(OrbitError::Eigen)?;
    let ev = schur.complex_eigenvalues();
    let mut mu: Vec<Complex<f64>> = ev.iter().copied().collect();
    mu.sort_by(|a, b| b.norm().total_cmp(&a.norm()).then(b.im.total_cmp(&a.im)));
    let condition = mu.iter().map(|&l| eigen_condition(monodromy, l)).collect();
    let multipliers: Vec<[f64; 2]> = mu.iter().map(|z| [z.re, z.im]).collect();
    let max_modulus = system::max_modulus(&multipliers);
    let id = DMatrix::<f64>::identity(m, m);
    let test_period_doubling = (monodromy + &id).lu().determinant();
    let test_fold = (monodromy - &id).lu().determinant();
    let mut ns = Complex::new(1.0, 0.0);
    for i in 0..m {
        for j in i + 1..m {
            ns *= mu[i] * mu[j] - 1.0;
        }
    }
    Ok(Floquet {
        multipliers,
        condition,
        max_modulus,
        stable: system::is_stable_multiplier(max_modulus),
        test_period_doubling,
        test_fold,
        test_neimark_sacker: ns.re,
    })
}

/// Inverse iteration for an eigenvector of `a` (complex) near `lambda`.
fn inverse_iteration(
    a: &DMatrix<Complex<f64>>,
    lambda: Complex<f64>,
) -> Option<DVector<Complex<f64>>> {
    let m = a.nrows();
    let shift = lambda + Complex::new(1.0, 0.7) * 1e-10 * (1.0 + lambda.norm());
    let mut s = a.clone();
    for i in 0..m {
        s[(i, i)] -= shift;
    }
    let lu = s.lu();
    let mut v = DVector::from_fn(m, |i, _| {
        Complex::new(1.0 + 0.37 * i as f64, 0.11 * i as f64)
    });
    for _ in 0..4 {
        let w = lu.solve(&v)?;
        let n = w.norm();
        if !(n.is_finite() && n > 0.0) {
            return None;
        }
        v = w / Complex::new(n, 0.0);
    }
    Some(v)
}

/// `κ(λ) = ‖x‖‖y‖/|yᴴx|` by inverse iteration (right on `A`, left on `Aᴴ`).
fn eigen_condition(a: &DMatrix<f64>, lambda: Complex<f64>) -> f64 {
    let ac = a.map(|v| Complex::new(v, 0.0));
    let x = inverse_iteration(&ac, lambda);
    let y = inverse_iteration(&ac.adjoint(), lambda.conj());
    match (x, y) {
        (Some(x), Some(y)) => {
            let d = y.dotc(&x).norm();
            if d > 0.0 {
                x.norm() * y.norm() / d
            } else {
                f64::INFINITY
            }
        }
        _ => f64::INFINITY,
    }
}

/// A real unit eigenvector of `a` for the real eigenvalue nearest `lambda` (inverse iteration),
/// e.g. the `−1` eigenvector at a period doubling.
///
/// # Errors
/// Non-square or non-finite matrix, or the iteration fails.
pub fn real_eigenvector(a: &DMatrix<f64>, lambda: f64) -> Result<DVector<f64>> {
    let m = a.nrows();
    if a.ncols() != m || m == 0 || a.iter().any(|v| !v.is_finite()) || !lambda.is_finite() {
        return Err(OrbitError::Eigen);
    }
    let mut s = a.clone();
    let shift = lambda + 1e-10 * (1.0 + lambda.abs());
    for i in 0..m {
        s[(i, i)] -= shift;
    }
    let lu = s.lu();
    let mut v = DVector::from_fn(m, |i, _| 1.0 + 0.37 * i as f64);
    for _ in 0..6 {
        let w = lu.solve(&v).ok_or(OrbitError::Eigen)?;
        let n = w.norm();
        if !(n.is_finite() && n > 0.0) {
            return Err(OrbitError::Eigen);
        }
        v = w / n;
    }
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The one stability type: largest modulus and the verdict at the one threshold, from any
    /// multipliers and from a monodromy.
    #[test]
    fn stability_type_and_threshold() {
        // |0.6 + 0.8i| = 1 exactly: on the circle, stable; 1 + 2·tol: unstable
        let s = Stability::from_multipliers(vec![[0.5, 0.0], [0.6, 0.8], [0.6, -0.8]]);
        assert!((s.max_modulus - 1.0).abs() < 1e-16 && s.stable);
        let u = Stability::from_multipliers(vec![[-(1.0 + 2.0 * STABILITY_TOLERANCE), 0.0]]);
        assert!(!u.stable);
        let none = Stability::from_multipliers(vec![]);
        assert!(none.max_modulus == 0.0 && none.stable);
        // a monodromy with μ = ±i√1.2: outside the circle
        let m = DMatrix::from_row_slice(2, 2, &[0.0, -1.2, 1.0, 0.0]);
        let f = floquet(&m).unwrap();
        let st = f.stability();
        assert_eq!(st, Stability::from_multipliers(f.multipliers.clone()));
        assert!(!st.stable && (st.max_modulus - 1.2f64.sqrt()).abs() < 1e-14);
    }

    #[test]
    fn multipliers_and_condition_of_known_matrices() {
        // a scaled rotation: μ = 0.9 e^{±0.3i}, normal, κ = 1
        let (c, s) = (0.9 * 0.3_f64.dcos(), 0.9 * 0.3_f64.dsin());
        let f = floquet(&DMatrix::from_row_slice(2, 2, &[c, -s, s, c])).unwrap();
        assert!((f.max_modulus - 0.9).abs() < 1e-14);
        assert!(f.stable);
        assert!((f.multipliers[0][1].abs() - s).abs() < 1e-14);
        for k in &f.condition {
            assert!((k - 1.0).abs() < 1e-6, "{k}");
        }
        // non-normal: [[1.2, 100], [0, −0.5]]: κ = ‖x‖‖y‖/|yᴴx| ≫ 1
        let f = floquet(&DMatrix::from_row_slice(2, 2, &[1.2, 100.0, 0.0, -0.5])).unwrap();
        assert!(!f.stable);
        assert!((f.multipliers[0][0] - 1.2).abs() < 1e-12);
        // κ = sqrt(1 + (100/1.7)²) for both eigenvalues of a 2×2 upper triangular matrix
        let k = (1.0 + (100.0_f64 / 1.7).powi(2)).sqrt();
        for c in &f.condition {
            assert!((c / k - 1.0).abs() < 1e-6, "{c} vs {k}");
        }
        // test functions: det(Φ + I) = (2.2)(0.5), det(Φ − I) = (0.2)(−1.5)
        assert!((f.test_period_doubling - 1.1).abs() < 1e-12);
        assert!((f.test_fold + 0.3).abs() < 1e-12);
        assert!(floquet(&DMatrix::from_element(1, 1, f64::NAN)).is_err());
        assert!(floquet(&DMatrix::zeros(2, 3)).is_err());
    }

    #[test]
    fn crossings_are_classified() {
        let inside = [[0.5, 0.0], [-0.5, 0.0]];
        assert_eq!(
            classify_crossing(&inside, &[[1.1, 0.0], [-0.5, 0.0]], 1e-9),
            vec![Crossing::Fold]
        );
        assert_eq!(
            classify_crossing(&inside, &[[0.5, 0.0], [-1.1, 0.0]], 1e-9),
            vec![Crossing::PeriodDoubling]
        );
        assert_eq!(
            classify_crossing(&[[0.5, 0.5], [0.5, -0.5]], &[[0.8, 0.8], [0.8, -0.8]], 1e-9),
            vec![Crossing::NeimarkSacker]
        );
        // stabilisation is a crossing too; a real collision outside the circle is not
        assert_eq!(
            classify_crossing(&[[0.5, 0.0], [-1.1, 0.0]], &inside, 1e-9),
            vec![Crossing::PeriodDoubling]
        );
        assert!(
            classify_crossing(&[[1.5, 0.0], [1.2, 0.0]], &[[1.3, 0.2], [1.3, -0.2]], 1e-9)
                .is_empty()
        );
        let c = OutsideCount::of(&[[1.5, 0.0], [-2.0, 0.0], [0.0, 1.5], [0.0, -1.5]], 1e-9);
        assert_eq!(
            (c.real_plus, c.real_minus, c.complex, c.total()),
            (1, 1, 2, 4)
        );
    }

    #[test]
    fn real_eigenvector_of_minus_one() {
        let a = DMatrix::from_row_slice(2, 2, &[-1.0, 0.3, 0.0, 0.5]);
        let v = real_eigenvector(&a, -1.0).unwrap();
        let r = &a * &v + &v;
        assert!(r.amax() < 1e-8, "{r}");
        assert!(real_eigenvector(&DMatrix::from_element(1, 1, f64::NAN), -1.0).is_err());
    }
}
