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

/// `text` with every decimal number that has a fraction or an exponent (`0.0022578832900051198`,
/// `-5.29e-3`) rewritten by [`fmt_sig`] to `digits` significant digits; integers (counts,
/// indices) and digits inside words (`x2`, `Eq20`) are left as they are. For texts that embed
/// solver values through `Debug` (a stop reason, an error), whose full digits would make every
/// rounding-level change a change of the text.
///
/// ```
/// use geardyn_system::format::round_numbers_in;
/// assert_eq!(
///     round_numbers_in("Degenerate { parameter: 10.938149508668943, first: -5.300337e-3 } (x2, 7 pieces)", 4),
///     "Degenerate { parameter: 10.94, first: -0.0053 } (x2, 7 pieces)"
/// );
/// ```
pub fn round_numbers_in(text: &str, digits: usize) -> String {
    let b = text.as_bytes();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    while i < b.len() {
        let word_before = i > 0 && (b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_');
        if !b[i].is_ascii_digit() || word_before {
            // one whole character (text may hold any UTF-8)
            let c = text[i..].chars().next().unwrap_or(' ');
            out.push(c);
            i += c.len_utf8().max(1);
            continue;
        }
        let start = i;
        let digits_from = |mut j: usize| {
            while j < b.len() && b[j].is_ascii_digit() {
                j += 1;
            }
            j
        };
        i = digits_from(i);
        let mut real = false;
        if i + 1 < b.len() && b[i] == b'.' && b[i + 1].is_ascii_digit() {
            i = digits_from(i + 1);
            real = true;
        }
        if i < b.len() && (b[i] == b'e' || b[i] == b'E') {
            let mut j = i + 1;
            if j < b.len() && (b[j] == b'+' || b[j] == b'-') {
                j += 1;
            }
            if j < b.len() && b[j].is_ascii_digit() {
                i = digits_from(j);
                real = true;
            }
        }
        let number = &text[start..i];
        match number.parse::<f64>() {
            Ok(x) if real => {
                // a minus sign just before belongs to the number
                let x = if out.ends_with('-') {
                    out.pop();
                    -x
                } else {
                    x
                };
                out.push_str(&fmt_sig(x, digits));
            }
            _ => out.push_str(number),
        }
    }
    out
}

fn trim_zeros(s: &str) -> String {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        s.to_owned()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_in_text_are_rounded_and_the_rest_is_kept() {
        // integers, digits inside words and non-ASCII text stay; reals are rounded
        assert_eq!(
            round_numbers_in("12 piece(s) at ω1 = 100 rad/s", 3),
            "12 piece(s) at ω1 = 100 rad/s"
        );
        assert_eq!(
            round_numbers_in("Eq20, x2.5, b̄ 0.31234", 2),
            "Eq20, x2.5, b̄ 0.31"
        );
        assert_eq!(
            round_numbers_in("residual 3.0411232917179512e-5)", 3),
            "residual 0.0000304)"
        );
        assert_eq!(
            round_numbers_in("value: -0.005290085575176574 }", 3),
            "value: -0.00529 }"
        );
        assert_eq!(round_numbers_in("1e-5 and 2E+3", 2), "0.00001 and 2000");
        // a trailing dot or a bare `e` is not part of a number
        assert_eq!(round_numbers_in("at 3. then 4e", 2), "at 3. then 4e");
        assert_eq!(round_numbers_in("", 3), "");
    }
}
