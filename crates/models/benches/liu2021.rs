//! One steady-state response of the Liu 2021 NFG model (Table 1, ω1 = 160 rad/s, constant-b̄
//! reading): harmonic balance on the paper's and on a full basis, and time integration.
#![allow(missing_docs)] // criterion_group! generates an undocumented pub fn

use criterion::{Criterion, criterion_group, criterion_main};
use models::liu2021::{self, BaseRadius, HbmOptions, IntegrationOptions};
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
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
