//! A short `sin_cos` for inner loops (the time stepping of Liu's Eq. (9), the Duhamel
//! quadrature of Karpov's Eq. (8), the terms of the Chen fractal of Yu's Eq. (3)): Cody–Waite
//! reduction by `π/2` and the Taylor polynomials on `[−π/4, π/4]`.
//!
//! `x = k π/2 + r`, `k = round(2x/π)`, with `π/2 = P₁ + P₂ + P₃` split so that `k P₁` and
//! `k P₂` are exact for `|k| < 2²⁰` (`P₁`, `P₂` carry 33 bits each): `r = ((x − k P₁) − k P₂) −
//! k P₃` has an absolute error of about one unit in the last place of `r`. On `|r| ≤ π/4` the
//! Taylor series of `sin` through `r¹⁷` and of `cos` through `r¹⁸` leave remainders below
//! `(π/4)¹⁹/19! ≈ 8·10⁻²⁰`, so the result is within a few `10⁻¹⁶` of the exact value (tested
//! against [`crate::sin_cos`]): rounding level, at a fraction of the cost of musl's reduction
//! and polynomials. Beyond `|x| = 2¹⁹` (and for NaN, ±∞) it falls back to [`crate::sin_cos`].
//!
//! Deterministic like the rest of the crate (IEEE `+`, `−`, `×`, no contraction), but not the
//! same bits as [`crate::sin_cos`]: a caller chooses one of the two for a quantity and keeps it.
//!
//! ```
//! let (s, c) = geardyn_math::short::sin_cos(1.0);
//! let (s0, c0) = geardyn_math::sin_cos(1.0);
//! assert!((s - s0).abs() <= 3e-16 && (c - c0).abs() <= 3e-16);
//! ```

/// `π/2` to 33 bits.
const P1: f64 = 1.570_796_326_734_125_6;
/// The next 33 bits of `π/2`.
const P2: f64 = 6.077_100_506_303_966e-11;
/// The remainder `π/2 − P₁ − P₂` to 53 bits.
const P3: f64 = 2.022_266_248_795_950_6e-21;
/// `1.5·2⁵²`: adding and subtracting it rounds to the nearest integer (ties to even).
const ROUND: f64 = 6_755_399_441_055_744.0;
/// Largest `|x|` reduced here (`|k| < 2¹⁹`, so `k P₁`, `k P₂` are exact).
const LIMIT: f64 = 524_288.0;

/// `(sin x, cos x)` to a few units of `10⁻¹⁶` (see the module docs).
#[inline(always)]
pub fn sin_cos(x: f64) -> (f64, f64) {
    // NaN and ±∞ go to the fallback
    if x.is_nan() || x.abs() > LIMIT {
        return fallback(x);
    }
    let k = (x * core::f64::consts::FRAC_2_PI + ROUND) - ROUND;
    let r = ((x - k * P1) - k * P2) - k * P3;
    let z = r * r;
    // sin r = r + r z (−1/3! + z (1/5! − …)), cos r = 1 − z/2 + z² (1/4! − z (1/6! − …)),
    // the polynomials in z by Estrin's scheme (short dependency chains)
    let z2 = z * z;
    let z4 = z2 * z2;
    let ps = ((-1.0 / 6.0 + z * (1.0 / 120.0)) + z2 * (-1.0 / 5040.0 + z * (1.0 / 362_880.0)))
        + z4 * ((-1.0 / 39_916_800.0 + z * (1.0 / 6_227_020_800.0))
            + z2 * (-1.0 / 1_307_674_368_000.0 + z * (1.0 / 355_687_428_096_000.0)));
    let pc = ((1.0 / 24.0 + z * (-1.0 / 720.0)) + z2 * (1.0 / 40_320.0 + z * (-1.0 / 3_628_800.0)))
        + z4 * ((1.0 / 479_001_600.0 + z * (-1.0 / 87_178_291_200.0))
            + z2 * (1.0 / 20_922_789_888_000.0 + z * (-1.0 / 6_402_373_705_728_000.0)));
    let s = r + r * z * ps;
    let c = 1.0 - 0.5 * z + z2 * pc;
    // the quadrant q = k mod 4 (k is an integer-valued float below 2¹⁹ in magnitude):
    // (s, c), (c, −s), (−s, −c), (−c, s) for q = 0, 1, 2, 3, without branches (the quadrant
    // is data-dependent, a `match` on it mispredicts): swap on odd q, then flip the sign bits
    let q = (k as i64) as u64;
    let (a, b) = if q & 1 == 0 { (s, c) } else { (c, s) };
    let sin = f64::from_bits(a.to_bits() ^ ((q & 2) << 62));
    let cos = f64::from_bits(b.to_bits() ^ ((q.wrapping_add(1) & 2) << 62));
    (sin, cos)
}

/// The fallback beyond the reduced range: [`crate::sin_cos`], out of line and cold, so that its
/// code does not keep [`sin_cos`] from being inlined into the loops that call it.
#[cold]
#[inline(never)]
fn fallback(x: f64) -> (f64, f64) {
    crate::sin_cos(x)
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::vec::Vec;

    #[test]
    fn constants_split_half_pi() {
        // P1 and P2 carry at most 33 significant bits (k·P exact for |k| < 2^20)
        for p in [P1, P2] {
            assert_eq!(p.to_bits() & ((1u64 << 20) - 1), 0, "{p:e}");
        }
        assert_eq!(
            (P1 + P2 + P3).to_bits(),
            std::f64::consts::FRAC_PI_2.to_bits()
        );
    }

    /// Within 3·10⁻¹⁶ of [`crate::sin_cos`] over the reduced range (dense near 0 and
    /// at the quadrant boundaries, and spread up to the limit); the fallback beyond.
    #[test]
    fn agrees_with_libm_to_rounding_level() {
        let mut worst = 0.0f64;
        let mut xs: Vec<f64> = (0..20_000)
            .map(|i| -30.0 + 60.0 * f64::from(i) / 20_000.0)
            .collect();
        xs.extend((0..20_000).map(|i| 1.7 * f64::from(i) * (1.0 + 1e-7 * f64::from(i))));
        xs.extend((1..2000).map(|k| f64::from(k) * std::f64::consts::FRAC_PI_4));
        xs.extend([0.0, -0.0, 1e-300, 5e5, -5e5, LIMIT, -LIMIT]);
        for &x in &xs {
            let (s, c) = sin_cos(x);
            let (s0, c0) = crate::sin_cos(x);
            worst = worst.max((s - s0).abs()).max((c - c0).abs());
            assert!(s * s + c * c - 1.0 < 1e-15);
        }
        assert!(worst <= 3e-16, "worst difference {worst:e}");
        for x in [LIMIT * 1.5, -1e12, 1e300] {
            assert_eq!(sin_cos(x), crate::sin_cos(x));
        }
        let (s, c) = sin_cos(f64::NAN);
        assert!(s.is_nan() && c.is_nan());
        let (s, c) = sin_cos(f64::INFINITY);
        assert!(s.is_nan() && c.is_nan());
    }
}
