//! Basin studies (`[basin]`): every cell labelled, fractions that sum to one, outputs identical
//! for any thread count and for a sharded run, and the study-file checks.

#![allow(clippy::float_cmp)]

use geardyn_study::shard::ShardSpec;

/// A 2 × 2 Liu basin at ε = 0, 160 rad/s with short, coarse windows (20 periods from the start,
/// none discarded, rtol 1e-5, samples every 1.0: a mechanics test, not a settled answer), so that
/// the test stays fast at opt-level 0.
fn liu_basin(extra: &str) -> String {
    format!(
        "name = \"b\"\nmodel = \"liu2021\"\n[overrides]\neccentricity = 0.0\nomega1 = 160.0\n\
         readings.base_radius = \"mean\"\n[solver]\nmethod = \"time-stepping\"\n\
         [solver.settings]\nwindow_periods = 20\nmax_transient_periods = 0\n\
         transient_periods = 0\nrtol = 1e-5\nsample_step = 1.0\n\
         [basin]\nq = {{ from = -2.0, to = 0.5, steps = 2 }}\n\
         q_dot = {{ from = -0.5, to = 0.5, steps = 2 }}\n{extra}"
    )
}

use crate::user_study::{err, run};

#[test]
fn every_cell_is_labelled_and_the_fractions_sum_to_one() {
    let text = liu_basin("");
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| run(&text));
    let two = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap()
        .install(|| run(&text));
    let b = one.basins.as_ref().expect("basins");
    assert!(one.failed.is_empty(), "{:?}", one.failed);
    assert!(!b.attractors.is_empty());
    let sum: f64 = b.attractors.iter().map(|a| a.fraction).sum::<f64>() + b.failed_fraction();
    assert!((sum - 1.0).abs() < 1e-12, "{sum}");
    // the table: the grid (q fastest), the model's columns, the label
    let csv = one.table.to_csv();
    assert!(csv.starts_with("q,q_dot,rsv [1],ppv [1]"), "{csv}");
    assert!(csv.lines().next().unwrap().ends_with(",attractor"), "{csv}");
    assert_eq!(one.column("q").unwrap(), [-2.0, 0.5, -2.0, 0.5]);
    assert_eq!(one.column("q_dot").unwrap(), [-0.5, -0.5, 0.5, 0.5]);
    let labels = one.column("attractor").unwrap();
    assert!(labels.iter().all(|l| l.is_finite()));
    // each cell's label is the attractor of its own rsv, motion and ppv
    let (rsv, ppv) = (one.column("rsv").unwrap(), one.column("ppv").unwrap());
    for k in 0..4 {
        let a = &b.attractors[labels[k] as usize];
        assert_eq!(f64::from(a.state), rsv[k]);
        assert!(ppv[k] >= a.ppv_min && ppv[k] <= a.ppv_max);
    }
    // fractions table: one row per attractor and the failed row; the map; the summary
    assert_eq!(one.tables.len(), 1);
    assert_eq!(one.tables[0].name, "b_fractions");
    assert_eq!(one.tables[0].rows.len(), b.attractors.len() + 1);
    assert!(one.maps.iter().any(|m| m.name == "b_attractor_map"));
    assert_eq!(
        one.summary["basin"]["attractors"].as_array().unwrap().len(),
        b.attractors.len()
    );
    // bit-identical for one and two threads
    assert_eq!(csv, two.table.to_csv());
    assert_eq!(one.tables[0].to_csv(), two.tables[0].to_csv());
    // and sharded in two, merged: the same outputs
    let parts: Vec<String> = (0..2)
        .map(|i| {
            geardyn_study::run_shard_from_str(&text, ShardSpec::new(i + 1, 2).unwrap()).unwrap()
        })
        .collect();
    let merged = geardyn_study::merge_from_str(&text, &parts).unwrap();
    assert_eq!(csv, merged.table.to_csv());
    assert_eq!(one.tables[0].to_csv(), merged.tables[0].to_csv());
}

#[test]
fn basin_files_are_checked_before_computing() {
    let e = err(&liu_basin("ppv_tol = 0.0\n"));
    assert!(e.contains("basin.ppv_tol"), "{e}");
    let e = err(&liu_basin("").replace("steps = 2 }\nq_dot", "steps = 1 }\nq_dot"));
    assert!(
        e.contains("basin.q.steps") && e.contains("[2, 1000]"),
        "{e}"
    );
    let e = err(&liu_basin("").replace(
        "from = -0.5, to = 0.5, steps = 2",
        "from = 0.5, to = 0.5, steps = 2",
    ));
    assert!(e.contains("basin.q_dot.to"), "{e}");
    let e = err(&liu_basin("").replace(
        "steps = 2 }\nq_dot = { from = -0.5, to = 0.5, steps = 2 }",
        "steps = 1000 }\nq_dot = { from = -0.5, to = 0.5, steps = 1000 }",
    ));
    assert!(e.contains("basin.cells"), "{e}");
    let e = err(&format!(
        "{}\n[sweep]\nparameter = \"omega1\"\nvalues = [150.0]\n",
        liu_basin("")
    ));
    assert!(e.contains("fixed parameters"), "{e}");
    // harmonic balance has no initial state (nor `motion`): refused
    let e = err(&liu_basin("")
        .replace("method = \"time-stepping\"", "method = \"hbm\"")
        .replace(
            "window_periods = 20\nmax_transient_periods = 0\ntransient_periods = 0\n",
            "",
        ));
    assert!(e.contains("[basin]") && e.contains("initial"), "{e}");
    // the model checks each initial state: a longer base state is refused by Liu
    let e = err(&liu_basin("").replace("[solver]", "initial = [0.0, 0.0, 1.0]\n[solver]"));
    assert!(e.contains("initial"), "{e}");
    // the work limits apply to the grid as to a sweep
    let e = err(&liu_basin("").replace("[solver]", "[limits]\nmax_points = 3\n[solver]"));
    assert!(e.contains("max_points") || e.contains("3"), "{e}");
}
