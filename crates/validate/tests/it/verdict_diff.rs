//! Issue 28, "done when": on synthetic studies (fast), a retune that moves values inside their
//! bands gives a small committed diff and a `--diff` that says "no verdict changed" with the
//! moved values listed; a change that flips a verdict is at the top of `--diff` and fails the
//! `--check` verdict comparison.

use math::DetMath;
use std::collections::BTreeMap;

use geardyn_validate::{
    Cell, Claim, Comparison, Cost, Figure, Paper, ReadingsIndex, Reference, Series, Study,
    StudyOutput, StudyResult, Table, Tolerance, Verdict, check_verdicts, diff_verdicts,
    parse_verdicts, render_all, render_stats,
};

/// The knobs a "solver constant" would move: the in-band value, its neighbour, the far
/// deviation, the curve, the solver statistics and a one-period sample of a chaotic orbit.
struct Knobs {
    fc: f64,
    ratio: f64,
    xi: f64,
    curve_eps: f64,
    steps: u64,
    chaotic_sample: f64,
}

const BASE: Knobs = Knobs {
    fc: 38.6712,
    ratio: 1.0010,
    xi: 220.692,
    curve_eps: 0.0,
    steps: 47_072,
    chaotic_sample: 262.6,
};

/// A solver-constant retune: every value moves a little (the in-band ones by far less than
/// their band, `ratio` by 0.4 of its band), counters and the chaotic sample move a lot.
const RETUNED: Knobs = Knobs {
    fc: 38.67121,
    ratio: 1.0030,
    xi: 220.75,
    curve_eps: 1e-7,
    steps: 48_311,
    chaotic_sample: 280.7,
};

/// A model change that moves f_c out of its band.
const FLIPPED: Knobs = Knobs {
    fc: 38.69,
    ..RETUNED
};

fn output(k: &Knobs) -> Result<StudyOutput, geardyn_validate::Error> {
    let mut out = StudyOutput::new();
    out.compare(Comparison::new(
        "f_c at ω1 = 160 rad/s",
        "Hz",
        Reference::computed(38.67, "Table 2"),
        k.fc,
        Tolerance::printed("38.67")?,
    ));
    out.compare(Comparison::new(
        "ratio",
        "1",
        Reference::computed(1.0, "text"),
        k.ratio,
        Tolerance::printed("1.00")?,
    ));
    out.compare(
        Comparison::new(
            "ξ (theoretical) at n = 1064 rpm",
            "1",
            Reference::computed(56.0, "Table 2"),
            k.xi,
            Tolerance::printed("56.0")?,
        )
        .within(k.xi, k.xi + 14.2)
        .reading("R-LIU-TABLE2"),
    );
    out.claim(Claim::new(
        "the gear rattles above 150 rad/s",
        "p. 9",
        "bilateral from 152.5 rad/s",
        Verdict::Pass,
    ));
    let mut t = Table::new(
        "sweep",
        &[
            ("omega1", "rad/s"),
            ("ppv_time", "1"),
            ("time_motion_period", "1"),
            ("ppv_window", "1"),
            ("steps_accepted", "1"),
            ("residual_norm_hbm", "1"),
        ],
    );
    for (i, w) in [150.0, 152.5, 155.0].into_iter().enumerate() {
        let periodic = i != 1;
        t.push(vec![
            Cell::Num(w),
            Cell::Num(if periodic {
                0.1 * w * (1.0 + k.curve_eps)
            } else {
                k.chaotic_sample
            }),
            Cell::Num(if periodic { 1.0 } else { 0.0 }),
            Cell::Num(0.2 * w * (1.0 + k.curve_eps)),
            Cell::Count(k.steps + i as u64),
            Cell::Num(1e-20 * k.fc),
        ])?;
    }
    out.table(t);
    out.figure(
        Figure::new("ppv", "ppv vs ω1", ("ω1", "rad/s"), ("ppv", "1")).with(Series::line(
            "time integration",
            (0..50)
                .map(|i| {
                    let x = 100.0 + i as f64;
                    (x, (x / 10.0).dsin() * (1.0 + k.curve_eps))
                })
                .collect(),
        )),
    );
    // a time record at the chaotic point: reshuffled by any retune
    out.figure(
        Figure::new(
            "time_152.5",
            "record at 152.5 rad/s",
            ("t", "s"),
            ("q", "1"),
        )
        .with(Series::line(
            "time integration",
            (0..40)
                .map(|i| (i as f64, (i as f64 * k.chaotic_sample).dsin()))
                .collect(),
        ))
        .non_periodic_record(true),
    );
    Ok(out)
}

fn base() -> Result<StudyOutput, geardyn_validate::Error> {
    output(&BASE)
}
fn retuned() -> Result<StudyOutput, geardyn_validate::Error> {
    output(&RETUNED)
}
fn flipped() -> Result<StudyOutput, geardyn_validate::Error> {
    output(&FLIPPED)
}

fn study(run: fn() -> Result<StudyOutput, geardyn_validate::Error>) -> Study {
    Study {
        id: "liu2021-synthetic",
        paper: Paper::Liu2021,
        source: "Table 2, p. 12",
        title: "synthetic",
        description: "",
        cost: Cost::Fast,
        run,
    }
}

fn results(run: fn() -> Result<StudyOutput, geardyn_validate::Error>) -> Vec<StudyResult> {
    let s = study(run);
    vec![StudyResult {
        study: s,
        output: s.execute(),
        cost: Default::default(),
    }]
}

