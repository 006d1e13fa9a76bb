//! Fuzzing of the study path and the models' entry points (proptest-generated inputs).
//!
//! * `fuzz_smoke` (always): a few dozen cases, part of `cargo test`.
//! * `fuzz_budget` (`#[ignore]`; run by `.ci/run` in release): cases until the time budget
//!   `GEARDYN_FUZZ_SECONDS` (default 45 s) is spent.
//!
//! Every case runs on a watchdog thread: a case over `CASE_SECONDS` is a hang and fails the
//! run. Asserted: no panic escapes, no panic is caught inside a point (a caught panic is a bug
//! behind a safety net), and no success carries a non-finite number.

use std::sync::mpsc;
use std::time::{Duration, Instant};

use geardyn_study::{RunOptions, UserStudy, run_study_from_str};
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::{Config, TestRng, TestRunner};

/// Longest a single case may take before it counts as a hang (debug builds are slower).
const CASE_SECONDS: u64 = if cfg!(debug_assertions) { 60 } else { 20 };

/// Values a hostile user would try, and ordinary ones.
fn number() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(0.0),
        Just(-1.0),
        Just(-3.0),
        Just(1e-300),
        Just(1e-12),
        Just(1e17),
        Just(1e300),
        Just(-1e308),
        Just(4503599627370496.0),
        Just(9.223372036854776e18),
        Just(4294967295.0),
        Just(0.5),
        Just(2.0),
        (-3i32..4).prop_map(|e| 10f64.powi(e)),
        (0.01f64..10.0),
    ]
}

fn model_case() -> impl Strategy<
    Value = (
        &'static str,
        &'static str,
        Vec<&'static str>,
        Vec<&'static str>,
    ),
> {
    prop_oneof![
        Just((
            "karpov2017-kinematics",
            "kinematics",
            vec!["r", "u", "b", "xi", "j", "z1", "omega1", "delta_max"],
            vec![],
        )),
        Just((
            "karpov2017",
            "time-stepping",
            vec!["omega", "b", "xi", "k", "tau_end"],
            vec!["rtol"],
        )),
        Just((
            "liu2021",
            "time-stepping",
            vec![
                "omega1",
                "eccentricity",
                "kr",
                "er",
                "half_backlash",
                "load_torque",
                "z1"
            ],
            vec![
                "transient_periods",
                "record_periods",
                "sample_step",
                "max_step",
                "rtol"
            ],
        )),
        Just((
            "liu2021",
            "hbm",
            vec!["omega1", "eccentricity", "kr", "er", "half_backlash"],
            vec!["tol", "max_iter", "samples", "full_r"],
        )),
        Just((
            "yu2021",
            "time-stepping",
            vec![
                "omega",
                "mass_g",
                "torque",
                "mesh_stiffness",
                "ste_amplitude",
                "chen_dimension"
            ],
            vec![
                "transient_periods",
                "record_periods",
                "steps_per_period",
                "rms_harmonics"
            ],
        )),
        Just((
            "yu2021",
            "hbm",
            vec!["omega", "torque", "ste_amplitude"],
            vec!["harmonics", "samples", "tolerance", "max_iterations"],
        )),
    ]
}

/// A study file: a model, some overrides, maybe a sweep, some settings, small limits so that
/// every case is cheap.
fn study_text() -> impl Strategy<Value = String> {
    (
        model_case(),
        proptest::collection::vec((0usize..8, number()), 0..4),
        proptest::collection::vec((0usize..5, number()), 0..3),
        proptest::option::of((0usize..8, number(), number(), 2i64..4)),
        prop_oneof![
            Just(""),
            Just("variant = \"chen\"\n"),
            Just("variant = 2\n")
        ],
    )
        .prop_map(
            |((model, method, params, settings), ov, st, sweep, extra)| {
                let mut t = format!("name = \"fuzz\"\nmodel = \"{model}\"\n");
                t.push_str("[limits]\nmax_points = 4\nmax_steps = 200000\n[overrides]\n");
                if model == "yu2021" {
                    t.push_str("omega = 0.7\n");
                    t.push_str(extra);
                }
                let mut seen = std::collections::BTreeSet::new();
                if model == "yu2021" {
                    seen.insert("omega");
                }
                for (i, v) in ov {
                    let k = params[i % params.len()];
                    if seen.insert(k) {
                        t.push_str(&format!("{k} = {v:e}\n"));
                    }
                }
                if let Some((i, a, b, n)) = sweep {
                    let k = params[i % params.len()];
                    if !seen.contains(k) {
                        t.push_str(&format!(
                            "[sweep]\nparameter = \"{k}\"\nfrom = {a:e}\nto = {b:e}\nsteps = {n}\n"
                        ));
                    }
                }
                t.push_str(&format!(
                    "[solver]\nmethod = \"{method}\"\n[solver.settings]\n"
                ));
                let mut seen = std::collections::BTreeSet::new();
                if !settings.is_empty() {
                    for (i, v) in st {
                        let k = settings[i % settings.len()];
                        if seen.insert(k) {
                            t.push_str(&format!("{k} = {v:e}\n"));
                        }
                    }
                }
                t
            },
        )
}

