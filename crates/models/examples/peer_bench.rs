//! geardyn's side of the same-algorithm peer comparison (issue 26): times one section and
//! prints one JSON document (the problem data the peers need, the results, their accuracy and
//! the timings). Driven by `docs/peers/compare.py`, which alternates these runs with the peers'.
//!
//! `cargo run --release -p geardyn-models --example peer_bench -- <section> [reps]`, sections:
//!
//! * `karpov`: `Karpov2017::duhamel()` (period folding, error-controlled to 1e-7·A) at Fig. 3
//!   data (`ω = 1`, `ξ = 2`, `k = 1/10`, `τ_end = 10⁵`), both readings, `B = 0.001, 0.01, 0.05`;
//!   `X`, `X'` at `τ_end`, the error estimate and a reference (`duhamel_folded(0.25)`).
//! * `liu`: Liu 2021 at 160 rad/s (constant b̄), three periods, DP5(4) rtol 1e-8 with the gap
//!   events, `TimeSystem` with `Trig::Kernel` and `Trig::Libm`; a fixed-step DP5 loop on the
//!   same right-hand side (no control, no events) as the stepper's floor; a reference at
//!   rtol 1e-12.
//! * `hbm`: the cold Liu HBM solve (paper basis, 15 unknowns, `liu2021::solve_hbm`) and the
//!   Duffing oscillator of the `hbm` bench at `H = 400` (801 unknowns) by Newton–Krylov and by
//!   dense Newton, with the work counters; the Liu solve also re-solved along a sweep on one
//!   prepared problem (`liu2021::PreparedHbm`, neighbouring speeds alternating).
//!
//! * `sweep`: the 61-point Liu ω₁ sweep of the sweep goal (100–250 rad/s, default
//!   `IntegrationOptions`), per point the adaptive run and the fixed-step loop with as many
//!   steps over the same span.
//!
//! * `wp`: the work–precision runs (own DP5, own DOP853, `ode_solvers` DOP853 at rtol
//!   1e-6 … 1e-12) of Liu at 160 and 180 rad/s and of Yu, with references; driven by
//!   `docs/peers/work_precision.py`.
//! * `dop853-once <own|ode_solvers> <0|1>`: one Liu 160 rad/s DOP853 run (events off/on) for
//!   callgrind instruction counts of the own stepper against the `ode_solvers` backend.
//!
//! `karpov` takes a third argument, `printed` or `accumulated`, to run one reading only.
//!
//! Times are the minimum over at least `reps` calls (and 0.2 s) after one warm-up (wall clock, seconds, `time_s`)
//! and the mean on-CPU time per call of the same calls (`cpu_s`, Linux; what `compare.py`
//! takes: on a loaded machine the run queue inflates wall times).

use geardyn_models::karpov2017::{Excitation, Karpov2017};
use geardyn_models::liu2021::{self, BaseRadius, HbmOptions, Trig};
use hbm::{Basis, HbmProblem, Method, SolverOptions};
use math::DetMath;
use serde_json::{Value, json};
use std::hint::black_box;
use std::time::Instant;
use system::problems::BenchDuffing as Duffing;
use timestep::OdeSystem;

/// Nanoseconds this thread has run on a CPU (Linux `/proc/thread-self/schedstat`; None
/// elsewhere). Accounted at context switches and scheduler ticks: read it around a batch.
fn on_cpu_ns() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    s.split_whitespace().next()?.parse().ok()
}

thread_local! {
    /// On-CPU seconds per call of the last [`best`] (mean over its calls; NaN off Linux).
    static LAST_CPU: std::cell::Cell<f64> = const { std::cell::Cell::new(f64::NAN) };
}