/// Changed lines per file (a line-multiset difference: what `git diff` would count).
fn changed_lines(
    a: &BTreeMap<String, Vec<u8>>,
    b: &BTreeMap<String, Vec<u8>>,
) -> BTreeMap<String, usize> {
    let mut out = BTreeMap::new();
    for (k, va) in a {
        let vb = b.get(k).cloned().unwrap_or_default();
        if *va == vb {
            continue;
        }
        let la: Vec<&str> = std::str::from_utf8(va).unwrap().lines().collect();
        let lb: Vec<String> = String::from_utf8(vb)
            .unwrap()
            .lines()
            .map(str::to_owned)
            .collect();
        let mut count = 0;
        for l in &la {
            if !lb.iter().any(|m| m == l) {
                count += 1;
            }
        }
        for l in &lb {
            if !la.contains(&l.as_str()) {
                count += 1;
            }
        }
        out.insert(k.clone(), count);
    }
    out
}

fn verdicts(files: &BTreeMap<String, Vec<u8>>) -> String {
    String::from_utf8(files["verdicts.csv"].clone()).unwrap()
}

/// (a) A retune that moves values inside their bands: the committed diff is a handful of lines
/// (the one value that moved by 0.4 of its band, its deviation in REPORT.md and the study CSV,
/// its verdict line, and the one-line stats digest); solver counters and the chaotic sample do
/// not appear; `--diff` says no verdict changed and lists the moved value.
#[test]
fn retune_inside_the_bands_is_a_small_diff_and_no_verdict_change() {
    let idx = ReadingsIndex::default();
    let (ra, rb) = (results(base), results(retuned));
    let (a, b) = (render_all(&ra, &idx), render_all(&rb, &idx));
    let changed = changed_lines(&a, &b);
    let total: usize = changed.values().sum();
    assert!(total <= 12, "retune diff too large: {changed:?}");
    for f in changed.keys() {
        assert!(
            !f.ends_with("_sweep.csv") && !f.ends_with("_ppv.csv") && !f.ends_with(".svg"),
            "{f} changed although its data moved below drawing precision"
        );
    }
    assert!(
        changed.contains_key("stats-digest.txt"),
        "the stats digest catches the counters"
    );
    let stats_a = render_stats(&ra);
    let stats_b = render_stats(&rb);
    let sweep = "liu2021/liu2021-synthetic_sweep.csv";
    let sa = String::from_utf8(stats_a[sweep].clone()).unwrap();
    let sb = String::from_utf8(stats_b[sweep].clone()).unwrap();
    assert!(sa.contains("47072") && sb.contains("48311") && sb.contains("280.7"));
    let committed = String::from_utf8(b[sweep].clone()).unwrap();
    assert!(!committed.contains("steps_accepted") && !committed.contains("residual_norm"));
    assert!(committed.contains("n/p") && !committed.contains("280.7"));
    // the record of the non-periodic orbit: in stats/ (moved), not committed
    let record = "liu2021/liu2021-synthetic_time_152.5.csv";
    assert!(!a.contains_key(record) && !b.contains_key(record.replace(".csv", ".svg").as_str()));
    assert_ne!(stats_a[record], stats_b[record]);

    let d = diff_verdicts(
        &parse_verdicts(&verdicts(&a)).unwrap(),
        &parse_verdicts(&verdicts(&b)).unwrap(),
    );
    assert!(!d.changes_meaning());
    let md = d.to_markdown("main", &|_, _| String::new());
    assert!(md.contains("**No verdict changed.**"), "{md}");
    assert!(
        md.contains("«ratio»") && md.contains("1.0010 → 1.0030"),
        "{md}"
    );
    assert!(
        !md.contains("f_c at ω1"),
        "a move of 0.002 band is not listed: {md}"
    );
    assert_eq!(d.moved.len(), 1);
    assert!(d.figures.is_empty());
    assert!(check_verdicts(&verdicts(&a), &verdicts(&b)).is_ok());
}

/// (b) A change that flips a verdict: first entry of `--diff`, and the `--check` verdict
/// comparison fails naming it.
#[test]
fn a_flipped_verdict_tops_the_diff_and_fails_the_check() {
    let idx = ReadingsIndex::default();
    let a = render_all(&results(base), &idx);
    let b = render_all(&results(flipped), &idx);
    let d = diff_verdicts(
        &parse_verdicts(&verdicts(&a)).unwrap(),
        &parse_verdicts(&verdicts(&b)).unwrap(),
    );
    assert!(d.changes_meaning());
    assert_eq!(d.verdicts.len(), 1);
    let md = d.to_markdown("main", &|_, _| String::new());
    let first = md.lines().find(|l| l.starts_with("- ")).expect("an entry");
    assert!(
        first.contains("pass → DEVIATION") && first.contains("f_c at ω1 = 160 rad/s"),
        "{md}"
    );
    assert!(md.contains("**1 verdict(s) changed.**"));
    let err = check_verdicts(&verdicts(&a), &verdicts(&b)).unwrap_err();
    assert!(err.contains("pass → DEVIATION"), "{err}");
}

/// Rows added and removed are listed; the verdict file round-trips through its parser.
#[test]
fn rows_added_and_removed() {
    let idx = ReadingsIndex::default();
    let a = verdicts(&render_all(&results(base), &idx));
    let rows = parse_verdicts(&a).unwrap();
    assert_eq!(geardyn_validate::verdicts::verdicts_csv(&rows), a);
    let mut fewer = rows.clone();
    let gone = fewer.remove(1);
    let d = diff_verdicts(&rows, &fewer);
    assert_eq!(d.removed, vec![gone]);
    assert!(check_verdicts(&a, &geardyn_validate::verdicts::verdicts_csv(&fewer)).is_err());
    let d = diff_verdicts(&fewer, &rows);
    assert_eq!(d.added.len(), 1);
}