/// Run one study text on a watchdog thread; panics (failing the test) on an escaped panic, a
/// caught panic, a non-finite success or a hang.
fn check_study(text: String, tally: &mut [u32; 4]) {
    let (tx, rx) = mpsc::channel();
    let t = text.clone();
    std::thread::spawn(move || {
        let r = std::panic::catch_unwind(|| {
            // the parser alone must never panic either
            let _ = UserStudy::parse(&t);
            run_study_from_str(&t, &RunOptions::default())
        });
        let _ = tx.send(r.map(|r| r.map(|o| (o.failed, o.table))).map_err(|_| ()));
    });
    match rx.recv_timeout(Duration::from_secs(CASE_SECONDS)) {
        Err(_) => panic!("hang (> {CASE_SECONDS} s) on\n{text}"),
        Ok(Err(())) => panic!("panic escaped on\n{text}"),
        Ok(Ok(Err(_))) => tally[0] += 1, // a clear error
        Ok(Ok(Ok((failed, table)))) => {
            let k = if failed.is_empty() {
                1
            } else if failed.len() == table.rows.len() {
                3
            } else {
                2
            };
            tally[k] += 1;
            for f in &failed {
                assert!(
                    !f.error.contains("panic caught"),
                    "caught panic: {}\n{text}",
                    f.error
                );
            }
            let bad: std::collections::BTreeSet<usize> = failed.iter().map(|f| f.index).collect();
            for (i, row) in table.rows.iter().enumerate() {
                if bad.contains(&i) {
                    continue;
                }
                for c in row {
                    if let geardyn_study::Cell::Num(x) = c {
                        assert!(x.is_finite(), "non-finite success in row {i}\n{text}");
                    }
                }
            }
        }
    }
}