/// Minimum wall time (s) of one call over at least `reps` calls and 0.2 s, after one warm-up
/// call; the mean on-CPU time per call of the same calls goes to `LAST_CPU` (a shared machine's run queue
/// inflates wall times, not CPU times).
fn best<T>(reps: u32, mut f: impl FnMut() -> T) -> f64 {
    black_box(f());
    let mut t_min = f64::INFINITY;
    let c0 = on_cpu_ns();
    // at least `reps` calls and 0.2 s: the on-CPU clock is accounted at scheduler ticks
    let start = Instant::now();
    let mut n = 0u32;
    while n < reps.max(1) || start.elapsed().as_secs_f64() < 0.2 {
        let t = Instant::now();
        black_box(f());
        t_min = t_min.min(t.elapsed().as_secs_f64());
        n += 1;
    }
    let cpu = match (c0, on_cpu_ns()) {
        (Some(a), Some(b)) => (b - a) as f64 * 1e-9 / f64::from(n),
        _ => f64::NAN,
    };
    LAST_CPU.with(|c| c.set(cpu));
    t_min
}

/// The on-CPU time per call of the last [`best`].
fn cpu() -> f64 {
    LAST_CPU.with(std::cell::Cell::get)
}

fn karpov(reps: u32, only: Option<&str>) -> Value {
    let mut cases = Vec::new();
    for (reading, ex) in [
        ("printed", Excitation::PrintedPhase),
        ("accumulated", Excitation::AccumulatedPhase),
    ] {
        if only.is_some_and(|o| o != reading) {
            continue;
        }
        for b in [0.001, 0.01, 0.05] {
            let m = Karpov2017::fig3()
                .with(|p| {
                    p.excitation = ex;
                    p.b = b;
                })
                .expect("valid");
            let r = m.duhamel().expect("converges");
            let reference = m.duhamel_folded(0.25).expect("runs");
            let t = best(reps, || m.duhamel().expect("converges"));
            let t_cpu = cpu();
            cases.push(json!({
                "reading": reading, "params": {
                    "omega": m.params().omega, "b": b, "xi": m.params().xi, "k": m.params().k,
                    "tau_end": m.params().tau_end,
                },
                "x": r.x, "v": r.v, "amplitude": r.amplitude,
                "error_estimate": r.error_estimate, "rounding_estimate": r.rounding_estimate,
                "phase_budget": r.phase_budget,
                "panels": r.panels, "folded_periods": r.folded_periods,
                "x_ref": reference.x, "v_ref": reference.v,
                "ref_error_estimate": reference.error_estimate,
                "error": (r.x - reference.x).dhypot(r.v - reference.v),
                "time_s": t, "cpu_s": t_cpu,
            }));
        }
    }
    json!({ "section": "karpov", "cases": cases })
}

/// Fixed-step Dormand–Prince 5(4) (the 7-stage FSAL tableau, no error estimate, no control,
/// no events) on `sys` with step `h`: the stepper's floor on this right-hand side.
fn dp5_fixed<S: OdeSystem>(sys: &S, y0: [f64; 2], t_end: f64, n: u64) -> [f64; 2] {
    const A: [[f64; 5]; 5] = [
        [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0],
        [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0],
        [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0],
        [
            19372.0 / 6561.0,
            -25360.0 / 2187.0,
            64448.0 / 6561.0,
            -212.0 / 729.0,
            0.0,
        ],
        [
            9017.0 / 3168.0,
            -355.0 / 33.0,
            46732.0 / 5247.0,
            49.0 / 176.0,
            -5103.0 / 18656.0,
        ],
    ];
    const C: [f64; 5] = [1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0];
    const B: [f64; 6] = [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ];
    let h = t_end / n as f64;
    let mut y = y0;
    let mut k = [[0.0; 2]; 7];
    sys.rhs(0.0, &y, &mut k[0]);
    for i in 0..n {
        let t = i as f64 * h;
        for s in 0..5 {
            let mut ys = y;
            for d in 0..2 {
                let mut acc = 0.0;
                for j in 0..=s {
                    acc += A[s][j] * k[j][d];
                }
                ys[d] += h * acc;
            }
            let mut out = [0.0; 2];
            sys.rhs(t + C[s] * h, &ys, &mut out);
            k[s + 1] = out;
        }
        for d in 0..2 {
            let mut acc = 0.0;
            for j in 0..6 {
                acc += B[j] * k[j][d];
            }
            y[d] += h * acc;
        }
        let mut out = [0.0; 2];
        sys.rhs(t + h, &y, &mut out);
        k[0] = out;
    }
    y
}

