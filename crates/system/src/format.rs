//! The one number formatter of the workspace: a fixed number of significant digits, the same
//! text on every platform (CSV files, snapshots, reports and study outputs all use it).

/// Six significant digits: [`fmt_sig`]`(x, 6)`.
pub fn fmt6(x: f64) -> String {
    fmt_sig(x, 6)
}

/// Format `x` to `digits` significant digits (at least 1), deterministically.
///
/// Plain decimal notation for 1e-5 ≤ |x| < 1e7, scientific (`1.5e-7`) otherwise; trailing zeros
/// are dropped; zero (either sign) is `0`; non-finite values are `NaN`, `inf`, `-inf`.
///
/// ```
/// use geardyn_system::format::fmt_sig;
/// assert_eq!(fmt_sig(3.14159265, 6), "3.14159");
/// assert_eq!(fmt_sig(9.9999996, 6), "10");
/// assert_eq!(fmt_sig(-0.000_001_234_567, 3), "-1.23e-6");
/// assert_eq!(fmt_sig(1234.5, 2), "1200");
/// assert_eq!(fmt_sig(-0.0, 6), "0");
/// ```
pub fn fmt_sig(x: f64, digits: usize) -> String {
    if x.is_nan() {
        return "NaN".to_owned();
    }
    if x.is_infinite() {
        return if x > 0.0 { "inf" } else { "-inf" }.to_owned();
    }
    if x == 0.0 {
        return "0".to_owned();
    }
    let digits = digits.max(1);
    let sci = format!("{:.*e}", digits - 1, x);
    let (mantissa, exp) = sci.split_once('e').unwrap_or((sci.as_str(), "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    if (-5..7).contains(&exp) {
        // Place the decimal point in the correctly rounded mantissa digits (no second rounding).
        let neg = mantissa.starts_with('-');
        let d: String = mantissa.chars().filter(char::is_ascii_digit).collect();
        let body = if exp >= 0 {
            let e = exp as usize + 1;
            let mut int = d.chars().take(e).collect::<String>();
            while int.len() < e {
                int.push('0');
            }
            let frac: String = d.chars().skip(e).collect();
            if frac.is_empty() {
                int
            } else {
                format!("{int}.{frac}")
            }
        } else {
            format!("0.{}{d}", "0".repeat((-exp - 1) as usize))
        };
        let body = trim_zeros(&body);
        if neg { format!("-{body}") } else { body }
    } else {
        format!("{}e{exp}", trim_zeros(mantissa))
    }
}

fn trim_zeros(s: &str) -> String {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        s.to_owned()
    }
}