/// The models' constructors and cheap entry points with raw random numbers.
fn check_entry_points(v: Vec<f64>) {
    use models::karpov2017::Karpov2017;
    let (tx, rx) = mpsc::channel();
    let vv = v.clone();
    std::thread::spawn(move || {
        let r = std::panic::catch_unwind(move || {
            let g = |i: usize| vv[i % vv.len()];
            if let Ok(m) = Karpov2017::fig3().with(|p| {
                p.omega = g(0);
                p.b = g(1).abs().min(0.99);
                p.xi = g(2);
                p.k = g(3);
                p.tau_end = g(4);
            }) {
                // Keep the work per case small (the estimate of the quadrature's panel count);
                // larger cases are refused by the panel budget, tested in the model's own tests.
                // `panel_estimate` is a lower bound (smallest phase rate 1 + ω(1 − B)); the mean
                // rate 1 + ω bounds the work better when B → 1 (ω = 9.2e18, B = 0.99 took 6 s
                // per call at an "estimate" of 9e4 panels).
                let p = m.params();
                let cheap = |theta: f64| {
                    let theta = theta.clamp(1e-3, 8.0);
                    m.panel_estimate(theta) < 2e5
                        && 3.0 * p.tau_end * (1.0 + p.omega) / (2.0 * theta) < 2e5
                };
                if cheap(g(5)) && cheap(g(5).clamp(0.5, 8.0)) {
                    if let Ok(r) = m.duhamel_with(g(5)) {
                        assert!(r.x.is_finite() && r.envelope.is_finite(), "karpov {vv:?}");
                    }
                    if let Ok(r) = m.duhamel_with(g(5).clamp(0.5, 8.0)) {
                        assert!(r.amplitude.is_finite(), "karpov {vv:?}");
                    }
                    // the folded rule costs at most ~4× the direct one (its phase over the
                    // folded period is ≈ 4Bωτ_end ≤ 4 × the direct rule's)
                    if let Ok(r) = m.duhamel_folded(g(5).clamp(0.5, 8.0)) {
                        assert!(r.amplitude.is_finite(), "karpov folded {vv:?}");
                    }
                }
            }
            let _ = backlash::ChenFractal::new(g(6), g(7), g(8).abs().min(4e9) as u32)
                .map(|c| c.value(g(0)));
            let mut p = models::liu2021::table1();
            p.omega1 = g(0);
            p.eccentricity = g(1);
            p.kr = g(2);
            p.half_backlash = g(3);
            let _ = p.model();
            let mut y = models::yu2021::Yu2021Params::table1();
            y.mass_g = g(4);
            y.torque = g(5);
            if let Ok(m) = models::yu2021::Yu2021Model::new(&y, models::yu2021::Options::default())
            {
                let s = models::yu2021::RunSettings {
                    omega: g(6),
                    transient_periods: 1,
                    record_periods: 1,
                    steps_per_period: (g(7).abs().min(1e19)) as usize,
                };
                // only the size check: a run is cheap only within a budget
                if let Ok(n) = m.run_steps(&s)
                    && n < 200_000
                {
                    let _ = m.simulate(&s, None);
                }
            }
        });
        let _ = tx.send(r.is_ok());
    });
    match rx.recv_timeout(Duration::from_secs(CASE_SECONDS)) {
        Err(_) => panic!("hang (> {CASE_SECONDS} s) on {v:?}"),
        Ok(false) => panic!("panic on {v:?}"),
        Ok(true) => {}
    }
}

/// Returns (study files, parameter sets, [errors, all points ok, some failed, all failed]).
fn run_for(cases: u32, budget: Duration) -> (u32, u32, [u32; 4]) {
    let start = Instant::now();
    let mut runner = TestRunner::new_with_rng(
        Config {
            cases,
            failure_persistence: None,
            ..Config::default()
        },
        TestRng::deterministic_rng(proptest::test_runner::RngAlgorithm::ChaCha),
    );
    let (mut studies, mut sets, mut tally) = (0, 0, [0u32; 4]);
    let studies_s = study_text();
    let sets_s = proptest::collection::vec(number(), 9);
    while studies < cases && start.elapsed() < budget {
        let text = studies_s.new_tree(&mut runner).expect("strategy").current();
        let t0 = Instant::now();
        check_study(text.clone(), &mut tally);
        if t0.elapsed() > Duration::from_secs(2) {
            println!(
                "slow study case ({:.1} s):\n{text}",
                t0.elapsed().as_secs_f64()
            );
        }
        studies += 1;
        let v = sets_s.new_tree(&mut runner).expect("strategy").current();
        let t0 = Instant::now();
        check_entry_points(v.clone());
        if t0.elapsed() > Duration::from_secs(2) {
            println!(
                "slow parameter set ({:.1} s): {v:?}",
                t0.elapsed().as_secs_f64()
            );
        }
        sets += 1;
    }
    (studies, sets, tally)
}

#[test]
fn fuzz_smoke() {
    let (a, b, _) = run_for(24, Duration::from_secs(120));
    assert!(a > 0 && b > 0);
}

#[test]
#[ignore = "time-budgeted fuzzer; run by .ci/run (cargo test --release -- --ignored)"]
fn fuzz_budget() {
    let secs = std::env::var("GEARDYN_FUZZ_SECONDS")
        .ok()
        .and_then(|s| s.parse::<u64>().ok())
        .unwrap_or(45);
    let (a, b, t) = run_for(u32::MAX, Duration::from_secs(secs));
    println!(
        "fuzz: {a} study files ({} refused with an error, {} all points computed, {} with \
         failed points, {} with every point failed) and {b} parameter sets in {secs} s; \
         no panic, hang or non-finite success",
        t[0], t[1], t[2], t[3]
    );
}