/// `liu-profile <reps> <kernel|libm|table>`: only the adaptive runs of `liu` (events on), for a
/// profiler.
fn liu_profile(reps: u32, trig: &str) -> Value {
    let mut p = liu2021::table1();
    p.omega1 = 160.0;
    p.readings.base_radius = BaseRadius::Mean;
    let m = p.model().expect("Table 1 is valid");
    let t3 = 3.0 * m.period();
    let y0 = [m.static_position(0.0), 0.0];
    let opts = timestep::Options::default()
        .with_tol(1e-8, 1e-8 * 1e-3 * m.backlash.max(m.b0))
        .with_h_max(0.5)
        .with_events(true)
        .with_output(timestep::Output::Final);
    let trig = match trig {
        "libm" => Trig::Libm,
        "table" => Trig::Table,
        _ => Trig::Kernel,
    };
    let sys = liu2021::TimeSystem::with_trig(m, trig);
    let t = best(reps, || {
        timestep::integrate(&sys, 0.0, &y0, t3, &opts).expect("integrates")
    });
    json!({ "section": "liu-profile", "time_s": t })
}

fn liu(reps: u32) -> Value {
    let mut p = liu2021::table1();
    p.omega1 = 160.0;
    p.readings.base_radius = BaseRadius::Mean;
    let m = p.model().expect("Table 1 is valid");
    let t3 = 3.0 * m.period();
    let y0 = [m.static_position(0.0), 0.0];
    let atol = 1e-8 * 1e-3 * m.backlash.max(m.b0);
    let opts = timestep::Options::default()
        .with_tol(1e-8, atol)
        .with_h_max(0.5)
        .with_events(true)
        .with_output(timestep::Output::Final);
    let tight = timestep::Options::default()
        .with_tol(1e-12, 1e-12 * 1e-3 * m.backlash.max(m.b0))
        .with_h_max(0.5)
        .with_output(timestep::Output::Final);
    let reference = timestep::integrate(&liu2021::TimeSystem::new(m), 0.0, &y0, t3, &tight)
        .expect("integrates");
    let mut runs = Vec::new();
    for (name, trig) in [
        ("kernel", Trig::Kernel),
        ("libm", Trig::Libm),
        ("table", Trig::Table),
    ] {
        let sys = liu2021::TimeSystem::with_trig(m, trig);
        let run = || timestep::integrate(&sys, 0.0, &y0, t3, &opts).expect("integrates");
        let s = run();
        let t = best(reps, run);
        let t_cpu = cpu();
        let steps = s.stats.n_accepted + s.stats.n_rejected;
        // the fixed-step loop with as many steps as the adaptive run attempted
        let tf = best(reps, || dp5_fixed(&sys, y0, t3, steps));
        let tf_cpu = cpu();
        runs.push(json!({
            "trig": name, "stats": s.stats, "y_final": s.y_final, "time_s": t,
            "error_q": (s.y_final[0] - reference.y_final[0]).abs(),
            "error_v": (s.y_final[1] - reference.y_final[1]).abs(),
            "fixed_step_loop_s": tf, "fixed_steps": steps, "cpu_s": t_cpu,
            "fixed_step_loop_cpu_s": tf_cpu,
        }));
    }
    json!({
        "section": "liu", "model": m, "y0": y0, "tau_end": t3, "rtol": 1e-8, "atol": atol,
        "h_max": 0.5, "reference": reference.y_final, "runs": runs,
    })
}

