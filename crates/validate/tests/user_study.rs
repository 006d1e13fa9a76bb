//! The shipped user-study examples parse and (where fast) run.

use geardyn_validate::{UserStudy, run_user_study};

#[test]
fn karpov_kinematics_example_runs() {
    let text = include_str!("../../../validation/examples/karpov-delta-vs-b.toml");
    let study = UserStudy::parse(text).unwrap();
    let out = run_user_study(&study, || {}).unwrap();
    assert_eq!(out.table.rows.len(), 50 * 4);
    assert_eq!(
        out.summary["failed_points"].as_array().map(Vec::len),
        Some(0)
    );
    assert_eq!(out.figures.len(), 5);
    // δ exact grows with B along each curve.
    let s = &out.figures[0].series[0].points;
    assert!(s.windows(2).all(|w| w[1].1 > w[0].1));
}

#[test]
fn bad_parameter_is_a_study_file_error() {
    let text = "name = \"x\"\nmodel = \"karpov2017-kinematics\"\n[overrides]\nnope = 1.0\n\
                [solver]\nmethod = \"kinematics\"\n";
    let study = UserStudy::parse(text).unwrap();
    let err = run_user_study(&study, || {}).unwrap_err().to_string();
    assert!(err.contains("nope"), "{err}");
}

#[test]
fn invalid_value_is_a_failed_point_not_a_panic() {
    let text = "name = \"x\"\nmodel = \"karpov2017-kinematics\"\n[overrides]\nb = 1.5\n\
                [solver]\nmethod = \"kinematics\"\n";
    let study = UserStudy::parse(text).unwrap();
    let out = run_user_study(&study, || {}).unwrap();
    assert_eq!(
        out.summary["failed_points"].as_array().map(Vec::len),
        Some(1)
    );
}

#[test]
fn every_shipped_example_parses() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../validation/examples");
    let mut n = 0;
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(Result::ok)
        .collect();
    entries.sort_by_key(|e| e.file_name());
    for e in entries {
        let path = e.path();
        if path.extension().and_then(|x| x.to_str()) == Some("toml") {
            let text = std::fs::read_to_string(&path).unwrap();
            let s = UserStudy::parse(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            assert!(geardyn_validate::MODELS.iter().any(|(m, _)| *m == s.model));
            n += 1;
        }
    }
    assert!(n >= 4, "expected the shipped examples, found {n}");
}

#[test]
fn unwired_or_misconfigured_models_are_errors() {
    let text = "name = \"x\"\nmodel = \"liu2021\"\n[solver]\nmethod = \"kinematics\"\n";
    let study = UserStudy::parse(text).unwrap();
    assert!(run_user_study(&study, || {}).is_err());
    let text = "name = \"x\"\nmodel = \"yu2021\"\n[solver]\nmethod = \"time-stepping\"\n";
    let study = UserStudy::parse(text).unwrap();
    let err = run_user_study(&study, || {}).unwrap_err().to_string();
    assert!(err.contains("omega"), "{err}");
}

/// Both engines of the Yu model are reachable from a study file and agree on a non-impacting
/// Kahraman–Singh point (the models crate tests the engines against each other to 1e-8).
#[test]
fn yu_engines_selectable_and_agree() {
    let run = |engine: u32| {
        let text = format!(
            "name = \"x\"\nmodel = \"yu2021\"\n[overrides]\nomega = 0.3\nvariant = 1\n\
             [solver]\nmethod = \"time-stepping\"\n[solver.settings]\nengine = {engine}\n\
             transient_periods = 20\nrecord_periods = 4\nsteps_per_period = 128\n"
        );
        let study = UserStudy::parse(&text).unwrap();
        let out = run_user_study(&study, || {}).unwrap();
        assert_eq!(
            out.summary["failed_points"].as_array().map(Vec::len),
            Some(0)
        );
        let col = out
            .table
            .columns
            .iter()
            .position(|c| c.name == "df")
            .expect("df column");
        match &out.table.rows[0][col] {
            geardyn_validate::Cell::Num(x) => *x,
            other => panic!("df is not a number: {other:?}"),
        }
    };
    let (rk4, dp) = (run(0), run(1));
    assert!(
        rk4 > 1.0 && (rk4 - dp).abs() < 1e-4 * rk4,
        "DF {rk4} vs {dp}"
    );

    let bad = "name = \"x\"\nmodel = \"yu2021\"\n[overrides]\nomega = 0.3\n\
               [solver]\nmethod = \"time-stepping\"\n[solver.settings]\nengine = 7\n";
    let study = UserStudy::parse(bad).unwrap();
    let err = run_user_study(&study, || {}).unwrap_err().to_string();
    assert!(err.contains("engine"), "{err}");
}
