//! The Liu et al. (2021) period-1 branch (Table 1, constant b̄) continued in ω1 by shooting, with
//! stability, grazings, contact changes and period doublings printed.
//!
//! `cargo run --release -p geardyn-orbit --example liu_branch -- up` (from 100 rad/s upward, the
//! no-rattle / unilateral branch) or `-- down` (from 220 rad/s downward, the bilateral branch).

use models::liu2021::{self, BaseRadius, IntegrationOptions};
use orbit::{ContinuationOptions, OrbitProblem, Parameter, ShootingCorrection, ShootingOptions};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let down = std::env::args().nth(1).as_deref() == Some("down");
    let w_start = if down { 220.0 } else { 100.0 };
    let mut par = liu2021::table1();
    par.readings.base_radius = BaseRadius::Mean;
    par.omega1 = w_start;
    let m = par.model()?;
    let conv = m.omega_c / w_start; // ω̄_c per rad/s
    // time-stepping guess: 200 periods from the quasi-static contact position
    let ti = liu2021::integrate(
        &m,
        &IntegrationOptions {
            transient_periods: 199.0,
            record_periods: 1.0,
            initial: Some((-m.backlash - m.b0, 0.0)),
            ..IntegrationOptions::default()
        },
    )?;
    let x0 = [*ti.q.last().ok_or("empty")?, *ti.v.last().ok_or("empty")?];
    let mut p = OrbitProblem::new(m, m.period())?;
    let opts = ContinuationOptions {
        initial_step: 1.0,
        max_step: 2.0,
        min_step: 1e-6,
        max_points: 400,
        corrector: ShootingCorrection {
            parameter: Parameter::BaseFrequency,
            range: [95.0 * conv, 225.0 * conv],
            direction: if down { -1.0 } else { 1.0 },
            // arclength unit: 1 rad/s of ω1, or a tenth of the half backlash in the state
            parameter_scale: conv,
            state_scale: 0.1 * m.backlash,
            locate_tol: 1e-9,
            shooting: ShootingOptions {
                tol: 1e-8,
                max_iter: 20,
                ..ShootingOptions::default()
            },
            ..ShootingCorrection::default()
        },
        ..ContinuationOptions::default()
    };
    let t0 = std::time::Instant::now();
    let br = p.continuation(&x0, m.omega_c, &opts)?;
    println!(
        "{} points in {:?}, stop {:?}",
        br.points.len(),
        t0.elapsed(),
        br.stop
    );
    println!("omega1,events,stable,max_modulus,min_e0,max_e0,min_e1,max_e1");
    for pt in &br.points {
        let e = |i: usize, j: usize| pt.extrema.get(i).map_or(f64::NAN, |x| x[j]);
        println!(
            "{:.4},{},{},{:.4e},{:.4e},{:.4e},{:.4e},{:.4e}",
            pt.parameter / conv,
            pt.events,
            pt.floquet.stable,
            pt.floquet.max_modulus,
            e(0, 0),
            e(0, 1),
            e(1, 0),
            e(1, 1)
        );
    }
    for s in &br.special {
        println!(
            "{:?} at ω1 = {:.5} rad/s (located {}, bracket ±{:.2e} rad/s, stable {})",
            s.kind,
            s.point.parameter / conv,
            s.located,
            0.5 * s.precision() / conv,
            s.point.floquet.stable
        );
    }
    Ok(())
}