/// `sweep [reps]`: the 61-point ω₁ sweep of the `geardyn study` goal (Table 1, ω₁ = 100, 102.5,
/// …, 250 rad/s, `liu2021::integrate` with the default `IntegrationOptions`: the default
/// `Trig::Table`, rtol 1e-8, events, 2 + 1 periods). Per point: the adaptive run in process, and the
/// fixed-step DP5 loop on the same right-hand side over the same span with as many steps as
/// that point attempted (accepted + rejected) — the goal's denominator point by point instead
/// of the 160 rad/s cost times the total.
fn sweep(reps: u32) -> Value {
    let opts = liu2021::IntegrationOptions::default();
    let mut points = Vec::new();
    let (mut adaptive_cpu, mut fixed_cpu) = (0.0, 0.0);
    let (mut accepted, mut rejected) = (0u64, 0u64);
    for i in 0..61u32 {
        let mut p = liu2021::table1();
        p.omega1 = 100.0 + 2.5 * f64::from(i);
        let m = p.model().expect("Table 1 is valid");
        let r = liu2021::integrate(&m, &opts).expect("integrates");
        let steps = r.stats.n_accepted + r.stats.n_rejected;
        best(reps, || liu2021::integrate(&m, &opts).expect("integrates"));
        let ta = cpu();
        let sys = liu2021::TimeSystem::new(m);
        let span = (opts.transient_periods + opts.record_periods) * m.period();
        let y0 = [m.static_position(0.0), 0.0];
        best(reps, || dp5_fixed(&sys, y0, span, steps));
        let tf = cpu();
        adaptive_cpu += ta;
        fixed_cpu += tf;
        accepted += r.stats.n_accepted;
        rejected += r.stats.n_rejected;
        points.push(json!({
            "omega1": p.omega1, "accepted": r.stats.n_accepted, "rejected": r.stats.n_rejected,
            "adaptive_cpu_s": ta, "fixed_step_loop_cpu_s": tf,
            "fixed_ns_per_step": tf * 1e9 / steps as f64,
        }));
    }
    json!({
        "section": "sweep", "accepted": accepted, "rejected": rejected,
        "adaptive_cpu_s": adaptive_cpu, "fixed_step_loop_cpu_s": fixed_cpu,
        "adaptive_over_fixed": adaptive_cpu / fixed_cpu, "points": points,
    })
}

/// Final-state error `max_i |y_i − ref_i| / max(1, ‖ref‖∞)`.
fn state_error(y: &[f64], reference: &[f64]) -> f64 {
    let scale = reference.iter().fold(1.0f64, |a, v| a.max(v.abs()));
    y.iter()
        .zip(reference)
        .fold(0.0f64, |a, (u, r)| a.max((u - r).abs()))
        / scale
}

/// The work–precision runs of one system: per rtol (1e-6 … 1e-12, `atol = rtol · atol_scale`)
/// and method, the final-state error against a reference (the own DOP853 at rtol 1e-14,
/// checked against the own DP5 at rtol 1e-14: `reference_spread`) and the mean on-CPU time per
/// call; the methods alternate at each tolerance.
fn wp_runs<S: OdeSystem>(
    sys: &S,
    y0: &[f64],
    t_end: f64,
    h_max: f64,
    atol_scale: f64,
    reps: u32,
) -> (Vec<f64>, f64, Vec<Value>) {
    use timestep::Method as M;
    let opts = |m: M, rtol: f64| {
        timestep::Options::default()
            .with_method(m)
            .with_tol(rtol, rtol * atol_scale)
            .with_h_max(h_max)
            .with_output(timestep::Output::Final)
    };
    let reference =
        timestep::integrate(sys, 0.0, y0, t_end, &opts(M::Dop853, 1e-14)).expect("integrates");
    let check = timestep::integrate(sys, 0.0, y0, t_end, &opts(M::DormandPrince54, 1e-14))
        .expect("integrates");
    let spread = state_error(&check.y_final, &reference.y_final);
    let mut runs = Vec::new();
    for k in 6..=12 {
        let rtol = 10f64.powi(-k);
        for (name, m) in [
            ("dp5", M::DormandPrince54),
            ("dop853", M::Dop853),
            ("ode_solvers_dop853", M::OdeSolversDop853),
        ] {
            // the `ode_solvers` backend (events by restarts, Hermite interpolant) takes 100×
            // the steps here: one tolerance only, for the own-vs-backend comparison
            if name == "ode_solvers_dop853" && k != 8 {
                continue;
            }
            let o = opts(m, rtol);
            let run = || timestep::integrate(sys, 0.0, y0, t_end, &o).expect("integrates");
            let s = run();
            let wall = best(reps, run);
            runs.push(json!({
                "method": name, "rtol": rtol, "atol": rtol * atol_scale,
                "error": state_error(&s.y_final, &reference.y_final),
                "cpu_s": cpu(), "time_s": wall, "stats": s.stats, "y_final": s.y_final,
                "status": format!("{:?}", s.status),
            }));
        }
    }
    (reference.y_final, spread, runs)
}

