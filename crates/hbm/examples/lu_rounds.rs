//! Alternated on-CPU timing of nalgebra's LU against [`BlockedLu`] (and of the Duffing `H = 400`
//! dense Newton solve with either), for `docs/performance/hbm.md` ("Round 12").
//!
//! ```text
//! cargo run --release -p geardyn-hbm --example lu_rounds -- [rounds] [lu|nb|duffing]...
//! ```
//!
//! Each round times every case once, in turn (so a load change hits all cases alike), as the
//! mean on-CPU time per call (Linux `/proc/thread-self/schedstat`) over at least 0.2 s; the
//! output is the median and range over rounds and the ratio nalgebra / blocked per round.
#![allow(missing_docs)]

use geardyn_hbm::{Basis, nalgebra::DMatrix};
use geardyn_hbm::{BlockedLu, DenseLu, HbmProblem, SolverOptions};
use math::DetMath;
use std::hint::black_box;

#[path = "../tests/it/common/random_matrix.rs"]
mod random_matrix;
use random_matrix::random_matrix;
use system::problems::BenchDuffing as Duffing;

fn on_cpu_ns() -> u64 {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").unwrap_or_default();
    s.split_whitespace()
        .next()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0)
}

/// Mean on-CPU seconds per call of `f` over at least 3 calls and 0.2 s of CPU.
fn cpu_per_call(mut f: impl FnMut()) -> f64 {
    f();
    let c0 = on_cpu_ns();
    let mut calls = 0u64;
    loop {
        f();
        calls += 1;
        let c = on_cpu_ns() - c0;
        if calls >= 3 && c >= 200_000_000 {
            return c as f64 * 1e-9 / calls as f64;
        }
    }
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    if v.len() % 2 == 1 {
        v[m]
    } else {
        0.5 * (v[m - 1] + v[m])
    }
}

fn report(name: &str, times: &[Vec<f64>], labels: &[&str]) {
    for (t, l) in times.iter().zip(labels) {
        let mut s = t.clone();
        let (lo, hi) = (
            s.iter().copied().fold(f64::INFINITY, f64::min),
            s.iter().copied().fold(0.0, f64::max),
        );
        println!(
            "{name} {l}: median {:.4e} s (range {:.4e}–{:.4e})",
            median(&mut s),
            lo,
            hi
        );
    }
    for (t, l) in times.iter().zip(labels).skip(1) {
        let mut r: Vec<f64> = times[0].iter().zip(t).map(|(a, b)| a / b).collect();
        let (lo, hi) = (
            r.iter().copied().fold(f64::INFINITY, f64::min),
            r.iter().copied().fold(0.0, f64::max),
        );
        println!(
            "{name} {} / {l}: median {:.3}x (range {:.3}–{:.3})",
            labels[0],
            median(&mut r),
            lo,
            hi
        );
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let rounds: usize = args.first().and_then(|a| a.parse().ok()).unwrap_or(5);
    let want = |s: &str| args.iter().skip(1).any(|a| a == s) || args.len() <= 1;

    if want("lu") {
        for n in [15usize, 31, 65, 131, 201, 401, 801] {
            let a = random_matrix(n, n as u64);
            let b: Vec<f64> = (0..n).map(|i| (i as f64).dsin()).collect();
            let mut t = vec![Vec::new(), Vec::new()];
            for _ in 0..rounds {
                t[0].push(cpu_per_call(|| {
                    let mut x = nalgebra_solve(&a, &b);
                    black_box(&mut x);
                }));
                t[1].push(cpu_per_call(|| {
                    let lu = BlockedLu::new(black_box(a.clone())).expect("regular");
                    let mut x = b.clone();
                    lu.solve_mut(&mut x).expect("length");
                    black_box(&mut x);
                }));
            }
            report(&format!("lu+solve n={n}"), &t, &["nalgebra", "blocked"]);
        }
    }
    if want("nb") {
        for n in [131usize, 257, 401, 801] {
            let a = random_matrix(n, 7);
            let nbs = [16usize, 32, 48, 64, 96, 128];
            let mut t = vec![Vec::new(); nbs.len()];
            for _ in 0..rounds {
                for (i, &nb) in nbs.iter().enumerate() {
                    t[i].push(cpu_per_call(|| {
                        black_box(BlockedLu::with_block_size(a.clone(), nb).expect("regular"));
                    }));
                }
            }
            let labels: Vec<String> = nbs.iter().map(|nb| format!("nb={nb}")).collect();
            let labels: Vec<&str> = labels.iter().map(String::as_str).collect();
            report(&format!("factor n={n}"), &t, &labels);
        }
    }
    if want("duffing") {
        let omega = 1.3;
        let mut p1 =
            HbmProblem::new(Duffing { omega }, Basis::full(1).expect("b"), omega).expect("p");
        let mut g = p1.zero_guess();
        g[1] = 0.8;
        let s1 = p1.solve(&g, &SolverOptions::default()).expect("solve");
        for h in [65usize, 100, 200, 400] {
            let basis = Basis::full(h).expect("basis");
            let mut p = HbmProblem::new(Duffing { omega }, basis.clone(), omega).expect("problem");
            let z = s1.embed(&basis);
            let o = SolverOptions::default();
            let mut t = vec![Vec::new(), Vec::new()];
            let mut res = [0.0; 2];
            for _ in 0..rounds {
                for (i, lu) in [DenseLu::Nalgebra, DenseLu::Blocked]
                    .into_iter()
                    .enumerate()
                {
                    p.set_dense_lu(lu);
                    t[i].push(cpu_per_call(|| {
                        let s = p.solve(black_box(&z), &o).expect("solve");
                        assert!(s.converged);
                        res[i] = s.residual_norm;
                    }));
                }
            }
            println!(
                "duffing H={h}: residual nalgebra {:.3e}, blocked {:.3e}",
                res[0], res[1]
            );
            report(
                &format!("duffing H={h} ({} unknowns) dense Newton", 2 * h + 1),
                &t,
                &["nalgebra", "blocked"],
            );
        }
    }
}

fn nalgebra_solve(a: &DMatrix<f64>, b: &[f64]) -> geardyn_hbm::nalgebra::DVector<f64> {
    let lu = black_box(a.clone()).lu();
    lu.solve(&geardyn_hbm::nalgebra::DVector::from_column_slice(b))
        .expect("regular")
}
