//! Per-step cost of the functions a time-stepping model calls in its right-hand side.
#![allow(missing_docs)]

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use geardyn_gear_geometry::{KarpovPair, NfgPair, RigidAccelerationForm};

fn bench(c: &mut Criterion) {
    let k = KarpovPair::karpov2017_table1();
    let dev = k.deviation();
    let nfg = NfgPair::liu2021_table1();
    let mut g = c.benchmark_group("per_step");
    g.bench_function("karpov_ratio", |b| b.iter(|| k.ratio(black_box(1.234))));
    g.bench_function("karpov_mesh_frequency", |b| {
        b.iter(|| k.mesh_frequency(black_box(1.234), black_box(100.0)))
    });
    g.bench_function("karpov_mesh_phase", |b| {
        b.iter(|| k.mesh_phase(black_box(1.234)))
    });
    g.bench_function("karpov_dimensionless_mesh_phase", |b| {
        b.iter(|| dev.dimensionless_mesh_phase(black_box(12345.6), black_box(1.0), 0.1))
    });
    g.bench_function("karpov_output_angle_closed_form", |b| {
        b.iter(|| k.output_angle(black_box(1.234)))
    });
    g.bench_function("liu_base_radius", |b| {
        b.iter(|| nfg.base_radius(black_box(1.234)))
    });
    g.bench_function("liu_rigid_acceleration", |b| {
        b.iter(|| {
            nfg.rigid_acceleration(
                RigidAccelerationForm::Derived,
                black_box(0.0037),
                black_box(50.0),
            )
        })
    });
    g.finish();
    let mut g = c.benchmark_group("design_time");
    g.bench_function("karpov_output_angle_quadrature", |b| {
        b.iter(|| k.output_angle_quadrature(black_box(1.234), 1e-13))
    });
    g.bench_function("karpov_speed_fluctuation_numeric", |b| {
        b.iter(|| black_box(&k).speed_fluctuation_numeric())
    });
    g.bench_function("karpov_new_closing", |b| {
        b.iter(|| KarpovPair::new(black_box(k.params())))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
