//! Fixed, platform-independent number formatting for CSV, snapshots and the report.

/// Number of significant digits used in every CSV file, snapshot and report table.
pub const SIGNIFICANT_DIGITS: usize = 6;

/// Format `x` to `digits` significant digits, deterministically: the one formatter of the
/// workspace lives in the base crate (`system::format::fmt_sig`), re-exported here.
///
/// ```
/// use geardyn_plot::fmt_sig;
/// assert_eq!(fmt_sig(3.14159265, 6), "3.14159");
/// assert_eq!(fmt_sig(-0.0, 6), "0");
/// ```
pub use system::format::fmt_sig;

/// [`fmt_sig`] at [`SIGNIFICANT_DIGITS`] (re-exported from `system::format`).
pub use system::format::fmt6;

/// What a committed file writes for a value that is not settled: a statistic of a non-periodic
/// orbit, a cell marked [`crate::Cell::Unsettled`], a span marked [`unsettled`].
pub const NOT_PERIODIC: &str = "n/p";

/// Quote a CSV field when it contains a comma, quote or newline (RFC 4180). A field that is one
/// [`unsettled`] span as a whole is quoted inside the span, so that the committed form is a
/// bare `n/p` whatever the value (a flag whose text had a comma committed as `"n/p"` in one run
/// and `n/p` in another) and the full form stays valid CSV.
pub fn csv_field(s: &str) -> String {
    if let Some(inner) = s
        .strip_prefix(UNSETTLED_OPEN)
        .and_then(|r| r.strip_suffix(UNSETTLED_CLOSE))
        .filter(|r| !r.contains([UNSETTLED_OPEN, UNSETTLED_CLOSE]))
    {
        return unsettled(csv_field(inner));
    }
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_owned()
    }
}

/// Escape a Markdown table cell.
pub fn md_cell(s: &str) -> String {
    s.replace('|', "\\|").replace('\n', " ")
}

/// Half a unit in the last digit of a printed decimal number.
pub fn half_last_digit(printed: &str) -> Result<f64, crate::error::Error> {
    let bad = || crate::error::Error::PrintedNumber {
        printed: printed.to_owned(),
    };
    let t = printed.trim();
    let (mant, exp) = match t.split_once(['e', 'E']) {
        Some((m, e)) => (m, e.parse::<i32>().map_err(|_| bad())?),
        None => (t, 0),
    };
    let m = mant.trim_start_matches(['+', '-']);
    if m.is_empty()
        || !m.chars().all(|c| c.is_ascii_digit() || c == '.')
        || m.matches('.').count() > 1
    {
        return Err(bad());
    }
    let decimals = m.split_once('.').map_or(0, |(_, d)| d.len()) as i32;
    Ok(0.5 * 10f64.powi(exp - decimals))
}

/// Opening mark of a text span that does not settle under a solver retune ([`unsettled`]).
pub const UNSETTLED_OPEN: char = '⟦';
/// Closing mark of a text span that does not settle under a solver retune.
pub const UNSETTLED_CLOSE: char = '⟧';

/// Mark a number (or any text) in a claim's evidence, a flag or a note as not settling under a
/// solver retune — a statistic of a non-periodic orbit, a count of points that move under a
/// tighter tolerance. Committed files write the span as `n/p` ([`committed_text`]); the
/// uncommitted `validation/stats/` has it in full ([`full_text`]).
///
/// ```
/// use geardyn_plot::{committed_text, full_text, unsettled};
/// let s = format!("slope {} ± {}", unsettled(11.5), unsettled(1.3));
/// assert_eq!(committed_text(&s), "slope n/p ± n/p");
/// assert_eq!(full_text(&s), "slope 11.5 ± 1.3");
/// ```
pub fn unsettled(x: impl std::fmt::Display) -> String {
    format!("{UNSETTLED_OPEN}{x}{UNSETTLED_CLOSE}")
}

/// `s` with every [`unsettled`] span replaced by `n/p` (an unclosed span runs to the end).
pub fn committed_text(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    let mut inside = false;
    for c in s.chars() {
        match c {
            UNSETTLED_OPEN if !inside => {
                inside = true;
                out.push_str(NOT_PERIODIC);
            }
            UNSETTLED_CLOSE if inside => inside = false,
            _ if inside => {}
            _ => out.push(c),
        }
    }
    out
}

/// `s` with the marks of [`unsettled`] spans removed (the values in full).
pub fn full_text(s: &str) -> String {
    s.chars()
        .filter(|&c| c != UNSETTLED_OPEN && c != UNSETTLED_CLOSE)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The committed form of an unsettled field does not depend on its value.
    #[test]
    fn unsettled_fields_commit_alike() {
        let a = csv_field(&unsettled("period-2, not reproducible"));
        let b = csv_field(&unsettled(""));
        assert_eq!(committed_text(&a), NOT_PERIODIC);
        assert_eq!(committed_text(&b), NOT_PERIODIC);
        assert_eq!(full_text(&a), "\"period-2, not reproducible\"");
        // a span inside a longer field: the field is quoted as a whole
        let c = csv_field(&format!("x, {}", unsettled(1)));
        assert_eq!(committed_text(&c), "\"x, n/p\"");
    }

    #[test]
    fn formats() {
        assert_eq!(fmt_sig(1.0, 6), "1");
        assert_eq!(fmt_sig(0.1 + 0.2, 6), "0.3");
        assert_eq!(fmt_sig(123_456_789.0, 6), "1.23457e8");
        assert_eq!(fmt_sig(1e-7, 6), "1e-7");
        assert_eq!(fmt_sig(f64::NAN, 6), "NaN");
        assert_eq!(fmt_sig(f64::NEG_INFINITY, 6), "-inf");
        assert_eq!(fmt_sig(999_999.6, 6), "1000000");
        assert_eq!(fmt_sig(0.000_099_999_99, 3), "0.0001");
    }

    #[test]
    fn csv_quoting() {
        assert_eq!(csv_field("a,b"), "\"a,b\"");
        assert_eq!(csv_field("say \"x\""), "\"say \"\"x\"\"\"");
        assert_eq!(csv_field("plain"), "plain");
    }
}
