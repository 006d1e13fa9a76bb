//! Criterion benches of the `hbm` engine (figures in `docs/performance/hbm.md`).
#![allow(missing_docs)]

use criterion::{Criterion, criterion_group, criterion_main};
use geardyn_hbm::{
    Basis, BlockedLu, DenseLu, HbmProblem, Method, SecondOrderSystem, SolverOptions, SystemError,
};
use geardyn_system::problems::BenchDuffing as Duffing;
use math::DetMath;
use nalgebra::DMatrix;
use std::hint::black_box;

#[path = "../../crates/hbm/tests/it/common/random_matrix.rs"]
mod random_matrix;
use random_matrix::random_matrix;

/// Liu-type 1-DOF rattle model: `q'' + 2ζq' + F(t) f(q) = F_m + F_e cos(Z2 ω t)` with
/// `F(t) = 1 + ε_c cos ωt + ε_e cos Z2ωt` and a dead zone `f`.
#[derive(Clone)]
struct Rattle {
    omega: f64,
    z2: f64,
}

impl SecondOrderSystem for Rattle {
    fn n_dof(&self) -> usize {
        1
    }
    fn mass(&self) -> DMatrix<f64> {
        DMatrix::identity(1, 1)
    }
    fn damping(&self) -> DMatrix<f64> {
        DMatrix::from_element(1, 1, 0.1)
    }
    fn nonlinear_force(&self, t: f64, q: &[f64], _qd: &[f64], g: &mut [f64]) {
        let k = 1.0 + 0.1 * (self.omega * t).dcos() + 0.2 * (self.z2 * self.omega * t).dcos();
        let f = if q[0] > 1.0 {
            q[0] - 1.0
        } else if q[0] < -1.0 {
            q[0] + 1.0
        } else {
            0.0
        };
        g[0] = k * f;
    }
    fn force_jacobian(&self, t: f64, q: &[f64], _qd: &[f64], a: &mut [f64], b: &mut [f64]) {
        let k = 1.0 + 0.1 * (self.omega * t).dcos() + 0.2 * (self.z2 * self.omega * t).dcos();
        a[0] = if q[0].abs() > 1.0 { k } else { 0.0 };
        b[0] = 0.0;
    }
    fn forcing(&self, t: f64, f: &mut [f64]) {
        f[0] = 0.5 + 0.1 * (self.z2 * self.omega * t).dcos();
    }
    fn set_base_frequency(&mut self, omega: f64) -> Result<(), SystemError> {
        self.omega = omega;
        Ok(())
    }
}

