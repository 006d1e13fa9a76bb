//! One steady-state response of the Liu 2021 NFG model (Table 1, ω1 = 160 rad/s, constant-b̄
//! reading): harmonic balance on the paper's and on a full basis, and time integration; a
//! warm-started bilateral point (220 rad/s), the period-map stability and a short continuation.
#![allow(missing_docs)] // criterion_group! generates an undocumented pub fn

use criterion::{Criterion, criterion_group, criterion_main};
use geardyn_models::liu2021::{
    self, BaseRadius, BranchStability, HbmOptions, HbmStart, IntegrationOptions,
    SpeedContinuationOptions,
};
use math::DetMath;
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let mut p = liu2021::table1();
    p.readings.base_radius = BaseRadius::Mean;
    let m = p.model().expect("Table 1 is valid");
    let mut g = c.benchmark_group("liu2021");
    g.sample_size(10);
    g.bench_function("hbm_paper_basis_15", |b| {
        b.iter(|| liu2021::solve_hbm(black_box(&m), &HbmOptions::default(), None))
    });
    let full = HbmOptions::full(&m, 1);
    g.bench_function("hbm_full_basis_131", |b| {
        b.iter(|| liu2021::solve_hbm(black_box(&m), &full, None))
    });
    // a sweep of cold paper-basis solves (8 speeds), each point built fresh or on the thread's
    // prepared problem (`PreparedHbm::per_thread`, what a parallel sweep's worker reuses)
    let sweep: Vec<liu2021::Model> = (0..8)
        .map(|i| {
            let mut q = p;
            q.omega1 = 150.0 + 2.5 * f64::from(i);
            q.model().expect("valid")
        })
        .collect();
    let paper = HbmOptions::default();
    g.bench_function("hbm_paper_sweep_8_fresh", |b| {
        b.iter(|| {
            for m in &sweep {
                black_box(liu2021::solve_hbm_with(m, &paper, HbmStart::Cold).expect("solves"));
            }
        })
    });
    g.bench_function("hbm_paper_sweep_8_per_thread", |b| {
        b.iter(|| {
            for m in &sweep {
                let mut hbm = liu2021::PreparedHbm::per_thread(m, &paper).expect("prepares");
                black_box(hbm.solve(m, HbmStart::Cold).expect("solves"));
            }
        })
    });
    let opts = IntegrationOptions::default();
    g.bench_function("time_integration_3_periods", |b| {
        b.iter(|| liu2021::integrate(black_box(&m), &opts))
    });
    let mut p220 = p;
    p220.omega1 = 220.0;
    let m220 = p220.model().expect("valid");
    let ti220 = liu2021::integrate(&m220, &opts).expect("integrates");
    g.bench_function("hbm_paper_warm_start_220", |b| {
        b.iter(|| {
            liu2021::solve_hbm_with(
                black_box(&m220),
                &HbmOptions::default(),
                HbmStart::FromTimeResponse(&ti220),
            )
        })
    });
    let full220 = HbmOptions::full(&m220, 1);
    g.bench_function("hbm_full_warm_start_220", |b| {
        b.iter(|| {
            liu2021::solve_hbm_with(
                black_box(&m220),
                &full220,
                HbmStart::FromTimeResponse(&ti220),
            )
        })
    });
    let hb220 =
        liu2021::solve_hbm_with(&m220, &full220, HbmStart::FromTimeResponse(&ti220)).expect("ok");
    g.bench_function("shooting_multipliers_220", |b| {
        b.iter(|| liu2021::shooting_multipliers(black_box(&m220), &hb220))
    });
    let mut p180 = p;
    p180.omega1 = 180.0;
    let copts = SpeedContinuationOptions {
        omega1_end: 195.0,
        max_points: 40,
        stability: BranchStability::None,
        ..SpeedContinuationOptions::default()
    };
    g.bench_function("continuation_paper_180_to_fold", |b| {
        b.iter(|| liu2021::continue_in_speed(black_box(&p180), &copts, HbmStart::Cold))
    });
    g.finish();
}

