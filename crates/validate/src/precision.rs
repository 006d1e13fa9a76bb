//! The precision of the committed outputs (issue 28): what a reviewer judges, at the precision
//! that matters, and nothing else.
//!
//! * A compared model value is written to a decimal step tied to its row
//!   ([`value_step`]): a power of ten no larger than 1/[`BAND_FRACTION`] of the row's *scale*,
//!   the larger of the tolerance band half-width and the distance `|model − paper|`. A move well
//!   inside the band (or small against a deviation's distance) changes no committed byte.
//! * Figure data is written at drawing precision ([`DRAWING_STEPS`] steps per axis range, a
//!   power of ten: under one pixel of the 800×560 SVG), and the SVG is drawn from that data.
//! * Data tables: numbers at drawing precision of their column's range; the solver statistics
//!   ([`is_solver_statistic`]: steps, RHS calls, events, residual norms, truncation, error
//!   estimates, changes under a tighter tolerance) and the one-period samples of non-periodic
//!   orbits ([`one_period_samples`]) are left out and written, at full precision, only to the
//!   uncommitted `validation/stats/` (checked for determinism through a content digest).

use crate::format::fmt6;
use crate::table::{Cell, Table};
use math::DetMath;

/// A compared model value is written to a power of ten no larger than 1/`BAND_FRACTION` of its
/// row's scale (band half-width, or the distance to the paper value when larger).
pub const BAND_FRACTION: f64 = 20.0;

/// Figure and table data are written to a power of ten no larger than 1/`DRAWING_STEPS` of the
/// axis (column) range: below one pixel of the SVG.
pub const DRAWING_STEPS: f64 = 1000.0;

/// `--diff` lists a model value as moved when it moved by more than this fraction of its band
/// half-width (smaller moves are counted, not listed).
pub const MOVE_FRACTION: f64 = 0.1;

/// Marker of a value left out of a committed table (defined with the number formats in `plot`).
pub use plot::NOT_PERIODIC;

/// The power-of-ten exponent `e` with `10^e ≤ scale / divisions < 10^(e+1)`, or `None` when the
/// scale is zero or not finite (then numbers are written at 6 significant digits).
pub fn step_exponent(scale: f64, divisions: f64) -> Option<i32> {
    let s = scale.abs() / divisions;
    if !(s.is_finite() && s > 0.0) {
        return None;
    }
    let mut e = s.dlog10().floor() as i32;
    // guard the floor against log10 rounding at exact powers of ten
    if 10f64.powi(e + 1) <= s {
        e += 1;
    } else if 10f64.powi(e) > s {
        e -= 1;
    }
    Some(e.clamp(-300, 300))
}

/// `x` rounded to `10^e` and written with exactly the decimals that step has (`e ≥ 0`: an
/// integer). Falls back to 6 significant digits for non-finite values or absurd magnitudes.
pub fn fmt_step(x: f64, e: i32) -> String {
    if !x.is_finite() || !(-15..=15).contains(&e) || x.abs() >= 1e17 {
        return fmt6(x);
    }
    let step = 10f64.powi(e);
    let q = (x / step).round();
    let s = if e >= 0 {
        format!("{}", q * step)
    } else {
        format!("{:.*}", (-e) as usize, q * step)
    };
    // no "-0.00"
    if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') {
        s[1..].to_owned()
    } else {
        s
    }
}

/// The exponent of the step a compared model value is written to: 1/[`BAND_FRACTION`] of the
/// larger of the band half-width `half_width` and `|model − paper|` (and of the interval's
/// distance, when there is one).
pub fn value_step(half_width: f64, model: f64, paper: f64, interval: Option<(f64, f64)>) -> i32 {
    let mut scale = if half_width.is_finite() {
        half_width.abs()
    } else {
        0.0
    };
    let mut dist = |x: f64| {
        let d = (x - paper).abs();
        if d.is_finite() {
            scale = scale.max(d);
        }
    };
    dist(model);
    if let Some((lo, hi)) = interval {
        dist(lo);
        dist(hi);
    }
    if scale == 0.0 {
        // exact agreement with a zero band: the paper's own magnitude
        scale = paper.abs().max(model.abs()) * 1e-6;
    }
    step_exponent(scale, BAND_FRACTION).unwrap_or(-6)
}