/// `wp [reps]`: the work–precision runs of `docs/peers/work_precision.py` — Liu 2021 at 160 and
/// 180 rad/s (Table 1, constant b̄, `Trig::Kernel`, 3 periods from the quasi-static contact
/// position, steps ≤ 0.5, gap events) and Yu 2021 (Table 1, ω* = 0.9, 10 periods from the
/// model's initial state, steps ≤ T/4, events on), each with own DP5, own DOP853 and the
/// `ode_solvers` DOP853 at rtol 1e-8 only (it takes about 100× the steps of the own one on
/// these problems: events by restarts). The Liu cases carry the model for the Python
/// peers (scipy, the numba DP5 of `liu_dp5_events_numba.py`).
fn wp(reps: u32) -> Value {
    use geardyn_models::yu2021::{Options as YuOptions, Yu2021Model, Yu2021Params, Yu2021SixDof};
    let mut cases = Vec::new();
    for omega1 in [160.0, 180.0] {
        let mut p = liu2021::table1();
        p.omega1 = omega1;
        p.readings.base_radius = BaseRadius::Mean;
        let m = p.model().expect("Table 1 is valid");
        let t_end = 3.0 * m.period();
        let y0 = [m.static_position(0.0), 0.0];
        let atol_scale = 1e-3 * m.backlash.max(m.b0);
        let sys = liu2021::TimeSystem::with_trig(m, Trig::Kernel);
        let (reference, spread, runs) = wp_runs(&sys, &y0, t_end, 0.5, atol_scale, reps);
        cases.push(json!({
            "case": format!("liu{omega1}"), "title": format!("Liu 2021, {omega1} rad/s"),
            "model": m, "y0": y0, "tau_end": t_end, "h_max": 0.5, "atol_scale": atol_scale,
            "reference": reference, "reference_spread": spread, "runs": runs,
        }));
    }
    let w = 0.9;
    let m = Yu2021Model::new(&Yu2021Params::table1(), YuOptions::default()).expect("Table 1");
    let sys = timestep::FirstOrder(
        timestep::Mechanical::new(Yu2021SixDof::new(&m, w).expect("valid")).expect("valid"),
    );
    let period = std::f64::consts::TAU / w;
    let y0 = m.initial_state();
    let (reference, spread, runs) = wp_runs(&sys, &y0, 10.0 * period, period / 4.0, 1e-2, reps);
    cases.push(json!({
        "case": "yu", "title": "Yu 2021, ω* = 0.9", "y0": y0, "tau_end": 10.0 * period,
        "h_max": period / 4.0, "atol_scale": 1e-2, "reference": reference,
        "reference_spread": spread, "runs": runs,
    }));
    json!({ "section": "wp", "cases": cases })
}

