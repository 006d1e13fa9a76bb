//! The Karpov amplitudes published in `validation/` (Figs. 3–6, both readings, `τ_end = 10⁵`)
//! are converged to the stated tolerance: for every row, repeating the accepted quadrature with
//! its panels halved moves `A` by at most `1e-7·A` (column `A_change_halved`, computed by the
//! study itself), and the stated error estimate is within the same tolerance.
//!
//! The CSVs are the full-precision outputs of `cargo xtask validate` in `validation/stats/`
//! (issue 28: the committed tables hold values at drawing precision, the accuracy columns only
//! there; the stats' digest is committed and checked by `cargo xtask validate --check`). Before
//! a first `cargo xtask validate` (a fresh clone), or outside the workspace (a packaged crate),
//! there is nothing to read and the test says so.

use std::path::PathBuf;

/// `DUHAMEL_RTOL` of the model (the relative tolerance every amplitude is computed to).
const RTOL: f64 = 1e-7;
/// The CSVs print 6 significant digits: a change at the tolerance can round up by half a unit
/// of the 6th digit of itself.
const PRINT: f64 = 1.0 + 5e-6;

fn dir() -> Option<PathBuf> {
    let d = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../validation/stats/karpov2017");
    d.join("karpov2017-fig4-a-vs-omega_a-vs-omega.csv")
        .is_file()
        .then_some(d)
}

/// Columns by header name (the unit in brackets stripped), rows as strings.
fn read(path: &PathBuf) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    let mut lines = text.lines();
    let header = lines
        .next()
        .expect("header")
        .split(',')
        .map(|h| {
            h.split(" [")
                .next()
                .unwrap_or(h)
                .trim_matches('"')
                .to_string()
        })
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    (header, rows)
}

fn col(header: &[String], name: &str) -> usize {
    header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("column {name} missing in {header:?}"))
}

#[test]
fn published_karpov_amplitudes_converge_under_halving() {
    let Some(dir) = dir() else {
        eprintln!(
            "validation/stats/karpov2017 not found (run `cargo xtask validate` first; a packaged \
             crate has none): nothing to check"
        );
        return;
    };
    let files = [
        ("karpov2017-fig4-a-vs-omega_a-vs-omega.csv", "A"),
        ("karpov2017-fig5-a-vs-b-k_a-vs-b.csv", "A"),
        ("karpov2017-fig6-a-vs-b-xi_a-vs-b.csv", "A"),
        ("karpov2017-fig3-time-series_summary.csv", "a_final_duhamel"),
    ];
    let mut checked = 0;
    for (file, a_name) in files {
        let (header, rows) = read(&dir.join(file));
        let (ia, ie, ih) = if a_name == "A" {
            (
                col(&header, "A"),
                col(&header, "A_error_estimate"),
                col(&header, "A_change_halved"),
            )
        } else {
            (
                col(&header, a_name),
                col(&header, "a_final_error_estimate"),
                col(&header, "a_final_change_halved"),
            )
        };
        assert!(!rows.is_empty(), "{file}: no rows");
        for r in &rows {
            let num = |i: usize| -> f64 {
                r[i].parse()
                    .unwrap_or_else(|e| panic!("{file}: {:?}: {e}", r[i]))
            };
            let (a, est, dh) = (num(ia), num(ie), num(ih));
            // 1e-14·τ_end: the rounding floor of the model's acceptance test
            let tol = (RTOL * a + 1e-14 * 1e5) * PRINT;
            assert!(
                dh <= tol,
                "{file}: {r:?}: A moves by {dh:e} > {tol:e} under halving"
            );
            assert!(est <= tol, "{file}: {r:?}: estimate {est:e} > {tol:e}");
            checked += 1;
        }
    }
    // Figs. 4 (2 readings × 3 B × 41 ω), 5 (2 × 4 k × 5 B), 6 (2 × 5 ξ × 5 B), 3 (2 readings)
    assert_eq!(checked, 246 + 40 + 50 + 2);
}