/// True for a column that describes the computation rather than the model: step statistics
/// (`steps_accepted`, `steps_rejected`, `rhs_calls`, `events`, also with a suffix such as
/// ` dynamic`), residual norms, truncation estimates, quadrature error estimates, the
/// Poincaré section's repeat distance against its tolerance (`section_margin`, at the
/// integrator's error for a periodic orbit) and the change of a result under a tighter
/// tolerance or a halved step. Matched on the column name
/// so that every study's new tables follow the rule.
pub fn is_solver_statistic(name: &str) -> bool {
    let n = name.trim().to_ascii_lowercase();
    let first = n.split([' ', '[']).next().unwrap_or("");
    ["steps_accepted", "steps_rejected", "rhs_calls", "events"].contains(&first)
        || n.starts_with("residual_norm")
        || n.starts_with("truncation")
        || n.starts_with("section_margin")
        || n.contains("error_estimate")
        || (n.contains("change") && (n.contains("100x") || n.contains("halved")))
}

/// True for a column that says whether a row's motion is periodic (`time_motion_period`,
/// `motion period (0 non-periodic)`, `motion period dynamic (0 non-periodic)`): value 0 marks a
/// non-periodic orbit.
pub fn is_motion_period(name: &str) -> bool {
    let n = name.to_ascii_lowercase();
    n.contains("motion_period") || n.contains("motion period")
}

/// The columns of `table` whose cell in row `row` is a one-period (one-record) sample of a
/// non-periodic orbit, so not reproducible below its scatter: when a motion-period column of
/// the row is 0, the time-reference columns (suffix `_time`) — or, in a table without such
/// columns, every numeric column except the first (the swept value), the motion-period columns
/// and the solver statistics.
pub fn one_period_samples(table: &Table, row: &[Cell]) -> Vec<usize> {
    let non_periodic = table
        .columns
        .iter()
        .zip(row)
        .any(|(c, v)| is_motion_period(&c.name) && matches!(v, Cell::Num(x) if *x == 0.0));
    let non_periodic = non_periodic
        || table
            .columns
            .iter()
            .zip(row)
            .any(|(c, v)| is_motion_period(&c.name) && matches!(v, Cell::Count(0)));
    if !non_periodic {
        return Vec::new();
    }
    let has_time = table.columns.iter().any(|c| c.name.ends_with("_time"));
    table
        .columns
        .iter()
        .enumerate()
        .filter(|(i, c)| {
            if has_time {
                c.name.ends_with("_time")
            } else {
                *i > 0 && !is_motion_period(&c.name) && !is_solver_statistic(&c.name)
            }
        })
        .filter(|(i, _)| matches!(row.get(*i), Some(Cell::Num(_))))
        .map(|(i, _)| i)
        .collect()
}

/// Significant digits of a committed table number ([`committed_table_csv`]).
pub const TABLE_DIGITS: i32 = 4;

/// A committed table number is never written finer than `10^-TABLE_FLOOR_DECADES` of its
/// column's largest magnitude (values near zero carry no noise digits).
pub const TABLE_FLOOR_DECADES: i32 = 6;

/// The exponent of the step a table number `x` is committed at: `digits` significant digits
/// of `x` itself ([`TABLE_DIGITS`] unless the table says fewer), floored at `floor` (the column's floor exponent, see
/// [`table_floor_exponent`]). Depends on `x` and on the decade of the column's largest
/// magnitude only — not on which other values are settled — so that a value that becomes
/// unsettled (or settled) under a retune does not re-round its column.
pub fn table_value_exponent(x: f64, floor: Option<i32>, digits: i32) -> Option<i32> {
    let own = step_exponent(x, 1.0).map(|e| e - (digits - 1));
    match (own, floor) {
        (Some(e), Some(f)) => Some(e.max(f)),
        (Some(e), None) => Some(e),
        (None, f) => f,
    }
}