/// Time stepping of the Liu problem at ω₁ = 160 rad/s (Table 1, constant-b̄ reading as the
/// paper's figures, and the default time-varying reading): the right-hand side alone, the raw
/// `timestep::integrate` over three periods `T = 2π/ω̄_c` from the static position
/// (Dormand–Prince 5(4), rtol 1e-8, atol 1e-11·max(b̄, B₀), steps ≤ 0.5, gap-edge events on,
/// `Output::Final`) and the model's `integrate` (the same, plus 0.1-spaced samples of the last
/// period). Each through the generic adapter `FirstOrder(Mechanical(model))` and through the
/// lean `liu2021::TimeSystem` (bit-identical results). Steps per second = accepted steps /
/// time (the counts are printed).
fn bench_timestep(c: &mut Criterion) {
    use geardyn_timestep as ts;
    use ts::OdeSystem;
    let mut g = c.benchmark_group("liu2021_timestep");
    g.sample_size(20);
    for base_radius in [BaseRadius::Mean, BaseRadius::TimeVarying] {
        let label = match base_radius {
            BaseRadius::Mean => "mean",
            _ => "varying",
        };
        let m = liu2021::Parameters {
            omega1: 160.0,
            readings: liu2021::Readings {
                base_radius,
                ..liu2021::Readings::default()
            },
            ..liu2021::table1()
        }
        .model()
        .expect("Table 1 is valid");
        let (t3, lean) = (3.0 * m.period(), liu2021::TimeSystem::new(m));
        let mech = ts::FirstOrder(ts::Mechanical::new(m).expect("valid"));
        // right-hand side alone, 1024 distinct times spread over three periods and over the
        // contact states (q inside and outside the gap)
        let pts: Vec<(f64, [f64; 2])> = (0..1024)
            .map(|i| {
                let x = f64::from(i) / 1024.0;
                (
                    t3 * x,
                    [m.backlash * 3.0 * (7.0 * x).dsin(), 0.01 * (3.0 * x).dcos()],
                )
            })
            .collect();
        fn calls<S: OdeSystem>(sys: &S, pts: &[(f64, [f64; 2])]) -> f64 {
            let mut acc = 0.0;
            let mut dy = [0.0; 2];
            for (t, y) in pts {
                sys.rhs(*t, black_box(y), &mut dy);
                acc += dy[1];
            }
            acc
        }
        g.bench_function(format!("rhs_1024_calls_mechanical_{label}"), |b| {
            b.iter(|| calls(&mech, &pts))
        });
        g.bench_function(format!("rhs_1024_calls_lean_{label}"), |b| {
            b.iter(|| calls(&lean, &pts))
        });
        let opts = ts::Options::default()
            .with_tol(1e-8, 1e-8 * 1e-3 * m.backlash.max(m.b0))
            .with_h_max(0.5)
            .with_output(ts::Output::Final);
        let y0 = [m.static_position(0.0), 0.0];
        let s = ts::integrate(&lean, 0.0, &y0, t3, &opts).expect("integrates");
        eprintln!(
            "liu2021 160 rad/s {label}, 3 periods (tau_end {t3:.1}), events on: {:?}, \
             y_final {:?}",
            s.stats, s.y_final
        );
        g.bench_function(
            format!("integrate_3_periods_final_mechanical_{label}"),
            |b| b.iter(|| ts::integrate(black_box(&mech), 0.0, &y0, t3, &opts)),
        );
        g.bench_function(format!("integrate_3_periods_final_lean_{label}"), |b| {
            b.iter(|| ts::integrate(black_box(&lean), 0.0, &y0, t3, &opts))
        });
        let io = IntegrationOptions::default();
        g.bench_function(format!("model_integrate_default_{label}"), |b| {
            b.iter(|| liu2021::integrate(black_box(&m), &io))
        });
    }
    g.finish();
}

/// The cost of the long-window statistics per simulated period against the plain time response
/// (issue 22 goal: at most 1.2×). At ω1 = 177.5 rad/s (non-periodic bilateral rattle):
/// `plain` integrates 10 + 50 periods with uniform samples (60 periods simulated);
/// `long_window` runs the nominal record (10 + 2·50), the rtol/100 record (10 + 50) and the
/// second start (10 + 50) and computes every statistic (230 periods simulated). Cost per period
/// = time / periods simulated; the tighter-tolerance run costs more steps per period by design.
fn bench_long_window(c: &mut Criterion) {
    let mut p = liu2021::table1();
    p.readings.base_radius = BaseRadius::Mean;
    p.omega1 = 177.5;
    let m = p.model().expect("valid");
    let mut g = c.benchmark_group("liu2021_long_window");
    g.sample_size(10);
    let plain = IntegrationOptions {
        transient_periods: 10.0,
        record_periods: 50.0,
        ..IntegrationOptions::default()
    };
    g.bench_function("plain_response_60_periods_177.5", |b| {
        b.iter(|| liu2021::integrate(black_box(&m), &plain))
    });
    let lw = liu2021::LongWindowOptions::default();
    g.bench_function("long_window_230_periods_177.5", |b| {
        b.iter(|| liu2021::long_window(black_box(&m), &lw))
    });
    // the statistics alone on a recorded window (no integration)
    let r = liu2021::integrate(&m, &plain).expect("integrates");
    eprintln!(
        "samples in the window: {} ({} per period)",
        r.tau.len(),
        r.tau.len() / 50
    );
    let wo = geardyn_models::response::WindowOptions {
        lines: [1, m.z2],
        ..geardyn_models::response::WindowOptions::new(m.period())
    };
    g.bench_function("window_stats_only_50_periods", |b| {
        b.iter(|| {
            geardyn_models::response::window_stats(
                black_box(&r.tau),
                &r.q,
                &r.v,
                |_| m.backlash, // constant b̄, as `long_window` passes it
                &[],
                &wo,
            )
        })
    });
    g.finish();
}

criterion_group!(benches, bench, bench_timestep, bench_long_window);
criterion_main!(benches);
