//! One steady-state response of the Liu 2021 NFG model (Table 1, ω1 = 160 rad/s, constant-b̄
//! reading): harmonic balance on the paper's and on a full basis, and time integration; a
//! warm-started bilateral point (220 rad/s), the period-map stability and a short continuation.
#![allow(missing_docs)] // criterion_group! generates an undocumented pub fn

use criterion::{Criterion, criterion_group, criterion_main};
use geardyn_models::liu2021::{
    self, BaseRadius, BranchStability, HbmOptions, HbmStart, IntegrationOptions,
    SpeedContinuationOptions,
};
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

criterion_group!(benches, bench);
criterion_main!(benches);
