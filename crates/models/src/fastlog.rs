//! A short natural logarithm for the inner loop of Karpov's Duhamel quadrature (the
//! accumulated phase `G(θ) = −(c/ε)(ln(1 + ε cos θ) − ln(1 + ε))`, once per node).
//!
//! `y = m·2ᵉ` with `m ∈ [√½, √2)`; then `ln m = 2 atanh s`, `s = (m − 1)/(m + 1)`,
//! `|s| ≤ 3 − 2√2 ≈ 0.172`, by its odd series `2(s + s³/3 + … + s²³/23)` (the next term is
//! below `0.172²⁵/25 ≈ 3·10⁻²¹`), and `ln y = e·ln 2 + ln m` with `ln 2` split in two parts
//! (`e·L₁` exact). `m − 1` is exact, so the result is within a few `10⁻¹⁶` of the exact value
//! (absolute for `|ln y| ≲ 1`, relative beyond) — tested against the platform's `ln`. For
//! `y` not normal and positive (0, subnormal, negative, NaN, +∞) it falls back to [`f64::ln`].

use math::DetMath;
/// `ln 2` to 33 bits (`e·L1` is exact for `|e| < 2²⁰`).
const L1: f64 = 0.693_147_180_485_539_1;
/// `ln 2 − L1`.
const L2: f64 = 7.440_617_110_012_397e-11;

/// `ln y` to a few units of `10⁻¹⁶` (see the module docs).
#[inline]
pub(crate) fn ln(y: f64) -> f64 {
    if !(f64::MIN_POSITIVE..f64::INFINITY).contains(&y) {
        return fallback(y);
    }
    // y = m·2^e, m in [1, 2) from the bits of the (normal, positive) y, then in [√½, √2)
    let bits = y.to_bits();
    let mut e = ((bits >> 52) as i64) - 1023;
    let mut m = f64::from_bits((bits & 0x000f_ffff_ffff_ffff) | 0x3ff0_0000_0000_0000);
    if m >= std::f64::consts::SQRT_2 {
        m *= 0.5;
        e += 1;
    }
    let f = m - 1.0;
    let s = f / (2.0 + f);
    let z = s * s;
    let z2 = z * z;
    let z4 = z2 * z2;
    let z8 = z4 * z4;
    // 1/3 + z/5 + … + z¹⁰/23, by Estrin's scheme (short dependency chains)
    let p = ((1.0 / 3.0 + z * (1.0 / 5.0)) + z2 * (1.0 / 7.0 + z * (1.0 / 9.0)))
        + z4 * ((1.0 / 11.0 + z * (1.0 / 13.0)) + z2 * (1.0 / 15.0 + z * (1.0 / 17.0)))
        + z8 * ((1.0 / 19.0 + z * (1.0 / 21.0)) + z2 * (1.0 / 23.0));
    let ln_m = 2.0 * s + 2.0 * s * z * p;
    let e = e as f64;
    e * L1 + (e * L2 + ln_m)
}

/// The fallback outside the normal positive numbers: `geardyn-math`'s `ln`, out of line and
/// cold, so that its code does not keep [`ln`] from being inlined into the loops that call it.
#[cold]
#[inline(never)]
fn fallback(y: f64) -> f64 {
    y.dln()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ln2_split() {
        // L1 carries at most 33 significant bits (e·L1 exact for |e| < 2^20)
        assert_eq!(L1.to_bits() & ((1u64 << 20) - 1), 0);
        assert_eq!((L1 + L2).to_bits(), std::f64::consts::LN_2.to_bits());
    }

    /// Within a few 10⁻¹⁶ of the platform's `ln` (relative to `max(1, |ln y|)`) over the range
    /// Karpov's phase uses (`y = 1 + ε cos θ ∈ (0, 2)`, dense near 0 and near 1), beyond it,
    /// and the fallback outside.
    #[test]
    fn agrees_with_libm_to_rounding_level() {
        let mut ys: Vec<f64> = (1..40_000).map(|i| 2.0 * f64::from(i) / 40_000.0).collect();
        ys.extend((1..400).map(|i| 10f64.dpowf(-f64::from(i) / 25.0)));
        ys.extend((1..400).map(|i| 1.0 + 10f64.dpowf(-f64::from(i) / 25.0)));
        ys.extend((1..400).map(|i| 1.0 - 10f64.dpowf(-f64::from(i) / 25.0)));
        ys.extend((0..20_000).map(|i| 1e3 * f64::from(i) / 20_000.0 + 1e-3));
        ys.extend([1.0, f64::MIN_POSITIVE, 1e300, f64::MAX]);
        let mut worst = 0.0f64;
        for &y in &ys {
            let (a, b) = (ln(y), y.dln());
            worst = worst.max((a - b).abs() / b.abs().max(1.0));
        }
        assert!(worst <= 4e-16, "worst difference {worst:e}");
        assert_eq!(ln(1.0).to_bits(), 0.0f64.to_bits());
        for y in [
            0.0,
            -0.0,
            1e-310,
            -1.0,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ] {
            let (a, b) = (ln(y), y.dln());
            assert!(
                a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()),
                "{y}: {a} vs {b}"
            );
        }
    }
}
