//! Per-step cost of the functions a time-stepping model calls in its right-hand side.
#![allow(missing_docs)]

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use geardyn_gear_geometry::{
    CentreDistance, KarpovPair, KarpovPairParams, NfgPair, NfgPairParams, RigidAccelerationForm,
};

fn bench(c: &mut Criterion) {
    // the values of Karpov 2017 Table 1 and Liu 2021 Table 1, as literal inputs
    let k = KarpovPair::new(KarpovPairParams {
        r: 0.050,
        u: 2.0,
        b: 0.01,
        xi: 2.0,
        j: 4,
        z1: 32,
        centre_distance: CentreDistance::Closing,
    })
    .expect("valid pair");
    let dev = k.deviation();
    let nfg = NfgPair::new(NfgPairParams {
        module: 2.5e-3,
        z1: 18,
        ratio: 3.5,
        eccentricity: 0.2,
        pressure_angle: 20f64.to_radians(),
    })
    .expect("valid pair");
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
