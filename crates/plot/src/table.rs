//! Data tables, written as CSV with units in the header.

use serde::Serialize;

use crate::error::Error;
use crate::format::{csv_field, fmt6};

/// One cell: a number (formatted to [`crate::SIGNIFICANT_DIGITS`]), text (e.g. a rattle state)
/// or a count.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[non_exhaustive]
pub enum Cell {
    /// A number.
    Num(f64),
    /// A label.
    Text(String),
    /// A count (steps, right-hand-side evaluations, events): written in full, every digit.
    Count(u64),
    /// A number that does not settle under a solver retune, so it is not what a reviewer
    /// judges: a sample of a non-periodic orbit, a long-window statistic whose variants
    /// disagree, an iterate of a solver that did not converge, or a solution seeded from one of
    /// those (a warm start from a chaotic time response). Written at 6 significant digits to
    /// the uncommitted `validation/stats/`, as [`crate::NOT_PERIODIC`] in the
    /// committed table (issue 28).
    Unsettled(f64),
}

impl From<f64> for Cell {
    fn from(x: f64) -> Self {
        Cell::Num(x)
    }
}

impl From<&str> for Cell {
    fn from(s: &str) -> Self {
        Cell::Text(s.to_owned())
    }
}

impl From<String> for Cell {
    fn from(s: String) -> Self {
        Cell::Text(s)
    }
}

impl Cell {
    /// The cell as it appears in CSV and snapshots.
    pub fn render(&self) -> String {
        match self {
            Cell::Num(x) => fmt6(*x),
            Cell::Text(s) => s.clone(),
            Cell::Count(n) => n.to_string(),
            Cell::Unsettled(x) => fmt6(*x),
        }
    }

    /// `x` as [`Cell::Unsettled`] when `unsettled`, else as [`Cell::Num`].
    pub fn settled_if(x: f64, unsettled: bool) -> Self {
        if unsettled {
            Cell::Unsettled(x)
        } else {
            Cell::Num(x)
        }
    }

    /// The number in the cell (`None` for text).
    pub fn number(&self) -> Option<f64> {
        match self {
            Cell::Num(x) | Cell::Unsettled(x) => Some(*x),
            Cell::Count(n) => Some(*n as f64),
            Cell::Text(_) => None,
        }
    }

    /// A count carried as a number (the study outputs are `f64`): [`Cell::Count`] when `x`
    /// is a whole number in `[0, 2⁵³]`, else [`Cell::Num`] (NaN of a failed point).
    pub fn count(x: f64) -> Self {
        if (0.0..=9_007_199_254_740_992.0).contains(&x) && x.fract() == 0.0 {
            Cell::Count(x as u64)
        } else {
            Cell::Num(x)
        }
    }
}

/// A column: name and unit (`1` for dimensionless, empty for labels).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Column {
    /// Name, e.g. `omega1`.
    pub name: String,
    /// Unit, e.g. `rad/s`.
    pub unit: String,
}

/// A data table; written to `validation/<paper>/<study-id>_<name>.csv`, header `name [unit]`.
///
/// ```
/// use geardyn_plot::Table;
/// let mut t = Table::new("sweep", &[("omega1", "rad/s"), ("rsv", "1")]);
/// t.push_nums(&[150.0, 0.25]).unwrap();
/// assert_eq!(t.to_csv(), "omega1 [rad/s],rsv [1]\n150,0.25\n");
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Table {
    /// File-name part (`a-z`, `0-9`, `-`, `_`, `.`).
    pub name: String,
    /// Header.
    pub columns: Vec<Column>,
    /// Rows, each as long as the header.
    pub rows: Vec<Vec<Cell>>,
    /// The table records a non-periodic (chaotic) orbit: written to the uncommitted
    /// `validation/stats/` only ([`Table::non_periodic_record`]).
    pub non_periodic: bool,
    /// Why the record is not committed, when it is not a non-periodic orbit
    /// ([`Table::unsettled_record`]).
    pub record_reason: Option<String>,
    /// The values are reproducible to this many significant digits only (the study's own
    /// accuracy check): committed at no more ([`Table::reproducible_digits`]).
    pub digits: Option<i32>,
    /// The values are reproducible only to `10^-decades` of the largest magnitude (an absolute
    /// noise floor, e.g. the small lines of a spectrum): committed no finer
    /// ([`Table::reproducible_decades`]).
    pub decades: Option<i32>,
}