/// `dop853-once <own|ode_solvers> <events: 0|1>`: one Liu 160 rad/s run (3 periods, rtol 1e-10,
/// steps ≤ 0.5) with the own or the `ode_solvers` DOP853, for instruction counts under
/// `valgrind --tool=callgrind` (load-independent); prints the statistics.
fn dop853_once(which: &str, events: bool) -> Value {
    let mut p = liu2021::table1();
    p.omega1 = 160.0;
    p.readings.base_radius = BaseRadius::Mean;
    let m = p.model().expect("Table 1 is valid");
    let y0 = [m.static_position(0.0), 0.0];
    let method = if which == "own" {
        timestep::Method::Dop853
    } else {
        timestep::Method::OdeSolversDop853
    };
    let opts = timestep::Options::default()
        .with_method(method)
        .with_tol(1e-10, 1e-13 * m.backlash.max(m.b0))
        .with_h_max(0.5)
        .with_events(events)
        .with_output(timestep::Output::Final);
    let sys = liu2021::TimeSystem::with_trig(m, Trig::Kernel);
    let s = timestep::integrate(&sys, 0.0, &y0, 3.0 * m.period(), &opts).expect("integrates");
    json!({ "section": "dop853-once", "method": which, "events": events, "stats": s.stats,
            "y_final": s.y_final })
}

/// On-CPU time of the FFTs of a cold Liu solve: `residuals` × (complex inverse + real
/// forward, size `n`), `jacobians` × complex forward (size `n`), one complex inverse of size
/// `m` (the metrics' samples), on this thread's planned transforms.
fn fft_floor(n: usize, m: usize, residuals: u64, jacobians: u64, reps: u32) -> f64 {
    use fft::Complex;
    let mut planner = fft::FftPlanner::new();
    let (fwd, inv, inv_m) = (
        planner.plan_forward(n),
        planner.plan_inverse(n),
        planner.plan_inverse(m),
    );
    let r2c = fft::RealFftPlanner::new().plan_forward(n);
    let mut buf: Vec<Complex<f64>> = (0..n).map(|i| Complex::new(i as f64, 0.5)).collect();
    let mut buf_m: Vec<Complex<f64>> = (0..m).map(|i| Complex::new(i as f64, 0.5)).collect();
    let mut scratch = vec![Complex::default(); 4 * m];
    let (mut rin, mut rout, mut rs) = (
        r2c.make_input_vec(),
        r2c.make_output_vec(),
        r2c.make_scratch_vec(),
    );
    // the on-CPU time, as for the solve it is compared with
    let _wall = best(reps, || {
        for _ in 0..residuals {
            inv.process_with_scratch(&mut buf, &mut scratch);
            for (r, b) in rin.iter_mut().zip(&buf) {
                *r = b.re;
            }
            r2c.process_with_scratch(&mut rin, &mut rout, &mut rs)
                .expect("planned lengths");
        }
        for _ in 0..jacobians {
            fwd.process_with_scratch(&mut buf, &mut scratch);
        }
        inv_m.process_with_scratch(&mut buf_m, &mut scratch);
        buf[0].re + buf_m[0].re
    });
    cpu()
}

