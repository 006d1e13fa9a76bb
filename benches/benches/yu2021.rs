//! Criterion benches: one steady-state response of each Yu 2021 model (Table 1, ω* = 0.9,
//! 100 transient + 10 recorded mesh periods, 256 samples per period) on each engine: the
//! model's fixed-step RK4, the `timestep` engine (Dormand–Prince 5(4), rtol 1e-8, atol 1e-10,
//! dead-zone edges as events), and one period-1 harmonic balance of the Kahraman–Singh pair on
//! the `hbm` engine (H = 16, from the time solution's harmonics).

#![allow(missing_docs)]

use criterion::{Criterion, criterion_group, criterion_main};
use geardyn_models::yu2021::{
    BacklashUpdate, Engine, HbmSettings, Options, RunSettings, Yu2021Model, Yu2021Params,
};

fn bench(c: &mut Criterion) {
    let p = Yu2021Params::table1();
    let set = RunSettings {
        omega: 0.9,
        transient_periods: 100,
        record_periods: 10,
        steps_per_period: 256,
    };
    for (name, o) in [
        ("yu2021/kahraman_singh", Options::kahraman_singh()),
        ("yu2021/chen", Options::chen()),
        ("yu2021/yu6dof_in_rhs", Options::default()),
        (
            "yu2021/yu6dof_fig8",
            Options {
                update: BacklashUpdate::PreviousStep,
                ..Options::default()
            },
        ),
    ] {
        let m = Yu2021Model::new(&p, o).expect("table1 is valid");
        c.bench_function(name, |b| b.iter(|| m.simulate(&set, None).expect("runs")));
    }
    for (name, o) in [
        ("yu2021/kahraman_singh_timestep", Options::kahraman_singh()),
        ("yu2021/yu6dof_in_rhs_timestep", Options::default()),
    ] {
        let m = Yu2021Model::new(&p, o).expect("table1 is valid");
        let engine = Engine::timestep();
        c.bench_function(name, |b| {
            b.iter(|| m.simulate_with(&set, &engine, None).expect("runs"))
        });
    }
    let ks = Yu2021Model::new(&p, Options::kahraman_singh()).expect("table1 is valid");
    let r = ks
        .simulate(&RunSettings { omega: 0.5, ..set }, None)
        .expect("runs");
    let hs = HbmSettings {
        harmonics: 16,
        samples: 256,
        ..HbmSettings::default()
    };
    let guess = r.fourier_coefficients(hs.harmonics);
    c.bench_function("yu2021/ks_hbm_h16", |b| {
        b.iter(|| ks.harmonic_balance(0.5, &hs, Some(&guess)).expect("solves"))
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