fn benches(c: &mut Criterion) {
    // 1. Liu basis R = 1 (15 unknowns), dead zone with two-frequency parametric stiffness
    let omega = 0.12;
    let basis = Basis::liu_multifrequency(1, 10).expect("basis");
    let mut p = HbmProblem::new(Rattle { omega, z2: 10.0 }, basis, omega).expect("problem");
    let mut z0 = p.zero_guess();
    z0[0] = 1.5;
    for method in [Method::Newton, Method::Broyden] {
        let opts = SolverOptions {
            method,
            ..SolverOptions::default()
        };
        let sol = p.solve(&z0, &opts).expect("solve");
        assert!(sol.converged, "{}", sol.termination);
        c.bench_function(&format!("solve_liu_basis_15_unknowns_{method:?}"), |b| {
            b.iter(|| black_box(p.solve(black_box(&z0), &opts).expect("solve")))
        });
    }
    let mut r = vec![0.0; p.n_unknowns()];
    c.bench_function("residual_liu_basis_15_unknowns", |b| {
        b.iter(|| p.residual(black_box(&z0), &mut r).expect("residual"))
    });

    // 2. full basis H = 200 (401 unknowns, N = 1024), Duffing near resonance, from the H = 1
    // solution
    let omega = 1.3;
    let mut p1 = HbmProblem::new(Duffing { omega }, Basis::full(1).expect("b"), omega).expect("p");
    let mut g = p1.zero_guess();
    g[1] = 0.8;
    let s1 = p1.solve(&g, &SolverOptions::default()).expect("solve");
    let big = Basis::full(200).expect("basis");
    let mut p200 = HbmProblem::new(Duffing { omega }, big.clone(), omega).expect("problem");
    let z200 = s1.embed(&big);
    let opts = SolverOptions::default();
    let sol = p200.solve(&z200, &opts).expect("solve");
    assert!(sol.converged);
    println!("H=200 Newton iterations: {}", sol.iterations);
    let mut group = c.benchmark_group("large");
    group.sample_size(10);
    group.bench_function("solve_full_basis_h200_401_unknowns", |b| {
        b.iter(|| black_box(p200.solve(black_box(&z200), &opts).expect("solve")))
    });
    let mut jac = DMatrix::zeros(401, 401);
    let mut r = vec![0.0; 401];
    group.bench_function("residual_and_jacobian_h200", |b| {
        b.iter(|| {
            p200.residual_and_jacobian(black_box(&z200), &mut r, &mut jac)
                .expect("jacobian")
        })
    });

    // 2b. dense Newton (LU) vs Jacobian-free Newton–Krylov, H = 50…400, same start
    for h in [10usize, 20, 50, 100, 200, 400] {
        let basis = Basis::full(h).expect("basis");
        let mut ph = HbmProblem::new(Duffing { omega }, basis.clone(), omega).expect("problem");
        let zh = s1.embed(&basis);
        for method in [Method::Newton, Method::NewtonKrylov] {
            let o = SolverOptions {
                method,
                ..SolverOptions::default()
            };
            let s = ph.solve(&zh, &o).expect("solve");
            assert!(s.converged, "{method:?} H = {h}: {}", s.termination);
            println!("H={h} {method:?}: {} iterations", s.iterations);
            group.bench_function(format!("duffing_h{h}_{method:?}"), |b| {
                b.iter(|| black_box(ph.solve(black_box(&zh), &o).expect("solve")))
            });
        }
    }

    // 2c. the dense Newton at H = 400 (801 unknowns) with either LU (Round 12)
    let basis = Basis::full(400).expect("basis");
    let mut ph = HbmProblem::new(Duffing { omega }, basis.clone(), omega).expect("problem");
    let zh = s1.embed(&basis);
    for lu in [DenseLu::Nalgebra, DenseLu::Blocked] {
        ph.set_dense_lu(lu);
        let s = ph.solve(&zh, &opts).expect("solve");
        assert!(s.converged, "{lu:?}: {}", s.termination);
        group.bench_function(format!("duffing_h400_Newton_lu_{lu:?}"), |b| {
            b.iter(|| black_box(ph.solve(black_box(&zh), &opts).expect("solve")))
        });
    }

    // (the 150-point continuation bench moved with the continuation to `orbit`'s benches)
    group.finish();
}

/// nalgebra's LU against `BlockedLu` (factor + one solve, the matrix copied in both), n = 15 …
/// 801: `dense_lu/{nalgebra,blocked}/{n}`.
fn dense_lu(c: &mut Criterion) {
    let mut group = c.benchmark_group("dense_lu");
    group.sample_size(10);
    for n in [15usize, 31, 65, 131, 201, 401, 801] {
        let a = random_matrix(n, n as u64);
        let rhs = nalgebra::DVector::from_fn(n, |i, _| (i as f64).dsin());
        group.bench_function(format!("nalgebra/{n}"), |b| {
            b.iter(|| {
                let lu = black_box(a.clone()).lu();
                black_box(lu.solve(&rhs).expect("regular"))
            })
        });
        group.bench_function(format!("blocked/{n}"), |b| {
            b.iter(|| {
                let lu = BlockedLu::new(black_box(a.clone())).expect("regular");
                let mut x = rhs.clone();
                lu.solve_mut(x.as_mut_slice()).expect("length");
                black_box(x)
            })
        });
    }
    group.finish();
}

criterion_group!(hbm_benches, benches, dense_lu);
criterion_main!(hbm_benches);
