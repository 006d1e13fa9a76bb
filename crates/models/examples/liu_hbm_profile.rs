//! Where a cold 15-unknown Liu HBM solve spends its time (issue 13): times each stage of
//! `liu2021::solve_hbm` separately, in release: `cargo run --release -p geardyn-models --example liu_hbm_profile`.

use geardyn_models::liu2021::{self, BaseRadius, Basis, HbmOptions};
use std::hint::black_box;
use std::time::Instant;

fn time<T>(label: &str, reps: u32, mut f: impl FnMut() -> T) -> f64 {
    for _ in 0..reps / 10 + 1 {
        black_box(f());
    }
    // best of 7 batches (the machine is shared), wall clock and time on the CPU (Linux
    // /proc/thread-self/schedstat: what an idle core would take, less cache interference)
    // (the CPU time is accounted at scheduler ticks: averaged over all batches)
    let mut us = f64::INFINITY;
    let n = reps / 7 + 1;
    let c0 = cpu_ns();
    for _ in 0..7 {
        let t = Instant::now();
        for _ in 0..n {
            black_box(f());
        }
        us = us.min(t.elapsed().as_secs_f64() * 1e6 / f64::from(n));
    }
    let cpu_us = match (c0, cpu_ns()) {
        (Some(a), Some(b)) => (b - a) as f64 * 1e-3 / f64::from(7 * n),
        _ => f64::NAN,
    };
    println!("{label:<48} wall {us:9.2} µs   on-CPU {cpu_us:9.2} µs");
    us
}

fn main() {
    let mut p = liu2021::table1();
    p.readings.base_radius = BaseRadius::Mean;
    let m = p.model().expect("Table 1 is valid");
    let reps = 2000;
    let opts = HbmOptions::default();
    if std::env::args().nth(1).as_deref() == Some("json") {
        // the problem and the solution for the scipy peer (docs/peers/liu_hbm_scipy.py)
        let sol = liu2021::solve_hbm(&m, &opts, None).expect("solves");
        let out = serde_json::json!({
            "model": m,
            "harmonics": sol.solution.basis.harmonics(),
            "grid": 1024,
            "tol": opts.tol,
            "truncation": sol.solution.truncation,
            "coefficients": sol.solution.coefficients,
            "ppv": sol.rattle.ppv,
            "rsv": sol.rattle.state.rsv(),
        });
        println!("{out}");
        return;
    }
    if std::env::args().nth(1).as_deref() == Some("solves") {
        // for an instruction-count profile: `valgrind --tool=callgrind … solves`
        for _ in 0..50 {
            black_box(liu2021::solve_hbm(&m, &opts, None).expect("solves"));
        }
        return;
    }
    let sol = liu2021::solve_hbm(&m, &opts, None).expect("solves");
    println!(
        "iterations {}, residual {:.3e}, converged {}",
        sol.solution.iterations,
        sol.solution.residual_norm,
        sol.converged()
    );
    time("solve_hbm (cold, incl. metrics)", reps, || {
        liu2021::solve_hbm(&m, &opts, None)
    });
    let basis = Basis::PAPER.to_hbm(m.z2).expect("basis");
    time("problem construction (plans + tables)", reps, || {
        geardyn_hbm_problem(&m, &basis)
    });
    let mut pr = geardyn_hbm_problem(&m, &basis);
    let nz = pr.n_unknowns();
    let z = sol.solution.coefficients.clone();
    let mut z2 = z.clone();
    z2[1] *= 1.0 + 1e-9;
    let mut r = vec![0.0; nz];
    // alternate two points: the problem skips the AFT at the point it evaluated last
    let mut flip = false;
    time("residual", reps * 10, || {
        flip = !flip;
        pr.residual(if flip { &z } else { &z2 }, &mut r)
    });
    let mut jac = hbm_jac(nz);
    time("residual + Jacobian", reps * 10, || {
        flip = !flip;
        pr.residual_and_jacobian(if flip { &z } else { &z2 }, &mut r, &mut jac)
    });
    time("Jacobian at the last residual's point", reps * 10, || {
        pr.residual_and_jacobian(&z, &mut r, &mut jac)
    });
    time("time_series(4096)", reps, || sol.solution.time_series(4096));
    time("displacement_samples(0, 4096)", reps, || {
        sol.solution.displacement_samples(0, 4096)
    });
    let ts = sol.solution.time_series(4096);
    time("rattle over 4096 samples", reps, || {
        m.rattle(
            ts.time
                .iter()
                .copied()
                .zip(ts.displacement[0].iter().copied()),
        )
    });
}

/// Nanoseconds this thread has spent on a CPU (None off Linux).
fn cpu_ns() -> Option<u64> {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()?
        .split_whitespace()
        .next()?
        .parse()
        .ok()
}

fn geardyn_hbm_problem(m: &liu2021::Model, basis: &hbm::Basis) -> hbm::HbmProblem<liu2021::Model> {
    hbm::HbmProblem::with_grid_size(*m, basis.clone(), m.omega_c, 1024).expect("problem")
}

fn hbm_jac(n: usize) -> hbm::nalgebra::DMatrix<f64> {
    hbm::nalgebra::DMatrix::zeros(n, n)
}
