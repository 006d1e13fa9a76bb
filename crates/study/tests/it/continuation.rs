//! `[continuation]` study files: the Liu period-1 branch in ω1 with its unilateral-onset
//! grazing, and that grazing continued in (ω1, T2); the checks of the table.

use geardyn_study::{Cell, shard::ShardSpec};

use crate::user_study::{err, run};

/// Below Liu's unilateral onset (Table 1, the validation's constant-b̄ reading) up to it, and the onset in (ω1, T2).
const ONSET: &str = r#"
name = "onset"
model = "liu2021"
[overrides]
omega1 = 132.0
base_radius = "mean"   # the constant-b̄ reading of the validation
[solver]
method = "shooting"
[solver.settings]
transient_periods = 10   # the free transient decays by e^-17 a period (Table 1 damping)
[continuation]
parameter = "omega1"
to = 145.0
max_step = 2.0
stop_at = ["grazing"]
[continuation.codim2]
parameter = "load_torque"
range = [29.0, 31.0]
kinds = ["grazing"]
max_step = 0.5
max_points = 3
max_curves = 1
max_switches = 1
"#;

/// The unilateral onset by bisection on time integration, `liu2021-orbit-branch`'s committed
/// row (134.80941, bracket half-width 4.9e-4 rad/s with the located grazing's).
const ONSET_TI: f64 = 134.80941;

fn num(c: &Cell) -> f64 {
    c.number().unwrap_or(f64::NAN)
}

#[test]
#[ignore = "heavy: a Liu branch and a codim-2 curve by shooting, 6 s in the dev profile (cargo xtask heavy-tests; the Python test runs the same study)"]
fn liu_onset_branch_and_codim2_curve() {
    let out = run(ONSET);
    assert!(out.failed.is_empty(), "{:?}", out.failed);
    let c = &out.summary["continuation"];
    // the branch stops at its first special point, the drive flank's grazing, inside the
    // time-integration bracket widened by the located grazing's precision
    let special = out
        .tables
        .iter()
        .find(|t| t.name == "onset_special")
        .unwrap();
    assert_eq!(special.rows.len(), 1, "{c}");
    assert_eq!(
        special.rows[0][0],
        Cell::Text("grazing drive flank (max)".into())
    );
    let w = num(&special.rows[0][1]);
    // measured: 134.809409, 8e-7 from the bisection; bound: the bisection's half-width
    assert!((w - ONSET_TI).abs() < 4.9e-4, "onset {w}");
    assert!(
        c["stop"]
            .as_str()
            .unwrap()
            .starts_with("stopped after its first grazing drive flank")
    );
    // the branch below it: stable, in contact (drive-flank gap max < 0)
    let t = &out.table;
    let names: Vec<&str> = t.columns.iter().map(|c| c.name.as_str()).collect();
    let j = |n: &str| {
        names
            .iter()
            .position(|c| *c == n)
            .unwrap_or_else(|| panic!("{n}: {names:?}"))
    };
    assert!(t.rows.len() >= 4);
    for r in &t.rows[..t.rows.len() - 1] {
        assert!(num(&r[j("omega1")]) < w + 1e-9);
        assert!(num(&r[j("drive_flank_max")]) < 0.0);
        assert!((num(&r[j("stable")]) - 1.0).abs() < 0.5);
    }
    // the codim-2 curve: both directions from the onset at T2 = 30 N·m
    let curves = out
        .tables
        .iter()
        .find(|t| t.name == "onset_curves")
        .unwrap();
    let c2 = c["curves"].as_array().unwrap();
    assert_eq!(c2.len(), 2, "{c}");
    assert!(curves.rows.len() >= 4, "{c}");
    for r in &curves.rows {
        let (w2, t2) = (num(&r[4]), num(&r[5]));
        assert!((29.0 - 1e-9..=31.0 + 1e-9).contains(&t2) && w2.is_finite());
    }
    // a point of the curve away from the start: shooting there grazes the drive flank
    let far = curves
        .rows
        .iter()
        .max_by(|a, b| {
            (num(&a[5]) - 30.0)
                .abs()
                .total_cmp(&(num(&b[5]) - 30.0).abs())
        })
        .unwrap();
    let (w2, t2) = (num(&far[4]), num(&far[5]));
    assert!((t2 - 30.0).abs() > 0.2, "{t2}");
    let one = run(&format!(
        "name = \"check\"\nmodel = \"liu2021\"\n[overrides]\nomega1 = {w2:?}\nload_torque = {t2:?}\n\
         base_radius = \"mean\"\n\
         [solver]\nmethod = \"shooting\"\n[solver.settings]\ntransient_periods = 200\n"
    ));
    let gap = one.column("gap_max_drive").unwrap()[0];
    // measured: −9e-11 b̄ at (134.7207, 29.688); bound: the Newton tolerance of both solves
    assert!(
        gap.abs() < 1e-8,
        "gap max of the drive flank {gap} at ({w2}, {t2})"
    );
    // figures beside the CSV
    let figs: Vec<&str> = out.figures.iter().map(|f| f.name.as_str()).collect();
    assert_eq!(figs, ["onset_branch_q", "onset_branch_qp", "onset_curves"]);
    for f in &out.figures {
        f.to_svg().unwrap();
    }
}