fn hbm(reps: u32) -> Value {
    // Liu cold solve, paper basis
    let mut p = liu2021::table1();
    p.readings.base_radius = BaseRadius::Mean;
    let m = p.model().expect("Table 1 is valid");
    let o = HbmOptions::default();
    let sol = liu2021::solve_hbm(&m, &o, None).expect("solves");
    let t_liu = best(reps * 20, || {
        liu2021::solve_hbm(&m, &o, None).expect("solves")
    });
    let t_liu_cpu = cpu();
    // the same cold solve along a sweep: one prepared problem (`liu2021::PreparedHbm`, plans,
    // buffers and basis kept) re-solved at alternating neighbouring speeds (160 and 161 rad/s)
    let mut p2 = p;
    p2.omega1 += 1.0;
    let m2 = p2.model().expect("valid");
    let mut prepared = liu2021::PreparedHbm::new(&m, &o).expect("prepares");
    let mut flip = false;
    let t_prep = best(reps * 20, || {
        flip = !flip;
        let mm = if flip { &m2 } else { &m };
        prepared.solve(mm, liu2021::HbmStart::Cold).expect("solves")
    });
    let t_prep_cpu = cpu();
    // the FFT floor of that solve: per residual one complex inverse FFT (q and q' packed) and
    // one real-to-complex forward FFT of N = 1024, per Jacobian one complex forward FFT, and
    // the 4096-point inverse FFT of the metrics' samples
    let (residuals, jacobians) = (sol.solution.iterations + 1, sol.solution.iterations);
    let floor = fft_floor(1024, 4096, residuals, jacobians, reps * 20);
    let liu = json!({
        "fft_floor_s": floor, "fft_floor_counts": {
            "residuals": residuals, "jacobians": jacobians, "grid": 1024, "metrics_grid": 4096,
        },
        "model": m, "harmonics": sol.solution.basis.harmonics(), "grid": 1024, "tol": o.tol,
        "coefficients": sol.solution.coefficients, "residual_norm": sol.solution.residual_norm,
        "truncation": sol.solution.truncation, "iterations": sol.solution.iterations,
        "ppv": sol.rattle.ppv, "time_s": t_liu, "cpu_s": t_liu_cpu,
        "prepared_time_s": t_prep, "prepared_cpu_s": t_prep_cpu,
    });
    // Duffing H = 400 from the embedded H = 1 solution
    let omega = 1.3;
    let mut p1 =
        HbmProblem::new(Duffing { omega }, Basis::full(1).expect("b"), omega).expect("problem");
    let mut g = p1.zero_guess();
    g[1] = 0.8;
    let s1 = p1
        .solve(&g, &SolverOptions::default())
        .expect("H = 1 solves");
    let h = 400;
    let basis = Basis::full(h).expect("basis");
    let z0 = s1.embed(&basis);
    let mut runs = Vec::new();
    let mut reference: Option<Vec<f64>> = None;
    for (name, method, r) in [
        ("newton_krylov", Method::NewtonKrylov, reps),
        ("dense_newton", Method::Newton, 3),
    ] {
        let mut ph = HbmProblem::new(Duffing { omega }, basis.clone(), omega).expect("problem");
        let so = SolverOptions {
            method,
            ..SolverOptions::default()
        };
        ph.reset_counters();
        let s = ph.solve(&z0, &so).expect("solves");
        let c = ph.counters();
        let t = best(r, || ph.solve(&z0, &so).expect("solves"));
        let t_cpu = cpu();
        let coeff = s.coefficients.clone();
        let diff = reference.as_ref().map(|rf| {
            rf.iter()
                .zip(&coeff)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max)
        });
        reference.get_or_insert(coeff.clone());
        runs.push(json!({
            "method": name, "iterations": s.iterations, "residual_norm": s.residual_norm,
            "residuals": c.residuals, "jacobian_products": c.jacobian_products,
            "max_diff_to_newton_krylov": diff, "time_s": t, "cpu_s": t_cpu,
            "grid": ph.grid_size(),
        }));
    }
    json!({
        "section": "hbm", "liu": liu,
        "duffing": {
            "h": h, "omega": omega, "damping": 0.1, "forcing": 0.3, "z0": z0,
            "tolerance": SolverOptions::default().tolerance,
            "solution": reference, "runs": runs,
        },
    })
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let section = args.get(1).map_or("karpov", String::as_str);
    let reps = args.get(2).and_then(|a| a.parse().ok()).unwrap_or(5u32);
    let out = match section {
        "karpov" => karpov(reps, args.get(3).map(String::as_str)),
        "liu" => liu(reps),
        "liu-profile" => liu_profile(reps, args.get(3).map_or("kernel", String::as_str)),
        "hbm" => hbm(reps),
        "sweep" => sweep(reps),
        "wp" => wp(reps),
        "dop853-once" => dop853_once(
            args.get(2).map_or("own", String::as_str),
            args.get(3).is_some_and(|a| a == "1"),
        ),
        other => {
            eprintln!("unknown section {other:?}: karpov | liu | hbm | sweep | wp | dop853-once");
            std::process::exit(2);
        }
    };
    println!("{out}");
}
