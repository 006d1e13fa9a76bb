//! Steps per second of the Liu time stepping at ω₁ = 160 rad/s (issue 13), with the counts:
//! `cargo run --release -p geardyn-models --example liu_timestep_rate`.
//!
//! Problem: Table 1 at 160 rad/s (both `BaseRadius` readings), three periods `T = 2π/ω̄_c`
//! from the quasi-static contact position at rest, Dormand–Prince 5(4), rtol 1e-8,
//! atol 1e-11·max(b̄, B₀), steps ≤ 0.5, gap-edge events on, `Output::Final` (the settings of
//! `liu2021::integrate`). Each run is timed by the wall clock (best batch) and by the time the
//! thread spent on a CPU (Linux `/proc/thread-self/schedstat`, averaged over all batches): the
//! machine is shared, and the on-CPU figure is what an idle core would take.
//!
//! `liu_timestep_rate [reps] [--json PATH]` also writes the model (serde), the settings and
//! these results to `PATH`, the input of the peer script `docs/peers/liu_timestep_peers.py`.

use geardyn_models::liu2021::{self, BaseRadius};
use std::hint::black_box;
use std::time::Instant;
use timestep::OdeSystem;

/// Nanoseconds this thread has run on a CPU (None off Linux).
fn on_cpu_ns() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    s.split_whitespace().next()?.parse().ok()
}

/// (best wall, mean on-CPU) seconds per call of `f`, over 5 batches of `n` calls.
fn time<T>(n: u32, mut f: impl FnMut() -> T) -> (f64, f64) {
    black_box(f());
    let c0 = on_cpu_ns();
    let mut wall = f64::INFINITY;
    for _ in 0..5 {
        let t = Instant::now();
        for _ in 0..n {
            black_box(f());
        }
        wall = wall.min(t.elapsed().as_secs_f64() / f64::from(n));
    }
    let cpu = match (c0, on_cpu_ns()) {
        (Some(a), Some(b)) => (b - a) as f64 * 1e-9 / f64::from(5 * n),
        _ => f64::NAN,
    };
    (wall, cpu)
}