/// The floor exponent of a table column: [`TABLE_FLOOR_DECADES`] decades below the decade of
/// the largest magnitude over *every* number of the column, settled or not (the rows of a
/// table are a fixed grid, so the set does not change with the classification of its points).
pub fn table_floor_exponent<'a>(cells: impl Iterator<Item = &'a Cell>) -> Option<i32> {
    let mag = cells
        .filter_map(|c| match c {
            Cell::Num(x) | Cell::Unsettled(x) if x.is_finite() => Some(x.abs()),
            _ => None,
        })
        .fold(0.0_f64, f64::max);
    step_exponent(mag, 1.0).map(|e| e - TABLE_FLOOR_DECADES)
}

/// The committed form of a data table: solver statistics dropped, one-period samples of
/// non-periodic rows and [`Cell::Unsettled`] cells written as [`NOT_PERIODIC`]. The first
/// column (the swept or tabulated input) is written at drawing precision of its range
/// (1/[`DRAWING_STEPS`]); every other number at [`TABLE_DIGITS`] significant digits of its own
/// ([`table_value_exponent`]), so that a value's committed form depends on that value alone
/// (and on the decade of its column's largest magnitude, for values near zero). Returns the
/// CSV text.
pub fn committed_table_csv(table: &Table) -> String {
    let keep: Vec<usize> = (0..table.columns.len())
        .filter(|&i| !is_solver_statistic(&table.columns[i].name))
        .collect();
    let blanks: Vec<Vec<usize>> = table
        .rows
        .iter()
        .map(|row| one_period_samples(table, row))
        .collect();
    let first = column_exponent(table.rows.iter().filter_map(|r| r.first()));
    let floors: Vec<Option<i32>> = (0..table.columns.len())
        .map(|i| {
            let f = table_floor_exponent(table.rows.iter().filter_map(|r| r.get(i)));
            // a declared noise floor: 10^-decades of the largest magnitude
            match table.decades {
                Some(d) => f.map(|e| e + TABLE_FLOOR_DECADES - d.clamp(1, TABLE_FLOOR_DECADES)),
                None => f,
            }
        })
        .collect();
    let digits = table
        .digits
        .map_or(TABLE_DIGITS, |d| d.clamp(1, TABLE_DIGITS));
    let mut t = Table::new(&table.name, &[]);
    t.columns = keep.iter().map(|&i| table.columns[i].clone()).collect();
    for (row, blank) in table.rows.iter().zip(&blanks) {
        let cells = keep
            .iter()
            .map(|&i| match row.get(i) {
                Some(_) if blank.contains(&i) => Cell::Text(NOT_PERIODIC.to_owned()),
                Some(Cell::Unsettled(_)) => Cell::Text(NOT_PERIODIC.to_owned()),
                Some(Cell::Num(x)) => {
                    let e = if i == 0 {
                        first
                    } else {
                        table_value_exponent(*x, floors[i], digits)
                    };
                    match e {
                        Some(e) => Cell::Text(fmt_data(*x, e)),
                        None => Cell::Num(*x),
                    }
                }
                Some(c) => c.clone(),
                None => Cell::Text(String::new()),
            })
            .collect();
        t.rows.push(cells);
    }
    t.to_csv()
}

/// `x` at the step `10^e`, trailing zeros dropped (table and figure data).
pub fn fmt_data(x: f64, e: i32) -> String {
    let s = fmt_step(x, e);
    if s.contains('.') && !s.contains('e') {
        s.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        s
    }
}

/// Drawing-precision exponent of a set of numbers: 1/[`DRAWING_STEPS`] of their range, or of
/// their largest magnitude when they are all equal; `None` without finite numbers.
pub fn column_exponent<'a>(cells: impl Iterator<Item = &'a Cell>) -> Option<i32> {
    let (mut lo, mut hi, mut mag) = (f64::INFINITY, f64::NEG_INFINITY, 0.0_f64);
    for c in cells {
        if let Cell::Num(x) = c {
            if x.is_finite() {
                lo = lo.min(*x);
                hi = hi.max(*x);
                mag = mag.max(x.abs());
            }
        }
    }
    if !lo.is_finite() {
        return None;
    }
    let range = hi - lo;
    let scale = if range > 1e-12 * mag { range } else { mag };
    step_exponent(scale, DRAWING_STEPS)
}

