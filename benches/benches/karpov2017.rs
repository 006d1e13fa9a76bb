//! Criterion benches: the final amplitude of the Karpov 2017 oscillator (Eq. 9–10, Fig. 3 data:
//! `ω = 1`, `B = 0.01`, `ξ = 2`, `k = 1/10`) by the Duhamel fast path and by time stepping.
//!
//! * `duhamel_fig3_*`: the paper's `τ_end = 10⁵`, both readings of the excitation phase
//!   (`R-KARPOV-EQ9`), error-controlled to 1e-7 relative on `A` (`Karpov2017::duhamel`);
//!   `*_b0.05` the same at `B = 0.05` (the upper end of the issue-13 target). Period folding
//!   (the `N` whole periods of `g` summed in closed form onto one period).
//! * `levin_*`: the previous default, Levin collocation in the bulk with Gauss–Legendre
//!   pairs around the stationary points (`duhamel_levin(1e-7)`), for comparison.
//! * `gauss_legendre_fig3_printed_tau1e5`: the plain phase-bounded Gauss–Legendre rule
//!   (`duhamel_with(4.0)`) on the printed Fig. 3 point, for comparison.
//! * `*_tau2000`: the same response to `τ_end = 2000` by the Duhamel integral and by
//!   `timestep` Dormand–Prince 5(4) at `rtol = 1e-8` and `1e-10` (the two agree to ~1e-7 relative), so the
//!   two methods can be compared on one problem.

#![allow(missing_docs)]

use criterion::{Criterion, criterion_group, criterion_main};
use geardyn_models::karpov2017::{Excitation, Karpov2017};
use geardyn_timestep::{self as timestep, Method, Options, Output};

fn bench(c: &mut Criterion) {
    let fig3 = Karpov2017::fig3();
    let printed = fig3
        .with(|p| p.excitation = Excitation::PrintedPhase)
        .expect("valid");
    c.bench_function("karpov2017/duhamel_fig3_accumulated_tau1e5", |b| {
        b.iter(|| fig3.duhamel().expect("converges"))
    });
    c.bench_function("karpov2017/duhamel_fig3_printed_tau1e5", |b| {
        b.iter(|| printed.duhamel().expect("converges"))
    });
    c.bench_function("karpov2017/levin_fig3_printed_tau1e5", |b| {
        b.iter(|| printed.duhamel_levin(1e-7).expect("converges"))
    });
    // the plain phase-bounded Gauss–Legendre rule at the default budget (the pre-Levin path)
    c.bench_function("karpov2017/gauss_legendre_fig3_printed_tau1e5", |b| {
        b.iter(|| printed.duhamel_with(4.0).expect("runs"))
    });
    let printed5 = printed.with(|p| p.b = 0.05).expect("valid");
    c.bench_function("karpov2017/duhamel_printed_tau1e5_b0.05", |b| {
        b.iter(|| printed5.duhamel().expect("converges"))
    });
    c.bench_function("karpov2017/levin_printed_tau1e5_b0.05", |b| {
        b.iter(|| printed5.duhamel_levin(1e-7).expect("converges"))
    });
    let accumulated5 = fig3.with(|p| p.b = 0.05).expect("valid");
    c.bench_function("karpov2017/duhamel_accumulated_tau1e5_b0.05", |b| {
        b.iter(|| accumulated5.duhamel().expect("converges"))
    });

    let short = fig3.with(|p| p.tau_end = 2000.0).expect("valid");
    c.bench_function("karpov2017/duhamel_tau2000", |b| {
        b.iter(|| short.duhamel().expect("converges"))
    });
    for (name, rtol, atol) in [
        ("karpov2017/dopri54_rtol1e-8_tau2000", 1e-8, 1e-10),
        ("karpov2017/dopri54_rtol1e-10_tau2000", 1e-10, 1e-12),
    ] {
        let opts = Options::default()
            .with_method(Method::DormandPrince54)
            .with_tol(rtol, atol)
            .with_output(Output::Final);
        c.bench_function(name, |b| {
            let ode = short.time_stepping().expect("M = 1 inverts");
            b.iter(|| timestep::integrate(&ode, 0.0, &[0.0, 0.0], 2000.0, &opts).expect("runs"))
        });
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = bench
}
criterion_main!(benches);