/// Integrates `sys` and prints the counts, the times and the steps per second.
fn report<S: OdeSystem>(
    label: &str,
    sys_label: &str,
    sys: &S,
    y0: &[f64],
    t_end: f64,
    opts: &timestep::Options,
    reps: u32,
) -> serde_json::Value {
    let run = || timestep::integrate(sys, 0.0, y0, t_end, opts).expect("integrates");
    let s = run();
    let (w, c) = time(reps, run);
    let st = s.stats;
    println!(
        "{label:<8} {sys_label:<10} events {:<5}: accepted {} rejected {} rhs {} events {}  \
         wall {:6.2} ms ({:4.2} M steps/s)  on-CPU {:6.2} ms ({:4.2} M steps/s)  y_final {:?}",
        opts.events,
        st.n_accepted,
        st.n_rejected,
        st.n_rhs,
        st.n_events,
        w * 1e3,
        st.n_accepted as f64 / w * 1e-6,
        c * 1e3,
        st.n_accepted as f64 / c * 1e-6,
        s.y_final
    );
    serde_json::json!({
        "reading": label, "system": sys_label, "events": opts.events,
        "stats": st, "y_final": s.y_final, "wall_s": w, "on_cpu_s": c,
    })
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let reps = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(10u32);
    let json_path = args
        .iter()
        .position(|a| a == "--json")
        .and_then(|i| args.get(i + 1));
    let mut runs = Vec::new();
    let mut models = serde_json::Map::new();
    for (label, base_radius) in [
        ("mean", BaseRadius::Mean),
        ("varying", BaseRadius::TimeVarying),
    ] {
        let mut p = liu2021::table1();
        p.omega1 = 160.0;
        p.readings.base_radius = base_radius;
        let m = p.model().expect("Table 1 is valid");
        let mech = timestep::FirstOrder(timestep::Mechanical::new(m).expect("valid"));
        let lean = liu2021::TimeSystem::new(m);
        let t3 = 3.0 * m.period();
        let y0 = [m.static_position(0.0), 0.0];
        // the right-hand side alone, at the states of the orbit itself: every accepted step
        // of the run (one distinct time per call, so the time cache never hits)
        let orbit = timestep::integrate(
            &lean,
            0.0,
            &y0,
            t3,
            &timestep::Options::default().with_h_max(0.5),
        )
        .expect("integrates");
        let pts: Vec<(f64, &[f64])> = orbit
            .t
            .iter()
            .enumerate()
            .map(|(i, &t)| (t, orbit.state(i)))
            .collect();
        fn calls<S: OdeSystem>(sys: &S, pts: &[(f64, &[f64])]) -> f64 {
            let mut dy = [0.0; 2];
            let mut acc = 0.0;
            for (t, y) in pts {
                sys.rhs(*t, black_box(y), &mut dy);
                acc += dy[1];
            }
            acc
        }
        let n = pts.len() as f64;
        let (w, c) = time(20 * reps, || calls(&mech, &pts));
        println!(
            "{label:<8} rhs FirstOrder(Mechanical)  wall {:6.1} ns  on-CPU {:6.1} ns per call",
            w / n * 1e9,
            c / n * 1e9
        );
        let (w, c) = time(20 * reps, || calls(&lean, &pts));
        println!(
            "{label:<8} rhs TimeSystem (lean)       wall {:6.1} ns  on-CPU {:6.1} ns per call",
            w / n * 1e9,
            c / n * 1e9
        );
        for events in [true, false] {
            let opts = timestep::Options::default()
                .with_tol(1e-8, 1e-8 * 1e-3 * m.backlash.max(m.b0))
                .with_h_max(0.5)
                .with_events(events)
                .with_output(timestep::Output::Final);
            runs.push(report(label, "Mechanical", &mech, &y0, t3, &opts, reps));
            runs.push(report(label, "TimeSystem", &lean, &y0, t3, &opts, reps));
        }
        // a reference for the accuracy of every run: events on, rtol 1e-12
        let tight = timestep::Options::default()
            .with_tol(1e-12, 1e-12 * 1e-3 * m.backlash.max(m.b0))
            .with_h_max(0.5)
            .with_output(timestep::Output::Final);
        let reference = timestep::integrate(&lean, 0.0, &y0, t3, &tight).expect("integrates");
        // the model's own run (2 transient + 1 recorded period, samples every 0.1): the ppv
        let io = liu2021::IntegrationOptions::default();
        let ti = liu2021::integrate(&m, &io).expect("integrates");
        let record: Vec<f64> = ti.tau.clone();
        models.insert(
            label.to_string(),
            serde_json::json!({
                "model": m, "y0": y0, "tau_end": t3, "rtol": 1e-8,
                "atol": 1e-8 * 1e-3 * m.backlash.max(m.b0), "h_max": 0.5,
                "reference_rtol_1e-12": reference.y_final,
                "integrate": {
                    "options": io, "ppv": ti.rattle.ppv, "q_min": ti.rattle.q_min,
                    "q_max": ti.rattle.q_max, "tau_first": record.first(),
                    "tau_last": record.last(), "samples": record.len(), "stats": ti.stats,
                },
            }),
        );
    }
    // the driver's floor: the same stepper on y'' = −y (one multiply per call)
    let sys = timestep::FnSystem::new(2, |_t: f64, y: &[f64], dy: &mut [f64]| {
        dy[0] = y[1];
        dy[1] = -y[0];
    });
    let o = timestep::Options::default()
        .with_events(false)
        .with_output(timestep::Output::Final);
    let run = || timestep::integrate(&sys, 0.0, &[1.0, 0.0], 2000.0, &o).expect("ok");
    let st = run().stats;
    let (w, c) = time(reps, run);
    println!(
        "floor    y''=-y, rtol 1e-8, no events: accepted {} rhs {}  wall {:5.1} ns/step  on-CPU \
         {:5.1} ns/step ({:4.1} M steps/s)",
        st.n_accepted,
        st.n_rhs,
        w / st.n_accepted as f64 * 1e9,
        c / st.n_accepted as f64 * 1e9,
        st.n_accepted as f64 / c * 1e-6
    );
    if let Some(path) = json_path {
        let doc = serde_json::json!({ "models": models, "runs": runs });
        std::fs::write(path, serde_json::to_string_pretty(&doc).expect("json"))
            .expect("writable path");
        println!("wrote {path}");
    }
}