impl Table {
    /// An empty table with `(name, unit)` columns.
    pub fn new(name: &str, columns: &[(&str, &str)]) -> Self {
        Table {
            name: name.to_owned(),
            columns: columns
                .iter()
                .map(|(n, u)| Column {
                    name: (*n).to_owned(),
                    unit: (*u).to_owned(),
                })
                .collect(),
            rows: Vec::new(),
            non_periodic: false,
            record_reason: None,
            digits: None,
            decades: None,
        }
    }

    /// Commit no finer than `10^-decades` of the largest magnitude (at least 1 decade): the
    /// study's own check shows an absolute noise floor there. The stats copy keeps every digit.
    pub fn reproducible_decades(mut self, decades: i32) -> Self {
        self.decades = Some(decades.max(1));
        self
    }

    /// Commit the numbers (after the first column) at no more than `digits` significant digits
    /// (at least 1; the default is 4, `TABLE_DIGITS` of the validation harness): the study's own accuracy
    /// check reproduces them only to that precision. The stats copy keeps every digit.
    pub fn reproducible_digits(mut self, digits: i32) -> Self {
        self.digits = Some(digits.max(1));
        self
    }

    /// Mark the table (when `non_periodic`) as a record of a non-periodic orbit (time series at a chaotic point):
    /// written to `validation/stats/` only, with one line in the snapshot (issue 28).
    pub fn non_periodic_record(mut self, non_periodic: bool) -> Self {
        self.non_periodic = non_periodic;
        self
    }

    /// Mark the table as a record that does not settle under a solver retune for the reason
    /// given (for example a continuation path past a loss of stability): written to
    /// `validation/stats/` only, with the reason in the snapshot.
    pub fn unsettled_record(mut self, reason: &str) -> Self {
        self.non_periodic = true;
        self.record_reason = Some(reason.to_owned());
        self
    }

    /// Append a row of cells.
    pub fn push(&mut self, row: Vec<Cell>) -> Result<(), Error> {
        if row.len() != self.columns.len() {
            return Err(Error::RowLength {
                table: self.name.clone(),
                expected: self.columns.len(),
                got: row.len(),
            });
        }
        self.rows.push(row);
        Ok(())
    }

    /// Append a row of numbers.
    pub fn push_nums(&mut self, row: &[f64]) -> Result<(), Error> {
        self.push(row.iter().map(|&x| Cell::Num(x)).collect())
    }

    /// The CSV text (RFC 4180 quoting, `\n` line ends, numbers at 6 significant digits).
    pub fn to_csv(&self) -> String {
        let mut s = String::new();
        let header: Vec<String> = self
            .columns
            .iter()
            .map(|c| {
                if c.unit.is_empty() {
                    csv_field(&c.name)
                } else {
                    csv_field(&format!("{} [{}]", c.name, c.unit))
                }
            })
            .collect();
        s.push_str(&header.join(","));
        s.push('\n');
        for row in &self.rows {
            let cells: Vec<String> = row.iter().map(|c| csv_field(&c.render())).collect();
            s.push_str(&cells.join(","));
            s.push('\n');
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn row_length_checked() {
        let mut t = Table::new("t", &[("a", "m"), ("state", "")]);
        assert!(t.push_nums(&[1.0]).is_err());
        t.push(vec![1.0.into(), "bilateral".into()]).unwrap();
        assert_eq!(t.to_csv(), "a [m],state\n1,bilateral\n");
    }

    /// Counts are written with every digit; anything that is not a whole count stays a number.
    #[test]
    fn counts_are_written_in_full() {
        assert_eq!(Cell::count(1_234_567.0).render(), "1234567");
        assert_eq!(Cell::Num(1_234_567.0).render(), "1234570");
        assert_eq!(Cell::count(0.0), Cell::Count(0));
        assert_eq!(Cell::count(f64::NAN).render(), "NaN");
        assert_eq!(Cell::count(-1.0), Cell::Num(-1.0));
        assert_eq!(Cell::count(2.5), Cell::Num(2.5));
        assert_eq!(Cell::count(1e300), Cell::Num(1e300));
    }
}
