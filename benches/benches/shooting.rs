//! One shooting Newton solve of the Liu et al. (2021) period-1 bilateral orbit at ω1 = 220 rad/s
//! (Table 1, constant b̄) from a time-stepping guess, against the 12-period time response and the
//! warm-started harmonic balance of the same point, at the same integration tolerance
//! (rtol 1e-8). Numbers go in `docs/performance.md`, never in a timed test.
#![allow(missing_docs)] // criterion_group! generates an undocumented pub fn

use criterion::{Criterion, criterion_group, criterion_main};
use geardyn_models::liu2021::{self, BaseRadius, HbmOptions, HbmStart, IntegrationOptions, Model};
use orbit::{FlowMethod, FlowOptions, OrbitProblem, ShootingOptions};
use std::hint::black_box;

fn model() -> Model {
    let mut p = liu2021::table1();
    p.readings.base_radius = BaseRadius::Mean;
    p.omega1 = 220.0;
    p.model().expect("Table 1 model")
}

fn bench(c: &mut Criterion) {
    let m = model();
    let rtol = 1e-8;
    let ti_opts = IntegrationOptions {
        transient_periods: 11.0,
        record_periods: 1.0,
        rtol,
        ..IntegrationOptions::default()
    };
    // the time-stepping guess: the default short run (2 transient periods, 1 recorded)
    let guess = liu2021::integrate(&m, &IntegrationOptions::default()).expect("integration");
    let x0 = [*guess.q.last().expect("q"), *guess.v.last().expect("v")];
    let p = OrbitProblem::new(m, m.period())
        .expect("problem")
        .with_flow_options(FlowOptions {
            rtol,
            atol: 1e-12,
            ..FlowOptions::default()
        })
        .expect("options");
    let so = ShootingOptions {
        tol: 1e-8,
        ..ShootingOptions::default()
    };
    let mut g = c.benchmark_group("liu2021_220");
    g.sample_size(10);
    g.bench_function("shooting_newton_from_time_stepping_guess", |b| {
        b.iter(|| black_box(p.shoot(black_box(&x0), &so).expect("shooting")))
    });
    g.bench_function("time_response_12_periods", |b| {
        b.iter(|| black_box(liu2021::integrate(black_box(&m), &ti_opts).expect("integration")))
    });
    let ti = liu2021::integrate(&m, &ti_opts).expect("integration");
    g.bench_function("hbm_warm_from_time_response", |b| {
        b.iter(|| {
            black_box(
                liu2021::solve_hbm_with(
                    &m,
                    &HbmOptions::default(),
                    HbmStart::FromTimeResponse(&ti),
                )
                .expect("hbm"),
            )
        })
    });
    g.finish();
}

/// One period of the Liu flow with its variational equations at the flows' default tolerance
/// (rtol 1e-10, atol 1e-12) from a settled state, on each pair (`orbit::FlowMethod`), at
/// 140 rad/s (unilateral, few events) and 220 rad/s (bilateral, 252 events a period).
fn flow_pairs(c: &mut Criterion) {
    let mut g = c.benchmark_group("liu2021_flow_one_period");
    g.sample_size(10);
    for w in [140.0, 220.0] {
        let mut p = liu2021::table1();
        p.readings.base_radius = BaseRadius::Mean;
        p.omega1 = w;
        let m = p.model().expect("Table 1 model");
        let settled = liu2021::integrate(
            &m,
            &IntegrationOptions {
                transient_periods: 199.0,
                record_periods: 1.0,
                sample_step: m.period(),
                initial: Some((-m.backlash - m.b0, 0.0)),
                ..IntegrationOptions::default()
            },
        )
        .expect("integration");
        let x = [*settled.q.last().expect("q"), *settled.v.last().expect("v")];
        for (name, method) in [
            ("dp5", FlowMethod::DormandPrince54),
            ("dop853", FlowMethod::Dop853),
        ] {
            let prob = OrbitProblem::new(m, m.period())
                .expect("problem")
                .with_flow_options(FlowOptions {
                    method,
                    ..FlowOptions::default()
                })
                .expect("options");
            g.bench_function(format!("{name}_{w}"), |b| {
                b.iter(|| {
                    black_box(
                        prob.flow(0.0, black_box(&x), m.period(), true)
                            .expect("flow"),
                    )
                })
            });
        }
    }
    g.finish();
}

/// The 150-point continuation of the Duffing response (H = 5) with Floquet stability: the
/// bench that was `hbm`'s `continuation_150_points_h5_with_stability`, now through the one
/// continuation (`orbit::continue_hbm`).
fn hbm_continuation(c: &mut Criterion) {
    use geardyn_system::problems::BenchDuffing;
    let copts = orbit::HbmContinuationOptions {
        max_points: 150,
        max_step: 0.03,
        ..orbit::HbmContinuationOptions::default()
    };
    c.bench_function("hbm/continuation_150_points_h5_with_stability", |b| {
        b.iter(|| {
            let mut p = geardyn_hbm::HbmProblem::new(
                BenchDuffing { omega: 0.5 },
                geardyn_hbm::Basis::full(5).expect("b"),
                0.5,
            )
            .expect("p");
            let z0 = p.zero_guess();
            let br = orbit::continue_hbm(
                &mut p,
                orbit::Parameter::BaseFrequency,
                &z0,
                0.5,
                5.0,
                &copts,
            )
            .expect("continuation");
            assert_eq!(br.points.len(), 150);
            black_box(br)
        })
    });
}

criterion_group!(benches, bench, flow_pairs, hbm_continuation);
criterion_main!(benches);
