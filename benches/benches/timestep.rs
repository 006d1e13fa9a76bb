//! Benchmarks: 1-DOF backlash oscillator with mesh-stiffness excitation over 20,000
//! dimensionless time units at rtol 1e-8, with and without event location, per method.

#![allow(missing_docs)]
use criterion::{Criterion, criterion_group, criterion_main};
use geardyn_timestep::*;
use std::hint::black_box;

fn backlash() -> FirstOrder<DeadZoneOscillator> {
    FirstOrder(DeadZoneOscillator {
        zeta: 0.05,
        kappa: 0.2,
        omega: 1.5,
        f_mean: 0.1,
        f_amp: 0.5,
        b: 1.0,
    })
}

fn bench(c: &mut Criterion) {
    let sys = backlash();
    let mut g = c.benchmark_group("backlash_1dof_T20000_rtol1e-8");
    g.sample_size(10);
    for (name, m, ev) in [
        ("dp54_events", Method::DormandPrince54, true),
        ("dp54_plain", Method::DormandPrince54, false),
        ("odesolvers_dopri5_events", Method::OdeSolversDopri5, true),
    ] {
        let o = Options::default()
            .with_method(m)
            .with_tol(1e-8, 1e-10)
            .with_events(ev)
            .with_output(Output::Final);
        let s = integrate(&sys, 0.0, &[1.1, 0.0], 20_000.0, &o).unwrap();
        eprintln!("{name}: {:?} status {:?}", s.stats, s.status);
        g.bench_function(name, |b| {
            b.iter(|| integrate(black_box(&sys), 0.0, &[1.1, 0.0], 20_000.0, &o).unwrap())
        });
    }
    g.finish();
    // ode_solvers' Dop853 takes steps of ~0.005 on this problem even without events (see
    // docs/performance/timestep.md), so it is timed over 200 time units only
    let mut g = c.benchmark_group("backlash_1dof_T200_rtol1e-8");
    g.sample_size(10);
    for (name, m) in [
        ("dp54_events", Method::DormandPrince54),
        ("odesolvers_dop853_events", Method::OdeSolversDop853),
    ] {
        let o = Options::default()
            .with_method(m)
            .with_tol(1e-8, 1e-10)
            .with_output(Output::Final);
        g.bench_function(name, |b| {
            b.iter(|| integrate(black_box(&sys), 0.0, &[1.1, 0.0], 200.0, &o).unwrap())
        });
    }
    g.finish();
}

/// Stepper and controller overhead: Dormand–Prince 5(4) on a trivial 2-state right-hand side
/// (`y'' = −y`, one multiply per call), no events, `Output::Final`, rtol 1e-8. The time per
/// accepted step is the floor of the driver loop for a 2-state problem.
fn bench_overhead(c: &mut Criterion) {
    let sys = FnSystem::new(2, |_t: f64, y: &[f64], dy: &mut [f64]| {
        dy[0] = y[1];
        dy[1] = -y[0];
    });
    let o = Options::default()
        .with_tol(1e-8, 1e-10)
        .with_events(false)
        .with_output(Output::Final);
    let s = integrate(&sys, 0.0, &[1.0, 0.0], 10_000.0, &o).unwrap();
    eprintln!("trivial rhs, T = 10,000: {:?}", s.stats);
    let mut g = c.benchmark_group("dp54_overhead_trivial_rhs");
    g.sample_size(20);
    g.bench_function("harmonic_T10000", |b| {
        b.iter(|| integrate(black_box(&sys), 0.0, &[1.0, 0.0], 10_000.0, &o).unwrap())
    });
    g.finish();
}

criterion_group!(benches, bench, bench_overhead);
criterion_main!(benches);