#[test]
fn continuation_tables_are_checked_before_any_computation() {
    let base = "name = \"x\"\nmodel = \"liu2021\"\n[solver]\nmethod = \"shooting\"\n";
    for (extra, want) in [
        (
            "[continuation]\nparameter = \"speed\"\nto = 1.0\n",
            "not a continuation parameter",
        ),
        (
            "[continuation]\nparameter = \"omega1\"\nto = 150.0\n[continuation.codim2]\nparameter = \"backlash\"\nrange = [0.0, 1.0]\n",
            "continuation.codim2.parameter",
        ),
        (
            "[sweep]\nparameter = \"load_torque\"\nvalues = [1.0, 2.0]\n[continuation]\nparameter = \"omega1\"\nto = 150.0\n",
            "remove [sweep]",
        ),
        (
            "[continuation]\nparameter = \"omega1\"\nto = inf\n",
            "continuation.to",
        ),
    ] {
        let e = err(&format!("{base}{extra}"));
        assert!(e.contains(want), "{extra}: {e}");
    }
    let e = err(
        "name = \"x\"\nmodel = \"liu2021\"\n[solver]\nmethod = \"time-stepping\"\n\
         [continuation]\nparameter = \"omega1\"\nto = 150.0\n",
    );
    assert!(e.contains("method = \"shooting\""), "{e}");
    let e = err(
        "name = \"x\"\nmodel = \"yu2021\"\n[solver]\nmethod = \"shooting\"\n\
         [continuation]\nparameter = \"omega1\"\nto = 150.0\n",
    );
    assert!(
        e.contains("has no [continuation] study") && e.contains("liu2021"),
        "{e}"
    );
    let e = geardyn_study::run_shard_from_str(
        &format!("{base}[continuation]\nparameter = \"omega1\"\nto = 150.0\n"),
        ShardSpec::new(1, 2).unwrap(),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("does not shard"), "{e}");
}

#[test]
fn a_continuation_that_cannot_start_is_one_failed_point() {
    // the start equals the end: the model refuses the range, the study reports one failed
    // point with the message instead of an error or a panic
    let out = run(
        "name = \"x\"\nmodel = \"liu2021\"\n[overrides]\nomega1 = 150.0\n[solver]\n\
         method = \"shooting\"\n[continuation]\nparameter = \"omega1\"\nto = 150.0\n",
    );
    assert_eq!(out.failed.len(), 1);
    assert!(
        out.failed[0].error.contains("must differ"),
        "{}",
        out.failed[0].error
    );
    assert!(out.all_failed());
    // a codim-2 range without the second parameter's start value (T2 = 30 N·m, Table 1)
    let out = run(
        "name = \"x\"\nmodel = \"liu2021\"\n[overrides]\nomega1 = 150.0\n[solver]\n\
         method = \"shooting\"\n[continuation]\nparameter = \"omega1\"\nto = 160.0\n\
         [continuation.codim2]\nparameter = \"load_torque\"\nrange = [40.0, 60.0]\n",
    );
    assert_eq!(out.failed.len(), 1);
    let e = &out.failed[0].error;
    assert!(
        e.contains("continuation.codim2.range") && e.contains("30"),
        "{e}"
    );
}
