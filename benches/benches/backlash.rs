//! Criterion benches of the hot paths: f(x; b), B(t) and b_s.
#![allow(missing_docs)]

use math::DetMath;
use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use geardyn_backlash::{
    CentreDisplacement, ConstantBacklashParams, DeadZone, DynamicBacklash, DynamicForm,
    PairGeometry, PressureAngleLaw, RadicandPolicy, Regularisation, SurfaceFractal, dead_zone,
};

fn xs() -> Vec<f64> {
    (0..1024).map(|i| (f64::from(i) - 512.0) * 0.01).collect()
}

fn bench_dead_zone(c: &mut Criterion) {
    let x = xs();
    c.bench_function("dead_zone exact, 1024 points", |b| {
        b.iter(|| {
            let mut s = 0.0;
            for &v in &x {
                s += dead_zone(black_box(v), black_box(1.0));
            }
            s
        })
    });
    let exact = DeadZone::EXACT;
    c.bench_function("DeadZone::eval exact (f, f_x, f_b), 1024 points", |b| {
        b.iter(|| {
            let mut s = 0.0;
            for &v in &x {
                let e = exact.eval(black_box(v), black_box(1.0));
                s += e.f + e.df_dx + e.df_db;
            }
            s
        })
    });
    let smooth = DeadZone::new(Regularisation::Smooth { eps: 1e-3 }).unwrap();
    c.bench_function("DeadZone::eval smooth, 1024 points", |b| {
        b.iter(|| {
            let mut s = 0.0;
            for &v in &x {
                let e = smooth.eval(black_box(v), black_box(1.0));
                s += e.f + e.df_dx + e.df_db;
            }
            s
        })
    });
}

fn bench_dynamic(c: &mut Criterion) {
    let g = PairGeometry::new(0.094, 0.094, 20f64.to_radians()).expect("valid geometry");
    let disp: Vec<CentreDisplacement> = (0..1024)
        .map(|i| {
            let t = f64::from(i) * 0.01;
            CentreDisplacement::new(1e-6 * t.dsin(), 2e-6 * t.dcos(), -1e-6 * t.dcos(), 0.5e-6)
        })
        .collect();
    for (name, form, law) in [
        (
            "involute",
            DynamicForm::Involute,
            PressureAngleLaw::Involute,
        ),
        ("YuEq10", DynamicForm::YuEq10, PressureAngleLaw::Involute),
    ] {
        let d = DynamicBacklash::new(g, 3e-5, form, law, RadicandPolicy::ClampZero).unwrap();
        c.bench_function(
            &format!("B(t) eval {name} (B + gradient), 1024 points"),
            |b| {
                b.iter(|| {
                    let mut s = 0.0;
                    for q in &disp {
                        if let Ok(e) = d.eval(black_box(q)) {
                            s += e.b + e.grad[0];
                        }
                    }
                    s
                })
            },
        );
    }
}

fn bench_constant(c: &mut Criterion) {
    // the parameters of reading R-YU-FIG4 (Yu's set, `geardyn_models::yu2021::fig4_backlash_params`)
    let p = ConstantBacklashParams {
        b0: 30e-6,
        gamma: 1.5,
        l_a: 1e-3,
        l_s: 1e-6,
        sampling_length: 1e-3,
        quadrature: geardyn_backlash::Quadrature::default(),
        form: geardyn_backlash::ConstantPartForm::AbsoluteMean,
    };
    let s = SurfaceFractal::new(1.4, 1e-11).unwrap();
    let mut group = c.benchmark_group("b_s");
    group.sample_size(10);
    group.bench_function("constant_part l_s = 1 µm (Fig. 4 settings)", |b| {
        b.iter(|| p.constant_part(black_box(s), black_box(s)).unwrap().b_s)
    });
    let mut coarse = p;
    coarse.l_s = 1e-5;
    group.bench_function("constant_part l_s = 10 µm", |b| {
        b.iter(|| {
            coarse
                .constant_part(black_box(s), black_box(s))
                .unwrap()
                .b_s
        })
    });
    group.finish();
}

criterion_group!(benches, bench_dead_zone, bench_dynamic, bench_constant);
criterion_main!(benches);