/// Round `x` to the step `10^e` (the value [`fmt_step`] writes).
pub fn round_step(x: f64, e: Option<i32>) -> f64 {
    match e {
        Some(e) if x.is_finite() && (-15..=15).contains(&e) => {
            let step = 10f64.powi(e);
            let r = (x / step).round() * step;
            // parse back the printed form so that the drawn and written values agree exactly
            fmt_step(r, e).parse().unwrap_or(r)
        }
        _ => x,
    }
}

/// FNV-1a 64-bit digest of `bytes` (stable across platforms and Rust versions), as 16 hex digits.
pub fn digest(bytes: &[u8]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in bytes {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}

impl crate::Comparison {
    /// Half-width of the tolerance band around the paper value.
    pub fn half_width(&self) -> f64 {
        self.tolerance.allowed(self.reference.value)
    }

    /// The exponent of the decimal step this row's model value is committed at
    /// ([`value_step`]).
    pub fn committed_exponent(&self) -> i32 {
        value_step(
            self.half_width(),
            self.model,
            self.reference.value,
            self.interval,
        )
    }

    /// True when the value is committed as [`NOT_PERIODIC`]: marked unsettled by its study, or
    /// flagged (it rests on a point that is non-converged, unstable or not reproducible, so the
    /// value moves under a solver retune; the verdict is inconclusive and the flags say why).
    pub fn committed_blank(&self) -> bool {
        self.unsettled || !self.flags.is_empty()
    }

    /// The model value as committed (snapshot, REPORT.md, study CSV, `verdicts.csv`): rounded to
    /// [`committed_exponent`](Self::committed_exponent), with the interval (`165.0 [163.1, 166.9]`);
    /// [`NOT_PERIODIC`] when [`committed_blank`](Self::committed_blank).
    pub fn committed_model(&self) -> String {
        if self.committed_blank() {
            return NOT_PERIODIC.to_owned();
        }
        let e = self.committed_exponent();
        match self.interval {
            Some((lo, hi)) => format!(
                "{} [{}, {}]",
                fmt_step(self.model, e),
                fmt_step(lo, e),
                fmt_step(hi, e)
            ),
            None => fmt_step(self.model, e),
        }
    }

    /// The deviation as committed: `(model − paper, relative in %)`, from the rounded model
    /// value, so that it moves only when the committed model value moves.
    pub fn committed_deviation(&self) -> (String, String) {
        if self.committed_blank() {
            return (NOT_PERIODIC.to_owned(), NOT_PERIODIC.to_owned());
        }
        let e = self.committed_exponent();
        let m = round_step(self.model, Some(e));
        let d = m - self.reference.value;
        let rel = if self.reference.value == 0.0 || !d.is_finite() {
            "—".to_owned()
        } else {
            format!(
                "{}%",
                crate::fmt_sig(100.0 * d / self.reference.value.abs(), 3)
            )
        };
        (fmt_step(d, e), rel)
    }
}

/// Significant digits of a committed figure ordinate: a y value is never written finer than
/// this many digits of its own ([`drawn_figure`]).
pub const FIGURE_DIGITS: i32 = 3;

/// A figure at drawing precision: the points that do not settle under a solver retune
/// ([`crate::Series::unsettled`]) left out (a series left without points is dropped); every x
/// rounded to 1/[`DRAWING_STEPS`] of the x axis range; every y to the coarser of 1/
/// [`DRAWING_STEPS`] of the y axis range and [`FIGURE_DIGITS`] significant digits of its own.
/// The axis ranges are the fixed ones ([`crate::Figure::ranges`]), else the ranges of *all*
/// points, settled or not, so that a point that becomes unsettled under a retune does not
/// re-round the others. Its CSV and SVG are what is committed.
pub fn drawn_figure(f: &crate::Figure) -> crate::Figure {
    let axis = |fixed: Option<(f64, f64)>, pick: &dyn Fn(&(f64, f64)) -> f64| match fixed {
        Some((a, b)) => step_exponent((b - a).abs(), DRAWING_STEPS),
        None => {
            let cells: Vec<Cell> = f
                .series
                .iter()
                .flat_map(|s| s.points.iter())
                .map(|p| Cell::Num(pick(p)))
                .collect();
            column_exponent(cells.iter())
        }
    };
    let ex = axis(f.x_range, &|p| p.0);
    let mut ey = axis(f.y_range, &|p| p.1);
    if let Some(d) = f.decades {
        // a declared noise floor: 10^-decades of the largest magnitude of all points
        let mag = f
            .series
            .iter()
            .flat_map(|s| s.points.iter())
            .map(|p| p.1.abs())
            .filter(|y| y.is_finite())
            .fold(0.0_f64, f64::max);
        let floor = step_exponent(mag, 1.0).map(|e| e - d.max(1));
        ey = match (ey, floor) {
            (Some(a), Some(b)) => Some(a.max(b)),
            (a, b) => a.or(b),
        };
    }
    let mut g = f.clone();
    // the drawn x axis spans every point, settled or not (x is mostly the swept input): leaving
    // out an end point does not re-scale the drawing
    if g.x_range.is_none() && f.series.iter().any(|s| s.unsettled.iter().any(|&u| u)) {
        g.x_range = Some(f.data_range(|p| p.0));
    }
    for s in &mut g.series {
        if s.unsettled.iter().any(|&u| u) {
            let flags = std::mem::take(&mut s.unsettled);
            let kept = s
                .points
                .iter()
                .enumerate()
                .filter(|(i, _)| !flags.get(*i).copied().unwrap_or(false))
                .map(|(_, p)| *p)
                .collect();
            s.points = kept;
        }
        s.unsettled.clear();
    }
    // a series emptied by its unsettled points stays (a legend entry without points): whether
    // its last point settles must not add or remove a series from the committed drawing
    let mut had_points = f.series.iter().map(|s| !s.points.is_empty());
    g.series.retain(|_| had_points.next().unwrap_or(false));
    let digits = f
        .digits
        .map_or(FIGURE_DIGITS, |d| d.clamp(1, FIGURE_DIGITS));
    for s in &mut g.series {
        for p in &mut s.points {
            let own = step_exponent(p.1, 1.0).map(|e| e - (digits - 1));
            let e = match (ey, own) {
                (Some(a), Some(b)) => Some(a.max(b)),
                (a, b) => a.or(b),
            };
            *p = (round_step(p.0, ex), round_step(p.1, e));
        }
    }
    g
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_and_formatting() {
        assert_eq!(step_exponent(0.05, 20.0), Some(-3));
        assert_eq!(step_exponent(1.0, 10.0), Some(-1));
        assert_eq!(step_exponent(0.0, 10.0), None);
        assert_eq!(fmt_step(3.80049, -3), "3.800");
        assert_eq!(fmt_step(220.692, 0), "221");
        assert_eq!(fmt_step(14124.3, 2), "14100");
        assert_eq!(fmt_step(-0.0004, -3), "0.000");
        assert_eq!(fmt_step(f64::NAN, -3), "NaN");
    }

    /// A move well inside the band changes no digit; the band's own size sets the step, and a
    /// deviation's distance coarsens it.
    #[test]
    fn value_steps_follow_the_band() {
        let e = value_step(0.05, 3.8001, 3.8, None);
        assert_eq!(e, -3);
        assert_eq!(fmt_step(3.8001, e), fmt_step(3.8003, e));
        let e = value_step(0.05, 220.692, 56.0, Some((220.692, 234.915)));
        assert_eq!(e, 0);
        assert_eq!(fmt_step(220.692, e), "221");
    }

    #[test]
    fn solver_statistics_by_name() {
        for n in [
            "steps_accepted",
            "rhs_calls dynamic",
            "events",
            "residual_norm_hbm_warm",
            "truncation_hbm",
            "A_error_estimate",
            "metric change at 100x tighter tol",
            "a_final_change_halved",
        ] {
            assert!(is_solver_statistic(n), "{n}");
        }
        for n in [
            "B D=1.8 events",
            "ppv_time",
            "omega1",
            "time_reproducible_100x",
        ] {
            assert!(!is_solver_statistic(n), "{n}");
        }
    }

    #[test]
    fn committed_tables_drop_statistics_and_non_periodic_samples() {
        let mut t = Table::new(
            "sweep",
            &[
                ("omega1", "rad/s"),
                ("ppv_time", "1"),
                ("time_motion_period", "1"),
                ("ppv_window", "1"),
                ("steps_accepted", "1"),
            ],
        );
        t.push(vec![
            100.0.into(),
            0.123_456_7.into(),
            1.0.into(),
            0.2.into(),
            Cell::Count(4711),
        ])
        .unwrap();
        t.push(vec![
            102.5.into(),
            0.987_654.into(),
            0.0.into(),
            0.3.into(),
            Cell::Count(4712),
        ])
        .unwrap();
        let csv = committed_table_csv(&t);
        assert_eq!(
            csv,
            "omega1 [rad/s],ppv_time [1],time_motion_period [1],ppv_window [1]\n\
             100,0.1235,1,0.2\n\
             102.5,n/p,0,0.3\n"
        );
    }

    /// An unsettled cell is `n/p`; the stats copy (`to_csv`) has it in full. A committed number
    /// has 4 significant digits of its own, so moving (or un-settling) another value of the
    /// column changes no committed byte of it.
    #[test]
    fn unsettled_cells_are_left_out_and_do_not_re_round_the_column() {
        let mut t = Table::new("sweep", &[("x", "1"), ("ppv", "1")]);
        t.push(vec![1.0.into(), 0.123_456.into()]).unwrap();
        t.push(vec![2.0.into(), 0.124_001.into()]).unwrap();
        t.push(vec![3.0.into(), Cell::Unsettled(97.5)]).unwrap();
        assert_eq!(
            committed_table_csv(&t),
            "x [1],ppv [1]\n1,0.1235\n2,0.124\n3,n/p\n"
        );
        assert!(t.to_csv().ends_with("3,97.5\n"));
        // moving the unsettled value changes no committed byte
        let mut u = t.clone();
        u.rows[2][1] = Cell::Unsettled(12.0);
        assert_eq!(committed_table_csv(&t), committed_table_csv(&u));
        // nor does settling it (the others keep their digits)
        let mut v = t.clone();
        v.rows[2][1] = Cell::Num(12.0);
        assert_eq!(
            committed_table_csv(&v),
            "x [1],ppv [1]\n1,0.1235\n2,0.124\n3,12\n"
        );
    }

    /// Values near zero are written to the column floor (6 decades below its largest
    /// magnitude), not to 4 digits of their own noise; fewer digits when the study says so.
    #[test]
    fn table_numbers_have_their_own_digits_above_the_column_floor() {
        assert_eq!(table_value_exponent(0.123_456, Some(-7), 4), Some(-4));
        assert_eq!(table_value_exponent(3.1e-12, Some(-7), 4), Some(-7));
        assert_eq!(table_value_exponent(0.0, Some(-7), 4), Some(-7));
        assert_eq!(table_value_exponent(0.123_456, None, 2), Some(-2));
        let mut t = Table::new("s", &[("k", "1"), ("a", "1")]).reproducible_digits(2);
        t.push_nums(&[1.0, 0.1409]).unwrap();
        t.push_nums(&[2.0, 1.0]).unwrap();
        t.push_nums(&[3.0, 2.0e-9]).unwrap();
        assert_eq!(committed_table_csv(&t), "k [1],a [1]\n1,0.14\n2,1\n3,0\n");
    }

    /// A declared noise floor (Liu Fig. 17): every value at 10^-2 of the largest magnitude.
    #[test]
    fn declared_noise_floor() {
        use crate::{Figure, Series};
        let mut t = Table::new("s", &[("k", "1"), ("a", "1")]).reproducible_decades(2);
        t.push_nums(&[1.0, 0.1409]).unwrap();
        t.push_nums(&[2.0, 1.0]).unwrap();
        t.push_nums(&[3.0, 0.00723]).unwrap();
        assert_eq!(
            committed_table_csv(&t),
            "k [1],a [1]\n1,0.14\n2,1\n3,0.01\n"
        );
        let f = Figure::new("f", "t", ("x", "1"), ("y", "1"))
            .with(Series::line(
                "a",
                vec![(1.0, 0.1409), (2.0, 1.0), (3.0, 0.00723)],
            ))
            .reproducible_decades(2);
        let d = drawn_figure(&f);
        assert_eq!(d.series[0].points[0].1.to_bits(), 0.14f64.to_bits());
        assert_eq!(d.series[0].points[2].1.to_bits(), 0.01f64.to_bits());
    }

    /// A figure's committed ordinates: the coarser of the axis step and 3 significant digits
    /// of their own; the axis range includes the unsettled points, so leaving one out does not
    /// re-round the others.
    #[test]
    fn figure_ordinates_do_not_follow_the_unsettled_points() {
        use crate::{Figure, Series};
        let pts = vec![(0.0, 1.234_56e-4), (1.0, 2.345_67e-3), (2.0, 1.5e-3)];
        let f = |u: [bool; 3]| {
            Figure::new("f", "t", ("x", "1"), ("y", "1"))
                .with(Series::line("a", pts.clone()).unsettled(u))
        };
        let a = drawn_figure(&f([false, false, false]));
        let b = drawn_figure(&f([false, true, false]));
        assert_eq!(a.series[0].points[0], (0.0, 1.23e-4));
        assert_eq!(a.series[0].points[1], (1.0, 2.35e-3));
        assert_eq!(
            b.series[0].points,
            vec![a.series[0].points[0], a.series[0].points[2]]
        );
    }

    /// Unsettled figure points leave the committed figure; an emptied series stays as a
    /// legend entry without points.
    #[test]
    fn unsettled_points_leave_the_drawn_figure() {
        use crate::{Figure, Series};
        let f = Figure::new("f", "t", ("x", "1"), ("y", "1"))
            .with(
                Series::line("a", vec![(0.0, 1.0), (1.0, 2.0), (2.0, 50.0)])
                    .unsettled([false, false, true]),
            )
            .with(Series::markers("b", vec![(0.0, 7.0)]).unsettled([true]));
        let d = drawn_figure(&f);
        assert_eq!(d.series.len(), 2);
        assert_eq!(d.series[0].points, vec![(0.0, 1.0), (1.0, 2.0)]);
        assert!(d.series[1].points.is_empty() && d.series[1].label == "b");
        assert!(d.series[0].unsettled.is_empty());
        // the original keeps every point (validation/stats/)
        assert_eq!(f.series[0].points.len(), 3);
    }

    /// An unsettled comparison commits `n/p` for value and deviation, and keeps its verdict.
    #[test]
    fn unsettled_comparisons_commit_the_verdict_only() {
        use crate::{Comparison, Reference, Tolerance};
        let c = Comparison::new(
            "xi",
            "1",
            Reference::computed(53.6, "paper"),
            85.0,
            Tolerance::numerical(1e-3),
        )
        .within(35.0, 135.0);
        let v = c.verdict();
        let u = c.clone().unsettled_if(true);
        assert_eq!(u.committed_model(), NOT_PERIODIC);
        assert_eq!(
            u.committed_deviation(),
            (NOT_PERIODIC.to_owned(), NOT_PERIODIC.to_owned())
        );
        assert_eq!(u.verdict(), v);
        assert_ne!(c.committed_model(), NOT_PERIODIC);
        // a flagged row (inconclusive) commits n/p too
        let f = c
            .clone()
            .flagged("at 162.5: time integration: non-periodic motion");
        assert_eq!(f.committed_model(), NOT_PERIODIC);
        assert_eq!(f.verdict(), crate::Verdict::Inconclusive);
    }

    #[test]
    fn digest_is_fnv1a() {
        assert_eq!(digest(b""), "cbf29ce484222325");
        assert_eq!(digest(b"a"), "af63dc4c8601ec8c");
    }
}
